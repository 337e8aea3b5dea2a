#include "bench_options.hpp"

#include <algorithm>
#include <map>
#include <string_view>

#include <CLI/CLI.hpp>

#include "bench_accel.hpp"
#include "cli_support.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/render_scene.hpp"

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
  cli::add_resource_options(app, options.threads);
  app.add_flag("--json", options.json, "Print a JSON document instead of the table");
  app.add_option("--width", options.width, "Image width in pixels (default: the scene camera's)")
      ->check(CLI::Range(1, 32768));
  app.add_option("--height", options.height, "Image height in pixels (default: the scene camera's)")
      ->check(CLI::Range(1, 32768));
  // The render settings the ray sets share with visfield render, declared once (render_setting_specs()).
  std::map<std::string, std::string, std::less<>> settings;
  for (const RenderSettingSpec& spec : render_setting_specs())
    if (std::string_view key = spec.param.key;
        key == "ao_rays" || key == "ao_directions" || key == "max_distance" || key == "seed" || key == "integrator")
      cli::add_param_option(app, spec.param, settings[std::string(key)]);
  settings.at("ao_rays") = std::to_string(options.ao_rays);  // 4 per hit by default, as the bench always had
  app.get_option("--ao-rays")->default_str(settings.at("ao_rays"));
  settings.at("integrator") = options.integrator;
  app.get_option("--integrator")->default_str(options.integrator)->description("(--walk) " +
                                                                              app.get_option("--integrator")->get_description());
  std::string ray_order = "pixel";
  app.add_option("--ray-order", ray_order,
                 "pixel: each pixel's rays together (as visfield render traces them for most structures); line: AO rays "
                 "along the lines (--ao-directions N) grouped by line, pixel order within each (the VLF-RT workload as "
                 "a stream per line), handed to every structure in that order")
      ->check(CLI::IsMember({"pixel", "line"}));
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

  std::string written;
  for (const auto& [key, value] : settings) written += (written.empty() ? "" : ",") + key + "=" + value;
  const RenderSettings shared = with_render_settings({}, written, "visfield-bench");
  options.ao_rays = shared.ao_rays;
  options.psf_level = shared.psf_level;
  options.max_distance = shared.max_distance;
  options.seed = shared.seed;
  options.integrator = settings.at("integrator");
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
  options.accels = split_spec_list(accel_list);
  options.line_major = ray_order == "line";
  if (options.line_major && (options.kind != RayKind::ao || options.psf_level == 0))
    throw UsageError("--ray-order line: only for AO rays along the lines (--rays ao --ao-directions N)");
  if (app.count("--count") > 0) options.count = static_cast<std::size_t>(count);
  if (app.count("--move-object") > 0) {
    if (options.dynamic_frames == 0) throw UsageError("--move-object: only with --dynamic");
    options.move_object = static_cast<std::uint32_t>(move_object);
  }
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
