"""Small geometry helpers shared by the plots, previews, viewer and exports: rotations, and the springs and joints
as line segments."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

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
