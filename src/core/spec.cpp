#include "visfield/core/spec.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "visfield/core/error.hpp"

namespace vf {
namespace {

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::vector<std::string_view> split(std::string_view text, char separator) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

bool parse_double(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(out);
}

// A number as a parameter may write it: finite, or "inf" where the range reaches infinity.
bool parse_number(const ParamSpec& p, const std::string& text, double& out) {
  if (text == "inf" && std::isinf(p.max)) {
    out = p.max;
    return true;
  }
  return parse_double(text, out);
}

}  // namespace

std::optional<std::vector<double>> parse_number_list(std::string_view text) {
  std::vector<double> numbers;
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    double value = 0.0;
    if (!parse_double(std::string(text.substr(start, end - start)), value)) return std::nullopt;
    numbers.push_back(value);
    start = end + 1;
  }
  return numbers;
}

std::string expected_value(const ParamSpec& p) {
  switch (p.type) {
    case ParamType::whole: {
      std::string s = "a non-negative integer";
      if (p.max > 0.0) s += " in " + format_number(p.min) + ".." + format_number(p.max);
      return s;
    }
    case ParamType::number:
      if (std::isinf(p.max)) return std::string("a number ") + (p.above_min ? "> " : ">= ") + format_number(p.min) + " (or inf)";
      return std::string("a number in ") + (p.above_min ? "(" : "[") + format_number(p.min) + ", " + format_number(p.max) + "]";
    case ParamType::boolean: return "1, 0, true, false, on, off, yes or no";
    case ParamType::choice: {
      std::string s = "one of ";
      for (const std::string_view c : split(p.choices, '|')) s += (s.size() > 7 ? ", " : "") + std::string(c);
      return s;
    }
    case ParamType::text: return "a non-empty text";
  }
  return "a value";
}

std::string param_value_error(const ParamSpec& param, std::string_view value) {
  Spec spec;
  spec.name = "value";
  spec.params.emplace_back(std::string(param.key), std::string(value));
  try {
    (void)read_params(spec, std::span<const ParamSpec>(&param, 1), "");
  } catch (const Error& e) {
    // read_params says ": KEY=VALUE: expected ..."; a front end names the key its own way.
    const std::string message = e.what();
    const std::size_t at = message.find(": expected ");
    return std::string(value) + (at == std::string::npos ? ": " + message : message.substr(at));
  }
  return "";
}

Spec parse_spec(std::string_view text, std::string_view what) {
  Spec spec;
  const std::size_t colon = text.find(':');
  spec.name = std::string(text.substr(0, colon));
  const std::string where = std::string(what) + spec.name;
  if (spec.name.empty()) throw Error(std::string(what) + "'" + std::string(text) + "': no name before the parameters");
  if (colon == std::string_view::npos) return spec;
  const std::string_view tail = text.substr(colon + 1);
  if (tail.empty() || tail.back() == ',')
    throw Error(where + ": empty parameter list entry (write " + spec.name + ":key=value,...)");
  for (const std::string_view item : split(tail, ',')) {
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos || eq == 0)
      throw Error(where + ": parameter '" + std::string(item) + "' is not key=value");
    std::string key(item.substr(0, eq));
    for (const auto& [seen, value] : spec.params)
      if (seen == key) throw Error(where + ": " + key + " is given twice");
    spec.params.emplace_back(std::move(key), std::string(item.substr(eq + 1)));
  }
  return spec;
}

std::vector<std::string> split_spec_list(std::string_view text) {
  std::vector<std::string> specs;
  for (const std::string_view item : split(text, ',')) {
    const std::size_t eq = item.find('='), colon = item.find(':');
    const bool continues = eq != std::string_view::npos && (colon == std::string_view::npos || colon > eq);
    if (continues && !specs.empty()) specs.back().append(",").append(item);
    else specs.emplace_back(item);
  }
  return specs;
}

