#pragma once
/// \file Numbers as text, for reports, tables and messages.

#include <string>

namespace vf {

/// `value` printed with a printf pattern that takes one double, e.g. formatted("%.2f", x) (at most 63 characters).
std::string formatted(const char* pattern, double value);

}  // namespace vf
