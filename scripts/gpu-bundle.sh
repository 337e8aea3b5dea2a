#!/usr/bin/env bash
# Builds the GPU bundle: everything a lent GPU machine (nvcc and a driver, but none of our Debian
# dependencies, no network, minutes of machine time) needs to run the CUDA checks with one command
# and no build there (docs/cuda.md, "A GPU run").
#
# Usage: scripts/gpu-bundle.sh [MODELS_DIR]      (default ../shared/models)
#
# Builds Release with VISFIELD_CUDA=ON for sm_90 (its machine code alone: the H100 and H200 need no PTX,
# which would double the kernels' bytes) and x86-64-v3 host code (not -march=native: the GPU
# machine's processor is not this one) in build-gpu-bundle/ (incremental after the first time; ccache
# when installed), then stages in gpu-bundle/ (ignored through .git/info/exclude):
#   bin/     test_cuda, test_gpu, visfield, visfield-bench, visfield-experiments (without Embree: 42 MiB)
#   lib/     every shared library they load except glibc's and the driver's (found with ldd)
#   models/  the meshes the checks read, xz-compressed (a third smaller than gzip: the bundle is at its limit)
#   run.sh   scripts/gpu-bundle-run.sh: the whole GPU run, results under $OUT
#   BUILD    the commit, date and flags it was built from
# Prints the bundle's size and fails above 60 MiB. Then, on the device machine, from the repository
# root with gpu-bundle carried: bash gpu-bundle/run.sh
set -euo pipefail
cd "$(dirname "$0")/.."
models=$(cd "${1:-../shared/models}" 2>/dev/null && pwd) || { echo "gpu-bundle: error: no models folder '${1:-../shared/models}'" >&2; exit 2; }
build=build-gpu-bundle
bundle=gpu-bundle
limit_mib=60
meshes=(bun_zipper.ply sponza.obj sponza.mtl igea-triangles.ply conference.obj conference.mtl cow.obj)
export PATH="/usr/local/cuda/bin:$PATH"
command -v nvcc >/dev/null || { echo "gpu-bundle: error: no nvcc (looked in /usr/local/cuda/bin and PATH)" >&2; exit 2; }
for m in "${meshes[@]}"; do
  [[ -f "$models/$m" ]] || { echo "gpu-bundle: error: $models/$m is missing" >&2; exit 2; }
done
grep -qxF "/$bundle/" .git/info/exclude 2>/dev/null || echo "/$bundle/" >>.git/info/exclude

# 1. Build (configure once; later runs rebuild only what changed).
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DVISFIELD_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES=90-real \
    -DVISFIELD_NATIVE=OFF -DCMAKE_CXX_FLAGS=-march=x86-64-v3 -DVISFIELD_PYTHON=OFF -DVISFIELD_EMBREE=OFF \
    "${launcher[@]}" >/dev/null
fi
cmake --build "$build" -j"$(nproc)" --target test_cuda test_gpu visfield visfield-bench visfield-experiments

# 2. Stage binaries, libraries and meshes.
rm -rf "$bundle"
mkdir -p "$bundle/bin" "$bundle/lib" "$bundle/models"
programs=(test_cuda test_gpu visfield visfield-bench visfield-experiments)
for p in "${programs[@]}"; do
  cp "$build/bin/$p" "$bundle/bin/"
  strip "$bundle/bin/$p"
done
# glibc's libraries and the loader come with any Linux; the driver's (libcuda, libnvidia-*) with the GPU.
system='^(linux-vdso|ld-linux|libc|libm|libdl|libpthread|librt|libresolv|libutil|libcuda|libnvidia-)[.-]'
for p in "${programs[@]}"; do ldd "$bundle/bin/$p"; done | awk '/=>/ && $3 ~ /^\// {print $1, $3}' | sort -u |
  while read -r name path; do
    [[ "$name" =~ $system ]] && continue
    cp -L "$path" "$bundle/lib/$name"
  done
for m in "${meshes[@]}"; do xz -9e -T2 -c "$models/$m" >"$bundle/models/$m.xz"; done
# Copies of the cow on an exact ground (scripts/copies-scene.py), the mesh named relative to the scene
# file: both are unpacked into one folder there.
copies=$(mktemp -d)
ln -s "$models/cow.obj" "$copies/cow.obj"
for n in 9 1024; do
  /usr/bin/python3 scripts/copies-scene.py "$copies/cow.obj" "$n" 12 "$copies/cows$n.json" --ground -3.64 >/dev/null
  for f in "cows$n.json" "cows$n-ground.obj"; do xz -9e -c "$copies/$f" >"$bundle/models/$f.xz"; done
done
rm -rf "$copies"
cp scripts/gpu-bundle-run.sh "$bundle/run.sh"
chmod +x "$bundle/run.sh"
{
  echo "commit $(git rev-parse --short HEAD)$(git diff --quiet HEAD 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "built $(date -u +%Y-%m-%dT%H:%MZ) on $(uname -m), nvcc $(nvcc --version | sed -n 's/.*release \([0-9.]*\).*/\1/p')"
  echo "flags Release, VISFIELD_CUDA=ON, sm_90 code alone (no PTX), host -march=x86-64-v3, no Embree, stripped"
} >"$bundle/BUILD"

# 3. Size.
bytes=$(du -sb "$bundle" | cut -f1)
mib=$(((bytes + 1048575) / 1048576))
echo "gpu-bundle: $bundle is $mib MiB ($(ls "$bundle/lib" | wc -l) libraries, ${#meshes[@]} meshes); limit $limit_mib MiB"
du -sh "$bundle"/* | sed 's/^/  /'
if ((bytes > limit_mib * 1048576)); then
  echo "gpu-bundle: error: $mib MiB is over the $limit_mib MiB limit" >&2
  exit 1
fi
