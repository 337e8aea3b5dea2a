#pragma once
/// \file The instruction sets of the SIMD kernels, and the one this process runs. The library is
/// built for x86-64-v3 (AVX2 and FMA) and runs on any processor that has them; each kernel (the
/// BVH's walks, the field lookups and lanes, BeamField's packets, the renderers' sample lanes) also
/// has a copy for AVX-512 (x86-64-v4) where the build made one, taken at run time on processors that
/// run it. Every path answers with the same bits.

#include <atomic>
#include <string>
#include <string_view>

namespace vf {

/// A kernel path, narrowest first.
enum class Isa : int { avx2 = 0, avx512 = 1 };

namespace isa_detail {
/// The active path (set once before main from the processor and VISFIELD_ISA, or by set_active_isa).
extern std::atomic<Isa> active;
}  // namespace isa_detail

/// The path the kernels take. O(1): a relaxed load.
inline Isa active_isa() { return isa_detail::active.load(std::memory_order_relaxed); }

/// "avx2" or "avx512".
const char* isa_name(Isa isa);

/// The path named "avx2" or "avx512"; throws vf::Error "<what>'<name>': unknown instruction set (valid: avx2, avx512)".
Isa parse_isa(std::string_view name, std::string_view what = "VISFIELD_ISA=");

/// Whether this build compiled the kernels' copy for `isa`.
bool isa_built(Isa isa);

/// Whether this processor and its operating system run `isa`'s instructions.
bool cpu_runs(Isa isa);

/// The widest path both built and run here: the default of active_isa(), which VISFIELD_ISA=avx2
/// lowers. A VISFIELD_ISA naming an unknown set or one this machine or build lacks is reported by
/// check_isa_environment(), and the default kept.
Isa widest_isa();

/// Throws vf::Error when VISFIELD_ISA is set to a path that is unknown, not built or not run here
/// (the command-line tools call it first, so that a bad value is one line and exit 2, not ignored).
void check_isa_environment();

/// Makes `isa` the kernels' path for the whole process; throws vf::Error where it is not built or
/// not run here. Call it while no query runs (benchmarks compare paths in one process).
void set_active_isa(Isa isa);

/// One line for reports: "avx512 (built: avx2, avx512; this processor runs: avx2, avx512)".
std::string isa_summary();

}  // namespace vf
