#pragma once
/// \file The parallel tile loop every renderer runs its per-pixel work in (non-template, so renderers
/// that are templates over the accelerator stay small).

#include <cstdint>
#include <functional>
#include <string>

#include "visfield/render/render_stats.hpp"

namespace vf {

/// The pixels [x0, x1) x [y0, y1) of an image.
struct ImageTile {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// The pixels a render of a width x height image computes: `region` when it is set (x1 > x0 or
/// y1 > y0), else the whole image. Throws vf::Error when a set region is empty or leaves the image.
ImageTile render_region(const ImageTile& region, int width, int height);

/// Cuts `region` into tile_size x tile_size tiles (row-major from its corner, edge tiles clipped) and calls
/// `shade` once per tile, in parallel over TBB's threads; `shade` returns the rays it traced (by kind) and must
/// only write its own tile's pixels. Shows a ProgressBar labelled `label` ticking per tile when
/// `progress` is set and the loop runs over ~1 s. When `stats` is given, sets its resolution (the region's), the
/// total rays and the wall seconds. Exceptions from `shade` propagate. tile_size must be >= 1.
void for_each_tile(const ImageTile& region, int tile_size, const std::string& label, bool progress,
                   const std::function<RayCounts(const ImageTile&)>& shade, RenderStats* stats);

}  // namespace vf
