// The C API (include/visfield/visfield.h) over the C++ library: handles own C++ objects, every entry
// point catches what the library throws and turns it into a vf_error with a one-line message.

#include "visfield/visfield.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <shared_mutex>
#include <span>
#include <string>
#include <vector>

#include "capi/handles.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/field/field_file.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/scene_geometry.hpp"
#include "visfield/registry/structure_queries.hpp"

// The C structs must match the library's rays, so arrays of them pass without a copy.
static_assert(sizeof(vf_ray) == sizeof(vf::Ray) && offsetof(vf_ray, org_x) == offsetof(vf::Ray, org) &&
              offsetof(vf_ray, dir_x) == offsetof(vf::Ray, dir) && offsetof(vf_ray, tmin) == offsetof(vf::Ray, tmin) &&
              offsetof(vf_ray, tmax) == offsetof(vf::Ray, tmax));

namespace vf::capi {
namespace {

// The library version the C API reports.
constexpr const char* kVersion = VISFIELD_VERSION;

struct LastError {
  vf_error code = VF_OK;
  std::string message;
};
thread_local LastError last_error;

struct Callback {
  vf_error_callback function = nullptr;
  void* user = nullptr;
};
Callback error_callback;

std::mutex threads_mutex;
std::unique_ptr<ThreadLimit> thread_limit;

vf_error fail(vf_error code, const std::string& message) {
  last_error.code = code;
  last_error.message = message;
  if (error_callback.function) error_callback.function(code, last_error.message.c_str(), error_callback.user);
  return code;
}

// Runs `body`, mapping what it throws to a code. Order matters: the subclasses of vf::Error first.
template <class Body>
vf_error guard(Body&& body) {
  try {
    body();
    last_error.code = VF_OK;
    return VF_OK;
  } catch (const ArgumentError& e) {
    return fail(VF_ERROR_INVALID_ARGUMENT, e.what());
  } catch (const UnsupportedError& e) {
    return fail(VF_ERROR_UNSUPPORTED, e.what());
  } catch (const Interrupted& e) {
    return fail(VF_ERROR_INTERRUPTED, e.what());
  } catch (const MemoryRefused& e) {
    return fail(VF_ERROR_OUT_OF_MEMORY, e.what());
  } catch (const Error& e) {
    return fail(VF_ERROR_BAD_INPUT, e.what());
  } catch (const std::bad_alloc&) {
    return fail(VF_ERROR_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    return fail(VF_ERROR_INTERNAL, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(VF_ERROR_INTERNAL, "internal error: an unknown exception");
  }
}

void need_pointer(const void* p, std::size_t count, const char* what) {
  if (p == nullptr && count > 0) throw ArgumentError(std::string(what) + " is NULL");
}

// Refuses a count whose arrays (`bytes_each` bytes an element) would not fit the address space.
void need_count(std::size_t count, std::size_t bytes_each, const char* what) {
  if (count > static_cast<std::size_t>(PTRDIFF_MAX) / bytes_each)
    throw ArgumentError(std::string(what) + ": " + std::to_string(count) + " of " + std::to_string(bytes_each) +
                        " bytes each would not fit in memory (the count is wrong)");
}

HandleTable<SceneObject> scenes(0xA1, "scene");
HandleTable<StructureObject> structures(0xA2, "structure");
HandleTable<FieldObject> fields(0xA3, "field");

template <class Handle>
std::uintptr_t number_of(Handle handle) {
  return reinterpret_cast<std::uintptr_t>(handle);
}

std::shared_ptr<SceneObject> scene_of(vf_scene h) { return scenes.get(number_of(h)); }
std::shared_ptr<StructureObject> structure_of(vf_structure h) { return structures.get(number_of(h)); }
std::shared_ptr<FieldObject> field_of(vf_field h) { return fields.get(number_of(h)); }

// Releases a handle of `table`; NULL is accepted and ignored, as free() does.
template <class T, class Handle>
vf_error release(HandleTable<T>& table, Handle handle) {
  return guard([&] {
    if (handle != nullptr) table.release(number_of(handle));
  });
}

vf_hit to_c(const Hit& h) {
  return vf_hit{h.t, h.u, h.v, h.prim, h.instance, h.normal.x, h.normal.y, h.normal.z};
}

RayArrays soa_rays(const vf_rays_soa& r, std::size_t count) {
  for (const float* p : {r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z}) need_pointer(p, count, "rays: an origin or direction array");
  RayArrays a;
  a.ox.data = r.org_x, a.oy.data = r.org_y, a.oz.data = r.org_z;
  a.dx.data = r.dir_x, a.dy.data = r.dir_y, a.dz.data = r.dir_z;
  a.tmin.data = r.tmin, a.tmax.data = r.tmax;
  a.count = count;
  return a;
}

// Calls emit(i, answer) for the field's answer to every object-space ray, a chunk at a time.
template <class Emit>
void for_each_field_answer(const field::ObjectField& f, const vf_ray* rays, std::size_t count, Emit&& emit) {
  std::vector<field::FieldAnswer> answers;
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t n = std::min(kChunk, count - first);
    answers.resize(n);
    f.trace_rays(std::span<const Ray>(reinterpret_cast<const Ray*>(rays) + first, n), answers);
    for (std::size_t k = 0; k < n; ++k) emit(first + k, answers[k]);
  }
}


}  // namespace
}  // namespace vf::capi

using namespace vf;
using namespace vf::capi;

extern "C" {

const char* vf_version(void) { return kVersion; }
vf_error vf_last_error(void) { return last_error.code; }
const char* vf_last_error_message(void) { return last_error.code == VF_OK ? "" : last_error.message.c_str(); }

void vf_set_error_callback(vf_error_callback callback, void* user) { error_callback = Callback{callback, user}; }

vf_error vf_set_threads(int threads) {
  return guard([&] {
    if (threads < 0) throw ArgumentError("threads: expected 0 (all) or a positive count, got " + std::to_string(threads));
    const std::lock_guard<std::mutex> lock(threads_mutex);
    thread_limit.reset();
    thread_limit = std::make_unique<ThreadLimit>(threads);
  });
}

vf_error vf_scene_create(vf_scene* out) {
  return guard([&] {
    need_pointer(out, 1, "out");
    auto object = std::make_shared<SceneObject>();
    object->scene = std::make_shared<Scene>();
    *out = reinterpret_cast<vf_scene>(scenes.add(std::move(object)));
  });
}

vf_error vf_scene_load(const char* path, vf_scene* out) {
  return guard([&] {
    need_pointer(path, 1, "path");
    need_pointer(out, 1, "out");
    auto object = std::make_shared<SceneObject>();
    object->scene = std::make_shared<Scene>(load_scene(path));
    *out = reinterpret_cast<vf_scene>(scenes.add(std::move(object)));
  });
}

vf_error vf_scene_add_mesh(vf_scene scene, const float* vertices, size_t vertex_count, const uint32_t* indices, size_t triangle_count,
                           uint32_t* mesh) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    need_count(vertex_count, 3 * sizeof(float), "add_mesh: vertex_count");
    need_count(triangle_count, 3 * sizeof(uint32_t), "add_mesh: triangle_count");
    need_pointer(vertices, vertex_count, "vertices");
    need_pointer(indices, triangle_count, "indices");
    if (triangle_count == 0) throw ArgumentError("add_mesh: a mesh needs at least one triangle");
    TriangleMesh m;
    m.positions.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) m.positions[i] = Vec3f{vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]};
    m.triangles.resize(triangle_count);
    for (std::size_t i = 0; i < triangle_count; ++i) m.triangles[i] = {indices[3 * i], indices[3 * i + 1], indices[3 * i + 2]};
    const std::unique_lock<std::shared_mutex> exclusive(h->lock);
    Scene& s = *h->scene;
    m.name = "mesh " + std::to_string(s.meshes.size());
    try {
      validate_mesh(m, m.name);
    } catch (const Error& e) {
      throw ArgumentError(std::string("add_mesh: ") + e.what());
    }
    s.meshes.push_back(std::move(m));
    if (mesh) *mesh = static_cast<uint32_t>(s.meshes.size() - 1);
  });
}

