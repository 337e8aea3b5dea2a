#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "cli_support.hpp"
#include "commands.hpp"
#include "integrator_options.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/io/image_io.hpp"
#if VISFIELD_HAVE_CUDA
#include <variant>

#include "visfield/core/spec.hpp"
#include "visfield/cuda/device.hpp"
#include "visfield/cuda/render_ao.hpp"
#include "visfield/gpu/packed_scene.hpp"
#endif

namespace vf::cli {

namespace {

struct RenderOptions {
  std::string scene;
  IntegratorOptions shading;
  std::string out;  // empty: visfield-<integrator>.png
  int width = 0;
  int height = 0;
  int threads = 0;
  bool no_progress = false;
  std::string device = "cpu";
  std::string up, view, camera, background;  // as written; read into `settings` by the callback
  RenderSettings settings;                   // the render settings, view and background included
};

std::string output_path(const RenderOptions& o) { return o.out.empty() ? "visfield-" + o.shading.integrator() + ".png" : o.out; }

// Upper bound of the rays a render traces: every camera sample, and its secondary rays when it hits.
std::uint64_t rays_of_render(const Camera& camera, const RenderOptions& o, const Scene& scene) {
  return static_cast<std::uint64_t>(camera.width) * static_cast<std::uint64_t>(camera.height) *
         static_cast<std::uint64_t>(o.shading.settings.spp) * (1u + rays_per_hit(o.shading, scene));
}

std::string structure_summary(const BuiltStructure& built) {
  const AccelStats s = structure_stats(built.structure);
  return built.resolved + " (build " + std::to_string(s.build_ms) + " ms, " +
         format_bytes(static_cast<double>(s.memory_bytes)) + ")";
}

#if VISFIELD_HAVE_CUDA
// --device cuda: camera rays through --accel on the CPU, AO rays generated and traced on the GPU,
// through the --occluder's fields (packed and copied to the device) or, for an exact occluder, the
// GPU BVH of the whole scene (every exact structure answers alike).
int run_render_cuda(const RenderOptions& o) {
  const std::string out = output_path(o);
  check_image_extension(out);
  check_writable(out);
  cuda::require_device();
  ThreadLimit limit(o.threads);
  const Scene scene = load_scene_argument(o.scene);
  SceneGeometry geometry(scene);
  const Camera camera = render_camera(scene, o.settings);
  require_memory(static_cast<double>(camera.width) * static_cast<double>(camera.height) * (sizeof(Vec3f) + 12.0 + 56.0),
                 "a " + std::to_string(camera.width) + "x" + std::to_string(camera.height) + " image and its surface points");
  const BuildContext context{rays_of_render(camera, o, scene), !o.no_progress};
  const BuiltStructure closest = build_structure_for(o.shading.accel, geometry, context, "--accel", o.scene);
  const std::string occluder_choice = occluder_spec(o.shading, scene);
  std::optional<BuiltStructure> fields;
  if (!occluder_choice.empty() && find_structure(parse_spec(occluder_choice, "--occluder").name).exactness == Exactness::approximate)
    fields = build_structure_for(occluder_choice, geometry, context, "--occluder", o.scene);
  cuda::DeviceFieldScene device_fields;
  cuda::DeviceBvh device_bvh;
  cuda::GpuOccluder occluder;
  std::string occluder_summary;
  if (fields) {
    const auto* field_scene = std::get_if<field::FieldScene>(&fields->structure);
    if (!field_scene) throw Error("--occluder " + occluder_choice + ": --device cuda traces fields or exact geometry");
    const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(scene, *field_scene);
    device_fields = cuda::DeviceFieldScene::upload(packed);
    occluder.fields = &device_fields;
    occluder_summary = structure_summary(*fields) + ", " + format_bytes(static_cast<double>(device_fields.bytes())) + " on the device";
  } else {
    const gpu::GpuBvh bvh = gpu::GpuBvh::build(geometry.flattened());
    device_bvh = cuda::DeviceBvh::upload(bvh);
    occluder.exact = &device_bvh;
    occluder_summary = "gpu-bvh (build " + std::to_string(bvh.stats().build_ms) + " ms, " +
                       format_bytes(static_cast<double>(device_bvh.bytes())) + " on the device)";
  }
  const std::unique_ptr<SceneQueries> queries = scene_queries(closest.structure, closest.structure);
  RenderStats stats;
  Image image = cuda::render_ao(*queries, scene, camera, ao_options(o.shading, !o.no_progress), occluder, &stats);
  put_render_background(image, *queries, camera, o.settings);
  write_image(out, image);
  std::cout << "wrote " << std::filesystem::absolute(out).string() << "\n";
  std::cout << "render: " << scene.instanced_triangle_count() - closest.degenerate_triangles << " triangles, accel "
            << structure_summary(closest) << ", occluder " << occluder_summary << ", device " << cuda::device_info().name << ", "
            << limit.threads() << " threads, spp " << o.shading.settings.spp << ", " << integrator_summary(o.shading) << ": " << stats.summary()
            << "\n";
  return 0;
}
#endif

int run_render(const RenderOptions& o) {
#if VISFIELD_HAVE_CUDA
  if (o.device == "cuda") return run_render_cuda(o);
#endif
  const std::string out = output_path(o);
  check_image_extension(out);
  check_writable(out);
  ThreadLimit limit(o.threads);
  const Scene scene = load_scene_argument(o.scene);
  SceneGeometry geometry(scene);
  const Camera camera = render_camera(scene, o.settings);
  // The float image, its coverage and alpha, and its encoded copy (at most 4 bytes a pixel for PNG, 16 for EXR).
  require_memory(static_cast<double>(camera.width) * static_cast<double>(camera.height) * (sizeof(Vec3f) + 8.0 + 16.0),
                 "a " + std::to_string(camera.width) + "x" + std::to_string(camera.height) + " image");
  const BuildContext context{rays_of_render(camera, o, scene), !o.no_progress};
  const BuiltStructure closest = build_structure_for(o.shading.accel, geometry, context, "--accel", o.scene);
  const std::string occluder_choice = occluder_spec(o.shading, scene);
  std::optional<BuiltStructure> occluder;
  if (!occluder_choice.empty() && occluder_choice != o.shading.accel)
    occluder = build_structure_for(occluder_choice, geometry, context, "--occluder", o.scene);
  const std::unique_ptr<SceneQueries> queries = scene_queries(closest.structure, occluder ? occluder->structure : closest.structure);

  RenderStats stats;
  const Integrator integrator = integrator_of(o.shading);
  Image image = integrator == Integrator::ao
                    ? render_ao(*queries, scene, camera, ao_options(o.shading, !o.no_progress), &stats)
                    : render_shaded(integrator, *queries, scene, camera, shading_options(o.shading, !o.no_progress), &stats);
  put_render_background(image, *queries, camera, o.settings);
  write_image(out, image);

  std::cout << "wrote " << std::filesystem::absolute(out).string() << "\n";
  std::cout << "render: " << scene.instanced_triangle_count() - closest.degenerate_triangles << " triangles, accel "
            << structure_summary(closest) << (occluder ? ", occluder " + structure_summary(*occluder) : std::string())
            << ", " << limit.threads() << " threads, spp " << o.shading.settings.spp << ", " << integrator_summary(o.shading) << ": "
            << stats.summary() << "\n";
  return 0;
}

}  // namespace

void register_render_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a mesh, scene file or builtin:NAME (ambient occlusion by default)");
  add_scene_argument(*cmd, options->scene);
  add_integrator_options(*cmd, options->shading, "ao");
  cmd->add_option("--width", options->width, "Image width in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--height", options->height, "Image height in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  add_resource_options(*cmd, options->threads);
  cmd->add_option("--up", options->up, "The world's up axis: x, y or z with an optional sign (+z, -y; default +y, or the scene camera's)");
  cmd->add_option("--view", options->view,
                  "AZIMUTH,ELEVATION in degrees: look from there at the whole scene, framed (azimuth 0 is the front, "
                  "positive turns right; elevation within [-90, 90]; default " +
                      std::to_string(static_cast<int>(kDefaultAzimuth)) + "," + std::to_string(static_cast<int>(kDefaultElevation)) +
                      " when the scene has no camera)");
  cmd->add_option("--camera", options->camera,
                  "FROM,TO[,UP[,FOV]]: a camera at FROM looking at TO (three numbers each), up UP (default --up), vertical "
                  "field of view FOV degrees (default the scene camera's, else 45)");
  cmd->add_option("--background", options->background,
                  "What shows where nothing is hit: transparent (a PNG or EXR with alpha), white, black, grey, #RRGGBB or "
                  "R,G,B in [0, 1] (sRGB; default #3A3F47, a dark slate)");
  cmd->add_option("-o,--out", options->out, "Output image (.png 8-bit sRGB or .exr float; default visfield-INTEGRATOR.png)");
  cmd->add_flag("--no-progress", options->no_progress, "Do not draw the progress bar");
  add_device_option(*cmd, options->device);
  cmd->callback([options, &action, cmd] {
    // --occluders and --occluder must agree; checked while parsing, so a conflict is a usage error.
    check_integrator_options(*cmd, options->shading);
    check_device_option(options->device, options->shading);
    if (!options->camera.empty() && !options->view.empty()) throw CLI::ValidationError("--view", "--camera places the camera itself: give one of them");
    RenderSettings& s = options->settings;
    s = render_settings(options->shading, !options->no_progress);
    s.width = options->width, s.height = options->height;
    // The library's one-line messages ("up: expected ..."), as usage errors naming the option instead.
    auto read = [](const std::string& option, auto parse) {
      try {
        parse();
      } catch (const Error& e) {
        const std::string message = e.what(), key = option.substr(2) + ": ";
        throw CLI::ValidationError(option, message.starts_with(key) ? message.substr(key.size()) : message);
      }
    };
    if (!options->up.empty()) read("--up", [&] { s.up = parse_up(options->up); });
    if (!options->view.empty()) read("--view", [&] { s.view = parse_view(options->view); });
    if (!options->camera.empty()) read("--camera", [&] { s.camera = parse_camera_placement(options->camera); });
    if (!options->background.empty()) read("--background", [&] { s.background = parse_background(options->background); });
    action = [options] { return run_render(*options); };
  });
}

}  // namespace vf::cli
