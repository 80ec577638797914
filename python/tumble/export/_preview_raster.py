"""The preview's depth buffer, in numpy: triangles filled row by row into fragments (a pixel, a depth and the face it
shows), the nearest fragment kept at each pixel, edges found where neighbouring pixels show different faces, and
points and lines tested against the buffer so that what lies behind a face is not drawn. Pixel centres are at whole
coordinates, as Pillow draws."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class DepthBuffer:
    """What a frame's faces leave in a ``height`` x ``width`` picture, held over a window (the bounds of what they
    cover and a pixel round it) whose first pixel is at row ``top`` and column ``left``: at each of its pixels the
    face shown (-1 for none) and its depth (larger is nearer the viewer; -inf where no face is)."""

    face: np.ndarray
    depth: np.ndarray
    top: int
    left: int
    height: int
    width: int

    @classmethod
    def empty(cls, height: int, width: int) -> "DepthBuffer":
        """A picture without faces."""
        return cls(np.full((0, 0), -1, dtype=np.int64), np.zeros((0, 0)), 0, 0, height, width)

    def window(self) -> tuple[slice, slice]:
        """The window's rows and columns in the picture."""
        rows, columns = self.face.shape
        return slice(self.top, self.top + rows), slice(self.left, self.left + columns)

    def depth_at(self, rows: np.ndarray, columns: np.ndarray) -> np.ndarray:
        """The depth at pixels of the picture (-inf where no face is)."""
        r, c = rows - self.top, columns - self.left
        inside = (r >= 0) & (r < self.depth.shape[0]) & (c >= 0) & (c < self.depth.shape[1])
        out = np.full(len(r), -np.inf)
        out[inside] = self.depth[r[inside], c[inside]]
        return out


