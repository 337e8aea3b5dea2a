#include "dynamic_run.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <variant>

#include "agreement.hpp"
#include "bench_accel.hpp"
#include "bench_run.hpp"
#include "query_runner.hpp"
#include "report.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf::bench {

namespace {

// Where the object is in frame `frame`: its first transform moved along a small orbit (1% of the
// scene's radius) in the horizontal plane, a different place every frame.
Transform frame_transform(const Transform& start, int frame, float scene_radius) {
  Transform t = start;
  const float angle = 0.7f * static_cast<float>(frame + 1);
  t.translation = t.translation + Vec3f{std::cos(angle), 0.0f, std::sin(angle)} * (0.01f * scene_radius);
  return t;
}

// Moves object `id` to `t` in place when `accel` can update; false (untouched) when it cannot.
bool update_in_place(BenchAccel& accel, ObjectId id, const Transform& t) {
  auto* ours = std::get_if<AnyStructure>(&accel);
  return ours && vf::update_in_place(*ours, id, t);
}

// True when the last commit of a BeamField rebuilt it whole.
bool last_commit_rebuilt(const BenchAccel& accel) {
  const auto* ours = std::get_if<AnyStructure>(&accel);
  const auto* field = ours ? std::get_if<BeamField>(ours) : nullptr;
  return field && field->beam_stats().last_commit_rebuilt;
}

}  // namespace

std::uint32_t default_moving_object(const Scene& scene) {
  const double target = 0.05 * static_cast<double>(scene.instanced_triangle_count());
  const Instance* best = nullptr;
  double best_distance = 0.0;
  for (const Instance& instance : scene.instances()) {
    const double distance = std::fabs(static_cast<double>(scene.meshes[instance.mesh].triangles.size()) - target);
    if (!best || distance < best_distance || (distance == best_distance && instance.id < best->id)) {
      best = &instance;
      best_distance = distance;
    }
  }
  if (!best) throw Error("--dynamic: the scene has no objects to move");
  return best->id;
}

DynamicReport run_dynamic_bench(const BenchOptions& options) {
  const ThreadLimit thread_limit(options.threads);
  Scene scene = load_scene(options.scene);
  const ObjectId moved = options.move_object ? *options.move_object : default_moving_object(scene);
  if (!scene.find_instance(moved)) throw Error("--move-object: the scene has no object " + std::to_string(moved));
  const Transform start = scene.instance(moved).transform;
  const float radius = 0.5f * length(scene.bounds().extent());
  const Camera camera = bench_camera(scene, options);
  check_ray_memory(estimated_ray_count(options, camera), 2);
  const BuildContext context{estimated_ray_count(options, camera)};

  DynamicReport report;
  report.scene = scene.name.empty() ? options.scene : scene.name;
  report.triangles = scene.instanced_triangle_count();
  report.moved_object = moved;
  report.moved_triangles = scene.meshes[scene.instance(moved).mesh].triangles.size();
  report.frames = options.dynamic_frames;
  report.kind = options.kind;
  report.threads = thread_limit.threads();

  const TimingPlan once{0, 1};
  std::vector<Ray> rays;
  for (const std::string& spec : options.accels) {
    scene.set_transform(moved, start);
    std::vector<BuiltBenchAccel> built;
    {
      SceneGeometry geometry(scene);
      built.push_back(build_bench_accel(spec, geometry, context, thread_limit.threads()));
    }
    if (rays.empty()) rays = bench_ray_set(options, scene, camera, built);
    DynamicRow row;
    row.accel = built.front().resolved;
    std::vector<double> update_ms, trace_ms;
    QueryResults last;
    for (int frame = 0; frame < options.dynamic_frames; ++frame) {
      const Transform t = frame_transform(start, frame, radius);
      scene.set_transform(moved, t);
      const Stopwatch watch;
      row.incremental = update_in_place(built.front().accel, moved, t);
      if (!row.incremental) {
        SceneGeometry geometry(scene);
        built.front() = build_bench_accel(spec, geometry, context, thread_limit.threads());
      }
      update_ms.push_back(watch.elapsed_ms());
      if (last_commit_rebuilt(built.front().accel)) ++row.full_rebuilds;
      const BenchAccel* accel = &built.front().accel;
      QueryMeasurement m = std::move(measure_queries(std::span(&accel, 1), rays, options.kind, once).front());
      trace_ms.push_back(m.timings.median_ms());
      last = std::move(m.results);
    }
    // A fresh build over the last frame's scene: its time, and its answers as the reference.
    const Stopwatch watch;
    SceneGeometry geometry(scene);
    const BuiltBenchAccel fresh = build_bench_accel(spec, geometry, context, thread_limit.threads());
    row.rebuild_ms = watch.elapsed_ms();
    const BenchAccel* fresh_accel = &fresh.accel;
    const QueryMeasurement reference = std::move(measure_queries(std::span(&fresh_accel, 1), rays, options.kind, once).front());
    row.mismatches = count_mismatches(last, reference.results, options.kind);
    row.update_ms = median(update_ms);
    row.trace_ms = median(trace_ms);
    row.mrays_per_s = mrays_per_second(rays.size(), row.trace_ms);
    report.rows.push_back(std::move(row));
  }
  report.rays = rays.size();
  return report;
}

