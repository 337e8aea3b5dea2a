#pragma once
/// \file How far one image is from another: the figures approximate structures are judged by.

#include "visfield/core/image.hpp"

namespace vf {

/// Differences of an image from a reference, over every channel of every pixel.
struct ImageDifference {
  double rms = 0.0;        ///< Root mean square of the differences.
  double max_abs = 0.0;    ///< Largest absolute difference.
  double psnr_db = 0.0;    ///< 10 log10(1 / rms^2) for values in [0, 1]; +infinity for identical images.
};

/// `image` against `reference`; throws vf::Error when their sizes differ. O(pixels).
ImageDifference compare_images(const Image& image, const Image& reference);

}  // namespace vf
