#pragma once
/// \file Float RGB(A) images, the output of every renderer.

#include <cstddef>
#include <vector>

#include "visfield/core/vec.hpp"

namespace vf {

/// Linear float RGB image, row-major, row 0 at the top, with an optional alpha channel. Value type.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<Vec3f> pixels;  ///< width * height entries.
  /// Empty: opaque. Else width * height coverages in [0, 1]; `pixels` then hold the covered part's own
  /// colour (straight, not premultiplied, alpha; PNG stores it so, EXR premultiplied).
  std::vector<float> alpha;

  Image() = default;
  /// A black image of the given size.
  Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h)) {}
  /// Pixel (x, y), no bounds check.
  Vec3f& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  /// Pixel (x, y), no bounds check.
  const Vec3f& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

}  // namespace vf
