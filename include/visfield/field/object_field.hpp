#pragma once
/// \file ObjectField: the per-object 4D visibility (displacement) field of "Presampled visibility
/// fields for ambient occlusion" (2008) and, on the CPU, the intra-object query of "4D visibility
/// fields on the GPU". For one mesh: its bounding sphere; positional samples on it (the
/// two-hemisphere octahedral set, sphere_positions.hpp); at each sample an N×N table over the
/// hemisphere around the inward normal (hemisphere_map.hpp) whose cells hold the distance from
/// the sample to the mesh along the cell's direction, normalised by the diameter 2R
/// (cell_codec.hpp). A query answers in constant time, whatever the triangle count: it is an
/// approximate occluder. Object space throughout; instances map rays in (a field is shared by
/// every instance of its mesh).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "visfield/core/triangle_set.hpp"
#include "visfield/core/vec.hpp"
#include "visfield/field/cell_codec.hpp"
#include "visfield/field/hemisphere_map.hpp"
#include "visfield/field/sphere_positions.hpp"

namespace vf::field {

/// How a query reads the direction table of a positional sample.
enum class DirectionLookup : unsigned char {
  nearest = 0,   ///< The cell the direction falls in (the paper).
  bilinear = 1,  ///< The four nearest cell centres, weighted bilinearly (hits vote, hit distances average).
};

/// Which positional samples a query reads.
enum class PositionLookup : unsigned char {
  nearest = 0,  ///< The sample nearest to the point where the ray meets the sphere (the paper).
  blend = 1,    ///< The three samples of the lattice triangle around it, barycentric weights.
};

/// Parameters of a field. Defaults: the papers' 4226 positions × 32² concentric+Malley u8 cells,
/// looked up as the paper does.
struct ObjectFieldConfig {
  int positions = 4226;  ///< Positional samples: 290, 1090, 4226 or 16642 (levels 3–6).
  int directions = 32;   ///< N of the N×N direction table per sample, in [8, 256].
  HemisphereMapping mapping = HemisphereMapping::concentric_malley;
  CellStorage storage = CellStorage::u8;
  DirectionLookup direction_lookup = DirectionLookup::nearest;
  PositionLookup position_lookup = PositionLookup::nearest;

  /// Throws vf::Error naming the first value out of range.
  void validate() const;
  /// The positional level (3–6) of `positions`.
  int position_level() const;
};

/// A sphere in object space.
struct BoundingSphere {
  Vec3f centre{0.0f};
  float radius = 0.0f;
};

/// The sphere every field of `triangles` uses: the centre of their bounding box, and the largest
/// distance from it to a corner, enlarged by 1e-4 relative so that no surface touches it.
BoundingSphere bounding_sphere_of(const TriangleSet& triangles);

/// An approximate answer in object space: a hit at ray parameter t, or a miss.
struct FieldAnswer {
  bool hit = false;
  float t = 0.0f;
};

/// Object-space rays as arrays (structure of arrays) for ObjectField::trace_batch: origin, direction
/// (any non-zero length) and [tmin, tmax], `count` of each. The arrays are the caller's.
struct ObjectRays {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *tmin, *tmax;
  std::size_t count;
};

/// An immutable ObjectField. Queries are const and thread-safe. Movable.
class ObjectField {
 public:
  /// Precomputes the field of `object_triangles` (object space, non-empty): for every positional
  /// sample and used cell, one closest-hit ray through an exact BVH, in parallel (TBB). Refuses
  /// with vf::Error before allocating when estimate_bytes() exceeds the memory limit; throws
  /// vf::Interrupted on a signal. `progress(n)` (optional, thread-safe) is told of n more samples done.
  static ObjectField build(const TriangleSet& object_triangles, const ObjectFieldConfig& config,
                           const std::function<void(std::size_t)>& progress = {});

  /// A field from stored tables (a .vfield file): `cells` as cell_table() returns them, `averages`
  /// one per position for CellStorage::bit (else empty). Throws vf::Error when a size does not
  /// match `config` or the sphere is not finite and positive.
  static ObjectField from_tables(const ObjectFieldConfig& config, const BoundingSphere& sphere, std::vector<std::uint8_t> cells,
                                 std::vector<float> averages, double build_ms, std::size_t rays_traced);

  /// Bytes of the field's tables for `config`: positions × ⌈N² × bits per cell / 8⌉, plus per
  /// position 72 bytes of hemisphere frame and sample direction (twice: per sample and as arrays
  /// for the batch) and, for the 1-bit variant, 4 of average distance; 4 bytes of padding.
  static double table_bytes(const ObjectFieldConfig& config);
  /// Peak bytes build() takes for `triangles` triangles: the tables plus the exact BVH's build.
  static double estimate_build_bytes(std::size_t triangles, const ObjectFieldConfig& config);

