#include "visfield/render/walkthrough.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "visfield/core/error.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/io/atomic_file.hpp"

namespace vf {
namespace {

constexpr const char* kCsvHeader = "frame,update_ms,trace_ms,rays,rebuilt";
constexpr const char* kCsvTitle = "# visfield walk: ";

}  // namespace

Camera place_frame(Scene& scene, const Camera& base, int frame, int frames) {
  if (frames < 2) throw Error("walk: frames must be at least 2, got " + std::to_string(frames));
  if (frame < 0 || frame >= frames) throw Error("walk: frame " + std::to_string(frame) + " is not in [0, " + std::to_string(frames) + ")");
  if (scene.animation.empty())
    throw Error("walk: " + (scene.name.empty() ? std::string("the scene") : scene.name) +
                " has no \"camera_path\" and no object \"keyframes\"; nothing moves");
  const auto [t0, t1] = scene.animation.time_span();
  const float time = t0 + (t1 - t0) * static_cast<float>(frame) / static_cast<float>(frames - 1);
  for (const ObjectPath& path : scene.animation.objects) scene.set_transform(path.object, SceneAnimation::placement_at(path, time));
  Camera camera = base;
  if (!scene.animation.camera.empty()) {
    const CameraKey key = scene.animation.camera_at(time);
    camera.position = key.position;
    camera.look_at = key.look_at;
    camera.up = key.up;
  }
  return camera;
}

std::vector<WalkFrame> render_walkthrough(Scene& scene, WalkStructures& structures, const WalkOptions& options) {
  if (options.frames < 2) throw Error("walk: frames must be at least 2, got " + std::to_string(options.frames));
  const Camera base = scene.camera_or_default(options.width, options.height);
  std::vector<ObjectId> moving;
  for (const ObjectPath& path : scene.animation.objects) moving.push_back(path.object);
  std::vector<WalkFrame> frames;
  for (int f = 0; f < options.frames; ++f) {
    WalkFrame frame;
    frame.frame = f;
    const Camera camera = place_frame(scene, base, f, options.frames);
    const Stopwatch update;
    // Every frame follows when anything moves, frame 0 too: the structures were built over the
    // placements the scene file gives, which the first keys may change.
    frame.rebuilt = moving.empty() ? false : structures.follow(scene, moving);
    frame.update_ms = moving.empty() ? 0.0 : update.elapsed_ms();
    RenderStats stats;
    const Image image = options.integrator == Integrator::ao
                            ? render_ao(structures.queries(), scene, camera, options.ao, &stats)
                            : render_shaded(options.integrator, structures.queries(), scene, camera, options.shading, &stats);
    frame.trace_ms = stats.seconds * 1000.0;
    frame.rays = stats.rays;
    frames.push_back(frame);
    if (options.on_frame) options.on_frame(f, image);
  }
  return frames;
}

void write_walk_csv(const std::filesystem::path& path, const WalkSeries& series) {
  std::ostringstream text;
  text << kCsvTitle << series.label << "\n" << kCsvHeader << "\n";
  for (const WalkFrame& f : series.frames) {
    char row[160];
    std::snprintf(row, sizeof row, "%d,%.4f,%.4f,%llu,%d\n", f.frame, f.update_ms, f.trace_ms,
                  static_cast<unsigned long long>(f.rays), f.rebuilt ? 1 : 0);
    text << row;
  }
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_file_bytes(tmp, text.str()); });
}

void check_walk_plot_path(const std::filesystem::path& path) {
  if (path.extension() != ".svg")
    throw Error(path.string() + ": the plot is written as SVG: name it .svg (for a PNG, plot the --csv files with "
                                "/usr/bin/python3 -m visfield.plot, which needs python3-matplotlib)");
  check_writable(path);
}

void write_walk_plot(const std::filesystem::path& path, const std::vector<WalkSeries>& series) {
  check_walk_plot_path(path);
  const std::string svg = walk_plot_svg(series);
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_file_bytes(tmp, svg); });
}

WalkSeries read_walk_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot read");
  WalkSeries series;
  std::string line;
  auto fail = [&](int number, const std::string& problem) {
    throw Error(path.string() + ": line " + std::to_string(number) + ": " + problem);
  };
  if (!std::getline(in, line) || !line.starts_with(kCsvTitle)) fail(1, "not a visfield walk CSV (expected \"# visfield walk: LABEL\")");
  series.label = line.substr(std::char_traits<char>::length(kCsvTitle));
  if (!std::getline(in, line) || line != kCsvHeader) fail(2, std::string("expected the header \"") + kCsvHeader + "\"");
  for (int number = 3; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    WalkFrame f;
    unsigned long long rays = 0;
    int rebuilt = 0, used = 0;
    if (std::sscanf(line.c_str(), "%d,%lf,%lf,%llu,%d%n", &f.frame, &f.update_ms, &f.trace_ms, &rays, &rebuilt, &used) != 5 ||
        used != static_cast<int>(line.size()) || f.frame < 0 || !(f.update_ms >= 0.0) || !(f.trace_ms >= 0.0) ||
        f.update_ms > 1e12 || f.trace_ms > 1e12 || (rebuilt != 0 && rebuilt != 1))
      fail(number, "expected frame,update_ms,trace_ms,rays,rebuilt (non-negative numbers), got \"" + line.substr(0, 80) + "\"");
    f.rays = rays;
    f.rebuilt = rebuilt == 1;
    series.frames.push_back(f);
  }
  if (series.frames.empty()) throw Error(path.string() + ": no frames");
  return series;
}

}  // namespace vf
