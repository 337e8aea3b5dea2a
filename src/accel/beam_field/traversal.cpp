// BeamField queries (VLF-RT §3.3–5). The ray looks up its nearest line, is clipped to the bounding
// sphere, and its projection on the line's PSF base is walked tile by tile front to back (a 2D DDA);
// in each tile the ray's depth interval there picks the first and last tile-BSP leaf, and the leaves
// are visited linearly near to far. A ray along a stored direction stays in one tile: no walk.
//
// Why the answer is exact: a triangle the ray hits at parameter τ is referenced by the tile that
// holds the projection of the hit point (tiles are rasterised with a slack far above every rounding
// here), in the leaves of its depth range clipped to that beam (widened by the same slack); the walk
// visits every tile the projected segment crosses, with the τ interval it spends there, and in it the
// leaves of that interval. There the ray point at τ lies within the slack of the triangle, so inside
// the reference's footprint (its clipped box widened by the slack), and the footprint filter keeps
// it. Each kept triangle gets the full watertight test (the same as brute force), so every reported
// t is brute force's t. The walk stops only when every τ below the best
// hit has been covered, with a margin for the rounding of the float t.
//
// A kernel file: compiled once per instruction set (src/core/isa_dispatch.hpp).

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>

#include "beam_field/beam_layout.hpp"
#include "beam_field/tile_footprint.hpp"
#include "beam_field/tile_geometry.hpp"
#include "beam_field/tile_raster.hpp"
#include "core/isa_dispatch.hpp"
#include "simd/watertight_block.hpp"
#include "visfield/accel/beam_field.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/triangle_intersect.hpp"

