#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include "cli_support.hpp"
#include "commands.hpp"
#include "select_cli_support.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/select/decision.hpp"

namespace vf::cli {

namespace {

struct SelectCommandOptions {
  std::string scene;
  double rays = 0;
  std::string calibration;
  std::string kind = "path";
  double sample_rays = 500;
  std::uint64_t seed = 1;
  int threads = 0;
};

std::string rays_text(double rays) {
  if (std::isinf(rays)) return "infinite (the grid is never slower per ray)";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.0f", rays);
  return buffer;
}

int run_select(const SelectCommandOptions& o) {
  const std::uint64_t rays = ray_count(o.rays, "--rays");
  SelectOptions options;
  options.sample_rays = ray_count(o.sample_rays, "--sample-rays");
  options.seed = o.seed;
  validate_select_options(options);
  const Calibration calibration = o.calibration.empty() ? builtin_calibration() : load_calibration(o.calibration);
  ThreadLimit limit(o.threads);
  if (!o.calibration.empty()) require_calibration_for(calibration, this_machine(limit.threads()), o.calibration);
  const NamedScene loaded = load_named(o.scene);
  const RayKind kind = *parse_ray_kind(o.kind);
  const Selection s = select_structure(loaded.scene, loaded.triangles, rays, calibration, kind, options);
  const GridStatistics& g = s.grid_statistics;
  std::cout << "scene:              " << o.scene << "\n"
            << "calibration:        " << (o.calibration.empty() ? "built in" : o.calibration) << " ("
            << calibration.machine.cpu_model << ", " << calibration.machine.threads << " threads)\n"
            << "triangles N:        " << s.triangles << "\n"
            << "grid:               " << s.grid_resolution[0] << " x " << s.grid_resolution[1] << " x " << s.grid_resolution[2]
            << " cells, " << format_bytes(static_cast<double>(s.grid_memory_bytes)) << "\n"
            << "grid statistics:    sparseness " << g.sparseness << ", maxRefs " << g.max_refs << ", mean " << g.mean
            << ", variance " << g.variance << ", std dev " << g.std_dev << ", skewness " << g.skewness << ", kurtosis "
            << g.kurtosis << "\n"
            << "T_B^G (measured):   " << s.grid_build_ms << " ms\n"
            << "t_R^G (sampled):    " << s.grid_ray_us << " us per ray (" << s.sample_count << " " << ray_kind_name(kind)
            << " rays, " << limit.threads() << " threads)\n"
            << "T_B^H (estimated):  " << s.tree_build_ms << " ms\n"
            << "t_R^H (estimated):  " << s.tree_ray_us << " us per ray\n"
            << "R_C:                " << rays_text(s.critical_rays) << "\n"
            << "R:                  " << s.rays << " rays\n"
            << "estimated totals:   grid " << s.grid_total_ms << " ms, kdtree " << s.tree_total_ms << " ms (build included)\n"
            << "decision:           " << s.structure << "\n";
  return 0;
}

}  // namespace

void register_select_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<SelectCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "select", "Choose between the uniform grid and the SAH kd-tree for a workload of R rays (build, sample, estimate R_C)");
  add_scene_argument(*cmd, options->scene);
  cmd->add_option("--rays", options->rays, "R: rays the workload will trace")->check(number_in(0.0, 1e15))->required();
  cmd->add_option("--calibration", options->calibration, "Calibration file from `visfield calibrate` (default: built in)");
  cmd->add_option("--kind", options->kind, "Kind of the workload's rays")
      ->check(CLI::IsMember({"random", "path"}))
      ->capture_default_str();
  cmd->add_option("--sample-rays", options->sample_rays, "S: sample rays timed through the grid")
      ->check(number_in(5.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "Seed of the sample rays")->capture_default_str();
  add_resource_options(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_select(*options); }; });
}

}  // namespace vf::cli
