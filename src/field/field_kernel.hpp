#pragma once
// The ObjectField query of field_query.hpp on L::kWidth rays at once (L: a backend of
// kernel_lanes.hpp). Each step is the scalar step on lanes, in the same order with the same
// operations, so every lane's answer is bit for bit trace_field()'s (tests/unit/field checks it):
// the arctangents are field_query's polynomial, the table reads are gathers, branches are masks.
// Cycles go to the gathers (the chosen sample's direction, three for blending, one cell code, and on
// AVX-512 the ray itself when it is gathered from an array of Rays; AVX2 loads its row and
// transposes), to the arithmetic of the two
// arctangents and the hemisphere frame, and on Intel's cores to the divider (a packet read from
// inside takes four divisions and six square roots; the query shares and avoids divisions for
// it); see docs/objectfield-measurements.md.

#include <bit>
#include <cstddef>
#include <cstdint>

#include "kernel_lanes.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/field/field_query.hpp"

// A timing-bound build (CMake VISFIELD_FIELD_BOUND, docs/benchmark.md "Taking parts out") takes a part
// of the query out to measure what the rest costs; its answers are wrong on purpose.
#ifndef VISFIELD_FIELD_BOUND
#define VISFIELD_FIELD_BOUND 0
#endif

namespace vf::field {

/// What a timing-bound build takes out of the query (VISFIELD_FIELD_BOUND, in this order).
enum class TimingBound {
  none,          ///< the query as it is
  no_lookups,    ///< a lone object's culled stream answers every packet "miss": reading, mapping, culling, packing
  read_and_map,  ///< that stream only reads its rays and maps them into object space
  read_only,     ///< that stream only reads its rays (the rows' transposes)
  cached_cells,  ///< every lookup reads the cells of samples 0-3 (a few KiB, in L1): no table misses
  // The stages of the paper's lookup (locate() and finish()) left out one after another, later ones
  // keeping the earlier ones out; each stage's stand-in is a few operations on what it would read.
  no_map,               ///< the hemisphere map (square_point): the cell from the read direction's x and y
  no_map_line,          ///< and the sample's line (sample_read): read along the ray, no shift or limit
  no_map_line_lattice,  ///< and the lattice triangle and its heaviest corner: the sample from the point's x
  sphere_only,          ///< and the table read: the answer from the cell's indices; the sphere and placing are left
};
inline constexpr TimingBound kTimingBound = static_cast<TimingBound>(VISFIELD_FIELD_BOUND);

template <class L>
class FieldKernel {
 public:
  using F = typename L::F;
  using I = typename L::I;
  using M = typename L::M;
  static constexpr int kWidth = L::kWidth;
  /// Every lane.
  static M all_lanes() { return L::all(); }

  /// Object-space rays on lanes.
  struct Rays {
    F ox, oy, oz, dx, dy, dz, tmin, tmax;
  };
  /// Answers on lanes: hit, ray parameter t, and the raw normal code of the answering cell.
  struct Answer {
    M hit;
    F t;
    I normal_code;
  };

  /// Whether this kernel reads tables of these sizes (its byte offsets fit 31 bits); otherwise the
  /// caller runs trace_field().
  static bool reads(std::size_t cell_bytes, std::size_t normal_bytes) {
    return cell_bytes < (std::size_t{1} << 31) && normal_bytes < (std::size_t{1} << 31);
  }

  /// Answers `a` as FieldAnswers into out[0 .. kWidth).
  static void store(const FieldTables& f, const Answer& a, FieldAnswer* out) {
    alignas(64) float t[kWidth], nx[kWidth], ny[kWidth], nz[kWidth];
    L::store(t, a.t);
    const bool normals = f.normals != NormalStorage::none;
    if (normals) {
      const Vec n = decode_normals(f, a.normal_code);
      L::store(nx, n.x);
      L::store(ny, n.y);
      L::store(nz, n.z);
    }
    const std::uint32_t hits = L::bits(a.hit);
    for (int lane = 0; lane < kWidth; ++lane) {
      FieldAnswer& o = out[lane];
      if (!((hits >> lane) & 1u)) {
        o = FieldAnswer{};
        continue;
      }
      o.hit = true;
      o.t = t[lane];
      o.has_normal = normals;
      o.normal = normals ? hd::Vec3<float>{nx[lane], ny[lane], nz[lane]} : hd::Vec3<float>{0.0f, 0.0f, 0.0f};
    }
  }

  /// Answers `a` as FieldAnswers into out[position[lane]].
  static void store_at(const FieldTables& f, const Answer& a, FieldAnswer* out, const std::uint32_t* position) {
    FieldAnswer packet[kWidth];
    store(f, a, packet);
    for (int lane = 0; lane < kWidth; ++lane) out[position[lane]] = packet[lane];
  }

  /// marks[lane] = 1 for the lanes that hit: one masked store.
  static void mark_run(const Answer& a, std::uint8_t* marks) {
    if (L::bits(a.hit) != 0) L::set_bytes(marks, a.hit);
  }

  /// marks[index[lane]] = 1 for the lanes that hit (what an occlusion query needs).
  static void mark(const Answer& a, const std::uint32_t* index, std::uint8_t* marks) {
    std::uint32_t hits = L::bits(a.hit);
    if (hits == 0) return;
    if (L::bits(L::load(index) == L::splat(static_cast<int>(index[0])) + L::lane_index()) == L::bits(L::all())) {
      mark_run(a, marks + index[0]);  // consecutive rays (a lone object's block)
      return;
    }
    for (; hits != 0; hits &= hits - 1) marks[index[std::countr_zero(hits)]] = 1;
  }

