"""Fracture from Python: Mesh.fracture's pieces (closed, their volumes the mesh's, the same seed the same bits),
World.add_fractured's glue (bounds from face area times strength, exact on a two-piece bar), a glued object that
holds until it is hit, and bad input refused by name, the world left as it was."""

import copy
import math

import numpy as np
import pytest

import tumble


def slab(name="pane", half=(0.2, 0.01, 0.15)):
    v, t = tumble.Box(half).triangle_mesh()
    return tumble.Mesh(v, t, name=name)


def test_pieces_are_closed_solids_that_fill_the_mesh_and_the_seed_decides_them():
    pane = slab()
    pieces = pane.fracture(pieces=12, seed=3)
    assert len(pieces) == 12 and [p.name for p in pieces[:2]] == ["pane.001", "pane.002"]
    # volumes add up to the mesh's to rounding (1e-12 relative: a few hundred cut points, each exact to 1e-16)
    assert sum(p.volume for p in pieces) == pytest.approx(pane.volume, rel=1e-12)
    again = pane.fracture(pieces=12, seed=3)
    assert all(np.array_equal(a.vertices, b.vertices) for a, b in zip(pieces, again))
    other = pane.fracture(pieces=12, seed=4)
    assert not np.array_equal(pieces[0].vertices, other[0].vertices)


def test_given_points_cut_where_asked():
    bar = slab("bar", (1.0, 0.1, 0.05))
    halves = bar.fracture(points=[(-0.5, 0, 0), (1.0, 0, 0)])
    # the plane halfway between the points, x = 0.25: 1.25 and 0.75 of the 0.02 m^2 section
    assert [h.volume for h in halves] == pytest.approx([0.025, 0.015], abs=1e-15)


def test_a_two_piece_bar_is_glued_by_one_weld_with_bounds_from_its_section():
    bar = slab("bar", (1.0, 0.1, 0.05))
    halves = bar.fracture(points=[(-0.5, 0, 0), (0.5, 0, 0)])
    w = tumble.World(mode="fast")
    hs = w.add_fractured(bar, halves, density=1000.0, strength=2e5)
    assert len(hs) == 2 and w.bodies.names[:2] == ["bar.001", "bar.002"]
    (joint,) = w.joint_handles
    force, torque, window = w.joint_breaking(joint)
    area = 0.2 * 0.1
    # force: strength x area; torque: strength x area x r / 4 (a round face of that area, r = sqrt(area / pi))
    assert force == pytest.approx(2e5 * area, rel=1e-12)
    assert torque == pytest.approx(2e5 * area * math.sqrt(area / math.pi) / 4, rel=1e-12)
    assert window == 0.01
    # placed where they were modelled: the two centres of mass at x = -0.5 and 0.5
    assert w.bodies.positions[:, 0] == pytest.approx([-0.5, 0.5], abs=1e-12)


@pytest.mark.parametrize("mode", ["fast", "accurate"])
def test_a_glued_bar_hangs_as_one_until_loaded_past_its_strength(mode):
    """A 2 m bar of two glued halves hanging from one end: the weld carries the free half's weight (98.1 N at
    10 kg, its torque 98.1 x 0.5 N m about the face's centre); at a strength that holds that, it hangs as one; at
    half that, it breaks."""
    bar = slab("bar", (1.0, 0.1, 0.05))
    halves = bar.fracture(points=[(-0.5, 0, 0), (0.5, 0, 0)])
    area = 0.2 * 0.1
    torque = 10.0 * 9.81 * 0.5
    holds = 2.0 * torque * 4 / (area * math.sqrt(area / math.pi))  # strength whose torque bound is twice the load
    for strength, breaks in ((holds, False), (holds / 4, True)):
        w = tumble.World(mode=mode) if mode == "fast" else tumble.World()
        a, b = w.add_fractured(bar, halves, density=500.0, strength=strength)
        w.add_joint(tumble.Weld(a, None, anchor_a=(0, 0, 0), world_point=(-0.5, 0, 0)))
        w.run(0.5)
        assert bool(w.broken_joints()) == breaks
        if not breaks:
            # held: the free half's centre within a millimetre of where it was glued (soft welds sag a little)
            assert np.linalg.norm(w.bodies.positions[w.bodies.row(b)] - (0.5, 0, 0)) < 1e-3


def test_bad_input_is_refused_by_name_and_nothing_is_added():
    pane = slab()
    for kwargs, name in [(dict(pieces=0), "pieces"), (dict(pieces=5000), "pieces"), (dict(), "pieces"),
                         (dict(points=[(5.0, 0, 0)]), "points"), (dict(points=[(0, 0, 0)], seed=1), "seed"),
                         (dict(pieces=4, near=(9.0, 0, 0)), "near")]:
        with pytest.raises(ValueError, match=f"`{name}`"):
            pane.fracture(**kwargs)
    pieces = pane.fracture(pieces=4, seed=0)
    w = tumble.World()
    w.add_ground()
    before = copy.copy(w)
    for kwargs, name in [(dict(strength=0.0), "strength"), (dict(strength=float("nan")), "strength"),
                         (dict(strength=1e6, window=-1.0), "window"), (dict(), "strength")]:
        with pytest.raises(ValueError, match=f"`{name}`"):
            w.add_fractured(pane, pieces, **kwargs)
    with pytest.raises(ValueError, match="`pieces`"):
        w.add_fractured(pane, pieces[:2], strength=1e6)
    assert len(w.bodies.handles) == len(before.bodies.handles) and w.joint_count == 0
    w.run(0.1)
    before.run(0.1)
    assert np.array_equal(w.bodies.positions, before.bodies.positions)


def test_a_glued_object_is_kept_by_files_and_copies_to_the_bit(tmp_path):
    """A pane glued and hit, saved mid-run (its welds' bounds, windows and averaged loads, which have broken) and
    copied: the loaded world and the copy go on as the world does, bit for bit; the pieces keep their names."""
    w = tumble.scenes.glass_pane()
    w.run(0.125)
    path = w.save(tmp_path / "pane.tumble")
    loaded = tumble.World.load(path)
    twin = copy.copy(w)
    runs = [x.run(0.125) for x in (w, loaded, twin)]
    for other in runs[1:]:
        assert np.array_equal(runs[0].body_positions, other.body_positions)
    # (a loaded world's handles are its own: the broken welds are compared by count)
    assert len(loaded.broken_joints()) == len(w.broken_joints()) > 0
    assert loaded.bodies.names[1:3] == ["pane.001", "pane.002"]  # after the ground
    assert [loaded.joint_breaking(j) for j in loaded.joint_handles] == [w.joint_breaking(j) for j in w.joint_handles]
