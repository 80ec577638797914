"""Accurate mode against Drake's CENIC (Kurtz and Castro 2025, error-controlled convex contact steps) on the same
scenes, one thread each, one run after the other: error against wall time.

    python3 benches/peers/cenic.py [--quick] [--drake-python PYTHON]

The scenes are tumble's ``tumble.scenes.benchmark`` ones (z up, g = 9.81, restitution 0, the same friction on both
surfaces, inclines by tilting gravity): the slide (a 0.4 m cube, density 500, at 2 m/s on mu 0.5, 1 s: its stop
distance against v^2 / (2 mu g)), the incline (a 0.1 m cube, density 500, mu 0.5, 35 degrees for 1 s against
g (sin - mu cos) t^2 / 2, and 20 degrees for 2 s, where it sticks), the roll (a sphere of radius 0.1 m, density
1000, mu 0.3, 30 degrees, 1 s, against (5/7) g sin t^2 / 2), the 20-cube pile (3 s) and ten dominoes (4 s). Drake
is given the same bodies on a continuous MultibodyPlant with hydroelastic contact for boxes (compliant, modulus
1e8 Pa, Hunt-Crossley dissipation 10 s/m; point contact makes a box rest on one point and rock) and point contact for
the sphere, against a rigid half-space floor, integrated by CENIC at target accuracies 1e-1 to 1e-5; tumble's accurate mode at contact tolerances
1e-2 to 1e-6 m. The pile and the dominoes have no closed form: each engine is measured against its own tightest run
(CENIC at 1e-6, tumble at 1e-6 m: the largest distance of any body from it), and their boxes' resting penetration
into the floor at the end (the deepest corner below it, the same measure of both).

Drake runs in ``--drake-python`` (an interpreter with ``drake==1.51.1``; default: this one), each scene in its own
process, so the two engines never share an interpreter; tumble runs here.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time

G = 9.81
SCENES = {
    # name: (tumble benchmark, parameters, span, closed form or None)
    "slide": ("slide", {}, 1.0, 2.0 ** 2 / (2 * 0.5 * G)),
    "incline 35": ("incline", {"degrees": 35.0}, 1.0,
                   G * (math.sin(math.radians(35)) - 0.5 * math.cos(math.radians(35))) / 2),
    "incline 20 (sticks)": ("incline", {"degrees": 20.0}, 2.0, 0.0),
    "roll": ("roll", {}, 1.0, 5 / 7 * G * math.sin(math.radians(30)) / 2),
    "20-cube pile": ("cube_pile", {}, 3.0, None),
    "ten dominoes": ("domino_row", {}, 4.0, None),
}


# the boxes' half extents in the scenes with several bodies (for the resting penetration into the floor)
HALVES = {"cube_pile": (0.1, 0.1, 0.1), "domino_row": (0.02, 0.1, 0.2)}


def floor_depth(kind: str, poses: list[tuple[list[float], list[list[float]]]]) -> float | None:
    """How deep the deepest box corner lies below the floor z = 0 (m): the same measure of both engines' end
    states, their resting penetration (CENIC's hydroelastic contact has no single depth to read during a run)."""
    if kind not in HALVES:
        return None
    hx, hy, hz = HALVES[kind]
    lowest = math.inf
    for centre, r in poses:
        for sx in (-1, 1):
            for sy in (-1, 1):
                for sz in (-1, 1):
                    z = centre[2] + r[2][0] * sx * hx + r[2][1] * sy * hy + r[2][2] * sz * hz
                    lowest = min(lowest, z)
    return max(0.0, -lowest)


def rotation(q) -> list[list[float]]:
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = (float(c) for c in q)
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def tumble_run(name: str, tolerance: float) -> dict:
    """One accurate-mode run of a scene at a contact tolerance, one thread, frames every 1/60 s."""
    import tumble

    kind, params, span, _ = SCENES[name]
    w = tumble.scenes.benchmark(kind, **params)
    w.threads = 1
    w.set_mode("accurate", contact_tolerance=tolerance)
    start = w.bodies.positions[1:].copy()  # body 0 is the static ground
    clock = time.perf_counter()
    run = w.run(span, 1 / 60)
    wall = time.perf_counter() - clock
    end = w.bodies.positions[1:]
    turns = w.bodies.orientations[1:]
    floor = floor_depth(kind, [(list(c), rotation(q)) for c, q in zip(end, turns)])
    return {"wall": wall, "moved": float(end[0, 0] - start[0, 0]), "positions": end.tolist(),
            "penetration": run.report.max_penetration, "floor": floor, "steps": run.report.contact_steps}


def drake_run(name: str, accuracy: float) -> dict:
    """One CENIC run of a scene at a target accuracy (in the interpreter that has drake)."""
    from pydrake.geometry import (AddCompliantHydroelasticProperties, AddContactMaterial,
                                  AddRigidHydroelasticProperties, Box, HalfSpace, ProximityProperties, Sphere)
    from pydrake.math import RigidTransform, RollPitchYaw
    from pydrake.multibody.math import SpatialVelocity
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph, ContactModel, CoulombFriction
    from pydrake.multibody.tree import SpatialInertia
    from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator
    from pydrake.systems.framework import DiagramBuilder

    kind, params, span, _ = SCENES[name]
    mu = 0.3 if kind == "roll" else 0.5
    tilt = math.radians(params.get("degrees", 30.0 if kind == "roll" else 0.0))
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlantSceneGraph(builder, time_step=0.0)
    plant.set_contact_model(ContactModel.kHydroelasticWithFallback)
    plant.mutable_gravity_field().set_gravity_vector([G * math.sin(tilt), 0.0, -G * math.cos(tilt)])
    friction = CoulombFriction(mu, mu)
    floor = ProximityProperties()
    AddContactMaterial(dissipation=10.0, friction=friction, properties=floor)
    AddRigidHydroelasticProperties(properties=floor)
    plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform(), HalfSpace(), "floor", floor)
    bodies = []  # (body, pose, velocity)

    def add(shape, inertia, pose, velocity=None, angular=None):
        k = len(bodies)
        body = plant.AddRigidBody(f"body{k}", inertia)
        props = ProximityProperties()
        AddContactMaterial(dissipation=10.0, friction=friction, properties=props)
        if isinstance(shape, Box):
            # boxes hydroelastic (point contact makes a box rest on one point and rock); the sphere point contact
            size = min(shape.width(), shape.depth(), shape.height())
            AddCompliantHydroelasticProperties(resolution_hint=size / 2, hydroelastic_modulus=1e8, properties=props)
        plant.RegisterCollisionGeometry(body, RigidTransform(), shape, f"shape{k}", props)
        bodies.append((body, pose, SpatialVelocity(angular or [0, 0, 0], velocity or [0, 0, 0])))

    if kind in ("slide", "incline"):
        h = 0.2 if kind == "slide" else 0.05
        add(Box(2 * h, 2 * h, 2 * h), SpatialInertia.SolidBoxWithDensity(500.0, 2 * h, 2 * h, 2 * h),
            RigidTransform([0, 0, h]), velocity=[2.0, 0, 0] if kind == "slide" else None)
    elif kind == "roll":
        add(Sphere(0.1), SpatialInertia.SolidSphereWithDensity(1000.0, 0.1), RigidTransform([0, 0, 0.1]))
    elif kind == "cube_pile":
        n = 0
        for layer, count in enumerate((7, 7, 6)):
            offset = 0.12 * layer
            for k in range(count):
                i, j = k % 3, k // 3
                at = [0.26 * i + offset, 0.26 * j + offset, 0.1 + 0.05 + 0.3 * layer]
                turn = 0.3 if n % 3 == 2 else 0.0
                # tumble's from_euler_angles(roll, pitch, yaw) is R = Rz(yaw) Ry(pitch) Rx(roll), as RollPitchYaw
                pose = RigidTransform(RollPitchYaw(turn, 0.5 * turn, 0.2 * turn), at)
                add(Box(0.2, 0.2, 0.2), SpatialInertia.SolidBoxWithDensity(500.0, 0.2, 0.2, 0.2), pose)
                n += 1
    elif kind == "domino_row":
        for k in range(10):
            velocity = angular = None
            if k == 0:
                # turning about its front bottom edge at 2 rad/s: v = w x (c - edge)
                angular, velocity = [0, 2.0, 0], [2.0 * 0.2, 0, 2.0 * 0.02]
            add(Box(0.04, 0.2, 0.4), SpatialInertia.SolidBoxWithDensity(700.0, 0.04, 0.2, 0.4),
                RigidTransform([0.25 * k, 0, 0.2]), velocity=velocity, angular=angular)
    plant.Finalize()
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    for body, pose, velocity in bodies:
        plant.SetFreeBodyPose(plant_context, body, pose)
        plant.SetFreeBodySpatialVelocity(context=plant_context, body=body, V_JpJc=velocity)
    integrator = ResetIntegratorFromFlags(simulator, "cenic", 0.1)
    integrator.set_target_accuracy(accuracy)
    simulator.Initialize()
    start = [plant.EvalBodyPoseInWorld(plant_context, b).translation().copy() for b, _, _ in bodies]
    clock = time.perf_counter()
    simulator.AdvanceTo(span)
    wall = time.perf_counter() - clock
    poses = [plant.EvalBodyPoseInWorld(plant_context, b) for b, _, _ in bodies]
    end = [p.translation() for p in poses]
    floor = floor_depth(kind, [(list(p.translation()), p.rotation().matrix().tolist()) for p in poses])
    return {"wall": wall, "moved": float(end[0][0] - start[0][0]), "positions": [list(p) for p in end],
            "floor": floor, "steps": integrator.get_num_steps_taken()}


