// visfield.Field: one mesh's ObjectField, built, saved, loaded and queried in the mesh's object space.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "handles.hpp"
#include "keywords.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/field/field_file.hpp"

namespace vf::python {
namespace {

const TriangleMesh& mesh_of(const Scene& scene, std::uint32_t mesh) {
  if (mesh >= scene.meshes.size())
    throw py::value_error("mesh " + std::to_string(mesh) + " does not exist (the scene has " + std::to_string(scene.meshes.size()) + ")");
  return scene.meshes[mesh];
}

// The field's answers for `rays` (object space, read in place), a chunk at a time.
std::vector<field::FieldAnswer> trace(const field::ObjectField& f, const RayArrays& rays) {
  constexpr std::size_t kChunk = std::size_t{1} << 16;
  std::vector<field::FieldAnswer> answers(rays.count);
  std::vector<Ray> chunk;
  for (std::size_t first = 0; first < rays.count; first += kChunk) {
    const std::size_t n = std::min(kChunk, rays.count - first);
    chunk.resize(n);
    for (std::size_t k = 0; k < n; ++k) chunk[k] = rays.at(first + k);
    f.trace_rays(chunk, std::span<field::FieldAnswer>(answers.data() + first, n));
  }
  return answers;
}

// The parameters Field.build takes: the field structure's (registry), but for the scene-level
// cache, meshes and cull, which a single mesh's field has no use for.
std::vector<ParamSpec> field_build_params() {
  std::vector<ParamSpec> params;
  for (const ParamSpec& p : find_structure("field").params)
    if (p.key != "cache" && p.key != "meshes" && p.key != "cull") params.push_back(p);
  return params;
}

}  // namespace

void bind_fields(py::module_& m) {
  static const std::string build_doc =
      "Precomputes the field of mesh `mesh` of `scene`. Keywords, as `field:` specs and `visfield field build` take them "
      "(default, range):\n" +
      describe_params(field_build_params(), "  ") + "The GIL is released while it runs.";
  py::class_<FieldHandle>(m, "Field",
                          "One mesh's ObjectField (approximate, constant time per ray): distances from its bounding sphere inwards, "
                          "queried in the mesh's object space.")
      .def_static(
          "build",
          [](const SceneHandle& scene, std::uint32_t mesh, const py::kwargs& kwargs) {
            const std::shared_ptr<Scene> s = scene.shared();
            const TriangleMesh& source = mesh_of(*s, mesh);
            const std::vector<ParamSpec> params = field_build_params();
            std::string spec = "field";
            for (const auto& [key_handle, value] : kwargs) {
              const std::string key = key_handle.cast<std::string>();
              if (std::none_of(params.begin(), params.end(), [&](const ParamSpec& p) { return p.key == key; })) {
                std::string valid;
                for (const ParamSpec& p : params) valid += (valid.empty() ? "" : ", ") + std::string(p.key);
                throw py::type_error("unknown keyword argument '" + key + "' (valid: " + valid + ")");
              }
              spec += (spec == "field" ? ":" : ",") + key + "=" + spec_text(key, value);
            }
            field::ObjectFieldConfig config;
            try {
              config = field_config_from_spec(spec, "");
            } catch (const Error& e) {
              throw py::value_error(e.what());
            }
            std::shared_ptr<FieldHolder> holder;
            {
              py::gil_scoped_release release;
              const TriangleSet triangles = mesh_triangles(source);
              if (triangles.size() == 0) throw Error("mesh " + std::to_string(mesh) + " has no triangles of non-zero area");
              holder = std::make_shared<FieldHolder>(FieldHolder{field::ObjectField::build(triangles, config), field::mesh_hash(triangles)});
            }
            return FieldHandle(std::move(holder), "field");
          },
          py::arg("scene"), py::arg("mesh") = 0, build_doc.c_str())
      .def_static(
          "load",
          [](const std::string& path, const SceneHandle& scene, std::uint32_t mesh) {
            const std::shared_ptr<Scene> s = scene.shared();
            const TriangleMesh& source = mesh_of(*s, mesh);
            std::shared_ptr<FieldHolder> holder;
            {
              py::gil_scoped_release release;
              const std::uint64_t hash = field::mesh_hash(mesh_triangles(source));
              holder = std::make_shared<FieldHolder>(FieldHolder{field::load_field(path, hash).field, hash});
            }
            return FieldHandle(std::move(holder), "field");
          },
          py::arg("path"), py::arg("scene"), py::arg("mesh") = 0, "Reads a .vfield file made for mesh `mesh` of `scene` (refused when made for another mesh).")
      .def(
          "save",
          [](const FieldHandle& h, const std::string& path) {
            const std::shared_ptr<FieldHolder> kept = h.shared();  // alive should another thread close it meanwhile
            const FieldHolder& f = *kept;
            py::gil_scoped_release release;
            field::save_field(f.field, f.mesh_hash, path);
          },
          py::arg("path"), "Writes the field to a .vfield file atomically (no partial file on failure).")
      .def_property_readonly("positions", [](const FieldHandle& h) { return h.get().field.position_count(); })
      .def_property_readonly("directions", [](const FieldHandle& h) { return h.get().field.config().directions; })
      .def_property_readonly("has_normals", [](const FieldHandle& h) { return h.get().field.config().normals != field::NormalStorage::none; })
      .def_property_readonly("memory_bytes", [](const FieldHandle& h) { return h.get().field.memory_bytes(); })
      .def_property_readonly("build_ms", [](const FieldHandle& h) { return h.get().field.build_ms(); })
      .def_property_readonly(
          "sphere",
          [](const FieldHandle& h) {
            const field::BoundingSphere& s = h.get().field.sphere();
            return py::make_tuple(py::make_tuple(s.centre.x, s.centre.y, s.centre.z), s.radius);
          },
          "The bounding sphere in object space: ((x, y, z), radius).")
      .def(
          "intersect",
          [](const FieldHandle& h, const py::object& origins, const py::object& directions, const py::object& tmin, const py::object& tmax) {
            const std::shared_ptr<FieldHolder> kept = h.shared();  // alive should another thread close it meanwhile
            const FieldHolder& f = *kept;
            const RayInput in = ray_input(origins, directions, tmin, tmax);
            const RayArrays& rays = in.rays;
            py::array_t<float> t(static_cast<py::ssize_t>(rays.count));
            py::array_t<float> normal({static_cast<py::ssize_t>(rays.count), py::ssize_t{3}});
            {
              py::gil_scoped_release release;
              const std::vector<field::FieldAnswer> answers = trace(f.field, rays);
              float* tp = t.mutable_data();
              float* np = normal.mutable_data();
              for (std::size_t i = 0; i < answers.size(); ++i) {
                const field::FieldAnswer& a = answers[i];
                tp[i] = a.hit ? a.t : std::numeric_limits<float>::infinity();
                np[3 * i] = a.has_normal ? a.normal.x : 0.0f;
                np[3 * i + 1] = a.has_normal ? a.normal.y : 0.0f;
                np[3 * i + 2] = a.has_normal ? a.normal.z : 0.0f;
              }
            }
            return answer_type("FieldHits")(per_ray(t, in.single), per_ray(normal, in.single));
          },
          py::arg("origins"), py::arg("directions") = py::none(), py::arg("tmin") = 0.0, py::arg("tmax") = std::numeric_limits<double>::infinity(),
          "Approximate closest hits of object-space rays (arguments as Structure.intersect()): visfield.FieldHits(t, normal), "
          "t = inf for a miss, the unit normal where the field has a normal field (zero otherwise).")
      .def(
          "occluded",
          [](const FieldHandle& h, const py::object& origins, const py::object& directions, const py::object& tmin, const py::object& tmax) {
            const std::shared_ptr<FieldHolder> kept = h.shared();  // alive should another thread close it meanwhile
            const FieldHolder& f = *kept;
            const RayInput in = ray_input(origins, directions, tmin, tmax);
            const RayArrays& rays = in.rays;
            py::array_t<bool> out(static_cast<py::ssize_t>(rays.count));
            {
              py::gil_scoped_release release;
              const std::vector<field::FieldAnswer> answers = trace(f.field, rays);
              bool* o = out.mutable_data();
              for (std::size_t i = 0; i < answers.size(); ++i) o[i] = answers[i].hit;
            }
            return per_ray(out, in.single);
          },
          py::arg("origins"), py::arg("directions") = py::none(), py::arg("tmin") = 0.0, py::arg("tmax") = std::numeric_limits<double>::infinity(),
          "Approximate occlusion of object-space rays (arguments as Structure.intersect()): a bool array (a bool for one ray).")
      .def("close", &FieldHandle::close, "Frees the field now.")
      .def_property_readonly("closed", &FieldHandle::closed)
      .def("__enter__", [](FieldHandle& h) -> FieldHandle& { return h; })
      .def("__exit__", [](FieldHandle& h, const py::args&) { h.close(); })
      .def("__repr__", [](const FieldHandle& h) {
        if (h.closed()) return std::string("<visfield.Field (closed)>");
        const field::ObjectField& f = h.get().field;
        return "<visfield.Field " + std::to_string(f.position_count()) + " positions x " + std::to_string(f.config().directions) + "^2>";
      });
}

}  // namespace vf::python
