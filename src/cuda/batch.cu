// The batch API's kernels: one thread a ray through the device traversal code of
// include/visfield/gpu (the very functions the host queries run).

#include "visfield/cuda/batch.hpp"

#include "launch.cuh"
#include "visfield/gpu/bvh_traversal.hpp"
#include "visfield/gpu/field_scene_view.hpp"

namespace vf::cuda {
namespace {

template <int Capacity, gpu::FieldForm Form, class View>
__global__ void __launch_bounds__(detail::kBlockThreads, detail::kMinBlocksPerSm)
    occluded_kernel(View view, const Ray* rays, std::size_t n, std::uint8_t* out) {
  for (std::size_t i = detail::first_index(); i < n; i += detail::index_step())
    out[i] = detail::occluded_in<Capacity, Form>(view, rays[i]) ? 1 : 0;
}

template <int Capacity, gpu::FieldForm Form, class View>
__global__ void __launch_bounds__(detail::kBlockThreads, detail::kIntersectBlocks<View>)
    intersect_kernel(View view, const Ray* rays, std::size_t n, Hit* out) {
  for (std::size_t i = detail::first_index(); i < n; i += detail::index_step())
    detail::store_hit(out + i, detail::intersect_in<Capacity, Form>(view, rays[i]));
}

template <class View>
void launch_occluded(const View& view, const Ray* rays, std::size_t n, std::uint8_t* out) {
  if (n == 0) return;
  detail::with_stack_capacity(detail::stack_bound(view), [&](auto capacity) {
    detail::with_field_form(view, [&](auto form) {
      detail::launch_and_finish("occluded kernel", [&] {
        occluded_kernel<capacity.value, form.value><<<detail::blocks_for(n), detail::kBlockThreads>>>(view, rays, n, out);
      });
    });
  });
}

template <class View>
void launch_intersect(const View& view, const Ray* rays, std::size_t n, Hit* out) {
  if (n == 0) return;
  detail::with_stack_capacity(detail::stack_bound(view), [&](auto capacity) {
    detail::with_field_form(view, [&](auto form) {
      detail::launch_and_finish("intersect kernel", [&] {
        intersect_kernel<capacity.value, form.value><<<detail::blocks_for(n), detail::kBlockThreads>>>(view, rays, n, out);
      });
    });
  });
}

/// `rays` copied to the device, `run` on them, the n answers of type A back.
template <class A, class Run>
std::vector<A> on_host_rays(std::span<const Ray> rays, Run&& run) {
  const DeviceArray<Ray> d_rays = DeviceArray<Ray>::from(rays);
  DeviceArray<A> d_out(rays.size());
  run(d_rays.data(), rays.size(), d_out.data());
  return d_out.to_host();
}

}  // namespace

void occluded(const DeviceBvh& bvh, const Ray* rays, std::size_t n, std::uint8_t* out) { launch_occluded(bvh.view(), rays, n, out); }
void intersect(const DeviceBvh& bvh, const Ray* rays, std::size_t n, Hit* out) { launch_intersect(bvh.view(), rays, n, out); }
void occluded(const DeviceFieldScene& scene, const Ray* rays, std::size_t n, std::uint8_t* out) {
  launch_occluded(scene.view(), rays, n, out);
}
void intersect(const DeviceFieldScene& scene, const Ray* rays, std::size_t n, Hit* out) { launch_intersect(scene.view(), rays, n, out); }

std::vector<std::uint8_t> occluded(const DeviceBvh& bvh, std::span<const Ray> rays) {
  return on_host_rays<std::uint8_t>(rays, [&](const Ray* r, std::size_t n, std::uint8_t* o) { occluded(bvh, r, n, o); });
}
std::vector<Hit> intersect(const DeviceBvh& bvh, std::span<const Ray> rays) {
  return on_host_rays<Hit>(rays, [&](const Ray* r, std::size_t n, Hit* o) { intersect(bvh, r, n, o); });
}
std::vector<std::uint8_t> occluded(const DeviceFieldScene& scene, std::span<const Ray> rays) {
  return on_host_rays<std::uint8_t>(rays, [&](const Ray* r, std::size_t n, std::uint8_t* o) { occluded(scene, r, n, o); });
}
std::vector<Hit> intersect(const DeviceFieldScene& scene, std::span<const Ray> rays) {
  return on_host_rays<Hit>(rays, [&](const Ray* r, std::size_t n, Hit* o) { intersect(scene, r, n, o); });
}

}  // namespace vf::cuda
