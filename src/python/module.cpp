// The Python module visfield._visfield (re-exported by python/visfield/__init__.py): exceptions,
// threads, version, and the bindings of bind_*.cpp.

#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>

#include "handles.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"

namespace py = pybind11;

namespace {

std::mutex threads_mutex;
std::unique_ptr<vf::ThreadLimit> thread_limit;
int threads_in_force = 0;

}  // namespace

PYBIND11_MODULE(_visfield, m) {
  m.doc() = "visfield: fast ray-scene visibility queries (exact structures, BeamField, ObjectFields) from NumPy";
  m.attr("__version__") = VISFIELD_VERSION;
  m.attr("INVALID_ID") = py::int_(vf::kInvalidId);

  // vf::Error (bad files, refused builds) becomes visfield.Error, a refused allocation MemoryError,
  // a SIGINT/SIGTERM KeyboardInterrupt.
  static py::exception<vf::Error> error(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const vf::MemoryRefused& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const vf::Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const vf::Error& e) {
      error(e.what());
    }
  });

  m.def(
      "set_threads",
      [](int threads) {
        if (threads < 0) throw py::value_error("threads: expected 0 (all hardware threads) or a positive count, got " + std::to_string(threads));
        const std::lock_guard<std::mutex> lock(threads_mutex);
        thread_limit.reset();
        thread_limit = std::make_unique<vf::ThreadLimit>(threads);
        threads_in_force = thread_limit->threads();
      },
      py::arg("threads"), "Worker threads for every build, query and render from now on (0 = all hardware threads).");
  m.def(
      "threads", [] { return threads_in_force ? threads_in_force : vf::hardware_threads(); }, "Worker threads in force.");

  vf::python::bind_scene(m);
  vf::python::bind_structures(m);
  vf::python::bind_fields(m);
  vf::python::bind_render(m);
}
