"""Property tests (hypothesis) of every public call: random arrays, dtypes, shapes, layouts, specs and
option values, drawn around and outside the ranges the library's own tables report. Each call answers
with a clean exception (TypeError, ValueError, MemoryError; visfield.Error only for a missing file or a
refused build) or with answers equal to brute force bit for bit (exact structures), or of the promised
shape and dtype (fields, images). Derandomized: every run draws the same 2,000 examples a property.
Bugs found this way stay out of the properties, pinned by their smallest reproducers as strict xfails."""

import math
import os
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import visfield as vf

PROPERTY = settings(max_examples=2000, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
INVALID_ID = np.uint32(vf.INVALID_ID)

# NumPy warns when the library converts 1e39 to float32 or complex to float: expected here.
pytestmark = [pytest.mark.filterwarnings("ignore::RuntimeWarning"), pytest.mark.filterwarnings("ignore::numpy.ComplexWarning")]


# ---------------------------------------------------------------- scenes

CUBE_VERTICES = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.float64)
CUBE_TRIANGLES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                           [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
TETRA_VERTICES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
TETRA_TRIANGLES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
GROUND_VERTICES = np.array([[-10, -1, -10], [10, -1, -10], [10, -1, 10], [-10, -1, 10]], dtype=np.float64)
GROUND_TRIANGLES = np.array([[0, 1, 2], [0, 2, 3]])
# A zero-area triangle beside a sliver one.
SLIVER_VERTICES = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1e-6, 0]], dtype=np.float64)
SLIVER_TRIANGLES = np.array([[0, 1, 2], [0, 2, 3]])


def rigid(angle=0.0, axis=(0, 0, 1), scale=1.0, translation=(0, 0, 0)):
    """The (3, 4) matrix [scale * R | t] of a rotation by `angle` radians about `axis`."""
    x, y, z = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    c, s = math.cos(angle), math.sin(angle)
    r = np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                  [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                  [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])
    return np.hstack([scale * r, np.reshape(translation, (3, 1))])


def make_query_scene():
    """Meshes placed so that rays meet shared edges, coplanar faces of two objects, a scaled and
    rotated copy, a zero-area triangle and a ground; returns (scene, interesting world points)."""
    scene = vf.Scene()
    cube = scene.add_mesh(CUBE_VERTICES, CUBE_TRIANGLES)
    tetra = scene.add_mesh(TETRA_VERTICES, TETRA_TRIANGLES)
    ground = scene.add_mesh(GROUND_VERTICES, GROUND_TRIANGLES)
    sliver = scene.add_mesh(SLIVER_VERTICES, SLIVER_TRIANGLES)
    placements = [(cube, rigid()), (cube, rigid(translation=(1, 0, 0))), (cube, rigid(math.pi / 2, (0, 1, 0), 2.0, (-3, 0.5, 1))),
                  (tetra, rigid()), (tetra, rigid(math.pi / 4, (0, 0, 1), 0.5, (0, 2, 0))), (ground, rigid()),
                  (sliver, rigid(0.3, (1, 1, 0), 1.5, (0, 1.5, 0.5)))]
    vertices = {cube: CUBE_VERTICES, tetra: TETRA_VERTICES, ground: GROUND_VERTICES, sliver: SLIVER_VERTICES}
    points = []
    for mesh, matrix in placements:
        scene.add_instance(mesh, matrix)
        world = vertices[mesh] @ matrix[:, :3].T + matrix[:, 3]
        points.extend(world)
        points.extend((world[:-1] + world[1:]) / 2)  # points on edges (and inside faces)
    return scene, np.array(points)


QUERY_SCENE, QUERY_POINTS = make_query_scene()
FLAT_SPECS = ["bvh:levels=1", "grid:levels=1", "kdtree:levels=1", "median-bsp:levels=1", "beam", "beam:dirs=33,n=16,stream=0"]
TWO_LEVEL_SPECS = ["bvh:levels=2", "grid:levels=2", "kdtree:levels=2", "median-bsp:levels=2"]
STRUCTURES = {spec: vf.build(QUERY_SCENE, spec) for spec in FLAT_SPECS + TWO_LEVEL_SPECS}
BRUTE = {1: vf.build(QUERY_SCENE, "brute:levels=1"), 2: vf.build(QUERY_SCENE, "brute:levels=2")}
FIELD = vf.Field.build(QUERY_SCENE, 0, positions=290, directions=8, normals="oct16")
FIELD_TARGETS = np.vstack([CUBE_VERTICES, (CUBE_VERTICES[:-1] + CUBE_VERTICES[1:]) / 2, np.random.default_rng(0).random((16, 3))])


def levels_of(spec):
    """The brute-force oracle a resolved spec answers as: 2 for two-level structures, else 1."""
    return 2 if "levels=2" in spec.split("->")[-1] else 1


def fixed_rays(scene, n, seed):
    """(origins, directions) float32: rays from around the scene's bounds towards points inside them."""
    rng = np.random.default_rng(seed)
    lo, hi = (np.asarray(b, dtype=np.float64) for b in scene.bounds)
    extent = np.maximum(hi - lo, 1e-3)
    origins = lo - 0.5 * extent + 2.0 * extent * rng.random((n, 3))
    targets = lo + extent * rng.random((n, 3))
    return origins.astype(np.float32), (targets - origins).astype(np.float32)