  /// Answers for packets 0 .. packets−1 of kWidth rays: emit(k, trace_lanes(load(k))), with the
  /// paper's lookups pipelined one packet ahead (locate k+1 and ask for its cells, then read k's), so
  /// the table's cache misses overlap the next packet's arithmetic (measured: 34 -> 30.5 cycles a ray
  /// from the order alone; the prefetches then gained 8–14% on 4 MiB tables and 20% on a 65 MiB one).
  template <class Load, class Emit>
  static void stream(const FieldTables& f, std::size_t packets, const Load& load, const Emit& emit) {
    if (packets == 0) return;
    if (f.direction_lookup != DirectionLookup::nearest || f.position_lookup != PositionLookup::nearest) {
      for (std::size_t k = 0; k < packets; ++k) emit(k, trace_lanes(f, load(k), L::all()));
      return;
    }
    Located slot[2];
    locate(f, load(0), L::all(), slot[0]);
    for (std::size_t k = 0; k < packets; ++k) {
      if (k + 1 < packets) {
        locate(f, load(k + 1), L::all(), slot[(k + 1) & 1]);
        prefetch_cells(f, slot[(k + 1) & 1]);
      }
      emit(k, finish(f, slot[k & 1]));
    }
  }

  /// The world-space candidates rays[index[k]], k < count, through the query, kWidth at a time,
  /// culled first: a packet whose rays all may meet the sphere (may_meet) goes through as it is;
  /// the rays of other packets that may meet it are gathered into new full packets, and the rest
  /// are misses that are never traced. emit(packet_index, packet_position, answer) takes each
  /// packet's answers with its rays' indices into `rays` and their k. The candidates left over
  /// (fewer than 2·kWidth: the last partial packets) go to rest_index / rest_position and their
  /// number to `rest`, for the caller to trace one by one. Pipelined as stream() is.
  template <class Emit>
  static void stream_culled(const FieldTables& f, const Ray* rays, const std::uint32_t* index, std::size_t count, const float* limit,
                            const InverseTransform& to_object, std::uint32_t* rest_index, std::uint32_t* rest_position,
                            std::size_t& rest, const Emit& emit) {
    struct Packet {
      Located located;
      Rays rays;
      alignas(64) std::uint32_t index[kWidth];
      alignas(64) std::uint32_t position[kWidth];
    };
    if constexpr (kTimingBound == TimingBound::read_and_map || kTimingBound == TimingBound::read_only) {
      read_bound(rays, index, count, limit, to_object);
      rest = 0;
      return;
    }
    alignas(64) std::uint32_t pending_index[3 * kWidth], pending_position[3 * kWidth];
    std::size_t pending = 0, at = 0;
    // The next full packet of rays that may meet the sphere; false when no full packet is left.
    const auto next = [&](Packet& p) {
      while (pending < kWidth && at + kWidth <= count) {
        // Gathered into the packet's own place: a full packet stays, a partial one is overwritten.
        gather(rays, index + at, limit, to_object, p.rays);
        const M m = may_meet(f, p.rays);
        const I position = L::splat(static_cast<int>(at)) + L::lane_index();
        if (L::bits(m) == L::bits(L::all())) {
          L::store(reinterpret_cast<std::int32_t*>(p.index), L::load(index + at));
          L::store(reinterpret_cast<std::int32_t*>(p.position), position);
          at += kWidth;
          return true;
        }
        L::compress(pending_position + pending, position, m);
        pending += static_cast<std::size_t>(L::compress(pending_index + pending, L::load(index + at), m));
        at += kWidth;
      }
      if (pending < kWidth) return false;
      for (int lane = 0; lane < kWidth; ++lane) {
        p.index[lane] = pending_index[lane];
        p.position[lane] = pending_position[lane];
      }
      pending -= kWidth;
      for (std::size_t k = 0; k < pending; ++k) {
        pending_index[k] = pending_index[kWidth + k];
        pending_position[k] = pending_position[kWidth + k];
      }
      gather(rays, p.index, limit, to_object, p.rays);
      return true;
    };
    if constexpr (kTimingBound == TimingBound::no_lookups) {
      for (Packet p; next(p);) emit(p.index, p.position, Answer{L::none(), L::splat(0.0f), L::splat(0)});
      rest = 0;
      return;
    }
    const bool paper = f.direction_lookup == DirectionLookup::nearest && f.position_lookup == PositionLookup::nearest;
    Packet packet[2];
    bool have = next(packet[0]);
    if (have && paper) locate(f, packet[0].rays, L::all(), packet[0].located);
    for (int current = 0; have; current ^= 1) {
      Packet& p = packet[current];
      Packet& following = packet[current ^ 1];
      have = next(following);
      if (have && paper) {
        locate(f, following.rays, L::all(), following.located);
        prefetch_cells(f, following.located);
      }
      emit(p.index, p.position, paper ? finish(f, p.located) : trace_lanes(f, p.rays, L::all()));
    }
    rest = 0;
    for (std::size_t k = 0; k < pending; ++k) {
      rest_index[rest] = pending_index[k];
      rest_position[rest++] = pending_position[k];
    }
    for (; at < count; ++at) {
      rest_index[rest] = index[at];
      rest_position[rest++] = static_cast<std::uint32_t>(at);
    }
  }

  /// The timing bounds' stream: every full packet of consecutive candidates read as the culled stream
  /// reads it (and mapped, for READ_AND_MAP), then summed so that the reads stay.
  static void read_bound(const Ray* rays, const std::uint32_t* index, std::size_t count, const float* limit,
                         const InverseTransform& to_object) {
    F sum = L::splat(0.0f);
    for (std::size_t at = 0; at + kWidth <= count; at += kWidth) {
      Rays r;
      if constexpr (kTimingBound == TimingBound::read_and_map) {
        gather(rays, index + at, limit, to_object, r);
      } else {
        const float* first = reinterpret_cast<const float*>(rays) + 8 * static_cast<std::size_t>(index[at]);
        for (int line = 0; line < kWidth * 8; line += 16) __builtin_prefetch(first + 4 * 8 * kWidth + line);
        F column[8];
        L::transpose_rows(first, column);
        r = {column[0], column[1], column[2], column[3], column[4], column[5], column[6], column[7]};
      }
      sum = sum + r.ox + r.oy + r.oz + r.dx + r.dy + r.dz + r.tmin + r.tmax;
    }
    alignas(64) float lanes[kWidth];
    L::store(lanes, sum);
    [[maybe_unused]] volatile float kept = lanes[0];
  }

