// visfield-experiments: the papers' figures reproduced on this machine (the ObjectField papers'
// ray-set figures, the GPU fields paper's rendered ones on the CPU, and its GPU figures with
// --device cuda). Each prints a markdown table beside the paper's numbers. A bad command line is one
// line on stderr and exit 2; a failure (a bad mesh, no GPU) one line and exit 1.

#include <algorithm>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cuda_figure_names.hpp"
#include "field_figures.hpp"
#include "render_figures.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/parse_only.hpp"
#if VISFIELD_HAVE_CUDA
#include "cuda_figures.hpp"
#endif

namespace {

constexpr int kExitFailure = 1, kExitUsage = 2;

std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

int fail(const std::string& message, int status) {
  std::cerr << "visfield-experiments: error: " << one_line(message) << "\n";
  return status;
}

bool listed(const std::vector<std::string>& names, const std::string& name) { return std::find(names.begin(), names.end(), name) != names.end(); }

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace vf::experiments;
  vf::install_interrupt_handlers();
  std::vector<std::string> figures = field_figure_names();
  for (const std::string& name : render_figure_names()) figures.push_back(name);
  for (const std::string& name : cuda_only_figure_names()) figures.push_back(name);
  std::string figure, scene, images, device = "cpu";
  int threads = 0;
  CLI::App app{"visfield-experiments: the papers' figures reproduced on this machine, as markdown tables"};
  app.add_option("--figure", figure,
                 "fig6 (positions x directions: precompute, AO time, RMS), fig5 (mappings, 1-bit variant), fig8 (--scene: "
                 "a folder of models; each alone, then three together), lookups (nearest, bilinear, blend), gpu3 (the "
                 "GPU paper's Figure 3), and with visfield's integrators the GPU paper's gpu7 (soft shadows), gpu8 "
                 "(--scene: the models' folder; three models' soft shadows), gpu9 (glossy reflections with normal "
                 "fields); with --device cuda gpu3, gpu5 (Figure 5's frame time) and gpu7 on the GPU")
      ->required()
      ->check(CLI::IsMember(figures));
  app.add_option("--scene", scene, "The caster (a mesh file), or for fig8 and gpu8 the folder of the models")->required();
  app.add_option("--threads", threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  app.add_option("--figure-images", images,
                 "gpu7, gpu8, gpu9: folder to write every rendered image in (PNG; compare pairs with `visfield compare`)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--device", device, "cpu, or cuda: the GPU figures gpu3, gpu5 and gpu7 on the GPU")->check(CLI::IsMember({"cpu", "cuda"}));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    return fail(e.what(), kExitUsage);
  }
  if (device == "cuda" && !listed(cuda_figure_names(), figure))
    return fail("--figure " + figure + ": not with --device cuda (GPU figures: " + joined(cuda_figure_names()) + ")", kExitUsage);
  if (device != "cuda" && listed(cuda_only_figure_names(), figure)) return fail("--figure " + figure + ": only with --device cuda", kExitUsage);
#if !VISFIELD_HAVE_CUDA
  if (device == "cuda") return fail("--device cuda: this build has no CUDA (configure with -DVISFIELD_CUDA=ON)", kExitUsage);
#endif
  if (vf::parse_only()) return 0;
  try {
    if (device == "cuda") {
#if VISFIELD_HAVE_CUDA
      run_cuda_figure(figure, scene, threads, std::cout);
#endif
      return 0;
    }
    const vf::ThreadLimit limit(threads);
    if (listed(render_figure_names(), figure))
      run_render_figure(figure, scene, images, std::cout);
    else
      run_field_figure(figure, scene, std::cout);
    return 0;
  } catch (const vf::Interrupted& e) {
    std::cerr << "visfield-experiments: " << e.what() << "\n";
    return 128 + e.signal();
  } catch (const std::exception& e) {
    return fail(e.what(), kExitFailure);
  }
}
