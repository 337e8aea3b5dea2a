#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <exception>
#include <string>
#include <vector>

#include "file_checks.hpp"
#include "image_formats.hpp"
#include "visfield/core/error.hpp"

namespace vf::io_detail {
namespace {

constexpr const char* kChannels[3] = {"R", "G", "B"};

// Slices for the three float channels of `pixels`, laid out as Image stores them.
Imf::FrameBuffer rgb_frame_buffer(const Vec3f* pixels, const Imath::Box2i& window) {
  Imf::FrameBuffer frame;
  for (int c = 0; c < 3; ++c) {
    const char* base = reinterpret_cast<const char*>(pixels) + c * sizeof(float);
    frame.insert(kChannels[c], Imf::Slice::Make(Imf::FLOAT, base, window, sizeof(Vec3f)));
  }
  return frame;
}

}  // namespace

void write_exr(const std::filesystem::path& path, const Image& image) {
  try {
    Imf::Header header(image.width, image.height);
    for (const char* name : kChannels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    // EXR's colour is premultiplied by its alpha.
    std::vector<Vec3f> premultiplied;
    if (!image.alpha.empty()) {
      header.channels().insert("A", Imf::Channel(Imf::FLOAT));
      premultiplied.resize(image.pixels.size());
      for (std::size_t i = 0; i < image.pixels.size(); ++i) premultiplied[i] = image.pixels[i] * image.alpha[i];
    }
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer frame = rgb_frame_buffer(image.alpha.empty() ? image.pixels.data() : premultiplied.data(), header.dataWindow());
    if (!image.alpha.empty())
      frame.insert("A", Imf::Slice::Make(Imf::FLOAT, image.alpha.data(), header.dataWindow(), sizeof(float)));
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw Error(path.string() + ": cannot write EXR: " + one_line(e.what()));
  }
}

Image read_exr(const std::filesystem::path& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const long long width = static_cast<long long>(window.max.x) - window.min.x + 1;
    const long long height = static_cast<long long>(window.max.y) - window.min.y + 1;
    if (width <= 0 || height <= 0 || width * height > (1ll << 31))
      throw Error(path.string() + ": EXR data window of " + std::to_string(width) + "x" + std::to_string(height) +
                  " pixels is out of range");
    Image image(static_cast<int>(width), static_cast<int>(height));
    Imf::FrameBuffer frame = rgb_frame_buffer(image.pixels.data(), window);
    const bool with_alpha = file.header().channels().findChannel("A") != nullptr;
    if (with_alpha) {
      image.alpha.resize(image.pixels.size());
      frame.insert("A", Imf::Slice::Make(Imf::FLOAT, image.alpha.data(), window, sizeof(float)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (with_alpha)
      for (std::size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = image.alpha[i] > 0.0f ? image.pixels[i] * (1.0f / image.alpha[i]) : Vec3f{0.0f};
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(path.string() + ": malformed EXR: " + one_line(e.what()));
  }
}

}  // namespace vf::io_detail
