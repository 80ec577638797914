"""A check of glTF binary files by hand, as the Khronos validator checks them (it cannot be installed here: npm and
GitHub are unreachable): ``validate`` reads a .glb, asserts what the validator asserts and returns it read back.
Used by test_gltf.py."""

import dataclasses
import functools
import json
import struct
from pathlib import Path

import numpy as np
import pygltflib

from tumble._geometry import rotation_matrix

DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
Y_UP = rotation_matrix(np.array([np.sqrt(0.5), -np.sqrt(0.5), 0.0, 0.0]))  # the root: -90 degrees about x


# ---------------------------------------------------------------------------------------------------------------
# The checks of the Khronos validator that apply to these files, done by hand.


def parse_glb(data: bytes) -> tuple[dict, bytes]:
    """The JSON and BIN chunks of a GLB, its header and chunk lengths checked."""
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    offset, chunks = 12, []
    while offset < length:
        chunk_length, chunk_type = struct.unpack_from("<II", data, offset)
        assert chunk_length % 4 == 0 and offset + 8 + chunk_length <= length
        chunks.append((chunk_type, data[offset + 8:offset + 8 + chunk_length]))
        offset += 8 + chunk_length
    assert offset == length
    assert chunks[0][0] == 0x4E4F534A and len(chunks) <= 2  # JSON, then at most a BIN chunk
    text = chunks[0][1].decode("utf-8")
    assert text.rstrip(" ") == text.rstrip()  # padded with spaces only
    blob = b""
    if len(chunks) == 2:
        assert chunks[1][0] == 0x004E4942
        blob = chunks[1][1]
    return json.loads(text), blob


@dataclasses.dataclass
class Glb:
    """A .glb read back: its JSON, every accessor's data, and indexes to look nodes up."""

    doc: dict
    data: dict[int, np.ndarray]

    def __post_init__(self) -> None:
        self.ids = {n.get("name"): i for i, n in enumerate(self.doc["nodes"])}
        self.parents = {c: p for p, n in enumerate(self.doc["nodes"]) for c in n.get("children", [])}
        self.keyed = {(c["target"]["node"], c["target"]["path"]): a["samplers"][c["sampler"]]["output"]
                      for a in self.doc.get("animations", []) for c in a["channels"]}

    def read(self, node: int, path: str, frame: int) -> np.ndarray:
        """``node``'s ``path`` at keyframe ``frame``: its animation's, else its fixed value."""
        if (node, path) in self.keyed:
            return self.data[self.keyed[node, path]][frame].astype(float)
        default = {"translation": [0, 0, 0], "rotation": [0, 0, 0, 1], "scale": [1, 1, 1]}[path]
        return np.asarray(self.doc["nodes"][node].get(path, default), dtype=float)

    def world_matrix(self, node: int | str, frame: int) -> np.ndarray:
        """The 4 x 4 transform of ``node`` (its index or name) at ``frame``, its ancestors' applied."""
        node = self.ids[node] if isinstance(node, str) else node
        m = np.eye(4)
        while True:
            local = np.eye(4)
            x, y, z, w = self.read(node, "rotation", frame)
            local[:3, :3] = rotation_matrix(np.array([w, x, y, z])) * self.read(node, "scale", frame)
            local[:3, 3] = self.read(node, "translation", frame)
            m = local @ m
            if node not in self.parents:
                return m
            node = self.parents[node]