  /// The parameters given at build.
  const ObjectFieldConfig& config() const { return config_; }
  /// The bounding sphere of the object.
  const BoundingSphere& sphere() const { return sphere_; }
  /// Number of positional samples.
  std::size_t position_count() const { return positions_.size(); }
  /// Bytes held by the tables and the per-sample frames (table_bytes() of the config).
  std::size_t memory_bytes() const {
    return cells_.capacity() + averages_.capacity() * sizeof(float) + frames_.capacity() * sizeof(Vec3f) +
           lookup_rows_.capacity() * sizeof(float);
  }
  /// Wall-clock precompute time in milliseconds.
  double build_ms() const { return build_ms_; }
  /// Rays traced by the precompute (used cells × positions).
  std::size_t rays_traced() const { return rays_traced_; }

  /// The raw table: per positional sample ⌈N² × bits / 8⌉ bytes, cell (i, j) at j·N + i, each
  /// encoded as cell_codec.hpp says (u16 and f32 little-endian, bits from the low end of a byte).
  std::span<const std::uint8_t> cell_table() const { return {cells_.data(), cells_.size() - kTablePadding}; }
  /// The 1-bit variant's mean normalised hit distance per sample (empty for other storage).
  const std::vector<float>& averages() const { return averages_; }
  /// Bytes of one positional sample's table.
  std::size_t sample_stride() const { return sample_stride_; }
  /// Whether `config` (lookup options aside) equals `other`'s: the same tables.
  static bool same_tables(const ObjectFieldConfig& config, const ObjectFieldConfig& other);

  /// Cell (i, j) of sample `sample`: whether it holds a hit, and the hit's distance over 2R (decoded).
  FieldAnswer cell(std::size_t sample, int i, int j) const;

  /// The field's answer for the object-space ray org + t·dir (dir non-zero, any length), within
  /// [tmin, tmax]. A ray that starts outside the sphere reads the table of the sample where it
  /// enters (inter-object); one that starts inside compares its distance to the exit point with
  /// the distance stored there for the reverse direction (intra-object, the GPU paper's d1 vs d2).
  FieldAnswer trace(const Vec3f& org, const Vec3f& dir, float tmin, float tmax) const;

  /// trace() for every ray of `rays`, answers into out[0 .. rays.count). With AVX-512 and the
  /// paper's lookups (nearest position, nearest cell) 16 rays run per step with polynomial
  /// arctangents and gathered table reads: the answers equal trace()'s except for rays within
  /// about 1e-5 of a cell's or a sample's border, which may read the neighbour. Otherwise one
  /// trace() per ray. Thread-safe.
  void trace_batch(const ObjectRays& rays, FieldAnswer* out) const;

  /// The distance (over 2R) below which an intra-object answer counts as the ray's own start
  /// surface: half a cell plus half the positional spacing, so it shrinks as the field grows finer.
  float self_offset() const { return self_offset_; }

 private:
  ObjectField(const ObjectFieldConfig& config, const BoundingSphere& sphere);
  /// The table's answer (normalised) for sample `sample` and world-space unit direction `d` pointing into the sphere.
  FieldAnswer read(std::size_t sample, const Vec3f& d) const;
  /// The answer for point `p` on the sphere (unit direction `from_centre`) and inward unit `d`, by the position lookup.
  FieldAnswer read_at(const Vec3f& from_centre, const Vec3f& d) const;
  /// Fills frames_ from the positional samples (each hemisphere's pole points inward).
  void compute_frames();
  /// Sets cell (i, j) of `sample` (build only).
  void store(std::size_t sample, int i, int j, bool hit, float x);

  ObjectFieldConfig config_;
  BoundingSphere sphere_;
  SpherePositions positions_;
  std::size_t sample_stride_ = 0;      // bytes per positional sample
  // Zero bytes after the table, so that the batch may read 32 bits at any cell.
  static constexpr std::size_t kTablePadding = 4;
  std::vector<std::uint8_t> cells_;    // sample-major; within a sample, cell j·N + i; then the padding
  std::vector<float> averages_;        // 1-bit variant: mean normalised hit distance per sample
  std::vector<Vec3f> frames_;          // per sample: u, v, w (inward pole) of its hemisphere, 3 entries
  // The same for the batch, as arrays of floats: 3 rows (x, y, z) of the upper hemisphere's sample
  // directions, then 9 rows (u.x .. w.z) of the frames; see lookup_rows_.
  std::vector<float> lookup_rows_;
  float self_offset_ = 0.0f;
  double build_ms_ = 0.0;
  std::size_t rays_traced_ = 0;
};

/// "concentric" etc. for a mapping; the names the CLI and files use.
std::string mapping_name(HemisphereMapping mapping);
/// "u8", "u16", "f32", "bit".
std::string storage_name(CellStorage storage);

}  // namespace vf::field
