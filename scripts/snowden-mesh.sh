#!/usr/bin/env bash
# Writes Snowden's bust as a binary PLY: a scanned mesh of 109,259 triangles that is not among the
# shared models, for the many-copies measurement (scripts/copies-scene.py BUST.ply N 10 OUT.json
# --ground 0, then visfield-bench --scene OUT.json --rays ao --accel field,embree:levels=2). The mesh comes from the npm package `snowden` 1.0.1 (stackgl, MIT; the bust's
# scan was published on Thingiverse, thing 815042), fetched with `npm pack` into a temporary folder
# and converted by node; nothing of it is kept in the repository.
# Usage: scripts/snowden-mesh.sh OUT.ply   (needs npm and node: apt-get install npm)
set -euo pipefail
out=${1:?usage: scripts/snowden-mesh.sh OUT.ply}
out=$(realpath -m "$out")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack --silent snowden@1.0.1 > /dev/null && tar xzf snowden-1.0.1.tgz)
# The package's hi.js holds the positions and faces as base64 float and integer arrays; a binary
# little-endian PLY of them is what visfield (and any mesh tool) reads. The bust is moved to stand
# on y = 0 with its x and z centred on the origin, so scaled copies stand on a ground at 0.
OUT="$out" node -e '
const mesh = require(process.argv[1]);
const header = "ply\nformat binary_little_endian 1.0\ncomment Snowden bust, npm package snowden 1.0.1 (MIT)\n" +
  `element vertex ${mesh.positions.length}\nproperty float x\nproperty float y\nproperty float z\n` +
  `element face ${mesh.cells.length}\nproperty list uchar int vertex_indices\nend_header\n`;
const lo = [0, 1, 2].map((k) => Math.min(...mesh.positions.map((p) => p[k])));
const hi = [0, 1, 2].map((k) => Math.max(...mesh.positions.map((p) => p[k])));
const shift = [-(lo[0] + hi[0]) / 2, -lo[1], -(lo[2] + hi[2]) / 2];
const vertices = Buffer.alloc(12 * mesh.positions.length);
mesh.positions.forEach((p, i) => p.forEach((c, k) => vertices.writeFloatLE(c + shift[k], 12 * i + 4 * k)));
const faces = Buffer.alloc(13 * mesh.cells.length);
mesh.cells.forEach((f, i) => { faces.writeUInt8(3, 13 * i); f.forEach((v, k) => faces.writeInt32LE(v, 13 * i + 1 + 4 * k)); });
require("fs").writeFileSync(process.env.OUT, Buffer.concat([Buffer.from(header, "ascii"), vertices, faces]));
' "$work/package/hi.js" 2> /dev/null
echo "wrote $out"
