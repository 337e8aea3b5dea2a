// The C API against the C++ library on the same rays: every answer equal bit for bit, through the
// array-of-structures and the structure-of-arrays calls, for exact structures and fields; BeamField
// updates through the C calls equal a fresh build; every error comes back as a code and one line,
// through vf_last_error_message() and the callback, and nothing throws across the boundary.

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "differential/ray_sets.hpp"
#include "support/test_scale.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/field/field_file.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/scene_geometry.hpp"
#include "visfield/registry/structure_queries.hpp"
#include "visfield/visfield.h"

namespace vf {
namespace {

// The row-major 3x4 matrix [s*R | t] the C API takes for `t`.
std::array<float, 12> matrix_of(const Transform& t) {
  std::array<float, 12> m{};
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) m[static_cast<std::size_t>(4 * r + k)] = t.rotation.rows[static_cast<std::size_t>(r)][k] * t.scale;
    m[static_cast<std::size_t>(4 * r + 3)] = t.translation[r];
  }
  return m;
}

// A C scene made from the arrays of a C++ scene's meshes and objects (the same ids, in order).
vf_scene c_scene_of(const Scene& scene) {
  vf_scene c = nullptr;
  EXPECT_EQ(vf_scene_create(&c), VF_OK);
  for (const TriangleMesh& m : scene.meshes) {
    std::vector<float> v;
    for (const Vec3f& p : m.positions) v.insert(v.end(), {p.x, p.y, p.z});
    std::vector<std::uint32_t> i;
    for (const TriangleIndices& t : m.triangles) i.insert(i.end(), {t[0], t[1], t[2]});
    std::uint32_t index = 0;
    EXPECT_EQ(vf_scene_add_mesh(c, v.data(), m.positions.size(), i.data(), m.triangles.size(), &index), VF_OK) << vf_last_error_message();
  }
  for (const Instance& o : scene.instances()) {
    const std::array<float, 12> m = matrix_of(o.transform);
    std::uint32_t id = 0;
    EXPECT_EQ(vf_scene_add_instance(c, o.mesh, o.transform.is_identity() ? nullptr : m.data(), &id), VF_OK) << vf_last_error_message();
    EXPECT_EQ(id, o.id);
  }
  return c;
}

std::vector<vf_ray> c_rays(const std::vector<Ray>& rays) {
  std::vector<vf_ray> out(rays.size());
  std::memcpy(out.data(), rays.data(), rays.size() * sizeof(Ray));
  return out;
}

void expect_same_hits(const std::vector<Hit>& expected, const std::vector<vf_hit>& got, const std::string& what) {
  ASSERT_EQ(expected.size(), got.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const Hit& e = expected[i];
    const vf_hit& g = got[i];
    const bool same = std::memcmp(&e.t, &g.t, sizeof(float)) == 0 && e.u == g.u && e.v == g.v && e.prim == g.prim &&
                      e.instance == g.instance && e.normal.x == g.ng_x && e.normal.y == g.ng_y && e.normal.z == g.ng_z;
    if (!same && ++differ <= 3) ADD_FAILURE() << what << ": ray " << i << " t " << e.t << " vs " << g.t << ", object " << e.instance << " vs " << g.instance;
  }
  EXPECT_EQ(differ, 0u) << what;
}

struct CApiStructures : ::testing::TestWithParam<const char*> {};