def same_bits(a, b):
    """Equal shapes, dtypes and bytes (NaN equals NaN of the same bits; -0 differs from 0)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


HIT_FIELDS = ("t", "prim", "instance", "u", "v", "normal")


def assert_same_hits(got, expected, label, rays=slice(None)):
    """Hits equal bit for bit in every field, for the rays `rays` selects (of answers given per ray, or of one ray's)."""
    for field in HIT_FIELDS:
        a, b = np.asarray(getattr(got, field)), np.asarray(getattr(expected, field))
        assert a.shape == b.shape, (label, field, a.shape, b.shape)
        if a.ndim == 0 or (field == "normal" and a.ndim == 1):  # one ray's answer: all of it
            assert same_bits(a, b), (label, field, a, b)
        else:
            assert same_bits(a[rays], b[rays]), (label, field, a[rays], b[rays])


# ---------------------------------------------------------------- ray arguments

def rarely(draw, n):
    """True about once in n draws (hypothesis draws small integers far more often than large ones)."""
    return draw(st.integers(0, n)) == n


SAFE_FLOATS = [0.0, -0.0, 0.5, 1.0, -1.0, 2.0, 3.0, 10.0, 1e-45, -1e-45, 1e-40, 5e-324, 1e-30, 1e30, -1e30, 3.4e38]
POISON = [math.nan, math.inf, -math.inf, 1e39, -1e300]  # NaN or infinite once float32
REAL_DTYPES = [np.float32, np.float64, np.float16, np.int8, np.int32, np.int64, np.uint8]
FLOAT_DTYPES = [np.float32, np.float64, np.float16]
OTHER_DTYPES = [np.bool_, np.complex64, np.complex128, object, str]
LAYOUTS = ["contiguous", "fortran", "strided", "reversed", "unaligned", "readonly", "list"]
POINT_COORDINATES = np.array(sorted(set(QUERY_POINTS.ravel().tolist())))


@st.composite
def real_values(draw, shape, poison=20):
    """A float64 array of `shape`: values near the scene (its vertices' coordinates among them) and the
    special ones of SAFE_FLOATS, about once in `poison` arrays one that is NaN or infinite in float32.
    The values come from a NumPy generator seeded by hypothesis (drawing each through hypothesis costs
    ten times as much)."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    size = int(np.prod(shape))
    pools = [rng.uniform(-12, 12, size), rng.uniform(-3, 3, size), rng.choice(POINT_COORDINATES, size), rng.choice(SAFE_FLOATS, size)]
    values = np.choose(rng.choice(4, size, p=[0.3, 0.25, 0.3, 0.15]), pools).reshape(shape)
    if size and rarely(draw, poison):
        values.flat[draw(st.integers(0, size - 1))] = draw(st.sampled_from(POISON))
    return values


@st.composite
def as_argument(draw, values, real_only=False):
    """`values` in a random dtype (mostly floating, often integer, rarely not real) and memory layout, or as nested lists."""
    if not real_only and rarely(draw, 20):
        dtype = draw(st.sampled_from(OTHER_DTYPES))
    else:
        dtype = draw(st.sampled_from(REAL_DTYPES if draw(st.booleans()) else FLOAT_DTYPES))
    with np.errstate(all="ignore"):
        if np.dtype(dtype).kind in "iu":
            info = np.iinfo(dtype)
            array = np.clip(np.nan_to_num(np.round(values)), info.min, info.max).astype(dtype)
        else:
            array = values.astype(dtype)
    layout = draw(st.sampled_from(LAYOUTS))
    if layout == "fortran":
        return np.asfortranarray(array)
    if layout == "strided" and array.ndim >= 1:
        return np.repeat(array, 2, axis=0)[::2]
    if layout == "reversed" and array.ndim >= 1:
        return np.ascontiguousarray(array[::-1])[::-1]
    if layout == "unaligned" and array.dtype.kind in "fiu" and array.dtype.itemsize > 1:
        buffer = np.zeros(array.nbytes + 1, dtype=np.uint8)
        view = buffer[1:].view(array.dtype).reshape(array.shape)
        view[...] = array
        return view
    if layout == "readonly":
        array.setflags(write=False)
    if layout == "list":
        return array.tolist()
    return array


@st.composite
def direction_values(draw, origins, shape, targets):
    """Directions of `shape`: random, or towards `targets` (vertices, points on edges) from `origins`, scaled."""
    if draw(st.integers(0, 2)) == 0 or origins.shape != shape or len(shape) != 2:
        return draw(real_values(shape))
    targets = targets[np.random.default_rng(draw(st.integers(0, 2**32 - 1))).integers(0, len(targets), shape[0])].reshape(shape)
    directions = (targets - origins) * draw(st.sampled_from([1.0, 1.0, 1e-3, 1e3, 1e-38, 1e20]))
    if shape[0] and rarely(draw, 6):
        directions[draw(st.integers(0, shape[0] - 1))] = 0.0  # a zero direction: a valid ray that hits nothing
    return directions


RANGE_NUMBERS = [0.0, -0.0, -1.0, 0.5, 1.0, 5.0, 1e-45, 1e30, 1e300, math.inf, -math.inf, 3, -2]


@st.composite
def range_arguments(draw, n):
    """tmin or tmax: left out, a number, a NumPy scalar, an array (N,) (reversed intervals too) or something wrong."""
    kind = draw(st.sampled_from(["default"] * 12 + ["number"] * 6 + ["numpy"] * 3 + ["array"] * 6 + ["wrong length", "2-d", "bad type"]))
    numbers = st.one_of(st.sampled_from(RANGE_NUMBERS + [math.nan]), st.floats(-20, 20))
    if kind == "default":
        return None
    if kind == "number":
        return draw(numbers)
    if kind == "numpy":
        dtype = draw(st.sampled_from([np.float16, np.float32, np.float64, np.int64, np.uint8]))
        with np.errstate(all="ignore"):
            value = np.array(draw(numbers) if np.dtype(dtype).kind == "f" else draw(st.integers(0, 200))).astype(dtype)
        return value if draw(st.booleans()) else value[()]
    if kind == "bad type":
        return draw(st.sampled_from(["far", b"1", True, 1j, [1.0, "a"], object()]))
    length = {"array": n, "wrong length": n + draw(st.sampled_from([-1, 1, 2])), "2-d": n}[kind]
    if length < 0:
        length = 1
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    values = np.where(rng.random(length) < 0.6, rng.uniform(-20, 20, length), rng.choice(RANGE_NUMBERS, length))
    if length and rarely(draw, 20):
        values[draw(st.integers(0, length - 1))] = math.nan
    if kind == "2-d":
        values = values.reshape(length, 1) if draw(st.booleans()) else values.reshape(1, length)
    return draw(as_argument(values))


@st.composite
def ray_arguments(draw, targets=QUERY_POINTS):
    """(args, kwargs) for intersect()/occluded(): shapes (N, 3), (3,), (N, 6), mismatched or wrong, any dtype and layout;
    many rays aim at `targets`."""
    form = draw(st.sampled_from(["pair"] * 4 + ["shared origin", "shared direction", "one", "one", "whole", "whole", "one whole",
                                                 "mismatch", "wrong"]))
    n = 0 if rarely(draw, 10) else draw(st.integers(1, 6))
    if form == "wrong":
        shapes = draw(st.lists(st.lists(st.integers(0, 7), max_size=3).map(tuple), min_size=1, max_size=2))
        arrays = [draw(as_argument(draw(real_values(shape)))) for shape in shapes]
        args = arrays if len(arrays) == 2 else [arrays[0], None]
    elif form in ("whole", "one whole"):
        shape = (n, 6) if form == "whole" else (6,)
        origins = draw(real_values((shape[0], 3) if form == "whole" else (3,)))
        directions = draw(direction_values(origins, origins.shape, targets))
        args = [draw(as_argument(np.concatenate([origins, directions], axis=-1))), None]
    else:
        origin_shape = {"pair": (n, 3), "shared origin": (3,), "shared direction": (n, 3), "one": (3,), "mismatch": (n, 3)}[form]
        direction_shape = {"pair": (n, 3), "shared origin": (n, 3), "shared direction": (3,), "one": (3,),
                           "mismatch": (n + draw(st.integers(1, 3)), 3)}[form]
        origins = draw(real_values(origin_shape))
        directions = draw(direction_values(origins, direction_shape, targets))
        args = [draw(as_argument(origins)), draw(as_argument(directions))]
    count = n if form != "one" and form != "one whole" else 1
    kwargs = {}
    for name in ("tmin", "tmax"):
        value = draw(range_arguments(count))
        if value is not None:
            kwargs[name] = value
    if args[1] is None and draw(st.booleans()):
        args = args[:1]
    return args, kwargs


class Refused(Exception):
    """What a call must raise: the exception type and a pattern of its message."""

    def __init__(self, kind, pattern):
        super().__init__(pattern)
        self.kind, self.pattern = kind, pattern


def as_real(value, name):
    """The library's reading of a real-number argument: float32, or Refused(TypeError)."""
    if value is None or isinstance(value, (str, bytes)):
        raise Refused(TypeError, name)
    try:
        array = np.asarray(value)
    except Exception:
        raise Refused(TypeError, name)
    if array.dtype.kind not in "fiu":
        raise Refused(TypeError, name)
    with np.errstate(all="ignore"):
        return array.astype(np.float32)


def as_rows(value, width, name):
    """as_real(), then the shape the library takes: (N, width) or (width,), else Refused(ValueError)."""
    array = as_real(value, name)
    if not ((array.ndim == 2 and array.shape[1] == width) or (array.ndim == 1 and array.shape[0] == width)):
        raise Refused(ValueError, name + ": expected shape")
    return array


def expected_rays(args, kwargs):
    """The rays the library reads from the arguments, as float32 (origins, directions, tmin, tmax, single),
    or Refused with the exception and message the library must raise, checked in the library's order."""
    origins = args[0]
    directions = args[1] if len(args) > 1 else None
    if directions is None:
        whole = as_rows(origins, 6, "rays")
        o, d = whole[..., 0:3], whole[..., 3:6]
        single = whole.ndim == 1
    else:
        o, d = as_rows(origins, 3, "origins"), as_rows(directions, 3, "directions")
        single = o.ndim == 1 and d.ndim == 1
    n_o = len(o) if o.ndim == 2 else 1
    n_d = len(d) if d.ndim == 2 else 1
    if o.ndim == 1 and d.ndim == 2:
        n_o = n_d
    if d.ndim == 1 and o.ndim == 2:
        n_d = n_o
    if n_o != n_d:
        raise Refused(ValueError, "origins and directions")
    n = n_o
    ranges = []
    for name, default in (("tmin", 0.0), ("tmax", math.inf)):
        value = kwargs.get(name, default)
        array = as_real(value, name)
        if array.ndim == 0:
            number = float(value)
            if math.isnan(number):
                raise Refused(ValueError, name + " is NaN")
            with np.errstate(all="ignore"):
                ranges.append(np.full(n, np.float32(number)))
        elif array.ndim != 1 or len(array) != n:
            raise Refused(ValueError, name + ": expected a number or shape")
        else:
            ranges.append(array)
    o, d = np.broadcast_to(o, (n, 3)), np.broadcast_to(d, (n, 3))
    bad = ~np.isfinite(o).all(axis=1) | ~np.isfinite(d).all(axis=1) | np.isnan(ranges[0]) | np.isnan(ranges[1])
    if bad.any():
        raise Refused(ValueError, f"ray {int(np.argmax(bad))} has")
    return (np.ascontiguousarray(o), np.ascontiguousarray(d), np.ascontiguousarray(ranges[0]), np.ascontiguousarray(ranges[1]), single)


def expect_rays(args, kwargs):
    """expected_rays(), Refused returned rather than raised."""
    try:
        return expected_rays(args, kwargs)
    except Refused as refused:
        return refused


def one_ray(array, single):
    """A per-ray answer as an array of rays (a single ray's scalar or row as one)."""
    array = np.asarray(array)
    return array[np.newaxis] if single else array


# ---------------------------------------------------------------- structure and render parameters

def parse_expected(expected):
    """A table's "expected" text as (kind, ...): int lo..hi, num [lo, hi], positive, choice, text."""
    m = re.fullmatch(r"a non-negative integer in (\S+)\.\.(\S+)", expected)
    if m:
        return ("int", int(float(m[1])), int(float(m[2])))
    if expected == "a non-negative integer":
        return ("int", 0, 2**64 - 1)
    m = re.fullmatch(r"a number in \[(\S+), (\S+)\]", expected)
    if m:
        return ("num", float(m[1]), float(m[2]))
    if expected == "a number > 0 (or inf)":
        return ("positive",)
    m = re.fullmatch(r"one of (.+)", expected)
    if m:
        return ("choice", m[1].split(", "))
    if expected.startswith("1, 0, true"):
        return ("choice", re.split(r", | or ", expected))
    if expected == "a non-empty text":
        return ("text",)
    raise AssertionError(f"a kind of parameter these tests do not know yet: {expected!r}")


# Valid values above these bounds cost seconds a build or a render (they are checked by the same code);
# specs that leave these keys out get these values, not the defaults (a field of 4226 x 32^2 takes 0.7 s).
CHEAP_DEFAULTS = {"field": {"positions": "290", "directions": "8"}, "beam": {"dirs": "33", "n": "16"}}
CAPS = {("beam", "dirs"): 129, ("beam", "n"): 24, ("field", "positions"): 290, ("field", "directions"): 12,
        ("render", "spp"): 2, ("render", "ao_rays"): 4, ("render", "shadow_rays"): 4, ("render", "glossy_rays"): 4}


@st.composite
def param_value(draw, owner, param, keyword=False):
    """(value, valid) for parameter `param` of `owner`: inside its range (at and near the bounds) or outside it.
    Values are ints, floats, bools or strings, as keyword arguments take them; with `keyword`, also
    values of other types (None, bytes, lists, complex), which keyword arguments refuse (valid=None)."""
    kind = parse_expected(param["expected"])
    cap = CAPS.get((owner, param["key"]))
    if keyword and rarely(draw, 30):
        return draw(st.sampled_from([None, b"1", [1], 1j, (2, 3)])), None
    inside = not rarely(draw, 5)
    if kind[0] == "int":
        lo, hi = kind[1], kind[2]
        top = min(hi, cap) if cap else hi
        if inside:
            value = draw(st.one_of(st.sampled_from([lo, top, min(lo + 1, top), max(top - 1, lo)]), st.integers(lo, min(top, lo + 64))))
            return (str(value) if draw(st.booleans()) else value), True
        return draw(st.sampled_from([-1, lo - 1 if lo > 0 else -1, hi + 1, 10**20, lo + 0.5, float(lo + 1), "x", "", "1.5", "nan"])), False
    if kind[0] == "num":
        lo, hi = kind[1], kind[2]
        if inside:
            value = draw(st.one_of(st.sampled_from([lo, hi, (lo + hi) / 2]), st.floats(lo, hi)))
            return (repr(value) if draw(st.booleans()) else value), True
        return draw(st.sampled_from([lo - max(abs(lo) / 2, 1e-9), hi + max(abs(hi), 1.0), math.nan, math.inf, -math.inf, "x", ""])), False
    if kind[0] == "positive":
        if inside:
            return draw(st.one_of(st.sampled_from([0.5, 1.0, 100.0, math.inf, "inf", 1]), st.floats(1e-3, 1e6))), True
        return draw(st.sampled_from([0, 0.0, -1.0, -math.inf, math.nan, "x", "0"])), False
    if kind[0] == "choice":
        items = [i for i in kind[1] if not (cap and i.isdigit() and int(i) > cap)]
        if inside:
            value = draw(st.sampled_from(items))
            if value.isdigit() and draw(st.booleans()):
                return int(value), True
            return value, True
        return draw(st.sampled_from(["x" + items[0], items[0].upper() + "X", "", "none of these"])), False
    return draw(st.sampled_from(["/nonexistent/file", ""])), False


def spec_text(value):
    """A keyword value as the library writes it into a spec (python/visfield's keywords.hpp)."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        return "inf" if value == math.inf else repr(value)
    return str(value)


STRUCTURE_NAMES = vf.structures()
STRUCTURE_PARAMS = {name: [p for p in vf.structure_params(name) if p["key"] != "cache"] for name in STRUCTURE_NAMES}
FIELD_BUILD_PARAMS = [p for p in vf.structure_params("field") if p["key"] not in ("cache", "meshes", "cull")]
RENDER_SETTINGS = vf.render_settings()
TRUTHY = {"1", "true", "on", "yes"}


@st.composite
def structure_specs(draw):
    """(spec, verdict): 'ok' for a spec that must build, 'bad' for one that must be refused (ValueError),
    'file' for one naming a file that is not there (visfield.Error)."""
    if rarely(draw, 8):
        garbage = draw(st.one_of(st.text(max_size=20), st.sampled_from(["", ":", "bvh:", "bvh:leaf", "bvh:=3", ",", "bvh:leaf=8,",
                                                                        "bvh:leaf=8,,bins=4", "BVH", "bvh ", "octree", "bvh\x00"])))
        verdict = "ok" if garbage in STRUCTURE_NAMES else "bad"
        return garbage, verdict
    name = draw(st.sampled_from(STRUCTURE_NAMES))
    params = STRUCTURE_PARAMS[name]
    chosen = draw(st.lists(st.sampled_from(params), unique_by=lambda p: p["key"], max_size=len(params))) if params else []
    verdict = "ok"
    entries = []
    for p in chosen:
        value, valid = draw(param_value(name, p))
        if p["key"] == "calibration" and value:
            verdict = "file" if verdict == "ok" else verdict
        elif not valid:
            verdict = "bad"
        entries.append(f"{p['key']}={spec_text(value)}")
    values = dict(e.split("=", 1) for e in entries)
    for key, value in CHEAP_DEFAULTS.get(name, {}).items():
        if key not in values:
            entries.append(f"{key}={value}")
    if name == "field" and values.get("lines") in TRUTHY and values.get("blend") in TRUTHY:
        entries = [e for e in entries if not e.startswith("blend=")]  # test_lines_and_blend_in_a_spec_are_a_value_error
    mangle = draw(st.integers(0, 19))
    if mangle == 19 and entries:
        entries.append(entries[0])  # a key given twice
        verdict = "bad"
    elif mangle == 18:
        entries.append("nokey=1")
        verdict = "bad"
    spec = name + (":" + ",".join(entries) if entries else "")
    return spec, verdict


def tiny_scene():
    """Two meshes, three objects (one scaled and turned), 16 triangles."""
    scene = vf.Scene()
    cube = scene.add_mesh(CUBE_VERTICES, CUBE_TRIANGLES)
    tetra = scene.add_mesh(TETRA_VERTICES, TETRA_TRIANGLES)
    scene.add_instance(cube)
    scene.add_instance(tetra, rigid(0.7, (1, 2, 3), 1.5, (2, 0, 0)))
    scene.add_instance(cube, rigid(-0.4, (0, 1, 0), 0.5, (0, 2, 1)))
    return scene


BUILD_SCENE = tiny_scene()
BUILD_RAYS = fixed_rays(BUILD_SCENE, 64, 1)
BUILD_BRUTE = {levels: vf.build(BUILD_SCENE, f"brute:levels={levels}") for levels in (1, 2)}
BUILD_ANSWERS = {levels: brute.intersect(*BUILD_RAYS) for levels, brute in BUILD_BRUTE.items()}


# ---------------------------------------------------------------- vf.build

@PROPERTY
@given(structure_specs())
def test_build_gives_a_structure_or_a_clean_error(spec_and_verdict):
    """vf.build over random specs: a structure answering as brute force (exact ones), or ValueError / MemoryError."""
    spec, verdict = spec_and_verdict
    event(f"verdict: {verdict}")
    try:
        structure = vf.build(BUILD_SCENE, spec)
    except MemoryError:
        assert verdict == "ok", spec
        return
    except vf.Error as e:
        assert verdict == "file", (spec, e)
        return
    except ValueError as e:
        assert verdict == "bad", (spec, e)
        return
    assert verdict == "ok", spec
    assert isinstance(structure, vf.Structure) and not structure.closed
    assert structure.spec.split(":")[0] == spec.split(":")[0].strip()
    if structure.exact:
        hits = structure.intersect(*BUILD_RAYS)
        assert_same_hits(hits, BUILD_ANSWERS[levels_of(structure.spec)], structure.spec)
        assert same_bits(structure.occluded(*BUILD_RAYS), np.isfinite(hits.t))
    else:
        assert structure.spec.split(":")[0] in ("field", "auto")


def test_lines_and_blend_in_a_spec_are_a_value_error():
    """A field spec asking for two position lookups is a bad spec: ValueError, as Field.build's."""
    with pytest.raises(ValueError):
        vf.build(BUILD_SCENE, "field:positions=290,directions=8,lines=1,blend=1")


# ---------------------------------------------------------------- Structure.intersect and occluded

def check_refused(call, refused):
    """call() raises the exception `refused` names, with its pattern in the message."""
    event(f"refused: {refused.kind.__name__}")
    with pytest.raises(refused.kind, match=re.escape(refused.pattern)):
        call()


def moderate_rays(o, d):
    """Rays whose hits lie well inside float32: origins up to 1e18, distances to the scene up to 1e30
    directions. Beyond, t nears the largest float32, where structures' plane and cell arithmetic overflows
    (a grid's cell walk from an origin at 3.4e38 misses what brute force finds)."""
    reach = np.abs(o).max(axis=1) + 20.0
    scale = np.abs(d).max(axis=1).astype(np.float64)
    return (np.abs(o).max(axis=1) <= 1e18) & ((scale == 0) | (reach <= 1e30 * scale))


def compared(spec, o, d, tmin):
    """The rays whose answers from `spec` are compared with brute force's: the moderate ones (tmin < 0 and
    denormal coordinates included)."""
    return moderate_rays(o, d)


def per_ray(hits, single):
    """Hits with one entry a ray: a single ray's scalars and rows as arrays of one."""
    return vf.Hits(*(one_ray(getattr(hits, field), single) for field in HIT_FIELDS))


@PROPERTY
@given(ray_arguments())
def test_intersect_equals_brute_force_or_refuses_cleanly(arguments):
    """Structure.intersect: every exact structure's hits equal brute force's bit for bit, or a clean TypeError/ValueError."""
    args, kwargs = arguments
    expected = expect_rays(args, kwargs)
    if isinstance(expected, Refused):
        for structure in (BRUTE[1], STRUCTURES["bvh:levels=1"], STRUCTURES["beam"]):
            check_refused(lambda: structure.intersect(*args, **kwargs), expected)
        return
    o, d, tmin, tmax, single = expected
    moderate = moderate_rays(o, d)
    reference = {levels: brute.intersect(*args, **kwargs) for levels, brute in BRUTE.items()}
    hits = reference[1]
    assert np.ndim(hits.t) == (0 if single else 1) and np.shape(hits.normal) == ((3,) if single else (len(o), 3))
    assert hits.t.dtype == np.float32 and hits.prim.dtype == np.uint32 and hits.instance.dtype == np.uint32
    for spec, structure in STRUCTURES.items():
        got = per_ray(structure.intersect(*args, **kwargs), single)
        assert_same_hits(got, per_ray(reference[levels_of(spec)], single), spec, compared(spec, o, d, tmin))
    # The same rays as contiguous float32 arrays: the same answers (dtype, layout and shape only change the reading).
    flat = BRUTE[1].intersect(o, d, tmin=tmin, tmax=tmax)
    assert_same_hits(per_ray(hits, single), flat, "float32")
    # What a hit and a miss are.
    hit, miss = np.isfinite(flat.t) & moderate, ~np.isfinite(flat.t) & moderate
    event("answered: some hits" if hit.any() else "answered: no hit")
    assert not np.isnan(flat.t).any()
    assert (flat.t[hit] > tmin[hit]).all() and (flat.t[hit] <= tmax[hit]).all()
    assert (flat.prim[miss] == INVALID_ID).all() and (flat.instance[miss] == INVALID_ID).all()
    assert (flat.u[miss] == 0).all() and (flat.v[miss] == 0).all() and (flat.normal[miss] == 0).all()
    assert (flat.prim[hit] != INVALID_ID).all() and np.isin(flat.instance[hit], QUERY_SCENE.objects).all()


@PROPERTY
@given(ray_arguments())
def test_occluded_equals_brute_force_or_refuses_cleanly(arguments):
    """Structure.occluded: every exact structure's answers equal brute force's (and its hits'), or a clean TypeError/ValueError."""
    args, kwargs = arguments
    expected = expect_rays(args, kwargs)
    if isinstance(expected, Refused):
        for structure in (BRUTE[2], STRUCTURES["kdtree:levels=1"], STRUCTURES["beam:dirs=33,n=16,stream=0"]):
            check_refused(lambda: structure.occluded(*args, **kwargs), expected)
        return
    o, d, tmin, tmax, single = expected
    consistent = np.ones(len(o), dtype=bool)
    reference = {}
    for levels, brute in BRUTE.items():
        blocked = brute.occluded(*args, **kwargs)
        assert np.asarray(blocked).dtype == bool and np.ndim(blocked) == (0 if single else 1)
        reference[levels] = one_ray(blocked, single)
        hit = np.isfinite(brute.intersect(o, d, tmin=tmin, tmax=tmax).t)
        assert same_bits(reference[levels][consistent], hit[consistent])
    event("answered: some occluded" if reference[1].any() else "answered: none occluded")
    for spec, structure in STRUCTURES.items():
        got, rays = one_ray(structure.occluded(*args, **kwargs), single), compared(spec, o, d, tmin)
        assert same_bits(got[rays], reference[levels_of(spec)][rays]), spec


@pytest.mark.parametrize("spec", ["bvh:levels=1", "bvh:levels=2"])
def test_bvh_finds_hits_behind_the_origin_as_brute_force_does(spec):
    """A range reaching behind the origin (tmin < 0): the BVH's closest hit is brute force's."""
    scene = vf.Scene()
    scene.add_instance(scene.add_mesh(CUBE_VERTICES, CUBE_TRIANGLES))
    origin, direction = np.float32([5, 0.5, 0.5]), np.float32([1, 0, 0])
    expected = vf.build(scene, "brute:levels=1").intersect(origin, direction, tmin=-100.0)
    assert expected.t == -5.0
    assert_same_hits(vf.build(scene, spec).intersect(origin, direction, tmin=-100.0), expected, spec)
    assert vf.build(scene, spec).occluded(origin, direction, tmin=-100.0)


@pytest.mark.parametrize("case", ["tiny", "denormal"])
def test_occluded_is_whether_intersect_hits(case):
    """occluded() is True exactly where intersect() returns a hit, whatever the scale of the ray's numbers."""
    scene = vf.Scene()
    if case == "tiny":
        ground = np.array([[-10, -1, -10], [10, -1, -10], [0, -1, 10]], dtype=np.float64)
        scene.add_instance(scene.add_mesh(ground, np.array([[0, 1, 2]])))
        origin, direction, tmin = np.float32([0, 1.625, -10]), np.float32([0, -1e-37, 6e-37]), 0.0
    else:
        scene.add_instance(scene.add_mesh(CUBE_VERTICES, CUBE_TRIANGLES))
        origin = np.float32([1e-40, 0.0298302, 0.35355338])
        direction, tmin = -origin, 1.0
    brute = vf.build(scene, "brute:levels=1")
    assert bool(brute.occluded(origin, direction, tmin=tmin)) == bool(np.isfinite(brute.intersect(origin, direction, tmin=tmin).t))


@pytest.mark.parametrize("spec", ["kdtree:levels=1", "median-bsp:levels=1", "kdtree:levels=2", "median-bsp:levels=2"])
def test_bsp_trees_find_edge_hits_of_denormal_rays(spec):
    """A ray whose coordinates are denormal floats: the kd-tree's and the median BSP's hit is brute force's."""
    scene = vf.Scene()
    scene.add_instance(scene.add_mesh(CUBE_VERTICES, CUBE_TRIANGLES))
    origin, direction = np.float32([2, -1e-45, 0.5]), np.float32([-1, 1e-45, 0])
    expected = vf.build(scene, f"brute:levels={levels_of(spec)}").intersect(origin, direction)
    assert expected.t == 1.0
    assert_same_hits(vf.build(scene, spec).intersect(origin, direction), expected, spec)


# ---------------------------------------------------------------- Field.build, Field.intersect and occluded

FIELD_SCENE = vf.Scene()
FIELD_SCENE.add_mesh(CUBE_VERTICES, CUBE_TRIANGLES)
FIELD_SCENE.add_mesh(TETRA_VERTICES, TETRA_TRIANGLES)
FIELD_SCENE.add_mesh(SLIVER_VERTICES[:3], SLIVER_TRIANGLES[:1])  # no triangle of non-zero area


@st.composite
def field_keywords(draw):
    """(mesh, keywords, verdict) for Field.build: verdict 'ok', 'bad' (ValueError), 'type' (TypeError) or 'empty' (visfield.Error)."""
    mesh = draw(st.sampled_from([3, 7, -1, 2**32])) if rarely(draw, 10) else draw(st.sampled_from([0, 1, 2]))
    chosen = draw(st.lists(st.sampled_from(FIELD_BUILD_PARAMS), unique_by=lambda p: p["key"], max_size=len(FIELD_BUILD_PARAMS)))
    keywords, verdicts = {}, []
    for p in chosen:
        value, valid = draw(param_value("field", p, keyword=True))
        keywords[p["key"]] = value
        verdicts.append("type" if valid is None else "ok" if valid else "bad")
    if rarely(draw, 15):
        keywords["resolution"] = 3
        verdicts.append("type")
    if mesh < 0 or mesh >= 2**32:
        return mesh, keywords, "type"
    if mesh > 2:
        return mesh, keywords, "bad"
    if "type" in verdicts:
        return mesh, keywords, "type"
    texts = {k: spec_text(v) for k, v in keywords.items()}
    if "bad" in verdicts or (texts.get("lines") in TRUTHY and texts.get("blend") in TRUTHY):
        return mesh, keywords, "bad"
    for key, value in CHEAP_DEFAULTS["field"].items():
        keywords.setdefault(key, int(value))
    return mesh, keywords, "empty" if mesh == 2 else "ok"


@PROPERTY
@given(field_keywords())
def test_field_build_gives_a_field_or_a_clean_error(case):
    """Field.build with random keywords: a field of those parameters, or TypeError / ValueError (visfield.Error for a mesh of zero area)."""
    mesh, keywords, verdict = case
    event(f"verdict: {verdict}")
    expected = {"type": TypeError, "bad": ValueError, "empty": vf.Error}.get(verdict)
    if expected is not None:
        with pytest.raises(expected):
            vf.Field.build(FIELD_SCENE, mesh, **keywords)
        return
    field = vf.Field.build(FIELD_SCENE, mesh, **keywords)
    assert field.positions == int(keywords["positions"])
    assert field.directions == int(keywords["directions"])
    assert field.has_normals == (str(keywords.get("normals", "none")) != "none")
    (centre, radius) = field.sphere
    assert radius > 0 and all(math.isfinite(c) for c in centre)
    t, normal = field.intersect(*BUILD_RAYS)
    assert t.dtype == np.float32 and t.shape == (64,) and normal.shape == (64, 3)
    assert same_bits(field.occluded(*BUILD_RAYS), np.isfinite(t))


def check_field_hits(hits, o, tmin, tmax, single):
    """FieldHits of the promised dtypes and shapes; hits in (tmin, tmax], unit normals, zero ones for misses."""
    t, normal = one_ray(hits.t, single), one_ray(hits.normal, single)
    assert t.dtype == np.float32 and normal.dtype == np.float32 and t.shape == (len(o),) and normal.shape == (len(o), 3)
    hit = np.isfinite(t)
    event("answered: some hits" if hit.any() else "answered: no hit")
    assert not np.isnan(t).any()
    assert (t[hit] > tmin[hit]).all() and (t[hit] <= tmax[hit]).all()
    assert (normal[~hit] == 0).all()
    lengths = np.linalg.norm(normal[hit], axis=1)
    assert (np.abs(lengths - 1) < 1e-2).all() or (lengths == 0).all()


@PROPERTY
@given(ray_arguments(FIELD_TARGETS))
def test_field_intersect_answers_or_refuses_cleanly(arguments):
    """Field.intersect: (t, normal) of one entry a ray, the same whatever the dtype and layout, or a clean TypeError/ValueError."""
    args, kwargs = arguments
    expected = expect_rays(args, kwargs)
    if isinstance(expected, Refused):
        check_refused(lambda: FIELD.intersect(*args, **kwargs), expected)
        return
    o, d, tmin, tmax, single = expected
    hits = FIELD.intersect(*args, **kwargs)
    assert isinstance(hits, vf.FieldHits)
    check_field_hits(hits, o, tmin, tmax, single)
    flat = FIELD.intersect(o, d, tmin=tmin, tmax=tmax)
    assert same_bits(one_ray(hits.t, single), flat.t) and same_bits(one_ray(hits.normal, single), flat.normal)


@PROPERTY
@given(ray_arguments(FIELD_TARGETS))
def test_field_occluded_answers_or_refuses_cleanly(arguments):
    """Field.occluded: a bool a ray, equal to whether intersect() hits, or a clean TypeError/ValueError."""
    args, kwargs = arguments
    expected = expect_rays(args, kwargs)
    if isinstance(expected, Refused):
        check_refused(lambda: FIELD.occluded(*args, **kwargs), expected)
        return
    o, d, tmin, tmax, single = expected
    blocked = FIELD.occluded(*args, **kwargs)
    assert np.asarray(blocked).dtype == bool and np.ndim(blocked) == (0 if single else 1)
    event("answered: some occluded" if np.any(blocked) else "answered: none occluded")
    assert same_bits(one_ray(blocked, single), np.isfinite(FIELD.intersect(o, d, tmin=tmin, tmax=tmax).t))


# ---------------------------------------------------------------- Scene.add_mesh

@st.composite
def mesh_arrays(draw):
    """(vertices, indices, occluder, verdict): verdict 'ok', 'bad' (ValueError) or 'type' (TypeError)."""
    n_vertices = draw(st.integers(0, 2)) if rarely(draw, 10) else draw(st.integers(3, 8))
    shape = draw(st.sampled_from([(n_vertices, 2), (n_vertices, 3, 1), (3,), ()])) if rarely(draw, 10) else (n_vertices, 3)
    scale = draw(st.sampled_from([2e12, 1e38, 1e39])) if rarely(draw, 10) else draw(st.sampled_from([1.0, 1e-30, 1e-40, 1e6, 1e11]))
    vertices_f64 = draw(real_values(shape, poison=20)) * scale
    vertices = draw(as_argument(vertices_f64, real_only=True))
    n_triangles = draw(st.integers(0, 6)) if rarely(draw, 10) else draw(st.integers(1, 6))
    index_shape = draw(st.sampled_from([(n_triangles, 2), (3,)])) if rarely(draw, 10) else (n_triangles, 3)
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    index_values = rng.integers(0, max(n_vertices, 1), index_shape)
    if index_values.size and rarely(draw, 10):
        index_values.flat[draw(st.integers(0, index_values.size - 1))] = draw(st.sampled_from([-1, n_vertices, 2**31, 2**32 + 1]))
    integers = [np.int64, np.int32, np.uint32, np.uint8, np.uint64, np.int16]
    index_dtype = draw(st.sampled_from([np.float64, np.bool_, object] if rarely(draw, 10) else integers))
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        indices = index_values.astype(index_dtype)
    occluder = draw(st.sampled_from(["Auto", "", 3])) if rarely(draw, 10) else draw(st.sampled_from(["auto", "exact", "field"]))
    # The checks in the library's order.
    if not isinstance(occluder, str):
        return vertices, indices, occluder, "type"
    if np.ndim(vertices) != 2 or np.shape(vertices)[1] != 3:
        return vertices, indices, occluder, "bad"
    if indices.dtype.kind not in "iu":
        return vertices, indices, occluder, "type"
    if indices.ndim != 2 or indices.shape[1] != 3 or occluder not in ("auto", "exact", "field"):
        return vertices, indices, occluder, "bad"
    wide = indices.astype(np.int64)
    v32 = np.asarray(vertices, dtype=np.float32)
    if ((wide < 0) | (wide >= len(vertices))).any() or len(indices) == 0:
        return vertices, indices, occluder, "bad"
    if not np.isfinite(v32).all() or (np.abs(v32) > 1e12).any():
        return vertices, indices, occluder, "bad"  # every vertex is checked, used or not
    return vertices, indices, occluder, "ok"


@PROPERTY
@given(mesh_arrays())
def test_add_mesh_gives_a_mesh_or_a_clean_error(case):
    """Scene.add_mesh with random arrays: a mesh whose structures answer as brute force, or a clean TypeError/ValueError."""
    vertices, indices, occluder, verdict = case
    scene = vf.Scene()
    event(f"verdict: {verdict}")
    if verdict != "ok":
        with pytest.raises(TypeError if verdict == "type" else ValueError):
            scene.add_mesh(vertices, indices, occluder)
        assert scene.mesh_count == 0
        return
    mesh = scene.add_mesh(vertices, indices, occluder)
    assert mesh == 0 and scene.mesh_count == 1 and scene.object_count == 0
    scene.add_instance(mesh)
    assert scene.triangle_count == len(indices)
    origins, directions = fixed_rays(scene, 32, 3)
    reference = {levels: vf.build(scene, f"brute:levels={levels}").intersect(origins, directions) for levels in (1, 2)}
    v32 = np.asarray(vertices, dtype=np.float32)
    event("tiny coordinates" if ((v32 != 0) & (np.abs(v32) < 1e-30)).any() else "moderate coordinates")
    for spec in ("bvh:levels=1", "bvh:levels=2", "grid:levels=1", "kdtree:levels=1", "median-bsp:levels=1", "beam:dirs=33,n=16"):
        assert_same_hits(vf.build(scene, spec).intersect(origins, directions), reference[levels_of(spec)], spec)


def test_beam_field_finds_hits_of_rays_from_far_away():
    """A ray from two billion units away (here beside an unused vertex): BeamField's hit is brute force's (its clip to the
    bounding sphere cancelled to nothing before it took the chord from the line's point nearest the centre)."""
    scene = vf.Scene()
    vertices = np.array([[-2, 2, 3], [0, -1, 0], [10, 0, -1], [-4, -4, -2147483648.0]])
    scene.add_instance(scene.add_mesh(vertices, np.array([[0, 1, 2]])))
    origin = np.float32([9.281092643737793, -2.129011392593384, -2138392832.0])
    direction = np.float32([-2.214426040649414, 2.2623448371887207, 2138392832.0])
    expected = vf.build(scene, "brute:levels=1").intersect(origin, direction)
    assert expected.t == 1.0
    assert_same_hits(vf.build(scene, "beam:dirs=33,n=16").intersect(origin, direction), expected, "beam")


@pytest.mark.parametrize("spec", ["bvh:levels=1", "bvh:levels=2"])
def test_bvh_builds_over_a_mesh_of_denormal_extent(spec):
    """A BVH over a mesh only 1e-40 thick builds (in a child process: it segfaulted before its binning
    ignored axes whose bins / extent overflows)."""
    code = ("import numpy as np, visfield as vf; scene = vf.Scene(); "
            "vertices = np.array([[0, 0, 1e-40], [0, 0, 0], [0, 1, 0], [1e-40, 0, 0]]); "
            "scene.add_instance(scene.add_mesh(vertices, np.array([[2, 1, 0], [2, 3, 1]]))); "
            f"vf.build(scene, {spec!r})")
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(vf.__file__)))
    result = subprocess.run([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=package_root), capture_output=True, timeout=120)
    assert result.returncode == 0, (result.returncode, result.stderr[-500:])


