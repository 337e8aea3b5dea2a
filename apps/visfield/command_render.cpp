#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/render/ao.hpp"

namespace vf::cli {

namespace {

struct RenderOptions {
  std::string scene;
  std::string accel = "bvh";
  std::string occluder;  // empty: the --accel structure answers the occlusion rays too
  std::string occluders;  // "field", "exact", or empty: as the scene marks its meshes
  std::string integrator = "ao";
  std::string out = "visfield-ao.png";
  int spp = 1;
  int ao_rays = 64;
  std::string ao_directions = "random";  // "random", or a line count: one AO ray along each line
  double max_distance = std::numeric_limits<double>::infinity();
  int width = 0;
  int height = 0;
  int threads = 0;
  std::uint64_t seed = 1;
  bool no_progress = false;
};

// Level of the line set --ao-directions names (0 for random directions).
int psf_level_of(const RenderOptions& o) {
  for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level)
    if (o.ao_directions == std::to_string(DirectionLines::count(level))) return level;
  return 0;
}

// AO rays per camera sample that hits: --ao-rays, or about half the lines of the PSF set.
std::uint64_t ao_rays_per_hit(const RenderOptions& o) {
  const int level = psf_level_of(o);
  return level == 0 ? static_cast<std::uint64_t>(o.ao_rays) : DirectionLines::count(level);
}

// Upper bound of the rays a render traces: every camera sample, and its AO rays when it hits.
std::uint64_t rays_of_render(const Camera& camera, const RenderOptions& o) {
  return static_cast<std::uint64_t>(camera.width) * static_cast<std::uint64_t>(camera.height) *
         static_cast<std::uint64_t>(o.spp) * (1u + ao_rays_per_hit(o));
}

// The spec of the structure that answers the AO rays ("" = the --accel one). --occluders field
// asks for fields (the --occluder field spec, or the default one) for every mesh the scene does not
// mark exact; --occluders exact for exact geometry only (--occluder, if given, must be exact).
// Without either option, a scene that marks meshes "occluder": "field" gets fields for those.
std::string occluder_spec(const RenderOptions& o, const Scene& scene) {
  if (o.occluders == "field" && o.occluder.empty()) return "field";
  if (!o.occluders.empty() || !o.occluder.empty()) return o.occluder;
  for (const TriangleMesh& mesh : scene.meshes)
    if (mesh.occluder == MeshOccluder::field) return "field:meshes=marked";
  return "";
}

std::string structure_summary(const BuiltStructure& built) {
  const AccelStats s = structure_stats(built.structure);
  return built.resolved + " (build " + std::to_string(s.build_ms) + " ms, " +
         format_bytes(static_cast<double>(s.memory_bytes)) + ")";
}

int run_render(const RenderOptions& o) {
  check_image_extension(o.out);
  check_writable(o.out);
  ThreadLimit limit(o.threads);
  const Scene scene = load_scene_argument(o.scene);
  SceneGeometry geometry(scene);
  const Camera camera = scene.camera_or_default(o.width, o.height);
  // The float image and its encoded copy (at most 4 bytes a pixel for PNG, 12 for EXR).
  require_memory(static_cast<double>(camera.width) * static_cast<double>(camera.height) * (sizeof(Vec3f) + 12.0),
                 "a " + std::to_string(camera.width) + "x" + std::to_string(camera.height) + " image");
  const BuildContext context{rays_of_render(camera, o), !o.no_progress};
  const BuiltStructure closest = build_structure_for(o.accel, geometry, context, "--accel", o.scene);
  const std::string occluder_choice = occluder_spec(o, scene);
  std::optional<BuiltStructure> occluder;
  if (!occluder_choice.empty() && occluder_choice != o.accel)
    occluder = build_structure_for(occluder_choice, geometry, context, "--occluder", o.scene);

  AoOptions ao;
  ao.spp = o.spp;
  ao.ao_rays = o.ao_rays;
  ao.psf_level = psf_level_of(o);
  ao.max_distance = static_cast<float>(o.max_distance);
  ao.seed = o.seed;
  ao.progress = !o.no_progress;
  RenderStats stats;
  const Image image = std::visit(
      [&](const auto& camera_rays, const auto& occlusion_rays) {
        return render_ao(camera_rays, occlusion_rays, scene, camera, ao, &stats);
      },
      closest.structure, occluder ? occluder->structure : closest.structure);
  write_image(o.out, image);

  std::cout << "wrote " << std::filesystem::absolute(o.out).string() << "\n";
  std::cout << "render: " << scene.instanced_triangle_count() - closest.degenerate_triangles << " triangles, accel "
            << structure_summary(closest) << (occluder ? ", occluder " + structure_summary(*occluder) : std::string())
            << ", " << limit.threads() << " threads, spp " << o.spp << ", "
            << (ao.psf_level ? "AO along " + o.ao_directions + " lines" : std::to_string(o.ao_rays) + " AO rays") << ": "
            << stats.summary() << "\n";
  return 0;
}

}  // namespace

