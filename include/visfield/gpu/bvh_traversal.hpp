#pragma once
/// \file Closest hit and any hit through the GPU BVH layout (bvh_layout.hpp), written once for host
/// and device (no STL, no exceptions): a fixed-size stack, children visited near to far for closest
/// hits and in slot order for any hit, as the CPU Bvh's walks do. Boxes are tested as the CPU's
/// conservative test does (src/accel/bvh/box_test.hpp: far distances scaled by 1 + 2^-16, the ray's
/// interval widened by 2^-16, NaN slabs ignored) on decoded boxes that contain the CPU's padded
/// boxes, and leaves run the one watertight test (core/triangle_intersect.hpp) with the CPU's
/// tie-break (equal t: the lowest TriangleSet index). So the answers are BruteForce's: the same t,
/// u, v, triangle, object and normal (tests/unit/gpu checks it on the host; tests/cuda on a GPU).

#include "visfield/core/host_device.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/triangle_intersect.hpp"
#include "visfield/gpu/bvh_layout.hpp"

namespace vf::gpu {

/// No traversal stack holds more entries than this: 7 pushes per 8-wide level, and no leaf is
/// deeper than the CPU builder's 64 binary levels. The host queries use it; kernels use the smallest
/// of kStackCapacities that holds the tree's BvhView::stack_bound, so that a thread reserves local
/// memory for the stack its tree needs, not for the worst tree.
inline constexpr int kStackSize = 7 * 64 + 1;
/// The stack capacities kernels are compiled for, smallest first (the last is kStackSize): field-only
/// scenes and small rooms need 16 at most, the scanned models 37-48, sponza 62, conference 82.
inline constexpr int kStackCapacities[] = {16, 64, 128, kStackSize};

/// The smallest of kStackCapacities that holds `bound` entries (host: the kernels' launch picks it).
inline int stack_capacity_for(unsigned int bound) {
  for (const int c : kStackCapacities)
    if (bound <= static_cast<unsigned int>(c)) return c;
  return kStackSize;
}

/// Relative widening of the ray's interval and of far slab distances (box_test.hpp's constants).
inline constexpr float kIntervalSlack = 0x1p-16f;
inline constexpr float kFarScale = 1.0f + 0x1p-16f;
inline constexpr float kFarScaleBehind = 1.0f - 0x1p-16f;

/// A far slab distance moved up by the relative slack, below zero as above (box_test.hpp).
VF_HOST_DEVICE inline float scale_far(float t) { return t < 0.0f ? t * kFarScaleBehind : t * kFarScale; }

/// t moved down by the relative slack (infinities unchanged); box_test.hpp's widen_down.
VF_HOST_DEVICE inline float widen_down(float t) { return t - t == 0.0f ? t - hd::abs(t) * kIntervalSlack : t; }
/// t moved up by the relative slack (infinities unchanged); box_test.hpp's widen_up.
VF_HOST_DEVICE inline float widen_up(float t) { return t - t == 0.0f ? t + hd::abs(t) * kIntervalSlack : t; }

/// Per-ray constants of the box test: the origin and the reciprocal direction (±inf for ±0), and
/// whether each component is negative (then the near plane is the box's upper one).
struct BoxRay {
  float org[3], inv[3];
  bool negative[3];

