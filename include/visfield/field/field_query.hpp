#pragma once
/// \file One ObjectField query in object space, exactly as the CPU's single-ray path, its SIMD
/// batch (src/field/field_kernel.hpp) and the CUDA kernels compute it: the same float operations
/// in the same order, so that the three give the same bits (host and device, no STL). Products
/// that feed a sum are explicit fused multiply-adds (hd::fma): IEEE rounds them once everywhere,
/// so they keep the bits equal where a compiler's own contraction would not. The field is
/// read through FieldTables, plain pointers to its tables, so that a device copy reads the same.
///
/// A ray meets the bounding sphere. From outside, it reads the table of the positional sample
/// where it enters, in its own direction, and hits at entry + stored distance (inter-object, the
/// 2008 paper). From inside (an AO ray leaving the object's own surface), it reads, at the sample
/// where it leaves, the distance d2 back along the reverse direction and hits when d2 is shorter
/// than its own distance d1 to that point, beyond the start surface (intra-object, the GPU paper).

#include "visfield/core/host_device.hpp"
#include "visfield/core/orthonormal_basis.hpp"
#include "visfield/field/cell_codec.hpp"
#include "visfield/field/hemisphere_map.hpp"
#include "visfield/field/normal_codec.hpp"
#include "visfield/field/position_lookup.hpp"

