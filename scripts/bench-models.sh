#!/usr/bin/env bash
# Runs visfield-bench on every mesh of a folder (default: test-meshes in the checkout) for one ray kind and
# prints a markdown table: per structure Mrays/s (ratio to Embree; build ms; rays that disagree with
# Embree's answer).
# Usage: scripts/bench-models.sh [MODELS_DIR] [RAY_KIND] [ACCELS] [extra visfield-bench options...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
models=${1:-$root/test-meshes}
kind=${2:-ao}
accels=${3:-bvh,kdtree,grid,median-bsp,embree}
shift $(( $# < 3 ? $# : 3 ))
bench=$root/build/bin/visfield-bench
[ -x "$bench" ] || { echo "bench-models: error: $bench not built (run the README's build first)" >&2; exit 1; }

echo "| model | triangles | rays | $(echo "$accels" | sed 's/,/ Mrays\/s (× Embree) | /g') Mrays/s |"
echo "|---|---:|---:|$(echo "$accels" | sed 's/[^,]*/---:/g; s/,/|/g')|"
for mesh in "$models"/*.{obj,ply,gltf,glb,stl}; do
  [ -f "$mesh" ] || continue
  "$bench" --scene "$mesh" --rays "$kind" --accel "$accels" --threads 2 --json "$@" 2>/dev/null | python3 -c '
import json, sys
r = json.load(sys.stdin)
cells = []
for row in r["results"]:
    ratio = row.get("ratio_to_embree")
    cells.append("%.2f (%s; %.0f ms; %d)" % (row["mrays_per_s"], "%.2f×" % ratio if ratio is not None else "n/a",
                                             row["build_ms"], row["mismatches"]))
print("| %s | %d | %d | %s |" % (sys.argv[1], r["triangles"], r["rays"], " | ".join(cells)))
' "$(basename "$mesh")"
done
