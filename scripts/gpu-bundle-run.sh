#!/usr/bin/env bash
# The GPU run, staged as gpu-bundle/run.sh by scripts/gpu-bundle.sh (docs/cuda.md, "A GPU run").
# From the repository root of a GPU machine, with gpu-bundle carried: bash gpu-bundle/run.sh
#
# No build and nothing installed: payload.tar.xz unpacked into $TMPDIR (xz, else Python's lzma: the
# device image has Python, not always xz), then its programs with LD_LIBRARY_PATH at its lib/ folder.
# Steps, each under its own timeout and all within VISFIELD_GPU_BUDGET_S seconds (default 400, so
# that the run ends inside 7 minutes):
#   device    nvidia-smi, the driver, the kernels' registers and stack frames (cuobjdump)
#   tests     test_cuda with VISFIELD_REQUIRE_CUDA=1 (no device: fail, not skip), every kernel kind
#             against the CPU bit for bit on >= 10M rays; test_gpu (the device code on the host)
#   sanitizers  a subset of test_cuda under compute-sanitizer memcheck (a tenth of the rays), then
#             racecheck and synccheck (a fiftieth) and initcheck (a five-hundredth: it is the slowest)
#   bench     visfield-bench --device cuda: AO on bunny, sponza and conference, fields and exact BVH, GPU vs CPU
#   figures   the GPU paper's Figures 5, 3 and 7 (visfield-experiments --device cuda --figure gpu5, gpu3,
#             gpu7), an AO render of igea; the same render through the exact GPU BVH, and both against
#             the CPU renderer's images of the same settings (visfield compare)
#   ncu       Nsight Compute on the AO kernel's three launches (fields through the kernel fitted to their
#             form, through the generic one, then the exact BVH), when a minute is left
#   copies    visfield-bench --device cuda on 9 and 1024 copies of the cow, field objects on an exact ground
# Writes to $OUT (else gpu-bundle/out), at most 8 files: summary.md (the one-screen table, also
# printed last), device.txt, tests.log, sanitizers.log, bench.log, figures.log, igea-ao.png, ncu.log.
# Without a GPU it checks that every program loads from the bundle alone, says so in one line and
# exits 0; a program that does not load is an error (exit 1).
set -uo pipefail
bundle=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=${OUT:-$bundle/out}
export PATH="/usr/local/cuda/bin:${PATH:-/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin}"
here=${TMPDIR:-/tmp}/visfield-bundle
rm -rf "$here"
mkdir -p "$here"
if command -v xz >/dev/null; then
  xz -dc "$bundle/payload.tar.xz" | tar -C "$here" -xf - || { echo "run.sh: error: cannot unpack $bundle/payload.tar.xz" >&2; exit 1; }
else
  python3 -c 'import sys, tarfile; tarfile.open(sys.argv[1], "r:xz").extractall(sys.argv[2])' "$bundle/payload.tar.xz" "$here" ||
    { echo "run.sh: error: cannot unpack $bundle/payload.tar.xz" >&2; exit 1; }
fi
cp "$bundle/BUILD" "$here/BUILD"
export LD_LIBRARY_PATH="$here/lib"
bin=$here/bin
budget=${VISFIELD_GPU_BUDGET_S:-400}
start=$SECONDS

