#pragma once
/// \file What a ray-query structure is: its traits (name, statistics, exact or approximate), the two
/// query roles (closest hit, occlusion) as separate concepts, and the update lifecycle of structures
/// that change after they are built. Renderers take one structure per role and name no type.

#include <concepts>
#include <cstddef>
#include <string>

#include "visfield/core/ray.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/transform.hpp"

namespace vf {

/// Build statistics every structure reports.
struct AccelStats {
  double build_ms = 0.0;            ///< Wall-clock build time in milliseconds.
  std::size_t memory_bytes = 0;     ///< Bytes held by the built structure (triangle copies included).
  std::size_t node_count = 0;       ///< Interior nodes (or cells).
  std::size_t leaf_count = 0;       ///< Leaves (or non-empty cells).
  std::size_t reference_count = 0;  ///< Triangle (or object) references stored in leaves.
  int max_depth = 0;                ///< Deepest leaf.
};

/// Whether a structure answers as brute force does (exact) or within stated error bounds (approximate).
enum class Exactness { exact, approximate };

/// "exact" or "approximate".
constexpr const char* exactness_name(Exactness e) { return e == Exactness::exact ? "exact" : "approximate"; }

/// The error an approximate structure states for its answers, measured against an exact structure on
/// the same rays (tests/approximate checks every bound). A bound of 0 promises exact agreement.
struct ErrorBounds {
  double occlusion_disagreement = 0.0;  ///< Largest fraction of rays whose occluded() answer differs.
  double hit_disagreement = 0.0;        ///< Largest fraction of rays where one side hits and the other misses.
  double distance_rms = 0.0;            ///< Largest RMS of t - t_exact over rays both hit, over the scene's bounding-sphere diameter (for unit directions).
  double image_rms = 0.0;               ///< Largest RMS difference of an AO image in [0, 1] rendered with it as the occluder.
};

/// A built structure: a static name() (its registry name), a static `exactness`, and stats().
template <class S>
concept StructureType = requires(const S& s) {
  { S::name() } -> std::convertible_to<std::string>;
  { S::exactness } -> std::convertible_to<Exactness>;
  { s.stats() } -> std::convertible_to<AccelStats>;
};

/// The closest-hit role: intersect(ray) returns the nearest hit with tmin <= t <= tmax, or a miss.
/// Const and thread-safe.
template <class S>
concept ClosestHitQuery = StructureType<S> && requires(const S& s, const Ray& ray) {
  { s.intersect(ray) } -> std::same_as<Hit>;
};

/// The occlusion role: occluded(ray) tells whether anything lies on the ray within (tmin, tmax].
/// Const and thread-safe.
template <class S>
concept OcclusionQuery = StructureType<S> && requires(const S& s, const Ray& ray) {
  { s.occluded(ray) } -> std::same_as<bool>;
};

/// A structure answering both roles (every exact structure).
template <class S>
concept Accelerator = ClosestHitQuery<S> && OcclusionQuery<S>;

/// A structure whose answers are exactly brute force's (same t, same triangle except on exact ties).
template <class S>
concept ExactStructure = StructureType<S> && (S::exactness == Exactness::exact);

/// A structure whose answers are approximate, with the bounds it promises.
template <class S>
concept ApproximateStructure = StructureType<S> && (S::exactness == Exactness::approximate) && requires(const S& s) {
  { s.error_bounds() } -> std::convertible_to<ErrorBounds>;
};

/// A structure whose objects change after the build (Embree's scene lifecycle): remove, insert and move
/// objects of a Scene by id, then commit(). Edits are staged: until commit() returns, queries answer
/// for the last committed state; after it, they answer exactly as a fresh build over the edited scene
/// would. Edits and commit() must not run concurrently with queries or with each other.
template <class S>
concept UpdatableStructure = StructureType<S> && requires(S& s, const Scene& scene, ObjectId id, const Transform& t) {
  s.remove(id);         ///< Takes object `id` out.
  s.insert(scene, id);  ///< Adds object `id` of `scene` (its mesh and transform as they are now).
  s.move(id, t);        ///< Places object `id` by `t`.
  s.commit();           ///< Applies the staged edits.
};

}  // namespace vf