  VF_HOST_DEVICE explicit BoxRay(const Ray& ray) {
    const float d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
    const float o[3] = {ray.org.x, ray.org.y, ray.org.z};
    for (int a = 0; a < 3; ++a) {
      org[a] = o[a];
      inv[a] = 1.0f / d[a];
      // NaN where a non-zero component's reciprocal overflows (box_test.hpp's box_reciprocal).
      if (d[a] != 0.0f && hd::abs(inv[a]) == INFINITY) inv[a] = hd::copysign(NAN, d[a]);
      negative[a] = hd::copysign(1.0f, d[a]) < 0.0f;
    }
  }
};

/// x86 maxps: a > b ? a : b, so the running value b survives a NaN slab (box_test.hpp).
VF_HOST_DEVICE inline float max_nan_second(float a, float b) { return a > b ? a : b; }
/// x86 minps: a < b ? a : b.
VF_HOST_DEVICE inline float min_nan_second(float a, float b) { return a < b ? a : b; }

/// Whether child `slot` of `node` meets [tmin, tmax] (already widened); its entry distance to `t_near`.
VF_HOST_DEVICE inline bool child_hit(const WideNode& node, int slot, const BoxRay& r, float tmin, float tmax, float& t_near) {
  float near_t = tmin, far_t = tmax;
  VF_UNROLL
  for (int a = 2; a >= 0; --a) {
    const float scale = exponent_scale(node.exponent[a]);
    const float lo = decode(node.origin[a], node.lo[a][slot], scale);
    const float hi = decode(node.origin[a], node.hi[a][slot], scale);
    const float n = ((r.negative[a] ? hi : lo) - r.org[a]) * r.inv[a];
    const float f = ((r.negative[a] ? lo : hi) - r.org[a]) * r.inv[a];
    // z first, then y, then x: the CPU's max(nx, max(ny, max(nz, tmin))).
    near_t = max_nan_second(n, near_t);
    far_t = min_nan_second(f, far_t);
  }
  t_near = near_t;
  return near_t <= scale_far(far_t);
}

/// Any triangle hit in (ray.tmin, ray.tmax]. O(log n) typical. `Capacity` (entries of the traversal
/// stack) must be at least bvh.stack_bound.
template <int Capacity = kStackSize>
VF_HOST_DEVICE inline bool occluded(const BvhView& bvh, const Ray& ray) {
  if (bvh.node_count == 0) return false;
  const BoxRay box(ray);
  const WatertightRay wray(ray);
  const float box_tmin = widen_down(ray.tmin), box_tmax = widen_up(ray.tmax);
  unsigned int stack[Capacity];
  int sp = 0;
  unsigned int ref = 0;
  for (;;) {
    if (ref & kLeafBit) {
      const unsigned int first = ref & ((1u << 27) - 1u), end = first + ((ref >> 27) & 15u) + 1u;
      for (unsigned int k = first; k < end; ++k) {
        const WideTriangle tri = load_triangle(bvh.triangles, k);
        TriangleHit h;
        if (intersect_triangle(wray, Vec3f{tri.p0[0], tri.p0[1], tri.p0[2]}, Vec3f{tri.p1[0], tri.p1[1], tri.p1[2]},
                               Vec3f{tri.p2[0], tri.p2[1], tri.p2[2]}, ray.tmin, ray.tmax, h))
          return true;
      }
    } else {
      const WideNode node = load_node(bvh.nodes, ref);
      unsigned int next = 0;
      bool found = false;
      VF_UNROLL
      for (int slot = 0; slot < 8; ++slot) {
        const unsigned char meta = node.meta[slot];
        if (meta == kEmptySlot) continue;
        float t_near;
        if (!child_hit(node, slot, box, box_tmin, box_tmax, t_near)) continue;
        const unsigned int child = (node.interior >> slot) & 1u
                                       ? node.child_base + meta
                                       : leaf_reference(node.triangle_base + (meta & 31u), (meta >> 5) + 1u);
        // The first child is walked now, the others pushed in slot order (the CPU's descend_and_push).
        if (!found) {
          next = child;
          found = true;
        } else {
          stack[sp++] = child;
        }
      }
      if (found) {
        ref = next;
        continue;
      }
    }
    if (sp == 0) return false;
    ref = stack[--sp];
  }
}

/// The triangle of leaf reference `ref` that the leaves' closest test keeps: tests each against
/// [tmin, best_t] and keeps a nearer hit, or an equally near one of a lower TriangleSet index.
struct ClosestLeafHit {
  float t, u, v;
  unsigned int index = 0xffffffffu;  ///< TriangleSet index; 0xffffffff: none yet.
  unsigned int slot = 0;             ///< Its position in the flat triangle array.
};

/// Tests the triangles of leaf `ref` against [tmin, best.t]; true when one improved `best`.
VF_HOST_DEVICE inline bool closest_in_leaf(const BvhView& bvh, unsigned int ref, const WatertightRay& wray, float tmin,
                                           ClosestLeafHit& best) {
  const unsigned int first = ref & ((1u << 27) - 1u), end = first + ((ref >> 27) & 15u) + 1u;
  bool improved = false;
  for (unsigned int k = first; k < end; ++k) {
    const WideTriangle tri = load_triangle(bvh.triangles, k);
    TriangleHit h;
    if (!intersect_triangle(wray, Vec3f{tri.p0[0], tri.p0[1], tri.p0[2]}, Vec3f{tri.p1[0], tri.p1[1], tri.p1[2]},
                            Vec3f{tri.p2[0], tri.p2[1], tri.p2[2]}, tmin, best.t, h))
      continue;
    if (h.t < best.t || tri.index < best.index) {  // h.t <= best.t here: equal t goes to the lower index
      best.t = h.t;
      best.u = h.u;
      best.v = h.v;
      best.index = tri.index;
      best.slot = k;
      improved = true;
    }
  }
  return improved;
}

/// Closest hit in (ray.tmin, ray.tmax]: BruteForce's answer (t, u, v, prim, instance and the
/// triangle's geometric normal cross(p1 − p0, p2 − p0)), or a miss. O(log n) typical. `Capacity`
/// must be at least bvh.stack_bound.
template <int Capacity = kStackSize>
VF_HOST_DEVICE inline Hit intersect(const BvhView& bvh, const Ray& ray) {
  if (bvh.node_count == 0) return Hit{};
  struct Entry {
    unsigned int ref;
    float t_near;
  };
  const BoxRay box(ray);
  const WatertightRay wray(ray);
  const float box_tmin = widen_down(ray.tmin);
  ClosestLeafHit best;
  best.t = ray.tmax;
  best.u = best.v = 0.0f;
  float cull_t = widen_up(ray.tmax);
  Entry stack[Capacity];
  int sp = 0;
  unsigned int ref = 0;
  for (;;) {
    if (!(ref & kLeafBit)) {
      const WideNode node = load_node(bvh.nodes, ref);
      Entry hits[8];
      int count = 0;
      VF_UNROLL
      for (int slot = 0; slot < 8; ++slot) {
        const unsigned char meta = node.meta[slot];
        if (meta == kEmptySlot) continue;
        float t_near;
        if (!child_hit(node, slot, box, box_tmin, cull_t, t_near)) continue;
        const unsigned int child = (node.interior >> slot) & 1u
                                       ? node.child_base + meta
                                       : leaf_reference(node.triangle_base + (meta & 31u), (meta >> 5) + 1u);
        // Insertion by entry distance, ties in slot order (the CPU's stable sort).
        int j = count++;
        for (; j > 0 && hits[j - 1].t_near > t_near; --j) hits[j] = hits[j - 1];
        hits[j] = Entry{child, t_near};
      }
      if (count > 0) {
        for (int i = count - 1; i > 0; --i) stack[sp++] = hits[i];
        ref = hits[0].ref;
        continue;
      }
    } else if (closest_in_leaf(bvh, ref, wray, ray.tmin, best)) {
      cull_t = widen_up(best.t);
    }
    // The next subtree from the stack that can still hold a nearer hit.
    do {
      if (sp == 0) {
        if (best.index == 0xffffffffu) return Hit{};
        const WideTriangle tri = load_triangle(bvh.triangles, best.slot);
        const Vec3f p0{tri.p0[0], tri.p0[1], tri.p0[2]};
        const Vec3f normal = cross(Vec3f{tri.p1[0], tri.p1[1], tri.p1[2]} - p0, Vec3f{tri.p2[0], tri.p2[1], tri.p2[2]} - p0);
        return Hit::triangle(best.t, best.u, best.v, bvh.prim[best.index], bvh.instance[best.index], normal);
      }
      --sp;
    } while (stack[sp].t_near > cull_t);
    ref = stack[sp].ref;
  }
}

}  // namespace vf::gpu