namespace vf::isa_avx512 {
Hit beam_intersect(const BeamField& field, const Ray& ray, BeamQueryCounters* counters);
bool beam_occluded(const BeamField& field, const Ray& ray, BeamQueryCounters* counters);
Hit beam_intersect_on_line(const BeamField& field, const Ray& ray, std::uint32_t line);
bool beam_occluded_on_line(const BeamField& field, const Ray& ray, std::uint32_t line);
void intersect_batch(const BeamField& field, std::span<const Ray> rays, std::span<Hit> hits);
void occluded_batch(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
void occluded_block(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
}  // namespace vf::isa_avx512

namespace vf {
namespace beam {
namespace {

/// Counting policies: NoCount compiles to nothing.
struct NoCount {
  void ray() {}
  void single_tile() {}
  void tile() {}
  void leaf() {}
  void test() {}
};
struct Count {
  BeamQueryCounters& c;
  void ray() { ++c.rays; }
  void single_tile() { ++c.single_tile; }
  void tile() { ++c.tiles; }
  void leaf() { ++c.leaves; }
  void test() { ++c.triangle_tests; }
};

constexpr std::uint32_t kNoLine = 0xffffffffu;

// Relative error allowed for a float t from the watertight test when deciding that every τ below it
// has been searched (the test's t is a convex combination of the corners' depths, accurate to a few
// float ulps; 1e-5 is far above that and costs at most a leaf more).
constexpr double kTRelativeMargin = 1e-5;

// The float watertight test decides a hit as if the triangle's corners were moved by up to about
// 1e-6 of their distance from the ray's origin (the shear and the edge products round relative to
// the coordinates), so the ray point at a reported t lies within that distance of a point of the
// triangle. 4e-6 (|o - c| + R) bounds it with room to spare; the build's slack covers it for
// origins within 4 R of the centre, and a ray from farther widens its own walk by it.
constexpr double kLateralError = 4e-6;

/// A ray in the frame of a line: the part of it inside the bounding sphere (a little wider, for
/// rounding), τ in [ta, tb], and its origin and direction in PSF coordinates (s, t across the line,
/// shifted by R so that tiles start at 0; w along it). Every walk and the per-tile packets start here,
/// so that they pick the same tiles, leaves and footprint keys.
struct LineFrameRay {
  double ta = 0, tb = 0;
  double s0 = 0, t0 = 0, w0 = 0, ds = 0, dt = 0, dw = 0;
  double inv_dir_length = 0;  ///< 1 / |dir|
  double lateral = 0;         ///< How far a reported hit point may lie from its triangle (kLateralError).
  bool forward = true;        ///< Along the line (w grows with τ).

  /// Sets up `ray` (valid) in the frame of `line`; false when it misses the sphere or its part inside
  /// is empty.
  bool set(const BeamLayout& layout, const Ray& ray, std::uint32_t line) {
    const TileGeometry& g = layout.geometry;
    const FrameD& f = layout.frames[line];
    const double dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
    const double ox = static_cast<double>(ray.org.x) - g.center[0], oy = static_cast<double>(ray.org.y) - g.center[1],
                 oz = static_cast<double>(ray.org.z) - g.center[2];
    const double dd = dx * dx + dy * dy + dz * dz;
    const double oo = ox * ox + oy * oy + oz * oz;
    const double length = std::sqrt(dd);
    // The chord from the line's point nearest the centre (Haines et al., Ray Tracing Gems ch. 7):
    // b^2 - dd (oo - r^2) would cancel to nothing for an origin a million radii away.
    const double ux = dx / length, uy = dy / length, uz = dz / length;
    const double along = ox * ux + oy * uy + oz * uz;
    const double qx = ox - along * ux, qy = oy - along * uy, qz = oz - along * uz;
    const double half_chord2 = g.radius * g.radius - (qx * qx + qy * qy + qz * qz);
    if (!(half_chord2 >= 0.0)) return false;
    const double half_chord = std::sqrt(half_chord2);
    const double pad = (1e-9 * (std::fabs(along) + half_chord) + g.slack) / length;
    const double t_in = (-along - half_chord) / length - pad, t_out = (-along + half_chord) / length + pad;
    ta = std::max<double>(ray.tmin, t_in), tb = std::min<double>(ray.tmax, t_out);
    if (!(ta <= tb)) return false;
    s0 = f.u[0] * ox + f.u[1] * oy + f.u[2] * oz + g.radius;
    t0 = f.v[0] * ox + f.v[1] * oy + f.v[2] * oz + g.radius;
    w0 = f.w[0] * ox + f.w[1] * oy + f.w[2] * oz;
    ds = f.u[0] * dx + f.u[1] * dy + f.u[2] * dz;
    dt = f.v[0] * dx + f.v[1] * dy + f.v[2] * dz;
    dw = f.w[0] * dx + f.w[1] * dy + f.w[2] * dz;
    forward = dw >= 0.0;
    inv_dir_length = 1.0 / length;
    lateral = kLateralError * (std::sqrt(oo) + g.radius);
    return true;
  }

  /// The tile (ix, iy) where τ = ta projects and whether τ = tb projects into the same one (clamped
  /// to the grid): the single-tile fast path.
  bool single_tile(const TileGeometry& g, int& ix, int& iy) const {
    const double inv = g.inv_tile_size;
    const double xa = (s0 + ta * ds) * inv, xb = (s0 + tb * ds) * inv;
    const double ya = (t0 + ta * dt) * inv, yb = (t0 + tb * dt) * inv;
    ix = clamp_cell(xa, g.n), iy = clamp_cell(ya, g.n);
    return ix == clamp_cell(xb, g.n) && iy == clamp_cell(yb, g.n);
  }

  /// The footprint key of the ray's points over τ in [enter, exit] in tile (ix, iy), widened by
  /// `margin` (a hit point lies within it of the triangle) and a rounding allowance.
  std::uint32_t segment_key(const TileGeometry& g, int ix, int iy, double enter, double exit, double margin) const {
    const double x = ix, y = iy;
    const double inv = g.inv_tile_size, e = margin * inv + 1e-9;
    const double sa = (s0 + enter * ds) * inv - x, sb = (s0 + exit * ds) * inv - x;
    const double ya = (t0 + enter * dt) * inv - y, yb = (t0 + exit * dt) * inv - y;
    return footprint_key(std::min(sa, sb) - e, std::max(sa, sb) + e, std::min(ya, yb) - e, std::max(ya, yb) + e);
  }

  /// The leaves of `record` from the one holding the depth at τ = enter to the one holding it at
  /// τ = exit (walk order; `from` > `to` walking against the line), widened by `depth_margin`.
  void leaves(const RecordView& record, double enter, double exit, double depth_margin, int& from, int& to) const {
    const double sign = forward ? 1.0 : -1.0;
    const double w_enter = w0 + enter * dw - sign * depth_margin, w_exit = w0 + exit * dw + sign * depth_margin;
    from = leaf_of(w_enter, record.lo(), record.scale(), record.last_leaf());
    to = leaf_of(w_exit, record.lo(), record.scale(), record.last_leaf());
  }

  static int clamp_cell(double x, int n) {
    if (!(x > 0.0)) return 0;
    if (x >= n - 1) return n - 1;
    return static_cast<int>(x);
  }
};

/// The walk of one ray. kAny: stop at the first hit (occlusion).
template <bool kAny, class Counter>
class Walk {
 public:
  Walk(const BeamLayout& layout, const Ray& ray, Counter counter)
      : layout_(layout), ray_(ray), wray_(ray), counter_(counter) {}

  /// The answer, with the ray's nearest line looked up here or given (any line gives the same answer).
  Hit run(std::uint32_t given_line = kNoLine) {
    counter_.ray();
    if (!ray_.is_valid() || layout_.live_slots == 0) return {};
    const TileGeometry& g = layout_.geometry;
    const std::uint32_t line = given_line == kNoLine ? layout_.lines.nearest(ray_.dir).line : given_line;
    dir_ = &layout_.directions[line];
    if (!f_.set(layout_, ray_, line)) return {};
    const double ta = f_.ta, tb = f_.tb;
    if (f_.lateral > g.slack) return run_wide(ta, tb, f_.lateral);
    margin_ = g.slack;
    const double inv = g.inv_tile_size;
    const int n = g.n;
    int ix = 0, iy = 0;
    if (f_.single_tile(g, ix, iy)) {
      counter_.single_tile();
      visit_tile(ix, iy, ta, tb, 0.0, true);
      return best_;
    }

    // 2D DDA over the tiles the projected segment crosses, with the τ interval spent in each.
    const double x_rate = f_.ds * inv, y_rate = f_.dt * inv;
    const int step_x = x_rate > 0.0 ? 1 : -1, step_y = y_rate > 0.0 ? 1 : -1;
    const auto next_crossing = [&](int cell, int step, double origin, double rate) {
      if (rate == 0.0) return std::numeric_limits<double>::infinity();
      const double boundary = (cell + (step > 0 ? 1 : 0)) * g.tile_size;
      return (boundary - origin) / (rate * g.tile_size);
    };
    double enter = ta;
    double cross_x = next_crossing(ix, step_x, f_.s0, x_rate), cross_y = next_crossing(iy, step_y, f_.t0, y_rate);
    for (;;) {
      const double exit = std::max(enter, std::min({cross_x, cross_y, tb}));
      if (visit_tile(ix, iy, enter, exit, 0.0, true))
        return best_;
      if (exit >= tb) return best_;
      if (best_ && stop_t() <= exit) return best_;
      if (cross_x <= cross_y) {
        ix += step_x;
        enter = cross_x;
        cross_x = next_crossing(ix, step_x, f_.s0, x_rate);
      } else {
        iy += step_y;
        enter = cross_y;
        cross_y = next_crossing(iy, step_y, f_.t0, y_rate);
      }
      if (ix < 0 || ix >= n || iy < 0 || iy >= n) return best_;
    }
  }

 private:
  // The walk of a ray whose origin is too far for the build's slack: every tile within `lateral` of
  // the projected segment, in the order the ray enters them (each with its τ interval in the tile
  // widened by `lateral`), every leaf of that interval widened by `lateral` in depth. Rare (origins
  // beyond 4 R of the centre), so plainness wins over speed here.
  Hit run_wide(double ta, double tb, double lateral) {
    const TileGeometry& g = layout_.geometry;
    margin_ = lateral;
    const double inv = g.inv_tile_size;
    const double e = lateral * inv;  // in tiles
    const double x0 = f_.s0 * inv, y0 = f_.t0 * inv, xr = f_.ds * inv, yr = f_.dt * inv;
    std::vector<std::uint32_t> tiles;
    const Point2 a{x0 + ta * xr, y0 + ta * yr}, b{x0 + tb * xr, y0 + tb * yr};
    rasterize_triangle(TileGrid{0.0, 0.0, 1.0, g.n}, a, b, b, e, tiles);
    struct Span {
      double enter, exit;
      std::uint32_t tile;
    };
    std::vector<Span> spans;
    spans.reserve(tiles.size());
    const auto slab = [&](double origin, double rate, double lo, double hi, double& enter, double& exit) {
      if (rate == 0.0) return;
      double t1 = (lo - origin) / rate, t2 = (hi - origin) / rate;
      if (t1 > t2) std::swap(t1, t2);
      enter = std::max(enter, t1), exit = std::min(exit, t2);
    };
    const auto n = static_cast<std::uint32_t>(g.n);
    for (const std::uint32_t tile : tiles) {
      const double x = tile % n, y = tile / n;
      double enter = ta, exit = tb;
      slab(x0, xr, x - 2.0 * e, x + 1.0 + 2.0 * e, enter, exit);
      slab(y0, yr, y - 2.0 * e, y + 1.0 + 2.0 * e, enter, exit);
      // The rasteriser found the tile within e of the segment; should rounding make the widened
      // slabs miss it, the whole segment stands in (conservative).
      if (!(enter <= exit)) enter = ta, exit = tb;
      spans.push_back({enter, exit, tile});
    }
    std::sort(spans.begin(), spans.end(), [](const Span& p, const Span& q) { return p.enter < q.enter || (p.enter == q.enter && p.tile < q.tile); });
    for (const Span& span : spans) {
      if (best_ && stop_t() < span.enter) break;
      if (visit_tile(static_cast<int>(span.tile % n), static_cast<int>(span.tile / n), span.enter, span.exit, lateral, false))
        return best_;
    }
    return best_;
  }

  // A τ beyond which no hit can beat the best one, for the float rounding of best_.t.
  double stop_t() const {
    const double t = best_.t;
    return t + kTRelativeMargin * std::fabs(t) + margin_ * f_.inv_dir_length;
  }

  // Tests the leaves of tile (ix, iy) that the ray's τ interval [enter, exit] covers, widened by
  // `depth_margin` in depth. Returns true when the walk is over: a hit for kAny, or (when `may_finish`,
  // i.e. every earlier τ is searched) a closest hit no later leaf or tile can beat.
  bool visit_tile(int ix, int iy, double enter, double exit, double depth_margin, bool may_finish) {
    counter_.tile();
    const std::uint32_t offset = dir_->tiles[static_cast<std::size_t>(iy) * static_cast<std::size_t>(layout_.geometry.n) + static_cast<std::size_t>(ix)];
    if (offset == kEmptyTile) return false;
    const RecordView record(dir_->arena.data() + offset);
    const double lo = record.lo(), scale = record.scale();
    const int last = record.last_leaf();
    const std::uint32_t key = f_.segment_key(layout_.geometry, ix, iy, enter, exit, margin_);
    // Leaves in walk order, from the one holding the entry depth to the one holding the exit depth.
    int from = 0, to = 0;
    f_.leaves(record, enter, exit, depth_margin, from, to);
    const int step = from <= to ? 1 : -1;
    for (int leaf = from;; leaf += step) {
      counter_.leaf();
      if (record.leaf_size(leaf) != 0 && test_leaf(record, leaf, key)) return true;
      if (!kAny && may_finish && best_) {
        // Every τ of this tile up to the end of this leaf is searched (and every τ before the tile):
        // done when the best hit lies before both.
        const double t_stop = stop_t();
        const int stop_leaf = leaf_of(f_.w0 + t_stop * f_.dw, lo, scale, last);
        if (t_stop <= exit && (f_.forward ? stop_leaf <= leaf : stop_leaf >= leaf)) return true;
      }
      if (leaf == to) return false;
    }
  }

  // Tests the references of `leaf` whose footprint overlaps `key`: their triangles are fetched
  // together first (they are scattered over the triangle array), then tested in reference order,
  // kBlock at a time with the SIMD watertight test of the BVH's leaves (a lone one with the scalar
  // test: the same bits either way). Returns true when kAny and one is hit.
  bool test_leaf(const RecordView& record, int leaf, std::uint32_t key) {
    const std::uint32_t* slots = record.leaf_slots(leaf);
    const std::uint32_t size = record.leaf_size(leaf);
    const std::uint32_t* footprints = record.leaf_footprints(leaf);
    constexpr std::uint32_t kBatch = 16;
    std::uint32_t batch[kBatch];
    for (std::uint32_t begin = 0; begin < size; begin += kBatch) {
      std::uint32_t count = 0;
      for_each_overlapping(footprints, begin, std::min(size, begin + kBatch), key, [&](std::uint32_t r) {
        batch[count++] = slots[r];
        __builtin_prefetch(&layout_.triangles[slots[r]]);
        return false;
      });
      for (std::uint32_t k = 0; k < count; k += kBlock) {
        const std::uint32_t n = std::min<std::uint32_t>(kBlock, count - k);
        if ((n == 1 ? test(batch[k]) : test_block(batch + k, n)) && kAny) return true;
      }
    }
    return false;
  }

  // Tests triangle slots[0 .. n) (2 <= n <= kBlock) at once; true when one is hit (for closest
  // hits: when one became the best, in reference order, as test() one by one would).
  bool test_block(const std::uint32_t* slots, std::uint32_t n) {
    if (!block_ray_) {
      block_ray_.emplace(wray_);
      block_tmin_ = simd::Lanes<kBlock>::broadcast(ray_.tmin);
      for (int lane = 0; lane < static_cast<int>(kBlock); ++lane) block_.clear(lane);
    }
    for (std::uint32_t k = 0; k < n; ++k) {
      counter_.test();
      const std::array<Vec3f, 3>& p = layout_.triangles[slots[k]];
      block_.set(static_cast<int>(k), p[0], p[1], p[2]);
    }
    // Lanes past n keep their last triangle's coordinates but corner 0 made NaN: unused lanes.
    for (std::uint32_t k = n; k < block_used_; ++k)
      for (int axis = 0; axis < 3; ++axis) block_.p[axis * kBlock + k] = std::numeric_limits<float>::quiet_NaN();
    block_used_ = n;
    const simd::Lanes<kBlock> tmax = simd::Lanes<kBlock>::broadcast(best_ ? best_.t : ray_.tmax);
    if constexpr (kAny) {
      if (simd::intersect_block<kBlock, false>(block_, *block_ray_, block_tmin_, tmax, nullptr) == 0) return false;
      best_.found = true;
      return true;
    } else {
      simd::BlockHits<kBlock> hits;
      simd::LaneBits lanes = simd::intersect_block<kBlock, true>(block_, *block_ray_, block_tmin_, tmax, &hits);
      bool improved = false;
      for (; lanes != 0; lanes &= lanes - 1) {
        const int l = simd::first_lane(lanes);
        const std::uint32_t slot = slots[l];
        const ObjectId id = layout_.instance[slot];
        const std::uint32_t prim = layout_.prim[slot];
        // As test() in reference order: a later lane must beat the best so far; equal t goes to the
        // lower (object, triangle).
        if (best_ && (hits.t[l] > best_.t || (hits.t[l] == best_.t && (id > best_.instance || (id == best_.instance && prim >= best_.prim)))))
          continue;
        best_ = Hit::triangle(hits.t[l], hits.u[l], hits.v[l], prim, id, block_.normal(l));
        improved = true;
      }
      return improved;
    }
  }

  bool test(std::uint32_t slot) {
    counter_.test();
    const std::array<Vec3f, 3>& p = layout_.triangles[slot];
    TriangleHit h;
    const float tmax = best_ ? best_.t : ray_.tmax;
    if (!intersect_triangle(wray_, p[0], p[1], p[2], ray_.tmin, tmax, h)) return false;
    if constexpr (!kAny) {
      const ObjectId id = layout_.instance[slot];
      const std::uint32_t prim = layout_.prim[slot];
      // Equal t: the lower (object, triangle) wins, as brute force over the flattened scene.
      if (best_ && h.t == best_.t && (id > best_.instance || (id == best_.instance && prim >= best_.prim))) return true;
      best_ = Hit::triangle(h.t, h.u, h.v, prim, id, cross(p[1] - p[0], p[2] - p[0]));
    } else {
      best_.found = true;
    }
    return true;
  }

  static constexpr std::uint32_t kBlock = 8;

  const BeamLayout& layout_;
  const Ray& ray_;
  WatertightRay wray_;
  // The SIMD block test's ray and triangles, made on the first block of a walk.
  std::optional<simd::BlockRay<kBlock>> block_ray_;
  simd::Lanes<kBlock> block_tmin_;
  simd::TriangleBlock<kBlock> block_;
  std::uint32_t block_used_ = kBlock;
  Counter counter_;
  const DirectionTiles* dir_ = nullptr;
  LineFrameRay f_;
  double margin_ = 0;  // lateral margin of this walk (the build's slack, or the ray's own)
  Hit best_;
};

/// The tile of line `line` that holds the projection of `origin` (clamped to the grid): where a ray
/// from there along the line is traced. Only an ordering key: any value gives the same answers.
std::uint32_t origin_tile(const BeamLayout& layout, const Vec3f& origin, std::uint32_t line) {
  const TileGeometry& g = layout.geometry;
  const PsfPoint p = project(layout.frames[line], g.center, origin);
  return static_cast<std::uint32_t>(g.cell(p.t)) * static_cast<std::uint32_t>(g.n) + static_cast<std::uint32_t>(g.cell(p.s));
}

/// Starts loading the header of tile `tile`'s record in direction `line`.
void prefetch_record(const BeamLayout& layout, std::uint32_t line, std::uint32_t tile) {
  const DirectionTiles& dir = layout.directions[line];
  const std::uint32_t offset = dir.tiles[tile];
  if (offset == kEmptyTile) return;
  const std::uint32_t* record = dir.arena.data() + offset;
  __builtin_prefetch(record);
  __builtin_prefetch(record + 16);  // the leaf starts of a deeper tile-BSP
}

/// Starts loading the footprints and references of the leaf of tile `tile` (direction `line`) that
/// holds the depth of `ray`'s origin: the first leaf the ray tests when it runs along the line.
void prefetch_origin_leaf(const BeamLayout& layout, const Ray& ray, std::uint32_t line, std::uint32_t tile) {
  const DirectionTiles& dir = layout.directions[line];
  const std::uint32_t offset = dir.tiles[tile];
  if (offset == kEmptyTile) return;
  const RecordView record(dir.arena.data() + offset);
  const FrameD& f = layout.frames[line];
  const PsfPoint p = project(f, layout.geometry.center, ray.org);
  const int leaf = leaf_of(p.w, record.lo(), record.scale(), record.last_leaf());
  // The walk reads from this leaf on, towards higher leaves for a ray along the line, lower ones
  // for a ray against it: four lines that way.
  const bool forward = f.w[0] * ray.dir.x + f.w[1] * ray.dir.y + f.w[2] * ray.dir.z >= 0.0;
  const auto* at = reinterpret_cast<const char*>(record.leaf_footprints(leaf));
  for (int k = 0; k < 4; ++k) __builtin_prefetch(at + (forward ? 64 : -64) * k);
}

/// Sorts idx[0 .. count) by key[idx[k]] (< key_count), the order among equal keys unspecified: a
/// counting sort when the keys are few against the group (O(count + key_count)), else a comparison
/// sort of the small group. `scratch` is reused between calls.
void sort_by_key(std::uint32_t* idx, std::size_t count, const std::uint32_t* key, std::size_t key_count, std::vector<std::uint32_t>& scratch) {
  if (count < 2) return;
  if (key_count > 4 * count) {
    std::sort(idx, idx + count, [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
    return;
  }
  scratch.assign(key_count + 1 + count, 0);
  std::uint32_t* start = scratch.data();
  std::uint32_t* sorted = scratch.data() + key_count + 1;
  for (std::size_t k = 0; k < count; ++k) ++start[key[idx[k]] + 1];
  for (std::size_t k = 0; k < key_count; ++k) start[k + 1] += start[k];
  for (std::size_t k = 0; k < count; ++k) sorted[start[key[idx[k]]]++] = idx[k];
  std::copy(sorted, sorted + count, idx);
}

/// The indices i of line_of counting-sorted by line_of[i] (< lines): order, with line k's indices in
/// order[start[k] .. start[k + 1]), each line's in increasing i.
std::pair<std::vector<std::size_t>, std::vector<std::uint32_t>> order_by_line(std::size_t lines, const std::vector<std::uint32_t>& line_of) {
  std::vector<std::size_t> start(lines + 1, 0);
  for (const std::uint32_t line : line_of) ++start[line + 1];
  for (std::size_t k = 0; k < lines; ++k) start[k + 1] += start[k];
  std::vector<std::uint32_t> order(line_of.size());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < line_of.size(); ++i) order[fill[line_of[i]]++] = static_cast<std::uint32_t>(i);
  return {std::move(start), std::move(order)};
}

/// Runs query(i, rays[i], line_of(i)) for i = idx[0 .. count), in that order (sorted by line and origin
/// tile, tile_of(i)): a block's rays, lines and tiles are first gathered into local arrays
/// (independent loads, which the memory system overlaps), then traced in order with each ray's tile
/// record prefetched kRecordAhead rays ahead and its origin leaf kLeafAhead rays ahead (by when the
/// record has arrived), so that the misses of consecutive rays overlap too.
template <class LineOf, class TileOf, class Query>
void trace_in_order(const BeamLayout& layout, std::span<const Ray> rays, const std::uint32_t* idx, std::size_t count, LineOf&& line_of,
                    TileOf&& tile_of, Query&& query) {
  constexpr std::size_t kBlock = 256, kRecordAhead = 16, kLeafAhead = 8;
  Ray block_rays[kBlock];
  std::uint32_t block_lines[kBlock], block_tiles[kBlock];
  for (std::size_t first = 0; first < count; first += kBlock) {
    const std::size_t size = std::min(kBlock, count - first);
    for (std::size_t k = 0; k < size; ++k) {
      const std::uint32_t i = idx[first + k];
      block_rays[k] = rays[i];
      block_lines[k] = line_of(i);
      block_tiles[k] = tile_of(i);
    }
    for (std::size_t k = 0; k < size; ++k) {
      if (k + kRecordAhead < size) prefetch_record(layout, block_lines[k + kRecordAhead], block_tiles[k + kRecordAhead]);
      if (k + kLeafAhead < size) prefetch_origin_leaf(layout, block_rays[k + kLeafAhead], block_lines[k + kLeafAhead], block_tiles[k + kLeafAhead]);
      query(idx[first + k], block_rays[k], block_lines[k]);
    }
  }
}

/// Runs query(i, rays[i], line) for every ray, grouped by nearest line and, within a line, by the
/// tile of the origin: lines and tiles are found in parallel, the ray indices counting-sorted by line,
/// each line's indices sorted by tile (in parallel), and the sorted order traced in parallel chunks.
/// The field is far larger than the caches: this order reads each direction's tile records once,
/// front to back, instead of once per ray (AO rays from one point use every direction).
/// `line_of`, when given, holds every ray's nearest line already.
template <class Query>
void for_each_by_line(const BeamLayout& layout, std::span<const Ray> rays, Query&& query, std::vector<std::uint32_t> line_of = {}) {
  const bool lines_known = line_of.size() == rays.size();
  line_of.resize(rays.size());
  std::vector<std::uint32_t> tile_of(rays.size());
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (!lines_known) line_of[i] = rays[i].is_valid() ? layout.lines.nearest(rays[i].dir).line : 0;
      tile_of[i] = rays[i].is_valid() ? origin_tile(layout, rays[i].org, line_of[i]) : 0;
    }
  });
  auto by_line = order_by_line(layout.lines.size(), line_of);
  const std::vector<std::size_t>& start = by_line.first;
  std::vector<std::uint32_t>& order = by_line.second;
  const std::size_t tiles = static_cast<std::size_t>(layout.geometry.n) * static_cast<std::size_t>(layout.geometry.n);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, layout.lines.size(), 8), [&](const auto& range) {
    std::vector<std::uint32_t> scratch;
    for (std::size_t line = range.begin(); line != range.end(); ++line)
      sort_by_key(order.data() + start[line], start[line + 1] - start[line], tile_of.data(), tiles, scratch);
  });
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 1024), [&](const auto& range) {
    check_interrupt();
    trace_in_order(
        layout, rays, order.data() + range.begin(), range.size(), [&](std::uint32_t i) { return line_of[i]; },
        [&](std::uint32_t i) { return tile_of[i]; }, query);
  });
}

