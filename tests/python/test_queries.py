"""Answers from Python equal the C++ API's on the same rays, bit for bit, for every kind of structure,
whatever the memory layout of the NumPy arrays."""

import os
import threading
import time

import numpy as np
import pytest

import visfield as vf
from conftest import random_rays

SPECS = ["bvh", "kdtree", "grid", "median-bsp", "bvh:levels=2", "beam:dirs=33,n=16", "field:positions=290,directions=16"]
SCENE = "builtin:boxes:size=40,seed=3"
EXAMPLE_MESH = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples", "meshes", "tetra.obj")


def hits_as_words(hits):
    """Python hits as the C++ tool writes them: 8 32-bit words a ray."""
    words = np.zeros((len(hits.t), 8), dtype=np.uint32)
    words[:, 0] = hits.t.view(np.uint32)
    words[:, 1] = hits.prim
    words[:, 2] = hits.instance
    words[:, 3] = hits.u.view(np.uint32)
    words[:, 4] = hits.v.view(np.uint32)
    words[:, 5:8] = hits.normal.view(np.uint32)
    return words


@pytest.mark.parametrize("spec", SPECS)
def test_answers_equal_the_cpp_api(spec, cpp_answers):
    scene = vf.load(SCENE)
    structure = vf.build(scene, spec)
    rays = random_rays(scene, 20000, 7, finite_tmax=True)
    hits = structure.intersect(rays[:, 0:3], rays[:, 3:6], tmin=rays[:, 6], tmax=rays[:, 7])
    expected = cpp_answers(SCENE, spec, "intersect", rays)
    assert np.array_equal(hits_as_words(hits), expected)
    assert (hits.t < np.inf).sum() > 1000  # the rays do hit things
    occluded = structure.occluded(rays[:, 0:3], rays[:, 3:6], tmin=rays[:, 6], tmax=rays[:, 7])
    assert occluded.dtype == bool
    assert np.array_equal(occluded, cpp_answers(SCENE, spec, "occluded", rays))


def test_answers_equal_the_cpp_api_on_a_real_mesh(models_dir, cpp_answers):
    path = f"{models_dir}/bun_zipper.ply"
    scene = vf.load(path)
    rays = random_rays(scene, 20000, 3)
    for spec in ["bvh", "beam:dirs=129,n=32"]:
        hits = vf.build(scene, spec).intersect(rays[:, 0:3], rays[:, 3:6])
        assert np.array_equal(hits_as_words(hits), cpp_answers(path, spec, "intersect", rays)), spec


def test_any_layout_gives_the_same_answers():
    scene = vf.load(SCENE)
    bvh = vf.build(scene, "bvh")
    rays = random_rays(scene, 5000, 11)
    origins = np.ascontiguousarray(rays[:, 0:3])
    directions = np.ascontiguousarray(rays[:, 3:6])
    reference = bvh.intersect(origins, directions)
    # Strided views into one (N, 8) array, Fortran order, and every other row of a doubled array.
    assert np.array_equal(bvh.intersect(rays[:, 0:3], rays[:, 3:6]).t, reference.t)
    assert np.array_equal(bvh.intersect(np.asfortranarray(origins), np.asfortranarray(directions)).t, reference.t)
    doubled = np.repeat(rays, 2, axis=0)
    assert np.array_equal(bvh.intersect(doubled[::2, 0:3], doubled[::2, 3:6]).prim, reference.prim)
    # Scalars for the range, or arrays.
    limit = np.full(len(rays), 5.0, dtype=np.float32)
    assert np.array_equal(bvh.occluded(origins, directions, tmax=5.0), bvh.occluded(origins, directions, tmax=limit))
    assert np.array_equal(bvh.occluded(origins, directions, tmin=0.0, tmax=np.inf), bvh.occluded(origins, directions))


