// The watertight test (core/triangle_intersect.hpp) and may_meet_sphere() (field/sphere_cull.hpp)
// with a ray in each lane: the same operations in the same order, the watertight test's per-ray
// permutation as selects, so a lane decides what the scalar code decides. Lanes whose edge
// functions come out 0 (where the scalar test falls back to double) are decided by the scalar test itself.
// A kernel file: compiled once per instruction set (src/core/isa_dispatch.hpp).

// GCC 12 reports the undefined-value operands of its own avx512fintrin.h (_mm512_undefined_*) as
// uninitialised once inlined (as in field_batch.cpp): a false positive of the compiler's headers.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "block_lanes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/isa_dispatch.hpp"
#include "field_kernel.hpp"
#include "kernel_lanes.hpp"
#include "visfield/core/triangle_intersect.hpp"
#include "visfield/field/sphere_cull.hpp"

namespace vf::isa_avx512 {
void occluded_by_small_exact(std::span<const std::array<Vec3f, 3>> triangles, std::span<const Ray> rays, std::uint8_t* occluded);
void closest_by_small_exact(const TriangleSet& exact, const Bvh& bvh, std::span<const Ray> rays, Hit* best);
std::size_t cells_of_rays(const field::CellGrid& grid, std::span<const Ray> rays, const std::uint8_t* skip, std::int32_t* cell,
                          std::uint32_t* in_cells);
std::size_t rays_meeting_sphere(const Vec3f& centre, float radius, std::span<const Ray> rays, std::uint32_t* out);
void append_meeting_spheres(std::span<const field::SphereTarget> targets, std::span<const Ray> rays, const std::uint32_t* ids,
                            const std::uint8_t* skip);
void append_meeting_spheres(std::span<const field::SphereTarget> targets, const Ray* rays, const std::uint32_t* ids, std::size_t count);
void append_meeting_spheres(std::span<const field::SphereTarget> targets, const float* const columns[8], std::size_t count,
                            const std::uint32_t* ids, const std::uint8_t* settled);
}  // namespace vf::isa_avx512

namespace vf::field {
namespace {

// The grid's cells, in median object boxes, widest first: the widest whose pairs of cells (two
// neighbours along an axis) have lists short enough to be used, so that a ray crossing one boundary
// still takes a list. (1024 copies' AO, medians of 9 interleaved rounds: busts 3.72x at 2, 3.90x at
// 1.5, 3.95x at 1.25, their pairs' lists 24.6, 13.0, 9.1 objects; bunnies 3.89x at 2, 3.88x at 1.75,
// 3.93x at 1.5, pairs 9.5 at 2.)
constexpr double kCellWidths[] = {2.0, 1.75, 1.5, 1.25, 1.0};
// Lists of a shape longer than this on average are not used: their rays go down the tree. (1024
// copies' AO: the bunnies' pairs, 9.5 objects, paid and their fours, 16.7, were level; the busts'
// cells, 14.6, paid and their pairs, 24.6, lost.)
constexpr double kLongestLists = 16.0;

bool occluded_one(std::span<const std::array<Vec3f, 3>> triangles, const Ray& ray) {
  const WatertightRay r(ray);
  TriangleHit hit;
  for (const std::array<Vec3f, 3>& t : triangles)
    if (intersect_triangle(r, t[0], t[1], t[2], ray.tmin, ray.tmax, hit)) return true;
  return false;
}

#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
/// Triangle k of `exact` hit at (t, u, v), as a Bvh reports it (the lanes' closest hits only).
Hit triangle_hit(const TriangleSet& exact, std::size_t k, float t, float u, float v) {
  const std::array<Vec3f, 3>& c = exact.triangles[k];
  return Hit::triangle(t, u, v, exact.prim[k], exact.instance[k], cross(c[1] - c[0], c[2] - c[0]));
}

#if defined(__AVX512F__)
using L = lanes::Avx512;
#else
using L = lanes::Avx2;
#endif
using F = L::F;
using M = L::M;

/// A packet of L::kWidth consecutive rays as the watertight test sees them: WatertightRay's
/// permutation (kz the largest |dir| component, kx and ky the next, swapped when dir[kz] < 0) as
/// selects, and its shear.
class ShearedPacket {
 public:
  explicit ShearedPacket(const Ray* rays) {
    static_assert(sizeof(Ray) == 8 * sizeof(float), "a Ray is 8 floats: org, dir, tmin, tmax");
    F c[8];
    L::transpose_rows(reinterpret_cast<const float*>(rays), c);
    ox_ = c[0], oy_ = c[1], oz_ = c[2], tmin = c[6], tmax = c[7];
    const F dx = c[3], dy = c[4], dz = c[5];
    const F ax = abs(dx), ay = abs(dy), az = abs(dz);
    const M x_first = ax >= ay;
    kz_x_ = x_first & (ax >= az), kz_y_ = ~x_first & (ay >= az);
    d_z_ = pick_z(dx, dy, dz);
    swap_ = d_z_ < L::splat(0.0f);
    d_x_ = pick_x(dx, dy, dz), d_y_ = pick_y(dx, dy, dz);
  }

  /// The shear (three divisions), which terms() needs: made once moving_away() has not settled every lane.
  void shear() { sx_ = d_x_ / d_z_, sy_ = d_y_ / d_z_, sz_ = L::splat(1.0f) / d_z_; }

