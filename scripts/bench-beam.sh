#!/usr/bin/env bash
# The BeamField measurements of the README: VLF-RT's Table 1 (AO along the 513 stored lines), its
# Figure 5 (primary rays into random soups of 1K to 1M triangles, with a PNG plot) and the parameter
# sweeps the defaults come from. Each run's JSON goes to OUTDIR; a markdown summary to stdout.
#
# Usage: scripts/bench-beam.sh table1 MODELS_DIR OUTDIR   (cow, bunny, dragon, Igea, Armadillo, teapot and
#                                                          Sponza from MODELS_DIR; about 30 minutes)
#        scripts/bench-beam.sh sweeps MODEL OUTDIR         (one mesh; dirs, n and depth, one at a time)
#        scripts/bench-beam.sh scaling OUTDIR              (soups; needs gnuplot for the plot:
#                                                          apt-get install gnuplot-nox)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bench=$root/build/bin/visfield-bench
[ -x "$bench" ] || { echo "bench-beam: error: $bench not built (run the README's build first)" >&2; exit 1; }
py=/usr/bin/python3

summarise() {  # summarise FILE...: one markdown row per structure of each JSON report
  "$py" - "$@" <<'EOF'
import json, sys
for path in sys.argv[1:]:
    try:
        r = json.load(open(path))
    except (OSError, ValueError):
        print("| %s | failed or refused (see %s.err) |" % (path, path))
        continue
    for row in r["results"]:
        ratio = row.get("ratio_to_embree")
        work = row.get("beam_work")
        print("| %s | %d | %d | %s | %.2f | %s | %.0f | %.0f | %d | %s |" % (
            r["scene"], r["triangles"], r["rays"], row["accel"], row["mrays_per_s"],
            "%.2f×" % ratio if ratio is not None else "-", row["build_ms"], row["bytes"] / 2**20, row["mismatches"],
            "%.1f tests, %.1f leaves" % (work["triangle_tests"], work["leaves"]) if work else ""))
EOF
}

header='| scene | triangles | rays | accel | Mrays/s | × Embree | build ms | MiB | mismatches | work per ray |
|---|---:|---:|---|---:|---:|---:|---:|---:|---|'

run() {  # run OUT ARGS...: one visfield-bench run, JSON to OUT, errors to OUT.err
  local out=$1
  shift
  "$bench" --threads 2 --json "$@" > "$out" 2> "$out.err" || true
}

mode=${1:-}
case "$mode" in
  table1)
    # The paper's workload: a 256x256 view, one AO ray along each of the 513 lines from every visible
    # point (every line carries a ray from every point: a parallel projection per line). In one
    # process per model: BeamField at our defaults (n=64, depth 4), the median BSP at three depths
    # (0 = round(log2 N), then deeper, as the paper tuned its CRT's), the kd-tree, the BVH and Embree.
    # BeamField at the paper's 128x128 tiles and tile-BSP depths 3, 4 and 5 runs in processes of its
    # own beside Embree (each field is 4x the default's memory); ratios are taken through Embree's rate
    # in each process. Then the user's view: `visfield render` wall and render times, three runs each,
    # interleaved, for BeamField, the median BSP and the BVH.
    models=$2 out=$3
    mkdir -p "$out"
    for m in cow.obj bun_zipper.ply dragon_vrip_res2.ply igea-triangles.ply Armadillo.ply teapot.obj sponza.obj; do
      [ -f "$models/$m" ] || { echo "bench-beam: $models/$m is missing; skipped" >&2; continue; }
      run "$out/table1-${m%.*}.json" --scene "$models/$m" --rays ao --ao-directions 513 --width 256 --height 256 \
        --accel beam,median-bsp,median-bsp:depth=20,median-bsp:depth=24,kdtree,bvh,embree --reps 3 --warmup 1
      for depth in 3 4 5; do
        run "$out/table1-${m%.*}-n128-depth$depth.json" --scene "$models/$m" --rays ao --ao-directions 513 --width 256 \
          --height 256 --accel "beam:n=128,depth=$depth,embree" --reps 3 --warmup 1
      done
    done
    echo "$header"
    summarise "$out"/table1-*.json
    echo
    "$py" - "$out" <<'EOF2'
import glob, json, os, sys
by_model = {}
for path in sorted(glob.glob(os.path.join(sys.argv[1], "table1-*.json"))):
    try:
        r = json.load(open(path))
    except (OSError, ValueError):
        continue
    for row in r["results"]:
        if row.get("ratio_to_embree") is None or row["accel"].startswith("embree"):
            continue
        by_model.setdefault(r["scene"], []).append((row["accel"], row["ratio_to_embree"]))
print("| model | BeamField, defaults (× Embree) | BeamField, best at n=128 | median BSP, best | beam ÷ median BSP, defaults | best ÷ best | BVH (× Embree) |")
print("|---|---:|---:|---:|---:|---:|---:|")
for scene, rows in by_model.items():
    get = lambda prefix: [(a, x) for a, x in rows if a.startswith(prefix)]
    beam = [x for a, x in rows if a.startswith("beam") and "n=128" not in a]
    at128 = [(x, a) for a, x in rows if "n=128" in a]
    beam128 = max(at128) if at128 else (0.0, "-")
    bsp = max((x, a) for a, x in get("median-bsp"))
    bvh = [x for a, x in rows if a.startswith("bvh")]
    if not beam or not bvh:
        continue
    best_beam = max(beam[0], beam128[0])
    print("| %s | %.2f× | %.2f× (%s) | %.2f× (%s) | %.2f× | %.2f× | %.2f× |" % (
        scene, beam[0], beam128[0], beam128[1], bsp[0], bsp[1], beam[0] / bsp[0], best_beam / bsp[0], bvh[0]))
