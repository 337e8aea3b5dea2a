"""Plots of visfield's figure data, drawn by matplotlib (Debian's python3-matplotlib).

The walkthrough plot (the VLF-RT paper's Figure 6) from the CSV files that `visfield walk --csv` and
`visfield-bench --walk-csv` write, as PNG, PDF or SVG (by the output's extension)::

    /usr/bin/python3 -m visfield.plot walk walk.png bvh.csv beam.csv

`visfield walk --plot walk.svg` draws the same plot as SVG without Python.
"""

import argparse
import csv
import sys


def read_walk_csv(path):
    """(label, frames, update_ms, trace_ms) of a walkthrough CSV: a "# visfield walk: LABEL" line, then
    the header frame,update_ms,trace_ms,rays,rebuilt and one row a frame. ValueError on another file."""
    with open(path, newline="") as f:
        first = f.readline().strip()
        if not first.startswith("# visfield walk: "):
            raise ValueError(f"{path}: not a visfield walk CSV (no '# visfield walk: LABEL' line)")
        rows = list(csv.DictReader(f))
    try:
        frames = [int(r["frame"]) for r in rows]
        update = [float(r["update_ms"]) for r in rows]
        trace = [float(r["trace_ms"]) for r in rows]
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"{path}: expected the columns frame,update_ms,trace_ms,rays,rebuilt ({e})") from None
    return first[len("# visfield walk: "):], frames, update, trace


def walk(csv_paths, out, title=None):
    """Draws milliseconds per frame of every CSV in `csv_paths` (solid: update + trace, dashed: the update
    where it took time) and writes `out`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(9, 5))
    for path in csv_paths:
        label, frames, update, trace = read_walk_csv(path)
        line, = axes.plot(frames, [u + t for u, t in zip(update, trace)], label=label, linewidth=1.5)
        if any(u > 0 for u in update):
            axes.plot(frames, update, linestyle="--", linewidth=1, color=line.get_color())
    axes.set_xlabel("frame")
    axes.set_ylabel("ms per frame (solid: update + trace, dashed: update)")
    axes.set_ylim(bottom=0)
    axes.grid(True, color="#e0e0e0")
    axes.legend()
    if title:
        axes.set_title(title)
    figure.tight_layout()
    figure.savefig(out)
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m visfield.plot", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="what", required=True)
    w = sub.add_parser("walk", help="frame times of walkthrough CSVs")
    w.add_argument("out", help="the plot: .png, .pdf or .svg")
    w.add_argument("csv", nargs="+", help="CSV files of visfield walk --csv or visfield-bench --walk-csv")
    w.add_argument("--title")
    args = parser.parse_args(argv)
    try:
        walk(args.csv, args.out, args.title)
    except (OSError, ValueError) as e:
        print(f"visfield.plot: error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
