#pragma once
/// \file The exact structures every differential test runs, taken from the registry: a structure
/// added to the registry is tested here without touching this file.

#include <string>
#include <vector>

#include "support/test_scale.hpp"
#include "visfield/registry/registry.hpp"

namespace vf::test {

/// For every exact registry entry: "name:levels=1" and "name:levels=2" when it takes a levels
/// parameter (flattened and instance layer), else just "name". Left out, as they could not fail:
/// "brute:levels=1", the oracle itself, and "auto", which builds a grid or a kd-tree, each tested
/// under its own name (test_registry checks what auto picks). The list, and so the names of the
/// tests made from it, do not depend on VISFIELD_TEST_SCALE: build test_sized(spec).
inline std::vector<std::string> exact_structure_specs() {
  std::vector<std::string> specs;
  for (const StructureInfo& info : structure_table()) {
    if (info.exactness != Exactness::exact || info.name == "auto") continue;
    bool levels = false;
    for (const ParamSpec& p : info.params) levels = levels || p.key == "levels";
    if (!levels) {
      specs.emplace_back(info.name);
      continue;
    }
    if (info.name != "brute") specs.push_back(std::string(info.name) + ":levels=1");
    specs.push_back(std::string(info.name) + ":levels=2");
  }
  return specs;
}

/// The spec a test builds for `spec`: itself, except that under the scaled-down sanitizer run
/// (VISFIELD_TEST_SCALE < 1) BeamField is built with 33 directions and n = 16 (its smallest sizes;
/// the same code paths), so that it builds on every shared model within CI's time.
inline std::string test_sized(const std::string& spec) { return spec == "beam" && test_scale() < 1.0 ? "beam:dirs=33,n=16" : spec; }

/// The specs of exact_structure_specs() that build the instance layer.
inline std::vector<std::string> two_level_specs() {
  std::vector<std::string> specs;
  for (const std::string& spec : exact_structure_specs())
    if (spec.ends_with(":levels=2")) specs.push_back(spec);
  return specs;
}

/// A test name for a spec ("bvh:levels=2" -> "bvh_levels_2").
inline std::string spec_test_name(std::string spec) {
  for (char& c : spec)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return spec;
}

}  // namespace vf::test