TEST_P(CApiStructures, AnswersEqualTheCppApiOnTheSameRays) {
  const Scene scene = load_scene("builtin:boxes:size=40,seed=3");
  SceneGeometry geometry(scene);
  const BuiltStructure cpp = build_structure(GetParam(), geometry);
  std::vector<Ray> rays = test::random_rays(flatten(scene), 11, 20000);
  for (std::size_t i = 1; i < rays.size(); i += 2) rays[i].tmax = 0.3f * max_component(scene.bounds().extent());

  vf_scene c = nullptr;
  ASSERT_EQ(vf_scene_load("builtin:boxes:size=40,seed=3", &c), VF_OK);  // the very scene the C++ side loaded
  vf_structure s = nullptr;
  ASSERT_EQ(vf_structure_build(c, GetParam(), &s), VF_OK) << vf_last_error_message();
  EXPECT_EQ(std::string(vf_structure_spec(s)), cpp.resolved);

  std::vector<Hit> expected(rays.size());
  intersect_batch(cpp.structure, rays, expected);
  std::vector<std::uint8_t> expected_occluded(rays.size());
  occluded_batch(cpp.structure, rays, expected_occluded);

  const std::vector<vf_ray> cr = c_rays(rays);
  std::vector<vf_hit> hits(rays.size());
  ASSERT_EQ(vf_intersect(s, cr.data(), cr.size(), hits.data()), VF_OK) << vf_last_error_message();
  expect_same_hits(expected, hits, "vf_intersect");
  std::vector<std::uint8_t> occluded(rays.size(), 7);
  ASSERT_EQ(vf_occluded(s, cr.data(), cr.size(), occluded.data()), VF_OK);
  EXPECT_EQ(occluded, expected_occluded);

  // Structure of arrays, tmin/tmax given for half, defaulted for the other half.
  std::vector<float> col[8];
  for (auto& c8 : col) c8.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const float v[8] = {rays[i].org.x, rays[i].org.y, rays[i].org.z, rays[i].dir.x, rays[i].dir.y, rays[i].dir.z, rays[i].tmin, rays[i].tmax};
    for (int k = 0; k < 8; ++k) col[k][i] = v[k];
  }
  const vf_rays_soa soa{col[0].data(), col[1].data(), col[2].data(), col[3].data(), col[4].data(), col[5].data(), col[6].data(), col[7].data()};
  std::vector<float> t(rays.size()), u(rays.size()), v(rays.size()), nx(rays.size()), ny(rays.size()), nz(rays.size());
  std::vector<std::uint32_t> prim(rays.size()), instance(rays.size());
  const vf_hits_soa out{t.data(), u.data(), v.data(), prim.data(), instance.data(), nx.data(), ny.data(), nz.data()};
  ASSERT_EQ(vf_intersect_soa(s, &soa, rays.size(), &out), VF_OK) << vf_last_error_message();
  std::vector<vf_hit> from_soa(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) from_soa[i] = vf_hit{t[i], u[i], v[i], prim[i], instance[i], nx[i], ny[i], nz[i]};
  expect_same_hits(expected, from_soa, "vf_intersect_soa");
  std::fill(occluded.begin(), occluded.end(), 7);
  ASSERT_EQ(vf_occluded_soa(s, &soa, rays.size(), occluded.data()), VF_OK);
  EXPECT_EQ(occluded, expected_occluded);

  vf_structure_stats stats{};
  ASSERT_EQ(vf_structure_get_stats(s, &stats), VF_OK);
  EXPECT_EQ(stats.memory_bytes, structure_stats(cpp.structure).memory_bytes);
  vf_structure_release(s);
  vf_scene_release(c);
}

