#pragma once
/// \file The ObjectField papers' experiments, reproduced on this machine: `visfield-experiments --figure
/// NAME --scene CASTER`. Each prints a markdown table: what we measured, beside the paper's numbers
/// where the paper gives them.

#include <ostream>
#include <string>
#include <vector>

namespace vf::experiments {

/// The figures --figure accepts: "fig6" (positional x directional resolution: precompute, AO time,
/// RMS; also the GPU paper's 16642-position row), "fig5" (mappings and the 1-bit variant of
/// Figure 7 at equal memory), "fig8" (cow, bunny, Igea, dragon, Armadillo and three of them
/// together: exact and field AO times, precompute, RMS; --scene is then the models' folder),
/// "lookups" (nearest, bilinear, blend and both at equal memory: inter- and intra-object error
/// and time per query, which set the defaults), "gpu3" (the GPU paper's Figure 3: AO of a ground
/// under the caster, image RMS at {1090, 4226, 16642} x {32^2, 64^2, 128^2}).
std::vector<std::string> field_figure_names();

/// Runs figure `name` with `caster_path` (a mesh file, the papers use the Stanford bunny; for fig8
/// the folder of the models) placed in the Figure-6 corner, and prints its table to `out`. Throws
/// vf::Error on a bad mesh.
void run_field_figure(const std::string& name, const std::string& caster_path, std::ostream& out);

}  // namespace vf::experiments
