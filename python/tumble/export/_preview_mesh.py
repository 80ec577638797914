"""The geometry a preview draws, gathered once per run: every collider's faces in its body's frame (polygons with
their triangles and normals), each body's colour, the floor, and the points that frame the camera."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .._geometry import link_segments, rotation_matrices, rotation_matrix
from .._mesh import PREVIEW, collider_mesh, half_space_plane

if TYPE_CHECKING:
    from .._run import Run

# The colours of bodies given none (sRGB): the first, grey, for bodies that do not move, the others in turn for
# those that do.
BODY_COLOURS = [(140, 140, 145), (66, 133, 244), (234, 140, 50), (52, 168, 83), (171, 71, 188), (0, 172, 193),
                (219, 68, 55), (158, 157, 36), (121, 85, 72), (236, 64, 122)]


@dataclass
class Meshes:
    """All bodies' faces in one set of arrays: vertices in their body's frame and the body of each; per face its
    corners (a loop of vertex indices), body and normal (body frame); the triangles (vertex indices) that fill the
    faces and the face of each. A face is a set of coplanar
    triangles joined along their shared edges (a box has six), so that it is shaded as one with its outline.
    ``colours`` holds each body's colour (sRGB, (B, 3)); ``planes`` each half-space as (body, point, normal) in
    the world at the first frame; ``bare`` the bodies without shapes; ``moving`` whether each body moves."""

    vertices: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    vertex_body: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    faces: list[list[int]] = field(default_factory=list)
    face_body: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    normals: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    triangles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), dtype=np.int64))
    triangle_face: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    colours: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), dtype=np.uint8))
    planes: list[tuple[int, np.ndarray, np.ndarray]] = field(default_factory=list)
    moving: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    bare: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))


def feature_edges(v: np.ndarray, triangles: np.ndarray) -> set[tuple[int, int]]:
    """The mesh's edges that bound a face: on one triangle only, or between triangles that are not coplanar (a box's
    face diagonals are left out)."""
    normals: dict[tuple[int, int], list[np.ndarray]] = {}
    for tri in triangles:
        n = np.cross(v[tri[1]] - v[tri[0]], v[tri[2]] - v[tri[0]])
        n = n / (np.linalg.norm(n) or 1.0)
        for a, c in zip(tri, np.roll(tri, 1)):
            normals.setdefault((min(int(a), int(c)), max(int(a), int(c))), []).append(n)
    return {e for e, ns in normals.items() if len(ns) == 1 or any(np.dot(ns[0], m) < 1 - 1e-6 for m in ns[1:])}


def polygon_faces(v: np.ndarray, triangles: np.ndarray) -> tuple[list[list[int]], list[list[int]]]:
    """The mesh's faces as loops of vertex indices, and the triangles of each: triangles joined across edges that
    bound no face (coplanar neighbours), each group's outline followed around; a group whose outline is not one loop
    stays triangles."""
    bounding = feature_edges(v, triangles)
    parent = list(range(len(triangles)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    owner: dict[tuple[int, int], int] = {}
    for t, tri in enumerate(triangles.tolist()):
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            key = (min(a, b), max(a, b))
            if key in bounding:
                continue
            if key in owner:
                parent[root(t)] = root(owner[key])
            else:
                owner[key] = t
    groups: dict[int, list[int]] = {}
    for t in range(len(triangles)):
        groups.setdefault(root(t), []).append(t)
    faces, filled = [], []
    for members in groups.values():
        directed = [(a, b) for t in members for a, b in zip(triangles[t], np.roll(triangles[t], -1))]
        inner = {(a, b) for a, b in directed if (b, a) in set(directed)}
        outline = {int(a): int(b) for a, b in directed if (a, b) not in inner}
        loop = [next(iter(outline))] if outline else []
        while loop and outline.get(loop[-1]) not in (None, loop[0]) and len(loop) <= len(outline):
            loop.append(outline[loop[-1]])
        if len(loop) == len(outline) and len(outline) == len([e for e in directed if e not in inner]):
            faces.append(loop)
            filled.append(members)
        else:
            faces.extend([int(x) for x in triangles[t]] for t in members)
            filled.extend([t] for t in members)
    return faces, filled


def srgb(linear: tuple[float, ...]) -> tuple[int, int, int]:
    """A linear RGB(A) colour (as bodies are given one) in 8-bit sRGB, as a picture shows it; alpha is left out."""
    c = np.clip(np.asarray(linear[:3], dtype=float), 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    r, g, b = (int(v) for v in np.round(255 * s))
    return (r, g, b)


def body_colours(run: "Run", moving: np.ndarray) -> np.ndarray:
    """Each body's colour (B, 3), sRGB: its own where it was given one, else grey for a body that does not move and
    the palette's colours in turn for those that do."""
    out = np.zeros((len(moving), 3), dtype=np.uint8)
    for b in range(len(moving)):
        given = run.color(b)
        out[b] = srgb(given) if given is not None else BODY_COLOURS[1 + b % (len(BODY_COLOURS) - 1) if moving[b] else 0]
    return out


