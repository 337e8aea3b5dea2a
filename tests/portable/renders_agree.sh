#!/usr/bin/env bash
# tests/portable/renders_agree.sh VALGRIND VISFIELD OUT_DIR: a soft-shadow render through fields under
# valgrind (which hides AVX-512, so the kernels take their AVX2 copies and any AVX-512 instruction
# reached stops the run with SIGILL), and the same render on the processor's own path: the images must
# be the same to the last bit (visfield compare: rms 0).
set -euo pipefail
valgrind=$1 visfield=$2 out=$3
mkdir -p "$out"
render=(render builtin:cornell --integrator softshadow --occluders field --width 24 --height 24 --spp 1 --threads 2 --no-progress)
"$valgrind" --tool=none --error-exitcode=99 -q "$visfield" "${render[@]}" --out "$out/avx2.exr"
"$visfield" "${render[@]}" --out "$out/native.exr"
"$visfield" info builtin:cornell | grep '^kernels:'
"$visfield" compare "$out/avx2.exr" "$out/native.exr"
