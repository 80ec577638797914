"""Small geometry helpers shared by the plots, previews, viewer and exports: rotations, and the springs and joints
as line segments; and the public ones animators reach for (``tumble.quaternion_to_matrix``, ``tumble.up_axis``,
``tumble.quaternion_to_euler``), each over one quaternion or an array of them, (w, x, y, z) as runs store them."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from ._run import Run


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def rotation_matrices(q: np.ndarray) -> np.ndarray:
    """The rotation matrices (..., 3, 3) of unit quaternions (..., 4) stored (w, x, y, z)."""
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=float), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=-2,
    )


# One end of a spring or joint: ("particle", row, unused), ("body", row, point in the body frame) or ("world", -1,
# world point); a link is its kind ("spring", "ball", "hinge", ...) and its two ends.
LinkEnd = tuple[str, int, tuple[float, float, float]]
Link = tuple[str, LinkEnd, LinkEnd]


def normal_links(links: list[Any]) -> list[Link]:
    """Links as the world lists them (``World._links``) or as read back from JSON, in one form of tuples."""
    def end(e: Any) -> LinkEnd:
        kind, row, point = e
        return (str(kind), int(row), (float(point[0]), float(point[1]), float(point[2])))

    return [(str(k), end(a), end(b)) for k, a, b in links]


def link_segments(run: "Run", frame: int) -> np.ndarray:
    """The run's springs and joints at ``frame`` as (L, 2, 3) segments: each end a particle's position, a body's
    point carried by its pose, or a fixed world point; a joint that has broken by then (``run.link_ends``) is a
    segment of no length at its second end."""
    out = np.zeros((len(run.links), 2, 3))
    ended = getattr(run, "link_ends", {})
    for i, (_, *ends) in enumerate(run.links):
        broken = i in ended and run.times[frame] >= ended[i]
        for j, (kind, row, point) in enumerate(ends[1:] * 2 if broken else ends):
            if kind == "particle":
                out[i, j] = run.particle_positions[frame, row]
            elif kind == "body":
                out[i, j] = run.body_positions[frame, row] + rotation_matrix(run.body_orientations[frame, row]) @ point
            else:
                out[i, j] = point
    return out


# Blender's Euler orders: the axes in the order the rotations apply ("XYZ": about x first, then y, then z).
EulerOrder = Literal["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"]
# Blender's table (math_rotation.cc, rotOrders): each order's axes i, j, k and whether they are an odd permutation.
_ORDERS: dict[str, tuple[tuple[int, int, int], bool]] = {
    "XYZ": ((0, 1, 2), False), "XZY": ((0, 2, 1), True), "YXZ": ((1, 0, 2), True),
    "YZX": ((1, 2, 0), False), "ZXY": ((2, 0, 1), False), "ZYX": ((2, 1, 0), True),
}
# Below this cosine of the middle angle the first and last axes line up (gimbal lock): the last angle is taken as 0
# and the first carries the turn, as Blender does (its threshold is 16 float32 epsilons; this one, float64's, keeps
# each angle's error from the matrix's rounding (1e-16 over the cosine) below 1e-7 rad).
_LOCKED = 1e-9
_AXIS_NAMES = np.array([["-x", "-y", "-z"], ["+x", "+y", "+z"]])
_TURN = 2.0 * np.pi


def _unit_quaternions(q: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """``q`` as float quaternions (..., 4) of unit length; ValueError naming ``q`` for another shape or a zero one."""
    a = np.asarray(q, dtype=float)
    if a.ndim == 0 or a.shape[-1] != 4:
        raise ValueError(f"invalid argument `q`: expected quaternions (w, x, y, z) of shape (4,) or (..., 4), got "
                         f"shape {a.shape}")
    norm = np.linalg.norm(a, axis=-1, keepdims=True)
    if np.any(norm == 0.0):
        raise ValueError("invalid argument `q`: a quaternion of length 0 is no rotation")
    unit: npt.NDArray[np.float64] = a / norm
    return unit


def quaternion_to_matrix(q: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """The rotation matrix (3, 3) of a quaternion (w, x, y, z), scalar first as runs store them, or the matrices
    (..., 3, 3) of an array of them (..., 4), such as ``run.orientations_of(body)`` (F, 4). The matrix turns a body's
    local coordinates into world axes: its columns are the body's x, y and z axes in the world. A quaternion not of
    unit length is normalised; one of length 0 raises ValueError, as does a last axis that is not 4 long."""
    return rotation_matrices(_unit_quaternions(q))


def up_axis(q: npt.ArrayLike, up: npt.ArrayLike = (0.0, 0.0, 1.0)) -> str | npt.NDArray[np.str_]:
    """Which of a body's local axes points most nearly along ``up`` (world +z by default), as a name: ``"+x"``,
    ``"-x"``, ``"+y"``, ``"-y"``, ``"+z"`` or ``"-z"`` — the face a die shows on top is the one whose outward normal
    is that axis. ``q`` is the body's orientation (w, x, y, z): one quaternion gives a ``str``, an array (..., 4)
    such as ``run.orientations_of(die)`` an array of names (...,) of the same leading shape. An exact tie (a body
    balanced on an edge or a corner) goes to the first of x, y, z. ValueError for an orientation that is not finite
    (a run that diverged) or an ``up`` that is not a finite, non-zero 3-vector."""
    turn = quaternion_to_matrix(q)
    if not np.all(np.isfinite(turn)):
        raise ValueError("invalid argument `q`: an orientation is not finite")
    direction = np.asarray(up, dtype=float)
    if direction.shape != (3,) or not np.all(np.isfinite(direction)) or not np.any(direction):
        raise ValueError(f"invalid argument `up`: expected a finite, non-zero 3-vector, got {up!r}")
    local = np.einsum("...ji,j->...i", turn, direction)  # up in the body's axes: R^T up
    axis = np.argmax(np.abs(local), axis=-1)
    positive = np.take_along_axis(local, axis[..., None], axis=-1)[..., 0] > 0.0
    names = _AXIS_NAMES[positive.astype(int), axis]
    return str(names) if names.ndim == 0 else names


def _euler_pair(turn: npt.NDArray[np.float64],
                order: str) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """The two Euler angle triples (..., 3) (angles about x, y, z) of the rotation matrices ``turn``, in Blender's
    way (mat3_normalized_to_eulo2), and where they are in gimbal lock (...,): the second is the first with its
    middle angle mirrored through a quarter turn and the others turned by half a turn; in gimbal lock (and where
    the matrix is not finite) the two are one."""
    (i, j, k), odd = _ORDERS[order]

    def m(a: int, b: int) -> npt.NDArray[np.float64]:  # Blender's mat[a][b]: column a, row b
        return turn[..., b, a]

    cy = np.hypot(m(i, i), m(i, j))
    free = cy > _LOCKED
    first, second = np.empty(turn.shape[:-1]), np.empty(turn.shape[:-1])
    first[..., i] = np.where(free, np.arctan2(m(j, k), m(k, k)), np.arctan2(-m(k, j), m(j, j)))
    first[..., j] = np.arctan2(-m(i, k), cy)
    first[..., k] = np.where(free, np.arctan2(m(i, j), m(i, i)), np.where(np.isnan(cy), np.nan, 0.0))
    second[..., i] = np.where(free, np.arctan2(-m(j, k), -m(k, k)), first[..., i])
    second[..., j] = np.where(free, np.arctan2(-m(i, k), -cy), first[..., j])
    second[..., k] = np.where(free, np.arctan2(-m(i, j), -m(i, i)), first[..., k])
    return (-first, -second, ~free) if odd else (first, second, ~free)


def _wrap(angles: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Angles brought within half a turn of 0."""
    return angles - _TURN * np.round(angles / _TURN)


