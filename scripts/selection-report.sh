#!/usr/bin/env bash
# Measures every structure on the shared meshes, the built-in scenes and two scenes of copies; makes
# the measurements the built-in calibration (src/select/builtin_calibration.json) and writes
# docs/selection-report.md from it (the paper's Table 1, leave-k-out and decision accuracy; the
# planner's accuracy and regret; fields sized from a target error).
#   scripts/selection-report.sh MODELS_DIR [WORK_DIR]    (about 20 minutes on 2 cores)
# The report alone, from the built-in measurements:
#   visfield report --from src/select/builtin_calibration.json --splits 20 --split-seed 1 --out docs/selection-report.md
set -euo pipefail
models=${1:?usage: $0 MODELS_DIR [WORK_DIR]}
work=${2:-build/selection-report}
root="$(cd "$(dirname "$0")/.." && pwd)"
visfield=${VISFIELD:-$root/build/bin/visfield}
mkdir -p "$work"
# Scenes of many objects for the instanced and field candidates: 25 cows, and 100 on an exact ground.
/usr/bin/python3 "$root/scripts/copies-scene.py" "$models/cow.obj" 25 15 "$work/cows25.json"
/usr/bin/python3 "$root/scripts/copies-scene.py" "$models/cow.obj" 100 15 "$work/cows100-ground.json" --ground -4.4
# BeamField over a few GiB is left out (refused by the limit), as a user's machine would refuse it.
measure=("$visfield" report --models "$models" --scene "$work/cows25.json" --scene "$work/cows100-ground.json"
  --rays 100000 --sample-rays 500 --build-repetitions 3 --bounces 2 --seed 1 --threads 2 --max-memory 6GiB
  --save-measurements "$work/calibration.json" --splits 20 --split-seed 1 --out "$work/measured-report.md")
"${measure[@]}"
"$root/scripts/builtin-calibration.sh" "$work/calibration.json" "scripts/selection-report.sh MODELS_DIR, that is: ${measure[*]#$root/}"
cd "$root"
"$visfield" report --from src/select/builtin_calibration.json --splits 20 --split-seed 1 --out docs/selection-report.md
