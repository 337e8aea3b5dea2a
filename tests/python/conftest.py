"""Shared fixtures of the Python tests: where the shared models and the C++ reference tool are."""

import os
import subprocess

import numpy as np
import pytest

import visfield as vf


@pytest.fixture(scope="session")
def models_dir():
    """The shared test meshes (skip when absent: a clone of the repository alone has none; fail
    instead under VISFIELD_REQUIRE_MODELS=1, as in CI, where they are there)."""
    path = os.environ.get("VISFIELD_MODELS_DIR", "")
    if not path or not os.path.isdir(path):
        if os.environ.get("VISFIELD_REQUIRE_MODELS") == "1":
            pytest.fail(f"shared models not in '{path}' (VISFIELD_REQUIRE_MODELS=1)")
        pytest.skip("shared models not present")
    return path


@pytest.fixture(scope="session")
def cpp_answers(tmp_path_factory):
    """answers(scene, spec, query, rays (N, 8) float32) -> the C++ API's answers (tests/python/api_answers.cpp)."""
    tool = os.environ.get("VISFIELD_API_ANSWERS", "")
    if not tool or not os.path.exists(tool):
        pytest.fail("VISFIELD_API_ANSWERS does not name the api_answers tool (run the tests through ctest)")
    folder = tmp_path_factory.mktemp("answers")

    def answers(scene, spec, query, rays):
        rays_path, out_path = folder / "rays.bin", folder / "out.bin"
        np.ascontiguousarray(rays, dtype=np.float32).tofile(rays_path)
        subprocess.run([tool, scene, spec, query, str(rays_path), str(out_path)], check=True)
        raw = np.fromfile(out_path, dtype=np.uint8)
        if query == "occluded":
            return raw.astype(bool)
        return raw.view(np.uint32).reshape(-1, 8)

    return answers


def random_rays(scene, n, seed, finite_tmax=False):
    """(N, 8) float32 rays around the scene's bounds: origin, direction, tmin, tmax."""
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    extent = hi - lo
    rays = np.zeros((n, 8), dtype=np.float32)
    rays[:, 0:3] = lo - 0.25 * extent + 1.5 * extent * rng.random((n, 3))
    rays[:, 3:6] = rng.normal(size=(n, 3))
    rays[:, 6] = 0.0
    rays[:, 7] = np.inf
    if finite_tmax:
        rays[1::2, 7] = 0.3 * float(extent.max())
    return rays
