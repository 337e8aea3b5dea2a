#pragma once
/// \file The ObjectFields of a scene as one approximate structure: one field per mesh, shared by
/// every object (instance) of that mesh, each object reached through its inverse transform; meshes
/// marked MeshOccluder::exact (grounds, walls: the receivers) stay exact triangles in a BVH beside
/// them. It answers both query roles (a field hit has a distance, an object and, with a normal
/// field, a normal; no triangle), and is meant for the occlusion role: AO and shadow rays
/// (`--occluder field`), and for approximate hit points off field objects (glossy reflections).

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <array>
#include <vector>

#include "visfield/accel/box_tree.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/query.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/field/object_field.hpp"
#include "visfield/field/sphere_cull.hpp"

namespace vf::field {

struct RayRows;       // src/field/block_lanes.hpp: a block's pending rays, mapped into object space
struct SphereTarget;  // src/field/block_lanes.hpp: a sphere those rays are culled against

/// A uniform grid of cells over a scene's field objects, as FieldScene routes a batch's rays through it
/// (ObjectCull::grid): a ray whose part within the objects' boxes lies in one cell (or two neighbouring
/// cells an axis) can meet only the boxes that reach those cells, and takes their list of objects
/// instead of walking the tree. Plain data.
struct CellGrid {
  float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {0.0f, 0.0f, 0.0f};  ///< The boxes' hull, grown by the margin.
  float origin[3] = {0.0f, 0.0f, 0.0f};       ///< Cell (0, 0, 0)'s low corner.
  float edge[3] = {1.0f, 1.0f, 1.0f};         ///< The cells' sides.
  float inverse_edge[3] = {1.0f, 1.0f, 1.0f};  ///< 1 / edge.
  int cells[3] = {0, 0, 0};                   ///< Cells along each axis (none: no grid).
  unsigned shapes = 0;  ///< Bit s: the lists of shape s (bit a of s: two cells along axis a) are used.
  /// How far past its cell a computed point of a ray may lie, the ray still in the cell: a quarter of the
  /// margin by which each cell's list reaches past the cell (the rest covers the rounding).
  float tolerance = 0.0f;
  /// Rays from origins outside this box are never routed: farther away, rounding could outgrow the margin.
  float near_lo[3] = {0.0f, 0.0f, 0.0f}, near_hi[3] = {0.0f, 0.0f, 0.0f};
  /// Cells in all.
  std::size_t count() const { return static_cast<std::size_t>(cells[0]) * static_cast<std::size_t>(cells[1]) * static_cast<std::size_t>(cells[2]); }
};

/// Which meshes of a scene a FieldScene represents by fields (the others stay exact triangles).
enum class FieldMeshes : unsigned char {
  all,     ///< Every mesh an object uses, except those marked MeshOccluder::exact (`--occluders field`).
  marked,  ///< Only the meshes marked MeshOccluder::field (a scene JSON's "occluder": "field").
};

/// How a scene of several field objects finds the objects a ray may meet (past kFewObjects; the same
/// answers, bit for bit, whichever).
enum class ObjectCull : unsigned char {
  grid,  ///< A batch's rays whose part within the objects' boxes lies in one cell of a CellGrid (or two
         ///< neighbouring cells an axis) take that cell's objects; the others go down the tree. O(1) per ray so routed.
  tree,  ///< A BVH over the objects' spheres (BoxTree) for every ray: O(log objects) per ray (to measure the grid).
  each,  ///< Every object's sphere tested in turn: O(objects) per ray (to measure the tree).
};

/// Fields of a scene's meshes, shared by their objects, under a BVH over the objects' world-space
/// spheres. Immutable; queries are const and thread-safe. Movable.
class FieldScene {
 public:
  /// Builds the field of every mesh some object uses (each once, with `config` overridden by the
  /// mesh's own table parameters, TriangleMesh::field_params) as `meshes` chooses, then the object
  /// list, and a BVH over the objects of the meshes that stay exact. A mesh with a
  /// `field_file` takes its field from that file when it exists (refused when made for another
  /// mesh; its own parameters then apply, the lookups `config`'s) and writes it there when not; with
  /// a `cache_folder`, every other mesh's field is read from or written to
  /// `cache_folder/<mesh name>-<mesh hash>-<parameters>.vfield` likewise. Objects must have uniform scale (Transform guarantees it). Throws vf::Error on bad
  /// parameters or memory (checked up front for all fields together), vf::Interrupted on a
  /// signal. `progress(n)`: n more positional samples done, over progress_total(scene, config).
  /// `cull` chooses how rays find their objects; answers are the same bit for bit either way.
  static FieldScene build(const Scene& scene, const ObjectFieldConfig& config,
                          const std::function<void(std::size_t)>& progress = {}, const std::string& cache_folder = "",
                          FieldMeshes meshes = FieldMeshes::all, ObjectCull cull = ObjectCull::grid);
  /// Peak bytes build() takes: every field's tables, the largest field mesh's BVH build, and the
  /// exact objects' triangles and BVH.
  static double estimate_build_bytes(const Scene& scene, const ObjectFieldConfig& config, FieldMeshes meshes = FieldMeshes::all);
  /// Positional samples build() will precompute (for a progress bar).
  static std::size_t progress_total(const Scene& scene, const ObjectFieldConfig& config, FieldMeshes meshes = FieldMeshes::all);
  /// The field parameters mesh `mesh` is built with: `config` with the mesh's own table parameters.
  /// Throws vf::Error naming the mesh on a bad parameter.
  static ObjectFieldConfig mesh_config(const TriangleMesh& mesh, const ObjectFieldConfig& config);

