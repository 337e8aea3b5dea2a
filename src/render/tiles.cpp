#include "visfield/render/tiles.hpp"

#include <algorithm>
#include <atomic>

#include <tbb/blocked_range.h>

#include "visfield/core/stopwatch.hpp"
#include "visfield/render/progress.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/interrupt.hpp"

namespace vf {

void for_each_tile(int width, int height, int tile_size, const std::string& label, bool progress,
                   const std::function<std::uint64_t(const ImageTile&)>& shade, RenderStats* stats) {
  const Stopwatch watch;
  const int tiles_x = (width + tile_size - 1) / tile_size;
  const int tiles_y = (height + tile_size - 1) / tile_size;
  const auto tile_count = static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y);
  ProgressBar bar(label, tile_count, progress);
  // An integer sum: the total does not depend on the order the tiles finish in.
  std::atomic<std::uint64_t> rays{0};
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, tile_count, 1), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      check_interrupt();
      const int tx = static_cast<int>(i % static_cast<std::size_t>(tiles_x));
      const int ty = static_cast<int>(i / static_cast<std::size_t>(tiles_x));
      const ImageTile tile{tx * tile_size, ty * tile_size, std::min(width, (tx + 1) * tile_size),
                           std::min(height, (ty + 1) * tile_size)};
      rays.fetch_add(shade(tile), std::memory_order_relaxed);
      bar.tick();
    }
  });
  bar.finish();
  if (stats) {
    stats->width = width;
    stats->height = height;
    stats->rays = rays.load();
    stats->seconds = watch.elapsed_s();
  }
}

}  // namespace vf
