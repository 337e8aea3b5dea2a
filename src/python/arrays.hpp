#pragma once
// Private to the Python module: NumPy arguments read in place (no copy of ray arrays) and checked,
// with TypeError for a wrong dtype, ValueError for a wrong shape or a NaN.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstddef>
#include <string>

#include "visfield/core/transform.hpp"
#include "visfield/registry/structure_queries.hpp"

namespace vf::python {

namespace py = pybind11;

/// `array` as float32 rows of 3 (shape (N, 3), any strides), read in place. Throws TypeError or ValueError naming `name`.
inline void rows_of_three(const py::array& array, const char* name, StridedFloats& x, StridedFloats& y, StridedFloats& z, std::size_t& count) {
  if (!array.dtype().is(py::dtype::of<float>()))
    throw py::type_error(std::string(name) + ": expected a float32 array, got " + std::string(py::str(array.dtype())) +
                         " (convert with .astype(numpy.float32))");
  if (array.ndim() != 2 || array.shape(1) != 3)
    throw py::value_error(std::string(name) + ": expected shape (N, 3), got " + std::string(py::str(py::tuple(py::cast(std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim()))))));
  const auto* base = static_cast<const char*>(array.data());
  const py::ssize_t row = array.strides(0), column = array.strides(1);
  x = {reinterpret_cast<const float*>(base), row};
  y = {reinterpret_cast<const float*>(base + column), row};
  z = {reinterpret_cast<const float*>(base + 2 * column), row};
  count = static_cast<std::size_t>(array.shape(0));
}

/// tmin or tmax: a Python number (every ray) or a float32 array of shape (N,), read in place.
inline StridedFloats range_column(const py::object& value, std::size_t count, const char* name) {
  if (py::isinstance<py::array>(value)) {
    const auto array = py::reinterpret_borrow<py::array>(value);
    if (!array.dtype().is(py::dtype::of<float>()))
      throw py::type_error(std::string(name) + ": expected a number or a float32 array, got an array of " + std::string(py::str(array.dtype())));
    if (array.ndim() != 1 || static_cast<std::size_t>(array.shape(0)) != count)
      throw py::value_error(std::string(name) + ": expected a number or shape (" + std::to_string(count) + ",)");
    return {static_cast<const float*>(array.data()), array.strides(0)};
  }
  if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value))
    throw py::type_error(std::string(name) + ": expected a number or a float32 array");
  const double v = value.cast<double>();
  if (std::isnan(v)) throw py::value_error(std::string(name) + " is NaN");
  return {nullptr, sizeof(float), static_cast<float>(v)};
}

/// The rays of (origins, directions, tmin, tmax), checked: equal lengths; NaN or infinite origins or
/// directions and NaN ranges raise ValueError naming the first bad ray (a zero direction or an empty
/// range is a valid ray that hits nothing). The arrays are
/// read in place; they must stay alive (they are the caller's arguments) while the rays are used.
inline RayArrays ray_arrays(const py::array& origins, const py::array& directions, const py::object& tmin, const py::object& tmax) {
  RayArrays rays;
  std::size_t n_origins = 0, n_directions = 0;
  rows_of_three(origins, "origins", rays.ox, rays.oy, rays.oz, n_origins);
  rows_of_three(directions, "directions", rays.dx, rays.dy, rays.dz, n_directions);
  if (n_origins != n_directions)
    throw py::value_error("origins and directions: " + std::to_string(n_origins) + " and " + std::to_string(n_directions) + " rows; expected equal lengths");
  rays.count = n_origins;
  rays.tmin = range_column(tmin, rays.count, "tmin");
  rays.tmax = range_column(tmax, rays.count, "tmax");
  std::size_t bad = rays.count;
  std::string problem;
  {
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < rays.count && bad == rays.count; ++i) {
      const Ray r = rays.at(i);
      if (!is_finite(r.org)) bad = i, problem = "a NaN or infinite origin";
      else if (!is_finite(r.dir)) bad = i, problem = "a NaN or infinite direction";
      else if (std::isnan(r.tmin) || std::isnan(r.tmax)) bad = i, problem = "a NaN tmin or tmax";
    }
  }
  if (bad != rays.count) throw py::value_error("ray " + std::to_string(bad) + " has " + problem);
  return rays;
}

/// A rigid transform with uniform scale from a (3, 4) or (4, 4) matrix [s·R | t] (None: identity).
inline Transform transform_of(const py::object& value) {
  Transform t;
  if (value.is_none()) return t;
  const auto m = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!m || m.ndim() != 2 || m.shape(1) != 4 || (m.shape(0) != 3 && m.shape(0) != 4))
    throw py::value_error("transform: expected a (3, 4) or (4, 4) matrix of numbers");
  const auto a = m.unchecked<2>();
  if (m.shape(0) == 4 && !(a(3, 0) == 0 && a(3, 1) == 0 && a(3, 2) == 0 && a(3, 3) == 1))
    throw py::value_error("transform: the last row of a (4, 4) matrix must be [0, 0, 0, 1]");
  const double det = a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
                     a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
  if (!(det > 0.0) || !std::isfinite(det))
    throw py::value_error("transform: the 3x3 part must be a rotation times a uniform scale > 0 (its determinant is " + std::to_string(det) + ")");
  const double s = std::cbrt(det);
  for (int r = 0; r < 3; ++r)
    t.rotation.rows[static_cast<std::size_t>(r)] =
        Vec3f{static_cast<float>(a(r, 0) / s), static_cast<float>(a(r, 1) / s), static_cast<float>(a(r, 2) / s)};
  t.translation = Vec3f{static_cast<float>(a(0, 3)), static_cast<float>(a(1, 3)), static_cast<float>(a(2, 3))};
  t.scale = static_cast<float>(s);
  if (!t.is_valid()) throw py::value_error("transform: the 3x3 part is not a rotation times a uniform scale (no shear, no mirroring)");
  return t;
}

}  // namespace vf::python
