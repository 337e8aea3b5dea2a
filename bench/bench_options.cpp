#include "bench_options.hpp"

#include <algorithm>
#include <sstream>

#include <CLI/CLI.hpp>

#include "bench_accel.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/ray.hpp"

namespace vf::bench {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

void check_accel_names(const std::vector<std::string>& requested) {
  const std::vector<std::string> valid = bench_accel_names();
  for (std::size_t i = 0; i < requested.size(); ++i) {
    const std::string& name = requested[i];
    if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
      if (name == kEmbreeName) {
        throw UsageError(
            "--accel embree: this visfield-bench was built without Embree (configure with -DVISFIELD_EMBREE=ON)");
      }
      throw UsageError("--accel: unknown structure '" + name + "' (valid: " + joined(valid) + ")");
    }
    if (std::find(requested.begin(), requested.begin() + static_cast<std::ptrdiff_t>(i), name) !=
        requested.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw UsageError("--accel: '" + name + "' is listed twice");
    }
  }
}

}  // namespace

std::optional<BenchOptions> parse_bench_options(int argc, const char* const* argv, std::ostream& help_out) {
  BenchOptions options;
  std::string kind_name;
  std::int64_t count = 0;

  CLI::App app{"Times the same rays through visfield's structures and Embree 3 in one process.", "visfield-bench"};
  app.add_option("--scene", options.scene, "Mesh file, scene .json, or builtin:NAME[:size=N,seed=S]")->required();
  app.add_option("--rays", kind_name, "Ray set: primary, ao, shadow or random")
      ->required()
      ->check(CLI::IsMember({"primary", "ao", "shadow", "random"}));
  app.add_option("--accel", options.accels, "Comma-separated structures: " + joined(bench_accel_names()))
      ->required()
      ->delimiter(',');
  app.add_option("--count", count, "Exact number of rays (default: one image's worth)")
      ->check(CLI::Range(std::int64_t{1}, kMaxRayCount));
  app.add_option("--threads", options.threads, "Worker threads for every structure, 0 = all hardware threads")
      ->check(CLI::Range(0, kMaxThreads));
  app.add_flag("--json", options.json, "Print a JSON document instead of the table");
  app.add_option("--width", options.width, "Image width in pixels (default: the scene camera's)")
      ->check(CLI::Range(1, 32768));
  app.add_option("--height", options.height, "Image height in pixels (default: the scene camera's)")
      ->check(CLI::Range(1, 32768));
  app.add_option("--ao-rays", options.ao_rays, "AO rays per primary hit")->check(CLI::Range(1, 1024));
  app.add_option("--max-distance", options.max_distance,
                 "AO ray length in scene units (default unlimited, as visfield render)");
  app.add_option("--seed", options.seed, "Seed of the AO, shadow and random rays");
  app.add_option("--reps", options.reps, "Timed repetitions (the median is reported)")->check(CLI::Range(1, 1000));
  app.add_option("--warmup", options.warmup, "Untimed runs before the timed ones")->check(CLI::Range(0, 100));
  std::uint64_t auto_rays = 0;
  std::string calibration;
  app.add_option("--auto-rays", auto_rays, "With --accel auto: the ray count to decide for (default: this bench's)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 50));
  app.add_option("--calibration", calibration, "With --accel auto: calibration file from `visfield calibrate`");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    help_out << app.help();
    return std::nullopt;
  } catch (const CLI::ParseError& error) {
    throw UsageError(error.what());
  }

  options.kind = *parse_ray_kind(kind_name);
  if (app.count("--auto-rays") > 0) options.auto_rays = auto_rays;
  if (app.count("--calibration") > 0) options.calibration = calibration;
  if (app.count("--count") > 0) options.count = static_cast<std::size_t>(count);
  if (!(options.max_distance > 0.0f))
    throw UsageError("--max-distance: must be positive, got " + app["--max-distance"]->as<std::string>());
  if (options.accels.empty()) throw UsageError("--accel: no structure named");
  check_accel_names(options.accels);
  return options;
}

void check_ray_memory(std::size_t ray_count, std::size_t structure_count) {
  const std::size_t per_ray = sizeof(Ray) + structure_count * sizeof(Hit);
  const std::size_t needed = ray_count * per_ray;
  const std::size_t available = physical_memory_bytes();
  if (available > 0 && needed > available) {
    std::ostringstream message;
    message << ray_count << " rays with results for " << structure_count
            << (structure_count == 1 ? " structure" : " structures") << " need about " << needed / (1024 * 1024)
            << " MiB, more than this machine's " << available / (1024 * 1024) << " MiB";
    throw UsageError(message.str());
  }
}

}  // namespace vf::bench
