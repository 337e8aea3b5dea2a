/// \file visfield-bench: the same rays through visfield's structures and Embree 3, in one process.

#include <algorithm>
#include <exception>
#include <iostream>
#include <string>

#include "bench_options.hpp"
#include "bench_run.hpp"
#if VISFIELD_HAVE_CUDA
#include "cuda_bench.hpp"
#include "cuda_figures.hpp"
#endif
#include "dynamic_run.hpp"
#include "field_figures.hpp"
#include "render_figures.hpp"
#include "walk_run.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parse_only.hpp"

namespace {

constexpr int kExitBadInput = 1;
constexpr int kExitUsage = 2;

// Prints the one-line error report; line breaks inside a library's message become spaces.
int fail(std::string message, int status) {
  for (char& c : message) c = c == '\n' || c == '\r' ? ' ' : c;
  while (!message.empty() && message.back() == ' ') message.pop_back();
  std::cerr << "visfield-bench: error: " << message << "\n";
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  vf::install_interrupt_handlers();
  try {
    const auto options = vf::bench::parse_bench_options(argc, argv, std::cout);
    if (!options || vf::parse_only()) return 0;
    if (options->device == "cuda") {
#if VISFIELD_HAVE_CUDA
      if (!options->figure.empty())
        vf::bench::run_cuda_figure(*options, std::cout);
      else
        vf::bench::run_cuda_bench(*options, std::cout);
      return 0;
#else
      return fail("--device cuda: this build has no CUDA (configure with -DVISFIELD_CUDA=ON)", kExitUsage);
#endif
    }
    if (!options->figure.empty()) {
      const vf::ThreadLimit limit(options->threads);
      const std::vector<std::string> rendered = vf::bench::render_figure_names();
      if (std::find(rendered.begin(), rendered.end(), options->figure) != rendered.end())
        vf::bench::run_render_figure(options->figure, options->scene, options->figure_images, std::cout);
      else
        vf::bench::run_field_figure(options->figure, options->scene, std::cout);
      return 0;
    }
    if (options->walk_frames > 0) {
      vf::bench::run_walk_bench(*options, std::cout);
      return 0;
    }
    if (options->dynamic_frames > 0) {
      const vf::bench::DynamicReport report = vf::bench::run_dynamic_bench(*options);
      if (options->json) {
        std::cout << vf::bench::dynamic_report_json(report).dump(2) << "\n";
      } else {
        vf::bench::print_dynamic_table(std::cout, report);
      }
      return 0;
    }
    const vf::bench::BenchReport report = vf::bench::run_bench(*options);
    vf::bench::print_report(std::cout, report, options->json);
    return 0;
  } catch (const vf::Interrupted& interrupted) {
    return fail(interrupted.what(), 128 + interrupted.signal());
  } catch (const vf::bench::UsageError& error) {
    return fail(error.what(), kExitUsage);
  } catch (const vf::Error& error) {
    return fail(error.what(), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return fail("out of memory", kExitBadInput);
  } catch (const std::exception& error) {
    return fail(error.what(), kExitBadInput);
  }
}
