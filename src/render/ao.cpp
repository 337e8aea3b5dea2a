#include "visfield/render/ao.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>

#include "occlusion_batch.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/progress.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/render/tiles.hpp"

namespace vf {
namespace {

/// Bytes of unoccluded flags a block of AO along the lines may hold: samples x lines.
constexpr std::size_t kLineBlockBytes = std::size_t{1} << 26;

/// AO along the lines of `lines` (VLF-RT §7) for an occluder that prefers line streams, traced line
/// by line: the region's rows are taken in
/// blocks of at most kLineBlockBytes / lines pixel samples; in a block, the camera pass finds every
/// sample's surface point, then each line (in parallel) hands the rays along it from all the block's
/// points, in sample order, to queries.occluded_block in one call — a stream of parallel rays, which a
/// BeamField traces tile by tile, reading each tile record once — and each sample sums its
/// unoccluded lines' weights in line order, the order and the operations of the ray-by-ray loop, so
/// the image is the same for every structure, thread count and block size.
Image render_ao_lines(const SceneQueries& queries, const Scene& scene, const PinholeCamera& pinhole, const AoOptions& opt,
                      const ImageTile& region, const DirectionLines& lines, RenderStats* stats) {
  const Stopwatch watch;
  const SurfaceSpawner spawner(scene);
  const int width = region.x1 - region.x0, height = region.y1 - region.y0;
  const auto spp = static_cast<std::size_t>(opt.spp);
  const std::size_t row_samples = static_cast<std::size_t>(width) * spp;
  const std::size_t block_samples = std::max<std::size_t>(kLineBlockBytes / lines.size(), 1024);
  const int rows_per_block = static_cast<int>(std::clamp<std::size_t>(block_samples / row_samples, 1, static_cast<std::size_t>(height)));
  const int blocks = (height + rows_per_block - 1) / rows_per_block;
  Image image(width, height);
  ProgressBar bar("ao", static_cast<std::size_t>(blocks) * lines.size(), opt.progress);
  std::atomic<std::uint64_t> ao_rays{0};
  struct Point {
    Vec3f position, normal;
    bool hit = false;
  };
  std::vector<Point> points;
  std::vector<std::uint8_t> open;  // open[line * samples + sample]: its ray along the line got through
  for (int y0 = region.y0; y0 < region.y1; y0 += rows_per_block) {
    const int y1 = std::min(region.y1, y0 + rows_per_block);
    const std::size_t samples = static_cast<std::size_t>(y1 - y0) * row_samples;
    points.assign(samples, Point{});
    vf::parallel_for(tbb::blocked_range<int>(y0, y1, 1), [&](const tbb::blocked_range<int>& rows) {
      check_interrupt();
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = region.x0; x < region.x1; ++x) {
          const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(pinhole.width()) + x;
          for (std::size_t s = 0; s < spp; ++s) {
            Rng rng(opt.seed, pixel, s);
            const Ray primary = pixel_ray(pinhole, x, y, opt.spp > 1, rng);
            const Hit hit = queries.intersect_camera(primary);
            if (!hit) continue;
            const SurfacePoint point = spawner.surface_point(primary, hit);
            points[(static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x - region.x0)) * spp + s] =
                Point{point.position, point.normal, true};
          }
        }
    });
    open.assign(lines.size() * samples, 0);
    vf::parallel_for(tbb::blocked_range<std::size_t>(0, lines.size(), 1), [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<Ray> rays;
      std::vector<std::uint32_t> sample_of;
      std::vector<std::uint8_t> occluded;
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        check_interrupt();
        const Vec3f& w = lines.direction(k);
        rays.clear();
        sample_of.clear();
        for (std::size_t s = 0; s < samples; ++s) {
          if (!points[s].hit) continue;
          const float c = dot(points[s].normal, w);
          if (c == 0.0f) continue;
          rays.push_back(Ray{points[s].position, c > 0.0f ? w : -w, 0.0f, opt.max_distance});
          sample_of.push_back(static_cast<std::uint32_t>(s));
        }
        occluded.resize(rays.size());
        queries.occluded_block(std::span<const Ray>(rays), std::span<std::uint8_t>(occluded));
        std::uint8_t* line_open = open.data() + k * samples;
        for (std::size_t r = 0; r < rays.size(); ++r) line_open[sample_of[r]] = occluded[r] ? 0 : 1;
        ao_rays.fetch_add(rays.size(), std::memory_order_relaxed);
        bar.tick();
      }
    });
    vf::parallel_for(tbb::blocked_range<int>(y0, y1, 1), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = region.x0; x < region.x1; ++x) {
          const std::size_t first = (static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x - region.x0)) * spp;
          float value = 0.0f;
          for (std::size_t s = first; s < first + spp; ++s) {
            if (!points[s].hit) {
              value += kAoBackground;
              continue;
            }
            float total = 0.0f;
            Vec3f sum{0.0f};
            for (std::size_t k = 0; k < lines.size(); ++k) {
              const float c = dot(points[s].normal, lines.direction(k));
              if (c == 0.0f) continue;
              total += std::fabs(c);
              if (open[k * samples + s]) sum += Vec3f{std::fabs(c)};
            }
            value += total > 0.0f ? sum.x / total : 1.0f;
          }
          image.at(x - region.x0, y - region.y0) = Vec3f(value / static_cast<float>(opt.spp));
        }
    });
  }
  bar.finish();
  if (stats) {
    stats->width = width;
    stats->height = height;
    stats->by_kind = RayCounts{static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) * spp, 0, 0, ao_rays.load()};
    stats->rays = stats->by_kind.total();
    stats->seconds = watch.elapsed_s();
  }
  return image;
}

}  // namespace

