#pragma once
/// \file The query roles a renderer uses, behind one non-template interface, so that integrators are
/// ordinary compiled code that names no structure: camera rays go to a closest-hit structure, and
/// every ray after the first hit (shadow, AO, reflection, refraction, path bounce) to the occlusion
/// structure, which may be the same exact structure or one that mixes fields with exact geometry.
/// One virtual call per ray or per block costs nothing next to a traversal.

#include <cstdint>
#include <span>

#include "visfield/accel/batch.hpp"
#include "visfield/accel/query.hpp"
#include "visfield/core/ray.hpp"

namespace vf {

/// The rays of a render, by role. Implementations are const and thread-safe.
class SceneQueries {
 public:
  virtual ~SceneQueries() = default;
  /// Nearest hit of a camera ray (the closest-hit role: always exact geometry in visfield's renders).
  virtual Hit intersect_camera(const Ray& ray) const = 0;
  /// Nearest hit of a secondary ray that needs the surface it reaches (reflection, refraction, path
  /// bounce): the occlusion structure's intersect, so field-represented objects answer from their
  /// distance field (and normal field where they have one: has_normal), else the closest-hit one.
  virtual Hit intersect_secondary(const Ray& ray) const = 0;
  /// Whether anything blocks `ray` (shadow and AO rays), through the occlusion structure.
  virtual bool occluded(const Ray& ray) const = 0;
  /// occluded[i] = occluded(rays[i]) ? 1 : 0 on the calling thread, through the structure's batch path
  /// when it has one (the ObjectFields' SIMD kernel). Spans of equal size.
  virtual void occluded_block(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const = 0;
  /// True when the occlusion structure traces rays along one direction line fastest all together, as
  /// one stream per line (a BeamField): render_ao along the lines then hands it each line's rays from a
  /// whole block of the image, where it traces every other structure point by point (their caches
  /// favour the rays of one point). The images are the same either way.
  virtual bool occluder_prefers_line_streams() const = 0;
};

/// SceneQueries over two built structures, held by reference (they must outlive this): `closest` for
/// camera rays, `occluder` for the rest (its intersect for secondary hits when it has one).
template <ClosestHitQuery C, OcclusionQuery O>
class QueriesOver final : public SceneQueries {
 public:
  /// Borrows both structures; they may be the same object.
  QueriesOver(const C& closest, const O& occluder) : closest_(closest), occluder_(occluder) {}
  Hit intersect_camera(const Ray& ray) const override { return closest_.intersect(ray); }
  Hit intersect_secondary(const Ray& ray) const override {
    if constexpr (ClosestHitQuery<O>) return occluder_.intersect(ray);
    else return closest_.intersect(ray);
  }
  bool occluded(const Ray& ray) const override { return occluder_.occluded(ray); }
  void occluded_block(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const override {
    using vf::occluded_block;  // the generic loop, unless the structure's own overload is found by ADL
    occluded_block(occluder_, rays, occluded);
  }
  bool occluder_prefers_line_streams() const override {
    using vf::prefers_line_streams;  // false, unless the structure's own overload is found by ADL
    return prefers_line_streams(occluder_);
  }

 private:
  const C& closest_;
  const O& occluder_;
};

}  // namespace vf
