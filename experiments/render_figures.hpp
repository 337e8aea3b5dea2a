#pragma once
/// \file The GPU visibility-fields paper's ray-tracing figures reproduced on the CPU with visfield's
/// integrators: `visfield-experiments --figure gpu7|gpu8|gpu9 --scene ...`. Each renders the same view with
/// field occluders and with the exact BVH and prints a markdown table: render time, field memory, and
/// RMS (0-255, all pixels, values clamped to [0, 1]) against the exact reference.

#include <ostream>
#include <string>
#include <vector>

namespace vf::experiments {

/// "gpu7" (soft shadows of the caster on a ground, 3 sphere lights, 20 shadow rays, fields at
/// {4226, 16642} x {32^2, 64^2, 128^2} against an exact 256-ray reference), "gpu8" (three models of a
/// folder together under 3 sphere lights: field and exact times and RMS) and "gpu9" (glossy
/// reflections of a model on a polished floor, 4 rays per reflective pixel, normal fields).
std::vector<std::string> render_figure_names();

/// Runs render figure `name` with `scene_path` (gpu7, gpu9: a mesh file; gpu8: a folder holding
/// bun_zipper.ply, dragon_vrip_res2.ply and Armadillo.ply) and prints its table to `out`; with
/// `images` (a folder, "" = none) every rendered image goes there as NAME-WHAT.png, so each RMS can
/// be checked with `visfield compare`. Throws vf::Error on a bad mesh or folder.
void run_render_figure(const std::string& name, const std::string& scene_path, const std::string& images, std::ostream& out);

}  // namespace vf::experiments