  /// Lanes (with tmin >= 0) whose ray the test cannot find in `box` (every vertex's bounds): the
  /// origin on or beyond the box's face across the ray's kz axis, the ray moving away from it. Exactly
  /// so: then each vertex's sz · (p − o)[kz] is <= 0 (or a zero), so t_scaled has the sign opposite to
  /// det's or is a zero (the edge functions share their sign wherever the test goes on), and t <= 0
  /// is never > tmin. (A ground's own shading points start on it.)
  M moving_away(const Bounds3f& box) const {
    const F zero = L::splat(0.0f), o = pick_z(ox_, oy_, oz_);
    const F lo = pick_z(L::splat(box.lo.x), L::splat(box.lo.y), L::splat(box.lo.z));
    const F hi = pick_z(L::splat(box.hi.x), L::splat(box.hi.y), L::splat(box.hi.z));
    return (tmin >= zero) & (((d_z_ > zero) & (o >= hi)) | ((d_z_ < zero) & (o <= lo)));
  }

  /// intersect_triangle()'s terms for triangle `t` on every lane (after shear()).
  struct Terms {
    F e0, e1, e2, det, t_scaled;
    M edge;     // some edge function is 0: the scalar test decides in double
    M crosses;  // no edge function is 0, they do not differ in sign, and det is not 0
  };
  Terms terms(const std::array<Vec3f, 3>& t) const {
    // The vertices relative to the origin, permuted and sheared.
    F px[3], py[3], pz[3];
    for (int k = 0; k < 3; ++k) {
      const F x = L::splat(t[k].x) - ox_, y = L::splat(t[k].y) - oy_, z = L::splat(t[k].z) - oz_;
      pz[k] = pick_z(x, y, z);
      px[k] = pick_x(x, y, z) - sx_ * pz[k];
      py[k] = pick_y(x, y, z) - sy_ * pz[k];
    }
    Terms r;
    const F zero = L::splat(0.0f);
    r.e0 = px[2] * py[1] - py[2] * px[1];
    r.e1 = px[0] * py[2] - py[0] * px[2];
    r.e2 = px[1] * py[0] - py[1] * px[0];
    r.edge = (r.e0 == zero) | (r.e1 == zero) | (r.e2 == zero);
    const M negative = (r.e0 < zero) | (r.e1 < zero) | (r.e2 < zero);
    const M positive = (r.e0 > zero) | (r.e1 > zero) | (r.e2 > zero);
    r.det = r.e0 + r.e1 + r.e2;
    r.t_scaled = r.e0 * (sz_ * pz[0]) + r.e1 * (sz_ * pz[1]) + r.e2 * (sz_ * pz[2]);
    r.crosses = ~r.edge & ~(negative & positive) & ~(r.det == zero);
    return r;
  }

  F tmin, tmax;

 private:
  F pick_z(F x, F y, F z) const { return select(kz_x_, x, select(kz_y_, y, z)); }
  F pick_next(F x, F y, F z) const { return select(kz_x_, y, select(kz_y_, z, x)); }
  F pick_after(F x, F y, F z) const { return select(kz_x_, z, select(kz_y_, x, y)); }
  F pick_x(F x, F y, F z) const { return select(swap_, pick_after(x, y, z), pick_next(x, y, z)); }
  F pick_y(F x, F y, F z) const { return select(swap_, pick_next(x, y, z), pick_after(x, y, z)); }