  /// Closest hit in [tmin, tmax] over every object: the exact part's hit or a nearer field answer (each
  /// object's within [tmin, tmax]; of equals, the exact part's, then the lowest object index's:
  /// replaces_closest()), with the object's id, no triangle, and the world-space normal when the
  /// fields have normals.
  Hit intersect(const Ray& ray) const;
  /// Occlusion: whether some object's field, or the exact part, reports a hit in [tmin, tmax].
  bool occluded(const Ray& ray) const;
  /// Memory of the fields (each once), the object list and the exact part; build_ms of the whole
  /// build; node_count = fields, leaf_count = field objects, reference_count = positional samples
  /// over all fields.
  const AccelStats& stats() const { return stats_; }
  /// The errors tests/approximate holds this structure to at the default parameters (measured on
  /// the built-in scenes; see the README's ObjectField section).
  ErrorBounds error_bounds() const;
  /// The field of mesh `mesh`, or null when no object uses it.
  const ObjectField* mesh_field(std::uint32_t mesh) const {
    return mesh < fields_.size() ? fields_[mesh].get() : nullptr;
  }
  /// "field".
  static std::string name() { return "field"; }
  static constexpr Exactness exactness = Exactness::approximate;

  /// Whether the objects are found through the tree over their spheres (cull grid or tree, and more
  /// than a few objects) rather than by testing every sphere.
  bool uses_tree() const;
  /// How many of `rays` a batch would route through the grid (to a list of objects or to none), not
  /// down the tree: 0 without a grid (ObjectCull other than grid, or few objects). O(rays).
  std::size_t routed_by_grid(std::span<const Ray> rays) const;
  /// The boxes a tree over the objects is built over, one per object in order: each sphere grown by
  /// 1% of its radius and 1e-5 of the scene's size, so that no rounding leaves out an object may_meet
  /// lets in. O(objects).
  std::vector<Bounds3f> object_boxes() const;

