"""Binary glTF 2.0 export of a run with pygltflib: one node per body carrying its colliders' meshes, one per particle
carrying a small sphere, each with translation and rotation keyed at every frame. tumble's world is z-up and
glTF's y-up, so everything hangs under a root node turned -90 degrees about x."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pygltflib as g

from ._geometry import rotation_matrix

if TYPE_CHECKING:
    from ._run import Run

FLOAT, UINT = g.FLOAT, g.UNSIGNED_INT


class _Blob:
    """Accumulates binary data and the accessors that describe it."""

    def __init__(self, gltf: g.GLTF2) -> None:
        self.gltf = gltf
        self.data = bytearray()

    def accessor(self, array: np.ndarray, kind: str, target: int | None = None, bounds: bool = False) -> int:
        array = np.ascontiguousarray(array, dtype=np.uint32 if kind == "INDEX" else np.float32)
        while len(self.data) % 4:
            self.data.append(0)
        offset = len(self.data)
        self.data.extend(array.tobytes())
        self.gltf.bufferViews.append(g.BufferView(buffer=0, byteOffset=offset, byteLength=array.nbytes, target=target))
        gltf_type = {"INDEX": g.SCALAR, "SCALAR": g.SCALAR, "VEC3": g.VEC3, "VEC4": g.VEC4}[kind]
        accessor = g.Accessor(
            bufferView=len(self.gltf.bufferViews) - 1,
            componentType=UINT if kind == "INDEX" else FLOAT,
            count=array.shape[0] if kind != "INDEX" else array.size,
            type=gltf_type,
        )
        if bounds:
            flat = array.reshape(array.shape[0], -1)
            accessor.min = flat.min(axis=0).tolist()
            accessor.max = flat.max(axis=0).tolist()
        self.gltf.accessors.append(accessor)
        return len(self.gltf.accessors) - 1

    def mesh(self, vertices: np.ndarray, triangles: np.ndarray) -> int:
        position = self.accessor(vertices, "VEC3", g.ARRAY_BUFFER, bounds=True)
        indices = self.accessor(triangles.reshape(-1), "INDEX", g.ELEMENT_ARRAY_BUFFER)
        self.gltf.meshes.append(g.Mesh(primitives=[g.Primitive(attributes=g.Attributes(POSITION=position), indices=indices)]))
        return len(self.gltf.meshes) - 1


def _sphere(radius: float) -> tuple[np.ndarray, np.ndarray]:
    from ._tumble import Sphere  # noqa: PLC0415

    v, t = Sphere(radius).triangle_mesh(12)
    return np.asarray(v), np.asarray(t)


def export(run: "Run", path: Path) -> Path:
    if path.suffix.lower() != ".glb":
        raise ValueError(f"invalid argument `path`: glTF binary files end in .glb, got {path.name!r}")
    gltf = g.GLTF2(asset=g.Asset(generator="tumble", version="2.0"))
    blob = _Blob(gltf)
    times = blob.accessor(run.times - run.times[0], "SCALAR", bounds=True)
    root = g.Node(name="tumble (z-up)", rotation=[-np.sqrt(0.5), 0.0, 0.0, np.sqrt(0.5)], children=[])
    gltf.nodes.append(root)
    animation = g.Animation(name="run", channels=[], samplers=[])

    def animated_node(name: str, mesh: int, translations: np.ndarray, rotations: np.ndarray | None) -> None:
        gltf.nodes.append(g.Node(name=name, mesh=mesh))
        node = len(gltf.nodes) - 1
        root.children.append(node)
        keyed = [("translation", blob.accessor(translations, "VEC3"))]
        if rotations is not None:
            keyed.append(("rotation", blob.accessor(rotations[:, [1, 2, 3, 0]], "VEC4")))  # glTF stores x, y, z, w
        for target, output in keyed:
            animation.samplers.append(g.AnimationSampler(input=times, output=output, interpolation="LINEAR"))
            animation.channels.append(
                g.AnimationChannel(sampler=len(animation.samplers) - 1, target=g.AnimationChannelTarget(node=node, path=target))
            )

    marker = None
    for b in range(run.body_positions.shape[1]):
        colliders = run.shapes[b] if b < len(run.shapes) else []
        if colliders:
            vertices, triangles, base = [], [], 0
            for shape, offset, orientation in colliders:
                v, t = shape.triangle_mesh(24, 10.0)
                v = np.asarray(v) @ rotation_matrix(np.asarray(orientation)).T + np.asarray(offset)
                vertices.append(v)
                triangles.append(np.asarray(t) + base)
                base += len(v)
            mesh = blob.mesh(np.concatenate(vertices), np.concatenate(triangles))
        else:
            marker = marker if marker is not None else blob.mesh(*_sphere(0.05))
            mesh = marker
        animated_node(f"body {b}", mesh, run.body_positions[:, b], run.body_orientations[:, b])
    if run.particle_positions.shape[1]:
        dot = blob.mesh(*_sphere(0.01))
        for i in range(run.particle_positions.shape[1]):
            animated_node(f"particle {i}", dot, run.particle_positions[:, i], None)
    if animation.channels:
        gltf.animations.append(animation)
    gltf.scenes.append(g.Scene(nodes=[0]))
    gltf.scene = 0
    gltf.buffers.append(g.Buffer(byteLength=len(blob.data)))
    gltf.set_binary_blob(bytes(blob.data))
    gltf.save_binary(str(path))
    return path
