"""visfield over a Dask cluster (dask.distributed): the frames of a walkthrough, the tiles of one
large image, and the ObjectFields of a folder of meshes, spread over the workers.

    from dask.distributed import Client
    import visfield.distributed as vfd

    client = Client("tcp://scheduler:8786")          # or Client(LocalCluster(n_workers=2))
    image = vfd.render_tiles(client, "scene.json", width=4096, height=4096, ao_rays=256)
    frames = vfd.render_frames(client, "walk.json", frames=420, integrator="whitted")
    paths = vfd.build_fields(client, "meshes/", "fields/", positions=4226, directions=32)

How it works:
- Tasks carry a scene's path, the settings and their piece of work, never a pickled scene. Each
  worker loads a scene once and keeps it, with the structures built over it, for every later task
  on the same scene and structures (a cache in the worker process). Every worker must see the
  same file at the same path: a shared folder, or the same copy on every machine.
- Results come back in the order of the work (tile by tile, frame by frame, mesh by mesh).
- A task that fails is submitted again, up to `retries` times; each failure is reported as a
  RetryWarning (and logged to the "visfield.distributed" logger) and appended to `failures` when
  the caller passes a list. A task that fails on its last try raises TaskError.
- The output equals a single-machine run bit for bit: a pixel depends only on (seed, pixel,
  sample), never on the tile it was rendered in or the worker that rendered it.
"""

import logging
import os
import threading
import uuid
import warnings
from dataclasses import dataclass

import numpy as np

import visfield

__all__ = ["RetryWarning", "TaskError", "TaskFailure", "build_fields", "render_frames", "render_tiles"]

_log = logging.getLogger("visfield.distributed")

MESH_EXTENSIONS = (".obj", ".ply", ".stl", ".gltf", ".glb")


class RetryWarning(UserWarning):
    """A task failed and was submitted again."""


class TaskError(RuntimeError):
    """A task failed on every try."""


@dataclass
class TaskFailure:
    """One failed try of one task: which piece of work, which try (1 = the first), and the error."""

    what: str
    index: int
    attempt: int
    error: str


# ----- Worker side: what each worker process keeps between tasks -----

_cache = {}
_cache_lock = threading.RLock()  # re-entrant: a renderer is made while its scene is fetched
# Injected failures for the tests: a folder (set on every worker with client.run(); None in normal
# use) where a file named KIND-INDEX makes the next try of that task raise, on whichever worker
# removes the file first: once across the cluster.
_fault_folder = None


def _cached(key, make):
    with _cache_lock:
        if key not in _cache:
            _cache[key] = make()
        return _cache[key]


def _scene_key(path):
    return (os.path.abspath(path), os.path.getmtime(path) if os.path.exists(path) else 0.0)


def _scene(path):
    return _cached(("scene",) + _scene_key(path), lambda: visfield.load(path))


def _renderer(path, structures):
    key = ("renderer",) + _scene_key(path) + tuple(sorted(structures.items()))
    return _cached(key, lambda: visfield.Renderer(_scene(path), **structures))


def _maybe_fail(kind, index):
    if _fault_folder is None:
        return
    try:
        os.remove(os.path.join(_fault_folder, f"{kind}-{index}"))
    except FileNotFoundError:
        return
    raise RuntimeError(f"injected failure of {kind} {index}")


def _render_tile(path, structures, settings, index, region):
    _maybe_fail("tile", index)
    return _renderer(path, structures).render(region=region, **settings)


def _render_frame(path, structures, settings, frame, frames, width, height):
    _maybe_fail("frame", frame)
    scene = _scene(path)
    placed, camera = scene.frame(frame, frames, width, height)
    if scene.objects_move:
        # The objects stand elsewhere in every frame: structures over this frame's placements.
        return visfield.Renderer(placed, **structures).render(camera=camera, **settings)
    return _renderer(path, structures).render(camera=camera, **settings)


def _build_field(mesh_path, out_path, index, params):
    _maybe_fail("field", index)
    scene = visfield.load(mesh_path)
    field = visfield.Field.build(scene, 0, **params)
    field.save(out_path)
    return out_path


# ----- Client side -----