  F ox_, oy_, oz_, d_x_, d_y_, d_z_, sx_, sy_, sz_;
  M kz_x_, kz_y_, swap_;
};

/// One packet of L::kWidth consecutive rays at `rays`: the lanes that hit, and in `redo` the lanes
/// left to the scalar test.
M occluded_packet(std::span<const std::array<Vec3f, 3>> triangles, const Bounds3f& box, const Ray* rays, M& redo) {
  ShearedPacket packet(rays);
  const M all = L::all();
  M hit = L::none();
  redo = L::none();
  // Lanes that cannot hit are settled before any triangle, and a packet of them before its shear: a
  // ground's shadow rays going up from it and from the objects on it.
  const M away = packet.moving_away(box);
  if (L::bits(away) == L::bits(all)) return hit;
  packet.shear();
  for (const std::array<Vec3f, 3>& t : triangles) {
    const ShearedPacket::Terms e = packet.terms(t);
    const F distance = e.t_scaled * (L::splat(1.0f) / e.det);
    hit = hit | (e.crosses & (distance > packet.tmin) & (distance <= packet.tmax) & (distance <= L::splat(kLargestHitT)));
    redo = redo | e.edge;
    if (L::bits(hit | redo | away) == L::bits(all)) break;
  }
  redo = redo & ~hit & ~away;  // the scalar test misses where the lanes cannot hit
  return hit;
}

/// One packet of L::kWidth consecutive rays at `rays`: on each lane, the nearest triangle hit in
/// (tmin, tmax] (the lowest index of equals), as the index `nearest` (-1 for none) with its t, u and v;
/// in `redo` the lanes left to the scalar test.
void closest_packet(std::span<const std::array<Vec3f, 3>> triangles, const Ray* rays, L::I& nearest, F& t, F& u, F& v, M& redo) {
  ShearedPacket packet(rays);
  packet.shear();
  nearest = L::splat(-1);
  t = packet.tmax;  // a Bvh's best t starts at tmax, so a hit at tmax counts (the first of equals)
  u = v = L::splat(0.0f);
  redo = L::none();
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    const ShearedPacket::Terms e = packet.terms(triangles[k]);
    const F inv_det = L::splat(1.0f) / e.det;
    const F distance = e.t_scaled * inv_det;
    // Triangles in ascending order: a later one replaces only a nearer hit, or equals tmax when none.
    const M first = nearest == L::splat(-1);
    const M hit = e.crosses & (distance > packet.tmin) & (distance <= L::splat(kLargestHitT)) & ((distance < t) | ((distance == t) & first));
    nearest = select(hit, L::splat(static_cast<int>(k)), nearest);
    t = select(hit, distance, t);
    u = select(hit, e.e1 * inv_det, u);
    v = select(hit, e.e2 * inv_det, v);
    redo = redo | e.edge;
  }
}

/// What may_meet_sphere() computes of a ray alone: made once a packet for every sphere.
struct LineTerms {
  F dd, root;  // |dir|^2 and |dir|
};

[[gnu::always_inline]] inline LineTerms line_terms(const F c[8]) {
  const F dd = c[3] * c[3] + c[4] * c[4] + c[5] * c[5];
  return {dd, sqrt(dd)};
}

/// may_meet_sphere() on rays in columns (origin, direction, tmin, tmax), with their line_terms().
[[gnu::always_inline]] inline M meets_sphere(const Vec3f& centre, float radius, const F c[8], const LineTerms& line) {
  const F dx = c[3], dy = c[4], dz = c[5];
  const float wide = radius * 1.001f;
  const F ocx = L::splat(centre.x) - c[0], ocy = L::splat(centre.y) - c[1], ocz = L::splat(centre.z) - c[2];
  const F sx = ocy * dz - ocz * dy, sy = ocz * dx - ocx * dz, sz = ocx * dy - ocy * dx;
  const M near = ~(sx * sx + sy * sy + sz * sz > L::splat(wide * wide) * line.dd);
  const F along = ocx * dx + ocy * dy + ocz * dz;
  const F reach = L::splat(wide) * line.root;
  return near & (along + reach >= c[6] * line.dd) & (along - reach <= c[7] * line.dd);
}

/// The lanes whose bit of `bits` is set.
M lanes_of_bits(std::uint32_t bits) { return ((L::splat(static_cast<int>(bits)) >> L::lane_index()) & L::splat(1)) == L::splat(1); }

/// The lanes whose byte of skip[0 .. L::kWidth) is 0.
M open_lanes(const std::uint8_t* skip) {
  std::uint32_t open = 0;
  for (int word = 0; word < L::kWidth / 8; ++word) {
    std::uint64_t x;
    std::memcpy(&x, skip + 8 * word, 8);
    // The high bit of each byte that is not 0, then those 8 bits gathered into the top byte.
    const std::uint64_t low7 = 0x7F7F7F7F7F7F7F7Full;
    const std::uint64_t set = (((x & low7) + low7) | x) & ~low7;
    open |= static_cast<std::uint32_t>(~((set >> 7) * 0x0102040810204080ull >> 56) & 0xFFu) << (8 * word);
  }
  return lanes_of_bits(open);
}

/// The lanes k < `lanes` whose settled[ids[k]] is 0 (every one of them when `settled` is null).
M open_by_ids(const std::uint8_t* settled, const std::uint32_t* ids, int lanes) {
  if (!settled) return lanes_of_bits(static_cast<std::uint32_t>((std::uint64_t{1} << lanes) - 1u));
  std::uint32_t open = 0;
  for (int lane = 0; lane < lanes; ++lane) open |= static_cast<std::uint32_t>(settled[ids[lane]] == 0) << lane;
  return lanes_of_bits(open);
}

/// The packet of world-space rays in columns `c` (origin, direction, tmin, tmax) on the lanes `open`,
/// whose ids are ids[0 .. L::kWidth): for each target, the lanes that may meet its sphere, mapped into
/// its object's space and compressed onto its rows.
[[gnu::always_inline]] inline void append_packet(std::span<const SphereTarget> targets, const F c[8], M open, const std::uint32_t* ids) {
  using Kernel = FieldKernel<L>;
  const LineTerms line = line_terms(c);
  for (const SphereTarget& t : targets) {
    const M meets = meets_sphere(t.centre, t.radius, c, line) & open;
    if (L::bits(meets) == 0) continue;
    typename Kernel::Rays r{c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]};
    Kernel::to_object_space(r, *t.to_object);
    const F* column[8] = {&r.ox, &r.oy, &r.oz, &r.dx, &r.dy, &r.dz, &r.tmin, &r.tmax};
    RayRows& out = *t.out;
    for (int k = 0; k < 8; ++k) L::compress(out.row[k].data() + out.count, *column[k], meets);
    if (out.tagged) L::compress(out.tag.data() + out.count, L::splat(static_cast<int>(t.tag)), meets);
    out.count += static_cast<std::size_t>(L::compress(out.id.data() + out.count, L::load(ids), meets));
  }
}

/// may_meet_sphere() on the L::kWidth consecutive rays at `rays`.
M packet_meets_sphere(const Vec3f& centre, float radius, const Ray* rays) {
  F c[8];
  L::transpose_rows(reinterpret_cast<const float*>(rays), c);
  return meets_sphere(centre, radius, c, line_terms(c));
}
#endif

}  // namespace