// ---- Streams: rays along a stored line, traced tile by tile in packets --------------------------

constexpr int kPacket = simd::kNativeWidth;

// A measurement build's cut (CMake VISFIELD_MEASURE_BEAM_CUT; 0 in every other build).
#ifndef VISFIELD_MEASURE_BEAM_CUT
#define VISFIELD_MEASURE_BEAM_CUT 0
#endif
constexpr int kMeasureCut = VISFIELD_MEASURE_BEAM_CUT;

/// Up to kPacket rays of one tile, along one line in one orientation, traced together.
struct alignas(64) Packet {
  simd::RayBlock<kPacket> origins;              // org permuted to the shared kx, ky, kz; NaN in unused lanes
  alignas(64) std::uint32_t keys[kPacket];      // footprint keys
  alignas(64) float tmin[kPacket];
  alignas(64) float tmax[kPacket];
  int from[kPacket], to[kPacket];               // first and last leaf, counted in walk order
  std::uint32_t ray[kPacket];                   // index in the batch
  int count = 0;
};

/// A stream ray in its tile: its first and last leaf in walk order and its footprint key, exactly as
/// Walk::visit_tile computes them on the single-tile path.
struct TileRay {
  std::uint32_t ray;
  std::uint32_t key;
  int from, to;
};

