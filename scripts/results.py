#!/usr/bin/python3
"""The raw results behind every figure visfield reports, and the tables made from them.

A results folder (bench/results/<date>-<cpu>-<kernels>/) holds machine.json (the processor, its
kernels' path, the compiler, Embree, the GPU where one ran, the commit and the date) and one file per
workload, NAME.json: the command line, its wall time, exit status, output, and its JSON output parsed
where it printed some (visfield-bench --json). scripts/measure.sh writes them through `run`; the
README's headline table and the measurement pages are made from them by `table` and `readme`.

  results.py machine OUT_DIR VISFIELD_BIN         write OUT_DIR/machine.json
  results.py run OUT_DIR NAME -- COMMAND...        run COMMAND, write OUT_DIR/NAME.json (fails when it fails)
  results.py table [RESULTS_DIR...]                print the headline table of the newest results
  results.py readme README.md [--check | --write]  the README's headline table from bench/results/:
                                                   --check fails (exit 1) where the README differs
  results.py pages [--check | --write]             the measurement pages (docs/*-measurements.md,
                                                   docs/render-figures.md) from bench/results/, likewise
"""
import datetime
import glob
import json
import math
import os
import platform
import re
import shlex
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "bench", "results")
BEGIN = "<!-- headline table: made by scripts/results.py readme README.md --write from bench/results/; do not edit -->"
END = "<!-- end of the headline table -->"


def fail(message):
    print("results: error: " + message, file=sys.stderr)
    sys.exit(1)


def git(*args):
    try:
        return subprocess.run(["git", "-C", ROOT] + list(args), capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def commit():
    """The commit measured, marked when the tree had changes."""
    head = git("rev-parse", "--short=7", "HEAD")
    dirty = subprocess.run(["git", "-C", ROOT, "diff", "--quiet", "HEAD"]).returncode != 0
    return head + (" (with uncommitted changes)" if dirty else "")


def cpu_model():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%MZ")


def write_machine(out_dir, visfield):
    """machine.json: what the numbers in out_dir were measured on."""
    info = subprocess.run([visfield, "info", "builtin:cornell"], capture_output=True, text=True)
    kernels = re.search(r"^kernels: +(.*)$", info.stdout, re.M)
    cache = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(visfield))), "CMakeCache.txt")
    compiler = "unknown"
    if os.path.exists(cache):
        found = re.search(r"^CMAKE_CXX_COMPILER:\w+=(.*)$", open(cache).read(), re.M)
        if found:
            version = subprocess.run([found.group(1), "--version"], capture_output=True, text=True).stdout.splitlines()
            compiler = version[0] if version else found.group(1)
    gpu = None
    try:
        smi = subprocess.run(["nvidia-smi", "--query-gpu=name,driver_version", "--format=csv,noheader"], capture_output=True, text=True)
        if smi.returncode == 0 and smi.stdout.strip():
            gpu = smi.stdout.strip().splitlines()[0]
    except OSError:
        pass
    machine = {
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "kernels": kernels.group(1) if kernels else "unknown",
        "isa": os.environ.get("VISFIELD_ISA") or (kernels.group(1).split()[0] if kernels else "unknown"),
        "compiler": compiler,
        "os": platform.platform(),
        "gpu": gpu,
        "commit": commit(),
        "date": now(),
    }
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "machine.json"), "w") as f:
        json.dump(machine, f, indent=2)
        f.write("\n")
    return machine


