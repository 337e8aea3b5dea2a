// visfield.Structure, visfield.build() and visfield.structures(): any structure of the registry
// by spec, queried with NumPy arrays read in place, the GIL released while it works.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <limits>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>

#include "arrays.hpp"
#include "handles.hpp"
#include "keywords.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/registry/planning.hpp"
#include "visfield/registry/scene_geometry.hpp"
#include "visfield/registry/structure_queries.hpp"

namespace vf::python {
namespace {

template <class T>
py::array_t<T> new_array(std::size_t n) {
  return py::array_t<T>(static_cast<py::ssize_t>(n));
}

// Runs an edit of an updatable structure without the GIL, under its exclusive lock (the structure
// kept alive should another thread close it meanwhile); ValueError for an unknown id.
template <class Edit>
void edit(StructureHandle& h, Edit&& body) {
  const std::shared_ptr<BuiltHandle> b = h.shared();
  if (!is_updatable(b->structure))
    throw py::value_error("the structure " + b->spec + " cannot be edited after its build (BeamField and two-level structures can)");
  try {
    py::gil_scoped_release release;
    const std::unique_lock<std::shared_mutex> exclusive(b->lock);
    body(b->structure);
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
}

}  // namespace

void bind_structures(py::module_& m) {
  m.def(
      "structures", [] { return structure_names(); }, "Names of every structure the registry builds (see `visfield structures`).");
  m.def(
      "structure_params", [](const std::string& name) { return params_as_dicts(find_structure(name).params); }, py::arg("name"),
      "The parameters of structure `name` as its specs take them: [{key, default, help, expected}, ...].");

  m.def(
      "build",
      [](const SceneHandle& scene, const std::string& spec) {
        const std::shared_ptr<Scene> s = scene.shared();
        try {
          check_structure_spec(spec, "spec ");
        } catch (const Error& e) {
          throw py::value_error(e.what());
        }
        if (s->instances().empty() || s->instanced_triangle_count() == 0) throw py::value_error("build: the scene has no triangles");
        std::shared_ptr<BuiltHandle> built;
        {
          py::gil_scoped_release release;
          SceneGeometry geometry(*s);
          BuiltStructure b = build_structure(spec, geometry, {}, "spec ");
          built = std::make_shared<BuiltHandle>(std::move(b.structure), std::move(b.resolved));
        }
        return StructureHandle(std::move(built), "structure");
      },
      py::arg("scene"), py::arg("spec") = "bvh",
      "Builds the structure `spec` names ('bvh', 'kdtree:kt=10', 'beam:dirs=513', 'field:positions=4226', ...) over the scene as it is "
      "now. The memory estimate is checked first (MemoryError). The GIL is released while it builds.");

  m.def(
      "plan",
      [](const SceneHandle& scene, double rays, const std::string& kind, double error, double updates,
         const std::optional<std::string>& calibration) {
        const std::shared_ptr<Scene> s = scene.shared();
        const std::optional<RayKind> parsed = parse_ray_kind(kind);
        if (!parsed) throw py::value_error("plan: kind must be ao, shadow, camera, primary, random or path, got " + kind);
        PlanRequest request;
        request.rays = rays;
        request.kind = *parsed;
        request.max_error = error;
        request.updates = updates;
        request.max_memory = memory_limit().bytes;
        try {
          validate_plan_request(request);
        } catch (const Error& e) {
          throw py::value_error(e.what());
        }
        if (s->instances().empty() || s->instanced_triangle_count() == 0) throw py::value_error("plan: the scene has no triangles");
        Plan plan;
        {
          py::gil_scoped_release release;
          const Calibration c = calibration ? load_calibration(*calibration) : builtin_calibration();
          if (calibration) require_calibration_for(c, this_machine(threads_in_force()), *calibration);
          SceneGeometry geometry(*s);
          const RayKind kinds[] = {request.kind};
          const bool probe = request.max_error > 0.0 && is_occlusion_kind(request.kind);
          plan = plan_structures(geometry, profile_for_plan(geometry, kinds, probe), c, request);
        }
        py::list rows;
        for (const PlanRow& r : plan.rows) {
          py::dict row;
          row["spec"] = r.spec, row["build_ms"] = r.build_ms, row["ray_us"] = r.ray_us, row["update_ms"] = r.update_ms;
          row["total_ms"] = r.total_ms, row["bytes"] = r.bytes, row["error"] = r.error, row["error_measured"] = r.error_measured;
          row["excluded"] = r.excluded;
          rows.append(row);
        }
        py::dict out;
        out["chosen"] = plan.rows[plan.chosen].spec, out["reason"] = plan.reason, out["rows"] = rows;
        return out;
      },
      py::arg("scene"), py::arg("rays"), py::arg("kind") = "path", py::arg("error") = 0.0, py::arg("updates") = 0.0,
      py::arg("calibration") = py::none(),
      "The planner's table for a workload of `rays` rays of `kind` (ao, shadow, camera, random, path), `updates` object moves and "
      "an AO image RMS `error` (0-255; 0 = exact structures only), as `visfield select` prints it: {'chosen': spec, 'reason': "
      "text, 'rows': [{spec, build_ms, ray_us, update_ms, total_ms, bytes, error, error_measured, excluded}, ...]}. build(scene, "
      "'auto:rays=R,kind=K,error=E,updates=U') builds the chosen one. ValueError on a bad request; visfield.Error when "
      "no structure fits (the memory limit).");

  py::class_<StructureHandle>(m, "Structure", "A built structure: exact (bvh, kdtree, grid, median-bsp, beam, brute) or approximate (field).")
      .def_property_readonly("spec", [](const StructureHandle& h) { return h.get().spec; }, "The spec as resolved ('bvh:levels=1').")
      .def_property_readonly(
          "exact",
          [](const StructureHandle& h) {
            return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::exactness == Exactness::exact; }, h.get().structure);
          },
          "True for an exact structure (answers as brute force does).")
      .def_property_readonly("updatable", [](const StructureHandle& h) { return is_updatable(h.get().structure); },
                             "True when objects can be removed, inserted and moved after the build.")
      .def_property_readonly(
          "stats",
          [](const StructureHandle& h) {
            const std::shared_ptr<BuiltHandle> b = h.shared();
            const std::shared_lock<std::shared_mutex> shared(b->lock);  // not mid-commit
            const AccelStats s = structure_stats(b->structure);
            py::dict d;
            d["build_ms"] = s.build_ms, d["memory_bytes"] = s.memory_bytes, d["nodes"] = s.node_count, d["leaves"] = s.leaf_count;
            d["references"] = s.reference_count, d["depth"] = s.max_depth;
            return d;
          },
          "Build time (ms), memory (bytes), nodes, leaves, references, depth.")
      .def(
          "intersect",
          [](const StructureHandle& h, const py::object& origins, const py::object& directions, const py::object& tmin, const py::object& tmax) {
            const std::shared_ptr<BuiltHandle> b = h.shared();  // alive should another thread close it meanwhile
            const RayInput in = ray_input(origins, directions, tmin, tmax);
            const RayArrays& rays = in.rays;
            auto t = new_array<float>(rays.count), u = new_array<float>(rays.count), v = new_array<float>(rays.count);
            auto prim = new_array<std::uint32_t>(rays.count), instance = new_array<std::uint32_t>(rays.count);
            py::array_t<float> normal({static_cast<py::ssize_t>(rays.count), py::ssize_t{3}});
            HitArrays out;
            out.t.data = t.mutable_data(), out.u.data = u.mutable_data(), out.v.data = v.mutable_data();
            out.prim.data = prim.mutable_data(), out.instance.data = instance.mutable_data();
            float* n = normal.mutable_data();
            out.nx = {n, 3 * sizeof(float)}, out.ny = {n + 1, 3 * sizeof(float)}, out.nz = {n + 2, 3 * sizeof(float)};
            {
              py::gil_scoped_release release;
              const std::shared_lock<std::shared_mutex> shared(b->lock);
              intersect_arrays(b->structure, rays, out);
            }
            const bool one = in.single;
            return answer_type("Hits")(per_ray(t, one), per_ray(prim, one), per_ray(instance, one), per_ray(u, one), per_ray(v, one), per_ray(normal, one));
          },
          py::arg("origins"), py::arg("directions") = py::none(), py::arg("tmin") = 0.0, py::arg("tmax") = std::numeric_limits<double>::infinity(),
          "Closest hits of rays origins[i] + t*directions[i], t in (tmin, tmax]. origins and directions: real numbers of shape (N, 3), "
          "or (3,) for one shared by every ray (float32 is read in place whatever its strides; other dtypes and lists are converted "
          "to float32 first, one pass and 12 bytes a ray); or, with directions left out, origins holds whole rays (N, 6): origin then "
          "direction. tmin/tmax: numbers or arrays (N,). Returns visfield.Hits(t, prim, instance, u, v, normal), one entry per ray "
          "(scalars for one ray given as (3,) vectors): a miss has t = inf and prim = instance = INVALID_ID; a field's hit has "
          "prim = INVALID_ID. The GIL is released while it runs.")
      .def(
          "occluded",
          [](const StructureHandle& h, const py::object& origins, const py::object& directions, const py::object& tmin, const py::object& tmax) {
            const std::shared_ptr<BuiltHandle> b = h.shared();
            const RayInput in = ray_input(origins, directions, tmin, tmax);
            py::array_t<bool> out(static_cast<py::ssize_t>(in.rays.count));
            static_assert(sizeof(bool) == sizeof(std::uint8_t));
            {
              py::gil_scoped_release release;
              const std::shared_lock<std::shared_mutex> shared(b->lock);
              occluded_arrays(b->structure, in.rays, StridedOut<std::uint8_t>{reinterpret_cast<std::uint8_t*>(out.mutable_data()), 1});
            }
            return per_ray(out, in.single);
          },
          py::arg("origins"), py::arg("directions") = py::none(), py::arg("tmin") = 0.0, py::arg("tmax") = std::numeric_limits<double>::infinity(),
          "Whether each ray hits anything in (tmin, tmax]: a bool array (a bool for one ray given as (3,) vectors). Arguments as intersect().")
      .def(
          "remove", [](StructureHandle& h, ObjectId id) { edit(h, [&](AnyStructure& s) { remove_object(s, id); }); }, py::arg("id"),
          "Stages removing object `id` (updatable structures; commit() applies).")
      .def(
          "insert",
          [](StructureHandle& h, const SceneHandle& scene, ObjectId id) {
            const std::shared_ptr<Scene> s = scene.shared();
            edit(h, [&](AnyStructure& st) { insert_object(st, *s, id); });
          },
          py::arg("scene"), py::arg("id"), "Stages inserting object `id` of `scene` as it is there now.")
      .def(
          "move",
          [](StructureHandle& h, ObjectId id, const py::object& transform) {
            const Transform t = transform_of(transform);
            edit(h, [&](AnyStructure& st) { move_object(st, id, t); });
          },
          py::arg("id"), py::arg("transform"), "Stages placing object `id` by a (3, 4) or (4, 4) matrix [s*R | t].")
      .def(
          "commit", [](StructureHandle& h) { edit(h, [](AnyStructure& s) { commit_objects(s); }); },
          "Applies the staged edits: afterwards the answers equal a fresh build's.")
      .def("close", &StructureHandle::close, "Frees the structure now.")
      .def_property_readonly("closed", &StructureHandle::closed)
      .def("__enter__", [](StructureHandle& h) -> StructureHandle& { return h; })
      .def("__exit__", [](StructureHandle& h, const py::args&) { h.close(); })
      .def("__repr__", [](const StructureHandle& h) {
        return h.closed() ? std::string("<visfield.Structure (closed)>") : "<visfield.Structure " + h.get().spec + ">";
      });
}

}  // namespace vf::python
