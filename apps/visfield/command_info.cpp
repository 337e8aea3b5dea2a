#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/core/isa.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::cli {

namespace {

std::ostream& operator<<(std::ostream& os, const Vec3f& v) { return os << "(" << v.x << ", " << v.y << ", " << v.z << ")"; }

int run_info(const StructureCommandOptions& o) {
  ThreadLimit limit(o.threads);
  double load_ms = 0.0;
  const Scene scene = load_scene_argument(o.scene, &load_ms);
  SceneGeometry geometry(scene);
  std::size_t vertices = 0, mesh_bytes = 0, duplicates = 0;
  for (const TriangleMesh& m : scene.meshes) {
    vertices += m.positions.size();
    mesh_bytes += m.memory_bytes();
    duplicates += m.count_duplicates();
  }
  const BuiltStructure built = build_structure_for(o.structure, geometry, {}, "--accel", o.scene);
  const std::size_t instanced = scene.instanced_triangle_count();
  const Bounds3f bounds = scene.bounds();
  std::cout << "scene:              " << scene.name << "\n"
            << "meshes:             " << scene.meshes.size() << " (" << vertices << " vertices, "
            << format_bytes(static_cast<double>(mesh_bytes)) << ", " << geometry.unique_triangle_count()
            << " triangles used)\n"
            << "objects:            " << scene.instances().size() << "\n"
            << "triangles:          " << instanced << " instanced, " << instanced - built.degenerate_triangles << " kept\n"
            << "degenerate:         " << built.degenerate_triangles << " zero-area triangles left out\n"
            << "duplicates:         " << duplicates << " triangles repeat another's vertices (kept)\n"
            << "bounds:             " << bounds.lo << " - " << bounds.hi << "\n"
            << "materials:          " << scene.materials.size() << "\n"
            << "lights:             " << scene.point_lights.size() << " point, " << scene.sphere_lights.size() << " sphere\n"
            << "camera:             " << (scene.camera ? "from the scene" : "framed automatically") << "\n"
            << "load:               " << load_ms << " ms\n"
            << "kernels:            " << isa_summary() << "\n";
  print_structure(std::cout, "--accel", built, limit.threads());
  return 0;
}

}  // namespace

void register_info_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<StructureCommandOptions>(StructureCommandOptions{.scene = "", .structure = "bvh", .threads = 0});
  CLI::App* cmd = app.add_subcommand("info", "Print counts, bounds, degenerate triangles and the built structure's memory");
  add_scene_argument(*cmd, options->scene);
  add_structure_option(*cmd, "--accel", options->structure, "Structure to build and measure, NAME[:key=value,...]")
      ->capture_default_str();
  add_resource_options(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_info(*options); }; });
}

}  // namespace vf::cli
