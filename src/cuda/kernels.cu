// The rendering kernels: one thread a ray, generated on the device by gpu/ray_generation.hpp and
// traced by the device traversal code of include/visfield/gpu.

#include "visfield/cuda/kernels.hpp"

#include "launch.cuh"
#include "visfield/core/error.hpp"
#include "visfield/gpu/bvh_traversal.hpp"
#include "visfield/gpu/field_scene_view.hpp"

namespace vf::cuda {
namespace {

template <int Capacity, bool kStreams, gpu::FieldForm Form, class View>
__global__ void __launch_bounds__(detail::kBlockThreads, detail::kMinBlocksPerSm)
    ao_kernel(View view, const gpu::SurfaceFrame* points, std::size_t n, AoParams p, std::uint32_t* unoccluded) {
  const std::size_t rays = static_cast<std::size_t>(p.rays_per_point), total = n * rays;
  for (std::size_t idx = detail::first_index(); idx < total; idx += detail::index_step()) {
    std::size_t i, k;
    detail::divide(idx, rays, i, k);
    const Ray ray = detail::ao_ray_of<kStreams>(points, i, k, p);
    detail::add_vote(unoccluded, i, !detail::occluded_in<Capacity, Form>(view, ray));
  }
}

template <int Capacity, gpu::FieldForm Form, class View>
__global__ void __launch_bounds__(detail::kBlockThreads, detail::kMinBlocksPerSm)
    shadow_kernel(View view, const gpu::SurfaceFrame* points, std::size_t n, const gpu::SphereLightData* lights, int light_count,
                              int rays_per_light, std::uint64_t seed, std::uint32_t* visible) {
  const std::size_t per_light = static_cast<std::size_t>(rays_per_light), per_point = per_light * static_cast<std::size_t>(light_count);
  const std::size_t total = n * per_point;
  for (std::size_t idx = detail::first_index(); idx < total; idx += detail::index_step()) {
    std::size_t i, rest, l, k;
    detail::divide(idx, per_point, i, rest);
    detail::divide(rest, per_light, l, k);
    const Ray ray = gpu::cone_ray(points[i].position, lights[l], seed, i, rest);
    detail::add_vote(visible, i * static_cast<std::size_t>(light_count) + l, !detail::occluded_in<Capacity, Form>(view, ray));
  }
}

// Closest hits over fields, as the closest-hit batch kernel (intersect_kernel), whose 3 blocks an SM
// were measured faster than 4: at 64 registers this kernel spilled 446 bytes a thread, at 80 it
// spills 88 (nvcc -Xptxas -v, sm_90). Its own speed is not timed.
template <int Capacity>
__global__ void __launch_bounds__(detail::kBlockThreads, detail::kIntersectBlocks<gpu::FieldSceneView>)
    glossy_kernel(gpu::FieldSceneView view, const GlossyPoint* points, std::size_t n, int rays_per_point, std::uint64_t seed,
                              Hit* hits, float* weights) {
  const std::size_t rays = static_cast<std::size_t>(rays_per_point), total = n * rays;
  for (std::size_t idx = detail::first_index(); idx < total; idx += detail::index_step()) {
    std::size_t i, k;
    detail::divide(idx, rays, i, k);
    const GlossyPoint& p = points[i];
    const gpu::GlossySample s = gpu::glossy_ray(p.frame, p.wo, p.alpha, seed, i, k);
    detail::store_hit(hits + idx, s.valid ? gpu::intersect<Capacity>(view, s.ray) : Hit{});
    weights[idx] = s.valid ? s.weight : 0.0f;
  }
}

template <class View>
void launch_ao(const View& view, const gpu::SurfaceFrame* points, std::size_t n, const AoParams& p, std::uint32_t* unoccluded) {
  if (p.rays_per_point < 1) throw Error("ambient occlusion: rays_per_point must be at least 1");
  if (n == 0) return;  // before the memset: an empty output may be a null pointer
  check(cudaMemset(unoccluded, 0, n * sizeof(std::uint32_t)), "cudaMemset");
  const std::size_t total = n * static_cast<std::size_t>(p.rays_per_point);
  detail::with_stack_capacity(detail::stack_bound(view), [&](auto capacity) {
    detail::with_ao_keying(p, [&](auto streams) {
      detail::with_field_form(view, [&](auto form) {
        detail::launch_and_finish("ambient occlusion kernel", [&] {
          ao_kernel<capacity.value, streams.value, form.value>
              <<<detail::blocks_for(total), detail::kBlockThreads>>>(view, points, n, p, unoccluded);
        });
      });
    });
  });
}

template <class View>
void launch_shadows(const View& view, const gpu::SurfaceFrame* points, std::size_t n, const gpu::SphereLightData* lights, int light_count,
                    int rays_per_light, std::uint64_t seed, std::uint32_t* visible) {
  if (rays_per_light < 1 || light_count < 0) throw Error("soft shadows: rays_per_light must be at least 1");
  const std::size_t counts = n * static_cast<std::size_t>(light_count), total = counts * static_cast<std::size_t>(rays_per_light);
  if (total == 0) return;  // before the memset: an empty output may be a null pointer
  check(cudaMemset(visible, 0, counts * sizeof(std::uint32_t)), "cudaMemset");
  detail::with_stack_capacity(detail::stack_bound(view), [&](auto capacity) {
    detail::with_field_form(view, [&](auto form) {
      detail::launch_and_finish("soft shadow kernel", [&] {
        shadow_kernel<capacity.value, form.value><<<detail::blocks_for(total), detail::kBlockThreads>>>(
            view, points, n, lights, light_count, rays_per_light, seed, visible);
      });
    });
  });
}

}  // namespace

void ambient_occlusion(const DeviceFieldScene& scene, const gpu::SurfaceFrame* points, std::size_t n, const AoParams& params,
                       std::uint32_t* unoccluded) {
  launch_ao(scene.view(), points, n, params, unoccluded);
}

void ambient_occlusion(const DeviceBvh& bvh, const gpu::SurfaceFrame* points, std::size_t n, const AoParams& params,
                       std::uint32_t* unoccluded) {
  launch_ao(bvh.view(), points, n, params, unoccluded);
}

void soft_shadows(const DeviceFieldScene& scene, const gpu::SurfaceFrame* points, std::size_t n, const gpu::SphereLightData* lights,
                  int light_count, int rays_per_light, std::uint64_t seed, std::uint32_t* visible) {
  launch_shadows(scene.view(), points, n, lights, light_count, rays_per_light, seed, visible);
}

void soft_shadows(const DeviceBvh& bvh, const gpu::SurfaceFrame* points, std::size_t n, const gpu::SphereLightData* lights,
                  int light_count, int rays_per_light, std::uint64_t seed, std::uint32_t* visible) {
  launch_shadows(bvh.view(), points, n, lights, light_count, rays_per_light, seed, visible);
}

void glossy_reflections(const DeviceFieldScene& scene, const GlossyPoint* points, std::size_t n, int rays_per_point, std::uint64_t seed,
                        Hit* hits, float* weights) {
  if (rays_per_point < 1) throw Error("glossy reflections: rays_per_point must be at least 1");
  const std::size_t total = n * static_cast<std::size_t>(rays_per_point);
  if (total == 0) return;
  const gpu::FieldSceneView view = scene.view();
  detail::with_stack_capacity(detail::stack_bound(view), [&](auto capacity) {
    detail::launch_and_finish("glossy reflection kernel", [&] {
      glossy_kernel<capacity.value><<<detail::blocks_for(total), detail::kBlockThreads>>>(view, points, n, rays_per_point, seed, hits,
                                                                                        weights);
    });
  });
}

}  // namespace vf::cuda
