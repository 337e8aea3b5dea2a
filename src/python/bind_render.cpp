// visfield.Renderer, visfield.render(), visfield.compare() and the image files.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include "handles.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/render/compare.hpp"

namespace vf::python {
namespace {

py::array_t<float> to_numpy(const Image& image) {
  py::array_t<float> out({static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width), py::ssize_t{3}});
  std::memcpy(out.mutable_data(), image.pixels.data(), image.pixels.size() * sizeof(Vec3f));
  return out;
}

Image from_numpy(const py::array& array, const char* name) {
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a || a.ndim() != 3 || a.shape(2) != 3) throw py::value_error(std::string(name) + ": expected an image of shape (height, width, 3)");
  Image image(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
  std::memcpy(static_cast<void*>(image.pixels.data()), a.data(), image.pixels.size() * sizeof(Vec3f));
  return image;
}

// The settings of render()'s keyword arguments (the names and defaults of `visfield render`).
RenderSettings settings_of(const std::string& integrator, const std::string& accel, const std::optional<std::string>& occluder,
                           const std::optional<std::string>& occluders, int width, int height, const std::optional<std::array<int, 4>>& region,
                           int spp, int ao_rays, const std::string& ao_directions, double max_distance, int depth, int shadow_rays,
                           int glossy_rays, double ambient, std::uint64_t seed, bool progress) {
  RenderSettings s;
  const std::optional<Integrator> which = parse_integrator(integrator);
  if (!which) throw py::value_error("integrator: expected raycast, whitted, ao, softshadow, glossy or path, got '" + integrator + "'");
  s.integrator = *which;
  s.accel = accel;
  s.occluder = occluder.value_or("");
  s.occluders = occluders.value_or("");
  s.width = width, s.height = height;
  if (region) s.region = ImageTile{(*region)[0], (*region)[1], (*region)[2], (*region)[3]};
  s.spp = spp, s.ao_rays = ao_rays, s.depth = depth, s.shadow_rays = shadow_rays, s.glossy_rays = glossy_rays;
  s.max_distance = static_cast<float>(max_distance);
  s.ambient = static_cast<float>(ambient);
  s.seed = seed;
  s.progress = progress;
  if (ao_directions != "random") {
    for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level)
      if (ao_directions == std::to_string(DirectionLines::count(level))) s.psf_level = level;
    if (s.psf_level == 0) throw py::value_error("ao_directions: expected 'random', '33', '129', '513', '2049' or '8193', got '" + ao_directions + "'");
  }
  return s;
}

// Runs `body` without the GIL; a vf::Error about the settings (not memory, not a signal) raises ValueError.
template <class Body>
void settings_errors_as_value_errors(Body&& body) {
  try {
    py::gil_scoped_release release;
    body();
  } catch (const MemoryRefused&) {
    throw;
  } catch (const Interrupted&) {
    throw;
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
}

// One render through `renderer`: the image, or (image, stats) with `with_stats`.
py::object render_with(const SceneRenderer& renderer, const RenderSettings& s, const std::optional<Camera>& camera, bool with_stats) {
  RenderResult result;
  settings_errors_as_value_errors([&] { result = renderer.render(s, camera ? &*camera : nullptr); });
  if (!with_stats) return to_numpy(result.image);
  py::dict stats;
  const RenderStats& st = result.stats;
  stats["seconds"] = st.seconds, stats["rays"] = st.rays, stats["camera_rays"] = st.by_kind.camera, stats["shadow_rays"] = st.by_kind.shadow;
  stats["reflection_rays"] = st.by_kind.reflection, stats["ao_rays"] = st.by_kind.ao;
  stats["accel"] = result.accel, stats["occluder"] = result.occluder, stats["build_ms"] = result.build_ms;
  return py::make_tuple(to_numpy(result.image), stats);
}

std::shared_ptr<RendererHolder> make_renderer(const SceneHandle& scene, const RenderSettings& s, std::uint64_t rays) {
  auto holder = std::make_shared<RendererHolder>();
  holder->scene = scene.shared();
  settings_errors_as_value_errors([&] { holder->renderer = std::make_unique<SceneRenderer>(*holder->scene, s, rays); });
  return holder;
}

#define VF_RENDER_ARGS                                                                                                               \
  py::arg("integrator") = "ao", py::arg("width") = 0, py::arg("height") = 0, py::arg("region") = py::none(), py::arg("camera") = py::none(), \
      py::arg("spp") = 1, py::arg("ao_rays") = 64, py::arg("ao_directions") = "random",                                              \
      py::arg("max_distance") = std::numeric_limits<double>::infinity(), py::arg("depth") = 5, py::arg("shadow_rays") = 20,           \
      py::arg("glossy_rays") = 4, py::arg("ambient") = 0.1, py::arg("seed") = 1, py::arg("progress") = false, py::arg("stats") = false

}  // namespace

