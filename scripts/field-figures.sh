#!/usr/bin/env bash
# Regenerates the ObjectField measurements (docs/objectfield-measurements.md): the 2008 paper's
# Figures 6, 5/7 and 8 with visfield-bench --figure, and the GPU paper's intra-object AO (121 rays
# per pixel at 16642 positions x 64^2) as renders compared with the exact ones.
# Usage: scripts/field-figures.sh MODELS_DIR [OUT.md]   (MODELS_DIR holds bun_zipper.ply, cow.obj, ...)
set -euo pipefail
cd "$(dirname "$0")/.."
models=${1:?usage: scripts/field-figures.sh MODELS_DIR [OUT.md]}
out=${2:-docs/objectfield-measurements.md}
bin=build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
{
  echo "# ObjectField measurements"
  echo
  echo "Written by \`scripts/field-figures.sh MODELS_DIR\` on $(date -u +%Y-%m-%d), $(nproc) threads."
  echo
  "$bin/visfield-bench" --figure fig6 --scene "$models/bun_zipper.ply"
  echo
  "$bin/visfield-bench" --figure fig5 --scene "$models/bun_zipper.ply"
  echo
  "$bin/visfield-bench" --figure fig8 --scene "$models"
  echo
  echo "## GPU paper, Figure 5 on the CPU: intra-object AO, 256x256 pixels, 121 rays per pixel, 16642 x 64x64"
  echo
  for model in igea-triangles.ply Armadillo.ply; do
    echo "### $model"
    echo
    echo '```'
    "$bin/visfield" render "$models/$model" --width 256 --height 256 --ao-rays 121 --no-progress --out "$work/exact.png" | tail -1
    "$bin/visfield" render "$models/$model" --width 256 --height 256 --ao-rays 121 --no-progress \
      --occluder field:positions=16642,directions=64 --out "$work/field.png" | tail -1
    "$bin/visfield" compare "$work/field.png" "$work/exact.png"
    echo '```'
    echo
  done
} > "$out"
echo "wrote $out"
