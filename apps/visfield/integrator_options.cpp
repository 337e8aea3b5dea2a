#include "integrator_options.hpp"

#include <algorithm>

#include "cli_support.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/registry.hpp"

namespace vf::cli {

void add_integrator_options(CLI::App& cmd, IntegratorOptions& o, const std::string& integrator) {
  o.integrator = integrator;
  add_structure_option(cmd, "--accel", o.accel,
                       "Structure for camera rays (and every later ray unless --occluder), NAME[:key=value,...]; "
                       "`visfield structures` lists them")
      ->capture_default_str();
  add_structure_option(cmd, "--occluder", o.occluder,
                       "Structure for every ray after the camera's (AO, shadow, reflection), NAME[:key=value,...] "
                       "(default: the --accel one)");
  cmd.add_option("--occluders", o.occluders,
                 "How every ray after the camera's (AO, shadow, reflection) sees the scene's objects: field (ObjectFields "
                 "for every mesh the scene does not mark exact; --occluder may give the field:... parameters) or exact "
                 "(exact geometry only). Default: the scene's own marks (meshes with \"occluder\": \"field\" get fields)")
      ->check(CLI::IsMember({"field", "exact"}));
  cmd.add_option("--integrator", o.integrator,
                 "What to render: raycast (camera rays, diffuse colour lit by the lights, no shadows), whitted (hard "
                 "shadows, mirror reflection and refraction to --depth), ao (ambient occlusion), softshadow (sphere "
                 "lights by --shadow-rays rays each), glossy (direct light and --glossy-rays reflection rays), path "
                 "(path tracing: light sampling with MIS, Russian roulette, --depth bounces)")
      ->check(CLI::IsMember({"raycast", "whitted", "ao", "softshadow", "glossy", "path"}))
      ->capture_default_str();
  cmd.add_option("--spp", o.spp, "Camera samples per pixel")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd.add_option("--ao-rays", o.ao_rays, "ao: rays per camera sample")->check(CLI::Range(1, 65536))->capture_default_str();
  cmd.add_option("--ao-directions", o.ao_directions,
                 "ao: random (--ao-rays cosine-weighted directions), or 33|129|513|2049|8193: one ray along each line of "
                 "that octahedral set, cosine-weighted (VLF-RT's AO; a beam:dirs= of the same count traces them on its "
                 "fast path)")
      ->check(CLI::IsMember({"random", "33", "129", "513", "2049", "8193"}))
      ->capture_default_str();
  cmd.add_option("--max-distance", o.max_distance, "ao: ray length (world units; default unlimited)")
      ->check(positive_number(/*infinity_allowed=*/true));
  cmd.add_option("--depth", o.depth, "whitted: reflection/refraction levels; path: bounces")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd.add_option("--shadow-rays", o.shadow_rays, "softshadow: rays per sphere light per camera sample")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  cmd.add_option("--glossy-rays", o.glossy_rays, "glossy: reflection rays per reflective camera sample")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  cmd.add_option("--ambient", o.ambient, "raycast, whitted, softshadow, glossy: ambient light as a fraction of the diffuse colour")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  cmd.add_option("--seed", o.seed, "Random seed (the image depends on it, not on the thread count)")->capture_default_str();
}

void check_integrator_options(const CLI::App& cmd, const IntegratorOptions& o) {
  // Which integrators read each integrator-specific option; giving it to another is a mistake.
  struct Use {
    const char* option;
    std::initializer_list<const char*> integrators;
  };
  const Use uses[] = {{"--ao-rays", {"ao"}},          {"--ao-directions", {"ao"}},         {"--max-distance", {"ao"}},
                      {"--depth", {"whitted", "path"}}, {"--shadow-rays", {"softshadow"}},  {"--glossy-rays", {"glossy"}},
                      {"--ambient", {"raycast", "whitted", "softshadow", "glossy"}}};
  for (const Use& use : uses) {
    if (cmd.count(use.option) == 0) continue;
    const bool used = std::any_of(use.integrators.begin(), use.integrators.end(), [&](const char* i) { return o.integrator == i; });
    if (!used) {
      std::string which;
      for (const char* i : use.integrators) which += (which.empty() ? "" : ", ") + std::string(i);
      throw CLI::ValidationError(use.option, "only for --integrator " + which + " (this render is " + o.integrator + ")");
    }
  }

  const bool field_spec =
      !o.occluder.empty() && find_structure(parse_spec(o.occluder, "").name).exactness == Exactness::approximate;
  if (o.occluders == "exact" && field_spec)
    throw CLI::ValidationError("--occluder", o.occluder + ": --occluders exact needs an exact structure");
  if (o.occluders == "field" && !o.occluder.empty() && !field_spec)
    throw CLI::ValidationError("--occluder", o.occluder + ": --occluders field needs a field:... spec");
}

std::string occluder_spec(const IntegratorOptions& o, const Scene& scene) { return vf::occluder_spec(render_settings(o, false), scene); }

void add_device_option(CLI::App& cmd, std::string& device) {
  cmd.add_option("--device", device,
                 "Where the secondary rays are traced: cpu, or cuda (the GPU: ambient occlusion rays generated and traced "
                 "on the device, through --occluder's fields or an exact GPU BVH; camera rays stay on the CPU)")
      ->check(CLI::IsMember({"cpu", "cuda"}))
      ->capture_default_str();
}

void check_device_option(const std::string& device, const IntegratorOptions& o) {
  if (device != "cuda") return;
#if !VISFIELD_HAVE_CUDA
  throw CLI::ValidationError("--device", "cuda: this build has no CUDA (configure with -DVISFIELD_CUDA=ON)");
#endif
  if (o.integrator != "ao")
    throw CLI::ValidationError("--device", "cuda renders --integrator ao (the soft-shadow and glossy kernels run in visfield-bench)");
  if (o.ao_directions != "random") throw CLI::ValidationError("--device", "cuda traces random AO directions (--ao-directions random)");
}

int psf_level_of(const IntegratorOptions& o) {
  for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level)
    if (o.ao_directions == std::to_string(DirectionLines::count(level))) return level;
  return 0;
}

Integrator integrator_of(const IntegratorOptions& o) { return *parse_integrator(o.integrator); }

RenderSettings render_settings(const IntegratorOptions& o, bool progress) {
  RenderSettings s;
  s.integrator = integrator_of(o);
  s.accel = o.accel;
  s.occluder = o.occluder;
  s.occluders = o.occluders;
  s.spp = o.spp;
  s.ao_rays = o.ao_rays;
  s.psf_level = psf_level_of(o);
  s.max_distance = static_cast<float>(o.max_distance);
  s.depth = o.depth;
  s.shadow_rays = o.shadow_rays;
  s.glossy_rays = o.glossy_rays;
  s.ambient = static_cast<float>(o.ambient);
  s.seed = o.seed;
  s.progress = progress;
  return s;
}

AoOptions ao_options(const IntegratorOptions& o, bool progress) { return vf::ao_options(render_settings(o, progress)); }

ShadingOptions shading_options(const IntegratorOptions& o, bool progress) { return vf::shading_options(render_settings(o, progress)); }

std::uint64_t rays_per_hit(const IntegratorOptions& o, const Scene& scene) { return vf::rays_per_hit(render_settings(o, false), scene); }

std::string integrator_summary(const IntegratorOptions& o) {
  if (integrator_of(o) != Integrator::ao) return o.integrator;
  return psf_level_of(o) ? "AO along " + o.ao_directions + " lines" : std::to_string(o.ao_rays) + " AO rays";
}

}  // namespace vf::cli