def run(out_dir, name, command):
    """Runs `command`, keeps what it printed and how long it took in out_dir/name.json. The commit is
    the one checked out when the run starts (a long run's tree may move on while it runs)."""
    measured = commit()
    start = time.monotonic()
    done = subprocess.run(command, capture_output=True, text=True)
    seconds = time.monotonic() - start
    record = {
        "name": name,
        "command": " ".join(shlex.quote(os.path.relpath(a, ROOT) if os.path.isabs(a) and a.startswith(ROOT) else a) for a in command),
        "environment": {k: v for k, v in os.environ.items() if k.startswith("VISFIELD_") and k != "VISFIELD_MODELS_DIR"},
        "commit": measured,
        "date": now(),
        "seconds": round(seconds, 3),
        "exit": done.returncode,
        "stdout": done.stdout,
        "stderr": done.stderr[-4000:],
    }
    try:
        record["json"] = json.loads(done.stdout)
    except ValueError:
        pass
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")
    print("measure: %-32s %7.1f s%s" % (name, seconds, "" if done.returncode == 0 else "  FAILED (exit %d)" % done.returncode), file=sys.stderr)
    if done.returncode != 0:
        sys.stderr.write(done.stderr[-2000:])
        sys.exit(done.returncode)


# ---- reading results


def load(folder):
    """{name: record} of one results folder, and its machine.json."""
    machine = json.load(open(os.path.join(folder, "machine.json")))
    records = {}
    for path in glob.glob(os.path.join(folder, "*.json")):
        name = os.path.basename(path)[:-5]
        if name != "machine":
            records[name] = json.load(open(path))
    return machine, records


def meshes(n):
    """'1 mesh', '6 meshes'."""
    return "%d mesh%s" % (n, "" if n == 1 else "es")


def geomean(values):
    values = [v for v in values if v and v > 0]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else None


def bench_rows(record):
    """{accel: row} of a visfield-bench --json record."""
    return {row["accel"]: row for row in record.get("json", {}).get("results", [])}


def ratio(record, prefix):
    """The ratio to Embree of the first row whose accel starts with `prefix`."""
    for accel, row in bench_rows(record).items():
        if accel.startswith(prefix) and row.get("ratio_to_embree"):
            return row["ratio_to_embree"]
    return None


def best_ratio(record, prefix):
    """The first `prefix` row's rate over the fastest Embree row's."""
    mine = rate(record, prefix)
    embree = [row["mrays_per_s"] for accel, row in bench_rows(record).items() if accel.startswith("embree")]
    return mine / max(embree) if mine and embree else None


def rate(record, prefix):
    for accel, row in bench_rows(record).items():
        if accel.startswith(prefix):
            return row["mrays_per_s"]
    return None


def matching(records, pattern):
    return [records[n] for n in sorted(records) if re.fullmatch(pattern, n)]


def machine_class(machine):
    """"AMD EPYC, 2 cores, AVX-512 kernels": the processor and the path that ran."""
    isa = {"avx512": "AVX-512", "avx2": "AVX2"}.get(machine.get("isa"), machine.get("isa", "?"))
    return "%s, %s cores, %s kernels" % (machine["cpu"], machine["cores"], isa)


def render_seconds(record):
    found = re.search(r", ([0-9.]+) s, [0-9.]+ Mrays/s", record["stderr"] + record["stdout"])
    return float(found.group(1)) if found else None