namespace {

/// cells_of_rays() for one ray.
std::int32_t cell_of_ray(const CellGrid& g, const Ray& ray) {
  const float o[3] = {ray.org.x, ray.org.y, ray.org.z}, d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  // The ray's parameters through the hull (grown by a margin above the rounding of t), then the two
  // ends of that part: both within one cell's bounds (grown by the tolerance) put the whole part there,
  // a cell being convex. Comparisons are written so that NaN fails them.
  float t0 = ray.tmin, t1 = ray.tmax;
  if (!(t0 >= -3.4e38f) || !(t1 >= t0 || t1 < t0)) return kManyCells;  // NaN
  for (int a = 0; a < 3; ++a) {
    if (!(o[a] >= g.near_lo[a] && o[a] <= g.near_hi[a]) || !(std::fabs(d[a]) >= 1e-30f && std::fabs(d[a]) <= 3.4e38f)) return kManyCells;
    const float inverse = 1.0f / d[a];
    const float to_lo = (g.lo[a] - o[a]) * inverse, to_hi = (g.hi[a] - o[a]) * inverse;
    t0 = std::max(t0, std::min(to_lo, to_hi));
    t1 = std::min(t1, std::max(to_lo, to_hi));
  }
  if (t0 > t1) return kNoCell;
  std::int32_t index = 0, shape = 0;
  for (int a = 2; a >= 0; --a) {
    if (g.cells[a] == 1) continue;  // the part lies within the hull's slab, so within the one cell
    const float p0 = o[a] + t0 * d[a], p1 = o[a] + t1 * d[a];
    const float first = std::min(p0, p1), last = std::max(p0, p1), end = static_cast<float>(g.cells[a] - 1);
    const float k = std::min(std::max(std::floor((first - g.origin[a]) * g.inverse_edge[a]), 0.0f), end);
    const float low = (g.origin[a] - g.tolerance) + k * g.edge[a];
    if (!(first >= low)) return kManyCells;
    if (!(last <= low + (g.edge[a] + 2.0f * g.tolerance))) {
      if (!(k < end && last <= low + (2.0f * g.edge[a] + 2.0f * g.tolerance))) return kManyCells;
      shape |= 1 << a;
    }
    index = index * g.cells[a] + static_cast<std::int32_t>(k);
  }
  if (((g.shapes >> shape) & 1u) == 0) return kManyCells;
  return shape * static_cast<std::int32_t>(g.count()) + index;
}

}  // namespace

void occluded_by_small_exact(std::span<const std::array<Vec3f, 3>> triangles, std::span<const Ray> rays, std::uint8_t* occluded) {
  VF_USE_WIDER(occluded_by_small_exact, triangles, rays, occluded);
  std::size_t i = 0;
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  Bounds3f box;
  for (const std::array<Vec3f, 3>& t : triangles)
    for (const Vec3f& p : t) box.extend(p);
  for (; i + L::kWidth <= rays.size(); i += L::kWidth) {
    // The block's first pass over its rays reads them from memory: ask for those 4 packets on now.
    for (std::size_t line = 0; line < L::kWidth * sizeof(Ray); line += 64)
      __builtin_prefetch(reinterpret_cast<const char*>(rays.data() + i + 4 * L::kWidth) + line);
    M redo;
    const std::uint32_t hits = L::bits(occluded_packet(triangles, box, rays.data() + i, redo));
    for (int lane = 0; lane < L::kWidth; ++lane) occluded[i + static_cast<std::size_t>(lane)] = (hits >> lane) & 1u;
    for (std::uint32_t left = L::bits(redo); left != 0; left &= left - 1) {
      const std::size_t k = i + static_cast<std::size_t>(std::countr_zero(left));
      occluded[k] = occluded_one(triangles, rays[k]) ? 1 : 0;
    }
  }
#endif
  for (; i < rays.size(); ++i) occluded[i] = occluded_one(triangles, rays[i]) ? 1 : 0;
}

void closest_by_small_exact(const TriangleSet& exact, const Bvh& bvh, std::span<const Ray> rays, Hit* best) {
  VF_USE_WIDER(closest_by_small_exact, exact, bvh, rays, best);
  std::size_t i = 0;
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  for (; i + L::kWidth <= rays.size(); i += L::kWidth) {
    for (std::size_t line = 0; line < L::kWidth * sizeof(Ray); line += 64)
      __builtin_prefetch(reinterpret_cast<const char*>(rays.data() + i + 4 * L::kWidth) + line);
    L::I nearest;
    F t, u, v;
    M redo;
    closest_packet(exact.triangles, rays.data() + i, nearest, t, u, v, redo);
    alignas(64) std::int32_t index[L::kWidth];
    alignas(64) float ts[L::kWidth], us[L::kWidth], vs[L::kWidth];
    L::store(index, nearest);
    L::store(ts, t);
    L::store(us, u);
    L::store(vs, v);
    const std::uint32_t scalar = L::bits(redo);
    for (int lane = 0; lane < L::kWidth; ++lane) {
      const std::size_t k = i + static_cast<std::size_t>(lane);
      if ((scalar >> lane) & 1u)
        best[k] = bvh.intersect(rays[k]);
      else
        best[k] = index[lane] < 0 ? Hit{} : triangle_hit(exact, static_cast<std::size_t>(index[lane]), ts[lane], us[lane], vs[lane]);
    }
  }
#endif
  (void)exact;  // lanes only: the scalar rest goes through the Bvh
  for (; i < rays.size(); ++i) best[i] = bvh.intersect(rays[i]);
}

