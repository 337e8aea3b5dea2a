"""Every bad argument raises a Python exception with a clear message; nothing crashes."""

import numpy as np
import pytest

import visfield as vf

ORIGINS = np.zeros((4, 3), dtype=np.float32)
DIRECTIONS = np.tile(np.array([0, 0, 1], dtype=np.float32), (4, 1))


@pytest.fixture(scope="module")
def bvh():
    return vf.build(vf.load("builtin:sphere"), "bvh")


@pytest.mark.parametrize("method", ["intersect", "occluded"])
def test_ray_arrays_are_checked(bvh, method):
    query = getattr(bvh, method)
    with pytest.raises(TypeError, match="origins: expected an array of real numbers, got an array of complex128"):
        query(ORIGINS.astype(np.complex128), DIRECTIONS)
    with pytest.raises(TypeError, match="directions: expected an array of real numbers, got an array of bool"):
        query(ORIGINS, DIRECTIONS.astype(bool))
    with pytest.raises(TypeError, match="origins: expected an array of real numbers, got an array of object"):
        query(np.array([[0, 0, None]] * 4), DIRECTIONS)
    with pytest.raises(ValueError, match=r"origins: expected shape \(N, 3\) or \(3,\), got \(4, 2\)"):
        query(ORIGINS[:, :2], DIRECTIONS)
    with pytest.raises(ValueError, match=r"directions: expected shape \(N, 3\) or \(3,\), got \(4, 3, 1\)"):
        query(ORIGINS, DIRECTIONS.reshape(4, 3, 1))
    with pytest.raises(ValueError, match=r"rays: expected shape \(N, 6\) or \(6,\), got \(4, 3\)"):
        query(ORIGINS)
    with pytest.raises(ValueError, match="4 and 3 rows"):
        query(ORIGINS, DIRECTIONS[:3])
    bad = ORIGINS.copy()
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match="ray 2 has a NaN or infinite origin"):
        query(bad, DIRECTIONS)
    bad = DIRECTIONS.copy()
    bad[1, 0] = np.inf
    with pytest.raises(ValueError, match="ray 1 has a NaN or infinite direction"):
        query(ORIGINS, bad)
    with pytest.raises(ValueError, match="tmin is NaN"):
        query(ORIGINS, DIRECTIONS, tmin=float("nan"))
    with pytest.raises(ValueError, match="tmax: expected a number or shape"):
        query(ORIGINS, DIRECTIONS, tmax=np.ones(3, dtype=np.float32))
    with pytest.raises(TypeError, match="tmax: expected a number or an array of real numbers, got str"):
        query(ORIGINS, DIRECTIONS, tmax="far")
    with pytest.raises(TypeError, match="directions: expected an array of real numbers, got str"):
        query(ORIGINS, "not an array")
    limits = np.ones(4, dtype=np.float32)
    limits[3] = np.nan
    with pytest.raises(ValueError, match="ray 3 has a NaN tmin or tmax"):
        query(ORIGINS, DIRECTIONS, tmax=limits)


def test_closed_handles_refuse_every_use():
    scene = vf.load("builtin:sphere")
    structure = vf.build(scene, "bvh")
    field = vf.Field.build(scene, 0, positions=290, directions=8)
    renderer = vf.Renderer(scene)
    structure.close()
    field.close()
    renderer.close()
    with pytest.raises(ValueError, match="this structure is closed"):
        structure.intersect(ORIGINS, DIRECTIONS)
    with pytest.raises(ValueError, match="this structure is closed"):
        _ = structure.spec
    with pytest.raises(ValueError, match="this field is closed"):
        field.occluded(ORIGINS, DIRECTIONS)
    with pytest.raises(ValueError, match="this renderer is closed"):
        renderer.render(width=8, height=8)
    with vf.load("builtin:sphere") as other:
        pass
    assert other.closed
    with pytest.raises(ValueError, match="this scene is closed"):
        vf.build(other, "bvh")
    scene.close()
    with pytest.raises(ValueError, match="this scene is closed"):
        _ = scene.triangle_count


