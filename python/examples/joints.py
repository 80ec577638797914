"""Jointed scenes from Python: a pendulum, a hanging chain and a motor-driven door built with the joint classes, and
Newton's cradle and a ragdoll on stairs from tumble.scenes. Writes each run's glTF, plot and GIF.

    python python/examples/joints.py [--scene pendulum|chain|cradle|door|ragdoll|all] [--out tumble-out] [--no-gif]
"""

import argparse
import math
from pathlib import Path

import numpy as np
from _common import run_and_write

import tumble


def pendulum() -> tumble.World:
    """A 1 kg ball on a 1 m rod, released from the horizontal (accurate mode)."""
    w = tumble.World(rtol=1e-10, atol=1e-12)
    bob = w.add_body(tumble.Sphere(radius=0.05), mass=1.0, position=(1.0, 0.0, 0.0))
    w.add_joint(tumble.Distance(None, bob, world_point=(0.0, 0.0, 0.0)))
    return w


def chain(links: int = 20) -> tumble.World:
    """20 rods of 0.1 m and 1 kg on ball joints, a 10 kg weight at the end (fast mode, 1/60 s)."""
    w = tumble.World(mode="fast", dt=1 / 60)
    above = None
    for k in range(links):
        rod = w.add_body(tumble.Capsule(half_height=0.04, radius=0.01), mass=1.0, position=(0, 0, 2.45 - 0.1 * k))
        if above is None:
            w.add_joint(tumble.Ball(None, rod, world_point=(0, 0, 2.5), anchor_b=(0, 0, 0.05)))
        else:
            w.add_joint(tumble.Ball(above, rod, anchor_a=(0, 0, -0.05), anchor_b=(0, 0, 0.05)))
        above = rod
    weight = w.add_body(tumble.Sphere(radius=0.1), mass=10.0, position=(0, 0, 2.4 - 0.1 * links))
    w.add_joint(tumble.Ball(above, weight, anchor_a=(0, 0, -0.05), anchor_b=(0, 0, 0.1)))
    return w


def door() -> tumble.World:
    """A 20 kg door whose motor (1 rad/s, at most 20 N m) opens it to its limit at 1.5 rad (fast mode, 1/60 s)."""
    w = tumble.World(mode="fast", dt=1 / 60)
    w.add_ground(restitution=0.0, friction=0.5)
    panel = w.add_body(tumble.Box(half_extents=(0.5, 0.02, 1.0)), mass=20.0, position=(0.5, 0.0, 1.01))
    w.add_joint(tumble.Hinge(None, panel, world_point=(0, 0, 1.01), anchor_b=(-0.5, 0, 0), axis=(0, 0, 1),
                             limits=(0.0, 1.5), motor=tumble.Motor(speed=1.0, max_torque=20.0)))
    return w


SCENES = {
    "pendulum": (pendulum, 4.0, 1 / 240),
    "chain": (chain, 5.0, 1 / 60),
    "cradle": (tumble.scenes.newtons_cradle, 3.0, 1 / 240),
    "door": (door, 3.0, 1 / 60),
    "ragdoll": (tumble.scenes.ragdoll, 3.0, 1 / 60),
}

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--scene", default="all", choices=[*SCENES, "all"])
parser.add_argument("--out", type=Path, default=Path("tumble-out"), help="directory for the outputs")
parser.add_argument("--no-gif", action="store_true", help="skip the GIF previews (the slowest output)")
args = parser.parse_args()
for name in SCENES if args.scene == "all" else [args.scene]:
    build, duration, frames = SCENES[name]
    print(f"== {name}")
    world = build()
    args.duration = duration
    run = run_and_write(world, f"joints_{name}", args, frame_interval=frames)
    r = run.report
    print(f"joints: {r.joint_rows} rows, largest error {r.joint_error:.1e} m and {r.joint_angle_error:.1e} rad")
    if name == "pendulum":
        x = run.body_positions[:, 0, 0]
        k = np.nonzero((x[:-1] > 0) & (x[1:] <= 0))[0]
        t = run.times[k] + x[k] / (x[k] - x[k + 1]) * (run.times[k + 1] - run.times[k])
        exact = 4 * math.sqrt(1 / 9.81) * 1.854074677301372
        print(f"period {t[1] - t[0]:.10f} s against {exact:.10f} s (relative {(t[1] - t[0] - exact) / exact:.1e})")
