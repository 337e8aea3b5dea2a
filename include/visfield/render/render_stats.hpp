#pragma once
/// \file What a render reports: resolution, rays traced, time.

#include <cstdint>
#include <string>

namespace vf {

/// Counts of one render; rays = primary + secondary rays actually traced.
struct RenderStats {
  int width = 0;           ///< Image width in pixels.
  int height = 0;          ///< Image height in pixels.
  std::uint64_t rays = 0;  ///< Every ray traced: primary, occlusion, shadow, ...
  double seconds = 0.0;    ///< Wall-clock time of the render.
  /// Millions of rays per second (0 when no time was measured).
  double mrays_per_s() const { return seconds > 0.0 ? static_cast<double>(rays) / seconds * 1e-6 : 0.0; }
  /// "512x512, 16.8M rays, 1.23 s, 13.7 Mrays/s".
  std::string summary() const;
};

}  // namespace vf
