// The fuzz targets' driver for builds without libFuzzer (the test suite's): runs every input of the
// given folders through LLVMFuzzerTestOneInput, then mutations of them from a fixed seed for a fixed
// time. A target that crashes, leaks (under ASan) or throws anything but vf::Error fails the run.
//
// Usage: fuzz_NAME_replay [--seed S] [--mutate-ms MS] FOLDER...
// When an input crashes the target (an abort, a sanitizer report, an uncaught exception, a fault),
// it is written to ./fuzz-crash-input before the process dies, to be added to regressions/NAME.

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "visfield/core/rng.hpp"
#include "visfield/core/stopwatch.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) __attribute__((weak));

namespace {

using Bytes = std::vector<std::uint8_t>;

// Text fragments that parsers trip on, spliced into inputs by the mutator.
const char* const kInteresting[] = {"0", "-1", "1e308", "-1e308", "nan", "inf", "4294967296", "18446744073709551616",
                                    "\"", "{", "}", "[", "]", ",", ":", "=", "\n", "\0", "1e-45", "65535", "9999999999"};

// The input being run, for the crash handler.
const Bytes* g_current = nullptr;

// Async-signal-safe: open, write, close only.
void save_current_input(int signal_number) {
  if (g_current != nullptr) {
    const int fd = ::open("fuzz-crash-input", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      const ssize_t written = ::write(fd, g_current->data(), g_current->size());
      static_cast<void>(written);
      ::close(fd);
    }
    static const char message[] = "fuzz replay: the crashing input is in ./fuzz-crash-input\n";
    const ssize_t shown = ::write(2, message, sizeof message - 1);
    static_cast<void>(shown);
  }
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

void run(const Bytes& input) {
  g_current = &input;
  LLVMFuzzerTestOneInput(input.data(), input.size());
  g_current = nullptr;
}

Bytes mutate(const Bytes& base, const std::vector<Bytes>& corpus, vf::Rng& rng) {
  Bytes out = base;
  const int edits = 1 + static_cast<int>(rng.next_u32() % 4);
  for (int e = 0; e < edits; ++e) {
    const std::size_t at = out.empty() ? 0 : rng.next_u32() % (out.size() + 1);
    switch (rng.next_u32() % 6) {
      case 0:  // flip a bit
        if (!out.empty()) out[std::min(at, out.size() - 1)] ^= static_cast<std::uint8_t>(1u << (rng.next_u32() % 8));
        break;
      case 1:  // delete a run
        if (!out.empty()) out.erase(out.begin() + static_cast<std::ptrdiff_t>(std::min(at, out.size() - 1)),
                                    out.begin() + static_cast<std::ptrdiff_t>(std::min(out.size(), at + 1 + rng.next_u32() % 16)));
        break;
      case 2:  // insert a random byte
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::uint8_t>(rng.next_u32()));
        break;
      case 3: {  // insert an interesting fragment
        const std::string f = kInteresting[rng.next_u32() % std::size(kInteresting)];
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), f.begin(), f.end());
        break;
      }
      case 4: {  // duplicate a chunk of itself
        if (out.empty()) break;
        const std::size_t from = rng.next_u32() % out.size(), len = std::min<std::size_t>(out.size() - from, 1 + rng.next_u32() % 64);
        const Bytes chunk(out.begin() + static_cast<std::ptrdiff_t>(from), out.begin() + static_cast<std::ptrdiff_t>(from + len));
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), chunk.begin(), chunk.end());
        break;
      }
      default: {  // splice in part of another input
        const Bytes& other = corpus[rng.next_u32() % corpus.size()];
        if (other.empty()) break;
        const std::size_t from = rng.next_u32() % other.size(), len = std::min<std::size_t>(other.size() - from, 1 + rng.next_u32() % 128);
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), other.begin() + static_cast<std::ptrdiff_t>(from),
                   other.begin() + static_cast<std::ptrdiff_t>(from + len));
      }
    }
  }
  if (out.size() > (1u << 16)) out.resize(1u << 16);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  for (const int signal_number : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(signal_number, save_current_input);
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
  std::uint64_t seed = 1;
  double mutate_ms = 0.0;
  std::vector<Bytes> corpus;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (arg == "--mutate-ms" && i + 1 < argc) {
      mutate_ms = std::atof(argv[++i]);
    } else {
      std::error_code ec;
      for (const auto& entry : std::filesystem::directory_iterator(arg, ec)) {
        if (!entry.is_regular_file()) continue;
        std::ifstream in(entry.path(), std::ios::binary);
        corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      }
      if (ec) {
        std::fprintf(stderr, "fuzz replay: error: %s: %s\n", arg.c_str(), ec.message().c_str());
        return 2;
      }
    }
  }
  if (corpus.empty()) corpus.emplace_back();
  for (const Bytes& input : corpus) run(input);
  vf::Rng rng(seed);
  std::size_t runs = corpus.size();
  const vf::Stopwatch watch;
  while (watch.elapsed_ms() < mutate_ms) {
    run(mutate(corpus[rng.next_u32() % corpus.size()], corpus, rng));
    ++runs;
  }
  std::printf("fuzz replay: %zu inputs, %zu runs, seed %llu\n", corpus.size(), runs, static_cast<unsigned long long>(seed));
  return 0;
}
