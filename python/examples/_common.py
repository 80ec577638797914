"""What every example shares: its command line (--duration, --out, --no-gif) and writing a run's outputs."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import tumble


def _seconds(text: str) -> float:
    """A duration: a finite number of seconds above 0, else argparse's usage error."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not 0.0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"must be a finite number of seconds above 0, got {text!r}")
    return value


def _count(text: str) -> int:
    """A count: a whole number from 1 to 1000, else argparse's usage error."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if not 1 <= value <= 1000:
        raise argparse.ArgumentTypeError(f"must be from 1 to 1000, got {text!r}")
    return value


def arguments(description: str, duration: float, **counts: tuple[int, str]) -> argparse.Namespace:
    """The common options, and one integer option per keyword: name=(default, what it counts)."""
    p = argparse.ArgumentParser(description=description.replace("\n", " "), add_help=False)
    p.add_argument("-h", "--help", action="help", help="Shows this help and exits.")
    p.add_argument("--duration", type=_seconds, default=duration, metavar="SECONDS",
                   help=f"How many seconds to simulate. The default is {duration:g}.")
    for name, (default, text) in counts.items():
        p.add_argument(f"--{name}", type=_count, default=default, metavar="N",
                       help=f"How many {text}. The default is {default}.")
    p.add_argument("--out", type=Path, default=Path("tumble-out"), metavar="DIR",
                   help="The folder to write into; it is made if missing. The default is tumble-out.")
    p.add_argument("--no-gif", action="store_true", help="Writes no GIF preview.")
    args = p.parse_args()
    if args.out.exists() and not args.out.is_dir():
        p.error(f"argument --out: {str(args.out)!r} is a file, not a folder")
    return args


def run_and_write(world: tumble.World, name: str, args: argparse.Namespace, frame_interval: float = 1 / 60):
    """Runs the world with a progress bar, prints its plan and report, and writes name.glb, name.png, name.gif."""
    plan = world.plan()
    print(f"plan    {' -> '.join(plan['stages'])} ({plan['mode']} mode, {plan['state_len']} state variables)")
    run = world.run(args.duration, frame_interval, progress=True)
    run.name = name
    print(run.report)
    args.out.mkdir(parents=True, exist_ok=True)
    written = [run.export_gltf(args.out / f"{name}.glb")]
    run.plot(args.out / f"{name}.png")
    written.append(args.out / f"{name}.png")
    if not args.no_gif:
        written.append(run.animate(args.out / f"{name}.gif"))
    for path in written:
        print("wrote  ", path)
    return run


def energy_change(run) -> float:
    """Relative change of mechanical energy from the first frame to the last."""
    e = np.asarray(run.energy)
    return float((e[-1] - e[0]) / abs(e[0]))
