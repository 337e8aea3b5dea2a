#pragma once
/// \file Where the shared test meshes are: the environment's VISFIELD_MODELS_DIR when it is set (a
/// prebuilt test binary run on another machine, as the GPU bundle's), else the folder configured at
/// build time. A test that needs a mesh skips when it is absent, unless the environment sets
/// VISFIELD_REQUIRE_MODELS=1 (CI, where the meshes are there): then it fails.

#include <cstdlib>
#include <filesystem>
#include <string>

namespace vf::test {

/// The shared meshes' folder (it may not exist).
inline std::filesystem::path models_dir() {
  const char* override_dir = std::getenv("VISFIELD_MODELS_DIR");
  return override_dir && *override_dir ? std::filesystem::path(override_dir) : std::filesystem::path(VISFIELD_MODELS_DIR);
}

/// Whether the environment sets VISFIELD_REQUIRE_MODELS=1.
inline bool models_required() {
  const char* value = std::getenv("VISFIELD_REQUIRE_MODELS");
  return value != nullptr && std::string(value) == "1";
}

}  // namespace vf::test

/// Skips the test when `present` is false ("WHAT is not in the models folder"), or fails it under
/// VISFIELD_REQUIRE_MODELS=1.
#define VF_SKIP_WITHOUT_MODELS(present, what)                                                                   \
  do {                                                                                                          \
    if (!(present)) {                                                                                           \
      if (::vf::test::models_required())                                                                        \
        FAIL() << (what) << " is not in " << ::vf::test::models_dir() << " (VISFIELD_REQUIRE_MODELS=1)";          \
      GTEST_SKIP() << (what) << " is not in " << ::vf::test::models_dir();                                      \
    }                                                                                                           \
  } while (0)
