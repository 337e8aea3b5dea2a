#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "integrator_options.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/registry/walk_structures.hpp"
#include "visfield/render/progress.hpp"

namespace vf::cli {

namespace {

struct WalkCommandOptions {
  std::string scene;
  IntegratorOptions shading;
  int frames = 60;
  int width = 256;
  int height = 256;
  std::string csv = "walk.csv";
  std::string plot;                   // "" = no plot
  std::vector<std::string> plot_with;  // other runs' CSVs drawn on the same plot
  std::string frames_dir;             // "" = frame images are not kept
  int threads = 0;
  bool no_progress = false;
};

std::string formatted_ms(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f ms", ms);
  return text;
}

int run_walk(const WalkCommandOptions& o) {
  // Everything that can be refused is checked before the first frame.
  check_writable(o.csv);
  if (!o.plot.empty()) check_walk_plot_path(o.plot);
  std::vector<WalkSeries> others;
  for (const std::string& path : o.plot_with) others.push_back(read_walk_csv(path));
  if (!o.frames_dir.empty() && !std::filesystem::is_directory(o.frames_dir))
    throw Error(o.frames_dir + ": --frames-dir must be an existing folder");
  ThreadLimit limit(o.threads);
  Scene scene = load_scene_argument(o.scene);
  if (scene.animation.empty())
    throw Error(o.scene + ": the scene has no \"camera_path\" and no object \"keyframes\"; nothing to walk through");
  const std::uint64_t rays_per_frame = static_cast<std::uint64_t>(o.width) * static_cast<std::uint64_t>(o.height) *
                                       static_cast<std::uint64_t>(o.shading.settings.spp) * (1u + rays_per_hit(o.shading, scene));
  const BuildContext context{rays_per_frame * static_cast<std::uint64_t>(o.frames), !o.no_progress};
  std::string occluder = occluder_spec(o.shading, scene);
  if (occluder == o.shading.accel) occluder.clear();
  RegistryWalkStructures structures(scene, o.shading.accel, occluder, context);

  WalkOptions walk;
  walk.frames = o.frames;
  walk.integrator = integrator_of(o.shading);
  walk.shading = shading_options(o.shading, false);
  walk.ao = ao_options(o.shading, false);
  walk.width = o.width;
  walk.height = o.height;
  ProgressBar bar("walk", static_cast<std::size_t>(o.frames), !o.no_progress);
  walk.on_frame = [&](int frame, const Image& image) {
    if (!o.frames_dir.empty()) {
      char name[32];
      std::snprintf(name, sizeof name, "frame-%05d.png", frame);
      write_image(std::filesystem::path(o.frames_dir) / name, image);
    }
    bar.tick();
  };
  WalkSeries series{structures.label(), render_walkthrough(scene, structures, walk)};
  bar.finish();
  write_walk_csv(o.csv, series);
  std::cout << "wrote " << std::filesystem::absolute(o.csv).string() << "\n";
  if (!o.plot.empty()) {
    others.insert(others.begin(), series);
    write_walk_plot(o.plot, others);
    std::cout << "wrote " << std::filesystem::absolute(o.plot).string() << "\n";
  }
  std::vector<double> update, trace;
  std::uint64_t rays = 0;
  int rebuilds = 0;
  for (const WalkFrame& f : series.frames) {
    update.push_back(f.update_ms);
    trace.push_back(f.trace_ms);
    rays += f.rays;
    rebuilds += f.rebuilt ? 1 : 0;
  }
  double trace_total = 0.0;
  for (double t : trace) trace_total += t;
  std::cout << "walk: " << o.frames << " frames of " << o.width << "x" << o.height << ", " << series.label << ", "
            << limit.threads() << " threads, " << integrator_summary(o.shading) << ": median update "
            << formatted_ms(median(update)) << " (" << rebuilds << " rebuilds), median trace " << formatted_ms(median(trace))
            << ", " << rays << " rays, " << (trace_total > 0.0 ? static_cast<double>(rays) / trace_total * 1e-3 : 0.0)
            << " Mrays/s\n";
  return 0;
}

}  // namespace

void register_walk_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<WalkCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "walk", "Render a scene's walkthrough (its \"camera_path\" and objects' \"keyframes\") frame by frame, timing each "
              "frame's structure update and render; write the times as CSV and plot them");
  add_scene_argument(*cmd, options->scene);
  add_integrator_options(*cmd, options->shading, "raycast");
  cmd->add_option("--frames", options->frames, "Frames, spread evenly over the animation's keys")
      ->check(CLI::Range(2, 1000000))
      ->capture_default_str();
  cmd->add_option("--width", options->width, "Frame width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", options->height, "Frame height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--csv", options->csv, "Per-frame times: frame,update_ms,trace_ms,rays,rebuilt")->capture_default_str();
  cmd->add_option("--plot", options->plot, "Plot of the frame times (.svg), like the VLF-RT paper's Figure 6");
  cmd->add_option("--plot-with", options->plot_with, "Other runs' --csv files to draw on the same plot")->check(CLI::ExistingFile);
  cmd->add_option("--frames-dir", options->frames_dir, "Folder to keep every frame in as frame-NNNNN.png");
  add_resource_options(*cmd, options->threads);
  cmd->add_flag("--no-progress", options->no_progress, "Do not draw the progress bar");
  cmd->callback([options, &action, cmd] {
    check_integrator_options(*cmd, options->shading);
    if (!options->plot_with.empty() && options->plot.empty())
      throw CLI::ValidationError("--plot-with", "needs --plot");
    action = [options] { return run_walk(*options); };
  });
}

}  // namespace vf::cli
