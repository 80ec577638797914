"""The peer comparison's scenes in PyBullet (issue 13), at its defaults, one markdown row each: the same scene
definitions as ``python_engines.py`` (MuJoCo), ``benches/peers/rapier`` and tumble's ``examples/fast_scenes.rs``.

Bullet multiplies the two bodies' friction coefficients, so every body and the floor get sqrt(mu): each pair then
meets at mu, as in the other engines (Rapier averages, MuJoCo takes the larger, tumble the geometric mean). The pile
runs without and with sleeping, as in the others; the solver, substeps and continuous collision stay at Bullet's
defaults.

Run: ``pip install -r benches/peers/requirements.txt`` then ``python3 benches/peers/pybullet_scenes.py 100 1000``.
Not part of CI.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

G = 9.81


def _world(dt: float, floor_mu: float):
    import pybullet as p

    client = p.connect(p.DIRECT)
    p.setGravity(0, 0, -G, physicsClientId=client)
    p.setTimeStep(dt, physicsClientId=client)
    plane = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client)
    floor = p.createMultiBody(0, plane, physicsClientId=client)
    p.changeDynamics(floor, -1, lateralFriction=math.sqrt(floor_mu), physicsClientId=client)
    return client


def _cube(client, half: float, density: float, at, mu: float, sleep: bool = True) -> int:
    import pybullet as p

    shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=[half] * 3, physicsClientId=client)
    body = p.createMultiBody(density * (2 * half) ** 3, shape, basePosition=list(at), physicsClientId=client)
    p.changeDynamics(body, -1, lateralFriction=math.sqrt(mu), physicsClientId=client)
    if not sleep:
        p.changeDynamics(body, -1, activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING, physicsClientId=client)
    return body


def _penetration(client, bodies: list[int], half: float) -> float:
    """The deepest overlap recomputed from the poses (``overlap.py``), as for every engine."""
    import pybullet as p

    from overlap import deepest

    boxes = []
    for b in bodies:
        at, (x, y, z, w) = p.getBasePositionAndOrientation(b, physicsClientId=client)
        boxes.append((np.full(3, half), np.array([w, x, y, z]), np.array(at)))
    return deepest(boxes)


def _positions(client, bodies: list[int]) -> np.ndarray:
    import pybullet as p

    return np.array([p.getBasePositionAndOrientation(b, physicsClientId=client)[0] for b in bodies])


def pile(n: int, sleep: bool) -> tuple[float, float]:
    import pybullet as p

    client = _world(1 / 60, 0.5)
    cubes = []
    for k in range(n):
        layer, i, j = k // 100, (k % 100) // 10, k % 10
        cubes.append(_cube(client, 0.5, 1000.0, (1.2 * i, 1.2 * j, 2.5 + 1.2 * layer), 0.5, sleep=sleep))
    worst, spent = 0.0, 0.0
    for step in range(600):
        clock = time.perf_counter()
        p.stepSimulation(physicsClientId=client)
        spent += time.perf_counter() - clock
        if step >= 500:
            worst = max(worst, _penetration(client, cubes, 0.5))
    p.disconnect(client)
    return spent * 1e3 / 600, worst


def _displacement(client, bodies: list[int], steps: int) -> float:
    import pybullet as p

    start = _positions(client, bodies)
    worst = 0.0
    for _ in range(steps):
        p.stepSimulation(physicsClientId=client)
        worst = max(worst, float(np.max(np.linalg.norm(_positions(client, bodies) - start, axis=1))))
    return worst


def main() -> None:
    import pybullet as p

    sizes = [int(a) for a in sys.argv[1:]] or [100, 1000]
    print("| PyBullet 3.2.7 (defaults) | value |\n|---|---|")
    for n in sizes:
        for sleep, label in ((False, "no sleep"), (True, "sleeping")):
            ms, pen = pile(n, sleep)
            print(f"| pile {n}, {label}: ms a step / penetration (last 100 steps) | {ms:.3f} ms / {pen * 1e3:.3f} mm |")
    dt = 1 / 240
    client = _world(dt, 0.6)
    stack = [_cube(client, 0.25, 500.0, (0.0, 0.0, 0.25 + 0.5 * k), 0.6) for k in range(10)]
    print(f"| stack of 10: largest displacement in 10 s | {_displacement(client, stack, 2400) * 1e3:.3f} mm |")
    p.disconnect(client)
    client = _world(dt, 0.5)
    box = _cube(client, 0.2, 500.0, (0.0, 0.0, 0.2), 0.5)
    p.resetBaseVelocity(box, [2.0, 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=client)
    for _ in range(480):
        p.stepSimulation(physicsClientId=client)
    exact = 4.0 / (2 * 0.5 * G)
    x = _positions(client, [box])[0, 0]
    print(f"| slide: stop distance error | {(x - exact) / exact * 100:+.3f}% |")
    p.disconnect(client)
    client = _world(dt, 0.5)
    rest = _cube(client, 0.5, 1000.0, (0.0, 0.0, 0.5), 0.5)
    print(f"| rest: largest displacement in 10 s | {_displacement(client, [rest], 2400):.2e} m |")
    p.disconnect(client)
    client = _world(1 / 60, 0.5)
    wall_shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=[0.005, 2, 2], physicsClientId=client)
    p.createMultiBody(0, wall_shape, basePosition=[5, 0, 2], physicsClientId=client)
    ball_shape = p.createCollisionShape(p.GEOM_SPHERE, radius=0.05, physicsClientId=client)
    ball = p.createMultiBody(1000.0 * 4 / 3 * math.pi * 0.05**3, ball_shape, basePosition=[0, 0, 2],
                             physicsClientId=client)
    p.resetBaseVelocity(ball, [1000.0, 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=client)
    for _ in range(30):
        p.stepSimulation(physicsClientId=client)
    x = _positions(client, [ball])[0, 0]
    print(f"| bullet: ball ends at x (wall at 5 m) | {x:.3f} m ({'held by the wall' if x < 5.0 else 'TUNNELLED'}) |")
    p.disconnect(client)


if __name__ == "__main__":
    main()
