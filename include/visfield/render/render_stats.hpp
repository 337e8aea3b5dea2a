#pragma once
/// \file What a render reports: resolution, rays traced by kind, time.

#include <cstdint>
#include <string>

namespace vf {

/// Rays a render traced, by what they were for. Plain value; sums are order-independent integers.
struct RayCounts {
  std::uint64_t camera = 0;      ///< Primary rays from the camera.
  std::uint64_t shadow = 0;      ///< Rays towards a light (point, sphere or emitting surface).
  std::uint64_t reflection = 0;  ///< Reflected, refracted and path-bounce rays (closest-hit queries after the camera's).
  std::uint64_t ao = 0;          ///< Ambient-occlusion rays.

  /// Every ray of every kind.
  constexpr std::uint64_t total() const { return camera + shadow + reflection + ao; }
  /// Adds `o`'s counts kind by kind.
  constexpr RayCounts& operator+=(const RayCounts& o) {
    camera += o.camera, shadow += o.shadow, reflection += o.reflection, ao += o.ao;
    return *this;
  }
};

/// Counts of one render; rays = primary + secondary rays actually traced.
struct RenderStats {
  int width = 0;           ///< Image width in pixels.
  int height = 0;          ///< Image height in pixels.
  RayCounts by_kind;       ///< The rays, by kind.
  std::uint64_t rays = 0;  ///< Every ray traced (by_kind.total()).
  double seconds = 0.0;    ///< Wall-clock time of the render.
  /// Millions of rays per second (0 when no time was measured).
  double mrays_per_s() const { return seconds > 0.0 ? static_cast<double>(rays) / seconds * 1e-6 : 0.0; }
  /// "512x512, 16.8M rays (camera 262k, shadow 0, reflection 0, AO 16.5M), 1.23 s, 13.7 Mrays/s".
  std::string summary() const;
};

}  // namespace vf
