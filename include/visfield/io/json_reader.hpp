#pragma once
/// \file Typed, path-aware reading of JSON files, so every error names the file and the JSON path
/// ("scene.json: instances[1].scale: expected a number > 0, got -2"). Every file visfield reads
/// (scene files, calibration files) goes through it.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "visfield/core/vec.hpp"

namespace vf::json {

/// Accepted interval of a number, with the words an error message uses for it.
struct NumberRange {
  double lo = -1e300;
  double hi = 1e300;
  bool lo_open = false;
  bool hi_open = false;

  static NumberRange any() { return {}; }
  static NumberRange positive() { return {0.0, 1e300, true, false}; }
  static NumberRange non_negative() { return {0.0, 1e300, false, false}; }
  static NumberRange closed(double lo, double hi) { return {lo, hi, false, false}; }
  static NumberRange open(double lo, double hi) { return {lo, hi, true, true}; }

  bool contains(double v) const;
  /// "a number", "a number > 0", "a number in [0, 1]", ...; `plural` gives "numbers ...".
  std::string describe(bool plural = false) const;
};

/// Reads a JSON text file; throws vf::Error "<file>: invalid JSON at line L, column C: ..." on a
/// syntax error or a key repeated within one object. Comments (// and /* */) are allowed.
nlohmann::json parse_json_file(const std::filesystem::path& path);

/// Parses JSON text as parse_json_file does; `source` names it in messages.
nlohmann::json parse_json_text(const std::string& text, const std::string& source);

/// Deepest nesting of arrays and objects visfield accepts in any JSON, its own files and glTF alike.
inline constexpr int kMaxJsonDepth = 64;

/// Throws vf::Error "<source>: invalid JSON: arrays and objects nested more than 64 deep" when
/// `text` nests deeper than kMaxJsonDepth, before any parser recurses into it (strings and comments
/// are skipped; syntax is otherwise not checked). O(size), no allocation.
void check_json_nesting(std::string_view text, const std::string& source);

/// One JSON value plus where it sits: the file (for messages) and its path from the root.
/// Borrows the document, which must outlive it. Every accessor throws vf::Error on a type or range
/// mismatch, naming file, path, what was expected and the value found.
class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string file, std::string path = {});

  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }

  /// Throws "<file>: <path>: <problem>".
  [[noreturn]] void fail(const std::string& problem) const;
  /// Throws "<file>: <path>: expected <expected>, got <value>".
  [[noreturn]] void fail_expected(const std::string& expected) const;

  /// Requires an object whose keys all appear in `allowed` (a misspelt key must not pass silently).
  void require_object(std::span<const std::string_view> allowed) const;
  /// As above, for a list written in place.
  void require_object(std::initializer_list<std::string_view> allowed) const {
    require_object(std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  /// The member `key` of an object; throws when absent.
  JsonField member(std::string_view key) const;
  /// The member `key` of an object, or nothing when absent.
  std::optional<JsonField> optional_member(std::string_view key) const;
  /// The elements of an array (at least `min_count` of them).
  std::vector<JsonField> elements(std::size_t min_count = 0) const;

  /// A non-empty string.
  std::string as_string() const;
  /// A finite number inside `range` that fits a float.
  float as_float(const NumberRange& range = NumberRange::any()) const;
  /// An integer (a number with no fractional part) in [lo, hi].
  int as_int(int lo, int hi) const;
  /// A finite number inside `range`, in double precision.
  double as_double(const NumberRange& range = NumberRange::any()) const;
  /// A non-negative integer in [lo, hi] (the full 64-bit range is kept exactly).
  std::uint64_t as_uint64(std::uint64_t lo, std::uint64_t hi) const;
  /// An array of exactly 3 numbers, each inside `range`.
  Vec3f as_vec3(const NumberRange& range = NumberRange::any()) const;

 private:
  JsonField child(const nlohmann::json& value, std::string path) const;

  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

}  // namespace vf::json
