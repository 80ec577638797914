"""Binary glTF 2.0 export of a run with pygltflib.

The file holds one node per body, per particle and per spring or joint, all under a root node turned -90 degrees
about x (tumble is z-up, glTF y-up), and one animation, "run", that keys their translation and rotation (and the
links' scale) at every frame; static bodies are placed once, unanimated. A run does not record which bodies are
static: those carrying a half-space or triangle mesh are, and so are taken those that never move at all (their
velocities zero at every frame) and that no spring or joint holds.

Meshes are shared: bodies whose collider sets are identical (the same shapes, compared by their JSON from
``Shape.__reduce__``, at exactly the same offsets and orientations) and alike static or dynamic use one mesh, so a
row of twenty dominoes carries one domino mesh; particles share one small sphere, springs and joints one thin
cylinder (``_gltf_links``). A body's node carries its name (``add_body(name=...)``, else "body N"). Materials are
plain, named pbrMetallicRoughness colours: a body given a colour has it (bodies of one colour share the material,
blended where alpha is below 1), other static bodies are grey and double-sided (the ground is a finite square),
other dynamic bodies a palette colour per distinct collider set; particles, springs and joints one colour each.

Keyframe times are strictly increasing in float32 (frames that would repeat a time are dropped) and a run that
diverged is written up to its last frame whose poses are all finite, so the file has no NaN or infinity."""

from __future__ import annotations

import struct
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt
import pygltflib as g

from .._mesh import MARKER, body_mesh, pivoted, shape_mesh

if TYPE_CHECKING:
    from .._run import Run

Array = npt.NDArray[np.float64]

# Base colours (linear RGBA) and names: static bodies, dynamic bodies (a colour per distinct collider set, in the
# order the sets first appear), particles, springs and joints.
STATIC = ("static body", (0.55, 0.55, 0.55, 1.0))
PALETTE = (
    ("body orange", (0.90, 0.42, 0.12, 1.0)),
    ("body blue", (0.16, 0.40, 0.85, 1.0)),
    ("body green", (0.22, 0.65, 0.30, 1.0)),
    ("body red", (0.80, 0.15, 0.20, 1.0)),
    ("body purple", (0.50, 0.30, 0.78, 1.0)),
    ("body teal", (0.10, 0.62, 0.62, 1.0)),
)
PARTICLE = ("particle", (0.92, 0.92, 0.95, 1.0))
SPRING = ("spring", (0.95, 0.75, 0.15, 1.0))
JOINT = ("joint", (0.12, 0.12, 0.16, 1.0))
# Shapes that only a static body may carry; their meshes are open (the ground square), so seen from both sides.
STATIC_ONLY = ("half-space", "triangle mesh")
Y_UP = [-float(np.sqrt(0.5)), 0.0, 0.0, float(np.sqrt(0.5))]  # -90 degrees about x, as glTF's (x, y, z, w)


