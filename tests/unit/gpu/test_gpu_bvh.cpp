// The GPU BVH layout traversed on the host by the device's own code (bvh_traversal.hpp) against the
// oracle: the same closest hit bit for bit (t, u, v, triangle, object, normal) and the same
// occlusion as BruteForce on random soups, coplanar sets, a shared-edge height field and the
// adversarial ray sets of the differential tests; on the shared models against BruteForce on a
// sample and the CPU Bvh (itself tested equal to BruteForce) on 100k rays. Also the layout's own
// promises: decoded child boxes contain their triangles, every triangle is referenced once.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "support/models.hpp"
#include "differential/test_scenes.hpp"
#include "support/same_hit.hpp"
#include "support/test_scale.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/error.hpp"
#include "visfield/gpu/bvh_traversal.hpp"
#include "visfield/gpu/gpu_bvh.hpp"
#include "visfield/gpu/texture_layout.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf::test {
namespace {

/// The adversarial ray sets of tests/differential plus the boundary-t copies of their hits.
std::vector<Ray> adversarial(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  std::vector<Ray> rays;
  for (auto make : {random_rays, axis_parallel_rays, zero_component_rays, surface_origin_rays, grazing_rays}) {
    const std::vector<Ray> part = make(set, seed, n);
    rays.insert(rays.end(), part.begin(), part.end());
  }
  return rays;
}

/// Counts the rays where `gpu` and `oracle` differ (closest hit bits, occlusion), with the first one
/// described in a failure message.
template <class Oracle>
void expect_same(const gpu::GpuBvh& gpu, const Oracle& oracle, const std::vector<Ray>& rays, const std::string& label,
                 bool with_boundary = true) {
  std::size_t closest = 0, occluded = 0, hits = 0;
  std::vector<Hit> oracle_hits(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    oracle_hits[i] = oracle.intersect(rays[i]);
    const Hit got = gpu.intersect(rays[i]);
    hits += oracle_hits[i] ? 1 : 0;
    if (!same_bits(got, oracle_hits[i])) {
      if (closest++ == 0) ADD_FAILURE() << label << ": first closest-hit mismatch at ray " << i << " t " << got.t << " vs " << oracle_hits[i].t;
    }
    if (gpu.occluded(rays[i]) != oracle.occluded(rays[i])) {
      if (occluded++ == 0) ADD_FAILURE() << label << ": first occlusion mismatch at ray " << i;
    }
  }
  EXPECT_EQ(closest, 0u) << label;
  EXPECT_EQ(occluded, 0u) << label;
  EXPECT_GT(hits, 0u) << label;
  if (!with_boundary) return;
  const std::vector<Ray> boundary = boundary_t_rays(rays, oracle_hits);
  std::size_t boundary_mismatches = 0;
  for (const Ray& r : boundary)
    if (!same_bits(gpu.intersect(r), oracle.intersect(r)) || gpu.occluded(r) != oracle.occluded(r)) ++boundary_mismatches;
  EXPECT_EQ(boundary_mismatches, 0u) << label << " (boundary t copies)";
}

TEST(GpuBvh, EmptySetMissesEverything) {
  const gpu::GpuBvh bvh = gpu::GpuBvh::build(TriangleSet{});
  EXPECT_TRUE(bvh.nodes().empty());
  EXPECT_FALSE(bvh.intersect(Ray{{0, 0, 0}, {1, 0, 0}}));
  EXPECT_FALSE(bvh.occluded(Ray{{0, 0, 0}, {1, 0, 0}}));
}

TEST(GpuBvh, RefusesBadConfig) {
  const TriangleSet set = set_from_triangles(random_soup(1, 10, 0.01f, 0.1f));
  EXPECT_THROW(gpu::GpuBvh::build(set, {.bin_count = 1}), Error);
  EXPECT_THROW(gpu::GpuBvh::build(set, {.max_leaf_size = 5}), Error);
  EXPECT_THROW(gpu::GpuBvh::build(set, {.max_leaf_size = 0}), Error);
}

TEST(GpuBvh, DecodedBoxesContainTheirTrianglesAndEveryTriangleIsInOneLeaf) {
  const TriangleSet set = set_from_triangles(random_soup(7, 5000, 0.001f, 0.2f));
  const gpu::GpuBvh bvh = gpu::GpuBvh::build(set);
  ASSERT_EQ(bvh.triangles().size(), set.size());
  std::vector<int> seen(set.size(), 0);
  for (const gpu::WideTriangle& t : bvh.triangles()) ++seen[t.index];
  for (std::size_t i = 0; i < set.size(); ++i) ASSERT_EQ(seen[i], 1) << i;
  // Walk every node: each triangle lies in its leaf slot's decoded box and in every ancestor's (a
  // traversal reaches it only through all of them), not merely in the nearest one.
  struct Box {
    float lo[3], hi[3];
  };
  const auto slot_box = [](const gpu::WideNode& n, int slot) {
    Box b;
    for (int a = 0; a < 3; ++a) {
      const float scale = gpu::exponent_scale(n.exponent[a]);
      b.lo[a] = gpu::decode(n.origin[a], n.lo[a][slot], scale);
      b.hi[a] = gpu::decode(n.origin[a], n.hi[a][slot], scale);
    }
    return b;
  };
  std::size_t checked = 0;
  std::function<void(std::uint32_t, const Box&)> check = [&](std::uint32_t index, const Box& ancestors) {
    const gpu::WideNode& n = bvh.nodes()[index];
    for (int slot = 0; slot < 8; ++slot) {
      if (n.meta[slot] == gpu::kEmptySlot) continue;
      const Box b = slot_box(n, slot);
      Box within;  // this slot's box and every ancestor's
      for (int a = 0; a < 3; ++a) {
        ASSERT_TRUE(b.lo[a] <= b.hi[a]);
        within.lo[a] = std::max(b.lo[a], ancestors.lo[a]);
        within.hi[a] = std::min(b.hi[a], ancestors.hi[a]);
      }
      if ((n.interior >> slot) & 1u) {
        check(n.child_base + n.meta[slot], within);
        continue;
      }
      const unsigned first = n.triangle_base + (n.meta[slot] & 31u), count = (n.meta[slot] >> 5) + 1u;
      ASSERT_LE(count, static_cast<unsigned>(gpu::kMaxLeafTriangles));
      for (unsigned k = first; k < first + count; ++k) {
        const gpu::WideTriangle& t = bvh.triangles()[k];
        ++checked;
        for (const float* p : {t.p0, t.p1, t.p2})
          for (int a = 0; a < 3; ++a) {
            ASSERT_LE(within.lo[a], p[a]) << "triangle " << t.index << " outside an ancestor's box";
            ASSERT_GE(within.hi[a], p[a]) << "triangle " << t.index << " outside an ancestor's box";
          }
      }
    }
  };
  const float inf = std::numeric_limits<float>::infinity();
  check(0, Box{{-inf, -inf, -inf}, {inf, inf, inf}});
  EXPECT_EQ(checked, set.size());
}

TEST(GpuBvh, EqualsBruteForceOnSoupsAndAdversarialRays) {
  struct Case {
    std::string name;
    std::vector<Triangle> triangles;
  };
  const std::vector<Case> cases = {
      {"one triangle", {{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}}},
      {"small soup", random_soup(3, 100, 0.01f, 0.3f)},
      {"fine soup", random_soup(4, 20000, 0.0005f, 0.02f)},
      {"mixed scales", random_soup(5, 5000, 1e-4f, 0.5f)},
      {"coplanar", coplanar_soup(6, 2000, {0, 0.5f, 0}, {1, 0, 0}, {0, 0, 1})},
      {"height field", height_field(8, 60)},
  };
  for (const Case& c : cases) {
    const TriangleSet set = set_from_triangles(c.triangles);
    // Under the sanitizers the brute-force oracle of the 20k-triangle soup takes a tenth of the rays.
    const auto rays_for = [&](std::size_t n) { return set.size() >= 10000 ? scaled_count(n) : n; };
    expect_same(gpu::GpuBvh::build(set), BruteForce::build(set), adversarial(set, 11, rays_for(1500)), c.name);
    expect_same(gpu::GpuBvh::build(set, {.max_leaf_size = 1}), BruteForce::build(set), adversarial(set, 12, rays_for(500)),
                c.name + " (leaf 1)");
  }
}

/// The most entries a traversal stack can hold, recomputed from the layout alone: over root-to-node
/// paths, the sum of each node's used slots less one.
unsigned int stack_bound_of(const gpu::GpuBvh& bvh) {
  std::function<unsigned int(std::uint32_t, unsigned int)> walk = [&](std::uint32_t index, unsigned int above) {
    const gpu::WideNode& n = bvh.nodes()[index];
    unsigned int used = 0;
    for (int slot = 0; slot < 8; ++slot) used += n.meta[slot] != gpu::kEmptySlot ? 1u : 0u;
    const unsigned int here = above + (used > 0 ? used - 1 : 0);
    unsigned int most = here;
    for (int slot = 0; slot < 8; ++slot)
      if (n.meta[slot] != gpu::kEmptySlot && ((n.interior >> slot) & 1u)) most = std::max(most, walk(n.child_base + n.meta[slot], here));
    return most;
  };
  return bvh.nodes().empty() ? 0 : walk(0, 0);
}

/// Closest and any hit with a traversal stack of `Capacity` entries equal the full stack's on `rays`
/// (under AddressSanitizer, a stack too small for the tree is an overflow).
template <int Capacity>
void expect_capacity_suffices(const gpu::GpuBvh& bvh, const std::vector<Ray>& rays, const std::string& label) {
  const gpu::BvhView view = bvh.view();
  ASSERT_LE(view.stack_bound, static_cast<unsigned int>(Capacity)) << label;
  std::size_t differ = 0;
  for (const Ray& r : rays)
    differ += !same_bits(gpu::intersect<Capacity>(view, r), bvh.intersect(r)) || gpu::occluded<Capacity>(view, r) != bvh.occluded(r);
  EXPECT_EQ(differ, 0u) << label;
}

TEST(GpuBvh, StackBoundIsTheLayoutsAndTheKernelsCapacityHoldsIt) {
  struct Case {
    std::string name;
    std::vector<Triangle> triangles;
  };
  const std::vector<Case> cases = {{"one triangle", {{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}}},
                                   {"fine soup", random_soup(4, 20000, 0.0005f, 0.02f)},
                                   {"mixed scales", random_soup(5, 5000, 1e-4f, 0.5f)},
                                   {"nested shells", nested_shells(40, 24)},
                                   {"deeper nested shells", nested_shells(80, 24)}};
  std::vector<int> capacities_seen;
  for (const Case& c : cases) {
    const TriangleSet set = set_from_triangles(c.triangles);
    const gpu::GpuBvh bvh = gpu::GpuBvh::build(set);
    const unsigned int bound = bvh.stack_bound();
    EXPECT_EQ(bound, stack_bound_of(bvh)) << c.name;
    EXPECT_EQ(bvh.view().stack_bound, bound) << c.name;
    EXPECT_LE(bound, static_cast<unsigned int>(7 * bvh.stats().max_depth)) << c.name;
    const int capacity = gpu::stack_capacity_for(bound);
    EXPECT_GE(capacity, static_cast<int>(bound)) << c.name;
    capacities_seen.push_back(capacity);
    const std::vector<Ray> rays = adversarial(set, 31, 800);
    if (capacity == gpu::kStackCapacities[0])
      expect_capacity_suffices<gpu::kStackCapacities[0]>(bvh, rays, c.name);
    else if (capacity == gpu::kStackCapacities[1])
      expect_capacity_suffices<gpu::kStackCapacities[1]>(bvh, rays, c.name);
    else if (capacity == gpu::kStackCapacities[2])
      expect_capacity_suffices<gpu::kStackCapacities[2]>(bvh, rays, c.name);
    else
      expect_capacity_suffices<gpu::kStackCapacities[3]>(bvh, rays, c.name);
    std::printf("%s: %zu triangles, depth %d, stack bound %u, capacity %d\n", c.name.c_str(), set.size(), bvh.stats().max_depth, bound,
                capacity);
  }
  for (int k = 0; k < 4; ++k)
    EXPECT_NE(std::find(capacities_seen.begin(), capacities_seen.end(), gpu::kStackCapacities[k]), capacities_seen.end())
        << "no case exercised capacity " << gpu::kStackCapacities[k];
  EXPECT_EQ(gpu::GpuBvh::build(TriangleSet{}).stack_bound(), 0u);
  EXPECT_EQ(gpu::stack_capacity_for(0), gpu::kStackCapacities[0]);
  EXPECT_EQ(gpu::stack_capacity_for(static_cast<unsigned int>(gpu::kStackCapacities[0]) + 1), gpu::kStackCapacities[1]);
  EXPECT_EQ(gpu::stack_capacity_for(100000), gpu::kStackSize);
}

TEST(GpuBvh, FieldTextureShapeFollowsTheDevicesLimits) {
  const gpu::Texture3DLimits sm90{16384, 16384, 16384};  // cudaDevAttrMaxTexture3D{Width,Height,Depth} of sm_90
  EXPECT_EQ(gpu::field_texture_shape(2 * 4226, 32, sm90).stack, 1u);
  EXPECT_EQ(gpu::field_texture_shape(2 * 16642, 64, sm90).stack, 3u);
  EXPECT_EQ(gpu::field_texture_shape(2 * 16642, 64, sm90).depth, 11095u);
  const gpu::Texture3DLimits small{512, 1024, 2048};  // a smaller device: more samples a slice
  EXPECT_EQ(gpu::field_texture_shape(2048, 64, small).stack, 1u);
  EXPECT_EQ(gpu::field_texture_shape(2049, 64, small).stack, 2u);
  EXPECT_EQ(gpu::field_texture_shape(2049, 64, small).depth, 1025u);
  const gpu::FieldTextureShape shape = gpu::field_texture_shape(2 * 4226, 32, small);
  EXPECT_GE(shape.stack * shape.depth, 2u * 4226u);
  EXPECT_LE(shape.depth, small.depth);
  EXPECT_LE(32u * shape.stack, small.height);
  EXPECT_THROW(gpu::field_texture_shape(2 * 16642, 128, small), Error) << "128 x 17 rows exceed a height of 1024";
  EXPECT_THROW(gpu::field_texture_shape(10, 1024, small), Error) << "wider than the device allows";
  EXPECT_THROW(gpu::field_texture_shape(0, 32, small), Error);
}

TEST(GpuBvh, EqualsTheOracleOnTheSharedModels) {
  std::size_t k = 0;
  for (const char* model : {"bun_zipper.ply", "cow.obj", "igea-triangles.ply", "Armadillo.ply", "teapot.obj",
                            "CornellBox-Original.obj", "sponza.obj", "conference.obj"}) {
    if (!sampled(k++, 3)) continue;
    const std::filesystem::path path = models_dir() / model;
    VF_SKIP_WITHOUT_MODELS(std::filesystem::exists(path), model);
    const TriangleSet set = flatten(load_scene(path.string()));
    const gpu::GpuBvh gpu = gpu::GpuBvh::build(set);
    // BruteForce on a sample (it is O(N) a ray), the CPU Bvh (equal to BruteForce by the
    // differential tests) on 100k model rays.
    const std::vector<Ray> rays = model_rays(set, 2024, scaled_count(100'000));
    expect_same(gpu, BruteForce::build(set), std::vector<Ray>(rays.begin(), rays.begin() + scaled_count(2000)),
                std::string(model) + " vs brute force", false);
    expect_same(gpu, Bvh::build(set), rays, std::string(model) + " vs bvh", false);
    EXPECT_EQ(gpu.stack_bound(), stack_bound_of(gpu)) << model;
    std::printf("%s: depth %d, stack bound %u, kernel stack capacity %d\n", model, gpu.stats().max_depth, gpu.stack_bound(),
                gpu::stack_capacity_for(gpu.stack_bound()));
  }
}

}  // namespace
}  // namespace vf::test
