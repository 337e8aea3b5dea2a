#include "bench_options.hpp"

#include <algorithm>

#include <CLI/CLI.hpp>

#include "bench_accel.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/spec.hpp"

namespace vf::bench {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

// --device cuda runs the static benchmark: the walkthrough and moving-object modes are usage errors.
void check_device(const BenchOptions& o) {
  if (o.device == "cuda" && (o.walk_frames > 0 || o.dynamic_frames > 0)) throw UsageError("--device cuda: not with --walk or --dynamic");
}

void check_accel_specs(const std::vector<std::string>& requested) {
  for (std::size_t i = 0; i < requested.size(); ++i) {
    const std::string& spec = requested[i];
    if (spec.empty()) throw UsageError("--accel: empty structure name in the list");
    check_bench_accel(spec);
    if (std::find(requested.begin(), requested.begin() + static_cast<std::ptrdiff_t>(i), spec) !=
        requested.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw UsageError("--accel: '" + spec + "' is listed twice");
    }
  }
  // An approximate structure's error is measured against exact answers of the same rays.
  const auto is_exact = [](const std::string& spec) {
    const std::string name = spec.substr(0, spec.find(':'));
    return name == kEmbreeName || find_structure(name).exactness == Exactness::exact;
  };
  if (std::none_of(requested.begin(), requested.end(), is_exact))
    throw UsageError("--accel: list an exact structure (bvh, embree, ...) beside " + requested.front() +
                     " to measure its error against");
}

}  // namespace

