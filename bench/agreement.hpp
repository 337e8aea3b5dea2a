#pragma once
/// \file Do two structures give the same answers on the same rays?

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "query_runner.hpp"
#include "visfield/core/ray.hpp"

namespace vf::bench {

/// Relative tolerance on t between two closest hits of the same ray.
inline constexpr float kRelativeTTolerance = 1e-5f;
/// Absolute tolerance on t, for hits so close to the origin that the relative one is meaningless.
inline constexpr float kAbsoluteTTolerance = 1e-6f;

/// True when two closest-hit answers for one ray agree: both miss, or both hit
/// with |ta - tb| <= max(kRelativeTTolerance * max(|ta|, |tb|), kAbsoluteTTolerance). The triangle
/// may differ (exact ties, shared edges).
bool same_closest_hit(const Hit& a, const Hit& b);

/// Rays whose closest-hit answers disagree (same_closest_hit false). Spans of equal size.
std::size_t count_hit_mismatches(std::span<const Hit> a, std::span<const Hit> b);

/// Rays whose occlusion answers differ. Spans of equal size.
std::size_t count_occlusion_mismatches(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b);

/// Mismatches between two structures' answers for the same rays and kind.
std::size_t count_mismatches(const QueryResults& a, const QueryResults& b, RayKind kind);

/// How far an approximate structure's answers are from an exact one's on the same rays.
struct ApproximateAgreement {
  double differing_fraction = 0.0;  ///< Rays whose occluded() answers (occlusion kinds) or hit/miss (others) differ.
  std::optional<double> mean_distance_error;  ///< Closest-hit kinds: mean |t - t_exact| |dir| over rays both hit.
};

/// The agreement of `approximate`'s answers with `exact`'s for the same rays and kind; `rays` gives
/// the direction lengths for the distance error.
ApproximateAgreement measure_agreement(const QueryResults& approximate, const QueryResults& exact, RayKind kind,
                                       std::span<const Ray> rays);

}  // namespace vf::bench
