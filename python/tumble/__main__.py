"""Runs a built-in scene, prints its plan and run report, and writes its animation, a preview, a plot and the report
into a folder.

    python -m tumble [--scene NAME] [--duration SECONDS] [--fps FRAMES] [--out DIR] [--no-gif] [--view]

The default scene is twenty dominoes toppling one another for 6 s. The folder gets NAME.glb (glTF for Blender and
web viewers), NAME.gif (a preview), NAME.png (energy and what else the run has, over time) and NAME-report.txt; the
last lines say how long each took.
"""

from __future__ import annotations

import argparse
import importlib.util
import textwrap
import time
from pathlib import Path
from typing import Callable

import numpy as np

from . import scenes
from ._install import install_hint
from ._run import Run
from ._world import World

# Each scene: how to build it, its default duration (s) and what it shows.
SCENES: dict[str, tuple[Callable[[], World], float, str]] = {
    "dominoes": (scenes.dominoes, 6.0, "twenty dominoes toppling one another (fast mode)"),
    "bouncing-ball": (scenes.bouncing_ball, 5.0, "a ball bouncing on the floor, each impact located exactly"),
    "tumbling-box": (scenes.tumbling_box, 4.0, "a box thrown spinning onto the floor, stopped by friction"),
    "pyramid": (scenes.pyramid, 5.0, "a pyramid of cubes, each resting on two below"),
    "cloth-drape": (scenes.cloth_drape, 3.0, "a cloth of particles falling over a ball onto the floor"),
    "cloth": (scenes.cloth, 3.0, "a cloth of particles and springs hanging from two corners"),
    "top": (scenes.spinning_top, 3.0, "a heavy spinning top precessing about its tip"),
    "pendulum": (scenes.pendulum, 4.0, "a ball on a rigid rod released from the horizontal"),
    "chain": (scenes.chain, 5.0, "a chain of twenty rods hanging from a point, a weight at its end"),
    "cradle": (scenes.newtons_cradle, 3.0, "Newton's cradle, the first ball pulled out and let go"),
    "door": (scenes.door, 3.0, "a door swung open by its hinge's motor to its limit"),
    "ragdoll": (scenes.ragdoll, 3.0, "a ragdoll of ten parts pushed down a flight of stairs"),
    "ball-in-cup": (scenes.ball_in_cup, 3.0, "a ball dropped into a cup of one non-convex mesh, staying in"),
    "ring-on-peg": (scenes.ring_on_peg, 3.0, "a ring (a torus mesh) tossed onto a peg, sliding down around it"),
    "chair": (scenes.chair, 2.0, "a chair of one non-convex mesh standing on its four legs"),
    "torus-roll": (scenes.torus_roll, 3.0, "a torus mesh rolling on its edge"),
    "mesh-pile": (scenes.mesh_pile, 3.0, "fifty meshes of five kinds dropped in a pile (fast mode)"),
    "vase-drop": (scenes.vase_drop, 2.0, "a vase of 50 glued pieces dropped onto the floor, shattering (fast mode)"),
    "glass-pane": (scenes.glass_pane, 1.0, "a steel ball thrown through a pane of 50 glued pieces (fast mode)"),
    "wrecking-ball": (scenes.wrecking_ball, 2.0, "a wrecking ball swung into a wall of 48 glued bricks (fast mode)"),
}


def _number(what: str, low: float, high: float, low_included: bool) -> Callable[[str], float]:
    """A parser of a number of ``what`` from ``low`` (included or not) to ``high`` (included; inf excluded), whose
    failures are argparse's usage errors."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number of {what}, got {text!r}") from None
        above = value >= low if low_included else value > low
        if not (above and value <= high and value < float("inf")):
            bounds = f"from {low:g} to {high:g}" if high < float("inf") else f"finite and above {low:g}"
            raise argparse.ArgumentTypeError(f"must be {bounds} {what}, got {text!r}")
        return value

    return parse


# Durations: a finite number of seconds above 0. Preview rates: 1 to 50 frames a second (GIF players slow faster
# ones down).
_duration = _number("seconds", 0.0, float("inf"), low_included=False)
_fps = _number("frames a second", 1.0, 50.0, low_included=True)


def parser() -> argparse.ArgumentParser:
    """The command line's parser."""
    doc = __doc__ or ""
    width = max(len(name) for name in SCENES)
    scenes_help = "\n".join(f"  {name:{width}}  {what}" for name, (_, _, what) in SCENES.items())
    p = argparse.ArgumentParser(
        prog="python -m tumble", description=textwrap.fill(doc.split("\n\n")[0].replace("\n", " "), 79),
        epilog=f"scenes:\n{scenes_help}", formatter_class=argparse.RawDescriptionHelpFormatter, add_help=False)
    p.add_argument("-h", "--help", action="help", help="Shows this help and exits.")
    p.add_argument("--scene", choices=list(SCENES), default="dominoes", metavar="NAME",
                   help="The scene to run (listed below). The default is dominoes.")
    p.add_argument("--duration", type=_duration, metavar="SECONDS",
                   help="How many seconds to simulate. Each scene has its own default, from 3 to 6 s.")
    p.add_argument("--fps", type=_fps, default=15.0, metavar="FRAMES",
                   help="Frames a second in the preview, from 1 to 50. The default is 15.")
    p.add_argument("--out", default="tumble-out", metavar="DIR",
                   help="The folder to write into; it is made if missing. The default is tumble-out.")
    p.add_argument("--no-gif", action="store_true", help="Writes no GIF preview.")
    p.add_argument("--view", action="store_true",
                   help="Opens the run in the interactive viewer afterwards (needs the viewer extra: "
                        f"{install_hint('viewer')}); Ctrl-C ends it.")
    return p