void register_render_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render ambient occlusion of a mesh, scene file or builtin:NAME");
  add_scene_argument(*cmd, options->scene);
  add_structure_option(*cmd, "--accel", options->accel,
                       "Structure for camera rays (and occlusion rays unless --occluder), NAME[:key=value,...]; "
                       "`visfield structures` lists them")
      ->capture_default_str();
  add_structure_option(*cmd, "--occluder", options->occluder,
                       "Structure for the occlusion (AO) rays, NAME[:key=value,...] (default: the --accel one)");
  cmd->add_option("--integrator", options->integrator, "What to render: ao (ambient occlusion)")
      ->check(CLI::IsMember({"ao"}))
      ->capture_default_str();
  cmd->add_option("--occluders", options->occluders,
                  "How the AO rays see the scene's objects: field (ObjectFields for every mesh the scene does not mark "
                  "exact; --occluder may give the field:... parameters) or exact (exact geometry only). Default: the "
                  "scene's own marks (meshes with \"occluder\": \"field\" get fields)")
      ->check(CLI::IsMember({"field", "exact"}));
  cmd->add_option("--spp", options->spp, "Camera samples per pixel")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--ao-rays", options->ao_rays, "AO rays per camera sample")->check(CLI::Range(1, 65536))->capture_default_str();
  cmd->add_option("--ao-directions", options->ao_directions,
                  "AO directions: random (--ao-rays cosine-weighted ones), or 33|129|513|2049|8193: one ray along each "
                  "line of that octahedral set, cosine-weighted (VLF-RT's AO; a beam:dirs= of the same count traces "
                  "them on its fast path)")
      ->check(CLI::IsMember({"random", "33", "129", "513", "2049", "8193"}))
      ->capture_default_str();
  cmd->add_option("--max-distance", options->max_distance, "AO ray length (world units; default unlimited)")
      ->check(positive_number(/*infinity_allowed=*/true));
  cmd->add_option("--width", options->width, "Image width in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--height", options->height, "Image height in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  add_resource_options(*cmd, options->threads);
  cmd->add_option("--seed", options->seed, "Random seed (the image depends on it, not on the thread count)")->capture_default_str();
  cmd->add_option("-o,--out", options->out, "Output image (.png 8-bit sRGB or .exr float)")->capture_default_str();
  cmd->add_flag("--no-progress", options->no_progress, "Do not draw the progress bar");
  cmd->callback([options, &action] {
    // --occluders and --occluder must agree; checked while parsing, so a conflict is a usage error.
    const bool field_spec = !options->occluder.empty() &&
                            find_structure(parse_spec(options->occluder, "").name).exactness == Exactness::approximate;
    if (options->occluders == "exact" && field_spec)
      throw CLI::ValidationError("--occluder", options->occluder + ": --occluders exact needs an exact structure");
    if (options->occluders == "field" && !options->occluder.empty() && !field_spec)
      throw CLI::ValidationError("--occluder", options->occluder + ": --occluders field needs a field:... spec");
    action = [options] { return run_render(*options); };
  });
}

}  // namespace vf::cli