def headline_rows(folder, machine, records):
    """The headline rows `folder` has: (key, what, figure, page)."""
    rows = []
    isa = machine.get("isa")
    medians = []
    for number in (1, 2):
        runs = sorted(r["seconds"] for r in matching(records, r"readme-command%d-\d+" % number) if r["exit"] == 0)
        if runs:
            note = "median of %d" % len(runs) if len(runs) > 1 else "1 run"
            last = matching(records, r"readme-command%d-\d+" % number)[-1]
            counted = re.findall(r"tests passed, \d+ tests failed out of (\d+)", last["stdout"])
            skipped = len(re.findall(r"\(Skipped\)", last["stdout"]))
            if counted and skipped:
                note += "; %d of %s tests skip there: no shared meshes" % (skipped, counted[-1])
            medians.append("command %d %.0f s (%s)" % (number, runs[len(runs) // 2], note))
    if medians:
        rows.append(("readme", "The README's commands on a fresh clone, packages purged, no compiler cache",
                     ", ".join(medians), "docs/testing.md"))
    runs = matching(records, r"bvh-(ao|shadow|primary|random)-.*")
    bvh = [best_ratio(r, "bvh") for r in runs]
    if bvh and all(bvh):
        models = len({n.split("-", 2)[2] for n in records if re.fullmatch(r"bvh-(ao|shadow|primary|random)-.*", n)})
        kinds = len({n.split("-")[1] for n in records if re.fullmatch(r"bvh-(ao|shadow|primary|random)-.*", n)})
        single = [ratio(r, "bvh") for r in runs]
        rows.append(("bvh-" + isa, "Exact BVH, %s x %d ray kinds" % (meshes(models), kinds),
                     "%.2fx Embree's best call (%.2f-%.2fx), %.2fx its rtcIntersect1 (geometric means)" %
                     (geomean(bvh), min(bvh), max(bvh), geomean(single)), "docs/bvh-measurements.md"))
    two = [best_ratio(r, "bvh:levels=2") for r in matching(records, r"instances-.*")]
    if two and all(two):
        rows.append(("instances-" + isa, "Two-level BVH over copies of meshes, AO and camera rays",
                     "%.2fx Embree's best instancing (geometric mean)" % geomean(two), "docs/bvh-measurements.md"))
    beam = []
    for r in matching(records, r"beam-table1-.*"):
        b, m = rate(r, "beam"), max((row["mrays_per_s"] for a, row in bench_rows(r).items() if a.startswith("median-bsp")), default=None)
        if b and m:
            beam.append(b / m)
    if beam:
        rows.append(("beam", "BeamField, VLF-RT's Table 1 workload (AO along 513 lines, 256x256)",
                     "%.2fx our median BSP (geometric mean of %s), exact" % (geomean(beam), meshes(len(beam))), "docs/beamfield-measurements.md"))
    intra = [ratio(r, "field") for r in matching(records, r"field-intra-.*")]
    if intra and all(intra):
        rows.append(("field-intra", "ObjectField, AO rays from each mesh's own surface",
                     "%.1fx Embree (geometric mean of %s), about 3%% of answers differ" % (geomean(intra), meshes(len(intra))),
                     "docs/objectfield-measurements.md"))
    copies = matching(records, r"field-copies-1024")
    if copies and ratio(copies[0], "field"):
        rows.append(("field-copies", "ObjectField, 1024 copies of the bunny on a ground, AO",
                     "%.2fx Embree's instancing" % ratio(copies[0], "field"), "docs/objectfield-measurements.md"))
    # The VLF-RT corner's figures are on the ObjectField page (page_field), not in the headline: ten rows at most.
    exact, field = matching(records, r"render-ao-exact"), matching(records, r"render-ao-field")
    if exact and field:
        e = [render_seconds(r) for r in matching(records, r"render-ao-exact(-\d+)?")]
        f = [render_seconds(r) for r in matching(records, r"render-ao-field(-\d+)?")]
        compare = matching(records, r"render-ao-compare")
        rms = re.search(r"rms:\s+([0-9.]+)", compare[0]["stdout"]) if compare else None
        if all(e) and all(f):
            figure = "%.1fx faster than the BVH render" % (sorted(e)[len(e) // 2] / sorted(f)[len(f) // 2])
            if rms:
                figure += ", image RMS %.2f (0-255)" % float(rms.group(1))
            rows.append(("render", "An AO render through fields (Igea, 512x512, 121 rays a pixel)", figure, "docs/render-figures.md"))
    report = os.path.join(folder, "planner-report.md")
    if "planner" in records and os.path.exists(report):
        found = re.search(r"Overall: ([0-9]+) of ([0-9]+) choices right", open(report).read())
        if found:
            rows.append(("planner", "The planner (`auto`): held-out scenes, ray kinds and counts",
                         "picks the measured fastest in %s of %s" % found.groups(), "docs/selection-report.md"))
    return rows


def folders(paths=None):
    """Results folders, newest first (by machine.json's date)."""
    found = paths or [d for d in glob.glob(os.path.join(RESULTS, "*")) if os.path.exists(os.path.join(d, "machine.json"))]
    return sorted(found, key=lambda d: json.load(open(os.path.join(d, "machine.json")))["date"], reverse=True)


def table(paths=None):
    """The headline table: each row from the newest folder that has it (the BVH's rows once per
    kernel path: AVX2 and AVX-512)."""
    order = ["readme", "bvh-avx2", "bvh-avx512", "instances-avx2", "instances-avx512", "beam", "field-intra", "field-copies",
             "render", "planner"]
    rows = {}
    for folder in folders(paths):
        machine, records = load(folder)
        for key, what, figure, page in headline_rows(folder, machine, records):
            rows.setdefault(key, "| %s | %s | %s | [history](%s) |" % (what, figure, machine_class(machine), page))
    header = ["| what | measured | machine | page |", "|---|---|---|---|"]
    return "\n".join(header + [rows[k] for k in sorted(rows, key=lambda k: order.index(k) if k in order else len(order))])


def readme(path, mode):
    text = open(path).read()
    if BEGIN not in text or END not in text:
        fail("%s has no headline table markers (%s ... %s)" % (path, BEGIN, END))
    before, rest = text.split(BEGIN, 1)
    current, after = rest.split(END, 1)
    made = "\n" + table() + "\n"
    if mode == "--write":
        open(path, "w").write(before + BEGIN + made + END + after)
        return
    if current != made:
        old, new = current.strip().splitlines(), made.strip().splitlines()
        for i in range(max(len(old), len(new))):
            a = old[i] if i < len(old) else "(none)"
            b = new[i] if i < len(new) else "(none)"
            if a != b:
                fail("%s: the headline table's line %d is\n  %s\nbut bench/results/ makes it\n  %s\n"
                     "(scripts/results.py readme %s --write)" % (path, i + 1, a, b, path))
    print("readme: the headline table matches bench/results/ (%d rows)" % (len(made.strip().splitlines()) - 2))


# ---- the measurement pages


def raw_link(folder, name, depth="../"):
    return "[raw](%s%s)" % (depth, os.path.relpath(os.path.join(folder, name + ".json"), ROOT))


def fmt(x, pattern="%.2f"):
    return "-" if x is None else pattern % x


def section(folder, machine, title):
    return ["## %s" % title, "",
            "%s; measured %s at commit %s (%s)." % (machine_class(machine), machine["date"][:10], machine["commit"], machine["compiler"]), ""]


def embree_best_of(record):
    """(accel, Mrays/s) of the fastest Embree row."""
    rows = [(a, r["mrays_per_s"]) for a, r in bench_rows(record).items() if a.startswith("embree")]
    return max(rows, key=lambda x: x[1]) if rows else (None, None)


def ours(record, prefix):
    for accel, row in bench_rows(record).items():
        if accel.startswith(prefix):
            return accel, row
    return None, None


def page_bvh(sources):
    lines = ["# The exact BVH against Embree", "",
             "Made by `scripts/results.py pages --write` from the raw files of [bench/results/](../bench/results/), which",
             "`scripts/measure.sh` writes; do not edit. Each row: `visfield-bench --scene MESH --rays KIND --accel",
             "bvh,bvh:call=1,embree,embree:call=best --count 1000000 --threads 2 --reps 5` (the same rays through each structure,",
             "in one process, repetitions interleaved); *one ray at a time* is our BVH called ray by ray (`call=1`), not through",
             "its batch path; Embree's first row is called as most users call it (`rtcIntersect1` /",
             "`rtcOccluded1`, medium build quality), *Embree best* is the fastest of its calls (single rays, 16-ray packets,",
             "streams) at both build qualities. Work per ray: the BVH's nodes, leaves and triangle tests.", ""]
    for folder, machine, records in sources:
        runs = matching(records, r"bvh-(ao|shadow|primary|random)-.*")
        two = matching(records, r"instances-.*")
        if not runs and not two:
            continue
        lines += section(folder, machine, machine_class(machine))
        if runs:
            lines += ["| mesh | rays | BVH Mrays/s | one ray at a time | Embree Mrays/s | BVH ÷ Embree | Embree best | BVH ÷ Embree best | nodes / leaves / tests a ray | |",
                      "|---|---|--:|--:|--:|--:|---|--:|---|---|"]
            ratios, best_ratios = [], []
            for r in runs:
                doc = r["json"]
                accel, row = ours(r, "bvh")
                _, embree = ours(r, "embree")
                best, best_rate = embree_best_of(r)
                work = row.get("bvh_work") if row else None
                ratios.append(row["mrays_per_s"] / embree["mrays_per_s"])
                best_ratios.append(row["mrays_per_s"] / best_rate)
                single = [x for a, x in bench_rows(r).items() if a.startswith("bvh") and "call=1" in a]
                lines.append("| %s | %s | %.2f | %s | %.2f | %.2fx | %s | %.2fx | %s | %s |" % (
                    doc["scene"], doc["kind"], row["mrays_per_s"], "%.2f" % single[0]["mrays_per_s"] if single else "-",
                    embree["mrays_per_s"], ratios[-1],
                    best.split("->")[-1].strip() if best else "-", best_ratios[-1],
                    "%.1f / %.1f / %.1f" % (work["nodes"], work["leaves"], work["triangle_tests"]) if work else "-",
                    raw_link(folder, r["name"])))
            lines += ["", "Geometric means: %.2fx Embree, %.2fx Embree best, over %d cells." % (geomean(ratios), geomean(best_ratios), len(runs)), ""]
        if two:
            lines += ["Copies of meshes: the two-level BVH (`bvh:levels=2`) against Embree's instancing (`embree:levels=2`).", "",
                      "| scene | rays | BVH Mrays/s | Embree Mrays/s | BVH ÷ Embree | BVH ÷ Embree best | |", "|---|---|--:|--:|--:|--:|---|"]
            for r in two:
                doc = r["json"]
                _, row = ours(r, "bvh")
                _, embree = ours(r, "embree")
                _, best_rate = embree_best_of(r)
                lines.append("| %s | %s | %.2f | %.2f | %.2fx | %.2fx | %s |" % (
                    doc["scene"], doc["kind"], row["mrays_per_s"], embree["mrays_per_s"], row["mrays_per_s"] / embree["mrays_per_s"],
                    row["mrays_per_s"] / best_rate, raw_link(folder, r["name"])))
            lines.append("")
    return lines


def page_beam(sources):
    lines = ["# BeamField measurements", "",
             "Made by `scripts/results.py pages --write` from the raw files of [bench/results/](../bench/results/); do not edit.",
             "VLF-RT's Table 1 workload: a 256x256 view, one AO ray along each of the 513 stored lines from every visible",
             "point, `visfield-bench --rays ao --ao-directions 513 --width 256 --height 256 --accel beam,median-bsp,embree`:",
             "BeamField at its defaults against our spatial-median BSP (the paper's baseline) and Embree, every answer",
             "checked against Embree's.", ""]
    for folder, machine, records in sources:
        runs = matching(records, r"beam-table1-.*")
        if not runs:
            continue
        lines += section(folder, machine, machine_class(machine))
        lines += ["| mesh | rays | BeamField Mrays/s | median BSP Mrays/s | Embree Mrays/s | BeamField ÷ median BSP | BeamField ÷ Embree | mismatches | build ms (BeamField) | |",
                  "|---|--:|--:|--:|--:|--:|--:|--:|--:|---|"]
        for r in runs:
            doc = r["json"]
            _, beam = ours(r, "beam")
            _, bsp = ours(r, "median-bsp")
            _, embree = ours(r, "embree")
            lines.append("| %s | %d | %.2f | %.2f | %.2f | %.2fx | %.2fx | %d | %.0f | %s |" % (
                doc["scene"], doc["rays"], beam["mrays_per_s"], bsp["mrays_per_s"], embree["mrays_per_s"],
                beam["mrays_per_s"] / bsp["mrays_per_s"], beam["mrays_per_s"] / embree["mrays_per_s"], beam["mismatches"],
                beam["build_ms"], raw_link(folder, r["name"])))
        lines.append("")
    return lines


def page_field(sources):
    lines = ["# ObjectField measurements", "",
             "Made by `scripts/results.py pages --write` from the raw files of [bench/results/](../bench/results/); do not edit.",
             "Fields are approximate: each row gives the share of answers that differ from Embree's exact ones.", ""]
    for folder, machine, records in sources:
        intra = matching(records, r"field-intra-.*")
        copies = matching(records, r"field-copies-.*")
        corner = matching(records, r"field-corner")
        if not (intra or copies or corner):
            continue
        lines += section(folder, machine, machine_class(machine))
        if intra:
            lines += ["AO rays from each mesh's own surface (`visfield-bench --scene MESH --rays ao --accel field,embree --count 1000000`):", "",
                      "| mesh | field Mrays/s | Embree Mrays/s | field ÷ Embree | answers that differ | field build ms | field bytes | |",
                      "|---|--:|--:|--:|--:|--:|--:|---|"]
            for r in intra:
                doc = r["json"]
                _, field = ours(r, "field")
                _, embree = ours(r, "embree")
                lines.append("| %s | %.1f | %.2f | %.1fx | %.2f%% | %.0f | %d | %s |" % (
                    doc["scene"], field["mrays_per_s"], embree["mrays_per_s"], field["mrays_per_s"] / embree["mrays_per_s"],
                    100.0 * field.get("differing_fraction", 0.0), field["build_ms"], field["bytes"], raw_link(folder, r["name"])))
            lines.append("")
        if copies:
            lines += ["Copies of the bunny on an exact ground (`scripts/copies-scene.py bun_zipper.ply N 0.25 OUT.json --ground 0.025`),",
                      "every copy a field object, against Embree's instancing:", "",
                      "| scene | field Mrays/s | Embree Mrays/s | field ÷ Embree | answers that differ | field bytes | Embree bytes | |",
                      "|---|--:|--:|--:|--:|--:|--:|---|"]
            for r in copies:
                doc = r["json"]
                _, field = ours(r, "field")
                _, embree = ours(r, "embree")
                lines.append("| %s | %.1f | %.2f | %.2fx | %.2f%% | %d | %d | %s |" % (
                    doc["scene"], field["mrays_per_s"], embree["mrays_per_s"], field["mrays_per_s"] / embree["mrays_per_s"],
                    100.0 * field.get("differing_fraction", 0.0), field["bytes"], embree["bytes"], raw_link(folder, r["name"])))
            lines.append("")
        for r in corner:
            lines += ["The VLF-RT corner's inter-object AO rays (`%s`, its output as printed; %s):" % (r["command"], raw_link(folder, r["name"])), "",
                      r["stdout"].strip(), ""]
    return lines


def page_render(sources):
    lines = ["# Rendered figures", "",
             "Made by `scripts/results.py pages --write` from the raw files of [bench/results/](../bench/results/); do not edit.", ""]
    for folder, machine, records in sources:
        exact = matching(records, r"render-ao-exact(-\d+)?")
        field = matching(records, r"render-ao-field(-\d+)?")
        figures = matching(records, r"render-gpu\d.*")
        if not (exact or figures):
            continue
        lines += section(folder, machine, machine_class(machine))
        if exact and field:
            e = sorted(render_seconds(r) for r in exact)
            f = sorted(render_seconds(r) for r in field)
            compare = matching(records, r"render-ao-compare")
            lines += ["An AO render of Igea (512x512, 121 AO rays a pixel), its AO rays through fields against the same render",
                      "through the exact BVH (`visfield render igea-triangles.ply --occluders field|exact --ao-rays 121 --width 512",
                      "--height 512 --threads 2`, %d rounds interleaved; render seconds, the builds apart):" % len(e), "",
                      "| occluders | render s (median) | each round | |", "|---|--:|---|---|",
                      "| exact BVH | %.3f | %s | %s |" % (e[len(e) // 2], ", ".join("%.3f" % x for x in e), raw_link(folder, exact[0]["name"])),
                      "| fields | %.3f | %s | %s |" % (f[len(f) // 2], ", ".join("%.3f" % x for x in f), raw_link(folder, field[0]["name"])), ""]
            if compare:
                lines += ["`visfield compare` of the two images (%s):" % raw_link(folder, compare[0]["name"]), "", "```",
                          re.sub(r"/tmp/[^ ]*/", "", compare[0]["stdout"]).strip(), "```", ""]
        for r in figures:
            lines += ["`%s` (its output as printed; %s):" % (re.sub(r"/tmp/[^ ]*/", "", r["command"]), raw_link(folder, r["name"])), "",
                      r["stdout"].strip(), ""]
    return lines


def page_walk(sources):
    lines = ["# Walkthrough measurements (VLF-RT Figure 6)", "",
             "Made by `scripts/results.py pages --write` from the raw files of [bench/results/](../bench/results/); do not edit.",
             "Sponza walked through in 420 frames of 256x256 with 4 point lights, every structure rendering the same frames in",
             "one process (`visfield-bench --walk`).", ""]
    for folder, machine, records in sources:
        walks = matching(records, r"walk-.*")
        if not walks:
            continue
        lines += section(folder, machine, machine_class(machine))
        for r in walks:
            lines += ["`%s` (%s):" % (re.sub(r"/tmp/[^ ]*/", "", r["command"]), raw_link(folder, r["name"])), "",
                      re.sub(r"/tmp/[^ ]*/", "", r["stdout"]).strip(), ""]
    return lines


PAGES = {
    "docs/bvh-measurements.md": page_bvh,
    "docs/beamfield-measurements.md": page_beam,
    "docs/objectfield-measurements.md": page_field,
    "docs/render-figures.md": page_render,
    "docs/walkthrough-measurements.md": page_walk,
}


def pages(mode):
    sources = []
    for folder in folders():
        machine, records = load(folder)
        sources.append((folder, machine, records))
    stale = []
    for path, make in PAGES.items():
        text = "\n".join(make(sources)).rstrip() + "\n"
        full = os.path.join(ROOT, path)
        if mode == "--write":
            open(full, "w").write(text)
        elif not os.path.exists(full) or open(full).read() != text:
            stale.append(path)
    if stale:
        fail("%s differ from what bench/results/ makes of them (scripts/results.py pages --write)" % ", ".join(stale))
    print("pages: %d measurement pages %s" % (len(PAGES), "written" if mode == "--write" else "match bench/results/"))


def main(argv):
    if len(argv) < 2:
        fail("usage: see the top of scripts/results.py")
    verb = argv[1]
    if verb == "machine" and len(argv) == 4:
        write_machine(argv[2], argv[3])
    elif verb == "run" and len(argv) >= 6 and argv[4] == "--":
        run(argv[2], argv[3], argv[5:])
    elif verb == "table":
        print(table(argv[2:] or None))
    elif verb == "readme" and len(argv) == 4 and argv[3] in ("--check", "--write"):
        readme(argv[2], argv[3])
    elif verb == "pages" and len(argv) == 3 and argv[2] in ("--check", "--write"):
        pages(argv[2])
    else:
        fail("unknown or incomplete command: %s (see the top of scripts/results.py)" % " ".join(argv[1:]))


if __name__ == "__main__":
    main(sys.argv)
