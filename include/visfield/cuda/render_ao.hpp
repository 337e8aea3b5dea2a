#pragma once
/// \file `visfield render --device cuda`: the ambient-occlusion image with its AO rays generated and
/// traced on the GPU. Camera rays and the surface points they reach are the CPU renderer's
/// (SceneQueries::intersect_camera, SurfaceSpawner), and each sample's AO rays continue its
/// generator as the CPU renderer's do (gpu::ao_ray's stream form): the same rays, answered with the
/// CPU's bits, so the image is render_ao's pixel for pixel.

#include <cstdint>
#include <vector>

#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/image.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/cuda/device_scene.hpp"
#include "visfield/gpu/ray_generation.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/render_stats.hpp"
#include "visfield/render/sample_rays.hpp"

namespace vf::cuda {

/// What AO rays go through on the device: the scene's fields (with their exact part) or the exact
/// BVH. Exactly one is set; both borrowed.
struct GpuOccluder {
  const DeviceFieldScene* fields = nullptr;
  const DeviceBvh* exact = nullptr;
};

/// The frame of a SurfacePoint, as the kernels read it.
inline gpu::SurfaceFrame surface_frame(const SurfacePoint& p) { return {p.position, p.normal, p.tangent, p.bitangent}; }

/// Camera-sample surface frames of `camera`'s view: per pixel sample (Rng(seed, pixel, s) draws the
/// jitter, as render_ao) the frame of its hit, compacted in pixel-sample order; `slot_point[k]` is
/// the index of sample k's frame or −1 for a miss; `streams` (optional) gets each frame's generator
/// as the jitter left it, where render_ao draws that sample's AO rays from. Parallel over rows.
std::vector<gpu::SurfaceFrame> camera_surface_frames(const SceneQueries& queries, const Scene& scene, const Camera& camera, int spp,
                                                     std::uint64_t seed, std::vector<std::int64_t>& slot_point,
                                                     std::vector<Rng>* streams = nullptr);

/// The AO image with `options.ao_rays` device-generated rays a hit through `occluder`; a miss is
/// kAoBackground, a hit the fraction of its rays left unoccluded. `stats` (optional) gets the rays
/// and the wall time. Throws vf::Error for psf_level (line directions, CPU only), bad options, or a
/// CUDA failure.
Image render_ao(const SceneQueries& queries, const Scene& scene, const Camera& camera, const AoOptions& options,
                const GpuOccluder& occluder, RenderStats* stats = nullptr);

}  // namespace vf::cuda
