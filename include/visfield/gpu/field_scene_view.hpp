#pragma once
/// \file A scene's ObjectFields as a GPU reads them, host and device: every field's tables in one
/// contiguous buffer (FieldSlot: the tables' parameters and byte offsets, rebased to FieldTables
/// pointers wherever the buffer lives), the field objects with their inverse transforms, and the
/// exact meshes in the GPU BVH layout, and a tree over the objects when they are many (object_tree.hpp).
/// occluded() and intersect() answer as FieldScene does, bit for bit: the same objects (a closest hit
/// picked among them by the same rule, whatever their order), the same culling test, the same ray
/// transform and the same trace_field() (field/field_query.hpp), then the exact part through
/// bvh_traversal.hpp.

#include "visfield/core/host_device.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/field/closest_answer.hpp"
#include "visfield/field/field_query.hpp"
#include "visfield/field/sphere_cull.hpp"
#include "visfield/gpu/bvh_traversal.hpp"
#include "visfield/gpu/object_tree.hpp"

namespace vf::gpu {

/// No table: an offset that FieldSlot::rebase turns into a null pointer.
inline constexpr unsigned long long kNoTable = ~0ull;

/// One field in the packed buffer: its FieldTables with null pointers, and where each table starts
/// (bytes from the buffer's start, or kNoTable).
struct FieldSlot {
  field::FieldTables tables;
  unsigned long long upper = kNoTable, quadrant = kNoTable, cells = kNoTable, averages = kNoTable, normal_cells = kNoTable,
                     cell_centres = kNoTable;

