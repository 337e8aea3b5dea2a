// visfield.Renderer, visfield.render(), visfield.compare() and the image files.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include "handles.hpp"
#include "keywords.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/render/compare.hpp"

namespace vf::python {
namespace {

// (height, width, 3), or (height, width, 4) with the alpha channel of a transparent background.
py::array_t<float> to_numpy(const Image& image) {
  const py::ssize_t channels = image.alpha.empty() ? 3 : 4;
  py::array_t<float> out({static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width), channels});
  float* data = out.mutable_data();
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) data[channels * i + c] = image.pixels[i][c];
    if (channels == 4) data[4 * i + 3] = image.alpha[i];
  }
  return out;
}

Image from_numpy(const py::array& array, const char* name) {
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a || a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4))
    throw py::value_error(std::string(name) + ": expected an image of shape (height, width, 3), or (height, width, 4) with alpha");
  const py::ssize_t channels = a.shape(2);
  Image image(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
  if (channels == 4) image.alpha.resize(image.pixels.size());
  const float* data = a.data();
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    image.pixels[i] = {data[channels * i], data[channels * i + 1], data[channels * i + 2]};
    if (channels == 4) image.alpha[i] = data[4 * i + 3];
  }
  return image;
}

// A keyword's value as the command line writes it: a string as it is, a sequence of numbers
// joined by commas ((45, 30) -> "45,30").
std::string option_text(const py::handle& value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  std::string text;
  for (const py::handle item : py::iter(value)) text += (text.empty() ? "" : ",") + py::str(item).cast<std::string>();
  return text;
}

// The type of `value` as Python names it.
std::string type_name(const py::handle& value) { return py::str(value.get_type().attr("__name__")).cast<std::string>(); }