namespace {

/// Cells about `target` wide along each axis of `hull` longer than that: of sides from 7/8 to 5/4 of the
/// target and shifts of the cells against the hull, the one whose boundaries cut the fewest boxes
/// (grown by `margin`; per unit of side, so that wider cells do not win by having fewer boundaries),
/// the side nearest the target of equals. Objects in rows (copies on a lattice) then sit whole in their
/// cells: their rays stay in one cell more often, and each cell's list holds only its own objects.
CellGrid fitted_cells(std::span<const Bounds3f> boxes, const Bounds3f& hull, double margin, double target) {
  CellGrid g;
  for (int a = 0; a < 3; ++a) {
    const double length = static_cast<double>(hull.hi[a]) - hull.lo[a];
    g.origin[a] = hull.lo[a];
    g.cells[a] = 1;
    g.edge[a] = length > 0.0 ? static_cast<float>(length) : 1.0f;
    if (!(target > 0.0) || length <= target) continue;
    double best_score = std::numeric_limits<double>::infinity(), best_edge = target, best_origin = hull.lo[a];
    for (int step = 0; step <= 24; ++step) {
      const double e = target * (0.875 + 0.375 * step / 24.0);
      for (int shift = 0; shift < 16; ++shift) {
        const double o = hull.lo[a] - e * shift / 16.0;
        std::size_t cut = 0;
        for (const Bounds3f& b : boxes)
          cut += std::floor((b.lo[a] - margin - o) / e) != std::floor((b.hi[a] + margin - o) / e) ? 1 : 0;
        const double score = static_cast<double>(cut) * e;
        if (score < best_score || (score == best_score && std::fabs(e - target) < std::fabs(best_edge - target))) {
          best_score = score;
          best_edge = e;
          best_origin = o;
        }
      }
    }
    g.origin[a] = static_cast<float>(best_origin);
    g.edge[a] = static_cast<float>(best_edge);
    g.cells[a] = static_cast<int>(std::clamp(std::ceil((hull.hi[a] - static_cast<double>(g.origin[a])) / g.edge[a]), 1.0, 1024.0));
  }
  return g;
}

/// The lists of `g`'s cells (list shape · count + c, as cell_grid_over() keeps them), each box in
/// index order into those it reaches grown by `margin` (cell k of an axis spans origin + k·edge ..
/// + edge, as the rays' test computes it): a box reaching cells from .. to is in the lists of the
/// shapes that reach back one cell along their axes.
std::vector<std::vector<std::uint32_t>> cell_lists(const CellGrid& g, std::span<const Bounds3f> boxes, double margin) {
  const auto range = [&](const Bounds3f& b, int a, int& from, int& to) {
    const double e = g.edge[a];
    from = static_cast<int>(std::clamp(std::floor((b.lo[a] - margin - g.origin[a]) / e), 0.0, g.cells[a] - 1.0));
    to = static_cast<int>(std::clamp(std::floor((b.hi[a] + margin - g.origin[a]) / e), 0.0, g.cells[a] - 1.0));
  };
  const std::size_t count = g.count();
  std::vector<std::vector<std::uint32_t>> lists(kCellShapes * count);
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    int from[3], to[3];
    for (int a = 0; a < 3; ++a) range(boxes[k], a, from[a], to[a]);
    for (std::size_t shape = 0; shape < kCellShapes; ++shape) {
      int back[3];
      for (int a = 0; a < 3; ++a) back[a] = std::max(from[a] - static_cast<int>((shape >> a) & 1u), 0);
      for (int z = back[2]; z <= to[2]; ++z)
        for (int y = back[1]; y <= to[1]; ++y)
          for (int x = back[0]; x <= to[0]; ++x)
            lists[shape * count + (static_cast<std::size_t>(z) * static_cast<std::size_t>(g.cells[1]) + static_cast<std::size_t>(y)) * static_cast<std::size_t>(g.cells[0]) +
                  static_cast<std::size_t>(x)]
                .push_back(static_cast<std::uint32_t>(k));
    }
  }
  return lists;
}

/// Whether the lists of `shape` hold at most kLongestLists objects on average over those not empty.
bool short_lists(const std::vector<std::vector<std::uint32_t>>& lists, std::size_t count, std::size_t shape) {
  std::size_t entries = 0, used = 0;
  for (std::size_t c = 0; c < count; ++c) {
    entries += lists[shape * count + c].size();
    used += lists[shape * count + c].empty() ? 0 : 1;
  }
  return static_cast<double>(entries) <= kLongestLists * static_cast<double>(std::max<std::size_t>(used, 1));
}

}  // namespace

