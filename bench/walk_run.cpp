#include "walk_run.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "bench_accel.hpp"
#include "bench_run.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/text.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/render/walkthrough.hpp"

namespace vf::bench {
namespace {

// The bench's structures (ours or Embree) for a walkthrough: updated in place where ours can, else
// rebuilt over the moved scene.
class BenchWalkStructures final : public WalkStructures {
 public:
  BenchWalkStructures(const Scene& scene, std::string spec, const BuildContext& context, int threads)
      : spec_(std::move(spec)), context_(context), threads_(threads) {
    build(scene);
  }
  bool follow(const Scene& scene, std::span<const ObjectId> moved) override {
    if (auto* ours = std::get_if<AnyStructure>(&built_->accel)) {
      bool in_place = true;
      for (const ObjectId id : moved) in_place = in_place && update_in_place(*ours, id, scene.instance(id).transform);
      if (in_place) return false;
    }
    build(scene);
    return true;
  }
  const SceneQueries& queries() const override { return *queries_; }
  std::string label() const override { return built_->resolved; }

 private:
  void build(const Scene& scene) {
    SceneGeometry geometry(scene);
    built_ = std::make_unique<BuiltBenchAccel>(build_bench_accel(spec_, geometry, context_, threads_));
    queries_ = std::visit(
        [](const auto& structure) -> std::unique_ptr<SceneQueries> {
          using S = std::decay_t<decltype(structure)>;
          if constexpr (std::is_same_v<S, AnyStructure>) return scene_queries(structure, structure);
          else return std::make_unique<QueriesOver<S, S>>(structure, structure);
        },
        built_->accel);
  }
  std::string spec_;
  BuildContext context_;
  int threads_;
  std::unique_ptr<BuiltBenchAccel> built_;
  std::unique_ptr<SceneQueries> queries_;
};

std::string fixed(double v, const char* pattern = "%.2f") { return formatted(pattern, v); }

}  // namespace

void run_walk_bench(const BenchOptions& options, std::ostream& out) {
  const ThreadLimit limit(options.threads);
  if (!options.walk_plot.empty()) check_walk_plot_path(options.walk_plot);
  if (!options.walk_csv_dir.empty() && !std::filesystem::is_directory(options.walk_csv_dir))
    throw Error(options.walk_csv_dir + ": --walk-csv must be an existing folder");
  const Scene original = load_scene(options.scene);
  const Camera camera = bench_camera(original, options);
  WalkOptions walk;
  walk.frames = options.walk_frames;
  walk.integrator = *parse_integrator(options.integrator);
  walk.shading.progress = false;
  walk.shading.seed = options.seed;
  walk.ao.progress = false;
  walk.ao.ao_rays = options.ao_rays;
  walk.ao.seed = options.seed;
  walk.width = camera.width;
  walk.height = camera.height;
  std::vector<WalkSeries> series;
  for (const std::string& spec : options.accels) {
    Scene scene = original;
    BenchWalkStructures structures(scene, spec, BuildContext{static_cast<std::uint64_t>(camera.width) * camera.height * 8u * options.walk_frames},
                                   limit.threads());
    series.push_back(WalkSeries{structures.label(), render_walkthrough(scene, structures, walk)});
    if (!options.walk_csv_dir.empty()) {
      std::string name = structures.label();
      std::replace_if(name.begin(), name.end(), [](char c) { return c == ':' || c == ',' || c == '=' || c == '/'; }, '_');
      write_walk_csv(std::filesystem::path(options.walk_csv_dir) / (name + ".csv"), series.back());
    }
  }
  std::optional<double> embree_ms;
  for (const WalkSeries& s : series) {
    std::vector<double> trace;
    for (const WalkFrame& f : s.frames) trace.push_back(f.trace_ms);
    if (s.label.starts_with("embree")) embree_ms = median(trace);
  }
  out << "walk " << options.scene << " | " << options.walk_frames << " frames of " << camera.width << "x" << camera.height << " | "
      << options.integrator << " | threads " << limit.threads() << "\n\n"
      << "| structure | median update ms | median render ms | mean frame ms | Mrays/s | render time / Embree's |\n"
      << "|---|---:|---:|---:|---:|---:|\n";
  for (const WalkSeries& s : series) {
    std::vector<double> update, trace;
    double total_ms = 0.0, trace_ms = 0.0;
    std::uint64_t rays = 0;
    for (const WalkFrame& f : s.frames) {
      update.push_back(f.update_ms);
      trace.push_back(f.trace_ms);
      total_ms += f.update_ms + f.trace_ms;
      trace_ms += f.trace_ms;
      rays += f.rays;
    }
    out << "| " << s.label << " | " << fixed(median(update)) << " | " << fixed(median(trace)) << " | "
        << fixed(total_ms / static_cast<double>(s.frames.size())) << " | " << fixed(static_cast<double>(rays) / trace_ms * 1e-3) << " | "
        << (embree_ms ? fixed(median(trace) / *embree_ms, "%.2fx") : std::string("-")) << " |\n";
  }
  if (!options.walk_plot.empty()) write_walk_plot(options.walk_plot, series);
}

}  // namespace vf::bench
