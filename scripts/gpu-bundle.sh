#!/usr/bin/env bash
# Builds the GPU bundle: everything a lent GPU machine (nvcc and a driver, but none of our Debian
# dependencies, no network, minutes of machine time) needs to run the CUDA checks with one command
# and no build there (docs/cuda.md, "A GPU run").
#
# Usage: scripts/gpu-bundle.sh [MODELS_DIR]      (default ../shared/models)
#
# Builds Release with VISFIELD_CUDA=ON for sm_90 (its machine code alone: the H100 and H200 need no PTX,
# which would double the kernels' bytes), host code portable as every build's is (x86-64-v3 with AVX-512
# kernels chosen at run time: the GPU machine's processor is not this one) and every module a shared library (BUILD_SHARED_LIBS=ON: the five programs share one copy of the
# library instead of linking it five times), in build-gpu-bundle/ (incremental after the first time;
# ccache when installed), then stages in gpu-bundle/ (ignored through .gitignore):
#   payload.tar.xz  bin/ (test_cuda, test_gpu, visfield, visfield-bench, visfield-experiments, without
#                   Embree), lib/ (the modules and every shared library the programs load except
#                   glibc's and the driver's, found with ldd), models/ (the meshes the checks read):
#                   stripped, then packed with xz (run.sh unpacks it on the device)
#   run.sh          scripts/gpu-bundle-run.sh: the whole GPU run, results under $OUT
#   BUILD           the commit, date and flags it was built from
# Prints the bundle's size and fails above 48 MiB (the device tool carries at most 64). Then, on the
# device machine, from the repository root with gpu-bundle carried: bash gpu-bundle/run.sh
set -euo pipefail
cd "$(dirname "$0")/.."
models=$(cd "${1:-../shared/models}" 2>/dev/null && pwd) || { echo "gpu-bundle: error: no models folder '${1:-../shared/models}'" >&2; exit 2; }
build=build-gpu-bundle
bundle=gpu-bundle
limit_mib=48
meshes=(bun_zipper.ply sponza.obj sponza.mtl igea-triangles.ply conference.obj conference.mtl cow.obj)
export PATH="/usr/local/cuda/bin:$PATH"
command -v nvcc >/dev/null || { echo "gpu-bundle: error: no nvcc (looked in /usr/local/cuda/bin and PATH)" >&2; exit 2; }
for m in "${meshes[@]}"; do
  [[ -f "$models/$m" ]] || { echo "gpu-bundle: error: $models/$m is missing" >&2; exit 2; }
done

# 1. Build (configure once; later runs rebuild only what changed).
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
  fi
  generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DVISFIELD_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES=90-real \
    -DVISFIELD_PYTHON=OFF -DVISFIELD_EMBREE=OFF -DBUILD_SHARED_LIBS=ON "${launcher[@]}" >/dev/null
fi
cmake --build "$build" -j"$(nproc)" --target test_cuda test_gpu visfield visfield-bench visfield-experiments

# 2. Stage binaries, libraries and meshes in a scratch folder, then pack them.
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
rm -rf "$bundle"
mkdir -p "$bundle" "$stage/bin" "$stage/lib" "$stage/models"
programs=(test_cuda test_gpu visfield visfield-bench visfield-experiments)
for p in "${programs[@]}"; do
  cp "$build/bin/$p" "$stage/bin/"
  strip "$stage/bin/$p"
done
# glibc's libraries and the loader come with any Linux; the driver's (libcuda, libnvidia-*) with the GPU.
# The modules' own libraries (libvisfield_*.so) are found through the build tree's run path.
system='^(linux-vdso|ld-linux|libc|libm|libdl|libpthread|librt|libresolv|libutil|libcuda|libnvidia-)[.-]'
for p in "${programs[@]}"; do ldd "$build/bin/$p"; done | awk '/=>/ && $3 ~ /^\// {print $1, $3}' | sort -u |
  while read -r name path; do
    [[ "$name" =~ $system ]] && continue
    cp -L "$path" "$stage/lib/$name"
    strip --strip-unneeded "$stage/lib/$name"
  done
for m in "${meshes[@]}"; do cp "$models/$m" "$stage/models/"; done
# Copies of the cow on an exact ground (scripts/copies-scene.py), the mesh named relative to the scene
# file: all are unpacked into one folder there.
for n in 9 1024; do
  /usr/bin/python3 scripts/copies-scene.py "$stage/models/cow.obj" "$n" 12 "$stage/models/cows$n.json" --ground -3.64 >/dev/null
done
tar -C "$stage" -cf - bin lib models | xz -9e -T2 >"$bundle/payload.tar.xz"
cp scripts/gpu-bundle-run.sh "$bundle/run.sh"
chmod +x "$bundle/run.sh"
{
  echo "commit $(git rev-parse --short HEAD)$(git diff --quiet HEAD 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "built $(date -u +%Y-%m-%dT%H:%MZ) on $(uname -m), nvcc $(nvcc --version | sed -n 's/.*release \([0-9.]*\).*/\1/p')"
  echo "flags Release, VISFIELD_CUDA=ON, sm_90 code alone (no PTX), portable host code, shared modules, no Embree, stripped"
} >"$bundle/BUILD"

# 3. Size.
bytes=$(du -sb "$bundle" | cut -f1)
mib=$(((bytes + 1048575) / 1048576))
echo "gpu-bundle: $bundle is $mib MiB ($(ls "$stage/lib" | wc -l) libraries, ${#meshes[@]} meshes; $(du -sm "$stage" | cut -f1) MiB unpacked); limit $limit_mib MiB"
du -sh "$stage"/* "$bundle"/* | sed 's/^/  /'
if ((bytes > limit_mib * 1048576)); then
  echo "gpu-bundle: error: $mib MiB is over the $limit_mib MiB limit" >&2
  exit 1
fi