  /// The world-space rays rays[index[lane]] (kWidth indices, repeats allowed) through the query
  /// without the sphere cull: how a partial packet runs, its spare lanes repeating one of its rays.
  static Answer trace_indexed(const FieldTables& f, const Ray* rays, const std::uint32_t* index, const float* limit,
                              const InverseTransform& to_object) {
    Rays r;
    gather(rays, index, limit, to_object, r);
    return trace_lanes(f, r, L::all());
  }

  /// Lanes whose ray may meet the bounding sphere ahead of its origin: a cheaper test than the
  /// query's (no square root, no division), with margins so that it never drops a ray the query
  /// would answer (a dropped ray's answer is a miss). For culling the rays that cannot meet it.
  static M may_meet(const FieldTables& f, const Rays& r) {
    const Vec d{r.dx, r.dy, r.dz};
    const Vec oc{r.ox - L::splat(f.centre.x), r.oy - L::splat(f.centre.y), r.oz - L::splat(f.centre.z)};
    const F oo = dot(oc, oc), b = dot(oc, d), dd = dot(d, d);
    const float r2 = f.radius * f.radius;
    // The query's c = |oc|² − R², made smaller (more rays pass) by more than its rounding.
    const F c = oo * L::splat(1.0f - 1e-5f) - L::splat(r2 * (1.0f + 1e-3f));
    const M outside_going_away = (oo > L::splat(r2 * (1.0f + 1e-3f))) & (b > L::splat(0.0f));
    return (b * b - dd * c >= L::splat(0.0f)) & ~outside_going_away;
  }

  /// Stores the lanes' rays into structure-of-arrays rows at `at` (kWidth places each).
  static void store_rows(const Rays& r, float* const rows[8], std::size_t at) {
    const F* column[8] = {&r.ox, &r.oy, &r.oz, &r.dx, &r.dy, &r.dz, &r.tmin, &r.tmax};
    for (int k = 0; k < 8; ++k) L::store(rows[k] + at, *column[k]);
  }

  /// kWidth consecutive object-space rays from structure-of-arrays rows starting at `at`.
  static Rays load(const float* const rows[8], std::size_t at) {
    for (int k = 0; k < 8; ++k) __builtin_prefetch(rows[k] + at + 4 * kWidth);
    return {L::load(rows[0] + at), L::load(rows[1] + at), L::load(rows[2] + at), L::load(rows[3] + at),
            L::load(rows[4] + at), L::load(rows[5] + at), L::load(rows[6] + at), L::load(rows[7] + at)};
  }

  /// World-space rays rays[index[k]] (k < kWidth), with tmax replaced by limit[index[k]] when
  /// `limit` is given, mapped into object space as InverseTransform::apply() maps them, into `r`.
  // Written in place and inlined: returned by value, a packet's 512 bytes went through memcpy calls
  // (23% of the intra-object AO stream's instructions).
  [[gnu::always_inline]] static void gather(const Ray* rays, const std::uint32_t* index, const float* limit,
                                            const InverseTransform& to_object, Rays& r) {
    static_assert(sizeof(Ray) == 8 * sizeof(float), "a Ray is 8 floats: org, dir, tmin, tmax");
    const I at = L::load(index);
    const float* base = reinterpret_cast<const float*>(rays);
    const M all = L::all();
    F column[8];
    if (L::bits(at == L::splat(static_cast<int>(index[0])) + L::lane_index()) == L::bits(all)) {
      // Consecutive rays (the common case of one object): loaded and transposed, not gathered; the
      // rays four packets on are asked for now (a batch streams its rays from memory once).
      const float* at_first = base + 8 * static_cast<std::size_t>(index[0]);
      for (int line = 0; line < kWidth * 8; line += 16) __builtin_prefetch(at_first + 4 * 8 * kWidth + line);
      L::transpose_rows(at_first, column);
      if (limit) column[7] = L::load(limit + index[0]);
    } else {
      L::transpose_rows_at(base, index, column);
      if (limit) column[7] = lanes::gather(limit, at, all);
    }
    r.ox = column[0], r.oy = column[1], r.oz = column[2];
    r.dx = column[3], r.dy = column[4], r.dz = column[5];
    r.tmin = column[6], r.tmax = column[7];
    to_object_space(r, to_object);
  }

  /// World-space rays on lanes mapped in place into object space as InverseTransform::apply() maps them.
  // In place: taken and returned by value, a packet's rays went through memcpy calls.
  [[gnu::always_inline]] static void to_object_space(Rays& r, const InverseTransform& to_object) {
    if (to_object.identity) return;
    const Mat3& m = to_object.linear;
    const F px = r.ox - L::splat(to_object.translation.x), py = r.oy - L::splat(to_object.translation.y),
            pz = r.oz - L::splat(to_object.translation.z);
    const F dx = r.dx, dy = r.dy, dz = r.dz;
    r.ox = row_dot(m.rows[0], px, py, pz);
    r.oy = row_dot(m.rows[1], px, py, pz);
    r.oz = row_dot(m.rows[2], px, py, pz);
    r.dx = row_dot(m.rows[0], dx, dy, dz);
    r.dy = row_dot(m.rows[1], dx, dy, dz);
    r.dz = row_dot(m.rows[2], dx, dy, dz);
  }

 private:
  struct Vec {
    F x, y, z;
  };
  static F row_dot(const Vec3f& row, F x, F y, F z) { return L::splat(row.x) * x + L::splat(row.y) * y + L::splat(row.z) * z; }
  // hd::fused_dot on lanes.
  static F dot(const Vec& a, const Vec& b) { return fma(a.x, b.x, fma(a.y, b.y, a.z * b.z)); }

