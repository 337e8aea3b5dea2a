#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "bitmap_font.hpp"
#include "visfield/core/error.hpp"
#include "visfield/render/walkthrough.hpp"

namespace vf {
namespace {

constexpr int kTextScale = 2;  // font pixels are drawn 2 x 2
const Vec3f kPalette[] = {{0.85f, 0.1f, 0.1f}, {0.1f, 0.35f, 0.85f}, {0.1f, 0.6f, 0.2f},
                          {0.9f, 0.55f, 0.0f}, {0.55f, 0.2f, 0.7f}, {0.0f, 0.6f, 0.65f}, {0.4f, 0.4f, 0.4f}};

class Canvas {
 public:
  Canvas(int w, int h) : image(w, h) { std::fill(image.pixels.begin(), image.pixels.end(), Vec3f{1.0f}); }
  void dot(int x, int y, const Vec3f& c) {
    if (x >= 0 && y >= 0 && x < image.width && y < image.height) image.at(x, y) = c;
  }
  void box(int x0, int y0, int x1, int y1, const Vec3f& c) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) dot(x, y, c);
  }
  // A line `thick` pixels wide; with `dotted`, only every other run of 4 pixels.
  void line(int x0, int y0, int x1, int y1, const Vec3f& c, int thick, bool dotted) {
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (int step = 0;; ++step) {
      if (!dotted || (step / 4) % 2 == 0) box(x0 - thick / 2, y0 - thick / 2, x0 + (thick - 1) / 2, y0 + (thick - 1) / 2, c);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) err += dy, x0 += sx;
      if (e2 <= dx) err += dx, y0 += sy;
    }
  }
  // Text with its top-left corner at (x, y).
  void text(int x, int y, const std::string& s, const Vec3f& c) {
    for (char ch : s) {
      const std::string_view g = render_detail::glyph(ch);
      for (int r = 0; r < render_detail::kGlyphHeight; ++r)
        for (int k = 0; k < render_detail::kGlyphWidth; ++k)
          if (g[static_cast<std::size_t>(r * render_detail::kGlyphWidth + k)] == '#')
            box(x + k * kTextScale, y + r * kTextScale, x + (k + 1) * kTextScale - 1, y + (r + 1) * kTextScale - 1, c);
      x += (render_detail::kGlyphWidth + 1) * kTextScale;
    }
  }
  static int text_width(const std::string& s) { return static_cast<int>(s.size()) * (render_detail::kGlyphWidth + 1) * kTextScale; }
  Image image;
};

// A round step (1, 2 or 5 times a power of ten) that cuts [0, top] into about five intervals.
double nice_step(double top) {
  const double raw = top / 5.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) return m * power;
  return 10.0 * power;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, v == std::floor(v) ? "%.0f" : "%.1f", v);
  return text;
}

}  // namespace

Image plot_walk(const std::vector<WalkSeries>& series, int width, int height) {
  if (width < 320 || height < 200) throw Error("plot: at least 320 x 200 pixels, got " + std::to_string(width) + " x " + std::to_string(height));
  if (series.empty()) throw Error("plot: no series");
  Canvas canvas(width, height);
  const Vec3f ink{0.0f}, grid{0.88f};
  int frames = 2;
  double top = 0.0;
  for (const WalkSeries& s : series)
    for (const WalkFrame& f : s.frames) {
      frames = std::max(frames, f.frame + 1);
      top = std::max(top, f.update_ms + f.trace_ms);
    }
  const double step = nice_step(top > 0.0 ? top * 1.05 : 1.0);
  top = step * std::ceil((top > 0.0 ? top * 1.05 : 1.0) / step);
  const int left = 80, right = width - 20, upper = 50, lower = height - 50;
  auto px = [&](double frame) { return left + static_cast<int>(std::lround((right - left) * frame / (frames - 1))); };
  auto py = [&](double ms) { return lower - static_cast<int>(std::lround((lower - upper) * ms / top)); };
  for (double v = 0.0; v <= top + 1e-9; v += step) {
    canvas.line(left, py(v), right, py(v), grid, 1, false);
    const std::string label = number(v);
    canvas.text(left - 8 - Canvas::text_width(label), py(v) - 7, label, ink);
  }
  const double frame_step = std::max(1.0, nice_step(frames - 1));
  for (double f = 0.0; f <= frames - 1 + 1e-9; f += frame_step) {
    canvas.line(px(f), lower, px(f), lower + 5, ink, 1, false);
    const std::string label = number(f);
    canvas.text(px(f) - Canvas::text_width(label) / 2, lower + 10, label, ink);
  }
  canvas.line(left, upper, left, lower, ink, 1, false);
  canvas.line(left, lower, right, lower, ink, 1, false);
  canvas.text(left, 14, "ms per frame (solid: update + trace, dotted: update)", ink);
  canvas.text(right - Canvas::text_width("frame"), lower + 30, "frame", ink);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Vec3f& colour = kPalette[k % std::size(kPalette)];
    const std::vector<WalkFrame>& fs = series[k].frames;
    for (std::size_t i = 1; i < fs.size(); ++i) {
      canvas.line(px(fs[i - 1].frame), py(fs[i - 1].update_ms + fs[i - 1].trace_ms), px(fs[i].frame),
                  py(fs[i].update_ms + fs[i].trace_ms), colour, 2, false);
      if (fs[i - 1].update_ms > 0.0 || fs[i].update_ms > 0.0)
        canvas.line(px(fs[i - 1].frame), py(fs[i - 1].update_ms), px(fs[i].frame), py(fs[i].update_ms), colour, 1, true);
    }
    if (fs.size() == 1) canvas.box(px(fs[0].frame) - 2, py(fs[0].trace_ms) - 2, px(fs[0].frame) + 2, py(fs[0].trace_ms) + 2, colour);
    // The legend, top right, one row per series.
    const int y = upper + 8 + static_cast<int>(k) * 20;
    const int x = right - 10 - Canvas::text_width(series[k].label) - 30;
    canvas.box(x, y + 5, x + 20, y + 8, colour);
    canvas.text(x + 28, y, series[k].label, ink);
  }
  return canvas.image;
}

}  // namespace vf