vf_error vf_scene_add_instance(vf_scene scene, uint32_t mesh, const float* transform_3x4, uint32_t* id) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    const Transform transform = transform_from_3x4(transform_3x4);
    const std::unique_lock<std::shared_mutex> exclusive(h->lock);
    Scene& s = *h->scene;
    if (mesh >= s.meshes.size())
      throw ArgumentError("add_instance: mesh " + std::to_string(mesh) + " does not exist (the scene has " + std::to_string(s.meshes.size()) + ")");
    const ObjectId added = s.add_instance(mesh, transform);
    if (id) *id = added;
  });
}

vf_error vf_scene_set_transform(vf_scene scene, uint32_t id, const float* transform_3x4) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    const Transform transform = transform_from_3x4(transform_3x4);
    const std::unique_lock<std::shared_mutex> exclusive(h->lock);
    as_argument_error([&] { h->scene->set_transform(id, transform); });
  });
}

vf_error vf_scene_remove_instance(vf_scene scene, uint32_t id) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    const std::unique_lock<std::shared_mutex> exclusive(h->lock);
    as_argument_error([&] { h->scene->remove_instance(id); });
  });
}

vf_error vf_scene_counts(vf_scene scene, size_t* meshes, size_t* objects, size_t* triangles) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    const Scene& s = *h->scene;
    if (meshes) *meshes = s.meshes.size();
    if (objects) *objects = s.instances().size();
    if (triangles) *triangles = s.instanced_triangle_count();
  });
}

