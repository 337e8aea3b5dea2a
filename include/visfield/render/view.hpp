#pragma once
/// \file How a render looks at a scene and what it shows behind it, as `visfield render --up --view
/// --camera --background` and Python's render() take them: the texts they accept, the camera they
/// choose, and the background put where camera rays miss (a colour, or alpha 0).

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/image.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/tiles.hpp"

namespace vf {

/// Azimuth and elevation in degrees around the framed scene (framed_view()).
struct ViewAngles {
  float azimuth = kDefaultAzimuth;
  float elevation = kDefaultElevation;
};

/// A camera given by where it stands and what it looks at; the up direction and the vertical field
/// of view are optional (the render's up axis and the scene camera's fov, else 45°, when absent).
struct CameraPlacement {
  Vec3f from;
  Vec3f to;
  std::optional<Vec3f> up;
  std::optional<float> fov_degrees;
};

/// What shows where camera rays miss every object.
struct Background {
  Vec3f color{0.0f};         ///< Linear RGB.
  bool transparent = false;  ///< Alpha 0 there instead: the image gets an alpha channel (Image::alpha).
};

/// The default background: a dark slate (sRGB #3A3F47), apart from AO's white and from black.
Background default_background();

/// "x", "y", "z" with an optional sign ("+z", "-y"; either case) as a unit axis. Throws a one-line
/// vf::Error "up: expected ..." otherwise.
Vec3f parse_up(std::string_view text);

/// "AZIMUTH,ELEVATION" in degrees (finite; elevation within [-90, 90]). Throws a one-line vf::Error.
ViewAngles parse_view(std::string_view text);

/// "FROM,TO[,UP[,FOV]]": 6, 9 or 10 numbers (FROM != TO, UP not parallel to TO - FROM, FOV in (0, 180)
/// degrees). Throws a one-line vf::Error.
CameraPlacement parse_camera_placement(std::string_view text);

/// "transparent", a name (white, black, grey/gray), "#RRGGBB" or "R,G,B" in [0, 1] (both sRGB, as a
/// colour picker writes them). Throws a one-line vf::Error.
Background parse_background(std::string_view text);

/// The camera a render uses: `placement` when given (its up, else `up`, else +Y; its fov, else the
/// scene camera's, else 45°); else, when `up` or `angles` are given, framed_view() of the scene from
/// `angles` (default: the three-quarter view) around `up` (default +Y) with the scene camera's fov;
/// else the scene's camera (Scene::camera_or_default()). `width`/`height` > 0 replace the camera's.
/// Throws vf::Error on a placement the pinhole camera refuses.
Camera view_camera(const Scene& scene, const std::optional<Vec3f>& up, const std::optional<ViewAngles>& angles,
                   const std::optional<CameraPlacement>& placement, int width, int height);

/// The fraction of each pixel's camera samples (as the integrators draw them: Rng(seed, pixel, s),
/// jittered when spp > 1) that hit an object through `queries`' camera structure, for the pixels of
/// `region` (render_region()), row-major. Parallel; the same for any thread count.
std::vector<float> camera_coverage(const SceneQueries& queries, const Camera& camera, int spp, std::uint64_t seed,
                                   const ImageTile& region);

/// Puts `background` behind `image`, whose missed samples were rendered as `rendered` (AO's white,
/// the shading integrators' black): an opaque colour replaces `rendered` in proportion to each pixel's
/// uncovered fraction; a transparent one sets Image::alpha to `coverage` and the colour to that of the
/// covered samples alone (0 where nothing is covered). `coverage` is camera_coverage() of the image.
void put_background(Image& image, const std::vector<float>& coverage, const Vec3f& rendered, const Background& background);

}  // namespace vf
