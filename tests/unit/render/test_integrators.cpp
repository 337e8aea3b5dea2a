#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "test_scenes.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/bsdf.hpp"
#include "visfield/render/compare.hpp"
#include "visfield/render/integrators.hpp"
#include "visfield/render/lights.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

ShadingOptions quiet(int spp = 1) {
  ShadingOptions o;
  o.spp = spp;
  o.progress = false;
  return o;
}

Vec3f mean(const Image& image) {
  Vec3f sum{0.0f};
  for (const Vec3f& p : image.pixels) sum += p;
  return sum * (1.0f / static_cast<float>(image.pixels.size()));
}

float max_difference(const Image& a, const Image& b) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) worst = std::fmax(worst, max_component(abs(a.pixels[i] - b.pixels[i])));
  return worst;
}

// A grey (albedo 0.5) ground, 400 units wide, lit by one sphere light of radiance 10 centred `height`
// above the origin; the camera looks at the origin from the side with a 1-degree field of view.
Scene lit_ground(float height, float radius, float radiance) {
  Scene scene = test::plane_scene(200.0f);
  scene.materials[0].diffuse = Vec3f{0.5f};
  scene.sphere_lights.push_back(SphereLight{{0.0f, height, 0.0f}, radius, Vec3f{radiance}});
  return scene;
}
Camera side_camera() { return test::camera_looking_at({2.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 9, 9, 1.0f); }

// Radiance of a Lambertian surface of albedo `albedo` under a sphere light of radiance L seen at
// half-angle asin(r / d) straight above: irradiance pi L (r/d)^2, times albedo / pi.
float expected_under_sphere(float albedo, float radiance, float radius, float height) {
  return albedo * radiance * (radius * radius) / (height * height);
}

struct Built {
  explicit Built(const Scene& scene, const std::string& spec = "bvh")
      : geometry(scene), structure(build_structure(spec, geometry)), queries(scene_queries(structure.structure, structure.structure)) {}
  SceneGeometry geometry;
  BuiltStructure structure;
  std::unique_ptr<SceneQueries> queries;
};

TEST(PathTracer, DirectLightFromASmallSphereMatchesTheAnalyticRadiance) {
  const Scene scene = lit_ground(1.0f, 0.2f, 10.0f);
  const Built built(scene);
  ShadingOptions o = quiet(64);
  o.max_depth = 4;
  const float expected = expected_under_sphere(0.5f, 10.0f, 0.2f, 1.0f);  // 0.2
  const Vec3f got = mean(render_shaded(Integrator::path, *built.queries, scene, side_camera(), o));
  EXPECT_NEAR(got.x, expected, 0.02f * expected);
  EXPECT_NEAR(got.y, expected, 0.02f * expected);
}

TEST(PathTracer, ALargeNearSphereNeedsBothStrategiesAndStillMatches) {
  // The light fills 42% of the sky's solid-angle weight: Bsdf samples find it often, and MIS must
  // neither count it twice nor lose it.
  const Scene scene = lit_ground(1.5f, 1.0f, 1.0f);
  const Built built(scene);
  const float expected = expected_under_sphere(0.5f, 1.0f, 1.0f, 1.5f);
  const Vec3f got = mean(render_shaded(Integrator::path, *built.queries, scene, side_camera(), quiet(64)));
  EXPECT_NEAR(got.x, expected, 0.02f * expected);
}

// The soft-shadow render of a ground under one sphere light, `spp` samples a pixel and `rays` a
// light: within `tolerance` (relative) of the analytic radiance, every camera and shadow ray counted.
void expect_analytic_soft_shadow(int spp, int rays, float tolerance) {
  const Scene scene = lit_ground(1.0f, 0.2f, 10.0f);
  const Built built(scene);
  ShadingOptions o = quiet(spp);
  o.ambient = 0.0f;
  o.shadow_rays = rays;
  const float expected = expected_under_sphere(0.5f, 10.0f, 0.2f, 1.0f);
  RenderStats stats;
  const Vec3f got = mean(render_shaded(Integrator::softshadow, *built.queries, scene, side_camera(), o, &stats));
  EXPECT_NEAR(got.x, expected, tolerance * expected);
  const auto samples = 9u * 9u * static_cast<std::uint64_t>(spp);
  EXPECT_EQ(stats.by_kind.camera, samples);
  EXPECT_EQ(stats.by_kind.shadow, samples * static_cast<std::uint64_t>(rays));
}

TEST(SoftShadows, ConeSamplesOfASphereLightMatchTheAnalyticRadiance) { expect_analytic_soft_shadow(4, 32, 0.01f); }

// More rays for one shading point than a tile's batch holds (5000 > 4096): the batch grows to take
// them, and they still average to the light's radiance.
TEST(SoftShadows, MoreRaysForAPointThanTheBatchHoldsStillMatchTheAnalyticRadiance) { expect_analytic_soft_shadow(1, 5000, 0.005f); }

// Bits of a float, so that -0 and +0 (and NaNs) tell apart.
std::uint32_t bits(float x) { return std::bit_cast<std::uint32_t>(x); }
bool same_bits(const Vec3f& a, const Vec3f& b) { return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z); }

