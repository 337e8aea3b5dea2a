#pragma once
/// \file ObjectField: the per-object 4D visibility (displacement) field of "Presampled visibility
/// fields for ambient occlusion" (2008) and, on the CPU, the intra-object query of "4D visibility
/// fields on the GPU". For one mesh: its bounding sphere; positional samples on it (the
/// two-hemisphere octahedral set, sphere_positions.hpp); at each sample an N×N table over the
/// hemisphere around the inward normal (hemisphere_map.hpp) whose cells hold the distance from
/// the sample to the mesh along the cell's direction, normalised by the diameter 2R
/// (cell_codec.hpp), and optionally the normal of the surface hit (normal_codec.hpp, the GPU
/// paper's normal fields). A query (field_query.hpp) answers in constant time, whatever the
/// triangle count: it is an approximate occluder. Object space throughout; instances map rays in
/// (a field is shared by every instance of its mesh).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "visfield/accel/aligned_vector.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/core/vec.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/field/field_query.hpp"
#include "visfield/field/sphere_positions.hpp"

namespace vf::field {

/// Parameters of a field. Defaults: the papers' 4226 positions × 32² concentric+Malley u8 cells,
/// no normal field, one sample and one cell read as the paper does, along the line through the ray's
/// far end (as fast as the paper's parallel read, and a third fewer wrong answers: the README's ObjectField section).
struct ObjectFieldConfig {
  int positions = 4226;  ///< Positional samples: 290, 1090, 4226 or 16642 (levels 3–6).
  int directions = 32;   ///< N of the N×N direction table per sample, in [8, 256].
  HemisphereMapping mapping = HemisphereMapping::concentric_malley;
  CellStorage storage = CellStorage::u8;
  NormalStorage normals = NormalStorage::none;  ///< A normal per cell beside the distance (GPU paper's normal fields).
  DirectionLookup direction_lookup = DirectionLookup::nearest;
  PositionLookup position_lookup = PositionLookup::nearest;
  SampleLine sample_line = SampleLine::through;  ///< The line each sample's table is read along.

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
  /// sample and used cell, one closest-hit ray through an exact BVH, in parallel (TBB); with a
  /// normal field, the hit triangle's unit geometric normal beside the distance. Refuses with
  /// vf::Error before allocating when estimate_build_bytes() exceeds the memory limit; throws
  /// vf::Interrupted on a signal. `progress(n)` (optional, thread-safe) is told of n more samples done.
  static ObjectField build(const TriangleSet& object_triangles, const ObjectFieldConfig& config,
                           const std::function<void(std::size_t)>& progress = {});

  /// A field from stored tables (a .vfield file): `cells` and `normals` as cell_table() and
  /// normal_table() return them (copied once, into the field's own aligned tables), `averages` one
  /// per position for CellStorage::bit (else empty). Throws vf::Error when a size does not match
  /// `config` or the sphere is not finite and positive.
  static ObjectField from_tables(const ObjectFieldConfig& config, const BoundingSphere& sphere, std::span<const std::uint8_t> cells,
                                 std::vector<float> averages, std::span<const std::uint8_t> normals, double build_ms,
                                 std::size_t rays_traced);

  /// Bytes a field of `config` holds: positions × N² × (bits per cell + bits per normal) / 8
  /// (each sample's distance table rounded up to whole bytes), plus per position 6 bytes of sample
  /// direction (12 per upper sample) and, for the 1-bit variant, 4 of average distance; 4 bytes of
  /// padding per table; 8 bytes per (|i|, |j|) of the lattice for the SIMD lookup, (n + 1)².
  static double table_bytes(const ObjectFieldConfig& config);
  /// Peak bytes build() takes for `triangles` triangles: the tables plus the exact BVH's build.
  static double estimate_build_bytes(std::size_t triangles, const ObjectFieldConfig& config);

  /// The parameters given at build.
  const ObjectFieldConfig& config() const { return config_; }
  /// The bounding sphere of the object.
  const BoundingSphere& sphere() const { return sphere_; }
  /// Number of positional samples.
  std::size_t position_count() const { return 2 * upper_.size(); }
  /// Bytes held (table_bytes() of the config).
  std::size_t memory_bytes() const {
    return cells_.capacity() + normals_.capacity() + averages_.capacity() * sizeof(float) + upper_.capacity() * sizeof(upper_[0]) +
           quadrant_.capacity() * sizeof(quadrant_[0]) + cell_centres_.capacity() * sizeof(cell_centres_[0]);
  }
  /// Wall-clock precompute time in milliseconds.
  double build_ms() const { return build_ms_; }
  /// Rays traced by the precompute (used cells × positions).
  std::size_t rays_traced() const { return rays_traced_; }

  /// The raw distance table: per positional sample sample_stride() bytes, cell (i, j) at j·N + i,
  /// each encoded as cell_codec.hpp says (u16 and f32 little-endian, bits from the low end of a byte).
  std::span<const std::uint8_t> cell_table() const { return {cells_.data(), cells_.size() - kTablePadding}; }
  /// The raw normal table (empty without a normal field): per sample normal_stride() bytes, cell
  /// (i, j) at (j·N + i) × 2 or × 4 bytes, little-endian normal_codec.hpp codes.
  std::span<const std::uint8_t> normal_table() const {
    return normals_.empty() ? std::span<const std::uint8_t>{} : std::span<const std::uint8_t>{normals_.data(), normals_.size() - kTablePadding};
  }
  /// The 1-bit variant's mean normalised hit distance per sample (empty for other storage).
  const std::vector<float>& averages() const { return averages_; }
  /// Bytes of one positional sample's distance table.
  std::size_t sample_stride() const { return sample_stride_; }
  /// Bytes of one positional sample's normal table (0 without a normal field).
  std::size_t normal_stride() const { return normal_stride_; }
  /// Whether `config` (lookup options aside) equals `other`'s: the same tables.
  static bool same_tables(const ObjectFieldConfig& config, const ObjectFieldConfig& other);
  /// What the query code reads (field_query.hpp), borrowed from this field.
  FieldTables tables() const;