  // hd::atan_unit on lanes.
  [[gnu::always_inline]] static F atan_unit(F x) {
    const F x2 = x * x;
    F p = L::splat(-0.01172120f);
    p = fma(p, x2, L::splat(0.05265332f));
    p = fma(p, x2, L::splat(-0.11643287f));
    p = fma(p, x2, L::splat(0.19354346f));
    p = fma(p, x2, L::splat(-0.33262347f));
    p = fma(p, x2, L::splat(0.99997726f));
    return x * p;
  }

  // hd::lookup_atan2 on lanes.
  [[gnu::always_inline]] static F atan2(F y, F x) {
    const F ax = abs(x), ay = abs(y), zero = L::splat(0.0f);
    const F big = select(ax < ay, ay, ax), small = select(ay < ax, ay, ax);
    F a = atan_unit(select(big > zero, small / big, zero));
    a = select(ay > ax, L::splat(1.57079632679489661923f) - a, a);
    a = select(x < zero, L::splat(3.14159265358979323846f) - a, a);
    return select(y < zero, -a, a);
  }

  // disk_to_concentric on lanes.
  [[gnu::always_inline]] static void disk_to_square(F x, F y, F& s, F& t) {
    const F zero = L::splat(0.0f), half = L::splat(0.5f);
    const F r = sqrt(fma(x, x, y * y));
    const M positive = r > zero, x_major = abs(x) >= abs(y);
    // The major axis's coordinate is ±r, the minor's r·(4/π)·atan(minor/major).
    const F major = copysign(r, select(x_major, x, y));
    const F minor = major * L::splat(4 / hd::kPi<float>) * atan_unit(select(x_major, y, x) / select(x_major, x, y));
    const F a = select(positive, select(x_major, major, minor), zero);
    const F b = select(positive, select(x_major, minor, major), zero);
    s = fma(a, half, half);
    t = fma(b, half, half);
  }

