#include "cli_support.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <variant>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf::cli {

void add_scene_argument(CLI::App& cmd, std::string& scene) {
  cmd.add_option("scene", scene, "Mesh file, scene .json, or builtin:NAME[:size=N,seed=S]")->required();
}

namespace {

// A number as a person writes it: 1e+15, 0.5, 64.
std::string shown(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The option's value as a double, or nothing when it is not a number at all.
std::optional<double> as_number(const std::string& text) {
  double v = 0.0;
  if (!CLI::detail::lexical_cast(text, v)) return std::nullopt;
  return v;
}

}  // namespace

CLI::Validator number_in(double lo, double hi) {
  const std::string range = "[" + shown(lo) + ", " + shown(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& value) {
        const std::optional<double> v = as_number(value);
        if (v && *v >= lo && *v <= hi) return std::string();
        return "must be a number in " + range + ", got " + value;
      },
      "NUMBER in " + range);
}

CLI::Validator positive_number(bool infinity_allowed) {
  const std::string expected = infinity_allowed ? "a number > 0 (or inf)" : "a number > 0";
  return CLI::Validator(
      [infinity_allowed, expected](std::string& value) {
        const std::optional<double> v = as_number(value);
        if (v && *v > 0.0 && (infinity_allowed || std::isfinite(*v))) return std::string();
        return "must be " + expected + ", got " + value;
      },
      "NUMBER > 0");
}

CLI::Option* add_param_option(CLI::App& cmd, const ParamSpec& param, std::string& value) {
  std::string name = "--" + std::string(param.key);
  std::replace(name.begin(), name.end(), '_', '-');
  value = std::string(param.default_value);
  // No validator description: the range is in the help text already.
  const CLI::Validator check([param](std::string& text) { return param_value_error(param, text); }, "");
  return cmd.add_option(name, value, std::string(param.help) + " (" + expected_value(param) + ")")->check(check)->capture_default_str();
}

void add_resource_options(CLI::App& cmd, int& threads) {
  cmd.add_option("--threads", threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  const CLI::Validator size(
      [](std::string& value) {
        return parse_byte_size(value) ? std::string() : "expected " + std::string(kByteSizeSyntax) + ", got " + value;
      },
      "SIZE");
  cmd.add_option_function<std::string>(
         "--max-memory",
         [](const std::string& value) {
           const double bytes = *parse_byte_size(value);
           set_memory_limit(bytes, "--max-memory " + format_bytes(bytes));
         },
         "Refuse builds and ray sets estimated to need more (default: the memory available at the start of each build)")
      ->check(size);
}

CLI::Option* add_structure_option(CLI::App& cmd, const std::string& name, std::string& spec, const std::string& help,
                                  const std::string& only) {
  const CLI::Validator registered(
      [name, only](std::string& value) {
        // CLI11 puts "--accel: " before the message; the spec's name follows.
        try {
          check_structure_spec(value, "");
        } catch (const Error& e) {
          return std::string(e.what());
        }
        if (!only.empty() && parse_spec(value, "").name != only) return value + ": must be " + only;
        return std::string();
      },
      "SPEC");
  return cmd.add_option(name, spec, help)->check(registered);
}

Scene load_scene_argument(const std::string& spec, double* load_ms) {
  const Stopwatch watch;
  Scene scene = load_scene(spec);
  if (load_ms) *load_ms = watch.elapsed_ms();
  return scene;
}

void warn_degenerate_triangles(const std::string& scene_spec, std::size_t count) {
  if (count > 0)
    std::cerr << "visfield: warning: " << scene_spec << ": " << count << " zero-area triangles left out of the acceleration structure\n";
}

BuiltStructure build_structure_for(const std::string& structure_spec, SceneGeometry& geometry, const BuildContext& context,
                                   const std::string& option, const std::string& scene_spec) {
  if (geometry.scene().instances().empty() || geometry.instanced_triangle_count() == 0)
    throw Error(scene_spec + ": the scene has no triangles");
  BuiltStructure built = build_structure(structure_spec, geometry, context, option + " ");
  if (built.degenerate_triangles >= geometry.instanced_triangle_count())
    throw Error(scene_spec + ": the scene has no non-degenerate triangles");
  warn_degenerate_triangles(scene_spec, built.degenerate_triangles);
  return built;
}

void print_structure(std::ostream& out, const std::string& option, const BuiltStructure& built, int threads) {
  const AccelStats s = structure_stats(built.structure);
  std::string label = option + ":";
  label.resize(std::max<std::size_t>(label.size() + 1, 20), ' ');
  out << label << built.resolved << " (" << threads << " threads)\n"
      << "  build:            " << s.build_ms << " ms\n"
      << "  memory:           " << format_bytes(static_cast<double>(s.memory_bytes)) << " (" << s.memory_bytes
      << " bytes)\n"
      << "  build estimate:   " << format_bytes(built.estimated_bytes) << " (checked before the build against "
      << memory_limit().source << ")\n"
      << "  nodes:            " << s.node_count << "\n"
      << "  leaves:           " << s.leaf_count << "\n"
      << "  references:       " << s.reference_count << "\n"
      << "  max depth:        " << s.max_depth << "\n";
  if (const auto* field = std::get_if<BeamField>(&built.structure)) {
    const BeamFieldStats b = field->beam_stats();
    out << "  directions:       " << b.directions << " lines x " << b.resolution << "x" << b.resolution << " tiles\n"
        << "  per direction:    " << format_bytes(static_cast<double>(b.bytes_per_direction)) << "\n"
        << "  refs/triangle:    " << b.references_per_triangle << " (over all directions; "
        << b.references_per_triangle / static_cast<double>(std::max<std::size_t>(b.directions, 1)) << " per direction)\n"
        << "  empty tiles:      " << 100.0 * b.empty_tile_fraction << "% of " << b.tiles << "\n";
  }
}

void check_image_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".png" && ext != ".exr") throw Error(path + ": output must end in .png or .exr");
}

}  // namespace vf::cli
