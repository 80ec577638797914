"""Kinematic bodies' paths: a function of time sampled into the keyframes ``World.add_body(keyframes=...)`` takes."""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import numpy.typing as npt


def keyframes_from(
    f: Callable[[float], Any], times: npt.ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Samples a path given as a function of time into keyframes: ``f(t)`` returns a position (3,) or a pair
    (position (3,), orientation (4,) as w, x, y, z). Returns ``(times, positions, orientations)`` for
    ``World.add_body(shape, keyframes=...)``; between the samples the body moves linearly and turns at a constant
    rate, so sample as finely as the path bends (the path is followed exactly at the sample times)."""
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"invalid argument `times`: expected a non-empty 1-D array, got shape {t.shape}")
    positions = np.empty((t.size, 3))
    orientations = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    for k, tk in enumerate(t):
        pose = f(float(tk))
        if isinstance(pose, tuple) and len(pose) == 2:
            positions[k], orientations[k] = np.asarray(pose[0], dtype=float), np.asarray(pose[1], dtype=float)
        else:
            positions[k] = np.asarray(pose, dtype=float)
    return t, positions, orientations
