#include "bench_run.hpp"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "agreement.hpp"
#include "bench_accel.hpp"
#include "visfield/render/ray_sets.hpp"
#include "query_runner.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/isa.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/io/scene_file.hpp"

#if VISFIELD_HAVE_EMBREE
#include "embree_scene.hpp"
#endif

namespace vf::bench {

namespace {


bool is_embree(const BuiltBenchAccel& a) { return a.resolved.starts_with(kEmbreeName); }

// AO and shadow rays start from the hits of one of our exact structures when one is listed (they
// are watertight and agree with brute force), otherwise from Embree's. The options guarantee an
// exact structure: approximate hits have no triangle to spawn from.
const BuiltBenchAccel& ray_source(const std::vector<BuiltBenchAccel>& built) {
  const auto exact = [](const BuiltBenchAccel& a) { return bench_accel_is_exact(a.accel); };
  const auto ours = std::find_if(built.begin(), built.end(), [&](const BuiltBenchAccel& a) { return exact(a) && !is_embree(a); });
  return ours != built.end() ? *ours : *std::find_if(built.begin(), built.end(), exact);
}

}  // namespace

Camera bench_camera(const Scene& scene, const BenchOptions& options) {
  Camera camera = scene.camera_or_default(0, 0);
  if (options.width > 0) camera.width = options.width;
  if (options.height > 0) camera.height = options.height;
  return camera;
}

std::size_t estimated_ray_count(const BenchOptions& options, const Camera& camera) {
  if (options.count) return *options.count;
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
  if (options.kind != RayKind::ao) return pixels;
  return pixels * (options.psf_level > 0 ? DirectionLines::count(options.psf_level) : static_cast<std::size_t>(options.ao_rays));
}

std::vector<Ray> bench_ray_set(const BenchOptions& options, const Scene& scene, const Camera& camera,
                               const std::vector<BuiltBenchAccel>& built) {
  RaySetRequest request;
  request.kind = options.kind;
  request.camera = camera;
  request.ao_rays = options.ao_rays;
  request.psf_level = options.psf_level;
  request.max_distance = options.max_distance;
  request.count = options.count;
  request.seed = options.seed;
  std::vector<Ray> rays =
      visit_accel(ray_source(built).accel, [&](const auto& structure) { return make_ray_set(structure, scene, request); });
  if (!options.line_major) return rays;
  // Grouped by line (a counting sort on the stored direction's line), pixel order within each.
  const DirectionLines lines(options.psf_level);
  std::vector<std::uint32_t> line_of(rays.size());
  std::vector<std::size_t> start(lines.size() + 1, 0);
  for (std::size_t i = 0; i < rays.size(); ++i) ++start[(line_of[i] = lines.nearest(rays[i].dir).line) + 1];
  for (std::size_t k = 0; k < lines.size(); ++k) start[k + 1] += start[k];
  std::vector<Ray> by_line(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) by_line[start[line_of[i]]++] = rays[i];
  return by_line;
}

BenchReport run_bench(const BenchOptions& options) {
  const ThreadLimit thread_limit(options.threads);
  const Scene scene = load_scene(options.scene);
  SceneGeometry geometry(scene);
  const Camera camera = bench_camera(scene, options);
  check_ray_memory(estimated_ray_count(options, camera), options.accels.size());

  // `auto` decides for this bench's ray count unless its rays= says otherwise; the decision's own cost
  // (grid build + sample rays) is not part of the row's build time.
  const BuildContext context{estimated_ray_count(options, camera)};
  std::vector<BuiltBenchAccel> built;
  std::vector<std::size_t> row_spec;  // the --accel entry each row comes from
  for (std::size_t s = 0; s < options.accels.size(); ++s)
    for (BuiltBenchAccel& row : build_bench_rows(options.accels[s], geometry, context, thread_limit.threads())) {
      built.push_back(std::move(row));
      row_spec.push_back(s);
    }

  // In huge-page storage, for every structure alike: a million rays span 8,000 small pages, and the
  // field kernel, streaming them fastest, waited on the TLB (under perf, 12% of its samples on the
  // rays' load; without, bunny AO through the field 140-144 -> 145-149 Mrays/s).
  const AlignedVector<Ray> ray_storage = [&] {
    const std::vector<Ray> generated = bench_ray_set(options, scene, camera, built);
    return AlignedVector<Ray>(generated.begin(), generated.end());
  }();
  const std::span<const Ray> rays(ray_storage.data(), ray_storage.size());

  const TimingPlan plan{options.warmup, options.reps};
  std::vector<const BenchAccel*> accels;
  std::vector<bool> one_ray;
  for (const BuiltBenchAccel& entry : built) accels.push_back(&entry.accel), one_ray.push_back(entry.one_ray);
  const std::vector<QueryMeasurement> measurements = measure_queries(accels, rays, options.kind, plan, one_ray);

  // Of the rows `embree:call=best` tried, the fastest stands for it.
  std::vector<bool> shown(built.size(), true);
  for (std::size_t i = 0; i < built.size(); ++i) {
    if (!built[i].best_of_spec) continue;
    for (std::size_t j = 0; j < built.size(); ++j)
      if (j != i && row_spec[j] == row_spec[i] && measurements[j].timings.median_ms() < measurements[i].timings.median_ms()) shown[i] = false;
  }
  // Ratios are to the first Embree row shown; its answers (any Embree row's) are the reference.
  std::size_t first_embree = built.size();
  for (std::size_t i = 0; i < built.size() && first_embree == built.size(); ++i)
    if (shown[i] && is_embree(built[i])) first_embree = i;
  const auto embree = first_embree < built.size() ? built.begin() + static_cast<std::ptrdiff_t>(first_embree) : built.end();
  // The reference answers are exact ones: Embree's, else the first exact structure's.
  const auto first_exact =
      std::find_if(built.begin(), built.end(), [](const BuiltBenchAccel& b) { return bench_accel_is_exact(b.accel); });
  const std::size_t reference = static_cast<std::size_t>((embree != built.end() ? embree : first_exact) - built.begin());
  const double embree_mrays =
      embree != built.end() ? mrays_per_second(rays.size(), measurements[reference].timings.median_ms()) : 0.0;

  BenchReport report;
  report.scene = scene.name.empty() ? options.scene : scene.name;
  report.triangles = scene.instanced_triangle_count();
  report.kind = options.kind;
  report.rays = rays.size();
  report.threads = thread_limit.threads();
  report.isa = isa_name(active_isa());
  report.width = camera.width;
  report.height = camera.height;
  report.reps = options.reps;
  report.warmup = options.warmup;
  report.ao_rays = options.psf_level > 0 ? static_cast<int>(DirectionLines::count(options.psf_level)) : options.ao_rays;
  report.max_distance = options.max_distance;
  report.reference = built[reference].resolved;
#if VISFIELD_HAVE_EMBREE
  if (embree != built.end()) report.embree = embree_description();
#endif
  for (std::size_t i = 0; i < built.size(); ++i) {
    if (!shown[i]) continue;
    const AccelStats stats = bench_accel_stats(built[i].accel);
    ResultRow row;
    row.accel = built[i].best_of_spec ? options.accels[row_spec[i]] + " -> " + built[i].resolved.substr(built[i].resolved.find(':') + 1)
                                      : built[i].resolved;
    row.embree = is_embree(built[i]);
    row.build_ms = stats.build_ms;
    row.bytes = stats.memory_bytes;
    row.median_ms = measurements[i].timings.median_ms();
    row.mrays_per_s = mrays_per_second(rays.size(), row.median_ms);
    if (embree != built.end() && embree_mrays > 0.0) row.ratio_to_embree = row.mrays_per_s / embree_mrays;
    if (bench_accel_is_exact(built[i].accel))
      row.mismatches = count_mismatches(measurements[i].results, measurements[reference].results, options.kind);
    else
      row.approximate = measure_agreement(measurements[i].results, measurements[reference].results, options.kind, rays);
    if (const auto counters = count_beam_work(built[i].accel, rays, options.kind); counters && counters->rays > 0) {
      const double per_ray = 1.0 / static_cast<double>(counters->rays);
      row.beam_work = BeamWork{counters->single_tile * per_ray, counters->tiles * per_ray, counters->leaves * per_ray,
                               counters->triangle_tests * per_ray};
    }
    if (const auto counters = count_bvh_work(built[i].accel, rays, options.kind); counters && counters->rays > 0) {
      const double per_ray = 1.0 / static_cast<double>(counters->rays);
      row.bvh_work = BvhWork{counters->nodes * per_ray, counters->leaves * per_ray, counters->blocks * per_ray,
                             counters->triangle_tests * per_ray};
    }
    report.rows.push_back(std::move(row));
  }
  // Embree at its best: the fastest of its rows, and every row against it.
  const ResultRow* best = nullptr;
  for (const ResultRow& row : report.rows)
    if (row.embree && (!best || row.mrays_per_s > best->mrays_per_s)) best = &row;
  if (best && best->mrays_per_s > 0.0) {
    report.embree_best = best->accel;
    const double best_mrays = best->mrays_per_s;
    for (ResultRow& row : report.rows) row.ratio_to_embree_best = row.mrays_per_s / best_mrays;
  }
  return report;
}

void print_report(std::ostream& out, const BenchReport& report, bool json) {
  if (json) {
    out << report_json(report).dump(2) << "\n";
  } else {
    print_table(out, report);
  }
}

}  // namespace vf::bench