def gather_meshes(run: "Run") -> Meshes:
    """The run's colliders as faces (see ``Meshes``); spheres and round shapes coarsely tessellated."""
    out = Meshes()
    bodies = run.body_positions.shape[1]
    moving = np.array([bool(np.ptp(run.body_positions[:, b], axis=0).any()
                            or np.ptp(run.body_orientations[:, b], axis=0).any()) for b in range(bodies)], dtype=bool)
    out.moving = moving
    vertices: list[np.ndarray] = []
    vertex_body: list[int] = []
    normals, face_body, triangles, triangle_face = [], [], [], []
    base = 0
    for b in range(bodies):
        for shape, offset, orientation in run.shapes[b] if b < len(run.shapes) else []:
            if shape.kind == "half-space":
                middle, normal = half_space_plane(shape)
                r = rotation_matrix(np.asarray(orientation, dtype=float))
                rb = rotation_matrix(run.body_orientations[0, b])
                point = run.body_positions[0, b] + rb @ (np.asarray(offset, dtype=float) + r @ middle)
                out.planes.append((b, point, rb @ r @ normal))
                continue
            v, t = collider_mesh(shape, offset, orientation, PREVIEW)
            t = np.asarray(t, dtype=np.int64)
            faces, filled = polygon_faces(v, t)
            for f, members in zip(faces, filled):
                corners = v[t[members]]  # the face's normal from its triangles: a corner of its outline may be reflex
                n = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]).sum(axis=0)
                normals.append(n / (np.linalg.norm(n) or 1.0))
                triangle_face.extend([len(out.faces)] * len(members))
                triangles.append(t[members] + base)
                out.faces.append([base + i for i in f])
            vertices.append(v)
            vertex_body.extend([b] * len(v))
            face_body.extend([b] * len(faces))
            base += len(v)
    out.bare = np.array([b for b in range(bodies) if not (run.shapes[b] if b < len(run.shapes) else [])],
                        dtype=np.int64)
    if out.faces:
        out.vertices, out.vertex_body = np.concatenate(vertices), np.asarray(vertex_body, dtype=np.int64)
        out.normals, out.face_body = np.asarray(normals), np.asarray(face_body, dtype=np.int64)
        out.triangles, out.triangle_face = np.concatenate(triangles), np.asarray(triangle_face, dtype=np.int64)
    out.colours = body_colours(run, moving)
    return out


def scene_points(run: "Run", meshes: Meshes, samples: int = 60) -> np.ndarray:
    """Points spanning the scene over the run: the moving bodies' vertices and the particles at up to ``samples``
    frames, the still bodies' vertices, and the springs' and joints' ends (bodies without shapes count by their
    centres). Never empty: an empty scene spans a metre around the origin."""
    frames = np.unique(np.linspace(0, run.frames - 1, min(samples, run.frames)).round().astype(int))
    points = [run.particle_positions[frames].reshape(-1, 3)]
    shaped = np.zeros(run.body_positions.shape[1], dtype=bool)
    shaped[meshes.vertex_body] = True
    for b in np.flatnonzero(~shaped):
        if not any(body == b for body, _, _ in meshes.planes):
            points.append(run.body_positions[frames, b])
    if len(meshes.vertices):
        still = ~meshes.moving[meshes.vertex_body]
        r = rotation_matrices(run.body_orientations[0])[meshes.vertex_body[still]]
        points.append(np.einsum("nij,nj->ni", r, meshes.vertices[still])
                      + run.body_positions[0][meshes.vertex_body[still]])
        mover = meshes.moving[meshes.vertex_body]
        for f in frames if mover.any() else []:
            r = rotation_matrices(run.body_orientations[f])[meshes.vertex_body[mover]]
            points.append(np.einsum("nij,nj->ni", r, meshes.vertices[mover])
                          + run.body_positions[f][meshes.vertex_body[mover]])
    if run.links:
        points.extend(link_segments(run, int(f)).reshape(-1, 3) for f in frames)
    out = np.concatenate(points) if points else np.zeros((0, 3))
    if len(out) == 0:
        return np.array([[-0.5, -0.5, 0.0], [0.5, 0.5, 1.0]])
    lo, hi = out.min(axis=0), out.max(axis=0)
    pad = np.maximum(0.0, 0.25 - (hi - lo)) / 2  # a scene at least 25 cm across each way
    return np.vstack([out, lo - pad, hi + pad])


def _nice(step: float) -> float:
    """The number 1, 2 or 5 times a power of ten nearest above ``step``."""
    power = 10.0 ** np.floor(np.log10(step))
    return float(next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= step))


def floor_quad(meshes: Meshes, points: np.ndarray) -> tuple[np.ndarray, list[tuple[np.ndarray, np.ndarray]]] | None:
    """The floor to draw: the first upward half-space's plane over the scene's footprint (padded by a tenth), as
    a quad (4, 3) and grid lines at a round spacing (about eight across); None without such a half-space.
    A floor far below everything (more than the scene's size) is left out."""
    plane = next(((p, n) for _, p, n in meshes.planes if n[2] > 0.3), None)
    if plane is None:
        return None
    point, normal = plane
    lo, hi = points[:, :2].min(axis=0), points[:, :2].max(axis=0)
    pad = 0.1 * max(float((hi - lo).max()), 0.5)
    height = point[2] - (normal[0] * (points[:, 0] - point[0]) + normal[1] * (points[:, 1] - point[1])) / normal[2]
    if float((points[:, 2] - height).min()) > max(float(np.ptp(points, axis=0).max()), 0.5):
        return None
    lo, hi = lo - pad, hi + pad

    def on_plane(x: float, y: float) -> np.ndarray:
        z = point[2] - (normal[0] * (x - point[0]) + normal[1] * (y - point[1])) / normal[2]
        return np.array([x, y, z])

    quad = np.array([on_plane(lo[0], lo[1]), on_plane(hi[0], lo[1]), on_plane(hi[0], hi[1]), on_plane(lo[0], hi[1])])
    spacing = _nice(float((hi - lo).max()) / 8)
    grid = []
    for x in np.arange(np.ceil(lo[0] / spacing), np.floor(hi[0] / spacing) + 1) * spacing:
        grid.append((on_plane(x, lo[1]), on_plane(x, hi[1])))
    for y in np.arange(np.ceil(lo[1] / spacing), np.floor(hi[1] / spacing) + 1) * spacing:
        grid.append((on_plane(lo[0], y), on_plane(hi[0], y)))
    return quad, grid
