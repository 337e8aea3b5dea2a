#include "visfield/field/object_field.hpp"

#include <algorithm>
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
namespace {

hd::Vec3<float> to_hd(const Vec3f& v) { return {v.x, v.y, v.z}; }

/// Folds the answers of several table reads by weight: hits win when they carry at least half the
/// weight, and their distances are averaged over the hit weight.
struct Vote {
  float total = 0.0f, hit_weight = 0.0f, distance = 0.0f;
  void add(float weight, const FieldAnswer& a) {
    total += weight;
    if (a.hit) {
      hit_weight += weight;
      distance += weight * a.t;
    }
  }
  FieldAnswer result() const {
    if (total <= 0.0f || hit_weight < 0.5f * total) return {};
    return {true, distance / hit_weight};
  }
};

}  // namespace

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
  if (direction_lookup != DirectionLookup::nearest && direction_lookup != DirectionLookup::bilinear)
    throw Error("field direction lookup: unknown value");
  if (position_lookup != PositionLookup::nearest && position_lookup != PositionLookup::blend)
    throw Error("field position lookup: unknown value");
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

double ObjectField::table_bytes(const ObjectFieldConfig& config) {
  const double cells = static_cast<double>(config.directions) * config.directions;
  const double per_sample = std::ceil(cells * cell_bits(config.storage) / 8.0);
  const double averages = config.storage == CellStorage::bit ? 4.0 : 0.0;
  // Frames as Vec3f and as rows, the upper samples' directions as rows (half the samples, 3 floats).
  return static_cast<double>(config.positions) * (per_sample + averages + 6.0 * sizeof(Vec3f) + 6.0) + 4.0;
}

double ObjectField::estimate_build_bytes(std::size_t triangles, const ObjectFieldConfig& config) {
  return table_bytes(config) + Bvh::estimate_build_bytes(triangles);
}

ObjectField::ObjectField(const ObjectFieldConfig& config, const BoundingSphere& sphere)
    : config_(config), sphere_(sphere), positions_(config.position_level()) {
  const std::size_t cells = static_cast<std::size_t>(config.directions) * static_cast<std::size_t>(config.directions);
  sample_stride_ = (cells * static_cast<std::size_t>(cell_bits(config.storage)) + 7) / 8;
  const float n = static_cast<float>(positions_.lattice_size());
  self_offset_ = 0.5f / static_cast<float>(config.directions) + 0.25f * (std::numbers::pi_v<float> / 2.0f) / n;
}