def _run(client, what, function, tasks, retries, failures):
    """Submits function(*task) for every task; the results in task order, failures retried."""
    if retries < 0:
        raise ValueError(f"retries: expected 0 or more, got {retries}")
    from dask.distributed import as_completed

    batch = uuid.uuid4().hex[:8]
    pending = {}
    for i, task in enumerate(tasks):
        future = client.submit(function, *task, key=f"visfield-{what}-{batch}-{i}-0", pure=False)
        pending[future] = (i, 1)
    results = [None] * len(tasks)
    completed = as_completed(list(pending))
    for future in completed:
        index, attempt = pending.pop(future)
        if future.status != "error":
            results[index] = future.result()
            continue
        error = future.exception()
        failure = TaskFailure(what, index, attempt, f"{type(error).__name__}: {error}")
        if failures is not None:
            failures.append(failure)
        if attempt > retries:
            for other in pending:
                other.cancel()
            raise TaskError(f"{what} {index} failed on all {attempt} tries; the last: {failure.error}") from error
        message = f"{what} {index} failed on try {attempt} ({failure.error}); submitting it again"
        _log.warning(message)
        warnings.warn(message, RetryWarning, stacklevel=3)
        again = client.submit(function, *tasks[index], key=f"visfield-{what}-{batch}-{index}-{attempt}", pure=False)
        pending[again] = (index, attempt + 1)
        completed.add(again)
    return results


def _structures(accel, occluder, occluders):
    return {"accel": accel, "occluder": occluder, "occluders": occluders}


def render_tiles(client, scene, *, tile=128, accel="bvh", occluder=None, occluders=None, width=0, height=0, retries=2, failures=None,
                 **settings):
    """Renders one image of `scene` (a path every worker can read) in tiles of `tile` x `tile`
    pixels spread over the cluster, and assembles them: an array (height, width, 3) float32 (4 with
    background="transparent") equal
    to visfield.render(visfield.load(scene), ...) with the same settings. `settings` are
    visfield.render's (integrator, spp, ao_rays, seed, ...)."""
    if tile < 1:
        raise ValueError(f"tile: expected a positive size, got {tile}")
    camera = visfield.load(scene).camera(width, height)
    w, h = camera.width, camera.height
    regions = [(x, y, min(x + tile, w), min(y + tile, h)) for y in range(0, h, tile) for x in range(0, w, tile)]
    settings = dict(settings, width=w, height=h)
    structures = _structures(accel, occluder, occluders)
    tasks = [(os.path.abspath(scene), structures, settings, i, region) for i, region in enumerate(regions)]
    parts = _run(client, "tile", _render_tile, tasks, retries, failures)
    image = np.zeros((h, w, parts[0].shape[2]), dtype=np.float32)  # 4 channels with background="transparent"
    for (x0, y0, x1, y1), part in zip(regions, parts):
        image[y0:y1, x0:x1] = part
    return image


def render_frames(client, scene, frames, *, accel="bvh", occluder=None, occluders=None, width=256, height=256, retries=2, failures=None,
                  **settings):
    """Renders frames 0 .. frames-1 of the walkthrough of `scene` (a path every worker can read;
    the scene has a "camera_path" or object "keyframes") over the cluster: a list of arrays
    (height, width, 3), in frame order, each equal to that frame rendered on one machine. A
    camera-only walk reuses each worker's structures; objects that move get structures per frame.
    `settings` are visfield.render's (integrator, spp, ...)."""
    if frames < 2:
        raise ValueError(f"frames: expected at least 2, got {frames}")
    source = visfield.load(scene)
    if not source.moves:
        raise ValueError(f"{scene}: the scene has no camera_path and no object keyframes; nothing to walk through")
    structures = _structures(accel, occluder, occluders)
    tasks = [(os.path.abspath(scene), structures, settings, f, frames, width, height) for f in range(frames)]
    return _run(client, "frame", _render_frame, tasks, retries, failures)


def build_fields(client, folder, out_folder, *, retries=2, failures=None, **params):
    """Precomputes the ObjectField of every mesh file in `folder` (.obj, .ply, .stl, .gltf, .glb;
    every worker must read it) into `out_folder` as NAME.vfield, over the cluster. `params` are
    visfield.Field.build's (positions, directions, mapping, storage, normals). Returns the written
    paths in the order of the sorted mesh names."""
    meshes = sorted(name for name in os.listdir(folder) if name.lower().endswith(MESH_EXTENSIONS))
    if not meshes:
        raise ValueError(f"{folder}: no mesh files ({', '.join(MESH_EXTENSIONS)})")
    os.makedirs(out_folder, exist_ok=True)
    tasks = []
    for i, name in enumerate(meshes):
        stem = os.path.splitext(name)[0]
        tasks.append((os.path.abspath(os.path.join(folder, name)), os.path.abspath(os.path.join(out_folder, stem + ".vfield")), i, params))
    return _run(client, "field", _build_field, tasks, retries, failures)
