#pragma once
/// \file Writing images: PNG (8-bit sRGB, stb) and EXR (linear float, OpenEXR), atomically.

#include <filesystem>

#include "visfield/core/image.hpp"

namespace vf {

/// Writes `image` as PNG (8-bit, sRGB-encoded, clamped) or EXR (32-bit float linear RGB), chosen by
/// the extension (.png / .exr, case-insensitive). Writes a temporary file in the same folder and
/// renames it, so a failure leaves no partial output. Throws vf::Error on an unknown extension or
/// an I/O failure.
void write_image(const std::filesystem::path& path, const Image& image);

/// Reads a PNG or EXR written by write_image back into linear float RGB (for tests and compare).
Image read_image(const std::filesystem::path& path);

}  // namespace vf
