#!/usr/bin/env bash
# Renders the integrator pictures of the README (docs/images/integrators/*.png): the Stanford bunny
# (clay) and the Utah teapot (polished metal) on a ground, one sphere light and one point light,
# through every integrator of `visfield render`, exact geometry (the BVH).
# Usage: scripts/integrator-gallery.sh MODELS_DIR [OUT_DIR]   (MODELS_DIR holds bun_zipper.ply, teapot.obj)
set -euo pipefail
cd "$(dirname "$0")/.."
models=$(cd "${1:?usage: scripts/integrator-gallery.sh MODELS_DIR [OUT_DIR]}" && pwd)
out=${2:-docs/images/integrators}
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/ground.obj" <<'OBJ'
v -8 0 -8
v -8 0 8
v 8 0 8
v 8 0 -8
f 1 2 3 4
OBJ
cat > "$work/gallery.json" <<JSON
{
  "name": "gallery",
  "meshes": [
    {"name": "bunny", "path": "$models/bun_zipper.ply"},
    {"name": "teapot", "path": "$models/teapot.obj"},
    {"name": "ground", "path": "ground.obj", "occluder": "exact"}
  ],
  "materials": [
    {"name": "clay", "diffuse": [0.75, 0.55, 0.4]},
    {"name": "metal", "diffuse": [0.05, 0.05, 0.05], "specular": [0.85, 0.8, 0.7], "roughness": 0.08},
    {"name": "floor", "diffuse": [0.55, 0.55, 0.6], "specular": [0.15, 0.15, 0.15], "roughness": 0.3}
  ],
  "instances": [
    {"mesh": "bunny", "scale": 10, "translate": [-0.5, -0.33, 0], "material": "clay"},
    {"mesh": "teapot", "scale": 0.25, "translate": [1.0, 0, 0.3], "rotate_euler_deg": [0, -30, 0], "material": "metal"},
    {"mesh": "ground", "material": "floor"}
  ],
  "camera": {"position": [0, 1.6, 4.5], "look_at": [0, 0.6, 0], "up": [0, 1, 0], "fov_deg": 40, "width": 320, "height": 240},
  "lights": [
    {"type": "sphere", "center": [-2, 4, 3], "radius": 0.4, "radiance": [40, 38, 34]},
    {"type": "point", "position": [2.5, 5, 3], "intensity": [20, 20, 22]}
  ]
}
JSON
render() { build/bin/visfield render "$work/gallery.json" --no-progress "$@" | tail -1; }
render --integrator raycast --spp 4 --out "$out/raycast.png"
render --integrator whitted --spp 4 --out "$out/whitted.png"
render --integrator ao --spp 4 --ao-rays 32 --out "$out/ao.png"
render --integrator softshadow --spp 4 --shadow-rays 8 --out "$out/softshadow.png"
render --integrator glossy --spp 4 --glossy-rays 4 --out "$out/glossy.png"
render --integrator path --spp 64 --depth 6 --out "$out/path.png"
