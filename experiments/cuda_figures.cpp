#include "cuda_figures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "cuda_common.hpp"
#include "timing.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/text.hpp"
#include "visfield/cuda/device.hpp"
#include "visfield/cuda/kernels.hpp"
#include "visfield/cuda/render_ao.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/gpu/packed_scene.hpp"
#include "visfield/io/mesh_loader.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/render/ray_sets.hpp"

namespace vf::experiments {
namespace {

using namespace vf::bench;  // the benchmark's building blocks: structures by spec, ray sets, timing

const TimingPlan kPlan{2, 9};

/// A caster's mesh (a field) and an exact ground square of half-width `half` radii under its lowest
/// point: the GPU paper's Figures 3 and 7 setting. `scale` sizes the caster to a sphere of that
/// radius at the origin standing on y = 0 (0: the mesh as it is).
Scene caster_on_ground(const std::string& path, float half, float scale_to_radius) {
  Scene scene;
  TriangleMesh caster = load_mesh(path).mesh;
  const TriangleSet set = mesh_triangles(caster);
  if (set.size() == 0) throw Error(path + ": no triangles of non-zero area");
  const field::BoundingSphere sphere = field::bounding_sphere_of(set);
  caster.occluder = MeshOccluder::field;
  caster.material_ids.clear();
  scene.meshes.push_back(std::move(caster));
  Instance object;
  object.mesh = 0;
  float radius = sphere.radius, floor = set.bounds.lo.y;
  Vec3f centre = sphere.centre;
  if (scale_to_radius > 0.0f) {
    object.transform.scale = scale_to_radius / sphere.radius;
    const Vec3f c = sphere.centre * object.transform.scale;
    object.transform.translation = Vec3f{-c.x, -set.bounds.lo.y * object.transform.scale, -c.z};
    radius = scale_to_radius;
    floor = 0.0f;
    centre = Vec3f{0.0f, 0.0f, 0.0f};
  }
  scene.add_instance(object);
  TriangleMesh ground;
  ground.name = "ground";
  ground.occluder = MeshOccluder::exact;
  const float h = half * radius;
  ground.positions = {{centre.x - h, floor, centre.z - h}, {centre.x + h, floor, centre.z - h}, {centre.x + h, floor, centre.z + h},
                      {centre.x - h, floor, centre.z + h}};
  ground.triangles = {{0, 2, 1}, {0, 3, 2}};
  scene.meshes.push_back(std::move(ground));
  scene.add_instance(1);
  return scene;
}

/// The camera's primary hits (exact CPU BVH) and, for the pixels whose hit passes `keep`, their
/// surface frames; pixel_point[p] is the frame index or -1.
struct GBuffer {
  std::vector<Hit> hits;
  std::vector<gpu::SurfaceFrame> frames;
  std::vector<std::int64_t> pixel_point;
};
template <class Keep>
GBuffer g_buffer(const Scene& scene, const Camera& camera, const Bvh& bvh, Keep&& keep) {
  GBuffer g;
  const std::vector<Ray> primary = make_primary_rays(scene, camera);
  g.hits.resize(primary.size());
  intersect_batch(bvh, std::span<const Ray>(primary), std::span<Hit>(g.hits));
  const SurfaceSpawner spawner(scene);
  g.pixel_point.assign(primary.size(), -1);
  for (std::size_t p = 0; p < primary.size(); ++p) {
    if (!g.hits[p] || !keep(g.hits[p])) continue;
    g.pixel_point[p] = static_cast<std::int64_t>(g.frames.size());
    g.frames.push_back(cuda::surface_frame(spawner.surface_point(primary[p], g.hits[p])));
  }
  return g;
}

/// `scene`'s fields at `positions` x `directions`^2 (meshes marked field): the CPU's, and the same
/// packed and on the device.
struct DeviceFields {
  field::FieldScene cpu;
  gpu::PackedFieldScene packed;
  cuda::DeviceFieldScene device;
};
DeviceFields device_fields(const Scene& scene, int positions, int directions) {
  field::ObjectFieldConfig config;
  config.positions = positions;
  config.directions = directions;
  field::FieldScene fields = field::FieldScene::build(scene, config, {}, "", field::FieldMeshes::marked);
  gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(scene, fields);
  cuda::DeviceFieldScene device = cuda::DeviceFieldScene::upload(packed);
  return {std::move(fields), std::move(packed), std::move(device)};
}

/// AO counts of `frames` (device) through `occluder`, with the kernel's median time.
template <class D>
std::vector<std::uint32_t> timed_ao(const D& occluder, const cuda::DeviceArray<gpu::SurfaceFrame>& frames, const cuda::AoParams& p,
                                    double& ms) {
  cuda::DeviceArray<std::uint32_t> open(frames.size());
  ms = time_runs_measured(kPlan, [&] {
         return cuda::kernel_ms([&] { cuda::ambient_occlusion(occluder, frames.data(), frames.size(), p, open.data()); });
       }).median_ms();
  return open.to_host();
}

/// The CPU's counts for the kernels' `rays` through `structure`: unoccluded rays per run of `per_group`.
template <class S>
std::vector<std::uint32_t> cpu_counts(const S& structure, const std::vector<Ray>& rays, std::size_t per_group) {
  std::vector<std::uint8_t> occluded(rays.size());
  occluded_batch(structure, std::span<const Ray>(rays), std::span<std::uint8_t>(occluded));
  return open_counts(occluded, per_group);
}

/// |a - b| / b in percent (0 when both are 0).
double percent_apart(double a, double b) { return b != 0.0 ? 100.0 * std::abs(a - b) / b : a == b ? 0.0 : 100.0; }

// The GPU paper's Figure 3 on the GPU: the ground's AO under the caster, 256 rays per ground pixel of
// a 256x256 view (the caster flat grey, the background white), fields at {1090, 4226, 16642} x
// {32^2, 64^2, 128^2} against the exact GPU BVH on the same rays; beside each, the CPU's RMS: its
// fields against its exact BVH on the kernels' rays made on the host.
void figure3(const std::string& caster, std::ostream& out) {
  const Scene scene = caster_on_ground(caster, 3.0f, 0.0f);
  const Camera camera = scene.camera_or_default(256, 256);
  const TriangleSet set = flatten(scene);
  const Bvh bvh = Bvh::build(set);
  const ObjectId ground = scene.instances().back().id;
  const GBuffer g = g_buffer(scene, camera, bvh, [&](const Hit& h) { return h.instance == ground; });
  const auto frames = cuda::DeviceArray<gpu::SurfaceFrame>::from(std::span<const gpu::SurfaceFrame>(g.frames));
  const cuda::AoParams p{256, 1, std::numeric_limits<float>::infinity()};
  const auto image = [&](const std::vector<std::uint32_t>& open) {
    std::vector<double> pixels(g.hits.size());
    for (std::size_t i = 0; i < pixels.size(); ++i)
      pixels[i] = !g.hits[i] ? 255.0 : g.pixel_point[i] < 0 ? 128.0 : 255.0 * open[static_cast<std::size_t>(g.pixel_point[i])] / 256.0;
    return pixels;
  };
  const cuda::DeviceBvh exact = cuda::DeviceBvh::upload(gpu::GpuBvh::build(set));
  double exact_ms = 0.0;
  const std::vector<double> reference = image(timed_ao(exact, frames, p, exact_ms));
  const std::vector<Ray> cpu_rays = kernel_ao_rays(g.frames, p);
  const std::vector<double> cpu_reference = image(cpu_counts(bvh, cpu_rays, 256));
  double worst_percent = 0.0;
  const std::size_t rays = g.frames.size() * 256;
  out << rays << " AO rays (256 per ground pixel of a 256x256 view). Exact GPU BVH: " << formatted("%.3f ms (%.2f G rays/s)", exact_ms, grays(rays, exact_ms))
      << ".\n\nEach cell: AO kernel ms / RMS (0-255, all pixels) against the exact GPU image (the CPU's against its exact image, "
         "on the same rays) / field memory; the GPU paper's (its 2010 GPU) below.\n\n| positions | 32x32 | 64x64 | 128x128 |\n|---|---|---|---|\n";
  const char* const paper[3][3] = {{"81.2 ms / 0.596", "82.7 ms / 0.589", "82.9 ms / 0.586"},
                                   {"83.2 ms / 0.454", "83.3 ms / 0.424", "-"},
                                   {"84.2 ms / 0.421", "-", "-"}};
  const int positions[] = {1090, 4226, 16642};
  for (int k = 0; k < 3; ++k) {
    out << "| " << positions[k];
    for (const int n : {32, 64, 128}) {
      const DeviceFields f = device_fields(scene, positions[k], n);
      double ms = 0.0;
      const std::vector<double> field = image(timed_ao(f.device, frames, p, ms));
      const double gpu_rms = rms_difference(field, reference), cpu_rms = rms_difference(image(cpu_counts(f.cpu, cpu_rays, 256)), cpu_reference);
      worst_percent = std::max(worst_percent, percent_apart(gpu_rms, cpu_rms));
      out << " | " << formatted("%.3f ms / %.3f (CPU %.3f) / ", ms, gpu_rms, cpu_rms) << format_bytes(static_cast<double>(f.packed.buffer().size()));
    }
    out << " |\n| paper | " << paper[k][0] << " | " << paper[k][1] << " | " << paper[k][2] << " |\n";
  }
  out << "\nGPU RMS against the CPU's: at most " << formatted("%.3f", worst_percent) << "% apart (target: within 1%).\n";
}

// The GPU paper's Figure 5 setting: intra-object AO of the caster alone (the paper's igea), fields of
// 16642 positions x 64^2, 121 rays per pixel of a 512x512 view. Primary visibility is the G-buffer
// (the paper rasterised it), computed once; the frame time is the AO pass over it: rays generated
// and traced on the device, one count per pixel back.
void figure5(const std::string& caster, std::ostream& out) {
  Scene scene = load_scene(caster);
  for (TriangleMesh& mesh : scene.meshes) mesh.occluder = MeshOccluder::field;
  const Camera camera = scene.camera_or_default(512, 512);
  const TriangleSet set = flatten(scene);
  const Bvh bvh = Bvh::build(set);
  const GBuffer g = g_buffer(scene, camera, bvh, [](const Hit&) { return true; });
  const auto frames = cuda::DeviceArray<gpu::SurfaceFrame>::from(std::span<const gpu::SurfaceFrame>(g.frames));
  const cuda::AoParams p{121, 1, std::numeric_limits<float>::infinity()};
  const DeviceFields f = device_fields(scene, 16642, 64);
  double field_ms = 0.0, exact_ms = 0.0;
  const std::vector<std::uint32_t> field = timed_ao(f.device, frames, p, field_ms);
  // The frame as an application would run it: frames up, the AO pass, the counts down.
  cuda::DeviceArray<std::uint32_t> open(g.frames.size());
  const double frame_ms = time_runs(kPlan, [&] {
                            const auto up = cuda::DeviceArray<gpu::SurfaceFrame>::from(std::span<const gpu::SurfaceFrame>(g.frames));
                            cuda::ambient_occlusion(f.device, up.data(), g.frames.size(), p, open.data());
                            (void)open.to_host();
                          }).median_ms();
  const cuda::DeviceBvh exact = cuda::DeviceBvh::upload(gpu::GpuBvh::build(set));
  const std::vector<std::uint32_t> reference = timed_ao(exact, frames, p, exact_ms);
  std::vector<double> a(g.hits.size(), 255.0), b(g.hits.size(), 255.0);
  for (std::size_t i = 0; i < a.size(); ++i)
    if (g.pixel_point[i] >= 0) {
      a[i] = 255.0 * field[static_cast<std::size_t>(g.pixel_point[i])] / 121.0;
      b[i] = 255.0 * reference[static_cast<std::size_t>(g.pixel_point[i])] / 121.0;
    }
  const std::size_t rays = g.frames.size() * 121;
  out << set.size() << " triangles, 512x512, " << g.frames.size() << " pixels on the model, 121 AO rays each (" << rays
      << " rays), fields 16642 x 64x64 u8 (" << format_bytes(static_cast<double>(f.packed.buffer().size())) << ").\n\n"
      << "| AO pass | ms per frame | G rays/s | RMS (0-255) vs exact |\n|---|---:|---:|---:|\n"
      << "| fields, kernel | " << formatted("%.3f | %.2f", field_ms, grays(rays, field_ms)) << " | " << formatted("%.3f", rms_difference(a, b)) << " |\n"
      << "| fields, frames up + kernel + counts down | " << formatted("%.3f | %.2f", frame_ms, grays(rays, frame_ms)) << " | |\n"
      << "| exact GPU BVH, kernel | " << formatted("%.3f | %.2f", exact_ms, grays(rays, exact_ms)) << " | 0 |\n\n"
      << "Target: at most 5 ms per frame; the paper: 202 ms on a GeForce 8800.\n";
}

// The GPU paper's Figure 7 on the GPU: soft shadows of the caster on the ground from three sphere
// lights, 20 rays per light and pixel through fields at {4226, 16642} x {32^2, 64^2, 128^2}; the
// reference is the exact GPU BVH with 256 rays per light. A pixel is its diffuse surface lit by each
// light's unoccluded irradiance (radiance x the cone's solid angle x the cosine to its axis) times
// the fraction of that light's rays that reach it, plus 0.1 ambient: the soft-shadow integrator's
// estimate with the cosine taken at the cone's axis. Beside each RMS, the CPU's: its fields against its
// exact BVH, on the kernels' rays made on the host.
void figure7(const std::string& caster, std::ostream& out) {
  Scene scene = caster_on_ground(caster, 6.0f, 1.0f);
  const float distance = 4.0f, radius = 0.3f, radiance = 60.0f;
  const std::vector<gpu::SphereLightData> lights = {{Vec3f{-0.5f, 1.0f, 0.6f} * distance, radius},
                                                     {Vec3f{0.6f, 0.9f, 0.5f} * distance, radius},
                                                     {Vec3f{0.1f, 1.1f, -0.4f} * distance, radius}};
  Camera camera;
  camera.position = {0.0f, 2.2f, 3.6f};
  camera.look_at = {0.0f, 0.7f, 0.0f};
  camera.width = camera.height = 256;
  camera.fov_degrees = 45.0f;
  const TriangleSet set = flatten(scene);
  const Bvh bvh = Bvh::build(set);
  const ObjectId ground = scene.instances().back().id;
  const GBuffer g = g_buffer(scene, camera, bvh, [](const Hit&) { return true; });
  const auto frames = cuda::DeviceArray<gpu::SurfaceFrame>::from(std::span<const gpu::SurfaceFrame>(g.frames));
  const auto d_lights = cuda::DeviceArray<gpu::SphereLightData>::from(std::span<const gpu::SphereLightData>(lights));
  const int light_count = static_cast<int>(lights.size());
  const std::uint64_t seed = 1;
  // The image from visible[point * lights + light], the rays of `per_light` per light that got through.
  const auto shade = [&](const std::vector<std::uint32_t>& v, int per_light) {
    std::vector<double> pixels(g.hits.size(), 0.0);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      if (g.pixel_point[i] < 0) continue;
      const std::size_t point = static_cast<std::size_t>(g.pixel_point[i]);
      const gpu::SurfaceFrame& f = g.frames[point];
      const double albedo = g.hits[i].instance == ground ? 0.7 : 0.8;
      double value = 0.1 * albedo;
      for (std::size_t l = 0; l < lights.size(); ++l) {
        const Vec3f to = lights[l].centre - f.position;
        const double d = length(to);
        const double cos_axis = std::max(0.0, static_cast<double>(dot(to, f.normal)) / d);
        const double sin2 = (radius * radius) / (d * d);
        const double solid_angle = 2.0 * std::numbers::pi * sin2 / (1.0 + std::sqrt(std::max(0.0, 1.0 - sin2)));
        value += albedo / std::numbers::pi * radiance * solid_angle * cos_axis * v[point * lights.size() + l] / per_light;
      }
      pixels[i] = 255.0 * std::min(1.0, value);
    }
    return pixels;
  };
  const auto shadows = [&](const auto& occluder, int per_light, double& ms) {
    cuda::DeviceArray<std::uint32_t> visible(g.frames.size() * lights.size());
    ms = time_runs_measured(kPlan, [&] {
           return cuda::kernel_ms([&] {
             cuda::soft_shadows(occluder, frames.data(), g.frames.size(), d_lights.data(), light_count, per_light, seed, visible.data());
           });
         }).median_ms();
    return shade(visible.to_host(), per_light);
  };
  // The kernel's shadow rays on the host: point-major, then light, then sample l * per_light + k.
  const auto cpu_rays = [&](int per_light) {
    const std::size_t n = static_cast<std::size_t>(per_light);
    std::vector<Ray> rays(g.frames.size() * lights.size() * n);
    vf::parallel_for(std::size_t{0}, g.frames.size(), [&](std::size_t i) {
      for (std::size_t l = 0; l < lights.size(); ++l)
        for (std::size_t k = 0; k < n; ++k)
          rays[(i * lights.size() + l) * n + k] = gpu::cone_ray(g.frames[i].position, lights[l], seed, i, l * n + k);
    });
    return rays;
  };
  const std::vector<Ray> cpu_rays20 = cpu_rays(20);
  const std::vector<double> cpu_reference = shade(cpu_counts(bvh, cpu_rays(256), 256), 256);
  double worst_percent = 0.0;
  double reference_ms = 0.0, exact20_ms = 0.0;
  const cuda::DeviceBvh exact = cuda::DeviceBvh::upload(gpu::GpuBvh::build(set));
  const std::vector<double> reference = shadows(exact, 256, reference_ms);
  const std::vector<double> exact20 = shadows(exact, 20, exact20_ms);
  const std::size_t rays20 = g.frames.size() * lights.size() * 20;
  out << "256x256 pixels, 3 sphere lights, 20 shadow rays per light and pixel (" << rays20 << " rays). Reference: exact GPU BVH, "
      << "256 rays per light, " << formatted("%.3f ms", reference_ms) << ". Exact GPU BVH with 20 rays: "
      << formatted("%.3f ms (%.2f G rays/s), RMS %.2f", exact20_ms, grays(rays20, exact20_ms), rms_difference(exact20, reference))
      << " (the noise of 20 rays alone).\n\nEach cell: kernel ms / RMS (0-255) against the reference (the CPU's against its "
         "reference, on the same rays) / field memory; the GPU paper's (its 2010 GPU) below.\n\n| positions | 32x32 | 64x64 | 128x128 |\n|---|---|---|---|\n";
  const char* const paper[2][3] = {{"348.0 ms / 5.95 / 4.1 MB", "348.5 ms / 4.82 / 16.5 MB", "348.7 ms / 4.44 / 66.0 MB"},
                                   {"348.5 ms / 5.94 / 16.3 MB", "348.6 ms / 4.80 / 65.0 MB", "-"}};
  const int positions[] = {4226, 16642};
  for (int k = 0; k < 2; ++k) {
    out << "| " << positions[k];
    for (const int n : {32, 64, 128}) {
      const DeviceFields f = device_fields(scene, positions[k], n);
      double ms = 0.0;
      const std::vector<double> field = shadows(f.device, 20, ms);
      const double gpu_rms = rms_difference(field, reference), cpu_rms = rms_difference(shade(cpu_counts(f.cpu, cpu_rays20, 20), 20), cpu_reference);
      worst_percent = std::max(worst_percent, percent_apart(gpu_rms, cpu_rms));
      out << " | " << formatted("%.3f ms / %.2f (CPU %.2f) / ", ms, gpu_rms, cpu_rms) << format_bytes(static_cast<double>(f.packed.buffer().size()));
    }
    out << " |\n| paper | " << paper[k][0] << " | " << paper[k][1] << " | " << paper[k][2] << " |\n";
  }
  out << "\nGPU RMS against the CPU's: at most " << formatted("%.3f", worst_percent) << "% apart (target: within 1%).\n";
}

}  // namespace

void run_cuda_figure(const std::string& name, const std::string& caster_path, int threads, std::ostream& out) {
  cuda::require_device();
  const ThreadLimit limit(threads);
  out << "## " << name << " on the GPU (" << cuda::device_info().name << "), caster " << caster_path << ", " << limit.threads()
      << " CPU threads for the precomputes\n\n";
  if (name == "gpu3")
    figure3(caster_path, out);
  else if (name == "gpu5")
    figure5(caster_path, out);
  else if (name == "gpu7")
    figure7(caster_path, out);
  else
    throw Error("--figure " + name + ": not a GPU figure");
}

}  // namespace vf::experiments
