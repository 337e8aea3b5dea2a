#include "kdtree/sah_events.hpp"

#include <algorithm>

#include <tbb/blocked_range.h>

#include "kdtree/flat_tree.hpp"
#include "kdtree/kd_nodes.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::kd {
namespace {

/// Runs f(axis) for the three axes, as parallel tasks when the node is large.
template <class F>
void for_each_axis(std::size_t node_size, F&& f) {
  if (node_size >= kParallelSubtreeSize)
    vf::parallel_for(0, 3, [&](int axis) { f(axis); });
  else
    for (int axis = 0; axis < 3; ++axis) f(axis);
}

/// check_interrupt() on every 65536th `i`: the loops over a large node's events run for a good
/// part of a second at the root of a big scene, too long to leave a signal unanswered.
inline void poll_interrupt(std::size_t i) {
  if ((i & 0xFFFF) == 0) check_interrupt();
}

/// The cheapest plane on one axis (sweep of Wald & Havran, section 4.2).
SplitPlane sweep_axis(const SahNode& node, int axis, const KdTreeConfig& config) {
  const std::vector<Event>& events = node.events[axis];
  const std::size_t total = node.size();
  std::size_t below = 0, above = total;
  const SplitCost cost_of(node.box, axis, total, config);
  SplitPlane best;
  for (std::size_t i = 0, planes = 0; i < events.size(); ++planes) {
    poll_interrupt(planes);
    const float p = events[i].position;
    std::size_t ends = 0, planars = 0, starts = 0;
    for (; i < events.size() && events[i].position == p && events[i].type() == EventType::end; ++i) ++ends;
    for (; i < events.size() && events[i].position == p && events[i].type() == EventType::planar; ++i) ++planars;
    for (; i < events.size() && events[i].position == p && events[i].type() == EventType::start; ++i) ++starts;
    // Triangles ending at p or lying in p no longer reach above it.
    above -= planars + ends;
    const double planar_below = cost_of(p, below + planars, above);
    const double planar_above = planars == 0 ? planar_below : cost_of(p, below, above + planars);
    const bool go_below = planar_below <= planar_above;
    const double cost = go_below ? planar_below : planar_above;
    if (cost < best.cost) best = {axis, p, go_below, cost};
    // Triangles starting at p or lying in p reach below every later plane.
    below += starts + planars;
  }
  return best;
}

/// `filtered` (sorted) merged with `added` (sorted here).
std::vector<Event> merge_events(std::vector<Event>&& filtered, std::vector<Event>&& added) {
  if (added.empty()) return std::move(filtered);
  std::sort(added.begin(), added.end());
  std::vector<Event> merged(filtered.size() + added.size());
  std::merge(filtered.begin(), filtered.end(), added.begin(), added.end(), merged.begin());
  return merged;
}

}  // namespace

SplitCost::SplitCost(const Bounds3f& box, int axis, std::size_t total, const KdTreeConfig& config)
    : lo_(box.lo[axis]), hi_(box.hi[axis]), total_(total), traversal_(config.traversal_cost),
      intersection_(config.intersection_cost), empty_bonus_(config.empty_bonus) {
  const double e1 = static_cast<double>(box.hi[(axis + 1) % 3]) - box.lo[(axis + 1) % 3];
  const double e2 = static_cast<double>(box.hi[(axis + 2) % 3]) - box.lo[(axis + 2) % 3];
  cross_ = e1 * e2;
  perimeter_ = e1 + e2;
  const double area = (hi_ - lo_) * perimeter_ + cross_;
  inverse_area_ = area > 0.0 ? 1.0 / area : 0.0;
}

double SplitCost::operator()(float position, std::size_t below, std::size_t above) const {
  if (inverse_area_ == 0.0 || (below == total_ && position >= hi_) || (above == total_ && position <= lo_))
    return std::numeric_limits<double>::infinity();
  // Half surface areas of the children: length along the axis times the perimeter, plus the face.
  const double p_below = ((position - lo_) * perimeter_ + cross_) * inverse_area_;
  const double p_above = ((hi_ - position) * perimeter_ + cross_) * inverse_area_;
  double cost = traversal_ + intersection_ * (p_below * static_cast<double>(block_count(static_cast<std::uint32_t>(below))) +
                                             p_above * static_cast<double>(block_count(static_cast<std::uint32_t>(above))));
  if (below == 0 || above == 0) cost *= empty_bonus_;
  return cost;
}

void add_axis_events(const Bounds3f& b, int axis, std::uint32_t local_triangle, std::vector<Event>& events) {
  if (b.lo[axis] == b.hi[axis]) {
    events.push_back(Event::make(b.lo[axis], EventType::planar, local_triangle));
  } else {
    events.push_back(Event::make(b.lo[axis], EventType::start, local_triangle));
    events.push_back(Event::make(b.hi[axis], EventType::end, local_triangle));
  }
}

SahNode make_root(const TriangleSet& set) {
  SahNode root;
  root.box = set.bounds;
  const std::size_t n = set.size();
  root.triangles.resize(n);
  for (std::size_t i = 0; i < n; ++i) root.triangles[i] = static_cast<std::uint32_t>(i);
  for (std::vector<Event>& e : root.events) e.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    Bounds3f b;
    for (const Vec3f& p : set.triangles[i]) b.extend(p);
    for (int axis = 0; axis < 3; ++axis) add_axis_events(b, axis, static_cast<std::uint32_t>(i), root.events[axis]);
  }
  // (position, key) is unique per event, so the parallel sort's order is the only possible one.
  for_each_axis(n, [&](int axis) { vf::parallel_sort(root.events[axis].begin(), root.events[axis].end()); });
  return root;
}