CellGrid cell_grid_over(std::span<const Bounds3f> boxes, std::span<const ObjectField* const> field_of, std::vector<std::uint32_t>& first,
                        std::vector<std::uint32_t>& items) {
  first.clear();
  items.clear();
  if (boxes.empty()) return CellGrid{};
  Bounds3f hull;
  for (const Bounds3f& b : boxes) hull.extend(b);
  double diagonal = 0.0;
  for (int a = 0; a < 3; ++a) diagonal += (static_cast<double>(hull.hi[a]) - hull.lo[a]) * (static_cast<double>(hull.hi[a]) - hull.lo[a]);
  diagonal = std::sqrt(diagonal);
  // The margin: far above the rounding of a float ray's points within 3 scene sizes of the hull
  // (cells_of_rays() routes none from farther), and small against the gaps between objects.
  const double margin = 1e-4 * diagonal;
  std::vector<double> sides;
  for (const Bounds3f& b : boxes) sides.push_back(static_cast<double>(b.hi.x) - b.lo.x);
  std::nth_element(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(sides.size() / 2), sides.end());
  const double median = sides[sides.size() / 2];
  CellGrid g;
  std::vector<std::vector<std::uint32_t>> lists;
  for (const double width : kCellWidths) {
    const CellGrid candidate = fitted_cells(boxes, hull, margin, median * width);
    // At most a few cells an object (a sparse scene's grid would be mostly empty cells).
    if (static_cast<double>(candidate.count()) > 4.0 * static_cast<double>(boxes.size()) + 64.0) break;
    g = candidate;
    lists = cell_lists(g, boxes, margin);
    bool pairs_used = true;
    for (int a = 0; a < 3; ++a) pairs_used = pairs_used && (g.cells[a] == 1 || short_lists(lists, g.count(), std::size_t{1} << a));
    if (pairs_used) break;
  }
  if (lists.empty()) return CellGrid{};
  for (int a = 0; a < 3; ++a) {
    g.lo[a] = static_cast<float>(hull.lo[a] - margin / 8.0);
    g.hi[a] = static_cast<float>(hull.hi[a] + margin / 8.0);
    g.inverse_edge[a] = 1.0f / g.edge[a];
    g.near_lo[a] = static_cast<float>(hull.lo[a] - 2.0 * diagonal);
    g.near_hi[a] = static_cast<float>(hull.hi[a] + 2.0 * diagonal);
  }
  g.tolerance = static_cast<float>(0.25 * margin);
  // The rounding of a routed ray's points (its origin plus t times its direction, within 3 scene sizes of
  // the hull) and of the cells' bounds, a few float ulps of the largest coordinate: within an eighth
  // of the margin, or no ray is routed (a scene far from the world's origin).
  double largest = 0.0;
  for (int a = 0; a < 3; ++a) largest = std::max({largest, std::fabs(static_cast<double>(g.near_lo[a])), std::fabs(static_cast<double>(g.near_hi[a]))});
  if (8.0 * 1.2e-7 * (largest + 3.0 * diagonal) > margin / 8.0) return CellGrid{};
  // The shapes whose lists are short enough to pay; none (no grid) when the cells' own are not.
  for (std::size_t shape = 0; shape < kCellShapes; ++shape)
    if (short_lists(lists, g.count(), shape)) g.shapes |= 1u << shape;
  if ((g.shapes & 1u) == 0) return CellGrid{};
  first.push_back(0);
  for (std::vector<std::uint32_t>& list : lists) {
    std::stable_sort(list.begin(), list.end(), [&](std::uint32_t a, std::uint32_t b) { return field_of[a] < field_of[b]; });
    items.insert(items.end(), list.begin(), list.end());
    first.push_back(static_cast<std::uint32_t>(items.size()));
  }
  return g;
}

std::size_t cells_of_rays(const CellGrid& grid, std::span<const Ray> rays, const std::uint8_t* skip, std::int32_t* cell,
                          std::uint32_t* in_cells) {
  VF_USE_WIDER(cells_of_rays, grid, rays, skip, cell, in_cells);
  const CellGrid g = grid;  // a copy: the stores to `cell` could alias its integers
  std::size_t i = 0, placed = 0;
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  // cell_of_ray() on lanes, the same operations: its early answers as masks, decided together at the end.
  for (; i + L::kWidth <= rays.size(); i += L::kWidth) {
    F c[8];
    L::transpose_rows(reinterpret_cast<const float*>(rays.data() + i), c);
    F t0 = c[6], t1 = c[7];
    M many = ~(t0 >= L::splat(-3.4e38f)) | ~((t1 >= t0) | (t1 < t0));
    for (int a = 0; a < 3; ++a) {
      const F o = c[a], d = c[3 + a];
      many = many | ~((o >= L::splat(g.near_lo[a])) & (o <= L::splat(g.near_hi[a]))) | ~((abs(d) >= L::splat(1e-30f)) & (abs(d) <= L::splat(3.4e38f)));
      const F inverse = L::splat(1.0f) / d;
      const F to_lo = (L::splat(g.lo[a]) - o) * inverse, to_hi = (L::splat(g.hi[a]) - o) * inverse;
      t0 = max(min(to_lo, to_hi), t0);
      t1 = min(max(to_lo, to_hi), t1);
    }
    const M none = t0 > t1;
    M outside = L::none();  // the part not within one or two cells an axis (cell_of_ray()'s later kManyCells)
    L::I index = L::splat(0), shape = L::splat(0);
    for (int a = 2; a >= 0; --a) {
      if (g.cells[a] == 1) continue;
      const F o = c[a], d = c[3 + a];
      const F p0 = o + t0 * d, p1 = o + t1 * d;
      const F first = min(p0, p1), last = max(p0, p1), end = L::splat(static_cast<float>(g.cells[a] - 1));
      const F k = min(max(floor((first - L::splat(g.origin[a])) * L::splat(g.inverse_edge[a])), L::splat(0.0f)), end);
      const F low = L::splat(g.origin[a] - g.tolerance) + k * L::splat(g.edge[a]);
      const M in_one = last <= low + L::splat(g.edge[a] + 2.0f * g.tolerance);
      const M in_two = (k < end) & (last <= low + L::splat(2.0f * g.edge[a] + 2.0f * g.tolerance));
      outside = outside | ~(first >= low) | ~(in_one | in_two);
      shape = select(in_one, shape, shape | L::splat(1 << a));
      index = index * L::splat(g.cells[a]) + to_int(k);
    }
    outside = outside | (((L::splat(static_cast<int>(g.shapes)) >> shape) & L::splat(1)) == L::splat(0));
    index = index + shape * L::splat(static_cast<int>(g.count()));
    if (skip) many = many | ~open_lanes(skip + i);
    index = select(outside, L::splat(kManyCells), index);
    index = select(none, L::splat(kNoCell), index);
    index = select(many, L::splat(kManyCells), index);
    L::store(cell + i, index);
    placed += static_cast<std::size_t>(L::compress(in_cells + placed, L::lane_index() + L::splat(static_cast<int>(i)), ~many & ~none & ~outside));
  }
#endif
  for (; i < rays.size(); ++i) {
    cell[i] = skip && skip[i] ? kManyCells : cell_of_ray(g, rays[i]);
    if (cell[i] >= 0) in_cells[placed++] = static_cast<std::uint32_t>(i);
  }
  return placed;
}

