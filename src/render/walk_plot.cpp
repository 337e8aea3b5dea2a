// The walkthrough plot as SVG: text, so any browser shows it and no font is rasterised here.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/render/walkthrough.hpp"

namespace vf {
namespace {

const char* const kPalette[] = {"#d91a1a", "#1a59d9", "#1a9933", "#e68c00", "#8c33b3", "#009aa6", "#666666"};

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

// `text` with the five characters XML reserves escaped.
std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string walk_plot_svg(const std::vector<WalkSeries>& series, int width, int height) {
  if (width < 320 || height < 200) throw Error("plot: at least 320 x 200 pixels, got " + std::to_string(width) + " x " + std::to_string(height));
  if (series.empty()) throw Error("plot: no series");
  int frames = 2;
  double top = 0.0;
  for (const WalkSeries& s : series)
    for (const WalkFrame& f : s.frames) {
      frames = std::max(frames, f.frame + 1);
      top = std::max(top, f.update_ms + f.trace_ms);
    }
  const double step = nice_step(top > 0.0 ? top * 1.05 : 1.0);
  top = step * std::ceil((top > 0.0 ? top * 1.05 : 1.0) / step);
  const double left = 80, right = width - 20, upper = 50, lower = height - 50;
  const auto px = [&](double frame) { return left + (right - left) * frame / (frames - 1); };
  const auto py = [&](double ms) { return lower - (lower - upper) * ms / top; };
  std::ostringstream svg;
  svg.setf(std::ios::fixed);
  svg.precision(1);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height << "\" viewBox=\"0 0 " << width
      << ' ' << height << "\" font-family=\"sans-serif\" font-size=\"13\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (double v = 0.0; v <= top + 1e-9; v += step) {
    svg << "<line x1=\"" << left << "\" y1=\"" << py(v) << "\" x2=\"" << right << "\" y2=\"" << py(v) << "\" stroke=\"#e0e0e0\"/>"
        << "<text x=\"" << left - 8 << "\" y=\"" << py(v) + 4 << "\" text-anchor=\"end\">" << number(v) << "</text>\n";
  }
  const double frame_step = std::max(1.0, nice_step(frames - 1));
  for (double f = 0.0; f <= frames - 1 + 1e-9; f += frame_step)
    svg << "<line x1=\"" << px(f) << "\" y1=\"" << lower << "\" x2=\"" << px(f) << "\" y2=\"" << lower + 5 << "\" stroke=\"black\"/>"
        << "<text x=\"" << px(f) << "\" y=\"" << lower + 20 << "\" text-anchor=\"middle\">" << number(f) << "</text>\n";
  svg << "<polyline points=\"" << left << ',' << upper << ' ' << left << ',' << lower << ' ' << right << ',' << lower
      << "\" fill=\"none\" stroke=\"black\"/>\n"
      << "<text x=\"" << left << "\" y=\"" << upper - 20 << "\">ms per frame (solid: update + trace, dotted: update)</text>\n"
      << "<text x=\"" << right << "\" y=\"" << lower + 40 << "\" text-anchor=\"end\">frame</text>\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const char* colour = kPalette[k % std::size(kPalette)];
    const std::vector<WalkFrame>& fs = series[k].frames;
    bool updates = false;
    svg << "<polyline class=\"frame\" fill=\"none\" stroke-width=\"2\" stroke=\"" << colour << "\" points=\"";
    for (const WalkFrame& f : fs) {
      svg << px(f.frame) << ',' << py(f.update_ms + f.trace_ms) << ' ';
      updates = updates || f.update_ms > 0.0;
    }
    svg << "\"/>\n";
    if (updates) {
      svg << "<polyline class=\"update\" fill=\"none\" stroke-dasharray=\"4 4\" stroke=\"" << colour << "\" points=\"";
      for (const WalkFrame& f : fs) svg << px(f.frame) << ',' << py(f.update_ms) << ' ';
      svg << "\"/>\n";
    }
    // The legend, top right, one row per series.
    const double y = upper + 14 + 20.0 * static_cast<double>(k);
    svg << "<line x1=\"" << right - 230 << "\" y1=\"" << y - 4 << "\" x2=\"" << right - 210 << "\" y2=\"" << y - 4
        << "\" stroke-width=\"3\" stroke=\"" << colour << "\"/><text x=\"" << right - 202 << "\" y=\"" << y << "\">"
        << escaped(series[k].label) << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace vf