namespace vf::field {

/// How a query reads the direction table of a positional sample.
enum class DirectionLookup : unsigned char {
  nearest = 0,   ///< The cell the direction falls in (the paper).
  bilinear = 1,  ///< The four nearest cell centres, weighted bilinearly (hits vote, hit distances average).
};

/// Which positional samples a query reads.
enum class PositionLookup : unsigned char {
  nearest = 0,  ///< The sample nearest to the point where the ray meets the sphere (the paper), as the
                ///< heaviest corner of its lattice triangle (heaviest_corner_position()).
  blend = 1,    ///< The three samples of the lattice triangle around it, barycentric weights.
  lines = 2,    ///< From outside, the stored lines nearest to the ray's chord in the sphere vote (read_lines();
                ///< it picks the cells too); from inside as `nearest`.
};

/// Which line through a positional sample its table is read along.
enum class SampleLine : unsigned char {
  parallel = 0,  ///< The ray's own direction, moved to the sample (the papers).
  through = 1,   ///< From the sample through the ray's far end in the sphere (its origin from inside, its exit from
                 ///< outside): the line meets the ray there, so the sample's offset shrinks to nothing along it.
};

/// An approximate answer in object space: a hit at ray parameter t, or a miss; with a normal field,
/// the unit object-space normal of the surface the answering cell saw.
struct FieldAnswer {
  bool hit = false;
  bool has_normal = false;
  float t = 0.0f;
  hd::Vec3<float> normal{0.0f, 0.0f, 0.0f};
};

/// What a query reads of one field: its parameters and borrowed pointers to its tables (valid as
/// long as the field). Plain data: copied by value to a device.
struct FieldTables {
  int lattice_n = 0;      ///< Half-width of the positional lattice, 2^level (8 .. 64).
  int upper_count = 0;    ///< Samples per hemisphere, octa::point_count(lattice_n).
  int directions = 0;     ///< N of the N×N direction tables.
  HemisphereMapping mapping = HemisphereMapping::concentric_malley;
  CellStorage storage = CellStorage::u8;
  NormalStorage normals = NormalStorage::none;
  DirectionLookup direction_lookup = DirectionLookup::nearest;
  PositionLookup position_lookup = PositionLookup::nearest;
  SampleLine sample_line = SampleLine::parallel;
  hd::Vec3<float> centre{0.0f, 0.0f, 0.0f};  ///< Bounding sphere, object space.
  float radius = 0.0f;
  float self_offset = 0.0f;                  ///< Intra-object start-surface offset over 2R.
  const hd::Vec3<float>* upper = nullptr;    ///< Upper samples' unit directions, by octa::point_index.
  /// The same directions' |x| and |y| (low and high 32 bits) by (|i|, |j|) at |i|·(n + 1) + |j|:
  /// what the SIMD lookup gathers (one 64-bit read a corner); the scalar query does not read it.
  const unsigned long long* quadrant = nullptr;
  const unsigned char* cells = nullptr;      ///< Distance tables, sample after sample.
  unsigned long long cell_stride = 0;        ///< Bytes per sample of `cells`.
  const float* averages = nullptr;           ///< CellStorage::bit: mean hit distance per sample.
  const unsigned char* normal_cells = nullptr;  ///< Normal tables, sample after sample (or null).
  unsigned long long normal_stride = 0;      ///< Bytes per sample of `normal_cells`.
  /// PositionLookup::lines: each cell's direction in a sample's frame, at j·N + i (cell_direction(), as
  /// the precompute cast it, rounded to float); null otherwise.
  const hd::Vec3<float>* cell_centres = nullptr;
};

/// The inward unit normal of positional sample `sample`, the pole of its direction table: minus
/// its direction, whose lower-hemisphere copy mirrors z (negated, not subtracted, so that the
/// equator's two copies keep their signed zeros apart and their frames as the precompute built them).
VF_HOST_DEVICE inline hd::Vec3<float> sample_inward(const FieldTables& f, int sample) {
  const bool lower = sample >= f.upper_count;
  const hd::Vec3<float> p = f.upper[lower ? sample - f.upper_count : sample];
  return {-p.x, -p.y, lower ? p.z : -p.z};
}

/// Cell (i, j) of `sample`: hit or miss, the normalised distance (over 2R) of a hit, and its normal
/// when the field has one.
VF_HOST_DEVICE inline FieldAnswer read_cell(const FieldTables& f, int sample, int i, int j) {
  const unsigned long long c = static_cast<unsigned long long>(j) * static_cast<unsigned long long>(f.directions) +
                               static_cast<unsigned long long>(i);
  const unsigned char* base = f.cells + static_cast<unsigned long long>(sample) * f.cell_stride;
  FieldAnswer a;
  switch (f.storage) {
    case CellStorage::u8: {
      const unsigned code = base[c];
      a.hit = quantized_is_hit(CellStorage::u8, code);
      a.t = decode_quantized(CellStorage::u8, code);
      break;
    }
    case CellStorage::u16: {
      const unsigned code = static_cast<unsigned>(base[2 * c]) | static_cast<unsigned>(base[2 * c + 1]) << 8;
      a.hit = quantized_is_hit(CellStorage::u16, code);
      a.t = decode_quantized(CellStorage::u16, code);
      break;
    }
    case CellStorage::f32: {
      float value;
      unsigned char* bytes = reinterpret_cast<unsigned char*>(&value);
      for (int k = 0; k < 4; ++k) bytes[k] = base[4 * c + static_cast<unsigned long long>(k)];
      a.hit = value <= 1.5f;
      a.t = value;
      break;
    }
    case CellStorage::bit:
    default:
      a.hit = (base[c >> 3] >> (c & 7)) & 1u;
      a.t = f.averages[sample];
      break;
  }
  if (!a.hit) return {};
  if (f.normals != NormalStorage::none) {
    const unsigned char* n = f.normal_cells + static_cast<unsigned long long>(sample) * f.normal_stride;
    const unsigned code = f.normals == NormalStorage::oct16
                              ? static_cast<unsigned>(n[2 * c]) | static_cast<unsigned>(n[2 * c + 1]) << 8
                              : static_cast<unsigned>(n[4 * c]) | static_cast<unsigned>(n[4 * c + 1]) << 8 |
                                    static_cast<unsigned>(n[4 * c + 2]) << 16 | static_cast<unsigned>(n[4 * c + 3]) << 24;
    a.normal = decode_normal(f.normals, code);
    a.has_normal = true;
  }
  return a;
}

/// Folds the answers of several table reads by weight: a hit when hits carry at least half the
/// weight, at the hit-weighted mean distance, with the normal of the heaviest hit (the first of equals).
struct FieldVote {
  float total = 0.0f, hit_weight = 0.0f, distance = 0.0f, heaviest = -1.0f;
  FieldAnswer heaviest_hit;

