#pragma once
// Private to the Python module: keyword arguments written as spec values, so that the library's
// one table of parameters (names, defaults, ranges) checks what Python passes.

#include <pybind11/pybind11.h>

#include <cmath>
#include <span>
#include <string>

#include "visfield/core/spec.hpp"

namespace vf::python {

namespace py = pybind11;

/// A keyword argument's value as a spec writes it: True/False as 1/0, numbers as Python prints them
/// (positive infinity as inf), text as it is (ValueError if it holds ','); TypeError for anything else.
inline std::string spec_text(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "1" : "0";
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) {
    const double v = value.cast<double>();
    return std::isinf(v) && v > 0.0 ? std::string("inf") : py::repr(value).cast<std::string>();
  }
  if (py::isinstance<py::str>(value)) {
    // A ',' would end this key's value and start another key's in the spec the value is written into.
    std::string text = value.cast<std::string>();
    if (text.find(',') != std::string::npos) throw py::value_error(name + ": a value cannot hold ',', got '" + text + "'");
    return text;
  }
  throw py::type_error(name + ": expected a number or a string, got " + py::str(value.get_type()).cast<std::string>());
}

/// Declared parameters as Python sees them: a list of {"key", "default", "help", "expected"} dicts.
inline py::list params_as_dicts(std::span<const ParamSpec> params) {
  py::list out;
  for (const ParamSpec& p : params) {
    py::dict d;
    d["key"] = std::string(p.key), d["default"] = std::string(p.default_value), d["help"] = std::string(p.help);
    d["expected"] = expected_value(p);
    out.append(d);
  }
  return out;
}

}  // namespace vf::python
