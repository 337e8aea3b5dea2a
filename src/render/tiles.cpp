#include "visfield/render/tiles.hpp"

#include <algorithm>
#include <atomic>

#include <tbb/blocked_range.h>

#include "visfield/core/error.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/render/progress.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/interrupt.hpp"

namespace vf {

ImageTile render_region(const ImageTile& region, int width, int height) {
  if (region.x1 <= region.x0 && region.y1 <= region.y0 && region.x0 == 0 && region.y0 == 0) return ImageTile{0, 0, width, height};
  if (!(0 <= region.x0 && region.x0 < region.x1 && region.x1 <= width && 0 <= region.y0 && region.y0 < region.y1 && region.y1 <= height))
    throw Error("render: region [" + std::to_string(region.x0) + ", " + std::to_string(region.x1) + ") x [" + std::to_string(region.y0) +
                ", " + std::to_string(region.y1) + ") is empty or not inside the " + std::to_string(width) + "x" +
                std::to_string(height) + " image");
  return region;
}

void for_each_tile(const ImageTile& region, int tile_size, const std::string& label, bool progress,
                   const std::function<RayCounts(const ImageTile&)>& shade, RenderStats* stats) {
  const Stopwatch watch;
  const int width = region.x1 - region.x0, height = region.y1 - region.y0;
  const int tiles_x = (width + tile_size - 1) / tile_size;
  const int tiles_y = (height + tile_size - 1) / tile_size;
  const auto tile_count = static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y);
  ProgressBar bar(label, tile_count, progress);
  // An integer sum: the total does not depend on the order the tiles finish in.
  std::atomic<std::uint64_t> camera{0}, shadow{0}, reflection{0}, ao{0};
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, tile_count, 1), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      check_interrupt();
      const int tx = static_cast<int>(i % static_cast<std::size_t>(tiles_x));
      const int ty = static_cast<int>(i / static_cast<std::size_t>(tiles_x));
      const ImageTile tile{region.x0 + tx * tile_size, region.y0 + ty * tile_size, region.x0 + std::min(width, (tx + 1) * tile_size),
                           region.y0 + std::min(height, (ty + 1) * tile_size)};
      const RayCounts counts = shade(tile);
      camera.fetch_add(counts.camera, std::memory_order_relaxed);
      shadow.fetch_add(counts.shadow, std::memory_order_relaxed);
      reflection.fetch_add(counts.reflection, std::memory_order_relaxed);
      ao.fetch_add(counts.ao, std::memory_order_relaxed);
      bar.tick();
    }
  });
  bar.finish();
  if (stats) {
    stats->width = width;
    stats->height = height;
    stats->by_kind = RayCounts{camera.load(), shadow.load(), reflection.load(), ao.load()};
    stats->rays = stats->by_kind.total();
    stats->seconds = watch.elapsed_s();
  }
}

}  // namespace vf
