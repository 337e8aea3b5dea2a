#include "visfield/select/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "visfield/core/error.hpp"
#include "visfield/select/experiment.hpp"
#include "visfield/select/timing.hpp"

namespace vf {
namespace {

std::string fixed(double value, int decimals) {
  if (std::isnan(value)) return "n/a";
  if (std::isinf(value)) return value > 0 ? "∞" : "-∞";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

// Integer with thousands separators ("1,234,567"), as the paper prints ray counts; ∞ for infinity.
std::string grouped(double value) {
  if (std::isnan(value)) return "n/a";
  if (std::isinf(value)) return "∞";
  const std::string digits = fixed(std::round(value), 0);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i != 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// A scene as the tables show it: mesh files by their file name, other specs (builtin:...) as given.
std::string scene_label(const std::string& name) {
  if (name.rfind("builtin:", 0) == 0) return name;
  const std::string file = std::filesystem::path(name).filename().string();
  return file.empty() ? name : file;
}

std::string percent(std::size_t part, std::size_t whole) {
  return whole ? fixed(100.0 * static_cast<double>(part) / static_cast<double>(whole), 0) + "%" : "n/a";
}

std::string scientific(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.0e", value);
  return buffer;
}

void write_header(std::ostringstream& md, const Calibration& c, const ReportOptions& options) {
  const CalibrationOptions& s = c.settings;
  md << "# Choosing a structure: calibration, the grid-or-kd-tree selection and the planner\n\n"
     << "Reproduces the evaluation of Hapala, Karlík, Havran, *When It Makes Sense to Use Uniform Grids for Ray Tracing*"
     << " (section 4) with visfield's `grid` (UniformGrid, default density) and `kdtree` (KdTree, SAH).\n\n"
     << "- Machine: " << c.machine.cpu_model << " (" << c.machine.hostname << "), " << c.machine.threads << " threads\n"
     << "- Rays per scene and kind: M = " << s.rays << ", each traced once per structure; per-ray time = median over"
     << " batches of ~" << kTimingBatchQueries << " rays (after one untimed batch) of the single-thread time, divided by"
     << " the thread count. Decision sample: S = " << s.sample_rays << " other rays (seed + 1) through the grid only, in "
     << kSampleParts << " batches (one untimed), median\n"
     << "- Builds: median of " << s.build_repetitions << "; path-tracing rays: camera ray, " << s.path_bounces
     << " cosine-weighted diffuse bounces, one shadow ray per hit; seed " << s.seed << "\n"
     << "- ε = " << options.epsilon << "; leave-k-out: " << options.splits << " random splits per k (seed " << options.seed
     << ")\n";
  const CalibrationConstants all = compute_constants(c.scenes);
  md << "- Constants over all " << c.scenes.size() << " scenes: C_B = " << all.build_ms_per_n_log2_n
     << " ms per N log2 N, C_R = " << all.ray_us(RayKind::random) << " µs (random), " << all.ray_us(RayKind::path)
     << " µs (path) per log2 N\n";
  if (!options.command.empty()) md << "- Command: `" << options.command << "`\n";
  md << "\nExact R_C = (T_B^H − T_B^G) / (t^G − t^H): the ray count at which grid and kd-tree, each built from scratch,"
     << " take the same total time (the definition of the paper's Table 1; ∞ where the grid is never slower per ray)."
     << " Estimated R_C = T_B^H,est / (t^G,sample (1 + ε) − t^H,est) with T_B^H,est = C_B N log2 N and"
     << " t^H,est = C_R log2 N (eqs. 7, 8) calibrated on all *other* scenes (leave-one-out), t^G,sample from the S sample"
     << " rays. Error = 100 (R_est − R_C) / R_C.\n\n";
}

void write_table1(std::ostringstream& md, const Calibration& c, const ReportOptions& options) {
  const std::vector<CriticalRaysEstimate> random = leave_one_out(c.scenes, RayKind::random, options.epsilon);
  const std::vector<CriticalRaysEstimate> path = leave_one_out(c.scenes, RayKind::path, options.epsilon);
  md << "## Table 1: measurements, exact and estimated critical ray counts\n\n"
     << "Build times in ms, per-ray times in µs (mesh files by file name; the measured paths are in the calibration"
     << " file).\n\n"
     << "| Scene | N | σ | T_B^G | T_B^H | random t^G | t^H | R_C | R_est | err % | path t^G | t^H | R_C | R_est | err % |\n"
     << "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (std::size_t i = 0; i < c.scenes.size(); ++i) {
    const SceneMeasurement& s = c.scenes[i];
    md << "| " << scene_label(s.name) << " | " << grouped(static_cast<double>(s.triangles)) << " | "
       << fixed(s.grid_statistics.std_dev, 2) << " | " << fixed(s.grid_build_ms, 2) << " | " << fixed(s.tree_build_ms, 2);
    for (RayKind kind : kCalibratedKinds) {
      const CriticalRaysEstimate& e = kind == RayKind::random ? random[i] : path[i];
      md << " | " << fixed(s.timings(kind).grid_us, 3) << " | " << fixed(s.timings(kind).tree_us, 3) << " | "
         << grouped(e.exact) << " | " << grouped(e.estimate) << " | " << fixed(e.error_percent, 1);
    }
    md << " |\n";
  }
  md << "\n";
}

void write_statistics(std::ostringstream& md, const Calibration& c) {
  md << "## Grid statistics (eqs. 1–6) and the inputs of the estimate\n\n"
     << "Est/meas: the leave-one-out estimate of the kd-tree's build time and per-ray time over the measured value;"
     << " sample/full: the grid's per-ray time on the S sample rays over that on all M rays.\n\n"
     << "| Scene | resolution | sparseness | maxRefs | mean | variance | skewness | kurtosis | T_B^H est/meas"
     << " | random t^H est/meas | random t^G sample/full | path t^H est/meas | path t^G sample/full |\n"
     << "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (std::size_t i = 0; i < c.scenes.size(); ++i) {
    const SceneMeasurement& s = c.scenes[i];
    const CalibrationConstants constants = constants_without(c.scenes, i);
    const GridStatistics& g = s.grid_statistics;
    md << "| " << scene_label(s.name) << " | " << s.grid_resolution[0] << "×" << s.grid_resolution[1] << "×" << s.grid_resolution[2]
       << " | " << fixed(g.sparseness, 3) << " | " << g.max_refs << " | " << fixed(g.mean, 2) << " | " << fixed(g.variance, 1)
       << " | " << fixed(g.skewness, 2) << " | " << fixed(g.kurtosis, 1) << " | "
       << fixed(estimated_tree_build_ms(constants, s.triangles) / s.tree_build_ms, 2);
    for (RayKind kind : kCalibratedKinds) {
      const RayTimings& t = s.timings(kind);
      md << " | " << fixed(estimated_tree_ray_us(constants, kind, s.triangles) / t.tree_us, 2) << " | "
         << fixed(t.grid_sample_us / t.grid_us, 2);
    }
    md << " |\n";
  }
  md << "\n";
}

void write_leave_k_out(std::ostringstream& md, const Calibration& c, const ReportOptions& options) {
  const std::vector<LeaveKOutRow> random = leave_k_out(c.scenes, RayKind::random, options.splits, options.seed, options.epsilon);
  const std::vector<LeaveKOutRow> path = leave_k_out(c.scenes, RayKind::path, options.splits, options.seed, options.epsilon);
  md << "## Leave-k-out: calibrate on k random scenes, estimate R_C of the others\n\n"
     << "Mean error and mean |error| in % over all (split, estimated scene) pairs; pairs where the exact or estimated"
     << " R_C is ∞ (or the exact one 0) have no relative error and are counted as left out (paper: Figures 1 and 2).\n\n"
     << "| k | random: mean err % | mean \\|err\\| % | pairs | left out | path: mean err % | mean \\|err\\| % | pairs | left out |\n"
     << "|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (std::size_t i = 0; i < random.size(); ++i) {
    md << "| " << random[i].k;
    for (const LeaveKOutRow* row : {&random[i], &path[i]})
      md << " | " << fixed(row->mean_error_percent, 1) << " | " << fixed(row->mean_abs_error_percent, 1) << " | "
         << row->estimates << " | " << row->undefined;
    md << " |\n";
  }
  md << "\n";
}

void write_decisions(std::ostringstream& md, const Calibration& c, const ReportOptions& options) {
  md << "## Decision accuracy\n\n"
     << "For each workload of R rays and each scene: the decision (leave-one-out calibration, sampled grid time) is right"
     << " when it picks the structure with the smaller measured total T_B + R t_R. Time/best: mean over scenes of the"
     << " decision's time (T_B^G always, then R t^G, or T_B^H + R t^H) over the better total.\n\n"
     << "| rays | R | decision right | % | always grid right | always kd-tree right | time / best |\n"
     << "|---|--:|--:|--:|--:|--:|--:|\n";
  std::size_t right = 0, total = 0;
  for (RayKind kind : kCalibratedKinds) {
    for (const DecisionRow& row : decision_accuracy(c.scenes, kind, options.decision_rays, options.epsilon)) {
      md << "| " << ray_kind_name(kind) << " | " << scientific(row.rays) << " | " << row.right << "/" << row.scenes << " | "
         << percent(row.right, row.scenes) << " | " << percent(row.grid_right, row.scenes) << " | "
         << percent(row.tree_right, row.scenes) << " | " << fixed(row.mean_time_ratio, 3) << " |\n";
      right += row.right;
      total += row.scenes;
    }
  }
  md << "\nOverall: " << right << " of " << total << " decisions right (" << percent(right, total) << ").\n";
}

// A pick this close to the measured fastest is within the noise of the timings themselves.
constexpr double kCloseRegret = 1.05;

// The planner's targets: every ray kind, R = 1e4 .. 1e9, E in {0, 1, 3, 8}.
constexpr double kPlanRays[] = {1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
constexpr double kPlanErrors[] = {0.0, 1.0, 3.0, 8.0};

void write_planner(std::ostringstream& md, const Calibration& c) {
  const int threads = c.machine.threads;
  md << "\n## The planner: every structure, every ray kind, an error tolerance\n\n"
     << "For each scene, the planner (`auto:rays=R,kind=K,error=E`, `visfield select`) is fitted on every *other* scene"
     << " (leave-one-out) and picks among " << plan_candidates().size() << " candidates from the scene's profile alone (counts, grid"
     << " build and sample, the same sample through a two-level BVH, AO occlusion and, when E > 0, the error of the probe field). It is right when its pick is the candidate with the lowest measured total build + R t_R"
     << " among those allowed (exact ones; fields too when their *measured* AO RMS is ≤ E > 0). Regret = measured total of"
     << " the pick / the lowest. Each cell: right / scenes, then the worst regret. Fields answer AO and shadow rays only."
     << " When a field would beat the pick by more than its build and the error model can neither rule it out (its fit × exp(−2.5 σ)"
     << " ≤ E) nor vouch for it (its 90% bound > E), the planner measures its RMS (as it measures the probe's: build it, render the"
     << " error image) and takes it if it meets E; then the next such field, against the new pick.\n\n"
     << "| kind | E |";
  for (double r : kPlanRays) md << " R = " << scientific(r) << " |";
  md << "\n|---|--:|";
  for (std::size_t i = 0; i < std::size(kPlanRays); ++i) md << "--:|";
  md << "\n";
  std::size_t right = 0, total = 0, error_missed = 0, close = 0, measured = 0, measured_kept = 0;
  std::vector<double> regrets;
  for (RayKind kind : kRayKinds) {
    for (double e : kPlanErrors) {
      if (e > 0.0 && !is_occlusion_kind(kind)) continue;  // only fields use E, and they answer occlusion only
      md << "| " << ray_kind_name(kind) << " | " << fixed(e, 0) << " |";
      for (double r : kPlanRays) {
        PlanRequest request;
        request.rays = r;
        request.kind = kind;
        request.max_error = e;
        std::size_t cell_right = 0;
        double worst = 1.0;
        const std::vector<PlanOutcome> outcomes = plan_leave_one_out(c.scenes, request, threads);
        for (const PlanOutcome& o : outcomes) {
          cell_right += o.right() ? 1 : 0;
          close += o.error_kept && o.regret() <= kCloseRegret ? 1 : 0;
          error_missed += o.error_kept ? 0 : 1;
          measured += static_cast<std::size_t>(o.measured);
          measured_kept += static_cast<std::size_t>(o.measured_kept);
          worst = std::max(worst, o.regret());
          regrets.push_back(o.regret());
        }
        right += cell_right;
        total += outcomes.size();
        md << " " << cell_right << "/" << outcomes.size() << " (" << fixed(worst, 2) << ") |";
      }
      md << "\n";
    }
  }
  std::sort(regrets.begin(), regrets.end());
  const double median_regret = regrets.empty() ? 1.0 : regrets[regrets.size() / 2];
  md << "\nOverall: " << right << " of " << total << " choices right (" << percent(right, total) << "); within "
     << fixed(100.0 * (kCloseRegret - 1.0), 0) << "% of the fastest (the spread of repeated timings on this machine): " << close
     << " (" << percent(close, total) << "); regret median "
     << fixed(median_regret, 3) << ", 90th percentile " << fixed(regrets.empty() ? 1.0 : regrets[regrets.size() * 9 / 10], 2)
     << ", worst " << fixed(regrets.empty() ? 1.0 : regrets.back(), 2) << "; picks whose measured error exceeded E: "
     << error_missed << ". Fields measured because the model could not vouch for them: " << measured << ", of which " << measured_kept
     << " met E and were chosen (the others count their build in the regret).\n\n";

  // One workload in full, to show what is picked and why it loses where it does.
  PlanRequest shown;
  shown.rays = 1e7;
  shown.kind = RayKind::ao;
  shown.max_error = 8.0;
  md << "Per scene, " << scientific(shown.rays) << " AO rays with E = " << fixed(shown.max_error, 0) << ":\n\n"
     << "| scene | picked | measured fastest | regret |\n|---|---|---|--:|\n";
  for (const PlanOutcome& o : plan_leave_one_out(c.scenes, shown, threads))
    md << "| " << scene_label(o.scene) << " | `" << o.chosen << "`" << (o.error_kept ? "" : " (error over E)") << " | `" << o.best
       << "` | " << fixed(o.regret(), 2) << " |\n";

  const FieldErrorModel& f = c.plan.field_error;
  md << "\n## Fields sized from a target error (`visfield field build --target-rms E`)\n\n"
     << "Error model over all scenes, with p = log(positions / 1090), d = log(directions / 16) and o = log(AO occluded + 0.01):"
     << " log RMS = log RMS_probe + " << fixed(f.coefficients[0], 3) << " p + " << fixed(f.coefficients[1], 3) << " d + "
     << fixed(f.coefficients[2], 3) << " p d + " << fixed(f.coefficients[3], 3) << " d o + " << fixed(f.coefficients[4], 3)
     << " p o, residual σ (1.4826 × their median absolute deviation) = " << fixed(f.sigma, 3) << " over " << f.samples << " fields, RMS_probe the"
     << " measured RMS of `" << kFieldProbe << "` on the scene (the smallest field: the planner builds it to profile a scene"
     << " when E > 0; its own RMS is known, not predicted). Fields are tried smallest first: one is picked when exp(1.2816 σ) × the fit"
     << " (its 90% bound) is ≤ E, or when its measured RMS is (measured when the fit × exp(−2.5 σ) is ≤ E) (`field build --target-rms` builds it and measures"
     << " its error image, as for the probe). RMS: the AO image (128 × 128,"
     << " the scene's camera, 32 AO rays of unlimited length per pixel that sees the scene) against the exact one with the same"
     << " rays, 0-255. Leave-one-out: the model is fitted without the scene it sizes. A refusal (no field is expected to"
     << " meet E) is right when no measured field meets E. Size: the pick's bytes / the smallest measured field that"
     << " meets E.\n\n"
     << "| E | fields picked | picks that meet E | refusals | refusals where a field meets E | size ratio median | worst | fields measured |\n"
     << "|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (double e : {1.0, 3.0, 8.0}) {
    const std::vector<TargetRmsOutcome> outcomes = target_rms_leave_one_out(c.scenes, e, threads);
    std::size_t met = 0, picks = 0, wrong_refusals = 0, measured = 0;
    std::vector<double> ratios;
    for (const TargetRmsOutcome& o : outcomes) {
      measured += static_cast<std::size_t>(o.measured);
      picks += o.chosen.empty() ? 0 : 1;
      met += !o.chosen.empty() && o.met() ? 1 : 0;
      wrong_refusals += o.chosen.empty() && !o.met() ? 1 : 0;
      if (o.size_ratio() > 0.0) ratios.push_back(o.size_ratio());
    }
    std::sort(ratios.begin(), ratios.end());
    md << "| " << fixed(e, 0) << " | " << picks << "/" << outcomes.size() << " | " << met << "/" << picks << " | " << outcomes.size() - picks
       << " | " << wrong_refusals << " | " << (ratios.empty() ? "n/a" : fixed(ratios[ratios.size() / 2], 2)) << " | "
       << (ratios.empty() ? "n/a" : fixed(ratios.back(), 2)) << " | " << measured << " |\n";
  }
  md << "\n| scene | AO occluded | probe RMS | E = 1 | E = 3 | E = 8 |\n|---|--:|--:|---|---|---|\n";
  const std::vector<TargetRmsOutcome> one = target_rms_leave_one_out(c.scenes, 1.0, threads);
  const std::vector<TargetRmsOutcome> three = target_rms_leave_one_out(c.scenes, 3.0, threads);
  const std::vector<TargetRmsOutcome> eight = target_rms_leave_one_out(c.scenes, 8.0, threads);
  for (std::size_t i = 0; i < one.size(); ++i) {
    double occluded = 0.0, probe = 0.0;
    for (const SceneMeasurement& s : c.scenes)
      if (s.name == one[i].scene) occluded = s.plan.profile.ao_occluded, probe = s.plan.profile.field_probe_rms;
    md << "| " << scene_label(one[i].scene) << " | " << fixed(occluded, 3) << " | " << fixed(probe, 2);
    for (const TargetRmsOutcome* o : {&one[i], &three[i], &eight[i]}) {
      md << " | ";
      if (o->chosen.empty())
        md << "none" << (o->met() ? "" : " (one meets it)");
      else
        md << o->chosen.substr(o->chosen.find(':') + 1) << ": " << fixed(o->chosen_rms, 2) << (o->met() ? "" : " ✗");
    }
    md << " |\n";
  }
}

bool has_plan(const Calibration& c) {
  std::size_t planned = 0;
  for (const SceneMeasurement& s : c.scenes) planned += s.plan.candidates.empty() ? 0 : 1;
  return planned >= 2;
}

}  // namespace

std::string report_markdown(const Calibration& measured, const ReportOptions& options) {
  if (measured.scenes.size() < 2)
    throw Error("report: needs at least 2 measured scenes, got " + std::to_string(measured.scenes.size()));
  if (options.splits < 1) throw Error("report: splits must be at least 1");
  std::ostringstream md;
  write_header(md, measured, options);
  write_table1(md, measured, options);
  write_statistics(md, measured);
  write_leave_k_out(md, measured, options);
  write_decisions(md, measured, options);
  if (has_plan(measured)) write_planner(md, measured);
  return md.str();
}

}  // namespace vf