/// What one thread reuses between tiles.
struct StreamScratch {
  std::vector<TileRay> rays, sorted;
  std::vector<std::uint32_t> counts;
};

/// What one thread reuses between calls of occluded_streams.
struct StreamBuffers {
  std::vector<std::uint32_t> bucket_of, tile_of, order, sort;
  std::vector<LineFrameRay> frame_of;
  std::vector<std::size_t> start, fill, groups;
  StreamScratch scratch;
};

/// Occlusion of the rays idx[0 .. count) of `rays`, which all run along `line` the same way (the
/// same direction bit for bit, whose watertight constants `shear` holds) and stay in tile `tile`:
/// the record is read once, the rays sorted by first leaf, and each packet of kPacket of them walks
/// the leaves near to far once; in each leaf every reference whose footprint meets some live ray's key
/// is tested against those rays at once. A ray's candidates are those Walk would test (the leaves
/// from its origin's to its end's, the references its key lets through), so its answer is Walk's.
void trace_tile_stream(const BeamLayout& layout, std::uint32_t line, std::uint32_t tile, const simd::BlockRay<kPacket>& shear,
                       std::span<const Ray> rays, std::span<const LineFrameRay> frames, const std::uint32_t* idx, std::size_t count,
                       std::span<std::uint8_t> occluded, StreamScratch& scratch) {
  const DirectionTiles& dir = layout.directions[line];
  const std::uint32_t offset = dir.tiles[tile];
  if (offset == kEmptyTile) {
    for (std::size_t k = 0; k < count; ++k) occluded[idx[k]] = 0;
    return;
  }
  const RecordView record(dir.arena.data() + offset);
  const TileGeometry& g = layout.geometry;
  const int ix = static_cast<int>(tile % static_cast<std::uint32_t>(g.n)), iy = static_cast<int>(tile / static_cast<std::uint32_t>(g.n));
  const int last = record.last_leaf();
  bool forward = true;
  scratch.rays.clear();
  for (std::size_t k = 0; k < count; ++k) {
    const LineFrameRay& f = frames[idx[k]];  // set up when the ray was binned
    int from = 0, to = 0;
    f.leaves(record, f.ta, f.tb, 0.0, from, to);
    forward = f.forward;  // the same for every ray of a stream (one direction)
    if (!forward) from = last - from, to = last - to;
    scratch.rays.push_back({idx[k], f.segment_key(g, ix, iy, f.ta, f.tb, g.slack), from, to});
  }
  // By first leaf (a counting sort over the leaves), so that a packet's rays start close together.
  std::vector<TileRay>& sorted = scratch.sorted;
  sorted.resize(count);
  scratch.counts.assign(static_cast<std::size_t>(last) + 2, 0);
  for (const TileRay& r : scratch.rays) ++scratch.counts[static_cast<std::size_t>(r.from) + 1];
  for (int l = 0; l <= last; ++l) scratch.counts[static_cast<std::size_t>(l) + 1] += scratch.counts[static_cast<std::size_t>(l)];
  for (const TileRay& r : scratch.rays) sorted[scratch.counts[static_cast<std::size_t>(r.from)]++] = r;

  using V = simd::Lanes<kPacket>;
  Packet p;
  for (std::size_t first = 0; first < count; first += kPacket) {
    p.count = static_cast<int>(std::min<std::size_t>(kPacket, count - first));
    int walk_end = 0;
    for (int l = 0; l < kPacket; ++l) {
      if (l < p.count) {
        const TileRay& r = sorted[first + static_cast<std::size_t>(l)];
        const Ray& ray = rays[r.ray];
        p.origins.org[l] = ray.org[shear.kx];
        p.origins.org[kPacket + l] = ray.org[shear.ky];
        p.origins.org[2 * kPacket + l] = ray.org[shear.kz];
        p.keys[l] = r.key;
        p.tmin[l] = ray.tmin;
        p.tmax[l] = ray.tmax;
        p.from[l] = r.from;
        p.to[l] = r.to;
        p.ray[l] = r.ray;
        walk_end = std::max(walk_end, r.to);
      } else {
        for (int axis = 0; axis < 3; ++axis) p.origins.org[axis * kPacket + l] = std::numeric_limits<float>::quiet_NaN();
        p.keys[l] = 0;
        p.tmin[l] = p.tmax[l] = 0.0f;
      }
    }
    const V tmin = V::load(p.tmin), tmax = V::load(p.tmax);
    simd::LaneBits hit = 0, active = 0;
    int entered = 0;
    for (int step = p.from[0]; step <= walk_end; ++step) {
      while (entered < p.count && p.from[entered] <= step) active |= simd::LaneBits{1} << entered++;
      if (active == 0) {
        if (entered == p.count) break;
        step = p.from[entered] - 1;  // the next ray's first leaf: nothing to test before it
        continue;
      }
      const int leaf = forward ? step : last - step;
      const std::uint32_t size = record.leaf_size(leaf);
      const std::uint32_t* footprints = record.leaf_footprints(leaf);
      const std::uint32_t* slots = record.leaf_slots(leaf);
      // kBatch references at a time: first which rays each one's footprint meets (its triangle
      // prefetched when any), then the tests, so that the triangles' loads overlap.
      constexpr std::uint32_t kBatch = 16;
      std::uint32_t batch[kBatch];
      simd::LaneBits meets[kBatch];
      for (std::uint32_t begin = 0; begin < size && active != 0; begin += kBatch) {
        if constexpr (kMeasureCut >= 2) break;
        std::uint32_t candidates = 0;
        for (std::uint32_t r = begin; r < std::min(size, begin + kBatch); ++r) {
          const simd::LaneBits m = overlapping_keys<kPacket>(footprints[r], p.keys) & active;
          if (m == 0) continue;
          batch[candidates] = slots[r];
          meets[candidates++] = m;
          __builtin_prefetch(&layout.triangles[slots[r]]);
        }
        if constexpr (kMeasureCut >= 1) continue;
        for (std::uint32_t c = 0; c < candidates; ++c) {
          const simd::LaneBits m = meets[c] & active;
          if (m == 0) continue;
          const std::array<Vec3f, 3>& t = layout.triangles[batch[c]];
          const simd::LaneBits now = simd::intersect_rays<kPacket>(p.origins, shear, t[0], t[1], t[2], tmin, tmax) & m;
          if (now == 0) continue;
          hit |= now;
          active &= ~now;
          if (active == 0) break;
        }
      }
      // Rays whose last leaf this was leave the packet.
      for (simd::LaneBits left = active; left != 0; left &= left - 1) {
        const int l = simd::first_lane(left);
        if (p.to[l] == step) active &= ~(simd::LaneBits{1} << l);
      }
    }
    for (int l = 0; l < p.count; ++l) occluded[p.ray[l]] = (hit >> l) & 1u;
  }
}