class Writer:
    """Builds the glTF document: geometry (one buffer view per accessor), keyframes (one buffer view shared by all
    of them, written by ``finish``), named materials, meshes, nodes and the animation's channels."""

    def __init__(self, times: Array) -> None:
        self.gltf = g.GLTF2(asset=g.Asset(generator="tumble", version="2.0"))
        self.data = bytearray()
        self.keys = bytearray()
        self.keyed: list[g.Accessor] = []
        self.materials: dict[str, int] = {}
        self.animation = g.Animation(name="run", channels=[], samplers=[])
        self.times = times  # the keyframe times, written once (by the first ``animate``) and shared by every sampler
        self.times_accessor: int | None = None

    def _accessor(self, array: np.ndarray, view: int | None, offset: int, bounds: bool) -> int:
        flat = array.reshape(array.shape[0], -1)
        accessor = g.Accessor(
            bufferView=view, byteOffset=offset, normalized=None,
            componentType=g.UNSIGNED_INT if array.dtype == np.uint32 else g.FLOAT,
            count=flat.shape[0], type={1: g.SCALAR, 3: g.VEC3, 4: g.VEC4}[flat.shape[1]],
        )
        if bounds:  # from the float32 values written, as the validator compares them
            accessor.min = [float(x) for x in flat.min(axis=0)]
            accessor.max = [float(x) for x in flat.max(axis=0)]
        self.gltf.accessors.append(accessor)
        return len(self.gltf.accessors) - 1

    def geometry(self, vertices: np.ndarray, triangles: np.ndarray) -> tuple[int, int]:
        """Accessors for a triangle mesh: positions (float VEC3 with bounds) and indices (unsigned int)."""
        found = []
        for array, target in ((np.asarray(vertices, np.float32).reshape(-1, 3), g.ARRAY_BUFFER),
                              (np.asarray(triangles, np.uint32).reshape(-1, 1), g.ELEMENT_ARRAY_BUFFER)):
            self.data.extend(bytes(-len(self.data) % 4))
            self.gltf.bufferViews.append(g.BufferView(buffer=0, byteOffset=len(self.data), byteLength=array.nbytes,
                                                      target=target))
            self.data.extend(np.ascontiguousarray(array).tobytes())
            found.append(self._accessor(array, len(self.gltf.bufferViews) - 1, 0, target == g.ARRAY_BUFFER))
        return found[0], found[1]

    def keyframes(self, values: np.ndarray, bounds: bool = False) -> int:
        """An accessor for (F, 1 | 3 | 4) keyframe values, in the shared keyframe buffer view."""
        array = np.ascontiguousarray(values, dtype=np.float32)
        index = self._accessor(array, None, len(self.keys), bounds)
        self.keyed.append(self.gltf.accessors[index])
        self.keys.extend(array.tobytes())
        return index

    def material(self, name: str, rgba: tuple[float, ...], double_sided: bool = False) -> int:
        """The material named ``name`` (made once): a plain, rough, non-metallic base colour (blended where its
        alpha is below 1)."""
        if name not in self.materials:
            self.gltf.materials.append(g.Material(
                name=name, doubleSided=double_sided, alphaMode="BLEND" if rgba[3] < 1.0 else "OPAQUE",
                pbrMetallicRoughness=g.PbrMetallicRoughness(baseColorFactor=list(rgba), metallicFactor=0.0,
                                                            roughnessFactor=0.8)))
            self.materials[name] = len(self.gltf.materials) - 1
        return self.materials[name]

    def mesh(self, name: str, geometry: tuple[int, int], material: int) -> int:
        """A mesh of one primitive: ``geometry`` (from ``geometry``, possibly shared by several meshes) drawn with
        ``material``."""
        primitive = g.Primitive(attributes=g.Attributes(POSITION=geometry[0]), indices=geometry[1], material=material)
        self.gltf.meshes.append(g.Mesh(name=name, primitives=[primitive]))
        return len(self.gltf.meshes) - 1

    def node(self, name: str, parent: int | None, mesh: int | None = None, **trs: Any) -> int:
        """A node under ``parent`` (None: a root), with optional ``translation``, ``rotation`` (x, y, z, w) and
        ``scale`` as lists of floats."""
        self.gltf.nodes.append(g.Node(name=name, mesh=mesh, **{k: [float(x) for x in v] for k, v in trs.items()}))
        index = len(self.gltf.nodes) - 1
        if parent is not None:
            self.gltf.nodes[parent].children.append(index)
        return index

    def animate(self, node: int, path: str, values: np.ndarray) -> None:
        """Keys ``node``'s ``path`` ("translation", "rotation" or "scale") at every frame (LINEAR)."""
        if len(self.times) < 2:  # a single frame: nothing to animate
            return
        if self.times_accessor is None:
            self.times_accessor = self.keyframes(self.times[:, None], bounds=True)
        sampler = g.AnimationSampler(input=self.times_accessor, output=self.keyframes(values), interpolation="LINEAR")
        self.animation.samplers.append(sampler)
        self.animation.channels.append(g.AnimationChannel(
            sampler=len(self.animation.samplers) - 1, target=g.AnimationChannelTarget(node=node, path=path)))

    def finish(self, path: Path) -> None:
        """Places the keyframes after the geometry in one buffer view and writes the .glb (its container written
        here: pygltflib's always adds a buffer and a BIN chunk, invalid when empty)."""
        if self.keys:
            self.data.extend(bytes(-len(self.data) % 4))
            self.gltf.bufferViews.append(g.BufferView(buffer=0, byteOffset=len(self.data),
                                                      byteLength=len(self.keys)))
            self.data.extend(self.keys)
            for accessor in self.keyed:
                accessor.bufferView = len(self.gltf.bufferViews) - 1
        if self.animation.channels:
            self.gltf.animations.append(self.animation)
        chunks = []
        if self.data:  # a buffer (and BIN chunk) of no bytes is invalid: an empty world has none
            self.gltf.buffers.append(g.Buffer(byteLength=len(self.data)))
            self.data.extend(bytes(-len(self.data) % 4))
            chunks.append((b"BIN\0", bytes(self.data)))
        text = self.gltf.gltf_to_json(separators=(",", ":"), indent=None).encode("utf-8")
        chunks.insert(0, (b"JSON", text + b" " * (-len(text) % 4)))
        # the GLB container: a 12-byte header, then each chunk's length, type and bytes (4-byte aligned)
        body = b"".join(struct.pack("<I", len(data)) + kind + data for kind, data in chunks)
        path.write_bytes(b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body)


