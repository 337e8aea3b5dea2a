#pragma once
/// \file Queries and edits of a structure whatever the registry built (AnyStructure), for callers
/// that hold one without naming its type: the C and Python APIs. Each call dispatches once to the
/// structure's own batch (BeamField groups by line, fields run their SIMD kernel). Rays and answers
/// can also be strided arrays (a NumPy array, a structure-of-arrays C buffer): they are converted a
/// chunk at a time, so no copy of the whole ray set is made.

#include <cstddef>
#include <cstdint>
#include <span>

#include "visfield/core/ray.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/registry/registry.hpp"

namespace vf {

/// hits[i] = structure.intersect(rays[i]), through the structure's batch path. Parallel; spans of
/// equal size (vf::Error otherwise); throws vf::Interrupted on a signal.
void intersect_batch(const AnyStructure& structure, std::span<const Ray> rays, std::span<Hit> hits);

/// occluded[i] = 1 when rays[i] hits anything in (tmin, tmax], else 0; as intersect_batch() above.
void occluded_batch(const AnyStructure& structure, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// `count` floats at byte stride `stride` from `data`, or the constant `fallback` when data is null.
/// A view: the caller owns the memory, which must outlive the call it is passed to.
struct StridedFloats {
  const float* data = nullptr;
  std::ptrdiff_t stride = sizeof(float);  ///< Bytes from one element to the next.
  float fallback = 0.0f;                  ///< The value of every element when data is null.

  /// Element i. O(1).
  float at(std::size_t i) const {
    if (data == nullptr) return fallback;
    return *reinterpret_cast<const float*>(reinterpret_cast<const char*>(data) + static_cast<std::ptrdiff_t>(i) * stride);
  }
};

/// Rays as eight strided float arrays (origin, direction, range). tmin defaults to 0 and tmax to
/// +infinity when their arrays are null.
struct RayArrays {
  StridedFloats ox, oy, oz, dx, dy, dz;
  StridedFloats tmin{nullptr, sizeof(float), 0.0f};
  StridedFloats tmax{nullptr, sizeof(float), std::numeric_limits<float>::infinity()};
  std::size_t count = 0;

  /// Ray i. O(1).
  Ray at(std::size_t i) const {
    return Ray{{ox.at(i), oy.at(i), oz.at(i)}, {dx.at(i), dy.at(i), dz.at(i)}, tmin.at(i), tmax.at(i)};
  }
};

/// An output array of `T` at byte stride `stride`; null = not wanted. A view over caller memory.
template <class T>
struct StridedOut {
  T* data = nullptr;
  std::ptrdiff_t stride = sizeof(T);

  /// Writes element i when the array is wanted. O(1).
  void set(std::size_t i, T value) const {
    if (data != nullptr) *reinterpret_cast<T*>(reinterpret_cast<char*>(data) + static_cast<std::ptrdiff_t>(i) * stride) = value;
  }
};

/// Where closest hits go, field by field (any may be null). A miss writes t = +infinity, u = v = 0,
/// prim = instance = kInvalidId and a zero normal; a hit without a triangle (a field's) writes
/// prim = kInvalidId. The normal is the geometric one, not normalised (Hit::normal).
struct HitArrays {
  StridedOut<float> t, u, v;
  StridedOut<std::uint32_t> prim, instance;
  StridedOut<float> nx, ny, nz;
};

/// Closest hits of `rays` into `hits`, a chunk of rays at a time through intersect_batch(). Parallel
/// within each chunk; throws vf::Interrupted on a signal. Memory: O(chunk), not O(rays).
void intersect_arrays(const AnyStructure& structure, const RayArrays& rays, const HitArrays& hits);

/// Occlusion of `rays` into `occluded` (1 or 0 at stride `occluded.stride`), as intersect_arrays().
void occluded_arrays(const AnyStructure& structure, const RayArrays& rays, const StridedOut<std::uint8_t>& occluded);

/// Whether `structure` can remove, insert and move objects after its build (UpdatableStructure).
bool is_updatable(const AnyStructure& structure);

/// Stages the removal of object `id` (see UpdatableStructure). Throws vf::Error when the structure
/// is not updatable or the edit is refused (unknown id).
void remove_object(AnyStructure& structure, ObjectId id);

/// Stages the insertion of object `id` of `scene` (its mesh and transform as they are now), as
/// remove_object() says.
void insert_object(AnyStructure& structure, const Scene& scene, ObjectId id);

/// Stages moving object `id` to `t`, as remove_object() says.
void move_object(AnyStructure& structure, ObjectId id, const Transform& t);

/// Applies the staged edits: afterwards the answers equal a fresh build's over the edited scene.
/// Throws vf::Error when the structure is not updatable.
void commit_objects(AnyStructure& structure);

}  // namespace vf
