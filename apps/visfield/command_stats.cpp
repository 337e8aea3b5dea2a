#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/accel/grid_stats.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::cli {

namespace {

int run_stats(const StructureCommandOptions& o) {
  ThreadLimit limit(o.threads);
  const Scene scene = load_scene_argument(o.scene);
  SceneGeometry geometry(scene);
  const BuiltStructure built = build_structure_for(o.structure, geometry, {}, "--grid", o.scene);
  const auto* grid = std::get_if<UniformGrid>(&built.structure);
  if (!grid) throw Error("--grid " + o.structure + ": statistics need a flattened grid (levels=1)");
  const GridStatistics g = compute_grid_statistics(*grid);
  const auto& r = grid->resolution();
  std::cout << "scene:              " << o.scene << "\n"
            << "cells:              " << r[0] << " x " << r[1] << " x " << r[2] << " = " << g.cell_count << "\n";
  print_structure(std::cout, "--grid", built, limit.threads());
  std::cout << "  empty cells:      " << g.empty_cells << "\n"
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
  auto options = std::make_shared<StructureCommandOptions>(StructureCommandOptions{.scene = "", .structure = "grid", .threads = 0});
  CLI::App* cmd = app.add_subcommand(
      "stats", "Print the uniform grid's statistics (sparseness, maxRefs, mean, variance, std dev, skewness, kurtosis)");
  add_scene_argument(*cmd, options->scene);
  add_structure_option(*cmd, "--grid", options->structure, "The grid to analyse, grid[:density=D,exact=0|1]", "grid")
      ->capture_default_str();
  add_resource_options(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_stats(*options); }; });
}

}  // namespace vf::cli
