#pragma once
// Private to the Python module: NumPy arguments read in place where they are float32 (converted once
// otherwise) and checked, with TypeError for what is not real numbers, ValueError for a wrong shape or a NaN.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "visfield/core/transform.hpp"
#include "visfield/registry/structure_queries.hpp"

namespace vf::python {

namespace py = pybind11;

/// Ray arguments as read: the rays, whether they were one ray given as vectors, and the arrays the
/// rays point into (the caller's own, or float32 copies of other dtypes), held while this lives.
struct RayInput {
  RayArrays rays;
  bool single = false;  ///< origins and directions were both (3,) vectors (or rays a (6,) one)
  std::vector<py::array> held;
};

/// `value` as a NumPy array (np.asarray's); TypeError naming `name` unless its numbers are real (a
/// floating or integer dtype: not bool, complex, text or objects).
inline py::array real_numbers(const py::object& value, const std::string& name, const char* expected = "an array of real numbers") {
  const auto refuse = [&](const std::string& got) { return py::type_error(name + ": expected " + expected + ", got " + got); };
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) || value.is_none())
    throw refuse(std::string(py::str(value.get_type().attr("__name__"))));
  py::array array;
  try {
    array = py::reinterpret_borrow<py::array>(py::module_::import("numpy").attr("asarray")(value));
  } catch (const py::error_already_set&) {
    throw refuse(std::string(py::str(value.get_type().attr("__name__"))));
  }
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') throw refuse("an array of " + std::string(py::str(array.dtype())));
  return array;
}

/// `value` as a NumPy array of real numbers in float32: read in place when it already is float32
/// (any strides), else converted to a new float32 array (any real floating or integer dtype, lists
/// too: one pass over the data, 4 bytes a number). Throws TypeError naming `name` for anything else.
inline py::array float32_array(const py::object& value, const std::string& name, const char* expected = "an array of real numbers") {
  const py::array array = real_numbers(value, name, expected);
  if (array.dtype().is(py::dtype::of<float>())) return array;
  return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
}

namespace detail {
inline std::string shape_of(const py::array& array) {
  return std::string(py::str(py::tuple(py::cast(std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim())))));
}
}  // namespace detail

/// Columns [first, first + 3) of `array` (shape (N, width) or (width,)) as three strided floats;
/// `count` is N, or 1 for a vector, whose rows then all read that one vector (stride 0).
inline void three_columns(const py::array& array, py::ssize_t first, StridedFloats& x, StridedFloats& y, StridedFloats& z, std::size_t& count) {
  const auto* base = static_cast<const char*>(array.data());
  const bool vector = array.ndim() == 1;
  const py::ssize_t row = vector ? 0 : array.strides(0), column = vector ? array.strides(0) : array.strides(1);
  x = {reinterpret_cast<const float*>(base + first * column), row};
  y = {reinterpret_cast<const float*>(base + (first + 1) * column), row};
  z = {reinterpret_cast<const float*>(base + (first + 2) * column), row};
  count = vector ? 1 : static_cast<std::size_t>(array.shape(0));
}

/// `value` as float32 rows of `width` numbers: shape (N, width), or (width,) for one. Throws ValueError naming `name`.
inline py::array rows_of(const py::object& value, py::ssize_t width, const std::string& name) {
  py::array array = float32_array(value, name);
  if (!((array.ndim() == 2 && array.shape(1) == width) || (array.ndim() == 1 && array.shape(0) == width)))
    throw py::value_error(name + ": expected shape (N, " + std::to_string(width) + ") or (" + std::to_string(width) + ",), got " + detail::shape_of(array));
  return array;
}

/// tmin or tmax: a number (every ray), or real numbers of shape (N,) (read in place when float32).
inline StridedFloats range_column(const py::object& value, std::size_t count, const char* name, std::vector<py::array>& held) {
  const py::array array = float32_array(value, name, "a number or an array of real numbers");
  if (array.ndim() == 0) {
    const double v = py::float_(value).cast<double>();
    if (std::isnan(v)) throw py::value_error(std::string(name) + " is NaN");
    return {nullptr, sizeof(float), static_cast<float>(v)};
  }
  if (array.ndim() != 1 || static_cast<std::size_t>(array.shape(0)) != count)
    throw py::value_error(std::string(name) + ": expected a number or shape (" + std::to_string(count) + ",), got " + detail::shape_of(array));
  held.push_back(array);
  return {static_cast<const float*>(array.data()), array.strides(0)};
}

/// The rays of (origins, directions, tmin, tmax), checked. origins and directions: real numbers of
/// shape (N, 3), or (3,) for one shared by every ray; with directions None, origins holds whole rays,
/// (N, 6) or (6,): origin then direction. Float32 arrays are read in place whatever their strides;
/// other dtypes are converted once. Equal lengths; NaN or infinite origins or directions and NaN
/// ranges raise ValueError naming the first bad ray (a zero direction or an empty range is a valid
/// ray that hits nothing).
inline RayInput ray_input(const py::object& origins, const py::object& directions, const py::object& tmin, const py::object& tmax) {
  RayInput in;
  RayArrays& rays = in.rays;
  std::size_t n_origins = 0, n_directions = 0;
  bool vector_origins = false, vector_directions = false;
  if (directions.is_none()) {
    const py::array whole = rows_of(origins, 6, "rays");
    in.held.push_back(whole);
    three_columns(whole, 0, rays.ox, rays.oy, rays.oz, n_origins);
    three_columns(whole, 3, rays.dx, rays.dy, rays.dz, n_directions);
    vector_origins = vector_directions = whole.ndim() == 1;
  } else {
    const py::array o = rows_of(origins, 3, "origins"), d = rows_of(directions, 3, "directions");
    in.held.push_back(o), in.held.push_back(d);
    three_columns(o, 0, rays.ox, rays.oy, rays.oz, n_origins);
    three_columns(d, 0, rays.dx, rays.dy, rays.dz, n_directions);
    vector_origins = o.ndim() == 1, vector_directions = d.ndim() == 1;
  }
  // A (3,) vector is one ray, or shared by every row of the other argument (one origin, many directions).
  if (vector_origins && !vector_directions) n_origins = n_directions;
  if (vector_directions && !vector_origins) n_directions = n_origins;
  if (n_origins != n_directions)
    throw py::value_error("origins and directions: " + std::to_string(n_origins) + " and " + std::to_string(n_directions) + " rows; expected equal lengths");
  in.single = vector_origins && vector_directions;
  rays.count = n_origins;
  rays.tmin = range_column(tmin, rays.count, "tmin", in.held);
  rays.tmax = range_column(tmax, rays.count, "tmax", in.held);
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
  return in;
}

/// `result` (an array of one element per ray) as the caller gave the rays: its first element alone
/// (a NumPy scalar, or a row) for one ray given as vectors.
inline py::object per_ray(const py::array& result, bool single) {
  if (!single) return result;
  return result[py::int_(0)];
}

/// The type `name` of python/visfield/hits.py (Hits, FieldHits), looked up when an answer is made:
/// the package imports this module, so it cannot import the package's types when it loads.
inline py::object answer_type(const char* name) {
  return py::module_::import("visfield.hits").attr(name);
}

/// A rigid transform with uniform scale from a (3, 4) or (4, 4) matrix [s·R | t] (None: identity).
inline Transform transform_of(const py::object& value) {
  Transform t;
  if (value.is_none()) return t;
  real_numbers(value, "transform", "a (3, 4) or (4, 4) matrix of real numbers");
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
