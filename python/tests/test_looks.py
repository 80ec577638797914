"""Bodies' names and colours (``add_body(name=..., color=...)``): checked by name, kept by copies, saved worlds and
runs, and written as glTF node names and materials, USD prim names and display colours, and the viewer's colours;
no part of the physics."""

import copy
import math

import numpy as np
import pytest

import tumble
from gltf_check import validate


def world(looks: bool = True) -> tumble.World:
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground(friction=0.5)
    named = {"name": "red box", "color": (0.8, 0.1, 0.1)} if looks else {}
    w.add_body(tumble.Box(half_extents=(0.2, 0.2, 0.2)), density=500.0, position=(0.0, 0.0, 0.5), **named)
    w.add_body(tumble.Box(half_extents=(0.2, 0.2, 0.2)), density=500.0, position=(1.0, 0.0, 0.5))
    glass = {"name": "glass ball", "color": (0.2, 0.4, 0.9, 0.5)} if looks else {}
    w.add_body(tumble.Sphere(radius=0.1), density=500.0, position=(0.0, 1.0, 0.8), **glass)
    # a second body of the same name, and one whose name is no USD identifier
    w.add_body(tumble.Sphere(radius=0.1), density=500.0, position=(1.0, 1.0, 0.8), **({"name": "glass ball"} if looks else {}))
    w.add_body(tumble.Sphere(radius=0.1), density=500.0, position=(2.0, 1.0, 0.8), **({"name": "3rd/ball"} if looks else {}))
    return w


EXPECTED_NAMES = [None, "red box", None, "glass ball", "glass ball", "3rd/ball"]  # row 0: the ground
EXPECTED_COLORS = [None, (0.8, 0.1, 0.1, 1.0), None, (0.2, 0.4, 0.9, 0.5), None, None]


def test_the_world_and_its_copies_and_files_keep_them(tmp_path):
    w = world()
    assert w.bodies.names == EXPECTED_NAMES
    assert w.bodies.colors == EXPECTED_COLORS  # RGB is opaque RGBA
    w.step(0.1)
    for copied in (copy.deepcopy(w), tumble.World.load(w.save(tmp_path / "w.json")),
                   tumble.World.load(w.save(tmp_path / "w.tumble"))):
        assert copied.bodies.names == EXPECTED_NAMES
        assert copied.bodies.colors == EXPECTED_COLORS


def test_runs_keep_them_and_save_them(tmp_path):
    run = world().run(0.1, 1 / 60)
    assert run.names == EXPECTED_NAMES and run.colors == EXPECTED_COLORS
    assert run.label(1) == "red box" and run.label(2) == "body 2"
    loaded = tumble.Run.load(run.save(tmp_path / "run.npz"))
    assert loaded.names == EXPECTED_NAMES and loaded.colors == EXPECTED_COLORS


def test_they_are_no_part_of_the_physics():
    a, b = world(True), world(False)
    ra, rb = a.run(0.5, 1 / 60), b.run(0.5, 1 / 60)
    assert np.array_equal(ra.body_positions, rb.body_positions)
    assert np.array_equal(ra.body_orientations, rb.body_orientations)


@pytest.mark.parametrize("kwargs, argument", [
    ({"name": ""}, "name"), ({"name": "a\nb"}, "name"), ({"name": "x" * 257}, "name"),
    ({"color": (1.2, 0.0, 0.0)}, "color"), ({"color": (0.0, math.nan, 0.0)}, "color"),
    ({"color": (0.1, 0.2)}, "color"), ({"color": (0.1, 0.2, 0.3, 0.4, 0.5)}, "color"), ({"color": "red"}, "color"),
])
def test_bad_names_and_colours_are_refused_by_name(kwargs, argument):
    w = world()
    before = w.bodies.names
    with pytest.raises(ValueError, match=f"`{argument}`"):
        w.add_body(tumble.Sphere(radius=0.1), density=500.0, **kwargs)
    assert w.bodies.names == before  # nothing was added


def test_gltf_nodes_carry_the_names_and_materials_the_colours(tmp_path):
    run = world().run(0.1, 1 / 60)
    glb = validate(run.export_gltf(tmp_path / "looks.glb"))
    doc = glb.doc
    nodes = [n["name"] for n in doc["nodes"]]
    for b, name in enumerate(EXPECTED_NAMES):
        assert (name if name is not None else f"body {b}") in nodes

    def material_of(node_name):
        node = next(n for n in doc["nodes"] if n["name"] == node_name)
        return doc["materials"][doc["meshes"][node["mesh"]]["primitives"][0]["material"]]

    red = material_of("red box")
    assert red["pbrMetallicRoughness"]["baseColorFactor"] == pytest.approx([0.8, 0.1, 0.1, 1.0])
    assert red.get("alphaMode", "OPAQUE") == "OPAQUE"
    glass = material_of("glass ball")
    assert glass["pbrMetallicRoughness"]["baseColorFactor"] == pytest.approx([0.2, 0.4, 0.9, 0.5])
    assert glass["alphaMode"] == "BLEND"
    # the uncoloured box of the red box's shape keeps a palette colour: colour splits a shared mesh
    assert material_of("body 2")["name"] != red["name"]


def test_usd_prims_carry_the_names_and_display_colours(tmp_path):
    pytest.importorskip("pxr", reason="usd-core is the `usd` extra")
    from pxr import Usd, UsdGeom  # noqa: PLC0415

    run = world().run(0.1, 1 / 60)
    stage = Usd.Stage.Open(str(run.export_usd(tmp_path / "looks.usda")))
    children = [p.GetName() for p in stage.GetPrimAtPath("/World").GetChildren()]
    # valid, unique identifiers; the unnamed keep body_N
    assert children[:6] == ["body_0", "red_box", "body_2", "glass_ball", "glass_ball_2", "_3rd_ball"]
    mesh = UsdGeom.Gprim(stage.GetPrimAtPath("/World/red_box/collider_0/mesh"))
    assert list(mesh.GetDisplayColorAttr().Get()[0]) == pytest.approx([0.8, 0.1, 0.1], rel=1e-6)  # float32
    glass = UsdGeom.Gprim(stage.GetPrimAtPath("/World/glass_ball/collider_0/mesh"))
    assert glass.GetDisplayOpacityAttr().Get()[0] == pytest.approx(0.5)
    # the uncoloured ball of the same shared mesh is not coloured by the other's opinion
    assert not UsdGeom.Gprim(stage.GetPrimAtPath("/World/glass_ball_2/collider_0/mesh")).GetDisplayColorAttr().Get()
    for shape in stage.GetPrimAtPath("/Shapes").GetChildren():
        assert UsdGeom.Mesh(shape).GetSubdivisionSchemeAttr().Get() == UsdGeom.Tokens.none


def test_the_viewer_shows_the_colours_in_srgb():
    from tumble.viewer._scene import PALETTE, body_colors  # noqa: PLC0415

    run = world().run(0.05, 1 / 60)
    colours = body_colors(run, 6)
    # linear 0.8 is sRGB 0.906 (231 of 255), linear 0.1 is 0.349 (89)
    assert tuple(colours[1]) == (231, 89, 89)
    assert tuple(colours[2]) == tuple(PALETTE[2])
