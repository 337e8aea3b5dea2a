#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/accel/any_accel.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::cli {

namespace {

struct InfoOptions {
  std::string scene;
  std::string accel = "bvh";
  int threads = 0;
};

std::ostream& operator<<(std::ostream& os, const Vec3f& v) { return os << "(" << v.x << ", " << v.y << ", " << v.z << ")"; }

int run_info(const InfoOptions& o) {
  ThreadLimit limit(o.threads);
  const LoadedScene loaded = load_and_flatten(o.scene);
  const Scene& scene = loaded.scene;
  std::size_t vertices = 0, mesh_bytes = 0;
  for (const TriangleMesh& m : scene.meshes) {
    vertices += m.positions.size();
    mesh_bytes += m.memory_bytes();
  }
  const Bounds3f bounds = scene.bounds();
  std::cout << "scene:              " << scene.name << "\n"
            << "meshes:             " << scene.meshes.size() << " (" << vertices << " vertices, " << format_bytes(mesh_bytes)
            << ")\n"
            << "instances:          " << scene.instances.size() << "\n"
            << "triangles:          " << scene.instanced_triangle_count() << " instanced, " << loaded.triangles.size()
            << " kept\n"
            << "degenerate:         " << loaded.triangles.degenerate_count << " zero-area triangles left out\n"
            << "bounds:             " << bounds.lo << " - " << bounds.hi << "\n"
            << "materials:          " << scene.materials.size() << "\n"
            << "lights:             " << scene.point_lights.size() << " point, " << scene.sphere_lights.size() << " sphere\n"
            << "camera:             " << (scene.camera ? "from the scene" : "framed automatically") << "\n"
            << "load:               " << loaded.load_ms << " ms (flatten " << loaded.flatten_ms << " ms)\n";
  const AnyAccel accel = build_accel(o.accel, loaded.triangles);
  const AccelStats s = accel_stats(accel);
  std::cout << "accel:              " << o.accel << " (" << limit.threads() << " threads)\n"
            << "  build:            " << s.build_ms << " ms\n"
            << "  memory:           " << format_bytes(s.memory_bytes) << " (" << s.memory_bytes << " bytes)\n"
            << "  nodes:            " << s.node_count << "\n"
            << "  leaves:           " << s.leaf_count << "\n"
            << "  references:       " << s.reference_count << "\n"
            << "  max depth:        " << s.max_depth << "\n";
  return 0;
}

}  // namespace

void register_info_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand("info", "Print counts, bounds, degenerate triangles and the built structure's memory");
  add_scene_argument(*cmd, options->scene);
  cmd->add_option("--accel", options->accel, "Structure to build and measure")
      ->check(CLI::IsMember(accel_names()))
      ->capture_default_str();
  add_threads_option(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_info(*options); }; });
}

}  // namespace vf::cli
