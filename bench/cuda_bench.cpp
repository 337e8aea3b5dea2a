#include "cuda_bench.hpp"

#include <bit>
#include <functional>
#include <cstdio>
#include <optional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_accel.hpp"
#include "bench_run.hpp"
#include "query_runner.hpp"
#include "cuda_common.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/cuda/batch.hpp"
#include "visfield/cuda/device.hpp"
#include "visfield/cuda/field_textures.hpp"
#include "visfield/cuda/kernels.hpp"
#include "visfield/cuda/render_ao.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/gpu/packed_scene.hpp"
#include "visfield/gpu/roofline.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf::bench {
namespace {

/// One line of the table: a query on the GPU beside the CPU on the same rays.
struct GpuRow {
  std::string query;
  std::size_t rays = 0;
  double gpu_ms = 0.0, cpu_ms = 0.0;
  std::size_t disagreements = 0;  ///< Rays (batch) or points (AO counts) whose answers differ in any bit.
  std::string agreement_unit;     ///< "rays" or "points".
};

/// The exact structure the CPU answers are compared with: the first exact --accel structure's results.
std::size_t first_exact(const std::vector<BuiltBenchAccel>& built) {
  for (std::size_t i = 0; i < built.size(); ++i)
    if (bench_accel_is_exact(built[i].accel)) return i;
  return 0;
}

/// Bits of two answer arrays that differ, counted per ray.
std::size_t differing(const QueryResults& cpu, const std::vector<Hit>& hits, const std::vector<std::uint8_t>& occluded) {
  std::size_t d = 0;
  const auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x); };
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const Hit& a = cpu.hits[i];
    const Hit& b = hits[i];
    d += !(a.found == b.found && bits(a.t) == bits(b.t) && bits(a.u) == bits(b.u) && bits(a.v) == bits(b.v) && a.prim == b.prim &&
           a.instance == b.instance && a.has_normal == b.has_normal && bits(a.normal.x) == bits(b.normal.x) &&
           bits(a.normal.y) == bits(b.normal.y) && bits(a.normal.z) == bits(b.normal.z));
  }
  for (std::size_t i = 0; i < occluded.size(); ++i) d += cpu.occluded[i] != occluded[i];
  return d;
}

/// The median device time of the kernels `job` launches (CUDA events around each launch), by `plan`.
double gpu_median_ms(const TimingPlan& plan, const std::function<void()>& job) {
  return time_runs_measured(plan, [&] { return cuda::kernel_ms(job); }).median_ms();
}

/// The batch API on `device` for the ray set already on the device: timed by `plan`, answers fetched once.
template <class D>
GpuRow batch_row(const std::string& name, const D& device, const cuda::DeviceArray<Ray>& rays, bool closest, const TimingPlan& plan,
                 const QueryMeasurement& cpu) {
  GpuRow row;
  row.query = name + (closest ? ", closest hit (batch)" : ", occlusion (batch)");
  row.rays = rays.size();
  std::vector<Hit> hits;
  std::vector<std::uint8_t> occluded;
  if (closest) {
    cuda::DeviceArray<Hit> out(rays.size());
    row.gpu_ms = gpu_median_ms(plan, [&] { cuda::intersect(device, rays.data(), rays.size(), out.data()); });
    hits = out.to_host();
  } else {
    cuda::DeviceArray<std::uint8_t> out(rays.size());
    row.gpu_ms = gpu_median_ms(plan, [&] { cuda::occluded(device, rays.data(), rays.size(), out.data()); });
    occluded = out.to_host();
  }
  row.cpu_ms = cpu.timings.median_ms();
  row.disagreements = differing(cpu.results, hits, occluded);
  row.agreement_unit = "rays";
  return row;
}

/// CPU counts of the kernels' AO rays (generated on the host by the same header), timed by `plan`
/// (the tracing only: generation is done before).
template <class S>
std::vector<std::uint32_t> cpu_ao(const S& structure, const std::vector<gpu::SurfaceFrame>& points, const cuda::AoParams& p,
                                  const TimingPlan& plan, double& ms) {
  const std::vector<Ray> rays = kernel_ao_rays(points, p);
  std::vector<std::uint8_t> occluded(rays.size());
  ms = time_runs(plan, [&] { occluded_batch(structure, std::span<const Ray>(rays), std::span<std::uint8_t>(occluded)); }).median_ms();
  return open_counts(occluded, static_cast<std::size_t>(p.rays_per_point));
}

std::size_t count_differences(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  std::size_t d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d += a[i] != b[i];
  return d;
}

