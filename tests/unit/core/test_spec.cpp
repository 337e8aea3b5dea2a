#include <gtest/gtest.h>

#include "visfield/core/error.hpp"
#include "visfield/core/spec.hpp"

namespace vf {
namespace {

constexpr ParamSpec kParams[] = {
    {"count", ParamType::whole, "8", "how many", 1, 100},
    {"scale", ParamType::number, "0.5", "how big", 0, 1},
    {"fast", ParamType::boolean, "true", "whether fast"},
    {"mode", ParamType::choice, "a", "which mode", 0, 0, "a|b|c"},
    {"file", ParamType::text, "", "a file"},
    {"seed", ParamType::whole, "1", "any seed"},
};

std::string read_error(const std::string& text) {
  try {
    read_params(parse_spec(text, "--x "), kParams, "--x thing");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Spec, SplitsNameAndParametersInOrder) {
  const Spec s = parse_spec("bvh:leaf=4,levels=2", "--accel ");
  EXPECT_EQ(s.name, "bvh");
  ASSERT_EQ(s.params.size(), 2u);
  EXPECT_EQ(s.params[0], (std::pair<std::string, std::string>{"leaf", "4"}));
  EXPECT_EQ(s.params[1], (std::pair<std::string, std::string>{"levels", "2"}));
  EXPECT_TRUE(parse_spec("grid", "--accel ").params.empty());
  EXPECT_EQ(parse_spec("auto:calibration=a/b.json", "").params[0].second, "a/b.json");
}

TEST(Spec, DefaultsFillInAndGivenValuesAreConverted) {
  const ParamValues defaults = read_params(parse_spec("thing", ""), kParams, "thing");
  EXPECT_EQ(defaults.whole("count"), 8u);
  EXPECT_EQ(defaults.number("scale"), 0.5);
  EXPECT_TRUE(defaults.boolean("fast"));
  EXPECT_EQ(defaults.text("mode"), "a");
  EXPECT_FALSE(defaults.has("file"));
  EXPECT_FALSE(defaults.given("count"));
  EXPECT_EQ(defaults.canonical(), "");
  const ParamValues v = read_params(parse_spec("thing:mode=c,count=1e2,fast=off,file=x.json,seed=18446744073709551615", ""),
                                    kParams, "thing");
  EXPECT_EQ(v.whole("count"), 100u);
  EXPECT_FALSE(v.boolean("fast"));
  EXPECT_EQ(v.text("mode"), "c");
  EXPECT_EQ(v.text("file"), "x.json");
  EXPECT_EQ(v.whole("seed"), 18446744073709551615ull);
  EXPECT_TRUE(v.given("count"));
  // Declaration order, as written.
  EXPECT_EQ(v.canonical(), "count=1e2,fast=off,mode=c,file=x.json,seed=18446744073709551615");
}

TEST(Spec, BadParametersNameTheKeyAndWhatWasExpected) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"thing:cuont=3", "--x thing: unknown key 'cuont' (valid keys: count, scale, fast, mode, file, seed)"},
      {"thing:count=0", "--x thing: count=0: expected a non-negative integer in 1..100"},
      {"thing:count=101", "count=101: expected a non-negative integer in 1..100"},
      {"thing:count=2.5", "count=2.5"},
      {"thing:count=-1", "count=-1"},
      {"thing:count=1e400", "count=1e400"},
      {"thing:seed=99999999999999999999", "below 2^64"},
      {"thing:scale=nan", "scale=nan: expected a number in [0, 1]"},
      {"thing:scale=1.5", "scale=1.5"},
      {"thing:fast=perhaps", "fast=perhaps: expected 1, 0, true, false, on, off, yes or no"},
      {"thing:mode=d", "mode=d: expected one of a, b, c"},
      {"thing:file=", "file=: expected a non-empty text"},
      {"thing:count=1,count=2", "count is given twice"},
      {"thing:", "empty parameter list"},
      {"thing:count=1,", "empty parameter list"},
      {"thing:count", "parameter 'count' is not key=value"},
      {"thing:=3", "parameter '=3' is not key=value"},
      {":count=1", "no name before the parameters"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string message = read_error(text);
    EXPECT_NE(message.find(expected), std::string::npos) << text << " -> '" << message << "'";
  }
}

TEST(Spec, ListsSplitBetweenSpecsNotBetweenParameters) {
  EXPECT_EQ(split_spec_list("bvh:leaf=4,levels=2,grid,embree:levels=2"),
            (std::vector<std::string>{"bvh:leaf=4,levels=2", "grid", "embree:levels=2"}));
  EXPECT_EQ(split_spec_list("bvh,kdtree"), (std::vector<std::string>{"bvh", "kdtree"}));
  EXPECT_EQ(split_spec_list("bvh,,kdtree"), (std::vector<std::string>{"bvh", "", "kdtree"}));
}

TEST(Spec, DescriptionsGiveDefaultsAndRanges) {
  const std::string text = describe_params(kParams, "  ");
  EXPECT_NE(text.find("  count=8"), std::string::npos) << text;
  EXPECT_NE(text.find("how many (a non-negative integer in 1..100)"), std::string::npos) << text;
  EXPECT_NE(text.find("file=..."), std::string::npos) << text;
}

}  // namespace
}  // namespace vf
