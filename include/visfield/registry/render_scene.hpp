#pragma once
/// \file One render of a scene from structure specs, as `visfield render` does it: the structures
/// are built by role from the registry (camera rays through `accel`, every later ray through the
/// occluder), then the integrator runs. For library callers that do not want to wire the roles
/// themselves: the Python module's render() and the distributed renders.

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "visfield/core/image.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/integrators.hpp"
#include "visfield/render/render_stats.hpp"
#include "visfield/render/view.hpp"

namespace vf {

/// What to render and through which structures. Defaults are `visfield render`'s.
struct RenderSettings {
  Integrator integrator = Integrator::ao;
  std::string accel = "bvh";  ///< Structure spec for camera rays (registry syntax).
  std::string occluder;       ///< Structure spec for every later ray; "" = see `occluders`, else `accel`'s structure.
  std::string occluders;      ///< "field" (fields for every mesh not marked exact), "exact", or "" (fields where the scene marks meshes).
  int width = 0;              ///< Image width in pixels; 0 = the scene camera's (else 512).
  int height = 0;             ///< Image height in pixels; 0 = the scene camera's (else 512).
  ImageTile region{};         ///< Pixels to render (unset = all); the result is the region (render_region()).
  int spp = 1;                ///< Camera samples per pixel.
  int ao_rays = 64;           ///< ao: random rays per hit.
  int psf_level = 0;          ///< ao: 0, or one ray along each line of the level-L octahedral set (AoOptions::psf_level).
  float max_distance = std::numeric_limits<float>::infinity();  ///< ao: ray length.
  int depth = 5;              ///< whitted levels, path bounces.
  int shadow_rays = 20;       ///< softshadow: rays per sphere light per sample.
  int glossy_rays = 4;        ///< glossy: reflection rays per reflective sample.
  float ambient = 0.1f;       ///< raycast, whitted, softshadow, glossy: ambient fraction of the diffuse colour.
  std::uint64_t seed = 1;     ///< The image depends on it, never on the thread count or the region.
  bool progress = false;      ///< Progress bars on stderr (precomputes, long renders).
  std::optional<Vec3f> up;                ///< The world's up axis (parse_up()); given alone, the default view around it.
  std::optional<ViewAngles> view;         ///< Azimuth and elevation around the framed scene (parse_view(), framed_view()).
  std::optional<CameraPlacement> camera;  ///< FROM, TO[, UP[, FOV]] (parse_camera_placement()); wins over `view`.
  Background background = default_background();  ///< What shows where camera rays miss (parse_background()).
};

/// One render setting as every front end takes it: `param` holds its key (the Python keyword; the
/// command line's option is "--" + key with '_' written '-'), type, default (RenderSettings{}'s, as a
/// test checks), help and range; `integrators` names those that read it ("ao", "whitted|path"; ""
/// for every one).
struct RenderSettingSpec {
  ParamSpec param;
  std::string_view integrators;
};

/// The render settings, declared once: integrator, spp, ao_rays, ao_directions, max_distance, depth,
/// shadow_rays, glossy_rays, ambient, seed. `visfield render` and `visfield walk`, the Python
/// module's render() and Renderer.render() take their names, defaults, ranges and help from here.
std::span<const RenderSettingSpec> render_setting_specs();

/// `base` with the settings "key=value,..." gives written over it (render_setting_specs()' keys,
/// checked against their ranges). Throws a one-line vf::Error starting with `where` on an unknown
/// key or a bad value.
RenderSettings with_render_settings(RenderSettings base, std::string_view settings, const std::string& where);

/// Setting `key` of `settings` written as render_setting_specs() writes values ("64", "inf",
/// "random", "ao"). Throws vf::Error for a key that is not a render setting.
std::string render_setting_text(const RenderSettings& settings, std::string_view key);

/// The occluder spec `settings` choose for `scene` ("" = the accel structure answers every ray):
/// occluders "field" asks for fields (the `occluder` field spec, or the default) for every mesh
/// the scene does not mark exact, "exact" for exact geometry only; with neither, a scene that marks
/// meshes "occluder": "field" gets fields for those. Throws vf::Error when `occluders` is not
/// field, exact or empty, or contradicts `occluder` (an exact spec with "field", a field spec with "exact").
std::string occluder_spec(const RenderSettings& settings, const Scene& scene);

/// Upper bound of the rays a camera sample that hits traces after the camera ray. O(1).
std::uint64_t rays_per_hit(const RenderSettings& settings, const Scene& scene);

/// The AO integrator's options from `settings`.
AoOptions ao_options(const RenderSettings& settings);

/// The shading integrators' options from `settings`.
ShadingOptions shading_options(const RenderSettings& settings);

/// The camera `settings` choose for `scene`: view_camera() of their up, view, camera, width and height.
Camera render_camera(const Scene& scene, const RenderSettings& settings);

/// Puts settings.background behind `image`, rendered through `queries` from `camera` with `settings`
/// (its integrator, spp, seed and region): put_background() with the image's camera_coverage(), which
/// traces one camera ray per sample again (skipped when the background is what the integrator left).
void put_render_background(Image& image, const SceneQueries& queries, const Camera& camera, const RenderSettings& settings);

/// A render and what it ran on.
struct RenderResult {
  Image image;               ///< Linear radiance (AO: unoccluded fraction), the region's size; alpha when transparent.
  RenderStats stats;         ///< Rays by kind, seconds.
  std::string accel;         ///< The camera-ray structure as resolved ("bvh:levels=1").
  std::string occluder;      ///< The occluder as resolved ("" = the accel structure).
  double build_ms = 0.0;     ///< Build time of the structures together.
};

/// The structures of one scene, built once by role, rendering any number of images through them:
/// the frames of a walk whose objects stay put, the regions of one image, several integrators.
class SceneRenderer {
 public:
  /// Builds the structures `settings` name (accel, occluder, occluders) over `scene`, which must
  /// outlive this and not change while it lives; the memory estimate is checked first. `rays`: what
  /// the renders will trace, for `auto` (0: one render of `settings`). Throws vf::Error on a bad
  /// spec or a failed build, vf::Interrupted on a signal.
  SceneRenderer(const Scene& scene, const RenderSettings& settings, std::uint64_t rays = 0);
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  /// Renders with `settings`' integrator, options, region and background (its structure specs are
  /// ignored) from `camera`, or render_camera() when null. Deterministic per
  /// (seed, pixel, sample). Thread-safe: renders may run at once. Throws vf::Error on bad settings.
  RenderResult render(const RenderSettings& settings, const Camera* camera = nullptr) const;

  /// The camera-ray structure as resolved ("bvh:levels=1").
  const std::string& accel() const;
  /// The occluder as resolved ("" = the accel structure answers every ray).
  const std::string& occluder() const;
  /// Build time of the structures together, in milliseconds.
  double build_ms() const;

 private:
  struct Built;
  const Scene& scene_;
  std::unique_ptr<Built> built_;
};

/// SceneRenderer(scene, settings).render(settings): builds the structures `settings` name over `scene`
/// (memory checked first) and renders its camera with `settings.integrator`. Throws as both do.
RenderResult render_scene(const Scene& scene, const RenderSettings& settings);

}  // namespace vf
