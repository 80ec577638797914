"""The rotation helpers animators reach for: ``tumble.quaternion_to_matrix``, ``tumble.up_axis`` and
``tumble.quaternion_to_euler``, against closed forms, round trips and (where Blender as a module is installed) Blender's
own ``mathutils``; and a die's face up read from a run by its handle."""

import math

import numpy as np
import pytest

import tumble

ORDERS = ["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"]
# float64 through a matrix and atan2: a few ulps of an angle of order 1
ROUNDING = 1e-12


def about(axis: str, angle) -> np.ndarray:
    """The quaternion(s) (w, x, y, z) of a turn by ``angle`` (scalar or (F,)) about the x, y or z axis."""
    angle = np.asarray(angle, dtype=float)
    q = np.zeros(angle.shape + (4,))
    q[..., 0] = np.cos(angle / 2)
    q[..., 1 + "xyz".index(axis)] = np.sin(angle / 2)
    return q


def product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The Hamilton product a b of quaternions (w, x, y, z): the turn b, then a."""
    w1, x1, y1, z1 = np.moveaxis(a, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(b, -1, 0)
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], axis=-1)


def from_euler(angles, order: str) -> np.ndarray:
    """The quaternion of Euler angles (about x, y, z) turned in ``order``: for "XYZ", x first, then y, then z."""
    angles = np.asarray(angles, dtype=float)
    q = about(order[0].lower(), angles[..., "XYZ".index(order[0])])
    for axis in order[1:]:
        q = product(about(axis.lower(), angles[..., "XYZ".index(axis)]), q)
    return q


def matrix_of_euler(angles, order: str) -> np.ndarray:
    """Blender's Euler matrix: for "XYZ", Rz @ Ry @ Rx."""
    def turn(axis, a):
        c, s = np.cos(a), np.sin(a)
        i, j = [(1, 2), (2, 0), (0, 1)]["XYZ".index(axis)]
        m = np.zeros(np.shape(a) + (3, 3))
        m[..., "XYZ".index(axis), "XYZ".index(axis)] = 1.0
        m[..., i, i], m[..., i, j], m[..., j, i], m[..., j, j] = c, -s, s, c
        return m

    angles = np.asarray(angles, dtype=float)
    out = turn(order[0], angles[..., "XYZ".index(order[0])])
    for axis in order[1:]:
        out = turn(axis, angles[..., "XYZ".index(axis)]) @ out
    return out


def random_quaternions(n: int, seed: int = 1) -> np.ndarray:
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def test_the_matrix_of_a_quaternion_is_the_closed_form_turn():
    a = 0.7
    c, s = math.cos(a), math.sin(a)
    np.testing.assert_allclose(tumble.quaternion_to_matrix(about("z", a)), [[c, -s, 0], [s, c, 0], [0, 0, 1]],
                               atol=ROUNDING)
    np.testing.assert_allclose(tumble.quaternion_to_matrix(about("x", a)), [[1, 0, 0], [0, c, -s], [0, s, c]],
                               atol=ROUNDING)
    np.testing.assert_allclose(tumble.quaternion_to_matrix(about("y", a)), [[c, 0, s], [0, 1, 0], [-s, 0, c]],
                               atol=ROUNDING)
    # vectorised over any leading shape; each matrix turns a vector as q v q* does
    q = random_quaternions(24).reshape(4, 6, 4)
    m = tumble.quaternion_to_matrix(q)
    assert m.shape == (4, 6, 3, 3)
    v = np.array([0.3, -1.2, 2.0])
    conjugate = q * [1, -1, -1, -1]
    turned = product(product(q, np.broadcast_to(np.r_[0.0, v], q.shape)), conjugate)[..., 1:]
    np.testing.assert_allclose(m @ v, turned, atol=ROUNDING * 10)  # ten products of order-1 terms
    np.testing.assert_allclose(m[1, 2], tumble.quaternion_to_matrix(list(q[1, 2])), atol=0)
    # a quaternion not of unit length is normalised
    np.testing.assert_allclose(tumble.quaternion_to_matrix(3.0 * q), m, atol=ROUNDING)


def test_the_matrix_refuses_what_is_no_quaternion():
    with pytest.raises(ValueError, match="`q`: expected quaternions"):
        tumble.quaternion_to_matrix([1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="`q`: a quaternion of length 0"):
        tumble.quaternion_to_matrix([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]])