def _ranges(counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For items with ``counts`` parts each: the item of each part and its place (0, 1, ...) within its item."""
    owner = np.repeat(np.arange(len(counts)), counts)
    starts = np.cumsum(counts) - counts
    return owner, np.arange(int(counts.sum())) - starts[owner]


def spans(corners: np.ndarray, width: int, height: int) -> tuple[np.ndarray, ...]:
    """The rows of pixels that triangles cover: ``corners`` (T, 3, 3) holds each triangle's corners as pixel x, y
    and depth. A pixel is covered when its centre lies in the triangle (on its edge included, so that neighbours
    leave no gap); only the picture's pixels count. Returns for each span (a row of one triangle's pixels) its
    triangle, row, first column, length, depth at its first pixel and depth's step a pixel right."""
    # depth across each triangle's plane: z = a x + b y + c
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    # the corners top to bottom: the rows from the first to the last cross the long edge (0 to 2) on one side and
    # the edges 0 to 1, then 1 to 2, on the other
    ordered = np.take_along_axis(corners, np.argsort(corners[..., 1], axis=1)[..., None], axis=1)
    (x0, x1, x2), (y0, y1, y2) = ordered[..., 0].T, ordered[..., 1].T
    top, bottom = np.maximum(np.ceil(y0), 0), np.minimum(np.floor(y2), height - 1)
    keep = (np.abs(normal[:, 2]) > 1e-9) & (bottom >= top) & (ordered[..., 0].max(axis=1) >= 0)
    keep &= ordered[..., 0].min(axis=1) <= width - 1
    triangles = np.flatnonzero(keep)
    n = normal[keep]
    a, b = -n[:, 0] / n[:, 2], -n[:, 1] / n[:, 2]
    c = corners[keep, 0, 2] - a * corners[keep, 0, 0] - b * corners[keep, 0, 1]

    def slope(xa: np.ndarray, xb: np.ndarray, ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
        out: np.ndarray = np.where(yb > ya, (xb - xa) / np.where(yb > ya, yb - ya, 1.0), 0.0)[keep]
        return out

    long, upper, lower = slope(x0, x2, y0, y2), slope(x0, x1, y0, y1), slope(x1, x2, y1, y2)
    x0, x1, y0, y1, top = x0[keep], x1[keep], y0[keep], y1[keep], top[keep]
    tri, k = _ranges((bottom[keep] - top + 1).astype(np.int64))
    row = top[tri] + k
    down = row - y0[tri]
    across = x0[tri] + down * long[tri]
    side = np.where(row < y1[tri], x0[tri] + down * upper[tri], x1[tri] + (row - y1[tri]) * lower[tri])
    start = np.maximum(np.ceil(np.minimum(across, side)), 0)
    length = np.minimum(np.floor(np.maximum(across, side)), width - 1) - start + 1
    some = length > 0
    tri, row, start, length = tri[some], row[some], start[some], length[some].astype(np.int64)
    step = a[tri]
    return (triangles[tri], row.astype(np.int64), start.astype(np.int64), length, c[tri] + step * start + b[tri] * row,
            step)


def depth_buffer(corners: np.ndarray, faces: np.ndarray, width: int, height: int) -> DepthBuffer:
    """The nearest of the triangles ``corners`` (T, 3, 3: pixel x, y and depth) at each pixel, with the face
    ``faces[t]`` of each triangle: every pixel of every span with its depth, the nearest depth at each pixel kept,
    and the face of a pixel that has it."""
    triangle, row, start, length, depth, step = spans(corners, width, height)
    if not len(row):
        return DepthBuffer.empty(height, width)
    top, bottom = max(int(row.min()) - 1, 0), min(int(row.max()) + 1, height - 1)
    left, right = max(int(start.min()) - 1, 0), min(int((start + length).max()), width - 1)
    rows, columns = bottom - top + 1, right - left + 1
    offsets = np.cumsum(length) - length
    along = np.arange(int(length.sum()))  # the pixels of all spans in a row, each span's pixels counted from 0 ...
    pixels = along + np.repeat((row - top) * columns + start - left - offsets, length)
    z = np.repeat(depth - step * offsets, length) + np.repeat(step, length) * along  # ... once its start is taken off
    nearest = np.full(rows * columns, -np.inf)
    np.maximum.at(nearest, pixels, z)
    won = z >= nearest[pixels]
    shown = np.full(rows * columns, -1, dtype=np.int64)
    shown[pixels[won]] = np.repeat(faces[triangle], length)[won]
    return DepthBuffer(shown.reshape(rows, columns), nearest.reshape(rows, columns), top, left, height, width)


def outlines(buffer: DepthBuffer) -> np.ndarray:
    """Where to draw edges in the buffer's window: of two neighbouring pixels showing different faces (or a face and
    none), the nearer one, so that each face's outline is one pixel wide and a body's silhouette lies on the
    body."""
    face, depth = buffer.face, buffer.depth
    out = np.zeros(face.shape, dtype=bool)
    for axis in (0, 1):
        a = [slice(None), slice(None)]
        b = [slice(None), slice(None)]
        a[axis], b[axis] = slice(None, -1), slice(1, None)
        differ = face[tuple(a)] != face[tuple(b)]
        first_nearer = depth[tuple(a)] >= depth[tuple(b)]
        out[tuple(a)] |= differ & first_nearer
        out[tuple(b)] |= differ & ~first_nearer
    out &= face >= 0
    return out


def in_front(buffer: DepthBuffer, points: np.ndarray, tolerance: float) -> np.ndarray:
    """Which of ``points`` (N, 3: pixel x, y and depth) no face hides: not more than ``tolerance`` behind the face at
    their nearest pixel (points outside the picture count as in front)."""
    px, py = np.round(points[:, 0]), np.round(points[:, 1])
    inside = (px >= 0) & (px < buffer.width) & (py >= 0) & (py < buffer.height)
    out = np.ones(len(points), dtype=bool)
    ix, iy = px[inside].astype(np.int64), py[inside].astype(np.int64)
    out[inside] = points[inside, 2] >= buffer.depth_at(iy, ix) - tolerance
    return out


def clip_segments(ends: np.ndarray, width: int, height: int) -> np.ndarray:
    """The parts of the segments ``ends`` (S, 2, 3: pixel x, y and depth at each end) within the picture (a pixel of
    margin), depth interpolated; segments wholly outside are dropped."""
    start, delta = ends[:, 0], ends[:, 1] - ends[:, 0]
    t0, t1 = np.zeros(len(ends)), np.ones(len(ends))
    keep = np.ones(len(ends), dtype=bool)
    for axis, high in ((0, width), (1, height)):
        for p, q in ((-delta[:, axis], start[:, axis] + 1.0), (delta[:, axis], high - start[:, axis])):
            with np.errstate(divide="ignore", invalid="ignore"):
                r = q / p
            t0 = np.where(p < 0, np.maximum(t0, r), t0)
            t1 = np.where(p > 0, np.minimum(t1, r), t1)
            keep &= ~((p == 0) & (q < 0))
    keep &= t0 <= t1
    t0, t1 = t0[keep, None], t1[keep, None]
    return np.stack([start[keep] + t0 * delta[keep], start[keep] + t1 * delta[keep]], axis=1)


def line_pixels(buffer: DepthBuffer, ends: np.ndarray, tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """The pixels (rows, columns) of the segments ``ends`` (S, 2, 3: pixel x, y and depth at each end) that no face
    hides: each segment's part in the picture sampled a pixel apart, each sample tested as ``in_front``."""
    height, width = buffer.height, buffer.width
    ends = clip_segments(ends, width, height)
    if not len(ends):
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    steps = np.ceil(np.abs(ends[:, 1, :2] - ends[:, 0, :2]).max(axis=1)).astype(np.int64)
    segment, k = _ranges(steps + 1)
    t = (k / np.maximum(steps[segment], 1))[:, None]
    samples = ends[segment, 0] + t * (ends[segment, 1] - ends[segment, 0])
    seen = in_front(buffer, samples, tolerance)
    px, py = np.round(samples[seen, 0]), np.round(samples[seen, 1])
    inside = (px >= 0) & (px < width) & (py >= 0) & (py < height)
    return py[inside].astype(np.int64), px[inside].astype(np.int64)