def table(rows: list[tuple[str, str, list[dict]]], reference: dict[str, dict]) -> None:
    print("| scene | engine | setting | wall (s) | error (m) | steps | resting floor penetration (m) |")
    print("|---|---|---|---|---|---|---|")
    for name, engine, results in rows:
        closed = SCENES[name][3]
        span = SCENES[name][2]
        for setting, r in results:
            if closed is not None:
                error = abs(r["moved"] - closed * (span ** 2 if name != "slide" else 1.0))
            else:
                ref = reference[engine]["positions"]
                error = max(math.dist(a, b) for a, b in zip(r["positions"], ref))
            floor = "" if r.get("floor") is None else f"{r['floor']:.2e}"
            print(f"| {name} | {engine} | {setting} | {r['wall']:.4f} | {error:.2e} | {r['steps']} | {floor} |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0].replace("\n", " "))
    p.add_argument("--quick", action="store_true", help="Two settings a scene, the first four scenes.")
    p.add_argument("--scenes", nargs="*", choices=list(SCENES), help="Only these scenes.")
    p.add_argument("--drake-python", default=sys.executable, help="An interpreter with drake==1.51.1.")
    p.add_argument("--engine", choices=["drake"], help=argparse.SUPPRESS)
    p.add_argument("--scene", help=argparse.SUPPRESS)
    p.add_argument("--setting", type=float, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.engine == "drake":
        print(json.dumps(drake_run(args.scene, args.setting)))
        return
    accuracies = [1e-1, 1e-3] if args.quick else [1e-1, 1e-2, 1e-3, 1e-4, 1e-5]
    tolerances = [1e-2, 1e-4] if args.quick else [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
    names = args.scenes or (list(SCENES)[:4] if args.quick else list(SCENES))
    for name in names:
        drake = []
        for a in accuracies + ([1e-6] if SCENES[name][3] is None else []):
            out = subprocess.run([args.drake_python, __file__, "--engine", "drake", "--scene", name,
                                  "--setting", str(a)], capture_output=True, text=True, check=True)
            drake.append((f"accuracy {a:.0e}", json.loads(out.stdout.strip().splitlines()[-1])))
        closed = SCENES[name][3] is not None
        ours = [(f"tolerance {t:.0e} m", tumble_run(name, t)) for t in (tolerances if closed else tolerances[:-1])]
        if not closed:
            ours.append(("tolerance 1e-6 m", tumble_run(name, 1e-6)))
        reference = {"cenic": drake[-1][1], "tumble": ours[-1][1]}
        if SCENES[name][3] is None:
            drake, ours = drake[:-1], ours[:-1]
        table([(name, "cenic", drake), (name, "tumble", ours)], reference)
        sys.stdout.flush()


if __name__ == "__main__":
    main()
