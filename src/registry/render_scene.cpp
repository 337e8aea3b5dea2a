#include "visfield/registry/render_scene.hpp"

#include <algorithm>
#include <memory>
#include <optional>

#include "visfield/core/direction_lines.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/scene_geometry.hpp"

namespace vf {

std::string occluder_spec(const RenderSettings& s, const Scene& scene) {
  if (!s.occluders.empty() && s.occluders != "field" && s.occluders != "exact")
    throw Error("occluders: expected \"field\", \"exact\" or nothing, got \"" + s.occluders + "\"");
  const bool field_spec = !s.occluder.empty() && find_structure(parse_spec(s.occluder, "occluder ").name, "occluder ").exactness ==
                                                     Exactness::approximate;
  if (s.occluders == "exact" && field_spec) throw Error("occluder " + s.occluder + ": occluders \"exact\" needs an exact structure");
  if (s.occluders == "field" && !s.occluder.empty() && !field_spec)
    throw Error("occluder " + s.occluder + ": occluders \"field\" needs a field:... spec");
  if (s.occluders == "field" && s.occluder.empty()) return "field";
  if (!s.occluders.empty() || !s.occluder.empty()) return s.occluder;
  for (const TriangleMesh& mesh : scene.meshes)
    if (mesh.occluder == MeshOccluder::field) return "field:meshes=marked";
  return "";
}

std::uint64_t rays_per_hit(const RenderSettings& s, const Scene& scene) {
  const auto lights = static_cast<std::uint64_t>(std::max<std::size_t>(1, scene.point_lights.size() + scene.sphere_lights.size()));
  switch (s.integrator) {
    case Integrator::ao: return s.psf_level == 0 ? static_cast<std::uint64_t>(s.ao_rays) : DirectionLines::count(s.psf_level);
    case Integrator::raycast: return 0;
    case Integrator::whitted: return lights + 1;
    case Integrator::softshadow: return lights * static_cast<std::uint64_t>(s.shadow_rays);
    case Integrator::glossy: return lights + static_cast<std::uint64_t>(s.glossy_rays);
    case Integrator::path: return 2 * static_cast<std::uint64_t>(s.depth);  // a bounce and a shadow ray per vertex
  }
  return 1;
}

AoOptions ao_options(const RenderSettings& s) {
  AoOptions ao;
  ao.spp = s.spp;
  ao.ao_rays = s.ao_rays;
  ao.psf_level = s.psf_level;
  ao.max_distance = s.max_distance;
  ao.seed = s.seed;
  ao.progress = s.progress;
  ao.region = s.region;
  return ao;
}

ShadingOptions shading_options(const RenderSettings& s) {
  ShadingOptions o;
  o.spp = s.spp;
  o.seed = s.seed;
  o.progress = s.progress;
  o.max_depth = s.depth;
  o.shadow_rays = s.shadow_rays;
  o.glossy_rays = s.glossy_rays;
  o.ambient = s.ambient;
  o.region = s.region;
  return o;
}

namespace {

void validate(const RenderSettings& s) {
  if (s.width < 0 || s.height < 0) throw Error("render: width and height must be positive (or 0 for the scene camera's)");
  if (s.integrator == Integrator::ao)
    validate_ao_options(ao_options(s));
  else
    validate_shading_options(shading_options(s));
}

}  // namespace

struct SceneRenderer::Built {
  BuiltStructure closest;
  std::optional<BuiltStructure> occluder;
  std::unique_ptr<SceneQueries> queries;
};

SceneRenderer::SceneRenderer(const Scene& scene, const RenderSettings& s, std::uint64_t rays) : scene_(scene) {
  validate(s);
  if (scene.instances().empty() || scene.instanced_triangle_count() == 0) throw Error(scene.name + ": the scene has no triangles");
  SceneGeometry geometry(scene);
  if (rays == 0) {
    const Camera camera = scene.camera_or_default(s.width, s.height);
    const ImageTile region = render_region(s.region, camera.width, camera.height);
    const auto pixels = static_cast<std::uint64_t>(region.x1 - region.x0) * static_cast<std::uint64_t>(region.y1 - region.y0);
    rays = pixels * static_cast<std::uint64_t>(s.spp) * (1u + rays_per_hit(s, scene));
  }
  const BuildContext context{rays, s.progress};
  auto built = std::make_unique<Built>(Built{build_structure(s.accel, geometry, context, "accel "), std::nullopt, nullptr});
  const std::string occluder_choice = occluder_spec(s, scene);
  if (!occluder_choice.empty() && occluder_choice != s.accel) built->occluder = build_structure(occluder_choice, geometry, context, "occluder ");
  built->queries = scene_queries(built->closest.structure, built->occluder ? built->occluder->structure : built->closest.structure);
  built_ = std::move(built);
}

SceneRenderer::~SceneRenderer() = default;

const std::string& SceneRenderer::accel() const { return built_->closest.resolved; }

const std::string& SceneRenderer::occluder() const {
  static const std::string none;
  return built_->occluder ? built_->occluder->resolved : none;
}

double SceneRenderer::build_ms() const {
  return structure_stats(built_->closest.structure).build_ms + (built_->occluder ? structure_stats(built_->occluder->structure).build_ms : 0.0);
}

RenderResult SceneRenderer::render(const RenderSettings& s, const Camera* given) const {
  validate(s);
  const Camera camera = given ? *given : scene_.camera_or_default(s.width, s.height);
  const ImageTile region = render_region(s.region, camera.width, camera.height);
  const double pixels = static_cast<double>(region.x1 - region.x0) * static_cast<double>(region.y1 - region.y0);
  require_memory(pixels * sizeof(Vec3f), "a " + std::to_string(camera.width) + "x" + std::to_string(camera.height) + " image");
  RenderResult result;
  result.accel = accel();
  result.occluder = occluder();
  result.build_ms = build_ms();
  result.image = s.integrator == Integrator::ao ? render_ao(*built_->queries, scene_, camera, ao_options(s), &result.stats)
                                                : render_shaded(s.integrator, *built_->queries, scene_, camera, shading_options(s), &result.stats);
  return result;
}

RenderResult render_scene(const Scene& scene, const RenderSettings& settings) { return SceneRenderer(scene, settings).render(settings); }

}  // namespace vf