@pytest.mark.parametrize("dtype", [np.complex128, np.bool_, np.str_])
def test_add_mesh_refuses_vertices_that_are_not_real_numbers(dtype):
    """Vertices of complex, bool or text: TypeError, as for ray arguments."""
    with pytest.raises(TypeError):
        vf.Scene().add_mesh(TETRA_VERTICES.astype(dtype), TETRA_TRIANGLES)


# ---------------------------------------------------------------- transforms; Scene.add_instance, set_transform, remove_instance

@st.composite
def transforms(draw, kinds=("rigid", "rigid", "rigid", "none", "bad", "arbitrary")):
    """(matrix, verdict): a rigid motion with uniform scale ('ok'), a refused matrix ('bad': ValueError), what is not real
    numbers ('type': TypeError), or arbitrary numbers ('maybe')."""
    kind = draw(st.sampled_from(kinds))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if kind == "none":
        return None, "ok"
    if kind == "rigid":
        axis, angle, scale = rng.normal(size=3), rng.uniform(-math.pi, math.pi), rng.choice([1.0, 0.5, 2.0, 0.25, 3.5])
        matrix = rigid(angle, axis if np.linalg.norm(axis) > 1e-6 else (0, 0, 1), scale, rng.uniform(-4, 4, 3))
        form = draw(st.sampled_from(["3x4", "4x4", "float32", "list"]))
        if form == "4x4":
            matrix = np.vstack([matrix, [0, 0, 0, 1]])
        elif form == "float32":
            matrix = matrix.astype(np.float32)
        elif form == "list":
            matrix = matrix.tolist()
        return matrix, "ok"
    if kind == "bad":
        identity = rigid()
        shear, mirror, nan, last = identity.copy(), identity.copy(), identity.copy(), np.vstack([identity, [0, 0, 1, 1]])
        shear[0, 1] = 0.5
        mirror[0, 0] = -1
        nan[1, 3] = math.nan
        if rarely(draw, 6):
            return draw(st.sampled_from(["abc", [["a"] * 4] * 3, identity.astype(np.complex128), identity > 0])), "type"
        return draw(st.sampled_from([shear, mirror, nan, last, np.zeros((3, 4)), np.eye(3), np.eye(4)[:, :3], np.zeros(12), np.eye(4) * 2,
                                     [[1, 2, 3]], identity * 1e200, identity * 1e-60])), "bad"
    return rng.uniform(-3, 3, (3, 4)), "maybe"