TEST(SoftShadows, ConeSamplesInPacketsAreTheOnesDrawnOneByOne) {
  Rng frames(3, 7);
  for (const std::size_t count : {0, 1, 3, 4, 5, 7, 8, 9, 15, 16, 17, 20, 33, 64, 100})
    for (int c = 0; c < 8; ++c) {
      // Near and far lights, small and large, from points all around; c == 0 looks straight down.
      const SphereLight light{Vec3f{frames.uniform(), frames.uniform(), frames.uniform()} * 20.0f - Vec3f{10.0f},
                              0.01f + 3.0f * frames.uniform() * frames.uniform(), Vec3f{5.0f, 4.0f, 3.0f}};
      const Vec3f from = c == 0 ? light.center - Vec3f{0.0f, 4.0f, 0.0f} : light.center + uniform_sphere(frames.uniform(), frames.uniform()) * (light.radius * (1.001f + 10.0f * frames.uniform()));
      const std::optional<SphereCone> cone = SphereCone::toward(light, from);
      ASSERT_TRUE(cone.has_value());
      Rng one(9, static_cast<std::uint64_t>(c), count), many = one;
      std::vector<Vec3f> wi(count);
      std::vector<float> distance(count);
      cone->sample(many, count, wi.data(), distance.data());
      for (std::size_t k = 0; k < count; ++k) {
        const float u = one.uniform(), v = one.uniform();
        const LightSample expected = cone->sample(u, v);
        ASSERT_TRUE(same_bits(expected.wi, wi[k]) && bits(expected.distance) == bits(distance[k]))
            << count << " samples, cone " << c << ", sample " << k;
      }
      EXPECT_EQ(one.next_u32(), many.next_u32()) << count;
    }
}

TEST(SoftShadows, TheBsdfEvaluatedForManyDirectionsIsEachEvaluatedAlone) {
  Rng frames(4, 2);
  for (const float roughness : {0.0f, 0.5f})
    for (const float transmission : {0.0f, 0.25f}) {
      Material material;
      material.diffuse = Vec3f{0.8f, 0.5f, 0.2f};
      material.specular = roughness > 0.0f ? Vec3f{0.3f} : Vec3f{0.0f};
      material.roughness = roughness;
      material.transmission = transmission;
      SurfacePoint point;
      point.normal = uniform_sphere(frames.uniform(), frames.uniform());
      orthonormal_basis(point.normal, point.tangent, point.bitangent);
      const Bsdf bsdf(material, point, true);
      // Directions on both sides of the surface and in its plane; viewers above and below it.
      std::vector<Vec3f> wi;
      for (int k = 0; k < 61; ++k) wi.push_back(uniform_sphere(frames.uniform(), frames.uniform()));
      wi.push_back(point.tangent);
      for (const Vec3f& wo : {point.normal, -point.normal, normalize(point.normal + point.tangent), point.bitangent}) {
        std::vector<Vec3f> f(wi.size());
        bsdf.eval(wo, std::span<const Vec3f>(wi), f.data());
        for (std::size_t k = 0; k < wi.size(); ++k)
          ASSERT_TRUE(same_bits(f[k], bsdf.eval(wo, wi[k]))) << "roughness " << roughness << ", transmission " << transmission << ", direction " << k;
      }
    }
}

