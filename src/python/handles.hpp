#pragma once
// Private to the Python module: what its Scene, Structure, Field and Renderer objects hold. Each can
// be closed (its C++ object freed at once); a closed object raises ValueError on every use.

#include <pybind11/pybind11.h>

#include <memory>
#include <shared_mutex>
#include <string>

#include "visfield/core/scene.hpp"
#include "visfield/field/object_field.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/render_scene.hpp"

namespace vf::python {

namespace py = pybind11;

/// A closable handle on a shared C++ object.
template <class T>
class Handle {
 public:
  Handle() = default;
  explicit Handle(std::shared_ptr<T> object, const char* kind) : object_(std::move(object)), kind_(kind) {}

  /// The object; ValueError when closed.
  T& get() const {
    if (!object_) throw py::value_error(std::string("this ") + kind_ + " is closed");
    return *object_;
  }
  /// The shared object (for keeping it alive); ValueError when closed.
  const std::shared_ptr<T>& shared() const {
    get();
    return object_;
  }
  /// Frees the object (others sharing it keep it).
  void close() { object_.reset(); }
  /// Whether close() ran.
  bool closed() const { return !object_; }

 private:
  std::shared_ptr<T> object_;
  const char* kind_ = "object";
};

/// visfield.Scene.
using SceneHandle = Handle<Scene>;

/// A built structure, its resolved spec, and the lock that keeps queries (shared) apart from edits
/// and commits (exclusive): a query that overlaps a commit on another thread waits for it and sees
/// the structure before or after it, as the C API's (include/visfield/visfield.h).
struct BuiltHandle {
  BuiltHandle(AnyStructure built, std::string resolved) : structure(std::move(built)), spec(std::move(resolved)) {}
  AnyStructure structure;
  std::string spec;
  mutable std::shared_mutex lock;
};
/// visfield.Structure.
using StructureHandle = Handle<BuiltHandle>;

/// One mesh's field and the hash of that mesh (what a saved file records).
struct FieldHolder {
  field::ObjectField field;
  std::uint64_t mesh_hash = 0;
};
/// visfield.Field.
using FieldHandle = Handle<FieldHolder>;

/// A SceneRenderer and the scene it borrows (kept alive with it).
struct RendererHolder {
  std::shared_ptr<const Scene> scene;
  std::unique_ptr<SceneRenderer> renderer;
};
/// visfield.Renderer.
using RendererHandle = Handle<RendererHolder>;

/// Adds Scene and Camera to the module.
void bind_scene(py::module_& m);
/// Adds Structure, build() and structures() to the module.
void bind_structures(py::module_& m);
/// Adds Field to the module.
void bind_fields(py::module_& m);
/// Adds Renderer, render(), compare(), read_image() and write_image() to the module.
void bind_render(py::module_& m);

}  // namespace vf::python
