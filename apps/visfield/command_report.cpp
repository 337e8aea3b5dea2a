#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_support.hpp"
#include "commands.hpp"
#include "select_cli_support.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/scenes/builtin.hpp"
#include "visfield/select/calibrate.hpp"
#include "visfield/select/report.hpp"

namespace vf::cli {

namespace {

struct ReportCommandOptions {
  std::string models;
  std::vector<std::string> scenes;
  bool no_builtin = false;
  std::string from;
  std::string save_measurements;
  std::string out = "report.md";
  MeasureFlags measure;
  std::size_t splits = 20;
  std::uint64_t split_seed = 1;
  int threads = 0;
};

// Mesh files of `folder` that load_scene reads, sorted by name.
std::vector<std::string> model_files(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw Error(folder + ": --models folder does not exist");
  std::vector<std::string> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (entry.is_regular_file() && (ext == ".obj" || ext == ".ply" || ext == ".gltf" || ext == ".glb" || ext == ".stl"))
      files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw Error(folder + ": no mesh files (.obj, .ply, .gltf, .glb, .stl) in the --models folder");
  return files;
}

std::vector<std::string> scene_specs(const ReportCommandOptions& o) {
  std::vector<std::string> specs;
  if (!o.models.empty()) specs = model_files(o.models);
  if (!o.no_builtin)
    for (const std::string& name : builtin_scene_names()) specs.push_back("builtin:" + name);
  specs.insert(specs.end(), o.scenes.begin(), o.scenes.end());
  if (specs.size() < 2) throw Error("report: needs at least 2 scenes, got " + std::to_string(specs.size()));
  return specs;
}

// The command that reproduces the report: every option that shapes it, defaults included, with the
// thread count that was in force (so `--threads 0` is quoted as the count it meant).
std::string command_line(const ReportCommandOptions& o, int threads) {
  std::ostringstream s;
  s << "visfield report";
  if (!o.from.empty()) {
    s << " --from " << o.from;
  } else {
    if (!o.models.empty()) s << " --models " << o.models;
    for (const std::string& scene : o.scenes) s << " --scene " << scene;
    if (o.no_builtin) s << " --no-builtin";
    s << " --rays " << static_cast<std::uint64_t>(o.measure.rays) << " --sample-rays "
      << static_cast<std::uint64_t>(o.measure.sample_rays) << " --build-repetitions " << o.measure.build_repetitions
      << " --bounces " << o.measure.bounces << " --seed " << o.measure.seed << (o.measure.no_plan ? " --no-plan" : "")
      << " --threads " << threads;
    // The memory limit decides which candidates are measured (a BeamField over it is left out).
    const MemoryLimit limit = memory_limit();
    if (limit.source.rfind("--max-memory ", 0) == 0) s << " --max-memory " << static_cast<std::uint64_t>(limit.bytes);
    if (!o.save_measurements.empty()) s << " --save-measurements " << o.save_measurements;
  }
  s << " --splits " << o.splits << " --split-seed " << o.split_seed << " --out " << o.out;
  return s.str();
}

int run_report(const ReportCommandOptions& o) {
  check_writable(o.out);
  if (!o.save_measurements.empty()) check_writable(o.save_measurements);
  ThreadLimit limit(o.threads);
  Calibration measured;
  if (!o.from.empty()) {
    measured = load_calibration(o.from);
  } else {
    o.measure.options();
    std::vector<NamedScene> scenes;
    for (const std::string& spec : scene_specs(o)) scenes.push_back(load_named(spec));
    measured = calibrate_with_progress(scenes, o.measure);
    if (!o.save_measurements.empty()) {
      save_calibration(o.save_measurements, measured);
      std::cout << "wrote " << std::filesystem::absolute(o.save_measurements).string() << "\n";
    }
  }
  ReportOptions report;
  report.splits = o.splits;
  report.seed = o.split_seed;
  report.command = command_line(o, limit.threads());
  const std::string markdown = report_markdown(measured, report);
  write_atomically(o.out, [&](const std::filesystem::path& tmp) { write_file_bytes(tmp, markdown); });
  std::cout << "wrote " << std::filesystem::absolute(o.out).string() << "\n";
  return 0;
}

}  // namespace

void register_report_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<ReportCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "report", "Measure grid and kd-tree on many scenes; write the paper's Table 1, leave-k-out and decision accuracy (markdown)");
  CLI::Option* models = cmd->add_option("--models", options->models, "Folder whose mesh files (.obj .ply .gltf .glb .stl) are measured");
  CLI::Option* scenes = cmd->add_option("--scene", options->scenes, "Further scene to measure (repeatable)");
  CLI::Option* no_builtin =
      cmd->add_flag("--no-builtin", options->no_builtin, "Leave out the built-in scenes (soup, stadium, sphere, boxes, cornell)");
  CLI::Option* save = cmd->add_option("--save-measurements", options->save_measurements, "Also write the measurements as a calibration file");
  cmd->add_option("--from", options->from, "Report on the measurements of this calibration file instead of measuring")
      ->excludes(models)
      ->excludes(scenes)
      ->excludes(no_builtin)
      ->excludes(save);
  cmd->add_option("-o,--out", options->out, "Markdown file to write")->capture_default_str();
  add_measure_flags(*cmd, options->measure);
  cmd->add_option("--splits", options->splits, "Random splits per k in the leave-k-out experiment")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--split-seed", options->split_seed, "Seed of the leave-k-out splits")->capture_default_str();
  add_resource_options(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_report(*options); }; });
}

}  // namespace vf::cli
