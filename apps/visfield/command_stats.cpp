#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/accel/grid_stats.hpp"
#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::cli {

namespace {

struct StatsOptions {
  std::string scene;
  std::string accel = "grid";
  int threads = 0;
};

int run_stats(const StatsOptions& o) {
  ThreadLimit limit(o.threads);
  const LoadedScene loaded = load_and_flatten(o.scene);
  const UniformGrid grid = UniformGrid::build(loaded.triangles);
  const GridStatistics g = compute_grid_statistics(grid);
  const AccelStats& s = grid.stats();
  const auto& r = grid.resolution();
  std::cout << "scene:              " << o.scene << " (" << loaded.triangles.size() << " triangles)\n"
            << "grid:               " << r[0] << " x " << r[1] << " x " << r[2] << " = " << g.cell_count << " cells\n"
            << "  build:            " << s.build_ms << " ms (" << limit.threads() << " threads)\n"
            << "  memory:           " << format_bytes(s.memory_bytes) << " (" << s.memory_bytes << " bytes)\n"
            << "  references:       " << s.reference_count << "\n"
            << "  empty cells:      " << g.empty_cells << "\n"
            << "  sparseness:       " << g.sparseness << "\n"
            << "  maxRefs:          " << g.max_refs << "\n"
            << "  mean:             " << g.mean << "\n"
            << "  variance:         " << g.variance << "\n"
            << "  std dev:          " << g.std_dev << "\n"
            << "  skewness:         " << g.skewness << "\n"
            << "  kurtosis:         " << g.kurtosis << "\n";
  return 0;
}

}  // namespace

void register_stats_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<StatsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "stats", "Print a structure's statistics (grid: sparseness, maxRefs, mean, variance, std dev, skewness, kurtosis)");
  add_scene_argument(*cmd, options->scene);
  cmd->add_option("--accel", options->accel, "Structure to analyse")->check(CLI::IsMember({"grid"}))->capture_default_str();
  add_threads_option(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_stats(*options); }; });
}

}  // namespace vf::cli