void bind_render(py::module_& m) {
  py::class_<RendererHandle>(m, "Renderer",
                             "A scene's structures built once by role (camera rays through `accel`, every later ray through the occluder), "
                             "rendering any number of images: frames of a camera path, regions of one image, several integrators.")
      .def(py::init([](const SceneHandle& scene, const std::string& accel, const std::optional<std::string>& occluder,
                       const std::optional<std::string>& occluders, std::uint64_t rays, bool progress) {
             RenderSettings s;
             s.accel = accel, s.occluder = occluder.value_or(""), s.occluders = occluders.value_or(""), s.progress = progress;
             return RendererHandle(make_renderer(scene, s, rays == 0 ? 1'000'000 : rays), "renderer");
           }),
           py::arg("scene"), py::arg("accel") = "bvh", py::arg("occluder") = py::none(), py::arg("occluders") = py::none(),
           py::arg("rays") = 0, py::arg("progress") = false,
           "Builds the structures (the scene must not change while the renderer lives). `rays`: how many the renders will trace, "
           "for accel='auto' (0: a million).")
      .def_property_readonly("accel", [](const RendererHandle& h) { return h.get().renderer->accel(); })
      .def_property_readonly("occluder", [](const RendererHandle& h) { return h.get().renderer->occluder(); })
      .def_property_readonly("build_ms", [](const RendererHandle& h) { return h.get().renderer->build_ms(); })
      .def(
          "render",
          [](const RendererHandle& h, const std::string& integrator, int width, int height, const std::optional<std::array<int, 4>>& region,
             const std::optional<Camera>& camera, int spp, int ao_rays, const std::string& ao_directions, double max_distance, int depth,
             int shadow_rays, int glossy_rays, double ambient, std::uint64_t seed, bool progress, bool with_stats) {
            const RenderSettings s = settings_of(integrator, "bvh", std::nullopt, std::nullopt, width, height, region, spp, ao_rays, ao_directions,
                                                 max_distance, depth, shadow_rays, glossy_rays, ambient, seed, progress);
            return render_with(*h.get().renderer, s, camera, with_stats);
          },
          VF_RENDER_ARGS,
          "Renders an image (height, width, 3) float32, linear. `region` (x0, y0, x1, y1) renders those pixels only, each equal to the "
          "whole image's; `camera` replaces the scene camera. With stats=True, (image, stats): seconds, rays by kind, the structures. "
          "Deterministic per (seed, pixel, sample). The GIL is released while it runs.")
      .def("close", &RendererHandle::close)
      .def_property_readonly("closed", &RendererHandle::closed)
      .def("__enter__", [](RendererHandle& h) -> RendererHandle& { return h; })
      .def("__exit__", [](RendererHandle& h, const py::args&) { h.close(); });

  m.def(
      "render",
      [](const SceneHandle& scene, const std::string& integrator, const std::string& accel, const std::optional<std::string>& occluder,
         const std::optional<std::string>& occluders, int width, int height, const std::optional<std::array<int, 4>>& region,
         const std::optional<Camera>& camera, int spp, int ao_rays, const std::string& ao_directions, double max_distance, int depth,
         int shadow_rays, int glossy_rays, double ambient, std::uint64_t seed, bool progress, bool with_stats) {
        const RenderSettings s = settings_of(integrator, accel, occluder, occluders, width, height, region, spp, ao_rays, ao_directions,
                                             max_distance, depth, shadow_rays, glossy_rays, ambient, seed, progress);
        const std::shared_ptr<RendererHolder> holder = make_renderer(scene, s, 0);
        return render_with(*holder->renderer, s, camera, with_stats);
      },
      py::arg("scene"), py::arg("integrator") = "ao", py::arg("accel") = "bvh", py::arg("occluder") = py::none(),
      py::arg("occluders") = py::none(), py::arg("width") = 0, py::arg("height") = 0, py::arg("region") = py::none(),
      py::arg("camera") = py::none(), py::arg("spp") = 1, py::arg("ao_rays") = 64, py::arg("ao_directions") = "random",
      py::arg("max_distance") = std::numeric_limits<double>::infinity(), py::arg("depth") = 5, py::arg("shadow_rays") = 20,
      py::arg("glossy_rays") = 4, py::arg("ambient") = 0.1, py::arg("seed") = 1, py::arg("progress") = false, py::arg("stats") = false,
      "Renders the scene as `visfield render` does (same options, same image): an array (height, width, 3) float32, linear; with "
      "stats=True, (image, stats).");

  m.def(
      "compare",
      [](const py::array& image, const py::array& reference) {
        const Image a = from_numpy(image, "image"), b = from_numpy(reference, "reference");
        ImageDifference d;
        try {
          d = compare_images(a, b);
        } catch (const Error& e) {
          throw py::value_error(e.what());
        }
        py::dict out;
        out["rms"] = d.rms, out["rms_255"] = 255.0 * d.rms, out["max"] = d.max_abs, out["max_255"] = 255.0 * d.max_abs, out["psnr_db"] = d.psnr_db;
        return out;
      },
      py::arg("image"), py::arg("reference"),
      "How far `image` is from `reference` (both (height, width, 3)): rms and max on the 0-1 scale and on 0-255 (rms_255, max_255), PSNR in dB.");

  m.def(
      "write_image",
      [](const std::string& path, const py::array& image) {
        const Image img = from_numpy(image, "image");
        py::gil_scoped_release release;
        write_image(path, img);
      },
      py::arg("path"), py::arg("image"), "Writes a linear (height, width, 3) image as .png (8-bit sRGB) or .exr (float), atomically.");
  m.def(
      "read_image",
      [](const std::string& path) {
        Image img;
        {
          py::gil_scoped_release release;
          img = read_image(path);
        }
        return to_numpy(img);
      },
      py::arg("path"), "Reads a .png or .exr image as linear (height, width, 3) float32.");
}

}  // namespace vf::python