void print_rows(std::ostream& out, const std::vector<GpuRow>& rows) {
  out << "| query | rays | GPU G rays/s | CPU G rays/s | GPU / CPU | GPU vs CPU |\n|---|---:|---:|---:|---:|---|\n";
  for (const GpuRow& r : rows) {
    const double g = grays(r.rays, r.gpu_ms), c = grays(r.rays, r.cpu_ms);
    out << "| " << r.query << " | " << r.rays << " | " << formatted("%.3f", g) << " | " << formatted("%.4f", c) << " | "
        << (c > 0.0 ? formatted("%.1fx", g / c) : std::string("-")) << " | "
        << (r.disagreements == 0 ? "bit-identical" : std::to_string(r.disagreements) + " " + r.agreement_unit + " differ") << " |\n";
  }
}

}  // namespace

void run_cuda_bench(const BenchOptions& options, std::ostream& out) {
  cuda::require_device();
  const cuda::DeviceInfo device = cuda::device_info();
  const ThreadLimit thread_limit(options.threads);
  const Scene scene = load_scene(options.scene);
  SceneGeometry geometry(scene);
  const Camera camera = bench_camera(scene, options);
  check_ray_memory(estimated_ray_count(options, camera), options.accels.size() + 1);
  const BuildContext context{estimated_ray_count(options, camera)};
  std::vector<BuiltBenchAccel> built;
  for (const std::string& spec : options.accels) built.push_back(build_bench_accel(spec, geometry, context, thread_limit.threads()));
  const std::vector<Ray> rays = bench_ray_set(options, scene, camera, built);
  const bool closest = options.kind == RayKind::primary || options.kind == RayKind::random;
  const TimingPlan plan{options.warmup, options.reps};

  // The CPU's answers and times on the ray set, every structure.
  std::vector<const BenchAccel*> accels;
  for (const BuiltBenchAccel& b : built) accels.push_back(&b.accel);
  const std::vector<QueryMeasurement> cpu = measure_queries(accels, rays, options.kind, plan);
  const std::size_t reference = first_exact(built);

  // The same rays on the GPU: the GPU BVH against the first exact structure, each field spec's packed
  // fields against that structure on the CPU.
  const auto d_rays = cuda::DeviceArray<Ray>::from(std::span<const Ray>(rays));
  const gpu::GpuBvh layout = gpu::GpuBvh::build(geometry.flattened());
  const cuda::DeviceBvh d_bvh = cuda::DeviceBvh::upload(layout);
  std::vector<GpuRow> rows;
  rows.push_back(batch_row("exact: GPU BVH vs " + built[reference].resolved, d_bvh, d_rays, closest, plan, cpu[reference]));
  const field::FieldScene* fields = nullptr;
  std::optional<gpu::PackedFieldScene> packed;
  cuda::DeviceFieldScene d_fields;
  // Where the fields share a form the kernels are compiled for it; the same queries through the
  // kernels that read every choice at run time measure what that gains.
  std::optional<cuda::DeviceFieldScene> d_generic;
  const std::string generic_name = ", generic kernel";
  std::vector<std::size_t> other_fields;  // the further field specs (such as field:cull=each): a batch row and an AO row each
  for (std::size_t i = 0; i < built.size(); ++i) {
    const AnyStructure* ours = std::get_if<AnyStructure>(&built[i].accel);
    const field::FieldScene* f = ours ? std::get_if<field::FieldScene>(ours) : nullptr;
    if (!f) continue;
    if (fields) {
      other_fields.push_back(i);
    } else {
      fields = f;
      packed.emplace(gpu::PackedFieldScene::pack(scene, *f));
      d_fields = cuda::DeviceFieldScene::upload(*packed);
      rows.push_back(batch_row(built[i].resolved, d_fields, d_rays, closest, plan, cpu[i]));
      if (packed->form() != gpu::FieldForm::any) {
        d_generic.emplace(cuda::DeviceFieldScene::upload(*packed, cuda::FieldKernels::generic));
        rows.push_back(batch_row(built[i].resolved + generic_name, *d_generic, d_rays, closest, plan, cpu[i]));
      }
    }
  }

  // AO rays generated on the device from the camera's hits (the first exact CPU structure's: ours),
  // --ao-rays a hit, through the fields and the exact GPU BVH, beside the CPU on the same rays.
  const Bvh camera_bvh = Bvh::build(geometry.flattened());
  const QueriesOver<Bvh, Bvh> camera_queries(camera_bvh, camera_bvh);
  std::vector<std::int64_t> slots;
  const std::vector<gpu::SurfaceFrame> points = cuda::camera_surface_frames(camera_queries, scene, camera, 1, options.seed, slots);
  const cuda::AoParams params{options.ao_rays, options.seed, options.max_distance};
  const std::size_t ao_rays = points.size() * static_cast<std::size_t>(options.ao_rays);
  const auto d_points = cuda::DeviceArray<gpu::SurfaceFrame>::from(std::span<const gpu::SurfaceFrame>(points));
  cuda::DeviceArray<std::uint32_t> d_open(points.size());
  const auto ao_row = [&](const std::string& name, auto&& run_gpu, const auto& cpu_structure) {
    GpuRow row;
    row.query = name;
    row.rays = ao_rays;
    row.gpu_ms = gpu_median_ms(plan, run_gpu);
    const std::vector<std::uint32_t> gpu_open = d_open.to_host();
    row.disagreements = count_differences(gpu_open, cpu_ao(cpu_structure, points, params, plan, row.cpu_ms));
    row.agreement_unit = "points";
    return row;
  };
  const std::string per_point = std::to_string(options.ao_rays) + " AO rays a hit, generated on the device";
  std::size_t field_ao_row = 0;
  if (fields) {
    field_ao_row = rows.size();
    rows.push_back(ao_row("fields: " + per_point,
                          [&] { cuda::ambient_occlusion(d_fields, d_points.data(), points.size(), params, d_open.data()); }, *fields));
    if (d_generic) {
      // Against the fitted kernel's counts (which the CPU's matched, or the row above says not).
      const std::vector<std::uint32_t> fitted_open = d_open.to_host();
      GpuRow row = rows.back();
      row.query = "fields" + generic_name + ": " + per_point;
      row.gpu_ms = gpu_median_ms(plan, [&] { cuda::ambient_occlusion(*d_generic, d_points.data(), points.size(), params, d_open.data()); });
      row.disagreements += count_differences(d_open.to_host(), fitted_open);
      rows.push_back(row);
    }
    try {
      const cuda::FieldTextures textures = cuda::FieldTextures::create(*packed);
      rows.push_back(ao_row("fields in 3D textures: " + per_point,
                            [&] { cuda::ambient_occlusion(d_fields, textures, d_points.data(), points.size(), params, d_open.data()); },
                            *fields));
    } catch (const Error& e) {
      out << "(no texture variant: " << e.what() << ")\n";
    }
  }
  for (const std::size_t i : other_fields) {
    const auto& f = std::get<field::FieldScene>(std::get<AnyStructure>(built[i].accel));
    const gpu::PackedFieldScene other = gpu::PackedFieldScene::pack(scene, f);
    const cuda::DeviceFieldScene d_other = cuda::DeviceFieldScene::upload(other);
    rows.push_back(batch_row(built[i].resolved, d_other, d_rays, closest, plan, cpu[i]));
    rows.push_back(ao_row(built[i].resolved + ": " + per_point,
                          [&] { cuda::ambient_occlusion(d_other, d_points.data(), points.size(), params, d_open.data()); }, f));
  }
  rows.push_back(ao_row("exact GPU BVH: " + per_point,
                        [&] { cuda::ambient_occlusion(d_bvh, d_points.data(), points.size(), params, d_open.data()); }, camera_bvh));

  // The roofline of the field lookups on this device.
  std::string roofline;
  if (fields) {
    const gpu::LookupCost cost = gpu::field_lookup_cost(packed->slots().front().tables, true, options.ao_rays, false);
    const gpu::Roofline bound = gpu::roofline(cost, device.peaks, static_cast<double>(packed->buffer().size()));
    const double measured = grays(ao_rays, rows[field_ao_row].gpu_ms) * 1e9;
    roofline = gpu::describe(cost, bound) + formatted("; measured %.1f G lookups/s, ", measured * 1e-9) +
               formatted("%.0f%% of the bound", 100.0 * measured / bound.bound_rays_per_s);
  }

  if (options.json) {
    nlohmann::json j;
    j["device"] = device.name;
    j["scene"] = options.scene;
    j["threads"] = thread_limit.threads();
    j["roofline"] = roofline;
    for (const GpuRow& r : rows)
      j["rows"].push_back({{"query", r.query}, {"rays", r.rays}, {"gpu_grays_per_s", grays(r.rays, r.gpu_ms)},
                           {"cpu_grays_per_s", grays(r.rays, r.cpu_ms)}, {"gpu_ms", r.gpu_ms}, {"cpu_ms", r.cpu_ms},
                           {"disagreements", r.disagreements}, {"unit", r.agreement_unit}});
    out << j.dump(2) << "\n";
    return;
  }
  out << "## " << (scene.name.empty() ? options.scene : scene.name) << " (" << scene.instanced_triangle_count() << " triangles): GPU "
      << device.name << " (" << device.sm_count << " SMs) beside the CPU (" << thread_limit.threads() << " threads), the same rays, "
      << "median of " << options.reps << " runs; GPU times are the kernels' own (CUDA events around each launch; rays and points "
      << "already on the device)\n\n";
  print_rows(out, rows);
  if (!roofline.empty()) out << "\nRoofline of a field lookup (" << device.name << "): " << roofline << "\n";
}

}  // namespace vf::bench
