#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "select_cli_support.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/text.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/registry/planning.hpp"

namespace vf::cli {

namespace {

struct SelectCommandOptions {
  std::string scene;
  double rays = 0;
  std::string kind = "path";
  double error = 0.0;
  double updates = 0.0;
  std::string calibration;
  double sample_rays = static_cast<double>(kProfileSampleRays);
  std::uint64_t seed = 1;
  int threads = 0;
};

int run_select(const SelectCommandOptions& o) {
  PlanRequest request;
  request.rays = static_cast<double>(ray_count(o.rays, "--rays"));
  request.kind = *parse_ray_kind(o.kind);
  request.max_error = o.error;
  request.updates = static_cast<double>(ray_count(o.updates, "--updates"));
  const std::size_t sample_rays = ray_count(o.sample_rays, "--sample-rays");
  const Calibration calibration = o.calibration.empty() ? builtin_calibration() : load_calibration(o.calibration);
  ThreadLimit limit(o.threads);
  if (!o.calibration.empty()) require_calibration_for(calibration, this_machine(limit.threads()), o.calibration);
  const MemoryLimit memory = memory_limit();
  request.max_memory = memory.bytes;
  validate_plan_request(request);
  const Scene scene = load_scene(o.scene);
  SceneGeometry geometry(scene);
  const RayKind kinds[] = {request.kind};
  const SceneProfile profile =
      profile_for_plan(geometry, kinds, request.max_error > 0.0 && is_occlusion_kind(request.kind), sample_rays, o.seed);
  const Plan plan = plan_structures(geometry, profile, calibration, request);

  std::cout << "scene:        " << o.scene << " (" << profile.triangles << " triangles, " << profile.unique_triangles
            << " in its meshes, " << profile.objects << " objects)\n"
            << "calibration:  " << (o.calibration.empty() ? "built in" : o.calibration) << " (" << calibration.machine.cpu_model
            << ", " << calibration.machine.threads << " threads)\n"
            << "workload:     " << formatted("%.0f", request.rays) << " " << ray_kind_name(request.kind) << " rays, "
            << formatted("%.0f", request.updates) << " updates, error <= " << formatted("%g", request.max_error) << ", memory limit "
            << memory.source << ", " << limit.threads() << " threads\n";
  const double sample_us = profile.grid_sample_us[plan_kind_index(request.kind)];
  if (sample_us > 0.0)
    std::cout << "grid sample:  " << formatted("%.4f", sample_us) << " us per ray (" << sample_rays << " rays), built in "
              << formatted("%.3f", profile.grid_build_ms) << " ms; AO rays occluded " << formatted("%.3f", profile.ao_occluded) << "\n";
  else
    std::cout << "grid sample:  none (the scene is too large to flatten for it)\n";
  std::cout << "BVH sample:   " << formatted("%.4f", profile.bvh_sample_us[plan_kind_index(request.kind)]) << " us per ray (the same rays, "
            << "two levels: each mesh once), built in " << formatted("%.3f", profile.bvh_build_ms) << " ms\n";
  if (profile.field_probe_rms >= 0.0)
    std::cout << "field probe:  " << kFieldProbe << " RMS " << formatted("%.3f", profile.field_probe_rms) << " (0-255)\n";
  std::cout << "\ncandidate                               build ms     us/ray  update ms     total ms       memory  error  \n";
  for (std::size_t i = 0; i < plan.rows.size(); ++i) {
    const PlanRow& r = plan.rows[i];
    char line[256];
    std::snprintf(line, sizeof line, "%s %-36s %9.4g %10.4g %10.4g %12.6g %12s %6.2f  %s\n", i == plan.chosen ? "*" : " ",
                  r.spec.c_str(), r.build_ms, r.ray_us, r.update_ms, r.total_ms, format_bytes(r.bytes).c_str(), r.error,
                  r.excluded.empty() ? (r.error_measured ? "(RMS measured)" : "") : ("(" + r.excluded + ")").c_str());
    std::cout << line;
  }
  std::cout << "\ndecision:     " << plan.rows[plan.chosen].spec << "\nwhy:          " << plan.reason << "\n";
  return 0;
}

}  // namespace

void register_select_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<SelectCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "select", "Plan a workload: predict every structure's build, ray and update time, memory and error; print them and the choice");
  add_scene_argument(*cmd, options->scene);
  cmd->add_option("--rays", options->rays, "R: rays the workload will trace")->check(number_in(0.0, 1e15))->required();
  cmd->add_option("--kind", options->kind, "Kind of the workload's rays (camera = primary)")
      ->check(CLI::IsMember({"ao", "shadow", "camera", "primary", "random", "path"}))
      ->capture_default_str();
  cmd->add_option("--error", options->error, "E: RMS (0-255) of an AO image allowed against the exact one; 0 = exact structures only")
      ->check(number_in(0.0, 255.0))
      ->capture_default_str();
  cmd->add_option("--updates", options->updates, "U: object moves the workload makes")->check(number_in(0.0, 1e15))->capture_default_str();
  cmd->add_option("--calibration", options->calibration, "Calibration file from `visfield calibrate` (default: built in)");
  cmd->add_option("--sample-rays", options->sample_rays, "Sample rays timed through the grid")
      ->check(number_in(5.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "Seed of the sample rays")->capture_default_str();
  add_resource_options(*cmd, options->threads);
  cmd->callback([options, &action] { action = [options] { return run_select(*options); }; });
}

}  // namespace vf::cli
