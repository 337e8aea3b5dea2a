#pragma once
/// \file What the CUDA tests share: the skip (or, with VISFIELD_REQUIRE_CUDA=1, the failure) when
/// there is no device, scenes with fields and exact parts, surface frames on their surfaces, bitwise
/// comparisons of answer arrays, and the count of rays compared per kernel kind.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "support/models.hpp"
#include "support/same_hit.hpp"
#include "support/test_scale.hpp"
#include "visfield/cuda/device.hpp"
#include "visfield/gpu/ray_generation.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/scenes/builtin.hpp"

/// Skips the test (ctest's "Skipped") when no CUDA device is usable, or fails it when the
/// environment sets VISFIELD_REQUIRE_CUDA=1 (a GPU run, where a skip would read as a pass).
#define VF_REQUIRE_CUDA_DEVICE()                                                                     \
  do {                                                                                               \
    if (!::vf::cuda::device_available()) {                                                           \
      if (::vf::test::cuda_required()) FAIL() << "VISFIELD_REQUIRE_CUDA=1 but no CUDA device is usable"; \
      GTEST_SKIP() << "no CUDA device found";                                                        \
    }                                                                                                \
  } while (0)

namespace vf::test {

/// Whether the environment sets VISFIELD_REQUIRE_CUDA=1: then a test without a device fails.
inline bool cuda_required() {
  const char* value = std::getenv("VISFIELD_REQUIRE_CUDA");
  return value != nullptr && std::string(value) == "1";
}

/// Prints "rays compared: KIND N", which gpu-bundle/run.sh sums per kind for its summary.
inline void report_rays(const char* kind, std::size_t n) { std::printf("rays compared: %s %zu\n", kind, n); }

/// `n` surface frames on random triangles of `set`, each on a random side of its triangle and
/// lifted off it by 1e-5 of the set's diameter (as SurfaceSpawner lifts hit points).
inline std::vector<gpu::SurfaceFrame> surface_frames(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x5f);
  const float lift = 1e-5f * length(set.bounds.extent());
  std::vector<gpu::SurfaceFrame> frames(n);
  for (gpu::SurfaceFrame& f : frames) {
    const auto& t = random_triangle(rng, set);
    Vec3f normal = normalize(cross(t[1] - t[0], t[2] - t[0]));
    if (!is_finite(normal)) normal = Vec3f{0.0f, 1.0f, 0.0f};
    if (rng.uniform() < 0.5f) normal = -normal;
    f.normal = normal;
    f.position = random_point_on(rng, t) + normal * lift;
    orthonormal_basis(f.normal, f.tangent, f.bitangent);
  }
  return frames;
}

/// A shared model's scene when models_dir() holds it, else nothing.
inline std::optional<Scene> shared_model(const char* file) {
  const std::filesystem::path path = models_dir() / file;
  if (!std::filesystem::exists(path)) {
    if (models_required()) ADD_FAILURE() << file << " is not in " << models_dir() << " (VISFIELD_REQUIRE_MODELS=1)";
    return std::nullopt;
  }
  return load_scene(path.string());
}

/// A model standing on an exact ground plane (the GPU fields paper's Figure 3 setting), the model's
/// mesh left to the occluder (a field), the ground marked exact.
inline Scene on_ground(Scene scene) {
  const Bounds3f b = scene.bounds();
  const Vec3f e = b.extent();
  const float size = max_component(e) * 3.0f;
  TriangleMesh ground;
  ground.name = "ground";
  ground.occluder = MeshOccluder::exact;
  const float y = b.lo.y, cx = b.center().x, cz = b.center().z;
  ground.positions = {{cx - size, y, cz - size}, {cx + size, y, cz - size}, {cx + size, y, cz + size}, {cx - size, y, cz + size}};
  ground.triangles = {{0, 2, 1}, {0, 3, 2}};
  scene.meshes.push_back(ground);
  scene.add_instance(static_cast<std::uint32_t>(scene.meshes.size() - 1));
  return scene;
}

/// Count of positions where two arrays of trivially comparable values differ.
template <class T>
std::size_t count_differences(const std::vector<T>& a, const std::vector<T>& b) {
  std::size_t d = a.size() == b.size() ? 0 : std::max(a.size(), b.size());
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) d += !(a[i] == b[i]);
  return d;
}

/// Count of hits that differ in any bit.
inline std::size_t count_hit_differences(const std::vector<Hit>& a, const std::vector<Hit>& b) {
  std::size_t d = a.size() == b.size() ? 0 : std::max(a.size(), b.size());
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) d += !same_bits(a[i], b[i]);
  return d;
}

}  // namespace vf::test
