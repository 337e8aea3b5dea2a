"""The examples in examples/python run and write their figures (small sizes)."""

import os
import subprocess
import sys

import pytest

REPOSITORY = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MESH = os.path.join(REPOSITORY, "examples", "meshes", "tetra.obj")


@pytest.mark.parametrize("script, arguments", [
    ("ao_two_structures.py", ["--size", "48", "--ao-rays", "4", "--accel", "bvh", "grid"]),
    ("field_error.py", ["--size", "48", "--ao-rays", "8", "--positions", "290", "--directions", "16"]),
])
def test_example_runs(script, arguments, tmp_path):
    out = tmp_path / "figure.png"
    result = subprocess.run([sys.executable, os.path.join(REPOSITORY, "examples", "python", script), MESH, *arguments, "--out", str(out)],
                            capture_output=True, text=True, env=dict(os.environ, MPLCONFIGDIR=str(tmp_path)))
    assert result.returncode == 0, result.stderr
    assert out.stat().st_size > 1000
    assert "wrote" in result.stdout
