"""What every example shares: its command line (--duration, --out, --no-gif) and writing a run's outputs."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import tumble


def arguments(description: str, duration: float, **counts: tuple[int, str]) -> argparse.Namespace:
    """The common options, and one integer option per keyword: name=(default, help)."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--duration", type=float, default=duration, help=f"simulated seconds (default {duration})")
    for name, (default, text) in counts.items():
        p.add_argument(f"--{name}", type=int, default=default, help=f"{text} (default {default})")
    p.add_argument("--out", type=Path, default=Path("tumble-out"), help="directory for the outputs")
    p.add_argument("--no-gif", action="store_true", help="skip the GIF preview (the slowest output)")
    return p.parse_args()


def run_and_write(world: tumble.World, name: str, args: argparse.Namespace, frame_interval: float = 1 / 60):
    """Runs the world with a progress bar, prints its plan and report, and writes name.glb, name.png, name.gif."""
    plan = world.plan()
    print(f"plan    {' -> '.join(plan['stages'])} ({plan['mode']} mode, {plan['state_len']} state variables)")
    run = world.run(args.duration, frame_interval, progress=True)
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
