"""Meshes from Python: ``tumble.Mesh`` from arrays, a ``trimesh.Trimesh`` or an OBJ, STL, PLY, glTF or GLB file
(units and up axis stated, a glTF's meshes placed by their nodes), its mass properties the solid's, bad meshes
refused by name with the world unchanged, ``add_body(mesh, ...)`` decomposed, as its hull or exact; and the user's
triangles (not the convex pieces) in the exported glTF and USD, at the simulated poses."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import tumble

# A unit cube's corners and outward triangles.
CUBE_V = np.array([[(i & 1), (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], dtype=float)
CUBE_T = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                   [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])


def test_a_mesh_from_arrays_has_the_solids_mass_properties() -> None:
    m = tumble.Mesh(CUBE_V * [0.3, 0.2, 0.5], CUBE_T, name="block")
    assert m.name == "block" and m.vertices.shape == (8, 3) and m.triangles.shape == (12, 3)
    p = m.mass_properties(700.0)
    a, b, c = 0.3, 0.2, 0.5
    mass = 700.0 * a * b * c
    # a box is integrated exactly: only rounding (1e-12 relative) separates it from the closed form
    assert p["mass"] == pytest.approx(mass, rel=1e-12)
    np.testing.assert_allclose(p["center_of_mass"], [a / 2, b / 2, c / 2], atol=1e-12)
    expected = np.diag([mass * (b * b + c * c), mass * (a * a + c * c), mass * (a * a + b * b)]) / 12.0
    np.testing.assert_allclose(p["inertia"], expected, atol=1e-12 * expected.max())
    assert isinstance(m, tumble.Shape) and m.kind == "mesh"


def test_a_trimesh_is_taken_as_it_is() -> None:
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box(extents=(0.2, 0.3, 0.4))
    m = tumble.Mesh(box)
    assert m.volume == pytest.approx(0.2 * 0.3 * 0.4, rel=1e-12)


@pytest.mark.parametrize("what, triangles, words", [
    ("open", CUBE_T[1:], "not closed"),
    ("inside out", CUBE_T[:, [0, 2, 1]], "inside out"),
    ("a flipped triangle", np.vstack([CUBE_T[:3], CUBE_T[3:4, [0, 2, 1]], CUBE_T[4:]]), "not consistently oriented"),
    ("a degenerate triangle", np.vstack([CUBE_T, [[0, 0, 1]]]), "degenerate"),
    ("a duplicate triangle", np.vstack([CUBE_T, CUBE_T[:1]]), "duplicates"),
    ("an index out of range", np.vstack([CUBE_T, [[0, 1, 99]]]), "referring past"),
])
def test_a_bad_mesh_is_refused_naming_it_and_what_is_wrong(what: str, triangles: np.ndarray, words: str) -> None:
    with pytest.raises(ValueError, match="mesh") as e:
        tumble.Mesh(CUBE_V, triangles, name="part")
    assert 'mesh "part"' in str(e.value) and words in str(e.value), what
    with pytest.raises(ValueError, match="not finite"):
        tumble.Mesh(np.where(CUBE_V == 1, np.nan, CUBE_V), CUBE_T)


def test_add_body_decomposes_a_moving_mesh_keeps_a_static_one_exact_and_refuses_what_does_not_apply() -> None:
    w = tumble.World()
    w.add_ground()
    mesh = tumble.Mesh(CUBE_V * 0.1, CUBE_T)
    w.add_body(mesh, density=500.0, position=(0, 0, 0.2))
    w.add_body(mesh, density=500.0, position=(0.3, 0, 0.2), shape="hull")
    w.add_body(mesh, static=True, position=(1, 0, 0.05))
    assert w.plan()["stages"][0] == "mesh-decomposition"
    w.step(0.1)
    before = (w.to_json(), w.bodies.positions.copy())
    for kwargs, words in [({"shape": "exact"}, "static"), ({"shape": "round"}, "decomposed"),
                          ({"decomposition": {"resolution": 2}}, "resolution"),
                          ({"decomposition": {"pieces": 3}}, "unknown key"),
                          ({"shape": "hull", "decomposition": {"resolution": 32}}, "decomposition")]:
        with pytest.raises(ValueError, match=words):
            w.add_body(mesh, density=500.0, **kwargs)
    with pytest.raises(ValueError, match="applies to a mesh"):
        w.add_body(tumble.Sphere(0.1), density=500.0, shape="hull")
    assert w.to_json() == before[0]
    np.testing.assert_array_equal(w.bodies.positions, before[1])


def test_pieces_are_convex_hulls_of_the_mesh() -> None:
    cup = tumble.scenes.ball_in_cup()
    pieces = tumble.Mesh(*tumble.Cylinder(0.05, 0.03).triangle_mesh(subdivisions=16)).pieces(resolution=32)
    assert pieces and all(isinstance(p, tumble.ConvexHull) for p in pieces)
    assert cup.report.mesh_pieces > 1 and "mesh_pieces" in cup.report.as_dict()


def write_obj(path: Path, v: np.ndarray, t: np.ndarray) -> None:
    lines = [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in v] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in t]
    path.write_text("o cube\n" + "\n".join(lines) + "\n")


def write_stl(path: Path, v: np.ndarray, t: np.ndarray) -> None:
    facets = []
    for tri in t:
        a, b, c = v[tri]
        n = np.cross(b - a, c - a)
        facets.append(f"facet normal {n[0]} {n[1]} {n[2]}\n outer loop\n" + "".join(
            f"  vertex {p[0]} {p[1]} {p[2]}\n" for p in (a, b, c)) + " endloop\nendfacet")
    path.write_text("solid cube\n" + "\n".join(facets) + "\nendsolid cube\n")


def write_ply(path: Path, v: np.ndarray, t: np.ndarray) -> None:
    head = ["ply", "format ascii 1.0", f"element vertex {len(v)}", "property double x", "property double y",
            "property double z", f"element face {len(t)}", "property list uchar int vertex_indices", "end_header"]
    path.write_text("\n".join(head + [f"{float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in v] + [f"3 {a} {b} {c}" for a, b, c in t])
                    + "\n")


def write_gltf(path: Path, v: np.ndarray, t: np.ndarray, translations: list[list[float]]) -> None:
    """A .gltf with one mesh used by a node per translation, its buffer embedded as a data URI."""
    import base64
    pos = v.astype(np.float32).tobytes()
    idx = t.astype(np.uint32).tobytes()
    blob = pos + idx
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3",
                       "min": v.min(axis=0).tolist(), "max": v.max(axis=0).tolist()},
                      {"bufferView": 1, "componentType": 5125, "count": t.size, "type": "SCALAR"}],
        "meshes": [{"name": "cube", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"name": f"cube {k}", "mesh": 0, "translation": tr} for k, tr in enumerate(translations)],
        "scenes": [{"nodes": list(range(len(translations)))}],
        "scene": 0,
    }
    path.write_text(json.dumps(doc))


@pytest.mark.parametrize("suffix, writer", [(".obj", write_obj), (".stl", write_stl), (".ply", write_ply)])
def test_a_mesh_file_loads_scaled_and_turned(tmp_path: Path, suffix: str, writer) -> None:
    path = tmp_path / f"cube{suffix}"
    writer(path, CUBE_V * [1, 2, 3], CUBE_T)  # 1 x 2 x 3 file units
    m = tumble.Mesh.load(path, scale=0.01)  # centimetres
    # STL stores float32: 1, 2, 3 are exact in it, so every format gives the volume to rounding
    assert m.volume == pytest.approx(6e-6, rel=1e-12)
    lo, hi = m.vertices.min(axis=0), m.vertices.max(axis=0)
    np.testing.assert_allclose(hi - lo, [0.01, 0.02, 0.03], atol=1e-15)
    # y up in the file: its 2-unit side becomes z (a +90 degree turn about x)
    up = tumble.Mesh.load(path, scale=0.01, up="y")
    np.testing.assert_allclose(up.vertices.max(axis=0) - up.vertices.min(axis=0), [0.01, 0.03, 0.02], atol=1e-15)
    assert up.volume == pytest.approx(m.volume, rel=1e-12)


def test_meshes_are_named_after_the_file_where_it_names_them_not(tmp_path: Path) -> None:
    """An OBJ without object names (tobj calls it "unnamed_object") and a GLB written by trimesh (its meshes
    "geometry_0", ...) give meshes named after the file, numbered as Blender numbers copies."""
    path = tmp_path / "die.obj"
    write_obj(path, CUBE_V, CUBE_T)
    path.write_text(path.read_text().replace("o cube\n", ""))  # no object name
    assert tumble.Mesh.load(path).name == "die" and [m.name for m in tumble.Mesh.load_all(path)] == ["die"]
    trimesh = pytest.importorskip("trimesh")
    scene = trimesh.Scene()
    for k in range(2):
        move = trimesh.transformations.translation_matrix((3 * k, 0, 0))
        scene.add_geometry(trimesh.creation.box(extents=(1, 1, 1)), transform=move)
    scene.export(tmp_path / "dice.glb")
    names = [m.name for m in tumble.Mesh.load_all(tmp_path / "dice.glb")]
    assert names == ["dice", "dice.001"], names
    assert tumble.Mesh.load(tmp_path / "dice.glb").name == "dice"


def test_load_refuses_to_merge_meshes_whose_solids_overlap_and_points_to_load_all(tmp_path: Path) -> None:
    """Two cubes sharing half their volume, merged, would count it twice; cubes apart merge into one mesh."""
    overlapping = tmp_path / "overlapping.gltf"
    write_gltf(overlapping, CUBE_V, CUBE_T, [[0, 0, 0], [0.5, 0, 0]])
    with pytest.raises(ValueError, match="overlap.*load_all"):
        tumble.Mesh.load(overlapping)
    assert len(tumble.Mesh.load_all(overlapping)) == 2
    # two cubes sharing a face merge into no solid (the face twice): said so, pointing to load_all as well
    touching = tmp_path / "touching.gltf"
    write_gltf(touching, CUBE_V, CUBE_T, [[0, 0, 0], [1, 0, 0]])
    with pytest.raises(ValueError, match="do not bound one solid.*load_all"):
        tumble.Mesh.load(touching)
    apart = tmp_path / "apart.gltf"
    write_gltf(apart, CUBE_V, CUBE_T, [[0, 0, 0], [1.5, 0, 0]])
    assert tumble.Mesh.load(apart).volume == pytest.approx(2.0, rel=1e-12)


def test_a_gltf_gives_each_mesh_at_its_node_and_load_merges_them(tmp_path: Path) -> None:
    path = tmp_path / "two.gltf"
    write_gltf(path, CUBE_V, CUBE_T, [[0, 0, 0], [3, 0, 0]])
    each = tumble.Mesh.load_all(path, up="z")
    assert [m.name for m in each] == ["cube 0", "cube 1"]
    np.testing.assert_allclose(each[1].vertices.min(axis=0), [3, 0, 0])
    # glTF is y up by its specification: by default the file's +y becomes +z and its +z becomes -y
    default = tumble.Mesh.load_all(path)
    np.testing.assert_allclose(default[1].vertices.min(axis=0), [3, -1, 0], atol=1e-15)
    np.testing.assert_allclose(default[1].vertices.max(axis=0), [4, 0, 1], atol=1e-15)
    merged = tumble.Mesh.load(path)
    assert merged.volume == pytest.approx(2.0, rel=1e-12) and len(merged.triangles) == 24
    # the same as a binary GLB
    pygltflib = pytest.importorskip("pygltflib")
    doc = pygltflib.GLTF2().load(str(path))
    doc.convert_buffers(pygltflib.BufferFormat.BINARYBLOB)
    doc.save_binary(str(tmp_path / "two.glb"))
    glb = tumble.Mesh.load_all(tmp_path / "two.glb", scale=0.5, up="y")
    assert len(glb) == 2 and glb[1].volume == pytest.approx(0.125, rel=1e-12)
    # y up: the node's +x translation stays along x, scaled
    np.testing.assert_allclose(glb[1].vertices.min(axis=0), [1.5, -0.5, 0.0], atol=1e-15)


def test_bad_files_are_refused_by_name(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="path"):
        tumble.Mesh.load(tmp_path / "missing.obj")
    (tmp_path / "x.fbx").write_text("")
    with pytest.raises(ValueError, match="unknown mesh format"):
        tumble.Mesh.load(tmp_path / "x.fbx")
    (tmp_path / "bad.ply").write_text("ply\nformat ascii 1.0\nnonsense\n")
    with pytest.raises(ValueError, match="bad.ply"):
        tumble.Mesh.load(tmp_path / "bad.ply")
    open_cube = tmp_path / "open.obj"
    write_obj(open_cube, CUBE_V, CUBE_T[1:])
    with pytest.raises(ValueError, match='mesh "cube" is not closed'):
        tumble.Mesh.load(open_cube)
    with pytest.raises(ValueError, match="up"):
        tumble.Mesh.load(open_cube, up="x")
    with pytest.raises(ValueError, match="scale"):
        tumble.Mesh.load(open_cube, scale=-1.0)


def rotation(wxyz: np.ndarray) -> np.ndarray:
    w, x, y, z = wxyz
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def world_vertices(mesh: tumble.Mesh, position: np.ndarray, wxyz: np.ndarray) -> np.ndarray:
    """The mesh's vertices where a body of it with its centre of mass at `position`, turned by `wxyz`, puts them:
    the centre of mass is the body frame's origin, so a vertex sits at R (v - com) + x."""
    com = mesh.mass_properties(1.0)["center_of_mass"]
    return (mesh.vertices - com) @ rotation(wxyz).T + position


