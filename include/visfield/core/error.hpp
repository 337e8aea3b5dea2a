#pragma once
/// \file The one exception type for bad input and refused requests.

#include <stdexcept>
#include <string>
#include <string_view>

namespace vf {

/// `text` on one line: each run of whitespace (newlines and tabs included) one space, none at either
/// end, and any other control character '?' (text a user typed or a file held cannot garble a line).
std::string one_line(std::string_view text);

/// Thrown for every user-facing failure (bad file, bad value, refused allocation); what() is one
/// line (one_line() of the message) that names the file or field and the problem, ready to print
/// after "visfield: error: ".
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(one_line(message)) {}
};

}  // namespace vf
