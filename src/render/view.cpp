#include "visfield/render/view.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"

namespace vf {
namespace {

std::string lower(std::string_view text) {
  std::string s(text);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// An sRGB channel in [0, 1], as the 8-bit code a PNG of it holds, in linear light.
float srgb_to_linear(double c) { return decode_srgb8(static_cast<std::uint8_t>(std::lround(c * 255.0))); }

// `text` in double quotes, for messages.
std::string quoted(std::string_view text) {
  std::string q(1, '"');
  q.append(text);
  q.push_back('"');
  return q;
}

Vec3f vec_at(const std::vector<double>& n, std::size_t i) {
  return Vec3f{static_cast<float>(n[i]), static_cast<float>(n[i + 1]), static_cast<float>(n[i + 2])};
}

}  // namespace

Background default_background() { return Background{Vec3f{decode_srgb8(0x3A), decode_srgb8(0x3F), decode_srgb8(0x47)}, false}; }

Vec3f parse_up(std::string_view text) {
  std::string s = lower(text);
  float sign = 1.0f;
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
    sign = s[0] == '-' ? -1.0f : 1.0f;
    s.erase(0, 1);
  }
  if (s == "x") return Vec3f{sign, 0.0f, 0.0f};
  if (s == "y") return Vec3f{0.0f, sign, 0.0f};
  if (s == "z") return Vec3f{0.0f, 0.0f, sign};
  throw Error("up: expected an axis x, y or z with an optional sign (+z, -y), got " + quoted(text));
}

ViewAngles parse_view(std::string_view text) {
  const std::optional<std::vector<double>> n = parse_number_list(text);
  if (!n || n->size() != 2)
    throw Error("view: expected AZIMUTH,ELEVATION in degrees (two numbers, \"45,30\"), got " + quoted(text));
  if (!std::isfinite(static_cast<float>((*n)[0]))) throw Error("view: the azimuth must be a finite number of degrees, got " + quoted(text));
  if (!((*n)[1] >= -90.0 && (*n)[1] <= 90.0))
    throw Error("view: the elevation must be within [-90, 90] degrees, got " + quoted(text));
  return ViewAngles{static_cast<float>((*n)[0]), static_cast<float>((*n)[1])};
}

CameraPlacement parse_camera_placement(std::string_view text) {
  const std::string given = quoted(text);
  const std::optional<std::vector<double>> n = parse_number_list(text);
  if (!n || (n->size() != 6 && n->size() != 9 && n->size() != 10))
    throw Error("camera: expected FROM,TO[,UP[,FOV]] (6, 9 or 10 numbers: \"0,1,5,0,0,0\"), got " + given);
  CameraPlacement placement{vec_at(*n, 0), vec_at(*n, 3), std::nullopt, std::nullopt};
  const Vec3f view = placement.to - placement.from;
  if (!(length(view) > 0.0f)) throw Error("camera: FROM and TO coincide in " + given);
  if (n->size() >= 9) {
    placement.up = vec_at(*n, 6);
    if (!(length(cross(normalize(view), *placement.up)) > 1e-6f * length(*placement.up)))
      throw Error("camera: UP is zero or parallel to TO - FROM in " + given);
  }
  if (n->size() == 10) {
    placement.fov_degrees = static_cast<float>((*n)[9]);
    if (!(*placement.fov_degrees > 0.0f && *placement.fov_degrees < 180.0f))
      throw Error("camera: the field of view must be in (0, 180) degrees, got " + given);
  }
  return placement;
}

Background parse_background(std::string_view text) {
  const std::string s = lower(text);
  if (s == "transparent") return Background{Vec3f{0.0f}, true};
  if (s == "white") return Background{Vec3f{1.0f}, false};
  if (s == "black") return Background{Vec3f{0.0f}, false};
  if (s == "grey" || s == "gray") return Background{Vec3f{srgb_to_linear(0.5)}, false};
  const std::string expected = "background: expected transparent, white, black, grey, #RRGGBB or R,G,B in [0, 1], got " + quoted(text);
  if (s.size() == 7 && s[0] == '#' && std::all_of(s.begin() + 1, s.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; })) {
    const auto channel = [&](int i) { return decode_srgb8(static_cast<std::uint8_t>(std::stoi(s.substr(1 + 2 * i, 2), nullptr, 16))); };
    return Background{Vec3f{channel(0), channel(1), channel(2)}, false};
  }
  const std::optional<std::vector<double>> n = parse_number_list(text);
  if (!n || n->size() != 3 || !std::all_of(n->begin(), n->end(), [](double c) { return c >= 0.0 && c <= 1.0; })) throw Error(expected);
  return Background{Vec3f{srgb_to_linear((*n)[0]), srgb_to_linear((*n)[1]), srgb_to_linear((*n)[2])}, false};
}

Camera view_camera(const Scene& scene, const std::optional<Vec3f>& up, const std::optional<ViewAngles>& angles,
                   const std::optional<CameraPlacement>& placement, int width, int height) {
  if (!placement && !up && !angles) return scene.camera_or_default(width, height);
  Camera camera = scene.camera.value_or(Camera{});
  if (width > 0) camera.width = width;
  if (height > 0) camera.height = height;
  if (!placement) {
    const ViewAngles a = angles.value_or(ViewAngles{});
    return framed_view(scene, up.value_or(Vec3f{0.0f, 1.0f, 0.0f}), a.azimuth, a.elevation, camera.fov_degrees, camera.width, camera.height);
  }
  camera.position = placement->from;
  camera.look_at = placement->to;
  camera.up = placement->up.value_or(up.value_or(Vec3f{0.0f, 1.0f, 0.0f}));
  camera.fov_degrees = placement->fov_degrees.value_or(camera.fov_degrees);
  if (!(length(cross(normalize(camera.look_at - camera.position), camera.up)) > 1e-6f))
    throw Error("camera: the up axis is parallel to TO - FROM (give UP, or another up axis)");
  return camera;
}

std::vector<float> camera_coverage(const SceneQueries& queries, const Camera& camera, int spp, std::uint64_t seed,
                                   const ImageTile& region) {
  const PinholeCamera pinhole(camera);
  const int width = region.x1 - region.x0;
  std::vector<float> coverage(static_cast<std::size_t>(width) * static_cast<std::size_t>(region.y1 - region.y0));
  vf::parallel_for(tbb::blocked_range<int>(region.y0, region.y1, 1), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = region.x0; x < region.x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(pinhole.width()) + static_cast<std::uint64_t>(x);
        int hits = 0;
        for (int s = 0; s < spp; ++s) {
          Rng rng(seed, pixel, static_cast<std::uint64_t>(s));
          if (queries.intersect_camera(pixel_ray(pinhole, x, y, spp > 1, rng))) ++hits;
        }
        coverage[static_cast<std::size_t>(y - region.y0) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x - region.x0)] =
            static_cast<float>(hits) / static_cast<float>(spp);
      }
  });
  return coverage;
}

void put_background(Image& image, const std::vector<float>& coverage, const Vec3f& rendered, const Background& background) {
  if (coverage.size() != image.pixels.size()) throw Error("background: the coverage does not match the image's size");
  if (background.transparent) image.alpha = coverage;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const float c = coverage[i];
    if (c == 1.0f) continue;
    Vec3f& p = image.pixels[i];
    if (!background.transparent)
      p = c == 0.0f ? background.color : p + (background.color - rendered) * (1.0f - c);
    else
      p = c > 0.0f ? (p - rendered * (1.0f - c)) * (1.0f / c) : Vec3f{0.0f};
  }
}

}  // namespace vf
