#include "visfield/select/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "visfield/core/error.hpp"
#include "visfield/io/atomic_file.hpp"

namespace vf {

std::size_t calibrated_kind_index(RayKind kind) {
  for (std::size_t i = 0; i < kCalibratedKinds.size(); ++i)
    if (kCalibratedKinds[i] == kind) return i;
  throw Error("calibration: " + std::string(ray_kind_name(kind)) + " rays are not calibrated (only random and path)");
}

double cost_log2(std::uint64_t triangles) { return std::log2(static_cast<double>(std::max<std::uint64_t>(triangles, 2))); }

CalibrationConstants compute_constants(std::span<const SceneMeasurement> scenes, std::span<const std::size_t> subset) {
  if (subset.empty()) throw Error("calibration: no calibration scenes");
  CalibrationConstants constants;
  for (std::size_t index : subset) {
    if (index >= scenes.size())
      throw Error("calibration: scene index " + std::to_string(index) + " out of range (" + std::to_string(scenes.size()) +
                  " scenes)");
    const SceneMeasurement& scene = scenes[index];
    const double log_n = cost_log2(scene.triangles);
    constants.build_ms_per_n_log2_n += scene.tree_build_ms / (static_cast<double>(scene.triangles) * log_n);
    for (RayKind kind : kCalibratedKinds) constants.ray_us_per_log2_n[calibrated_kind_index(kind)] += scene.timings(kind).tree_us / log_n;
  }
  const double s = static_cast<double>(subset.size());
  constants.build_ms_per_n_log2_n /= s;
  for (double& c : constants.ray_us_per_log2_n) c /= s;
  return constants;
}

CalibrationConstants compute_constants(std::span<const SceneMeasurement> scenes) {
  std::vector<std::size_t> all(scenes.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  return compute_constants(scenes, all);
}

void save_calibration(const std::filesystem::path& path, const Calibration& calibration) {
  const std::string text = calibration_to_json(calibration) + "\n";
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_file_bytes(tmp, text); });
}


}  // namespace vf
