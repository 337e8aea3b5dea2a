#include "visfield/render/ao.hpp"

#include "visfield/core/error.hpp"

namespace vf {

void validate_ao_options(const AoOptions& options) {
  if (options.spp < 1) throw Error("ao: spp must be at least 1, got " + std::to_string(options.spp));
  if (options.ao_rays < 1) throw Error("ao: ao_rays must be at least 1, got " + std::to_string(options.ao_rays));
  if (!(options.max_distance > 0.0f))
    throw Error("ao: max_distance must be positive, got " + std::to_string(options.max_distance));
  if (options.psf_level != 0 && (options.psf_level < DirectionLines::kMinLevel || options.psf_level > DirectionLines::kMaxLevel))
    throw Error("ao: psf_level must be 0 or in [2, 6], got " + std::to_string(options.psf_level));
  if (options.tile_size < 1) throw Error("ao: tile_size must be at least 1, got " + std::to_string(options.tile_size));
}

}  // namespace vf
