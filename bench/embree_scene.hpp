#pragma once
/// \file Embree 3 behind the query concepts, so visfield-bench runs it exactly like our own
/// structures. Compiled only when VISFIELD_HAVE_EMBREE is 1.

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "visfield/accel/query.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::bench {

struct EmbreeLayout;

/// How a batch calls Embree.
enum class EmbreeCall {
  one,       ///< rtcIntersect1 / rtcOccluded1 a ray at a time: what most users write.
  packet16,  ///< rtcIntersect16 / rtcOccluded16, packets of 16 consecutive rays under a coherent context (parallel rays).
  stream,    ///< rtcIntersect1M / rtcOccluded1M, streams of 256 consecutive rays (Embree's own reordering).
};

/// "1", "16" or "stream": the call's name in an `embree:call=` spec.
const char* embree_call_name(EmbreeCall call);

/// How one bench row builds and calls Embree.
struct EmbreeSettings {
  EmbreeCall call = EmbreeCall::one;
  bool high_quality = false;  ///< RTC_BUILD_QUALITY_HIGH (spatial splits) instead of Embree's default, medium.
};

/// The spec of an Embree row: "embree:levels=L", then ",call=C" and ",quality=high" where not the defaults.
std::string embree_spec(bool instanced, const EmbreeSettings& settings);

/// One Embree device and scene: either every triangle of a TriangleSet as one triangle geometry
/// (three vertices per triangle, primID = index in the set), or Embree's instancing (one scene per
/// mesh, one instance geometry per object). By default built as a typical user would (medium build
/// quality, no scene flags) and called a ray at a time; EmbreeSettings choose Embree at its best
/// (packets, streams, high quality). Batches run with flush-to-zero and denormals-are-zero set on
/// their threads, as Embree asks, and the callers' floating-point mode restored afterwards. Queries
/// are const and thread-safe. Copies share the built scene.
class EmbreeScene {
 public:
  /// Builds over `set`; `threads` > 0 caps Embree's build threads (0 = TBB's limit). stats().build_ms
  /// times geometry upload plus rtcCommitScene; stats().memory_bytes is what Embree's device holds
  /// once built (memory monitor callback: its allocations less its releases, as our structures count
  /// the bytes they keep) plus the (prim, instance) table that maps hits back. Throws vf::Error when
  /// Embree reports an error.
  static EmbreeScene build(const TriangleSet& set, int threads = 0, EmbreeSettings settings = {});
  /// Builds with Embree's instancing over `scene`'s objects: each mesh some object uses becomes an
  /// Embree scene of its object-space triangles (zero-area ones left out, as mesh_triangles does),
  /// each object an instance geometry with its transform. Statistics as for build().
  static EmbreeScene build_instanced(const Scene& scene, int threads = 0, EmbreeSettings settings = {});
  /// The same built scene, its batches through `call`.
  EmbreeScene with_call(EmbreeCall call) const;

  /// Closest hit in [tmin, tmax] (rtcIntersect1); u, v and the normal are Embree's.
  Hit intersect(const Ray& ray) const;
  /// True when anything is hit in [tmin, tmax] (rtcOccluded1).
  bool occluded(const Ray& ray) const;
  /// The settings it was built with and its batches' call.
  EmbreeSettings settings() const;
  /// Whether it holds Embree's instancing (build_instanced).
  bool instanced() const;
  /// Build statistics: build_ms and memory_bytes only (Embree does not expose its tree shape).
  const AccelStats& stats() const;
  /// The --accel name, "embree".
  static std::string name() { return "embree"; }
  static constexpr Exactness exactness = Exactness::exact;

  friend void intersect_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<Hit> hits);
  friend void occluded_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

 private:
  EmbreeScene(std::shared_ptr<const EmbreeLayout> layout, EmbreeCall call);
  std::shared_ptr<const EmbreeLayout> layout_;
  EmbreeCall call_;
};

/// hits[i] = the closest hit of rays[i], in parallel, through the settings' call (rays copied into
/// Embree's layout with vector loads and stores). The same answers whatever the call.
void intersect_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<Hit> hits);
/// occluded[i] = 1 when rays[i] is blocked, in parallel, through the settings' call. Same answers.
void occluded_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// "Embree 3.13.5, ISA AVX512, TBB tasking": the library version (from the device), the instruction
/// set Embree itself reports it chose on this machine (its verbose output) and its tasking system.
std::string embree_description();

}  // namespace vf::bench
