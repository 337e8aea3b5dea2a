// The planner's arithmetic: predictions, exclusions and the choice, the fit of its constants and of the
// field error model, and its judgement on stored measurements.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "synthetic.hpp"
#include "visfield/core/error.hpp"
#include "visfield/select/calibrate.hpp"
#include "visfield/select/experiment.hpp"
#include "visfield/select/plan.hpp"

namespace vf {
namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

double some_bytes(std::string_view) { return 1000.0; }

const PlanRow& row_of(const Plan& plan, std::string_view spec) {
  for (const PlanRow& row : plan.rows)
    if (row.spec == spec) return row;
  throw Error("no row " + std::string(spec));
}

TEST(Plan, PredictsEachCandidateFromItsFeaturesAndPicksTheLowestTotal) {
  const PlanModel model = test::synthetic_plan_model(2);
  const SceneProfile profile = test::synthetic_profile(1 << 16, 4, 0.25, 2);
  PlanRequest request;
  request.rays = 1e6;
  request.kind = RayKind::shadow;
  request.updates = 3;
  const Plan plan = make_plan(model, profile, request, 2, some_bytes);
  ASSERT_EQ(plan.rows.size(), plan_candidates().size());
  const std::size_t k = plan_kind_index(RayKind::shadow);
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < plan.rows.size(); ++i) {
    const PlanCandidate& c = plan_candidates()[i];
    const PlanRow& row = plan.rows[i];
    EXPECT_EQ(row.spec, c.spec);
    EXPECT_DOUBLE_EQ(row.build_ms, model.constants[i].build_ms * build_feature(c, profile));
    EXPECT_DOUBLE_EQ(row.ray_us, model.constants[i].ray_us[k] * std::pow(ray_feature(c, profile, RayKind::shadow), model.constants[i].ray_exponent[k]));
    const double update = c.updatable ? 0.5 * update_feature(c, profile) : row.build_ms;
    EXPECT_DOUBLE_EQ(row.update_ms, update);
    EXPECT_DOUBLE_EQ(row.total_ms, row.build_ms + 1e6 * row.ray_us / 1000.0 + 3 * update);
    if (c.approximate())
      EXPECT_EQ(row.excluded, "approximate; error=0 allows exact structures only");
    else
      EXPECT_EQ(row.excluded, "") << row.spec;
    if (row.excluded.empty()) lowest = std::min(lowest, row.total_ms);
  }
  ASSERT_LT(plan.chosen, plan.rows.size());
  EXPECT_EQ(plan.rows[plan.chosen].total_ms, lowest);
  EXPECT_NE(plan.reason.find("lowest predicted total"), std::string::npos) << plan.reason;
  EXPECT_NE(plan.reason.find("next "), std::string::npos) << plan.reason;
}

TEST(Plan, FeaturesFollowTheirShapes) {
  const SceneProfile p = test::synthetic_profile(1024, 8, 0.5);
  const auto at = [](std::string_view spec) -> const PlanCandidate& { return plan_candidates()[plan_candidate_index(spec)]; };
  EXPECT_DOUBLE_EQ(build_feature(at("grid:levels=1"), p), p.grid_build_ms);  // the profile built this very grid
  EXPECT_DOUBLE_EQ(build_feature(at("bvh:levels=1"), p), 8192.0 * 13.0);
  EXPECT_DOUBLE_EQ(build_feature(at("bvh:levels=2"), p), 1024.0 * 10.0 + 8.0 * 3.0);
  // Trees per ray: the profile's two-level BVH sample, scaled for flattened trees by their depth over
  // its depth (log2 8192 = 13 levels against log2 1024 + log2 8 = 13: equal here).
  const double bvh_ao = p.bvh_sample_us[plan_kind_index(RayKind::ao)];
  EXPECT_DOUBLE_EQ(ray_feature(at("bvh:levels=2"), p, RayKind::ao), bvh_ao);
  EXPECT_DOUBLE_EQ(ray_feature(at("bvh:levels=1"), p, RayKind::ao), bvh_ao * 13.0 / 13.0);
  const SceneProfile one = test::synthetic_profile(1024, 1, 0.5);
  EXPECT_DOUBLE_EQ(ray_feature(at("kdtree:levels=1"), one, RayKind::ao), bvh_ao * 10.0 / 11.0);  // log2 1 counts as 1
  EXPECT_DOUBLE_EQ(ray_feature(at("beam"), p, RayKind::ao), 13.0);
  EXPECT_DOUBLE_EQ(ray_feature(at("brute:levels=1"), p, RayKind::ao), 8192.0);
  EXPECT_DOUBLE_EQ(ray_feature(at("grid:levels=1"), p, RayKind::random), p.grid_sample_us[plan_kind_index(RayKind::random)]);
  EXPECT_DOUBLE_EQ(build_feature(at("field:positions=4226,directions=32"), p), 4226.0 * 32 * 32 * 10.0);
  EXPECT_DOUBLE_EQ(ray_feature(at("field:positions=4226,directions=32"), p, RayKind::ao), 3.0);
  EXPECT_DOUBLE_EQ(update_feature(at("beam"), p), 1024.0);
  EXPECT_DOUBLE_EQ(update_feature(at("bvh:levels=2"), p), 8.0 * 3.0);
  EXPECT_EQ(plan_candidate_index("octree"), kNone);
}

