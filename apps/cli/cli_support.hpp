#pragma once
/// \file Pieces every visfield subcommand and visfield-bench share: the scene argument, --threads and
/// --max-memory, structure and parameter options, loading with timing and warnings, and the printing
/// of a built structure.

#include <cstdint>
#include <iosfwd>
#include <string>

#include <CLI/CLI.hpp>

#include "visfield/core/scene.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/registry.hpp"

namespace vf::cli {

/// The options of a command that builds one structure over a scene (info, stats).
struct StructureCommandOptions {
  std::string scene;      ///< The scene argument.
  std::string structure;  ///< The structure spec.
  int threads = 0;        ///< --threads.
};

/// Registers the required positional "scene" (mesh file, scene .json or builtin:NAME[:size=N,seed=S]).
void add_scene_argument(CLI::App& cmd, std::string& scene);

/// Checks a real-valued option against [lo, hi] and prints the range as a person writes it
/// ("--rays: must be a number in [0, 1e+15], got -1"); NaN is refused.
CLI::Validator number_in(double lo, double hi);

/// Checks a real-valued option is > 0 (and not NaN); `infinity_allowed` also accepts "inf".
CLI::Validator positive_number(bool infinity_allowed);

/// Registers --KEY for a declared parameter (its key with '_' written '-'): its help and range, its
/// default, and the library's own check of a value (param_value_error: "--ao-rays: 0: expected a
/// non-negative integer in 1..65536"), so that an option and the spec key it mirrors cannot drift.
CLI::Option* add_param_option(CLI::App& cmd, const ParamSpec& param, std::string& value);

/// Registers --threads (0 = all cores, at most 4096) and --max-memory SIZE, which sets the process's
/// memory limit (vf::set_memory_limit) as soon as it is parsed; without it the limit is the memory
/// available when a build starts.
void add_resource_options(CLI::App& cmd, int& threads);

/// Registers a structure option (--accel, --occluder) whose value is checked against the registry
/// while the command line is parsed, so a bad spec fails before any loading; with `only` set, the
/// spec must name that structure.
CLI::Option* add_structure_option(CLI::App& cmd, const std::string& name, std::string& spec, const std::string& help,
                                  const std::string& only = "");

/// Loads the scene a user named; `load_ms` gets the time taken. Throws vf::Error on bad input.
Scene load_scene_argument(const std::string& spec, double* load_ms = nullptr);

/// Prints "visfield: warning: <scene>: N zero-area triangles left out of the acceleration structure"
/// on stderr when `count` > 0.
void warn_degenerate_triangles(const std::string& scene_spec, std::size_t count);

/// Builds `structure_spec` over `geometry` (option names the CLI option, for messages), warning on
/// stderr when zero-area triangles were left out. Throws vf::Error on a bad spec, a failed build, or a
/// scene with no triangle left.
BuiltStructure build_structure_for(const std::string& structure_spec, SceneGeometry& geometry, const BuildContext& context,
                                   const std::string& option, const std::string& scene_spec);

/// Prints the resolved spec and the build statistics of `built`, one "  key: value" line each.
void print_structure(std::ostream& out, const std::string& option, const BuiltStructure& built, int threads);

/// Throws vf::Error unless `path` ends in .png or .exr (checked before any work is done).
void check_image_extension(const std::string& path);

}  // namespace vf::cli