@st.composite
def object_ids(draw):
    """An object id: mostly a small one (of an object or of none), rarely one no uint32 holds (TypeError)."""
    return draw(st.sampled_from([-1, 2**32, 2**40])) if rarely(draw, 12) else draw(st.integers(0, 6))


@st.composite
def scene_edits(draw):
    """A list of add_instance / set_transform / remove_instance calls with random ids, meshes and matrices."""
    ops = []
    for _ in range(draw(st.integers(1, 8))):
        op = draw(st.sampled_from(["add", "add", "add", "move", "remove"]))
        if op == "add":
            mesh = draw(st.sampled_from([2, 5, -1, 2**32])) if rarely(draw, 10) else draw(st.sampled_from([0, 1]))
            ops.append(("add", mesh, draw(transforms())))
        elif op == "move":
            ops.append(("move", draw(object_ids()), draw(transforms())))
        else:
            ops.append(("remove", draw(object_ids())))
    return ops


def two_meshes():
    """A scene of the cube (mesh 0) and the tetrahedron (mesh 1), no objects."""
    scene = vf.Scene()
    scene.add_mesh(CUBE_VERTICES, CUBE_TRIANGLES)
    scene.add_mesh(TETRA_VERTICES, TETRA_TRIANGLES)
    return scene


MESHES = {0: (CUBE_VERTICES, CUBE_TRIANGLES), 1: (TETRA_VERTICES, TETRA_TRIANGLES)}