TEST(Plan, ExcludesByKindErrorAndMemoryAndSaysWhy) {
  const PlanModel model = test::synthetic_plan_model();
  SceneProfile profile = test::synthetic_profile(5000, 1, 0.5);  // at 50% occluded, more directions lower the fit
  profile.grid_sample_us.fill(100.0);  // slow exact structures: per ray, fields are the cheapest
  profile.bvh_sample_us.fill(100.0);
  PlanRequest request;
  request.kind = RayKind::random;
  request.max_error = 255;
  const Plan random = make_plan(model, profile, request, 2, some_bytes);
  EXPECT_EQ(row_of(random, "field:positions=1090,directions=16").excluded, "answers occlusion (ao, shadow) rays only");
  SceneProfile unsampled = profile;
  unsampled.bvh_sample_us.fill(0.0);
  EXPECT_EQ(row_of(make_plan(model, unsampled, request, 2, some_bytes), "kdtree:levels=1").excluded,
            "no BVH sample of random rays in the profile");
  SceneProfile unprobed = profile;
  unprobed.field_probe_rms = -1;
  request.kind = RayKind::shadow;
  EXPECT_EQ(row_of(make_plan(model, unprobed, request, 2, some_bytes), "field:positions=1090,directions=16").excluded,
            "the scene was not probed with a field");

  // AO with a tight error: fields whose 90% bound exceeds it are out, with the bound in the reason (the
  // probe with its measured RMS).
  request.kind = RayKind::ao;
  request.rays = 1e12;  // rays dominate: the cheapest per ray wins among those allowed
  const double bound_small = model.field_error.bound(1090, 16, 0.5, 2.0), bound_large = model.field_error.bound(1090, 64, 0.5, 2.0);
  ASSERT_GT(bound_small, bound_large);
  request.max_error = (bound_small + bound_large) / 2;
  const Plan tight = make_plan(model, profile, request, 2, some_bytes);
  EXPECT_EQ(row_of(tight, "field:positions=1090,directions=16").excluded.rfind("measured RMS ", 0), 0u);
  EXPECT_EQ(row_of(tight, "field:positions=1090,directions=64").excluded, "");
  EXPECT_EQ(tight.rows[tight.chosen].spec.rfind("field:", 0), 0u) << tight.rows[tight.chosen].spec;

  // Memory: everything but brute force is over the limit.
  request.max_error = 0;
  request.max_memory = 1500;
  const Plan small = make_plan(model, profile, request, 2, [](std::string_view spec) { return spec == "brute:levels=1" ? 1000.0 : 2000.0; });
  EXPECT_EQ(small.rows[small.chosen].spec, "brute:levels=1");
  EXPECT_NE(row_of(small, "bvh:levels=1").excluded.find("over the memory limit"), std::string::npos);
  request.max_memory = 500;
  EXPECT_THROW(make_plan(model, profile, request, 2, some_bytes), Error);
}

