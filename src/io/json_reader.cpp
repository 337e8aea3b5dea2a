#include "visfield/io/json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "file_checks.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"

namespace vf::json {

using io_detail::require_readable_file;

namespace {

// A found value as it appears in a message: compact JSON, cut short when long.
std::string show(const nlohmann::json& value) {
  std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  constexpr std::size_t kMax = 60;
  if (text.size() > kMax) text = text.substr(0, kMax) + "...";
  return text;
}

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Thrown from the parser callback when an object repeats a key.
struct DuplicateKey {
  std::string key;
};


// Larger texts are refused before parsing: the parsed values take several times the text's size.
constexpr std::uintmax_t kMaxJsonBytes = std::uintmax_t{256} << 20;

}  // namespace

bool NumberRange::contains(double v) const {
  return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

std::string NumberRange::describe(bool plural) const {
  std::string s = plural ? "numbers" : "a number";
  const bool has_lo = lo > -1e300, has_hi = hi < 1e300;
  if (has_lo && has_hi)
    return s + " in " + (lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + (hi_open ? ")" : "]");
  if (has_lo) return s + (lo_open ? " > " : " >= ") + format_number(lo);
  if (has_hi) return s + (hi_open ? " < " : " <= ") + format_number(hi);
  return s;
}

nlohmann::json parse_json_file(const std::filesystem::path& path) {
  require_readable_file(path);
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxJsonBytes)
    throw Error(path.string() + ": " + format_bytes(static_cast<double>(size)) + " of JSON, more than the " +
                format_bytes(static_cast<double>(kMaxJsonBytes)) + " visfield reads (meshes belong in mesh files)");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw Error(path.string() + ": cannot read");
  return parse_json_text(text.str(), path.string());
}

// kMaxJsonDepth is far beyond any file visfield writes or reads (scene files nest 4 deep, glTF files
// about 6) and far below where nested values exhaust the stack of a recursive parser or of code
// that walks them recursively (dump, destruction): Assimp's glTF reader overflows at about 100,000.
void check_json_nesting(std::string_view text, const std::string& source) {
  int depth = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      for (++i; i < text.size() && text[i] != '"'; ++i) i += text[i] == '\\';
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      i = std::min(text.find('\n', i), text.size());
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      i = std::min(text.find("*/", i + 2), text.size()) + 1;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw Error(source + ": invalid JSON: arrays and objects nested more than " + std::to_string(kMaxJsonDepth) +
                    " deep");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

nlohmann::json parse_json_text(const std::string& text, const std::string& source) {
  check_json_nesting(text, source);
  // nlohmann keeps the last of repeated keys; a repeated key is almost always a mistake, so refuse it.
  std::vector<std::set<std::string>> keys_per_open_object;
  const nlohmann::json::parser_callback_t check_keys = [&](int /*depth*/, nlohmann::json::parse_event_t event,
                                                         nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if (event == Event::object_start) keys_per_open_object.emplace_back();
    if (event == Event::object_end) keys_per_open_object.pop_back();
    if (event == Event::key && !keys_per_open_object.back().insert(parsed.get<std::string>()).second)
      throw DuplicateKey{parsed.get<std::string>()};
    return true;
  };
  try {
    return nlohmann::json::parse(text, check_keys, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const DuplicateKey& duplicate) {
    throw Error(source + ": invalid JSON: key \"" + one_line(duplicate.key) + "\" appears twice in one object");
  } catch (const nlohmann::json::parse_error& e) {
    // e.what() is "[json.exception.parse_error.101] parse error at line L, column C: <reason>".
    const std::string message = e.what();
    const std::size_t at = message.find("parse error at ");
    const std::string where = at == std::string::npos ? message : message.substr(at + 12);
    throw Error(source + ": invalid JSON " + one_line(where));
  } catch (const nlohmann::json::exception& e) {
    // Any other parser complaint, such as a number beyond double's range (out_of_range.406): its
    // message without nlohmann's "[json.exception.NAME.N] " tag.
    const std::string message = e.what();
    const std::size_t tag_end = message.find("] ");
    throw Error(source + ": invalid JSON: " + one_line(tag_end == std::string::npos ? message : message.substr(tag_end + 2)));
  }
}

JsonField::JsonField(const nlohmann::json& value, std::string file, std::string path)
    : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

JsonField JsonField::child(const nlohmann::json& value, std::string path) const { return {value, file_, std::move(path)}; }

void JsonField::fail(const std::string& problem) const {
  throw Error(file_ + ": " + (path_.empty() ? std::string("top level") : path_) + ": " + problem);
}

void JsonField::fail_expected(const std::string& expected) const { fail("expected " + expected + ", got " + show(*value_)); }

void JsonField::require_object(std::span<const std::string_view> allowed) const {
  if (!value_->is_object()) fail_expected("an object");
  for (const auto& [key, value] : value_->items()) {
    bool known = false;
    for (std::string_view a : allowed) known = known || key == a;
    if (known) continue;
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    fail("unknown key \"" + one_line(key) + "\" (expected one of: " + list + ")");
  }
}

std::optional<JsonField> JsonField::optional_member(std::string_view key) const {
  if (!value_->is_object()) fail_expected("an object");
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return child(*it, path_.empty() ? std::string(key) : path_ + "." + std::string(key));
}

JsonField JsonField::member(std::string_view key) const {
  std::optional<JsonField> m = optional_member(key);
  if (!m) fail("missing required key \"" + std::string(key) + "\"");
  return *m;
}

std::vector<JsonField> JsonField::elements(std::size_t min_count) const {
  if (!value_->is_array() || value_->size() < min_count)
    fail_expected(min_count == 0 ? std::string("an array") : "an array of at least " + std::to_string(min_count) +
                                                                 (min_count == 1 ? " element" : " elements"));
  std::vector<JsonField> out;
  out.reserve(value_->size());
  for (std::size_t i = 0; i < value_->size(); ++i) out.push_back(child((*value_)[i], path_ + "[" + std::to_string(i) + "]"));
  return out;
}

std::string JsonField::as_string() const {
  if (!value_->is_string() || value_->get_ref<const std::string&>().empty()) fail_expected("a non-empty string");
  return value_->get<std::string>();
}

float JsonField::as_float(const NumberRange& range) const {
  if (!value_->is_number()) fail_expected(range.describe());
  const double v = value_->get<double>();
  if (!std::isfinite(v) || std::fabs(v) > std::numeric_limits<float>::max() || !range.contains(v))
    fail_expected(range.describe());
  return static_cast<float>(v);
}

int JsonField::as_int(int lo, int hi) const {
  const std::string expected = "an integer in " + std::to_string(lo) + ".." + std::to_string(hi);
  if (!value_->is_number()) fail_expected(expected);
  const double v = value_->get<double>();
  if (!(v >= lo && v <= hi) || v != std::floor(v)) fail_expected(expected);
  return static_cast<int>(v);
}

double JsonField::as_double(const NumberRange& range) const {
  if (!value_->is_number()) fail_expected(range.describe());
  const double v = value_->get<double>();
  if (!std::isfinite(v) || !range.contains(v)) fail_expected(range.describe());
  return v;
}

std::uint64_t JsonField::as_uint64(std::uint64_t lo, std::uint64_t hi) const {
  const std::string expected = "an integer in " + std::to_string(lo) + ".." + std::to_string(hi);
  // JSON parsing gives non-negative integers, and only those, the unsigned type.
  if (!value_->is_number_unsigned()) fail_expected(expected);
  const auto v = value_->get<std::uint64_t>();
  if (v < lo || v > hi) fail_expected(expected);
  return v;
}

Vec3f JsonField::as_vec3(const NumberRange& range) const {
  if (!value_->is_array() || value_->size() != 3) fail_expected("an array of 3 " + range.describe(true));
  const std::vector<JsonField> parts = elements();
  return {parts[0].as_float(range), parts[1].as_float(range), parts[2].as_float(range)};
}

}  // namespace vf::json
