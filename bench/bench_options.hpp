#pragma once
/// \file visfield-bench's command line: parsing and validation, nothing else.

#include <cstdint>
#include <limits>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "visfield/render/ray_kind.hpp"

namespace vf::bench {

/// A bad command line: printed as "visfield-bench: error: <what>", exit status 2.
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message) : std::runtime_error(message) {}
};

/// Everything the command line sets; defaults are the values used when an option is absent.
struct BenchOptions {
  std::string scene;                 ///< Mesh file, scene JSON or builtin:NAME[:size=N,seed=S].
  RayKind kind = RayKind::primary;   ///< --rays.
  std::vector<std::string> accels;   ///< --accel specs, in the order given, no duplicates.
  std::optional<std::size_t> count;  ///< --count: exact number of rays; absent = one image's worth.
  int threads = 0;                   ///< --threads: worker threads, 0 = all hardware threads (cli::add_resource_options).
  bool json = false;                 ///< --json: print a JSON document instead of the table.
  int width = 0;                     ///< --width: image width in pixels; 0 = the scene camera's.
  int height = 0;                    ///< --height: image height in pixels; 0 = the scene camera's.
  int ao_rays = 4;                   ///< --ao-rays: AO rays per primary hit (the render setting ao_rays; 4 by default here).
  int psf_level = 0;                 ///< --ao-directions: 0 = random; L = one AO ray per line of the level-L set.
  bool line_major = false;           ///< --ray-order line: AO rays along the lines grouped by line (pixel order within one).
  float max_distance = std::numeric_limits<float>::infinity();  ///< --max-distance: AO ray length (as visfield render).
  std::uint64_t seed = 1;                                       ///< --seed: seeds the AO, shadow and random rays.
  int reps = 5;                                                 ///< --reps: timed repetitions; the median is reported.
  int warmup = 1;                                               ///< --warmup: untimed runs before the timed ones.
  int dynamic_frames = 0;                 ///< --dynamic: frames of the moving-object mode; 0 = the static benchmark.
  std::optional<std::uint32_t> move_object;  ///< --move-object: the object id moved in --dynamic (default: chosen).
  int walk_frames = 0;                    ///< --walk: frames of the scene's walkthrough per structure; 0 = no walkthrough.
  std::string integrator = "raycast";     ///< --integrator: what --walk renders (raycast, whitted, ...).
  std::string walk_csv_dir;               ///< --walk-csv: folder for one CSV of frame times per structure ("" = none).
  std::string walk_plot;                  ///< --walk-plot: the plot of every structure's frame times ("" = none).
  std::string device = "cpu";             ///< --device: cpu, or cuda (the GPU beside the CPU on the same rays).
};

/// Largest --count accepted (the rays alone would take 32 GB).
inline constexpr std::int64_t kMaxRayCount = 1'000'000'000;

/// Parses the command line. Returns nothing when --help was asked for (the help text then went to
/// `help_out`). Throws UsageError on a missing, malformed or out-of-range value, an unknown --accel
/// name or parameter (or "embree" in a build without Embree) or a spec listed twice.
std::optional<BenchOptions> parse_bench_options(int argc, const char* const* argv, std::ostream& help_out);

/// Refuses (vf::Error naming the estimate, see require_memory) a ray set whose rays and per-structure
/// results would not fit in the allocation budget. Call before generating the rays.
void check_ray_memory(std::size_t ray_count, std::size_t structure_count);

}  // namespace vf::bench
