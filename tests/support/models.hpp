#pragma once
/// \file Where the shared test meshes are: the environment's VISFIELD_MODELS_DIR when it is set (a
/// prebuilt test binary run on another machine, as the GPU bundle's), else the folder configured at
/// build time. Tests that need a mesh skip when it is absent.

#include <cstdlib>
#include <filesystem>

namespace vf::test {

/// The shared meshes' folder (it may not exist).
inline std::filesystem::path models_dir() {
  const char* override_dir = std::getenv("VISFIELD_MODELS_DIR");
  return override_dir && *override_dir ? std::filesystem::path(override_dir) : std::filesystem::path(VISFIELD_MODELS_DIR);
}

}  // namespace vf::test
