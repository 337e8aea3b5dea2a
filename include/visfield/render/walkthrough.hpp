#pragma once
/// \file Walkthroughs: a scene's keyframed camera and objects rendered frame by frame, each frame's
/// structure update and render timed (the VLF-RT paper's Figure 6), the times kept as CSV and drawn
/// as a plot. The structures are behind an interface, so the CLI (registry structures) and
/// visfield-bench (Embree too) run the same loop.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/image.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/integrators.hpp"

namespace vf {

/// What a walkthrough renders through: structures that follow the scene's objects from frame to frame.
class WalkStructures {
 public:
  virtual ~WalkStructures() = default;
  /// Brings the structures to `scene`'s current placements after the objects `moved` changed (none
  /// in a camera-only walk: nothing to do). Returns true when it rebuilt (a BeamField that rebuilt
  /// itself because an object left its sphere included), false when it updated in place.
  virtual bool follow(const Scene& scene, std::span<const ObjectId> moved) = 0;
  /// The queries of the current structures (valid until the next follow()).
  virtual const SceneQueries& queries() const = 0;
  /// The structures' name for tables and plots ("beam:dirs=513,n=128", "embree").
  virtual std::string label() const = 0;
};

/// One frame's times.
struct WalkFrame {
  int frame = 0;
  double update_ms = 0.0;  ///< Moving the objects in the structures (0 for a camera-only walk).
  double trace_ms = 0.0;   ///< Rendering the frame.
  std::uint64_t rays = 0;  ///< Rays the frame traced.
  bool rebuilt = false;    ///< The structures were rebuilt rather than updated in place.
};

/// A walkthrough's frames under one label (one line of a plot).
struct WalkSeries {
  std::string label;
  std::vector<WalkFrame> frames;
};

/// How to render a walkthrough.
struct WalkOptions {
  int frames = 60;                          ///< Frames (>= 2), spread evenly over the animation's time span.
  Integrator integrator = Integrator::raycast;
  ShadingOptions shading;                   ///< For every integrator but ao (spp, seed, depth, lights' rays).
  AoOptions ao;                             ///< For Integrator::ao.
  int width = 256, height = 256;            ///< Frame size in pixels.
  std::function<void(int, const Image&)> on_frame;  ///< Called with each frame's image (optional).
};

/// Frame `frame` of `frames` (>= 2) of `scene.animation`, at time t0 + (t1 - t0) frame / (frames - 1)
/// over the animation's time span: places every object that has a path (Scene::set_transform) and
/// returns the camera at that time (`base`'s field of view and size, the path's position, target and
/// up; `base` itself when there is no camera path). Throws vf::Error when the scene does not move or
/// frame is outside [0, frames).
Camera place_frame(Scene& scene, const Camera& base, int frame, int frames);

/// Renders frames 0 .. frames-1 of `scene.animation`: frame f at time t0 + (t1 - t0) f / (frames - 1)
/// over the animation's time span. Per frame: every object with a path is placed
/// (Scene::set_transform), `structures` follow them (timed: update_ms), and the camera at that time
/// (the scene camera's field of view, at width x height) renders the frame (timed: trace_ms).
/// Throws vf::Error when the scene has no animation or the options are out of range.
std::vector<WalkFrame> render_walkthrough(Scene& scene, WalkStructures& structures, const WalkOptions& options);

/// Writes `series` as CSV: a first line "# visfield walk: LABEL", then "frame,update_ms,trace_ms,rays,rebuilt"
/// and one row per frame; atomically (temporary file, then rename). Throws vf::Error on failure.
void write_walk_csv(const std::filesystem::path& path, const WalkSeries& series);
/// Reads a CSV that write_walk_csv() wrote; throws vf::Error naming the file, line and problem.
WalkSeries read_walk_csv(const std::filesystem::path& path);

/// The plot of the VLF-RT paper's Figure 6 as an SVG document: milliseconds per frame against the
/// frame, one colour per series: solid the frame time (update + trace), dashed the update alone
/// (where not zero), with axes, ticks and a legend; width x height (at least 320 x 200). Throws
/// vf::Error on a smaller size or no series.
std::string walk_plot_svg(const std::vector<WalkSeries>& series, int width = 900, int height = 500);

/// Throws vf::Error unless `path` names an SVG file (".svg") that can be written, before any work.
void check_walk_plot_path(const std::filesystem::path& path);
/// Writes walk_plot_svg(series) to `path` (".svg") atomically. Throws vf::Error naming the file.
void write_walk_plot(const std::filesystem::path& path, const std::vector<WalkSeries>& series);

}  // namespace vf