vf_error vf_scene_bounds(vf_scene scene, float lower[3], float upper[3]) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    need_pointer(lower, 1, "lower");
    need_pointer(upper, 1, "upper");
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    const Scene& s = *h->scene;
    if (s.instances().empty()) throw ArgumentError("bounds: the scene has no objects");
    const Bounds3f b = s.bounds();
    for (int k = 0; k < 3; ++k) lower[k] = b.lo[k], upper[k] = b.hi[k];
  });
}

vf_error vf_scene_release(vf_scene scene) { return release(scenes, scene); }

vf_error vf_structure_build(vf_scene scene, const char* spec, vf_structure* out) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    need_pointer(out, 1, "out");
    const std::string text = spec ? spec : "bvh";
    as_argument_error([&] { check_structure_spec(text, "spec "); });
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    const Scene& s = *h->scene;
    if (s.instances().empty() || s.instanced_triangle_count() == 0) throw ArgumentError("build: the scene has no triangles");
    SceneGeometry geometry(s);
    BuiltStructure built = build_structure(text, geometry, {}, "spec ");
    auto object = std::make_shared<StructureObject>(std::move(built.structure), std::move(built.resolved));
    *out = reinterpret_cast<vf_structure>(structures.add(std::move(object)));
  });
}

const char* vf_structure_spec(vf_structure structure) {
  const char* spec = "";
  guard([&] {
    if (structure) spec = structure_of(structure)->resolved.c_str();
  });
  return spec;
}

vf_error vf_structure_get_stats(vf_structure structure, vf_structure_stats* out) {
  return guard([&] {
    const std::shared_ptr<StructureObject> h = structure_of(structure);
    need_pointer(out, 1, "out");
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    const AccelStats s = structure_stats(h->structure);
    const bool exact = std::visit([](const auto& x) { return std::decay_t<decltype(x)>::exactness == Exactness::exact; }, h->structure);
    *out = vf_structure_stats{s.build_ms, s.memory_bytes, s.node_count, s.leaf_count, s.reference_count,
                              static_cast<uint64_t>(s.max_depth), exact ? 1 : 0, is_updatable(h->structure) ? 1 : 0};
  });
}

vf_error vf_structure_release(vf_structure structure) { return release(structures, structure); }

