"""Springs and joints in the glTF export (``_gltf``). glTF cannot animate a line's vertices, so each link is a node
carrying a thin cylinder of unit length along +z (one mesh for the springs and one for the joints, both on the same
geometry), keyed at every frame with its translation (the segment's midpoint), rotation (+z onto the segment) and
scale (the segment's length along z). Each joint also puts a small sphere at both of its anchors, a child of the
body or particle it is fixed to (or of the root, for a world point), so that it moves with it unanimated.

The rotations are continuous: each frame's is the previous one turned by the shortest arc from the previous
direction to the new one, so there is no flip where the segment points down and no spin between frames. A segment
of zero length (a ball joint that holds) keeps the previous direction and a tiny positive length."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._geometry import rotation_matrices
from .._mesh import LINK, shape_mesh

if TYPE_CHECKING:
    from ._gltf import Writer
    from .._run import Run


def segments(run: Run, frames: np.ndarray) -> np.ndarray:
    """The links at ``frames`` as (F, L, 2, 3) segments, as ``Run.link_segments`` gives them a frame at a time."""
    out = np.zeros((len(frames), len(run.links), 2, 3))
    for j in (0, 1):
        ends = [link[1 + j] for link in run.links]
        kinds = np.array([e[0] for e in ends], dtype=object)
        rows = np.array([e[1] for e in ends], dtype=np.int64)
        points = np.array([e[2] for e in ends], dtype=float).reshape(-1, 3)
        particle, body = kinds == "particle", kinds == "body"
        world = ~(particle | body)
        out[:, particle, j] = run.particle_positions[np.ix_(frames, rows[particle])]
        if body.any():
            turn = rotation_matrices(run.body_orientations[np.ix_(frames, rows[body])])
            out[:, body, j] = (run.body_positions[np.ix_(frames, rows[body])]
                               + np.einsum("fnij,nj->fni", turn, points[body]))
        out[:, world, j] = points[world]
    return out


def _arc(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Quaternions (x, y, z, w) of the shortest rotations taking unit vectors ``a`` onto ``b`` (both (L, 3)); half a
    turn about an axis perpendicular to ``a`` where they are opposite."""
    c = np.sum(a * b, axis=-1)
    q = np.concatenate([np.cross(a, b), (1.0 + c)[:, None]], axis=-1)
    opposite = c < -1.0 + 1e-9
    if opposite.any():
        axis = np.cross(a[opposite], [1.0, 0.0, 0.0])
        small = np.linalg.norm(axis, axis=-1) < 1e-3
        axis[small] = np.cross(a[opposite][small], [0.0, 1.0, 0.0])
        q[opposite] = np.concatenate([axis, np.zeros((len(axis), 1))], axis=-1)
    unit: np.ndarray = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return unit


def _multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton products p q of quaternions stored (x, y, z, w), (L, 4)."""
    pv, pw, qv, qw = p[:, :3], p[:, 3:], q[:, :3], q[:, 3:]
    return np.concatenate([pw * qv + qw * pv + np.cross(pv, qv), pw * qw - np.sum(pv * qv, axis=-1, keepdims=True)],
                          axis=-1)


def transforms(segs: np.ndarray, shortest: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Translations (F, L, 3), rotations (F, L, 4) as (x, y, z, w) and lengths (F, L) of the nodes that draw the
    (F, L, 2, 3) segments with a unit cylinder along +z centred on the origin: +z maps to the direction from the first
    end to the second. Lengths are at least ``shortest`` (> 0)."""
    frames, links = segs.shape[:2]
    d = segs[:, :, 1] - segs[:, :, 0]
    length = np.linalg.norm(d, axis=-1)
    rotations = np.zeros((frames, links, 4))
    current = np.tile([0.0, 0.0, 0.0, 1.0], (links, 1))
    axis = np.tile([0.0, 0.0, 1.0], (links, 1))
    for k in range(frames):
        has = length[k] > 0.0
        target = axis.copy()
        target[has] = d[k, has] / length[k, has, None]
        current = _multiply(_arc(axis, target), current)
        current /= np.linalg.norm(current, axis=-1, keepdims=True)
        axis = rotation_matrices(current[:, [3, 0, 1, 2]])[:, :, 2]  # where +z points now
        rotations[k] = current
    return segs.mean(axis=2), rotations, np.maximum(length, shortest)


def add_links(w: Writer, run: Run, frames: np.ndarray, root: int, body_nodes: list[int],
              particle_nodes: list[int], size: float) -> None:
    """Adds a node per link of ``run`` under ``root`` (named "spring i" or "<kind> joint i", i its index in
    ``run.links``) and each joint's anchor spheres, keyed at ``frames``. ``size`` (the scene's) scales the
    cylinder's radius and the spheres."""
    if not run.links:
        return
    from ._gltf import JOINT, SPRING, _sphere, continuous  # noqa: PLC0415

    radius = 0.002 * size
    v, t = _cylinder(radius)
    cylinder = w.geometry(v, t)
    meshes: dict[str, int] = {}  # "spring", "joint" and "joint anchor", made when first needed
    translations, rotations, lengths = transforms(segments(run, frames), 1e-6 * size)
    rotations = continuous(rotations)
    for i, (kind, *ends) in enumerate(run.links):
        spring = kind == "spring"
        if spring and "spring" not in meshes:
            meshes["spring"] = w.mesh("spring", cylinder, w.material(*SPRING))
        if not spring and "joint" not in meshes:
            meshes["joint"] = w.mesh("joint", cylinder, w.material(*JOINT))
            meshes["joint anchor"] = w.mesh("joint anchor", w.geometry(*_sphere(0.01 * size)), w.material(*JOINT))
        girth = 1.0 if spring else 2.0  # the joints' cylinders twice as thick
        scales = np.stack([np.full(len(frames), girth), np.full(len(frames), girth), lengths[:, i]], axis=-1)
        node = w.node(f"spring {i}" if spring else f"{kind} joint {i}", root, meshes["spring" if spring else "joint"],
                      translation=translations[0, i], rotation=rotations[0, i], scale=scales[0])
        w.animate(node, "translation", translations[:, i])
        w.animate(node, "rotation", rotations[:, i])
        w.animate(node, "scale", scales)
        if spring:
            continue
        for end, (where, row, point) in zip("ab", ends):
            parent = body_nodes[row] if where == "body" else particle_nodes[row] if where == "particle" else root
            offset = point if where != "particle" else (0.0, 0.0, 0.0)
            w.node(f"{kind} joint {i} anchor {end}", parent, meshes["joint anchor"], translation=offset)


def _cylinder(radius: float) -> tuple[np.ndarray, np.ndarray]:
    """A cylinder of ``radius`` and unit length along z, centred on the origin, with eight sides."""
    from .._tumble import Cylinder  # noqa: PLC0415

    return shape_mesh(Cylinder(0.5, radius), LINK)
