#include "visfield/registry/render_scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>

#include "visfield/core/direction_lines.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/scene_geometry.hpp"

namespace vf {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The render settings (render_setting_specs()). Their defaults are RenderSettings{}'s; a test holds
// them to it.
constexpr RenderSettingSpec kRenderSettings[] = {
    {{"integrator", ParamType::choice, "ao",
      "what to render: raycast (camera rays, diffuse colour lit by the lights, no shadows), whitted (hard shadows, mirror "
      "reflection and refraction to depth), ao (ambient occlusion), softshadow (sphere lights by shadow_rays rays each), "
      "glossy (direct light and glossy_rays reflection rays), path (path tracing: light sampling with MIS, Russian "
      "roulette, depth bounces)",
      0, 0, "raycast|whitted|ao|softshadow|glossy|path"},
     ""},
    {{"spp", ParamType::whole, "1", "camera samples per pixel (jittered when more than 1)", 1, 4096}, ""},
    {{"ao_rays", ParamType::whole, "64", "rays per camera sample", 1, 65536}, "ao"},
    {{"ao_directions", ParamType::choice, "random",
      "random (ao_rays cosine-weighted directions), or 33|129|513|2049|8193: one ray along each line of that octahedral "
      "set, cosine-weighted (VLF-RT's AO; a beam:dirs= of the same count traces them on its fast path)",
      0, 0, "random|33|129|513|2049|8193"},
     "ao"},
    {{"max_distance", ParamType::number, "inf", "ray length in world units", 0.0, kInfinity, {}, true}, "ao"},
    {{"depth", ParamType::whole, "5", "whitted: reflection and refraction levels; path: bounces", 1, 64}, "whitted|path"},
    {{"shadow_rays", ParamType::whole, "20", "rays per sphere light per camera sample", 1, 65536}, "softshadow"},
    {{"glossy_rays", ParamType::whole, "4", "reflection rays per reflective camera sample", 1, 65536}, "glossy"},
    {{"ambient", ParamType::number, "0.1", "ambient light as a fraction of the diffuse colour", 0.0, 100.0},
     "raycast|whitted|softshadow|glossy"},
    {{"seed", ParamType::whole, "1", "random seed (the image depends on it, never on the thread count)", 0, 0}, ""},
};

constexpr auto kRenderParams = [] {
  std::array<ParamSpec, std::size(kRenderSettings)> params{};
  for (std::size_t i = 0; i < params.size(); ++i) params[i] = kRenderSettings[i].param;
  return params;
}();

// "inf", or the shortest text that reads back as the float `v`.
std::string number_text(float v) {
  if (std::isinf(v)) return "inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", static_cast<double>(v));
  return text;
}

}  // namespace

std::span<const RenderSettingSpec> render_setting_specs() { return kRenderSettings; }

RenderSettings with_render_settings(RenderSettings s, std::string_view settings, const std::string& where) {
  if (settings.empty()) return s;
  const ParamValues p = read_params(parse_spec("render:" + std::string(settings), ""), kRenderParams, where);
  if (p.given("integrator")) s.integrator = *parse_integrator(p.text("integrator"));
  if (p.given("spp")) s.spp = static_cast<int>(p.whole("spp"));
  if (p.given("ao_rays")) s.ao_rays = static_cast<int>(p.whole("ao_rays"));
  if (p.given("ao_directions")) {
    s.psf_level = 0;
    for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level)
      if (p.text("ao_directions") == std::to_string(DirectionLines::count(level))) s.psf_level = level;
  }
  if (p.given("max_distance")) s.max_distance = static_cast<float>(p.number("max_distance"));
  if (p.given("depth")) s.depth = static_cast<int>(p.whole("depth"));
  if (p.given("shadow_rays")) s.shadow_rays = static_cast<int>(p.whole("shadow_rays"));
  if (p.given("glossy_rays")) s.glossy_rays = static_cast<int>(p.whole("glossy_rays"));
  if (p.given("ambient")) s.ambient = static_cast<float>(p.number("ambient"));
  if (p.given("seed")) s.seed = p.whole("seed");
  return s;
}

std::string render_setting_text(const RenderSettings& s, std::string_view key) {
  if (key == "integrator") return std::string(integrator_name(s.integrator));
  if (key == "spp") return std::to_string(s.spp);
  if (key == "ao_rays") return std::to_string(s.ao_rays);
  if (key == "ao_directions") return s.psf_level == 0 ? "random" : std::to_string(DirectionLines::count(s.psf_level));
  if (key == "max_distance") return number_text(s.max_distance);
  if (key == "depth") return std::to_string(s.depth);
  if (key == "shadow_rays") return std::to_string(s.shadow_rays);
  if (key == "glossy_rays") return std::to_string(s.glossy_rays);
  if (key == "ambient") return number_text(s.ambient);
  if (key == "seed") return std::to_string(s.seed);
  throw Error("render setting '" + std::string(key) + "': no such setting");
}

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

Camera render_camera(const Scene& scene, const RenderSettings& s) { return view_camera(scene, s.up, s.view, s.camera, s.width, s.height); }

void put_render_background(Image& image, const SceneQueries& queries, const Camera& camera, const RenderSettings& s) {
  const Vec3f rendered{s.integrator == Integrator::ao ? kAoBackground : 0.0f};
  const Background& b = s.background;
  if (!b.transparent && b.color.x == rendered.x && b.color.y == rendered.y && b.color.z == rendered.z) return;
  const ImageTile region = render_region(s.region, camera.width, camera.height);
  put_background(image, camera_coverage(queries, camera, s.spp, s.seed, region), rendered, b);
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
    const Camera camera = render_camera(scene, s);
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
  const Camera camera = given ? *given : render_camera(scene_, s);
  const ImageTile region = render_region(s.region, camera.width, camera.height);
  const double pixels = static_cast<double>(region.x1 - region.x0) * static_cast<double>(region.y1 - region.y0);
  require_memory(pixels * sizeof(Vec3f), "a " + std::to_string(camera.width) + "x" + std::to_string(camera.height) + " image");
  RenderResult result;
  result.accel = accel();
  result.occluder = occluder();
  result.build_ms = build_ms();
  result.image = s.integrator == Integrator::ao ? render_ao(*built_->queries, scene_, camera, ao_options(s), &result.stats)
                                                : render_shaded(s.integrator, *built_->queries, scene_, camera, shading_options(s), &result.stats);
  put_render_background(result.image, *built_->queries, camera, s);
  return result;
}

RenderResult render_scene(const Scene& scene, const RenderSettings& settings) { return SceneRenderer(scene, settings).render(settings); }

}  // namespace vf
