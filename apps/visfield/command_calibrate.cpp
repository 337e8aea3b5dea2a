#include <filesystem>
#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "select_cli_support.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/select/calibrate.hpp"

namespace vf::cli {

namespace {

struct CalibrateOptions {
  std::vector<std::string> scenes;
  std::string out;
  MeasureFlags measure;
  int threads = 0;
};

int run_calibrate(const CalibrateOptions& o) {
  o.measure.options();  // bad flags fail before any scene loads
  check_writable(o.out);
  ThreadLimit limit(o.threads);
  std::vector<NamedScene> scenes;
  for (const std::string& spec : o.scenes) scenes.push_back(load_named(spec));
  const Calibration calibration = calibrate_with_progress(scenes, o.measure);
  save_calibration(o.out, calibration);
  const CalibrationConstants& c = calibration.constants;
  std::cout << "constants: C_B " << c.build_ms_per_n_log2_n << " ms per N log2 N, C_R " << c.ray_us(RayKind::random)
            << " us (random) " << c.ray_us(RayKind::path) << " us (path) per log2 N, " << limit.threads() << " threads\n"
            << "wrote " << std::filesystem::absolute(o.out).string() << "\n";
  return 0;
}

}  // namespace

void register_calibrate_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Measure every structure's builds, ray times per kind, updates and field errors on a set of scenes; write the planner's constants");
  cmd->add_option("scenes", options->scenes, "Mesh files, scene .json files or builtin:NAME[:size=N,seed=S]")->required();
  cmd->add_option("-o,--out", options->out, "Calibration file to write (JSON)")->required();
  add_measure_flags(*cmd, options->measure);
  add_resource_options(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_calibrate(*options); }; });
}

}  // namespace vf::cli
