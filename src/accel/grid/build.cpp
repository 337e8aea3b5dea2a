// O(N + cells) parallel build of the uniform grid, without atomics and without sorting, as a
// two-level stable counting sort of (cell, triangle) references:
//  1. the triangles are split into chunks of consecutive indices; each chunk lists the cells its
//     triangles meet and counts them per bucket (a bucket is 2^shift consecutive cells);
//  2. a prefix sum over (bucket, chunk) gives every chunk its slice of every bucket;
//  3. each chunk writes its (cell, triangle) pairs into its slices, in triangle order;
//  4. each bucket counting-sorts its pairs by cell into the final arrays and sets its cells' offsets.
// Both sorts are stable, so every cell lists its triangles in increasing index order, whatever the
// thread count or scheduling.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>

#include "grid/cell_overlap.hpp"
#include "visfield/core/memory.hpp"
#include "grid/geometry.hpp"
#include "grid/grid_layout.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/interrupt.hpp"

namespace vf {
namespace {

using Triangles = std::vector<std::array<Vec3f, 3>>;

/// How the build splits its work.
struct Partition {
  std::size_t chunk_count = 1;   ///< Chunks of consecutive triangles.
  std::size_t chunk_size = 1;    ///< Triangles per chunk (the last may hold fewer).
  int bucket_shift = 0;          ///< A bucket is 2^bucket_shift consecutive cells.
  std::size_t bucket_count = 1;  ///< Buckets covering all cells.
};

// Enough chunks to balance the threads; few enough that the chunk x bucket counts stay small
// beside the cell array.
constexpr std::size_t kTrianglesPerChunk = 2048;
constexpr std::size_t kMaxChunks = 256;
constexpr int kMinBucketShift = 6;

Partition make_partition(std::size_t triangles, std::size_t cells) {
  Partition p;
  p.chunk_count = std::clamp<std::size_t>((triangles + kTrianglesPerChunk - 1) / kTrianglesPerChunk, 1, kMaxChunks);
  p.chunk_size = (triangles + p.chunk_count - 1) / p.chunk_count;
  const std::size_t budget = std::max(cells, triangles) / 8;
  p.bucket_shift = kMinBucketShift;
  while (((cells >> p.bucket_shift) + 1) * p.chunk_count > budget && (std::size_t{1} << p.bucket_shift) < cells)
    ++p.bucket_shift;
  p.bucket_count = (cells >> p.bucket_shift) + 1;
  return p;
}

struct Reference {
  std::uint32_t cell, triangle;
};

// Bytes a build holds per reference at its peak: the cell of pass 1, the pair of pass 3 and the
// final triangle index.
constexpr double kBytesPerReference = sizeof(std::uint32_t) + sizeof(Reference) + sizeof(std::uint32_t);
// Pass 1 adds each chunk's references to the shared total after this many triangles.
constexpr std::size_t kTotalUpdateInterval = 256;

/// The most references a grid may hold: offsets are 32-bit, and the build must fit in the memory limit.
std::uint64_t reference_limit() {
  const double by_memory = std::floor(memory_limit().bytes / kBytesPerReference);
  const double by_offsets = static_cast<double>(std::numeric_limits<std::uint32_t>::max());
  return static_cast<std::uint64_t>(std::min(by_memory, by_offsets));
}

[[noreturn]] void refuse_references(std::uint64_t limit) {
  throw Error("grid: the triangles would need more than " + std::to_string(limit) +
              " cell references (the limit of 32-bit offsets and of " + memory_limit().source + "); lower the density");
}

/// What pass 1 leaves for pass 3: per chunk, the cells met by its triangles in triangle order,
/// and per triangle how many there are.
struct FoundCells {
  std::vector<std::vector<std::uint32_t>> chunk_cells;
  std::vector<std::uint32_t> triangle_cell_count;
  std::vector<std::uint32_t> bucket_counts;  ///< [chunk][bucket]; after pass 2, slice starts.
};

// Pass 1. Refuses (throws) as soon as the references found exceed `limit`, before holding much
// more than that; the outcome depends only on the final total.
void find_cells(const Triangles& triangles, const grid::CellFinder& finder, const Partition& p, std::uint64_t limit,
                FoundCells& found) {
  found.chunk_cells.resize(p.chunk_count);
  found.triangle_cell_count.resize(triangles.size());
  found.bucket_counts.assign(p.chunk_count * p.bucket_count, 0);
  std::atomic<std::uint64_t> found_total{0};
  vf::parallel_for(std::size_t{0}, p.chunk_count, [&](std::size_t chunk) {
    check_interrupt();
    const std::size_t begin = chunk * p.chunk_size, end = std::min(triangles.size(), begin + p.chunk_size);
    std::vector<std::uint32_t>& cells = found.chunk_cells[chunk];
    std::uint32_t* const counts = found.bucket_counts.data() + chunk * p.bucket_count;
    cells.reserve(2 * (end - begin));
    std::size_t reported = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t before = cells.size();
      finder.for_each_cell(triangles[i], [&](std::size_t cell) {
        if (cells.size() >= limit) refuse_references(limit);
        cells.push_back(static_cast<std::uint32_t>(cell));
        ++counts[cell >> p.bucket_shift];
      });
      found.triangle_cell_count[i] = static_cast<std::uint32_t>(cells.size() - before);
      if ((i - begin) % kTotalUpdateInterval == kTotalUpdateInterval - 1 || i + 1 == end) {
        if (found_total.fetch_add(cells.size() - reported, std::memory_order_relaxed) + (cells.size() - reported) > limit)
          refuse_references(limit);
        reported = cells.size();
      }
    }
  });
}

// Pass 2: turns the counts into slice starts (bucket-major, chunk-minor); returns the starts of
// the buckets (bucket_count + 1 entries, the last the total, which pass 1 kept within 32 bits).
std::vector<std::uint64_t> slice_starts(const Partition& p, std::vector<std::uint32_t>& bucket_counts) {
  std::vector<std::uint64_t> bucket_start(p.bucket_count + 1, 0);
  for (std::size_t chunk = 0; chunk < p.chunk_count; ++chunk) {
    const std::uint32_t* row = bucket_counts.data() + chunk * p.bucket_count;
    for (std::size_t b = 0; b < p.bucket_count; ++b) bucket_start[b + 1] += row[b];
  }
  for (std::size_t b = 0; b < p.bucket_count; ++b) bucket_start[b + 1] += bucket_start[b];
  std::vector<std::uint32_t> next(bucket_start.begin(), bucket_start.end() - 1);
  for (std::size_t chunk = 0; chunk < p.chunk_count; ++chunk) {
    std::uint32_t* row = bucket_counts.data() + chunk * p.bucket_count;
    for (std::size_t b = 0; b < p.bucket_count; ++b) {
      const std::uint32_t count = row[b];
      row[b] = next[b];
      next[b] += count;
    }
  }
  return bucket_start;
}

// Pass 3.
void scatter_to_buckets(const FoundCells& found, const Partition& p, std::size_t triangle_count,
                        std::vector<std::uint32_t>& slice_cursor, std::vector<Reference>& by_bucket) {
  vf::parallel_for(std::size_t{0}, p.chunk_count, [&](std::size_t chunk) {
    check_interrupt();
    const std::size_t begin = chunk * p.chunk_size, end = std::min(triangle_count, begin + p.chunk_size);
    std::uint32_t* const cursor = slice_cursor.data() + chunk * p.bucket_count;
    const std::uint32_t* cell = found.chunk_cells[chunk].data();
    for (std::size_t i = begin; i < end; ++i)
      for (std::uint32_t k = found.triangle_cell_count[i]; k != 0; --k, ++cell)
        by_bucket[cursor[*cell >> p.bucket_shift]++] = {*cell, static_cast<std::uint32_t>(i)};
  });
}

// Pass 4: fills cell_start[first cell of the bucket ..] and refs; returns the non-empty cell count.
std::size_t sort_buckets(const std::vector<Reference>& by_bucket, const std::vector<std::uint64_t>& bucket_start,
                         const Partition& p, std::size_t cells, std::vector<std::uint32_t>& cell_start,
                         std::vector<std::uint32_t>& refs) {
  return vf::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, p.bucket_count), std::size_t{0},
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t non_empty) {
        check_interrupt();
        std::vector<std::uint32_t> cursor(std::size_t{1} << p.bucket_shift);
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
          const std::size_t first_cell = b << p.bucket_shift;
          if (first_cell >= cells) continue;
          const std::size_t cell_count = std::min(cells - first_cell, cursor.size());
          const std::size_t mask = cursor.size() - 1;
          std::fill_n(cursor.begin(), cell_count, 0u);
          for (std::uint64_t r = bucket_start[b]; r != bucket_start[b + 1]; ++r) ++cursor[by_bucket[r].cell & mask];
          auto offset = static_cast<std::uint32_t>(bucket_start[b]);
          for (std::size_t c = 0; c < cell_count; ++c) {
            const std::uint32_t count = cursor[c];
            non_empty += count != 0 ? 1 : 0;
            cell_start[first_cell + c] = offset;
            cursor[c] = offset;
            offset += count;
          }
          for (std::uint64_t r = bucket_start[b]; r != bucket_start[b + 1]; ++r)
            refs[cursor[by_bucket[r].cell & mask]++] = by_bucket[r].triangle;
        }
        return non_empty;
      },
      [](std::size_t a, std::size_t b) { return a + b; });
}

}  // namespace