TEST(Plan, TheProbesErrorIsItsMeasurement) {
  const SceneProfile profile = test::synthetic_profile(5000, 1, 0.5);
  PlanRequest any_error;
  any_error.kind = RayKind::ao;
  any_error.max_error = 255;
  const Plan plan = make_plan(test::synthetic_plan_model(), profile, any_error, 2, some_bytes);
  EXPECT_TRUE(row_of(plan, kFieldProbe).error_measured);
  EXPECT_EQ(row_of(plan, kFieldProbe).error, profile.field_probe_rms);
  EXPECT_FALSE(row_of(plan, "field:positions=1090,directions=32").error_measured);
  FieldErrorModel spread = test::synthetic_plan_model().field_error;
  spread.sigma = 0.5;
  EXPECT_EQ(spread.bound(1090, 16, 0.5, 3.25), 3.25);
  EXPECT_EQ(spread.optimistic(1090, 16, 0.5, 3.25), 3.25);
  EXPECT_GT(spread.bound(1090, 32, 0.5, 3.25), spread.predict(1090, 32, 0.5, 3.25));
}

TEST(Plan, MeasuresAFieldItsModelCannotVouchForAndSettlesOnTheMeasurement) {
  PlanModel model = test::synthetic_plan_model();
  model.field_error.sigma = 0.5;  // bounds 1.9x the fit
  for (std::size_t i = 0; i < plan_candidates().size(); ++i)
    if (plan_candidates()[i].approximate()) model.constants[i].build_ms = 1e-9;  // cheap fields: worth a build
  SceneProfile profile = test::synthetic_profile(5000, 1, 0.5);  // at 50% occluded, more directions lower the fit
  profile.grid_sample_us.fill(100.0);
  profile.bvh_sample_us.fill(100.0);  // slow exact structures: a field wins a large budget
  PlanRequest request;
  request.kind = RayKind::ao;
  request.rays = 1e9;
  const double fit = model.field_error.predict(1090, 64, 0.5, profile.field_probe_rms);
  request.max_error = 1.2 * fit;  // within the fit of the 64 directions, not within its bound (nor the probe's RMS)
  ASSERT_LT(request.max_error, profile.field_probe_rms);
  const Plan plan = make_plan(model, profile, request, 2, some_bytes);
  ASSERT_NE(plan.to_measure, kNoRow);
  const PlanRow& field = plan.rows[plan.to_measure];
  EXPECT_EQ(field.excluded.rfind("predicted RMS ", 0), 0u) << field.excluded;
  const PlanCandidate& candidate = plan_candidates()[plan.to_measure];
  EXPECT_LE(model.field_error.optimistic(candidate.positions, candidate.directions, 0.5, profile.field_probe_rms), request.max_error);
  EXPECT_GT(model.field_error.bound(candidate.positions, candidate.directions, 0.5, profile.field_probe_rms), request.max_error);
  EXPECT_LT(field.total_ms + field.build_ms, plan.rows[plan.chosen].total_ms);  // worth a build lost in vain
  EXPECT_NE(plan.reason.find("if its RMS"), std::string::npos) << plan.reason;

  Plan kept = plan;
  settle_plan(kept, 0.99 * request.max_error, request);
  EXPECT_EQ(kept.chosen, plan.to_measure);
  EXPECT_EQ(kept.to_measure, kNoRow);
  EXPECT_TRUE(kept.rows[kept.chosen].excluded.empty());
  EXPECT_TRUE(kept.rows[kept.chosen].error_measured);
  EXPECT_EQ(kept.rows[kept.chosen].error, 0.99 * request.max_error);
  EXPECT_NE(kept.reason.find("its RMS measured"), std::string::npos) << kept.reason;

  // Every field measured over the error: each is out with its measurement, the next one is weighed,
  // and the choice stays.
  Plan refused = plan;
  std::size_t measured = 0;
  while (refused.to_measure != kNoRow) {
    const std::size_t field_row = refused.to_measure;
    settle_plan(refused, 1.01 * request.max_error, request);
    ++measured;
    EXPECT_EQ(refused.chosen, plan.chosen);
    EXPECT_NE(refused.to_measure, field_row);
    EXPECT_EQ(refused.rows[field_row].excluded.rfind("measured RMS ", 0), 0u) << refused.rows[field_row].excluded;
    ASSERT_LE(measured, plan_candidates().size());
  }
  EXPECT_GE(measured, 1u);
  settle_plan(refused, 0.0, request);  // nothing left to settle
  EXPECT_EQ(refused.chosen, plan.chosen);

  // Fields as costly to build as the synthetic model makes them: none saves more than its build.
  const PlanModel costly = [&] {
    PlanModel m = test::synthetic_plan_model();
    m.field_error.sigma = 0.5;
    return m;
  }();
  EXPECT_EQ(make_plan(costly, profile, request, 2, some_bytes).to_measure, kNoRow);
  // A bound within the error: the field is taken without a measurement.
  request.rays = 1e9;
  model.field_error.sigma = 0.0;
  EXPECT_EQ(make_plan(model, profile, request, 2, some_bytes).to_measure, kNoRow);
}

