// The kernels' ray generation on the host: the polynomial sines and cosines against libm, and AO,
// soft-shadow and glossy rays against the CPU renderers' own sampling (core/sampling.hpp,
// SphereCone, Bsdf::sample_specular) drawing the same numbers: AO rays continuing a generator bit
// for bit, the others to a few ulps (their frames are written apart), deterministic in their keys.

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "visfield/core/sampling.hpp"
#include "visfield/gpu/ray_generation.hpp"
#include "visfield/render/bsdf.hpp"
#include "visfield/render/lights.hpp"
#include "visfield/render/sample_rays.hpp"

namespace vf::test {
namespace {

constexpr float kTolerance = 2e-6f;

void expect_near(const Vec3f& a, const Vec3f& b, float tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

gpu::SurfaceFrame frame_at(const Vec3f& position, const Vec3f& normal) {
  gpu::SurfaceFrame f{position, normalize(normal), {}, {}};
  orthonormal_basis(f.normal, f.tangent, f.bitangent);
  return f;
}

TEST(RayGeneration, PolynomialSinesAndCosinesMatchLibm) {
  for (int k = 0; k < 100000; ++k) {
    const float v = static_cast<float>(k) / 100000.0f;
    float s, c;
    sincos_turn(v, s, c);
    const double angle = 2.0 * std::numbers::pi * v;
    ASSERT_NEAR(s, std::sin(angle), 1e-6) << v;
    ASSERT_NEAR(c, std::cos(angle), 1e-6) << v;
    const float phi = (v - 0.5f) * static_cast<float>(std::numbers::pi / 2.0);
    sincos_eighth(phi, s, c);
    ASSERT_NEAR(s, std::sin(phi), 1e-6) << phi;
    ASSERT_NEAR(c, std::cos(phi), 1e-6) << phi;
  }
}

// The map with the polynomial sines against the same map in double with libm's.
TEST(RayGeneration, CosineHemisphereIsTheConcentricMapToRounding) {
  Rng rng(3);
  for (int k = 0; k < 100000; ++k) {
    const float s = rng.uniform(), t = rng.uniform();
    const double a = 2.0 * s - 1.0, b = 2.0 * t - 1.0;
    const double r = std::fabs(a) >= std::fabs(b) ? a : b;
    const double phi = std::fabs(a) >= std::fabs(b) ? std::numbers::pi / 4.0 * (b / a) : std::numbers::pi / 2.0 - std::numbers::pi / 4.0 * (a / b);
    const double x = r * std::cos(phi), y = r * std::sin(phi);
    const Vec3f w = cosine_hemisphere(s, t);
    const Vec3f cpu{static_cast<float>(x), static_cast<float>(y), static_cast<float>(std::sqrt(std::fmax(0.0, 1.0 - x * x - y * y)))};
    ASSERT_NEAR(w.x, cpu.x, 1e-6f);
    ASSERT_NEAR(w.y, cpu.y, 1e-6f);
    // z = sqrt(1 - x^2 - y^2) amplifies the ulps of x and y near the rim by 1/z.
    ASSERT_NEAR(w.z, cpu.z, 1e-6f + 2e-7f / std::fmax(cpu.z, 1e-4f));
    ASSERT_NEAR(length(w), 1.0f, 1e-5f);
    ASSERT_GE(w.z, 0.0f);
  }
  const Vec3f centre = cosine_hemisphere(0.5f, 0.5f);
  EXPECT_EQ(centre.x, 0.0f);
  EXPECT_EQ(centre.z, 1.0f);
}

TEST(RayGeneration, AoRaysDependOnTheirKeysOnly) {
  const gpu::SurfaceFrame f = frame_at({1.0f, 2.0f, 3.0f}, {0.3f, -1.0f, 0.2f});
  const Ray a = gpu::ao_ray(f, 7, 12345, 3, 2.5f);
  const Ray b = gpu::ao_ray(f, 7, 12345, 3, 2.5f);
  EXPECT_EQ(a.dir, b.dir);
  EXPECT_NE(gpu::ao_ray(f, 7, 12345, 4, 2.5f).dir, a.dir);
  EXPECT_NE(gpu::ao_ray(f, 8, 12345, 3, 2.5f).dir, a.dir);
  EXPECT_EQ(a.org, f.position);
  EXPECT_EQ(a.tmin, 0.0f);
  EXPECT_EQ(a.tmax, 2.5f);
  // The numbers are Rng(seed, point, sample)'s first two, turned by the surface's frame.
  Rng rng(7, 12345, 3);
  const float s = rng.uniform(), t = rng.uniform();
  const Vec3f local = cosine_hemisphere(s, t);
  expect_near(a.dir, f.tangent * local.x + f.bitangent * local.y + f.normal * local.z, kTolerance);
  for (int k = 0; k < 10000; ++k) ASSERT_GE(dot(gpu::ao_ray(f, 1, 9, k, 1.0f).dir, f.normal), 0.0f);
}

// What lets `visfield render --device cuda` draw the CPU renderer's AO rays: ray k continuing a
// pixel sample's generator is the k-th ray render's ao_rays() draws from it, bit for bit.
TEST(RayGeneration, AoRaysContinuingAStreamAreTheCpuRenderersBitForBit) {
  for (const std::size_t count : {1u, 5u, 64u, 121u}) {
    const gpu::SurfaceFrame f = frame_at({0.5f, -2.0f, 1.0f}, {-0.4f, 0.1f, 1.0f});
    const SurfacePoint point{f.position, f.normal, f.tangent, f.bitangent, f.position, true};
    Rng rng(5, 777 + count, 2);
    rng.uniform();  // the camera sample's jitter draws first
    rng.uniform();
    const Rng stream = rng;
    std::vector<Ray> cpu(count);
    ao_rays(point, rng, 3.0f, count, cpu.data());
    for (std::size_t k = 0; k < count; ++k) {
      const Ray gpu_ray = gpu::ao_ray(f, stream, k, 3.0f);
      ASSERT_EQ(gpu_ray.org, cpu[k].org) << k;
      ASSERT_EQ(gpu_ray.dir, cpu[k].dir) << count << " rays, ray " << k;
      ASSERT_EQ(gpu_ray.tmin, cpu[k].tmin);
      ASSERT_EQ(gpu_ray.tmax, cpu[k].tmax);
    }
    // ao_rays leaves the generator where the next sample's numbers start.
    EXPECT_EQ(rng.state(), stream.advanced(2 * count).state());
  }
}

TEST(RayGeneration, ConeRaysAreTheSoftShadowIntegratorsToRounding) {
  const SphereLight light{{0.5f, 4.0f, -1.0f}, 0.7f, Vec3f{3.0f}};
  const gpu::SphereLightData data{light.center, light.radius};
  for (int k = 0; k < 20000; ++k) {
    const Vec3f from{0.01f * static_cast<float>(k % 100), 0.0f, 0.02f * static_cast<float>(k / 100)};
    const Ray ray = gpu::cone_ray(from, data, 11, static_cast<unsigned>(k), 5);
    Rng rng(11, static_cast<unsigned>(k), 5);
    const float u = rng.uniform(), v = rng.uniform();
    const LightSample sample = SphereCone::toward(light, from)->sample(u, v);
    expect_near(ray.dir, sample.wi, 1e-5f);
    ASSERT_NEAR(ray.tmax, sample.distance * (1.0f - 1e-4f), 1e-4f * sample.distance);
    ASSERT_EQ(ray.org, from);
  }
  // Inside the light: an empty ray, which nothing occludes.
  EXPECT_EQ(gpu::cone_ray(light.center, data, 1, 2, 3).tmax, 0.0f);
}

TEST(RayGeneration, GlossyRaysAreBsdfSampleSpecularToRounding) {
  for (const float roughness : {0.0f, 0.1f, 0.3f, 0.7f}) {
    Material material;
    material.diffuse = Vec3f{0.0f};
    material.specular = Vec3f{1.0f};
    material.roughness = roughness;
    const Vec3f normal = normalize(Vec3f{0.2f, 1.0f, -0.1f});
    const gpu::SurfaceFrame f = frame_at({0.0f, 1.0f, 0.0f}, normal);
    SurfacePoint point;
    point.position = f.position;
    point.normal = f.normal;
    point.tangent = f.tangent;
    point.bitangent = f.bitangent;
    const Bsdf bsdf(material, point, true);
    const float alpha = roughness < kMirrorRoughness ? 0.0f : std::fmax(roughness * roughness, 1e-3f);
    int valid = 0, disagree = 0;
    for (int k = 0; k < 20000; ++k) {
      const Vec3f wo = normalize(Vec3f{std::cos(0.001f * k), 1.5f, std::sin(0.0013f * k)});
      const gpu::GlossySample g = gpu::glossy_ray(f, wo, alpha, 21, static_cast<unsigned>(k), 0);
      Rng rng(21, static_cast<unsigned>(k), 0);
      const std::optional<BsdfSample> cpu = bsdf.sample_specular(wo, rng);
      // Directions grazing the surface may fall on either side by an ulp of libm's sine.
      if (g.valid != cpu.has_value()) ++disagree;
      if (!g.valid || !cpu) continue;
      ++valid;
      expect_near(g.ray.dir, cpu->wi, 1e-5f);
      ASSERT_NEAR(g.weight, cpu->weight.x, 1e-4f * std::fmax(1.0f, cpu->weight.x));
      ASSERT_EQ(g.ray.org, f.position);
    }
    EXPECT_GT(valid, 10000) << roughness;
    EXPECT_LE(disagree, 2) << roughness;
  }
}

}  // namespace
}  // namespace vf::test
