// visfield.Scene and visfield.Camera.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "handles.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/render/walkthrough.hpp"

namespace vf::python {
namespace {

std::array<float, 3> to_array(const Vec3f& v) { return {v.x, v.y, v.z}; }
Vec3f to_vec(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

// Runs `edit` on the scene, a vf::Error (an unknown id, a bad transform) raising ValueError.
template <class Edit>
void edit_scene(SceneHandle& h, Edit&& edit) {
  Scene& s = h.get();
  try {
    edit(s);
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Camera>(m, "Camera", "A pinhole camera: position, look_at, up, vertical field of view in degrees, image size.")
      .def(py::init<>())
      .def_property("position", [](const Camera& c) { return to_array(c.position); }, [](Camera& c, std::array<float, 3> v) { c.position = to_vec(v); })
      .def_property("look_at", [](const Camera& c) { return to_array(c.look_at); }, [](Camera& c, std::array<float, 3> v) { c.look_at = to_vec(v); })
      .def_property("up", [](const Camera& c) { return to_array(c.up); }, [](Camera& c, std::array<float, 3> v) { c.up = to_vec(v); })
      .def_readwrite("fov_degrees", &Camera::fov_degrees)
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height)
      .def("__repr__", [](const Camera& c) {
        return "Camera(" + std::to_string(c.width) + "x" + std::to_string(c.height) + ", fov " + std::to_string(c.fov_degrees) + ")";
      });

  py::class_<SceneHandle>(m, "Scene",
                          "Meshes and objects (instances of meshes, each placed by a rotation, a translation and a uniform scale). "
                          "Object ids are stable: never reused, never renumbered.")
      .def(py::init([] { return SceneHandle(std::make_shared<Scene>(), "scene"); }), "An empty scene.")
      .def_static(
          "load",
          [](const std::string& path) {
            std::shared_ptr<Scene> s;
            {
              py::gil_scoped_release release;
              s = std::make_shared<Scene>(load_scene(path));
            }
            return SceneHandle(std::move(s), "scene");
          },
          py::arg("path"), "A scene from a mesh file (OBJ, PLY, glTF/GLB, STL...), a scene .json, or 'builtin:NAME[:key=value,...]'.")
      .def(
          "add_mesh",
          [](SceneHandle& h, const py::object& vertices, const py::object& index_values, const std::string& occluder) {
            const auto v = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(float32_array(vertices, "vertices", "a (V, 3) array of real numbers"));
            if (!v || v.ndim() != 2 || v.shape(1) != 3) throw py::value_error("vertices: expected a (V, 3) array of numbers");
            const py::array indices = real_numbers(index_values, "indices", "a (T, 3) array of integers");
            if (indices.dtype().kind() != 'i' && indices.dtype().kind() != 'u')
              throw py::type_error("indices: expected an integer array, got " + std::string(py::str(indices.dtype())));
            const auto i = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(indices);
            if (!i || i.ndim() != 2 || i.shape(1) != 3) throw py::value_error("indices: expected a (T, 3) array of vertex indices");
            TriangleMesh mesh;
            if (occluder == "exact")
              mesh.occluder = MeshOccluder::exact;
            else if (occluder == "field")
              mesh.occluder = MeshOccluder::field;
            else if (occluder != "auto")
              throw py::value_error("occluder: expected 'auto', 'exact' or 'field', got '" + occluder + "'");
            Scene& s = h.get();
            mesh.name = "mesh " + std::to_string(s.meshes.size());
            const auto va = v.unchecked<2>();
            for (py::ssize_t k = 0; k < v.shape(0); ++k) mesh.positions.push_back(Vec3f{va(k, 0), va(k, 1), va(k, 2)});
            const auto ia = i.unchecked<2>();
            for (py::ssize_t k = 0; k < i.shape(0); ++k) {
              for (int c = 0; c < 3; ++c)
                if (ia(k, c) < 0 || ia(k, c) >= v.shape(0))
                  throw py::value_error("indices: triangle " + std::to_string(k) + " names vertex " + std::to_string(ia(k, c)) + " of " +
                                        std::to_string(v.shape(0)));
              mesh.triangles.push_back({static_cast<std::uint32_t>(ia(k, 0)), static_cast<std::uint32_t>(ia(k, 1)), static_cast<std::uint32_t>(ia(k, 2))});
            }
            try {
              validate_mesh(mesh, mesh.name);
            } catch (const Error& e) {
              throw py::value_error(e.what());
            }
            s.meshes.push_back(std::move(mesh));
            return s.meshes.size() - 1;
          },
          py::arg("vertices"), py::arg("indices"), py::arg("occluder") = "auto",
          "Adds a mesh of (V, 3) vertices and (T, 3) vertex indices (copied); returns its index. `occluder` as a scene file's mesh "
          "\"occluder\": 'exact' keeps it exact geometry when renders use fields (grounds, walls), 'field' gives it a field even "
          "without occluders='field', 'auto' lets the render decide.")
      .def(
          "add_instance",
          [](SceneHandle& h, std::uint32_t mesh, const py::object& transform) {
            const Transform t = transform_of(transform);
            if (mesh >= h.get().meshes.size()) throw py::value_error("mesh " + std::to_string(mesh) + " does not exist");
            ObjectId id = kInvalidId;
            edit_scene(h, [&](Scene& s) { id = s.add_instance(mesh, t); });
            return id;
          },
          py::arg("mesh"), py::arg("transform") = py::none(),
          "Adds an object of mesh `mesh` placed by a (3, 4) or (4, 4) matrix [s*R | t] (None: identity); returns its id.")
      .def(
          "set_transform", [](SceneHandle& h, ObjectId id, const py::object& transform) {
            const Transform t = transform_of(transform);
            edit_scene(h, [&](Scene& s) { s.set_transform(id, t); });
          },
          py::arg("id"), py::arg("transform"), "Places object `id` by a (3, 4) or (4, 4) matrix.")
      .def(
          "remove_instance", [](SceneHandle& h, ObjectId id) { edit_scene(h, [&](Scene& s) { s.remove_instance(id); }); }, py::arg("id"),
          "Removes object `id`.")
      .def_property_readonly("name", [](const SceneHandle& h) { return h.get().name; })
      .def_property_readonly("mesh_count", [](const SceneHandle& h) { return h.get().meshes.size(); })
      .def_property_readonly("object_count", [](const SceneHandle& h) { return h.get().instances().size(); })
      .def_property_readonly("triangle_count", [](const SceneHandle& h) { return h.get().instanced_triangle_count(); },
                             "Triangles over all objects.")
      .def_property_readonly(
          "objects",
          [](const SceneHandle& h) {
            std::vector<ObjectId> ids;
            for (const Instance& o : h.get().instances()) ids.push_back(o.id);
            return ids;
          },
          "The object ids, increasing.")
      .def_property_readonly(
          "bounds",
          [](const SceneHandle& h) {
            const Scene& s = h.get();
            if (s.instances().empty()) throw py::value_error("bounds: the scene has no objects");
            const Bounds3f b = s.bounds();
            py::array_t<float> out({2, 3});
            auto o = out.mutable_unchecked<2>();
            for (int k = 0; k < 3; ++k) o(0, k) = b.lo[k], o(1, k) = b.hi[k];
            return out;
          },
          "World bounds of the objects: [[xmin, ymin, zmin], [xmax, ymax, zmax]].")
      .def_property_readonly("moves", [](const SceneHandle& h) { return !h.get().animation.empty(); },
                             "Whether the scene has a camera path or object keyframes (a walkthrough).")
      .def_property_readonly("objects_move", [](const SceneHandle& h) { return !h.get().animation.objects.empty(); },
                             "Whether some object has keyframes (structures must follow it from frame to frame).")
      .def(
          "camera", [](const SceneHandle& h, int width, int height) { return h.get().camera_or_default(width, height); }, py::arg("width") = 0,
          py::arg("height") = 0, "The scene camera (or one that frames the scene) at width x height (0: its own size, else 512).")
      .def(
          "copy", [](const SceneHandle& h) { return SceneHandle(std::make_shared<Scene>(h.get()), "scene"); },
          "A deep copy (edits of one do not change the other).")
      .def(
          "frame",
          [](const SceneHandle& h, int frame, int frames, int width, int height) {
            auto placed = std::make_shared<Scene>(h.get());
            Camera camera;
            try {
              camera = place_frame(*placed, placed->camera_or_default(width, height), frame, frames);
            } catch (const Error& e) {
              throw py::value_error(e.what());
            }
            return py::make_tuple(SceneHandle(std::move(placed), "scene"), camera);
          },
          py::arg("frame"), py::arg("frames"), py::arg("width") = 256, py::arg("height") = 256,
          "Frame `frame` of `frames` of the scene's walkthrough: (a copy of the scene with its moving objects placed, the camera).")
      .def("close", &SceneHandle::close, "Frees the scene now (structures built from it stay valid).")
      .def_property_readonly("closed", &SceneHandle::closed)
      .def("__enter__", [](SceneHandle& h) -> SceneHandle& { return h; })
      .def("__exit__", [](SceneHandle& h, const py::args&) { h.close(); })
      .def("__repr__", [](const SceneHandle& h) {
        if (h.closed()) return std::string("<visfield.Scene (closed)>");
        const Scene& s = h.get();
        return "<visfield.Scene " + s.name + ": " + std::to_string(s.meshes.size()) + " meshes, " + std::to_string(s.instances().size()) +
               " objects, " + std::to_string(s.instanced_triangle_count()) + " triangles>";
      });
}

}  // namespace vf::python
