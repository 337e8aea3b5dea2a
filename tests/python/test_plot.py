"""visfield.plot: the walkthrough plot drawn by matplotlib from the CSVs visfield writes."""

import subprocess
import sys

import pytest

import visfield.plot as vfp

CSV = "# visfield walk: {label}\nframe,update_ms,trace_ms,rays,rebuilt\n0,{u},10.5,100,0\n1,{u},11.0,100,0\n2,{u},9.8,100,0\n"


def test_walk_plot_from_csv_files(tmp_path):
    for label, update in (("bvh", 0.0), ("beam", 1.5)):
        (tmp_path / f"{label}.csv").write_text(CSV.format(label=label, u=update))
    label, frames, update, trace = vfp.read_walk_csv(tmp_path / "beam.csv")
    assert (label, frames, update, trace) == ("beam", [0, 1, 2], [1.5, 1.5, 1.5], [10.5, 11.0, 9.8])
    out = tmp_path / "walk.png"
    vfp.walk([tmp_path / "bvh.csv", tmp_path / "beam.csv"], out, title="test")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # The module's command line, as the refusal of `visfield walk --plot walk.png` names it.
    svg = tmp_path / "walk.svg"
    subprocess.run([sys.executable, "-m", "visfield.plot", "walk", str(svg), str(tmp_path / "bvh.csv")], check=True)
    assert b"<svg" in svg.read_bytes()[:400]


def test_walk_plot_refuses_other_files(tmp_path):
    (tmp_path / "other.csv").write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="not a visfield walk CSV"):
        vfp.read_walk_csv(tmp_path / "other.csv")
    assert vfp.main(["walk", str(tmp_path / "x.png"), str(tmp_path / "other.csv")]) == 1