def continuous(xyzw: np.ndarray) -> np.ndarray:
    """Unit quaternions (F, ..., 4), each sign chosen so that consecutive frames have a non-negative dot product
    (LINEAR interpolation then turns the short way instead of spinning)."""
    q: np.ndarray = xyzw / np.linalg.norm(xyzw, axis=-1, keepdims=True)
    if len(q) > 1:
        flips = np.sum(q[1:] * q[:-1], axis=-1) < 0
        sign = np.where(np.cumsum(flips, axis=0) % 2 == 1, -1.0, 1.0)
        q[1:] *= sign[..., None]
    return q


def kept_frames(run: Run) -> np.ndarray:
    """The frames written: up to the last frame whose times and poses are all finite, without those whose float32
    time (from the first frame) would not be greater than the previous written one's."""
    finite = np.isfinite(run.times)
    for array in (run.body_positions, run.body_orientations, run.particle_positions):
        finite &= np.isfinite(array.reshape(len(run.times), -1)).all(axis=1)
    last = int(np.argmin(finite)) if not finite.all() else len(finite)
    times = (run.times[:last] - run.times[0]).astype(np.float32)
    out: list[int] = []
    for k in range(last):
        if not out or times[k] > times[out[-1]]:
            out.append(k)
    return np.asarray(out, dtype=np.int64)


def _sphere(radius: float) -> tuple[np.ndarray, np.ndarray]:
    from .._tumble import Sphere  # noqa: PLC0415

    return shape_mesh(Sphere(radius), MARKER)


def _scene_size(run: Run, frame: int) -> float:
    """The diagonal of the box around the bodies, particles and links at ``frame`` (1 m if that is degenerate): the
    scale of the small spheres and of the links' cylinders."""
    points = [run.body_positions[frame], run.particle_positions[frame], run.link_segments(frame).reshape(-1, 3)]
    every = np.concatenate([p.reshape(-1, 3) for p in points])
    size = float(np.linalg.norm(every.max(axis=0) - every.min(axis=0))) if len(every) else 0.0
    return size if np.isfinite(size) and size > 1e-6 else 1.0


def _collider_geometry(w: Writer, colliders: list[Any], size: float) -> tuple[int, int]:
    """The geometry of a body's colliders placed in its frame (a small sphere for a body with none)."""
    if colliders:
        return w.geometry(*body_mesh(colliders))
    return w.geometry(*_sphere(0.02 * size))  # a body without colliders: a small sphere marks its centre of mass


