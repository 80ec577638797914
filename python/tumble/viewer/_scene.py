"""The viewer's 3-D scene (see ``_viewer``): each distinct collider shape meshed once and instanced per collider,
half-spaces as a gridded square, bodies without colliders as axes, particles, springs, joints and each frame's
contacts, all posed from a run's frame."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .._geometry import rotation_matrices
from .._mesh import half_space_plane, shape_mesh

if TYPE_CHECKING:
    from .._run import Run

# body colours (a body keeps its colour across frames and runs): saturated, so that they stand out of the grey
# ground and the light background
PALETTE = np.array([(231, 76, 60), (52, 152, 219), (46, 204, 113), (155, 89, 182), (241, 196, 15),
                    (230, 126, 34), (26, 188, 156), (236, 64, 122)], dtype=np.uint8)
GROUND = (190, 190, 185)
SPRING = (230, 140, 20)
JOINT = (120, 60, 200)
CONTACT = (220, 20, 20)
PARTICLE = (70, 70, 70)


# Most names shown at first: more would cover the scene (the "Names" box shows them all).
MAX_LABELS = 30


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The products a b of quaternions (..., 4) stored (w, x, y, z)."""
    aw, ax, ay, az = np.moveaxis(np.asarray(a, dtype=float), -1, 0)
    bw, bx, by, bz = np.moveaxis(np.asarray(b, dtype=float), -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def _z_to(n: np.ndarray) -> np.ndarray:
    """The quaternion (w, x, y, z) of the shortest rotation taking +z to the unit vector ``n``."""
    axis = np.cross((0.0, 0.0, 1.0), n)
    s, c = float(np.linalg.norm(axis)), float(n[2])
    if s < 1e-12:
        return np.array([1.0, 0.0, 0.0, 0.0]) if c > 0 else np.array([0.0, 1.0, 0.0, 0.0])
    half = 0.5 * math.atan2(s, c)
    return np.array([math.cos(half), *(math.sin(half) * axis / s)])


def _nice(x: float) -> float:
    """The number 1, 2 or 5 times a power of ten nearest below ``x`` (grid cells)."""
    p = 10.0 ** math.floor(math.log10(x))
    return max(m * p for m in (1.0, 2.0, 5.0) if m * p <= x)


def body_colors(run: "Run", bodies: int) -> np.ndarray:
    """(B, 3) sRGB colours (uint8) of the bodies: a body's own (given linear, as glTF and USD take it) or the
    palette's by its row."""
    out = PALETTE[np.arange(bodies) % len(PALETTE)].copy()
    for b in range(bodies):
        rgba = run.color(b)
        if rgba is not None:
            linear = np.asarray(rgba[:3], dtype=float)
            srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
            out[b] = np.round(255 * np.clip(srgb, 0.0, 1.0)).astype(np.uint8)
    return out


class Scene:
    """A run's scene on a viser server: the nodes built once, then posed at any frame by ``pose``."""

    def __init__(self, server: Any, run: "Run") -> None:
        self.run = run
        scene = server.scene
        bodies = run.body_positions.shape[1]
        shapes = [run.shapes[b] if b < len(run.shapes) else [] for b in range(bodies)]
        # colliders grouped by shape (its JSON): each group one mesh, an instance per collider
        groups: dict[str, tuple[Any, list[tuple[int, Any, Any]]]] = {}
        planes: list[tuple[int, Any, Any, Any]] = []
        radius = np.zeros(bodies)
        for b, colliders in enumerate(shapes):
            for shape, offset, orientation in colliders:
                if shape.kind == "half-space":
                    planes.append((b, shape, offset, orientation))
                    continue
                key = shape.__reduce__()[1][0]
                groups.setdefault(key, (shape, []))[1].append((b, offset, orientation))
        meshes = {key: shape_mesh(shape) for key, (shape, _) in groups.items()}
        for key, (_, members) in groups.items():
            extent = float(np.linalg.norm(meshes[key][0], axis=1).max(initial=0.0))
            for b, offset, _ in members:
                radius[b] = max(radius[b], extent + float(np.linalg.norm(offset)))
        self.center, self.size = _bounds(run, radius, [b for b, *_ in planes])
        size = self.size

        self.groups: list[tuple[Any, np.ndarray, np.ndarray, np.ndarray]] = []
        colours = body_colors(run, bodies)
        for i, (key, (shape, members)) in enumerate(groups.items()):
            rows = np.array([b for b, _, _ in members], dtype=np.int64)
            offsets = np.array([o for _, o, _ in members], dtype=float).reshape(-1, 3)
            rotations = np.array([q for _, _, q in members], dtype=float).reshape(-1, 4)
            handle = scene.add_batched_meshes_simple(
                f"/bodies/{shape.kind}_{i}", meshes[key][0], meshes[key][1],
                batched_wxyzs=np.tile((1.0, 0.0, 0.0, 0.0), (len(rows), 1)), batched_positions=np.zeros((len(rows), 3)),
                batched_colors=colours[rows], lod="off")
            self.groups.append((handle, rows, offsets, rotations))
        bare = np.array([b for b in range(bodies) if not shapes[b]], dtype=np.int64)
        self.axes = None if not len(bare) else (scene.add_batched_axes(
            "/bodies/axes", np.tile((1.0, 0.0, 0.0, 0.0), (len(bare), 1)), np.zeros((len(bare), 3)),
            axes_length=0.08 * size, axes_radius=0.006 * size), bare)
        for i, (b, shape, offset, orientation) in enumerate(planes):
            self._plane(scene, i, b, shape, offset, orientation)

        # each named body's name above it (shown while there are few enough to read: the "Names" box toggles them)
        named = [b for b in range(bodies) if b < len(run.names) and run.names[b] is not None]
        self.label_lift = radius
        self.labels = [(b, scene.add_label(f"/labels/body_{b}", str(run.names[b]), anchor="bottom-center",
                                           visible=len(named) <= MAX_LABELS)) for b in named]

        self.particles = None
        if run.particle_positions.shape[1]:
            self.particles = scene.add_point_cloud(
                "/particles", np.asarray(run.particle_positions[0], dtype=np.float32), PARTICLE,
                point_size=0.006 * size, point_shape="circle", precision="float32")
        self.links = None
        if run.links:
            colors = np.array([SPRING if kind == "spring" else JOINT for kind, _, _ in run.links], dtype=np.uint8)
            self.links = scene.add_line_segments(
                "/links", run.link_segments(0), np.repeat(colors[:, None, :], 2, axis=1), thickness=0.002 * size)
        self.contact_points = self.contact_normals = None
        if int(np.sum(run.contact_counts)):
            c = run.contact_points[:1]
            self.contact_points = scene.add_point_cloud(
                "/contacts/points", np.asarray(c[:, 0], dtype=np.float32), CONTACT, point_size=0.008 * size,
                point_shape="circle", precision="float32", visible=False)
            self.contact_normals = scene.add_line_segments(
                "/contacts/normals", self._normals(c), CONTACT, thickness=0.002 * size, visible=False)
        server.initial_camera.look_at = self.center
        server.initial_camera.position = self.center + size * np.array([0.35, -0.8, 0.5])
        server.initial_camera.near = max(1e-4, 1e-3 * size)
        server.initial_camera.far = max(1e3, 100.0 * size)

    def _plane(self, scene: Any, i: int, b: int, shape: Any, offset: Any, orientation: Any) -> None:
        """A half-space as an opaque square with a grid, under the scene (static: posed at the first frame)."""
        run = self.run
        # its boundary plane in the collider's frame, facing out of the solid side
        middle, normal = half_space_plane(shape)
        rotation = rotation_matrices(quat_mul(run.body_orientations[0, b], orientation))
        n = rotation @ normal
        point = (run.body_positions[0, b] + rotation_matrices(run.body_orientations[0, b]) @ np.asarray(offset, float)
                 + rotation @ middle)
        # the square's centre: the scene's centre projected onto the plane
        center = self.center - float(np.dot(self.center - point, n)) * n
        width = 3.0 * self.size + 2.0 * float(np.linalg.norm(center - point))
        cell = _nice(self.size / 10.0)
        scene.add_grid(f"/ground/plane_{i}", width, width, plane="xy", cell_size=cell, section_size=5 * cell,
                       cell_color=(160, 160, 155), section_color=(120, 120, 115), plane_color=GROUND,
                       plane_opacity=1.0, shadow_opacity=0.25, fade_distance=10.0 * width,
                       wxyz=_z_to(n), position=center)

    def _normals(self, contacts: np.ndarray) -> np.ndarray:
        return np.stack([contacts[:, 0], contacts[:, 0] + 0.04 * self.size * contacts[:, 1]], axis=1)

    def pose(self, k: int) -> None:
        """Poses every node at frame ``k``."""
        run = self.run
        positions, orientations = run.body_positions[k], run.body_orientations[k]
        rotations = rotation_matrices(orientations) if len(orientations) else np.zeros((0, 3, 3))
        for handle, rows, offsets, collider_rotations in self.groups:
            handle.batched_positions = positions[rows] + np.einsum("nij,nj->ni", rotations[rows], offsets)
            handle.batched_wxyzs = quat_mul(orientations[rows], collider_rotations)
        for b, label in self.labels:
            label.position = positions[b] + np.array([0.0, 0.0, self.label_lift[b]])
        if self.axes is not None:
            handle, rows = self.axes
            handle.batched_positions = positions[rows]
            handle.batched_wxyzs = orientations[rows]
        if self.particles is not None:
            self.particles.points = np.asarray(run.particle_positions[k], dtype=np.float32)
        if self.links is not None:
            self.links.points = run.link_segments(k)
        if self.contact_points is not None and self.contact_normals is not None:
            c = run.contacts(k)
            if len(c):
                self.contact_points.points = np.asarray(c[:, 0], dtype=np.float32)
                self.contact_normals.points = self._normals(c)
            self.contact_points.visible = self.contact_normals.visible = bool(len(c))


def _bounds(run: "Run", radius: np.ndarray, planes: list[int]) -> tuple[np.ndarray, float]:
    """The centre and size (the diagonal of the box holding every body, collider and particle over the run, at least
    0.5 m) of the scene; bodies whose only colliders are half-spaces do not count."""
    keep = np.array([b for b in range(run.body_positions.shape[1]) if b not in planes or radius[b] > 0], dtype=np.int64)
    lows, highs = [], []
    if len(keep) and run.frames:
        r = radius[keep][None, :, None]
        lows.append((run.body_positions[:, keep] - r).reshape(-1, 3))
        highs.append((run.body_positions[:, keep] + r).reshape(-1, 3))
    if run.particle_positions.shape[1] and run.frames:
        lows.append(run.particle_positions.reshape(-1, 3))
        highs.append(run.particle_positions.reshape(-1, 3))
    if not lows:
        return np.zeros(3), 1.0
    lo, hi = np.nanmin(np.concatenate(lows), axis=0), np.nanmax(np.concatenate(highs), axis=0)
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        return np.zeros(3), 1.0
    return (lo + hi) / 2, max(0.5, float(np.linalg.norm(hi - lo)))
