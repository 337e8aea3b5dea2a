#pragma once
/// \file The options `visfield render` and `visfield walk` share: the structures by role, the
/// integrator and its parameters. One definition, so both commands spell and check them alike.

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "visfield/core/scene.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/registry/render_scene.hpp"
#include "visfield/render/integrators.hpp"

namespace vf::cli {

/// The integrator and structure options of a rendering command.
struct IntegratorOptions {
  std::string accel = "bvh";
  std::string occluder;   ///< "" = the --accel structure answers every later ray too.
  std::string occluders;  ///< "field", "exact", or "" = as the scene marks its meshes.
  /// Each render setting's value as written (render_setting_specs(): --integrator, --spp, --ao-rays, ...).
  std::map<std::string, std::string, std::less<>> values;
  /// The render settings `values` give, read by check_integrator_options().
  RenderSettings settings;

  /// The integrator's name as written ("ao").
  const std::string& integrator() const { return values.at("integrator"); }
};

/// Adds --accel, --occluder, --occluders and an option for every render setting
/// (render_setting_specs(): --integrator, default `integrator` here, --spp, --ao-rays, ...).
void add_integrator_options(CLI::App& cmd, IntegratorOptions& options, const std::string& integrator);

/// Reads the render settings into `options.settings`; throws CLI::ValidationError when --occluders
/// and --occluder disagree, or when `cmd`'s command line gives an option the chosen integrator does
/// not use (--ao-rays with path, --shadow-rays with whitted, ...). Call from the command's callback.
void check_integrator_options(const CLI::App& cmd, IntegratorOptions& options);

/// The spec of the structure for every ray after the camera's ("" = the --accel one): --occluders
/// field asks for fields (the --occluder field spec, or the default) for every mesh the scene does
/// not mark exact, --occluders exact for exact geometry only; without either, a scene that marks
/// meshes "occluder": "field" gets fields for those.
std::string occluder_spec(const IntegratorOptions& options, const Scene& scene);

/// Adds --device cpu|cuda (default cpu): where `visfield render` traces its secondary rays.
void add_device_option(CLI::App& cmd, std::string& device);

/// Throws CLI::ValidationError (a usage error) for --device cuda in a build without CUDA ("this build
/// has no CUDA (configure with -DVISFIELD_CUDA=ON)"), or with an integrator or option the GPU path does
/// not run (it renders --integrator ao with random directions).
void check_device_option(const std::string& device, const IntegratorOptions& options);

/// The integrator the options name.
Integrator integrator_of(const IntegratorOptions& options);

/// The library's render settings from the options (`progress` as given; size and region left at their defaults).
RenderSettings render_settings(const IntegratorOptions& options, bool progress);

/// AoOptions from the options (`progress` as given).
AoOptions ao_options(const IntegratorOptions& options, bool progress);

/// ShadingOptions from the options (`progress` as given).
ShadingOptions shading_options(const IntegratorOptions& options, bool progress);

/// Rays per camera sample that hits, for the structures' expected ray count (auto's R): AO rays, or
/// what the shading integrator traces on average.
std::uint64_t rays_per_hit(const IntegratorOptions& options, const Scene& scene);

/// "64 AO rays", "AO along 513 lines", or the integrator's name, for summary lines.
std::string integrator_summary(const IntegratorOptions& options);

}  // namespace vf::cli
