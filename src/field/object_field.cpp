#include "visfield/field/object_field.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "visfield/accel/bvh.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/orthonormal_basis.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/stopwatch.hpp"

namespace vf::field {

std::string mapping_name(HemisphereMapping mapping) {
  switch (mapping) {
    case HemisphereMapping::polar: return "polar";
    case HemisphereMapping::rejection_malley: return "rejection";
    case HemisphereMapping::concentric_malley: return "concentric";
    case HemisphereMapping::concentric_equal_area: return "equal-area";
  }
  return "?";
}

std::string storage_name(CellStorage storage) {
  switch (storage) {
    case CellStorage::u8: return "u8";
    case CellStorage::u16: return "u16";
    case CellStorage::f32: return "f32";
    case CellStorage::bit: return "bit";
  }
  return "?";
}

std::string normals_name(NormalStorage normals) {
  switch (normals) {
    case NormalStorage::none: return "none";
    case NormalStorage::oct16: return "oct16";
    case NormalStorage::oct32: return "oct32";
  }
  return "?";
}

int ObjectFieldConfig::position_level() const {
  for (int level = SpherePositions::kMinLevel; level <= SpherePositions::kMaxLevel; ++level)
    if (SpherePositions::count(level) == static_cast<std::size_t>(positions)) return level;
  throw Error("field positions " + std::to_string(positions) + ": expected 290, 1090, 4226 or 16642");
}

void ObjectFieldConfig::validate() const {
  position_level();
  if (directions < 8 || directions > 256)
    throw Error("field directions " + std::to_string(directions) + ": expected 8..256 (cells per side of each table)");
  if (static_cast<int>(mapping) >= kMappingCount) throw Error("field mapping: unknown value");
  if (static_cast<int>(storage) >= kStorageCount) throw Error("field storage: unknown value");
  if (static_cast<int>(normals) >= kNormalStorageCount) throw Error("field normals: unknown value");
  if (direction_lookup != DirectionLookup::nearest && direction_lookup != DirectionLookup::bilinear)
    throw Error("field direction lookup: unknown value");
  if (position_lookup != PositionLookup::nearest && position_lookup != PositionLookup::blend && position_lookup != PositionLookup::lines)
    throw Error("field position lookup: unknown value");
  if (sample_line != SampleLine::parallel && sample_line != SampleLine::through) throw Error("field sample line: unknown value");
}

BoundingSphere bounding_sphere_of(const TriangleSet& triangles) {
  BoundingSphere sphere;
  sphere.centre = (triangles.bounds.lo + triangles.bounds.hi) * 0.5f;
  float r2 = 0.0f;
  for (const auto& t : triangles.triangles)
    for (const Vec3f& p : t) r2 = std::max(r2, dot(p - sphere.centre, p - sphere.centre));
  sphere.radius = std::sqrt(r2) * (1.0f + 1e-4f);
  return sphere;
}

namespace {

/// Bytes of one sample's distance table and normal table for `config`.
std::size_t cell_stride_of(const ObjectFieldConfig& config) {
  const std::size_t cells = static_cast<std::size_t>(config.directions) * static_cast<std::size_t>(config.directions);
  return (cells * static_cast<std::size_t>(cell_bits(config.storage)) + 7) / 8;
}
std::size_t normal_stride_of(const ObjectFieldConfig& config) {
  const std::size_t cells = static_cast<std::size_t>(config.directions) * static_cast<std::size_t>(config.directions);
  return cells * static_cast<std::size_t>(normal_bits(config.normals)) / 8;
}

Vec3f to_vec(const hd::Vec3<double>& v) { return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; }

}  // namespace

double ObjectField::table_bytes(const ObjectFieldConfig& config) {
  const double positions = static_cast<double>(config.positions);
  const double averages = config.storage == CellStorage::bit ? 4.0 : 0.0;
  const double padding = config.normals == NormalStorage::none ? 4.0 : 8.0;
  const double lattice_side = static_cast<double>((1 << config.position_level()) + 1);
  const double centres = config.position_lookup == PositionLookup::lines ? 12.0 * config.directions * config.directions : 0.0;
  return positions * (static_cast<double>(cell_stride_of(config) + normal_stride_of(config)) + averages + 6.0) + padding +
         8.0 * lattice_side * lattice_side + centres;
}

double ObjectField::estimate_build_bytes(std::size_t triangles, const ObjectFieldConfig& config) {
  return table_bytes(config) + Bvh::estimate_build_bytes(triangles);
}

ObjectField::ObjectField(const ObjectFieldConfig& config, const BoundingSphere& sphere)
    : config_(config), sphere_(sphere), sample_stride_(cell_stride_of(config)), normal_stride_(normal_stride_of(config)) {
  const SpherePositions positions(config.position_level());
  lattice_n_ = positions.lattice_size();
  upper_.reserve(positions.size() / 2);
  upper_.assign(positions.upper_table(), positions.upper_table() + positions.size() / 2);
  const int side = lattice_n_ + 1;
  quadrant_.reserve(static_cast<std::size_t>(side) * static_cast<std::size_t>(side));
  quadrant_.assign(static_cast<std::size_t>(side) * static_cast<std::size_t>(side), 0);
  for (int i = 0; i <= lattice_n_; ++i)
    for (int j = 0; i + j <= lattice_n_; ++j) {
      const hd::Vec3<float>& w = upper_[static_cast<std::size_t>(octa::point_index(i, j, lattice_n_))];
      quadrant_[static_cast<std::size_t>(i * side + j)] =
          std::bit_cast<std::uint32_t>(w.x) | static_cast<unsigned long long>(std::bit_cast<std::uint32_t>(w.y)) << 32;
    }
  if (config.position_lookup == PositionLookup::lines) {
    const int n = config.directions;
    cell_centres_.reserve(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const hd::Vec3<double> l = cell_direction<double>(config.mapping, i, j, n);
        cell_centres_.push_back({static_cast<float>(l.x), static_cast<float>(l.y), static_cast<float>(l.z)});
      }
  }
  self_offset_ = 0.5f / static_cast<float>(config.directions) + 0.25f * (std::numbers::pi_v<float> / 2.0f) / static_cast<float>(lattice_n_);
}

FieldTables ObjectField::tables() const {
  FieldTables t;
  t.lattice_n = lattice_n_;
  t.upper_count = static_cast<int>(upper_.size());
  t.directions = config_.directions;
  t.mapping = config_.mapping;
  t.storage = config_.storage;
  t.normals = config_.normals;
  t.direction_lookup = config_.direction_lookup;
  t.position_lookup = config_.position_lookup;
  t.cell_centres = cell_centres_.empty() ? nullptr : cell_centres_.data();
  t.sample_line = config_.sample_line;
  t.centre = {sphere_.centre.x, sphere_.centre.y, sphere_.centre.z};
  t.radius = sphere_.radius;
  t.self_offset = self_offset_;
  t.upper = upper_.data();
  t.quadrant = quadrant_.data();
  t.cells = cells_.data();
  t.cell_stride = sample_stride_;
  t.averages = averages_.data();
  t.normal_cells = normals_.empty() ? nullptr : normals_.data();
  t.normal_stride = normal_stride_;
  return t;
}

ObjectField ObjectField::build(const TriangleSet& object_triangles, const ObjectFieldConfig& config,
                               const std::function<void(std::size_t)>& progress) {
  config.validate();
  if (object_triangles.size() == 0) throw Error("object field: the mesh has no triangles");
  require_memory(estimate_build_bytes(object_triangles.size(), config),
                 "an object field of " + std::to_string(config.positions) + " positions x " +
                     std::to_string(config.directions) + "^2 " + storage_name(config.storage) + " cells" +
                     (config.normals == NormalStorage::none ? std::string() : " with " + normals_name(config.normals) + " normals"));
  const Stopwatch watch;
  ObjectField field(config, bounding_sphere_of(object_triangles));
  const Bvh bvh = Bvh::build(object_triangles);
  const SpherePositions positions(config.position_level());
  const std::size_t count = positions.size();
  const int n = config.directions;
  field.cells_.reserve(count * field.sample_stride_ + kTablePadding);
  field.cells_.assign(count * field.sample_stride_ + kTablePadding, 0);
  if (config.normals != NormalStorage::none) {
    field.normals_.reserve(count * field.normal_stride_ + kTablePadding);
    field.normals_.assign(count * field.normal_stride_ + kTablePadding, 0);
  }
  if (config.storage == CellStorage::bit) {
    field.averages_.reserve(count);
    field.averages_.assign(count, 0.0f);
  }
  const BoundingSphere sphere = field.sphere_;
  const float diameter = 2.0f * sphere.radius;
  std::vector<std::size_t> traced(count, 0);
  vf::parallel_for(std::size_t{0}, count, [&](std::size_t k) {
    check_interrupt();
    const hd::Vec3<double> out = positions.direction(k);
    const OrthonormalBasis<double> basis = orthonormal_basis(hd::Vec3<double>{-out.x, -out.y, -out.z});
    const Vec3f origin = sphere.centre + to_vec(out) * sphere.radius;
    double hit_sum = 0.0;
    std::size_t hits = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (!cell_used<double>(config.mapping, i, j, n)) {
          field.store(k, i, j, false, 0.0f, Vec3f{0.0f});
          continue;
        }
        const hd::Vec3<double> l = cell_direction<double>(config.mapping, i, j, n);
        const Vec3f dir = to_vec({basis.u.x * l.x + basis.v.x * l.y + basis.w.x * l.z, basis.u.y * l.x + basis.v.y * l.y + basis.w.y * l.z,
                                  basis.u.z * l.x + basis.v.z * l.y + basis.w.z * l.z});
        const Hit hit = bvh.intersect(Ray{origin, dir, 0.0f, diameter * 1.001f});
        ++traced[k];
        const float x = hit ? hit.t / diameter : 0.0f;
        field.store(k, i, j, hit.found, x, hit.normal);
        if (hit) {
          hit_sum += x;
          ++hits;
        }
      }
    if (config.storage == CellStorage::bit) field.averages_[k] = hits > 0 ? static_cast<float>(hit_sum / hits) : 0.0f;
    if (progress) progress(1);
  });
  for (const std::size_t t : traced) field.rays_traced_ += t;
  field.build_ms_ = watch.elapsed_ms();
  return field;
}