def test_misses_and_empty_batches():
    scene = vf.load(SCENE)
    bvh = vf.build(scene, "bvh")
    lo, hi = scene.bounds
    away = np.array([[0, hi[1] + 10, 0]], dtype=np.float32)
    up = np.array([[0, 1, 0]], dtype=np.float32)
    hits = bvh.intersect(away, up)
    assert hits.t[0] == np.inf and hits.prim[0] == vf.INVALID_ID and hits.instance[0] == vf.INVALID_ID
    empty = np.zeros((0, 3), dtype=np.float32)
    assert len(bvh.intersect(empty, empty).t) == 0
    assert len(bvh.occluded(empty, empty)) == 0


def test_scenes_from_arrays_and_instances():
    # A unit square floor; two objects of it, one lifted by 1 and scaled by 2.
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], dtype=np.float32)
    indices = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
    scene = vf.Scene()
    mesh = scene.add_mesh(vertices, indices)
    low = scene.add_instance(mesh)
    high = scene.add_instance(mesh, np.array([[2, 0, 0, 0], [0, 2, 0, 1], [0, 0, 2, 0]]))
    assert scene.object_count == 2 and scene.triangle_count == 4
    bvh = vf.build(scene, "bvh")
    origins = np.array([[0.5, 3, 0.5], [1.5, 3, 1.5]], dtype=np.float32)
    down = np.array([[0, -1, 0], [0, -1, 0]], dtype=np.float32)
    hits = bvh.intersect(origins, down)
    assert list(hits.instance) == [high, high]
    assert hits.t[0] == pytest.approx(2.0)
    scene.remove_instance(high)
    assert list(vf.build(scene, "bvh").intersect(origins, down).instance) == [low, vf.INVALID_ID]


def test_beamfield_updates_equal_a_fresh_build():
    scene = vf.load("builtin:boxes:size=12,seed=5")
    beam = vf.build(scene, "beam:dirs=33,n=16")
    assert beam.updatable and beam.exact
    moved = scene.objects[3]
    transform = np.array([[0, -1, 0, 0.3], [1, 0, 0, 0.1], [0, 0, 1, -0.2]])
    beam.move(moved, transform)
    beam.commit()
    scene.set_transform(moved, transform)
    rays = random_rays(scene, 10000, 5)
    fresh = vf.build(scene, "beam:dirs=33,n=16").intersect(rays[:, 0:3], rays[:, 3:6])
    got = beam.intersect(rays[:, 0:3], rays[:, 3:6])
    assert np.array_equal(got.t, fresh.t) and np.array_equal(got.instance, fresh.instance)
    beam.remove(moved)
    beam.commit()
    beam.insert(scene, moved)
    beam.commit()
    assert np.array_equal(beam.intersect(rays[:, 0:3], rays[:, 3:6]).t, fresh.t)


@pytest.mark.parametrize("spec", ["beam:dirs=33,n=16", "bvh:levels=2"])
def test_queries_racing_commits_see_the_structure_before_or_after_a_commit(spec):
    """Two threads query while the main thread moves every object back and forth and commits: each
    batch answers for a committed state (a fresh build's answers), never for one between."""
    scene = vf.load("builtin:boxes:size=8,seed=3")
    placements = {}
    for k, i in enumerate(scene.objects):
        placements[i] = np.eye(4)[:3]
        placements[i][:, 3] = (1.5 * k, 0.2 * k, 0.0)
        scene.set_transform(i, placements[i])
    placed = vf.build(scene, spec)
    rays = random_rays(scene, 3000, 9)
    shift = np.zeros((3, 4))
    shift[:, 3] = (0.25, 0.1, -0.15)
    states = []
    for offset in (np.zeros((3, 4)), shift):
        s = scene.copy()
        for i in scene.objects:
            s.set_transform(i, placements[i] + offset)
        states.append(vf.build(s, spec).intersect(rays[:, 0:3], rays[:, 3:6]).t)
    assert not np.array_equal(states[0], states[1])
    done, mixed, batches = threading.Event(), [], [0]

    def query():
        while not done.is_set():
            t = placed.intersect(rays[:, 0:3], rays[:, 3:6]).t
            if not any(np.array_equal(t, state) for state in states):
                mixed.append(t)
            batches[0] += 1

    threads = [threading.Thread(target=query) for _ in range(2)]
    for thread in threads:
        thread.start()
    try:
        for _ in range(2):
            for offset in (shift, np.zeros((3, 4))):
                seen = batches[0]
                while batches[0] < seen + 2:
                    time.sleep(0.001)
                for i in scene.objects:
                    placed.move(i, placements[i] + offset)
                placed.commit()
    finally:
        done.set()
        for thread in threads:
            thread.join()
    assert not mixed, f"{len(mixed)} of {batches[0]} batches answered for a state between commits"