def quaternion_to_euler(q: npt.ArrayLike, order: EulerOrder = "XYZ",
                        continuous: bool = True) -> npt.NDArray[np.float64]:
    """Euler angles (..., 3) in radians of quaternions (..., 4) (w, x, y, z), in Blender's convention: the angles
    about x, y and z in that order whatever ``order`` is (as ``rotation_euler`` holds them), with ``order`` naming
    the axes in the order the rotations apply — ``"XYZ"`` turns about x first, then y, then z: R = Rz @ Ry @ Rx.
    ``order`` is one of ``"XYZ"``, ``"XZY"``, ``"YXZ"``, ``"YZX"``, ``"ZXY"``, ``"ZYX"`` (Blender's
    ``rotation_mode`` names).

    A rotation has two Euler triples (and any angle plus whole turns). Each quaternion alone (one quaternion, or
    ``continuous=False``) gets the triple of the smaller angles, as ``mathutils.Quaternion.to_euler(order)`` gives.
    With ``continuous`` (the default) an array is taken as frames along its first axis, and each frame after the
    first gets the triple, and the whole turns, nearest the frame before, as Blender's ``to_euler(order,
    compatible)`` chained frame to frame gives: F-curves without jumps of a turn or flips, so that a spinning body's
    angle keeps growing. In gimbal lock (the middle angle a quarter turn) the last angle is 0 and the first carries
    the turn, as in Blender. A frame that is not finite stays so without breaking the frames after it."""
    if order not in _ORDERS:
        raise ValueError(f"invalid argument `order`: expected one of {', '.join(map(repr, _ORDERS))}, got {order!r}")
    first, second, locked = _euler_pair(quaternion_to_matrix(q), order)
    smaller = np.abs(second).sum(axis=-1) < np.abs(first).sum(axis=-1)
    if not continuous or first.ndim == 1 or len(first) == 0:
        return np.where(smaller[..., None], second, first)
    # The second triple is the first's mirror, a map that keeps the distance between triples (summed over the
    # angles, whole turns aside): from a frame to the next, the branch changes where the next frame's other triple
    # is nearer, whichever branch the frame is on; the branches of the frames since the first are those changes
    # summed (exclusive or). A frame in gimbal lock has one triple, on both branches: the frames after it count
    # their changes from it.
    def distance(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        apart: npt.NDArray[np.float64] = np.abs(_wrap(a - b)).sum(axis=-1)
        return apart

    switch = distance(second[1:], first[:-1]) < distance(first[1:], first[:-1])
    changes = np.concatenate([smaller[:1], switch], axis=0)
    summed = np.logical_xor.accumulate(changes, axis=0)
    frame = np.arange(len(first)).reshape((-1,) + (1,) * (first.ndim - 2))
    last_lock = np.maximum.accumulate(np.where(locked, frame, -1), axis=0)
    at_lock = np.take_along_axis(summed, np.maximum(last_lock, 0), axis=0) & (last_lock >= 0)
    angles = np.where((summed ^ at_lock)[..., None], second, first)
    # whole turns: each frame within half a turn of the one before (np.unwrap, where a frame that is not finite
    # adds no turns)
    turns = np.nan_to_num(np.round(np.diff(angles, axis=0) / _TURN), nan=0.0, posinf=0.0, neginf=0.0)
    angles[1:] -= _TURN * np.cumsum(turns, axis=0)
    return angles
