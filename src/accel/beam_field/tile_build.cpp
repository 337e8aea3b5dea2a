// BeamField construction and update: per direction, every triangle is projected along the line,
// conservatively rasterised into the tiles its projection comes within `slack` of, clipped to each
// such tile's beam for its depth range, and the tile's references are split into 2^D equal depth
// leaves. A fresh build and an update share all of it: an update only rebuilds the tiles its old and
// new triangles touch. A kernel file: compiled once per instruction set (src/core/isa_dispatch.hpp).

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>

#include "beam_field/beam_layout.hpp"
#include "beam_field/tile_clip.hpp"
#include "beam_field/tile_footprint.hpp"
#include "beam_field/tile_geometry.hpp"
#include "beam_field/tile_raster.hpp"
#include "core/isa_dispatch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::isa_avx512 {
void beam_build_all_directions(beam::BeamLayout& layout);
std::size_t beam_count_tile_references(const beam::BeamLayout& layout, std::size_t line, std::span<const std::array<Vec3f, 3>> triangles);
void beam_update_directions(beam::BeamLayout& layout, const beam::SlotEdits& edits);
}  // namespace vf::isa_avx512

namespace vf::beam {
namespace {

/// Where a triangle lies in one tile: its depth range there (widened by the slack) and its footprint.
struct Placement {
  double lo, hi;
  std::uint32_t footprint;
};

/// One reference before it is stored: a triangle slot in a tile, with its placement there.
struct Entry {
  std::uint32_t tile;
  std::uint32_t slot;
  double lo, hi;
  std::uint32_t footprint;
};

/// Per-thread buffers, reused across directions.
struct Scratch {
  std::vector<Entry> entries;
  std::vector<Entry> sorted;
  std::vector<std::uint32_t> tiles;
  std::vector<std::uint32_t> counts;
  std::vector<std::uint8_t> marked;
  std::vector<std::uint32_t> affected;
  std::vector<std::uint32_t> record;
  std::vector<std::uint32_t> arena;
  std::vector<Entry> tile_entries;
};

/// The direction-independent parts of rasterising into one direction's tiles.
class Rasterizer {
 public:
  Rasterizer(const BeamLayout& layout, std::size_t line)
      : frame_(layout.frames[line]), geometry_(layout.geometry),
        grid_{-layout.geometry.radius, -layout.geometry.radius, layout.geometry.tile_size, layout.geometry.n},
        flat_area_(1e-12 * layout.geometry.radius * layout.geometry.radius) {}

  /// Calls visit(tile, placement) for every tile triangle `corners` comes within slack of.
  template <class Visit>
  void rasterize(const std::array<Vec3f, 3>& corners, std::vector<std::uint32_t>& tiles, Visit&& visit) const {
    const Projected p = project_corners(corners);
    const auto index = [&](int x, int y) { return static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(geometry_.n) + static_cast<std::uint32_t>(x); };
    // A triangle inside one tile (the common case for fine meshes) keeps its whole depth range; one
    // whose box spans two tiles in a row or column meets both (it is connected); others are tested
    // tile by tile.
    if (p.x0 == p.x1 && p.y0 == p.y1) {
      visit(index(p.x0, p.y0), place(whole_box(p.c[0], p.c[1], p.c[2]), p.x0, p.y0));
      return;
    }
    tiles.clear();
    if ((p.x1 - p.x0) + (p.y1 - p.y0) == 1) {
      tiles.push_back(index(p.x0, p.y0));
      tiles.push_back(index(p.x1, p.y1));
    } else {
      rasterize_triangle(grid_, {p.c[0].s, p.c[0].t}, {p.c[1].s, p.c[1].t}, {p.c[2].s, p.c[2].t}, geometry_.slack, tiles);
    }
    const auto n = static_cast<std::uint32_t>(geometry_.n);
    for (const std::uint32_t tile : tiles) visit(tile, placement(p, static_cast<int>(tile % n), static_cast<int>(tile / n)));
  }

  /// Calls visit(tile) for every tile of the bounding box of `corners`' projection (widened by the
  /// slack): every tile rasterize() would visit, and for a large triangle a few more. O(box tiles).
  template <class Visit>
  void for_each_box_tile(const std::array<Vec3f, 3>& corners, Visit&& visit) const {
    const Projected p = project_corners(corners);
    for (int y = p.y0; y <= p.y1; ++y)
      for (int x = p.x0; x <= p.x1; ++x) visit(static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(geometry_.n) + static_cast<std::uint32_t>(x));
  }