def test_a_structure_closed_on_another_thread_finishes_the_queries_under_way():
    """close() while another thread's query runs without the GIL: that query finishes (the structure
    lives until it returns), and later calls raise ValueError."""
    scene = vf.load("builtin:soup:size=20000,seed=1")
    bvh = vf.build(scene, "bvh")
    rays = random_rays(scene, 400000, 3)
    results = []
    worker = threading.Thread(target=lambda: results.append(bvh.occluded(rays[:, 0:3], rays[:, 3:6])))
    worker.start()
    bvh.close()
    worker.join()
    assert len(results) == 1 and results[0].shape == (400000,)
    with pytest.raises(ValueError, match="closed"):
        bvh.occluded(rays[:, 0:3], rays[:, 3:6])


def test_fields_build_save_load_and_answer_as_the_field_structure(tmp_path):
    scene = vf.load(EXAMPLE_MESH)
    field = vf.Field.build(scene, 0, positions=290, directions=16, normals="oct16")
    assert field.positions == 290 and field.directions == 16 and field.has_normals
    path = tmp_path / "sphere.vfield"
    field.save(str(path))
    loaded = vf.Field.load(str(path), scene, 0)
    rays = random_rays(scene, 5000, 9)
    t, normal = field.intersect(rays[:, 0:3], rays[:, 3:6])
    t2, normal2 = loaded.intersect(rays[:, 0:3], rays[:, 3:6])
    assert np.array_equal(t, t2) and np.array_equal(normal, normal2)
    assert 100 < (t < np.inf).sum() < len(t)
    # The scene's fields as a structure (one identity object): the same distances.
    structure = vf.build(scene, "field:positions=290,directions=16,normals=oct16")
    assert not structure.exact
    assert np.array_equal(structure.intersect(rays[:, 0:3], rays[:, 3:6]).t, t)
    assert np.array_equal(field.occluded(rays[:, 0:3], rays[:, 3:6]), t < np.inf)
    other = vf.load("builtin:boxes:size=2,seed=1")
    with pytest.raises(vf.Error, match="another mesh"):
        vf.Field.load(str(path), other, 0)


def test_plan_weighs_every_structure_and_auto_builds_its_choice():
    scene = vf.load("builtin:sphere")  # one sphere of 20,000 triangles on a ground: fields beat the BVH per ray
    plan = vf.plan(scene, rays=1e12, kind="ao", error=255)
    assert {row["spec"] for row in plan["rows"]} >= {"bvh:levels=1", "beam", "field:positions=1090,directions=16"}
    assert plan["chosen"].startswith("field:")  # a trillion rays: the constant-time lookups
    assert "lowest predicted total" in plan["reason"]
    exact = vf.plan(scene, rays=1e12, kind="ao")
    assert not exact["chosen"].startswith("field:")
    assert all(row["excluded"] for row in exact["rows"] if row["spec"].startswith("field:"))
    built = vf.build(scene, "auto:rays=1000000000000,kind=ao,error=255")
    assert " -> field:" in built.spec and not built.exact
    with pytest.raises(ValueError, match="kind must be"):
        vf.plan(scene, rays=10, kind="diffuse")
    with pytest.raises(ValueError, match="error must be"):
        vf.plan(scene, rays=10, error=300)