TEST(Plan, FewRaysPickACheapBuildAndManyACheapRay) {
  const PlanModel model = test::synthetic_plan_model();
  const SceneProfile profile = test::synthetic_profile(100000, 1, 0.2);
  PlanRequest request;
  request.kind = RayKind::primary;
  request.rays = 1;
  const Plan few = make_plan(model, profile, request, 2, some_bytes);
  EXPECT_EQ(few.rows[few.chosen].spec, "grid:levels=1");  // build feature N at 1 ms: the cheapest build
  request.rays = 1e12;
  const Plan many = make_plan(model, profile, request, 2, some_bytes);
  EXPECT_EQ(many.rows[many.chosen].spec, "grid:levels=1");  // and its sampled 0.05 us is also the cheapest ray here
  // Per-ray constants are for the model's threads: with twice the threads, half the time per ray.
  const Plan doubled = make_plan(model, profile, request, 4, some_bytes);
  EXPECT_DOUBLE_EQ(row_of(doubled, "bvh:levels=1").ray_us, row_of(many, "bvh:levels=1").ray_us / 2);
  // The grid's sampled time is for the profile's threads, and rescales from those.
  EXPECT_DOUBLE_EQ(row_of(doubled, "grid:levels=1").ray_us, row_of(many, "grid:levels=1").ray_us / 2);
}

TEST(Plan, RefusesBadRequestsAndAForeignModel) {
  const PlanModel model = test::synthetic_plan_model();
  const SceneProfile profile = test::synthetic_profile(100, 1, 0.2);
  for (const auto& edit : {+[](PlanRequest& r) { r.rays = 0; }, +[](PlanRequest& r) { r.max_error = -1; },
                           +[](PlanRequest& r) { r.max_error = 300; }, +[](PlanRequest& r) { r.updates = -2; },
                           +[](PlanRequest& r) { r.max_memory = 0; }, +[](PlanRequest& r) { r.rays = std::nan(""); }}) {
    PlanRequest request;
    edit(request);
    EXPECT_THROW(make_plan(model, profile, request, 2, some_bytes), Error);
  }
  PlanModel short_model = model;
  short_model.constants.pop_back();
  EXPECT_THROW(make_plan(short_model, profile, PlanRequest{}, 2, some_bytes), Error);
}

