"""visfield from Python: fast ray-scene visibility queries on NumPy arrays.

Scenes come from mesh files, scene .json files, built-in scenes or NumPy arrays; any structure of
visfield's registry is built by its spec ("bvh", "kdtree:kt=10", "beam:dirs=513", "field:...");
queries take arrays of real numbers (float32 read in place, other dtypes converted once) and release
the GIL while they run::

    import numpy as np
    import visfield as vf

    scene = vf.load("bunny.ply")
    bvh = vf.build(scene, "bvh")
    hits = bvh.intersect(np.random.rand(1000, 3), np.random.rand(1000, 3) - 0.5)   # visfield.Hits
    blocked = bvh.occluded(rays_n_by_6, tmax=1.0)      # origin and direction in one (N, 6) array
    image = vf.render(scene, integrator="ao", ao_rays=64, width=256, height=256)

Fields (ObjectField), BeamField updates, renders with every integrator, image comparison, and
renders or field builds spread over a Dask cluster (visfield.distributed) are here too.
"""

from os import PathLike
from typing import Union

from . import _visfield
from ._visfield import (  # noqa: F401  (the public API)
    INVALID_ID,
    Camera,
    Error,
    Field,
    Renderer,
    Scene,
    Structure,
    __version__,
    build,
    compare,
    plan,
    read_image,
    render,
    render_settings,
    structure_params,
    structures,
    threads,
    write_image,
)
from .hits import FieldHits, Hits


def set_threads(threads: int) -> None:
    """Worker threads for every build, query and render from now on (0 = all hardware threads).

    A Python function (not the extension's own) so that it pickles by name: client.run(visfield.set_threads, 1)
    sets it on every Dask worker."""
    _visfield.set_threads(threads)


def load(path: Union[str, "PathLike[str]"]) -> Scene:
    """A scene from a mesh file, a scene .json file, or "builtin:NAME[:key=value,...]" (Scene.load)."""
    return Scene.load(str(path))


__all__ = [
    "INVALID_ID",
    "Camera",
    "Error",
    "Field",
    "FieldHits",
    "Hits",
    "Renderer",
    "Scene",
    "Structure",
    "__version__",
    "build",
    "compare",
    "load",
    "plan",
    "read_image",
    "render",
    "render_settings",
    "set_threads",
    "structure_params",
    "structures",
    "threads",
    "write_image",
]
