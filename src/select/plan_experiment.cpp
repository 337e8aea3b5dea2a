// The planner judged on stored measurements: leave-one-out choices against each scene's measured
// totals, and fields sized from a target error against their measured errors.
#include <algorithm>
#include <cmath>
#include <limits>

#include "visfield/core/error.hpp"
#include "visfield/select/experiment.hpp"

namespace vf {
namespace {

// Indices of the scenes that hold plan measurements.
std::vector<std::size_t> planned_scenes(std::span<const SceneMeasurement> scenes) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < scenes.size(); ++i)
    if (!scenes[i].plan.candidates.empty()) out.push_back(i);
  return out;
}

PlanModel model_without(std::span<const SceneMeasurement> scenes, const std::vector<std::size_t>& planned, std::size_t left_out,
                        int threads) {
  std::vector<PlanMeasurement> plans;
  std::vector<std::size_t> others;
  for (std::size_t i : planned) {
    if (i != left_out) others.push_back(plans.size());
    plans.push_back(scenes[i].plan);
  }
  return fit_plan_model(plans, others, threads);
}

bool has_field(const PlanMeasurement& plan) {
  return std::any_of(plan.candidates.begin(), plan.candidates.end(), [](const CandidateMeasurement& m) {
    const std::size_t i = plan_candidate_index(m.spec);
    return i < plan_candidates().size() && plan_candidates()[i].approximate();
  });
}

}  // namespace

std::vector<PlanOutcome> plan_leave_one_out(std::span<const SceneMeasurement> scenes, const PlanRequest& request, int threads) {
  const std::vector<std::size_t> planned = planned_scenes(scenes);
  if (planned.size() < 2) throw Error("plan: leave-one-out needs at least 2 scenes with plan measurements, got " + std::to_string(planned.size()));
  std::vector<PlanOutcome> out;
  for (std::size_t s : planned) {
    const PlanMeasurement& measured = scenes[s].plan;
    const PlanModel model = model_without(scenes, planned, s, threads);
    PlanRequest r = request;
    r.max_memory = std::numeric_limits<double>::max();  // only candidates the scene measured
    Plan plan = make_plan(model, measured.profile, r, measured.profile.threads, [&](std::string_view spec) {
      const CandidateMeasurement* m = measured.find(spec);
      return m ? static_cast<double>(m->memory_bytes) : std::numeric_limits<double>::infinity();
    });
    PlanOutcome o;
    o.scene = scenes[s].name;
    double spent_measuring_ms = 0.0;
    while (plan.to_measure != kNoRow) {
      // What the planner's measurements would find: each field's measured RMS; a field that fails cost its build.
      const CandidateMeasurement& field = *measured.find(plan.rows[plan.to_measure].spec);
      ++o.measured;
      if (field.ao_rms <= request.max_error) ++o.measured_kept;
      else spent_measuring_ms += field.build_ms;
      settle_plan(plan, field.ao_rms, r);
    }
    o.chosen = plan.rows[plan.chosen].spec;
    const CandidateMeasurement& chosen = *measured.find(o.chosen);
    o.chosen_ms = measured_total_ms(chosen, request.kind, request.rays, request.updates) + spent_measuring_ms;
    o.error_kept = chosen.ao_rms <= request.max_error;
    o.best_ms = std::numeric_limits<double>::infinity();
    for (const CandidateMeasurement& m : measured.candidates) {
      const PlanCandidate& c = plan_candidates()[plan_candidate_index(m.spec)];
      if (c.approximate() && (request.max_error <= 0.0 || m.ao_rms > request.max_error)) continue;
      const double total = measured_total_ms(m, request.kind, request.rays, request.updates);
      if (total < o.best_ms) o.best_ms = total, o.best = m.spec;
    }
    out.push_back(std::move(o));
  }
  return out;
}

std::vector<TargetRmsOutcome> target_rms_leave_one_out(std::span<const SceneMeasurement> scenes, double target, int threads) {
  std::vector<std::size_t> with_fields;
  for (std::size_t i : planned_scenes(scenes))
    if (has_field(scenes[i].plan)) with_fields.push_back(i);
  if (with_fields.size() < 2) throw Error("plan: target RMS needs at least 2 scenes with field measurements, got " + std::to_string(with_fields.size()));
  std::vector<TargetRmsOutcome> out;
  for (std::size_t s : with_fields) {
    const PlanMeasurement& measured = scenes[s].plan;
    const PlanModel model = model_without(scenes, with_fields, s, threads);
    TargetRmsOutcome o;
    o.scene = scenes[s].name;
    o.target = target;
    for (const CandidateMeasurement& m : measured.candidates)
      if (plan_candidates()[plan_candidate_index(m.spec)].approximate() && m.ao_rms <= target &&
          (o.smallest_bytes == 0.0 || static_cast<double>(m.memory_bytes) < o.smallest_bytes))
        o.smallest_bytes = static_cast<double>(m.memory_bytes);
    // What measuring a field would find: its measured RMS (a field the scene did not measure fails).
    const std::size_t pick = field_for_target_rms(model.field_error, measured.profile, target, [&](std::size_t candidate) {
      ++o.measured;
      const CandidateMeasurement* m = measured.find(plan_candidates()[candidate].spec);
      return m ? m->ao_rms : std::numeric_limits<double>::infinity();
    });
    if (pick < plan_candidates().size()) {
      if (const CandidateMeasurement* m = measured.find(plan_candidates()[pick].spec)) {
        o.chosen = m->spec;
        o.chosen_rms = m->ao_rms;
        o.chosen_bytes = static_cast<double>(m->memory_bytes);
      }
    }
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace vf
