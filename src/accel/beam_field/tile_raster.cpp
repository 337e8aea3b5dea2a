#include "beam_field/tile_raster.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vf::beam {
namespace {

// A separating-axis line: the closed half-plane dot(normal, x − origin) >= 0 holds the shape.
struct Edge {
  Point2 origin;
  double ns = 0.0, nt = 0.0;  // normal, not normalised
};

// Largest dot(normal, corner − origin) over the corners of the square centred at (cs, ct) with
// half-side h: the square's most inward point for this edge.
double deepest(const Edge& e, double cs, double ct, double h) {
  return e.ns * (cs - e.origin.s) + e.nt * (ct - e.origin.t) + h * (std::fabs(e.ns) + std::fabs(e.nt));
}

}  // namespace

void rasterize_triangle(const TileGrid& grid, Point2 a, Point2 b, Point2 c, double slack, std::vector<std::uint32_t>& tiles) {
  const double lo_s = std::min({a.s, b.s, c.s}) - slack, hi_s = std::max({a.s, b.s, c.s}) + slack;
  const double lo_t = std::min({a.t, b.t, c.t}) - slack, hi_t = std::max({a.t, b.t, c.t}) + slack;
  // Tiles of the bounding box, one more on each side (a box edge on a tile border touches both
  // tiles, and the division rounds); each tile is then tested exactly.
  const auto index = [&](double v, double lo) { return std::floor((v - lo) / grid.size); };
  const double last = grid.n - 1;
  const int x0 = static_cast<int>(std::clamp(index(lo_s, grid.lo_s) - 1.0, 0.0, last + 1.0));
  const int x1 = static_cast<int>(std::clamp(index(hi_s, grid.lo_s) + 1.0, -1.0, last));
  const int y0 = static_cast<int>(std::clamp(index(lo_t, grid.lo_t) - 1.0, 0.0, last + 1.0));
  const int y1 = static_cast<int>(std::clamp(index(hi_t, grid.lo_t) + 1.0, -1.0, last));
  if (x0 > x1 || y0 > y1) return;

  // Separating axes besides the tile's own (the bounding box): the triangle's edges with inward
  // normals. Each edge's inside is the side of the opposite corner; when the three disagree or one
  // is zero the triangle is seen edge-on (or rounding cannot tell): then it is its longest edge,
  // with both sides of that edge as axes and a margin for the rounding.
  const Point2 corners[3] = {a, b, c};
  Edge edges[3];
  double margin[3] = {slack, slack, slack};
  int edge_count = 0;
  double side[3];
  for (int i = 0; i < 3; ++i) {
    const Point2 p = corners[i], q = corners[(i + 1) % 3], r = corners[(i + 2) % 3];
    edges[i] = {p, -(q.t - p.t), q.s - p.s};
    side[i] = edges[i].ns * (r.s - p.s) + edges[i].nt * (r.t - p.t);
  }
  if ((side[0] > 0.0 && side[1] > 0.0 && side[2] > 0.0) || (side[0] < 0.0 && side[1] < 0.0 && side[2] < 0.0)) {
    for (int i = 0; i < 3; ++i)
      if (side[i] < 0.0) edges[i].ns = -edges[i].ns, edges[i].nt = -edges[i].nt;
    edge_count = 3;
  } else {
    int longest = 0;
    const auto length2 = [](const Edge& e) { return e.ns * e.ns + e.nt * e.nt; };
    for (int i = 1; i < 3; ++i)
      if (length2(edges[i]) > length2(edges[longest])) longest = i;
    if (length2(edges[longest]) > 0.0) {
      const double scale = std::max({std::fabs(lo_s), std::fabs(hi_s), std::fabs(lo_t), std::fabs(hi_t), grid.size});
      edges[0] = edges[longest];
      edges[1] = {edges[0].origin, -edges[0].ns, -edges[0].nt};
      margin[0] = margin[1] = slack + 1e-12 * scale;
      edge_count = 2;
    }
  }
  double limit[3];
  for (int i = 0; i < edge_count; ++i) limit[i] = -margin[i] * std::hypot(edges[i].ns, edges[i].nt);

  const double h = 0.5 * grid.size;
  for (int y = y0; y <= y1; ++y) {
    const double ct = grid.lo_t + (y + 0.5) * grid.size;
    if (ct + h < lo_t || ct - h > hi_t) continue;
    for (int x = x0; x <= x1; ++x) {
      const double cs = grid.lo_s + (x + 0.5) * grid.size;
      if (cs + h < lo_s || cs - h > hi_s) continue;
      bool separated = false;
      for (int i = 0; i < edge_count && !separated; ++i) separated = deepest(edges[i], cs, ct, h) < limit[i];
      if (!separated) tiles.push_back(static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(grid.n) + static_cast<std::uint32_t>(x));
    }
  }
}

void rasterize_triangle_rows(const TileGrid& grid, Point2 a, Point2 b, Point2 c, double slack, std::vector<std::uint32_t>& tiles) {
  // In tile units: tile (x, y) is the closed square [x, x + 1] x [y, y + 1].
  const double inv = 1.0 / grid.size, e = slack * inv;
  const Point2 p[3] = {{(a.s - grid.lo_s) * inv, (a.t - grid.lo_t) * inv},
                       {(b.s - grid.lo_s) * inv, (b.t - grid.lo_t) * inv},
                       {(c.s - grid.lo_s) * inv, (c.t - grid.lo_t) * inv}};
  const double lo_t = std::min({p[0].t, p[1].t, p[2].t}) - e, hi_t = std::max({p[0].t, p[1].t, p[2].t}) + e;
  const double last = grid.n - 1;
  const int y0 = static_cast<int>(std::clamp(std::ceil(lo_t) - 1.0, 0.0, last + 1.0));
  const int y1 = static_cast<int>(std::clamp(std::floor(hi_t), -1.0, last));
  const double scale = std::max({1.0, std::fabs(p[0].s), std::fabs(p[1].s), std::fabs(p[2].s), std::fabs(lo_t), std::fabs(hi_t)});
  const double margin = 1e-12 * scale;
  for (int y = y0; y <= y1; ++y) {
    // The s extent of the triangle within the row's strip (widened by the slack): a convex set whose
    // extreme points lie on its edges, so the extents of the three edges clipped to the strip.
    const double strip_lo = y - e, strip_hi = y + 1 + e;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i = 0; i < 3; ++i) {
      const Point2 u = p[i], v = p[(i + 1) % 3];
      if (u.t == v.t) {
        if (u.t < strip_lo || u.t > strip_hi) continue;
        lo = std::min({lo, u.s, v.s}), hi = std::max({hi, u.s, v.s});
        continue;
      }
      const double rate = (v.s - u.s) / (v.t - u.t);
      const double ta = std::max(strip_lo, std::min(u.t, v.t)), tb = std::min(strip_hi, std::max(u.t, v.t));
      if (ta > tb) continue;
      const double sa = u.s + (ta - u.t) * rate, sb = u.s + (tb - u.t) * rate;
      lo = std::min({lo, sa, sb}), hi = std::max({hi, sa, sb});
    }
    if (lo > hi) continue;
    const int x0 = static_cast<int>(std::clamp(std::ceil(lo - e - margin) - 1.0, 0.0, last + 1.0));
    const int x1 = static_cast<int>(std::clamp(std::floor(hi + e + margin), -1.0, last));
    for (int x = x0; x <= x1; ++x) tiles.push_back(static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(grid.n) + static_cast<std::uint32_t>(x));
  }
}

}  // namespace vf::beam
