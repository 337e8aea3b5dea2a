#pragma once
/// \file The batch API on the GPU: occlusion and closest hits for an array of rays in device memory
/// (one thread a ray), through the exact BVH or a scene's fields; and host-array conveniences that
/// copy in and out. Synchronous (they return when the answers are written). The answers are those
/// of the host queries (GpuBvh, PackedFieldScene), which equal BruteForce and FieldScene bit for bit.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visfield/core/ray.hpp"
#include "visfield/cuda/device_scene.hpp"

namespace vf::cuda {

/// occluded[i] = 1 when rays[i] hits a triangle in (tmin, tmax], else 0; `rays` and `occluded` are
/// device arrays of n. Throws vf::Error on a CUDA failure.
void occluded(const DeviceBvh& bvh, const Ray* rays, std::size_t n, std::uint8_t* occluded);
/// hits[i] = the closest hit of rays[i] (device arrays of n).
void intersect(const DeviceBvh& bvh, const Ray* rays, std::size_t n, Hit* hits);
/// occluded[i] = FieldScene::occluded(rays[i]) (device arrays of n).
void occluded(const DeviceFieldScene& scene, const Ray* rays, std::size_t n, std::uint8_t* occluded);
/// hits[i] = FieldScene::intersect(rays[i]) (device arrays of n).
void intersect(const DeviceFieldScene& scene, const Ray* rays, std::size_t n, Hit* hits);

/// occluded() for host rays: copied to the device and the answers back.
std::vector<std::uint8_t> occluded(const DeviceBvh& bvh, std::span<const Ray> rays);
/// intersect() for host rays.
std::vector<Hit> intersect(const DeviceBvh& bvh, std::span<const Ray> rays);
/// occluded() for host rays through fields.
std::vector<std::uint8_t> occluded(const DeviceFieldScene& scene, std::span<const Ray> rays);
/// intersect() for host rays through fields.
std::vector<Hit> intersect(const DeviceFieldScene& scene, std::span<const Ray> rays);

}  // namespace vf::cuda