// The soft-shadow render's rays of a shading point (sphere_light_rays: on lanes for Lambertian
// surfaces, a light's samples across packets) are the ones a loop drawing, evaluating and keeping
// one sample at a time makes, bit for bit, with the generator left where that loop leaves it.
TEST(SoftShadows, SphereLightRaysAreTheSamplesDrawnAndShadedOneByOne) {
  Rng frames(5, 3);
  std::size_t checked = 0, kept_total = 0;
  for (const std::size_t lights_count : {1, 2, 3, 7, 8, 9, 17})
    for (const int per_light : {1, 2, 3, 7, 8, 9, 16, 20, 33})
      for (int m = 0; m < 5; ++m) {
        // Lambertian (m 0-2: grey, coloured with a black channel, half transmissive), glossy, black.
        Material material;
        material.diffuse = m == 1 ? Vec3f{0.8f, 0.0f, 0.3f} : m == 4 ? Vec3f{0.0f} : Vec3f{0.6f};
        material.transmission = m == 2 ? 0.5f : 0.0f;
        if (m == 3) {
          material.specular = Vec3f{0.3f};
          material.roughness = 0.5f;
        }
        SurfacePoint point;
        point.position = Vec3f{frames.uniform(), frames.uniform(), frames.uniform()} * 4.0f - Vec3f{2.0f};
        point.normal = uniform_sphere(frames.uniform(), frames.uniform());
        orthonormal_basis(point.normal, point.tangent, point.bitangent);
        const Bsdf bsdf(material, point, true);
        // Lights all around (some behind the surface), one holding the point now and then; viewers mostly above.
        std::vector<SphereLight> lights;
        for (std::size_t j = 0; j < lights_count; ++j) {
          const Vec3f centre = point.position + uniform_sphere(frames.uniform(), frames.uniform()) * (0.5f + 6.0f * frames.uniform());
          const float radius = frames.uniform() < 0.1f ? 10.0f : 0.05f + frames.uniform();
          lights.push_back(SphereLight{centre, radius, Vec3f{1.0f + frames.uniform(), 2.0f, 3.0f * frames.uniform()}});
        }
        const Vec3f wo = frames.uniform() < 0.2f ? -point.normal : normalize(point.normal + uniform_sphere(frames.uniform(), frames.uniform()) * 0.5f);
        Rng one(11, checked, static_cast<std::uint64_t>(per_light)), many = one;
        const std::size_t room = lights_count * static_cast<std::size_t>(per_light) + kSphereLightRaysSlack;
        std::vector<Ray> rays(room);
        std::vector<Vec3f> contribution(room);
        const std::size_t n = sphere_light_rays(lights, point.position, bsdf, wo, per_light, many, rays.data(), contribution.data());
        std::size_t k = 0;
        for (const SphereLight& light : lights) {
          const std::optional<SphereCone> cone = SphereCone::toward(light, point.position);
          for (int s = 0; s < per_light; ++s) {
            const float u = one.uniform(), v = one.uniform();
            if (!cone) continue;
            const LightSample sample = cone->sample(u, v);
            const Vec3f f = bsdf.eval(wo, sample.wi);
            if (!(max_component(f) > 0.0f)) continue;
            ASSERT_LT(k, n) << lights_count << " lights, " << per_light << " rays each, material " << m;
            const Ray& got = rays[k];
            const Vec3f expected = f * cone->radiance() * ((1.0f / static_cast<float>(per_light)) / cone->pdf());
            ASSERT_TRUE(same_bits(got.org, point.position) && same_bits(got.dir, sample.wi) && bits(got.tmin) == bits(0.0f) &&
                        bits(got.tmax) == bits(sample.distance * (1.0f - 1e-4f)) && same_bits(contribution[k], expected))
                << lights_count << " lights, " << per_light << " rays each, material " << m << ", ray " << k;
            ++k;
          }
        }
        EXPECT_EQ(k, n) << lights_count << " lights, " << per_light << " rays each, material " << m;
        EXPECT_EQ(one.next_u32(), many.next_u32()) << lights_count << " lights, " << per_light << " rays each";
        ++checked;
        kept_total += n;
      }
  EXPECT_GT(kept_total, checked * 4);  // the cases keep rays, not only skip them
}

