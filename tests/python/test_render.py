"""render() draws what `visfield render` draws; regions, threads and the GIL."""

import os
import subprocess
import threading
import time

import numpy as np
import pytest

import visfield as vf


def test_render_equals_the_command_line(tmp_path):
    cli = os.environ.get("VISFIELD_CLI", "")
    if not cli:
        pytest.fail("VISFIELD_CLI does not name the visfield program (run the tests through ctest)")
    out = tmp_path / "cli.exr"
    subprocess.run([cli, "render", "builtin:cornell", "--integrator", "softshadow", "--shadow-rays", "3", "--spp", "2",
                    "--width", "40", "--height", "30", "--out", str(out), "--no-progress"], check=True, capture_output=True)
    image = vf.render(vf.load("builtin:cornell"), integrator="softshadow", shadow_rays=3, spp=2, width=40, height=30)
    assert image.shape == (30, 40, 3) and image.dtype == np.float32
    assert np.array_equal(image, vf.read_image(str(out)))


@pytest.mark.parametrize("integrator", ["raycast", "whitted", "ao", "softshadow", "glossy", "path"])
def test_a_region_is_the_same_pixels_of_the_whole_image(integrator):
    scene = vf.load("builtin:cornell")
    renderer = vf.Renderer(scene)
    whole = renderer.render(integrator=integrator, width=32, height=24, spp=2, ao_rays=4)
    part = renderer.render(integrator=integrator, width=32, height=24, spp=2, ao_rays=4, region=(3, 5, 20, 17))
    assert np.array_equal(part, whole[5:17, 3:20])


def test_images_do_not_depend_on_the_thread_count():
    scene = vf.load("builtin:cornell")
    try:
        vf.set_threads(1)
        assert vf.threads() == 1
        one = vf.render(scene, integrator="path", width=24, height=24, spp=2)
        vf.set_threads(2)
        two = vf.render(scene, integrator="path", width=24, height=24, spp=2)
    finally:
        vf.set_threads(0)
    assert np.array_equal(one, two)


def test_fields_and_compare():
    scene = vf.load("builtin:boxes:size=6,seed=2")
    exact = vf.render(scene, width=48, height=32, ao_rays=16)
    fields = vf.render(scene, width=48, height=32, ao_rays=16, occluders="field")
    same = vf.compare(exact, exact)
    assert same["rms"] == 0 and same["psnr_db"] == np.inf
    diff = vf.compare(fields, exact)
    assert 0 < diff["rms"] < 0.1 and diff["rms_255"] == pytest.approx(255 * diff["rms"])


def test_the_gil_is_released_while_visfield_works():
    # A Python thread keeps counting while another builds and queries: with the GIL held it could not.
    scene = vf.load("builtin:soup:size=20000,seed=1")
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    started = time.perf_counter()
    try:
        vf.build(scene, "beam:dirs=129,n=64")
    finally:
        finished = time.perf_counter()
        done.set()
        counter.join()
    during = [t for t in ticks if started < t < finished]
    assert finished - started > 0.05
    assert len(during) > 10, f"only {len(during)} ticks during a {finished - started:.2f} s build"


def test_write_and_read_images(tmp_path):
    image = np.random.default_rng(1).random((10, 12, 3)).astype(np.float32)
    vf.write_image(str(tmp_path / "a.exr"), image)
    assert np.array_equal(vf.read_image(str(tmp_path / "a.exr")), image)
    vf.write_image(str(tmp_path / "a.png"), image)
    assert vf.compare(vf.read_image(str(tmp_path / "a.png")), image)["max_255"] < 2.0  # 8-bit sRGB steps, in linear values