void validate_ao_options(const AoOptions& options) {
  if (options.spp < 1) throw Error("ao: spp must be at least 1, got " + std::to_string(options.spp));
  if (options.ao_rays < 1) throw Error("ao: ao_rays must be at least 1, got " + std::to_string(options.ao_rays));
  if (!(options.max_distance > 0.0f))
    throw Error("ao: max_distance must be positive, got " + std::to_string(options.max_distance));
  if (options.psf_level != 0 && (options.psf_level < DirectionLines::kMinLevel || options.psf_level > DirectionLines::kMaxLevel))
    throw Error("ao: psf_level must be 0 or in [2, 6], got " + std::to_string(options.psf_level));
  if (options.tile_size < 1) throw Error("ao: tile_size must be at least 1, got " + std::to_string(options.tile_size));
}

Image render_ao(const SceneQueries& queries, const Scene& scene, const Camera& camera, const AoOptions& opt,
                RenderStats* stats) {
  validate_ao_options(opt);
  const PinholeCamera pinhole(camera);
  const SurfaceSpawner spawner(scene);
  const ImageTile region = render_region(opt.region, pinhole.width(), pinhole.height());
  const std::optional<DirectionLines> lines =
      opt.psf_level > 0 ? std::optional<DirectionLines>(std::in_place, opt.psf_level) : std::nullopt;
  if (lines && queries.occluder_prefers_line_streams()) return render_ao_lines(queries, scene, pinhole, opt, region, *lines, stats);
  Image image(region.x1 - region.x0, region.y1 - region.y0);
  auto shade_tile = [&](const ImageTile& tile) -> RayCounts {
    RayCounts rays;
    const std::size_t samples = static_cast<std::size_t>(tile.x1 - tile.x0) * static_cast<std::size_t>(tile.y1 - tile.y0) *
                                static_cast<std::size_t>(opt.spp);
    render_detail::OcclusionBatch batch(queries, samples);
    std::vector<float> total(samples, 0.0f);  // the weight of each sample's AO rays; < 0 for a miss
    std::size_t slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(pinhole.width()) + x;
        for (int s = 0; s < opt.spp; ++s, ++slot) {
          Rng rng(opt.seed, pixel, static_cast<std::uint64_t>(s));
          const Ray primary = pixel_ray(pinhole, x, y, opt.spp > 1, rng);
          ++rays.camera;
          const Hit hit = queries.intersect_camera(primary);
          if (!hit) {
            total[slot] = -1.0f;
            continue;
          }
          const SurfacePoint point = spawner.surface_point(primary, hit);
          if (lines) {
            for (std::size_t k = 0; k < lines->size(); ++k) {
              const Vec3f& w = lines->direction(k);
              const float c = dot(point.normal, w);
              if (c == 0.0f) continue;
              ++rays.ao;
              total[slot] += std::fabs(c);
              batch.add(Ray{point.position, c > 0.0f ? w : -w, 0.0f, opt.max_distance}, slot, Vec3f{std::fabs(c)});
            }
          } else {
            // Made where the batch holds them; in parts of at most its capacity, each continuing rng.
            const auto count = static_cast<std::size_t>(opt.ao_rays);
            for (std::size_t first = 0; first < count; first += render_detail::OcclusionBatch::kCapacity) {
              const std::size_t take = std::min(count - first, render_detail::OcclusionBatch::kCapacity);
              ao_rays(point, rng, opt.max_distance, take, batch.append(take, slot, Vec3f{1.0f}).data());
            }
            total[slot] = static_cast<float>(opt.ao_rays);
            rays.ao += static_cast<std::uint64_t>(opt.ao_rays);
          }
        }
      }
    }
    batch.flush();
    slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        float sum = 0.0f;
        for (int s = 0; s < opt.spp; ++s, ++slot)
          sum += total[slot] < 0.0f ? kAoBackground : total[slot] > 0.0f ? batch.sum(slot).x / total[slot] : 1.0f;
        image.at(x - region.x0, y - region.y0) = Vec3f(sum / static_cast<float>(opt.spp));
      }
    return rays;
  };
  for_each_tile(region, opt.tile_size, "ao", opt.progress, shade_tile, stats);
  return image;
}

}  // namespace vf