 private:
  friend void occluded_batch(const FieldScene&, std::span<const Ray>, std::span<std::uint8_t>);
  friend void occluded_block(const FieldScene&, std::span<const Ray>, std::span<std::uint8_t>);
  friend void intersect_batch(const FieldScene&, std::span<const Ray>, std::span<Hit>);
  /// Rays per block of the batch queries: 16384 among several objects, 4096 for one.
  std::size_t block_size() const;
  /// Answers for the rays of one block (at most block_size()), into best (closest hits, when `closest`) or
  /// occluded; the batch queries run it per block in parallel.
  void trace_block(std::span<const Ray> rays, bool closest, Hit* best, std::uint8_t* occluded) const;
  /// trace_block()'s field part for closest hits when the objects are found through the tree:
  /// best[i] replaced where an object's field answer replaces_closest() it.
  void closest_by_tree(std::span<const Ray> rays, Hit* best) const;
  /// The block's (ray, object) pairs through the grid (ObjectCull::grid: the rays it routes, a list of
  /// cells at a time) and the tree (the others): each leaf taken where the walk reaches it, the
  /// rays its objects' spheres let in (rays[i] with settled[i] set left out, where `settled` is given;
  /// it marks the grid's rays during the call, and holds only the flushes' marks added on return)
  /// mapped into each object's space onto `rows` (tags: the objects' indices), and flush(field) called
  /// to trace and empty the rows, one field's pairs at a time, every kFlushPairs pairs and at the end.
  template <class Flush>
  void pairs_by_tree(std::span<const Ray> rays, std::uint8_t* settled, RayRows& rows, std::vector<SphereTarget>& targets,
                     Flush&& flush) const;
  /// trace_block()'s field part for occlusion when the objects are found through the tree:
  /// occluded[i] set where some object's field occludes rays[i] (rays already occluded left out).
  void occluded_by_tree(std::span<const Ray> rays, std::uint8_t* occluded) const;

  /// One object: its field, its world-to-object map, its rotation (for normals) and its world-space sphere.
  struct Object {
    ObjectId id;
    const ObjectField* field;
    InverseTransform to_object;
    Mat3 rotation;
    Vec3f centre;
    float radius;
  };
  /// Whether `ray` (world space) can meet object `o`'s sphere, slightly widened, within its [tmin, tmax].
  static bool may_meet(const Object& o, const Ray& ray) { return may_meet_sphere(o.centre, o.radius, ray); }
  /// Indices of the objects whose spheres `ray` may meet (may_meet), ascending, into `out`; every
  /// object when there is only one.
  void objects_met(const Ray& ray, std::vector<std::uint32_t>& out) const;
  /// The world-space hit of field answer `a` of object `o` (its normal rotated to world space).
  static Hit field_hit(const Object& o, const FieldAnswer& a);

  CellGrid grid_;  // over object_boxes(), with ObjectCull::grid when uses_tree() (src/field/block_lanes.hpp: cell_grid_over())
  std::vector<std::uint32_t> cell_first_;    // list l of the grid's cells (cell_grid_over()): cell_objects_[cell_first_[l] .. cell_first_[l + 1])
  std::vector<std::uint32_t> cell_objects_;
  std::vector<std::shared_ptr<const ObjectField>> fields_;  // by mesh index; null when unused
  std::vector<Object> objects_;
  ObjectCull cull_ = ObjectCull::grid;
  BoxTree tree_;  // over the objects' widened spheres, when uses_tree()
  std::optional<Bvh> exact_;  // the objects of meshes marked exact, when there are any
  // The same triangles when they are few (kSmallExactTriangles): batches test them all, a packet of
  // rays at a time, instead of walking the BVH ray by ray (the same answers, closest hits and occlusion).
  TriangleSet small_exact_;
  AccelStats stats_;
};

/// Batch occlusion through a FieldScene: occluded[i] is occluded(rays[i]) bit for bit, parallel over
/// blocks of rays; each object's candidate rays are traced 16 (AVX-512) or 8 (AVX2) at a time
/// (ObjectField::trace_rays). Spans of equal size. Throws vf::Interrupted on a signal.
void occluded_batch(const FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// occluded_batch() on the calling thread (for callers already parallel, such as a renderer's tiles):
/// the same answers, the same SIMD kernel, no task of its own.
void occluded_block(const FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// Batch closest hits through a FieldScene, as occluded_batch() above: hits[i] is intersect(rays[i]).
void intersect_batch(const FieldScene& fields, std::span<const Ray> rays, std::span<Hit> hits);

}  // namespace vf::field