def test_the_axis_pointing_up_in_closed_form():
    quarter = math.pi / 2
    assert tumble.up_axis([1.0, 0.0, 0.0, 0.0]) == "+z"
    assert isinstance(tumble.up_axis([1.0, 0.0, 0.0, 0.0]), str)
    cases = {  # a quarter turn about x takes the body's +y to the world's +z; about y, its -x
        "+y": about("x", quarter), "-y": about("x", -quarter), "-x": about("y", quarter), "+x": about("y", -quarter),
        "-z": about("x", math.pi), "+z": about("z", 2.0),
    }
    for name, q in cases.items():
        assert tumble.up_axis(q) == name
    # an array of orientations gives an array of names; nearly up is enough (0.6 rad from up)
    frames = np.array([about("x", 0.6), about("x", quarter - 0.6), about("y", math.pi - 0.6)])
    assert tumble.up_axis(frames).tolist() == ["+z", "+y", "-z"]
    assert tumble.up_axis(np.stack([frames, frames])).shape == (2, 3)
    # another up
    assert tumble.up_axis(about("z", quarter), up=(1.0, 0.0, 0.0)) == "-y"
    assert tumble.up_axis(about("z", quarter), up=(0.0, 0.0, -2.0)) == "-z"


def test_the_axis_pointing_up_refuses_bad_arguments():
    with pytest.raises(ValueError, match="`up`"):
        tumble.up_axis([1.0, 0.0, 0.0, 0.0], up=(0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="`up`"):
        tumble.up_axis([1.0, 0.0, 0.0, 0.0], up=(0.0, 1.0))
    with pytest.raises(ValueError, match="`q`: an orientation is not finite"):
        tumble.up_axis([math.nan, 0.0, 0.0, 0.0])


@pytest.mark.parametrize("tilt, face", [(0.6, "+z"), (0.95, "+y")])
def test_a_dropped_die_shows_the_face_it_falls_onto(tilt, face):
    """A die tilted about x on its edge falls back onto its bottom below 45 degrees and onto its side beyond."""
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground()
    die = w.add_body(tumble.Box(half_extents=(0.05, 0.05, 0.05)), density=1000.0,
                     position=(0.0, 0.0, 0.05 * (math.cos(tilt) + math.sin(tilt)) + 0.001),
                     orientation=tuple(about("x", tilt)))
    run = w.run(2.0, 1 / 30)
    up = tumble.up_axis(run.orientations_of(die))
    assert up[0] == ("+z" if tilt < math.pi / 4 else "+y") and up[-1] == face
    # it rests flat on that face: the soft contacts' small penetration tilts it by far less than a degree
    axis = tumble.quaternion_to_matrix(run.orientations_of(die)[-1])[:, "xyz".index(face[1])]
    assert axis[2] > math.cos(math.radians(1.0))


@pytest.mark.parametrize("order", ORDERS)
def test_euler_angles_of_a_composed_turn_are_its_angles(order):
    angles = np.array([0.3, -0.5, 1.1])  # about x, y, z; the middle one within a quarter turn
    np.testing.assert_allclose(tumble.quaternion_to_euler(from_euler(angles, order), order), angles, atol=ROUNDING)
    # the composition is Blender's: for XYZ, R = Rz @ Ry @ Rx
    np.testing.assert_allclose(tumble.quaternion_to_matrix(from_euler(angles, order)), matrix_of_euler(angles, order),
                               atol=ROUNDING)
    # a single turn about one axis is that angle alone
    for k, axis in enumerate("xyz"):
        want = np.zeros(3)
        want[k] = 2.5
        np.testing.assert_allclose(tumble.quaternion_to_euler(about(axis, 2.5), order), want, atol=ROUNDING)


@pytest.mark.parametrize("order", ORDERS)
def test_euler_angles_round_trip(order):
    q = random_quaternions(500)
    for continuous in (True, False):
        angles = tumble.quaternion_to_euler(q, order, continuous=continuous)
        assert angles.shape == (500, 3)
        np.testing.assert_allclose(matrix_of_euler(angles, order), tumble.quaternion_to_matrix(q), atol=ROUNDING)
    # frame by frame: each angle within half a turn, and the triple of the smaller angles (summed) of the two
    alone = tumble.quaternion_to_euler(q, order, continuous=False)
    assert np.abs(alone).max() <= math.pi
    middle = "XYZ".index(order[1])
    mirrored = alone + math.pi
    mirrored[:, middle] = math.pi - 2 * alone[:, middle]  # the other triple: (a + pi, pi - b, c + pi)
    mirrored[:, middle] = alone[:, middle] + math.pi - 2 * alone[:, middle]
    other = np.abs(np.remainder(mirrored + math.pi, 2 * math.pi) - math.pi).sum(axis=1)
    assert np.all(np.abs(alone).sum(axis=1) <= other + ROUNDING)
    # and back through quaternions: the same rotation (q or -q)
    back = from_euler(alone, order)
    np.testing.assert_allclose(np.abs(np.sum(back * q, axis=1)), 1.0, atol=ROUNDING)


def test_euler_angles_in_gimbal_lock():
    """The middle angle a quarter turn: the first and last axes line up; the last angle is 0, the first carries
    their sum, and the matrix is the same."""
    q = from_euler([0.4, math.pi / 2, 0.3], "XYZ")
    angles = tumble.quaternion_to_euler(q, "XYZ")
    # the lock's threshold (a cosine of 1e-9 taken as 0) bounds the error of the angles
    np.testing.assert_allclose(angles, [0.1, math.pi / 2, 0.0], atol=1e-8)
    np.testing.assert_allclose(matrix_of_euler(angles, "XYZ"), tumble.quaternion_to_matrix(q), atol=1e-8)


def test_euler_angles_are_continuous_over_frames():
    t = np.linspace(0.0, 10.0, 601)
    # spinning about z at 3 rad/s over a fixed tilt of 0.4 about x: R = Rz(3 t) Rx(0.4), Euler XYZ (0.4, 0, 3 t)
    spin = product(about("z", 3.0 * t), about("x", np.full_like(t, 0.4)))
    want = np.stack([np.full_like(t, 0.4), 0.0 * t, 3.0 * t], axis=1)
    # rounding grows with the angle (30 rad at the end): a few ulps of it
    np.testing.assert_allclose(tumble.quaternion_to_euler(spin, "XYZ"), want, atol=1e-12 * 30)
    alone = tumble.quaternion_to_euler(spin, "XYZ", continuous=False)
    np.testing.assert_allclose(np.cos(alone[:, 2]), np.cos(3.0 * t), atol=ROUNDING)
    assert np.abs(alone[:, 2]).max() <= math.pi, "frame by frame: within half a turn"
    # two turns about y: frame by frame the triple jumps (to (pi, pi - b, pi) and by whole turns); over frames it
    # stays (0, b, 0)
    b = np.linspace(0.0, 4 * math.pi, 1001)
    alone = tumble.quaternion_to_euler(about("y", b), "XYZ", continuous=False)
    assert np.abs(np.diff(alone, axis=0)).max() > 3.0
    turned = tumble.quaternion_to_euler(about("y", b), "XYZ")
    # through the lock (b = pi/2, 3 pi/2, ...) the first and last angles come from cosines down to 1e-9 there, the
    # matrix's rounding over them
    np.testing.assert_allclose(turned, np.stack([0 * b, b, 0 * b], axis=1), atol=1e-7)
    # frames along the first axis of an (F, B, 4) array, each body on its own
    both = tumble.quaternion_to_euler(np.stack([spin, spin[::-1]], axis=1), "XYZ")
    np.testing.assert_allclose(both[:, 0], want, atol=1e-12 * 30)
    # a frame that is not finite stays so and the frames after it carry on
    broken = spin.copy()
    broken[300] = np.nan
    angles = tumble.quaternion_to_euler(broken, "XYZ")
    assert np.isnan(angles[300]).all()
    np.testing.assert_allclose(np.delete(angles, 300, axis=0), np.delete(want, 300, axis=0), atol=1e-12 * 30)


def test_euler_order_is_checked():
    with pytest.raises(ValueError, match="`order`: expected one of 'XYZ'"):
        tumble.quaternion_to_euler([1.0, 0.0, 0.0, 0.0], "xyz")  # type: ignore[arg-type]


def tumbling(frames: int = 1201) -> np.ndarray:
    """A tumbling body's orientations: a spin about z, a nodding about x and a turn about y, through gimbal lock."""
    t = np.linspace(0.0, 10.0, frames)
    return product(product(about("z", 3.0 * t), about("x", 1.4 * np.sin(1.3 * t))), about("y", 2.1 * t))


@pytest.mark.parametrize("order", ORDERS)
def test_euler_angles_as_blenders_mathutils_gives_them(order):
    pytest.importorskip("bpy", reason="Blender as a module (the `blender` extra) brings mathutils")
    from mathutils import Quaternion

    q = random_quaternions(2000)
    mine = tumble.quaternion_to_euler(q, order, continuous=False)
    theirs = np.array([tuple(Quaternion(tuple(x)).to_euler(order)) for x in q])
    # mathutils works in float32: an angle's error is a few epsilons (1.2e-7) over the middle angle's cosine
    cosine = np.cos(mine[:, "XYZ".index(order[1])])
    assert (np.abs(mine - theirs).max(axis=1) * cosine).max() < 1e-6
    # frames chained as Blender's bake of Euler rotations does: each frame compatible with the last
    frames = tumbling()
    chained, last = [], None
    for x in frames:
        e = Quaternion(tuple(x)).to_euler(order, last) if last is not None else Quaternion(tuple(x)).to_euler(order)
        chained.append(tuple(e))
        last = e
    # float32 again: 6e-8 of an angle that grows to about 40 rad, and a few epsilons near the lock
    np.testing.assert_allclose(tumble.quaternion_to_euler(frames, order), np.array(chained), rtol=2e-7, atol=5e-6)
