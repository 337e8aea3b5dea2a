/// \file visfield-bench: the same rays through visfield's structures and Embree 3, in one process.

#include <algorithm>
#include <exception>
#include <iostream>
#include <string>

#include "bench_options.hpp"
#include "bench_run.hpp"
#if VISFIELD_HAVE_CUDA
#include "cuda_bench.hpp"
#endif
#include "dynamic_run.hpp"
#include "walk_run.hpp"
#include "visfield/core/isa.hpp"
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
    vf::check_isa_environment();
  } catch (const vf::Error& e) {
    return fail(e.what(), kExitUsage);
  }
  try {
    const auto options = vf::bench::parse_bench_options(argc, argv, std::cout);
    if (!options || vf::parse_only()) return 0;
    if (options->device == "cuda") {
#if VISFIELD_HAVE_CUDA
      vf::bench::run_cuda_bench(*options, std::cout);
      return 0;
#else
      return fail("--device cuda: this build has no CUDA (configure with -DVISFIELD_CUDA=ON)", kExitUsage);
#endif
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
