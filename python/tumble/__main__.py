"""The default job: ``python -m tumble`` runs a built-in scene, prints its plan and run report, and writes its
animation (glTF and a GIF preview), a plot and the report into an output folder.

    python -m tumble [--scene NAME] [--duration SECONDS] [--out DIR] [--no-gif]

Scenes: dominoes (the default), bouncing-ball, tumbling-box, pyramid, cloth-drape (contact), cloth, top.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from . import scenes

SCENES = {
    "dominoes": (scenes.dominoes, 6.0),
    "bouncing-ball": (scenes.bouncing_ball, 5.0),
    "tumbling-box": (scenes.tumbling_box, 4.0),
    "pyramid": (scenes.pyramid, 5.0),
    "cloth-drape": (scenes.cloth_drape, 3.0),
    "cloth": (scenes.cloth, 3.0),
    "top": (scenes.spinning_top, 3.0),
    "pendulum": (scenes.pendulum, 4.0),
    "chain": (scenes.chain, 5.0),
    "cradle": (scenes.newtons_cradle, 3.0),
    "door": (scenes.door, 3.0),
    "ragdoll": (scenes.ragdoll, 3.0),
}


def _duration(text: str) -> float:
    """A duration from the command line: a finite number of seconds > 0, else argparse's usage error."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not (0.0 < value < float("inf")):
        raise argparse.ArgumentTypeError(f"must be a finite number of seconds above 0, got {text!r}")
    return value


def main() -> None:
    parser = argparse.ArgumentParser(prog="python -m tumble", description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=list(SCENES), default="dominoes")
    parser.add_argument("--duration", type=_duration, help="seconds to simulate (each scene has a default)")
    parser.add_argument("--out", default="tumble-out", help="folder for the animation, plot and report")
    parser.add_argument("--no-gif", action="store_true", help="skip the GIF preview (the slowest output)")
    args = parser.parse_args()

    build, default_duration = SCENES[args.scene]
    world = build()
    duration = args.duration or default_duration
    plan = world.plan()
    print(f"scene   {args.scene}: {len(world.particles)} particles, {len(world.bodies)} bodies")
    print(f"plan    {' -> '.join(plan['stages'])} ({plan['state_len']} state variables, {plan['mode']} mode, "
          f"method {plan['method']}" + (f", jacobian {plan['jacobian']}" if plan["jacobian"] else "") + ")")
    run = world.run(duration, 1 / 60, progress=True)
    print(f"ran     {run.times[-1]:.3f} s in {run.frames} frames")
    print(f"energy  {run.energy[0]:.6g} J -> {run.energy[-1]:.6g} J ({run.energy[-1] - run.energy[0]:+.3g} J)")
    if args.scene == "top":
        axis = run.body_positions[:, 0, :2]
        angle = np.unwrap(np.arctan2(axis[:, 1], axis[:, 0]))
        rate = (angle[-1] - angle[0]) / (run.times[-1] - run.times[0])
        a, b, c = 0.02 * np.cos(0.3), 0.04 * 40.0, 1.0 * 9.81 * 0.1
        steady = (b - np.sqrt(b * b - 4 * a * c)) / (2 * a)
        print(f"top     precession {rate:+.4f} rad/s (steady precession of a heavy top: {steady:.4f} rad/s)")
    if len(run.contact_events):
        print(f"events  {len(run.contact_events)} contact events, the first at {run.contact_events[0]:.9f} s")
    print(run.report)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{args.scene}-report.txt").write_text(str(run.report) + "\n")
    written = [run.export_gltf(out / f"{args.scene}.glb"), out / f"{args.scene}-report.txt"]
    run.plot(out / f"{args.scene}.png")
    written.append(out / f"{args.scene}.png")
    if not args.no_gif:
        written.append(run.animate(out / f"{args.scene}.gif", fps=15))
    for path in written:
        print(f"wrote   {path}")


if __name__ == "__main__":
    main()