def test_bad_scenes_specs_and_settings():
    with pytest.raises(vf.Error, match="no such file"):
        vf.load("/nonexistent/model.obj")
    scene = vf.load("builtin:sphere")
    with pytest.raises(ValueError, match="unknown structure"):
        vf.build(scene, "octree")
    with pytest.raises(ValueError, match="leaf"):
        vf.build(scene, "bvh:leaf=0")
    with pytest.raises(MemoryError, match="would need about"):
        vf.build(scene, "beam:dirs=8193,n=1024")
    with pytest.raises(ValueError, match="cannot be edited"):
        vf.build(scene, "bvh").commit()
    beam = vf.build(scene, "beam:dirs=33,n=16")
    with pytest.raises(ValueError):
        beam.remove(12345)
    with pytest.raises(ValueError, match="does not exist"):
        scene.add_instance(7)
    with pytest.raises(ValueError, match="rotation times a uniform scale"):
        scene.add_instance(0, np.array([[1, 0.5, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]))
    with pytest.raises(ValueError, match=r"\(3, 4\) or \(4, 4\)"):
        scene.add_instance(0, np.eye(3))
    with pytest.raises(ValueError, match="names vertex 5"):
        vf.Scene().add_mesh(np.zeros((3, 3)), np.array([[0, 1, 5]]))
    with pytest.raises(TypeError, match="integer array"):
        vf.Scene().add_mesh(np.zeros((3, 3)), np.array([[0.0, 1.0, 2.0]]))
    with pytest.raises(ValueError, match="NaN or infinite"):
        vf.Scene().add_mesh(np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]]), np.array([[0, 1, 2]]))
    with pytest.raises(ValueError, match="integrator"):
        vf.render(scene, integrator="photon", width=8, height=8)
    with pytest.raises(ValueError, match="ao_directions"):
        vf.render(scene, ao_directions="100", width=8, height=8)
    with pytest.raises(ValueError, match="region"):
        vf.render(scene, width=8, height=8, region=(0, 0, 9, 4))
    with pytest.raises(ValueError, match="ao_rays"):
        vf.render(scene, width=8, height=8, ao_rays=0)
    with pytest.raises(ValueError, match="occluders"):
        vf.render(scene, width=8, height=8, occluders="everything")
    with pytest.raises(ValueError, match="positions"):
        vf.Field.build(scene, 0, positions=1000)
    with pytest.raises(ValueError, match="threads"):
        vf.set_threads(-2)
    with pytest.raises(ValueError, match="images of 4x4 and 5x4 pixels"):
        vf.compare(np.zeros((4, 4, 3)), np.zeros((4, 5, 3)))


def test_render_and_field_keywords_are_the_librarys_tables():
    """render(), Renderer.render() and Field.build() take their keywords, defaults and ranges from the
    library's one declaration (vf.render_settings(), vf.structure_params("field")): every default is
    accepted as written, the docstrings list every key, an unknown keyword names the valid ones."""
    scene = vf.load("builtin:cornell")
    settings = vf.render_settings()
    assert {s["key"] for s in settings} >= {"integrator", "spp", "ao_rays", "ao_directions", "max_distance", "depth", "seed"}
    defaults = {s["key"]: s["default"] for s in settings}
    typed = {k: (float(v) if k in ("max_distance", "ambient") else int(v) if v.isdigit() else v) for k, v in defaults.items()}
    with_defaults = vf.render(scene, width=8, height=8, **typed)
    assert np.array_equal(with_defaults, vf.render(scene, width=8, height=8))
    for s in settings:
        assert s["key"] + "=" + s["default"] in vf.render.__doc__, s["key"]
        assert s["key"] + "=" + s["default"] in vf.Renderer.render.__doc__, s["key"]
    with pytest.raises(TypeError, match="valid: .*ao_rays"):
        vf.render(scene, width=8, height=8, colour="red")
    field_params = [p for p in vf.structure_params("field") if p["key"] not in ("cache", "meshes", "cull")]
    assert {p["key"] for p in field_params} >= {"positions", "directions", "mapping", "storage", "normals", "through"}
    for p in field_params:
        assert p["key"] + "=" + p["default"] in vf.Field.build.__doc__, p["key"]
    field = vf.Field.build(scene, 0, **{p["key"]: p["default"] for p in field_params if p["key"] != "positions"}, positions=290)
    assert field.directions == int(next(p["default"] for p in field_params if p["key"] == "directions"))
    with pytest.raises(TypeError, match="valid: .*positions"):
        vf.Field.build(scene, 0, resolution=3)
    with pytest.raises(ValueError, match="directions=4"):
        vf.Field.build(scene, 0, positions=290, directions=4)
