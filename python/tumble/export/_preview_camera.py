"""The preview's camera: orthographic, z up, looking from a direction at a target. By default it looks down at the
scene from the side (azimuth -55 degrees, elevation 22), framed on the bounds of everything that moves; the preview's
``camera`` argument sets where it looks from and at, and ``zoom`` enlarges the picture about its middle."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

TITLE_BAND = 26  # px at the top for the scene's name and time
# The default view, in degrees: from the scene to the camera, turned from +x towards +y and raised above the floor.
AZIMUTH, ELEVATION = -55.0, 22.0
# What a ``camera`` mapping may hold.
CAMERA_KEYS = ("position", "target")


@dataclass
class Camera:
    """An orthographic camera: ``view`` turns world vectors into (right, up, towards the viewer); a world point p
    lands at pixel (cx + scale * right, cy - scale * up)."""

    view: np.ndarray
    centre: np.ndarray
    scale: float
    width: int
    height: int

    def project(self, points: np.ndarray) -> np.ndarray:
        """Pixel coordinates and depth (N, 3) of world points (N, 3); larger depth is nearer the viewer."""
        c = (np.asarray(points, dtype=float).reshape(-1, 3) - self.centre) @ self.view.T
        out: np.ndarray = np.empty_like(c)
        out[:, 0] = self.width / 2 + self.scale * c[:, 0]
        out[:, 1] = TITLE_BAND + (self.height - TITLE_BAND) / 2 - self.scale * c[:, 1]
        out[:, 2] = c[:, 2]
        return out


def towards_from(azimuth: float = AZIMUTH, elevation: float = ELEVATION) -> np.ndarray:
    """The unit vector from the scene to a camera at ``azimuth`` and ``elevation`` (degrees)."""
    a, e = np.radians(azimuth), np.radians(elevation)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def view_axes(towards: np.ndarray) -> np.ndarray:
    """The rows right, up and ``towards`` (unit, from the scene to the camera) of a view with z up: right is
    horizontal. Looking straight down, right is +x and up +y (straight up, right +x and up -y); within a millionth of
    a radian of that counts as straight."""
    towards = np.asarray(towards, dtype=float) / np.linalg.norm(towards)
    right = np.cross([0.0, 0.0, 1.0], towards)
    if np.linalg.norm(right) < 1e-6:  # vertical, to rounding (a target a micrometre off a metre's height)
        right = np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    return np.array([right, np.cross(towards, right), towards])


def frame_camera(points: np.ndarray, size: int, position: np.ndarray | None = None,
                 target: np.ndarray | None = None, zoom: float = 1.0) -> Camera:
    """A camera looking at ``points`` (the scene's extent) from the default view's direction, or from ``position``
    towards ``target`` (default: the middle of the points' bounds), scaled so that the points fill the picture:
    centred on the middle of their extent, or on ``target`` when given, the extent fitted about it; ``zoom`` then
    enlarges the picture about its middle. The picture's longer side is ``size`` pixels and its shape follows the
    scene's (the shorter side between half and all of the longer), so that a long row of bodies or a hanging chain
    is not a thin strip in a square."""
    points = np.asarray(points, dtype=float)
    if position is None:
        towards = towards_from()
    else:
        aim = (points.min(axis=0) + points.max(axis=0)) / 2 if target is None else target
        towards = np.asarray(position, dtype=float) - aim
        if np.linalg.norm(towards) < 1e-9:
            raise ValueError("invalid argument `camera`: its position must differ from the middle of the scene it "
                             f"looks at, got {np.asarray(position).tolist()} (give a `target`)")
    view = view_axes(towards)
    c = points @ view.T
    if target is None:
        middle = np.array([(c[:, 0].min() + c[:, 0].max()) / 2, (c[:, 1].min() + c[:, 1].max()) / 2, 0.0])
        span_x, span_y = float(np.ptp(c[:, 0])), float(np.ptp(c[:, 1]))
    else:
        t = np.asarray(target, dtype=float) @ view.T
        middle = np.array([t[0], t[1], 0.0])
        span_x, span_y = 2.0 * float(np.abs(c[:, 0] - t[0]).max()), 2.0 * float(np.abs(c[:, 1] - t[1]).max())
    span_x, span_y = max(span_x, 1e-3), max(span_y, 1e-3)
    if span_x >= span_y:
        width, height = size, int(np.clip(size * span_y / span_x, 0.5 * size, size))
    else:
        width, height = int(np.clip(size * span_x / span_y, 0.5 * size, size)), size
    width += width % 2
    height += TITLE_BAND + height % 2
    scale = zoom * 0.92 * min(width / span_x, (height - TITLE_BAND) / span_y)
    return Camera(view, middle @ view, scale, width, height)


def _point(value: Any, what: str) -> np.ndarray:
    """``value`` as a finite 3-vector, or a ValueError naming ``camera`` and ``what``."""
    try:
        out = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        out = np.zeros(0)
    if out.shape != (3,) or not np.isfinite(out).all():
        raise ValueError(f"invalid argument `camera`: its {what} must be three finite numbers (x, y, z in metres), "
                         f"got {value!r}")
    return out


def camera_view(camera: Any) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The position and target of a preview's ``camera`` argument: None (the default view: (None, None)), a
    mapping with ``position`` and optionally ``target`` (None: the middle of the scene), or an object with those
    attributes. Raises ValueError naming ``camera`` for anything else."""
    if camera is None:
        return None, None
    if isinstance(camera, Mapping):
        unknown = [k for k in camera if k not in CAMERA_KEYS]
        if unknown:
            raise ValueError(f"invalid argument `camera`: it takes {' and '.join(CAMERA_KEYS)}, got {unknown[0]!r}")
        position, target = camera.get("position"), camera.get("target")
    elif hasattr(camera, "position"):
        position, target = camera.position, getattr(camera, "target", None)
    else:
        raise ValueError("invalid argument `camera`: None, or a mapping (or object) with a `position` and "
                         f"optionally a `target`, got {camera!r}")
    if position is None:
        raise ValueError("invalid argument `camera`: it needs a `position` (where it looks from)")
    at = _point(position, "position")
    aim = None if target is None else _point(target, "target")
    if aim is not None and np.linalg.norm(at - aim) <= 1e-9 * max(1.0, float(np.abs(at).max())):
        raise ValueError(f"invalid argument `camera`: its position must differ from its target, got {at.tolist()}")
    return at, aim


def check_zoom(zoom: Any) -> float:
    """``zoom`` as a float: a finite number above 0 (2 draws everything twice as large about the picture's middle).
    Raises ValueError naming ``zoom`` otherwise."""
    if isinstance(zoom, bool) or not isinstance(zoom, (int, float, np.integer, np.floating)):
        raise ValueError(f"invalid argument `zoom`: a number above 0 (1 frames the scene), got {zoom!r}")
    if not (np.isfinite(zoom) and zoom > 0):
        raise ValueError(f"invalid argument `zoom`: a finite number above 0 (1 frames the scene), got {zoom!r}")
    return float(zoom)