def expected_bounds(model):
    """Scene.bounds of objects {id: (mesh, matrix)} of MESHES (a None matrix: identity): the bounds of
    each mesh's bounding box, placed."""
    corners = []
    for mesh, matrix in model.values():
        m = np.asarray(rigid() if matrix is None else matrix, dtype=np.float64)[:3]
        lo, hi = MESHES[mesh][0].min(axis=0), MESHES[mesh][0].max(axis=0)
        corners.append((lo + (hi - lo) * CUBE_VERTICES) @ m[:, :3].T + m[:, 3])
    points = np.vstack(corners)
    return np.array([points.min(axis=0), points.max(axis=0)])


@PROPERTY
@given(scene_edits())
def test_scene_edits_keep_ids_and_answers(ops):
    """Scene.add_instance/set_transform/remove_instance with random ids and matrices: clean errors, stable ids, answers as brute force."""
    scene = two_meshes()
    model = {}  # id -> (mesh, matrix)
    next_id = 0
    for op in ops:
        if op[0] == "add":
            _, mesh, (matrix, verdict) = op
            if mesh < 0 or mesh >= 2**32:
                with pytest.raises(TypeError):
                    scene.add_instance(mesh, matrix)
                continue
            if verdict in ("bad", "type") or (verdict == "ok" and mesh > 1):
                with pytest.raises(TypeError if verdict == "type" else ValueError):
                    scene.add_instance(mesh, matrix)
                continue
            try:
                new = scene.add_instance(mesh, matrix)
            except ValueError:
                assert verdict == "maybe" or mesh > 1
                continue
            assert mesh <= 1 and new == next_id
            model[new] = (mesh, matrix)
            next_id += 1
        elif op[0] == "move":
            _, id, (matrix, verdict) = op
            if id < 0 or id >= 2**32:
                with pytest.raises(TypeError):
                    scene.set_transform(id, matrix)
            elif verdict in ("bad", "type") or (verdict == "ok" and id not in model):
                with pytest.raises(TypeError if verdict == "type" else ValueError):
                    scene.set_transform(id, matrix)
            else:
                try:
                    scene.set_transform(id, matrix)
                except ValueError:
                    assert verdict == "maybe" or id not in model
                else:
                    model[id] = (model[id][0], matrix)
        else:
            _, id = op
            if id < 0 or id >= 2**32:
                with pytest.raises(TypeError):
                    scene.remove_instance(id)
            elif id not in model:
                with pytest.raises(ValueError):
                    scene.remove_instance(id)
            else:
                scene.remove_instance(id)
                del model[id]
    event(f"objects left: {min(len(model), 3)}{'+' if len(model) >= 3 else ''}")
    assert scene.objects == sorted(model) and scene.object_count == len(model)
    assert scene.triangle_count == sum(len(MESHES[mesh][1]) for mesh, _ in model.values())
    if not model:
        with pytest.raises(ValueError):
            vf.build(scene, "bvh")
        return
    np.testing.assert_allclose(scene.bounds, expected_bounds(model), rtol=1e-4, atol=1e-4)
    origins, directions = fixed_rays(scene, 32, 5)
    for levels in (1, 2):
        reference = vf.build(scene, f"brute:levels={levels}").intersect(origins, directions)
        assert np.isin(reference.instance[np.isfinite(reference.t)], list(model)).all()
        assert_same_hits(vf.build(scene, f"bvh:levels={levels}").intersect(origins, directions), reference, f"bvh:levels={levels}")


