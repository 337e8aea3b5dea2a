#pragma once
/// \file Batch queries for any Accelerator: many rays at once, parallel over TBB's threads.

#include <cstdint>
#include <optional>
#include <span>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "visfield/accel/accelerator.hpp"

namespace vf {

/// hits[i] = closest hit of rays[i] (prim == kInvalidId on a miss). Spans must have equal sizes.
/// Deterministic: each output depends only on its ray.
template <Accelerator A>
void intersect_batch(const A& accel, std::span<const Ray> rays, std::span<Hit> hits) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) hits[i] = accel.intersect(rays[i]).value_or(Hit{});
  });
}

/// occluded[i] = 1 when rays[i] hits anything in [tmin, tmax], else 0. Spans must have equal sizes.
template <Accelerator A>
void occluded_batch(const A& accel, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) occluded[i] = accel.occluded(rays[i]) ? 1 : 0;
  });
}

}  // namespace vf
