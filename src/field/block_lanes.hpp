#pragma once
// A FieldScene block's bookkeeping on lanes, 16 rays (AVX-512) or 8 (AVX2) at a time, each lane
// deciding exactly what the scalar code decides for its ray:
// - occlusion by the exact part when it is small (a ground, a few walls): every triangle tested
//   against a packet of rays. A lone ray's BVH walk costs more than a field lookup (its setup, a
//   root node of 8 boxes, a leaf), and in a mixed scene every ray makes one; here a triangle costs a
//   few operations a ray;
// - which rays of a block may meet an object's sphere (may_meet_sphere), for scenes of a few objects;
// - among many objects, a tree leaf's rays that may meet its objects' spheres, mapped into object
//   space and added to the pending (ray, object) pairs in the same pass.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "visfield/accel/bvh.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/field/object_field.hpp"

namespace vf::field {

/// Places past their count that append_meeting_spheres() reads of its columns and ids.
inline constexpr std::size_t kColumnsSlack = 16;

/// Exact parts of at most this many triangles are tested triangle by triangle (more go through their BVH).
inline constexpr std::size_t kSmallExactTriangles = 64;

/// occluded[i] = 1 when rays[i] hits one of `triangles` in (tmin, tmax] by the watertight test, else 0:
/// bit for bit what intersect_triangle() decides one ray and triangle at a time (and so what a Bvh or
/// BruteForce over them answers). Packets of lanes, the rest one by one; O(rays · triangles).
void occluded_by_small_exact(std::span<const std::array<Vec3f, 3>> triangles, std::span<const Ray> rays, std::uint8_t* occluded);

/// best[i] = the closest hit of rays[i] among `exact`'s triangles in (tmin, tmax] by the watertight
/// test, or a miss: bit for bit what `bvh` (built over them) answers (t, u, v, triangle, object,
/// normal; of equal t, the lowest index). Packets of lanes; a lane whose test falls back to double,
/// and the last partial packet, go through `bvh`. O(rays · triangles).
void closest_by_small_exact(const TriangleSet& exact, const Bvh& bvh, std::span<const Ray> rays, Hit* best);

/// Scenes of at most this many field objects find each object's rays by testing its sphere against
/// every ray of a block on lanes; more objects go through the tree over their spheres.
inline constexpr std::size_t kFewObjects = 16;

/// The indices i of rays[i] (ascending) that may meet the sphere (centre, radius) by
/// may_meet_sphere(), bit for bit, into out[0 ..) (room for rays.size()); returns how many. O(rays).
std::size_t rays_meeting_sphere(const Vec3f& centre, float radius, std::span<const Ray> rays, std::uint32_t* out);

/// A grid over `boxes` (object k's box is boxes[k]) for cells_of_rays(): along each axis longer than
/// its cells, cells from twice the median box wide down to once, the widest whose lists of two cells
/// along an axis are used (below), their side and offset fitted so that their boundaries cut the
/// fewest boxes (objects in rows then sit whole in cells). List s · count + c of
/// `first` and `items` (items[first[l] .. first[l + 1])) holds, in index order with those of one field
/// (field_of[k]) side by side, the boxes that reach, grown by the grid's margin (1e-4 of the hull's
/// diagonal), the cells from cell c up, one an axis or two along the axes whose bit is set in shape s.
/// Shapes whose lists hold more than 16 objects on average are left out (CellGrid::shapes: their rays
/// go down the tree). No grid (cells 0) when the cells' own lists are that long, when its cells would
/// outnumber 4 an object plus 64, or when the scene lies so far from the world's origin that float
/// rounding could outgrow the margin. O(boxes · cells' shapes).
CellGrid cell_grid_over(std::span<const Bounds3f> boxes, std::span<const ObjectField* const> field_of, std::vector<std::uint32_t>& first,
                        std::vector<std::uint32_t>& items);

/// The shapes of cells_of_rays()' answers: bit a set, two cells along axis a, else one.
inline constexpr std::size_t kCellShapes = 8;

/// cells_of_rays()'s answers besides a cell's index.
inline constexpr std::int32_t kNoCell = -1;  ///< The ray's segment misses the grid's hull: it meets no object's box.
inline constexpr std::int32_t kManyCells = -2;  ///< Its part in the hull is not within one cell (or it cannot be told).

/// For each ray not skipped (skip[i] != 0, where `skip` is given, gives kManyCells): the list of `grid`
/// (shape · count + first cell, a shape the grid uses) whose cells hold its segment's part within the
/// grid's hull, kNoCell when it has no such part, or kManyCells, into cell[i]; the indices of the rays given a cell, ascending, into in_cells (room for
/// every ray, and whole registers past them); returns how many. Conservative: a ray is given a cell or
/// kNoCell only when that holds for its exact segment (its points never lie farther than the grid's
/// tolerance, plus rounding, past the cell); rays with a direction component 0 or below 1e-30, not
/// finite, or from farther than the grid's near box get kManyCells. Packets of lanes, the rest one by
/// one, the same answers. O(rays).
std::size_t cells_of_rays(const CellGrid& grid, std::span<const Ray> rays, const std::uint8_t* skip, std::int32_t* cell,
                          std::uint32_t* in_cells);

/// Object-space rays as rows (origin x, y, z, direction x, y, z, tmin, tmax), what the field kernel
/// loads a packet at a time without gathering or transposing, each with its caller's id.
struct RayRows {
  std::array<std::vector<float>, 8> row;
  std::vector<std::uint32_t> id;
  /// When `tagged`: each row's SphereTarget::tag (which object the ray went to); else left alone.
  std::vector<std::uint32_t> tag;
  bool tagged = false;
  std::size_t count = 0;

