// Fuzz target: the scene JSON reader, through the file it reads (written to a private temporary
// folder, beside a small valid mesh that scene files may name as "tetra.obj").

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/io/scene_file.hpp"

namespace {

// A folder of this process's own, removed at exit, holding the scene file and the mesh it may name.
struct WorkFolder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("visfield-fuzz-scene-" + std::to_string(::getpid()));
  WorkFolder() {
    std::filesystem::create_directories(path);
    std::ofstream(path / "tetra.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  }
  ~WorkFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const WorkFolder folder;
  const std::filesystem::path path = folder.path / "scene.json";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    vf::load_scene_file(path);
  } catch (const vf::Error&) {
  }
  return 0;
}
