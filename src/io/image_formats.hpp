#pragma once
// Private to the io module: one writer and one reader per image format. Writers write exactly the
// path they are given (write_image makes that path a temporary sibling); errors name `path`.

#include <filesystem>

#include "visfield/core/image.hpp"

namespace vf::io_detail {

/// 8-bit sRGB RGB PNG through stb_image_write.
void write_png(const std::filesystem::path& path, const Image& image);
/// Any PNG stb_image decodes, converted to linear RGB.
Image read_png(const std::filesystem::path& path);
/// 32-bit float RGB EXR through OpenEXR.
void write_exr(const std::filesystem::path& path, const Image& image);
/// R, G, B channels of an EXR as float.
Image read_exr(const std::filesystem::path& path);

}  // namespace vf::io_detail