# Every program resolves each library through the bundle, except glibc's and the driver's.
system='^(linux-vdso|ld-linux|libc|libm|libdl|libpthread|librt|libresolv|libutil|libcuda|libnvidia-)[.-]'
check_loads() {
  local bad=0 p name path
  for p in "$bin"/*; do
    while read -r name path; do
      if [[ "$path" == "not" ]]; then
        echo "run.sh: error: $(basename "$p") needs $name, which is not in the bundle" >&2
        bad=1
      elif [[ ! "$name" =~ $system && "$path" != "$here/lib/"* ]]; then
        echo "run.sh: error: $(basename "$p") loads $name from $path, outside the bundle" >&2
        bad=1
      fi
    done < <(ldd "$p" | awk '/=>/ {print $1, $3}')
  done
  # Loading is more than finding: symbol versions (GLIBCXX, CUDA) are checked by starting them.
  "$bin/test_gpu" --gtest_list_tests >/dev/null 2>&1 || { echo "run.sh: error: test_gpu does not start" >&2; bad=1; }
  "$bin/test_cuda" --gtest_list_tests >/dev/null 2>&1 || { echo "run.sh: error: test_cuda does not start" >&2; bad=1; }
  "$bin/visfield" structures >/dev/null 2>&1 || { echo "run.sh: error: visfield does not start" >&2; bad=1; }
  "$bin/visfield-bench" --help >/dev/null 2>&1 || { echo "run.sh: error: visfield-bench does not start" >&2; bad=1; }
  "$bin/visfield-experiments" --help >/dev/null 2>&1 || { echo "run.sh: error: visfield-experiments does not start" >&2; bad=1; }
  return $bad
}
check_loads || exit 1
if ! nvidia-smi -L 2>/dev/null | grep -q '^GPU'; then
  echo "run.sh: no GPU here (nvidia-smi lists none): all $(ls "$bin" | wc -l) programs load from the bundle; nothing run"
  exit 0
fi

mkdir -p "$out"
models=$here/models
export VISFIELD_MODELS_DIR=$models
threads=$(nproc)

declare -A took status
# step NAME LIMIT LOG COMMAND...: COMMAND under `timeout` (the smaller of LIMIT and the budget left),
# its output appended to LOG; status[NAME] is ok, failed (exit N), timed out, or skipped.
step() {
  local name=$1 limit=$2 log=$3
  shift 3
  local left=$((budget - (SECONDS - start)))
  ((limit > left)) && limit=$left
  if ((limit < 10)); then
    status[$name]="skipped (budget spent)"
    echo "## $name: skipped, ${left}s of the budget left" >>"$log"
    return
  fi
  local t0=$SECONDS rc
  echo "## $name (limit ${limit}s): $*" >>"$log"
  timeout --kill-after=5 "$limit" "$@" >>"$log" 2>&1
  rc=$?
  took[$name]=$((SECONDS - t0))
  case $rc in
    0) status[$name]=ok ;;
    124 | 137) status[$name]="timed out after ${limit}s" ;;
    *) status[$name]="failed (exit $rc)" ;;
  esac
  echo "## $name: ${status[$name]} in ${took[$name]}s" >>"$log"
  echo "run.sh: $name: ${status[$name]} in ${took[$name]}s"
}

# 1. The device.
{
  nvidia-smi
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv
  nvcc --version | tail -2
  compute-sanitizer --version 2>&1 | head -2
  cat "$here/BUILD"
  echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2) x $threads"
} >"$out/device.txt" 2>&1
step kernels 30 "$out/device.txt" cuobjdump --dump-resource-usage "$bin/test_cuda"
device=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1)
driver=$(nvidia-smi --query-gpu=driver_version --format=csv,noheader | head -1)
echo "run.sh: $device, driver $driver, $(date -u +%Y-%m-%d), budget ${budget}s"

# 2. Tests: a test without a device fails; every kernel kind bit for bit against the CPU.
VISFIELD_REQUIRE_CUDA=1 step tests 200 "$out/tests.log" "$bin/test_cuda"
step gpu-unit 60 "$out/tests.log" "$bin/test_gpu"

# 3. compute-sanitizer on a subset: memcheck at a tenth of the rays (it slows kernels ~100x), then
#    racecheck (shared-memory hazards) and synccheck (barriers and warp intrinsics such as the counts'
#    __match_any_sync) at a fiftieth, initcheck (reads of memory nothing wrote) at a five-hundredth.
subset='Cuda.EmptyInputs*:Cuda.ExactBvhBatch*:Cuda.FieldBatch*:Cuda.AoKernels*:Cuda.SoftShadowAndGlossy*'
VISFIELD_REQUIRE_CUDA=1 VISFIELD_TEST_SCALE=0.1 step memcheck 120 "$out/sanitizers.log" \
  compute-sanitizer --tool memcheck --leak-check full --error-exitcode 99 "$bin/test_cuda" --gtest_filter="$subset"
for tool in racecheck synccheck initcheck; do
  scale=0.02
  [[ $tool == initcheck ]] && scale=0.002
  VISFIELD_REQUIRE_CUDA=1 VISFIELD_TEST_SCALE=$scale step "$tool" 120 "$out/sanitizers.log" \
    compute-sanitizer --tool "$tool" --error-exitcode 99 "$bin/test_cuda" --gtest_filter="$subset"
done

# 4. The benchmark: AO from the camera's hits of a 1024x1024 view, 64 rays a hit, on the GPU beside
#    the CPU (all cores), fields 4226 x 32^2 (the default) and the exact GPU BVH.
for scene in bun_zipper.ply sponza.obj conference.obj; do
  step "bench-${scene%%.*}" 90 "$out/bench.log" "$bin/visfield-bench" --device cuda --scene "$models/$scene" --rays ao \
    --ao-rays 64 --width 1024 --height 1024 --accel bvh,field --threads "$threads" --warmup 1 --reps 5
done

# 5. The GPU paper's figures and an AO image rendered on the device.
step gpu5 90 "$out/figures.log" "$bin/visfield-experiments" --device cuda --figure gpu5 --scene "$models/igea-triangles.ply" --threads "$threads"
step gpu3 90 "$out/figures.log" "$bin/visfield-experiments" --device cuda --figure gpu3 --scene "$models/bun_zipper.ply" --threads "$threads"
step gpu7 90 "$out/figures.log" "$bin/visfield-experiments" --device cuda --figure gpu7 --scene "$models/bun_zipper.ply" --threads "$threads"
step render 60 "$out/figures.log" "$bin/visfield" render "$models/igea-triangles.ply" --device cuda --occluders field --ao-rays 121 \
  --width 512 --height 512 --out "$out/igea-ao.png" --no-progress
# The device's renders against the CPU renderer's, same settings, through fields and through the exact
# BVH: the same AO rays (each sample's generator continued) with the same answers, so RMS 0 (EXR: no
# 8-bit rounding to hide a difference).
images=${TMPDIR:-/tmp}/visfield-images
mkdir -p "$images"
for occluder in field exact; do
  for where in cuda cpu; do
    step "render-$occluder-$where" 60 "$out/figures.log" "$bin/visfield" render "$models/igea-triangles.ply" --device "$where" \
      --occluders "$occluder" --ao-rays 121 --width 512 --height 512 --threads "$threads" --out "$images/igea-$occluder-$where.exr" --no-progress
  done
  step "compare-$occluder" 30 "$out/figures.log" "$bin/visfield" compare "$images/igea-$occluder-cuda.exr" "$images/igea-$occluder-cpu.exr"
done

# 6. What bounds the AO kernel over fields and over the exact BVH: one launch of each through Nsight
#    Compute, if a minute is left.
if command -v ncu >/dev/null && ((budget - (SECONDS - start) >= 60)); then
  step ncu 90 "$out/ncu.log" ncu --clock-control none --kernel-name regex:^ao_kernel --launch-count 3 \
    --section SpeedOfLight --section ComputeWorkloadAnalysis --section MemoryWorkloadAnalysis --section Occupancy \
    --section LaunchStats --section WarpStateStats --section InstructionStats \
    "$bin/visfield-bench" --device cuda --scene "$models/bun_zipper.ply" --rays ao --ao-rays 64 --width 512 --height 512 \
    --accel bvh,field --threads "$threads" --warmup 0 --reps 1
fi

# 7. Many field objects: found through the tree over them (field), and by testing every sphere
#    (field:cull=each), on the device beside the CPU. The CPU's exact reference is flattened, as the GPU
#    BVH is (a two-level tree moves rays into object space and rounds otherwise).
for n in 9 1024; do
  step "bench-cows$n" 90 "$out/bench.log" "$bin/visfield-bench" --device cuda --scene "$models/cows$n.json" --rays ao \
    --ao-rays 16 --width 512 --height 512 --accel bvh:levels=1,field,field:cull=each --threads "$threads" --warmup 1 --reps 3
done

# 8. The summary: one screen.
column() {  # column FILE PATTERN N: field N (|-separated, trimmed) of the first line holding PATTERN
  grep -F -- "$2" "$1" 2>/dev/null | head -1 | awk -F'|' -v n="$3" '{gsub(/^ +| +$/, "", $n); print $n}'
}
rays() {  # rays KIND: rays test_cuda compared bit for bit for KIND
  awk -v k="$1" '$1 == "rays" && $2 == "compared:" && $3 == k {s += $4} END {printf "%.1fM", s / 1e6}' "$out/tests.log" 2>/dev/null
}
apart() {  # apart FIGURE: how far the figure's GPU RMS lie from the CPU's ("at most X%"), or its step's status
  local a
  a=$(awk -v f="## $1 (" 'index($0, f) == 1 {on = 1} on && match($0, /at most [0-9.]+%/) {print substr($0, RSTART, RLENGTH); exit}' "$out/figures.log" 2>/dev/null)
  echo "${a:-${status[$1]:-not run}}"
}
cuda_log=$(sed -n '/^## tests (/,/^## tests:/p' "$out/tests.log" 2>/dev/null)
passed=$(grep -m1 -oE '^\[  PASSED  \] [0-9]+' <<<"$cuda_log" | grep -oE '[0-9]+$')
failed=$(grep -m1 -oE '^\[  FAILED  \] [0-9]+ tests?,' <<<"$cuda_log" | grep -oE '[0-9]+')
skipped=$(grep -m1 -oE '^\[  SKIPPED \] [0-9]+ tests?,' <<<"$cuda_log" | grep -oE '[0-9]+')
tests_line="${passed:-0} passed, ${failed:-0} failed, ${skipped:-0} skipped"
summary_of() {  # summary_of TOOL: the sanitizer's closing count for its step
  sed -n "/^## $1 (/,/^## $1:/p" "$out/sanitizers.log" 2>/dev/null | grep -E -m1 'ERROR SUMMARY|RACECHECK SUMMARY' | sed 's/^=* *//'
}
rms_of() {  # rms_of OCCLUDER: visfield compare's RMS (0-255) of the device's render against the CPU's
  sed -n "/^## compare-$1 (/,/^## compare-$1:/p" "$out/figures.log" 2>/dev/null | awk '$1 == "rms:" {print $2; exit}'
}
cows() {  # cows N PATTERN: the GPU G rays/s of the first row holding PATTERN in the bench of N cows
  sed -n "/^## bench-cows$1 (/,/^## bench-cows$1:/p" "$out/bench.log" 2>/dev/null | grep -m1 -F -- "$2" | awk -F'|' '{gsub(/ /, "", $4); print $4}'
}
deep=$(grep -m1 '^nested shells: stack bound' "$out/tests.log" 2>/dev/null | sed 's/^nested shells: //')
frame=$(column "$out/figures.log" '| fields, kernel |' 3)
summary=$(
  cat <<EOF
# GPU run: $device, driver $driver, $(date -u +%Y-%m-%d)

$(cat "$here/BUILD" | head -1); $threads CPU threads; $((SECONDS - start)) s of the ${budget} s budget.

| check | result | target |
|---|---|---|
| cuda tests, VISFIELD_REQUIRE_CUDA=1 | ${status[tests]:-not run}: $tests_line | all pass, none skipped |
| rays compared bit for bit: BVH closest / any | $(rays bvh-closest) / $(rays bvh-any) | >= 10M each, 0 differ |
| rays compared bit for bit: fields inter / intra (closest and any each) | $(rays fields-inter) / $(rays fields-intra) | >= 10M each, 0 differ |
| rays compared bit for bit: AO kernel, fields / BVH | $(rays ao-kernel-fields) / $(rays ao-kernel-bvh) | >= 10M each, 0 differ |
| test_gpu (device code on the host) | ${status[gpu-unit]:-not run} | ok |
| compute-sanitizer memcheck, subset | ${status[memcheck]:-not run}: $(summary_of memcheck) | 0 errors |
| racecheck / synccheck / initcheck, subset | $(for t in racecheck synccheck initcheck; do printf '%s: %s; ' "${status[$t]:-not run}" "$(summary_of $t)"; done) | 0 each |
| the largest stack capacity, 80 nested shells | ${deep:-not run} | 449, 0 differ |
| field AO, device rays, bunny 4226 x 32^2 (G rays/s) | $(column "$out/bench.log" '| fields: ' 4) | >= 20 |
| field AO, the generic kernel (every choice read at run time), bunny (G rays/s) | $(column "$out/bench.log" '| fields, generic kernel: ' 4) | (measured) |
| field AO through 3D textures, bunny (G rays/s) | $(column "$out/bench.log" '| fields in 3D textures: ' 4) | (measured) |
| exact GPU BVH AO, bunny (G rays/s) | $(column "$out/bench.log" '| exact GPU BVH: ' 4) | >= 1.5 |
| exact GPU BVH AO, sponza (G rays/s) | $(grep -F '| exact GPU BVH: ' "$out/bench.log" 2>/dev/null | sed -n 2p | awk -F'|' '{gsub(/ /, "", $4); print $4}') | >= 1.5 |
| exact GPU BVH AO, conference (G rays/s) | $(grep -F '| exact GPU BVH: ' "$out/bench.log" 2>/dev/null | sed -n 3p | awk -F'|' '{gsub(/ /, "", $4); print $4}') | (measured) |
| bench rows where GPU and CPU differ | $(grep -c ' differ |' "$out/bench.log" 2>/dev/null) of $(grep -c -E 'bit-identical|differ \|' "$out/bench.log" 2>/dev/null) | 0 |
| Figure 5: igea 16642 x 64^2, 121 rays, 512x512 (ms a frame) | ${frame:-?} | <= 5 |
| Figures 3 and 7: GPU RMS against the CPU's | gpu3 $(apart gpu3), gpu7 $(apart gpu7) | within 1% |
| AO render of igea on the device | ${status[render]:-not run}: igea-ao.png | |
| igea render, device against CPU renderer (RMS 0-255): fields / exact BVH | $(rms_of field) / $(rms_of exact) | 0 |
| ncu, field AO kernel | ${status[ncu]:-not run}: ncu.log | |
| field AO, 9 / 1024 cows on a ground: tree; every sphere (G rays/s) | $(cows 9 '| fields: ') / $(cows 1024 '| fields: '); $(cows 9 'cull=each: ') / $(cows 1024 'cull=each: ') | (measured) |

Steps (s): $(for s in kernels tests gpu-unit memcheck racecheck synccheck initcheck bench-bun_zipper bench-sponza bench-conference gpu5 gpu3 gpu7 render render-field-cuda render-field-cpu render-exact-cuda render-exact-cpu ncu bench-cows9 bench-cows1024; do printf '%s %s, ' "$s" "${took[$s]:--}"; done)
EOF
)
echo "$summary" >"$out/summary.md"
echo
echo "$summary"
