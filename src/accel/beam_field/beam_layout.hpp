#pragma once
// Private to accel: the storage of a BeamField and the geometry every part of it agrees on.
//
// Per direction, `tiles` holds for each of the n² tiles the offset of its record in `arena`, or
// kEmptyTile. A record is self-contained and contiguous, so that a query reads a few cache lines:
//
//   word 0       lo: the depth (along the line) where leaf 0 starts, float bits
//   word 1       scale: leaves per unit depth, float bits (leaf of depth w = floor((w - lo) * scale))
//   word 2       D: the tile-BSP depth, 2^D leaves
//   word 3       capacity: words the record may grow to in place (an update rewrites it there if it fits)
//   words 4..    2^D + 1 leaf starts: reference counts before each leaf (the last is the total)
//   then         leaf after leaf: the leaf's footprints (tile_footprint.hpp), then its references
//                (triangle slots) in the same order; a triangle spanning leaves is in each
//
// A leaf's footprints and references are adjacent, and the leaves follow each other in walk order,
// so a ray's leaf walk reads one contiguous run of memory.
//
// Triangles live in slots (world-space corners, mesh triangle, object); an object's triangles occupy a
// contiguous run of slots, which a move rewrites in place. Removed objects leave dead slots until a
// rebuild reclaims them.

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "visfield/accel/beam_field.hpp"
#include "visfield/core/direction_lines.hpp"

namespace vf::beam {

inline constexpr std::uint32_t kEmptyTile = 0xffffffffu;
inline constexpr std::uint32_t kRecordHeaderWords = 4;
/// The deepest tile-BSP (BeamFieldConfig::max_depth's upper bound): 4096 leaves.
inline constexpr int kMaxTileDepth = 12;

/// Read access to one tile record (layout above). O(1) per call; a view, owns nothing.
class RecordView {
 public:
  explicit RecordView(const std::uint32_t* record) : record_(record) {}

  float lo() const { return std::bit_cast<float>(record_[0]); }       ///< Depth where leaf 0 starts.
  float scale() const { return std::bit_cast<float>(record_[1]); }    ///< Leaves per unit depth.
  int depth() const { return static_cast<int>(record_[2]); }          ///< D: 2^D leaves.
  int last_leaf() const { return (1 << record_[2]) - 1; }             ///< 2^D - 1.
  std::uint32_t capacity() const { return record_[3]; }              ///< Words it may grow to in place.
  const std::uint32_t* starts() const { return record_ + kRecordHeaderWords; }  ///< 2^D + 1 leaf starts.
  std::uint32_t references() const { return starts()[last_leaf() + 1]; }      ///< All leaves' references.
  std::uint32_t leaf_size(int leaf) const { return starts()[leaf + 1] - starts()[leaf]; }  ///< References of `leaf`.
  /// The footprints of `leaf`'s references; its slots follow them.
  const std::uint32_t* leaf_footprints(int leaf) const { return data() + 2 * static_cast<std::size_t>(starts()[leaf]); }
  /// The triangle slots of `leaf`, in the order of its footprints.
  const std::uint32_t* leaf_slots(int leaf) const { return leaf_footprints(leaf) + leaf_size(leaf); }
  /// Words of the record.
  std::size_t words() const { return static_cast<std::size_t>(data() - record_) + 2 * static_cast<std::size_t>(references()); }

 private:
  const std::uint32_t* data() const { return record_ + kRecordHeaderWords + last_leaf() + 2; }
  const std::uint32_t* record_;
};

/// A PSF frame in double precision (converted from the float frame the direction set stores).
struct FrameD {
  double u[3], v[3], w[3];
};

/// One direction's tiles and records.
struct DirectionTiles {
  std::vector<std::uint32_t> tiles;  ///< n² record offsets into arena, or kEmptyTile.
  std::vector<std::uint32_t> arena;  ///< Records, back to back (holes after updates).
  std::size_t live_words = 0;        ///< Words of the records tiles point at (arena.size() minus holes).
  // Counts over the live records, kept by build and update so that statistics need no scan.
  std::size_t records = 0;                                    ///< Non-empty tiles.
  std::size_t leaves = 0;                                     ///< Leaves of all records.
  std::size_t references = 0;                                 ///< References of all records.
  std::array<std::uint32_t, kMaxTileDepth + 1> depths{};     ///< Records of each tile-BSP depth.

