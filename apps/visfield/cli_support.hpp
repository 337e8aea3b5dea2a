#pragma once
/// \file Shared pieces of the visfield subcommands: loading with warnings, validators, messages.

#include <string>

#include <CLI/CLI.hpp>

#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::cli {

/// Loads the scene a user named (file, .json or builtin:...) and flattens it, printing a warning
/// on stderr when zero-area triangles were left out. Throws vf::Error on bad input.
struct LoadedScene {
  Scene scene;
  TriangleSet triangles;
  double load_ms = 0.0;
  double flatten_ms = 0.0;
};
LoadedScene load_and_flatten(const std::string& spec);

/// Throws vf::Error unless `path` ends in .png or .exr (checked before any work is done).
void check_image_extension(const std::string& path);

/// Registers the required positional "scene" (mesh file, scene .json or builtin:NAME[:size=N,seed=S]).
void add_scene_argument(CLI::App& cmd, std::string& scene);

/// Registers --threads (0 = all cores, at most 4096).
void add_threads_option(CLI::App& cmd, int& threads);

/// "1.23 MiB"-style size.
std::string format_bytes(std::size_t bytes);

}  // namespace vf::cli
