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


def _z_up_t(path):
    """A "T" standing on +Z, as a scan with +Z up is: a post 3 high with a wide bar on top (OBJ)."""
    lines, first = [], 1
    for lo, hi in (((-0.3, -0.3, 0.0), (0.3, 0.3, 3.0)), ((-1.5, -0.3, 3.0), (1.5, 0.3, 3.4))):
        for c in range(8):
            lines.append("v %g %g %g" % tuple(hi[k] if c >> k & 1 else lo[k] for k in range(3)))
        for f in ((0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                  (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)):
            lines.append("f %d %d %d" % tuple(first + i for i in f))
        first += 8
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def _fill(alpha):
    """The larger of the covered pixels' bounding rectangle's width and height, as fractions of the image."""
    rows, cols = np.nonzero(alpha > 0)
    h, w = alpha.shape
    return max((cols.max() - cols.min() + 1) / w, (rows.max() - rows.min() + 1) / h)


def test_view_up_and_a_transparent_background_as_the_command_line(tmp_path):
    mesh = _z_up_t(tmp_path / "t.obj")
    scene = vf.load(mesh)
    image = vf.render(scene, up="z", view=(45, 30), background="transparent", width=64, height=48, ao_rays=4)
    assert image.shape == (48, 64, 4) and image.dtype == np.float32
    alpha = image[..., 3]
    assert set(np.unique(alpha)) == {0.0, 1.0}  # one sample a pixel: covered or not
    assert 0.5 <= _fill(alpha) <= 0.95
    assert np.all(image[alpha == 0][:, :3] == 0)
    # The post stands up the image: the covered rectangle is taller than wide.
    rows, cols = np.nonzero(alpha)
    assert rows.max() - rows.min() > cols.max() - cols.min()
    # The texts the command line takes are the same values.
    assert np.array_equal(image, vf.render(scene, up="+Z", view="45,30", background="transparent", width=64, height=48, ao_rays=4))
    cli = os.environ.get("VISFIELD_CLI", "")
    if not cli:
        pytest.fail("VISFIELD_CLI does not name the visfield program (run the tests through ctest)")
    out = tmp_path / "t.png"
    subprocess.run([cli, "render", mesh, "--up", "z", "--view", "45,30", "--background", "transparent", "--ao-rays", "4",
                    "--width", "64", "--height", "48", "--out", str(out), "--no-progress"], check=True, capture_output=True)
    png = vf.read_image(str(out))
    assert png.shape == (48, 64, 4)
    assert np.array_equal(png[..., 3], alpha)
    # An RGBA image writes and reads back.
    vf.write_image(str(tmp_path / "again.png"), image)
    assert np.array_equal(vf.read_image(str(tmp_path / "again.png"))[..., 3], alpha)


def test_the_default_view_frames_the_mesh_on_a_background_apart_from_it(tmp_path):
    scene = vf.load(_z_up_t(tmp_path / "t.obj"))
    clear = vf.render(scene, background="transparent", width=48, height=48, ao_rays=4)
    assert 0.5 <= _fill(clear[..., 3]) <= 0.95
    image = vf.render(scene, width=48, height=48, ao_rays=4)
    slate = np.array([0x3A, 0x3F, 0x47]) / 255.0
    slate = np.where(slate <= 0.04045, slate / 12.92, ((slate + 0.055) / 1.055) ** 2.4)
    background = image[clear[..., 3] == 0]
    assert np.allclose(background, slate, atol=1e-6)
    # The mesh (AO of a convex-ish shape: mostly near white) stands apart from the dark background.
    assert image[clear[..., 3] == 1].mean() > background.mean() + 0.3
    white = vf.render(scene, background="white", width=48, height=48, ao_rays=4)
    assert np.all(white[clear[..., 3] == 0] == 1.0)


def test_a_camera_placement_as_numbers_or_text():
    scene = vf.load("builtin:cornell")
    placed = vf.render(scene, camera=(0, 1, 4, 0, 1, 0), width=16, height=12, ao_rays=2)
    assert np.array_equal(placed, vf.render(scene, camera="0,1,4,0,1,0,0,1,0", width=16, height=12, ao_rays=2))
    camera = scene.camera(16, 12)
    camera.position, camera.look_at, camera.up = (0, 1, 4), (0, 1, 0), (0, 1, 0)
    assert np.array_equal(placed, vf.render(scene, camera=camera, width=16, height=12, ao_rays=2))
    assert not np.array_equal(placed, vf.render(scene, camera=(0, 1, 4, 0, 1, 0, 0, 1, 0, 20), width=16, height=12, ao_rays=2))


@pytest.mark.parametrize("keywords, needle", [
    ({"up": "w"}, "up: expected"),
    ({"view": (45,)}, "view: expected"),
    ({"view": (0, 95)}, "elevation"),
    ({"camera": (1, 2, 3)}, "camera: expected"),
    ({"camera": (0, 0, 5, 0, 0, 0, 0, 0, 1)}, "parallel"),
    ({"background": "pink"}, "background: expected"),
    ({"background": (2, 0, 0)}, "background: expected"),
])
def test_bad_view_and_background_values_are_value_errors(keywords, needle):
    with pytest.raises(ValueError, match=needle):
        vf.render(vf.load("builtin:cornell"), width=8, height=8, **keywords)