// A keyword that takes a whole number (a Python or NumPy integer, not a bool): TypeError for another
// type, ValueError past the range of int.
int int_keyword(const std::string& key, const py::handle& value) {
  if (py::isinstance<py::bool_>(value) || !py::isinstance(value, py::module_::import("numbers").attr("Integral")))
    throw py::type_error(key + ": expected an integer, got " + type_name(value));
  const py::int_ whole(py::reinterpret_borrow<py::object>(value));
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(whole.ptr(), &overflow);
  if (overflow != 0 || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    throw py::value_error(key + ": " + py::str(value).cast<std::string>() + " is out of range");
  return static_cast<int>(v);
}

// A keyword that takes True or False: TypeError for another type.
bool bool_keyword(const std::string& key, const py::handle& value) {
  if (!py::isinstance<py::bool_>(value) && !py::isinstance(value, py::module_::import("numpy").attr("bool_")))
    throw py::type_error(key + ": expected True or False, got " + type_name(value));
  return py::bool_(py::reinterpret_borrow<py::object>(value)).cast<bool>();
}

// A keyword that takes a spec text or None (empty): TypeError for another type.
std::string text_keyword(const std::string& key, const py::handle& value) {
  if (value.is_none()) return {};
  if (!py::isinstance<py::str>(value)) throw py::type_error(key + ": expected a text or None, got " + type_name(value));
  return value.cast<std::string>();
}

// region=(x0, y0, x1, y1): four integers, x0 < x1 and y0 < y1 (an empty region is a ValueError
// wherever it lies: the library reads (0, 0, 0, 0) as no region).
ImageTile region_keyword(const py::handle& value) {
  if (py::isinstance<py::str>(value) || !py::isinstance<py::sequence>(value))
    throw py::type_error("region: expected (x0, y0, x1, y1), got " + type_name(value));
  const py::sequence items = py::reinterpret_borrow<py::sequence>(value);
  if (items.size() != 4) throw py::value_error("region: expected four integers (x0, y0, x1, y1), got " + std::to_string(items.size()));
  std::array<int, 4> r{};
  for (std::size_t k = 0; k < 4; ++k) r[k] = int_keyword("region", items[k]);
  if (r[2] <= r[0] || r[3] <= r[1])
    throw py::value_error("region: (" + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " + std::to_string(r[2]) + ", " +
                          std::to_string(r[3]) + ") is empty: it needs x0 < x1 and y0 < y1");
  return ImageTile{r[0], r[1], r[2], r[3]};
}

// What render() and Renderer.render() take besides the render settings.
struct Frame {
  std::optional<Camera> camera;
  bool with_stats = false;
};

// Runs `read`; a vf::Error (a value the view or background options refuse) raises ValueError.
template <class Read>
void view_error_as_value_error(Read&& read) {
  try {
    read();
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
}

// render()'s and Renderer.render()'s keyword arguments: the render settings (render_setting_specs(),
// checked by the library), the image size and region, the camera, progress and stats, and with
// `structures` the structure specs. An unknown keyword is a TypeError naming the valid ones.
RenderSettings settings_of(const py::kwargs& kwargs, bool structures, Frame& frame) {
  RenderSettings s;
  std::string written;
  for (const auto& [key_handle, value] : kwargs) {
    const std::string key = key_handle.cast<std::string>();
    if (structures && (key == "accel" || key == "occluder" || key == "occluders")) {
      (key == "accel" ? s.accel : key == "occluder" ? s.occluder : s.occluders) = text_keyword(key, value);
    } else if (key == "width" || key == "height") {
      const int size = int_keyword(key, value);
      if (size < 0) throw py::value_error(key + ": must be positive (or 0 for the scene camera's), got " + std::to_string(size));
      (key == "width" ? s.width : s.height) = size;
    } else if (key == "region") {
      if (value.is_none()) continue;
      s.region = region_keyword(value);
    } else if (key == "camera") {
      if (value.is_none()) continue;
      if (py::isinstance<Camera>(value))
        frame.camera = value.cast<Camera>();
      else
        view_error_as_value_error([&] { s.camera = parse_camera_placement(option_text(value)); });
    } else if (key == "up" || key == "view" || key == "background") {
      if (value.is_none()) continue;
      view_error_as_value_error([&] {
        const std::string text = option_text(value);
        if (key == "up") s.up = parse_up(text);
        else if (key == "view") s.view = parse_view(text);
        else s.background = parse_background(text);
      });
    } else if (key == "progress") {
      s.progress = bool_keyword(key, value);
    } else if (key == "stats") {
      frame.with_stats = bool_keyword(key, value);
    } else {
      bool setting = false;
      for (const RenderSettingSpec& spec : render_setting_specs()) setting = setting || spec.param.key == key;
      if (!setting) {
        std::string valid = structures ? "accel, occluder, occluders, " : "";
        valid += "width, height, region, camera, up, view, background, progress, stats";
        for (const RenderSettingSpec& spec : render_setting_specs()) valid += ", " + std::string(spec.param.key);
        throw py::type_error("unknown keyword argument '" + key + "' (valid: " + valid + ")");
      }
      written += (written.empty() ? "" : ",") + key + "=" + spec_text(key, value);
    }
  }
  RenderSettings checked;
  try {
    checked = with_render_settings(s, written, "render");
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
  // A Camera brings its own image size (width and height were checked as given), which the region is checked against.
  if (frame.camera) checked.width = frame.camera->width, checked.height = frame.camera->height;
  return checked;
}

// The help of the render settings, one line each ("spp=1  camera samples per pixel (...)").
std::string settings_help() {
  std::vector<ParamSpec> params;
  for (const RenderSettingSpec& spec : render_setting_specs()) params.push_back(spec.param);
  return describe_params(params, "  ");
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

}  // namespace

void bind_render(py::module_& m) {
  // Docstrings built from the settings' table, kept for the module's life.
  static const std::string renderer_render_doc =
      "Renders an image (height, width, 3) float32, linear ((height, width, 4) with alpha for background='transparent'). "
      "Keywords: width, height (0: the scene camera's, else 512); region (x0, y0, x1, y1): those pixels only, each equal to "
      "the whole image's; camera: a Camera, or FROM, TO[, UP[, FOV]] as a sequence of 6, 9 or 10 numbers or a string "
      "(replaces the scene camera); up: the world's up axis ('z', '-y'); view: (azimuth, elevation) in degrees around the "
      "framed scene; background: 'transparent', 'white', 'black', 'grey', '#RRGGBB' or (r, g, b) in [0, 1], sRGB "
      "(default '#3A3F47'); progress; "
      "stats=True returns (image, stats): seconds, rays by kind, the structures; and the render settings, as `visfield "
      "render`'s options (default, range):\n" +
      settings_help() + "Deterministic per (seed, pixel, sample). The GIL is released while it runs.";
  static const std::string render_doc =
      "Renders the scene as `visfield render` does (same options, same image): an array (height, width, 3) float32, linear; "
      "with stats=True, (image, stats). Keywords: accel (default bvh), occluder, occluders (field or exact), width, height, "
      "region, camera, up, view, background, progress, stats (as Renderer.render), and the render settings (default, "
      "range):\n" +
      settings_help();
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
          [](const RendererHandle& h, const py::kwargs& kwargs) {
            Frame frame;
            const RenderSettings s = settings_of(kwargs, false, frame);
            const std::shared_ptr<RendererHolder> kept = h.shared();  // alive should another thread close it meanwhile
            return render_with(*kept->renderer, s, frame.camera, frame.with_stats);
          },
          renderer_render_doc.c_str())
      .def("close", &RendererHandle::close)
      .def_property_readonly("closed", &RendererHandle::closed)
      .def("__enter__", [](RendererHandle& h) -> RendererHandle& { return h; })
      .def("__exit__", [](RendererHandle& h, const py::args&) { h.close(); });

  m.def(
      "render",
      [](const SceneHandle& scene, const py::kwargs& kwargs) {
        Frame frame;
        const RenderSettings s = settings_of(kwargs, true, frame);
        const std::shared_ptr<RendererHolder> holder = make_renderer(scene, s, 0);
        return render_with(*holder->renderer, s, frame.camera, frame.with_stats);
      },
      py::arg("scene"), render_doc.c_str());

  m.def(
      "render_settings",
      [] {
        std::vector<ParamSpec> params;
        for (const RenderSettingSpec& spec : render_setting_specs()) params.push_back(spec.param);
        return params_as_dicts(params);
      },
      "The render settings render() and Renderer.render() take, as `visfield render` does: [{key, default, help, expected}, ...].");

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
      py::arg("path"), py::arg("image"),
      "Writes a linear (height, width, 3) image, or (height, width, 4) with straight alpha, as .png (8-bit sRGB) or .exr "
      "(float), atomically.");
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
      py::arg("path"), "Reads a .png or .exr image as linear (height, width, 3) float32, or (height, width, 4) when it has alpha.");
}

}  // namespace vf::python
