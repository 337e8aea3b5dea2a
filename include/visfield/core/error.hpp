#pragma once
/// \file The one exception type for bad input and refused requests.

#include <stdexcept>
#include <string>

namespace vf {

/// Thrown for every user-facing failure (bad file, bad value, refused allocation); what() is one
/// line that names the file or field and the problem, ready to print after "visfield: error: ".
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace vf