  // direction_to_square on lanes.
  [[gnu::always_inline]] static void to_square(HemisphereMapping mapping, const Vec& w, F& s, F& t) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f);
    switch (mapping) {
      case HemisphereMapping::polar: {
        F phi = atan2(w.y, w.x);
        phi = select(phi < zero, phi + L::splat(2 * hd::kPi<float>), phi);
        s = phi / L::splat(2 * hd::kPi<float>);
        s = select(s >= one, zero, s);
        t = atan2(sqrt(w.x * w.x + w.y * w.y), w.z) / L::splat(hd::kPi<float> / 2);
        return;
      }
      case HemisphereMapping::rejection_malley:
        s = (w.x + one) * L::splat(0.5f);
        t = (w.y + one) * L::splat(0.5f);
        return;
      case HemisphereMapping::concentric_malley:
        disk_to_square(w.x, w.y, s, t);
        return;
      case HemisphereMapping::concentric_equal_area:
      default: {
        const F k = one / sqrt(one + max(w.z, zero));
        disk_to_square(w.x * k, w.y * k, s, t);
        return;
      }
    }
  }

  // octa::point_index on lanes.
  [[gnu::always_inline]] static I point_index(I i, I j, int n) {
    const I n_v = L::splat(n);
    const I left = (i + n_v) * (i + n_v);
    const I right = L::splat(n * n) + L::splat(2 * n + 2) * i - i * i;
    return select(i <= L::splat(0), left, right) + j + n_v - abs(i);
  }

  /// cell_of on lanes.
  static I cell_of(F s, int n) { return min(max(to_int(s * L::splat(static_cast<float>(n))), L::splat(0)), L::splat(n - 1)); }

  /// The byte of f.cells where cell c (= j·N + i) of `sample` starts; for 1-bit cells, the byte
  /// that holds it.
  [[gnu::always_inline]] static I cell_byte(const FieldTables& f, I sample, I c) {
    if constexpr (kTimingBound == TimingBound::cached_cells) sample = sample & L::splat(3);
    const I base = sample * L::splat(static_cast<int>(f.cell_stride));
    switch (f.storage) {
      case CellStorage::u8: return base + c;
      case CellStorage::u16: return base + c + c;
      case CellStorage::f32: return base + (c << L::splat(2));
      case CellStorage::bit:
      default: return base + (c >> L::splat(3));
    }
  }

  /// read_cell on lanes (of `m`): hit, distance over 2R, and the normal code when the field has one.
  [[gnu::always_inline]] static Answer read_cell(const FieldTables& f, I sample, I i, I j, M m) {
    const I c = j * L::splat(f.directions) + i;
    const I at = cell_byte(f, sample, c);
    Answer a;
    switch (f.storage) {
      case CellStorage::u8: {
        const I code = lanes::gather_bytes(f.cells, at, m) & L::splat(0xFF);
        a.hit = m & (code <= L::splat(254));
        a.t = to_float(code) * L::splat(1.0f / 254.0f);
        break;
      }
      case CellStorage::u16: {
        const I code = lanes::gather_bytes(f.cells, at, m) & L::splat(0xFFFF);
        a.hit = m & (code <= L::splat(65534));
        a.t = to_float(code) * L::splat(1.0f / 65534.0f);
        break;
      }
      case CellStorage::f32: {
        a.t = lanes::gather(reinterpret_cast<const float*>(f.cells), at >> L::splat(2), m);
        a.hit = m & (a.t <= L::splat(1.5f));
        break;
      }
      case CellStorage::bit:
      default: {
        const I word = lanes::gather_bytes(f.cells, at, m);
        a.hit = m & (((word >> (c & L::splat(7))) & L::splat(1)) == L::splat(1));
        a.t = lanes::gather(f.averages, sample, a.hit);
        break;
      }
    }
    a.normal_code = L::splat(0);
    if (f.normals != NormalStorage::none) {
      const bool narrow = f.normals == NormalStorage::oct16;
      const I offset = sample * L::splat(static_cast<int>(f.normal_stride)) + (narrow ? c + c : c * L::splat(4));
      const I code = lanes::gather_bytes(f.normal_cells, offset, a.hit);
      a.normal_code = narrow ? code & L::splat(0xFFFF) : code;
    }
    return a;
  }

  /// FieldVote on lanes.
  struct Vote {
    F total = L::splat(0.0f), hit_weight = L::splat(0.0f), distance = L::splat(0.0f), heaviest = L::splat(-1.0f);
    I code = L::splat(0);
    void add(F w, const Answer& a, M m) {
      total = select(m, total + w, total);
      const M h = m & a.hit;
      hit_weight = select(h, hit_weight + w, hit_weight);
      distance = select(h, fma(w, a.t, distance), distance);
      const M heavier = h & (w > heaviest);
      heaviest = select(heavier, w, heaviest);
      code = select(heavier, a.normal_code, code);
    }
    Answer result() const {
      const F zero = L::splat(0.0f);
      return {(total > zero) & ~(hit_weight < L::splat(0.5f) * total), distance / hit_weight, code};
    }
  };

  /// square_of on lanes: the square point (s, t) of unit direction `d` in the table of the sample
  /// with inward normal `w`, whose frame is orthonormal_basis(w, inverse) (inverse = 1 / basis_denominator(w)).
  [[gnu::always_inline]] static void square_point(const FieldTables& f, const Vec& w, F inverse, const Vec& d, M m, F& s, F& t) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f);
    // orthonormal_basis(w, inverse)
    const F sign = copysign(one, w.z);
    const F a = -inverse;
    const F b = w.x * w.y * a;
    const Vec u{one + sign * w.x * w.x * a, sign * b, -sign * w.x};
    const Vec v{b, sign + w.y * w.y * a, -w.y};
    Vec local{dot(u, d), dot(v, d), dot(w, d)};
    const M grazing = m & (local.z < zero);
    if (any(grazing)) {
      const F planar = sqrt(fma(local.x, local.x, local.y * local.y));
      const M flat = planar > zero;
      local.x = select(grazing, select(flat, local.x / planar, zero), local.x);
      local.y = select(grazing, select(flat, local.y / planar, zero), local.y);
      local.z = select(grazing, select(flat, zero, one), local.z);
    }
    to_square(f.mapping, local, s, t);
  }

  /// read_direction on lanes: sample `sample` with inward normal `w` (its frame's `inverse` as
  /// square_point's), direction `d`.
  [[gnu::always_inline]] static Answer read_direction(const FieldTables& f, I sample, const Vec& w, F inverse, const Vec& d, M m) {
    const F one = L::splat(1.0f);
    F s, t;
    square_point(f, w, inverse, d, m, s, t);
    const int n = f.directions;
    if (f.direction_lookup == DirectionLookup::nearest) return read_cell(f, sample, cell_of(s, n), cell_of(t, n), m);
    const F n_f = L::splat(static_cast<float>(n)), half = L::splat(0.5f);
    const F fx = fma(s, n_f, -half), fy = fma(t, n_f, -half);
    const I i0 = to_int(floor(fx)), j0 = to_int(floor(fy));
    const F wa = fx - to_float(i0), wb = fy - to_float(j0);
    Vote vote;
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        I i = i0 + L::splat(di);
        const I j = min(max(j0 + L::splat(dj), L::splat(0)), L::splat(n - 1));
        if (f.mapping == HemisphereMapping::polar)
          i = select(i < L::splat(0), i + L::splat(n), select(L::splat(n - 1) < i, i - L::splat(n), i));
        else
          i = min(max(i, L::splat(0)), L::splat(n - 1));
        M used = m;
        if (f.mapping == HemisphereMapping::rejection_malley) used = used & cell_used(i, j, n);
        const F weight = (di ? wa : one - wa) * (dj ? wb : one - wb);
        vote.add(weight, read_cell(f, sample, i, j, used), used);
      }
    return vote.result();
  }

  /// cell_used<float> of rejection_malley on lanes.
  [[gnu::always_inline]] static M cell_used(I i, I j, int n) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f), two = L::splat(2.0f), n_f = L::splat(static_cast<float>(n));
    const F half = L::splat(1.0f / static_cast<float>(n));
    const F xc = two * (to_float(i) + L::splat(0.5f)) / n_f - one, yc = two * (to_float(j) + L::splat(0.5f)) / n_f - one;
    const F dx = max(abs(xc) - half, zero), dy = max(abs(yc) - half, zero);
    return dx * dx + dy * dy < one;
  }

  /// The lattice triangle around a unit point of the sphere: its corners (lattice coordinates,
  /// whether within the rim), the point's hemisphere, the triangle's barycentric cases and
  /// coordinates, and (once gathered by corner_directions) the corners' directions as magnitudes
  /// |x|, |y|, z (the corners share the point's quadrant).
  struct Corners {
    M lower, same, case_b, case_c;
    F fa, fb;
    M rim[3];
    I ci[3], cj[3];
    Vec magnitude[3];
    /// Upper-hemisphere index of corner k (0 beyond the rim).
    I index(int k, int n) const { return select(rim[k], point_index(ci[k], cj[k], n), L::splat(0)); }
  };

  /// fold_to_upper, octa::coordinates and octa::containing_triangle on lanes, without the corners'
  /// directions.
  [[gnu::always_inline]] static Corners lattice_triangle(const FieldTables& f, const Vec& e) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f);
    const int n = f.lattice_n;
    Corners c;
    c.lower = e.z < zero;
    const F ez = abs(e.z);
    const F r = sqrt(max(one - ez, zero));
    const F phi = atan2(abs(e.y), abs(e.x));
    const F v = r * phi * L::splat(2 / hd::kPi<float>), u = r - v;
    const F n_f = L::splat(static_cast<float>(n)), minus_n_f = L::splat(static_cast<float>(-n));
    const F la = select(e.x > zero, n_f * u, select(e.x < zero, minus_n_f * u, zero));
    const F lb = select(e.y > zero, n_f * v, select(e.y < zero, minus_n_f * v, zero));
    const I i0 = min(max(to_int(floor(la)), L::splat(-n)), L::splat(n - 1));
    const I j0 = min(max(to_int(floor(lb)), L::splat(-n)), L::splat(n - 1));
    c.fa = la - to_float(i0);
    c.fb = lb - to_float(j0);
    c.same = ~((i0 < L::splat(0)) ^ (j0 < L::splat(0)));
    c.case_b = c.same & (c.fa + c.fb > one);
    c.case_c = ~c.same & (c.fb <= c.fa);
    const M case_d = ~c.same & (c.fb > c.fa);
    const I one_i = L::splat(1);
    const I i1 = i0 + one_i, j1 = j0 + one_i;
    c.ci[0] = select(c.case_b, i1, i0);
    c.ci[1] = select(case_d, i0, i1);
    c.ci[2] = select(c.case_c | case_d, i1, i0);
    c.cj[0] = select(c.case_b, j1, j0);
    c.cj[1] = select(case_d, j1, j0);
    c.cj[2] = j1;
    for (int k = 0; k < 3; ++k) c.rim[k] = abs(c.ci[k]) + abs(c.cj[k]) <= L::splat(n);
    return c;
  }

  /// octa::containing_triangle's barycentric weights of the corners (before the rim's zeros).
  static void triangle_weights(const Corners& c, F weight[3]) {
    const F one = L::splat(1.0f), fa = c.fa, fb = c.fb;
    weight[0] = select(c.same, select(c.case_b, fa + fb - one, one - fa - fb), select(c.case_c, one - fa, one - fb));
    weight[1] = select(c.same, select(c.case_b, one - fb, fa), select(c.case_c, fa - fb, fb - fa));
    weight[2] = select(c.same, select(c.case_b, one - fa, fb), select(c.case_c, fb, fa));
  }

  /// The magnitudes of the direction of lattice point (|i|, |j|) = (ai, aj) of the upper table, read
  /// from FieldTables::quadrant, with z = 1 − r² computed as point_direction does.
  [[gnu::always_inline]] static Vec quadrant_direction(const FieldTables& f, I ai, I aj) {
    const int n = f.lattice_n;
    Vec m;
    lanes::gather_pairs(f.quadrant, ai * L::splat(n + 1) + aj, m.x, m.y);
    // r = |i|/n + |j|/n exactly (n a power of two); the centre's 1 − 0 is its z = 1.
    const F r = to_float(ai + aj) * L::splat(1.0f / static_cast<float>(n));
    m.z = select(ai + aj == L::splat(n), L::splat(0.0f), L::splat(1.0f) - r * r);
    return m;
  }

  /// The three corners' directions into c.magnitude (blending reads all three).
  [[gnu::always_inline]] static void corner_directions(const FieldTables& f, Corners& c) {
    for (int k = 0; k < 3; ++k) c.magnitude[k] = quadrant_direction(f, abs(c.ci[k]), abs(c.cj[k]));
  }

  /// Corner k's direction (the upper table's entry): the magnitudes with the signs of its lattice
  /// coordinates (+0 where a coordinate is 0, as point_direction writes it).
  static Vec corner_direction(const Corners& c, int k) { return signed_direction(c.magnitude[k], c.ci[k], c.cj[k]); }
  /// Magnitudes `m` of lattice point (i, j) with the point's signs.
  static Vec signed_direction(const Vec& m, I i, I j) {
    const I zero_i = L::splat(0);
    return {select(i < zero_i, -m.x, m.x), select(j < zero_i, -m.y, m.y), m.z};
  }

  /// sample_inward on lanes: the inward normal of the sample in direction `p` of the upper table.
  static Vec inward(const Corners& c, const Vec& p) { return Vec{-p.x, -p.y, select(c.lower, p.z, -p.z)}; }
  /// The index offset of the lanes' hemisphere.
  static I hemisphere_offset(const FieldTables& f, const Corners& c) { return select(c.lower, L::splat(f.upper_count), L::splat(0)); }

  /// heaviest_corner_position on lanes: the sample index and its inward normal, the one corner's
  /// direction read (nearest_position's three reads and cosines were 18% of intra-object AO on AVX2).
  [[gnu::always_inline]] static void heaviest_corner(const FieldTables& f, const Corners& c, M active, I& sample, Vec& w) {
    F weight[3];
    triangle_weights(c, weight);
    F best_weight = L::splat(-2.0f);
    I best_i = c.ci[0], best_j = c.cj[0];
    for (int k = 0; k < 3; ++k) {
      const M better = active & c.rim[k] & (weight[k] > best_weight);
      best_weight = select(better, weight[k], best_weight);
      best_i = select(better, c.ci[k], best_i);
      best_j = select(better, c.cj[k], best_j);
    }
    sample = point_index(best_i, best_j, f.lattice_n) + hemisphere_offset(f, c);
    w = inward(c, signed_direction(quadrant_direction(f, abs(best_i), abs(best_j)), best_i, best_j));
  }

  /// The ray against the bounding sphere on lanes: which lanes meet it as the scalar query lets them
  /// (from inside, or entering ahead), where, and the direction the table is read in.
  struct Geometry {
    M active, inside;
    F inv, s_min, s_max, s_enter, s_exit;  // inv: 1 / |dir|
    Vec far;                                // SphereVisit::far
  };

  /// sample_read on lanes: the sample with inward normal `w`, the lanes' Geometry `g` and their
  /// parallel direction `q`; the direction to read in, the shift of a hit's distance and its limit,
  /// and 1 / basis_denominator(w) for the sample's frame (shared with the line's 1 / len, as there).
  [[gnu::always_inline]] static void sample_read(const FieldTables& f, const Geometry& g, const Vec& w, const Vec& q, Vec& read, F& shift,
                                                 F& limit, F& inverse) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f), beyond = L::splat(2.0f);
    const F denominator = copysign(one, w.z) + w.z;
    shift = zero;
    limit = beyond;
    if (f.sample_line == SampleLine::parallel) {
      read = q;
      inverse = one / denominator;
      return;
    }
    const F radius = L::splat(f.radius);
    const Vec line{fma(w.x, radius, g.far.x), fma(w.y, radius, g.far.y), fma(w.z, radius, g.far.z)};
    const F len = sqrt(dot(line, line));
    const M long_enough = len > L::splat(kShortestLine * f.radius);
    // hd::reciprocals(len, denominator) where the line is long enough; elsewhere 1 / (1 · denominator)
    // and 1 · that, the frame's own quotient.
    const F len_or_one = select(long_enough, len, one);
    const F p = one / (len_or_one * denominator);
    const F inv = denominator * p;
    inverse = len_or_one * p;
    read = {select(long_enough, line.x * inv, q.x), select(long_enough, line.y * inv, q.y), select(long_enough, line.z * inv, q.z)};
    const M from_inside = long_enough & g.inside;
    if (!any(from_inside)) return;  // from outside (the corner's rays): neither a shift nor a limit
    const F inv_diameter = L::splat(inverse_diameter(f));
    shift = select(from_inside, (g.s_exit - len) * inv_diameter, zero);
    const Vec apart{read.x - q.x, read.y - q.y, read.z - q.z};
    const F chord = sqrt(dot(apart, apart));
    limit = select(from_inside, len * inv_diameter - max(L::splat(f.self_offset), L::splat(kChordShare) * chord), beyond);
  }

  /// shifted_answer on lanes.
  [[gnu::always_inline]] static void shift_answer(Answer& a, const F& shift, const F& limit) {
    a.hit = a.hit & (a.t < limit);
    a.t = a.t + shift;
  }

  /// read_sample on lanes: the sample `sample` with inward normal `w`.
  [[gnu::always_inline]] static Answer read_sample(const FieldTables& f, const Geometry& g, I sample, const Vec& w, const Vec& q, M m) {
    Vec read;
    F shift, limit, inverse;
    sample_read(f, g, w, q, read, shift, limit, inverse);
    Answer a = read_direction(f, sample, w, inverse, read, m);
    shift_answer(a, shift, limit);
    return a;
  }

  /// read_at on lanes: the lanes' Geometry `g`, the unit point `e` of the sphere, parallel direction `q`.
  [[gnu::always_inline]] static Answer read_at(const FieldTables& f, const Geometry& g, const Vec& e, const Vec& q, M active) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f);
    Corners c = lattice_triangle(f, e);
    if (f.position_lookup == PositionLookup::nearest) {
      I sample;
      Vec w;
      heaviest_corner(f, c, active, sample, w);
      return read_sample(f, g, sample, w, q, active);
    }
    // blend_positions: triangle weights, clamped at 0, zero beyond the rim, normalised; a corner
    // beyond the rim repeats the heaviest valid one.
    corner_directions(f, c);
    F weight[3];
    triangle_weights(c, weight);
    F total = zero, valid_weight = L::splat(-1.0f);
    I valid_index = L::splat(0), valid_k = L::splat(-1);
    Vec direction[3];
    for (int k = 0; k < 3; ++k) direction[k] = corner_direction(c, k);
    Vec valid_corner = direction[0];
    for (int k = 0; k < 3; ++k) {
      weight[k] = select(c.rim[k], max(weight[k], zero), zero);
      const M take = c.rim[k] & (weight[k] > valid_weight);
      valid_weight = select(take, weight[k], valid_weight);
      valid_index = select(take, c.index(k, f.lattice_n), valid_index);
      valid_k = select(take, L::splat(k), valid_k);
      valid_corner = {select(take, direction[k].x, valid_corner.x), select(take, direction[k].y, valid_corner.y),
                      select(take, direction[k].z, valid_corner.z)};
      total = total + weight[k];
    }
    const I offset = hemisphere_offset(f, c);
    Vote vote;
    for (int k = 0; k < 3; ++k) {
      const F w = select(total > zero, weight[k] / total, select(valid_k == L::splat(k), one, zero));
      const M m = active & (w > zero);
      if (!any(m)) continue;
      const I sample = select(c.rim[k], c.index(k, f.lattice_n), valid_index) + offset;
      const Vec p{select(c.rim[k], direction[k].x, valid_corner.x), select(c.rim[k], direction[k].y, valid_corner.y),
                  select(c.rim[k], direction[k].z, valid_corner.z)};
      vote.add(w, read_sample(f, g, sample, inward(c, p), q, m), m);
    }
    return vote.result();
  }

  /// The lanes' Geometry into `g`, the unit point `e` of the sphere where the table is read (entry, or exit
  /// from inside) and the direction `q` it is read in (into the sphere).
  // Written into `g` in place: returned by value into a Located, its copy was 3% of a stream's instructions.
  [[gnu::always_inline]] static void geometry(const FieldTables& f, const Rays& r, M valid, Vec& e_unit, Vec& q, Geometry& g) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f);
    const Vec dir{r.dx, r.dy, r.dz};
    const F len = sqrt(dot(dir, dir));
    g.inv = one / len;
    const Vec d{dir.x * g.inv, dir.y * g.inv, dir.z * g.inv};
    g.s_min = r.tmin * len;
    g.s_max = r.tmax * len;
    const Vec oc{r.ox - L::splat(f.centre.x), r.oy - L::splat(f.centre.y), r.oz - L::splat(f.centre.z)};
    const F b = dot(oc, d), c = dot(oc, oc) - L::splat(f.radius * f.radius);
    const F disc = fma(b, b, -c);
    g.active = valid & (disc >= zero);
    const F root = sqrt(max(disc, zero));
    g.s_enter = -b - root;
    g.s_exit = -b + root;
    g.inside = ~(c > zero);
    g.active = g.active & (g.inside | ~(g.s_enter < zero));
    const F s_at = select(g.inside, g.s_exit, g.s_enter);
    Vec e{fma(d.x, s_at, oc.x), fma(d.y, s_at, oc.y), fma(d.z, s_at, oc.z)};
    F e_inv = L::splat(1.0f / f.radius);
    if (any(g.active & ~g.inside)) e_inv = select(g.inside, e_inv, one / sqrt(dot(e, e)));
    e_unit = {e.x * e_inv, e.y * e_inv, e.z * e_inv};
    q = {select(g.inside, -d.x, d.x), select(g.inside, -d.y, d.y), select(g.inside, -d.z, d.z)};
    g.far = {zero, zero, zero};
    if (f.sample_line != SampleLine::parallel)
      g.far = {select(g.inside, oc.x, fma(d.x, g.s_exit, oc.x)), select(g.inside, oc.y, fma(d.y, g.s_exit, oc.y)),
               select(g.inside, oc.z, fma(d.z, g.s_exit, oc.z))};
  }

  /// The end of trace_field on lanes: the table's answer `a` placed along the ray and held to its range.
  [[gnu::always_inline]] static Answer place(const FieldTables& f, const Geometry& g, Answer a) {
    const float diameter = 2.0f * f.radius;
    // place_answer's fma(∓t, diameter, s_exit or s_enter), the sign moved onto the diameter.
    const F s_hit = fma(a.t, select(g.inside, L::splat(-diameter), L::splat(diameter)), select(g.inside, g.s_exit, g.s_enter));
    a.hit = a.hit & g.active & (~g.inside | (s_hit > L::splat(f.self_offset * diameter))) & (s_hit >= g.s_min) & (s_hit <= g.s_max);
    a.t = s_hit * g.inv;
    return a;
  }

  /// trace_field on lanes (of `valid`).
  [[gnu::always_inline]] static Answer trace_lanes(const FieldTables& f, const Rays& r, M valid) {
    Vec e, q;
    Geometry g;
    geometry(f, r, valid, e, q, g);
    if (!any(g.active)) return {L::none(), L::splat(0.0f), L::splat(0)};
    return place(f, g, read_at(f, g, e, q, g.active));
  }

  /// With the paper's lookups (one sample, one cell), trace_lanes() in two halves so that a stream
  /// can locate the next rays' cells before it reads this one's: `locate` finds the cell, `finish`
  /// reads it.
  struct Located {
    Geometry g;
    I sample, i, j;
    F shift, limit;  // sample_read's
  };

  [[gnu::always_inline]] static void locate(const FieldTables& f, const Rays& r, M valid, Located& l) {
    Vec e, q, w;
    geometry(f, r, valid, e, q, l.g);
    if constexpr (stage_out(TimingBound::no_map_line_lattice)) {
      l.sample = min(max(to_int(fma(e.x, L::splat(0.5f), L::splat(0.5f)) * L::splat(static_cast<float>(f.upper_count))), L::splat(0)),
                     L::splat(f.upper_count - 1));
      w = e;
    } else {
      heaviest_corner(f, lattice_triangle(f, e), l.g.active, l.sample, w);
    }
    Vec read;
    F inverse;
    if constexpr (stage_out(TimingBound::no_map_line)) {
      read = q, inverse = w.z, l.shift = L::splat(0.0f), l.limit = L::splat(2.0f);
    } else {
      sample_read(f, l.g, w, q, read, l.shift, l.limit, inverse);
    }
    F s, t;
    if constexpr (stage_out(TimingBound::no_map)) {
      // inverse · 0 keeps the frame's reciprocal computed, as square_point would use it
      s = fma(read.x, L::splat(0.5f), inverse * L::splat(0.0f) + L::splat(0.5f)), t = fma(read.y, L::splat(0.5f), L::splat(0.5f));
    } else {
      square_point(f, w, inverse, read, l.g.active, s, t);
    }
    l.i = cell_of(s, f.directions);
    l.j = cell_of(t, f.directions);
  }

  /// Whether a timing-bound build leaves out the lookup's stage `stage` (one of no_map .. sphere_only,
  /// each leaving out the ones before it too).
  static constexpr bool stage_out(TimingBound stage) { return kTimingBound >= stage && kTimingBound <= TimingBound::sphere_only; }

  /// Asks for the cache lines of the cells `l` will read (its active lanes'), so that they arrive while
  /// the next packet is located.
  [[gnu::always_inline]] static void prefetch_cells(const FieldTables& f, const Located& l) {
    if constexpr (stage_out(TimingBound::sphere_only)) return;
    const I offset = cell_byte(f, l.sample, l.j * L::splat(f.directions) + l.i);
    alignas(64) std::int32_t at[kWidth];
    L::store(at, select(l.g.active, offset, L::splat(0)));
    // Read back from memory: GCC would otherwise take each lane out of the register (two
    // instructions a lane where a load is one, and loads issue three a cycle).
    asm("" : "+m"(at));
    for (int lane = 0; lane < kWidth; ++lane) __builtin_prefetch(f.cells + at[lane]);
  }

  [[gnu::always_inline]] static Answer finish(const FieldTables& f, const Located& l) {
    Answer a;
    if constexpr (stage_out(TimingBound::sphere_only))
      a = {l.g.active & (l.i < l.j), to_float(l.i + l.sample) * L::splat(1.0f / 4096.0f), L::splat(0)};
    else
      a = read_cell(f, l.sample, l.i, l.j, l.g.active);
    shift_answer(a, l.shift, l.limit);
    return place(f, l.g, a);
  }

  /// decode_normal on lanes.
  [[gnu::always_inline]] static Vec decode_normals(const FieldTables& f, I code) {
    const F zero = L::splat(0.0f), one = L::splat(1.0f), two = L::splat(2.0f);
    const int half = f.normals == NormalStorage::oct16 ? 8 : 16;
    const F top = L::splat(static_cast<float>(normal_max_code(f.normals)));
    F u = to_float(code & L::splat(static_cast<int>(normal_max_code(f.normals)))) / top * two - one;
    F v = to_float(code >> L::splat(half)) / top * two - one;
    const F z = one - abs(u) - abs(v);
    const M folded = z < zero;
    const F fu = copysign(one - abs(v), u), fv = copysign(one - abs(u), v);
    u = select(folded, fu, u);
    v = select(folded, fv, v);
    const F inv = one / sqrt(u * u + v * v + z * z);
    return {u * inv, v * inv, z * inv};
  }
};

}  // namespace vf::field
