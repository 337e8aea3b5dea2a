#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/accel/any_accel.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/select/decision.hpp"

namespace vf::cli {

namespace {

struct RenderOptions {
  std::string scene;
  std::string integrator = "ao";
  std::string accel = "bvh";
  std::string out = "visfield-ao.png";
  int spp = 1;
  int ao_rays = 64;
  double max_distance = std::numeric_limits<double>::infinity();
  int width = 0;
  int height = 0;
  int threads = 0;
  std::uint64_t seed = 1;
  bool no_progress = false;
  std::uint64_t expected_rays = 0;  // for --accel auto; 0 = the rays this render will trace
  std::string calibration;          // for --accel auto; empty = the built-in calibration
};

// Upper bound of the rays a render traces: every camera sample, and its AO rays when it hits.
std::uint64_t rays_of_render(const Camera& camera, const RenderOptions& o) {
  return static_cast<std::uint64_t>(camera.width) * static_cast<std::uint64_t>(camera.height) *
         static_cast<std::uint64_t>(o.spp) * (1u + static_cast<std::uint64_t>(o.ao_rays));
}

int run_render(const RenderOptions& o) {
  check_image_extension(o.out);
  ThreadLimit limit(o.threads);
  LoadedScene loaded = load_and_flatten(o.scene);
  const Camera camera = loaded.scene.camera_or_default(o.width, o.height);
  std::string accel_name = o.accel;
  if (accel_name == "auto") {
    const std::uint64_t rays = o.expected_rays > 0 ? o.expected_rays : rays_of_render(camera, o);
    const std::optional<std::string> calibration =
        o.calibration.empty() ? std::nullopt : std::optional<std::string>(o.calibration);
    accel_name = resolve_auto_accel(loaded.scene, loaded.triangles, rays, calibration);
    std::cout << "auto: " << accel_name << " chosen for " << rays << " rays\n";
  }
  const AnyAccel accel = build_accel(accel_name, loaded.triangles);
  const AccelStats accel_stats_ = accel_stats(accel);

  AoOptions ao;
  ao.spp = o.spp;
  ao.ao_rays = o.ao_rays;
  ao.max_distance = static_cast<float>(o.max_distance);
  ao.seed = o.seed;
  ao.progress = !o.no_progress;
  RenderStats stats;
  const Image image = std::visit([&](const auto& a) { return render_ao(a, loaded.scene, camera, ao, &stats); }, accel);
  write_image(o.out, image);

  std::cout << "wrote " << std::filesystem::absolute(o.out).string() << "\n";
  std::cout << "render: " << loaded.triangles.size() << " triangles, accel " << accel_name << " (build "
            << accel_stats_.build_ms << " ms, " << format_bytes(accel_stats_.memory_bytes) << "), "
            << limit.threads() << " threads, spp " << o.spp << ", " << o.ao_rays << " AO rays: " << stats.summary()
            << "\n";
  return 0;
}

}  // namespace

void register_render_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render an image (ambient occlusion) of a mesh, scene file or builtin:NAME");
  add_scene_argument(*cmd, options->scene);
  cmd->add_option("--integrator", options->integrator, "Integrator")->check(CLI::IsMember({"ao"}))->capture_default_str();
  std::vector<std::string> accels = accel_names();
  accels.push_back("auto");
  cmd->add_option("--accel", options->accel, "Acceleration structure (auto: grid or kd-tree, chosen for --rays)")
      ->check(CLI::IsMember(accels))
      ->capture_default_str();
  cmd->add_option("--rays", options->expected_rays, "With --accel auto: expected ray count (default: this render's)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 50));
  cmd->add_option("--calibration", options->calibration, "With --accel auto: calibration file from `visfield calibrate`");
  cmd->add_option("--spp", options->spp, "Camera samples per pixel")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--ao-rays", options->ao_rays, "AO rays per camera sample")->check(CLI::Range(1, 65536))->capture_default_str();
  cmd->add_option("--max-distance", options->max_distance, "AO ray length (world units; default unlimited)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--width", options->width, "Image width in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--height", options->height, "Image height in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  add_threads_option(*cmd, options->threads);
  cmd->add_option("--seed", options->seed, "Random seed (the image depends on it, not on the thread count)")->capture_default_str();
  cmd->add_option("-o,--out", options->out, "Output image (.png 8-bit sRGB or .exr float)")->capture_default_str();
  cmd->add_flag("--no-progress", options->no_progress, "Do not draw the progress bar");
  cmd->callback([options, &action] {
    if (!std::isnan(options->max_distance) && options->max_distance <= 0.0)
      throw CLI::ValidationError("--max-distance", "must be > 0");
    action = [options] { return run_render(*options); };
  });
}

}  // namespace vf::cli