  /// The placement rasterize() gives triangle `corners` in tile `tile`, which it must reach. O(1).
  Placement place_in(const std::array<Vec3f, 3>& corners, std::uint32_t tile) const {
    const Projected p = project_corners(corners);
    const auto n = static_cast<std::uint32_t>(geometry_.n);
    return placement(p, static_cast<int>(tile % n), static_cast<int>(tile / n));
  }

 private:
  // A triangle in PSF coordinates and the tiles its box (widened by the slack) spans.
  struct Projected {
    PsfPoint c[3];
    int x0, x1, y0, y1;
  };

  Projected project_corners(const std::array<Vec3f, 3>& corners) const {
    const std::array<double, 3>& c = geometry_.center;
    Projected p{{project(frame_, c, corners[0]), project(frame_, c, corners[1]), project(frame_, c, corners[2])}, 0, 0, 0, 0};
    const double e = geometry_.slack;
    p.x0 = geometry_.cell(std::min({p.c[0].s, p.c[1].s, p.c[2].s}) - e), p.x1 = geometry_.cell(std::max({p.c[0].s, p.c[1].s, p.c[2].s}) + e);
    p.y0 = geometry_.cell(std::min({p.c[0].t, p.c[1].t, p.c[2].t}) - e), p.y1 = geometry_.cell(std::max({p.c[0].t, p.c[1].t, p.c[2].t}) + e);
    return p;
  }

  // The placement of a triangle in tile (x, y), one of those it reaches. A triangle within a 2×2
  // block of tiles keeps its whole box (the footprint is clamped to the tile anyway, and clipping
  // such a small triangle narrows its depth range little); a larger one is clipped to the beam.
  Placement placement(const Projected& p, int x, int y) const {
    if (p.x1 - p.x0 <= 1 && p.y1 - p.y0 <= 1) return place(whole_box(p.c[0], p.c[1], p.c[2]), x, y);
    const double e = geometry_.slack;
    const double s0 = -geometry_.radius + x * geometry_.tile_size - e, s1 = -geometry_.radius + (x + 1) * geometry_.tile_size + e;
    const double t0 = -geometry_.radius + y * geometry_.tile_size - e, t1 = -geometry_.radius + (y + 1) * geometry_.tile_size + e;
    return place(clip_to_beam(p.c[0], p.c[1], p.c[2], s0, s1, t0, t1, flat_area_), x, y);
  }

  // The placement in tile (x, y) of a triangle part whose box is `b`, widened by the slack: the ray
  // point at a hit lies within the slack of the triangle (see traversal.cpp).
  Placement place(const BeamBox& b, int x, int y) const {
    const double e = geometry_.slack, inv = geometry_.inv_tile_size;
    const double s_base = -geometry_.radius + x * geometry_.tile_size, t_base = -geometry_.radius + y * geometry_.tile_size;
    return {b.lo - e, b.hi + e,
            footprint((b.s_lo - e - s_base) * inv, (b.s_hi + e - s_base) * inv, (b.t_lo - e - t_base) * inv,
                      (b.t_hi + e - t_base) * inv)};
  }

