// The C++ library through its one handle: loads a mesh, a scene .json or a built-in scene, builds any
// structure by its spec, traces one ray down onto the scene and a batch of rays around it.
//   cmake -S examples/cpp -B build-example -DCMAKE_PREFIX_PATH=/usr/local && cmake --build build-example
//   build-example/trace bunny.ply bvh
#include <cstdio>
#include <vector>

#include "visfield/core/error.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/registry/structure.hpp"

int main(int argc, char** argv) {
  try {
    const vf::Scene scene = vf::load_scene(argc > 1 ? argv[1] : "builtin:sphere");
    const vf::Structure structure = vf::Structure::build(scene, argc > 2 ? argv[2] : "bvh");  // any spec

    const vf::Vec3f c = scene.bounds().center();
    const vf::Hit hit = structure.intersect(vf::Ray{{c.x, c.y + 1000.0f, c.z}, {0.0f, -1.0f, 0.0f}});
    std::printf("%s: hit: %s, t = %g, triangle %u of object %u\n", structure.spec().c_str(), hit ? "yes" : "no", hit.t, hit.prim,
                hit.instance);

    std::vector<vf::Ray> rays;  // a fan of rays from above the centre
    for (int i = 0; i < 1000; ++i) rays.push_back(vf::Ray{{c.x, c.y + 1000.0f, c.z}, {0.001f * static_cast<float>(i - 500), -1.0f, 0.0f}});
    std::vector<vf::Hit> hits(rays.size());
    structure.intersect(rays, hits);  // parallel, one dispatch for the batch
    int found = 0;
    for (const vf::Hit& h : hits) found += h ? 1 : 0;
    std::printf("batch: %d of %zu rays hit\n", found, rays.size());
    return hit ? 0 : 1;
  } catch (const vf::Error& e) {
    std::fprintf(stderr, "trace: error: %s\n", e.what());
    return 1;
  }
}
