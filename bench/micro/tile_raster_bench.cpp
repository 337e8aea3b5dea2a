// Micro-benchmark of BeamField's conservative rasteriser (the edge walk with interior fill by rows;
// commit 8899b4b timed it here beside the exact separating-axis test it replaced):
// random triangles of a given extent (in units of the bounding sphere's radius) projected into a
// 64x64 PSF, with the build's slack. Run: build/bin/visfield-microbench --benchmark_filter=Raster

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "beam_field/tile_raster.hpp"
#include "visfield/core/rng.hpp"

namespace {

using vf::beam::Point2;
using vf::beam::TileGrid;

constexpr TileGrid kGrid{-1.0, -1.0, 2.0 / 64.0, 64};
constexpr double kSlack = 2e-5;

std::vector<Point2> triangles(double extent) {
  vf::Rng rng(1, 2);
  const auto unit = [&] { return 2.0 * static_cast<double>(rng.uniform()) - 1.0; };
  std::vector<Point2> corners;
  for (int i = 0; i < 4096; ++i) {
    const double s = unit(), t = unit();
    for (int k = 0; k < 3; ++k) corners.push_back({s + extent * unit(), t + extent * unit()});
  }
  return corners;
}

void raster(benchmark::State& state) {
  const std::vector<Point2> corners = triangles(static_cast<double>(state.range(0)) / 100.0);
  std::vector<std::uint32_t> tiles;
  std::size_t total = 0, triangles_done = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < corners.size(); i += 3) {
      tiles.clear();
      vf::beam::rasterize_triangle(kGrid, corners[i], corners[i + 1], corners[i + 2], kSlack, tiles);
      total += tiles.size();
    }
    triangles_done += corners.size() / 3;
    benchmark::DoNotOptimize(tiles.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(triangles_done));
  state.counters["tiles_per_triangle"] = static_cast<double>(total) / static_cast<double>(triangles_done);
}

// Extents 0.02, 0.05, 0.1, 0.3 and 1 of the radius (the argument is in hundredths).
BENCHMARK(raster)->Name("Raster/edge_walk_rows")->Arg(2)->Arg(5)->Arg(10)->Arg(30)->Arg(100);

}  // namespace

BENCHMARK_MAIN();
