#pragma once
/// \file Scene JSON files (format documented in README.md) and the one entry point that turns a
/// user's scene argument (JSON file, mesh file or builtin:NAME[:key=value,...]) into a Scene.

#include <filesystem>
#include <string>

#include "visfield/core/scene.hpp"

namespace vf {

/// Parses a scene JSON file; mesh paths are relative to the file's folder. Throws vf::Error naming
/// the file and the JSON field (e.g. "scene.json: instances[2].scale: expected a number > 0").
Scene load_scene_file(const std::filesystem::path& path);

/// Loads what a user named: "builtin:NAME[:key=value,...]" (see scenes/builtin.hpp), a *.json scene
/// file, or any mesh file Assimp reads (one identity instance). Throws vf::Error on bad input.
Scene load_scene(const std::string& spec);

}  // namespace vf