ObjectField ObjectField::build(const TriangleSet& object_triangles, const ObjectFieldConfig& config,
                               const std::function<void(std::size_t)>& progress) {
  config.validate();
  if (object_triangles.size() == 0) throw Error("object field: the mesh has no triangles");
  require_memory(estimate_build_bytes(object_triangles.size(), config),
                 "an object field of " + std::to_string(config.positions) + " positions x " +
                     std::to_string(config.directions) + "^2 " + storage_name(config.storage) + " cells");
  const Stopwatch watch;
  ObjectField field(config, bounding_sphere_of(object_triangles));
  const Bvh bvh = Bvh::build(object_triangles);
  const std::size_t count = field.positions_.size();
  const int n = config.directions;
  field.cells_.assign(count * field.sample_stride_ + kTablePadding, 0);
  if (config.storage == CellStorage::bit) field.averages_.assign(count, 0.0f);
  field.compute_frames();
  const BoundingSphere sphere = field.sphere_;
  const float diameter = 2.0f * sphere.radius;
  std::vector<std::size_t> traced(count, 0);
  vf::parallel_for(std::size_t{0}, count, [&](std::size_t k) {
    check_interrupt();
    const hd::Vec3<double> out = field.positions_.direction(k);
    const OrthonormalBasis<double> basis = orthonormal_basis(hd::Vec3<double>{-out.x, -out.y, -out.z});
    const auto f = [](const hd::Vec3<double>& v) { return Vec3f{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; };
    const Vec3f origin = sphere.centre + f(out) * sphere.radius;
    double hit_sum = 0.0;
    std::size_t hits = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (!cell_used<double>(config.mapping, i, j, n)) {
          field.store(k, i, j, false, 0.0f);
          continue;
        }
        const hd::Vec3<double> l = cell_direction<double>(config.mapping, i, j, n);
        const Vec3f dir = f({basis.u.x * l.x + basis.v.x * l.y + basis.w.x * l.z, basis.u.y * l.x + basis.v.y * l.y + basis.w.y * l.z,
                             basis.u.z * l.x + basis.v.z * l.y + basis.w.z * l.z});
        const Hit hit = bvh.intersect(Ray{origin, dir, 0.0f, diameter * 1.001f});
        ++traced[k];
        const float x = hit ? hit.t / diameter : 0.0f;
        field.store(k, i, j, hit.found, x);
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

void ObjectField::compute_frames() {
  const std::size_t count = positions_.size(), upper = count / 2;
  frames_.resize(3 * count);
  lookup_rows_.assign(3 * upper + 9 * count, 0.0f);
  const hd::Vec3<float>* table = positions_.upper_table();
  for (std::size_t k = 0; k < upper; ++k) {
    lookup_rows_[k] = table[k].x;
    lookup_rows_[upper + k] = table[k].y;
    lookup_rows_[2 * upper + k] = table[k].z;
  }
  for (std::size_t k = 0; k < positions_.size(); ++k) {
    const hd::Vec3<double> out = positions_.direction(k);
    const OrthonormalBasis<double> basis = orthonormal_basis(hd::Vec3<double>{-out.x, -out.y, -out.z});
    const auto f = [](const hd::Vec3<double>& v) { return Vec3f{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; };
    frames_[3 * k] = f(basis.u);
    frames_[3 * k + 1] = f(basis.v);
    frames_[3 * k + 2] = f(basis.w);
    for (int row = 0; row < 9; ++row) lookup_rows_[3 * upper + static_cast<std::size_t>(row) * count + k] = frames_[3 * k + row / 3][row % 3];
  }
}

bool ObjectField::same_tables(const ObjectFieldConfig& a, const ObjectFieldConfig& b) {
  return a.positions == b.positions && a.directions == b.directions && a.mapping == b.mapping && a.storage == b.storage;
}

ObjectField ObjectField::from_tables(const ObjectFieldConfig& config, const BoundingSphere& sphere, std::vector<std::uint8_t> cells,
                                     std::vector<float> averages, double build_ms, std::size_t rays_traced) {
  config.validate();
  if (!is_finite(sphere.centre) || !std::isfinite(sphere.radius) || !(sphere.radius > 0.0f))
    throw Error("object field: its bounding sphere is not finite with a positive radius");
  ObjectField field(config, sphere);
  if (cells.size() != field.positions_.size() * field.sample_stride_)
    throw Error("object field: " + std::to_string(cells.size()) + " bytes of cells, expected " +
                std::to_string(field.positions_.size() * field.sample_stride_));
  const std::size_t expected_averages = config.storage == CellStorage::bit ? field.positions_.size() : 0;
  if (averages.size() != expected_averages)
    throw Error("object field: " + std::to_string(averages.size()) + " average distances, expected " + std::to_string(expected_averages));
  field.cells_.reserve(cells.size() + kTablePadding);
  field.cells_.assign(cells.begin(), cells.end());
  field.cells_.resize(cells.size() + kTablePadding, 0);
  field.averages_ = std::move(averages);
  field.compute_frames();
  field.build_ms_ = build_ms;
  field.rays_traced_ = rays_traced;
  return field;
}

void ObjectField::store(std::size_t sample, int i, int j, bool hit, float x) {
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
}

FieldAnswer ObjectField::cell(std::size_t sample, int i, int j) const {
  const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(config_.directions) + static_cast<std::size_t>(i);
  const std::uint8_t* base = cells_.data() + sample * sample_stride_;
  switch (config_.storage) {
    case CellStorage::u8: {
      const unsigned code = base[c];
      return quantized_is_hit(CellStorage::u8, code) ? FieldAnswer{true, decode_quantized(CellStorage::u8, code)} : FieldAnswer{};
    }
    case CellStorage::u16: {
      std::uint16_t code;
      std::memcpy(&code, base + 2 * c, 2);
      return quantized_is_hit(CellStorage::u16, code) ? FieldAnswer{true, decode_quantized(CellStorage::u16, code)} : FieldAnswer{};
    }
    case CellStorage::f32: {
      float value;
      std::memcpy(&value, base + 4 * c, 4);
      return value <= 1.5f ? FieldAnswer{true, value} : FieldAnswer{};
    }
    case CellStorage::bit:
      return (base[c >> 3] >> (c & 7)) & 1u ? FieldAnswer{true, averages_[sample]} : FieldAnswer{};
  }
  return {};
}

FieldAnswer ObjectField::read(std::size_t sample, const Vec3f& d) const {
  const Vec3f* frame = &frames_[3 * sample];
  hd::Vec3<float> local{dot(frame[0], d), dot(frame[1], d), dot(frame[2], d)};
  if (local.z < 0.0f) {  // grazing: the sample's pole differs a little from the entry point's normal
    const float planar = std::sqrt(local.x * local.x + local.y * local.y);
    local = planar > 0.0f ? hd::Vec3<float>{local.x / planar, local.y / planar, 0.0f} : hd::Vec3<float>{0.0f, 0.0f, 1.0f};
  }
  float s, t;
  direction_to_square(config_.mapping, local, s, t);
  const int n = config_.directions;
  if (config_.direction_lookup == DirectionLookup::nearest) return cell(sample, cell_of(s, n), cell_of(t, n));
  // Bilinear over the four cell centres around (s, t); polar tables wrap around in s.
  const float fx = s * static_cast<float>(n) - 0.5f, fy = t * static_cast<float>(n) - 0.5f;
  const int i0 = static_cast<int>(std::floor(fx)), j0 = static_cast<int>(std::floor(fy));
  const float a = fx - static_cast<float>(i0), b = fy - static_cast<float>(j0);
  Vote vote;
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      int i = i0 + di;
      const int j = std::clamp(j0 + dj, 0, n - 1);
      i = config_.mapping == HemisphereMapping::polar ? (i + n) % n : std::clamp(i, 0, n - 1);
      if (!cell_used<float>(config_.mapping, i, j, n)) continue;
      const float w = (di ? a : 1.0f - a) * (dj ? b : 1.0f - b);
      vote.add(w, cell(sample, i, j));
    }
  return vote.result();
}

FieldAnswer ObjectField::read_at(const Vec3f& from_centre, const Vec3f& d) const {
  const int n = positions_.lattice_size();
  if (config_.position_lookup == PositionLookup::nearest)
    return read(static_cast<std::size_t>(nearest_position(to_hd(from_centre), n, positions_.upper_table())), d);
  const PositionBlend<float> blend = blend_positions(to_hd(from_centre), n);
  Vote vote;
  for (int k = 0; k < 3; ++k)
    if (blend.weight[k] > 0.0f) vote.add(blend.weight[k], read(static_cast<std::size_t>(blend.index[k]), d));
  return vote.result();
}

FieldAnswer ObjectField::trace(const Vec3f& org, const Vec3f& dir, float tmin, float tmax) const {
  const float len = length(dir);
  const Vec3f d = dir * (1.0f / len);
  const float s_min = tmin * len, s_max = tmax * len;
  const float r = sphere_.radius, diameter = 2.0f * r;
  const Vec3f oc = org - sphere_.centre;
  const float b = dot(oc, d), c = dot(oc, oc) - r * r;
  const float disc = b * b - c;
  if (disc < 0.0f) return {};
  const float root = std::sqrt(disc);
  const float s_enter = -b - root, s_exit = -b + root;
  float s_hit;
  if (c > 0.0f) {
    // Inter-object: the table of the sample where the ray enters.
    if (s_enter < 0.0f) return {};
    const Vec3f entry = oc + d * s_enter;
    const FieldAnswer a = read_at(normalize(entry), d);
    if (!a.hit) return {};
    s_hit = s_enter + a.t * diameter;
  } else {
    // Intra-object: d2, stored at the exit point for the reverse direction, against d1 = s_exit.
    const Vec3f exit = oc + d * s_exit;
    const FieldAnswer a = read_at(normalize(exit), -d);
    if (!a.hit) return {};
    s_hit = s_exit - a.t * diameter;
    if (s_hit <= self_offset_ * diameter) return {};
  }
  if (s_hit < s_min || s_hit > s_max) return {};
  return {true, s_hit / len};
}

}  // namespace vf::field