vf_error vf_intersect(vf_structure structure, const vf_ray* rays, size_t count, vf_hit* hits) {
  return guard([&] {
    const std::shared_ptr<StructureObject> h = structure_of(structure);
    need_count(count, sizeof(vf_hit), "intersect: count");
    need_pointer(rays, count, "rays");
    need_pointer(hits, count, "hits");
    const std::span<const Ray> all(reinterpret_cast<const Ray*>(rays), count);
    std::vector<Hit> answers;
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    for (std::size_t first = 0; first < count; first += kChunk) {
      const std::size_t n = std::min(kChunk, count - first);
      answers.resize(n);
      intersect_batch(h->structure, all.subspan(first, n), answers);
      for (std::size_t k = 0; k < n; ++k) hits[first + k] = to_c(answers[k]);
    }
  });
}

vf_error vf_occluded(vf_structure structure, const vf_ray* rays, size_t count, uint8_t* occluded) {
  return guard([&] {
    const std::shared_ptr<StructureObject> h = structure_of(structure);
    need_count(count, sizeof(vf_ray), "occluded: count");
    need_pointer(rays, count, "rays");
    need_pointer(occluded, count, "occluded");
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    occluded_batch(h->structure, std::span<const Ray>(reinterpret_cast<const Ray*>(rays), count), std::span<std::uint8_t>(occluded, count));
  });
}

vf_error vf_intersect_soa(vf_structure structure, const vf_rays_soa* rays, size_t count, const vf_hits_soa* hits) {
  return guard([&] {
    const std::shared_ptr<StructureObject> h = structure_of(structure);
    need_count(count, sizeof(float), "intersect_soa: count");
    need_pointer(rays, 1, "rays");
    need_pointer(hits, 1, "hits");
    HitArrays out;
    out.t.data = hits->t, out.u.data = hits->u, out.v.data = hits->v;
    out.prim.data = hits->prim, out.instance.data = hits->instance;
    out.nx.data = hits->ng_x, out.ny.data = hits->ng_y, out.nz.data = hits->ng_z;
    const RayArrays in = soa_rays(*rays, count);
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    intersect_arrays(h->structure, in, out);
  });
}

vf_error vf_occluded_soa(vf_structure structure, const vf_rays_soa* rays, size_t count, uint8_t* occluded) {
  return guard([&] {
    const std::shared_ptr<StructureObject> h = structure_of(structure);
    need_count(count, sizeof(float), "occluded_soa: count");
    need_pointer(rays, 1, "rays");
    need_pointer(occluded, count, "occluded");
    const RayArrays in = soa_rays(*rays, count);
    const std::shared_lock<std::shared_mutex> shared(h->lock);
    occluded_arrays(h->structure, in, StridedOut<std::uint8_t>{occluded, 1});
  });
}

vf_error vf_structure_remove(vf_structure structure, uint32_t id) {
  return guard([&] { edit_object(*structure_of(structure), [&](AnyStructure& s) { remove_object(s, id); }); });
}

vf_error vf_structure_insert(vf_structure structure, vf_scene scene, uint32_t id) {
  return guard([&] {
    const std::shared_ptr<StructureObject> h = structure_of(structure);
    const std::shared_ptr<SceneObject> from = scene_of(scene);
    const std::shared_lock<std::shared_mutex> shared(from->lock);
    edit_object(*h, [&](AnyStructure& st) { insert_object(st, *from->scene, id); });
  });
}

vf_error vf_structure_move(vf_structure structure, uint32_t id, const float* transform_3x4) {
  return guard([&] {
    const std::shared_ptr<StructureObject> h = structure_of(structure);
    const Transform t = transform_from_3x4(transform_3x4);
    edit_object(*h, [&](AnyStructure& s) { move_object(s, id, t); });
  });
}

vf_error vf_structure_commit(vf_structure structure) {
  return guard([&] { edit_object(*structure_of(structure), [&](AnyStructure& s) { commit_objects(s); }); });
}