  /// Counts answer `a` with weight `w` (>= 0).
  VF_HOST_DEVICE void add(float w, const FieldAnswer& a) {
    total += w;
    if (!a.hit) return;
    hit_weight += w;
    distance = hd::fma(w, a.t, distance);
    if (w > heaviest) {
      heaviest = w;
      heaviest_hit = a;
    }
  }
  /// The folded answer.
  VF_HOST_DEVICE FieldAnswer result() const {
    if (!(total > 0.0f) || hit_weight < 0.5f * total) return {};
    FieldAnswer a = heaviest_hit;
    a.t = distance / hit_weight;
    return a;
  }
};

/// Whether cell (i, j) of the bilinear footprint counts: inside the table (polar tables wrap in i)
/// and used by the mapping. Writes the wrapped or clamped indices back.
VF_HOST_DEVICE inline bool bilinear_cell(const FieldTables& f, int& i, int& j) {
  const int n = f.directions;
  j = hd::clamp(j, 0, n - 1);
  i = f.mapping == HemisphereMapping::polar ? (i + n) % n : hd::clamp(i, 0, n - 1);
  return cell_used<float>(f.mapping, i, j, n);
}

/// Where unit direction `d` (pointing into the sphere) falls in a sample's table: the direction in
/// the sample's hemisphere frame (orthonormal_basis of its inward normal, as the precompute built
/// it; SampleRead::frame), mapped to the unit square (s, t).
VF_HOST_DEVICE inline void square_of(const FieldTables& f, const OrthonormalBasis<float>& frame, const hd::Vec3<float>& d, float& s,
                                     float& t) {
  hd::Vec3<float> local{hd::fused_dot(frame.u, d), hd::fused_dot(frame.v, d), hd::fused_dot(frame.w, d)};
  if (local.z < 0.0f) {  // grazing: the sample's pole differs a little from the entry point's normal
    const float planar = hd::sqrt(hd::fma(local.x, local.x, local.y * local.y));
    local = planar > 0.0f ? hd::Vec3<float>{local.x / planar, local.y / planar, 0.0f} : hd::Vec3<float>{0.0f, 0.0f, 1.0f};
  }
  direction_to_square(f.mapping, local, s, t);
}

/// The table of `sample` (hemisphere frame `frame`) read in unit direction `d` (pointing into the
/// sphere): the cell square_of() finds, or the bilinear vote of the four cells around it.
VF_HOST_DEVICE inline FieldAnswer read_direction(const FieldTables& f, int sample, const OrthonormalBasis<float>& frame,
                                                 const hd::Vec3<float>& d) {
  float s, t;
  square_of(f, frame, d, s, t);
  const int n = f.directions;
  if (f.direction_lookup == DirectionLookup::nearest) return read_cell(f, sample, cell_of(s, n), cell_of(t, n));
  const float fx = hd::fma(s, static_cast<float>(n), -0.5f), fy = hd::fma(t, static_cast<float>(n), -0.5f);
  const int i0 = static_cast<int>(hd::floor(fx)), j0 = static_cast<int>(hd::floor(fy));
  const float a = fx - static_cast<float>(i0), b = fy - static_cast<float>(j0);
  FieldVote vote;
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      int i = i0 + di, j = j0 + dj;
      if (!bilinear_cell(f, i, j)) continue;
      vote.add((di ? a : 1.0f - a) * (dj ? b : 1.0f - b), read_cell(f, sample, i, j));
    }
  return vote.result();
}

