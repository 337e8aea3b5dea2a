#pragma once
/// \file Shared pieces of the visfield subcommands: loading with warnings, validators, messages.

#include <string>

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

/// "1.23 MiB"-style size.
std::string format_bytes(std::size_t bytes);

}  // namespace vf::cli