def test_complex_transforms_are_refused():
    """A matrix of complex numbers is not a transform: TypeError (or ValueError), not a placed object."""
    scene = two_meshes()
    with pytest.raises((TypeError, ValueError)):
        scene.add_instance(0, rigid().astype(np.complex128))


# ---------------------------------------------------------------- Structure.remove, insert, move, commit

UPDATABLE_SPECS = ["beam:dirs=33,n=16", "bvh:levels=2", "grid:levels=2", "kdtree:levels=2", "median-bsp:levels=2", "brute:levels=2"]
EDIT_SCENE = tiny_scene()
EDIT_SCENE.add_instance(1, rigid(1.1, (0, 0, 1), 0.8, (-1.5, 0.2, 0.3)))
EDIT_SCENE.add_instance(0, rigid(0.2, (1, 0, 0), 1.0, (0.5, 0.5, 0.5)))
EDIT_MATRICES = {id: None for id in EDIT_SCENE.objects}
EDIT_RAYS = fixed_rays(EDIT_SCENE, 64, 7)


@st.composite
def structure_edits(draw):
    """(spec, ops): remove / insert / move / commit with random ids and matrices, inserts from the scene or a moved copy."""
    spec = draw(st.sampled_from(UPDATABLE_SPECS))
    ops = []
    for _ in range(draw(st.integers(1, 8))):
        op = draw(st.sampled_from(["remove", "insert", "move", "move", "commit"]))
        if op == "commit":
            ops.append(("commit",))
        elif op == "insert":
            ops.append(("insert", draw(object_ids()), draw(st.one_of(st.none(), transforms(kinds=("rigid",)).map(lambda t: t[0])))))
        elif op == "move":
            ops.append(("move", draw(object_ids()), draw(transforms())))
        else:
            ops.append(("remove", draw(object_ids())))
    return spec, ops