/// Where a ray meets a field's sphere: the point to read (a unit vector from the centre), the
/// direction to read it in, and what places the table's answer along the ray (sphere_visit()).
struct SphereVisit {
  bool inside = false;                     ///< The origin is inside the sphere (intra-object: read at the exit, backwards).
  float s_enter = 0.0f, s_exit = 0.0f;     ///< Where the ray's line enters and leaves the sphere (distances along the unit direction).
  float s_min = 0.0f, s_max = 0.0f;        ///< The ray's range in the same units.
  float inv = 0.0f;                        ///< 1 / |dir|: back to the ray's own t.
  hd::Vec3<float> point{0.0f, 0.0f, 0.0f};  ///< The point of the sphere to read at, as a unit vector.
  hd::Vec3<float> read{0.0f, 0.0f, 0.0f};   ///< The unit direction to read the table in (into the sphere).
  hd::Vec3<float> far{0.0f, 0.0f, 0.0f};    ///< The ray's far end in the sphere from its centre: the origin from inside, the exit from outside.
};

/// Below this length (over R) the line from a sample to the ray's far end has no direction to
/// speak of, and SampleLine::through reads parallel instead.
inline constexpr float kShortestLine = 1e-3f;
/// The share of |q − ray| (see SampleRead) a hit from inside must clear beyond the origin. The whole
/// chord bound is for an object as curved as its bounding sphere and hides real near occluders
/// (bunny 1090 x 64^2 AO image RMS 2.78 -> 3.68); a quarter removes the convex sphere's false shadow
/// (15.1 -> 0.28) and keeps every scanned mesh's RMS within 3% (docs/objectfield-measurements.md).
inline constexpr float kChordShare = 0.25f;

/// The line the table of `sample` is read along for visit `v`, as f.sample_line says: its unit
/// direction `q` (into the sphere), `shift`, what a hit's distance (over 2R) gains so that
/// place_answer() puts it where that line found it (from inside, the line through the origin is
/// `len` long where the ray's own is s_exit; otherwise 0), and `limit`, the distance (over 2R,
/// before the shift) a hit must stay short of.
///
/// From inside, the line through the origin leaves the ray's direction by an angle δ. Where it
/// passes below the start surface it enters a convex object before the origin, by a chord of at
/// most 2R·sin δ, so a hit that close to the origin is the start surface seen again: the limit
/// keeps the hit beyond max(self_offset, kChordShare·|q − ray|) of the origin (|q − ray| = 2 sin(δ/2)).
struct SampleRead {
  hd::Vec3<float> q{0.0f, 0.0f, 0.0f};
  float shift = 0.0f;
  float limit = 2.0f;            // beyond any stored distance
  OrthonormalBasis<float> frame;  // the sample's hemisphere frame, which square_of() reads q in
};

/// 1 / 2R: distances along a read are divided by the diameter as products by this constant (the
/// SIMD lookup's divider is its busiest unit; every implementation rounds it alike).
VF_HOST_DEVICE inline float inverse_diameter(const FieldTables& f) { return 1.0f / (2.0f * f.radius); }

/// The read of `sample` for visit `v` (O(1); two square roots and a division when through: the
/// line's length and the frame share one, hd::reciprocals).
VF_HOST_DEVICE inline SampleRead sample_read(const FieldTables& f, const SphereVisit& v, int sample) {
  const hd::Vec3<float> w = sample_inward(f, sample);  // the sample's point is −R·w
  if (f.sample_line == SampleLine::parallel) return {v.read, 0.0f, 2.0f, orthonormal_basis(w)};
  const hd::Vec3<float> g{hd::fma(w.x, f.radius, v.far.x), hd::fma(w.y, f.radius, v.far.y), hd::fma(w.z, f.radius, v.far.z)};
  const float len = hd::sqrt(hd::fused_dot(g, g));
  if (!(len > kShortestLine * f.radius)) return {v.read, 0.0f, 2.0f, orthonormal_basis(w)};
  float inv, inv_denominator;
  hd::reciprocals(len, basis_denominator(w), inv, inv_denominator);
  const OrthonormalBasis<float> frame = orthonormal_basis(w, inv_denominator);
  const hd::Vec3<float> q{g.x * inv, g.y * inv, g.z * inv};
  if (!v.inside) return {q, 0.0f, 2.0f, frame};
  const float inv_diameter = inverse_diameter(f);
  const hd::Vec3<float> apart{q.x - v.read.x, q.y - v.read.y, q.z - v.read.z};
  const float chord = hd::sqrt(hd::fused_dot(apart, apart));
  return {q, (v.s_exit - len) * inv_diameter, len * inv_diameter - hd::max(f.self_offset, kChordShare * chord), frame};
}