/// occluded_block, on the calling thread (and occluded_batch's runs of one line): rays along a stored
/// line that stay in one tile go to trace_tile_stream, grouped by (line, orientation) and binned by
/// tile; the rest are traced one by one in line and tile order.
void occluded_streams(const BeamLayout& layout, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  const std::size_t lines = layout.lines.size();
  const TileGeometry& g = layout.geometry;
  const auto n = static_cast<std::uint32_t>(g.n);
  const std::size_t tiles = static_cast<std::size_t>(n) * n;
  // Buckets: 2 line + (0 along, 1 against) for streams, 2 lines + line for rays one by one; rays
  // answered here (invalid, an empty field, missing the sphere) go to no bucket.
  const std::size_t buckets = 3 * lines;
  constexpr std::uint32_t kAnswered = 0xffffffffu;
  // The buffers live on with the thread: a renderer calls this once per line, and fresh allocations
  // cost page faults each time.
  thread_local StreamBuffers buffers;
  std::vector<std::uint32_t>& bucket_of = buffers.bucket_of;
  std::vector<std::uint32_t>& tile_of = buffers.tile_of;
  std::vector<LineFrameRay>& frame_of = buffers.frame_of;  // the stream rays' setups, for their packets
  bucket_of.resize(rays.size());
  tile_of.resize(rays.size());
  frame_of.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    if (!ray.is_valid() || layout.live_slots == 0) {
      bucket_of[i] = kAnswered;
      occluded[i] = 0;
      continue;
    }
    const NearestLine nearest = layout.lines.nearest(ray.dir);
    const Vec3f w = nearest.sign > 0 ? layout.lines.direction(nearest.line) : -layout.lines.direction(nearest.line);
    if (std::bit_cast<std::array<std::uint32_t, 3>>(ray.dir) == std::bit_cast<std::array<std::uint32_t, 3>>(w)) {
      LineFrameRay& f = frame_of[i];
      if (!f.set(layout, ray, nearest.line)) {
        bucket_of[i] = kAnswered;
        occluded[i] = 0;
        continue;
      }
      int ix = 0, iy = 0;
      if (f.lateral <= g.slack && f.single_tile(g, ix, iy)) {
        bucket_of[i] = 2 * nearest.line + (nearest.sign > 0 ? 0u : 1u);
        tile_of[i] = static_cast<std::uint32_t>(iy) * n + static_cast<std::uint32_t>(ix);
        continue;
      }
    }
    bucket_of[i] = static_cast<std::uint32_t>(2 * lines) + nearest.line;
    tile_of[i] = origin_tile(layout, ray.org, nearest.line);
  }
  std::vector<std::size_t>& start = buffers.start;
  start.assign(buckets + 1, 0);
  for (const std::uint32_t b : bucket_of)
    if (b != kAnswered) ++start[b + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<std::uint32_t>& order = buffers.order;
  order.resize(start[buckets]);
  buffers.fill.assign(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (bucket_of[i] != kAnswered) order[buffers.fill[bucket_of[i]]++] = static_cast<std::uint32_t>(i);
  for (std::size_t b = 0; b < buckets; ++b) sort_by_key(order.data() + start[b], start[b + 1] - start[b], tile_of.data(), tiles, buffers.sort);
  StreamScratch& scratch = buffers.scratch;
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::uint32_t* idx = order.data() + start[b];
    const std::size_t count = start[b + 1] - start[b];
    if (count == 0) continue;
    if (b >= 2 * lines) {
      const auto line = static_cast<std::uint32_t>(b - 2 * lines);
      trace_in_order(
          layout, rays, idx, count, [&](std::uint32_t) { return line; }, [&](std::uint32_t i) { return tile_of[i]; },
          [&](std::size_t i, const Ray& ray, std::uint32_t l) { occluded[i] = Walk<true, NoCount>(layout, ray, {}).run(l).found ? 1 : 0; });
      continue;
    }
    const auto line = static_cast<std::uint32_t>(b / 2);
    const simd::BlockRay<kPacket> shear{WatertightRay(rays[idx[0]])};
    // The tiles' groups of rays; each group's record is prefetched kRecordAhead groups ahead (the
    // first read of a record is a miss in a field no cache holds).
    constexpr std::size_t kRecordAhead = 4;
    std::vector<std::size_t>& groups = buffers.groups;
    groups.clear();
    for (std::size_t k = 0; k < count; ++k)
      if (k == 0 || tile_of[idx[k]] != tile_of[idx[k - 1]]) groups.push_back(k);
    groups.push_back(count);
    for (std::size_t j = 0; j + 1 < groups.size(); ++j) {
      if (j + kRecordAhead + 1 < groups.size()) prefetch_record(layout, line, tile_of[idx[groups[j + kRecordAhead]]]);
      trace_tile_stream(layout, line, tile_of[idx[groups[j]]], shear, rays, frame_of, idx + groups[j], groups[j + 1] - groups[j], occluded,
                        scratch);
    }
  }
}

