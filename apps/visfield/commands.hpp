#pragma once
/// \file The visfield subcommands; each registers its options and, when chosen, sets the action.

#include <functional>

#include <CLI/CLI.hpp>

namespace vf::cli {

/// What main() runs after parsing: returns the process exit code; may throw vf::Error.
using Action = std::function<int()>;

/// `visfield render <scene> ...`: an ambient-occlusion image with the chosen structures.
void register_render_command(CLI::App& app, Action& action);
/// `visfield walk`: a walkthrough rendered frame by frame, its times as CSV and a plot.
void register_walk_command(CLI::App& app, Action& action);
/// `visfield info <scene> ...`: counts, bounds, degenerate triangles and the built structure's memory.
void register_info_command(CLI::App& app, Action& action);
/// `visfield calibrate <scenes...> -o FILE`: measure grid and kd-tree, write the selection constants.
void register_calibrate_command(CLI::App& app, Action& action);
/// `visfield select <scene> --rays R`: grid or kd-tree for a workload of R rays, with every quantity.
void register_select_command(CLI::App& app, Action& action);
/// `visfield stats <scene> [--grid grid:...]`: the grid's statistics, resolution and memory.
void register_stats_command(CLI::App& app, Action& action);
/// `visfield report`: the grids-vs-hierarchies evaluation as markdown.
void register_report_command(CLI::App& app, Action& action);
/// `visfield structures`: the registry's structures, their metadata and parameters.
void register_structures_command(CLI::App& app, Action& action);

/// `visfield field build <mesh> -o F.vfield` and `visfield field info F.vfield`: ObjectField files.
void register_field_command(CLI::App& app, Action& action);

/// `visfield compare IMAGE REFERENCE [--diff F]`: RMS, max error, PSNR and an error image.
void register_compare_command(CLI::App& app, Action& action);

}  // namespace vf::cli