bool ObjectField::same_tables(const ObjectFieldConfig& a, const ObjectFieldConfig& b) {
  return a.positions == b.positions && a.directions == b.directions && a.mapping == b.mapping && a.storage == b.storage &&
         a.normals == b.normals;
}

ObjectField ObjectField::from_tables(const ObjectFieldConfig& config, const BoundingSphere& sphere, std::span<const std::uint8_t> cells,
                                     std::vector<float> averages, std::span<const std::uint8_t> normals, double build_ms,
                                     std::size_t rays_traced) {
  config.validate();
  if (!is_finite(sphere.centre) || !std::isfinite(sphere.radius) || !(sphere.radius > 0.0f))
    throw Error("object field: its bounding sphere is not finite with a positive radius");
  ObjectField field(config, sphere);
  const std::size_t count = field.position_count();
  if (cells.size() != count * field.sample_stride_)
    throw Error("object field: " + std::to_string(cells.size()) + " bytes of cells, expected " + std::to_string(count * field.sample_stride_));
  if (normals.size() != count * field.normal_stride_)
    throw Error("object field: " + std::to_string(normals.size()) + " bytes of normals, expected " +
                std::to_string(count * field.normal_stride_));
  const std::size_t expected_averages = config.storage == CellStorage::bit ? count : 0;
  if (averages.size() != expected_averages)
    throw Error("object field: " + std::to_string(averages.size()) + " average distances, expected " + std::to_string(expected_averages));
  field.cells_.reserve(cells.size() + kTablePadding);
  field.cells_.assign(cells.begin(), cells.end());
  field.cells_.resize(cells.size() + kTablePadding, 0);
  if (config.normals != NormalStorage::none) {
    field.normals_.reserve(normals.size() + kTablePadding);
    field.normals_.assign(normals.begin(), normals.end());
    field.normals_.resize(normals.size() + kTablePadding, 0);
  }
  field.averages_ = std::move(averages);
  field.averages_.shrink_to_fit();
  field.build_ms_ = build_ms;
  field.rays_traced_ = rays_traced;
  return field;
}

