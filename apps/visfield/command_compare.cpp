#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/render/compare.hpp"

namespace vf::cli {

namespace {

struct CompareOptions {
  std::string image, reference, diff;
};

// The papers' error images: |image - reference| per channel, times 5, clamped to 1.
constexpr float kDiffScale = 5.0f;

int run_compare(const CompareOptions& o) {
  if (!o.diff.empty()) {
    check_image_extension(o.diff);
    check_writable(o.diff);
  }
  const Image image = read_image(o.image), reference = read_image(o.reference);
  const ImageDifference d = compare_images(image, reference);
  std::cout << "compare: " << o.image << " against " << o.reference << " (" << image.width << "x" << image.height << ")\n"
            << "rms:  " << d.rms * 255.0 << " (0-255), " << d.rms << " (0-1)\n"
            << "max:  " << d.max_abs * 255.0 << " (0-255), " << d.max_abs << " (0-1)\n"
            << "psnr: " << d.psnr_db << " dB\n";
  if (!o.diff.empty()) {
    Image diff(image.width, image.height);
    for (std::size_t i = 0; i < diff.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c)
        diff.pixels[i][c] = std::min(1.0f, kDiffScale * std::fabs(image.pixels[i][c] - reference.pixels[i][c]));
    write_image(o.diff, diff);
    std::cout << "wrote " << std::filesystem::absolute(o.diff).string() << " (differences x" << kDiffScale << ")\n";
  }
  return 0;
}

}  // namespace

void register_compare_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand(
      "compare", "RMS (on 0-255 and 0-1), max error and PSNR of an image against a reference, and an error image x5");
  cmd->add_option("image", options->image, "The image to judge (PNG or EXR)")->required();
  cmd->add_option("reference", options->reference, "The reference image, same size")->required();
  cmd->add_option("--diff", options->diff, "Write |image - reference| x 5 to this PNG or EXR");
  cmd->callback([options, &action] { action = [options] { return run_compare(*options); }; });
}

}  // namespace vf::cli