def test_any_real_dtype_equals_the_float32_call_bit_for_bit():
    scene = vf.load(SCENE)
    bvh = vf.build(scene, "bvh")
    rng = np.random.default_rng(5)
    lo, hi = (np.asarray(b, dtype=np.float64) for b in scene.bounds)
    origins = lo + rng.random((4000, 3)) * (hi - lo)  # float64, NumPy's default
    directions = rng.random((4000, 3)) - 0.5
    reference = bvh.intersect(origins.astype(np.float32), directions.astype(np.float32))
    assert (reference.t < np.inf).sum() > 500
    got = bvh.intersect(origins, directions)
    assert np.array_equal(hits_as_words(got), hits_as_words(reference))
    assert np.array_equal(hits_as_words(bvh.intersect(origins.astype(np.float16), directions.astype(np.float16))),
                          hits_as_words(bvh.intersect(origins.astype(np.float16).astype(np.float32),
                                                      directions.astype(np.float16).astype(np.float32))))
    assert np.array_equal(bvh.occluded(origins, directions, tmax=np.full(4000, 2.0)),
                          bvh.occluded(origins.astype(np.float32), directions.astype(np.float32), tmax=2.0))
    # Integers and lists are real numbers too.
    assert np.array_equal(bvh.intersect(np.zeros((3, 3), dtype=np.int64), np.tile([0, 0, 1], (3, 1))).t,
                          bvh.intersect(np.zeros((3, 3), dtype=np.float32), np.tile(np.float32([0, 0, 1]), (3, 1))).t)
    assert np.array_equal(bvh.intersect([[0.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]]).t, bvh.intersect(np.zeros((1, 3)), np.float32([[0, 0, 1]])).t)


def test_whole_rays_one_ray_and_one_origin_for_many_rays():
    scene = vf.load(SCENE)
    bvh = vf.build(scene, "bvh")
    rays = random_rays(scene, 3000, 13)
    reference = bvh.intersect(rays[:, 0:3], rays[:, 3:6])
    # (N, 6): origin then direction, in one array (a strided view of the (N, 8) one too).
    assert np.array_equal(hits_as_words(bvh.intersect(np.ascontiguousarray(rays[:, 0:6]))), hits_as_words(reference))
    assert np.array_equal(hits_as_words(bvh.intersect(rays[:, 0:6])), hits_as_words(reference))
    assert np.array_equal(bvh.occluded(rays[:, 0:6]), bvh.occluded(rays[:, 0:3], rays[:, 3:6]))
    # One ray as (3,) vectors: scalars, the same as row i of the batch.
    i = int(np.flatnonzero(reference.t < np.inf)[0])
    one = bvh.intersect(rays[i, 0:3], rays[i, 3:6])
    assert np.ndim(one.t) == 0 and one.t == reference.t[i] and one.prim == reference.prim[i]
    assert one.instance == reference.instance[i] and one.u == reference.u[i] and one.v == reference.v[i]
    assert np.array_equal(one.normal, reference.normal[i]) and one.hit
    assert bool(bvh.occluded(rays[i, 0:6])) is True
    assert "t=" in repr(one) and "prim=" in repr(one)
    # One origin shared by every direction (a camera, a shading point).
    origin = rays[0, 0:3]
    shared = bvh.intersect(origin, rays[:, 3:6])
    assert np.array_equal(hits_as_words(shared), hits_as_words(bvh.intersect(np.tile(origin, (len(rays), 1)), rays[:, 3:6])))


def test_hits_is_a_named_tuple_with_a_readable_repr():
    scene = vf.load(SCENE)
    bvh = vf.build(scene, "bvh")
    rays = random_rays(scene, 1000, 17)
    hits = bvh.intersect(rays[:, 0:3], rays[:, 3:6])
    assert isinstance(hits, vf.Hits) and hits._fields == ("t", "prim", "instance", "u", "v", "normal")
    assert repr(hits) == f"Hits(1000 rays, {int(np.isfinite(hits.t).sum())} hits; fields t, prim, instance, u, v, normal)"
    assert np.array_equal(hits.hit, np.isfinite(hits.t))
    t, prim, instance, u, v, normal = hits  # unpacks as a tuple
    assert normal.shape == (1000, 3) and prim.dtype == np.uint32 and t.dtype == np.float32
