"""The peer comparison in one command: tumble's fast mode, Rapier, MuJoCo and PyBullet on the same scenes, one after
another on this machine, merged into one markdown table (a row per scene, a column per engine).

Each engine prints its own two-column table (``examples/fast_scenes.rs``, ``benches/peers/rapier``,
``python_engines.py``, ``pybullet_scenes.py``; the scene definitions are in their docstrings); this script runs them
in turn so that no two share the cores, and lines their rows up by label. An engine whose Python package is missing
is left out with a note (``pip install -r benches/peers/requirements.txt`` installs them). Not part of CI: the piles
take minutes.

    python3 benches/peers/compare.py             # piles of 100 and 1000
    python3 benches/peers/compare.py 100 --exact # also tumble's exact solver (slow on large piles)
    python3 benches/peers/compare.py --joints    # the joint scenes: tumble (fast and accurate), Rapier (impulse and
                                                 # multibody joints), MuJoCo (``examples/joint_scenes.rs``)
"""

from __future__ import annotations

import importlib.util
import os
import platform
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PEERS = os.path.join(ROOT, "benches", "peers")


def _table(command: list[str]) -> tuple[str, list[tuple[str, str]], str | None]:
    """Runs `command` and reads its two-column markdown table: (its header, [(label, value)], why it failed or
    None). Its own table goes to stderr as it comes, so that a long run's rows are seen before the end."""
    print(f"running: {' '.join(command)}", file=sys.stderr, flush=True)
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)  # noqa: S603
    sys.stderr.write(done.stdout)
    rows = [[cell.strip() for cell in line.strip().strip("|").split("|")] for line in done.stdout.splitlines()
            if line.startswith("|") and line.count("|") == 3]
    header = rows[0][0] if rows else os.path.basename(command[-1 - len([a for a in command if a.isdigit()])])
    body = [(r[0], r[1]) for r in rows[1:] if not set(r[0]) <= {"-"}]
    failure = None
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines()
        failure = f"{header} stopped: {lines[-1] if lines else f'exit status {done.returncode}'}"
    return header, body, failure


def joint_commands() -> tuple[list[list[str]], list[str]]:
    """The joint scenes' commands, and the peers left out."""
    cargo = ["cargo", "run", "--quiet", "--release"]
    rapier = cargo + ["--manifest-path", os.path.join(PEERS, "rapier", "Cargo.toml"), "--", "joints"]
    commands = [cargo + ["--example", "joint_scenes"], cargo + ["--example", "joint_scenes", "--", "accurate"],
                rapier, rapier + ["multibody"]]
    if importlib.util.find_spec("mujoco") is None:
        return commands, ["mujoco"]
    return commands + [[sys.executable, os.path.join(PEERS, "python_engines.py"), "joints"]], []


def main() -> None:
    args = sys.argv[1:]
    sizes = [a for a in args if a.isdigit()] or ["100", "1000"]
    cargo = ["cargo", "run", "--quiet", "--release"]
    commands = [cargo + ["--example", "fast_scenes", "--", "soft", *sizes]]
    if "--exact" in args:
        commands.append(cargo + ["--example", "fast_scenes", "--", "exact", *sizes])
    commands.append(cargo + ["--manifest-path", os.path.join(PEERS, "rapier", "Cargo.toml"), "--", *sizes])
    missing = []
    for module, script in (("mujoco", "python_engines.py"), ("pybullet", "pybullet_scenes.py")):
        if importlib.util.find_spec(module) is None:
            missing.append(module)
        else:
            commands.append([sys.executable, os.path.join(PEERS, script), *sizes])
    if "--joints" in args:
        commands, missing = joint_commands()
    columns, labels, failures = [], [], []
    for command in commands:
        header, rows, failure = _table(command)
        columns.append((header, dict(rows)))
        labels += [label for label, _ in rows if label not in labels]
        failures += [failure] if failure else []
    print(f"Measured {time.strftime('%Y-%m-%d')} on {platform.machine()}, {os.cpu_count()} cores, one run each "
          f"(`python3 benches/peers/compare.py {' '.join(args)}`).\n")
    print("| scene | " + " | ".join(h for h, _ in columns) + " |")
    print("|---|" + "---|" * len(columns))
    for label in labels:
        print(f"| {label} | " + " | ".join(values.get(label, "-") for _, values in columns) + " |")
    if missing:
        print(f"\nLeft out (not installed): {', '.join(missing)}.")
    for failure in failures:
        print(f"\n{failure}")


if __name__ == "__main__":
    main()
