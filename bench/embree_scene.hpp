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

/// One Embree device and scene: either every triangle of a TriangleSet as one triangle geometry
/// (three vertices per triangle, primID = index in the set), or Embree's instancing (one scene per
/// mesh, one instance geometry per object). Built with Embree's default settings (medium build
/// quality, no scene flags), as a typical user would. Queries are const and thread-safe
/// (rtcIntersect1 / rtcOccluded1 with a default intersect context). Move-only.
class EmbreeScene {
 public:
  /// Builds over `set`; `threads` > 0 caps Embree's build threads (0 = TBB's limit). stats().build_ms
  /// times geometry upload plus rtcCommitScene; stats().memory_bytes is what Embree's device
  /// allocated (memory monitor callback) plus the (prim, instance) table that maps hits back.
  /// Throws vf::Error when Embree reports an error.
  static EmbreeScene build(const TriangleSet& set, int threads = 0);
  /// Builds with Embree's instancing over `scene`'s objects: each mesh some object uses becomes an
  /// Embree scene of its object-space triangles (zero-area ones left out, as mesh_triangles does),
  /// each object an instance geometry with its transform. Statistics as for build().
  static EmbreeScene build_instanced(const Scene& scene, int threads = 0);
  EmbreeScene(EmbreeScene&&) noexcept;
  EmbreeScene& operator=(EmbreeScene&&) noexcept;
  ~EmbreeScene();

  /// Closest hit in [tmin, tmax] (rtcIntersect1); u, v and the normal are Embree's.
  Hit intersect(const Ray& ray) const;
  /// True when anything is hit in [tmin, tmax] (rtcOccluded1).
  bool occluded(const Ray& ray) const;
  /// Makes occluded_batch() trace the rays 16 at a time with rtcOccluded16 under a coherent
  /// context (Embree's ray packets, which suit parallel rays: AO along one line), or one at a time
  /// with rtcOccluded1 (packet = 1, the default). Throws vf::Error for other sizes, or 16 when this
  /// Embree was built without 16-wide packets.
  void set_packet_size(int packet);
  /// 1 or 16 (set_packet_size).
  int packet_size() const;
  /// Build statistics: build_ms and memory_bytes only (Embree does not expose its tree shape).
  const AccelStats& stats() const;
  /// The --accel name, "embree".
  static std::string name() { return "embree"; }
  static constexpr Exactness exactness = Exactness::exact;

  friend void occluded_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

 private:
  explicit EmbreeScene(std::unique_ptr<EmbreeLayout> layout);
  std::unique_ptr<EmbreeLayout> layout_;
};

/// occluded[i] = 1 when rays[i] is blocked, in parallel: one ray at a time (rtcOccluded1), or with
/// packet_size() 16 in consecutive packets of 16 (rtcOccluded16, coherent context). Same answers.
void occluded_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// "Embree 3.13.5, ISA avx512, TBB tasking, build quality medium (default)": the library version
/// (from the device), the instruction set its CPU dispatch picks on this machine (best of the ISAs
/// the library was compiled for that the CPU supports) and the settings EmbreeScene uses.
std::string embree_description();

}  // namespace vf::bench
