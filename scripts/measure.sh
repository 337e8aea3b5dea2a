#!/usr/bin/env bash
# Measures what visfield does on this machine: the headline workloads, each run as a user would run
# it, its raw output kept, then the headline table printed (the README's, made from these files).
#
# Usage: scripts/measure.sh [--quick] [--models DIR] [--out DIR] [--build DIR]
#   --quick    one mesh a workload, fewer repetitions, no walkthroughs or planner (the target: 10 minutes
#              on 2 cores, the full run 45; bench/results has the measured times)
#   --models   the test meshes (default ../shared/models; docs/testing.md names their public sources)
#   --out      where the raw files go (default bench/results/<date>-<cpu>-<kernels>)
#   --build    the build whose programs run (default build; it needs visfield-bench, hence
#              README command 2's configuration, and Embree for the comparisons)
# VISFIELD_ISA=avx2 measures the AVX2 kernels on a machine with AVX-512 (Embree then runs its AVX2
# code too). Every workload writes NAME.json (command, commit, date, wall time, output) beside
# machine.json; scripts/results.py makes the tables from them.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
quick=0 models=$root/../shared/models out="" build=$root/build
while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) quick=1 ;;
    --models) models=${2:?--models needs a folder}; shift ;;
    --out) out=${2:?--out needs a folder}; shift ;;
    --build) build=${2:?--build needs a folder}; shift ;;
    *) echo "measure: error: unknown option '$1' (--quick, --models DIR, --out DIR, --build DIR)" >&2; exit 2 ;;
  esac
  shift
done
bench=$build/bin/visfield-bench visfield=$build/bin/visfield experiments=$build/bin/visfield-experiments
for p in "$bench" "$visfield" "$experiments"; do
  [[ -x $p ]] || { echo "measure: error: $p is not built (README command 2 builds it)" >&2; exit 2; }
done
"$bench" --scene builtin:cornell --rays ao --accel embree --count 10 --reps 1 >/dev/null 2>&1 ||
  { echo "measure: error: $bench has no Embree (install libembree-dev: scripts/install-deps.sh --all, and build again)" >&2; exit 2; }
[[ -d $models ]] || { echo "measure: error: no models folder '$models' (--models DIR)" >&2; exit 2; }
models=$(cd "$models" && pwd)
py=/usr/bin/python3
results="$py $root/scripts/results.py"
kernels=$("$visfield" info builtin:cornell | sed -n 's/^kernels: *\([a-z0-9]*\).*/\1/p')
cpu=$(sed -n 's/^model name[^:]*: *//p' /proc/cpuinfo | head -1 | tr 'A-Z' 'a-z' | tr -cs 'a-z0-9' '-' | sed 's/-$//')
out=${out:-$root/bench/results/$(date -u +%Y-%m-%d)-$cpu-$kernels$([[ $quick == 1 ]] && echo -quick || true)}
mkdir -p "$out"
$results machine "$out" "$visfield"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start=$SECONDS
record() { $results run "$out" "$@"; }  # record NAME -- COMMAND...

# Meshes a workload runs on: one in --quick, all otherwise.
pick() { if [[ $quick == 1 ]]; then echo "$1"; else echo "$@"; fi; }
need() { for m in "$@"; do [[ -f $models/$m ]] || { echo "measure: error: $models/$m is missing" >&2; exit 2; }; done; }
reps=$([[ $quick == 1 ]] && echo 3 || echo 5)

# 1. The exact BVH against Embree, as most users call it and at its best: each mesh, each ray kind,
#    1M rays, 2 threads; our BVH through its batch path and one ray at a time (call=1).
bvh_models=$(pick bun_zipper.ply dragon_vrip_res2.ply Armadillo.ply sponza.obj conference.obj cow.obj)
need $bvh_models
for m in $bvh_models; do
  for kind in ao shadow primary random; do
    record "bvh-$kind-${m%%.*}" -- "$bench" --scene "$models/$m" --rays "$kind" --accel bvh,bvh:call=1,embree,embree:call=best --count 1000000 \
      --threads 2 --reps "$reps" --json
  done
done

# 2. Copies of meshes: the two-level BVH against Embree's instancing.
need bun_zipper.ply cow.obj
$py "$root/scripts/copies-scene.py" "$models/bun_zipper.ply" 100 0.25 "$work/bunnies100.json" >/dev/null
$py "$root/scripts/copies-scene.py" "$models/cow.obj" 1000 15 "$work/cows1000.json" >/dev/null
for scene in $(pick bunnies100 cows1000); do
  for kind in ao primary; do
    record "instances-$kind-$scene" -- "$bench" --scene "$work/$scene.json" --rays "$kind" \
      --accel bvh:levels=2,embree:levels=2,embree:levels=2,call=best --count 1000000 --threads 2 --reps "$reps" --json
  done
done

# 3. BeamField on VLF-RT's Table 1 workload: a 256x256 view, an AO ray along each of the 513 lines
#    from every visible point; against our median BSP (the paper's baseline) and Embree.
beam_models=$(pick cow.obj bun_zipper.ply igea-triangles.ply)
need $beam_models
for m in $beam_models; do
  record "beam-table1-${m%%.*}" -- "$bench" --scene "$models/$m" --rays ao --ao-directions 513 --width 256 --height 256 \
    --accel beam,median-bsp,embree --threads 2 --reps 3 --warmup 1 --json
