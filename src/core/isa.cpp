#include "visfield/core/isa.hpp"

#include <unistd.h>

#include <cstdlib>

#include "visfield/core/error.hpp"

namespace vf {
namespace isa_detail {

std::atomic<Isa> active{Isa::avx2};

}  // namespace isa_detail

namespace {

constexpr Isa kIsas[] = {Isa::avx2, Isa::avx512};

// The path VISFIELD_ISA names, or nothing when it is unset or cannot be taken here.
const char* requested_isa() {
  const char* value = std::getenv("VISFIELD_ISA");
  return value != nullptr && *value != '\0' ? value : nullptr;
}

Isa checked(Isa isa, std::string_view what) {
  if (!isa_built(isa))
    throw Error(std::string(what) + isa_name(isa) + ": this build has no " + isa_name(isa) + " kernels (configure with VISFIELD_WIDER_ISAS=avx512)");
  if (!cpu_runs(isa)) throw Error(std::string(what) + isa_name(isa) + ": this processor does not run " + isa_name(isa));
  return isa;
}

// Before main: the widest path, or the one VISFIELD_ISA names where it can be taken.
const bool initialised = [] {
  Isa isa = widest_isa();
  if (const char* value = requested_isa()) {
    try {
      isa = checked(parse_isa(value), "VISFIELD_ISA=");
    } catch (const Error&) {
      // Reported by check_isa_environment(); a library has no business exiting here.
    }
  }
  isa_detail::active.store(isa, std::memory_order_relaxed);
  return true;
}();

// Before anything else of the library runs: code built for a processor this one is not would stop
// at its first such instruction with SIGILL; this says why in one line instead. Compiled for any
// x86-64, so that it runs where the rest would not.
__attribute__((constructor(101), target("arch=x86-64"))) void require_baseline() {
  __builtin_cpu_init();
  bool runs = true;
  const char* needs = "";
#if defined(__AVX512F__)
  runs = runs && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512vl");
  needs = "AVX-512 (F, BW, DQ, VL)";
#elif defined(__AVX2__)
  runs = runs && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2");
  needs = "AVX2, FMA and BMI2 (x86-64-v3)";
#endif
  if (runs) return;
  const char start[] = "visfield: error: this processor lacks ";
  const char end[] = ", which this build of visfield needs (configure with VISFIELD_ARCH set to an older level)\n";
  std::size_t length = 0;
  while (needs[length] != '\0') ++length;
  [[maybe_unused]] ssize_t written = write(2, start, sizeof start - 1);
  written = write(2, needs, length);
  written = write(2, end, sizeof end - 1);
  _exit(1);
}

}  // namespace

// The baseline copy is AVX2 as built by default; a build for an older level (VISFIELD_ARCH) runs
// the kernels' scalar forms there.
#if defined(__AVX2__) && defined(__FMA__)
constexpr const char* kBaseName = "avx2";
#else
constexpr const char* kBaseName = "scalar";
#endif

const char* isa_name(Isa isa) { return isa == Isa::avx512 ? "avx512" : kBaseName; }

Isa parse_isa(std::string_view name, std::string_view what) {
  if (name == "avx2" || name == kBaseName) return Isa::avx2;
  if (name == "avx512") return Isa::avx512;
  throw Error(std::string(what) + "'" + std::string(name) + "': unknown instruction set (valid: avx2, avx512)");
}

bool isa_built(Isa isa) {
#if defined(VISFIELD_HAVE_AVX512)
  return isa == Isa::avx2 || isa == Isa::avx512;
#else
  return isa == Isa::avx2;
#endif
}

bool cpu_runs(Isa isa) {
  __builtin_cpu_init();
#if defined(__AVX2__)
  if (isa == Isa::avx2) return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  if (isa == Isa::avx2) return true;
#endif
  // x86-64-v4: what the AVX-512 copies are compiled for.
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd") &&
         __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
}

Isa widest_isa() {
  Isa widest = Isa::avx2;
  for (Isa isa : kIsas)
    if (isa_built(isa) && cpu_runs(isa)) widest = isa;
  return widest;
}

void check_isa_environment() {
  (void)initialised;
  if (const char* value = requested_isa()) checked(parse_isa(value), "VISFIELD_ISA=");
}

void set_active_isa(Isa isa) { isa_detail::active.store(checked(isa, "instruction set "), std::memory_order_relaxed); }

std::string isa_summary() {
  std::string built, runs;
  for (Isa isa : kIsas) {
    if (isa_built(isa)) built += std::string(built.empty() ? "" : ", ") + isa_name(isa);
    if (cpu_runs(isa)) runs += std::string(runs.empty() ? "" : ", ") + isa_name(isa);
  }
  return std::string(isa_name(active_isa())) + " (built: " + built + "; this processor runs: " + (runs.empty() ? "none" : runs) + ")";
}

}  // namespace vf
