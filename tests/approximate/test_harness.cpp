// The approximate-structure harness itself: it passes a structure that keeps its stated bounds, fails
// one that breaks them, and measures zero error for an exact structure. (The approximate structures
// of visfield, ObjectField among them, are tested with it against their own bounds.)

#include <bit>

#include <gtest/gtest.h>

#include "approximate/harness.hpp"
#include "differential/ray_sets.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::test {
namespace {

// A deterministic number in [0, 1) for a ray (hash of its origin and direction bits).
float ray_hash(const Ray& ray) {
  std::uint64_t h = 0;
  for (const float x : {ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z}) h = mix64(h ^ std::bit_cast<std::uint32_t>(x));
  return static_cast<float>(h >> 40) * 0x1p-24f;
}

// A test double of an approximate structure: an exact BVH whose distances are off by up to a relative
// `t_error` and whose occlusion answers are flipped on a `flip` fraction of the rays. It states
// `stated` as its bounds.
class Perturbed {
 public:
  Perturbed(const Bvh& exact, float t_error, float flip, ErrorBounds stated)
      : exact_(exact), t_error_(t_error), flip_(flip), stated_(stated) {}
  Hit intersect(const Ray& ray) const {
    Hit hit = exact_.intersect(ray);
    if (hit) hit.t *= 1.0f + t_error_ * (2.0f * ray_hash(ray) - 1.0f);
    return hit;
  }
  bool occluded(const Ray& ray) const { return exact_.occluded(ray) != (ray_hash(ray) < flip_); }
  const AccelStats& stats() const { return exact_.stats(); }
  ErrorBounds error_bounds() const { return stated_; }
  static std::string name() { return "perturbed"; }
  static constexpr Exactness exactness = Exactness::approximate;

 private:
  const Bvh& exact_;
  float t_error_, flip_;
  ErrorBounds stated_;
};
static_assert(ApproximateStructure<Perturbed> && !ExactStructure<Perturbed>);
static_assert(ExactStructure<Bvh> && !ApproximateStructure<Bvh>);

struct World {
  Scene scene = make_builtin_scene("cornell", {.size = 400});
  TriangleSet set = flatten(scene);
  Bvh bvh = Bvh::build(set);
  std::vector<Ray> rays = model_rays(set, 9, 20000);
  double diameter = length(set.bounds.extent());
  Camera camera = scene.camera_or_default(48, 36);
};

ApproximationError measure(const World& s, const Perturbed& p) {
  ApproximationError e = measure_approximation(p, s.bvh, s.rays, s.diameter);
  AoOptions options;
  options.ao_rays = 16;
  e.image_rms = ao_image_rms(p, s.bvh, s.scene, s.camera, options);
  return e;
}

TEST(ApproximateHarness, AStructureWithinItsBoundsPasses) {
  const World s;
  const Perturbed p(s.bvh, 1e-3f, 0.02f,
                    {.occlusion_disagreement = 0.03, .hit_disagreement = 0.0, .distance_rms = 1e-3, .image_rms = 0.05});
  const ApproximationError e = measure(s, p);
  EXPECT_NEAR(e.occlusion_disagreement, 0.02, 0.005);
  EXPECT_GT(e.distance_rms, 0.0);
  EXPECT_GT(e.image_rms, 0.0);
  EXPECT_TRUE(within_bounds(e, p.error_bounds()));
}

TEST(ApproximateHarness, AStructureBreakingItsBoundsFails) {
  const World s;
  // Flips 10% of the occlusion answers but promises 1%.
  const Perturbed liar(s.bvh, 0.0f, 0.10f, {.occlusion_disagreement = 0.01, .image_rms = 1.0});
  const ::testing::AssertionResult result = within_bounds(measure(s, liar), liar.error_bounds());
  EXPECT_FALSE(result);
  EXPECT_NE(std::string(result.message()).find("occlusion disagreement"), std::string::npos) << result.message();
  // Distances off by up to 5% relative, promised within 1e-4 of the diameter.
  const Perturbed far(s.bvh, 0.05f, 0.0f, {.distance_rms = 1e-4, .image_rms = 1.0});
  EXPECT_FALSE(within_bounds(measure(s, far), far.error_bounds()));
}

TEST(ApproximateHarness, AnExactStructureMeasuresNoError) {
  const World s;
  const Perturbed exact(s.bvh, 0.0f, 0.0f, {});
  const ApproximationError e = measure(s, exact);
  EXPECT_EQ(e.occlusion_disagreement, 0.0);
  EXPECT_EQ(e.hit_disagreement, 0.0);
  EXPECT_EQ(e.distance_rms, 0.0);
  EXPECT_EQ(e.image_rms, 0.0);
  EXPECT_GT(e.both_hit, s.rays.size() / 10);
  EXPECT_TRUE(within_bounds(e, exact.error_bounds()));
}

}  // namespace
}  // namespace vf::test