# float32 (glTF's only vertex and key type, USD's points) rounds each value by half an ulp, 6e-8 of it: at most
# 6e-9 m for the cup's 8 cm and the run's 0.1 m, a few such roundings composed: 3e-8 m.
FLOAT32 = 3e-8


def tossed_cup(tmp_path: Path) -> tuple[tumble.Run, tumble.Mesh]:
    mesh = tumble.Mesh(*tumble.Shape.triangle_mesh(tumble.Cylinder(0.04, 0.03), subdivisions=12), name="tin")
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground()
    h = w.add_body(mesh, density=800.0, position=(0.0, 0.0, 0.1), angular_velocity=(1.0, 2.0, 0.5))
    # placed by its modelled frame: the mesh's origin where it was put
    np.testing.assert_array_equal(w.bodies.origins[w.bodies.handles.index(h)], [0.0, 0.0, 0.1])
    return w.run(duration=0.5, frame_interval=1 / 30), mesh


def test_the_exported_gltf_draws_the_users_mesh_at_the_simulated_poses(tmp_path: Path) -> None:
    pygltflib = pytest.importorskip("pygltflib")
    run, mesh = tossed_cup(tmp_path)
    g = pygltflib.GLTF2().load(str(run.export_gltf(tmp_path / "cup.glb")))
    blob = g.binary_blob()

    def read(index: int, width: int, dtype=np.float32) -> np.ndarray:
        a = g.accessors[index]
        view = g.bufferViews[a.bufferView]
        return np.frombuffer(blob, dtype, a.count * width, view.byteOffset + a.byteOffset).reshape(a.count, width)

    node = next(k for k, n in enumerate(g.nodes) if n.name == "body 1")
    # the body's node holds the mesh directly or through a child
    holder = g.nodes[node] if g.nodes[node].mesh is not None else g.nodes[g.nodes[node].children[0]]
    prim = g.meshes[holder.mesh].primitives[0]
    local = read(prim.attributes.POSITION, 3).astype(float)
    assert len(local) == len(mesh.vertices), "the user's mesh, not its pieces"
    animation = g.animations[0]
    by_target = {(c.target.node, c.target.path): animation.samplers[c.sampler] for c in animation.channels}
    t = read(by_target[(node, "translation")].output, 3).astype(float)
    q = read(by_target[(node, "rotation")].output, 4).astype(float)
    # the node's pivot is the mesh's own origin (its vertices as modelled), not the centre of mass
    np.testing.assert_allclose(local, mesh.vertices, atol=FLOAT32, rtol=0)
    for frame in (0, len(t) // 2, len(t) - 1):
        x, y, z, w = q[frame]
        theirs = local @ rotation(np.array([w, x, y, z])).T + t[frame]
        mine = world_vertices(mesh, run.body_positions[frame, 1], run.body_orientations[frame, 1])
        np.testing.assert_allclose(theirs, mine, atol=FLOAT32, rtol=0)


def test_the_exported_usd_draws_the_users_mesh_at_the_simulated_poses(tmp_path: Path) -> None:
    pytest.importorskip("pxr", reason="usd-core is the `usd` extra")
    from pxr import Usd, UsdGeom
    from tumble.usd._write import time_codes
    run, mesh = tossed_cup(tmp_path)
    stage = Usd.Stage.Open(str(run.export_usd(tmp_path / "cup.usdc")))
    prim = stage.GetPrimAtPath("/World/body_1/collider_0/mesh")
    points = np.array(UsdGeom.Mesh(prim).GetPointsAttr().Get(), dtype=float)
    assert len(points) == len(mesh.vertices), "the user's mesh, not its pieces"
    # the body's pivot is the mesh's origin: at the start, where it was placed
    body = UsdGeom.Xformable(stage.GetPrimAtPath("/World/body_1")).ComputeLocalToWorldTransform(Usd.TimeCode(0))
    np.testing.assert_allclose(np.array(body.ExtractTranslation()), [0.0, 0.0, 0.1], atol=1e-15)
    for frame in (0, len(run.times) // 2, len(run.times) - 1):
        code = float(time_codes(run.times)[frame])
        m = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(code)))
        theirs = np.c_[points, np.ones(len(points))] @ m  # row vectors
        mine = world_vertices(mesh, run.body_positions[frame, 1], run.body_orientations[frame, 1])
        np.testing.assert_allclose(theirs[:, :3], mine, atol=FLOAT32, rtol=0)