  const FrameD& frame_;
  const TileGeometry& geometry_;
  TileGrid grid_;
  double flat_area_;
};

// A deeper tile-BSP than needed for leaf_size references per leaf costs leaf-start words and
// duplicated straddlers for nothing; one that would store more than kMaxDuplication references per
// triangle of the tile (triangles lying along the beam) is made shallower.
constexpr double kMaxDuplication = 3.0;

/// Appends the record of one tile (entries sorted by slot) to `out` (layout in beam_layout.hpp);
/// returns its offset there. Throws vf::Error past 32-bit offsets.
std::uint32_t make_record(std::span<const Entry> entries, const BeamFieldConfig& config, std::vector<std::uint32_t>& out) {
  double lo = entries[0].lo, hi = entries[0].hi;
  for (const Entry& e : entries) lo = std::min(lo, e.lo), hi = std::max(hi, e.hi);
  const std::size_t count = entries.size();
  int depth = 0;
  while (depth < config.max_depth && (count >> depth) > static_cast<std::size_t>(config.leaf_size)) ++depth;
  const float lo_f = static_cast<float>(lo);
  const auto scale_for = [&](int d) {
    const double width = hi - static_cast<double>(lo_f);
    return width > 0.0 ? static_cast<float>(static_cast<double>(1 << d) / width) : 0.0f;
  };
  const auto references_at = [&](int d) {
    const double scale = scale_for(d);
    std::size_t refs = 0;
    for (const Entry& e : entries)
      refs += static_cast<std::size_t>(leaf_of(e.hi, lo_f, scale, (1 << d) - 1) - leaf_of(e.lo, lo_f, scale, (1 << d) - 1) + 1);
    return refs;
  };
  if (!(scale_for(depth) > 0.0f) || !std::isfinite(scale_for(depth))) depth = 0;
  while (depth > 0 && static_cast<double>(references_at(depth)) > kMaxDuplication * static_cast<double>(count)) --depth;

  const int leaves = 1 << depth;
  const float scale_f = depth == 0 ? 0.0f : scale_for(depth);
  const std::size_t first_ref = kRecordHeaderWords + static_cast<std::size_t>(leaves) + 1;
  const std::size_t base = out.size();
  out.resize(base + first_ref, 0);
  std::uint32_t* words = out.data() + base;
  words[0] = std::bit_cast<std::uint32_t>(lo_f);
  words[1] = std::bit_cast<std::uint32_t>(scale_f);
  words[2] = static_cast<std::uint32_t>(depth);
  std::uint32_t* starts = words + kRecordHeaderWords;
  for (const Entry& e : entries) {
    const int a = leaf_of(e.lo, lo_f, scale_f, leaves - 1), b = leaf_of(e.hi, lo_f, scale_f, leaves - 1);
    for (int l = a; l <= b; ++l) ++starts[l + 1];
  }
  for (int l = 0; l < leaves; ++l) starts[l + 1] += starts[l];
  const std::uint32_t references = starts[leaves];
  const std::size_t size = first_ref + 2 * static_cast<std::size_t>(references);
  if (base + size >= kEmptyTile) throw Error("beam: a direction's tile records exceed 2^32 words (lower n, dirs or depth)");
  out.resize(base + size);
  words = out.data() + base;
  starts = words + kRecordHeaderWords;
  std::uint32_t* data = words + first_ref;
  // Leaf l's footprints begin at 2 starts[l], its slots after them; filled in entry (slot) order.
  std::uint32_t filled[1 << kMaxTileDepth];
  std::fill_n(filled, leaves, 0u);
  for (const Entry& e : entries) {
    const int a = leaf_of(e.lo, lo_f, scale_f, leaves - 1), b = leaf_of(e.hi, lo_f, scale_f, leaves - 1);
    for (int l = a; l <= b; ++l) {
      const std::size_t footprint_at = 2 * static_cast<std::size_t>(starts[l]) + filled[l]++;
      data[footprint_at] = e.footprint;
      data[footprint_at + (starts[l + 1] - starts[l])] = e.slot;
    }
  }
  words[3] = static_cast<std::uint32_t>(size);  // capacity: exactly its size when written
  return static_cast<std::uint32_t>(base);
}

/// Appends `record` to the direction's arena and returns its offset; throws past 32-bit offsets.
std::uint32_t append_record(DirectionTiles& dir, const std::vector<std::uint32_t>& record) {
  if (dir.arena.size() + record.size() >= kEmptyTile)
    throw Error("beam: a direction's tile records exceed 2^32 words (lower n, dirs or depth)");
  const auto offset = static_cast<std::uint32_t>(dir.arena.size());
  dir.arena.insert(dir.arena.end(), record.begin(), record.end());
  return offset;
}

/// Groups `entries` by tile (stable: slot order kept within a tile) into `sorted`, with counts.
void sort_by_tile(const std::vector<Entry>& entries, std::size_t tile_count, Scratch& s) {
  s.counts.assign(tile_count + 1, 0);
  for (const Entry& e : entries) ++s.counts[e.tile + 1];
  for (std::size_t i = 0; i < tile_count; ++i) s.counts[i + 1] += s.counts[i];
  s.sorted.resize(entries.size());
  std::vector<std::uint32_t>& fill = s.tiles;  // reused as the fill cursor
  fill.assign(s.counts.begin(), s.counts.end() - 1);
  for (const Entry& e : entries) s.sorted[fill[e.tile]++] = e;
}

void build_direction(const BeamLayout& layout, std::size_t line, DirectionTiles& dir, Scratch& s) {
  const Rasterizer raster(layout, line);
  const std::size_t tile_count = static_cast<std::size_t>(layout.geometry.n) * static_cast<std::size_t>(layout.geometry.n);
  s.entries.clear();
  std::vector<std::uint32_t> tiles;
  for (std::uint32_t slot = 0; slot < layout.triangles.size(); ++slot) {
    if (!layout.alive[slot]) continue;
    raster.rasterize(layout.triangles[slot], tiles, [&](std::uint32_t tile, Placement p) { s.entries.push_back({tile, slot, p.lo, p.hi, p.footprint}); });
  }
  sort_by_tile(s.entries, tile_count, s);
  dir.tiles.assign(tile_count, kEmptyTile);
  // Records go to the thread's scratch arena (whose memory is reused from direction to direction),
  // then into the direction's own, allocated once at its exact size.
  s.arena.clear();
  for (std::size_t tile = 0; tile < tile_count; ++tile) {
    const std::uint32_t begin = s.counts[tile], end = s.counts[tile + 1];
    if (begin == end) continue;
    dir.tiles[tile] = make_record(std::span<const Entry>(s.sorted.data() + begin, end - begin), layout.config, s.arena);
  }
  dir.arena.assign(s.arena.begin(), s.arena.end());
  dir.live_words = dir.arena.size();
  dir.records = dir.leaves = dir.references = 0;
  dir.depths.fill(0);
  for (const std::uint32_t offset : dir.tiles)
    if (offset != kEmptyTile) dir.count(offset, +1);
}

/// The distinct slots of a record (its references without the straddlers' repeats), ascending.
void record_slots(const std::uint32_t* record, std::vector<std::uint32_t>& slots) {
  const RecordView view(record);
  slots.clear();
  for (int leaf = 0; leaf <= view.last_leaf(); ++leaf)
    slots.insert(slots.end(), view.leaf_slots(leaf), view.leaf_slots(leaf) + view.leaf_size(leaf));
  std::sort(slots.begin(), slots.end());
  slots.erase(std::unique(slots.begin(), slots.end()), slots.end());
}


/// Writes to `out` the record `old` edited: without the references of dropped slots, with `added`
/// (sorted by slot) put in the leaves of their depth ranges under `old`'s leaf planes. The survivors
/// keep their leaves and footprints: nothing of theirs is recomputed. False (and `out` untouched)
/// when an added reference reaches more than a leaf beyond the depth span of `old`'s leaves: the
/// leaves are then redrawn from scratch. (Depths past the span fall in the end leaves, which is
/// exact, as queries clamp alike; it only unbalances the leaves.)
bool edit_record(const RecordView& old, const std::vector<std::uint8_t>& dropped, std::span<const Entry> added,
                 std::vector<std::uint32_t>& out) {
  const int last = old.last_leaf();
  const double lo = old.lo(), scale = old.scale();
  if (last > 0) {
    // Up to one leaf past either end is let in (clamped into the end leaf); the span itself never
    // moves, so that is all the imbalance edits can accumulate.
    const double width = 1.0 / scale, hi = lo + static_cast<double>(last + 1) * width;
    for (const Entry& e : added)
      if (e.lo < lo - width || e.hi > hi + width) return false;
  }
  const std::size_t leaves = static_cast<std::size_t>(last) + 1;
  const std::size_t first_ref = kRecordHeaderWords + leaves + 1;
  out.assign(first_ref, 0);
  out[0] = std::bit_cast<std::uint32_t>(old.lo());
  out[1] = std::bit_cast<std::uint32_t>(old.scale());
  out[2] = static_cast<std::uint32_t>(old.depth());
  const auto kept = [&](int leaf, std::uint32_t k) { return !dropped[old.leaf_slots(leaf)[k]]; };
  const auto range_of = [&](const Entry& e) {
    return std::pair{leaf_of(e.lo, lo, scale, last), leaf_of(e.hi, lo, scale, last)};
  };
  std::uint32_t* starts = out.data() + kRecordHeaderWords;
  for (int leaf = 0; leaf <= last; ++leaf)
    for (std::uint32_t k = 0; k < old.leaf_size(leaf); ++k) starts[leaf + 1] += kept(leaf, k) ? 1u : 0u;
  for (const Entry& e : added) {
    const auto [a, b] = range_of(e);
    for (int l = a; l <= b; ++l) ++starts[l + 1];
  }
  for (std::size_t l = 0; l < leaves; ++l) starts[l + 1] += starts[l];
  const std::size_t size = first_ref + 2 * static_cast<std::size_t>(starts[leaves]);
  out.resize(size);
  starts = out.data() + kRecordHeaderWords;
  std::uint32_t* data = out.data() + first_ref;
  for (int leaf = 0; leaf <= last; ++leaf) {
    const std::uint32_t count = starts[leaf + 1] - starts[leaf];
    std::uint32_t* footprints = data + 2 * static_cast<std::size_t>(starts[leaf]);
    std::uint32_t* slots = footprints + count;
    std::uint32_t filled = 0;
    for (std::uint32_t k = 0; k < old.leaf_size(leaf); ++k) {
      if (!kept(leaf, k)) continue;
      footprints[filled] = old.leaf_footprints(leaf)[k];
      slots[filled++] = old.leaf_slots(leaf)[k];
    }
    for (const Entry& e : added) {
      const auto [a, b] = range_of(e);
      if (leaf < a || leaf > b) continue;
      footprints[filled] = e.footprint;
      slots[filled++] = e.slot;
    }
  }
  out[3] = static_cast<std::uint32_t>(size);
  return true;
}

void update_direction(const BeamLayout& layout, const SlotEdits& edits, std::size_t line, DirectionTiles& dir, Scratch& s) {
  const Rasterizer raster(layout, line);
  const int n = layout.geometry.n;
  const std::size_t tile_count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  s.marked.assign(tile_count, 0);
  s.affected.clear();
  const auto mark = [&](std::uint32_t tile) {
    if (!s.marked[tile]) s.marked[tile] = 1, s.affected.push_back(tile);
  };
  std::vector<std::uint32_t> tiles;
  // The tiles the old triangles left: their boxes' tiles (a superset; a tile marked in vain is only
  // rebuilt as it was), found without clipping or footprints.
  for (const auto& corners : edits.old_corners) raster.for_each_box_tile(corners, mark);
  s.entries.clear();
  for (const std::uint32_t slot : edits.add)
    raster.rasterize(layout.triangles[slot], tiles, [&](std::uint32_t tile, Placement p) {
      mark(tile);
      s.entries.push_back({tile, slot, p.lo, p.hi, p.footprint});
    });
  std::sort(s.affected.begin(), s.affected.end());
  std::stable_sort(s.entries.begin(), s.entries.end(), [](const Entry& a, const Entry& b) { return a.tile < b.tile; });

  std::vector<std::uint32_t> survivors;
  std::size_t next_new = 0;
  for (const std::uint32_t tile : s.affected) {
    while (next_new < s.entries.size() && s.entries[next_new].tile < tile) ++next_new;
    const std::size_t first_new = next_new;
    while (next_new < s.entries.size() && s.entries[next_new].tile == tile) ++next_new;
    const std::span<const Entry> added(s.entries.data() + first_new, next_new - first_new);
    const std::uint32_t offset = dir.tiles[tile];
    s.record.clear();
    // Usually the tile's leaves stay and only the edited references change; otherwise the record is
    // redrawn with every surviving reference placed anew.
    if (offset == kEmptyTile || !edit_record(RecordView(dir.arena.data() + offset), edits.dropped, added, s.record)) {
      s.tile_entries.assign(added.begin(), added.end());
      if (offset != kEmptyTile) {
        record_slots(dir.arena.data() + offset, survivors);
        for (const std::uint32_t slot : survivors) {
          if (edits.dropped[slot]) continue;
          const Placement p = raster.place_in(layout.triangles[slot], tile);
          s.tile_entries.push_back({tile, slot, p.lo, p.hi, p.footprint});
        }
      }
      std::sort(s.tile_entries.begin(), s.tile_entries.end(), [](const Entry& a, const Entry& b) { return a.slot < b.slot; });
      if (!s.tile_entries.empty()) make_record(s.tile_entries, layout.config, s.record);
    }

    const std::size_t old_words = offset == kEmptyTile ? 0 : RecordView(dir.arena.data() + offset).words();
    dir.live_words -= old_words;
    if (offset != kEmptyTile) dir.count(offset, -1);
    if (s.record.empty() || RecordView(s.record.data()).references() == 0) {
      dir.tiles[tile] = kEmptyTile;
      continue;
    }
    dir.live_words += s.record.size();
    if (offset != kEmptyTile && s.record.size() <= dir.arena[offset + 3]) {
      const std::uint32_t capacity = dir.arena[offset + 3];
      std::copy(s.record.begin(), s.record.end(), dir.arena.begin() + offset);
      dir.arena[offset + 3] = capacity;
    } else {
      // A tile an object moves through is likely to change again next frame: its record gets a
      // quarter of room to grow in place, so that the arena does not grow (and move) every frame.
      const std::size_t capacity = s.record.size() + s.record.size() / 4 + 4;
      s.record[3] = static_cast<std::uint32_t>(capacity);
      s.record.resize(capacity, 0);
      dir.tiles[tile] = append_record(dir, s.record);
    }
    dir.count(dir.tiles[tile], +1);
  }
  // Records that moved to the end left holes; when holes outweigh the records, copy the live ones
  // into a fresh arena in tile order.
  if (dir.arena.size() > 2 * dir.live_words + 1024) {
    std::vector<std::uint32_t> compact;
    compact.reserve(dir.live_words);
    for (std::uint32_t& offset : dir.tiles) {
      if (offset == kEmptyTile) continue;
      const std::uint32_t* record = dir.arena.data() + offset;
      const std::size_t words = RecordView(record).words();
      const auto moved = static_cast<std::uint32_t>(compact.size());
      compact.insert(compact.end(), record, record + words);
      compact[moved + 3] = static_cast<std::uint32_t>(words);
      offset = moved;
    }
    dir.arena = std::move(compact);
    dir.live_words = dir.arena.size();
  }
}

}  // namespace

void build_all_directions(BeamLayout& layout) {
  VF_USE_WIDER(beam_build_all_directions, layout);
  layout.directions.assign(layout.lines.size(), {});
  tbb::enumerable_thread_specific<Scratch> scratch;
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, layout.lines.size(), 1), [&](const auto& range) {
    for (std::size_t line = range.begin(); line != range.end(); ++line) {
      check_interrupt();
      build_direction(layout, line, layout.directions[line], scratch.local());
    }
  });
}

