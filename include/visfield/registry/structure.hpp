#pragma once
/// \file vf::Structure: any structure of the registry behind one handle, as Embree's RTCScene and the
/// C API's vf_structure are. Built from a spec; one ray or a span of rays at a time. A batch call
/// dispatches once to the held structure's own batch path, so it costs what the concrete type's
/// does; the concrete type stays reachable through get<T>() and variant().

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "visfield/core/ray.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/registry/registry.hpp"

namespace vf {

/// A built structure of any kind (exact or field), owning everything it answers from: the scene it
/// was built over may change or go away afterwards. Threads: queries are const and may overlap each
/// other; an edit (remove, insert, move, commit) must not overlap any other call on the same
/// Structure, as with the standard containers (only updatable structures take edits). The C API and
/// the Python module serialize them for their callers: there a query overlapping a commit waits for
/// it and answers for the structure before or after it (include/visfield/visfield.h).
class Structure {
 public:
  /// Builds `spec` ("bvh", "kdtree:kt=10", "beam:dirs=513", "field:positions=4226", "auto:kind=ao", ...)
  /// over `scene` as it is now, after checking the memory estimate. Throws vf::Error on a bad spec, an
  /// empty scene or a refused or failed build.
  static Structure build(const Scene& scene, std::string_view spec = "bvh", const BuildContext& context = {});

  /// Takes over a structure build_structure() made.
  explicit Structure(BuiltStructure built);

  /// The closest hit in (tmin, tmax] (Hit::t = +inf for a miss). One dispatch per call.
  Hit intersect(const Ray& ray) const;
  /// Whether anything is hit in (tmin, tmax]. One dispatch per call.
  bool occluded(const Ray& ray) const;
  /// hits[i] = intersect(rays[i]) through the structure's batch path: parallel, one dispatch per
  /// batch; spans of equal size (vf::Error otherwise).
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
  /// occluded[i] = 1 when rays[i] is blocked, else 0; as the batch intersect().
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const;

  /// The spec as resolved ("bvh:levels=1", "auto:kind=ao,... -> beam").
  const std::string& spec() const { return built_.resolved; }
  /// True when the answers equal brute force's bit for bit (false for fields).
  bool exact() const;
  /// True when objects can be removed, inserted and moved after the build (BeamField, levels=2).
  bool updatable() const;
  /// Build time, memory, nodes, leaves, references, depth.
  AccelStats stats() const;

  /// Stages removing object `id`; commit() applies. vf::Error when not updatable or unknown.
  void remove(ObjectId id);
  /// Stages inserting object `id` of `scene` as it is there now; commit() applies.
  void insert(const Scene& scene, ObjectId id);
  /// Stages placing object `id` by `t`; commit() applies.
  void move(ObjectId id, const Transform& t);
  /// Applies the staged edits: afterwards the answers equal a fresh build's.
  void commit();

  /// The concrete structure when it is a `T` (Bvh, KdTree, BeamField, field::FieldScene, ...), else null.
  template <class T>
  const T* get() const {
    return std::get_if<T>(&built_.structure);
  }
  /// Every structure type behind one std::variant, for code generic over them.
  const AnyStructure& variant() const { return built_.structure; }

 private:
  BuiltStructure built_;
};

}  // namespace vf