TEST(Plan, FitRecoversTheConstantsAndTheErrorModelOfExactMeasurements) {
  const PlanModel truth = test::synthetic_plan_model(2);
  std::vector<PlanMeasurement> scenes;
  std::vector<std::size_t> all;
  const double occluded[] = {0.05, 0.2, 0.6, 0.9};
  for (std::size_t s = 0; s < 4; ++s) {
    scenes.push_back(test::synthetic_plan_measurement(truth, test::synthetic_profile(1000 << (3 * s), 1 + s * s, occluded[s])));
    all.push_back(s);
  }
  const PlanModel fitted = fit_plan_model(scenes, all, 2);
  ASSERT_EQ(fitted.constants.size(), truth.constants.size());
  for (std::size_t i = 0; i < truth.constants.size(); ++i) {
    EXPECT_NEAR(fitted.constants[i].build_ms, truth.constants[i].build_ms, 1e-9 * truth.constants[i].build_ms) << i;
    EXPECT_NEAR(fitted.constants[i].update_ms, truth.constants[i].update_ms, 1e-9) << i;
    for (std::size_t k = 0; k < kPlanKinds; ++k) {
      const double expected = plan_candidates()[i].answers(kRayKinds[k]) ? truth.constants[i].ray_us[k] : 0.0;
      EXPECT_NEAR(fitted.constants[i].ray_us[k], expected, 1e-9 * (1 + expected)) << i << " " << k;
      if (expected > 0) {
        EXPECT_NEAR(fitted.constants[i].ray_exponent[k], truth.constants[i].ray_exponent[k], 1e-9) << i << " " << k;
      }
    }
  }
  EXPECT_EQ(fitted.field_error.samples, 4 * 8u);  // the probe's rows say nothing: its RMS is measured
  for (std::size_t c = 0; c < kErrorFeatures; ++c) EXPECT_NEAR(fitted.field_error.coefficients[c], truth.field_error.coefficients[c], 1e-6) << c;
  EXPECT_NEAR(fitted.field_error.sigma, 0.0, 1e-6);
  // Below six field measurements there is no error model.
  std::vector<PlanMeasurement> few{scenes[0]};
  few[0].candidates.resize(plan_candidates().size() - 4);  // five fields left
  const std::size_t first[] = {0};
  EXPECT_EQ(fit_plan_model(few, first, 2).field_error.samples, 0u);
  EXPECT_THROW(fit_plan_model(scenes, {}, 2), Error);

  // Two scenes whose grid samples nearly agree and whose measured times do not: the grid's power is
  // kept within [0, 4] (a calibration under ASan fitted -8.5 and wrote a file it could not read back).
  std::vector<PlanMeasurement> two{scenes[0], scenes[1]};
  two[1].profile.grid_sample_us = two[0].profile.grid_sample_us;
  for (std::size_t k = 0; k < kPlanKinds; ++k) two[1].profile.grid_sample_us[k] *= 1.001;
  const std::size_t grid = plan_candidate_index("grid:levels=1");
  for (double& t : two[1].candidates[grid].ray_us) t *= 0.5;
  const std::size_t both[] = {0, 1};
  const PlanModel swung = fit_plan_model(two, both, 2);
  for (std::size_t k = 0; k < kPlanKinds; ++k) {
    EXPECT_GE(swung.constants[grid].ray_exponent[k], 0.0) << k;
    EXPECT_LE(swung.constants[grid].ray_exponent[k], 4.0) << k;
  }
}

TEST(Plan, TheTargetRmsPicksTheSmallestFieldWhoseBoundMeetsIt) {
  const PlanModel model = test::synthetic_plan_model();
  // At 30% occluded, fewer positions and more directions lower the bound (synthetic_plan_model's coefficients).
  const SceneProfile profile = test::synthetic_profile(3000, 1, 0.3);
  const double occluded = profile.ao_occluded, probe = profile.field_probe_rms;
  const std::size_t loosest = field_for_target_rms(model.field_error, profile, 1e6);
  ASSERT_LT(loosest, plan_candidates().size());
  EXPECT_EQ(plan_candidates()[loosest].spec, "field:positions=1090,directions=16");  // the smallest of all
  const double needs_64 = model.field_error.bound(1090, 32, occluded, probe) * 0.999;
  const std::size_t pick = field_for_target_rms(model.field_error, profile, needs_64);
  ASSERT_LT(pick, plan_candidates().size());
  EXPECT_EQ(plan_candidates()[pick].spec, "field:positions=1090,directions=64");
  EXPECT_EQ(field_for_target_rms(model.field_error, profile, 1e-3), kNone);
  EXPECT_EQ(field_for_target_rms(FieldErrorModel{}, profile, 100.0), kNone);
  // The bound scales with the probe: a scene whose small field fits it twice as badly needs more.
  SceneProfile rough = profile;
  rough.field_probe_rms = 2 * probe;
  EXPECT_DOUBLE_EQ(model.field_error.bound(4226, 32, occluded, 2 * probe), 2 * model.field_error.bound(4226, 32, occluded, probe));
  EXPECT_EQ(field_for_target_rms(model.field_error, rough, model.field_error.bound(1090, 64, occluded, probe)), kNone);
  rough.field_probe_rms = -1;  // not probed: no field is sized
  EXPECT_EQ(field_for_target_rms(model.field_error, rough, 1e6), kNone);

  // Measuring: fields the bound refuses and the fit does not rule out are measured, smallest first,
  // and the first whose measurement meets the target is picked.
  FieldErrorModel uncertain = model.field_error;
  uncertain.sigma = 0.5;
  const double target = uncertain.predict(1090, 64, occluded, probe);
  ASSERT_GT(uncertain.bound(1090, 64, occluded, probe), target);
  std::vector<std::string_view> asked;
  const std::size_t measured = field_for_target_rms(uncertain, profile, target, [&](std::size_t i) {
    asked.push_back(plan_candidates()[i].spec);
    return plan_candidates()[i].spec == "field:positions=1090,directions=64" ? target : 2 * target;
  });
  ASSERT_LT(measured, plan_candidates().size());
  EXPECT_EQ(plan_candidates()[measured].spec, "field:positions=1090,directions=64");
  ASSERT_GE(asked.size(), 2u);  // smaller fields not ruled out were measured first (the probe is measured already)
  const auto cells = [](std::string_view spec) {
    const PlanCandidate& c = plan_candidates()[plan_candidate_index(spec)];
    return static_cast<double>(c.positions) * c.directions * c.directions;
  };
  for (std::size_t i = 1; i < asked.size(); ++i) EXPECT_LT(cells(asked[i - 1]), cells(asked[i])) << asked[i];
  EXPECT_EQ(asked.back(), "field:positions=1090,directions=64");
  EXPECT_NE(field_for_target_rms(uncertain, profile, target), measured);  // bounds alone cannot admit it
}