def scene_of(placed):
    """EDIT_SCENE with only the objects of `placed` (id -> matrix or None for the original placement)."""
    scene = EDIT_SCENE.copy()
    for id in EDIT_SCENE.objects:
        if id not in placed:
            scene.remove_instance(id)
        elif placed[id] is not None:
            scene.set_transform(id, placed[id])
    return scene


def check_answers_as_a_fresh_build(structure, spec, placed):
    """The structure answers EDIT_RAYS as brute force built over scene_of(placed) (misses when it is empty)."""
    scene = scene_of(placed)
    hits = structure.intersect(*EDIT_RAYS)
    if not placed:
        assert (hits.t == np.inf).all() and (hits.instance == INVALID_ID).all()
        assert not structure.occluded(*EDIT_RAYS).any()
        return
    brute = vf.build(scene, f"brute:levels={levels_of(spec)}")
    assert_same_hits(hits, brute.intersect(*EDIT_RAYS), spec)
    assert same_bits(structure.occluded(*EDIT_RAYS), brute.occluded(*EDIT_RAYS))


@PROPERTY
@given(structure_edits())
def test_structure_edits_answer_as_a_fresh_build(case):
    """remove/insert/move/commit with random ids and matrices: clean errors, and after each commit the answers of a fresh build."""
    spec, ops = case
    event(f"structure: {spec}")
    structure = vf.build(EDIT_SCENE, spec)
    assert structure.updatable
    committed = dict(EDIT_MATRICES)
    staged = dict(committed)
    for op in ops:
        if op[0] == "commit":
            structure.commit()
            committed = dict(staged)
            check_answers_as_a_fresh_build(structure, spec, committed)
            continue
        id = op[1]
        if id < 0 or id >= 2**32:
            with pytest.raises(TypeError):
                {"remove": lambda: structure.remove(id), "insert": lambda: structure.insert(EDIT_SCENE, id),
                 "move": lambda: structure.move(id, rigid())}[op[0]]()
            continue
        if op[0] == "remove":
            if id in staged:
                structure.remove(id)
                del staged[id]
            else:
                with pytest.raises(ValueError):
                    structure.remove(id)
        elif op[0] == "insert":
            source = EDIT_SCENE if op[2] is None or id not in EDIT_MATRICES else scene_of({**EDIT_MATRICES, id: op[2]})
            if id in staged or id not in EDIT_MATRICES:
                with pytest.raises(ValueError):
                    structure.insert(source, id)
            else:
                structure.insert(source, id)
                staged[id] = op[2]
        else:
            matrix, verdict = op[2]
            if verdict in ("bad", "type") or (verdict == "ok" and id not in staged):
                with pytest.raises(TypeError if verdict == "type" else ValueError):
                    structure.move(id, matrix)
                continue
            try:
                structure.move(id, matrix)
            except ValueError:
                assert verdict == "maybe" or id not in staged
            else:
                assert id in staged
                staged[id] = matrix if matrix is not None else rigid()
    # Staged edits change nothing until commit().
    check_answers_as_a_fresh_build(structure, spec, committed)
    structure.commit()
    check_answers_as_a_fresh_build(structure, spec, staged)


# ---------------------------------------------------------------- vf.render and Renderer.render

RENDER_SCENE = vf.load("builtin:cornell:size=8")
RENDERER = vf.Renderer(RENDER_SCENE)
SMALL_FIELD = "field:positions=290,directions=8"
# The view and structure keywords: (values taken, values refused).
VIEW_OPTIONS = {
    "up": (["z", "-y", "+x", ["z"]], ["w", "", "zz", 3]),
    "view": ([(45, 30), "45,30", (0, 90), (-720, -90), [10.5, -3], np.array([1.0, 2.0])],
             [(0, 91), (1e300, 0), (math.nan, 0), (1, 2, 3), "abc", [], 5]),
    "background": (["transparent", "white", "black", "grey", "#00FF00", "#3a3f47", (0.1, 0.2, 0.3), (1, 1, 1)],
                   ["#00FF0", (2, 0, 0), (0.1, 0.2), (math.nan, 0, 0), "purple", [(0.1, 0.2, 0.3)]]),
    "camera": (["0,1,5,0,0,0", (0, 1, 5, 0, 0, 0), (0, 0, 5, 0, 0, 0, 0, 1, 0), (0, 0, 5, 0, 0, 0, 0, 1, 0, 60), None],
               [(0, 0, 5, 0, 0, 0, 0, 1, 0, 180), (0, 0, 5, 0, 0, 5), (0, 0, 5, 0, 0, 0, 0, 0, 1), (1, 2), "x"]),
}
STRUCTURE_OPTIONS = {
    "accel": (["bvh", "grid", "kdtree:levels=2", "brute", "beam:dirs=33,n=16", SMALL_FIELD, "auto"], ["nonsense", "bvh:leaf=0", "", None]),
    "occluder": (["", None, "bvh", "median-bsp", "beam:dirs=33,n=16", SMALL_FIELD], ["x", "grid:density=0"]),
    "occluders": (["exact", "field"], ["x", "FIELD"]),
}


@st.composite
def render_keywords(draw, structures):
    """(keywords, verdict, shape): random render settings and view keywords; with `structures`, also accel/occluder/occluders.
    verdict: True (an image of `shape`), False (ValueError or TypeError)."""
    keywords, valid = {}, True
    for setting in draw(st.lists(st.sampled_from(RENDER_SETTINGS), unique_by=lambda s: s["key"], max_size=6)):
        value, ok = draw(param_value("render", setting, keyword=True))
        keywords[setting["key"]], valid = value, valid and bool(ok)
    width, height = draw(st.integers(1, 6)), draw(st.integers(1, 6))
    if rarely(draw, 10):
        width, valid = draw(st.sampled_from([-1, -6])), False
    keywords["width"], keywords["height"] = width, height
    options = dict(VIEW_OPTIONS, **(STRUCTURE_OPTIONS if structures else {}))
    shape = (height, width)
    if draw(st.integers(0, 5)) == 0:
        camera = RENDER_SCENE.camera(draw(st.integers(1, 5)), draw(st.integers(1, 5)))
        keywords["camera"] = camera
        shape = (camera.height, camera.width)
        del options["camera"]
    for key in draw(st.lists(st.sampled_from(sorted(options)), unique=True)):
        good, bad = options[key]
        refused = rarely(draw, 4)
        keywords[key], valid = draw(st.sampled_from(bad if refused else good)), valid and not refused
    if isinstance(keywords.get("view"), tuple) and keywords["view"] == (1e300, 0) and keywords.get("camera") is not None:
        keywords["view"] = (0, 91)  # test_a_view_beside_a_camera_is_checked
    if keywords.get("occluders") == "field":
        if keywords.get("occluder") in (None, ""):
            keywords["occluder"] = SMALL_FIELD  # the default field takes a second and a half
        valid = valid and keywords["occluder"] == SMALL_FIELD
    if keywords.get("occluders") == "exact" and keywords.get("occluder") == SMALL_FIELD:
        valid = False
    if not structures and rarely(draw, 10):
        keywords["accel"], valid = "bvh", False  # a Renderer's structures are chosen when it is made
    if draw(st.integers(0, 3)) == 0:
        x0, y0 = draw(st.integers(-1, max(shape[1], 0))), draw(st.integers(-1, shape[0]))
        x1, y1 = draw(st.integers(-1, max(shape[1], 0) + 1)), draw(st.integers(-1, shape[0] + 1))
        if (x0, y0) == (0, 0) and x1 <= 0 and y1 <= 0:
            x1 = shape[1] + 1  # test_an_empty_region_at_the_origin_is_a_value_error
        keywords["region"] = (x0, y0, x1, y1)
        if 0 <= x0 < x1 <= shape[1] and 0 <= y0 < y1 <= shape[0]:
            shape = (y1 - y0, x1 - x0)
        else:
            valid = False
        if isinstance(keywords.get("camera"), vf.Camera) and keywords["width"] > 0:
            keywords["width"], keywords["height"] = keywords["camera"].width, keywords["camera"].height  # test_a_region_of_a_camera_s_image
    if draw(st.booleans()):
        keywords["stats"] = draw(st.booleans())
    channels = 4 if keywords.get("background") == "transparent" else 3
    return keywords, valid, shape + (channels,)