/// Answer `a` of the table read `r` describes: a miss where its hit is not short of r.limit,
/// otherwise its distance moved by r.shift.
VF_HOST_DEVICE inline FieldAnswer shifted_answer(const SampleRead& r, FieldAnswer a) {
  if (!a.hit) return a;
  if (!(a.t < r.limit)) return {};
  a.t = a.t + r.shift;
  return a;
}

/// The table of `sample` read for visit `v` along sample_read()'s line (shifted_answer()).
VF_HOST_DEVICE inline FieldAnswer read_sample(const FieldTables& f, const SphereVisit& v, int sample) {
  const SampleRead r = sample_read(f, v, sample);
  return shifted_answer(r, read_direction(f, sample, r.frame, r.q));
}

/// PositionLookup::lines: how many of the candidate lines vote.
inline constexpr int kLineVoters = 10;

/// PositionLookup::lines from outside: the stored lines (a sample's point, a cell's direction) nearest
/// to the ray's chord in the sphere, voting. At each end of the chord the nearest sample is read around
/// the line from it through the other end (the 3 × 3 cells around that line's cell: 18 candidates);
/// each candidate's distance from the chord is its RMS over the chord (e = |A|² + |B|² + A·B, A and B
/// its offsets at the chord's ends), and the kLineVoters nearest vote with weight 1 / √e. A read from
/// the far end sees the chord backwards: its distance is turned to run from the entry. Denser
/// candidates than one sample's four cells, and voting as interpolation does: at 4226 × 32² u8 the
/// corner's image RMS falls from 0.78 to 0.63 (docs/objectfield-measurements.md), at 18 cell
/// directions and 10 table reads a ray.
VF_HOST_DEVICE inline FieldAnswer read_lines(const FieldTables& f, const SphereVisit& v) {
  const int n = f.directions;
  const float chord = v.s_exit - v.s_enter;
  const hd::Vec3<float> entry{v.point.x * f.radius, v.point.y * f.radius, v.point.z * f.radius};
  const hd::Vec3<float> exit{hd::fma(v.read.x, chord, entry.x), hd::fma(v.read.y, chord, entry.y), hd::fma(v.read.z, chord, entry.z)};
  // The kLineVoters nearest candidates so far, nearest first (earlier candidates first among equals).
  float nearest_e[kLineVoters];
  int voter_sample[kLineVoters], voter_cell[kLineVoters];
  bool voter_far[kLineVoters];
  int voters = 0;
  for (int end = 0; end < 2; ++end) {
    const hd::Vec3<float> at = end == 0 ? entry : exit, pivot = end == 0 ? exit : entry;
    const float at_inv = 1.0f / hd::sqrt(hd::fused_dot(at, at));
    const int sample = nearest_position(hd::Vec3<float>{at.x * at_inv, at.y * at_inv, at.z * at_inv}, f.lattice_n, f.upper);
    const hd::Vec3<float> w = sample_inward(f, sample);
    const hd::Vec3<float> g{hd::fma(w.x, f.radius, pivot.x), hd::fma(w.y, f.radius, pivot.y), hd::fma(w.z, f.radius, pivot.z)};
    const float len = hd::sqrt(hd::fused_dot(g, g));
    if (!(len > kShortestLine * f.radius)) continue;
    const float len_inv = 1.0f / len;
    const OrthonormalBasis<float> frame = orthonormal_basis(w);
    float s, t;
    square_of(f, frame, hd::Vec3<float>{g.x * len_inv, g.y * len_inv, g.z * len_inv}, s, t);
    const int ci = cell_of(s, n), cj = cell_of(t, n);
    // The chord's ends from the sample's point −R·w.
    const hd::Vec3<float> from_entry{hd::fma(w.x, f.radius, entry.x), hd::fma(w.y, f.radius, entry.y), hd::fma(w.z, f.radius, entry.z)};
    const hd::Vec3<float> from_exit{hd::fma(w.x, f.radius, exit.x), hd::fma(w.y, f.radius, exit.y), hd::fma(w.z, f.radius, exit.z)};
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        int i = ci + di, j = cj + dj;
        if (j < 0 || j >= n || (f.mapping != HemisphereMapping::polar && (i < 0 || i >= n))) continue;
        if (!bilinear_cell(f, i, j)) continue;
        const int cell = j * n + i;
        const hd::Vec3<float> l = f.cell_centres[cell];
        const hd::Vec3<float> c{hd::fma(frame.u.x, l.x, hd::fma(frame.v.x, l.y, frame.w.x * l.z)),
                                hd::fma(frame.u.y, l.x, hd::fma(frame.v.y, l.y, frame.w.y * l.z)),
                                hd::fma(frame.u.z, l.x, hd::fma(frame.v.z, l.y, frame.w.z * l.z))};
        const float a_along = hd::fused_dot(from_entry, c), b_along = hd::fused_dot(from_exit, c);
        const hd::Vec3<float> a{hd::fma(-c.x, a_along, from_entry.x), hd::fma(-c.y, a_along, from_entry.y), hd::fma(-c.z, a_along, from_entry.z)};
        const hd::Vec3<float> b{hd::fma(-c.x, b_along, from_exit.x), hd::fma(-c.y, b_along, from_exit.y), hd::fma(-c.z, b_along, from_exit.z)};
        const float e = hd::fused_dot(a, a) + hd::fused_dot(b, b) + hd::fused_dot(a, b);
        // Insertion into the nearest kLineVoters.
        if (voters == kLineVoters && !(e < nearest_e[kLineVoters - 1])) continue;
        int k = voters < kLineVoters ? voters++ : kLineVoters - 1;  // the last place, or the farthest voter's
        for (; k > 0 && e < nearest_e[k - 1]; --k) {
          nearest_e[k] = nearest_e[k - 1];
          voter_sample[k] = voter_sample[k - 1];
          voter_cell[k] = voter_cell[k - 1];
          voter_far[k] = voter_far[k - 1];
        }
        nearest_e[k] = e;
        voter_sample[k] = sample;
        voter_cell[k] = cell;
        voter_far[k] = end == 1;
      }
  }
  const float floor = 1e-12f * f.radius * f.radius;  // an exact line's weight stays finite
  const float chord_over_diameter = chord * inverse_diameter(f);
  // Every voter decides hit or miss; the distance (and normal) is the entry end's voters' where one hit:
  // a far end's read sees the last surface along the chord, not the first.
  FieldVote vote, entry_end;
  for (int k = 0; k < voters; ++k) {
    FieldAnswer a = read_cell(f, voter_sample[k], voter_cell[k] % n, voter_cell[k] / n);
    const float weight = 1.0f / hd::sqrt(nearest_e[k] + floor);
    if (voter_far[k]) {
      if (a.hit) a.t = hd::max(0.0f, chord_over_diameter - a.t);
    } else {
      entry_end.add(weight, a);
    }
    vote.add(weight, a);
  }
  FieldAnswer answer = vote.result();
  if (answer.hit && entry_end.hit_weight > 0.0f) {
    answer = entry_end.heaviest_hit;
    answer.t = entry_end.distance / entry_end.hit_weight;
  }
  return answer;
}

