#pragma once
/// \file BeamField: the visibility field of VLF-RT (Mortensen, Khanna, Yu, Slater 2007). For every
/// line of an octahedral direction set (core/direction_lines.hpp) an n×n grid of parallel beams
/// ("tiles" of the line's parallel subfield, PSF) covers the projection of the scene's bounding
/// sphere; each tile lists the triangles its beam meets, split along the beam into 2^D equal depth
/// leaves (the paper's tile-BSP with spatial-median planes, walked linearly near to far). A ray looks
/// up its nearest line, walks the tiles its projection crosses (one tile when the ray runs along a
/// stored direction) and tests the triangles of the leaves its depth interval covers. Exact: the
/// same watertight triangle test as every other structure, on a candidate set that provably
/// contains the closest hit. Objects can be removed, inserted and moved without a full rebuild.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "visfield/accel/query.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

namespace beam {
struct BeamLayout;
}

/// Build parameters of BeamField. The defaults are the fastest measured on PSF-aligned AO rays over
/// bunny and sponza within the memory of this machine (README, "BeamField").
struct BeamFieldConfig {
  int level = 4;           ///< Direction set: 2·4^level + 1 lines; level in [2, 6] (33, 129, 513, 2049, 8193).
  int resolution = 64;     ///< n: tiles per side of each parallel subfield, in [16, 1024].
  int max_depth = 4;       ///< Deepest tile-BSP: at most 2^max_depth leaves per tile, in [0, 12].
  int leaf_size = 4;       ///< A tile of c > leaf_size references gets about c / leaf_size leaves (up to 2^max_depth), in [1, 4096].
  int stream = 1;          ///< 1: occluded_batch traces the rays that run along a stored line in per-tile packets; 0: ray by ray (the same answers; to measure the packets' gain), in [0, 1].

  /// Number of lines of `level`.
  std::size_t direction_count() const { return DirectionLines::count(level); }
};

/// Work done by queries, summed over the rays of a counting query (for checking the cost model).
/// Plain value; not thread-safe (use one per thread and add them up).
struct BeamQueryCounters {
  std::uint64_t rays = 0;            ///< Queries counted.
  std::uint64_t single_tile = 0;     ///< Rays whose whole segment stayed in one tile (the fast path).
  std::uint64_t tiles = 0;           ///< Tiles visited (empty ones included).
  std::uint64_t leaves = 0;          ///< Tile-BSP leaves visited.
  std::uint64_t triangle_tests = 0;  ///< Ray–triangle tests.

  /// Adds `o` to this.
  BeamQueryCounters& operator+=(const BeamQueryCounters& o) {
    rays += o.rays, single_tile += o.single_tile, tiles += o.tiles, leaves += o.leaves, triangle_tests += o.triangle_tests;
    return *this;
  }
};

/// BeamField-specific statistics beside AccelStats.
struct BeamFieldStats {
  std::size_t directions = 0;          ///< Lines of the direction set.
  int resolution = 0;                  ///< n.
  std::size_t tiles = 0;               ///< directions × n².
  std::size_t empty_tiles = 0;         ///< Tiles no triangle meets.
  std::size_t triangles = 0;           ///< Live triangles.
  std::size_t references = 0;          ///< Triangle references over all leaves of all tiles.
  std::size_t bytes_per_direction = 0; ///< memory_bytes / directions, rounded.
  double references_per_triangle = 0;  ///< references / triangles (over all directions).
  double empty_tile_fraction = 0;      ///< empty_tiles / tiles.
  double last_commit_ms = 0;           ///< Wall-clock time of the last commit() (0 before any).
  bool last_commit_rebuilt = false;    ///< The last commit() rebuilt everything (an object left the sphere, too many dead slots, or edits of over a third of the triangles).
};

/// An exact BeamField over a Scene's objects. Queries are const and thread-safe; edits are not (see
/// UpdatableStructure). Move-only.
class BeamField {
 public:
  /// Builds over the objects of `scene`, whose world-space triangles are `flattened` (flatten(scene)).
  /// Parallel over directions (TBB); the same structure for any thread count. Throws vf::Error on a
  /// bad config (validate()) or when the build would exceed 32-bit offsets or the memory limit.
  static BeamField build(const Scene& scene, const TriangleSet& flattened, const BeamFieldConfig& config = {});
  /// As above, flattening the scene itself.
  static BeamField build(const Scene& scene, const BeamFieldConfig& config = {});
  /// Throws vf::Error with one line naming the parameter and its range when `config` is invalid.
  static void validate(const BeamFieldConfig& config);
  /// Peak bytes build() would take on `scene`: the tile tables, the references (measured by
  /// rasterising the scene's triangles, or a sample of them, in 8 of the directions), the triangle
  /// copies and the per-thread build buffers. O(min(triangles, 20000) × 8) rasterisations.
  static double estimate_build_bytes(const Scene& scene, const BeamFieldConfig& config = {});

