#!/usr/bin/env bash
# Regenerates docs/render-figures.md: the GPU visibility-fields paper's ray-tracing figures on the
# CPU with visfield's integrators (soft shadows, Figures 7 and 8; glossy reflections with normal
# fields, Figure 9), fields against the exact BVH, then `visfield compare` on every field-vs-exact
# pair of images, and a few of the images (with their x5 error images) in docs/images/figures.
# Usage: scripts/render-figures.sh MODELS_DIR [OUT.md]   (MODELS_DIR holds bun_zipper.ply,
# dragon_vrip_res2.ply, Armadillo.ply; about 2 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
models=$(cd "${1:?usage: scripts/render-figures.sh MODELS_DIR [OUT.md]}" && pwd)
out=${2:-docs/render-figures.md}
experiments=build/bin/visfield-experiments
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
compare() {  # IMAGE REFERENCE: one table row of visfield compare's figures
  local line
  line=$(build/bin/visfield compare "$work/$1" "$work/$2" | tr '\n' ' ')
  echo "| $1 | $2 | $line |"
}
{
  echo "# The GPU fields paper's rendered figures, on the CPU"
  echo
  echo "Written by \`scripts/render-figures.sh MODELS_DIR\` on $(date -u +%Y-%m-%d), $(nproc) threads, $(lscpu | sed -n 's/^Model name: *//p' | head -1)."
  echo "Render times are medians of three after a warm-up and include the camera rays (through the BVH) and the shading."
  echo "RMS is over all pixels on the 0-255 scale, values clamped to [0, 1]."
  echo
  "$experiments" --figure gpu7 --scene "$models/bun_zipper.ply" --figure-images "$work"
  echo
  "$experiments" --figure gpu8 --scene "$models" --figure-images "$work"
  echo
  "$experiments" --figure gpu9 --scene "$models/bun_zipper.ply" --figure-images "$work"
  echo
  "$experiments" --figure gpu9 --scene "$models/Armadillo.ply" --figure-images "$work"
  echo
  echo "## visfield compare on every field-vs-exact pair"
  echo
  echo "The rendered PNGs (8-bit sRGB) compared by \`visfield compare IMAGE REFERENCE\` (linear values, so the"
  echo "figures differ a little from the tables' RMS of the linear renders clamped to [0, 1])."
  echo
  echo "| image | reference | visfield compare |"
  echo "|---|---|---|"
  for f in gpu7-field4226x32 gpu7-field4226x64 gpu7-field4226x128 gpu7-field16642x32 gpu7-field16642x64 gpu7-field16642x128 gpu7-exact20; do
    compare "$f.png" gpu7-exact256.png
  done
  compare gpu8-field4226x64.png gpu8-exact256.png
  compare gpu8-exact20.png gpu8-exact256.png
  for m in bun_zipper Armadillo; do
    compare "gpu9-$m-field4226x32.png" "gpu9-$m-exact.png"
    compare "gpu9-$m-field4226x64.png" "gpu9-$m-exact.png"
  done
  echo
  mkdir -p docs/images/figures
  cp "$work/gpu7-exact256.png" "$work/gpu7-field4226x64.png" "$work/gpu9-bun_zipper-exact.png" "$work/gpu9-bun_zipper-field4226x64.png" docs/images/figures/
  build/bin/visfield compare "$work/gpu7-field4226x64.png" "$work/gpu7-exact256.png" --diff docs/images/figures/gpu7-field4226x64-error.png > /dev/null
  build/bin/visfield compare "$work/gpu9-bun_zipper-field4226x64.png" "$work/gpu9-bun_zipper-exact.png" --diff docs/images/figures/gpu9-bun_zipper-field4226x64-error.png > /dev/null
  echo "| | exact | fields 4226 x 64x64 | error x5 |"
  echo "|---|---|---|---|"
  echo "| gpu7 soft shadows | ![](images/figures/gpu7-exact256.png) | ![](images/figures/gpu7-field4226x64.png) | ![](images/figures/gpu7-field4226x64-error.png) |"
  echo "| gpu9 glossy | ![](images/figures/gpu9-bun_zipper-exact.png) | ![](images/figures/gpu9-bun_zipper-field4226x64.png) | ![](images/figures/gpu9-bun_zipper-field4226x64-error.png) |"
} | sed -e "s|$models/||g" -e "s|$models|MODELS_DIR|g" -e "s|$work/||g" > "$out"
echo "wrote $out"
