"""Built-in scenes. ``cloth`` and ``spinning_top`` are built through the public API in the same order as the Rust
library's ``tumble::scenes``, so the two give the same numbers; the contact scenes come from the Rust library."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ._world import World

if TYPE_CHECKING:
    from ._tumble import Mesh, ParticleHandle


def cloth(
    n: int = 16,
    size: float = 1.0,
    mass: float = 0.5,
    stiffness: float = 1e3,
    damping: float = 0.5,
    pin_stiffness: float = 1e4,
) -> World:
    """A square cloth of n x n particles (total ``mass``, side ``size``) at height 1 m, corners (0, 0) and
    (size, 0) pinned by stiff springs, structural springs between neighbours and shear springs across every cell;
    stepped by implicit Euler at 1/240 s."""
    if not isinstance(n, int) or isinstance(n, bool):
        raise ValueError(f"invalid argument `n`: a cloth needs a whole number of particles a side, got {n!r}")
    World._check_scene(
        "cloth", n=n, size=size, mass=mass, stiffness=stiffness, damping=damping, pin_stiffness=pin_stiffness
    )
    w = World(integrator="implicit-euler", dt=1.0 / 240.0)
    spacing = size / (n - 1)
    m = mass / (n * n)
    ps = [w.add_particle(mass=m, position=(i * spacing, j * spacing, 1.0)) for j in range(n) for i in range(n)]

    def at(i: int, j: int) -> ParticleHandle:
        return ps[j * n + i]

    def spring(a: ParticleHandle, b: ParticleHandle) -> None:
        w.add_spring(a, b, stiffness=stiffness, damping=damping)

    for j in range(n):
        for i in range(n):
            if i + 1 < n:
                spring(at(i, j), at(i + 1, j))
            if j + 1 < n:
                spring(at(i, j), at(i, j + 1))
            if i + 1 < n and j + 1 < n:
                spring(at(i, j), at(i + 1, j + 1))
                spring(at(i + 1, j), at(i, j + 1))
    for corner in (at(0, 0), at(n - 1, 0)):
        index = ps.index(corner)
        x = tuple(w.particles.positions[index])
        w.add_spring(corner, None, stiffness=pin_stiffness, damping=damping, rest_length=0.0, world_point=x)
    return w


def spinning_top() -> World:
    """A heavy symmetric top (1 kg, I1 = I2 = 0.02, I3 = 0.04 kg m^2, centre of mass 0.1 m from its tip) whose tip a
    stiff damped spring holds at the origin; tilted 0.3 rad and spinning at 40 rad/s, it precesses at about
    0.618 rad/s (the slow root of I1 cos(theta) W^2 - I3 w3 W + M g l = 0). Stepped by Radau5 at 1e-8."""
    mass, i1, i3, arm, spin, tilt = 1.0, 0.02, 0.04, 0.1, 40.0, 0.3
    w = World(integrator="radau5", rtol=1e-8, atol=1e-8)
    axis = (0.0, -math.sin(tilt), math.cos(tilt))
    top = w.add_body(
        None,
        mass=mass,
        inertia=[[i1, 0, 0], [0, i1, 0], [0, 0, i3]],
        position=tuple(arm * a for a in axis),
        orientation=(math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0),
        angular_velocity=tuple(spin * a for a in axis),
    )
    w.add_spring(top, None, stiffness=1e5, damping=50.0, rest_length=0.0, anchor_a=(0, 0, -arm), world_point=(0, 0, 0))
    return w


def bouncing_ball(restitution: float = 0.8, radius: float = 0.1, height: float = 1.0) -> World:
    """A ball dropped from ``height`` onto the floor, bouncing with ``restitution`` (accurate mode, Dormand-Prince at
    1e-10): the n-th apex is at restitution^(2n) x height, and the ball comes to rest after finitely many bounces."""
    return World._rust_scene("bouncing_ball", restitution=restitution, radius=radius, height=height)


def tumbling_box() -> World:
    """A box thrown spinning onto the floor, brought to rest by friction and restitution 0.3 (fast mode)."""
    return World._rust_scene("tumbling_box")


def dominoes(count: int = 20, spacing: float = 0.5) -> World:
    """A row of ``count`` dominoes (0.08 x 0.4 x 0.8 m) ``spacing`` apart; the first is tipped (fast mode)."""
    return World._rust_scene("dominoes", count=count, spacing=spacing)


def pyramid(layers: int = 10) -> World:
    """A 2D pyramid of 0.5 m cubes, ``layers`` high, each resting on two below (fast mode)."""
    return World._rust_scene("pyramid", layers=layers)


def cloth_drape(n: int = 12, size: float = 1.2) -> World:
    """A cloth of n x n particles (1 cm spheres) falling over a ball onto the floor (fast mode at 1/480 s)."""
    return World._rust_scene("cloth_drape", n=n, size=size)


def pendulum(length: float = 1.0, radius: float = 0.05) -> World:
    """A 1 kg ball on a rigid rod of ``length`` from a fixed point, released from the horizontal (accurate mode,
    dopri5 at rtol 1e-10): its period matches 4 sqrt(L/g) K(sin 45 deg) to about 1e-10."""
    return World._rust_scene("pendulum", length=length, radius=radius)


def chain(links: int = 20) -> World:
    """``links`` rods of 0.1 m and 1 kg hanging from a fixed point by ball joints, a 10 kg weight at the end (fast
    mode at 1/60 s): it does not stretch."""
    return World._rust_scene("chain", links=links)


def newtons_cradle(balls: int = 5, angle: float = 0.5) -> World:
    """Newton's cradle: ``balls`` steel balls on hinges, the first pulled out by ``angle`` rad (fast mode at 1/240 s,
    restitution 1)."""
    return World._rust_scene("newtons_cradle", balls=balls, angle=angle)


def door() -> World:
    """A 20 kg door on a vertical hinge, its motor (1 rad/s, 20 N m) swinging it open to its limit at 1.5 rad (fast
    mode at 1/60 s)."""
    return World._rust_scene("door")


def ragdoll() -> World:
    """A 70 kg ragdoll of 10 parts (ball joints at the neck, shoulders and hips, limited hinges at the elbows and
    knees) pushed off the top of a flight of stairs (fast mode at 1/60 s)."""
    return World._rust_scene("ragdoll")


BENCHMARKS = ("slide", "incline", "roll", "cube_pile", "domino_row")


def benchmark(name: str = "slide", degrees: float = 35.0) -> World:
    """One of the scenes accurate mode is measured on against Drake's CENIC (accurate mode at its defaults; z up,
    restitution 0, inclines by tilting gravity): "slide" (a 0.4 m cube at 2 m/s on mu 0.5), "incline" (a 0.1 m cube
    on mu 0.5 tilted by ``degrees``), "roll" (a sphere of radius 0.1 m on mu 0.3 tilted 30 degrees), "cube_pile"
    (20 cubes of 0.2 m dropped in three layers) or "domino_row" (ten dominoes, the first tipped)."""
    if name not in BENCHMARKS:
        raise ValueError(f"name: expected one of {', '.join(BENCHMARKS)}, got {name!r}")
    return World._rust_scene("benchmark", which=BENCHMARKS.index(name) + 1, degrees=degrees)


def ball_in_cup(fast: bool = False, hull: bool = False) -> World:
    """A 3 cm rubber ball dropped into a ceramic cup (one non-convex mesh, decomposed) standing on the floor; it
    stays in. ``hull=True`` gives the cup its convex hull, and the ball lands on the lid (accurate mode, or fast)."""
    return World._rust_scene("ball_in_cup", fast=int(fast), hull=int(hull))


def ring_on_peg(fast: bool = False) -> World:
    """A wooden ring (a torus mesh) tossed onto a static peg (an exact cylinder mesh); it slides down around it."""
    return World._rust_scene("ring_on_peg", fast=int(fast))


def chair(fast: bool = False) -> World:
    """A chair of one non-convex mesh set down on its four legs."""
    return World._rust_scene("chair", fast=int(fast))


def torus_roll(fast: bool = False) -> World:
    """A rubber torus standing on edge, rolling along x at 1 m/s."""
    return World._rust_scene("torus_roll", fast=int(fast))


def mesh_pile(count: int = 50, fast: bool = True, hull: bool = False) -> World:
    """``count`` meshes of five kinds (cup, ring, stool, pebble, peg) dropped in a loose column (fast mode by
    default); ``hull=True`` gives each its convex hull."""
    return World._rust_scene("mesh_pile", count=count, fast=int(fast), hull=int(hull))


def _glued_world(fast: bool, dt: float | None = None) -> World:
    """A world with a floor, fast mode (at ``dt``, one thread) or accurate mode (one thread)."""
    if fast:
        w = World(mode="fast", dt=dt, threads=1) if dt else World(mode="fast", threads=1)
    else:
        w = World(threads=1)
    w.add_ground(friction=0.7)
    return w


def vase_mesh(segments: int = 100) -> "Mesh":
    """A vase turned from a profile of 51 points in ``segments`` steps (10,000 triangles at 100), 0.3 m tall with
    6 mm walls."""
    from ._tumble import Mesh  # noqa: PLC0415

    heights = [0.3 * k / 25 for k in range(26)]
    outer = [0.06 + 0.03 * math.sin(math.pi * z / 0.3) for z in heights]
    inner = [(r - 0.006, z) for r, z in zip(outer[::-1][:-2], heights[::-1][:-2])]
    profile = [(0.0, 0.0), *zip(outer, heights), *inner, (0.0, 0.008)]
    return Mesh.revolve(profile, segments=segments, name="vase")


def vase_drop(fast: bool = True, height: float = 1.0, strength: float = 2e6) -> World:
    """A ceramic vase (``vase_mesh``) cut into 50 pieces glued at ``strength`` Pa, dropped from ``height`` m."""
    mesh = vase_mesh()
    w = _glued_world(fast)
    w.add_fractured(mesh, mesh.fracture(pieces=50, seed=1), density=2400.0, strength=strength,
                    position=(0.0, 0.0, height))
    return w


def glass_pane(fast: bool = True, strength: float = 2e6) -> World:
    """A 0.8 x 0.6 m glass pane 8 mm thick standing on the floor, cut into 50 pieces (more of them where the ball
    hits) glued at ``strength`` Pa, and a 3 cm steel ball thrown through it at 10 m/s."""
    from ._tumble import Box, Mesh, Sphere  # noqa: PLC0415

    vertices, triangles = Box((0.4, 0.004, 0.3)).triangle_mesh()
    pane = Mesh(vertices, triangles, name="pane")
    w = _glued_world(fast)
    w.add_fractured(pane, pane.fracture(pieces=50, seed=2, near=(0.0, 0.0, 0.0)), density=2500.0,
                    strength=strength, position=(0.0, 0.0, 0.3))
    w.add_body(Sphere(0.03), density=7800.0, position=(0.0, -0.5, 0.3), velocity=(0.0, 10.0, 0.0), name="ball")
    return w


def wrecking_ball(fast: bool = True, dt: float | None = None, strength: float = 1e6, window: float = 0.01) -> World:
    """A wall of 48 bricks (0.3 x 0.2 x 0.15 m, 1800 kg/m^3) in six courses of eight, each course set half a brick
    along from the one below, glued at ``strength`` Pa averaged over ``window`` s (117 welds; 30 kN across a
    brick's end at 1 MPa), on the floor; and a 110 kg wrecking ball 0.3 m in radius on a 3 m rope, let go 67
    degrees out, that meets the fourth course's middle at the bottom of its swing at 6 m/s (0.98 s in). Fast mode
    at ``dt`` (1/240 s unless given) or accurate mode, one thread (``tumble::scenes::WreckingBall``)."""
    params: dict[str, float] = dict(fast=int(fast), strength=strength, window=window)
    if dt is not None:
        params["dt"] = dt
    return World._rust_scene("wrecking_ball", **params)
