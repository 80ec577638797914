"""The deepest overlap of a scene of boxes on the ground z = 0, from the poses: the same measure as
``overlap.rs`` (which tumble's ``fast_scenes`` and the Rapier project include), for the Python peers. For each pair
of boxes whose bounding boxes meet, the separating-axis depth over the 15 axes of two boxes (exact for convex
polyhedra); for each box, how far its lowest corner is below the ground. An engine's own contacts are not used.
"""

from __future__ import annotations

import numpy as np


def _rotation(q: np.ndarray) -> np.ndarray:
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def box_depth(ha: np.ndarray, ra: np.ndarray, ta: np.ndarray, hb: np.ndarray, rb: np.ndarray, tb: np.ndarray) -> float:
    """How deep two boxes (half extents, rotation, centre) overlap (0 if they do not)."""
    axes = [ra[:, i] for i in range(3)] + [rb[:, i] for i in range(3)]
    for i in range(3):
        for j in range(3):
            c = np.cross(ra[:, i], rb[:, j])
            n = np.linalg.norm(c)
            if n > 1e-9:
                axes.append(c / n)
    d = tb - ta
    depth = np.inf
    for axis in axes:
        reach = np.sum(ha * np.abs(ra.T @ axis)) + np.sum(hb * np.abs(rb.T @ axis))
        overlap = reach - abs(d @ axis)
        if overlap <= 0.0:
            return 0.0
        depth = min(depth, overlap)
    return float(depth)


def deepest(boxes: list[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> float:
    """The deepest overlap among boxes given as (half extents, quaternion (w, x, y, z), centre) and the ground."""
    rots = [_rotation(np.asarray(q, dtype=float)) for _, q, _ in boxes]
    halves = [np.asarray(h, dtype=float) for h, _, _ in boxes]
    centres = [np.asarray(t, dtype=float) for _, _, t in boxes]
    reach = [np.abs(r) @ h for r, h in zip(rots, halves)]
    lo = np.array([t - e for t, e in zip(centres, reach)])
    hi = np.array([t + e for t, e in zip(centres, reach)])
    worst = max([max(0.0, float(e[2] - t[2])) for t, e in zip(centres, reach)] + [0.0])
    order = np.argsort(lo[:, 0])
    for k, i in enumerate(order):
        for j in order[k + 1:]:
            if lo[j, 0] > hi[i, 0]:
                break
            if all(lo[j, c] <= hi[i, c] and lo[i, c] <= hi[j, c] for c in (1, 2)):
                worst = max(worst, box_depth(halves[i], rots[i], centres[i], halves[j], rots[j], centres[j]))
    return worst
