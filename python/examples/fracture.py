"""Fracture, measured: a 10,000-triangle vase cut into 50 pieces (the time, and the pieces' mass properties against
the vase's); the vase glued and standing on a table, unhit, in both modes (breaks, and how far a piece moved in
5 s); a wall of 48 glued bricks hit by a 110 kg ball at 6 m/s (the welds broken at three step sizes in fast mode,
and in accurate mode); a glass pane of 50 pieces hit by a ball in fast mode (the time against the time simulated,
one thread).

    python python/examples/fracture.py [--parts vase,wall,pane] [--modes fast,accurate]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import tumble


def vase() -> tumble.Mesh:
    """A vase turned from a profile of 51 points in 100 steps: 10,000 triangles."""
    z = np.linspace(0.0, 0.3, 26)
    outer = 0.06 + 0.03 * np.sin(np.pi * z / 0.3)
    profile = [(0.0, 0.0)] + [(r, h) for r, h in zip(outer, z)] + \
        [(r - 0.006, h) for r, h in zip(outer[::-1][:-2], z[::-1][:-2])] + [(0.0, 0.008)]
    return tumble.Mesh.revolve(profile, segments=100, name="vase")


def assembled(pieces: list[tumble.Mesh]) -> tuple[float, np.ndarray, np.ndarray]:
    """The pieces' mass, centre of mass and inertia about it at unit density (parallel axes)."""
    props = [p.mass_properties(1.0) for p in pieces]
    mass = sum(p["mass"] for p in props)
    com = sum(p["mass"] * np.asarray(p["center_of_mass"]) for p in props) / mass
    inertia = np.zeros((3, 3))
    for p in props:
        d = np.asarray(p["center_of_mass"]) - com
        inertia += np.asarray(p["inertia"]) + p["mass"] * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, com, inertia


def world(mode: str, dt: float | None = None) -> tumble.World:
    if mode == "fast":
        return tumble.World(mode="fast", dt=dt, threads=1) if dt else tumble.World(mode="fast", threads=1)
    return tumble.World(threads=1)


def measure_vase(modes: list[str]) -> None:
    mesh = vase()
    clock = time.perf_counter()
    pieces = mesh.fracture(pieces=50, seed=1)
    took = time.perf_counter() - clock
    mass, com, inertia = assembled(pieces)
    whole = mesh.mass_properties(1.0)
    print(f"vase of {len(mesh.triangles)} triangles into {len(pieces)} pieces: {took:.3f} s; mass "
          f"{abs(mass / whole['mass'] - 1):.1e}, centre {np.abs(com - whole['center_of_mass']).max() / 0.3:.1e}, "
          f"inertia {np.abs(inertia - whole['inertia']).max() / np.abs(whole['inertia']).max():.1e} (relative)")
    for mode in modes:
        w = world(mode)
        w.add_ground(friction=0.6)
        hs = w.add_fractured(mesh, pieces, density=2400.0, strength=5e6)
        start = w.bodies.positions.copy()
        clock = time.perf_counter()
        try:
            w.run(5.0)
            moved = np.linalg.norm(w.bodies.positions - start, axis=1).max()
            print(f"{mode:>8} vase standing glued, unhit, 5 s: {len(w.broken_joints())} of {w.joint_count} welds "
                  f"broke, pieces moved at most {moved * 1e3:.3f} mm ({time.perf_counter() - clock:.1f} s, "
                  f"{len(hs)} pieces)")
        except tumble.SimulationError as error:
            print(f"{mode:>8} vase standing glued: failed after {time.perf_counter() - clock:.1f} s: {error}")


def wall(mode: str, dt: float | None) -> tumble.World:
    """A wall of 8 x 6 bricks (0.3 x 0.2 x 0.15 m) glued at 1 MPa (30 kN across a 0.2 x 0.15 m face), on the
    ground, and a 110 kg ball 0.3 m in radius rolling into its middle at 6 m/s."""
    v, t = tumble.Box((1.2, 0.1, 0.45)).triangle_mesh()
    mesh = tumble.Mesh(v, t, name="wall")
    points = [(-1.05 + 0.3 * i, 0.0, -0.375 + 0.15 * j) for j in range(6) for i in range(8)]
    bricks = mesh.fracture(points=points)
    w = world(mode, dt)
    w.add_ground(friction=0.7)
    w.add_fractured(mesh, bricks, density=1800.0, strength=1e6, position=(0, 0, 0.45 + 1e-4), friction=0.7)
    radius = 0.3
    w.add_body(tumble.Sphere(radius), mass=110.0, position=(0.0, -1.0, 0.45), velocity=(0.0, 6.0, 0.0))
    return w


def measure_wall(modes: list[str]) -> None:
    for mode in modes:
        for dt in ((1 / 240, 1 / 480, 1 / 960) if mode == "fast" else (None,)):
            w = wall(mode, dt)
            clock = time.perf_counter()
            try:
                w.run(1.0)
                label = f"dt 1/{round(1 / dt)}" if dt else "accurate"
                print(f"wall hit: {label}: {len(w.broken_joints())} of {w.joint_count} welds broke "
                      f"({time.perf_counter() - clock:.1f} s)")
            except tumble.SimulationError as error:
                print(f"wall hit ({mode}): failed after {time.perf_counter() - clock:.1f} s: {error}")


def measure_pane() -> None:
    v, t = tumble.Box((0.4, 0.004, 0.3)).triangle_mesh()
    mesh = tumble.Mesh(v, t, name="pane")
    pieces = mesh.fracture(pieces=50, seed=2, near=(0.0, 0.0, 0.0))
    w = world("fast")
    w.add_ground()
    # the pane held in a frame of two posts (welded to the world at its lower corners), a ball thrown through it
    hs = w.add_fractured(mesh, pieces, density=2500.0, strength=2e6, position=(0, 0, 0.6))
    w.add_body(tumble.Sphere(0.03), density=7800.0, position=(0.0, -0.5, 0.6), velocity=(0.0, 10.0, 0.0))
    clock = time.perf_counter()
    w.run(1.0)
    took = time.perf_counter() - clock
    print(f"pane of {len(hs)} pieces hit by a steel ball at 10 m/s, fast mode, one thread: 1 s simulated in "
          f"{took:.2f} s ({1 / took:.1f} times real time); {len(w.broken_joints())} of {w.joint_count} welds broke")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--parts", default="vase,wall,pane")
    p.add_argument("--modes", default="fast,accurate")
    args = p.parse_args()
    parts, modes = args.parts.split(","), args.modes.split(",")
    if "vase" in parts:
        measure_vase(modes)
    if "wall" in parts:
        measure_wall(modes)
    if "pane" in parts:
        measure_pane()


if __name__ == "__main__":
    main()