ParamValues read_params(const Spec& spec, std::span<const ParamSpec> params, const std::string& where) {
  for (const auto& entry : spec.params) {
    const std::string& key = entry.first;
    const bool known = std::any_of(params.begin(), params.end(), [&](const ParamSpec& p) { return p.key == key; });
    if (known) continue;
    std::string valid;
    for (const ParamSpec& p : params) valid += (valid.empty() ? "" : ", ") + std::string(p.key);
    throw Error(where + ": unknown key '" + key + "' (" + (valid.empty() ? "it takes no parameters" : "valid keys: " + valid) + ")");
  }
  ParamValues out;
  for (const ParamSpec& p : params) {
    ParamValues::Value v;
    v.key = std::string(p.key);
    const auto written =
        std::find_if(spec.params.begin(), spec.params.end(), [&](const auto& kv) { return kv.first == p.key; });
    v.given = written != spec.params.end();
    if (!v.given && p.default_value.empty()) continue;
    v.text = v.given ? written->second : std::string(p.default_value);
    const auto fail = [&](const std::string& extra = "") {
      throw Error(where + ": " + v.key + "=" + v.text + ": expected " + expected_value(p) + extra);
    };
    switch (p.type) {
      case ParamType::whole: {
        const char* end = v.text.data() + v.text.size();
        const auto [ptr, ec] = std::from_chars(v.text.data(), end, v.whole);
        if (ec == std::errc::result_out_of_range) fail(" below 2^64");
        if (ec != std::errc{} || ptr != end) {
          // 1e6-style values: a finite double with no fractional part.
          double d = 0.0;
          if (v.text.find_first_of("eE") == std::string::npos || !parse_double(v.text, d) || d < 0.0 ||
              d != std::floor(d) || d >= 0x1p64)
            fail();
          v.whole = static_cast<std::uint64_t>(d);
        }
        v.number = static_cast<double>(v.whole);
        if (p.max > 0.0 && (v.number < p.min || v.number > p.max)) fail();
        break;
      }
      case ParamType::number:
        if (!parse_number(p, v.text, v.number) || v.number < p.min || v.number > p.max || (p.above_min && v.number == p.min)) fail();
        break;
      case ParamType::boolean:
        if (v.text == "1" || v.text == "true" || v.text == "on" || v.text == "yes") v.boolean = true;
        else if (v.text == "0" || v.text == "false" || v.text == "off" || v.text == "no") v.boolean = false;
        else fail();
        break;
      case ParamType::choice: {
        const std::vector<std::string_view> choices = split(p.choices, '|');
        if (std::find(choices.begin(), choices.end(), v.text) == choices.end()) fail();
        break;
      }
      case ParamType::text:
        if (v.text.empty()) fail();
        break;
    }
    if (v.given) out.canonical_ += (out.canonical_.empty() ? "" : ",") + v.key + "=" + v.text;
    out.values_.push_back(std::move(v));
  }
  return out;
}

const ParamValues::Value& ParamValues::find(std::string_view key) const {
  for (const Value& v : values_)
    if (v.key == key) return v;
  throw std::logic_error("parameter '" + std::string(key) + "' has no value");
}

bool ParamValues::given(std::string_view key) const {
  return std::any_of(values_.begin(), values_.end(), [&](const Value& v) { return v.key == key && v.given; });
}

bool ParamValues::has(std::string_view key) const {
  return std::any_of(values_.begin(), values_.end(), [&](const Value& v) { return v.key == key; });
}

std::uint64_t ParamValues::whole(std::string_view key) const { return find(key).whole; }
double ParamValues::number(std::string_view key) const { return find(key).number; }
bool ParamValues::boolean(std::string_view key) const { return find(key).boolean; }
const std::string& ParamValues::text(std::string_view key) const { return find(key).text; }

std::string describe_params(std::span<const ParamSpec> params, std::string_view indent) {
  std::string out;
  for (const ParamSpec& p : params) {
    std::string head = std::string(p.key) + "=" + (p.default_value.empty() ? "..." : std::string(p.default_value));
    if (head.size() < 18) head.resize(18, ' ');
    out += std::string(indent) + head + " " + std::string(p.help) + " (" + expected_value(p) + ")\n";
  }
  return out;
}

}  // namespace vf
