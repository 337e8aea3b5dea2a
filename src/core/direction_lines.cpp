#include "visfield/core/direction_lines.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/core/octahedral_lattice.hpp"
#include "visfield/core/orthonormal_basis.hpp"

namespace vf {
namespace {

using Vec3d = std::array<double, 3>;

double dot3(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

Vec3d lattice_direction(int i, int j, int n) {
  const hd::Vec3<double> w = octa::point_direction<double>(i, j, n);
  return {w.x, w.y, w.z};
}

// The PSF frame of unit direction w (w.z >= 0): the minimal rotation taking +z to w applied to +x
// and +y (the branchless basis of Duff et al. 2017), computed in double and rounded once.
PsfFrame frame_of(const Vec3d& w) {
  const OrthonormalBasis<double> basis = orthonormal_basis(hd::Vec3<double>{w[0], w[1], w[2]});
  const auto f = [](const hd::Vec3<double>& c) {
    return Vec3f{static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
  };
  return {f(basis.u), f(basis.v), f(basis.w)};
}

// Hash of a direction's bits for the stored-direction table.
std::size_t direction_hash(const Vec3f& d) {
  const auto bits = [](float x) { return static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(x)); };
  const std::uint64_t h = bits(d.x) * 0x9E3779B97F4A7C15ull ^ bits(d.y) * 0xC2B2AE3D27D4EB4Full ^ bits(d.z) * 0x165667B19E3779F9ull;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

bool same_bits(const Vec3f& a, const Vec3f& b) {
  return std::bit_cast<std::uint32_t>(a.x) == std::bit_cast<std::uint32_t>(b.x) &&
         std::bit_cast<std::uint32_t>(a.y) == std::bit_cast<std::uint32_t>(b.y) &&
         std::bit_cast<std::uint32_t>(a.z) == std::bit_cast<std::uint32_t>(b.z);
}

}  // namespace

std::size_t DirectionLines::count(int level) {
  const std::size_t n = std::size_t{1} << level;
  return 2 * n * n + 1;
}

DirectionLines::DirectionLines(int level) : level_(level) {
  if (level < kMinLevel || level > kMaxLevel)
    throw Error("direction level " + std::to_string(level) + ": expected " + std::to_string(kMinLevel) + ".." +
                std::to_string(kMaxLevel) + " (" + std::to_string(count(kMinLevel)) + " to " +
                std::to_string(count(kMaxLevel)) + " lines)");
  n_ = 1 << level;
  const int n = n_;
  lattice_to_line_.assign(static_cast<std::size_t>(octa::point_count(n)), -1);
  precise_.reserve(count(level));
  for (int i = -n; i <= n; ++i) {
    const int span = n - std::abs(i);
    for (int j = -span; j <= span; ++j) {
      // On the equator keep one point of each antipodal pair: j > 0, or (n, 0).
      const bool equator = std::abs(i) + std::abs(j) == n;
      if (equator && !(j > 0 || (i == n && j == 0))) continue;
      lattice_to_line_[static_cast<std::size_t>(octa::point_index(i, j, n))] = static_cast<std::int32_t>(precise_.size());
      precise_.push_back(lattice_direction(i, j, n));
    }
  }
  directions_.reserve(precise_.size());
  frames_.reserve(precise_.size());
  for (const Vec3d& w : precise_) {
    directions_.push_back({static_cast<float>(w[0]), static_cast<float>(w[1]), static_cast<float>(w[2])});
    frames_.push_back(frame_of(w));
  }
  // Load factor at most 1/4: a probe sequence is short.
  std::size_t table_size = 1;
  while (table_size < 4 * directions_.size()) table_size *= 2;
  stored_table_.assign(table_size, -1);
  for (std::size_t line = 0; line < directions_.size(); ++line) {
    std::size_t slot = direction_hash(directions_[line]) & (table_size - 1);
    while (stored_table_[slot] >= 0) slot = (slot + 1) & (table_size - 1);
    stored_table_[slot] = static_cast<std::int32_t>(line);
  }
}

std::int32_t DirectionLines::stored_line(const Vec3f& d) const {
  const std::size_t mask = stored_table_.size() - 1;
  for (std::size_t slot = direction_hash(d) & mask;; slot = (slot + 1) & mask) {
    const std::int32_t line = stored_table_[slot];
    if (line < 0 || same_bits(directions_[static_cast<std::size_t>(line)], d)) return line;
  }
}

std::int32_t DirectionLines::line_at(int i, int j) const { return lattice_to_line_[static_cast<std::size_t>(octa::point_index(i, j, n_))]; }

NearestLine DirectionLines::nearest(const Vec3f& direction) const {
  // A stored direction is its own nearest line (AO along the lines asks for nothing else).
  if (const std::int32_t line = stored_line(direction); line >= 0) return {static_cast<std::uint32_t>(line), 1};
  if (const std::int32_t line = stored_line(-direction); line >= 0) return {static_cast<std::uint32_t>(line), -1};
  const int n = n_;
  Vec3d d{direction.x, direction.y, direction.z};
  const double norm = std::sqrt(dot3(d, d));
  for (double& c : d) c /= norm;
  // Canonicalise to the upper hemisphere; on the equator, to the kept half (y > 0, or +x).
  const bool upper = d[2] > 0.0 || (d[2] == 0.0 && (d[1] > 0.0 || (d[1] == 0.0 && d[0] > 0.0)));
  const double s0 = upper ? 1.0 : -1.0;
  for (double& c : d) c *= s0;

  double a, b;
  octa::coordinates(hd::Vec3<double>{d[0], d[1], d[2]}, n, a, b);
  const octa::Triangle<double> triangle = octa::containing_triangle(a, b, n);

  // The corner nearest to d (outside the diamond only at the rim: skipped). A dropped equator
  // point stands for its antipode, the line's other end.
  double best = -2.0;
  NearestLine result;
  for (int k = 0; k < 3; ++k) {
    const int i = triangle.i[k], j = triangle.j[k];
    if (std::abs(i) + std::abs(j) > n) continue;
    std::int32_t line = line_at(i, j);
    double sign = s0;
    if (line < 0) {
      line = line_at(-i, -j);
      sign = -s0;
    }
    // d'·ω(i, j), where a dropped point's ω(i, j) is minus its line's direction.
    const double c = sign * s0 * dot3(d, precise_[static_cast<std::size_t>(line)]);
    if (c > best) {
      best = c;
      result = {static_cast<std::uint32_t>(line), static_cast<int>(sign)};
    }
  }
  return result;
}

}  // namespace vf
