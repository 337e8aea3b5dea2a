#pragma once
/// \file Which answer is a scene of field objects' closest hit, whatever order the objects' answers
/// come in: FieldScene's single-ray and batch queries and the GPU's copy of them all keep it by this
/// one rule, so that a walk may take the objects in any order and still give the same hit, bit for bit.
/// Each object's answer is its field's within the ray's own [tmin, tmax] (not cut at the nearest
/// answer so far, whose rounding would make the answer depend on the order).

#include "visfield/core/host_device.hpp"

namespace vf::field {

/// The closest hit so far came from the exact part (or there is none yet): no object index.
inline constexpr unsigned int kExactPart = 0xffffffffu;

/// Whether a field answer at `t` from object `object` (its index in the scene) replaces the closest
/// hit so far (`found`, at `best_t`, from object `best_object` or kExactPart): it is nearer, or as near
/// and from a lower object index. The exact part keeps its equals. O(1).
VF_HOST_DEVICE inline bool replaces_closest(float t, unsigned int object, bool found, float best_t, unsigned int best_object) {
  return !found || t < best_t || (t == best_t && best_object != kExactPart && object < best_object);
}

}  // namespace vf::field