INSTANTIATE_TEST_SUITE_P(Registry, CApiStructures,
                         ::testing::Values("bvh", "kdtree", "grid", "median-bsp", "bvh:levels=2", "beam:dirs=33,n=16", "field:positions=290,directions=16"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

TEST(CApi, AutoSpecsPlanTheWorkloadAndNameTheChoice) {
  vf_scene c = nullptr;
  ASSERT_EQ(vf_scene_load("builtin:sphere", &c), VF_OK);  // 20,000 triangles: fields beat the BVH per ray
  vf_structure loose = nullptr, exact = nullptr;
  ASSERT_EQ(vf_structure_build(c, "auto:rays=1000000000000,kind=ao,error=255", &loose), VF_OK) << vf_last_error_message();
  const std::string planned = vf_structure_spec(loose);
  EXPECT_EQ(planned.rfind("auto:kind=ao,rays=1000000000000,error=255 -> field:", 0), 0u) << planned;
  ASSERT_EQ(vf_structure_build(c, "auto:rays=1000000000000,kind=ao", &exact), VF_OK) << vf_last_error_message();
  EXPECT_EQ(std::string(vf_structure_spec(exact)).find("-> field:"), std::string::npos) << vf_structure_spec(exact);
  EXPECT_EQ(vf_structure_build(c, "auto:error=300", &exact), VF_ERROR_INVALID_ARGUMENT);
  vf_structure_release(loose);
  vf_structure_release(exact);
  vf_scene_release(c);
}

TEST(CApi, ScenesFromArraysEqualTheSceneTheyCopy) {
  // Identity objects: the C scene holds the same triangles bit for bit, so every answer is equal.
  Scene scene = load_scene("builtin:soup:size=2000,seed=4");
  vf_scene c = c_scene_of(scene);
  std::size_t meshes = 0, objects = 0, triangles = 0;
  ASSERT_EQ(vf_scene_counts(c, &meshes, &objects, &triangles), VF_OK);
  EXPECT_EQ(meshes, scene.meshes.size());
  EXPECT_EQ(objects, scene.instances().size());
  EXPECT_EQ(triangles, scene.instanced_triangle_count());
  float lo[3], hi[3];
  ASSERT_EQ(vf_scene_bounds(c, lo, hi), VF_OK);
  EXPECT_EQ(lo[0], scene.bounds().lo.x);
  EXPECT_EQ(hi[2], scene.bounds().hi.z);
  SceneGeometry geometry(scene);
  const BuiltStructure cpp = build_structure("bvh", geometry);
  vf_structure s = nullptr;
  ASSERT_EQ(vf_structure_build(c, "bvh", &s), VF_OK);
  const std::vector<Ray> rays = test::random_rays(flatten(scene), 5, 5000);
  std::vector<Hit> expected(rays.size());
  intersect_batch(cpp.structure, rays, expected);
  const std::vector<vf_ray> cr = c_rays(rays);
  std::vector<vf_hit> hits(rays.size());
  ASSERT_EQ(vf_intersect(s, cr.data(), cr.size(), hits.data()), VF_OK);
  expect_same_hits(expected, hits, "scene from arrays");

  // A placed object: the 3x4 matrix [s·R | t] becomes the same map (to float rounding).
  Transform t;
  t.rotation = Mat3::rotation(normalize(Vec3f{1, 2, 3}), 40.0f);
  t.scale = 2.5f;
  t.translation = Vec3f{1, -2, 3};
  float m[12];
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) m[4 * r + k] = t.rotation.rows[static_cast<std::size_t>(r)][k] * t.scale;
    m[4 * r + 3] = t.translation[r];
  }
  std::uint32_t id = 0;
  ASSERT_EQ(vf_scene_add_instance(c, 0, m, &id), VF_OK) << vf_last_error_message();
  const ObjectId cpp_id = scene.add_instance(0, t);
  EXPECT_EQ(id, cpp_id);
  ASSERT_EQ(vf_scene_bounds(c, lo, hi), VF_OK);
  const Bounds3f b = scene.bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(lo[k], b.lo[k], 1e-5f * (1 + std::fabs(b.lo[k])));
    EXPECT_NEAR(hi[k], b.hi[k], 1e-5f * (1 + std::fabs(b.hi[k])));
  }
  ASSERT_EQ(vf_scene_remove_instance(c, id), VF_OK);
  EXPECT_EQ(vf_scene_remove_instance(c, id), VF_ERROR_INVALID_ARGUMENT);
  vf_structure_release(s);
  vf_scene_release(c);
}

