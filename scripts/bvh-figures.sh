#!/usr/bin/env bash
# Regenerates docs/bvh-measurements.md: the exact BVH against Embree on every model × ray kind
# (flattened), and its instanced form against Embree's instancing on scenes of copies, with the
# BVH's work per ray (nodes, leaves, triangle tests) from visfield-bench's counting pass.
# With BASELINE=path/to/an/older/visfield-bench, each cell also gives that build's figures, the two
# binaries run in alternation (ROUNDS rounds, default 3) so that both see the same machine.
# Usage: [BASELINE=BENCH] [ROUNDS=N] scripts/bvh-figures.sh MODELS_DIR [OUT.md]
# (MODELS_DIR holds bun_zipper.ply, dragon_vrip_res2.ply, Armadillo.ply, sponza.obj,
# conference.obj, cow.obj, teapot.obj; about 10 minutes on 2 cores, twice that with BASELINE)
set -euo pipefail
cd "$(dirname "$0")/.."
models=$(cd "${1:?usage: scripts/bvh-figures.sh MODELS_DIR [OUT.md]}" && pwd)
out=${2:-docs/bvh-measurements.md}
bench=build/bin/visfield-bench
[ -x "$bench" ] || { echo "bvh-figures: error: $bench not built (run the README's build first)" >&2; exit 1; }
baseline=${BASELINE:-}
[ -z "$baseline" ] || [ -x "$baseline" ] || { echo "bvh-figures: error: BASELINE=$baseline is not an executable" >&2; exit 1; }
rounds=${ROUNDS:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# run NAME BINARY SCENE KIND ACCELS: one visfield-bench run, its JSON kept as $work/NAME.rROUND.json.
run() {
  "$2" --scene "$3" --rays "$4" --accel "$5" --count 1000000 --threads 2 --reps 5 --json 2>/dev/null > "$work/$1.r$round.json"
}
# measure NAME SCENE KIND ACCELS: queues the cell; run_cells runs every queued cell once a round, the
# baseline then the current build, so that a cell's rounds lie minutes apart: this machine's speed
# drifts for minutes at a time (ours and Embree's unequally), and back-to-back rounds all saw one state.
cells=()
measure() { cells+=("$1|$2|$3|$4"); }
run_cells() {
  for round in $(seq "$rounds"); do
    for cell in "${cells[@]}"; do
      IFS='|' read -r name scene kind accels <<<"$cell"
      [ -z "$baseline" ] || run "$name.base" "$baseline" "$scene" "$kind" "$accels"
      run "$name.new" "$bench" "$scene" "$kind" "$accels"
    done
  done
}

flat_models="bun_zipper.ply dragon_vrip_res2.ply Armadillo.ply sponza.obj conference.obj cow.obj"
kinds="ao shadow primary random"
for m in $flat_models; do
  [ -f "$models/$m" ] || { echo "bvh-figures: error: $models/$m not found" >&2; exit 1; }
  for k in $kinds; do measure "flat.$m.$k" "$models/$m" "$k" bvh,embree; done
done

# The scenes of the instancing table in docs/structures.md (the README's instancing row).
for n in 1000 100 10; do
  /usr/bin/python3 scripts/copies-scene.py "$models/bun_zipper.ply" $n 0.25 "$work/bunnies$n.json" >/dev/null
done
/usr/bin/python3 scripts/copies-scene.py "$models/cow.obj" 1000 15 "$work/cows1000.json" >/dev/null
/usr/bin/python3 scripts/copies-scene.py "$models/cow.obj" 16 15 "$work/cows16.json" >/dev/null
/usr/bin/python3 scripts/copies-scene.py "$models/teapot.obj" 100 8 "$work/teapots100.json" >/dev/null
copies="bunnies1000.json bunnies100.json bunnies10.json cows1000.json cows16.json teapots100.json"
copies+=" builtin:boxes:size=100000 builtin:boxes:size=10000 builtin:boxes:size=64"
for s in $copies; do
  scene=$s
  [ "${s#builtin:}" != "$s" ] || scene="$work/$s"
  for k in ao primary; do measure "two.$s.$k" "$scene" "$k" bvh:levels=2,embree:levels=2; done
done
run_cells

{
  echo "# The exact BVH against Embree"
  echo
  echo "Written by \`scripts/bvh-figures.sh MODELS_DIR\` on $(date -u +%Y-%m-%d), $(nproc) threads, $(lscpu | sed -n 's/^Model name: *//p' | head -1)."
  echo "Each cell: \`visfield-bench --rays KIND --accel bvh,embree --count 1000000 --threads 2 --reps 5\`, the median over"
  echo "$rounds rounds of the per-process figures (ours and Embree's on the same rays in one process); each round runs every"
  echo "cell of both tables once, so a cell's rounds lie minutes apart."
  [ -z "$baseline" ] || echo "\"before\" is the build at BASELINE, run in alternation with this one in every round."
  echo
  /usr/bin/python3 - "$work" "$rounds" "${baseline:+yes}" "$flat_models" "$kinds" "$copies" <<'PY'
import json, math, statistics, sys
work, rounds, with_base = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "yes"
flat_models, kinds, copies = sys.argv[4].split(), sys.argv[5].split(), sys.argv[6].split()

def runs(name):
    return [json.load(open(f"{work}/{name}.r{r}.json")) for r in range(1, rounds + 1)]

def figures(name, ours_prefix):
    """Median Mrays/s of ours and Embree's, median ratio, build ms, bytes and work per ray."""
    ours, embree, ratio = [], [], []
    for doc in runs(name):
        rows = {row["accel"].split(":")[0]: row for row in doc["results"]}
        mine = next(row for row in doc["results"] if row["accel"].startswith(ours_prefix))
        theirs = rows["embree"]
        ours.append(mine["mrays_per_s"]); embree.append(theirs["mrays_per_s"])
        ratio.append(mine["mrays_per_s"] / theirs["mrays_per_s"])
        last = (mine, theirs)
    mine, theirs = last
    return dict(ours=statistics.median(ours), embree=statistics.median(embree), ratio=statistics.median(ratio),
                build=mine["build_ms"], bytes=mine["bytes"], embree_build=theirs["build_ms"], embree_bytes=theirs["bytes"],
                work=mine.get("bvh_work"), mismatches=mine["mismatches"])

def mib(b):
    return f"{b / 2**20:.1f} MiB"

def geomean(xs):
    return math.exp(sum(math.log(x) for x in xs) / len(xs))

print("## Flattened (`bvh` = `bvh:levels=1`, `embree:levels=1`)\n")
head = "| model | rays | bvh Mrays/s | Embree Mrays/s | × Embree |"
if with_base:
    head += " before: bvh Mrays/s, × Embree |"
head += " nodes / ray | leaves / ray | triangle tests / ray |"
print(head)
print("|" + "---|" * (head.count("|") - 1))
ratios, base_ratios, builds = [], [], {}
for m in flat_models:
    for k in kinds:
        f = figures(f"flat.{m}.{k}.new", "bvh")
        ratios.append(f["ratio"])
        w = f["work"] or {}
        cells = [m, k, f"{f['ours']:.2f}", f"{f['embree']:.2f}", f"{f['ratio']:.2f}×"]
        if with_base:
            b = figures(f"flat.{m}.{k}.base", "bvh")
            base_ratios.append(b["ratio"])
            cells.append(f"{b['ours']:.2f}, {b['ratio']:.2f}×")
        cells += [f"{w.get('nodes', 0):.2f}", f"{w.get('leaves', 0):.2f}", f"{w.get('triangle_tests', 0):.2f}"]
        print("| " + " | ".join(cells) + " |")
        builds[m] = (f, b if with_base else None)
print()
print(f"Geometric mean of the ratios to Embree: **{geomean(ratios):.2f}×** (lowest {min(ratios):.2f}×, highest {max(ratios):.2f}×)"
      + (f"; before: {geomean(base_ratios):.2f}× ({min(base_ratios):.2f}–{max(base_ratios):.2f}×)." if with_base else "."))
print()
print("Build (ms) and memory, the last round's:\n")
head = "| model | bvh build | bvh memory | Embree build | Embree memory |" + (" before: bvh build, memory |" if with_base else "")
print(head)
print("|" + "---|" * (head.count("|") - 1))
for m, (f, b) in builds.items():
    cells = [m, f"{f['build']:.1f}", mib(f["bytes"]), f"{f['embree_build']:.1f}", mib(f["embree_bytes"])]
    if b:
        cells.append(f"{b['build']:.1f}, {mib(b['bytes'])}")
    print("| " + " | ".join(cells) + " |")
print()
print("## Two levels (`bvh:levels=2` against `embree:levels=2`)\n")
print("The scenes of the instancing table in [`structures.md`](structures.md#instances-and-updates): copies by")
print("`scripts/copies-scene.py` (1000, 100 and 10 bunnies 0.25 apart, 1000 and 16 cows 15 apart, 100 teapots 8 apart)")
print("and `builtin:boxes:size=N` (N 12-triangle boxes).\n")
head = "| scene | rays | bvh:levels=2 Mrays/s | Embree's instancing Mrays/s | × Embree |" + (" before: Mrays/s, × Embree |" if with_base else "")
print(head)
print("|" + "---|" * (head.count("|") - 1))
two_ratios, two_base_ratios = [], []
for s in copies:
    for k in ("ao", "primary"):
        f = figures(f"two.{s}.{k}.new", "bvh")
        two_ratios.append(f["ratio"])
        cells = [s, k, f"{f['ours']:.2f}", f"{f['embree']:.2f}", f"{f['ratio']:.2f}×"]
        if with_base:
            b = figures(f"two.{s}.{k}.base", "bvh")
            two_base_ratios.append(b["ratio"])
            cells.append(f"{b['ours']:.2f}, {b['ratio']:.2f}×")
        print("| " + " | ".join(cells) + " |")
print()
print(f"Geometric mean of the ratios to Embree's instancing: **{geomean(two_ratios):.2f}×** (lowest {min(two_ratios):.2f}×, "
      f"highest {max(two_ratios):.2f}×)"
      + (f"; before: {geomean(two_base_ratios):.2f}× ({min(two_base_ratios):.2f}–{max(two_base_ratios):.2f}×)." if with_base else "."))
PY
  cat <<'TEXT'

## Where the time goes

- **Counters** (the tables' last columns, from `visfield-bench`'s counting pass, `bvh_work` in its JSON): AO and
  shadow rays on the scanned models walk 7–8 nodes and 2 leaves (13–16 triangle tests) per ray; random and
  primary rays 2–3 nodes and under one leaf. Build parameters (`leaf=4|16`, `kt=0.25|0.5|2`, `bins=64`) moved
  no ratio beyond noise (bunny, Armadillo, conference; AO and random rays).
- **Profiles** (`perf record` on software events): in one ray's walk the samples sit on the loads of a node's
  boxes and of a leaf block and on the compares right after them: a chain of dependent loads and compares
  about 40 cycles long per node, with little else for the core to do. Stepping several rays' walks in turn
  (`interleave_walks`) fills that time: AO on the bunny 0.89x -> 1.10x Embree with four walks, shadow
  0.96x -> 1.18x. Software prefetch of the next node on the stack, 2 MiB pages for the nodes and blocks
  (`madvise`), and running a walk several steps before switching were each within noise and are not kept.
- **Short walks** (random rays on Sponza, the conference room and the cow: 2–2.5 nodes and under one leaf per
  ray) are bound by each ray's fixed cost. Measurement builds with parts of the closest-hit stream taken out
  (`cmake -DVISFIELD_MEASURE_BVH_CUT=1|2`, then `visfield-bench --rays random --accel bvh,embree --count
  1000000`, per thread of 2; Intel Xeon VM, 2026-11-26): the batch loop and the answers' memory alone 6 ns a
  ray (cut 1); with each ray's constants (the watertight shear and the box reciprocals) 30 ns (cut 2); the
  whole query 88 ns on the cow and 127 ns on Sponza, against Embree's 71 and 97 ns for everything.
- **Each ray's constants** (AMD EPYC, 2026-11-27, interleaved runs of the same rays): `perf annotate` put a
  fifth of the random-ray samples on the constants, on compare-and-branch pairs: the watertight test's
  permuted origin was read through `Vec3f::operator[]` with the ray's kx, ky, kz, whose branches GCC keeps
  and random directions mispredict. The permuted origin now comes without branches (register permutes at
  first, now an index into a local array; `TraversalRay` in `bvh_walks.hpp`), and the streams compute a run of 64 rays' constants in one loop
  before stepping their walks (`with_traversal_rays`), which overlaps the rays' dependent chains. The run
  alone: cow random 0.84x -> 0.92x Embree, Sponza random 0.82x -> 0.88x, conference AO 1.00x -> 1.08x; then
  the origin without branches: cow random 0.86x -> 1.00x, conference random 0.81x -> 0.93x, conference AO
  0.97x -> 1.19x, cow AO 0.98x -> 1.06x, Sponza AO 0.90x -> 1.32x. More walks in turn (4 any-hit, 3
  closest-hit) were then slower (conference random 0.89x -> 0.82x, cow AO 1.05x -> 1.01x). Random rays on
  Sponza and the conference room stayed just below Embree (0.91-0.99x from run to run): a short walk's cost is
  its fixed per-ray part (the constants, the answer), which the profile spreads flat over the stream's loop (`perf annotate`: no instruction above 3% of its samples);
  runs of 16 or 32 rays' constants instead of 64 were slower (Sponza random 0.88x -> 0.80-0.88x).
- **Each ray's constants as scalars** (2026-11-27, 3 interleaved rounds): a stream keeps a run of 64 rays'
  constants at hand, and held as 8-lane copies (the box test's origin and reciprocals, the triangle test's
  permuted origin and shear: about 480 bytes a ray) they filled the 32 KiB first-level cache beside the nodes and
  blocks. The box test's alone as scalars (30 -> 16 KiB a run) moved no ratio beyond noise; with the triangle
  test's too (`BoxRay` and `simd::BlockRay` hold floats, broadcast where a node or a block is tested: 84 bytes a
  ray, 5 KiB a run) every ratio rose: Sponza random 0.85-0.94x -> 0.96-1.01x, conference random 0.96-1.02x ->
  0.98-1.04x, cow random 0.97-1.03x -> 1.03-1.04x, bunny AO 1.06-1.10x -> 1.11-1.15x, Sponza AO 1.28-1.33x ->
  1.41-1.63x. Random rays on Sponza and the
  conference room were then the two cells left below 1.0x (0.97x each in that table's run).
- **Rays that miss the scene** (2026-11-27, AMD EPYC): measurement builds on Sponza's random rays put the batch
  loop at 1.5 ns a ray a thread (cut 1: 1360 Mrays/s), each ray's constants and answer at 7.5 ns (cut 2: 266
  Mrays/s) and the whole query at 104 ns (19 Mrays/s): the walks are the time. Half of the random segments
  through a scene's bounding sphere meet none of its boxes (Sponza 51%, conference 45%, cow 49%: the segments
  against the scene's bounds), and each such walk ended at the root after a branch that random rays mispredict
  half the time. The closest-hit stream now tests each run's rays against the root's boxes in a loop without
  branches, writes the misses there, and starts walks for the others alone (`intersect_stream` in
  `traversal.cpp`). Interleaved, 3 rounds: Sponza random 18.0-18.6 -> 19.2-19.9 Mrays/s, conference random
  20.6-20.8 -> 22.0-22.9, cow random 27.6 -> 29.4-29.9, cow camera rays 49.6-54.1 -> 57.3; three walks in turn
  instead of two were again slower (Sponza random 19.3-19.5 -> 18.3). This table's "before" column is the build
  before that change.
- **Rounds spread over the run**: this machine's speed drifts for minutes at a time, and not alike for ours and
  Embree's: three rounds of a cell run back to back once put the copies scenes' AO at 0.90-0.94x Embree's
  instancing for this build and the one before alike (bunnies100 AO 5.40 Mrays/s), where a few minutes later the
  same binaries gave 1.10-1.14x (8.2-8.5 Mrays/s). Each round now runs every cell once, so a cell's rounds lie
  minutes apart and its median is not one stretch's; in the tables' run the build before the change above is
  also at or above 1.0x everywhere (lowest 1.01x, Sponza random).
- **Two levels**: the objects' walks gain from the same constants (AO on copies of meshes 0.89–0.95x ->
  1.07–1.14x Embree's instancing). A 12-triangle box costs a ray transform, the ray's constants and a walk
  of one node and a leaf; since the constants have no branches, stepping that walk in turn with the others
  beats answering it at once (64 boxes: 0.65x -> 0.70x). With the objects taken out
  (`cmake -DVISFIELD_MEASURE_BVH_CUT=3`: the top level's walks alone, `visfield-bench --scene
  builtin:boxes:size=N --rays ao --accel bvh:levels=2,embree:levels=2 --count 1000000 --threads 2`): on 64
  boxes the top level alone runs 92 Mrays/s (22 ns a ray a thread) against 37 Mrays/s (54 ns) for the whole
  query and Embree's 54 (37 ns): the 0.9 boxes a ray enters cost 32 ns, Embree's whole query 37. On 10,000
  boxes the top level alone, which then never stops at a hit, runs 24.5–25.9 Mrays/s, below Embree's whole
  query (33). Two walks in turn were level with three, four and six slower (64 boxes: 0.80x, 0.81x, 0.70x,
  0.64x in one run).
- **Direct Bvhs** (2026-11-27, AMD EPYC): a Bvh of one or two leaf blocks (up to 16 triangles, the 12-triangle
  box among them) is queried without its node: its blocks are tested at once, and only the triangle test's
  constants are computed (no box reciprocals); the instance layer answers such an object at once instead of
  stepping a walk into it. 64 boxes, AO: 43.5 -> 53.3 Mrays/s (0.82x -> 1.00x Embree's instancing in that
  run); 10,000 boxes 32.6 -> 38.4 (0.95x -> 1.13x); primary rays on 64 boxes 1.12x -> 1.14-1.31x.
  Stepping the direct test in turn with the other walks measured 0.94-0.97x (answered at once: 0.99-1.01x),
  and one 4-lane division for the top level's three reciprocals was level with three scalar ones. On
  another day's machine state the same two builds gave 0.70x and 0.86-0.88x: the gain (+24%) held, the
  ratio to Embree moved with the machine.
TEXT
} > "$out"
echo "wrote $out"