  /// The tables with pointers into the buffer at `base` (host or device memory). O(1).
  VF_HOST_DEVICE field::FieldTables rebase(const unsigned char* base) const {
    field::FieldTables t = tables;
    t.upper = upper == kNoTable ? nullptr : reinterpret_cast<const hd::Vec3<float>*>(base + upper);
    t.quadrant = quadrant == kNoTable ? nullptr : reinterpret_cast<const unsigned long long*>(base + quadrant);
    t.cells = cells == kNoTable ? nullptr : base + cells;
    t.averages = averages == kNoTable ? nullptr : reinterpret_cast<const float*>(base + averages);
    t.normal_cells = normal_cells == kNoTable ? nullptr : base + normal_cells;
    t.cell_centres = cell_centres == kNoTable ? nullptr : reinterpret_cast<const hd::Vec3<float>*>(base + cell_centres);
    return t;
  }
};

/// One object of a field mesh: FieldScene's Object as plain data.
struct FieldObject {
  ObjectId id;
  unsigned int field;          ///< Index of its FieldSlot (one per mesh, shared by the mesh's objects).
  InverseTransform to_object;  ///< World to object space.
  Mat3 rotation;               ///< Object to world rotation, for field normals.
  Vec3f centre;                ///< World-space sphere.
  float radius;
};

/// The choices of a field's tables (mapping, storage, normals, lookups, sample line) a query is
/// compiled for. A kernel for one form folds every switch on them away; on a GPU, where a switch
/// costs issue slots even when all threads take the same branch, that is what a lookup spends most on.
enum class FieldForm : unsigned char {
  any = 0,       ///< Every choice read from the tables at run time.
  defaults = 1,  ///< ObjectFieldConfig's defaults: concentric Malley, u8, no normals, nearest, nearest, through.
};

/// Whether tables `t` are of form `form` (every table is of FieldForm::any).
VF_HOST_DEVICE inline bool has_form(const field::FieldTables& t, FieldForm form) {
  if (form == FieldForm::any) return true;
  return t.mapping == field::HemisphereMapping::concentric_malley && t.storage == field::CellStorage::u8 &&
         t.normals == field::NormalStorage::none && t.direction_lookup == field::DirectionLookup::nearest &&
         t.position_lookup == field::PositionLookup::nearest && t.sample_line == field::SampleLine::through;
}

/// `t` with the choices of `Form` as constants (`t` must be of that form): inlined into a query,
/// the switches on them fold away and the query computes what it computes on `t`, bit for bit.
template <FieldForm Form>
VF_HOST_DEVICE inline field::FieldTables with_form(field::FieldTables t) {
  if constexpr (Form == FieldForm::defaults) {
    t.mapping = field::HemisphereMapping::concentric_malley;
    t.storage = field::CellStorage::u8;
    t.normals = field::NormalStorage::none;
    t.direction_lookup = field::DirectionLookup::nearest;
    t.position_lookup = field::PositionLookup::nearest;
    t.sample_line = field::SampleLine::through;
  }
  return t;
}

/// What the queries read: borrowed pointers (host or device memory), the fields already rebased.
struct FieldSceneView {
  const field::FieldTables* fields = nullptr;
  const FieldObject* objects = nullptr;
  unsigned int object_count = 0;
  BvhView exact;                      ///< The meshes that stay exact (node_count 0 when none).
  FieldForm form = FieldForm::any;    ///< A form every field has: the queries the kernels compile for it.
  ObjectTreeView tree;                ///< Over the objects (node_count 0: each sphere tested in turn).
};

/// `ray` in object space: InverseTransform::apply's operations (identity: bit for bit the ray).
VF_HOST_DEVICE inline Ray to_object(const InverseTransform& m, const Ray& ray) {
  if (m.identity) return ray;
  return Ray{m.linear * (ray.org - m.translation), m.linear * ray.dir, ray.tmin, ray.tmax};
}

/// FieldScene's cull (field/sphere_cull.hpp): whether `ray` can meet object `o`'s sphere.
VF_HOST_DEVICE inline bool may_meet(const FieldObject& o, const Ray& ray) { return field::may_meet_sphere(o.centre, o.radius, ray); }

/// Object `o`'s field answer for world-space `ray` within [tmin, tmax], its field read as form `Form`.
template <FieldForm Form = FieldForm::any>
VF_HOST_DEVICE inline field::FieldAnswer trace_object(const FieldSceneView& scene, const FieldObject& o, const Ray& ray, float tmax) {
  const Ray local = to_object(o.to_object, ray);
  const hd::Vec3<float> org{local.org.x, local.org.y, local.org.z}, dir{local.dir.x, local.dir.y, local.dir.z};
  if constexpr (Form == FieldForm::any)
    return field::trace_field(scene.fields[o.field], org, dir, ray.tmin, tmax);
  else
    return field::trace_field(with_form<Form>(scene.fields[o.field]), org, dir, ray.tmin, tmax);
}

/// Whether has(o) holds for some object o that `ray` may meet: FieldScene's cull (every sphere in
/// turn, or, with a tree, the objects whose boxes the ray meets, each then culled by its sphere), the
/// objects in any order, stopping at the first that has (every one is asked when none has).
/// O(log objects + objects met) with a tree.
template <class Has>
VF_HOST_DEVICE inline bool some_object(const FieldSceneView& scene, const Ray& ray, Has&& has) {
  if (scene.tree.node_count > 0)
    return for_items_met(scene.tree, ray, [&](unsigned int k) {
      const FieldObject& o = scene.objects[k];
      return may_meet(o, ray) && has(o);
    });
  for (unsigned int k = 0; k < scene.object_count; ++k) {
    const FieldObject& o = scene.objects[k];
    if (scene.object_count > 1 && !may_meet(o, ray)) continue;
    if (has(o)) return true;
  }
  return false;
}

/// FieldScene::occluded: some field object reports a hit in [tmin, tmax], or the exact part does.
/// `Capacity` (the exact part's traversal stack) must be at least scene.exact.stack_bound; every
/// field must be of form `Form`.
template <int Capacity = kStackSize, FieldForm Form = FieldForm::any>
VF_HOST_DEVICE inline bool occluded(const FieldSceneView& scene, const Ray& ray) {
  if (some_object(scene, ray, [&](const FieldObject& o) { return trace_object<Form>(scene, o, ray, ray.tmax).hit; })) return true;
  return occluded<Capacity>(scene.exact, ray);
}

/// FieldScene::intersect: the exact part's closest hit, or a nearer field answer (of equals, the lowest
/// object index's: field::replaces_closest(), so the objects may come in the walk's order), with the
/// object's id, no triangle, and the world-space normal when the field has one. `Capacity` must be at
/// least scene.exact.stack_bound; every field must be of form `Form`.
template <int Capacity = kStackSize, FieldForm Form = FieldForm::any>
VF_HOST_DEVICE inline Hit intersect(const FieldSceneView& scene, const Ray& ray) {
  Hit best = intersect<Capacity>(scene.exact, ray);
  unsigned int best_object = field::kExactPart;
  some_object(scene, ray, [&](const FieldObject& o) {
    const field::FieldAnswer a = trace_object<Form>(scene, o, ray, ray.tmax);
    const auto k = static_cast<unsigned int>(&o - scene.objects);
    if (!a.hit || !field::replaces_closest(a.t, k, best.found, best.t, best_object)) return false;
    if (a.has_normal) {
      const Vec3f normal = o.rotation * Vec3f{a.normal.x, a.normal.y, a.normal.z};
      best = Hit::surface(a.t, o.id, &normal);
    } else {
      best = Hit::surface(a.t, o.id);
    }
    best_object = k;
    return false;  // every object it may meet
  });
  return best;
}

}  // namespace vf::gpu