  /// The rows' rays for ObjectField::mark_occluded (valid until the next append).
  ObjectRays view() const {
    return {row[0].data(), row[1].data(), row[2].data(), row[3].data(), row[4].data(), row[5].data(), row[6].data(), row[7].data(), count};
  }
  /// Repeats the last ray (count > 0) until count is a multiple of `width` (at most kRowsSlack).
  void pad_to(std::size_t width);
};

/// Rows a RayRows keeps free past its rays: whole-packet stores and padding to whole packets (32 lanes at most).
inline constexpr std::size_t kRowsSlack = 32;

/// A sphere a block's rays are culled against, the map into its object's space, and the rows its
/// rays go to.
struct SphereTarget {
  Vec3f centre;
  float radius;
  const InverseTransform* to_object;
  RayRows* out;
  std::uint32_t tag = 0;  // written beside each of its rays where `out` is tagged
};

/// For each of `targets`, the rays of `rays` that may meet its sphere by may_meet_sphere() (bit for
/// bit), leaving out rays[k] where skip[k] != 0 when `skip` is given, mapped by its `to_object` as
/// InverseTransform::apply() maps them (bit for bit), appended to its rows in order with ids[k] as the
/// id of rays[k]. One pass: a packet of lanes is read and transposed once for all targets, then tested,
/// mapped and compressed into each target's rows; where targets share their rows, each packet's rays
/// for one target follow another's. O(rays · targets).
void append_meeting_spheres(std::span<const SphereTarget> targets, std::span<const Ray> rays, const std::uint32_t* ids,
                            const std::uint8_t* skip = nullptr);
/// append_meeting_spheres() for the rays rays[ids[k]], k < count, each with the id ids[k] (ids readable,
/// as valid indices, up to kColumnsSlack places past count). The same rows, bit for bit. O(count · targets).
void append_meeting_spheres(std::span<const SphereTarget> targets, const Ray* rays, const std::uint32_t* ids, std::size_t count);
/// append_meeting_spheres() for rays given as columns (origin x, y, z, direction x, y, z, tmin, tmax;
/// `count` values each, readable up to kColumnsSlack places past count, as BoxTree::LeafRays holds them): ray k
/// has the id ids[k] and is left out where `settled` is given and settled[ids[k]] != 0. The same rows,
/// bit for bit, as for those rays as Rays. O(count · targets).
void append_meeting_spheres(std::span<const SphereTarget> targets, const float* const columns[8], std::size_t count, const std::uint32_t* ids,
                            const std::uint8_t* settled);

/// Occlusion of the object-space rays of `rows` by `field`: occluded[rows.id[k]] = 1 where trace()
/// of row k hits, other entries left as they are; the rows are then emptied. Whole packets (the last
/// row repeated); `marks` is scratch.
void mark_rows(const ObjectField& field, RayRows& rows, std::vector<std::uint8_t>& marks, std::uint8_t* occluded);

}  // namespace vf::field