  BeamField(BeamField&&) noexcept;
  BeamField& operator=(BeamField&&) noexcept;
  ~BeamField();

  /// Closest hit in (tmin, tmax]; equal to BruteForce over flatten(scene) (same t, triangle, object
  /// and normal; ties in t go to the lower (object, triangle)).
  Hit intersect(const Ray& ray) const;
  /// True when any triangle is hit in (tmin, tmax]; stops at the first.
  bool occluded(const Ray& ray) const;
  /// intersect() that also adds its work to `counters`.
  Hit intersect(const Ray& ray, BeamQueryCounters& counters) const;
  /// occluded() that also adds its work to `counters`.
  bool occluded(const Ray& ray, BeamQueryCounters& counters) const;

  /// intersect() for a ray whose nearest line is known (`line` from lines().nearest(ray.dir)); the
  /// same answer. For batch queries that group rays by line.
  Hit intersect_on_line(const Ray& ray, std::uint32_t line) const;
  /// occluded() for a ray whose nearest line is known; the same answer.
  bool occluded_on_line(const Ray& ray, std::uint32_t line) const;

  /// Build statistics: node_count = non-empty tiles, leaf_count = leaves, reference_count, bytes, ms;
  /// max_depth = deepest tile-BSP.
  const AccelStats& stats() const;
  /// Directions, tiles, references per triangle, empty-tile fraction, bytes per direction, last commit.
  BeamFieldStats beam_stats() const;
  /// The parameters it was built with.
  const BeamFieldConfig& config() const;
  /// Its direction set: rays along direction(k) (or its negation) run the single-tile fast path.
  const DirectionLines& lines() const;
  /// The registry name, "beam".
  static std::string name() { return "beam"; }
  static constexpr Exactness exactness = Exactness::exact;

  /// Stages the removal of object `id`; throws vf::Error when it is not in the field.
  void remove(ObjectId id);
  /// Stages adding object `id` of `scene` (its mesh and transform as they are now); throws vf::Error
  /// when `scene` has no such object or the field already holds it.
  void insert(const Scene& scene, ObjectId id);
  /// Stages moving object `id` to `transform`; throws vf::Error on an unknown id or a bad transform.
  void move(ObjectId id, const Transform& transform);
  /// Applies the staged edits: in every direction, the tiles the old and new triangles of the edited
  /// objects touch are rebuilt, the rest is left as it is (the paper's delete and re-insert).
  /// Rebuilds everything instead when an object leaves the bounding sphere, dead triangle slots
  /// outnumber live ones, or the edits touch more than a third of the live triangles (a rebuild is
  /// then the faster; scenes under about a thousand triangles excepted). Parallel over directions.
  /// Afterwards queries answer exactly as a fresh build over the edited scene.
  void commit();
  /// True when edits are staged and not committed.
  bool has_staged_edits() const;

  /// The storage (private to accel; for its batch queries).
  const beam::BeamLayout& layout() const { return *layout_; }

 private:
  explicit BeamField(std::unique_ptr<beam::BeamLayout> layout);
  std::unique_ptr<beam::BeamLayout> layout_;
};

/// Batch closest hits through a BeamField: hits[i] is intersect(rays[i]), as intersect_batch() gives,
/// but the rays are traced grouped by nearest line (and in their order within a line), so that
/// consecutive queries read the same direction's tiles: the field is far larger than the caches, and
/// AO rays from one point use hundreds of directions. Parallel; deterministic.
void intersect_batch(const BeamField& field, std::span<const Ray> rays, std::span<Hit> hits);
/// Batch occlusion through a BeamField: occluded[i] is occluded(rays[i]). The rays are grouped by
/// nearest line; those that run exactly along it (direction ±lines().direction(line), bit for bit:
/// AO along the lines) and stay in one tile are binned by tile (a counting sort) and traced as a
/// stream (config.stream = 1): each tile record is read once for all its rays, its leaves walked near
/// to far for all of them together, and each triangle tested against up to 16 rays at once with the
/// watertight test's constants shared along the line (the same bits as one ray at a time); a ray
/// leaves its packet at its first hit. The other rays are traced one by one in line and tile order.
/// Parallel; deterministic; O(rays + lines + tiles touched) beside the tracing.
void occluded_batch(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
/// occluded_batch() on the calling thread, for callers that are parallel already (a renderer tracing
/// its lines in parallel, each line's rays from a whole block of the image in one call). With
/// config.stream = 0, ray by ray in the given order.
void occluded_block(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
/// True with config.stream = 1: a renderer should hand it rays along one line together (batch.hpp).
inline bool prefers_line_streams(const BeamField& field) { return field.config().stream != 0; }

}  // namespace vf
