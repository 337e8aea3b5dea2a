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
#include "visfield/render/integrators.hpp"

namespace vf::cli {

namespace {

struct RenderOptions {
  std::string scene;
  std::string accel = "bvh";
  std::string occluder;  // empty: the --accel structure answers the occlusion rays too
  std::string occluders;  // "field", "exact", or empty: as the scene marks its meshes
  std::string integrator = "ao";
  std::string out;  // empty: visfield-<integrator>.png
  int spp = 1;
  int ao_rays = 64;
  std::string ao_directions = "random";  // "random", or a line count: one AO ray along each line
  double max_distance = std::numeric_limits<double>::infinity();
  int width = 0;
  int height = 0;
  int threads = 0;
  std::uint64_t seed = 1;
  bool no_progress = false;
  int depth = 5;
  int shadow_rays = 20;
  int glossy_rays = 4;
  double ambient = 0.1;
};

std::string output_path(const RenderOptions& o) { return o.out.empty() ? "visfield-" + o.integrator + ".png" : o.out; }

// Level of the line set --ao-directions names (0 for random directions).
int psf_level_of(const RenderOptions& o) {
  for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level)
    if (o.ao_directions == std::to_string(DirectionLines::count(level))) return level;
  return 0;
}

// Rays per camera sample that hits, for the structure's expected ray count (auto's R): AO rays, or
// what the shading integrator traces on average (lights counted as in the scene, at least one).
std::uint64_t rays_per_hit(const RenderOptions& o, const Scene& scene) {
  const int level = psf_level_of(o);
  const auto lights = static_cast<std::uint64_t>(std::max<std::size_t>(1, scene.point_lights.size() + scene.sphere_lights.size()));
  const auto depth = static_cast<std::uint64_t>(o.depth);
  if (o.integrator == "ao") return level == 0 ? static_cast<std::uint64_t>(o.ao_rays) : DirectionLines::count(level);
  if (o.integrator == "raycast") return 0;
  if (o.integrator == "whitted") return lights + 1;
  if (o.integrator == "softshadow") return lights * static_cast<std::uint64_t>(o.shadow_rays);
  if (o.integrator == "glossy") return lights + static_cast<std::uint64_t>(o.glossy_rays);
  return 2 * depth;  // path: a bounce and a shadow ray per vertex
}

// Upper bound of the rays a render traces: every camera sample, and its secondary rays when it hits.
std::uint64_t rays_of_render(const Camera& camera, const RenderOptions& o, const Scene& scene) {
  return static_cast<std::uint64_t>(camera.width) * static_cast<std::uint64_t>(camera.height) *
         static_cast<std::uint64_t>(o.spp) * (1u + rays_per_hit(o, scene));
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
  const std::string out = output_path(o);
  check_image_extension(out);
  check_writable(out);
  ThreadLimit limit(o.threads);
  const Scene scene = load_scene_argument(o.scene);
  SceneGeometry geometry(scene);
  const Camera camera = scene.camera_or_default(o.width, o.height);
  // The float image and its encoded copy (at most 4 bytes a pixel for PNG, 12 for EXR).
  require_memory(static_cast<double>(camera.width) * static_cast<double>(camera.height) * (sizeof(Vec3f) + 12.0),
                 "a " + std::to_string(camera.width) + "x" + std::to_string(camera.height) + " image");
  const BuildContext context{rays_of_render(camera, o, scene), !o.no_progress};
  const BuiltStructure closest = build_structure_for(o.accel, geometry, context, "--accel", o.scene);
  const std::string occluder_choice = occluder_spec(o, scene);
  std::optional<BuiltStructure> occluder;
  if (!occluder_choice.empty() && occluder_choice != o.accel)
    occluder = build_structure_for(occluder_choice, geometry, context, "--occluder", o.scene);
  const std::unique_ptr<SceneQueries> queries = scene_queries(closest.structure, occluder ? occluder->structure : closest.structure);

  const Integrator integrator = *parse_integrator(o.integrator);
  RenderStats stats;
  std::string what;
  Image image;
  if (integrator == Integrator::ao) {
    AoOptions ao;
    ao.spp = o.spp;
    ao.ao_rays = o.ao_rays;
    ao.psf_level = psf_level_of(o);
    ao.max_distance = static_cast<float>(o.max_distance);
    ao.seed = o.seed;
    ao.progress = !o.no_progress;
    image = render_ao(*queries, scene, camera, ao, &stats);
    what = ao.psf_level ? "AO along " + o.ao_directions + " lines" : std::to_string(o.ao_rays) + " AO rays";
  } else {
    ShadingOptions shading;
    shading.spp = o.spp;
    shading.seed = o.seed;
    shading.progress = !o.no_progress;
    shading.max_depth = o.depth;
    shading.shadow_rays = o.shadow_rays;
    shading.glossy_rays = o.glossy_rays;
    shading.ambient = static_cast<float>(o.ambient);
    image = render_shaded(integrator, *queries, scene, camera, shading, &stats);
    what = o.integrator;
  }
  write_image(out, image);

  std::cout << "wrote " << std::filesystem::absolute(out).string() << "\n";
  std::cout << "render: " << scene.instanced_triangle_count() - closest.degenerate_triangles << " triangles, accel "
            << structure_summary(closest) << (occluder ? ", occluder " + structure_summary(*occluder) : std::string())
            << ", " << limit.threads() << " threads, spp " << o.spp << ", " << what << ": " << stats.summary() << "\n";
  return 0;
}

}  // namespace

void register_render_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a mesh, scene file or builtin:NAME (ambient occlusion by default)");
  add_scene_argument(*cmd, options->scene);
  add_structure_option(*cmd, "--accel", options->accel,
                       "Structure for camera rays (and occlusion rays unless --occluder), NAME[:key=value,...]; "
                       "`visfield structures` lists them")
      ->capture_default_str();
  add_structure_option(*cmd, "--occluder", options->occluder,
                       "Structure for the occlusion (AO) rays, NAME[:key=value,...] (default: the --accel one)");
  cmd->add_option("--integrator", options->integrator,
                  "What to render: raycast (camera rays, diffuse colour lit by the lights, no shadows), whitted (hard "
                  "shadows, mirror reflection and refraction to --depth), ao (ambient occlusion), softshadow (sphere "
                  "lights by --shadow-rays rays each), glossy (direct light and --glossy-rays reflection rays), path "
                  "(path tracing: light sampling with MIS, Russian roulette, --depth bounces)")
      ->check(CLI::IsMember({"raycast", "whitted", "ao", "softshadow", "glossy", "path"}))
      ->capture_default_str();
  cmd->add_option("--depth", options->depth, "whitted: reflection/refraction levels; path: bounces")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--shadow-rays", options->shadow_rays, "softshadow: rays per sphere light per camera sample")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  cmd->add_option("--glossy-rays", options->glossy_rays, "glossy: reflection rays per reflective camera sample")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  cmd->add_option("--ambient", options->ambient,
                  "raycast, whitted, softshadow, glossy: ambient light as a fraction of the diffuse colour")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--occluders", options->occluders,
                  "How every ray after the camera's (AO, shadow, reflection) sees the scene's objects: field (ObjectFields for every mesh the scene does not mark "
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
  cmd->add_option("-o,--out", options->out, "Output image (.png 8-bit sRGB or .exr float; default visfield-INTEGRATOR.png)");
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
