"""The fuzzer's argument strategies: pools of extreme and badly typed values, scalars, vectors, quaternions,
counts, and shapes (valid or not). Part of ``test_fuzz.py``; ``fuzz_strategies.py`` builds calls from them."""

from __future__ import annotations


import numpy as np

from hypothesis import strategies as st

from fuzz_programs import INF, NAN, Raw, ShapeX

# ----------------------------------------------------------------------------------------------------------------
# Value pools and argument strategies: each draws a good value, or (when hostile) an extreme or badly typed one.

INTEGRATORS = ["euler", "euler-variable", "midpoint", "rk4", "ab4", "am4", "implicit-euler", "dopri5", "dop853",
               "symplectic-euler", "verlet", "rodas4", "radau5"]
ADAPTIVE = {"dopri5", "dop853", "rodas4", "radau5", "am4"}
EXTREME = [NAN, INF, -INF, -0.0, 0.0, 5e-324, -5e-324, 1e-300, 1e300, -1e300, 1e308, -1e308,
           1.7976931348623157e308, -1.0, 1e-9, 1e9, 1e16]
BAD_SCALARS = [None, "1.0", "abc", [1.0], (1.0, 2.0), 10**400, -(10**400), 2**64, Raw("1j"), np.float32("nan"),
               np.float64(1e308), np.int64(-1), Raw("object()"), Raw("{}")]
BAD_VECTORS = [None, (1.0, 2.0), (1.0, 2.0, 3.0, 4.0), "abc", Raw("np.zeros((1, 3))"), np.array([1, 2, 3]),
               [[1.0, 2.0, 3.0]], 5.0, Raw("{}"), Raw("np.array(['1', '2', '3'])"), (1.0, 2.0, "3"),
               [None, 0.0, 0.0], (10**400, 0.0, 0.0), Raw("iter([1.0, 2.0, 3.0])")]
BAD_QUATS = [(0.0, 0.0, 0.0, 0.0), (NAN, 0.0, 0.0, 0.0), (INF, 0.0, 0.0, 0.0), (1e300, 1e300, 0.0, 0.0),
             (5e-324, 0.0, 0.0, 0.0), (1.0, 0.0, 0.0), None, "abc", (1.0, 0.0, 0.0, 0.0, 0.0), (-0.0, 0.0, 0.0, -0.0)]
BAD_INTS = [-1, 0, 2**32, 2**64, 10**9, 1.5, NAN, INF, "8", None]
HOSTILE_DURATIONS = [1e300, INF, NAN, 0.0, -0.0, -1.0, 5e-324, 1e-300, 1e6, 1e16]
FAST_DTS = [1 / 240, 1 / 120, 1 / 60, 1 / 480]


def pick(draw, *options):
    """One of `options` ((weight, strategy or value), ...); shrinks towards the first."""
    total = sum(weight for weight, _ in options)
    r = draw(st.integers(0, total - 1))
    for weight, option in options:
        if r < weight:
            return draw(option) if isinstance(option, st.SearchStrategy) else option
        r -= weight
    raise AssertionError


@st.composite
def weighted(draw, *options):
    """`pick` as a strategy."""
    return pick(draw, *options)


def floats(lo: float, hi: float):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False, allow_subnormal=False)


@st.composite
def scalar(draw, lo: float, hi: float, hostile: bool, wide: tuple | None = None):
    """A float in [lo, hi]; with `wide`, now and then one in that valid but extreme range."""
    good = floats(lo, hi) if wide is None else weighted((9, floats(lo, hi)), (1, floats(*wide)))
    if not hostile:
        return draw(good)
    return pick(draw, (10, good), (6, st.sampled_from(EXTREME)), (4, st.sampled_from(BAD_SCALARS)))


@st.composite
def vector(draw, lo: float, hi: float, hostile: bool, n: int = 3, wide: tuple | None = None):
    component = floats(lo, hi) if wide is None else weighted((9, floats(lo, hi)), (1, floats(*wide)))
    good = st.tuples(*[component] * n)
    if not hostile:
        return pick(draw, (9, good), (1, good.map(lambda v: np.array(v, dtype=np.float64))))
    kind = pick(draw, (6, st.just("good")), (5, st.just("one")), (1, st.just("all")), (4, st.just("bad")))
    if kind == "good":
        return draw(good)
    if kind == "one":
        v = list(draw(good))
        v[draw(st.integers(0, n - 1))] = draw(st.sampled_from(EXTREME))
        return tuple(v)
    if kind == "all":
        return (draw(st.sampled_from(EXTREME)),) * n
    return draw(st.sampled_from(BAD_QUATS if n == 4 else BAD_VECTORS))


def quaternion(hostile: bool):
    return vector(-1.0, 1.0, hostile, 4)


@st.composite
def counts(draw, lo: int, hi: int, hostile: bool):
    if not hostile:
        return draw(st.integers(lo, hi))
    return pick(draw, (10, st.integers(lo, hi)), (6, st.sampled_from(BAD_INTS)))


@st.composite
def params(draw, spec: dict) -> tuple:
    """Some of the optional parameters in `spec` (name -> strategy)."""
    return tuple((name, draw(strategy)) for name, strategy in spec.items() if draw(st.booleans()))