TEST(Plan, LeaveOneOutIsRightWhenEverySceneFollowsTheModel) {
  const PlanModel truth = test::synthetic_plan_model(2);
  std::vector<SceneMeasurement> scenes(3);
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    scenes[s].name = "scene " + std::to_string(s);
    scenes[s].plan = test::synthetic_plan_measurement(truth, test::synthetic_profile(4000 << (2 * s), 1 + s, 0.1 + 0.3 * s, 2));
  }
  for (RayKind kind : kRayKinds)
    for (double rays : {1e4, 1e7, 1e9})
      for (double error : {0.0, 5.0}) {
        PlanRequest request;
        request.kind = kind;
        request.rays = rays;
        request.max_error = error;
        for (const PlanOutcome& o : plan_leave_one_out(scenes, request, 2)) {
          EXPECT_TRUE(o.right()) << o.scene << ": " << o.chosen << " vs " << o.best;
          EXPECT_DOUBLE_EQ(o.regret(), 1.0);
        }
      }
  // A scene where the usual pick is measured a thousand times slower per ray than the model says: the
  // planner, fitted on the others, still picks it for many camera rays and pays the regret.
  std::vector<SceneMeasurement> skewed = scenes;
  PlanRequest camera;
  camera.kind = RayKind::primary;
  camera.rays = 1e9;
  const std::string usual = plan_leave_one_out(skewed, camera, 2)[0].chosen;
  for (CandidateMeasurement& m : skewed[0].plan.candidates)
    if (m.spec == usual) m.ray_us[plan_kind_index(RayKind::primary)] *= 1000;
  const PlanOutcome o = plan_leave_one_out(skewed, camera, 2)[0];
  EXPECT_EQ(o.chosen, usual);
  EXPECT_FALSE(o.right());
  EXPECT_GT(o.regret(), 1.0);
  EXPECT_THROW(plan_leave_one_out(std::span<const SceneMeasurement>(scenes).first(1), camera, 2), Error);
}

TEST(Plan, TargetRmsLeaveOneOutMeetsAndSizesAgainstTheMeasuredFields) {
  const PlanModel truth = test::synthetic_plan_model(2);
  std::vector<SceneMeasurement> scenes(3);
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    scenes[s].name = "mesh " + std::to_string(s);
    scenes[s].plan = test::synthetic_plan_measurement(truth, test::synthetic_profile(2000, 1, 0.1 + 0.2 * s, 2));
  }
  for (double target : {0.5, 2.0, 3.0, 100.0}) {
    for (const TargetRmsOutcome& o : target_rms_leave_one_out(scenes, target, 2)) {
      EXPECT_TRUE(o.met()) << o.scene << " " << target;
      if (!o.chosen.empty()) {
        EXPECT_DOUBLE_EQ(o.size_ratio(), 1.0) << o.scene << " " << target;
      }
    }
  }
  // A mesh whose fields measure twice the model's error misses the targets the model just meets.
  for (CandidateMeasurement& m : scenes[1].plan.candidates) m.ao_rms *= 2;
  const double target = truth.field_error.bound(1090, 64, scenes[1].plan.profile.ao_occluded, 2.0) * 1.001;
  EXPECT_FALSE(target_rms_leave_one_out(scenes, target, 2)[1].met());
}

}  // namespace
}  // namespace vf
