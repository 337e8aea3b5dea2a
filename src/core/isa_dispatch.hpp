#pragma once
// How a kernel's source file becomes one copy per instruction set, and how a call finds the copy the
// process runs (include/visfield/core/isa.hpp).
//
// A module lists its kernels' files as KERNELS (CMakeLists.txt, visfield_library). Each is compiled
// once with the library (x86-64-v3), and once more for each wider set the build makes
// (VISFIELD_WIDER_ISAS; VF_ISA_AVX512 is then defined and the file compiled for x86-64-v4). A module's
// wider copies are linked into one object whose symbols are all local but for its entry points, the
// functions of namespace vf::isa_avx512 (ld -r with the COMDAT groups dissolved, then objcopy
// --keep-global-symbol): the wider copy's inline functions, templates and their static variables, the
// standard library's among them, never stand in for the baseline's, so nothing wider runs on a
// processor without it, and inside the copy every call stays in the copy.
//
// An entry point is a public function of the file whose baseline copy begins with
// VF_USE_WIDER(entry, arguments...): when the active path is wider it returns the answer of
// vf::isa_avx512::entry, which the wider copy defines (after VF_WIDER_ENTRY) to call the same public
// function, whose own VF_USE_WIDER is empty there.

#include "visfield/core/isa.hpp"

#if defined(VF_ISA_AVX512)
/// 1 in a wider copy of a kernel's file, 0 in the baseline's.
#define VF_IN_WIDER_COPY 1
#else
#define VF_IN_WIDER_COPY 0
#endif

/// Marks the definition of a wider copy's entry point: the one kind of symbol the copy exports.
#define VF_WIDER_ENTRY __attribute__((visibility("default")))

#if defined(VISFIELD_HAVE_AVX512) && !VF_IN_WIDER_COPY
/// In the baseline copy of an entry point: returns vf::isa_avx512::entry(arguments...) when the
/// AVX-512 path is active; nothing in the wider copy or a build without one.
#define VF_USE_WIDER(entry, ...)                                                                       \
  do {                                                                                                 \
    if (::vf::active_isa() == ::vf::Isa::avx512) return ::vf::isa_avx512::entry(__VA_ARGS__);         \
  } while (false)
#else
#define VF_USE_WIDER(entry, ...) \
  do {                           \
  } while (false)
#endif
