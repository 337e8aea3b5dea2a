#pragma once
/// \file Embree 3 behind the Accelerator concept, so visfield-bench runs it exactly like our own
/// structures. Compiled only when VISFIELD_HAVE_EMBREE is 1.

#include <memory>
#include <optional>
#include <string>

#include "visfield/accel/accelerator.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::bench {

/// One Embree device and scene holding every triangle of a TriangleSet as one triangle geometry
/// (three vertices per triangle, primID = index in the set). Built with Embree's default settings
/// (medium build quality, no scene flags), as a typical user would. Queries are const and
/// thread-safe (rtcIntersect1 / rtcOccluded1 with a default intersect context). Move-only.
class EmbreeScene {
 public:
  /// Builds over `set`; `threads` > 0 caps Embree's build threads (0 = TBB's limit). stats().build_ms
  /// times geometry upload plus rtcCommitScene; stats().memory_bytes is what Embree's device
  /// allocated (memory monitor callback) plus the (prim, instance) table that maps hits back.
  /// Throws vf::Error when Embree reports an error.
  static EmbreeScene build(const TriangleSet& set, int threads = 0);
  EmbreeScene(EmbreeScene&&) noexcept;
  EmbreeScene& operator=(EmbreeScene&&) noexcept;
  ~EmbreeScene();

  /// Closest hit in [tmin, tmax] (rtcIntersect1); u, v are Embree's barycentrics.
  std::optional<Hit> intersect(const Ray& ray) const;
  /// True when anything is hit in [tmin, tmax] (rtcOccluded1).
  bool occluded(const Ray& ray) const;
  /// Build statistics: build_ms and memory_bytes only (Embree does not expose its tree shape).
  const AccelStats& stats() const;
  /// The --accel name, "embree".
  static std::string name() { return "embree"; }

  struct Impl;

 private:
  explicit EmbreeScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// "Embree 3.13.5, ISA avx512, TBB tasking, build quality medium (default)": the library version
/// (from the device), the instruction set its CPU dispatch picks on this machine (best of the ISAs
/// the library was compiled for that the CPU supports) and the settings EmbreeScene uses.
std::string embree_description();

}  // namespace vf::bench
