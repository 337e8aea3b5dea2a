#include "cli_support.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "visfield/core/error.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf::cli {

namespace {
double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

LoadedScene load_and_flatten(const std::string& spec) {
  LoadedScene out;
  auto start = std::chrono::steady_clock::now();
  out.scene = load_scene(spec);
  out.load_ms = ms_since(start);
  start = std::chrono::steady_clock::now();
  out.triangles = flatten(out.scene);
  out.flatten_ms = ms_since(start);
  if (out.triangles.degenerate_count > 0)
    std::cerr << "visfield: warning: " << spec << ": " << out.triangles.degenerate_count
              << " zero-area triangles left out of the acceleration structure\n";
  if (out.triangles.size() == 0) throw Error(spec + ": the scene has no non-degenerate triangles");
  return out;
}

void check_image_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".png" && ext != ".exr") throw Error(path + ": output must end in .png or .exr");
}

void add_scene_argument(CLI::App& cmd, std::string& scene) {
  cmd.add_option("scene", scene, "Mesh file, scene .json, or builtin:NAME[:size=N,seed=S]")->required();
}

void add_threads_option(CLI::App& cmd, int& threads) {
  cmd.add_option("--threads", threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
}

std::string format_bytes(std::size_t bytes) {
  char buffer[64];
  const double b = static_cast<double>(bytes);
  if (b >= 1024.0 * 1024.0 * 1024.0) std::snprintf(buffer, sizeof buffer, "%.2f GiB", b / (1024.0 * 1024.0 * 1024.0));
  else if (b >= 1024.0 * 1024.0) std::snprintf(buffer, sizeof buffer, "%.2f MiB", b / (1024.0 * 1024.0));
  else if (b >= 1024.0) std::snprintf(buffer, sizeof buffer, "%.1f KiB", b / 1024.0);
  else std::snprintf(buffer, sizeof buffer, "%zu B", bytes);
  return buffer;
}

}  // namespace vf::cli
