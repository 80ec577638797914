"""glTF export: the .glb files of several scenes checked the way the Khronos glTF validator checks them, by hand
(``validate``: the validator ships only on npm and as GitHub release binaries, neither reachable here; no PyPI or
Debian package has it, and the crates.io wrapper gltf-validator downloads the binary when built), plus the Rust
``gltf`` crate's validation and meshoptimizer's gltfpack (cgltf's validation) where they can run; shared meshes,
materials, poses read back, and the springs' and joints' nodes against ``Run.link_segments``."""

import dataclasses
import functools
import json
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pygltflib
import pytest

import tumble
from tumble._geometry import rotation_matrices, rotation_matrix
from tumble._gltf_links import segments, transforms

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


# ---------------------------------------------------------------------------------------------------------------
# The runs and their files.


def small_run() -> tumble.Run:
    w = tumble.World(integrator="dopri5", rtol=1e-8, atol=1e-10)
    w.add_body(tumble.Box(half_extents=(0.2, 0.3, 0.4)), density=500.0, position=(0, 0, 2), angular_velocity=(1, 2, 3))
    w.add_particle(position=(1, 0, 1), velocity=(0, 1, 3))
    return w.run(1.0, 0.1)


RUNS = {
    "dominoes": lambda: tumble.scenes.dominoes().run(1.0),
    "cloth": lambda: tumble.scenes.cloth(n=10).run(0.5),
    "chain": lambda: tumble.scenes.chain().run(0.5),
    "ragdoll": lambda: tumble.scenes.ragdoll().run(0.5),
    "pendulum": lambda: tumble.scenes.pendulum().run(0.5),
    "newtons_cradle": lambda: tumble.scenes.newtons_cradle().run(0.25),
    "door": lambda: tumble.scenes.door().run(0.5),
    "spinning_top": lambda: tumble.scenes.spinning_top().run(0.25),
    "particles": small_run,
    "empty": lambda: tumble.World().run(0.1),
}
_cache: dict[str, tumble.Run] = {}


def run_of(name: str) -> tumble.Run:
    if name not in _cache:
        _cache[name] = RUNS[name]()
    return _cache[name]


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("gltf")
    return {name: run_of(name).export_gltf(folder / f"{name}.glb") for name in RUNS}


# ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(RUNS))
def test_the_file_validates(files: dict[str, Path], name: str) -> None:
    glb = validate(files[name])
    doc = glb.doc
    run = run_of(name)
    bodies, particles = run.body_positions.shape[1], run.particle_positions.shape[1]
    assert len(doc["nodes"]) >= 1 + bodies + particles + len(run.links)
    assert doc["nodes"][0]["rotation"] == pytest.approx([-np.sqrt(0.5), 0, 0, np.sqrt(0.5)])
    assert ("animations" in doc) == (name != "empty")


def test_identical_collider_sets_share_a_mesh(files: dict[str, Path]) -> None:
    glb = validate(files["dominoes"])
    doc = glb.doc
    run = run_of("dominoes")
    assert run.body_positions.shape[1] == 21
    # the ground and one domino
    assert len(doc["meshes"]) == 2
    ids = glb.ids
    meshes = [doc["nodes"][ids[f"body {b}"]]["mesh"] for b in range(21)]
    assert len(set(meshes[1:])) == 1 and meshes[0] != meshes[1]
    ground, domino = (doc["materials"][doc["meshes"][m]["primitives"][0]["material"]] for m in meshes[:2])
    assert ground["name"] == "static body" and ground["doubleSided"]
    assert ground["pbrMetallicRoughness"]["baseColorFactor"][:3] == pytest.approx([0.55] * 3)
    assert domino["name"].startswith("body ") and not domino.get("doubleSided", False)
    # the ragdoll's and the chain's bodies: a mesh for each distinct collider set and no more
    for name in ("ragdoll", "chain"):
        glb = validate(files[name])
        doc = glb.doc
        run = run_of(name)
        keys = {tuple((s.__reduce__()[1][0], tuple(p), tuple(q)) for s, p, q in body) for body in run.shapes}
        body_meshes = {doc["nodes"][glb.ids[f"body {b}"]]["mesh"] for b in range(len(run.shapes))}
        assert len(body_meshes) == len(keys) < len(run.shapes)


