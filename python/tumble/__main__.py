"""The default job: ``python -m tumble`` runs a built-in scene and prints its plan and run report.

    python -m tumble [--scene cloth|top] [--duration SECONDS] [--plot FILE] [--gif FILE] [--glb FILE]
"""

from __future__ import annotations

import argparse

import numpy as np

from . import scenes


def main() -> None:
    parser = argparse.ArgumentParser(prog="python -m tumble", description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=["cloth", "top"], default="cloth")
    parser.add_argument("--duration", type=float, default=3.0)
    parser.add_argument("--plot", help="write energy and step size over time (.png, .pdf, ...)")
    parser.add_argument("--gif", help="write an animated preview (.gif or .mp4)")
    parser.add_argument("--glb", help="write the animation as binary glTF (.glb)")
    args = parser.parse_args()

    world = scenes.cloth() if args.scene == "cloth" else scenes.spinning_top()
    plan = world.plan()
    print(f"scene   {args.scene}: {len(world.particles)} particles, {len(world.bodies)} bodies")
    print(f"plan    {' -> '.join(plan['stages'])} ({plan['state_len']} state variables, method {plan['method']}"
          + (f", jacobian {plan['jacobian']}" if plan["jacobian"] else "") + ")")
    run = world.run(args.duration, 1 / 60, progress=True)
    print(f"ran     {run.times[-1]:.3f} s in {run.frames} frames")
    drift = run.energy[-1] - run.energy[0]
    print(f"energy  {run.energy[0]:.6g} J -> {run.energy[-1]:.6g} J ({drift:+.3g} J; damping and implicit steps dissipate)")
    if args.scene == "top":
        axis = run.body_positions[:, 0, :2]
        angle = np.unwrap(np.arctan2(axis[:, 1], axis[:, 0]))
        rate = (angle[-1] - angle[0]) / (run.times[-1] - run.times[0])
        a, b, c = 0.02 * np.cos(0.3), 0.04 * 40.0, 1.0 * 9.81 * 0.1
        steady = (b - np.sqrt(b * b - 4 * a * c)) / (2 * a)
        print(f"top     precession {rate:+.4f} rad/s (steady precession of a heavy top: {steady:.4f} rad/s)")
    print(run.report)
    for path, write in ((args.plot, run.plot), (args.gif, run.animate), (args.glb, run.export_gltf)):
        if path:
            write(path)
            print(f"wrote   {path}")


if __name__ == "__main__":
    main()
