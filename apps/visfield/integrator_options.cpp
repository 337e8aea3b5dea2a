#include "integrator_options.hpp"

#include <algorithm>

#include "cli_support.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/registry.hpp"

namespace vf::cli {

void add_integrator_options(CLI::App& cmd, IntegratorOptions& o, const std::string& integrator) {
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
  for (const RenderSettingSpec& spec : render_setting_specs()) add_param_option(cmd, spec.param, o.values[std::string(spec.param.key)]);
  o.values.at("integrator") = integrator;
  cmd.get_option("--integrator")->default_str(integrator);
}

void check_integrator_options(const CLI::App& cmd, IntegratorOptions& o) {
  std::string written;
  for (const auto& [key, value] : o.values) written += (written.empty() ? "" : ",") + key + "=" + value;
  try {
    o.settings = with_render_settings({}, written, "render settings");
  } catch (const Error& e) {
    throw CLI::ValidationError("render settings", e.what());  // the options' own checks refuse first
  }
  // An integrator-specific option given to another integrator is a mistake.
  for (const RenderSettingSpec& spec : render_setting_specs()) {
    std::string option = "--" + std::string(spec.param.key);
    std::replace(option.begin(), option.end(), '_', '-');
    if (spec.integrators.empty() || cmd.count(option) == 0) continue;
    bool used = false;
    std::string which;
    for (std::size_t start = 0; start <= spec.integrators.size();) {
      const std::size_t end = std::min(spec.integrators.find('|', start), spec.integrators.size());
      const std::string_view name = spec.integrators.substr(start, end - start);
      used = used || name == o.integrator();
      which += (which.empty() ? "" : ", ") + std::string(name);
      start = end + 1;
    }
    if (!used) throw CLI::ValidationError(option, "only for --integrator " + which + " (this render is " + o.integrator() + ")");
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
  if (o.integrator() != "ao")
    throw CLI::ValidationError("--device", "cuda renders --integrator ao (the soft-shadow and glossy kernels run in visfield-bench)");
  if (o.values.at("ao_directions") != "random")
    throw CLI::ValidationError("--device", "cuda traces random AO directions (--ao-directions random)");
}

Integrator integrator_of(const IntegratorOptions& o) { return o.settings.integrator; }

RenderSettings render_settings(const IntegratorOptions& o, bool progress) {
  RenderSettings s = o.settings;
  s.accel = o.accel;
  s.occluder = o.occluder;
  s.occluders = o.occluders;
  s.progress = progress;
  return s;
}

AoOptions ao_options(const IntegratorOptions& o, bool progress) { return vf::ao_options(render_settings(o, progress)); }

ShadingOptions shading_options(const IntegratorOptions& o, bool progress) { return vf::shading_options(render_settings(o, progress)); }

std::uint64_t rays_per_hit(const IntegratorOptions& o, const Scene& scene) { return vf::rays_per_hit(render_settings(o, false), scene); }

std::string integrator_summary(const IntegratorOptions& o) {
  if (integrator_of(o) != Integrator::ao) return o.integrator();
  return o.settings.psf_level ? "AO along " + o.values.at("ao_directions") + " lines" : std::to_string(o.settings.ao_rays) + " AO rays";
}

}  // namespace vf::cli
