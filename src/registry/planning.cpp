#include "visfield/registry/planning.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/select/calibrate.hpp"
#include "visfield/render/ray_sets.hpp"

namespace vf {
namespace {

// Brute force traces at most this many triangle tests' worth of rays per set (its cost per ray is
// exactly proportional to N, so a few hundred rays measure it).
constexpr double kBruteTests = 5e7;
// A build slower than this is not repeated.
constexpr double kRepeatBuildsBelowMs = 1000.0;
// Timed moves of an object (alternately there and back), median; one when it is slower than a second.
constexpr int kTimedUpdates = 6;

// Microseconds per query of `queries` through `structure` (batch_passes_query_us).
double batch_query_us(const AnyStructure& structure, const QuerySet& queries) {
  return std::visit([&](const auto& s) { return batch_passes_query_us(s, queries); }, structure);
}

std::vector<std::uint8_t> occlusion_answers(const AnyStructure& structure, std::span<const Ray> rays) {
  std::vector<std::uint8_t> occluded(rays.size());
  std::visit([&](const auto& s) { occluded_batch(s, rays, std::span<std::uint8_t>(occluded)); }, structure);
  return occluded;
}

// One object moved a thousandth of the scene's diagonal and back, kTimedUpdates times; the median
// of one move and commit; -1 when the structure does not move objects in place.
double update_ms(AnyStructure& structure, const Scene& scene) {
  if (scene.instances().empty()) return -1.0;
  const Instance& object = scene.instances().front();
  Transform moved = object.transform;
  const Bounds3f bounds = scene.bounds();
  moved.translation = moved.translation + (bounds.hi - bounds.lo) * 1e-3f;
  std::vector<double> times;
  for (int i = 0; i < kTimedUpdates; ++i) {
    bool in_place = true;
    times.push_back(time_ms([&] { in_place = update_in_place(structure, object.id, i % 2 == 0 ? moved : object.transform); }));
    if (!in_place) return -1.0;
    if (times.back() > kRepeatBuildsBelowMs) break;  // as slow as a build: one move tells
  }
  return median(std::move(times));
}

// The AO rays a field's error is measured on, drawn through `exact`.
std::vector<Ray> error_rays(const AnyStructure& exact, const Scene& scene, std::uint64_t seed) {
  RaySetRequest request;
  request.kind = RayKind::ao;
  request.camera = scene.camera_or_default(kErrorImageSide, kErrorImageSide);
  request.ao_rays = kErrorAoRays;
  request.seed = seed;
  return std::visit([&](const auto& s) { return make_ray_set(s, scene, request); }, exact);
}

}  // namespace

SceneProfile profile_for_plan(SceneGeometry& geometry, std::span<const RayKind> kinds, bool probe_fields, std::size_t sample_rays,
                              std::uint64_t seed) {
  const bool flatten = geometry.instanced_triangle_count() <= kProfileFlattenLimit;
  // Two bounces as the calibration's path rays (CalibrationOptions::path_bounces).
  SceneProfile profile =
      profile_scene(geometry.scene(), flatten ? &geometry.flattened() : nullptr, kinds, sample_rays, seed, CalibrationOptions{}.path_bounces);
  if (probe_fields) profile.field_probe_rms = field_error_rms(kFieldProbe, geometry);
  return profile;
}

FieldErrorImage::FieldErrorImage(const AnyStructure& exact, const Scene& scene)
    : rays_(error_rays(exact, scene, 1)), exact_(occlusion_answers(exact, rays_)) {}

FieldErrorImage::FieldErrorImage(SceneGeometry& geometry)
    : FieldErrorImage(build_structure("bvh", geometry, {}, "plan ").structure, geometry.scene()) {}

double FieldErrorImage::rms(const AnyStructure& field) const { return ao_image_rms(occlusion_answers(field, rays_), exact_, kErrorAoRays); }

double field_error_rms(std::string_view spec, SceneGeometry& geometry) {
  const FieldErrorImage image(geometry);
  return image.rms(build_structure(spec, geometry, {}, "plan ").structure);
}

Plan plan_structures(SceneGeometry& geometry, const SceneProfile& profile, const Calibration& calibration, const PlanRequest& request,
                     std::optional<BuiltStructure>* measured_choice) {
  Plan plan = make_plan(calibration.plan, profile, request, threads_in_force(),
                        [&](std::string_view spec) { return estimate_structure_bytes(spec, geometry, "plan "); });
  std::optional<FieldErrorImage> image;  // made at the first measurement, for all of them
  while (plan.to_measure != kNoRow) {
    const std::size_t row = plan.to_measure;
    if (!image) image.emplace(geometry);
    BuiltStructure field = build_structure(plan.rows[row].spec, geometry, {}, "plan ");
    settle_plan(plan, image->rms(field.structure), request);
    // The choice moves only to a field measured within the error: the last one kept is the choice.
    if (measured_choice && plan.chosen == row) *measured_choice = std::move(field);
  }
  return plan;
}

double ao_image_rms(std::span<const std::uint8_t> occluded, std::span<const std::uint8_t> reference, int rays_per_pixel) {
  if (occluded.size() != reference.size() || rays_per_pixel < 1 || occluded.size() % static_cast<std::size_t>(rays_per_pixel) != 0)
    throw Error("ao_image_rms: " + std::to_string(occluded.size()) + " and " + std::to_string(reference.size()) +
                " answers do not make pixels of " + std::to_string(rays_per_pixel) + " rays");
  const std::size_t pixels = occluded.size() / static_cast<std::size_t>(rays_per_pixel);
  if (pixels == 0) return 0.0;
  double sum = 0.0;
  for (std::size_t p = 0; p < pixels; ++p) {
    int difference = 0;
    for (int r = 0; r < rays_per_pixel; ++r) {
      const std::size_t i = p * static_cast<std::size_t>(rays_per_pixel) + static_cast<std::size_t>(r);
      difference += (reference[i] ? 1 : 0) - (occluded[i] ? 1 : 0);
    }
    const double d = 255.0 * difference / rays_per_pixel;
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(pixels));
}

PlanMeasurement measure_plan(const NamedScene& named, const CalibrationOptions& options,
                             const std::function<void(std::string_view spec)>& on_candidate) {
  validate_calibration_options(options);
  const Scene& scene = named.scene;
  PlanMeasurement out;
  out.profile = profile_scene(scene, &named.triangles, kRayKinds, kProfileSampleRays, options.seed + 1, options.path_bounces);
  SceneGeometry geometry(scene);
  // Every kind's rays are drawn once, through the BVH (any exact structure draws the same rays).
  const BuiltStructure reference = build_structure("bvh:levels=1", geometry, {}, "plan ");
  const Bvh& bvh = std::get<Bvh>(reference.structure);
  std::array<QuerySet, kPlanKinds> queries;
  for (std::size_t k = 0; k < kPlanKinds; ++k)
    queries[k] = make_queries(kRayKinds[k], bvh, scene, named.triangles.bounds, options.rays, options.seed, options.path_bounces);
  const FieldErrorImage error_image(reference.structure, scene);

  for (const PlanCandidate& candidate : plan_candidates()) {
    if (on_candidate) on_candidate(candidate.spec);
    CandidateMeasurement m;
    m.spec = std::string(candidate.spec);
    std::optional<BuiltStructure> built;
    std::vector<double> builds;
    try {
      for (int r = 0; r < options.build_repetitions; ++r) {
        built.reset();
        built.emplace(build_structure(candidate.spec, geometry, {}, "plan "));
        builds.push_back(structure_stats(built->structure).build_ms);
        if (builds.back() > kRepeatBuildsBelowMs) break;
      }
    } catch (const MemoryRefused&) {
      continue;
    }
    m.build_ms = median(builds);
    m.memory_bytes = structure_stats(built->structure).memory_bytes;
    for (std::size_t k = 0; k < kPlanKinds; ++k) {
      m.ray_us[k] = -1.0;
      if (!candidate.answers(kRayKinds[k])) continue;
      const QuerySet& all = queries[k];
      if (candidate.shape == CostShape::brute) {
        const double most = std::max(256.0, kBruteTests / static_cast<double>(std::max<std::size_t>(named.triangles.size(), 1)));
        const std::size_t parts = static_cast<std::size_t>(std::ceil(static_cast<double>(all.size()) / most));
        m.ray_us[k] = batch_query_us(built->structure, query_parts(all, 0, 1, std::max<std::size_t>(parts, 1)));
      } else {
        m.ray_us[k] = batch_query_us(built->structure, all);
      }
    }
    if (candidate.approximate()) m.ao_rms = error_image.rms(built->structure);
    if (candidate.spec == kFieldProbe) out.profile.field_probe_rms = m.ao_rms;
    if (candidate.updatable) m.update_ms = update_ms(built->structure, scene);
    out.candidates.push_back(std::move(m));
  }
  return out;
}

}  // namespace vf
