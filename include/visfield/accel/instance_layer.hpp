#pragma once
/// \file The instance layer: one structure per mesh, shared by every object of that mesh, under a top
/// level (an 8-wide BVH) over the objects' world bounds, as Embree, pbrt and tinybvh do. Rays are
/// mapped into each object's space by its inverse transform. Objects can be removed, inserted and
/// moved after the build (UpdatableStructure).

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/median_bsp.hpp"
#include "visfield/accel/query.hpp"
#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

namespace instances {
struct InstanceLayout;
}

/// A structure over one mesh's object-space triangles (mesh_triangles()).
using MeshStructure = std::variant<Bvh, UniformGrid, KdTree, MedianBsp, BruteForce>;

/// Builds the structure of one mesh from its object-space triangles; may throw vf::Error.
using MeshStructureBuilder = std::function<MeshStructure(const TriangleSet& object_triangles)>;

/// Two-level structure over the objects of a Scene. Exact: an object's answer is its mesh structure's
/// answer for the ray mapped into object space (bit for bit the world ray for an identity transform),
/// and among objects the nearest t wins, equal t going to the lowest object id (so answers do not
/// depend on the top level's shape or on the order of edits). Hits carry the object id and the
/// world-space normal. Queries are const and thread-safe; edits are not (see UpdatableStructure).
/// Move-only.
class InstanceLayer {
 public:
  /// Builds the structure of every mesh some object uses (each once, with `build_mesh`) and the top
  /// level. O(unique triangles log + objects log objects); throws what build_mesh throws.
  static InstanceLayer build(const Scene& scene, MeshStructureBuilder build_mesh);
  /// Bytes of the top level and the per-object records for `objects` objects (the mesh structures
  /// not included): 256 per object.
  static double estimate_top_level_bytes(std::size_t objects) { return 256.0 * static_cast<double>(objects); }
  InstanceLayer(InstanceLayer&&) noexcept;
  InstanceLayer& operator=(InstanceLayer&&) noexcept;
  ~InstanceLayer();

  /// Closest hit in (tmin, tmax] over all objects.
  Hit intersect(const Ray& ray) const;
  /// True when any object is hit in (tmin, tmax]; stops at the first.
  bool occluded(const Ray& ray) const;
  /// Statistics of the committed state: memory of the top level plus each mesh structure once; node,
  /// leaf and reference counts summed over them likewise; depth of the top level plus the deepest
  /// mesh structure; build_ms of the initial build (or of the last commit).
  const AccelStats& stats() const;
  /// The name of the layer, "instances".
  static std::string name() { return "instances"; }
  static constexpr Exactness exactness = Exactness::exact;

  /// Stages the removal of object `id`; throws vf::Error when it is not in the layer.
  void remove(ObjectId id);
  /// Stages adding object `id` of `scene` with its mesh and transform; the mesh's structure is built
  /// at commit() when no other object uses it. Throws vf::Error when `scene` has no such object or the
  /// layer already holds it.
  void insert(const Scene& scene, ObjectId id);
  /// Stages moving object `id` to `transform`; throws vf::Error on an unknown id or a bad transform.
  void move(ObjectId id, const Transform& transform);
  /// Applies the staged edits: builds the structures of newly used meshes, drops those no object
  /// uses any more, rebuilds the top level. O(new mesh triangles log + objects log objects).
  void commit();
  /// True when edits are staged and not committed.
  bool has_staged_edits() const { return staged_; }
  /// Objects in the staged state (equal to the committed one after commit()).
  std::size_t object_count() const { return objects_.size(); }

 private:
  friend void occluded_block(const InstanceLayer&, std::span<const Ray>, std::span<std::uint8_t>);
  /// One object as the layer keeps it between commits.
  struct Object {
    ObjectId id;
    std::uint32_t mesh;
    Transform transform;
  };
  InstanceLayer();
  std::vector<Object>::iterator find(ObjectId id);

  std::unique_ptr<instances::InstanceLayout> layout_;            // committed, queried
  std::vector<std::shared_ptr<const MeshStructure>> meshes_;      // by mesh index; null when unused
  std::vector<Bounds3f> mesh_bounds_;                             // object-space bounds by mesh index
  std::vector<Object> objects_;                                   // staged state, by increasing id
  std::map<std::uint32_t, TriangleSet> new_meshes_;               // meshes to build at commit
  MeshStructureBuilder build_mesh_;
  bool staged_ = false;
};

/// occluded[i] = layer.occluded(rays[i]) for every i (spans of equal size), on the calling thread:
/// several rays' walks, through the top level and into the objects' Bvhs, stepped in turn so that
/// their latencies overlap (objects of other structures answer as their step comes). Bit for bit.
void occluded_block(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// occluded_block() over chunks of the rays in parallel (TBB); the same answers. Throws
/// vf::Interrupted on a signal.
void occluded_batch(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

}  // namespace vf
