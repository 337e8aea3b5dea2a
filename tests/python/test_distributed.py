"""visfield.distributed on a LocalCluster of 2 worker processes: the same images and fields as one
machine, in order; failed tasks retried and reported; scenes loaded once per worker."""

import logging
import os
import shutil
import warnings

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

import visfield as vf  # noqa: E402
import visfield.distributed as vfd  # noqa: E402

REPOSITORY = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WALK = os.path.join(REPOSITORY, "examples", "scenes", "walk.json")
EXAMPLE = os.path.join(REPOSITORY, "examples", "scenes", "example.json")


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    # A folder of its own for the workers' files: no stale lock of another run in the shared default.
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                       local_directory=str(tmp_path_factory.mktemp("dask")), silence_logs=logging.ERROR)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_tiles_of_one_image_equal_the_single_machine_render(client):
    settings = dict(integrator="ao", ao_rays=8, spp=2, seed=3)
    image = vfd.render_tiles(client, EXAMPLE, tile=24, width=100, height=70, **settings)
    reference = vf.render(vf.load(EXAMPLE), width=100, height=70, **settings)
    assert image.shape == (70, 100, 3)
    assert np.array_equal(image, reference)


def test_walkthrough_frames_come_back_in_order_equal_to_one_machine(client):
    frames = vfd.render_frames(client, WALK, 6, integrator="raycast", width=48, height=32)
    scene = vf.load(WALK)
    assert len(frames) == 6
    for f, image in enumerate(frames):
        placed, camera = scene.frame(f, 6, 48, 32)
        assert np.array_equal(image, vf.render(placed, integrator="raycast", camera=camera)), f"frame {f}"
    assert not np.array_equal(frames[0], frames[5])  # things move


def test_fields_of_a_folder(client, tmp_path):
    meshes = tmp_path / "meshes"
    meshes.mkdir()
    for name in ["tetra.obj", "ground.obj"]:
        shutil.copy(os.path.join(REPOSITORY, "examples", "meshes", name), meshes / name)
    (meshes / "notes.txt").write_text("not a mesh")
    written = ["ground.obj", "tetra.obj"]
    paths = vfd.build_fields(client, str(meshes), str(tmp_path / "fields"), positions=290, directions=16)
    assert [os.path.basename(p) for p in paths] == [os.path.splitext(n)[0] + ".vfield" for n in written]
    for name, path in zip(written, paths):
        scene = vf.load(str(meshes / name))
        local = vf.Field.build(scene, 0, positions=290, directions=16)
        remote = vf.Field.load(path, scene, 0)
        rng = np.random.default_rng(4)
        o = (rng.random((2000, 3)) * 4 - 2).astype(np.float32)
        d = rng.normal(size=(2000, 3)).astype(np.float32)
        assert np.array_equal(local.intersect(o, d)[0], remote.intersect(o, d)[0])


def inject_faults(client, folder, *names):
    """Makes the next try of each named task (KIND-INDEX) fail once, on whichever worker runs it."""
    for name in names:
        (folder / name).write_text("")
    client.run(setattr, vfd, "_fault_folder", str(folder))


def test_a_failed_task_is_retried_and_reported(client, tmp_path):
    inject_faults(client, tmp_path, "tile-1", "tile-3")
    failures = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        image = vfd.render_tiles(client, EXAMPLE, tile=32, width=64, height=64, ao_rays=4, failures=failures)
    client.run(setattr, vfd, "_fault_folder", None)
    assert np.array_equal(image, vf.render(vf.load(EXAMPLE), width=64, height=64, ao_rays=4))
    assert sorted(f.index for f in failures) == [1, 3]
    assert all("injected failure" in f.error and f.attempt == 1 for f in failures)
    assert sum(issubclass(w.category, vfd.RetryWarning) for w in caught) == 2


def test_a_task_that_fails_on_its_last_try_raises(client, tmp_path):
    inject_faults(client, tmp_path, "frame-2")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with pytest.raises(vfd.TaskError, match="frame 2 failed on all 1 tries"):
                vfd.render_frames(client, WALK, 4, integrator="raycast", width=16, height=16, retries=0)
    finally:
        client.run(setattr, vfd, "_fault_folder", None)


def test_scenes_are_loaded_once_per_worker(client):
    client.run(lambda: vfd._cache.clear())
    vfd.render_tiles(client, EXAMPLE, tile=16, width=64, height=64, ao_rays=2)
    loaded = client.run(lambda: sum(1 for key in vfd._cache if key[0] == "scene"))
    renderers = client.run(lambda: sum(1 for key in vfd._cache if key[0] == "renderer"))
    # 16 tiles over 2 workers, but each worker loaded the scene and built its structures at most once.
    assert all(n <= 1 for n in loaded.values()) and sum(loaded.values()) >= 1
    assert all(n <= 1 for n in renderers.values())