TEST(CApi, BeamFieldMovesThroughTheCApiEqualAFreshBuild) {
  Scene scene = load_scene("builtin:boxes:size=12,seed=5");
  vf_scene c = c_scene_of(scene);
  vf_structure beam = nullptr;
  ASSERT_EQ(vf_structure_build(c, "beam:dirs=33,n=16", &beam), VF_OK) << vf_last_error_message();
  const ObjectId moved = scene.instances()[3].id;
  const float m[12] = {0, -1, 0, 0.3f, 1, 0, 0, 0.1f, 0, 0, 1, -0.2f};  // 90° about z, shifted
  ASSERT_EQ(vf_structure_move(beam, moved, m), VF_OK) << vf_last_error_message();
  ASSERT_EQ(vf_structure_commit(beam), VF_OK);
  ASSERT_EQ(vf_scene_set_transform(c, moved, m), VF_OK);
  vf_structure fresh = nullptr;
  ASSERT_EQ(vf_structure_build(c, "beam:dirs=33,n=16", &fresh), VF_OK);
  const std::vector<vf_ray> rays = c_rays(test::random_rays(flatten(scene), 3, 20000));
  std::vector<vf_hit> a(rays.size()), b(rays.size());
  ASSERT_EQ(vf_intersect(beam, rays.data(), rays.size(), a.data()), VF_OK);
  ASSERT_EQ(vf_intersect(fresh, rays.data(), rays.size(), b.data()), VF_OK);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(vf_hit)), 0);
  // Remove and insert again: the same answers once more.
  ASSERT_EQ(vf_structure_remove(beam, moved), VF_OK);
  ASSERT_EQ(vf_structure_commit(beam), VF_OK);
  ASSERT_EQ(vf_structure_insert(beam, c, moved), VF_OK) << vf_last_error_message();
  ASSERT_EQ(vf_structure_commit(beam), VF_OK);
  ASSERT_EQ(vf_intersect(beam, rays.data(), rays.size(), a.data()), VF_OK);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(vf_hit)), 0);
  vf_structure_release(beam);
  vf_structure_release(fresh);
  vf_scene_release(c);
}

TEST(CApi, FieldsBuildSaveLoadAndAnswerAsTheCppField) {
  const Scene scene = load_scene("builtin:sphere");
  vf_scene c = c_scene_of(scene);
  vf_field f = nullptr;
  ASSERT_EQ(vf_field_build(c, 0, "positions=290,directions=16,normals=oct16", &f), VF_OK) << vf_last_error_message();
  vf_field_info info{};
  ASSERT_EQ(vf_field_get_info(f, &info), VF_OK);
  EXPECT_EQ(info.positions, 290u);
  EXPECT_EQ(info.directions, 16u);
  EXPECT_EQ(info.has_normals, 1);

  field::ObjectFieldConfig config;
  config.positions = 290, config.directions = 16, config.normals = field::NormalStorage::oct16;
  const field::ObjectField cpp = field::ObjectField::build(mesh_triangles(scene.meshes[0]), config);
  const std::vector<Ray> rays = test::random_rays(flatten(scene), 9, 5000);
  std::vector<vf_hit> hits(rays.size());
  std::vector<std::uint8_t> occluded(rays.size());
  const std::vector<vf_ray> cr = c_rays(rays);
  ASSERT_EQ(vf_field_intersect(f, cr.data(), cr.size(), hits.data()), VF_OK);
  ASSERT_EQ(vf_field_occluded(f, cr.data(), cr.size(), occluded.data()), VF_OK);
  std::size_t hit_count = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const field::FieldAnswer a = cpp.trace(rays[i].org, rays[i].dir, rays[i].tmin, rays[i].tmax);
    ASSERT_EQ(a.hit, occluded[i] == 1) << i;
    ASSERT_EQ(a.hit, hits[i].t < INFINITY) << i;
    if (!a.hit) continue;
    ++hit_count;
    EXPECT_EQ(a.t, hits[i].t) << i;
    EXPECT_EQ(a.normal.x, hits[i].ng_x) << i;
    EXPECT_EQ(hits[i].prim, VF_INVALID_ID);
  }
  EXPECT_GT(hit_count, 100u);
  EXPECT_LT(hit_count, rays.size());

  const std::filesystem::path path = std::filesystem::path(VISFIELD_TEST_BINARY_DIR) / "capi-sphere.vfield";
  ASSERT_EQ(vf_field_save(f, path.c_str()), VF_OK) << vf_last_error_message();
  vf_field loaded = nullptr;
  ASSERT_EQ(vf_field_load(path.c_str(), c, 0, &loaded), VF_OK) << vf_last_error_message();
  std::vector<vf_hit> again(rays.size());
  ASSERT_EQ(vf_field_intersect(loaded, cr.data(), cr.size(), again.data()), VF_OK);
  EXPECT_EQ(std::memcmp(hits.data(), again.data(), hits.size() * sizeof(vf_hit)), 0);

  // A file of another mesh is refused as bad input.
  vf_scene other = c_scene_of(load_scene("builtin:boxes:size=2,seed=1"));
  vf_field wrong = nullptr;
  EXPECT_EQ(vf_field_load(path.c_str(), other, 0, &wrong), VF_ERROR_BAD_INPUT);
  EXPECT_EQ(wrong, nullptr);
  EXPECT_NE(std::string(vf_last_error_message()).find("another mesh"), std::string::npos) << vf_last_error_message();
  vf_field_release(loaded);
  vf_field_release(f);
  vf_scene_release(other);
  vf_scene_release(c);
  std::filesystem::remove(path);
}