std::optional<BenchOptions> parse_bench_options(int argc, const char* const* argv, std::ostream& help_out) {
  BenchOptions options;
  std::string kind_name;
  std::int64_t count = 0;

  CLI::App app{"Times the same rays through visfield's structures and Embree 3 in one process.", "visfield-bench"};
  app.add_option("--scene", options.scene, "Mesh file, scene .json, or builtin:NAME[:size=N,seed=S]")->required();
  app.add_option("--rays", kind_name, "Ray set: primary, ao, shadow or random (required, except with --walk)")
      ->check(CLI::IsMember({"primary", "ao", "shadow", "random"}));
  std::string accel_list;
  app.add_option("--accel", accel_list,
                 "Comma-separated structures, each NAME[:key=value,...] (`visfield structures` lists the parameters): " +
                     joined(bench_accel_names()) + " (required)");
  app.add_option("--count", count, "Exact number of rays (default: one image's worth)")
      ->check(CLI::Range(std::int64_t{1}, kMaxRayCount));
  app.add_option("--threads", options.threads, "Worker threads for every structure, 0 = all hardware threads")
      ->check(CLI::Range(0, kMaxThreads));
  std::string max_memory;
  app.add_option("--max-memory", max_memory,
                 "Refuse builds and ray sets estimated to need more, e.g. 4G (default: the available memory)")
      ->check(CLI::Validator(
          [](std::string& value) {
            return parse_byte_size(value) ? std::string() : "expected " + std::string(kByteSizeSyntax) + ", got " + value;
          },
          "SIZE"));
  app.add_flag("--json", options.json, "Print a JSON document instead of the table");
  app.add_option("--width", options.width, "Image width in pixels (default: the scene camera's)")
      ->check(CLI::Range(1, 32768));
  app.add_option("--height", options.height, "Image height in pixels (default: the scene camera's)")
      ->check(CLI::Range(1, 32768));
  app.add_option("--ao-rays", options.ao_rays, "AO rays per primary hit")->check(CLI::Range(1, 1024));
  std::string ao_directions = "random";
  app.add_option("--ao-directions", ao_directions,
                 "AO ray directions: random (--ao-rays per hit), or 33|129|513|2049|8193: one ray along each line of that "
                 "octahedral set (VLF-RT's AO; beam:dirs= of the same count traces them on its fast path)")
      ->check(CLI::IsMember({"random", "33", "129", "513", "2049", "8193"}));
  std::string ray_order = "pixel";
  app.add_option("--ray-order", ray_order,
                 "pixel: each pixel's rays together (as visfield render traces them for most structures); line: AO rays "
                 "along the lines (--ao-directions N) grouped by line, pixel order within each (the VLF-RT workload as "
                 "a stream per line), handed to every structure in that order")
      ->check(CLI::IsMember({"pixel", "line"}));
  app.add_option("--max-distance", options.max_distance,
                 "AO ray length in scene units (default unlimited, as visfield render)");
  app.add_option("--seed", options.seed, "Seed of the AO, shadow and random rays");
  app.add_option("--reps", options.reps, "Timed repetitions (the median is reported)")->check(CLI::Range(1, 1000));
  app.add_option("--warmup", options.warmup, "Untimed runs before the timed ones")->check(CLI::Range(0, 100));
  app.add_option("--dynamic", options.dynamic_frames,
                 "Moving-object mode: for FRAMES frames move one object, update each structure (remove and insert; "
                 "a full rebuild where it cannot update) and trace the ray set; reports update, rebuild and trace times")
      ->check(CLI::Range(1, 100000));
  std::int64_t move_object = -1;
  app.add_option("--move-object", move_object,
                 "Object id moved by --dynamic (default: the object nearest to 5% of the scene's triangles)")
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{0xfffffffe}));

  app.add_option("--walk", options.walk_frames,
                 "Walkthrough mode: render FRAMES frames of the scene's camera path and object keyframes through each "
                 "--accel structure in turn (objects moved in place where the structure can, else rebuilt), timing each "
                 "frame's update and render (the VLF-RT paper's Figure 6); --rays is not needed")
      ->check(CLI::Range(2, 1000000));
  app.add_option("--integrator", options.integrator, "What --walk renders")
      ->check(CLI::IsMember({"raycast", "whitted", "ao", "softshadow", "glossy", "path"}));
  app.add_option("--walk-csv", options.walk_csv_dir, "--walk: folder to write one CSV of frame times per structure in");
  app.add_option("--walk-plot", options.walk_plot, "--walk: the plot (.svg) of every structure's frame times");
  app.add_option("--device", options.device,
                 "cpu, or cuda: the same rays through the GPU BVH and the --accel fields on the GPU beside the CPU's, "
                 "AO rays generated on the device, G rays/s, agreement and the roofline (the GPU paper's figures: "
                 "visfield-experiments --device cuda)")
      ->check(CLI::IsMember({"cpu", "cuda"}));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    help_out << app.help();
    return std::nullopt;
  } catch (const CLI::ParseError& error) {
    throw UsageError(error.what());
  }

  if (!max_memory.empty()) {
    const double bytes = *parse_byte_size(max_memory);
    set_memory_limit(bytes, "--max-memory " + format_bytes(bytes));
  }
  check_device(options);
  if (options.walk_frames > 0) {
    if (accel_list.empty()) throw UsageError("--accel is required");
    options.accels = split_spec_list(accel_list);
    return options;
  }
  if (!options.walk_csv_dir.empty() || !options.walk_plot.empty() || app.count("--integrator") > 0)
    throw UsageError("--integrator, --walk-csv and --walk-plot: only with --walk");
  if (kind_name.empty()) throw UsageError("--rays is required");
  if (accel_list.empty()) throw UsageError("--accel is required");
  options.kind = *parse_ray_kind(kind_name);
  for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level)
    if (ao_directions == std::to_string(DirectionLines::count(level))) options.psf_level = level;
  options.accels = split_spec_list(accel_list);
  options.line_major = ray_order == "line";
  if (options.line_major && (options.kind != RayKind::ao || options.psf_level == 0))
    throw UsageError("--ray-order line: only for AO rays along the lines (--rays ao --ao-directions N)");
  if (app.count("--count") > 0) options.count = static_cast<std::size_t>(count);
  if (app.count("--move-object") > 0) {
    if (options.dynamic_frames == 0) throw UsageError("--move-object: only with --dynamic");
    options.move_object = static_cast<std::uint32_t>(move_object);
  }
  if (!(options.max_distance > 0.0f))
    throw UsageError("--max-distance: must be positive, got " + app["--max-distance"]->as<std::string>());
  check_accel_specs(options.accels);
  return options;
}

void check_ray_memory(std::size_t ray_count, std::size_t structure_count) {
  const double per_ray = static_cast<double>(sizeof(Ray) + structure_count * sizeof(Hit));
  require_memory(static_cast<double>(ray_count) * per_ray,
                 std::to_string(ray_count) + " rays with results for " + std::to_string(structure_count) +
                     (structure_count == 1 ? " structure" : " structures"));
}

}  // namespace vf::bench