UniformGrid::UniformGrid(std::unique_ptr<const grid::GridLayout> layout) : layout_(std::move(layout)) {}
UniformGrid::UniformGrid(UniformGrid&&) noexcept = default;
UniformGrid& UniformGrid::operator=(UniformGrid&&) noexcept = default;
UniformGrid::~UniformGrid() = default;

const AccelStats& UniformGrid::stats() const { return layout_->stats; }
const GridGeometry& UniformGrid::geometry() const { return layout_->geometry; }
std::span<const std::uint32_t> UniformGrid::cell_starts() const { return layout_->cell_start; }
std::span<const std::uint32_t> UniformGrid::cell_references(std::size_t cell) const {
  const std::vector<std::uint32_t>& start = layout_->cell_start;
  return std::span<const std::uint32_t>(layout_->refs).subspan(start[cell], start[cell + 1] - start[cell]);
}

double UniformGrid::estimate_build_bytes(std::size_t triangles, const UniformGridConfig& config) {
  const auto n = static_cast<double>(triangles);
  return n * (80.0 + 4.0 * static_cast<double>(config.density) + 4.0 * 16.0);
}

UniformGrid UniformGrid::build(const TriangleSet& set, const UniformGridConfig& config) {
  const Stopwatch watch;
  auto g = std::make_unique<grid::GridLayout>();
  g->geometry = grid::make_geometry(set, config);
  g->slack_distance = set.size() > 0 ? grid::traversal_slack(g->geometry) : 0.0;
  const std::size_t cells = g->geometry.cell_count();
  const auto build_cells = [&] {
    g->cell_start.resize(cells + 1);
    if (cells == 0) return;
    const grid::CellFinder finder(g->geometry, grid::overlap_margin(g->geometry), config.exact_overlap);
    const Partition partition = make_partition(set.size(), cells);
    FoundCells found;
    find_cells(set.triangles, finder, partition, reference_limit(), found);
    const std::vector<std::uint64_t> bucket_start = slice_starts(partition, found.bucket_counts);
    const std::uint64_t total = bucket_start.back();
    std::vector<Reference> by_bucket(total);
    scatter_to_buckets(found, partition, set.size(), found.bucket_counts, by_bucket);
    found = FoundCells{};
    g->refs.resize(total);
    g->stats.leaf_count = sort_buckets(by_bucket, bucket_start, partition, cells, g->cell_start, g->refs);
    g->cell_start[cells] = static_cast<std::uint32_t>(total);
  };
  // The triangle set is copied while the cells are built.
  vf::parallel_invoke(build_cells, [&] {
    g->triangles = set.triangles;
    g->prim = set.prim;
    g->instance = set.instance;
  });
  AccelStats& s = g->stats;
  s.node_count = cells;
  s.reference_count = g->refs.size();
  s.max_depth = 0;
  s.memory_bytes = g->triangles.capacity() * sizeof(g->triangles[0]) +
                   (g->prim.capacity() + g->instance.capacity() + g->cell_start.capacity() + g->refs.capacity()) *
                       sizeof(std::uint32_t);
  s.build_ms = watch.elapsed_ms();
  return UniformGrid(std::move(g));
}

}  // namespace vf
