"""The colliders' mesher that every exporter uses (``tumble._mesh``): each shape's mesh closed, its triangles facing
outwards, enclosing the shape's volume; colliders placed by their offset and orientation; a half-space's plane."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tumble
from tumble import _mesh


def volume(v: np.ndarray, t: np.ndarray) -> float:
    """The volume a closed mesh encloses (positive when its triangles face outwards)."""
    a, b, c = (v[t[:, k].astype(np.int64)] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def closed(t: np.ndarray) -> bool:
    """Every edge is on two triangles that run along it in opposite directions (a closed, consistently wound
    surface)."""
    directed = [(int(a), int(b)) for tri in t for a, b in zip(tri, np.roll(tri, -1))]
    return len(set(directed)) == len(directed) and all((b, a) in set(directed) for a, b in directed)


def outward(v: np.ndarray, t: np.ndarray, centre: np.ndarray) -> bool:
    """Every triangle of a convex mesh faces away from a point inside it."""
    a, b, c = (v[t[:, k].astype(np.int64)] for k in range(3))
    normals = np.cross(b - a, c - a)
    return bool((np.einsum("ij,ij->i", normals, (a + b + c) / 3 - centre) > 0).all())


def test_a_box_is_8_vertices_and_12_triangles_around_its_volume():
    v, t = _mesh.shape_mesh(tumble.Box((0.5, 1.0, 2.0)))
    assert v.shape == (8, 3) and t.shape == (12, 3)
    np.testing.assert_array_equal(np.sort(np.abs(v), axis=0)[0], [0.5, 1.0, 2.0])  # the corners
    assert closed(t) and outward(v, t, np.zeros(3))
    assert volume(v, t) == pytest.approx(8 * 0.5 * 1.0 * 2.0, rel=1e-12)


def test_a_sphere_has_its_vertices_on_the_radius_and_faces_out():
    radius = 0.7
    for subdivisions in (_mesh.PREVIEW, _mesh.MARKER, _mesh.EXPORT):
        v, t = _mesh.shape_mesh(tumble.Sphere(radius), subdivisions)
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), radius, rtol=1e-12)
        assert closed(t) and outward(v, t, np.zeros(3))
        # inscribed: a little less than the ball, closer the finer
        assert 0.8 * 4 / 3 * math.pi * radius**3 < volume(v, t) < 4 / 3 * math.pi * radius**3
    coarse, fine = (_mesh.shape_mesh(tumble.Sphere(radius), n)[0] for n in (_mesh.PREVIEW, _mesh.EXPORT))
    assert len(coarse) < len(fine)  # the resolution is the parameter


def test_round_shapes_and_hulls_are_closed_and_enclose_their_volume():
    n = _mesh.EXPORT
    polygon = n / 2 * math.sin(2 * math.pi / n)  # the area of the n-gon inscribed in a unit circle
    cylinder = _mesh.shape_mesh(tumble.Cylinder(half_height=0.5, radius=0.2), n)
    assert np.abs(cylinder[0][:, 2]).max() == pytest.approx(0.5)  # along z
    assert volume(*cylinder) == pytest.approx(polygon * 0.2**2 * 1.0, rel=1e-9)
    capsule = _mesh.shape_mesh(tumble.Capsule(half_height=0.5, radius=0.2), n)
    assert np.abs(capsule[0][:, 2]).max() == pytest.approx(0.7)
    exact = math.pi * 0.2**2 * 1.0 + 4 / 3 * math.pi * 0.2**3
    assert 0.95 * exact < volume(*capsule) < exact
    tetrahedron = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    hull = _mesh.shape_mesh(tumble.ConvexHull(tetrahedron + [(0.1, 0.1, 0.1)]))  # an inner point is dropped
    assert len(hull[0]) == 4 and volume(*hull) == pytest.approx(1 / 6, rel=1e-12)
    for v, t in (cylinder, capsule, hull):
        assert closed(t) and outward(v, t, v.mean(axis=0))


def test_a_triangle_mesh_comes_back_as_given():
    vertices = np.array([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], dtype=float)
    triangles = np.array([(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)])
    v, t = _mesh.shape_mesh(tumble.TriMesh(vertices, triangles))
    np.testing.assert_array_equal(v, vertices)
    np.testing.assert_array_equal(t, triangles)


def test_a_half_space_is_a_square_on_its_plane_facing_out_of_the_solid():
    world = tumble.World()
    world.add_ground(height=0.0)
    ((shape, _, _),) = world.run(0.01).shapes[0]  # the ground's one collider
    assert shape.kind == "half-space"
    v, t = _mesh.shape_mesh(shape, extent=3.0)
    assert v.shape == (4, 3) and t.shape == (2, 3)
    np.testing.assert_array_equal(v[:, 2], 0.0)
    np.testing.assert_array_equal(np.sort(np.abs(v[:, :2]).ravel()), np.full(8, 3.0))
    point, normal = _mesh.half_space_plane(shape)
    np.testing.assert_array_equal(point, [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(normal, [0.0, 0.0, 1.0])  # the solid is below z = 0
    a, b, c = (v[t[:, k].astype(np.int64)] for k in range(3))
    assert (np.cross(b - a, c - a)[:, 2] > 0).all()  # both triangles face up, as the plane's normal


def test_a_collider_is_placed_by_its_offset_and_orientation():
    box = tumble.Box((0.1, 0.2, 0.3))
    quarter = (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))  # 90 degrees about z
    v, t = _mesh.collider_mesh(box, (1.0, 2.0, 3.0), quarter)
    local, same = _mesh.shape_mesh(box)
    np.testing.assert_array_equal(t, same)
    turned = np.stack([-local[:, 1], local[:, 0], local[:, 2]], axis=1)  # (x, y) -> (-y, x)
    np.testing.assert_allclose(v, turned + (1.0, 2.0, 3.0), atol=1e-15)
    # a body of two colliders: one mesh, the second's triangles numbered after the first's vertices
    sphere = tumble.Sphere(0.1)
    v2, t2 = _mesh.body_mesh([(box, (1.0, 2.0, 3.0), quarter), (sphere, (0.0, 0.0, -1.0), (1.0, 0.0, 0.0, 0.0))])
    s, st = _mesh.shape_mesh(sphere)
    assert len(v2) == 8 + len(s) and len(t2) == 12 + len(st)
    np.testing.assert_array_equal(v2[:8], v)
    np.testing.assert_array_equal(v2[8:], s + (0.0, 0.0, -1.0))
    np.testing.assert_array_equal(t2[12:], st + 8)
    assert volume(v2, t2) == pytest.approx(volume(local, same) + volume(s, st), rel=1e-12)
    empty_v, empty_t = _mesh.body_mesh([])
    assert empty_v.shape == (0, 3) and empty_t.shape == (0, 3)
