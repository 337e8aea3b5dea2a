// PNG and EXR round trips, and the no-partial-output guarantee of write_image / write_atomically.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>

#include "io_test_support.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/io/image_io.hpp"

namespace vf {
namespace {

using test::expect_one_line_error;
using test::TempDir;
using test::write_file;

// A gradient over [-0.25, 1.25] in x, a different one in y, and a constant blue channel: covers
// values the PNG clamps, the sRGB linear segment near 0 and the power segment.
Image gradient(int width, int height) {
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at(x, y) = {-0.25f + 1.5f * x / (width - 1), static_cast<float>(y) / (height - 1) * 0.01f, 0.5f};
  return image;
}

std::size_t file_count(const std::filesystem::path& folder) {
  return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(folder), {}));
}

std::string read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The sRGB transfer curve, written independently of the library's.
double srgb(double linear) {
  const double v = std::clamp(linear, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

TEST(ImageIo, ExrRoundTripIsExact) {
  TempDir dir;
  Image image = gradient(37, 23);
  image.at(3, 4) = {1e6f, -3.5f, 1e-30f};
  write_image(dir / "g.exr", image);
  const Image back = read_image(dir / "g.exr");
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) ASSERT_EQ(back.pixels[i], image.pixels[i]) << "pixel " << i;
}

TEST(ImageIo, PngRoundTripWithinOneSrgbStep) {
  TempDir dir;
  const Image image = gradient(64, 16);
  write_image(dir / "G.PNG", image);  // the extension is case-insensitive
  const Image back = read_image(dir / "G.PNG");
  ASSERT_EQ(back.width, 64);
  ASSERT_EQ(back.height, 16);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(srgb(back.pixels[i][c]), srgb(image.pixels[i][c]), 0.5 / 255 + 1e-6) << "pixel " << i << " channel " << c;
  EXPECT_EQ(back.at(0, 0).x, 0.0f);   // -0.25 clamped
  EXPECT_EQ(back.at(63, 0).x, 1.0f);  // 1.25 clamped
}

TEST(ImageIo, SrgbCodesRoundTrip) {
  for (int code = 0; code < 256; ++code) EXPECT_EQ(encode_srgb8(decode_srgb8(static_cast<std::uint8_t>(code))), code);
  EXPECT_EQ(encode_srgb8(std::nanf("")), 0);
  EXPECT_EQ(encode_srgb8(0.5f), 188);  // 255 * srgb(0.5) = 187.5..., rounded
}

TEST(ImageIo, UnknownExtensionWritesNothing) {
  TempDir dir;
  expect_one_line_error([&] { write_image(dir / "x.bmp", gradient(4, 4)); }, "unknown image format");
  expect_one_line_error([&] { read_image(dir / "x.jpg"); }, "unknown image format");
  EXPECT_EQ(file_count(dir.path()), 0u);
}

TEST(ImageIo, NonexistentFolderThrowsAndLeavesNothing) {
  TempDir dir;
  const auto target = dir / "missing/out.png";
  expect_one_line_error([&] { write_image(target, gradient(4, 4)); }, target.string());
  EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
  EXPECT_EQ(file_count(dir.path()), 0u);
}

TEST(ImageIo, EmptyImageIsRefused) {
  TempDir dir;
  expect_one_line_error([&] { write_image(dir / "e.exr", Image{}); }, "empty image");
  EXPECT_EQ(file_count(dir.path()), 0u);
}

TEST(ImageIo, TargetThatIsAFolderIsRefused) {
  TempDir dir;
  std::filesystem::create_directory(dir / "taken.png");
  expect_one_line_error([&] { write_image(dir / "taken.png", gradient(4, 4)); }, "taken.png");
  EXPECT_EQ(file_count(dir.path()), 1u);
}

TEST(ImageIo, MalformedFilesAreRefused) {
  TempDir dir;
  expect_one_line_error([&] { read_image(dir / "none.png"); }, "none.png: no such file");
  write_file(dir / "bad.png", "definitely not a png");
  expect_one_line_error([&] { read_image(dir / "bad.png"); }, "bad.png: malformed PNG");
  write_file(dir / "bad.exr", "definitely not an exr file");
  expect_one_line_error([&] { read_image(dir / "bad.exr"); }, "bad.exr: malformed EXR");
}

TEST(AtomicFile, ThrowingWriteLeavesTheTargetUntouched) {
  TempDir dir;
  const auto target = write_file(dir / "keep.txt", "original");
  EXPECT_THROW(write_atomically(target,
                                [](const std::filesystem::path& temp) {
                                  write_file_bytes(temp, "half-written");
                                  throw std::runtime_error("disk on fire");
                                }),
               std::runtime_error);
  EXPECT_EQ(read_all(target), "original");
  EXPECT_EQ(file_count(dir.path()), 1u);  // the temporary is gone
}

TEST(AtomicFile, ErrorsNameTheTargetNotTheTemporary) {
  TempDir dir;
  const auto target = dir / "out.bin";
  const std::string message = expect_one_line_error(
      [&] {
        write_atomically(target, [](const std::filesystem::path& temp) { throw Error(temp.string() + ": broken"); });
      },
      target.string() + ": broken");
  EXPECT_EQ(message.find(".tmp-"), std::string::npos) << message;
  EXPECT_EQ(file_count(dir.path()), 0u);
}

TEST(AtomicFile, SuccessfulWriteReplacesTheTarget) {
  TempDir dir;
  const auto target = write_file(dir / "data.txt", "old");
  write_atomically(target, [](const std::filesystem::path& temp) { write_file_bytes(temp, "new contents"); });
  EXPECT_EQ(read_all(target), "new contents");
  EXPECT_EQ(file_count(dir.path()), 1u);
}

}  // namespace
}  // namespace vf
