#pragma once
/// \file The rendering kernels: rays generated on the device (gpu/ray_generation.hpp, keyed by
/// (seed, point index, sample)) and traced through a scene's fields or the exact BVH, one thread a
/// ray. Inputs and outputs are device arrays; every call is synchronous. The CPU generates the same
/// rays with the same header, so tests compare answers bit for bit.

#include <cstddef>
#include <cstdint>
#include <limits>

#include "visfield/core/ray.hpp"
#include "visfield/cuda/device_scene.hpp"
#include "visfield/gpu/ray_generation.hpp"

namespace vf::cuda {

/// Ambient-occlusion rays per surface point.
struct AoParams {
  int rays_per_point = 64;  ///< >= 1.
  std::uint64_t seed = 1;
  float max_distance = std::numeric_limits<float>::infinity();
  /// A device array of one generator a point, or null: when set, point i's rays continue
  /// streams[i] (gpu::ao_ray's stream form, as the CPU renderer draws them) and `seed` is unused.
  const Rng* streams = nullptr;
};

/// unoccluded[i] = how many of point i's AO rays gpu::ao_ray(points[i], seed, i, k, max_distance)
/// (with streams: gpu::ao_ray(points[i], streams[i], k, max_distance)), k < rays_per_point, the
/// scene's fields (and exact part) leave unoccluded. Inter-object AO when the points lie outside the
/// objects' spheres, intra-object (the GPU paper's d1-vs-d2 test) inside.
void ambient_occlusion(const DeviceFieldScene& scene, const gpu::SurfaceFrame* points, std::size_t n, const AoParams& params,
                       std::uint32_t* unoccluded);
/// The same rays through the exact BVH: the reference.
void ambient_occlusion(const DeviceBvh& bvh, const gpu::SurfaceFrame* points, std::size_t n, const AoParams& params,
                       std::uint32_t* unoccluded);

/// visible[i * light_count + l] = how many of the shadow rays gpu::cone_ray(points[i].position,
/// lights[l], seed, i, l * rays_per_light + k), k < rays_per_light, reach sphere light l (`lights`:
/// device array of light_count).
void soft_shadows(const DeviceFieldScene& scene, const gpu::SurfaceFrame* points, std::size_t n, const gpu::SphereLightData* lights,
                  int light_count, int rays_per_light, std::uint64_t seed, std::uint32_t* visible);
/// The same rays through the exact BVH.
void soft_shadows(const DeviceBvh& bvh, const gpu::SurfaceFrame* points, std::size_t n, const gpu::SphereLightData* lights,
                  int light_count, int rays_per_light, std::uint64_t seed, std::uint32_t* visible);

/// A reflective surface point: its frame, the unit direction towards the viewer, GGX alpha (0: mirror).
struct GlossyPoint {
  gpu::SurfaceFrame frame;
  Vec3f wo;
  float alpha = 0.0f;
};

/// hits[i * rays_per_point + k] and weights[...] for reflection ray gpu::glossy_ray(points[i].frame,
/// points[i].wo, points[i].alpha, seed, i, k) traced to its closest hit through the fields (a field
/// hit carries the normal field's world-space normal) and the exact part; a sample below the surface
/// gets a miss and weight 0.
void glossy_reflections(const DeviceFieldScene& scene, const GlossyPoint* points, std::size_t n, int rays_per_point,
                        std::uint64_t seed, Hit* hits, float* weights);

}  // namespace vf::cuda