std::size_t rays_meeting_sphere(const Vec3f& centre, float radius, std::span<const Ray> rays, std::uint32_t* out) {
  VF_USE_WIDER(rays_meeting_sphere, centre, radius, rays, out);
  std::size_t i = 0, n = 0;
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  for (; i + L::kWidth <= rays.size(); i += L::kWidth) {
    std::uint32_t lanes = L::bits(packet_meets_sphere(centre, radius, rays.data() + i));
    for (; lanes != 0; lanes &= lanes - 1) out[n++] = static_cast<std::uint32_t>(i + static_cast<std::size_t>(std::countr_zero(lanes)));
  }
#endif
  for (; i < rays.size(); ++i)
    if (may_meet_sphere(centre, radius, rays[i])) out[n++] = static_cast<std::uint32_t>(i);
  return n;
}

void RayRows::pad_to(std::size_t width) {
  const std::size_t padded = (count + width - 1) / width * width;
  for (std::vector<float>& r : row) std::fill(r.data() + count, r.data() + padded, r[count - 1]);
  if (tagged) std::fill(tag.data() + count, tag.data() + padded, tag[count - 1]);
  count = padded;
}

void mark_rows(const ObjectField& field, RayRows& rows, std::vector<std::uint8_t>& marks, std::uint8_t* occluded) {
  const std::size_t pairs = rows.count;
  if (pairs == 0) return;
  // Whole packets: the last ray repeated rather than a partial packet traced one ray at a time.
  rows.pad_to(static_cast<std::size_t>(ObjectField::batch_width()));
  marks.assign(rows.count, 0);
  field.mark_occluded(rows.view(), marks.data());
  // Every mark or'ed in: a branch on the marks would be mispredicted for a large share of them.
  for (std::size_t k = 0; k < pairs; ++k) occluded[rows.id[k]] |= marks[k];
  rows.count = 0;
}

namespace {

/// Room in each target's rows for `count` more rays from every target sharing them.
void make_room(std::span<const SphereTarget> targets, std::size_t count) {
  // Targets all sharing their rows (a leaf's or a cell's objects of one field) are made room for once.
  const bool one_rows = std::all_of(targets.begin(), targets.end(), [&](const SphereTarget& u) { return u.out == targets.front().out; });
  for (const SphereTarget& t : one_rows ? targets.first(std::min<std::size_t>(targets.size(), 1)) : targets) {
    RayRows& out = *t.out;
    const auto sharing = one_rows ? targets.size()
                                  : static_cast<std::size_t>(std::count_if(targets.begin(), targets.end(), [&](const SphereTarget& u) { return u.out == t.out; }));
    const std::size_t need = out.count + sharing * count + kRowsSlack;
    for (std::vector<float>& row : out.row)
      if (row.size() < need) row.resize(std::max(need, 2 * row.size()));
    if (out.id.size() < need) out.id.resize(std::max(need, 2 * out.id.size()));
    if (out.tagged && out.tag.size() < need) out.tag.resize(std::max(need, 2 * out.tag.size()));
  }
}

/// The one ray `ray` (world space) with id `id`: appended, mapped, to the rows of each target whose
/// sphere it may meet.
void append_one(std::span<const SphereTarget> targets, const Ray& ray, std::uint32_t id) {
  for (const SphereTarget& t : targets) {
    if (!may_meet_sphere(t.centre, t.radius, ray)) continue;
    const Ray r = t.to_object->apply(ray);
    const float values[8] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
    RayRows& out = *t.out;
    for (int k = 0; k < 8; ++k) out.row[k][out.count] = values[k];
    if (out.tagged) out.tag[out.count] = t.tag;
    out.id[out.count++] = id;
  }
}

}  // namespace