def good_or_bad(draw, good: list, hostile: bool):
    if not hostile:
        return draw(st.sampled_from(good))
    return pick(draw, (8, st.sampled_from(good)), (4, st.sampled_from(EXTREME + BAD_SCALARS)))


CUBE = [(x, y, z) for x in (-0.3, 0.3) for y in (-0.2, 0.2) for z in (-0.25, 0.25)]
TETRA_V = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
TETRA_T = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
QUAD_V = [(-2.0, -2.0, 0.0), (2.0, -2.0, 0.0), (2.0, 2.0, 0.0), (-2.0, 2.0, 0.0)]
QUAD_T = [(0, 1, 2), (0, 2, 3)]
BAD_HULLS = [
    [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)],  # flat
    [(0, 0, 0)] * 5,
    [(0, 0, 0), (1, 0, 0), (0, 1, 0)],
    [],
    np.zeros((0, 3)),
    np.zeros((5, 2)),
    [tuple(1e300 * c for c in q) for q in CUBE],
    [tuple(1e-300 * c for c in q) for q in CUBE],
    [tuple(5e-324 if c > 0 else 0.0 for c in q) for q in CUBE],
    [tuple(1e-9 * c for c in q) for q in CUBE],
    "abc",
    [[]],
    [(NAN, NAN, NAN)] * 4,
    [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, INF)],
]
BAD_MESHES = [
    (np.eye(3), np.array([[0, 1]])),
    (QUAD_V, [(0, 1, 7)]),
    (QUAD_V, [(0, 1, -1)]),
    (QUAD_V, np.array([[0, 1, 2**32 + 2]], dtype=np.int64)),
    (QUAD_V, [(0.0, 1.5, 2.0)]),
    (QUAD_V, []),
    ([], []),
    (np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)),
    ([(NAN, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)], [(0, 1, 2)]),
    ([(1e300, 0.0, 0.0), (-1e300, 0.0, 0.0), (0.0, 1e300, 0.0)], [(0, 1, 2)]),
    ([(0.0, 0.0, 0.0)] * 3, [(0, 1, 2)]),
    (QUAD_V, [(0, 0, 0)]),
    (QUAD_V, "abc"),
    (QUAD_V, np.array([[0, 1, 2]], dtype=np.uint64)),
]


@st.composite
def hull_points(draw, hostile: bool):
    n = draw(st.integers(4, 12))
    good = st.lists(st.tuples(*[floats(-0.5, 0.5)] * 3), min_size=n, max_size=n)
    options = [(6, st.just(CUBE)), (6, good), (2, good.map(lambda p: np.array(p, dtype=np.float64)))]
    if hostile:
        options.append((6, st.sampled_from(BAD_HULLS)))
    return pick(draw, *options)


@st.composite
def shapes(draw, hostile: bool, valid_type: bool = False, static: bool = True):
    """A shape constructor call (TriMesh only if `static`); hostile: with bad arguments, or not a shape at all."""
    kind = draw(st.integers(0, 6 if static else 5))
    npos = draw(st.sampled_from([99, 0]))
    size = {"wide": (1e-3, 50.0)}
    if kind == 0:
        return ShapeX("Sphere", (("radius", draw(scalar(0.05, 0.8, hostile, **size))),), npos)
    if kind == 1:
        return ShapeX("Box", (("half_extents", draw(vector(0.05, 0.8, hostile, **size))),), npos)
    if kind in (2, 3):
        cls = "Capsule" if kind == 2 else "Cylinder"
        return ShapeX(cls, (("half_height", draw(scalar(0.05, 0.8, hostile, **size))),
                            ("radius", draw(scalar(0.05, 0.5, hostile, **size)))), npos)
    if kind == 4:
        return ShapeX("ConvexHull", (("points", draw(hull_points(hostile))),), npos)
    if kind == 5:  # a closed mesh (a moving body decomposes it); an open one, or worse, is refused by name
        scale = draw(scalar(0.1, 1.0, hostile, **size))
        meshes = [(8, st.just((TETRA_V, TETRA_T))), (2, st.just((QUAD_V, QUAD_T)))]
        v, t = pick(draw, *(meshes + ([(6, st.sampled_from(BAD_MESHES))] if hostile else [])))
        if isinstance(scale, float) and (v is TETRA_V):
            v = [tuple(scale * c for c in p) for p in v]
        return ShapeX("Mesh", (("vertices", v), ("triangles", t)), npos)
    if hostile and not valid_type and draw(st.integers(0, 3)) == 0:
        return draw(st.sampled_from([Raw('"sphere"'), 1.0, Raw("tumble.World()"), Raw("tumble.Sphere")]))
    meshes = [(8, st.sampled_from([(TETRA_V, TETRA_T), (QUAD_V, QUAD_T)])),
              (2, st.just((np.array(QUAD_V), np.array(QUAD_T, dtype=np.int64))))]
    v, t = pick(draw, *(meshes + ([(6, st.sampled_from(BAD_MESHES))] if hostile else [])))
    return ShapeX("TriMesh", (("vertices", v), ("triangles", t)), npos)