void ObjectField::store(std::size_t sample, int i, int j, bool hit, float x, const Vec3f& normal) {
  const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(config_.directions) + static_cast<std::size_t>(i);
  std::uint8_t* base = cells_.data() + sample * sample_stride_;
  switch (config_.storage) {
    case CellStorage::u8: base[c] = static_cast<std::uint8_t>(encode_quantized(config_.storage, hit, x)); break;
    case CellStorage::u16: {
      const auto code = static_cast<std::uint16_t>(encode_quantized(config_.storage, hit, x));
      std::memcpy(base + 2 * c, &code, 2);
      break;
    }
    case CellStorage::f32: {
      const float value = hit ? x : std::numeric_limits<float>::infinity();
      std::memcpy(base + 4 * c, &value, 4);
      break;
    }
    case CellStorage::bit:
      if (hit) base[c >> 3] |= static_cast<std::uint8_t>(1u << (c & 7));
      else base[c >> 3] &= static_cast<std::uint8_t>(~(1u << (c & 7)));
      break;
  }
  if (config_.normals == NormalStorage::none || !hit) return;
  const std::uint32_t code = encode_normal(config_.normals, hd::Vec3<float>{normal.x, normal.y, normal.z});
  std::memcpy(normals_.data() + sample * normal_stride_ + c * (normal_bits(config_.normals) / 8), &code, normal_bits(config_.normals) / 8);
}

FieldAnswer ObjectField::cell(std::size_t sample, int i, int j) const {
  return read_cell(tables(), static_cast<int>(sample), i, j);
}

FieldAnswer ObjectField::trace(const Vec3f& org, const Vec3f& dir, float tmin, float tmax) const {
  return trace_field(tables(), {org.x, org.y, org.z}, {dir.x, dir.y, dir.z}, tmin, tmax);
}

}  // namespace vf::field
