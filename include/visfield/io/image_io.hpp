#pragma once
/// \file Writing images: PNG (8-bit sRGB, stb) and EXR (linear float, OpenEXR), atomically.

#include <cstdint>
#include <filesystem>

#include "visfield/core/image.hpp"

namespace vf {

/// Writes `image` as PNG (8-bit, sRGB-encoded, clamped) or EXR (32-bit float linear RGB), with an
/// alpha channel when Image::alpha is set (PNG RGBA; EXR A, the colour premultiplied), chosen by
/// the extension (.png / .exr, case-insensitive). Writes a temporary file in the same folder and
/// renames it, so a failure leaves no partial output. Throws vf::Error on an unknown extension or
/// an I/O failure.
void write_image(const std::filesystem::path& path, const Image& image);

/// Reads a PNG or EXR written by write_image back into linear float RGB (for tests and compare).
/// PNG values are decoded from sRGB; EXR channels R, G, B are read as float (missing ones are 0). An
/// alpha channel (PNG grey+alpha or RGBA, EXR A) is read into Image::alpha, the colour unpremultiplied.
/// Throws vf::Error naming the file on a missing, unreadable or malformed file.
Image read_image(const std::filesystem::path& path);

/// Linear value to an 8-bit sRGB code: clamped to [0, 1] (NaN as 0), sRGB transfer curve, rounded.
std::uint8_t encode_srgb8(float linear);

/// 8-bit sRGB code to its linear value in [0, 1] (exact inverse of the transfer curve).
float decode_srgb8(std::uint8_t code);

}  // namespace vf
