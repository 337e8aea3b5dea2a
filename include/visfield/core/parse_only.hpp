#pragma once
/// \file VISFIELD_PARSE_ONLY=1: the command-line tools (visfield, visfield-bench) check their command
/// line as usual, then stop with exit 0 before any work. The documentation's test runs every command
/// the README and docs/ quote this way, so a quoted command that no longer parses fails a test.

#include <cstdlib>
#include <cstring>

namespace vf {

/// Whether the environment sets VISFIELD_PARSE_ONLY=1.
inline bool parse_only() {
  const char* value = std::getenv("VISFIELD_PARSE_ONLY");
  return value != nullptr && std::strcmp(value, "1") == 0;
}

}  // namespace vf
