"""Colliders as triangle meshes, for every exporter: USD (``_usd``), glTF (``_gltf``), the viewer
(``_viewer_scene``) and the preview (``_preview_mesh``).

The library triangulates a shape (``Shape.triangle_mesh``: spheres, boxes, capsules, cylinders, convex hulls,
triangle meshes, and a half-space as a square on its plane); this module turns that into numpy arrays, places a
collider by its offset and orientation in its body's frame, joins a body's colliders into one mesh, and reads a
half-space's plane. Triangles wind counter-clockwise seen from outside (their normals point outwards); a
half-space's square faces out of the solid side.

The exporters draw at different resolutions on purpose, named here: the files and the viewer at the library's 24
segments around a curved shape, the preview's software renderer (which outlines every face) at 8, the small marker
spheres of glTF at 12 and its link cylinders at 8 sides.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ._geometry import rotation_matrices, rotation_matrix

if TYPE_CHECKING:
    from ._tumble import Shape

# Segments around a curved shape: USD, glTF and the viewer (the library's default).
EXPORT = 24
# The preview: coarse, as it outlines every face of every body on every frame.
PREVIEW = 8
# glTF's small spheres marking particles, bodies without colliders and joint anchors.
MARKER = 12
# glTF's thin cylinders of the springs and joints.
LINK = 8
# The half-size of a half-space's square in the exported files (metres).
EXTENT = 10.0


def shape_mesh(shape: Shape, subdivisions: int = EXPORT, extent: float = EXTENT) -> tuple[np.ndarray, np.ndarray]:
    """The shape's surface in its own frame: vertices (V, 3) float64 and triangles (T, 3) uint32 of vertex
    indices, curved shapes with ``subdivisions`` segments around, a half-space a square of half-size ``extent``."""
    vertices, triangles = shape.triangle_mesh(subdivisions, extent)
    return np.asarray(vertices), np.asarray(triangles)


def collider_mesh(shape: Shape, offset: Sequence[float] | np.ndarray, orientation: Sequence[float] | np.ndarray,
                  subdivisions: int = EXPORT, extent: float = EXTENT) -> tuple[np.ndarray, np.ndarray]:
    """A collider's mesh (``shape_mesh``) placed in its body's frame: turned by ``orientation`` (w, x, y, z) and
    moved by ``offset``."""
    vertices, triangles = shape_mesh(shape, subdivisions, extent)
    placed = vertices @ rotation_matrix(np.asarray(orientation, dtype=float)).T + np.asarray(offset, dtype=float)
    return placed, triangles


def body_mesh(colliders: Sequence[tuple[Shape, Any, Any]], subdivisions: int = EXPORT,
              extent: float = EXTENT) -> tuple[np.ndarray, np.ndarray]:
    """A body's colliders ``[(shape, offset, orientation), ...]`` as one mesh in its frame (``collider_mesh``
    each, their vertices in order and the triangles renumbered to them)."""
    vertices, triangles, base = [], [], 0
    for shape, offset, orientation in colliders:
        v, t = collider_mesh(shape, offset, orientation, subdivisions, extent)
        vertices.append(v)
        triangles.append(t + base)
        base += len(v)
    if not vertices:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.uint32)
    return np.concatenate(vertices), np.concatenate(triangles)


def half_space_plane(shape: Shape) -> tuple[np.ndarray, np.ndarray]:
    """A half-space's boundary plane in its own frame as (point, unit normal): the centre of the library's square
    of it and the normal its triangles face, out of the solid side."""
    vertices, triangles = shape_mesh(shape, EXPORT, 1.0)
    v = np.asarray(vertices, dtype=float)
    a, c, d = v[np.asarray(triangles, dtype=np.int64)[0]]
    normal = np.cross(c - a, d - a)
    unit: np.ndarray = normal / np.linalg.norm(normal)
    return v.mean(axis=0), unit


# The shapes of bodies placed by their modelled frame (with a body of several colliders).
MODELLED = ("mesh", "decomposed mesh")


def pivoted(colliders: list[Any], positions: np.ndarray, orientations: np.ndarray) -> tuple[list[Any], np.ndarray]:
    """A body's colliders and its frames' positions (F, 3) moved so that the exported pivot is the body's modelled
    frame, not its centre of mass: for a body of a mesh or of several colliders, the first collider's frame (where
    the mesh's coordinates have their origin) becomes the node's origin, each collider offset by as much, and the
    positions moved to it along the orientations (F, 4) (w, x, y, z). Other bodies come back as they are."""
    if not colliders or (len(colliders) == 1 and colliders[0][0].kind not in MODELLED):
        return colliders, positions
    pivot = np.asarray(colliders[0][1], dtype=float)
    moved = [(s, np.asarray(p, dtype=float) - pivot, q) for s, p, q in colliders]
    return moved, positions + rotation_matrices(orientations) @ pivot
