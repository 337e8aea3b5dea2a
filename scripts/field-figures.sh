#!/usr/bin/env bash
# Regenerates the ObjectField measurements (docs/objectfield-measurements.md): the speed against
# Embree on the same AO rays, the 2008 paper's Figures 6, 5/7 and 8 and the lookup options with
# visfield-experiments --figure, and the GPU paper's Figures 3 and 5 on the CPU.
# Usage: [SNOWDEN=BUST.ply] scripts/field-figures.sh MODELS_DIR [OUT.md]   (MODELS_DIR holds bun_zipper.ply, cow.obj, ...)
# With SNOWDEN (written by scripts/snowden-mesh.sh: a scanned mesh not among the shared models) the
# many-copies measurement runs on its copies too. Takes 8-12 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
models=${1:?usage: scripts/field-figures.sh MODELS_DIR [OUT.md]}
out=${2:-docs/objectfield-measurements.md}
if [[ ! -f "$models/bun_zipper.ply" ]]; then
  echo "field-figures: error: $models holds no bun_zipper.ply (usage: scripts/field-figures.sh MODELS_DIR [OUT.md])" >&2
  exit 2
fi
bin=build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
threads=$(nproc)
# copies_tables MESH SPACING GROUND NAME: the bench's tables for 9 and 1024 copies of MESH on a ground.
copies_tables() {
  for count in 9 1024; do
    /usr/bin/python3 scripts/copies-scene.py "$1" "$count" "$2" "$work/$4$count.json" --ground "$3"
    echo '```'
    # From the scene's folder, so that the fields' cache has a short name in the table.
    (cd "$work" && "$root/$bin/visfield-bench" --scene "$4$count.json" --rays ao --accel field:cache=cache,field:cull=tree,cache=cache,field:cull=each,cache=cache,embree:levels=2 \
      --count 1000000 --threads "$threads" --reps 5)
    echo '```'
    echo
  done
}
{
  echo "# ObjectField measurements"
  echo
  echo "Written by \`scripts/field-figures.sh MODELS_DIR\` on $(date -u +%Y-%m-%d), $threads threads, $(lscpu | sed -n 's/^Model name: *//p' | head -1)."
  echo "Times are medians of three runs after a warm-up (fig8: of 15 rounds, interleaved); on a shared machine single figures read up to 10% apart."
  echo "The README's ObjectField section says what they mean."
  echo
  echo "## Speed against Embree on the same rays"
  echo
  echo "Intra-object AO: 1M rays, 4 per pixel, from each model's own surface (unlimited length);"
  echo "\`visfield-bench --scene MODEL --rays ao --accel field,bvh,embree --count 1000000 --threads $threads --reps 5\`."
  echo "Inter-object AO from the Figure-6 corner is the fig8 table below (field vs Embree column)."
  echo
  for model in cow.obj bun_zipper.ply dragon_vrip_res2.ply Armadillo.ply; do
    echo '```'
    "$bin/visfield-bench" --scene "$models/$model" --rays ao --accel field,bvh,embree --count 1000000 --threads "$threads" --reps 5
    echo '```'
    echo
  done
  echo "## The lookup's arithmetic, measured one change at a time"
  echo
  echo "Measured on 2026-11-26 (Intel Xeon, 2 threads) with binaries built before and after each change, interleaved,"
  echo "\`visfield-bench --scene MODEL --rays ao --accel field,embree --count 4000000 --threads 2 --reps 9\`, medians of 3 rounds (Mrays/s):"
  echo
  echo "| change | bunny | dragon | Armadillo | cow | kept |"
  echo "|---|---|---|---|---|---|"
  echo "| explicit fused multiply-adds (\`hd::fma\`, \`hd::fused_dot\`: dot products, polynomials, points along the ray) | 116.1 → 120.3 | 106.8 → 109.4 | 108.7 → 114.3 | 119.3 → 122.2 | yes (+2.5–5%; \`--figure lookups\`: 4–7% fewer ns a ray, errors unchanged to 3 digits) |"
  echo "| products by per-field reciprocals (the lattice angle's 1/(π/2), the through shift's 1/(2R)) | 120.3 → 117.3 | | 114.3 → 115.0 | | no (within noise) |"
  echo "| the kernel specialised at compile time for the default field (concentric, u8, no normals, nearest lookups: the choices as constants of an inlined copy) | 110.8 → 110.2 | | 107.9 → 108.5 | | no (within noise) |"
  echo
  echo "The batch kernel's time goes to the cell gather (15% of its samples on the instruction after it) and the"
  echo "lattice corners' gather (3%); the arithmetic is spread thin, so removing operations pays little on the CPU."
  echo
  echo "## The start-surface limit of a read from inside"
  echo
  echo "Read through the origin (\`through=1\`, the default), a sample's line leaves an AO ray by up to the sample"
  echo "spacing; on a convex surface it enters the object just before the origin. A hit from inside must now clear"
  echo "max(self_offset, kChordShare · |q − ray|) beyond the origin (\`field/field_query.hpp\`), with kChordShare = 1/4."
  echo "AO image RMS (0–255, hit pixels) against the exact render with the same rays,"
  echo "\`visfield render SCENE --occluder field:positions=P,directions=D --ao-rays 32 --width 128 --height 128\`,"
  echo "measured 2026-11-26 before → after (the whole chord, share 1, gave bunny 1090 × 64² 3.68 and cow 4.26):"
  echo
  echo "| scene | 1090 × 32² | 1090 × 64² | 4226 × 32² | 16642 × 64² |"
  echo "|---|---|---|---|---|"
  echo "| builtin:sphere | 0.27 → 0.27 | **15.08 → 0.28** | 0.27 → 0.27 | 0.28 → 0.27 |"
  echo "| bun_zipper.ply | 3.45 → 3.45 | 2.78 → 2.78 | 4.06 → 4.06 | 3.94 → 3.93 |"
  echo "| cow.obj | 3.93 → 3.96 | 3.11 → 3.17 | 4.23 → 4.24 | 3.93 → 4.03 |"
  echo "| Armadillo.ply | 3.66 → 3.68 | 3.14 → 3.19 | 3.58 → 3.59 | 3.40 → 3.40 |"
  echo "| builtin:cornell | 1.69 → 1.69 | 1.47 → 1.32 | 1.86 → 1.86 | 1.62 → 1.62 |"
  echo
  echo "Speed is unchanged (bunny AO, 3 interleaved rounds: 100.7–107.0 before, 102.7–109.0 Mrays/s after)."
  echo "Only reads from inside change. In fig6 below, the default column (through the far end) is unchanged to 3 digits;"
  echo "the through + bilinear + blend column, whose three samples lie further from the exit, rose at coarse"
  echo "positions (290 × 32²: 5.09 → 5.49; 1090 × 32²: 3.12 → 3.21) and is within 1% from 4226 positions on."
  echo
  echo "## Scenes of field objects on an exact ground, measured one change at a time"
  echo
  echo "Measured on 2026-11-26 as above, on copies of Snowden's bust (below), \`field,embree:levels=2 --count 1000000 --reps 5\`,"
  echo "two rounds (Mrays/s):"
  echo
  echo "| change | 9 busts | 1024 busts |"
  echo "|---|---|---|"
  echo "| before (the ground's BVH walked per ray, the tree at 9 objects, leftover rays one at a time) | 20.0, 20.7 | 9.7, 10.0 |"
  echo "| the exact part of ≤ 64 triangles tested in packets of rays on lanes | 26.3, 25.1 | 11.6, 11.0 |"
  echo "| up to 16 objects: each sphere against the block's rays on lanes, no tree | 35.1, 34.0 | 11.8, 11.7 |"
  echo "| an object's leftover partial packets through the kernel, spare lanes repeating a ray | 32.6, 32.7 | 11.1, 11.9 (the others of this row 31.5, 31.4 / 10.5, 10.5) |"
  echo
  echo "Before the first change a lone ray's walk of the ground's two-triangle BVH cost more than its field lookup"
  echo "(\`perf\`: 9.3% of the samples against 7.5% for the kernel); at 1024 objects the tree walk (13%) and the"
  echo "block's pairing and sphere tests (8%) then outweighed the lookups (6%)."
  echo
  echo "Measured on 2026-11-27 (AMD EPYC, 2 threads) on 1024 bunnies (below), \`field,embree:levels=2 --count 1000000"
  echo "--reps 5\` or \`--reps 7\`, Mrays/s of the fields (Embree's instancing in the same runs: 7.8–9.8, as the machine's load went):"
  echo
  echo "| change | 1024 bunnies | kept |"
  echo "|---|---|---|"
  echo "| before: each ray walked the tree over the objects (eight walks interleaved), its (object, ray) pairs grouped by object with a counting sort | 16.35 (9 bunnies 69.5) | |"
  echo "| the walks' pairs taken in rounds (each ray's first object, then its second...), each round's rays of all objects in one kernel batch | 13.9–14.3 | no |"
  echo "| the block's rays sent down the tree together (\`BoxTree::rays_by_item\`): each node tests its rays, each child gets those that meet its box, each object's rays arrive grouped | 17.5–18.4 | yes |"
  echo "| each object's open rays copied side by side before its sphere test and kernel, instead of gathered from the block by each | 17.5–22.5 → 23.6–23.8 | yes |"
  echo "| a node's test 16 rays at a time against a box (AVX-512), the rays' values moving down in columns, instead of a ray at a time against 8 boxes | 23.6–23.8 → 25.0–25.4 (4 rounds) | yes |"
  echo "| the rays the block's first pass (the exact ground's packets) reads, prefetched four packets ahead | 26.4 → 28.2 (9 bunnies 70 → 77) | yes |"
  echo "| blocks of 65536 rays (the three rows above were measured with them) instead of 16384 | 16384 level with 32768, 65536 7% slower (its rays outgrow a core's L2) | no: back to 16384 |"
  echo "| occlusion rays of many objects gathered into full packets of one field, in object space | +1% | no |"
  echo "| an object's open rays copied without a branch on \`occluded[i]\` (every ray written, the open ones kept by count) | 24.4–24.8 → 24.5–26.3 (4 rounds) | yes |"
  echo "| the (ray, object) pairs of the objects sharing a field traced as one stream of object-space rays (consecutive, full packets), flushed every 1024 pairs so that the rays a flush settles leave the later objects' lists (a single flush at the block's end, as in the row above, was level; 512 and 2048 pairs 1–3% below 1024) | 29.1–32.9 → 32.7–36.2 (4 rounds) | yes |"
  echo "| rays handed to a leaf of the tree over the objects carry their ids alone, not the box test's columns | 35.1–38.3 → 38.4–40.1 (4 rounds) | yes |"
  echo "| the tree pass's reciprocals and widened intervals 16 rays at a time instead of ray by ray | level | no |"
  echo
  echo "\`perf\` at the end (1024 bunnies, share of all the bench's samples): the tree pass 3.5%, the ground's packets"
  echo "(the block's first read of its rays from memory) 2.4%, the field kernel 2.5%, the objects' copies and sphere"
  echo "tests 1.8%: the tree is still the largest part, and the ≤ 2× growth of time per ray from 9 to 1024 objects"
  echo "(2.8× today) needs it and the copies about halved."
  echo
  echo "Renders (\`visfield render igea-triangles.ply --width 512 --height 512 --ao-rays 121\`, fields 16642 × 64² against the"
  echo "BVH, 3 interleaved rounds, Mrays/s): drawing each pixel's AO rays 16 at a time on lanes took the field render"
  echo "from 39.8–41.7 to 43.9–46.3 (3.4× the exact render's 12.9–13.7); the soft-shadow renders (docs/render-figures.md) gained from the"
  echo "exact ground in packets (Figure 7 through fields: 0.109–0.120 s before, same machine), then from the cone samples
drawn on lanes and shaded a chunk at a time (0.079 -> 0.047 s; the exact render 0.145 -> 0.110 s, then 0.105 s
with the BVH's interleaved walks)."
  echo
  echo "Measured on 2026-11-27 (AMD EPYC, 2 threads), binaries before and after each change run interleaved, 3 rounds:"
  echo
  echo "| change | measured | kept |"
  echo "|---|---|---|"
  echo "| arrays of 2 MiB and more (the cell tables, the Bvh's nodes) on huge-page boundaries, advised as transparent huge pages | Igea render through a 65 MiB field loaded from its cache 40.3–43.6 -> 59.4–63.7 Mrays/s; bunny AO 116.5–118.0 -> 120.4–121.8 | yes |"
  echo "| the next packet's cells prefetched as soon as they are located (the gather had 46% of the kernel's samples in the Igea render) | Igea render 59.3–67.2 -> 77.5–78.4 Mrays/s; bunny AO 116.6–120.6 -> 125.7–129.4, cow 109.5–113.6 -> 124.5–125.1 | yes |"
  echo "| the bench's rays in huge-page storage (read alike by every structure) | bunny AO 140.3–144.4 -> 144.9–149.1 Mrays/s, Embree level | yes |"
  echo "| soft shadows: a sample's runs summed in a register, a light's chunk queued by one call | Figure 8 through fields 14.6–16.6 -> 12.5–14.8 ns a shadow ray, the exact render 36.7–44.4 -> 34.3–41.0; images identical | yes |"
  echo "| a tile's camera rays traced together through the Bvh's interleaved walks | Igea field render 84.2–88.8 -> 82.8–85.9 Mrays/s | no |"
  echo "| the tree pass's columns on huge pages (1024 bunnies) | 2.97–3.13x -> 3.16–3.18x Embree | no (32 MiB a thread reserved for +4%) |"
  echo "| Figure 6's error: each cell's answer from k × k rays across it (the majority's hit, the hits' mean distance), and with the sample's point jittered over its neighbourhood (3 × 3 points) | 4226 × 32², image RMS read through the far end: 0.780 (one ray a cell) -> 1.418 (2 × 2), 0.791 (3 × 3), 0.869 (4 × 4); jittered points 0.777–0.789; 64²: 0.639 -> 0.644–0.925 (k × k), 0.635–0.640 (jittered; the paper 0.632) | no: the image error does not fall (across a straight silhouette the majority answers as the centre ray does) |"
  echo "| the tree pass: rays that share one range (AO rays) move down without its two columns (6 columns and the ids instead of 8 and the ids) | 1024 bunnies, 18 interleaved rounds: median 3.555x -> 3.575x Embree's instancing (31.4-33.6 against 31.5-32.8 Mrays/s in the steady rounds), again in a faster state 3.845x -> 3.81x | no: level (the pass is not bound by its stores) |"
  echo "| the tree pass compresses every chunk into every child, without the branch on an empty mask | 1024 bunnies, 8 interleaved rounds: median 3.89x -> 3.33x Embree's instancing | no (most chunks meet few children: the branch spares more than its mispredictions cost) |"
  echo "| the tree over the objects built with up to 2, 4 or 8 objects a leaf (a level fewer; the sphere tests sort out the extra pairs) | 1024 bunnies, 3 rounds: 3.50-3.70x (1 a leaf), 3.59-3.79x (2), 3.67-3.81x (4), 3.46-3.73x (8) | no: within noise, and a leaf met would no longer mean an object's box met |"
  echo "| the kernel 8 lanes wide (AVX2) instead of 16 (AVX-512) on this AMD EPYC, whose 512-bit operations take two passes through 256-bit units | intra AO, 2 rounds: bunny 171.6-189.7 -> 98.9-99.2 Mrays/s, cow 181.5-182.8 -> 100.5-100.6 | no: half the speed, so the kernel is bound by its instructions per packet, not by its lanes' arithmetic |"
  echo "| the next packet's cell addresses read back from memory for their prefetches (GCC had turned the stored offsets into \`vpextrd\` chains, two instructions a lane) | intra AO, 3 rounds: bunny 183.5-188.5 -> 188.7-190.7 Mrays/s, cow 182.5-185.1 -> 186.1-188.2 | yes |"
  echo "| the pending (ray, object) pairs mapped into object space 16 at a time on lanes and kept as rows (origin, direction and interval columns), which the kernel loads without gathering, transposing or culling again, instead of one scalar transform and a 32-byte copy a pair | 1024 bunnies, 7 interleaved rounds: 32.6-34.8 -> 34.4-37.0 Mrays/s (medians 34.4 -> 35.0); 9 bunnies level (97.5-97.8 against 89.2-97.2) | yes |"
  echo "| two packets side by side (\`lanes::Pair\`: 32 lanes on AVX-512, 16 on AVX2), each step the backend's on the first packet, then on the second, so their independent dependency chains interleave; the 8-lane row above had shown the kernel bound per instruction, not by its lanes | intra AO, 3 rounds: bunny 185.9-188.9 -> 232.8-239.0 Mrays/s (12.95-13.15x -> 16.24-16.63x Embree), cow 186.4 -> 237.4 (9.28x -> 11.73x); AVX2 kernel 8 -> 16 lanes on the bunny 99 -> 139-147; fig8 corner, 2 rounds, field AO 3.0 -> 2.2-2.4 ms a model (bunny 8.3-8.7x -> 10.2-12.0x, cow 5.4-5.6x -> 7.2-7.4x, three together 7.8-8.2x -> 9.1-9.3x); Igea render 88.0-90.6 -> 98.8-104.9 Mrays/s, images identical; 9 bunnies 81.1-84.5 -> 90.1-92.7; 1024 bunnies level (31.0-33.4 against 31.5-33.5) | yes |"
  echo "| four packets side by side (64 lanes) instead of two | intra AO bunny, 2 rounds: 209.7-214.1 -> 216.6-219.2 Mrays/s | no: within noise, and more spare lanes in objects' last packets |"
  echo "| fields alone (no exact part): a block's rays start open with one fill, not a loop asking the exact part for every ray (7% of the corner's AO samples) | fig8, 3 rounds of 15 runs: field AO 2.01-2.39 -> 1.94-2.16 ms a model, three together 3.71-3.91 -> 3.22-3.89 ms | yes |"
  echo "| a lone object's partial packets kept as mapped columns beside their indices until they fill a packet, instead of gathered (8 gathers a packet) and mapped again | fig8, 3 rounds of 15 runs: level (cow 2.01-2.26 -> 2.06-2.54 ms, bunny 2.03-2.39 -> 2.12-2.47) | no |"
  echo "| among many objects, an object's occlusion rays tested against its sphere, mapped into object space and compressed into the pending rows in one lanes pass over its copied rays (\`append_meeting_sphere\`), instead of an index list, a gather by index and a push of each pair's place | 1024 bunnies, 3 rounds: 39.7-40.6 -> 44.2-45.0 Mrays/s (3.95-3.99x -> 4.41-4.55x Embree's instancing) | yes |"
  echo "| the pending pairs traced in whole packets (the last pair repeated, not the last partial packet one ray at a time through \`trace_field\`), their marks or'ed in without a branch | 1024 bunnies, 7 rounds in a slow stretch: 32.9-42.4 -> 35.8-45.2 Mrays/s (medians 35.1 -> 39.7) | yes |"
  echo "| up to 16 objects, occlusion rays as rows too (each object's open rays that may meet its sphere mapped in one pass over the block, settled rays skipped on lanes, traced in whole packets), instead of index lists, gathers and the kernel's second cull | 9 bunnies, 7 rounds: 90.5-105.2 -> 87.7-106.8 Mrays/s (the 3 steady rounds 101.2-104.6 -> 105.9-106.8); fig8 three together 3.5-3.7 -> 3.4-3.7 ms | yes |"
  echo "| a lone object's occlusion rays as rows too | intra AO bunny, 2 rounds: 240.9-242.7 -> 167.4-170.4 Mrays/s; fig8 cow 1.8-1.9 -> 2.0-2.1 ms | no: a lone object's packets nearly all meet its sphere, and the rows are one more pass over the rays |"
  echo "| a lone object's packets of 32 rays that all pass wide of its world-space sphere (1.01 radius, ahead of the origin) left out before they are read, mapped and culled by the kernel's own test | fig8, 2 rounds: field AO 1.9-2.1 -> 2.4-2.8 ms a model (cow 8.0-8.3x -> 6.4-6.7x); intra AO bunny 227.3-229.0 -> 193.3-198.4 Mrays/s | no: the extra pass over the rays (a read and a division a ray) costs more than the mapping it spares |"
  echo
  echo "Measured on 2026-11-28 (Intel Xeon, 2 threads unless said), binaries before and after each change run interleaved;"
  echo "this machine's runs spread by up to ±20% from one minute to the next, so only ratios to Embree in the same run are compared:"
  echo
  echo "| change | measured | kept |"
  echo "|---|---|---|"
  echo "| the tree pass's interior regions in a scratch stack reused depth first (a node's children start at its mark, above which only finished subtrees lie), instead of one buffer grown for every node (3.8 MB a block of 16384 rays, 7.7 regions a ray: more than a core's L2) | 1024 bunnies, 4 rounds: 3.06-3.59x (median 3.26x) -> 3.44-3.87x (median 3.53x) Embree's instancing; 1 thread, 3 rounds: 3.42-3.56x -> 3.83-4.18x | yes |"
  echo "| from outside (no lane inside the sphere), the through read's chord, shift and limit left out (a root and two quotients a packet) | fig8, 5 rounds of 15 runs: medians level within the noise (cow 3.34 -> 3.01 ms, bunny 4.02 -> 3.41, dragon 3.10 -> 3.96, Igea 3.43 -> 3.46) | no: not measurable here |"
  echo "| (a later session, the same kind of machine; 1024 bunnies, ratios to Embree's instancing) a block whose open rays share tmin and tmax carries them as constants, not as two columns moved at every node | 6 rounds: 3.59-3.83x (median 3.74x) -> 3.70-4.22x (median 3.97x) | yes |"
  echo "| an interior child's rays moved by one compress of the lane numbers and a permute a column (one micro-op) instead of a compress a column (two) | 6 rounds, same runs: 3.97x -> 3.81-4.19x (median 4.14x) | yes |"
  echo "| one pass a node (each child's region sized for all the node's rays, each chunk tested and moved at once, leaves' ids closed up after) instead of masks first, then the moves | 3 rounds: 3.76-4.00x -> 3.43-3.52x | no: the sparse regions cost more than the second pass |"
  echo "| a full node's eight box tests unrolled | 8 rounds: medians 3.87x -> 3.97x (5 rounds ahead, 2 behind) | no: within the noise |"
  echo "| the setup's reciprocals 16 at a time; then also its rays written without a branch on the skipped ones | 8 rounds each: medians 3.95x -> 3.97x; 3.92x -> 3.81x | no |"
  echo "| the rows' compress once and permutes in \`append_meeting_sphere\` too | 3 rounds: 9 bunnies 5.98-6.23x -> 5.72-5.93x, 1024 bunnies 3.59-4.18x -> 3.61-3.95x | no |"
  echo "| an object's rays read where they lie in the block (16 rows through their ids, transposed) instead of copied side by side first | 3 rounds: 1024 bunnies 3.40-3.89x -> 3.46-3.66x, 9 bunnies 5.09-5.65x -> 4.44-5.62x | no |"
  echo "| (2026-11-28, a later session; 1024 bunnies, ratios to Embree's instancing) occlusion through the tree takes the objects with the most rays first, not in index order (the answer is the same in any order; the objects the rays leave occlude the most, and their flushes settle rays before the objects the rays merely pass are traced) | 8 rounds: medians 3.88x -> 4.02x; 5% fewer (ray, object) pairs traced (854,569 -> 812,740 a million rays) | yes |"
  echo "| the spheres tested at the tree's leaves as well as their boxes (a loose line-to-centre test on the columns, the directions from the reciprocals by one division a chunk), so that the objects' lists hold only rays near their spheres | 5 rounds: medians 3.76x -> 3.65x (with rcp14 instead of the division, timing only: 3.65x); pairs in the lists 1.64M -> 1.05M a million rays | no: the tests and divisions in the tree pass cost more than the copies and sphere tests they spare |"
  echo "| each ray's near objects first: a tree pass of the rays cut at 0.5-4 times the largest radius, traced, then the full pass for the rays still open | 2 rounds: 3.89-3.94x -> 2.35-2.86x | no: 20% of the rays settle on the ground, 32% after the near pass, 40% in all; the open 60% pay for both passes |"
  echo "| flushes every 512 or 2048 pairs instead of 1024 (with the order above) | 6 rounds: medians 3.97x (1024), 4.06x (512), 4.11x (2048) | no: within the noise |"
  echo "| the rays of an object's list prefetched 16 ids ahead as they are copied | 6 rounds: medians 4.05x -> 3.83x | no |"
  echo "| the tree pass's setup 16 rays at a time: read as rows, turned into columns in registers (the field kernel's transpose, now shared), reciprocals on lanes, skipped rays left out by one compress of lane numbers and a permute a column | 6 rounds: medians 3.89x -> 4.06x; 4 more after the transpose was shared: 3.96x -> 4.05x | yes |"
  echo "| (then) \`meets_sphere\` forced inline: the shared transpose had made GCC call it from \`append_meeting_sphere\` (9 bunnies 5.96x -> 5.42x) | 6 rounds against the session's first build: 9 bunnies 5.80x -> 5.99x, 1024 bunnies 3.92x -> 4.22x | yes |"
  echo "| leaves of 2 or 4 objects instead of 1 (the tree's visited nodes hold 3.3 children on average) | 5 rounds: medians 3.94x (1), 3.91x (2), 3.92x (4) | no: level |"
  echo "| blocks of 8192 rays instead of 16384 | 5 rounds: 1024 bunnies 4.19x -> 3.95x | no |"
  echo "| fig8, cow: the kernel's rays prefetched 0, 8 or 16 packets ahead instead of 4 | 2 rounds: 4 and 8 level (6.1-6.4x), 0 worse (5.3x) | no |"
  echo "| fig8, cow, parts taken out one at a time (temporary switches, timing only): every ray culled (no lookups); then also no mapping to object space; then the rays loaded without transposing | field AO 2.8-3.4 ms -> 1.3-1.4 ms -> 1.1-1.2 ms -> 1.1-1.4 ms | the bound: reading the 27 MB of rays takes ~1.2 ms and the lookups of the 29% that meet the cow's sphere ~1.5 ms, so 10x Embree's 18-23 ms (1.8-2.3 ms) is out of reach on this machine |"
  echo "| (a later session, timing-only switches) every \`vdivps\` of the kernel a product by its approximate reciprocal (\`rcp14\`); also every \`vsqrtps\` by \`rsqrt14\` | intra AO bunny, 3 rounds: 13.71-14.12x -> 15.61-16.48x Embree (divisions), 16.16-16.72x (both): the divider is the kernel's bottleneck on this Intel Xeon (\`perf\`: 19% of the kernel's samples behind \`vdivps\`/\`vsqrtps\`) | (timing only: the answers change) |"
  echo "| fewer divisions, the same bits on CPU, SIMD and CUDA: 2/π and 1/2R as products (the lattice angle, the through read's shift and limit), the through line's 1/len and the frame's 1/(sign + w.z) from one division (\`hd::reciprocals\`, \`orthonormal_basis(w, inverse)\`), the limit's work skipped by a packet read from outside | intra AO bunny, 10 rounds: medians 14.79x -> 15.43x; fig8, 2 alternating rounds: cow 5.8-5.9 -> 6.0-6.3x, bunny 8.6-9.0 -> 9.1-9.7x, Igea 14.7 -> 14.4-15.4x, dragon 10.7-11.0 -> 10.7-10.9x, Armadillo 10.2-10.5 -> 11.4-11.6x, three 6.8-7.1 -> 7.3-7.6x; 1024 bunnies 4 rounds 4.13x -> 4.17x, 9 bunnies 8 rounds 5.93x -> 6.27x; intra differ 2.92% both | yes |"
  echo "| the through limit's chord compared squared (no square root; timing-only switch) | intra AO, 6 and 10 rounds: bunny 14.86x -> 15.14x, 15.43x -> 15.05x; cow 8 rounds 10.45x -> 10.61x | no: level |"
  echo "| the cells prefetched to L2 (\`prefetcht1\`, \`prefetcht2\`) instead of L1 (\`perf\`: 8% of the kernel's samples wait on the prefetch loop) | intra AO bunny, 6 rounds: 14.64x (L1), 15.22x (T1), 14.67x (T2), ranges 13.1-16.0 | no: level |"
  echo "| the arctangent polynomial by Estrin's scheme (depth 4 instead of 6) | intra AO bunny, 8 rounds: 15.43x -> 15.45x | no: level (the chain's latency is not the bound) |"
  echo "| a lone transformed object's rays culled against its sphere in world space, mapped to object space only when they may meet it | fig8 bunny, 3 rounds: 8.6-8.9x -> 8.8-9.2x | no: level (streaming the rays is the floor: 27 MB read by two threads from a warm L3 takes 0.8-1.0 ms alone) |"
  echo "| (a later session, ratios to Embree in the same process) up to 16 objects, every sphere tested in one pass over a block (a packet read and transposed once for all objects, each object's rows filled as before), not a pass an object | fig8 three models, 3 rounds of 15 runs: 6.9-7.1x -> 7.8-8.2x; 9 bunnies, 3 rounds: 6.28-6.64x -> 5.81-7.66x | yes |"
  echo "| that pass's rays prefetched 4, 8 or 16 packets ahead (fields alone: nothing read them before; \`perf\` had a quarter of the pass's samples waiting on the first transpose) | fig8 three models, 3 rounds each: 7.5-8.0x (none) -> 9.1-9.2x (4); 9.2-9.4x (4) -> 9.4-9.6x (8); 16 level with 8 (9.3-10.0x) | yes (8) |"
  echo "| \`may_meet_sphere\` without a division: the line's distance from the centre as \\|oc × dir\\|² against wide² · \\|dir\\|² (host, device and lanes), \\|dir\\|² and \\|dir\\| made once a packet for every sphere | 9 bunnies, 3 rounds: 6.77-7.25x -> 7.72-7.77x; fig8 three models and 1024 bunnies level | yes |"
  echo "| an object's last partial packet through that pass on lanes too (copied into a whole packet, its spare lanes skipped), not ray by ray | 1024 bunnies, 4 rounds: medians 4.03x -> 3.88x; 9 bunnies level | no |"
  echo "| fig6 error: the read through the chord's midpoint or its quarter points instead of the far end (from outside) | 4226 × 32² image RMS 0.780 -> 0.779 (midpoint), 0.762 (three quarters), 0.874 (a quarter); 64² 0.639 -> 0.604, 0.625, 0.724 | no: level at 32² |"
  echo "| fig6 error, where it comes from (4226 × 32², read through the far end): the 164 floor vertices inside the bunny's sphere have per-vertex RMS 9.4 (the 3103 outside 1.24), but in the image they weigh little: with them exact the image RMS is 0.709, with the outside ones exact 0.325 | | the outside reads bound the image's error |"
  echo "| fig6 error: of the stored lines (a sample's point, a cell's direction) around the ray, the one nearest to its chord (RMS distance over the chord): 3 samples at the entry × their nearest cell; × 3 × 3 cells; the 3 samples at each end × 3 × 3 cells (54 lines) | 4226 × 32² image RMS 0.780 -> 0.774, 0.775, 0.767 | no: the line's distance from the ray is not the error's source |"
  echo "| fig6 error: the K nearest of those lines voting with weight 1/distance, K = 8, 16, 24, 32 of 54 | 0.704, 0.662, 0.603, 0.592 (64²: 0.418 at K = 24) | the idea of \`lines=1\`: voting, not the nearest line |"
  echo "| the cheaper candidate sets: the nearest sample at each end × 3 × 3 cells (18 lines), K = 6, 8, 10, 12, 18 | 4226 × 32² image RMS 0.681, 0.650, 0.634, 0.633, 0.659; 64² 0.512, 0.500, 0.496, 0.499, 0.515 | yes: \`lines=1\` (18 candidates, 10 voters) |"
  echo "| (2026-11-28, a later session; ratios to Embree's instancing) the tree over the objects with leaves of up to 4 or 8 objects, a leaf's objects that share a field taking its rays together: copied once, every packet tested against all their spheres in one pass (\`append_meeting_spheres\` into one set of rows) | 3 rounds: 1024 bunnies 4.26x (1 a leaf), 4.66x (4), 4.48x (8); busts 4.21x, 5.01x, 4.94x (medians) | yes: 4 a leaf |"
  echo "| closest hits with those leaves: each object's list copied for itself (4 lists of a leaf's rays); then each leaf's rays copied once for all its objects, the objects still in index order | \`--rays primary\` on 1024 bunnies, 3 rounds: 1.79x -> 1.63x; copied once, 5 rounds: 1.89x -> 1.86x (\`--rays random\` 0.94x -> 0.96x) | yes: copied once |"
  echo "| the 8-wide nodes collapsed for the fewest levels (a node opens only children with more leaves than 8^(h-1), so the nodes next to the leaves fill up: 467 nodes -> 218, of which 306 -> 24 with two children) | 1024 bunnies, 4 rounds: medians 4.30x -> 4.26x | no: level (the rays' node visits went from 5.3 to 5.6 each, the deeper tree of an uneven binary tree) |"
  echo "| a leaf's rays read where they lie in the block (16 rows through their ids, turned into columns in registers) instead of copied side by side first, with leaves of 4 | 1024 bunnies, 4 rounds of 11 runs: medians 4.60x both; busts 3 rounds level | no |"
  echo "| each ray's near objects first again (rays cut at 2, 3 or 5 times the largest radius through the tree, traced, then the rest of each open ray) | 1 round: 4.23x -> 3.28x, 3.52x, 3.79x; 46.3% of the rays settle in the near pass, 47.9% in all | no: the rays left open are the long ones, which cost the tree pass most |"
  echo "| the tree's walk carries the rays' directions instead of their reciprocals (each node's load divides again, as the single-ray walk does) | 1024 bunnies, 6 interleaved rounds: medians 4.54x both | yes: it lets a leaf hand on the rays themselves |"
  echo "| occlusion: the rays' values written beside each leaf's list as the walk reaches it, for the leaves' sphere tests to read in order instead of copying each leaf's rays from the block | 1024 bunnies, 6 rounds: medians 4.71x -> 4.38x (perf: the walk's samples +48%, its leaf stores going out to memory; the copies' -68%) | no |"
  echo "| occlusion: each leaf visited where the walk reaches it (\`BoxTree::visit_leaves\`), its rays taken from the walk's scratch as columns while in cache, the last partial packet on masked lanes, and rays settled by a flush dropped at the walk's next node; instead of the objects' lists sorted by ray count and each leaf's open rays copied from the block | 1024 bunnies, 4 rounds alternating the four scenes: medians 4.47x -> 4.83x (6 rounds of 1024 bunnies alone: 4.57x -> 4.81x); busts 4.98x -> 5.14x; 9 copies (no tree) 7.6x both; closest hits (\`--rays primary\`, \`random\`, 3 rounds) level | yes |"
  echo "| with leaves visited in the walk: 256 or 4096 pending pairs a flush instead of 1024; leaves of 2 or 8 objects instead of 4 | 1024 bunnies, 5 rounds: 4.85x (256), 4.89x (4096), 4.89x (1024); 4 rounds: 4.89x (2), 4.81x (8), 5.03x (4); busts 5.20x (2), 5.11x (8), 5.18x (4) | no: level or below |"
  echo "| the walk's scratch columns in one buffer, each region starting 64 bytes further into its page (so that a chunk's nine streams fall in nine L1 sets) | 1024 bunnies, 8 rounds: medians 4.64x both | no (the vectors had not collided) |"
  echo "| visits: the block's open rays grouped by their directions' octants before the walk (a pass of masked stores), so that most chunks share their signs and the box test picks each axis's planes once for 16 rays instead of blending per lane | 5 rounds: 1024 bunnies medians 4.90x -> 4.67x, busts 5.45x -> 4.88x | no: the chunks lose the block's spatial order, which costs more than the blends |"
  echo "| (2026-11-28, a later session) where the pairs go, counted (temporary counters; 2 runs of 1M AO rays on 1024 bunnies): 5.11M (ray, node) visits in 336K chunks of 16 lanes (15.2 live), 6.6 children tested a chunk; 1.73M (ray, object) pairs of which 0.54M hit; flushing after every leaf instead of every 1024 pairs: 1.63M pairs | | the pairs are not redundant: 69% are rays that pass through a sphere without a hit, which settling rays sooner cannot spare |"
  echo "| visits: each node's children nearest the mean origin of its open rays first (the objects near the rays, an AO ray's own and its neighbours, settle them before the walk takes them farther), instead of tree order | 1024 bunnies: 2% fewer pairs, 17% fewer nodes with rays; 5 rounds: medians 4.70x -> 4.79x, busts 4.97x -> 5.16x; then flushes of 64 or 256 pairs: level (4 rounds) | yes |"
  echo "| closest hits: each leaf visited where the walk reaches it, as occlusion's (object-tagged rows, a leaf's objects sharing a field traced in one stream), the objects in the walk's order and the hit kept by one rule everywhere (\`field/closest_answer.hpp\`: each object's answer within the ray's own range, nearer wins, equals to the exact part, then the lower index), instead of each object's list copied and traced on its own in index order, each answer cut at the nearest before it | 1024 bunnies, 3 rounds: \`--rays random\` 0.96-1.00x -> 1.48-1.52x, \`primary\` 1.65-2.00x -> 1.95-2.12x; busts random 1.38-1.42x -> 2.00-2.12x, primary 1.91-2.03x -> 2.12-2.36x | yes |"
  echo "| closest hits: a small exact part (the ground) tested a packet of rays at a time, as occlusion's (57% of 1024 bunnies' field time on random rays went to its BVH, a ray at a time) | 3 rounds, medians: 1024 bunnies primary 1.86x -> 3.62x, random 1.55x -> 2.35x; busts primary 2.04x -> 3.39x, random 2.06x -> 3.09x; 9 bunnies primary 1.34x -> 3.01x, random 1.55x -> 2.85x | yes |"
  echo "| the walk: a node's box tests over every slot in turn, unrolled (the unused passed over), so that each slot's box and count sit at fixed places and the counts in registers; and, apart, the settled rays' gather left out at a node made pending since the last leaf visit (its rays were all open when its parent tested them) | 1024 bunnies, 5 rounds: medians 4.99x -> 5.05x (unrolled), 4.94x -> 4.95x (gather); busts 5.33x -> 5.35x, 5.28x -> 5.30x | no: level |"
  echo "| a ray that misses the object's own bounding box answers a miss (a slab test in object space after the sphere's; timing-only switch on the lone object's culled stream). Of the corner's rays that meet the sphere, 86% meet the bunny's box, 65% the cow's | fig8, 3 rounds: bunny 8.3-8.8x -> 8.7-9.4x, cow 5.8-6.4x -> 6.5-7.6x; image RMS bunny 2.430 both, cow 2.758 -> 2.757 | no: too little for what it needs (a box in the field file and in the query on CPU, lanes and CUDA, alike bit for bit) |"
  echo "| (2026-11-29, a later session on an AMD EPYC, Zen 3: AVX2, no AVX-512; ratios to Embree's instancing) the tree's columns walk on AVX2 at 8 lanes (one template with AVX-512's 16), instead of a ray at a time with every leaf taken after the walk, in tree order (no settled rays left out, no near-first order) | 1024 bunnies, 3 rounds: medians 2.26x -> 2.82x | yes |"
  echo "| the AVX2 kernel lanes' compress (the sphere pass's rows, the kernel's pending rays) by one permute of the lane numbers and a whole store, not a lane at a time from the stack (~45% of the sphere pass's samples) | 3 rounds: 2.82x -> 3.01x (21.5 -> 24.1 Mrays/s). Both changes, 2 rounds: 1024 bunnies 1.91-2.30x -> 3.31-3.48x, busts 2.15-2.56x -> 3.56-3.63x, 9 bunnies 3.80-4.15x -> 4.37-4.58x, 9 busts 3.89-3.98x -> 4.37-4.55x; intra AO bunny 7.79-8.09x -> 8.11-8.89x | yes |"
  echo "| the walk's settled-ray check on AVX2 by a gather, as on AVX-512, instead of a lane at a time | 1024 bunnies, 5 rounds: 3.08-3.52x -> 3.00-3.38x; busts, 3 rounds: 3.24-3.80x -> 3.20-3.38x | no: level |"
  echo "| the AVX2 walk's box tests two chunks a step (each child's box read once for 16 rays, two independent test chains) | 1024 bunnies, 5 rounds: 3.20-3.59x -> 2.87-3.39x | no |"
  echo "| the field kernel at 8 AVX2 lanes (one packet) instead of two packets side by side, now that the compress is a permute | 1024 bunnies, 2 rounds: 3.37-3.55x -> 3.02-3.33x; intra AO bunny, 2 rounds: 6.08-7.90x -> 6.33-6.60x (a noisy hour) | no |"
  echo "| (the four scenes, 3 rounds alternating them, medians, Mrays/s and ratio, session start -> the three AVX2 changes above and the scattered rays' rows below) | 1024 bunnies 17.38 (2.31x) -> 27.36 (3.43x), 9 bunnies 46.17 (3.66x) -> 50.03 (4.13x): time per ray 9 -> 1024 2.66x -> 1.83x; busts 15.96 (2.79x) -> 22.94 (3.67x), 9 busts 38.70 (4.10x) -> 45.57 (4.52x): 2.42x -> 1.99x. Closest hits, 1024 bunnies, 2 rounds: camera rays 1.89-2.13x -> 2.78-2.92x, random 1.59-1.63x -> 1.73-1.78x | - |"
  echo "| a lone object's packets of scattered rays (the culled stream's, gathered from across a block) read as eight rows by index and transposed on AVX2, not gathered a column at a time (\`FieldKernel::gather\` was 31% of the corner cow's field samples); AVX-512 keeps its gathers | fig8, 3 rounds: cow 3.6-3.8x -> 4.0-4.2x (field AO 5.1-5.4 -> 4.5-4.7 ms), bunny level (4.9-6.6x) | yes |"
  echo "| (2026-11-29, the AVX2 EPYC again) the render samplers on AVX2 lanes: the sphere light's cone samples and the AO rays 8 at a time (\`SampleLanes\`, one interface over AVX-512's 16 lanes and AVX2's 8; the PCG's 64-bit multiply from three 32-bit ones), bit for bit the scalar draws; they had lanes on AVX-512 only, and a soft-shadow render through fields spent 48% of its samples in \`SphereCone::sample\` | 3 rounds, images identical: a Figure-7-like scene through fields 0.13 -> 0.05-0.06 s (1.3-1.6x -> 2.5-3.2x the exact render); \`--figure gpu7\`, 2 rounds, 4226 x 64² 0.123-0.124 -> 0.064-0.066 s (exact 0.213-0.241 -> 0.172-0.176 s: 1.7-1.9x -> 2.7x); \`--figure gpu8\` 0.103-0.133 -> 0.057-0.070 s (1.7-1.9x -> 2.1-2.8x); Igea AO 512² x 121, 5 rounds, 0.20-0.22 -> 0.10-0.14 s (2.8-3.7x, median 3.1x -> 4.5-5.5x, median 5.3x; Armadillo, 2 rounds, 3.1-3.6x -> 4.0-6.1x) | yes |"
  echo "| the corners' direction pairs read by eight 64-bit loads instead of two 4-lane \`vpgatherdq\` (AVX2; the gathers' wait showed as 14% of the kernel's samples) | intra AO bunny, 6 rounds: medians 7.45x -> 7.19x | no |"
  echo "| the field library compiled with \`-fschedule-insns -fsched-pressure\` (GCC's pressure-aware first scheduling pass, against the AVX2 kernel's spills: 2355 of 7969 instructions touch the stack) | intra AO bunny, 3 rounds: level (6.9-7.7x both); 2442 of 8032 instructions touch the stack | no |"
  echo "| two packets side by side (\`Pair<Avx2>\`) taking the corners and the nearest sample a packet at a time (the step with the most live values: 26% of the kernel's samples, 329 of its spilled instructions) | intra AO bunny, 4 rounds: medians 7.12x -> 6.89x | no |"
  echo "| (2026-11-29, a later session, the AVX2 EPYC) a shading point's shadow rays into all its sphere lights made in one pass on lanes (\`sphere_light_rays\`): every light's samples across the lanes, each lane's cone looked up by its light, the Lambertian \`Bsdf::eval\`, the keep test and the contributions, the kept rays compressed and written as whole packets into the tile's batch (its runs now columns), instead of three calls a light's chunk (sample, evaluate, queue: 3 packets a call at 20 rays a light) | images identical; a Figure-7-like scene (\`visfield render\`, spp 16), 7 interleaved rounds: field render medians 1.03 -> 0.91 s, exact level (2.25-2.55 s); \`--figure gpu7\` 4226 x 64², 7 rounds: field medians 0.076 -> 0.057 s, exact 0.174 -> 0.159 s (it draws the same samples), ratio medians 2.46x -> 2.65x; \`--figure gpu8\` level in 3 rounds (2.1-2.7x both): up to 0.019 s of its 0.06 s field render is the sharp render's cost (camera rays through the 618K-triangle BVH), and the sampling left is ~350 instructions a packet of 8 (the PCG's emulated 64-bit multiplies, the sines' polynomials, three roots, two divisions) | yes |"
  echo "| the AVX2 PCG lanes (every render sampler's generator): next_u32's 32-bit rotation as one 64-bit shift of the output word copied into both halves, two registers' words joined before one shift, conversion and scale for all 8 lanes (not two of 4), the multiplier's high word a constant | bits unchanged; a Figure-7-like scene, spp 16, 5 interleaved rounds: field render 0.93-1.03 -> 0.80-0.87 s; Igea's AO render through fields, 6 rounds: medians 48 -> 52.5 Mrays/s (42.1-54.7 -> 43.6-54.0) | yes |"
  echo "| a lone object's partly culled packets (\`stream_culled\`): their candidates' object-space rays compressed into rows as they are culled, a full packet then loaded, instead of their indices compressed and the rays gathered and mapped again by index (counted on the corner's cow: 29% of its rays meet the sphere; of 16-lane packets 7.6% all meet, 40% none, 52% some) | fig8 cow, 3 interleaved rounds: 4.3x, 4.4x, 4.8x -> 4.2x, 4.0x, 4.8x | no: level |"
  echo "| (AVX2 EPYC) blocks of 8192 or 4096 rays among many objects instead of 16384 (16384 rays' 512 KiB fill Zen 3's L2) | 1024 bunnies, 4 interleaved rounds: 3.23-3.41x (16384), 2.86-3.12x (8192), 2.72-3.30x (4096) | no |"
  echo "| a few exact triangles' occlusion packets (the ground of a field scene) settle first the lanes moving away from the triangles' box: origin on or beyond the box face across the ray's major axis (the watertight test's kz), moving away, tmin >= 0, so that every vertex's sheared z is <= 0 and t <= 0 (exact: not a margin); a packet of them skips the shear's divisions and the triangles | Figure-7-like scene, spp 16, 5 interleaved rounds: field render medians 0.90 -> 0.79 s (the ground's packets 12.6% -> 7.6% of its samples); 1024 bunnies' AO level (its AO rays seldom fill a packet going up); the session's start against its end (the one-pass shadow rays, the PCG, this): \`--figure gpu7\` 4226 x 64², 3 rounds, ratio medians 2.55x -> 2.96x (field 0.051-0.074 -> 0.046-0.052 s, exact 0.156-0.189 -> 0.143-0.163 s; every field size 2.2-3.7x), \`--figure gpu8\`, 4 rounds, 2.45x -> 3.06x (field medians 0.062 -> 0.050 s) | yes |"
  echo "| (2026-11-29, a later session, the AVX2 EPYC; found by counting instructions, \`scripts/count-instructions.py\`) a packet's world-space rays gathered straight into its place and mapped into object space in place, and the lanes' geometry written into the located packet in place, instead of returned by value: GCC copied each returned 512-byte packet with a \`memcpy\` call (a quarter of the intra-object stream's instructions: 44.8M -> 33.6M for 400K of the bunny's own AO rays, 112 -> 84 a ray) | intra AO bunny, 3 rounds: 6.6-8.3x -> 8.1-8.5x | yes |"
  echo "| the 8 x 8 transpose's rows loaded where its first step takes them (loaded into an array first, GCC made the loads a \`memcpy\` onto the stack: the ground's packets, the sphere pass, the tree's setup, the render samplers), and a few objects' rays mapped into object space in place | 1024 bunnies' field instructions 100.6M -> 94.6M for 200K rays; the session's start against its end (both changes), interleaved, medians: intra AO bunny 8.1x -> 8.8x (4 rounds), dragon 11.2x -> 11.9x, Armadillo 10.2x -> 11.6x, cow 6.2x -> 6.3x; \`--figure fig8\` (3 rounds) cow 4.7x -> 4.4x, bunny 5.9x -> 6.7x, Igea 9.4x -> 10.8x, dragon 7.1x -> 8.4x, three together 6.1x -> 6.8x; 1024 bunnies 3.12x -> 3.29x (5 rounds); Igea's AO render 4.7x -> 5.5x (5 rounds); \`--figure gpu7\` and \`gpu8\` level; answers and images identical | yes |"
  echo "| (timing only) the corners' quadrant reads (\`vpgatherdq\`) left out, to bound what reading the lattice's directions costs | intra AO bunny, 3 rounds: 8.9-9.8x -> 9.6-11.2x: the gathers are ~10-15% of the kernel's time | - |"
  echo "| the nearest sample's three corners made one at a time where they are compared (only the best so far live), instead of all three first | intra stream's instructions 33.6M -> 34.5M, more of them on the stack | no |"
  echo "| the AVX2 kernel at 8 lanes (one packet) or 32 (four side by side) instead of 16, now that the copies are gone | intra AO bunny, 3 rounds: 7.9-9.1x (16) against 6.7-6.9x (8) and 4.3-5.7x (32) | no |"
  echo "| a lone object's rays culled by the few objects' pass (world-space spheres, rows) instead of the culled stream | fig8 cow level (4.4x both, 2 rounds); intra AO bunny 9.0x -> 6.8-7.4x | no |"
  echo "| the tree walk's settled check reading a chunk's 8 bytes at once where its 8 ids are consecutive | 1024 bunnies' field instructions -2.5%; 4 rounds level (medians 3.42x, 3.48x) | no: not measurable |"
  echo "| a memory barrier after the lanes' geometry, so that its outputs are reloaded from the located packet instead of held in registers through the corners | intra stream's stack instructions 8.70M -> 8.05M; 4 rounds level (7.8-8.1x, 7.9-8.5x) | no |"
  echo "| a lone object's rays culled by may_meet_sphere() on the world-space rays (the object's world sphere from FieldScene) before they are mapped, so that only the packets that go through are mapped into object space (mapping them all was a fifth of the corner's field instructions) | corner's field instructions 696M -> 659M (the world test's cross products cost most of what the mapping saved); fig8, 3 interleaved rounds, level: cow 4.6/4.8/4.0x -> 4.7/4.5/4.8x, bunny 6.3/7.1/5.5x -> 6.1/6.3/6.5x | no |"
  echo "| (2026-11-29, a later session, the AVX2 EPYC; timing only, committed: CMake \`VISFIELD_FIELD_BOUND\`, docs/benchmark.md) parts of a lone object's query left out, 3 rounds interleaved, medians: field AO ms of the corner (cow; bunny), Mrays/s of intra AO (bunny) | the query: 4.0; 3.9 ms; 110 Mrays/s (4.6x, 6.5x, 8.9x Embree). \`cached-cells\` (every lookup reads samples 0-3's cells, in L1): 3.7; 3.7 ms; 121. \`no-lookups\` (read, map, cull, pack; every packet a miss): 1.3; 1.2 ms; 853. \`read-and-map\`: 1.0; 1.0 ms; 941. \`read-only\` (the rows' transposes): 1.0; 1.0 ms; 949 | the lookups are two thirds of the corner's time and seven eighths of intra AO's, their table misses under a tenth; 10x on the cow (Embree 18 ms) leaves 0.5 ms for its 242K lookups against 2.7 ms today (5.4x faster lookups), on the bunny 2.1x, 15x intra 1.9x |"
  echo "| (correction) the instruction counts of the rows above named by \`'*stream_culled*'\` left out the stream's next-packet lambda, whose name contains the pattern: callgrind stops counting inside a match called from a match. Named from its start (\`'vf::field::ObjectField::mark_occluded(*'\`), the bunny's intra stream is 39.4M instructions for 400K rays (98.6 a ray), not 33.6M (84); the corner's 696M was counted so already | | the A/B comparisons stand (both sides left the same lambda out); \`scripts/count-instructions.py\` now warns of such patterns |"
  echo "| (2026-11-29, a later session, the AVX2 EPYC) the lookups' sample: the heaviest corner of the point's lattice triangle (the largest barycentric weight, \`heaviest_corner_position()\`; on lanes one direction gathered) instead of the nearest of its three corners by cosine (three directions gathered, three dot products); the nearest sample for ~92.5% of points, at most ~18% farther in angle; scalar query, lanes and CUDA alike | intra AO, 4 interleaved rounds: bunny 7.5-8.8x (median 8.4x) -> 9.1-9.7x (9.45x) Embree; 2 rounds: dragon 12.6x -> 12.4-13.4x, Armadillo 10.6-11.7x -> 11.9-12.0x, cow 5.9-6.5x -> 6.6-6.8x; fig8, 2 rounds: cow 4.1-4.3x -> 4.9-5.1x, bunny 6.3x -> 6.4-7.0x, Igea 7.7-8.1x -> 8.1-8.6x; Igea AO render (512², 121 rays), 3 rounds: medians 4.8x -> 5.9x the BVH render; 1024 bunnies, 4 rounds: medians 3.58x -> 3.52x (level). Error: \`--figure lookups\` corner per-vertex RMS 2.430 -> 2.418, intra differ 2.90% -> 2.89% (1090 x 64²: 2.508 -> 2.519, 1.74% both; bit cells 90²: 1.614 -> 1.650); fig6 image RMS read through, 4226 x 32², 64², 128², 256²: 0.780, 0.639, 0.527, 0.493 -> 0.793, 0.657, 0.542, 0.495 (16642: 0.729, 0.590, 0.447, 0.374 -> 0.722, 0.587, 0.455, 0.376), at the paper's memory (1-bit) 0.590, 0.514 -> 0.603, 0.528 (paper 0.677, 0.632), \`lines=1\` 0.634, 0.496 -> 0.637, 0.496; Igea AO render RMS 2.298 -> 2.295; soft shadows \`--figure gpu7\` RMS level (2.72 -> 2.71, 1.45 -> 1.44, 1.31 -> 1.32, the rest equal), \`gpu8\` 1.78 both. The figure tables below were written before this change | yes: error x time lower (the image's error +0-3% at 4226 positions, the per-vertex error lower, time -11% to -20%) |"
  echo "| (2026-11-29, a later session, the AVX2 EPYC; timing only, committed: \`VISFIELD_FIELD_BOUND=no-map\`, \`no-map-line\`, \`no-map-line-lattice\`, \`sphere-only\`, docs/benchmark.md) the paper's lookup's stages left out one after another (the hemisphere map; then the sample's line; then the lattice triangle and its heaviest corner; then the table read), 3 interleaved rounds, medians: intra AO of the bunny, 1M rays, 2 threads (ms a million rays); the corner's cow and bunny (\`--figure fig8\`, ms) | intra bunny: the query 9.3 ms (107.7 Mrays/s, 9.4x Embree), \`cached-cells\` 9.3, \`no-map\` 8.6, \`no-map-line\` 7.1, \`no-map-line-lattice\` 5.6, \`sphere-only\` 2.8 (28x), \`no-lookups\` 1.3: the map 8%, the line 16%, the lattice 17%, the table read 29%, the sphere and placing 17%, the rest 14%. Corner cow: 4.3, 3.9, 4.4, 3.5, 3.0, 2.5 (7.9x), 1.4 ms; bunny: 4.0, 3.6, 3.5, 3.3, 2.8, 2.1 (12.1x), 1.4 ms (21x) | the table read's misses cost nothing beside the whole lookup (\`cached-cells\`) but 29% once the rest is out: the other stages hide its latency. No one stage is the 37% of intra AO's time that 15x asks for; the bunny's corner reaches 10x only with every stage but the sphere out |"
  echo "| (2026-11-29, a later session, the AVX2 EPYC) the AVX2 lanes' gathers (the cells' bytes, the quadrant table's pairs) as eight scalar loads and inserts instead of \`vpgatherdd\`/\`vpgatherdq\` (a microbenchmark: 4.2 against 5.1 ns an 8-lane gather from L1) | intra AO bunny, 3 rounds: 9.3-9.9x both; corner cow 4.4x, 4.3x | no: level |"
  echo "| the field kernel on AVX2 at 8 lanes (\`Avx2\`) or 32 (\`Pair<Pair<Avx2>>\`) instead of 16 (\`Pair<Avx2>\`) | intra AO bunny, 1 thread, 3 rounds: 16 lanes 49-56 Mrays/s, 8 lanes 41-43, 32 lanes 30-37 (spills: 16 ymm registers) | no |"
  echo "| the rays' prefetch 12 or 32 packets ahead instead of 4 (the corner's culled stream reads ~3.4 packets of rays for each it traces) | corner cow, 3 rounds: 4.3-4.8x, 4.4-4.8x, 4.5-4.7x | no: level |"
  echo "| the hits' marks of a packet of consecutive rays set by one 8-byte read-or-write instead of a byte a hit lane (a loop whose exit is mispredicted); the cells' prefetch left out | intra AO bunny, 1 thread, 4 rounds: 9.2-10.3x -> 9.9-10.6x (level); without the prefetch 8.3-9.1x | no; the prefetch stays |"
  echo "| every division, square root and arctangent of the kernel taken out (products instead; answers wrong), to bound the arithmetic | intra AO bunny, 1 thread, 4 rounds: 52-65 -> 60-76 Mrays/s (the divider's \`vsqrtps\`/\`vdivps\` ymm: 5 and 3 cycles each here, ~9% of a ray's time) | timing only: on this machine the divider is not the bound it was on the Xeon |"
  echo "| the sample's line and the frame from two independent divisions (1/len and 1/(sign + w.z)) and the map's local direction as the frame's products with the unnormalised line scaled by 1/len, so that the frame's dot products wait on the division alone and not on the line's square root (the chain from the corner's gather to the cell ~20 cycles shorter; timing only, on lanes) | intra AO bunny, 1 thread, 4 rounds: 8.3-10.6x (median 9.0x) -> 8.8-9.3x (9.1x) | no: level (the kernel is not bound by that chain) |"
  echo "| (2026-11-29, a later session) a grid in front of the tree over the objects: a block's rays whose part within the objects' boxes lies in one cell (cells ~2 median boxes) take the cell's list of objects, sorted by cell, and skip the walk; the rest go down the tree | 1024 bunnies, AO: the first version (rays placed by scalar doubles, copied by cell) 17.2-18.6 against 28.4 Mrays/s; rays placed on lanes, their ids sorted, 4 rounds: 2.97-3.70x -> 3.57-3.86x (44-46% of the open rays routed) | kept, with the next rows |"
  echo "| what placing and sorting the rays cost (rdtsc; a bound with both cached between runs) | placing 14.5 -> 9.3 cycles a ray once a lane's settled flag was read without a branch, sorting 10.8; cached: 1024 bunnies 3.46x -> 3.94x (medians of 4) | the sort then took only the rays given a cell |"
  echo "| the cells fitted to the objects' rows (side 7/8-5/4 of the target, offset: fewest boxes cut), margin 1e-4 of the hull (was 1e-3) | bunnies' cells' lists 5.4 objects; 3 rounds: 3.39-3.52x (tree alone) -> 3.61-3.74x | yes |"
  echo "| rays whose part spans two neighbouring cells along an axis take the list of those cells (8 shapes of list: one or two cells an axis) | routed 46% -> 88% of the open rays; 1024 bunnies in one process against \`field:cull=tree\`, medians of 7 rounds: 3.66x -> 4.06x; busts 3.98x -> 3.77x | yes, with the next row |"
  echo "| a shape's lists used only where they hold at most 16 objects on average (busts: cells 14.6, pairs 24.6, fours 41.7; bunnies 5.4, 9.5, 16.7) | busts, medians of 4: nothing routed 3.66x, cells only 3.90x, every shape 3.73x; bunnies, of 3: 3.41x, 3.71x, cells and pairs 3.89x, every shape 3.85x; then against \`field:cull=tree\` in one process, 7 rounds: bunnies 3.57x -> 3.96x, busts 3.91x -> 3.81x | yes |"
  echo "| the grid's blocks of 32768 rays instead of 16384 (fuller packets a list) | 1024 bunnies, 5 rounds: 4.19x -> 4.09x (medians) | no: level |"
  echo "| the columns walk in one pass: each chunk tested and moved at once into regions with room for all the node's rays (no masks kept, no second load) | 1024 bunnies, 3 rounds: 3.48-3.55x -> 2.99-3.36x | no |"
  echo "| the columns walk without its per-chunk check of settled rays (4% of a node's rays are settled by then) | 1024 bunnies, 4 rounds: 2.90-3.90x -> 3.29-3.82x | no: level |"
  echo "| the grid's cells 1.5, 2 or 3 median boxes wide (before the lists' limit) | 5 rounds, medians: bunnies 3.79x, 4.05x, 3.67x; busts 3.89x, 3.70x, 3.40x | 2 |"
  echo "| (2026-11-29, a later session, the AVX2 EPYC) the grid's cells narrowed from 2 median boxes (1.75, 1.5, 1.25, 1) until the lists of two cells along each axis hold at most 16 objects, so that a ray crossing one boundary still takes a list (busts: cells 1.5 boxes, lists 8.0 / 13.0 / 21.1 objects; bunnies stay at 2) | busts, 9 interleaved rounds of one build, medians: 3.72x at 2 boxes, 3.90x at 1.5, 3.95x at 1.25; bunnies 3.89x at 2, 3.88x at 1.75, 3.93x at 1.5. Against the build before, 5 rounds: busts 3.85x -> 4.08x, time per ray 9 -> 1024 busts 2.03x -> 1.86x (the bunnies' grid is the same). Grid against tree in one process (\`field:cull=tree\`), 7 and 9 rounds: busts 3.92x / 3.81x and 4.20x / 3.99x, growth 2.01x / 1.92x (tree 2.09x / 2.07x); bunnies 3.98x / 3.62x and 3.82x / 3.41x, growth 2.04x / 2.08x | yes |"
  echo "| the lists' limit 10 or 22 objects instead of 16 (with the narrowing above) | 5 rounds, medians: bunnies 3.89x, 4.02x (16), 3.84x; busts 3.74x, 4.11x, 3.65x | no |"
  echo "| (timing only) the rays left to the walk, the grid's rays, or both, taken out (not answered) | 1024 bunnies, 3 rounds, medians: 3.76x -> 6.52x without the walk's rays, 6.11x without the grid's, 16.5x without both; busts 3.84x -> 7.21x, 6.05x, 21.4x. Counted on 1M AO rays: bunnies 764K open after the ground, 79% routed (6.8 sphere tests, 0.88 traced pairs a ray), the other 21% walk (11.4 sphere tests at leaves, 2.27 pairs a ray); busts 70% routed (10.0 tests, 1.31 pairs), 30% walk (12.9, 3.17) | the walked rays (long and grazing: they pass many objects) take ~42% of the field's time on the bunnies, the routed ones ~38%, the ground, placing and sorting ~23% |"
  echo "| the walk's rays first tested against their origin's cell's objects, traced and flushed before the walk, so that those the near objects occlude skip it | 4 rounds, medians: bunnies 3.67x -> 3.51x, busts 3.87x -> 3.60x | no |"
  echo "| blocks of 8192 rays instead of 16384 (with the grid) | 5 rounds, medians: bunnies 3.75x -> 3.56x, busts 3.93x -> 3.77x | no |"
  echo "| the field kernel specialised at compile time for the default field on this AMD (storage, mapping, lookups and line as constants, the other branches gone) | intra AO bunny, 4 rounds: 8.48-9.15x -> 7.91-8.83x | no (as on the Xeon) |"
  echo "| the grid's counting sort clearing and summing only the counts of the shapes used (a shape two cells along an axis of one cell never used) | 7 rounds, medians: bunnies 3.92x -> 3.90x, busts 4.04x -> 4.03x | no: level |"
  echo "| the heaviest corner's direction computed on lanes by point_direction<float>'s own operations (a division, a square root, the sine and cosine polynomials: the table's bits, the tests pass) instead of gathered from the quadrant table | intra AO, 5 rounds, medians: bunny 9.48x -> 8.47x, cow 6.39x -> 6.70x; answers unchanged (2.92%, 3.27% differ) | no |"
  echo "| the kernel's file compiled with GCC's register-pressure-aware scheduling before allocation (\`-fschedule-insns -fsched-pressure\`, as a pragma) | intra AO, 5 rounds, medians: bunny 9.27x -> 9.16x, cow 6.86x -> 7.06x | no: level |"
  echo "| (counted, 1M AO rays, a build that counts at each flush) the traced (ray, object) pairs against the rays they occlude | 1024 bunnies: 898K pairs traced, 278K of them hits; 240K rays occluded by the fields, whose pairs in their flush number 404K: up to 164K pairs (18%) would be spared if each ray's nearest object were traced first and its other pairs only if it stayed open; busts: 1.33M pairs, 326K hits, 282K rays, 590K pairs, up to 308K (23%) | not built: a routed ray's pairs all come from one sphere pass over its list, so that pass could send each ray's nearest meeting sphere to a first round and the rest to a second, filtered by the first's marks (the kernel is ~30% of the field's time here, so at most ~5-7%) |"
  echo "| (2026-11-30, the AVX2 EPYC) a ray whose half-line misses the mesh's own bounding box (grown by 1e-3 R) answers a miss, built in full: the box in \`.vfield\` version 3, a separating-axis test (explicit fma, no division) after the sphere's in the scalar query and CUDA, the lanes' geometry and their cull before packing, and the scenes' sphere passes after mapping; tests: culled rays never meet the mesh (exact BVH, rays at the box's face vertices), the rest answer as without the box, batch == trace (branch \`box-cull\`, a0ca8c5) | fig8, 4 rounds, medians: cow 4.30x -> 4.75x, bunny 6.45x -> 5.65x, Igea 11.65x -> 11.25x, dragon 8.70x -> 7.90x, Armadillo 8.10x -> 7.50x, three 6.90x -> 7.00x (the cull before packing alone, no test in the lookup: cow 4.80x, bunny 6.40x, dragon 8.85x, Armadillo 7.75x); intra AO bunny, 3 rounds: 9.13x -> 8.21x; 5 rounds: 1024 bunnies 3.84x -> 3.85x, 1024 busts 4.19x -> 3.95x, 9 bunnies 5.05x -> 4.73x; false hits removed: 280 of 20K probe rays on a flat ground, 22 on the knot | no: the test and the sparser packets cost more than the lookups spared, except on the cow |"
  echo
  echo "## Many field objects: copies of the bunny on an exact ground"
  echo
  echo "AO rays (4 per pixel, unlimited length) from what the camera sees of 3 × 3 and 32 × 32 bunnies"
  echo "(\`scripts/copies-scene.py bun_zipper.ply N 0.25 OUT.json --ground 0.025\`), all field objects; the"
  echo "fields found through the grid and the tree over the objects' spheres (\`field\`, the default: rays within one or two"
  echo "cells of the grid take their list of objects, the others go down the tree; up to 16 objects it tests each sphere on lanes"
  echo "instead), through the tree alone (\`field:cull=tree\`) and by testing every sphere (\`field:cull=each\`), beside Embree's instancing;"
  echo "\`visfield-bench --scene OUT.json --rays ao --accel field,field:cull=tree,field:cull=each,embree:levels=2 --count 1000000 --threads $threads --reps 5\`."
  echo
  copies_tables "$models/bun_zipper.ply" 0.25 0.025 bunnies
  if [[ -n "${SNOWDEN:-}" ]]; then
    echo "The same with copies of Snowden's bust (109,259 triangles, a 3D scan; \`scripts/snowden-mesh.sh BUST.ply\` writes it"
    echo "from the npm package \`snowden\`, standing on y = 0): \`scripts/copies-scene.py BUST.ply N 10 OUT.json --ground 0\`."
    echo
    copies_tables "$SNOWDEN" 10 0 busts
  fi
  echo "### Closest hits among many field objects"
  echo
  echo "Camera rays (\`--rays primary\`) and random rays through the scene (\`--rays random\`) in the same 1024-copy scenes,"
  echo "the fields' closest hits beside Embree's instancing:"
  echo "\`visfield-bench --scene OUT.json --rays primary --accel field,embree:levels=2 --count 1000000 --threads $threads --reps 5\`, then \`--rays random\`."
  echo
  for scene in bunnies1024 ${SNOWDEN:+busts1024}; do
    for rays in primary random; do
      echo '```'
      (cd "$work" && "$root/$bin/visfield-bench" --scene "$scene.json" --rays "$rays" --accel field:cache=cache,embree:levels=2 \
        --count 1000000 --threads "$threads" --reps 5)
      echo '```'
      echo
    done
  done
  "$bin/visfield-experiments" --figure fig6 --scene "$models/bun_zipper.ply"
  echo
  "$bin/visfield-experiments" --figure lookups --scene "$models/bun_zipper.ply"
  echo
  "$bin/visfield-experiments" --figure fig5 --scene "$models/bun_zipper.ply"
  echo
  "$bin/visfield-experiments" --figure fig8 --scene "$models"
  echo
  "$bin/visfield-experiments" --figure gpu3 --scene "$models/bun_zipper.ply"
  echo
  echo "## GPU paper, Figure 5 on the CPU: intra-object AO, 512x512 pixels, 121 rays per pixel, 16642 x 64x64"
  echo
  echo "\`visfield render MODEL --width 512 --height 512 --ao-rays 121\` with the exact BVH, then with"
  echo "\`--occluders field --occluder field:positions=16642,directions=64\`, and \`visfield compare\`. Each tile's"
  echo "AO rays go through the fields' batch kernel; the camera rays through the BVH."
  echo
  for model in igea-triangles.ply Armadillo.ply; do
    echo "### $model"
    echo
    echo '```'
    "$bin/visfield" render "$models/$model" --width 512 --height 512 --ao-rays 121 --no-progress --out "$work/exact.png" | tail -1
    "$bin/visfield" render "$models/$model" --width 512 --height 512 --ao-rays 121 --no-progress --occluders field \
      --occluder field:positions=16642,directions=64 --out "$work/field.png" | tail -1
    "$bin/visfield" compare "$work/field.png" "$work/exact.png"
    echo '```'
    echo
  done
} | sed -e "s|$models|MODELS_DIR|g" -e "s|$work/||g" > "$work/out.md"
# Written whole or not at all: a run that fails part way leaves the last document as it was.
mv "$work/out.md" "$out"
echo "wrote $out"
