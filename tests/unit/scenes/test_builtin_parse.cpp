#include <gtest/gtest.h>

#include "visfield/core/error.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

// The vf::Error message of parse_builtin_scene(spec), or "" when it does not throw.
std::string parse_error(const std::string& spec) {
  try {
    parse_builtin_scene(spec);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(BuiltinParse, KeysSetSizeAndSeed) {
  const Scene parsed = parse_builtin_scene("builtin:soup:size=1000,seed=7");
  const Scene made = make_builtin_scene("soup", {.seed = 7, .size = 1000});
  EXPECT_EQ(parsed.name, "builtin:soup:size=1000,seed=7");
  EXPECT_EQ(parsed.meshes[0].positions, made.meshes[0].positions);
  EXPECT_EQ(parse_builtin_scene("builtin:soup:seed=7,size=1000").meshes[0].positions, made.meshes[0].positions);
  EXPECT_EQ(parse_builtin_scene("builtin:boxes").instances().size(), 65u);  // 64 boxes + the ground
  EXPECT_EQ(parse_builtin_scene("builtin:boxes:size=0").instances().size(), 65u);  // 0 = default
  EXPECT_EQ(parse_builtin_scene("builtin:sphere:size=100").instanced_triangle_count(), 102u);
}

TEST(BuiltinParse, BadSpecsGiveOneLineErrorsNamingTheProblem) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"builtin:teapot", "valid names: soup, stadium, sphere, boxes, cornell"},
      {"builtin:", "unknown built-in scene"},
      {"soup", "builtin:NAME"},
      {"builtin:soup:sise=10", "unknown key 'sise'"},
      {"builtin:soup:size=abc", "size=abc: expected a non-negative integer"},
      {"builtin:soup:size=-5", "size=-5: expected a non-negative integer"},
      {"builtin:soup:size=10x", "size=10x"},
      {"builtin:soup:size=1.5", "size=1.5"},
      {"builtin:soup:seed=", "seed=: expected"},
      {"builtin:soup:seed=99999999999999999999999", "below 2^64"},
      {"builtin:soup:size", "not key=value"},
      {"builtin:soup:", "empty parameter"},
      {"builtin:soup:size=10,", "empty parameter"},
      {"builtin:soup:size=10,,seed=1", "not key=value"},
      {"builtin:soup:size=10,size=20", "given twice"},
      {"builtin:soup:size=50000001", "out of range"},
  };
  for (const auto& [spec, expected] : cases) {
    const std::string msg = parse_error(spec);
    EXPECT_NE(msg.find(expected), std::string::npos) << spec << " -> '" << msg << "'";
    EXPECT_EQ(msg.find('\n'), std::string::npos) << spec;
  }
}

}  // namespace
}  // namespace vf
