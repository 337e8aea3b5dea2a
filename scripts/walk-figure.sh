#!/usr/bin/env bash
# Reproduces the VLF-RT paper's Figure 6 on Sponza (the nearest we have to its 51K-polygon
# classroom): a 420-frame walk down the atrium at 256x256, 4 point lights, ray casting and Whitted,
# BeamField (513 directions, 128x128 tiles) against the median BSP, the kd-tree, the BVH and Embree.
# Writes docs/walkthrough-measurements.md, the frame times as CSV in docs/data/walk-raycast/ and
# docs/data/walk-whitted/ (one file per structure), and their plots docs/images/walk-raycast.svg and
# walk-whitted.svg.
# Usage: scripts/walk-figure.sh MODELS_DIR [FRAMES]   (MODELS_DIR holds sponza.obj; takes about 2 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
models=$(cd "${1:?usage: scripts/walk-figure.sh MODELS_DIR [FRAMES]}" && pwd)
frames=${2:-420}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/sponza-walk.json" <<JSON
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
accels=beam:dirs=513,n=128,median-bsp,kdtree,bvh
build/bin/visfield-bench --help | grep -q "embree" && accels="$accels,embree"
out=docs/walkthrough-measurements.md
{
  echo "# Walkthrough measurements (VLF-RT Figure 6)"
  echo
  echo "Written by \`scripts/walk-figure.sh MODELS_DIR\` on $(date -u +%Y-%m-%d), $(nproc) threads, $(lscpu | sed -n 's/^Model name: *//p' | head -1)."
  echo "Sponza (Marko Dabrovic, 66,450 triangles) walked through in $frames frames of 256x256, 4 point lights,"
  echo "every structure rendering the same frames in one process (\`visfield-bench --walk\`); BeamField at 513 directions x 128x128 tiles."
  for mode in raycast whitted; do
    echo
    echo "## $mode"
    echo
    echo "\`visfield-bench --walk $frames --scene sponza-walk.json --accel $accels --integrator $mode --walk-csv docs/data/walk-$mode --walk-plot docs/images/walk-$mode.svg\`"
    echo
    rm -rf "docs/data/walk-$mode"
    mkdir -p "docs/data/walk-$mode"
    build/bin/visfield-bench --walk "$frames" --scene "$work/sponza-walk.json" --accel "$accels" --integrator "$mode" \
      --walk-csv "docs/data/walk-$mode" --walk-plot "docs/images/walk-$mode.svg" | sed "s|$work/||"
    echo
    echo "![$mode](images/walk-$mode.svg) (the frame times: [data/walk-$mode/](data/walk-$mode/))"
  done
} > "$out"
echo "wrote $out"