@functools.cache
def validate(path: Path) -> Glb:
    """Checks a .glb as the Khronos validator would and returns it read back (its JSON and every accessor's data): the
    GLB container; references in range; every buffer view inside the buffer and every accessor inside its view, aligned
    to its component size (4 bytes here), its component type and type valid for its use, min/max present where required
    and equal to the data, no NaN or infinity in any of it; indices in range and no degenerate triangles; materials'
    factors in range; the node hierarchy a forest whose roots are the scene's nodes; animation inputs strictly
    increasing with bounds, outputs as many, rotations unit quaternions, scales finite and non-zero; no unused object
    and no empty array."""
    doc, blob = parse_glb(path.read_bytes())
    pygltflib.GLTF2().load(str(path))  # and pygltflib reads it back
    assert doc["asset"]["version"] == "2.0"

    def empty_arrays(value: object) -> None:  # the schema's minItems: 1
        if isinstance(value, list):
            assert value
        for child in value.values() if isinstance(value, dict) else value if isinstance(value, list) else []:
            empty_arrays(child)

    empty_arrays(doc)

    def items(name: str) -> list[dict]:
        return doc.get(name, [])

    def ref(index: object, name: str) -> int:
        assert isinstance(index, int) and 0 <= index < len(items(name)), (name, index)
        return index

    used: dict[str, set[int]] = {name: set() for name in ("bufferViews", "accessors", "meshes", "materials")}
    buffers = items("buffers")
    assert len(buffers) == (1 if blob else 0)
    if buffers:  # a GLB's buffer is its BIN chunk, padded to 4 bytes
        assert "uri" not in buffers[0] and buffers[0]["byteLength"] <= len(blob) < buffers[0]["byteLength"] + 4
    for view in items("bufferViews"):
        buffer = buffers[ref(view["buffer"], "buffers")]
        assert view["byteLength"] >= 1 and view.get("byteOffset", 0) % 4 == 0
        assert view.get("byteOffset", 0) + view["byteLength"] <= buffer["byteLength"]
        assert view.get("target") in (None, ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER) and "byteStride" not in view
    data, covered = {}, {i: np.zeros(v["byteLength"], bool) for i, v in enumerate(items("bufferViews"))}
    for i, accessor in enumerate(items("accessors")):
        view = items("bufferViews")[ref(accessor["bufferView"], "bufferViews")]
        used["bufferViews"].add(accessor["bufferView"])
        dtype, width = np.dtype(DTYPES[accessor["componentType"]]), WIDTHS[accessor["type"]]
        assert accessor["count"] >= 1 and not accessor.get("normalized", False)
        start = accessor.get("byteOffset", 0)
        assert start % dtype.itemsize == 0 and (view.get("byteOffset", 0) + start) % 4 == 0
        end = start + accessor["count"] * width * dtype.itemsize
        assert end <= view["byteLength"]
        covered[accessor["bufferView"]][start:end] = True
        values = np.frombuffer(blob, dtype, accessor["count"] * width, view.get("byteOffset", 0) + start)
        values = values.reshape(accessor["count"], width)
        assert np.isfinite(values).all(), f"accessor {i} has NaN or infinity"
        for bound, actual in (("min", values.min(axis=0)), ("max", values.max(axis=0))):
            if bound in accessor:
                np.testing.assert_array_equal(np.asarray(accessor[bound], dtype), actual)
        data[i] = values
    assert all(c.all() for c in covered.values()), "bytes of a buffer view that no accessor reads"

    def accessor(index: int, ctype: tuple[int, ...], kind: str, target: int | None) -> dict:
        a = items("accessors")[ref(index, "accessors")]
        used["accessors"].add(index)
        assert a["componentType"] in ctype and a["type"] == kind
        assert items("bufferViews")[a["bufferView"]].get("target") == target
        return a

    for material in items("materials"):
        assert material.get("name")
        pbr = material["pbrMetallicRoughness"]
        assert len(pbr["baseColorFactor"]) == 4 and all(0 <= c <= 1 for c in pbr["baseColorFactor"])
        assert 0 <= pbr.get("metallicFactor", 1) <= 1 and 0 <= pbr.get("roughnessFactor", 1) <= 1
    for mesh in items("meshes"):
        for primitive in mesh["primitives"]:
            assert primitive.get("mode", 4) == 4 and set(primitive["attributes"]) == {"POSITION"}
            position = accessor(primitive["attributes"]["POSITION"], (5126,), "VEC3", ARRAY_BUFFER)
            assert "min" in position and "max" in position
            indices = accessor(primitive["indices"], (5121, 5123, 5125), "SCALAR", ELEMENT_ARRAY_BUFFER)
            triangles = data[primitive["indices"]].reshape(-1, 3)
            assert indices["count"] % 3 == 0 and triangles.max() < position["count"]
            assert (triangles[:, 0] != triangles[:, 1]).all() and (triangles[:, 1] != triangles[:, 2]).all()
            assert (triangles[:, 0] != triangles[:, 2]).all()
            used["materials"].add(ref(primitive["material"], "materials"))
    nodes = items("nodes")
    parent: dict[int, int] = {}
    for i, node in enumerate(nodes):
        assert "matrix" not in node
        if "mesh" in node:
            used["meshes"].add(ref(node["mesh"], "meshes"))
        for child in node.get("children", []):
            assert ref(child, "nodes") not in parent and child != i, "a node with two parents"
            parent[child] = i
        assert np.isfinite(node.get("translation", [0, 0, 0])).all() and len(node.get("translation", [0] * 3)) == 3
        assert abs(np.linalg.norm(node.get("rotation", [0, 0, 0, 1])) - 1) < 1e-6
        scale = np.asarray(node.get("scale", [1, 1, 1]))
        assert len(scale) == 3 and np.isfinite(scale).all() and (scale != 0).all()
    for i in range(len(nodes)):  # a forest: following parents never comes back
        seen, n = {i}, i
        while n in parent:
            n = parent[n]
            assert n not in seen, "a cycle in the node hierarchy"
            seen.add(n)
    scene = items("scenes")[ref(doc["scene"], "scenes")]
    assert len(set(scene["nodes"])) == len(scene["nodes"])
    assert all(ref(n, "nodes") not in parent for n in scene["nodes"])
    assert {n for n in range(len(nodes)) if n not in parent} == set(scene["nodes"])  # every node is in the scene
    for animation in items("animations"):
        targets = set()
        for channel in animation["channels"]:
            target = (ref(channel["target"]["node"], "nodes"), channel["target"]["path"])
            assert target not in targets and target[1] in ("translation", "rotation", "scale")
            targets.add(target)
            assert 0 <= channel["sampler"] < len(animation["samplers"])
        assert {c["sampler"] for c in animation["channels"]} == set(range(len(animation["samplers"])))
        paths = {c["sampler"]: c["target"]["path"] for c in animation["channels"]}
        for s, sampler in enumerate(animation["samplers"]):
            assert sampler.get("interpolation", "LINEAR") in ("LINEAR", "STEP")
            times = accessor(sampler["input"], (5126,), "SCALAR", None)
            assert "min" in times and "max" in times
            t = data[sampler["input"]][:, 0]
            assert t[0] >= 0 and (np.diff(t) > 0).all()
            out = accessor(sampler["output"], (5126,), "VEC4" if paths[s] == "rotation" else "VEC3", None)
            assert out["count"] == times["count"]
            values = data[sampler["output"]]
            if paths[s] == "rotation":
                assert np.abs(np.linalg.norm(values.astype(float), axis=1) - 1).max() < 1e-6
            if paths[s] == "scale":
                assert (values != 0).all()
    for name, indices in used.items():
        assert indices == set(range(len(items(name)))), f"unused {name}"
    return Glb(doc, data)
