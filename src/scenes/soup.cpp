// "soup": uniformly distributed random triangles, the artificial scene of the VLF-RT paper's scaling
// test (Havran-style random triangles; paper section 6.1, figures 4 and 5).
//
// The paper says only "uniformly distributed random triangles" and shows the 9K and 16K scenes; it
// gives no triangle size or shape. We follow it and fix what it leaves open: each triangle gets a
// centre uniform in the unit cube [0,1]^3 (shrunk by half of kTriangleSpan on every side) and three
// corners drawn independently and uniformly from the cube of side kTriangleSpan (10% of the scene
// cube) around that centre, so every corner lies inside [0,1]^3. The triangle size does not depend on
// the count, so the scene grows denser (more depth complexity) as the count rises, as in the paper's
// scaling test.

#include <tbb/blocked_range.h>

#include "generators.hpp"
#include "mesh_builders.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::scenes {
namespace {

constexpr float kTriangleSpan = 0.1f;  // side of the cube each triangle's corners are drawn from

}  // namespace

Scene make_soup_scene(std::uint64_t seed, std::size_t triangles) {
  TriangleMesh mesh;
  mesh.name = "soup";
  mesh.positions.resize(3 * triangles);
  mesh.triangles.resize(triangles);
  // One generator per triangle, keyed by its index: the soup is the same whatever the thread count.
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, triangles, 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      Rng rng(seed, i);
      const Vec3f centre{0.5f * kTriangleSpan + (1.0f - kTriangleSpan) * rng.uniform(),
                         0.5f * kTriangleSpan + (1.0f - kTriangleSpan) * rng.uniform(),
                         0.5f * kTriangleSpan + (1.0f - kTriangleSpan) * rng.uniform()};
      Vec3f corner[3];
      do {  // redraw the (astronomically rare) zero-area triangle from the same stream
        for (Vec3f& c : corner)
          c = centre + Vec3f{rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f} * kTriangleSpan;
      } while (is_degenerate_triangle(corner[0], corner[1], corner[2]));
      const auto first = static_cast<std::uint32_t>(3 * i);
      for (int k = 0; k < 3; ++k) mesh.positions[first + k] = corner[k];
      mesh.triangles[i] = {first, first + 1, first + 2};
    }
  });

  Scene scene;
  scene.materials[0] = make_material("soup", Vec3f{0.75f});
  scene.meshes.push_back(std::move(mesh));
  scene.add_instance(Instance{});
  Bounds3f cube;
  cube.extend(Vec3f{0.0f});
  cube.extend(Vec3f{1.0f});
  scene.camera = framing_camera(cube, {0.55f, 0.45f, 1.0f}, 45.0f);
  scene.point_lights.push_back(PointLight{{1.6f, 2.5f, 2.2f}, Vec3f{4.0f}});
  return scene;
}

}  // namespace vf::scenes