/// The answer for visit `v`: at the heaviest corner of v.point's lattice triangle (nearly always the
/// nearest sample), the blend of the three corners, or from outside the lines nearest to the ray's chord.
VF_HOST_DEVICE inline FieldAnswer read_at(const FieldTables& f, const SphereVisit& v) {
  if (f.position_lookup == PositionLookup::lines && !v.inside) return read_lines(f, v);
  if (f.position_lookup != PositionLookup::blend) return read_sample(f, v, heaviest_corner_position(v.point, f.lattice_n));
  const PositionBlend<float> blend = blend_positions(v.point, f.lattice_n);
  FieldVote vote;
  for (int k = 0; k < 3; ++k)
    if (blend.weight[k] > 0.0f) vote.add(blend.weight[k], read_sample(f, v, blend.index[k]));
  return vote.result();
}

/// The first half of trace_field(): false when the ray cannot meet the sphere ahead of its origin.
VF_HOST_DEVICE inline bool sphere_visit(const FieldTables& f, const hd::Vec3<float>& org, const hd::Vec3<float>& dir, float tmin, float tmax,
                                        SphereVisit& v) {
  const float len = hd::sqrt(hd::fused_dot(dir, dir));
  v.inv = 1.0f / len;
  const hd::Vec3<float> d{dir.x * v.inv, dir.y * v.inv, dir.z * v.inv};
  v.s_min = tmin * len, v.s_max = tmax * len;
  const hd::Vec3<float> oc{org.x - f.centre.x, org.y - f.centre.y, org.z - f.centre.z};
  const float b = hd::fused_dot(oc, d), c = hd::fused_dot(oc, oc) - f.radius * f.radius;
  const float disc = hd::fma(b, b, -c);
  if (!(disc >= 0.0f)) return false;
  const float root = hd::sqrt(disc);
  v.s_enter = -b - root, v.s_exit = -b + root;
  v.inside = !(c > 0.0f);
  if (!v.inside && v.s_enter < 0.0f) return false;
  const float s_at = v.inside ? v.s_exit : v.s_enter;
  hd::Vec3<float> e{hd::fma(d.x, s_at, oc.x), hd::fma(d.y, s_at, oc.y), hd::fma(d.z, s_at, oc.z)};
  // The point on the sphere as a unit vector: from inside, |e| is R to rounding, so a product by
  // 1/R will do; from outside, far origins cancel digits in e, and its own length is needed.
  const float e_inv = v.inside ? 1.0f / f.radius : 1.0f / hd::sqrt(hd::fused_dot(e, e));
  v.point = {e.x * e_inv, e.y * e_inv, e.z * e_inv};
  v.read = v.inside ? hd::Vec3<float>{-d.x, -d.y, -d.z} : d;
  v.far = v.inside ? oc : hd::Vec3<float>{hd::fma(d.x, v.s_exit, oc.x), hd::fma(d.y, v.s_exit, oc.y), hd::fma(d.z, v.s_exit, oc.z)};
  return true;
}

/// The second half of trace_field(): the table's answer `a` placed along the ray, held to its range
/// (and, from inside, beyond the start surface).
VF_HOST_DEVICE inline FieldAnswer place_answer(const FieldTables& f, const SphereVisit& v, FieldAnswer a) {
  if (!a.hit) return {};
  const float diameter = 2.0f * f.radius;
  const float s_hit = v.inside ? hd::fma(-a.t, diameter, v.s_exit) : hd::fma(a.t, diameter, v.s_enter);
  if (v.inside && !(s_hit > f.self_offset * diameter)) return {};
  if (!(s_hit >= v.s_min && s_hit <= v.s_max)) return {};
  a.t = s_hit * v.inv;
  return a;
}

/// The field's answer for the object-space ray org + t·dir, t in [tmin, tmax] (dir non-zero, any
/// length; t in its units). O(1) whatever the mesh.
VF_HOST_DEVICE inline FieldAnswer trace_field(const FieldTables& f, const hd::Vec3<float>& org, const hd::Vec3<float>& dir, float tmin,
                                              float tmax) {
  SphereVisit v;
  if (!sphere_visit(f, org, dir, tmin, tmax, v)) return {};
  return place_answer(f, v, read_at(f, v));
}

}  // namespace vf::field