void print_dynamic_table(std::ostream& out, const DynamicReport& report) {
  out << "scene " << report.scene << " | " << with_separators(report.triangles) << " triangles | object "
      << report.moved_object << " moves (" << with_separators(report.moved_triangles) << " triangles, "
      << formatted("%.1f%%", 100.0 * static_cast<double>(report.moved_triangles) / std::max<double>(1.0, static_cast<double>(report.triangles)))
      << " of the scene) for " << report.frames << " frames | " << ray_kind_name(report.kind)
      << " rays: " << with_separators(report.rays) << " per frame | threads " << report.threads << "\n";
  std::size_t name_width = 5;
  for (const DynamicRow& row : report.rows) name_width = std::max(name_width, row.accel.size());
  out << padded_right("accel", name_width) << "  " << padded_left("update", 7) << "  " << padded_left("update ms", 10)
      << "  " << padded_left("rebuild ms", 10) << "  " << padded_left("update/rebuild", 14) << "  "
      << padded_left("trace ms", 9) << "  " << padded_left("Mrays/s", 8) << "  " << padded_left("full rebuilds", 13)
      << "  mismatches vs fresh build\n";
  for (const DynamicRow& row : report.rows) {
    const std::string ratio = row.rebuild_ms > 0.0 ? formatted("%.3f", row.update_ms / row.rebuild_ms) : "-";
    out << padded_right(row.accel, name_width) << "  " << padded_left(row.incremental ? "edit" : "build", 7) << "  "
        << padded_left(formatted("%.1f", row.update_ms), 10) << "  " << padded_left(formatted("%.1f", row.rebuild_ms), 10)
        << "  " << padded_left(ratio, 14) << "  " << padded_left(formatted("%.1f", row.trace_ms), 9) << "  "
        << padded_left(formatted("%.2f", row.mrays_per_s), 8) << "  "
        << padded_left(with_separators(row.full_rebuilds), 13) << "  "
        << padded_left(with_separators(row.mismatches), 26) << "\n";
  }
}

nlohmann::ordered_json dynamic_report_json(const DynamicReport& report) {
  nlohmann::ordered_json doc;
  doc["scene"] = report.scene;
  doc["triangles"] = report.triangles;
  doc["moved_object"] = report.moved_object;
  doc["moved_triangles"] = report.moved_triangles;
  doc["frames"] = report.frames;
  doc["kind"] = std::string(ray_kind_name(report.kind));
  doc["rays"] = report.rays;
  doc["threads"] = report.threads;
  nlohmann::ordered_json& results = doc["results"] = nlohmann::ordered_json::array();
  for (const DynamicRow& row : report.rows) {
    results.push_back({{"accel", row.accel},
                       {"incremental", row.incremental},
                       {"update_ms", row.update_ms},
                       {"rebuild_ms", row.rebuild_ms},
                       {"trace_ms", row.trace_ms},
                       {"mrays_per_s", row.mrays_per_s},
                       {"full_rebuilds", row.full_rebuilds},
                       {"mismatches", row.mismatches}});
  }
  return doc;
}

}  // namespace vf::bench
