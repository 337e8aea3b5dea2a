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
};

int run_render(const RenderOptions& o) {
  check_image_extension(o.out);
  ThreadLimit limit(o.threads);
  LoadedScene loaded = load_and_flatten(o.scene);
  const AnyAccel accel = build_accel(o.accel, loaded.triangles);
  const AccelStats accel_stats_ = accel_stats(accel);
  const Camera camera = loaded.scene.camera_or_default(o.width, o.height);

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
  std::cout << "render: " << loaded.triangles.size() << " triangles, accel " << o.accel << " (build "
            << accel_stats_.build_ms << " ms, " << format_bytes(accel_stats_.memory_bytes) << "), "
            << limit.threads() << " threads, spp " << o.spp << ", " << o.ao_rays << " AO rays: " << stats.summary()
            << "\n";
  return 0;
}

}  // namespace

void register_render_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render an image (ambient occlusion) of a mesh, scene file or builtin:NAME");
  cmd->add_option("scene", options->scene, "Mesh file, scene .json, or builtin:NAME[:size=N,seed=S]")->required();
  cmd->add_option("--integrator", options->integrator, "Integrator")->check(CLI::IsMember({"ao"}))->capture_default_str();
  cmd->add_option("--accel", options->accel, "Acceleration structure")
      ->check(CLI::IsMember(accel_names()))
      ->capture_default_str();
  cmd->add_option("--spp", options->spp, "Camera samples per pixel")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--ao-rays", options->ao_rays, "AO rays per camera sample")->check(CLI::Range(1, 65536))->capture_default_str();
  cmd->add_option("--max-distance", options->max_distance, "AO ray length (world units; default unlimited)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--width", options->width, "Image width in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--height", options->height, "Image height in pixels (default: the scene camera's, else 512)")
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--threads", options->threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
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