done

# 4. ObjectField: AO rays from each mesh's own surface; 1024 copies on a ground; the corner's inter-object AO.
field_models=$(pick bun_zipper.ply dragon_vrip_res2.ply Armadillo.ply cow.obj)
need $field_models
for m in $field_models; do
  record "field-intra-${m%%.*}" -- "$bench" --scene "$models/$m" --rays ao --accel "field:cache=$work/fields,embree" --count 1000000 \
    --threads 2 --reps "$reps" --json
done
$py "$root/scripts/copies-scene.py" "$models/bun_zipper.ply" 1024 0.25 "$work/bunnies1024.json" --ground 0.025 >/dev/null
record field-copies-1024 -- "$bench" --scene "$work/bunnies1024.json" --rays ao --accel "field:cache=$work/fields,embree:levels=2" \
  --count 1000000 --threads 2 --reps "$reps" --json
if [[ $quick == 0 ]]; then
  need cow.obj bun_zipper.ply igea-triangles.ply dragon_vrip_res2.ply Armadillo.ply
  record field-corner -- "$experiments" --figure fig8 --scene "$models"
fi

# 5. A render through fields against the same render through the exact BVH (Igea, 512x512, 121 AO
#    rays a pixel), three rounds interleaved, then the images compared.
need igea-triangles.ply
rounds=$([[ $quick == 1 ]] && echo 1 || echo 3)
for round in $(seq "$rounds"); do
  for occluders in exact field; do
    suffix=$([[ $round == 1 ]] && echo "" || echo "-$round")
    record "render-ao-$occluders$suffix" -- "$visfield" render "$models/igea-triangles.ply" --occluders "$occluders" --ao-rays 121 \
      --width 512 --height 512 --threads 2 --out "$work/igea-$occluders.exr" --no-progress
  done
done
record render-ao-compare -- "$visfield" compare "$work/igea-field.exr" "$work/igea-exact.exr"
# The GPU fields paper's rendered figures on the CPU: soft shadows (Figures 7 and 8), glossy
# reflections with normal fields (Figure 9).
if [[ $quick == 0 ]]; then
  need bun_zipper.ply dragon_vrip_res2.ply Armadillo.ply
  record render-gpu7 -- "$experiments" --figure gpu7 --scene "$models/bun_zipper.ply" --threads 2
  record render-gpu8 -- "$experiments" --figure gpu8 --scene "$models" --threads 2
  record render-gpu9-bunny -- "$experiments" --figure gpu9 --scene "$models/bun_zipper.ply" --threads 2
fi

# 6. The VLF-RT paper's walkthrough (its Figure 6) on Sponza: 420 frames of 256x256, 4 point lights.
if [[ $quick == 0 ]]; then
  need sponza.obj
  cat >"$work/sponza-walk.json" <<JSON
{
  "name": "sponza-walk",
  "meshes": [{"name": "sponza", "path": "$models/sponza.obj"}],
  "camera": {"position": [-14, 2, 0], "look_at": [0, 2.5, 0], "fov_deg": 60, "width": 256, "height": 256},
  "camera_path": [
    {"time": 0, "position": [-14, 2, 0], "look_at": [0, 2.5, 0]},
    {"time": 1, "position": [-4, 2.5, 2], "look_at": [8, 3, 0]},
    {"time": 2, "position": [8, 3, 1], "look_at": [14, 6, -4]},
    {"time": 3, "position": [12, 6, 0], "look_at": [0, 4, -3]},
    {"time": 4, "position": [0, 8, -3], "look_at": [-12, 3, 2]}
  ],
  "lights": [
    {"type": "point", "position": [-10, 12, 0], "intensity": [120, 115, 100]},
    {"type": "point", "position": [-3, 12, 0], "intensity": [120, 115, 100]},
    {"type": "point", "position": [3, 12, 0], "intensity": [120, 115, 100]},
    {"type": "point", "position": [10, 12, 0], "intensity": [120, 115, 100]}
  ]
}
JSON
  for mode in raycast whitted; do
    record "walk-$mode" -- "$bench" --walk 420 --scene "$work/sponza-walk.json" --accel beam:dirs=513,n=128,median-bsp,kdtree,bvh,embree \
      --integrator "$mode" --threads 2
  done
fi

# 7. The planner: every structure measured on the meshes, built-in scenes and copies; how often its
#    choice is the measured fastest on scenes it was not calibrated on.
if [[ $quick == 0 ]]; then
  record planner -- "$visfield" report --models "$models" --scene "$work/bunnies100.json" --rays 20000 --sample-rays 500 \
    --build-repetitions 1 --seed 1 --threads 2 --splits 20 --split-seed 1 --out "$work/report.md"
  cp "$work/report.md" "$out/planner-report.md"
fi

echo "measure: $((SECONDS - start)) s; raw files in ${out#$root/}" >&2
$results table "$out"