/// occluded_batch's stream path for many rays (with at least half of them along their lines, else
/// for_each_by_line): the rays are counting-sorted by nearest line, and each
/// line's rays (in runs of at most kLineRun) are gathered into a contiguous copy and traced by
/// occluded_streams on one thread, the runs in parallel. A run's rays, their tiles and records then
/// stay in the caches, where one pass over the whole batch would fetch each ray from memory twice.
void occluded_streams_by_line(const BeamLayout& layout, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  constexpr std::size_t kLineRun = 32768;
  std::vector<std::uint32_t> line_of(rays.size());
  std::atomic<std::size_t> along{0};
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 4096), [&](const auto& range) {
    std::size_t on_lines = 0;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (!rays[i].is_valid()) {
        line_of[i] = 0;
        continue;
      }
      const NearestLine nearest = layout.lines.nearest(rays[i].dir);
      line_of[i] = nearest.line;
      const Vec3f w = nearest.sign > 0 ? layout.lines.direction(nearest.line) : -layout.lines.direction(nearest.line);
      on_lines += std::bit_cast<std::array<std::uint32_t, 3>>(rays[i].dir) == std::bit_cast<std::array<std::uint32_t, 3>>(w);
    }
    along.fetch_add(on_lines, std::memory_order_relaxed);
  });
  // Mostly rays off the lines (random AO directions, shadow rays): the streams would only add their
  // binning, so the rays go one by one, sorted by line and tile.
  if (2 * along.load() < rays.size()) {
    for_each_by_line(
        layout, rays, [&](std::size_t i, const Ray& ray, std::uint32_t line) { occluded[i] = Walk<true, NoCount>(layout, ray, {}).run(line).found ? 1 : 0; },
        std::move(line_of));
    return;
  }
  auto by_line = order_by_line(layout.lines.size(), line_of);
  const std::vector<std::size_t>& start = by_line.first;
  std::vector<std::uint32_t>& order = by_line.second;
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t line = 0; line < layout.lines.size(); ++line)
    for (std::size_t k = start[line]; k < start[line + 1]; k += kLineRun) runs.emplace_back(k, std::min(start[line + 1], k + kLineRun));
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, runs.size(), 1), [&](const auto& range) {
    std::vector<Ray> run_rays;
    std::vector<std::uint8_t> run_answers;
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      check_interrupt();
      const auto [first, last] = runs[r];
      run_rays.resize(last - first);
      run_answers.resize(last - first);
      for (std::size_t k = first; k < last; ++k) run_rays[k - first] = rays[order[k]];
      occluded_streams(layout, run_rays, run_answers);
      for (std::size_t k = first; k < last; ++k) occluded[order[k]] = run_answers[k - first];
    }
  });
}

}  // namespace
}  // namespace beam