EOF2
    echo
    echo "| model | render s (wall s): beam | median-bsp | bvh | beam ÷ median-bsp | beam ÷ bvh |"
    echo "|---|---:|---:|---:|---:|---:|"
    visfield=$root/build/bin/visfield
    for m in cow.obj bun_zipper.ply igea-triangles.ply sponza.obj; do
      [ -f "$models/$m" ] || continue
      declare -A render wall
      for round in 1 2 3; do
        for a in beam median-bsp bvh; do
          start=$(date +%s.%N)
          line=$("$visfield" render "$models/$m" --accel "$a" --ao-directions 513 --width 256 --height 256 --out "$out/render.png" --no-progress 2>&1 | tail -1)
          end=$(date +%s.%N)
          render[$a]+="$(sed -n 's/.*), \([0-9.]*\) s,.*/\1/p' <<<"$line") "
          wall[$a]+="$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f", b - a}') "
        done
      done
      median() { tr ' ' '\n' <<<"$1" | grep . | sort -g | sed -n 2p; }
      b=$(median "${render[beam]}") s=$(median "${render[median-bsp]}") v=$(median "${render[bvh]}")
      printf '| %s | %s (%s) | %s (%s) | %s (%s) | %.2f× | %.2f× |\n' "${m%.*}" "$b" "$(median "${wall[beam]}")" "$s" \
        "$(median "${wall[median-bsp]}")" "$v" "$(median "${wall[bvh]}")" "$(awk -v a="$s" -v b="$b" 'BEGIN {print a / b}')" \
        "$(awk -v a="$v" -v b="$b" 'BEGIN {print a / b}')"
      unset render wall
    done
    ;;
  sweeps)
    model=$2 out=$3
    name=$(basename "${model%.*}")
    mkdir -p "$out"
    for dirs in 129 513 2049; do
      run "$out/sweep-$name-dirs$dirs.json" --scene "$model" --rays ao --ao-directions "$dirs" --count 1000000 \
        --accel "beam:dirs=$dirs,embree" --reps 3
    done
    for n in 32 64 128 256 512; do
      run "$out/sweep-$name-n$n.json" --scene "$model" --rays ao --ao-directions 513 --count 1000000 \
        --accel "beam:n=$n,embree" --reps 3
    done
    for depth in 0 1 2 3 4 5 6 7 8; do
      run "$out/sweep-$name-depth$depth.json" --scene "$model" --rays ao --ao-directions 513 --count 1000000 \
        --accel "beam:depth=$depth,embree" --reps 3
    done
    echo "$header"
    summarise "$out"/sweep-"$name"-*.json
    ;;
  scaling)
    out=$2
    mkdir -p "$out"
    # BeamField runs apart (with Embree for its ratio), so that a field too large for this machine's
    # memory is refused without losing the other structures' figures.
    for size in 1000 4000 16000 64000 256000 1000000; do
      run "$out/scaling-$size.json" --scene "builtin:soup:size=$size" --rays primary --width 512 --height 512 \
        --accel median-bsp,kdtree,bvh,embree --reps 3
      run "$out/scaling-$size-beam.json" --scene "builtin:soup:size=$size" --rays primary --width 512 --height 512 \
        --accel beam,embree --reps 3
    done
    echo "$header"
    summarise "$out"/scaling-*.json
    # Frame time (ms for the 512x512 image) against triangles, one line per structure.
    "$py" - "$out" <<'EOF' > "$out/scaling.dat"
import json, sys, glob, os
rows = {}
for path in glob.glob(os.path.join(sys.argv[1], "scaling-*.json")):
    try:
        r = json.load(open(path))
    except (OSError, ValueError):
        continue
    for row in r["results"]:
        rows.setdefault(row["accel"].split(":")[0], {})[r["triangles"]] = row["median_ms"]
for accel, by_size in rows.items():
    points = sorted(by_size.items())
    print('"%s"' % accel)
    for tris, ms in points:
        print(tris, ms)
    print()
    print()
EOF
    if command -v gnuplot > /dev/null; then
      blocks=$(grep -c '^"' "$out/scaling.dat")
      gnuplot <<EOF
set terminal png size 900,600
set output "$out/scaling.png"
set title "512x512 primary rays into random triangle soups (2 threads)"
set logscale xy
set xlabel "triangles"
set ylabel "frame time (ms)"
set key top left
set grid
plot for [i=0:$((blocks - 1))] "$out/scaling.dat" index i with linespoints lw 2 title columnheader(1)
EOF
      echo "plot: $out/scaling.png"
    else
      echo "bench-beam: gnuplot not found (apt-get install gnuplot-nox): no plot" >&2
    fi
    ;;
  *)
    sed -n 2,10p "$0" >&2
    exit 2
    ;;
esac
