#pragma once
/// \file The octahedral line set of BeamField (VLF-RT): 2n²+1 directions over the upper hemisphere
/// (n = 2^level; 33, 129, 513, 2049, 8193 for levels 2–6), each standing for a line (both
/// orientations), with the O(1) nearest-line lookup and one parallel-subfield (PSF) frame per line.
///
/// Construction: the lattice {(i, j) : |i| + |j| <= n} on the four upper octahedron faces, mapped to
/// the sphere by the equal-area diamond map (ω = (sgn u cos φ r√(2−r²), sgn v sin φ r√(2−r²), 1 − r²)
/// with u = i/n, v = j/n, r = |u| + |v|, φ = (π/2)|v|/r), which is the most uniform of the usual
/// choices (largest / smallest cell solid angle 1.83 at n = 64). Of each antipodal pair on the
/// equator only the point with j > 0, or (n, 0), is kept. The lookup inverts the map to lattice
/// coordinates, finds the lattice triangle containing the direction and returns the vertex of that
/// triangle nearest to it, which is the nearest line of the whole set (checked against brute force in
/// the tests). Worst angle between a direction and its line: 8.82°, 4.47°, 2.26°, 1.15° for levels
/// 3–6 (about 73.5°/n).

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "visfield/core/vec.hpp"

namespace vf {

/// Orthonormal frame of one line: rows u, v and the line's direction w = u × v. Maps a point p to
/// PSF coordinates (dot(u, p), dot(v, p), dot(w, p)): beam position (s, t) and depth along w.
struct PsfFrame {
  Vec3f u, v, w;
};

/// The nearest line to a direction, and which way along it the direction points.
struct NearestLine {
  std::uint32_t line = 0;  ///< Index in [0, size()).
  int sign = 1;            ///< +1 when the direction is within 90° of direction(line), else −1.
};

/// The line set of one level. Immutable after construction; thread-safe; O(n²) memory
/// (about 80 bytes per line).
class DirectionLines {
 public:
  static constexpr int kMinLevel = 2;  ///< 33 lines
  static constexpr int kMaxLevel = 6;  ///< 8193 lines

  /// The set of `level` (n = 2^level); throws vf::Error outside [kMinLevel, kMaxLevel]. O(n²).
  explicit DirectionLines(int level);

  /// The level given at construction.
  int level() const { return level_; }
  /// n = 2^level, the lattice's half-width.
  int lattice_size() const { return n_; }
  /// Number of lines, 2n² + 1.
  std::size_t size() const { return directions_.size(); }
  /// Unit direction of `line` (z >= 0), rounded to float: what structures store and project along.
  const Vec3f& direction(std::size_t line) const { return directions_[line]; }
  /// The same direction in double precision, as the lookup compares it.
  const std::array<double, 3>& direction_precise(std::size_t line) const { return precise_[line]; }
  /// The PSF frame of `line`, computed once from its stored direction (so build and query agree bit
  /// for bit): the minimal rotation taking +z to the direction, applied to +x and +y.
  const PsfFrame& frame(std::size_t line) const { return frames_[line]; }

  /// The line nearest to `d` (any non-zero length; the larger |cos| wins) and the orientation of `d`
  /// along it. O(1): a few arithmetic operations and three dot products, or, when `d` is a stored
  /// direction or its negation bit for bit (AO along the lines), one hash probe or two. `d` must be
  /// finite and non-zero.
  NearestLine nearest(const Vec3f& d) const;

  /// Number of lines of `level` without building the set: 2·4^level + 1.
  static std::size_t count(int level);

 private:
  // Line index of lattice point (i, j), or -1 for a dropped equator point.
  std::int32_t line_at(int i, int j) const;
  // The line whose stored direction is bit for bit `d`, or -1.
  std::int32_t stored_line(const Vec3f& d) const;

  int level_ = 0;
  int n_ = 0;
  std::vector<std::int32_t> lattice_to_line_;  // dense over the 2n²+2n+1 lattice points
  std::vector<std::array<double, 3>> precise_;
  std::vector<Vec3f> directions_;
  std::vector<PsfFrame> frames_;
  std::vector<std::int32_t> stored_table_;  // open addressing over the stored directions' bits: line, or -1
};

}  // namespace vf