  /// Cell (i, j) of sample `sample`: whether it holds a hit, the hit's distance over 2R (decoded)
  /// and, with a normal field, its normal.
  FieldAnswer cell(std::size_t sample, int i, int j) const;

  /// The field's answer for the object-space ray org + t·dir (dir non-zero, any length), within
  /// [tmin, tmax]: trace_field() of field_query.hpp. O(1).
  FieldAnswer trace(const Vec3f& org, const Vec3f& dir, float tmin, float tmax) const;

  /// trace() for every ray of `rays`, answers into out[0 .. rays.count), bit for bit, `width` rays
  /// per step: 0 for the widest this build runs (32 with AVX-512, 16 with AVX2, else 1), or 32,
  /// 16, 8 or 1 to compare them (batch_width() says what a request runs). Thread-safe.
  void trace_batch(const ObjectRays& rays, FieldAnswer* out, int width = 0) const;

  /// trace() for the world-space rays rays[index[k]], k < count, each mapped by `to_object` (as
  /// InverseTransform::apply maps it) and limited to [tmin, limit[index[k]]] when `limit` is given
  /// (else [tmin, tmax]); answers (object-space normals) into out[0 .. count), bit for bit those of
  /// trace() on the mapped rays; `width` as for trace_batch(). `rays` holds fewer than 2^28 rays.
  /// Thread-safe.
  void trace_rays(const Ray* rays, const std::uint32_t* index, std::size_t count, const InverseTransform& to_object,
                  const float* limit, FieldAnswer* out, int width = 0) const;
  /// trace() for every object-space ray of `rays` into `out` (same size), through the batch kernel,
  /// in parallel (TBB) over blocks of rays; bit for bit trace()'s answers. Throws vf::Interrupted on a signal.
  void trace_rays(std::span<const Ray> rays, std::span<FieldAnswer> out) const;
  /// Occlusion for the same rays as trace_rays() (no limit): occluded[index[k]] = 1 where trace()
  /// of the mapped ray hits; other entries are left as they are. Thread-safe for disjoint `index` sets.
  void mark_occluded(const Ray* rays, const std::uint32_t* index, std::size_t count, const InverseTransform& to_object,
                     std::uint8_t* occluded, int width = 0) const;
  /// Occlusion for every object-space ray of `rays`: occluded[k] = 1 where trace() of ray k hits;
  /// other entries are left as they are. Through the batch kernel, on the calling thread.
  void mark_occluded(const ObjectRays& rays, std::uint8_t* occluded, int width = 0) const;
  /// The lanes per step a batch query asked for `width` runs in this build: 32, 16, 8 or 1.
  static int batch_width(int width = 0);
  /// The part of the query a timing-bound build leaves out (CMake VISFIELD_FIELD_BOUND: "no-lookups",
  /// "read-and-map", "read-only", "cached-cells", "no-map", "no-map-line", "no-map-line-lattice",
  /// "sphere-only"; its answers are wrong), "" in a normal build.
  static const char* timing_bound();

  /// The distance (over 2R) below which an intra-object answer counts as the ray's own start
  /// surface: half a cell plus half the positional spacing, so it shrinks as the field grows finer.
  float self_offset() const { return self_offset_; }

 private:
  ObjectField(const ObjectFieldConfig& config, const BoundingSphere& sphere);
  /// Sets cell (i, j) of `sample` (build only); `normal` is the hit's geometric normal.
  void store(std::size_t sample, int i, int j, bool hit, float x, const Vec3f& normal);

  ObjectFieldConfig config_;
  BoundingSphere sphere_;
  int lattice_n_ = 0;
  std::size_t sample_stride_ = 0;      // bytes per positional sample
  std::size_t normal_stride_ = 0;      // bytes per positional sample of the normal table
  // Zero bytes after each table, so that the batch may read 32 bits at any cell.
  static constexpr std::size_t kTablePadding = 4;
  AlignedVector<std::uint8_t> cells_;    // sample-major; within a sample, cell j·N + i; then the padding
  AlignedVector<std::uint8_t> normals_;  // the same layout for the normal codes (empty without normals)
  std::vector<float> averages_;        // 1-bit variant: mean normalised hit distance per sample
  std::vector<hd::Vec3<float>> upper_; // upper hemisphere's sample directions, by octa::point_index
  std::vector<unsigned long long> quadrant_;  // their |x|, |y| by (|i|, |j|) (FieldTables::quadrant)
  std::vector<hd::Vec3<float>> cell_centres_;  // PositionLookup::lines only (FieldTables::cell_centres)
  float self_offset_ = 0.0f;
  double build_ms_ = 0.0;
  std::size_t rays_traced_ = 0;
};

/// "concentric" etc. for a mapping; the names the CLI and files use.
std::string mapping_name(HemisphereMapping mapping);
/// "u8", "u16", "f32", "bit".
std::string storage_name(CellStorage storage);
/// "none", "oct16", "oct32".
std::string normals_name(NormalStorage normals);

}  // namespace vf::field
