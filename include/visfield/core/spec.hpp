#pragma once
/// \file The "name:key=value,key=value" syntax every parameterised choice uses: structures
/// (`--accel bvh:leaf=8`), built-in scenes (`builtin:soup:size=1000`). Parameters are declared in a
/// table (ParamSpec), which validates what a user writes and produces the help text.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vf {

/// A spec split into its name and its key=value parameters, in the order written.
struct Spec {
  std::string name;
  std::vector<std::pair<std::string, std::string>> params;
};

/// Splits "name[:key=value,...]". Throws a one-line vf::Error starting with `what` followed by the
/// name (what = "--accel " gives "--accel bvh: ...") on an empty name, an empty parameter list or
/// entry, an entry that is not key=value, an empty key or a key given twice.
Spec parse_spec(std::string_view text, std::string_view what);

/// Splits a comma-separated list of specs, "bvh:leaf=4,levels=2,grid,embree" -> {"bvh:leaf=4,levels=2",
/// "grid", "embree"}: an item holding '=' but no ':' before it continues the previous spec. Empty
/// items are kept (as empty strings) for the caller to refuse.
std::vector<std::string> split_spec_list(std::string_view text);

/// The finite numbers of a comma-separated list ("1,2.5,-3e2"), or std::nullopt when an item is not
/// one (or the list is empty).
std::optional<std::vector<double>> parse_number_list(std::string_view text);

/// The kinds of parameter values.
enum class ParamType {
  whole,    ///< A non-negative integer below 2^64 (also written like 1e6).
  number,   ///< A real number: finite, or "inf" when ParamSpec::max is infinity.
  boolean,  ///< 1/0, true/false, on/off, yes/no.
  choice,   ///< One of the words listed in ParamSpec::choices ("a|b|c").
  text,     ///< Any non-empty text without ',' (a file name, say).
};

/// One declared parameter: its key, type, default (as written on a command line) and range.
struct ParamSpec {
  std::string_view key;
  ParamType type = ParamType::whole;
  std::string_view default_value;  ///< Empty: no default (the parameter is then absent unless given).
  std::string_view help;           ///< What it sets, for the help text.
  double min = 0.0;                ///< Inclusive lower bound of whole and number values.
  double max = 0.0;                ///< Inclusive upper bound of whole and number values.
  std::string_view choices = {};   ///< "a|b|c" for choice values.
  bool above_min = false;          ///< number: `min` itself is excluded ("a number > 0").
};

/// Validated values of the declared parameters (defaults filled in). Plain value.
class ParamValues {
 public:
  /// True when the user wrote `key` (rather than taking the default).
  bool given(std::string_view key) const;
  /// True when `key` has a value (given, or declared with a default).
  bool has(std::string_view key) const;
  /// A whole value; throws std::logic_error when `key` is not a declared parameter with a value.
  std::uint64_t whole(std::string_view key) const;
  /// A number (whole values convert too).
  double number(std::string_view key) const;
  /// A boolean value.
  bool boolean(std::string_view key) const;
  /// The value as text (choice and text values; any value in its written form).
  const std::string& text(std::string_view key) const;
  /// "key=value,..." of the given values, in declaration order ("" when none): the canonical spec tail.
  const std::string& canonical() const { return canonical_; }

 private:
  friend ParamValues read_params(const Spec&, std::span<const ParamSpec>, const std::string&);
  struct Value {
    std::string key, text;
    double number = 0.0;
    std::uint64_t whole = 0;
    bool boolean = false, given = false;
  };
  const Value& find(std::string_view key) const;
  std::vector<Value> values_;
  std::string canonical_;
};

/// Checks `spec`'s parameters against `params` and converts them. Throws a one-line vf::Error starting
/// with `where` on an unknown key (listing the valid ones) or a value of the wrong type or out of range.
ParamValues read_params(const Spec& spec, std::span<const ParamSpec> params, const std::string& where);

/// What a value of `param` must be, as messages and help texts say it ("a non-negative integer in
/// 1..128", "a number > 0 (or inf)", "one of u8, u16").
std::string expected_value(const ParamSpec& param);

/// "" when `value` is a valid value of `param`, else "VALUE: expected ..." (read_params' check and
/// wording, for front ends that check one value at a time, such as a command-line option).
std::string param_value_error(const ParamSpec& param, std::string_view value);

/// One line per parameter, "key=default  help (range)", indented by `indent`, for help texts.
std::string describe_params(std::span<const ParamSpec> params, std::string_view indent);

}  // namespace vf