def main(argv: list[str] | None = None) -> None:
    """Runs the command line (``argv`` defaults to the process's arguments)."""
    p = parser()
    args = p.parse_args(argv)
    if args.view and importlib.util.find_spec("viser") is None:
        p.error(f"--view needs the viewer extra: {install_hint('viewer')}")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        p.error(f"argument --out: {str(out)!r} is a file, not a folder")
    start = time.perf_counter()
    build, default_duration, what = SCENES[args.scene]
    world = build()
    duration = args.duration or default_duration
    plan = world.plan()
    print(f"scene   {args.scene}, {what}: {len(world.particles)} particles, {len(world.bodies)} bodies")
    print(f"plan    {' -> '.join(plan['stages'])} ({plan['state_len']} state variables, {plan['mode']} mode, "
          f"method {plan['method']}" + (f", jacobian {plan['jacobian']}" if plan["jacobian"] else "") + ")")
    clock = time.perf_counter()
    run = world.run(duration, 1 / 60, progress=True)
    run.name = args.scene
    timings = {"run": time.perf_counter() - clock}
    print(f"ran     {run.times[-1]:.3f} s in {run.frames} frames")
    print(f"energy  {run.energy[0]:.6g} J -> {run.energy[-1]:.6g} J ({run.energy[-1] - run.energy[0]:+.3g} J)")
    if args.scene == "top":
        _precession(run)
    if len(run.contact_events):
        print(f"events  {len(run.contact_events)} contact events, the first at {run.contact_events[0]:.9f} s")
    print(run.report)
    out.mkdir(parents=True, exist_ok=True)
    outputs: list[tuple[str, Path, Callable[[Path], object]]] = [
        ("report", out / f"{args.scene}-report.txt", lambda path: path.write_text(str(run.report) + "\n")),
        ("glTF", out / f"{args.scene}.glb", run.export_gltf),
        ("plot", out / f"{args.scene}.png", run.plot),
    ]
    if not args.no_gif:
        outputs.append(("preview", out / f"{args.scene}.gif", lambda path: run.animate(path, fps=args.fps)))
    for label, path, write in outputs:
        clock = time.perf_counter()
        write(path)
        timings[label] = time.perf_counter() - clock
        print(f"wrote   {path} ({timings[label]:.2f} s)")
    total = time.perf_counter() - start
    shares = ", ".join(f"{label} {seconds:.2f} s" for label, seconds in timings.items())
    line = f"time    {total:.2f} s in all: {shares}"
    if "preview" in timings:
        line += f"; the preview is {100 * timings['preview'] / total:.0f}% of it"
    print(line)
    if args.view:
        run.show()  # prints http://127.0.0.1:8080 (the next free port if taken) and serves it until Ctrl-C


def _precession(run: Run) -> None:
    """Prints the top's precession rate beside the steady precession of a heavy top."""
    axis = run.body_positions[:, 0, :2]
    angle = np.unwrap(np.arctan2(axis[:, 1], axis[:, 0]))
    rate = (angle[-1] - angle[0]) / (run.times[-1] - run.times[0])
    a, b, c = 0.02 * np.cos(0.3), 0.04 * 40.0, 1.0 * 9.81 * 0.1
    steady = (b - np.sqrt(b * b - 4 * a * c)) / (2 * a)
    print(f"top     precession {rate:+.4f} rad/s (steady precession of a heavy top: {steady:.4f} rad/s)")


if __name__ == "__main__":
    main()
