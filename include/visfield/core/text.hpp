#pragma once
/// \file Numbers as text, for reports, tables and messages.

#include <string>

namespace vf {

/// Up to four doubles printed with a printf pattern that takes that many, e.g. formatted("%.2f", x) or
/// formatted("%.1f of %.1f", a, b) (at most 255 characters; arguments the pattern does not take are ignored).
std::string formatted(const char* pattern, double a, double b = 0.0, double c = 0.0, double d = 0.0);

}  // namespace vf