struct Recorded {
  int calls = 0;
  vf_error code = VF_OK;
  std::string message;
};

TEST(CApi, ErrorsComeBackAsCodesAndOneLine) {
  Recorded seen;
  vf_set_error_callback(
      [](vf_error code, const char* message, void* user) {
        auto* r = static_cast<Recorded*>(user);
        ++r->calls, r->code = code, r->message = message;
      },
      &seen);
  vf_structure s = nullptr;
  EXPECT_EQ(vf_structure_build(nullptr, "bvh", &s), VF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(std::string(vf_last_error_message()), "scene is NULL");
  EXPECT_EQ(seen.calls, 1);
  EXPECT_EQ(seen.code, VF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(seen.message, "scene is NULL");

  vf_scene scene = nullptr;
  ASSERT_EQ(vf_scene_load("builtin:sphere", &scene), VF_OK);
  EXPECT_EQ(vf_last_error(), VF_OK);
  EXPECT_EQ(vf_structure_build(scene, "bvh:leaf=0", &s), VF_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(vf_last_error_message()).find("leaf"), std::string::npos) << vf_last_error_message();
  EXPECT_EQ(vf_structure_build(scene, "octree", &s), VF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(s, nullptr);

  vf_scene missing = nullptr;
  EXPECT_EQ(vf_scene_load("/nonexistent/model.obj", &missing), VF_ERROR_BAD_INPUT);
  EXPECT_NE(std::string(vf_last_error_message()).find("no such file"), std::string::npos) << vf_last_error_message();

  const float vertices[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint32_t bad_indices[] = {0, 1, 5};
  std::uint32_t mesh = 0;
  EXPECT_EQ(vf_scene_add_mesh(scene, vertices, 3, bad_indices, 1, &mesh), VF_ERROR_INVALID_ARGUMENT);
  const float shear[12] = {1, 0.5f, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  std::uint32_t id = 0;
  EXPECT_EQ(vf_scene_add_instance(scene, 0, shear, &id), VF_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(vf_last_error_message()).find("rotation"), std::string::npos);
  EXPECT_EQ(vf_scene_add_instance(scene, 9, nullptr, &id), VF_ERROR_INVALID_ARGUMENT);

  ASSERT_EQ(vf_structure_build(scene, "bvh", &s), VF_OK);
  EXPECT_EQ(vf_structure_move(s, 0, nullptr), VF_ERROR_UNSUPPORTED);
  EXPECT_EQ(vf_structure_commit(s), VF_ERROR_UNSUPPORTED);
  EXPECT_EQ(vf_intersect(s, nullptr, 3, nullptr), VF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(vf_intersect(s, nullptr, 0, nullptr), VF_OK);  // an empty batch needs no arrays

  vf_structure beam = nullptr;
  ASSERT_EQ(vf_structure_build(scene, "beam:dirs=33,n=16", &beam), VF_OK);
  EXPECT_EQ(vf_structure_remove(beam, 12345), VF_ERROR_INVALID_ARGUMENT);

  // Refused from its estimate before allocating (8193 lines x 1024² tiles: tens of GiB of tile tables).
  vf_structure big = nullptr;
  EXPECT_EQ(vf_structure_build(scene, "beam:dirs=8193,n=1024", &big), VF_ERROR_OUT_OF_MEMORY);
  EXPECT_NE(std::string(vf_last_error_message()).find("would need about"), std::string::npos) << vf_last_error_message();
  EXPECT_EQ(big, nullptr);
  EXPECT_EQ(vf_set_threads(-1), VF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(vf_set_threads(0), VF_OK);

  vf_set_error_callback(nullptr, nullptr);
  const int calls = seen.calls;
  EXPECT_EQ(vf_structure_build(nullptr, nullptr, &s), VF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(seen.calls, calls);  // removed
  vf_structure_release(beam);
  vf_structure_release(s);
  vf_scene_release(scene);
  vf_scene_release(nullptr);  // accepted
}

TEST(CApi, StaleForgedAndForeignHandlesAndOverflowingCountsAreErrors) {
  vf_scene scene = nullptr;
  ASSERT_EQ(vf_scene_load("builtin:sphere", &scene), VF_OK);
  vf_structure bvh = nullptr;
  ASSERT_EQ(vf_structure_build(scene, "bvh", &bvh), VF_OK);
  vf_field field = nullptr;
  ASSERT_EQ(vf_field_build(scene, 0, "positions=290,directions=8", &field), VF_OK);
  const vf_ray ray{0, 0, 5, 0, 0, -1, 0, INFINITY};
  vf_hit hit{};
  ASSERT_EQ(vf_intersect(bvh, &ray, 1, &hit), VF_OK);
  EXPECT_TRUE(std::isfinite(hit.t));

  const auto refused = [](vf_error code, const std::string& needle) {
    EXPECT_EQ(code, VF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(vf_last_error_message()).find(needle), std::string::npos) << vf_last_error_message();
  };
  // An overflowing count is refused before any array is read (the arrays here hold one ray).
  std::uint8_t blocked = 0;
  refused(vf_intersect(bvh, &ray, SIZE_MAX / 8, &hit), "would not fit in memory");
  refused(vf_occluded(bvh, &ray, SIZE_MAX, &blocked), "would not fit in memory");
  refused(vf_field_intersect(field, &ray, SIZE_MAX / 16 + 1, &hit), "would not fit in memory");
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint32_t tri[3] = {0, 1, 2};
  refused(vf_scene_add_mesh(scene, v, SIZE_MAX / 4, tri, 1, nullptr), "would not fit in memory");

  // A handle of another kind, and handles never made.
  refused(vf_intersect(reinterpret_cast<vf_structure>(scene), &ray, 1, &hit), "not a live structure handle");
  refused(vf_scene_counts(reinterpret_cast<vf_scene>(bvh), nullptr, nullptr, nullptr), "not a live scene handle");
  refused(vf_field_occluded(reinterpret_cast<vf_field>(bvh), &ray, 1, &blocked), "not a live field handle");
  for (const std::uintptr_t forged : {std::uintptr_t{1}, std::uintptr_t{0xdeadbeef}, reinterpret_cast<std::uintptr_t>(&hit),
                                      reinterpret_cast<std::uintptr_t>(bvh) + 1, reinterpret_cast<std::uintptr_t>(bvh) ^ (std::uintptr_t{1} << 40)}) {
    refused(vf_intersect(reinterpret_cast<vf_structure>(forged), &ray, 1, &hit), "not a live structure handle");
    refused(vf_structure_release(reinterpret_cast<vf_structure>(forged)), "not a live structure handle");
  }
  EXPECT_STREQ(vf_structure_spec(reinterpret_cast<vf_structure>(scene)), "");

  // Released twice, and used after release: errors, and the process goes on.
  const vf_structure stale = bvh;
  EXPECT_EQ(vf_structure_release(bvh), VF_OK);
  refused(vf_structure_release(stale), "not a live structure handle");
  refused(vf_intersect(stale, &ray, 1, &hit), "not a live structure handle");
  refused(vf_structure_commit(stale), "not a live structure handle");
  EXPECT_EQ(vf_field_release(field), VF_OK);
  refused(vf_field_release(field), "not a live field handle");
  // A new handle in the freed slot is not the stale one.
  vf_structure again = nullptr;
  ASSERT_EQ(vf_structure_build(scene, "grid", &again), VF_OK);
  EXPECT_NE(again, stale);
  refused(vf_intersect(stale, &ray, 1, &hit), "not a live structure handle");
  ASSERT_EQ(vf_intersect(again, &ray, 1, &hit), VF_OK);
  EXPECT_EQ(vf_scene_release(scene), VF_OK);
  refused(vf_scene_release(scene), "not a live scene handle");
  ASSERT_EQ(vf_intersect(again, &ray, 1, &hit), VF_OK) << "a structure outlives its scene's handle";
  EXPECT_EQ(vf_structure_release(again), VF_OK);
  EXPECT_EQ(vf_structure_release(nullptr), VF_OK);
}

// Queries on two threads while a third moves every object back and forth and commits: each batch's
// answers are those of the structure before or after a commit (fresh builds of the two placements),
// never of a state between.
TEST(CApiThreads, QueriesRacingCommitsSeeTheStructureBeforeOrAfterACommit) {
  Scene scene = load_scene("builtin:boxes:size=8,seed=3");
  Scene moved = scene;
  for (const Instance& o : scene.instances()) {
    Transform t = o.transform;
    t.translation += Vec3f{0.25f, 0.1f, -0.15f};
    moved.set_transform(o.id, t);
  }
  const std::vector<vf_ray> rays = c_rays(test::random_rays(flatten(scene), 7, test::scaled_count(4000)));
  // A fresh build of `spec` over the C scene with every object placed as in `placed`.
  const auto answers_of = [&](const char* spec, const Scene& placed) {
    vf_scene c = c_scene_of(scene);
    for (const Instance& o : placed.instances()) EXPECT_EQ(vf_scene_set_transform(c, o.id, matrix_of(o.transform).data()), VF_OK);
    vf_structure fresh = nullptr;
    EXPECT_EQ(vf_structure_build(c, spec, &fresh), VF_OK);
    std::vector<vf_hit> hits(rays.size());
    EXPECT_EQ(vf_intersect(fresh, rays.data(), rays.size(), hits.data()), VF_OK);
    vf_structure_release(fresh);
    vf_scene_release(c);
    return hits;
  };

  for (const char* spec : {"beam:dirs=33,n=16", "bvh:levels=2"}) {
    const std::vector<vf_hit> before = answers_of(spec, scene), after = answers_of(spec, moved);
    ASSERT_NE(std::memcmp(before.data(), after.data(), before.size() * sizeof(vf_hit)), 0);
    vf_scene c = c_scene_of(scene);
    vf_structure s = nullptr;
    ASSERT_EQ(vf_structure_build(c, spec, &s), VF_OK) << vf_last_error_message();
    std::atomic<bool> done{false};
    std::atomic<int> mixed{0}, failed{0}, batches{0};
    const auto query = [&] {
      std::vector<vf_hit> hits(rays.size());
      while (!done.load()) {
        if (vf_intersect(s, rays.data(), rays.size(), hits.data()) != VF_OK) ++failed;
        const std::size_t bytes = hits.size() * sizeof(vf_hit);
        if (std::memcmp(hits.data(), before.data(), bytes) != 0 && std::memcmp(hits.data(), after.data(), bytes) != 0) ++mixed;
        ++batches;
      }
    };
    std::thread a(query), b(query);
    // Each round of edits starts while queries are under way (two more batches seen since the last).
    const auto queries_running = [&] {
      const int seen = batches.load();
      while (batches.load() < seen + 2) std::this_thread::yield();
    };
    for (int round = 0; round < 2; ++round)
      for (const Scene* placed : {&moved, &scene}) {
        queries_running();
        for (const Instance& o : placed->instances()) {
          const std::array<float, 12> m = matrix_of(o.transform);
          if (vf_structure_move(s, o.id, m.data()) != VF_OK) ++failed;
        }
        if (vf_structure_commit(s) != VF_OK) ++failed;
      }
    done = true;
    a.join();
    b.join();
    EXPECT_EQ(failed.load(), 0) << spec;
    EXPECT_EQ(mixed.load(), 0) << spec << ": a batch answered for a state between commits";
    EXPECT_GT(batches.load(), 0) << spec;
    vf_structure_release(s);
    vf_scene_release(c);
  }
}

}  // namespace
}  // namespace vf