def test_materials(files: dict[str, Path]) -> None:
    colours = {}
    for name in ("cloth", "chain", "ragdoll", "particles"):
        glb = validate(files[name])
        doc = glb.doc
        for material in doc["materials"]:
            colour = tuple(material["pbrMetallicRoughness"]["baseColorFactor"])
            assert colours.setdefault(material["name"], colour) == colour  # a name is one colour everywhere
    assert {"spring", "joint", "particle", "static body"} <= set(colours)
    assert len(set(colours.values())) == len(colours)  # and the colours tell them apart
    # the ragdoll's stairs are static (grey), its parts several colours; the chain's links held at rest stay coloured
    glb = validate(files["ragdoll"])
    doc = glb.doc
    body_materials = {doc["meshes"][doc["nodes"][i]["mesh"]]["primitives"][0]["material"]
                      for n, i in glb.ids.items() if n.startswith("body ")}
    names = {doc["materials"][m]["name"] for m in body_materials}
    assert "static body" in names and len(names) >= 4
    glb = validate(files["chain"])
    doc = glb.doc
    assert "static body" not in {m["name"] for m in doc["materials"]}


@pytest.mark.parametrize("name", ["dominoes", "ragdoll", "particles", "chain"])
def test_poses_read_back(files: dict[str, Path], name: str) -> None:
    glb = validate(files[name])
    doc, data = glb.doc, glb.data
    run = run_of(name)
    ids = glb.ids
    animation = doc["animations"][0]
    times = data[animation["samplers"][0]["input"]][:, 0]
    np.testing.assert_allclose(times, run.times - run.times[0], atol=1e-6)
    for frame in (0, run.frames // 2, run.frames - 1):
        for b in range(run.body_positions.shape[1]):
            m = glb.world_matrix(ids[f"body {b}"], frame)
            np.testing.assert_allclose(m[:3, 3], Y_UP @ run.body_positions[frame, b], atol=1e-5)
            np.testing.assert_allclose(m[:3, :3], Y_UP @ rotation_matrix(run.body_orientations[frame, b]), atol=1e-6)
        for i in range(run.particle_positions.shape[1]):
            m = glb.world_matrix(ids[f"particle {i}"], frame)
            np.testing.assert_allclose(m[:3, 3], Y_UP @ run.particle_positions[frame, i], atol=1e-5)


@pytest.mark.parametrize("name", ["cloth", "chain", "ragdoll", "pendulum", "door", "spinning_top"])
def test_link_nodes_reproduce_the_segments(files: dict[str, Path], name: str) -> None:
    glb = validate(files[name])
    doc = glb.doc
    run = run_of(name)
    ids = glb.ids
    assert run.links
    for frame in (0, run.frames // 2, run.frames - 1):
        expected = run.link_segments(frame) @ Y_UP.T
        for i, (kind, *ends) in enumerate(run.links):
            label = f"spring {i}" if kind == "spring" else f"{kind} joint {i}"
            m = glb.world_matrix(ids[label], frame)
            ends_drawn = (m @ np.array([[0, 0, -0.5, 1], [0, 0, 0.5, 1]]).T).T[:, :3]
            np.testing.assert_allclose(ends_drawn, expected[i], atol=1e-5)
            if kind != "spring":  # the anchor spheres sit on both ends
                for j, end in enumerate("ab"):
                    anchor = glb.world_matrix(ids[f"{label} anchor {end}"], frame)
                    np.testing.assert_allclose(anchor[:3, 3], expected[i, j], atol=1e-5)
                    np.testing.assert_allclose(anchor[:3, :3] @ anchor[:3, :3].T, np.eye(3), atol=1e-6)
    mesh_names = {doc["meshes"][doc["nodes"][i]["mesh"]]["name"] for n, i in ids.items()
                  if n.startswith(("spring ",)) or " joint " in n and "anchor" not in n}
    assert mesh_names == {"spring" if run.links[0][0] == "spring" else "joint"}
    # the segments for all frames at once agree with Run.link_segments
    frames = np.arange(run.frames)
    np.testing.assert_allclose(segments(run, frames), np.stack([run.link_segments(int(k)) for k in frames]), atol=1e-12)


def test_rotations_are_continuous(files: dict[str, Path]) -> None:
    for name in ("cloth", "chain", "ragdoll", "dominoes"):
        glb = validate(files[name])
        doc, data = glb.doc, glb.data
        for animation in doc["animations"]:
            for channel in animation["channels"]:
                if channel["target"]["path"] == "rotation":
                    q = data[animation["samplers"][channel["sampler"]]["output"]].astype(float)
                    assert (np.sum(q[1:] * q[:-1], axis=1) >= 0).all()


def test_link_transforms_of_hard_segments() -> None:
    # a segment of zero length, then pointing down (-z), flipping through -z, up, and of zero length again
    directions = [[0, 0, 0], [0, 0, -1], [1e-9, 0, -1], [-1e-9, 1e-12, -1], [0.3, 0, -1], [0, 0, 1], [0, 0, 0],
                  [1, 0, 0], [-1, 0, 0]]
    a = np.array([1.0, 2.0, 3.0])
    segs = np.array([[[a, a + d]] for d in np.asarray(directions, dtype=float)])
    translation, rotation, length = transforms(segs, 1e-6)
    assert np.isfinite(rotation).all() and np.isfinite(translation).all()
    np.testing.assert_allclose(np.linalg.norm(rotation, axis=-1), 1, atol=1e-12)
    assert (length >= 1e-6).all()
    assert (np.sum(rotation[1:] * rotation[:-1], axis=-1) >= 0).all()
    axes = rotation_matrices(rotation[..., [3, 0, 1, 2]])[..., 2]
    for k, d in enumerate(np.asarray(directions, dtype=float)):
        n = np.linalg.norm(d)
        if n > 0:
            np.testing.assert_allclose(axes[k, 0], d / n, atol=1e-12)
            np.testing.assert_allclose(length[k, 0], n)
        np.testing.assert_allclose(translation[k, 0], a + d / 2)
    np.testing.assert_allclose(axes[6], axes[5])  # zero length keeps the previous direction


def test_gltf_round_trip(tmp_path: Path) -> None:
    """The first exporter's test: a body and a particle, keyed at every frame."""
    run = small_run()
    path = run.export_gltf(tmp_path / "anim.glb")
    gltf = pygltflib.GLTF2().load(str(path))
    # Root, one body, one particle.
    assert len(gltf.nodes) == 3 and gltf.nodes[1].mesh is not None
    blob = gltf.binary_blob()

    def read_accessor(index: int, width: int) -> np.ndarray:
        a = gltf.accessors[index]
        view = gltf.bufferViews[a.bufferView]
        return np.frombuffer(blob, np.float32, a.count * width, view.byteOffset + a.byteOffset).reshape(a.count, width)

    animation = gltf.animations[0]
    by_target = {(c.target.node, c.target.path): animation.samplers[c.sampler] for c in animation.channels}
    times = read_accessor(by_target[(1, "translation")].input, 1)[:, 0]
    np.testing.assert_allclose(times, run.times - run.times[0], atol=1e-6)
    translation = read_accessor(by_target[(1, "translation")].output, 3)
    np.testing.assert_allclose(translation, run.body_positions[:, 0], rtol=1e-6, atol=1e-6)
    rotation = read_accessor(by_target[(1, "rotation")].output, 4)
    q = run.body_orientations[:, 0][:, [1, 2, 3, 0]]
    np.testing.assert_allclose(rotation * np.sign(np.sum(rotation * q, axis=1))[:, None], q, atol=1e-6)
    particle = read_accessor(by_target[(2, "translation")].output, 3)
    np.testing.assert_allclose(particle, run.particle_positions[:, 0], rtol=1e-6, atol=1e-6)


def test_a_run_that_diverged_is_written_up_to_its_last_finite_frame(tmp_path: Path) -> None:
    run = run_of("chain")
    positions = run.body_positions.copy()
    positions[10:, 3] = np.nan
    glb = validate(dataclasses.replace(run, body_positions=positions).export_gltf(tmp_path / "nan.glb"))
    doc, data = glb.doc, glb.data
    assert len(data[doc["animations"][0]["samplers"][0]["input"]]) == 10
    # a single frame: placed, not animated
    one = dataclasses.replace(run, **{k: getattr(run, k)[:1] for k in ("times", "body_positions",
                                                                     "body_orientations", "particle_positions")})
    glb = validate(one.export_gltf(tmp_path / "one.glb"))
    doc = glb.doc
    assert "animations" not in doc and len(doc["nodes"]) > 21


MUTATIONS = {
    "a mesh out of range": lambda d: d["nodes"][1].__setitem__("mesh", len(d["meshes"])),
    "positions without min": lambda d: d["accessors"][d["meshes"][0]["primitives"][0]["attributes"]["POSITION"]].pop(
        "min"),
    "an accessor past its view": lambda d: d["accessors"][0].__setitem__("count", d["accessors"][0]["count"] + 1),
    "a cycle of nodes": lambda d: d["nodes"][2].setdefault("children", []).append(0),
    "a rotation not unit": lambda d: d["nodes"][1].__setitem__("rotation", [0, 0, 0, 2]),
    "an unused material": lambda d: d["materials"].append(d["materials"][0]),
    "an empty array": lambda d: d["nodes"][1].__setitem__("children", []),
    "times not increasing": lambda d: None,  # the first two keyframe times swapped in the binary chunk
}


@pytest.mark.parametrize("mutation", list(MUTATIONS))
def test_the_check_rejects_broken_files(files: dict[str, Path], tmp_path: Path, mutation: str) -> None:
    doc, blob = parse_glb(files["chain"].read_bytes())
    MUTATIONS[mutation](doc)
    if mutation == "times not increasing":
        times = doc["accessors"][doc["animations"][0]["samplers"][0]["input"]]
        start = doc["bufferViews"][times["bufferView"]]["byteOffset"] + times.get("byteOffset", 0)
        blob = blob[:start] + blob[start + 4:start + 8] + blob[start:start + 4] + blob[start + 8:]
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<I", len(text)) + b"JSON" + text + struct.pack("<I", len(blob)) + b"BIN\0" + blob
    path = tmp_path / "broken.glb"
    path.write_bytes(b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body)
    with pytest.raises(AssertionError):
        validate(path)


def test_bad_path(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"\.glb"):
        small_run().export_gltf(tmp_path / "anim.gltf")


# ---------------------------------------------------------------------------------------------------------------
# Other validators, where they can run: the Rust gltf crate (built once into pytest's cache; it checks the GLB
# container, the JSON schema's types and enums, and every reference) and gltfpack (cgltf's validation: accessors
# inside their views and buffers, index ranges, sampler counts).

CHECKER = """\
fn main() {
    let mut failed = false;
    for path in std::env::args().skip(1) {
        let data = std::fs::read(&path).expect("readable");
        if let Err(e) = gltf::Gltf::from_slice(&data) {
            println!("{path}: {e}");
            failed = true;
        }
    }
    std::process::exit(failed as i32);
}
"""


@pytest.fixture(scope="module")
def gltf_crate(request: pytest.FixtureRequest) -> Path:
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.skip("no cargo to build the gltf crate's check")
    folder = request.config.cache.mkdir("gltf-crate-check")
    (folder / "src").mkdir(exist_ok=True)
    (folder / "Cargo.toml").write_text('[package]\nname = "gltf-check"\nversion = "0.0.0"\nedition = "2021"\n\n'
                                       '[dependencies]\ngltf = { version = "1.4", default-features = false }\n\n'
                                       "[workspace]\n")
    if not (folder / "src" / "main.rs").exists() or (folder / "src" / "main.rs").read_text() != CHECKER:
        (folder / "src" / "main.rs").write_text(CHECKER)
    # its own target folder, whatever CARGO_TARGET_DIR says (CI sets it for the project's build)
    built = subprocess.run([cargo, "build", "--quiet", "--target-dir", str(folder / "target")], cwd=folder,
                           capture_output=True, text=True, timeout=900, check=False)
    if built.returncode:
        pytest.skip(f"the gltf crate could not be built here: {built.stderr[-500:]}")
    return folder / "target" / "debug" / "gltf-check"


def test_the_gltf_crate_accepts_the_files(files: dict[str, Path], gltf_crate: Path) -> None:
    checked = subprocess.run([str(gltf_crate), *map(str, files.values())], capture_output=True, text=True, check=False)
    assert checked.returncode == 0, checked.stdout


@pytest.mark.skipif(shutil.which("gltfpack") is None, reason="gltfpack (Debian's package) is not installed")
def test_gltfpack_accepts_the_files(files: dict[str, Path], tmp_path: Path) -> None:
    for name, path in files.items():
        packed = subprocess.run(["gltfpack", "-i", str(path), "-o", str(tmp_path / f"{name}.glb")],
                                capture_output=True, text=True, check=False)
        assert packed.returncode == 0 and "rror" not in packed.stderr + packed.stdout, (name, packed.stderr)
