#pragma once
/// \file The event lists of the O(N log N) SAH kd-tree build (Wald & Havran 2006): per node and
/// axis, the sorted start / end / planar events of its triangles' (clipped) bounds; the sweep that
/// finds the cheapest plane; and the split of a node's lists into its children's without sorting
/// again (only the new events of triangles cut by the plane are sorted, then merged).

#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "kdtree/split_rules.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::kd {

/// Event kinds, in the order events at one position are swept.
enum class EventType : std::uint32_t { end = 0, planar = 1, start = 2 };

/// One event: a position on the list's axis, its kind and the node-local triangle index, packed so
/// that (position, key) orders events by position, then kind, then triangle.
struct Event {
  float position;
  std::uint32_t key;  ///< kind << 30 | local triangle index

  static Event make(float position, EventType type, std::uint32_t triangle) {
    return {position, (static_cast<std::uint32_t>(type) << 30) | triangle};
  }
  EventType type() const { return static_cast<EventType>(key >> 30); }
  std::uint32_t triangle() const { return key & ((1u << 30) - 1); }
  friend bool operator<(const Event& a, const Event& b) {
    return a.position < b.position || (a.position == b.position && a.key < b.key);
  }
};

/// The input of one node: its box, its triangles (TriangleSet indices, ascending; the node-local
/// index of a triangle is its position here) and the sorted events of their bounds in the box.
struct SahNode {
  Bounds3f box;
  std::vector<std::uint32_t> triangles;
  std::array<std::vector<Event>, 3> events;

  std::size_t size() const { return triangles.size(); }
};

/// A candidate plane and its SAH cost (infinite when there is none).
struct SplitPlane {
  int axis = -1;
  float position = 0.0f;
  bool planar_below = true;  ///< Triangles lying in the plane go below (else above).
  double cost = std::numeric_limits<double>::infinity();
};

/// The SAH cost of the planes of one node along one axis: cutting `box` at `position` with `below`
/// and `above` of its `total` triangles on each side costs K_T + K_I (P_below block_count(below) +
/// P_above block_count(above)) (K_I per SIMD leaf block),
/// times empty_bonus when a side is empty, P = child surface area / node surface area. Infinite
/// when the cut makes no progress (a child equal to the box holding every triangle) or the box has
/// no area. O(1) per plane.
class SplitCost {
 public:
  SplitCost(const Bounds3f& box, int axis, std::size_t total, const KdTreeConfig& config);
  double operator()(float position, std::size_t below, std::size_t above) const;

 private:
  double lo_, hi_;                 // the box along the axis
  double cross_, perimeter_;       // product and sum of the two other extents
  double inverse_area_;            // 1 / half surface area of the box (0 when it has none)
  std::size_t total_;
  double traversal_, intersection_, empty_bonus_;
};

/// Events of a triangle with bounds `b` along `axis`: one planar event where b is flat, else a start
/// and an end event. Appends to `events`.
void add_axis_events(const Bounds3f& b, int axis, std::uint32_t local_triangle, std::vector<Event>& events);

/// The root node over every triangle of `set`, events sorted (in parallel).
SahNode make_root(const TriangleSet& set);

/// The cheapest plane of `node` by one sweep over each axis's events: O(events). Ties keep the
/// first candidate (axis x before y before z, lower position first, planar triangles below).
SplitPlane find_best_split(const SahNode& node, const KdTreeConfig& config);

/// Moves `node`'s triangles into its two children at `plane`: triangles crossing the plane are
/// clipped to each child box (perfect splits) and their new events sorted and merged into the
/// children's filtered lists. O(events + k log k) for k crossing triangles.
std::pair<SahNode, SahNode> split_node(SahNode&& node, const SplitPlane& plane, const TriangleSet& set);

}  // namespace vf::kd
