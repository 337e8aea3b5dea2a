#!/usr/bin/env bash
# The whole GPU check of issue 11 in one go, on a machine with an NVIDIA GPU (an H100): configure and
# build with CUDA, run the cuda tests, run them again under compute-sanitizer memcheck, run the
# benchmarks and the GPU paper's figures, print a short table last and append the results, with the
# device name and the date, to bench/RESULTS.md. See docs/cuda.md.
#
# Usage: scripts/gpu-check.sh MODELS_DIR [BUILD_DIR [STEP...]]
#   MODELS_DIR  the shared test meshes (bun_zipper.ply, sponza.obj, igea-triangles.ply, ...); on the GPU
#               machine, a folder of the repository that .git/info/exclude ignores, copied there by the caller.
#   BUILD_DIR   default build-gpu; the logs go to BUILD_DIR/gpu-check/.
#   STEP        build, test, memcheck, bench, figures (= gpu5 gpu3 gpu7 render), summary (default: all, in
#               that order). Steps run apart resume from the logs of the earlier ones, for machines that
#               limit one command's time (10 minutes on this workplace's device machines).
# Environment: VISFIELD_GPU_DEBS=DIR  .deb files of the build dependencies (scripts/install-deps.sh's
#               list) to unpack first, for a machine that has CUDA but not them and cannot fetch them.
#              JOBS (default 16)  build jobs.
# Without a GPU it says so and stops (exit 0) before building anything.
set -euo pipefail
cd "$(dirname "$0")/.."
models=$(cd "${1:?usage: scripts/gpu-check.sh MODELS_DIR [BUILD_DIR]}" && pwd)
build=${2:-build-gpu}
steps=("${@:3}")
[[ ${#steps[@]} -gt 0 ]] || steps=(build test memcheck bench figures summary)
jobs=${JOBS:-16}
export PATH="/usr/local/cuda/bin:$PATH"

if ! command -v nvidia-smi >/dev/null 2>&1 || ! nvidia-smi -L 2>/dev/null | grep -q '^GPU'; then
  echo "gpu-check: no CUDA device found (nvidia-smi lists no GPU): nothing built or run"
  exit 0
fi
if ! command -v nvcc >/dev/null 2>&1; then
  echo "gpu-check: error: a GPU but no nvcc (looked in /usr/local/cuda/bin and PATH)" >&2
  exit 1
fi
if [[ -n "${VISFIELD_GPU_DEBS:-}" ]]; then
  for deb in "$VISFIELD_GPU_DEBS"/*.deb; do dpkg -x "$deb" /; done
  ldconfig
fi
device=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1)
date=$(date -u +%Y-%m-%d)
log="$build/gpu-check"
mkdir -p "$log"
bin="$build/bin"
threads=$(nproc)
echo "gpu-check: $device, $date, models $models, build $build, steps ${steps[*]}"
run() {  # run NAME COMMAND...: its output to $log/NAME.txt and the terminal
  echo "\$ ${*:2}" | tee "$log/$1.txt"
  "${@:2}" 2>&1 | tee -a "$log/$1.txt" || echo "gpu-check: $1 failed" | tee -a "$log/$1.txt"
}

# 1. Build (Release, sm_90 unless the cache says otherwise).
step_build() {
  cmake -S . -B "$build" -DVISFIELD_CUDA=ON -DVISFIELD_PYTHON=OFF -DCMAKE_BUILD_TYPE=Release -DVISFIELD_MODELS_DIR="$models" \
    -DCMAKE_CUDA_COMPILER="$(command -v nvcc)" >"$log/configure.txt"
  cmake --build "$build" -j"$jobs" --target test_cuda test_gpu visfield visfield-bench >"$log/build.txt" 2>&1 ||
    { tail -50 "$log/build.txt"; exit 1; }
}

# 2. The cuda tests (and the device-neutral unit tests), then the cuda tests under memcheck with a
#    tenth of the rays (memcheck runs kernels some 100 times slower).
step_test() {
  local status=passed
  ctest --test-dir "$build" -L 'cuda|unit' -R 'Cuda|GpuBvh|PackedFieldScene|RayGeneration|Roofline' --output-on-failure \
    >"$log/ctest.txt" 2>&1 || status=FAILED
  echo "$status ($(grep -c 'Skipped' "$log/ctest.txt" || true) skipped)" >"$log/status-test.txt"
  tail -15 "$log/ctest.txt"
}
step_memcheck() {
  local status=clean
  if command -v compute-sanitizer >/dev/null 2>&1; then
    VISFIELD_TEST_SCALE=0.1 compute-sanitizer --tool memcheck --error-exitcode 99 --leak-check full "$bin/test_cuda" \
      >"$log/memcheck.txt" 2>&1 || status="errors (exit $?)"
  else
    status="not run (no compute-sanitizer)"
  fi
  echo "$status" >"$log/status-memcheck.txt"
  tail -5 "$log/memcheck.txt" 2>/dev/null || true
}

# 3. Benchmarks: the exact GPU BVH and the fields beside the CPU on bunny and sponza AO rays, field
#    lookups with AO rays generated on the device; the GPU paper's Figures 5, 3 and 7.
step_bench() {
run bunny "$bin/visfield-bench" --device cuda --scene "$models/bun_zipper.ply" --rays ao --ao-rays 64 --width 1024 --height 1024 \
  --accel bvh,field --threads "$threads" --reps 9
run sponza "$bin/visfield-bench" --device cuda --scene "$models/sponza.obj" --rays ao --ao-rays 64 --width 1024 --height 1024 \
  --accel bvh,field --threads "$threads" --reps 9
run corner "$bin/visfield-bench" --device cuda --scene "$models/bun_zipper.ply" --rays ao --ao-rays 64 --width 1024 --height 1024 \
  --accel bvh,field:positions=16642,directions=64 --threads "$threads" --reps 9
}
step_gpu5() { run gpu5 "$bin/visfield-bench" --device cuda --figure gpu5 --scene "$models/igea-triangles.ply" --threads "$threads"; }
step_gpu3() { run gpu3 "$bin/visfield-bench" --device cuda --figure gpu3 --scene "$models/bun_zipper.ply" --threads "$threads"; }
step_gpu7() { run gpu7 "$bin/visfield-bench" --device cuda --figure gpu7 --scene "$models/bun_zipper.ply" --threads "$threads"; }
step_render() {
  run render "$bin/visfield" render "$models/igea-triangles.ply" --device cuda --occluders field --ao-rays 121 --width 512 \
    --height 512 --out "$log/igea-cuda.png" --no-progress
}
step_figures() { step_gpu5; step_gpu3; step_gpu7; step_render; }

# 4. The short table, last; everything appended to bench/RESULTS.md.
grays() {  # grays FILE PATTERN: the GPU G rays/s column of the table row matching PATTERN
  grep -F "$2" "$1" 2>/dev/null | head -1 | awk -F'|' '{gsub(/ /, "", $4); print $4}'
}
step_summary() {
local frame_ms
frame_ms=$(grep -F '| fields, kernel |' "$log/gpu5.txt" 2>/dev/null | awk -F'|' '{gsub(/ /, "", $3); print $3}' || true)
local summary
summary=$(cat <<EOF
| check | result | target |
|---|---|---|
| device | $device | H100 |
| cuda + gpu unit tests | $(cat "$log/status-test.txt" 2>/dev/null || echo 'not run') | passed, none skipped |
| test_cuda under compute-sanitizer memcheck | $(cat "$log/status-memcheck.txt" 2>/dev/null || echo 'not run') | clean |
| field AO, device-generated rays, bunny (G rays/s) | $(grays "$log/bunny.txt" "| fields: ") | >= 20 |
| field AO, 16642 x 64^2, 64 rays a hit, bunny (G rays/s) | $(grays "$log/corner.txt" "| fields: ") | >= 20 |
| exact GPU BVH AO, bunny (G rays/s) | $(grays "$log/bunny.txt" "| exact GPU BVH: ") | >= 1.5 |
| exact GPU BVH AO, sponza (G rays/s) | $(grays "$log/sponza.txt" "| exact GPU BVH: ") | >= 1.5 |
| Figure 5: igea, 16642 x 64^2, 121 rays/pixel, 512x512 (ms per frame) | ${frame_ms:-?} | <= 5 (paper: 202 on a GeForce 8800) |
| GPU vs CPU agreement (rows not bit-identical) | $(cat "$log"/bunny.txt "$log"/sponza.txt "$log"/corner.txt 2>/dev/null | grep -c ' differ |' || true) | 0 |
EOF
)
[[ -f bench/RESULTS.md ]] || printf '# GPU results\n\nAppended by scripts/gpu-check.sh on a GPU machine (docs/cuda.md).\n' >bench/RESULTS.md
{
  echo
  echo "## GPU check, $device, $date"
  echo
  echo "\`scripts/gpu-check.sh\` ($(git rev-parse --short HEAD 2>/dev/null || echo 'no git'), $threads CPU threads)."
  echo
  echo "$summary"
  for part in bunny sponza corner gpu5 gpu3 gpu7 render; do
    [[ -f "$log/$part.txt" ]] || continue
    echo
    echo '```'
    cat "$log/$part.txt"
    echo '```'
  done
  echo
  echo '```'
  tail -5 "$log/ctest.txt" 2>/dev/null || true
  tail -3 "$log/memcheck.txt" 2>/dev/null || true
  echo '```'
} >>bench/RESULTS.md
echo
echo "gpu-check: logs in $log; appended to bench/RESULTS.md"
echo "$summary"
}

for step in "${steps[@]}"; do
  case "$step" in
    build | test | memcheck | bench | figures | gpu5 | gpu3 | gpu7 | render | summary) "step_$step" ;;
    *) echo "gpu-check: error: unknown step '$step' (build, test, memcheck, bench, figures, gpu5, gpu3, gpu7, render, summary)" >&2; exit 2 ;;
  esac
done