def check_render(render, keywords, valid, shape):
    """render(**keywords) raises ValueError/TypeError, or returns a finite float32 image of `shape`; returns the image."""
    event("an image" if valid else "refused")
    if not valid:
        with pytest.raises((ValueError, TypeError)):
            render(**keywords)
        return None
    result = render(**keywords)
    image = result
    if keywords.get("stats"):
        image, stats = result
        assert stats["rays"] >= 0 and stats["seconds"] >= 0
    assert isinstance(image, np.ndarray) and image.dtype == np.float32 and image.shape == shape, (image.shape, shape)
    assert np.isfinite(image).all()
    return image


@PROPERTY
@given(render_keywords(structures=True))
def test_render_gives_an_image_or_a_clean_error(case):
    """vf.render with random settings, view keywords and structures: an image of the asked size, or ValueError/TypeError."""
    keywords, valid, shape = case
    check_render(lambda **k: vf.render(RENDER_SCENE, **k), keywords, valid, shape)


@PROPERTY
@given(render_keywords(structures=False))
def test_renderer_render_gives_vf_render_s_image_or_a_clean_error(case):
    """Renderer.render with random keywords: vf.render's image bit for bit, or ValueError/TypeError."""
    keywords, valid, shape = case
    image = check_render(RENDERER.render, keywords, valid, shape)
    if image is not None:
        again = vf.render(RENDER_SCENE, **dict(keywords, stats=False))
        assert same_bits(image, again)


@pytest.mark.parametrize("keyword", [{"width": 1.5}, {"width": 2**40}, {"region": (0, 0, 2)}, {"region": "0,0,1,1"}, {"progress": "x"},
                                     {"stats": "yes"}, {"accel": 3}, {"occluder": 3}])
def test_render_keywords_of_another_type_are_a_type_error(keyword):
    """A render keyword of the wrong type: TypeError or ValueError, never RuntimeError."""
    keywords = dict({"width": 2, "height": 2}, **keyword)
    with pytest.raises((TypeError, ValueError)):
        vf.render(RENDER_SCENE, **keywords)


@pytest.mark.parametrize("region", [(0, 0, 0, 0), (0, 0, -1, -1)])
def test_an_empty_region_at_the_origin_is_a_value_error(region):
    """An empty region is refused wherever it lies."""
    with pytest.raises(ValueError, match="region"):
        vf.render(RENDER_SCENE, width=2, height=2, region=region)


@pytest.mark.parametrize("call", ["render", "Renderer.render"])
def test_a_view_beside_a_camera_is_checked(call):
    """An infinite azimuth is refused whatever else the call gives."""
    with pytest.raises(ValueError, match="azimuth"):
        if call == "render":
            vf.render(RENDER_SCENE, width=2, height=2, camera=(0, 1, 5, 0, 0, 0), view=(1e300, 0))
        else:
            RENDERER.render(camera=RENDER_SCENE.camera(2, 2), view=(1e300, 0))


def test_a_region_of_a_camera_s_image():
    """A region inside the image of a Camera (1 x 2 pixels) is rendered, whatever width and height say."""
    image = vf.render(RENDER_SCENE, width=1, height=1, camera=RENDER_SCENE.camera(1, 2), region=(0, 0, 1, 2))
    assert image.shape == (2, 1, 3)


@pytest.mark.parametrize("call", ["render", "field"])
def test_a_keyword_value_cannot_set_other_keywords(call):
    """A keyword value holding ',key=value' is a bad value (ValueError), not a second keyword."""
    with pytest.raises(ValueError):
        if call == "render":
            vf.render(RENDER_SCENE, width=2, height=2, integrator="ao,spp=2")
        else:
            vf.Field.build(FIELD_SCENE, 0, positions=290, directions=8, mapping="concentric,storage=f32")


# ---------------------------------------------------------------- closed handles

def closed_handle(kind, how):
    """A Scene, Structure, Field or Renderer, closed by close() (once or twice) or by leaving a with block."""
    handle = {"scene": lambda: BUILD_SCENE.copy(), "structure": lambda: vf.build(BUILD_SCENE, "bvh"),
              "updatable": lambda: vf.build(BUILD_SCENE, "bvh:levels=2"),
              "field": lambda: vf.Field.build(FIELD_SCENE, 0, positions=290, directions=8),
              "renderer": lambda: vf.Renderer(RENDER_SCENE)}[kind]()
    if how == "with":
        with handle:
            pass
    else:
        handle.close()
        if how == "twice":
            handle.close()
    assert handle.closed
    return handle


def query(method):
    """A use of a handle: `method` with random ray arguments (drawn by rays())."""
    def use(handle, rays, id):
        args, kwargs = rays()
        return getattr(handle, method)(*args, **kwargs)
    return use


# What each kind of handle offers: properties by name, calls as use(handle, rays, id).
USES = {
    "scene": ["name", "mesh_count", "object_count", "triangle_count", "objects", "bounds", "moves", "objects_move",
              lambda s, rays, id: s.camera(id % 9, id % 7), lambda s, rays, id: s.copy(), lambda s, rays, id: s.frame(id % 3, 3),
              lambda s, rays, id: s.add_mesh(TETRA_VERTICES, TETRA_TRIANGLES), lambda s, rays, id: s.add_instance(id),
              lambda s, rays, id: s.set_transform(id, rigid()), lambda s, rays, id: s.remove_instance(id),
              lambda s, rays, id: vf.build(s, "bvh"), lambda s, rays, id: vf.render(s, width=2, height=2),
              lambda s, rays, id: vf.Field.build(s, id), lambda s, rays, id: vf.Renderer(s), lambda s, rays, id: vf.plan(s, rays=id + 1),
              lambda s, rays, id: vf.build(BUILD_SCENE, "bvh:levels=2").insert(s, id)],
    "structure": ["spec", "exact", "updatable", "stats", query("intersect"), query("occluded"), lambda s, rays, id: s.commit()],
    "updatable": [lambda s, rays, id: s.remove(id), lambda s, rays, id: s.insert(BUILD_SCENE, id), lambda s, rays, id: s.move(id, rigid()),
                  lambda s, rays, id: s.commit(), query("intersect")],
    "field": ["positions", "directions", "has_normals", "memory_bytes", "build_ms", "sphere", query("intersect"), query("occluded"),
              lambda f, rays, id: f.save(f"/nonexistent/{id}.vfield")],
    "renderer": ["accel", "occluder", "build_ms", lambda r, rays, id: r.render(width=id % 5 + 1, height=2)],
}


@PROPERTY
@given(st.sampled_from(sorted(USES)).flatmap(lambda kind: st.tuples(st.just(kind), st.sampled_from(USES[kind]))),
       st.sampled_from(["close", "twice", "with"]), st.integers(0, 2**32 - 1), st.data())
def test_closed_handles_raise_value_error(kind_and_use, how, id, data):
    """Every use of a closed Scene, Structure, Field or Renderer, whatever its arguments, raises ValueError naming it closed."""
    kind, use = kind_and_use
    handle = closed_handle(kind, how)
    with pytest.raises(ValueError, match="is closed"):
        if isinstance(use, str):
            getattr(handle, use)
        else:
            use(handle, lambda: data.draw(ray_arguments()), id)
    assert handle.closed