std::size_t count_tile_references(const BeamLayout& layout, std::size_t line, std::span<const std::array<Vec3f, 3>> triangles) {
  VF_USE_WIDER(beam_count_tile_references, layout, line, triangles);
  const Rasterizer raster(layout, line);
  std::vector<std::uint32_t> tiles;
  std::size_t count = 0;
  for (const auto& corners : triangles) raster.rasterize(corners, tiles, [&](std::uint32_t, Placement) { ++count; });
  return count;
}

void update_directions(BeamLayout& layout, const SlotEdits& edits) {
  VF_USE_WIDER(beam_update_directions, layout, edits);
  tbb::enumerable_thread_specific<Scratch> scratch;
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, layout.lines.size(), 1), [&](const auto& range) {
    for (std::size_t line = range.begin(); line != range.end(); ++line)
      update_direction(layout, edits, line, layout.directions[line], scratch.local());
  });
}

}  // namespace vf::beam

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void beam_build_all_directions(beam::BeamLayout& layout) { beam::build_all_directions(layout); }
VF_WIDER_ENTRY std::size_t beam_count_tile_references(const beam::BeamLayout& layout, std::size_t line,
                                                      std::span<const std::array<Vec3f, 3>> triangles) {
  return beam::count_tile_references(layout, line, triangles);
}
VF_WIDER_ENTRY void beam_update_directions(beam::BeamLayout& layout, const beam::SlotEdits& edits) { beam::update_directions(layout, edits); }
}  // namespace vf::isa_avx512
#endif
