"""glTF export: the .glb files of several scenes checked the way the Khronos glTF validator checks them, by hand
(``validate``: the validator ships only on npm and as GitHub release binaries, neither reachable here; no PyPI or
Debian package has it, and the crates.io wrapper gltf-validator downloads the binary when built), plus the Rust
``gltf`` crate's validation and meshoptimizer's gltfpack (cgltf's validation) where they can run; shared meshes,
materials, poses read back, and the springs' and joints' nodes against ``Run.link_segments``."""

import dataclasses
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
from tumble.export._gltf_links import segments, transforms

from gltf_check import Y_UP, parse_glb, validate

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
    # the ground, and a domino for each of the dominoes' two colours: the two share one geometry
    assert len(doc["meshes"]) == 3
    ids = glb.ids
    meshes = [doc["nodes"][ids[run.label(b)]]["mesh"] for b in range(21)]
    assert len(set(meshes[1:])) == 2 and meshes[0] not in meshes[1:]
    first, second = (doc["meshes"][m]["primitives"][0] for m in meshes[1:3])
    assert first["attributes"] == second["attributes"] and first["indices"] == second["indices"]
    ground = doc["materials"][doc["meshes"][meshes[0]]["primitives"][0]["material"]]
    domino = doc["materials"][first["material"]]
    assert ground["name"] == "static body" and ground["doubleSided"]
    assert ground["pbrMetallicRoughness"]["baseColorFactor"][:3] == pytest.approx([0.55] * 3)
    assert domino["name"].startswith("colour ") and not domino.get("doubleSided", False)
    assert domino["pbrMetallicRoughness"]["baseColorFactor"] == pytest.approx(run.colors[1])
    # the ragdoll's and the chain's bodies: a mesh for each distinct collider set and no more
    for name in ("ragdoll", "chain"):
        glb = validate(files[name])
        doc = glb.doc
        run = run_of(name)
        # (a collider set's bodies share a colour in these scenes)
        keys = {tuple((s.__reduce__()[1][0], tuple(p), tuple(q)) for s, p, q in body) for body in run.shapes}
        body_meshes = {doc["nodes"][glb.ids[run.label(b)]]["mesh"] for b in range(len(run.shapes))}
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
    # and the colours tell them apart, and from every body's
    own = {name: colours[name] for name in ("spring", "joint", "particle", "static body")}
    assert len(set(own.values())) == 4
    assert all(c not in own.values() for name, c in colours.items() if name not in own)
    # the ragdoll's stairs are static (grey), its parts several colours; the chain's links held at rest stay coloured
    glb = validate(files["ragdoll"])
    doc = glb.doc
    run = run_of("ragdoll")
    body_materials = {doc["meshes"][doc["nodes"][glb.ids[run.label(b)]]["mesh"]]["primitives"][0]["material"]
                      for b in range(len(run.shapes))}
    names = {doc["materials"][m]["name"] for m in body_materials}
    # the ground (unnamed, grey), the steps, the torso and head, the limbs
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
            m = glb.world_matrix(ids[run.label(b)], frame)
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
