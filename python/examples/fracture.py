"""Fracture, measured: a 10,000-triangle vase cut into 50 pieces (the time, and the pieces' mass properties against
the vase's); the vase glued and standing on a table, unhit, in both modes (breaks, and how far a piece moved in
5 s); a wall of 48 glued bricks (117 welds) hit by a 110 kg wrecking ball at 6 m/s (the welds broken at three step
sizes in fast mode, and in accurate mode); a glass pane of 50 pieces hit by a ball in fast mode (the time against the time simulated,
one thread).

    python python/examples/fracture.py [--parts vase,wall,pane] [--modes fast,accurate] [--windows 0.01]
        [--strength 1e6]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import tumble

WALL_RUN = 1.5
"""How long the wall is run (s): the ball strikes it at 0.98 s."""


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


def measure_vase(modes: list[str]) -> None:
    mesh = tumble.scenes.vase_mesh()
    clock = time.perf_counter()
    pieces = mesh.fracture(pieces=50, seed=1)
    took = time.perf_counter() - clock
    mass, com, inertia = assembled(pieces)
    whole = mesh.mass_properties(1.0)
    print(f"vase of {len(mesh.triangles)} triangles into {len(pieces)} pieces: {took:.3f} s; mass "
          f"{abs(mass / whole['mass'] - 1):.1e}, centre {np.abs(com - whole['center_of_mass']).max() / 0.3:.1e}, "
          f"inertia {np.abs(inertia - whole['inertia']).max() / np.abs(whole['inertia']).max():.1e} (relative)")
    for mode in modes:
        w = tumble.scenes.vase_drop(fast=mode == "fast", height=0.0, strength=5e6)
        start = w.bodies.positions.copy()
        clock = time.perf_counter()
        try:
            w.run(5.0)
            moved = np.linalg.norm(w.bodies.positions - start, axis=1).max()
            print(f"{mode:>8} vase standing glued, unhit, 5 s: {len(w.broken_joints())} of {w.joint_count} welds "
                  f"broke, pieces moved at most {moved * 1e3:.3f} mm ({time.perf_counter() - clock:.1f} s)")
        except tumble.SimulationError as error:
            print(f"{mode:>8} vase standing glued: failed after {time.perf_counter() - clock:.1f} s: {error}")


def measure_wall(modes: list[str], windows: list[float], strength: float) -> None:
    """The welds broken in 1.5 s (the ball strikes at 0.98 s), and of those the ones broken within 50 ms of the
    first break (the impact's own, before loosened bricks strike the others), with how many of those the finest
    step's run broke too (at the default strength, 1 MPa, when ``strength`` is another)."""
    for window in windows:
        finest: set[int] | None = None
        finest_first: set[int] | None = None
        if strength != 1e6 and "fast" not in modes:
            _, finest_first, finest = wall_breaks(tumble.scenes.wrecking_ball(dt=1 / 960, window=window), WALL_RUN)
        for mode in modes:
            for dt in ((1 / 960, 1 / 480, 1 / 240) if mode == "fast" else (None,)):
                w = tumble.scenes.wrecking_ball(fast=mode == "fast", dt=dt, window=window, strength=strength)
                clock = time.perf_counter()
                label = f"dt 1/{round(1 / dt)}" if dt else "accurate"
                try:
                    run = w.run(WALL_RUN)
                except tumble.SimulationError as error:
                    print(f"wall hit, window {window * 1e3:g} ms, {label}: failed after "
                          f"{time.perf_counter() - clock:.1f} s: {error}")
                    continue
                first, at_first, impact = wall_breaks(w, run=run)
                times = run.joint_break_times
                finest = impact if finest is None else finest
                finest_first = at_first if finest_first is None else finest_first
                welds = sum(1 for j in w.joint_handles if w.joint_breaking(j) is not None)
                print(f"wall hit, window {window * 1e3:g} ms, {label}: {len(times)} of {welds} welds broke "
                      f"in {WALL_RUN:g} s, {len(impact)} within 50 ms of the first break at {first:.4f} s ({len(impact & finest)} "
                      f"of them as at the finest step), {len(at_first)} at it ({len(at_first & finest_first)} as at "
                      f"the finest step's) ({time.perf_counter() - clock:.1f} s)")


def wall_impact(w: tumble.World, duration: float = WALL_RUN, run: tumble.Run | None = None) -> tuple[float, set[int]]:
    """The first break's time in ``run`` (or a run of ``w`` for ``duration``) and the welds (by their order)
    broken within 50 ms of it."""
    first, _, impact = wall_breaks(w, duration, run)
    return first, impact


def wall_breaks(
    w: tumble.World, duration: float = WALL_RUN, run: tumble.Run | None = None
) -> tuple[float, set[int], set[int]]:
    """The first break's time in ``run`` (or a run of ``w`` for ``duration``), the welds (by their order) broken
    then, and those broken within 50 ms of it."""
    run = w.run(duration) if run is None else run
    order = {j: k for k, j in enumerate(w.joint_handles)}
    times = np.asarray(run.joint_break_times)
    first = float(times.min()) if len(times) else 0.0
    at_first = {order[j] for t, j in zip(times, run.joint_breaks) if t == first}
    return first, at_first, {order[j] for t, j in zip(times, run.joint_breaks) if t < first + 0.05}


def measure_pane() -> None:
    w = tumble.scenes.glass_pane()
    clock = time.perf_counter()
    w.run(1.0)
    took = time.perf_counter() - clock
    print(f"pane of 50 pieces hit by a steel ball at 10 m/s, fast mode, one thread: 1 s simulated in "
          f"{took:.2f} s ({1 / took:.1f} times real time); {len(w.broken_joints())} of {w.joint_count} welds broke")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--parts", default="vase,wall,pane")
    p.add_argument("--modes", default="fast,accurate")
    p.add_argument("--windows", default="0.01", help="break windows (s) for the wall, comma-separated")
    p.add_argument("--strength", type=float, default=1e6, help="the wall's glue strength (Pa)")
    args = p.parse_args()
    parts, modes = args.parts.split(","), args.modes.split(",")
    if "vase" in parts:
        measure_vase(modes)
    if "wall" in parts:
        measure_wall(modes, [float(x) for x in args.windows.split(",")], args.strength)
    if "pane" in parts:
        measure_pane()


if __name__ == "__main__":
    main()
