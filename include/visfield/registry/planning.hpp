#pragma once
/// \file The planner (select/plan.hpp) over the registry's structures: a scene's profile, the plan
/// with the registry's memory estimates, and the calibration's measurement of every candidate.

#include <functional>
#include <optional>
#include <span>
#include <string_view>

#include "visfield/registry/registry.hpp"
#include "visfield/registry/scene_geometry.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/select/plan.hpp"
#include "visfield/select/workload.hpp"

namespace vf {

/// The profile of `geometry`'s scene with grid and BVH samples of `kinds` (profile_scene; the scene is
/// flattened unless it holds over kProfileFlattenLimit triangles) and, with `probe_fields`, the RMS of
/// the AO image through kFieldProbe (field_error_rms). `sample_rays` in 5..1e6.
SceneProfile profile_for_plan(SceneGeometry& geometry, std::span<const RayKind> kinds, bool probe_fields,
                              std::size_t sample_rays = kProfileSampleRays, std::uint64_t seed = 1);

/// make_plan for `geometry` with `calibration.plan` and each candidate's build estimate from the
/// registry, on the threads in force; a field the plan wants measured (Plan::to_measure) is built and
/// its RMS measured (field_error_rms) to settle the plan, and when `measured_choice` is given and a
/// measured field becomes the choice, that build is kept there (so the caller need not build it
/// again). Throws vf::Error on a bad request or when nothing qualifies.
Plan plan_structures(SceneGeometry& geometry, const SceneProfile& profile, const Calibration& calibration,
                     const PlanRequest& request, std::optional<BuiltStructure>* measured_choice = nullptr);

/// AO rays per hit pixel of the image a field's error is measured on.
inline constexpr int kErrorAoRays = 32;
/// Side of that image (the scene's camera, else the default framing).
inline constexpr int kErrorImageSide = 128;

/// The AO image a field's error is measured on (kErrorImageSide, kErrorAoRays, seed 1, drawn through
/// an exact structure) with the exact answers: made once, it measures any number of fields.
class FieldErrorImage {
 public:
  /// The image of `scene` drawn through `exact` (an exact structure over it).
  FieldErrorImage(const AnyStructure& exact, const Scene& scene);
  /// The image of `geometry`'s scene drawn through a BVH built over it.
  explicit FieldErrorImage(SceneGeometry& geometry);
  /// RMS (0-255) of the image through `field` (any structure over the scene) against the exact one.
  double rms(const AnyStructure& field) const;

 private:
  std::vector<Ray> rays_;
  std::vector<std::uint8_t> exact_;
};

/// FieldErrorImage(geometry).rms of the field `spec`. Cost: a field build, a BVH build and the image's
/// rays through both.
double field_error_rms(std::string_view spec, SceneGeometry& geometry);

/// RMS on the 0-255 scale between two AO images given as answers to the same AO rays, `rays_per_pixel`
/// consecutive rays for each pixel that sees the scene (make_ray_set's order): pixel value = 255 x the
/// fraction of its rays not occluded. Throws vf::Error when the sizes differ or are not a multiple.
double ao_image_rms(std::span<const std::uint8_t> occluded, std::span<const std::uint8_t> reference, int rays_per_pixel);

/// Every candidate of plan_candidates() built over `scene` and timed: build (median of
/// options.build_repetitions, one build past a second), memory, microseconds per ray of each kind it
/// answers (options.rays rays of each kind drawn through the BVH, traced as one batch on the threads in
/// force, median of 3 after a warm-up; brute force on at most 5e7 / N of them), one in-place update
/// (updatable candidates) and, for fields, the RMS of the AO image (kErrorImageSide, kErrorAoRays)
/// against the exact one. Candidates over the memory limit are left out. `on_candidate(spec)` runs
/// before each.
PlanMeasurement measure_plan(const NamedScene& scene, const CalibrationOptions& options,
                             const std::function<void(std::string_view spec)>& on_candidate = {});

}  // namespace vf