TEST(SoftShadows, AnOccluderBetweenGroundAndLightDarkensTheGround) {
  Scene scene = lit_ground(1.0f, 0.2f, 10.0f);
  TriangleMesh blocker;
  blocker.name = "blocker";
  test::add_quad(blocker, {-0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, {-0.5f, 0.5f, 0.5f});
  scene.meshes.push_back(blocker);
  scene.add_instance(1);
  const Built built(scene);
  ShadingOptions o = quiet(2);
  o.ambient = 0.0f;
  // The camera must see the ground under the blocker: from below the blocker's height, to the side.
  const Camera camera = test::camera_looking_at({2.0f, 0.3f, 0.0f}, {0.0f, 0.0f, 0.0f}, 9, 9, 1.0f);
  EXPECT_EQ(mean(render_shaded(Integrator::softshadow, *built.queries, scene, camera, o)).x, 0.0f);
}

TEST(Raycast, PointLightShadesByDistanceAndAngleWithoutShadows) {
  Scene scene = test::plane_scene(200.0f);
  scene.materials[0].diffuse = Vec3f{0.5f};
  scene.point_lights.push_back(PointLight{{0.0f, 2.0f, 0.0f}, Vec3f{4.0f}});
  // A blocker right under the light: raycast ignores it for shading (no shadow rays).
  TriangleMesh blocker;
  blocker.name = "blocker";
  test::add_quad(blocker, {-0.1f, 1.0f, -0.1f}, {0.1f, 1.0f, -0.1f}, {0.1f, 1.0f, 0.1f}, {-0.1f, 1.0f, 0.1f});
  scene.meshes.push_back(blocker);
  scene.add_instance(1);
  const Built built(scene);
  RenderStats stats;
  const Image image = render_shaded(Integrator::raycast, *built.queries, scene, side_camera(), quiet(), &stats);
  // E = I / d^2 = 1 at the origin; radiance = albedo / pi * E + ambient 0.1 * albedo.
  EXPECT_NEAR(image.at(4, 4).x, 0.5f / std::numbers::pi_v<float> + 0.05f, 2e-3f);
  EXPECT_EQ(stats.rays, 81u);
  EXPECT_EQ(stats.by_kind.shadow, 0u);
}

TEST(Whitted, ThePointLightsShadowIsBlack) {
  Scene scene = test::plane_scene(200.0f);
  scene.point_lights.push_back(PointLight{{0.0f, 2.0f, 0.0f}, Vec3f{4.0f}});
  TriangleMesh blocker;
  blocker.name = "blocker";
  test::add_quad(blocker, {-0.5f, 1.0f, -0.5f}, {0.5f, 1.0f, -0.5f}, {0.5f, 1.0f, 0.5f}, {-0.5f, 1.0f, 0.5f});
  scene.meshes.push_back(blocker);
  scene.add_instance(1);
  const Built built(scene);
  ShadingOptions o = quiet();
  o.ambient = 0.0f;
  const Camera camera = test::camera_looking_at({2.0f, 0.3f, 0.0f}, {0.0f, 0.0f, 0.0f}, 9, 9, 1.0f);
  EXPECT_EQ(mean(render_shaded(Integrator::whitted, *built.queries, scene, camera, o)).x, 0.0f);
}

// A diffuse panel facing down at y = 1, lit by a point light under it, over a perfect mirror floor
// (or no floor). Looking at the mirror from (2, 0.5, 0) must show what a camera at the mirrored
// position (2, -0.5, 0), with the mirrored up vector, sees of the panel directly.
Scene mirror_scene(bool with_mirror) {
  Scene scene;
  TriangleMesh panel;
  panel.name = "panel";
  test::add_quad(panel, {-6.0f, 1.0f, -3.0f}, {0.0f, 1.0f, -3.0f}, {0.0f, 1.0f, 3.0f}, {-6.0f, 1.0f, 3.0f});
  scene.meshes.push_back(panel);
  scene.add_instance(0);
  if (with_mirror) {
    Material mirror;
    mirror.diffuse = Vec3f{0.0f};
    mirror.specular = Vec3f{1.0f};
    scene.materials.push_back(mirror);
    TriangleMesh floor = test::plane_scene(50.0f).meshes[0];
    scene.meshes.push_back(floor);
    Instance instance;
    instance.mesh = 1;
    instance.material = 1;
    scene.add_instance(instance);
  }
  scene.point_lights.push_back(PointLight{{-2.0f, 0.5f, 0.0f}, Vec3f{3.0f}});
  return scene;
}

TEST(Whitted, APerfectMirrorShowsTheMirroredView) {
  const Scene mirrored = mirror_scene(true), direct = mirror_scene(false);
  const Built a(mirrored), b(direct);
  Camera via_mirror = test::camera_looking_at({2.0f, 0.5f, 0.0f}, {0.0f, 0.0f, 0.0f}, 15, 15, 20.0f);
  via_mirror.up = {0.0f, 1.0f, 0.0f};
  Camera from_below = via_mirror;
  from_below.position = {2.0f, -0.5f, 0.0f};
  from_below.up = {0.0f, -1.0f, 0.0f};
  ShadingOptions o = quiet();
  o.ambient = 0.0f;
  RenderStats stats;
  const Image seen = render_shaded(Integrator::whitted, *a.queries, mirrored, via_mirror, o, &stats);
  const Image truth = render_shaded(Integrator::whitted, *b.queries, direct, from_below, o);
  EXPECT_GT(mean(truth).x, 0.01f);
  EXPECT_LT(max_difference(seen, truth), 2e-3f);
  EXPECT_EQ(stats.by_kind.reflection, 15u * 15u);  // every camera ray meets the mirror once
}

TEST(Whitted, GlassOfIndexOneIsInvisible) {
  // A closed box of index 1 between the camera and the panel: Fresnel 0, rays pass straight through
  // (in at the front, out at the back), so the image equals the one without the box.
  Scene with_box = mirror_scene(false), without = mirror_scene(false);
  Material glass;
  glass.diffuse = Vec3f{0.0f};
  glass.transmission = 1.0f;
  glass.ior = 1.0f;
  with_box.materials.push_back(glass);
  with_box.meshes.push_back(test::closed_box_scene().meshes[0]);
  Instance box;
  box.mesh = 1;
  box.material = 1;
  box.transform.scale = 0.3f;
  box.transform.translation = {1.0f, -0.1f, 0.0f};
  with_box.add_instance(box);
  const Built a(with_box), b(without);
  Camera camera = test::camera_looking_at({2.0f, -0.5f, 0.0f}, {0.0f, 0.0f, 0.0f}, 15, 15, 20.0f);
  camera.up = {0.0f, -1.0f, 0.0f};
  ShadingOptions o = quiet();
  o.ambient = 0.0f;
  RenderStats stats;
  const Image through = render_shaded(Integrator::whitted, *a.queries, with_box, camera, o, &stats);
  const Image truth = render_shaded(Integrator::whitted, *b.queries, without, camera, o);
  EXPECT_GT(stats.by_kind.reflection, 15u * 15u / 2);  // most camera rays cross the box
  EXPECT_LT(max_difference(through, truth), 2e-3f);
}

// Glossy reflections of an object represented by a field: the reflection's hit point and normal come
// from the distance and normal fields, so with a normal field the image is close to the exact one,
// and closer than without (where a field hit faces the ray and shades flat).
TEST(Glossy, ReflectionsOffAFieldObjectUseItsNormalField) {
  Scene scene;
  TriangleMesh box = test::closed_box_scene().meshes[0];
  box.occluder = MeshOccluder::field;
  scene.meshes.push_back(box);
  TriangleMesh floor = test::plane_scene(20.0f).meshes[0];
  floor.occluder = MeshOccluder::exact;
  scene.meshes.push_back(floor);
  Material mirror;
  mirror.diffuse = Vec3f{0.0f};
  mirror.specular = Vec3f{1.0f};
  scene.materials.push_back(mirror);
  Instance cube;
  cube.transform.translation = {0.0f, 1.5f, 0.0f};
  cube.transform.rotation = Mat3::euler_xyz({20.0f, 35.0f, 0.0f});
  scene.add_instance(cube);
  Instance ground;
  ground.mesh = 1;
  ground.material = 1;
  scene.add_instance(ground);
  scene.point_lights.push_back(PointLight{{3.0f, 6.0f, 4.0f}, Vec3f{60.0f}});
  // Looking down at the floor in front of the cube: every pixel is the mirror, most show the cube.
  const Camera camera = test::camera_looking_at({0.0f, 1.2f, 5.0f}, {0.0f, 0.0f, 1.2f}, 32, 32, 30.0f);
  SceneGeometry geometry(scene);
  const BuiltStructure bvh = build_structure("bvh", geometry);
  const BuiltStructure with_normals = build_structure("field:meshes=marked,positions=4226,directions=64,normals=oct16", geometry);
  const BuiltStructure without = build_structure("field:meshes=marked,positions=4226,directions=64", geometry);
  ShadingOptions o = quiet();
  o.glossy_rays = 1;
  auto render_with = [&](const BuiltStructure& occluder) {
    return render_shaded(Integrator::glossy, *scene_queries(bvh.structure, occluder.structure), scene, camera, o);
  };
  const Image exact = render_with(bvh), normals = render_with(with_normals), flat = render_with(without);
  const double rms_normals = compare_images(normals, exact).rms, rms_flat = compare_images(flat, exact).rms;
  EXPECT_LT(rms_normals, 0.05) << rms_normals;
  EXPECT_LT(rms_normals, 0.7 * rms_flat) << rms_normals << " vs " << rms_flat;
}

// The Cornell room dressed for every integrator: a mirror tall box, a glass sphere, a glossy short
// box, and a sphere light beside the ceiling lamp's point-light stand-in.
Scene dressed_cornell() {
  Scene scene = make_builtin_scene("cornell");
  auto add = [&](Material m) {
    scene.materials.push_back(m);
    return static_cast<std::uint32_t>(scene.materials.size() - 1);
  };
  Material mirror;
  mirror.name = "mirror";
  mirror.diffuse = Vec3f{0.1f};
  mirror.specular = Vec3f{0.85f};
  Material glass;
  glass.name = "glass";
  glass.diffuse = Vec3f{0.0f};
  glass.transmission = 1.0f;
  glass.ior = 1.5f;
  Material glossy;
  glossy.name = "glossy";
  glossy.diffuse = Vec3f{0.4f, 0.4f, 0.6f};
  glossy.specular = Vec3f{0.5f};
  glossy.roughness = 0.3f;
  const std::uint32_t ids[] = {add(glossy), add(mirror), add(glass)};
  std::vector<Instance> objects = scene.instances();
  for (std::size_t i = 1; i < objects.size() && i <= 3; ++i) {
    scene.remove_instance(objects[i].id);
    objects[i].material = ids[i - 1];
    scene.add_instance(objects[i]);
  }
  scene.sphere_lights.push_back(SphereLight{{0.5f, 1.6f, 0.6f}, 0.1f, Vec3f{8.0f}});
  return scene;
}

Camera small_camera(const Scene& scene, int size) { return scene.camera_or_default(size, size); }

constexpr Integrator kShaded[] = {Integrator::raycast, Integrator::whitted, Integrator::softshadow, Integrator::glossy,
                                  Integrator::path};

ShadingOptions golden_options(Integrator integrator) {
  ShadingOptions o = quiet(integrator == Integrator::path ? 16 : 2);
  o.shadow_rays = 4;
  return o;
}

TEST(Integrators, EveryExactStructureGivesTheSameImages) {
  const Scene scene = dressed_cornell();
  const Camera camera = small_camera(scene, 24);
  const Built reference(scene, "bvh");
  for (const std::string& name : structure_names()) {
    if (find_structure(name).exactness != Exactness::exact || name == "bvh" || name == "auto") continue;
    const Built other(scene, name);
    for (Integrator integrator : kShaded) {
      const ShadingOptions o = golden_options(integrator);
      const Image a = render_shaded(integrator, *reference.queries, scene, camera, o);
      const Image b = render_shaded(integrator, *other.queries, scene, camera, o);
      std::size_t differing = 0;
      for (std::size_t i = 0; i < a.pixels.size(); ++i) differing += a.pixels[i] == b.pixels[i] ? 0 : 1;
      // Exact structures give the oracle's hits bit for bit, ties to the lowest index included: the
      // same rays, the same images.
      EXPECT_EQ(differing, 0u) << name << " " << integrator_name(integrator);
    }
    AoOptions ao;
    ao.progress = false;
    ao.ao_rays = 8;
    const Image a = render_ao(*reference.queries, scene, camera, ao), b = render_ao(*other.queries, scene, camera, ao);
    EXPECT_EQ(max_difference(a, b), 0.0f) << name;
  }
}

TEST(Integrators, ImagesDoNotDependOnTheThreadCount) {
  const Scene scene = dressed_cornell();
  const Built built(scene);
  for (Integrator integrator : kShaded) {
    Image one, two;
    {
      const ThreadLimit limit(1);
      one = render_shaded(integrator, *built.queries, scene, small_camera(scene, 20), golden_options(integrator));
    }
    {
      const ThreadLimit limit(2);
      two = render_shaded(integrator, *built.queries, scene, small_camera(scene, 20), golden_options(integrator));
    }
    EXPECT_EQ(one.pixels, two.pixels) << integrator_name(integrator);
  }
}

// Golden images: the dressed room at 32x32, stored as 8-bit PNGs under tests/data/golden. A render
// matches when its PNG differs by RMS <= 1.0 and at most 8 levels in any channel (room for other
// compilers' and ISAs' rounding, far below a visible change). VISFIELD_UPDATE_GOLDEN=1 rewrites them.
TEST(Integrators, GoldenImagesOfTheDressedCornellRoom) {
  const Scene scene = dressed_cornell();
  const Built built(scene);
  const std::filesystem::path folder = std::filesystem::path(VISFIELD_SOURCE_DIR) / "tests" / "data" / "golden";
  const bool update = std::getenv("VISFIELD_UPDATE_GOLDEN") != nullptr;
  for (Integrator integrator : kIntegrators) {
    Image image;
    if (integrator == Integrator::ao) {
      AoOptions ao;
      ao.progress = false;
      ao.ao_rays = 16;
      image = render_ao(*built.queries, scene, small_camera(scene, 32), ao);
    } else {
      image = render_shaded(integrator, *built.queries, scene, small_camera(scene, 32), golden_options(integrator));
    }
    const std::filesystem::path golden = folder / ("cornell-" + std::string(integrator_name(integrator)) + ".png");
    const std::filesystem::path rendered =
        std::filesystem::path(VISFIELD_TEST_BINARY_DIR) / ("cornell-" + std::string(integrator_name(integrator)) + ".png");
    write_image(rendered, image);
    if (update) write_image(golden, image);
    ASSERT_TRUE(std::filesystem::exists(golden)) << golden;
    const ImageDifference d = compare_images(read_image(rendered), read_image(golden));
    EXPECT_LE(d.rms * 255.0, 1.0) << integrator_name(integrator);
    EXPECT_LE(d.max_abs * 255.0, 8.0) << integrator_name(integrator);
  }
}

TEST(Integrators, BadOptionsAreRefused) {
  const Scene scene = test::plane_scene(1.0f);
  const Built built(scene);
  const Camera camera = side_camera();
  for (auto set : {+[](ShadingOptions& o) { o.spp = 0; }, +[](ShadingOptions& o) { o.max_depth = 0; },
                   +[](ShadingOptions& o) { o.shadow_rays = 0; }, +[](ShadingOptions& o) { o.glossy_rays = -1; },
                   +[](ShadingOptions& o) { o.ambient = -1.0f; }, +[](ShadingOptions& o) { o.tile_size = 0; }}) {
    ShadingOptions o = quiet();
    set(o);
    EXPECT_THROW(render_shaded(Integrator::raycast, *built.queries, scene, camera, o), Error);
  }
  EXPECT_THROW(render_shaded(Integrator::ao, *built.queries, scene, camera, quiet()), Error);
}

TEST(Integrators, NamesRoundTrip) {
  for (Integrator integrator : kIntegrators) EXPECT_EQ(parse_integrator(integrator_name(integrator)), integrator);
  EXPECT_FALSE(parse_integrator("phong"));
}

}  // namespace
}  // namespace vf
