#include "visfield/cuda/render_ao.hpp"

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/cuda/device_buffer.hpp"
#include "visfield/cuda/kernels.hpp"
#include "visfield/render/camera.hpp"

namespace vf::cuda {

std::vector<gpu::SurfaceFrame> camera_surface_frames(const SceneQueries& queries, const Scene& scene, const Camera& camera, int spp,
                                                     std::uint64_t seed, std::vector<std::int64_t>& slot_point,
                                                     std::vector<Rng>* streams) {
  const PinholeCamera pinhole(camera);
  const SurfaceSpawner spawner(scene);
  const std::size_t width = static_cast<std::size_t>(pinhole.width()), samples = static_cast<std::size_t>(spp);
  const std::size_t slots = width * static_cast<std::size_t>(pinhole.height()) * samples;
  std::vector<gpu::SurfaceFrame> frames(slots);
  std::vector<Rng> generators(streams ? slots : 0, Rng(0));
  std::vector<std::uint8_t> hit(slots, 0);
  vf::parallel_for(0, pinhole.height(), [&](int y) {
    for (int x = 0; x < pinhole.width(); ++x) {
      const std::uint64_t pixel = static_cast<std::uint64_t>(y) * width + static_cast<std::uint64_t>(x);
      for (int s = 0; s < spp; ++s) {
        Rng rng(seed, pixel, static_cast<std::uint64_t>(s));
        const Ray primary = pixel_ray(pinhole, x, y, spp > 1, rng);
        const Hit h = queries.intersect_camera(primary);
        if (!h) continue;
        const std::size_t slot = pixel * samples + static_cast<std::size_t>(s);
        frames[slot] = surface_frame(spawner.surface_point(primary, h));
        if (streams) generators[slot] = rng;
        hit[slot] = 1;
      }
    }
  });
  slot_point.assign(slots, -1);
  std::size_t next = 0;
  for (std::size_t k = 0; k < slots; ++k) {
    if (!hit[k]) continue;
    frames[next] = frames[k];
    if (streams) generators[next] = generators[k];
    slot_point[k] = static_cast<std::int64_t>(next++);
  }
  frames.resize(next);
  if (streams) {
    generators.erase(generators.begin() + static_cast<std::ptrdiff_t>(next), generators.end());
    *streams = std::move(generators);
  }
  return frames;
}

Image render_ao(const SceneQueries& queries, const Scene& scene, const Camera& camera, const AoOptions& o, const GpuOccluder& occluder,
                RenderStats* stats) {
  validate_ao_options(o);
  if (o.psf_level != 0) throw Error("ao on the GPU: line directions (--ao-directions) are CPU only; use random directions");
  if ((occluder.fields == nullptr) == (occluder.exact == nullptr)) throw Error("ao on the GPU: give fields or an exact BVH");
  const Stopwatch watch;
  std::vector<std::int64_t> slot_point;
  std::vector<Rng> streams;
  const std::vector<gpu::SurfaceFrame> frames = camera_surface_frames(queries, scene, camera, o.spp, o.seed, slot_point, &streams);
  const auto d_frames = DeviceArray<gpu::SurfaceFrame>::from(std::span<const gpu::SurfaceFrame>(frames));
  const auto d_streams = DeviceArray<Rng>::from(std::span<const Rng>(streams));
  DeviceArray<std::uint32_t> d_open(frames.size());
  const AoParams params{o.ao_rays, o.seed, o.max_distance, d_streams.data()};
  if (occluder.fields)
    ambient_occlusion(*occluder.fields, d_frames.data(), frames.size(), params, d_open.data());
  else
    ambient_occlusion(*occluder.exact, d_frames.data(), frames.size(), params, d_open.data());
  const std::vector<std::uint32_t> open = d_open.to_host();

  Image image(camera.width, camera.height);
  const std::size_t spp = static_cast<std::size_t>(o.spp);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const std::size_t pixel = static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(x);
      float sum = 0.0f;
      for (std::size_t s = 0; s < spp; ++s) {
        const std::int64_t p = slot_point[pixel * spp + s];
        sum += p < 0 ? kAoBackground : static_cast<float>(open[static_cast<std::size_t>(p)]) / static_cast<float>(o.ao_rays);
      }
      image.at(x, y) = Vec3f(sum / static_cast<float>(spp));
    }
  if (stats) {
    stats->width = camera.width;
    stats->height = camera.height;
    stats->by_kind.camera = slot_point.size();
    stats->by_kind.ao = frames.size() * static_cast<std::uint64_t>(o.ao_rays);
    stats->rays = stats->by_kind.total();
    stats->seconds = watch.elapsed_s();
  }
  return image;
}

}  // namespace vf::cuda