Hit BeamField::intersect(const Ray& ray) const {
  VF_USE_WIDER(beam_intersect, *this, ray, nullptr);
  return beam::Walk<false, beam::NoCount>(*layout_, ray, {}).run();
}

bool BeamField::occluded(const Ray& ray) const {
  VF_USE_WIDER(beam_occluded, *this, ray, nullptr);
  return beam::Walk<true, beam::NoCount>(*layout_, ray, {}).run().found;
}

Hit BeamField::intersect(const Ray& ray, BeamQueryCounters& counters) const {
  VF_USE_WIDER(beam_intersect, *this, ray, &counters);
  return beam::Walk<false, beam::Count>(*layout_, ray, beam::Count{counters}).run();
}

bool BeamField::occluded(const Ray& ray, BeamQueryCounters& counters) const {
  VF_USE_WIDER(beam_occluded, *this, ray, &counters);
  return beam::Walk<true, beam::Count>(*layout_, ray, beam::Count{counters}).run().found;
}

Hit BeamField::intersect_on_line(const Ray& ray, std::uint32_t line) const {
  VF_USE_WIDER(beam_intersect_on_line, *this, ray, line);
  return beam::Walk<false, beam::NoCount>(*layout_, ray, {}).run(line);
}

bool BeamField::occluded_on_line(const Ray& ray, std::uint32_t line) const {
  VF_USE_WIDER(beam_occluded_on_line, *this, ray, line);
  return beam::Walk<true, beam::NoCount>(*layout_, ray, {}).run(line).found;
}