  /// Adds (sign = +1) or removes (-1) the record at `offset` to or from the counts.
  void count(std::uint32_t offset, int sign);
};

inline void DirectionTiles::count(std::uint32_t offset, int sign) {
  const RecordView r(arena.data() + offset);
  const auto n = static_cast<std::size_t>(sign > 0 ? 1 : -1);  // wraps for -1: unsigned sums stay exact
  records += n;
  leaves += n * (static_cast<std::size_t>(r.last_leaf()) + 1);
  references += n * r.references();
  depths[static_cast<std::size_t>(r.depth())] += static_cast<std::uint32_t>(n);
}

/// Where the tiles lie: the bounding sphere (centre c, radius R) and n tiles of side 2R/n per axis.
struct TileGeometry {
  std::array<double, 3> center{};  ///< c, a float point (so p - c is exact in double for float p).
  double radius = 0.0;             ///< R: every live triangle corner lies within R of c.
  int n = 0;                       ///< Tiles per side.
  double tile_size = 0.0;          ///< 2R / n.
  double inv_tile_size = 0.0;      ///< n / 2R.
  double slack = 0.0;              ///< Build margin in (s, t) and depth: 2e-5 R (beam_field.cpp says why).

  /// Tile column (or row) of PSF coordinate s, clamped to [0, n).
  int cell(double s) const;
};

/// One object as the field holds it.
struct ObjectSlots {
  ObjectId id = kInvalidId;
  std::uint32_t mesh = 0;
  Transform transform;
  std::uint32_t first_slot = 0;  ///< Its triangles are slots [first_slot, first_slot + slot_count).
  std::uint32_t slot_count = 0;
};

/// Everything a BeamField holds.
struct BeamLayout {
  BeamFieldConfig config;
  DirectionLines lines{4};
  std::vector<FrameD> frames;  ///< By line.
  TileGeometry geometry;

  // Triangle slots.
  std::vector<std::array<Vec3f, 3>> triangles;
  std::vector<std::uint32_t> prim;
  std::vector<ObjectId> instance;
  std::vector<std::uint8_t> alive;
  std::size_t live_slots = 0;

  std::vector<DirectionTiles> directions;  ///< By line.
  std::vector<ObjectSlots> objects;        ///< Committed objects, by increasing id.

  // Edits: the objects as staged (by increasing id), and the object-space meshes they use (by the
  // scene's mesh index), which a move or insert places anew exactly as flatten() would.
  struct StagedObject {
    ObjectId id;
    std::uint32_t mesh;
    Transform transform;
  };
  std::vector<StagedObject> staged;
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;
  bool has_staged_edits = false;

  AccelStats stats;
  double last_commit_ms = 0.0;
  bool last_commit_rebuilt = false;

  /// Recounts stats (memory, references, leaves, tiles) from the directions' counts. O(directions).
  void recount();
};

/// The slots of `triangles` that a commit writes: `add` are (re)rasterised with their current corners,
/// `old_corners` are the corners of moved or removed slots before the edit (rasterised to find the
/// tiles they leave), `dropped` flags slots whose references must leave every tile.
struct SlotEdits {
  std::vector<std::uint32_t> add;                          ///< Slots to reference (sorted).
  std::vector<std::array<Vec3f, 3>> old_corners;           ///< Corners the edited slots had.
  std::vector<std::uint8_t> dropped;                       ///< By slot: 1 when its old references go.
};

/// Builds every direction from scratch over the live slots of `layout` (geometry already set). Parallel
/// over directions; throws vf::Error past 32-bit offsets. Sets layout.directions.
void build_all_directions(BeamLayout& layout);

/// References `triangles` would have in direction `line` of `layout` (frames and geometry set): the
/// tiles each comes within slack of, summed. O(triangles). For the memory estimate.
std::size_t count_tile_references(const BeamLayout& layout, std::size_t line, std::span<const std::array<Vec3f, 3>> triangles);

/// Applies `edits` to every direction of `layout`: the tiles the old corners and the added slots touch
/// are rebuilt from their surviving and new references; other tiles are untouched. Parallel over
/// directions.
void update_directions(BeamLayout& layout, const SlotEdits& edits);

}  // namespace vf::beam
