// The C++ API's answers for the Python tests to compare with: loads SCENE, builds SPEC from the
// registry, reads N rays from RAYS (N x 8 float32: origin, direction, tmin, tmax), answers each with
// the structure's single-ray query, and writes them to OUT: for "intersect" N hits of 8 words
// (t, prim, instance, u, v, normal x, y, z; float32 or uint32), for "occluded" N bytes.
// Usage: api_answers SCENE SPEC intersect|occluded RAYS OUT

#include <bit>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "visfield/io/scene_file.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/scene_geometry.hpp"

int main(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: api_answers SCENE SPEC intersect|occluded RAYS OUT\n";
    return 2;
  }
  try {
    const vf::Scene scene = vf::load_scene(argv[1]);
    vf::SceneGeometry geometry(scene);
    const vf::BuiltStructure built = vf::build_structure(argv[2], geometry);
    const std::string query = argv[3];
    std::ifstream in(argv[4], std::ios::binary);
    in.seekg(0, std::ios::end);
    const auto bytes = static_cast<std::size_t>(in.tellg());
    in.seekg(0);
    std::vector<vf::Ray> rays(bytes / sizeof(vf::Ray));
    in.read(reinterpret_cast<char*>(rays.data()), static_cast<std::streamsize>(rays.size() * sizeof(vf::Ray)));
    std::ofstream out(argv[5], std::ios::binary);
    for (const vf::Ray& ray : rays) {
      std::visit(
          [&](const auto& s) {
            if (query == "occluded") {
              const char answer = s.occluded(ray) ? 1 : 0;
              out.write(&answer, 1);
              return;
            }
            const vf::Hit h = s.intersect(ray);
            const std::uint32_t row[8] = {std::bit_cast<std::uint32_t>(h.t), h.prim, h.instance, std::bit_cast<std::uint32_t>(h.u),
                                          std::bit_cast<std::uint32_t>(h.v), std::bit_cast<std::uint32_t>(h.normal.x),
                                          std::bit_cast<std::uint32_t>(h.normal.y), std::bit_cast<std::uint32_t>(h.normal.z)};
            out.write(reinterpret_cast<const char*>(row), sizeof row);
          },
          built.structure);
    }
    return out ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "api_answers: " << e.what() << "\n";
    return 1;
  }
}