void append_meeting_spheres(std::span<const SphereTarget> targets, std::span<const Ray> rays, const std::uint32_t* ids,
                            const std::uint8_t* skip) {
  VF_USE_WIDER(append_meeting_spheres, targets, rays, ids, skip);
  make_room(targets, rays.size());
  std::size_t i = 0;
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  for (; i + L::kWidth <= rays.size(); i += L::kWidth) {
    // A block's rays come from memory on this pass (fields alone: nothing read them before): ask for
    // those 8 packets on now (the corner's three models: 7.5-8.0x -> 9.4-9.6x Embree; 4 packets 9.2-9.4x, 16 level with 8).
    for (std::size_t line = 0; line < L::kWidth * sizeof(Ray); line += 64)
      __builtin_prefetch(reinterpret_cast<const char*>(rays.data() + i + 8 * L::kWidth) + line);
    const M open = skip ? open_lanes(skip + i) : L::all();
    if (L::bits(open) == 0) continue;
    F c[8];
    L::transpose_rows(reinterpret_cast<const float*>(rays.data() + i), c);
    append_packet(targets, c, open, ids + i);
  }
#endif
  for (; i < rays.size(); ++i)
    if (!skip || !skip[i]) append_one(targets, rays[i], ids[i]);
}

void append_meeting_spheres(std::span<const SphereTarget> targets, const Ray* rays, const std::uint32_t* ids, std::size_t count) {
  VF_USE_WIDER(append_meeting_spheres, targets, rays, ids, count);
  make_room(targets, count);
  std::size_t i = 0;
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  static_assert(kColumnsSlack >= L::kWidth - 1, "a last partial packet reads whole registers");
  for (; i < count; i += L::kWidth) {
    F c[8];
    L::transpose_rows_at(reinterpret_cast<const float*>(rays), ids + i, c);
    append_packet(targets, c, open_by_ids(nullptr, ids + i, static_cast<int>(std::min<std::size_t>(L::kWidth, count - i))), ids + i);
  }
#endif
  for (; i < count; ++i) append_one(targets, rays[ids[i]], ids[i]);
}

void append_meeting_spheres(std::span<const SphereTarget> targets, const float* const columns[8], std::size_t count, const std::uint32_t* ids,
                            const std::uint8_t* settled) {
  VF_USE_WIDER(append_meeting_spheres, targets, columns, count, ids, settled);
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  static_assert(kColumnsSlack >= L::kWidth - 1, "a last partial packet reads whole registers");
#endif
  make_room(targets, count);
  std::size_t i = 0;
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
  // The last packet too (its spare lanes off): every column and the ids are readable past count.
  for (; i < count; i += L::kWidth) {
    const M open = open_by_ids(settled, ids + i, static_cast<int>(std::min<std::size_t>(L::kWidth, count - i)));
    if (L::bits(open) == 0) continue;
    F c[8];
    for (int k = 0; k < 8; ++k) c[k] = L::load(columns[k] + i);
    append_packet(targets, c, open, ids + i);
  }
#endif
  for (; i < count; ++i) {
    if (settled && settled[ids[i]]) continue;
    const Ray ray{{columns[0][i], columns[1][i], columns[2][i]}, {columns[3][i], columns[4][i], columns[5][i]}, columns[6][i], columns[7][i]};
    append_one(targets, ray, ids[i]);
  }
}

}  // namespace vf::field

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void occluded_by_small_exact(std::span<const std::array<Vec3f, 3>> triangles, std::span<const Ray> rays, std::uint8_t* occluded) {
  field::occluded_by_small_exact(triangles, rays, occluded);
}
VF_WIDER_ENTRY void closest_by_small_exact(const TriangleSet& exact, const Bvh& bvh, std::span<const Ray> rays, Hit* best) {
  field::closest_by_small_exact(exact, bvh, rays, best);
}
VF_WIDER_ENTRY std::size_t cells_of_rays(const field::CellGrid& grid, std::span<const Ray> rays, const std::uint8_t* skip, std::int32_t* cell,
                                         std::uint32_t* in_cells) {
  return field::cells_of_rays(grid, rays, skip, cell, in_cells);
}
VF_WIDER_ENTRY std::size_t rays_meeting_sphere(const Vec3f& centre, float radius, std::span<const Ray> rays, std::uint32_t* out) {
  return field::rays_meeting_sphere(centre, radius, rays, out);
}
VF_WIDER_ENTRY void append_meeting_spheres(std::span<const field::SphereTarget> targets, std::span<const Ray> rays, const std::uint32_t* ids,
                                           const std::uint8_t* skip) {
  field::append_meeting_spheres(targets, rays, ids, skip);
}
VF_WIDER_ENTRY void append_meeting_spheres(std::span<const field::SphereTarget> targets, const Ray* rays, const std::uint32_t* ids,
                                           std::size_t count) {
  field::append_meeting_spheres(targets, rays, ids, count);
}
VF_WIDER_ENTRY void append_meeting_spheres(std::span<const field::SphereTarget> targets, const float* const columns[8], std::size_t count,
                                           const std::uint32_t* ids, const std::uint8_t* settled) {
  field::append_meeting_spheres(targets, columns, count, ids, settled);
}
}  // namespace vf::isa_avx512
#endif
