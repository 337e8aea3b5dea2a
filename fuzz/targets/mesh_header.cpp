// Fuzz target: the checks visfield runs on a mesh file before Assimp reads it (magic bytes, the
// element counts a PLY, binary STL or GLB header declares, the nesting of a glTF's JSON). The first
// byte picks the extension, the rest is the file. Any input must pass or give a vf::Error, quickly
// and without allocating for what a header declares.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "mesh_header.hpp"
#include "visfield/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {"ply", "stl", "glb", "gltf", "obj"};
  const std::string ext = kExtensions[data[0] % 5];
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("visfield-fuzz-" + std::to_string(getpid()) + "." + ext);
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data + 1, 1, size - 1, file);
  std::fclose(file);
  try {
    vf::io_detail::check_mesh_header(path, ext);
  } catch (const vf::Error&) {
  }
  std::filesystem::remove(path);
  return 0;
}