vf_error vf_field_build(vf_scene scene, uint32_t mesh, const char* params, vf_field* out) {
  return guard([&] {
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    need_pointer(out, 1, "out");
    const field::ObjectFieldConfig config = field_config(params);
    TriangleSet triangles;
    {
      const std::shared_lock<std::shared_mutex> shared(h->lock);
      const Scene& s = *h->scene;
      if (mesh >= s.meshes.size()) throw ArgumentError("field_build: mesh " + std::to_string(mesh) + " does not exist");
      triangles = mesh_triangles(s.meshes[mesh]);
    }
    if (triangles.size() == 0) throw ArgumentError("field_build: mesh " + std::to_string(mesh) + " has no triangles of non-zero area");
    auto object = std::make_shared<FieldObject>(FieldObject{field::ObjectField::build(triangles, config), field::mesh_hash(triangles)});
    *out = reinterpret_cast<vf_field>(fields.add(std::move(object)));
  });
}

vf_error vf_field_load(const char* path, vf_scene scene, uint32_t mesh, vf_field* out) {
  return guard([&] {
    need_pointer(path, 1, "path");
    const std::shared_ptr<SceneObject> h = scene_of(scene);
    need_pointer(out, 1, "out");
    std::uint64_t hash = 0;
    {
      const std::shared_lock<std::shared_mutex> shared(h->lock);
      const Scene& s = *h->scene;
      if (mesh >= s.meshes.size()) throw ArgumentError("field_load: mesh " + std::to_string(mesh) + " does not exist");
      hash = field::mesh_hash(mesh_triangles(s.meshes[mesh]));
    }
    field::StoredField stored = field::load_field(path, hash);
    auto object = std::make_shared<FieldObject>(FieldObject{std::move(stored.field), hash});
    *out = reinterpret_cast<vf_field>(fields.add(std::move(object)));
  });
}

vf_error vf_field_save(vf_field f, const char* path) {
  return guard([&] {
    const std::shared_ptr<FieldObject> h = field_of(f);
    need_pointer(path, 1, "path");
    field::save_field(h->field, h->mesh_hash, path);
  });
}

vf_error vf_field_get_info(vf_field f, vf_field_info* out) {
  return guard([&] {
    const std::shared_ptr<FieldObject> h = field_of(f);
    need_pointer(out, 1, "out");
    const field::ObjectField& fd = h->field;
    const field::BoundingSphere& sp = fd.sphere();
    *out = vf_field_info{static_cast<uint32_t>(fd.position_count()), static_cast<uint32_t>(fd.config().directions),
                         {sp.centre.x, sp.centre.y, sp.centre.z}, sp.radius, fd.memory_bytes(), fd.build_ms(),
                         fd.config().normals != field::NormalStorage::none ? 1 : 0};
  });
}

vf_error vf_field_intersect(vf_field f, const vf_ray* rays, size_t count, vf_hit* hits) {
  return guard([&] {
    const std::shared_ptr<FieldObject> h = field_of(f);
    need_count(count, sizeof(vf_hit), "field_intersect: count");
    need_pointer(rays, count, "rays");
    need_pointer(hits, count, "hits");
    for_each_field_answer(h->field, rays, count, [&](std::size_t i, const field::FieldAnswer& a) {
      hits[i] = a.hit ? vf_hit{a.t, 0.0f, 0.0f, VF_INVALID_ID, 0, a.normal.x, a.normal.y, a.normal.z}
                      : vf_hit{INFINITY, 0.0f, 0.0f, VF_INVALID_ID, VF_INVALID_ID, 0.0f, 0.0f, 0.0f};
    });
  });
}

vf_error vf_field_occluded(vf_field f, const vf_ray* rays, size_t count, uint8_t* occluded) {
  return guard([&] {
    const std::shared_ptr<FieldObject> h = field_of(f);
    need_count(count, sizeof(vf_ray), "field_occluded: count");
    need_pointer(rays, count, "rays");
    need_pointer(occluded, count, "occluded");
    for_each_field_answer(h->field, rays, count, [&](std::size_t i, const field::FieldAnswer& a) { occluded[i] = a.hit ? 1 : 0; });
  });
}

vf_error vf_field_release(vf_field f) { return release(fields, f); }

}  // extern "C"
