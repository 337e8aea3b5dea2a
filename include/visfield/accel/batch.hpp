#pragma once
/// \file Batch queries for either role: many rays at once, parallel over TBB's threads; they throw
/// vf::Interrupted on SIGINT/SIGTERM (see interrupt.hpp).

#include <cstdint>
#include <memory>
#include <span>

#include <tbb/blocked_range.h>

#include "visfield/accel/query.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/interrupt.hpp"

namespace vf {

/// hits[i] = closest hit (or miss) of rays[i]. Spans must have equal sizes. Deterministic: each output
/// depends only on its ray.
template <ClosestHitQuery S>
void intersect_batch(const S& structure, std::span<const Ray> rays, std::span<Hit> hits) {
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    check_interrupt();
    // Constructed in place (Hit is trivially destructible): the query writes its answer straight into
    // the array, where an assignment would copy it from a temporary, which measured 5-7% slower.
    for (std::size_t i = range.begin(); i != range.end(); ++i) std::construct_at(&hits[i], structure.intersect(rays[i]));
  });
}

/// occluded[i] = 1 when rays[i] hits anything in (tmin, tmax], else 0. Spans must have equal sizes.
template <OcclusionQuery S>
void occluded_batch(const S& structure, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    check_interrupt();
    for (std::size_t i = range.begin(); i != range.end(); ++i) occluded[i] = structure.occluded(rays[i]) ? 1 : 0;
  });
}

/// occluded[i] = 1 when rays[i] hits anything, on the calling thread: the batch for callers that are
/// parallel already (a renderer's tiles). Structures with a faster way through many rays overload it
/// (FieldScene). Spans of equal size.
template <OcclusionQuery S>
void occluded_block(const S& structure, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  for (std::size_t i = 0; i < rays.size(); ++i) occluded[i] = structure.occluded(rays[i]) ? 1 : 0;
}

/// Whether `structure` traces rays along one direction line fastest as one stream per line (see
/// SceneQueries::occluder_prefers_line_streams): false, unless a structure overloads it (BeamField).
template <OcclusionQuery S>
constexpr bool prefers_line_streams(const S&) {
  return false;
}

}  // namespace vf