void intersect_batch(const BeamField& field, std::span<const Ray> rays, std::span<Hit> hits) {
  VF_USE_WIDER(intersect_batch, field, rays, hits);
  beam::for_each_by_line(field.layout(), rays, [&](std::size_t i, const Ray& ray, std::uint32_t line) {
    std::construct_at(&hits[i], field.intersect_on_line(ray, line));
  });
}

void occluded_batch(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  VF_USE_WIDER(occluded_batch, field, rays, occluded);
  if (field.config().stream) {
    beam::occluded_streams_by_line(field.layout(), rays, occluded);
    return;
  }
  beam::for_each_by_line(field.layout(), rays, [&](std::size_t i, const Ray& ray, std::uint32_t line) {
    occluded[i] = field.occluded_on_line(ray, line) ? 1 : 0;
  });
}

void occluded_block(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  VF_USE_WIDER(occluded_block, field, rays, occluded);
  if constexpr (beam::kMeasureCut >= 3) {
    std::fill(occluded.begin(), occluded.end(), std::uint8_t{0});
    return;
  }
  if (field.config().stream) {
    beam::occluded_streams(field.layout(), rays, occluded);
    return;
  }
  for (std::size_t i = 0; i < rays.size(); ++i) occluded[i] = field.occluded(rays[i]) ? 1 : 0;
}

}  // namespace vf

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY Hit beam_intersect(const BeamField& field, const Ray& ray, BeamQueryCounters* counters) {
  return counters ? field.intersect(ray, *counters) : field.intersect(ray);
}
VF_WIDER_ENTRY bool beam_occluded(const BeamField& field, const Ray& ray, BeamQueryCounters* counters) {
  return counters ? field.occluded(ray, *counters) : field.occluded(ray);
}
VF_WIDER_ENTRY Hit beam_intersect_on_line(const BeamField& field, const Ray& ray, std::uint32_t line) { return field.intersect_on_line(ray, line); }
VF_WIDER_ENTRY bool beam_occluded_on_line(const BeamField& field, const Ray& ray, std::uint32_t line) { return field.occluded_on_line(ray, line); }
VF_WIDER_ENTRY void intersect_batch(const BeamField& field, std::span<const Ray> rays, std::span<Hit> hits) { vf::intersect_batch(field, rays, hits); }
VF_WIDER_ENTRY void occluded_batch(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  vf::occluded_batch(field, rays, occluded);
}
VF_WIDER_ENTRY void occluded_block(const BeamField& field, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  vf::occluded_block(field, rays, occluded);
}
}  // namespace vf::isa_avx512
#endif