def _bodies(w: Writer, run: Run, frames: np.ndarray, root: int, size: float) -> list[int]:
    """A node per body under ``root``, sharing a mesh per distinct collider set; returns them."""
    positions, orientations = run.body_positions[frames], continuous(run.body_orientations[frames][..., [1, 2, 3, 0]])
    # a run does not say which bodies are static: those with a static-only shape are, and so are taken those that
    # never move at all and that no spring or joint holds (a chain at rest, its links held, stays coloured)
    linked = {row for _, *ends in run.links for where, row, _ in ends if where == "body"}
    meshes: dict[tuple[Any, ...], int] = {}  # (static, colour, collider set) -> mesh
    geometries: dict[tuple[Any, ...], tuple[int, int]] = {}  # collider set -> its geometry, whatever its colour
    nodes = []
    for b in range(positions.shape[1]):
        colliders = run.shapes[b] if b < len(run.shapes) else []
        wxyz = run.body_orientations[frames][:, b]
        colliders, placed = pivoted(colliders, positions[:, b], wxyz)
        static = any(s.kind in STATIC_ONLY for s, _, _ in colliders) or (
            len(frames) > 1 and b not in linked and not run.body_velocities[frames, b].any()
            and not run.body_angular_velocities[frames, b].any()
            and bool((positions[:, b] == positions[0, b]).all() and (orientations[:, b] == orientations[0, b]).all()))
        # identical collider sets: the same shapes (their JSON) at exactly the same offsets and orientations, and
        # the same colour where one was given
        color = run.color(b)
        shapes = tuple((s.__reduce__()[1][0], tuple(map(float, p)), tuple(map(float, q))) for s, p, q in colliders)
        key = (static, color, shapes)
        if key not in meshes:
            if color is not None:  # the body's own colour, a material named by it, shared by bodies of that colour
                label = "colour " + " ".join(f"{c:.4g}" for c in color) + (" (static)" if static else "")
                material = w.material(label, color, double_sided=static)
            elif static:
                material = w.material(*STATIC, double_sided=True)
            else:  # the palette's next colour for each distinct dynamic collider set
                material = w.material(*PALETTE[sum(1 for s, c, _ in meshes if not s and c is None) % len(PALETTE)])
            if shapes not in geometries:
                geometries[shapes] = _collider_geometry(w, colliders, size)
            kinds = " + ".join(s.kind for s, _, _ in colliders) or "marker"
            meshes[key] = w.mesh(f"{'static ' if static else ''}body mesh {len(meshes)}: {kinds}", geometries[shapes],
                                 material)
        nodes.append(w.node(run.label(b), root, meshes[key], translation=placed[0], rotation=orientations[0, b]))
        if not static:
            w.animate(nodes[-1], "translation", placed)
            w.animate(nodes[-1], "rotation", orientations[:, b])
    return nodes


def export(run: Run, path: Path) -> Path:
    """Writes ``run`` to ``path`` (a .glb); see the module's docstring."""
    from ._gltf_links import add_links  # noqa: PLC0415

    if path.suffix.lower() != ".glb":
        raise ValueError(f"invalid argument `path`: glTF binary files end in .glb, got {path.name!r}")
    frames = kept_frames(run)
    if not len(frames):
        raise ValueError("invalid argument `run`: it has no frame with finite poses to write")
    w = Writer(run.times[frames] - run.times[0])
    root = w.node("tumble (z-up)", None, rotation=Y_UP)
    w.gltf.scenes.append(g.Scene(name=run.name or "tumble run", nodes=[root]))
    w.gltf.scene = 0
    size = _scene_size(run, int(frames[0]))
    body_nodes = _bodies(w, run, frames, root, size)
    particle_nodes = []
    if run.particle_positions.shape[1]:
        dot = w.mesh("particle", w.geometry(*_sphere(0.006 * size)), w.material(*PARTICLE))
        particles = run.particle_positions[frames]
        for i in range(particles.shape[1]):
            particle_nodes.append(w.node(f"particle {i}", root, dot, translation=particles[0, i]))
            w.animate(particle_nodes[-1], "translation", particles[:, i])
    add_links(w, run, frames, root, body_nodes, particle_nodes, size)
    w.finish(path)
    return path
