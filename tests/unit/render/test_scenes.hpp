#pragma once
// Small hand-made scenes with known ambient occlusion, shared by the render tests.

#include <mutex>
#include <string>
#include <vector>

#include "visfield/accel/brute_force.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

// The oracle over a scene's flattened triangles: the exact structure the render tests trace.
inline BruteForce scene_oracle(const Scene& scene) { return BruteForce::build(flatten(scene)); }

// An occluder (the occlusion role only) that asks `inner` and records every query in call order.
// Thread-safe.
class RecordingOccluder {
 public:
  explicit RecordingOccluder(const BruteForce& inner) : inner_(inner) {}
  bool occluded(const Ray& ray) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    queries_.push_back(ray);
    return inner_.occluded(ray);
  }
  AccelStats stats() const { return {}; }
  static std::string name() { return "recording"; }
  static constexpr Exactness exactness = Exactness::exact;
  const std::vector<Ray>& queries() const { return queries_; }

 private:
  const BruteForce& inner_;
  mutable std::mutex mutex_;
  mutable std::vector<Ray> queries_;
};

// Adds quad (a, b, c, d) as two triangles to mesh.
inline void add_quad(TriangleMesh& mesh, const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d) {
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
  mesh.triangles.push_back({first, first + 1, first + 2});
  mesh.triangles.push_back({first, first + 2, first + 3});
}

// The square y = 0, |x|, |z| <= half.
inline Scene plane_scene(float half) {
  TriangleMesh mesh;
  mesh.name = "plane";
  add_quad(mesh, {-half, 0, -half}, {-half, 0, half}, {half, 0, half}, {half, 0, -half});
  return scene_from_mesh(mesh);
}

// The closed box [-1, 1]^3 (12 triangles, shared corners).
inline Scene closed_box_scene() {
  TriangleMesh mesh;
  mesh.name = "box";
  for (std::uint32_t c = 0; c < 8; ++c)
    mesh.positions.push_back({(c & 1) ? 1.0f : -1.0f, (c & 2) ? 1.0f : -1.0f, (c & 4) ? 1.0f : -1.0f});
  mesh.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                    {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  return scene_from_mesh(mesh);
}

// A 90-degree crease: the floor y = 0 for 0 <= x <= size and the wall x = 0 for 0 <= y <= size, both
// spanning |z| <= size.
inline Scene crease_scene(float size) {
  TriangleMesh mesh;
  mesh.name = "crease";
  add_quad(mesh, {0, 0, -size}, {0, 0, size}, {size, 0, size}, {size, 0, -size});
  add_quad(mesh, {0, 0, -size}, {0, size, -size}, {0, size, size}, {0, 0, size});
  return scene_from_mesh(mesh);
}

// A camera at `position` looking at `target` with up = -z (so the view must not be along z).
inline Camera camera_looking_at(const Vec3f& position, const Vec3f& target, int width, int height, float fov) {
  Camera camera;
  camera.position = position;
  camera.look_at = target;
  camera.up = {0.0f, 0.0f, -1.0f};
  camera.width = width;
  camera.height = height;
  camera.fov_degrees = fov;
  return camera;
}

}  // namespace vf::test