SplitPlane find_best_split(const SahNode& node, const KdTreeConfig& config) {
  std::array<SplitPlane, 3> per_axis;
  for_each_axis(node.size(), [&](int axis) { per_axis[axis] = sweep_axis(node, axis, config); });
  SplitPlane best;
  for (const SplitPlane& candidate : per_axis)
    if (candidate.cost < best.cost) best = candidate;
  return best;
}

std::pair<SahNode, SahNode> split_node(SahNode&& node, const SplitPlane& plane, const TriangleSet& set) {
  const std::size_t n = node.size();
  std::vector<Side> side(n);
  {
    std::vector<float> lo(n), hi(n);  // bounds along the split axis, from its events
    for (const Event& e : node.events[plane.axis]) {
      poll_interrupt(e.triangle());
      if (e.type() != EventType::end) lo[e.triangle()] = e.position;
      if (e.type() != EventType::start) hi[e.triangle()] = e.position;
    }
    for (std::size_t t = 0; t < n; ++t) side[t] = side_of(lo[t], hi[t], plane.position, plane.planar_below);
  }

  SahNode below, above;
  below.box = node.box;
  below.box.hi[plane.axis] = plane.position;
  above.box = node.box;
  above.box.lo[plane.axis] = plane.position;
  // Child-local index of every triangle, and the slot of each one cut by the plane.
  std::vector<std::uint32_t> below_index(n), above_index(n), cut_slot(n);
  std::vector<std::uint32_t> cut;  // node-local indices of the triangles cut by the plane
  for (std::size_t t = 0; t < n; ++t) {
    poll_interrupt(t);
    if (side[t] != Side::above) {
      below_index[t] = static_cast<std::uint32_t>(below.triangles.size());
      below.triangles.push_back(node.triangles[t]);
    }
    if (side[t] != Side::below) {
      above_index[t] = static_cast<std::uint32_t>(above.triangles.size());
      above.triangles.push_back(node.triangles[t]);
    }
    if (side[t] == Side::both) {
      cut_slot[t] = static_cast<std::uint32_t>(cut.size());
      cut.push_back(static_cast<std::uint32_t>(t));
    }
  }

  // Events of one-sided triangles move to their child unchanged (the order is kept), while the
  // events of cut triangles give their bounds in this node.
  std::vector<Bounds3f> cut_bounds(cut.size());
  std::array<std::vector<Event>, 3> below_kept, above_kept;
  for_each_axis(n, [&](int axis) {
    const std::vector<Event>& events = node.events[axis];
    std::size_t below_count = 0, above_count = 0;
    for (const Event& e : events) {
      below_count += side[e.triangle()] == Side::below ? 1 : 0;
      above_count += side[e.triangle()] == Side::above ? 1 : 0;
    }
    below_kept[axis].reserve(below_count);
    above_kept[axis].reserve(above_count);
    for (const Event& e : events) {
      const std::uint32_t t = e.triangle();
      poll_interrupt(t);
      if (side[t] == Side::below) {
        below_kept[axis].push_back(Event::make(e.position, e.type(), below_index[t]));
      } else if (side[t] == Side::above) {
        above_kept[axis].push_back(Event::make(e.position, e.type(), above_index[t]));
      } else {
        Bounds3f& b = cut_bounds[cut_slot[t]];
        if (e.type() != EventType::end) b.lo[axis] = e.position;
        if (e.type() != EventType::start) b.hi[axis] = e.position;
      }
    }
    node.events[axis] = {};
  });
  node.triangles = {};

  // Perfect splits: the bounds of each cut triangle clipped to each child box.
  std::vector<Bounds3f> below_bounds(cut.size()), above_bounds(cut.size());
  const auto clip_range = [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c != end; ++c) {
      const std::array<Vec3f, 3>& triangle = set.triangles[below.triangles[below_index[cut[c]]]];
      below_bounds[c] = straddler_bounds(triangle, cut_bounds[c], below.box);
      above_bounds[c] = straddler_bounds(triangle, cut_bounds[c], above.box);
    }
  };
  if (cut.size() >= kParallelSubtreeSize)
    vf::parallel_for(tbb::blocked_range<std::size_t>(0, cut.size(), 256),
                      [&](const auto& range) { clip_range(range.begin(), range.end()); });
  else
    clip_range(0, cut.size());

  for_each_axis(n, [&](int axis) {
    std::vector<Event> below_added, above_added;
    below_added.reserve(2 * cut.size());
    above_added.reserve(2 * cut.size());
    for (std::size_t c = 0; c < cut.size(); ++c) {
      add_axis_events(below_bounds[c], axis, below_index[cut[c]], below_added);
      add_axis_events(above_bounds[c], axis, above_index[cut[c]], above_added);
    }
    below.events[axis] = merge_events(std::move(below_kept[axis]), std::move(below_added));
    above.events[axis] = merge_events(std::move(above_kept[axis]), std::move(above_added));
  });
  return {std::move(below), std::move(above)};
}

}  // namespace vf::kd
