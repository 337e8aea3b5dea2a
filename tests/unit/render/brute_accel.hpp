#pragma once
// A self-contained Accelerator for the render tests: tests every triangle of a TriangleSet, so the
// render tests depend on nothing but core and the concept.

#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "visfield/accel/accelerator.hpp"
#include "visfield/core/triangle_intersect.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

class BruteAccel {
 public:
  explicit BruteAccel(const Scene& scene) : set_(flatten(scene)) {}
  std::optional<Hit> intersect(const Ray& ray) const {
    const WatertightRay wr(ray);
    std::optional<Hit> best;
    for (std::size_t i = 0; i < set_.size(); ++i) {
      const auto& tri = set_.triangles[i];
      TriangleHit h;
      if (intersect_triangle(wr, tri[0], tri[1], tri[2], ray.tmin, best ? best->t : ray.tmax, h))
        best = Hit{h.t, h.u, h.v, set_.prim[i], set_.instance[i]};
    }
    return best;
  }
  bool occluded(const Ray& ray) const {
    const WatertightRay wr(ray);
    for (const auto& tri : set_.triangles) {
      TriangleHit h;
      if (intersect_triangle(wr, tri[0], tri[1], tri[2], ray.tmin, ray.tmax, h)) return true;
    }
    return false;
  }
  AccelStats stats() const { return {}; }
  static std::string name() { return "test-brute"; }

 private:
  TriangleSet set_;
};
static_assert(Accelerator<BruteAccel>);

// Wraps BruteAccel and records every occlusion query, in call order (thread-safe).
class RecordingAccel {
 public:
  explicit RecordingAccel(const Scene& scene) : inner_(scene) {}
  std::optional<Hit> intersect(const Ray& ray) const { return inner_.intersect(ray); }
  bool occluded(const Ray& ray) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    occlusion_queries_.push_back(ray);
    return inner_.occluded(ray);
  }
  AccelStats stats() const { return {}; }
  static std::string name() { return "test-recording"; }
  const std::vector<Ray>& occlusion_queries() const { return occlusion_queries_; }

 private:
  BruteAccel inner_;
  mutable std::mutex mutex_;
  mutable std::vector<Ray> occlusion_queries_;
};
static_assert(Accelerator<RecordingAccel>);

}  // namespace vf::test
