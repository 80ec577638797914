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
    python3 benches/peers/compare.py --front     # the 1,000-cube pile at every Rapier substep count (1 to 16) and
                                                 # tumble settings from 2 x 1 to 16 x 2: time against penetration
    python3 benches/peers/compare.py --pyramids  # Box3D's two walls of cubes in tumble (default, 4 x 2, 2 x 1) and
                                                 # Rapier (4 substeps), beside Box3D's own figures

Penetration is the deepest overlap recomputed from the poses in every engine (``benches/peers/overlap.rs``, which
tumble's example and the Rapier project both include), never an engine's own manifolds.
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


#: tumble's settings on the front (substeps, sweeps) and Rapier's substep counts.
TUMBLE_FRONT = [(2, 1), (3, 1), (4, 1), (6, 1), (8, 1), (8, 2), (12, 2), (16, 2)]
RAPIER_FRONT = [1, 2, 4, 8, 16]

#: Box3D's own figures on its two walls (erincatto/box3d's `benchmarks.c`, f32, SSE2, 4 substeps, one worker),
#: measured on this 2-core machine beside Rapier 0.36.1 and tumble: ms a step and the large pyramid top's sink after
#: 200 steps. Box3D is not built here (its code stays out of this project); these are the numbers of that run.
BOX3D = {"large": (15.6, 691.0), "many": (28.6, None)}


def machine() -> str:
    """The machine the numbers come from: its processor's model (from /proc/cpuinfo where there is one), the
    architecture and the cores."""
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            names = [line.split(":", 1)[1].strip() for line in f if line.startswith("model name")]
        model = names[0] if names else model
    except OSError:
        pass
    return f"{model} ({platform.machine()}), {os.cpu_count()} cores"


def _pile_row(command: list[str]) -> tuple[float, float] | None:
    """(ms a step, penetration in mm) of the 1,000-cube pile without sleeping, from an engine's table."""
    _, rows, _ = _table(command)
    for label, value in rows:
        if label.startswith("pile 1000, no sleep"):
            ms, pen = value.split("/")
            return float(ms.strip().split()[0]), float(pen.strip().split()[0])
    return None


def front() -> None:
    """The 1,000-cube pile at every Rapier substep count and at tumble's settings, one thread each, and for each
    Rapier setting the quickest tumble setting that is no slower and penetrates no deeper."""
    cargo = ["cargo", "run", "--quiet", "--release"]
    rapier = cargo + ["--manifest-path", os.path.join(PEERS, "rapier", "Cargo.toml"), "--"]
    tumble = {s: _pile_row(cargo + ["--example", "fast_scenes", "--", "soft", "1000", "--threads", "1", "--only-piles",
                                    "--substeps", str(s[0]), "--iterations", str(s[1])]) for s in TUMBLE_FRONT}
    peer = {n: _pile_row(rapier + ["1000", "--only-piles", "--substeps", str(n)]) for n in RAPIER_FRONT}
    print(f"Measured {time.strftime('%Y-%m-%d')} on {machine()}, one thread each, "
          f"one run (`python3 benches/peers/compare.py --front`): the 1,000-cube pile, ms a step / deepest overlap.\n")
    print("| tumble substeps x sweeps | ms a step | overlap (mm) |\n|---|---|---|")
    for (s, k), row in tumble.items():
        print(f"| {s} x {k} | " + (f"{row[0]:.3f} | {row[1]:.3f} |" if row else "- | - |"))
    print("\n| Rapier 0.36.1 substeps | ms a step | overlap (mm) | tumble no slower and no deeper |\n|---|---|---|---|")
    for n, row in peer.items():
        if row is None:
            print(f"| {n} | - | - | - |")
            continue
        better = [(s, r) for s, r in tumble.items() if r and r[0] <= row[0] and r[1] <= row[1]]
        best = min(better, key=lambda x: x[1][0]) if better else None
        found = f"{best[0][0]} x {best[0][1]} ({best[1][0]:.3f} ms, {best[1][1]:.3f} mm)" if best else "none"
        print(f"| {n} | {row[0]:.3f} | {row[1]:.3f} | {found} |")


def pyramids() -> None:
    """Box3D's two walls in tumble (default, 4 x 2, 2 x 1) and Rapier (4 substeps), one thread each, beside
    Box3D's figures."""
    cargo = ["cargo", "run", "--quiet", "--release"]
    commands = [cargo + ["--example", "fast_scenes", "--", "pyramids", "--threads", "1"],
                cargo + ["--example", "fast_scenes", "--", "pyramids", "--threads", "1", "--substeps", "4",
                         "--iterations", "2"],
                cargo + ["--example", "fast_scenes", "--", "pyramids", "--threads", "1", "--substeps", "2",
                         "--iterations", "1"],
                cargo + ["--manifest-path", os.path.join(PEERS, "rapier", "Cargo.toml"), "--", "pyramids"]]
    columns = []
    for command, name in zip(commands, ["tumble (default)", "tumble 4 x 2", "tumble 2 x 1", "Rapier 0.36.1 (4)"]):
        _, rows, failure = _table(command)
        columns.append((name, dict(rows), failure))
    print(f"Measured {time.strftime('%Y-%m-%d')} on {machine()}, one thread each, "
          f"one run (`python3 benches/peers/compare.py --pyramids`). Box3D's column is its own run on this machine "
          f"(f32, SSE2, 4 substeps, one worker).\n")
    labels = [label for label in columns[0][1]]
    print("| scene | " + " | ".join(name for name, _, _ in columns) + " | Box3D |")
    print("|---|" + "---|" * (len(columns) + 1))
    for label in labels:
        box3d = BOX3D["large" if label.startswith("large") else "many"]
        box3d_cell = f"{box3d[0]} ms" + (f" / {box3d[1]:.0f} mm" if box3d[1] is not None else "")
        print(f"| {label} | " + " | ".join(values.get(label, "-") for _, values, _ in columns) + f" | {box3d_cell} |")
    for name, _, failure in columns:
        if failure:
            print(f"\n{name}: {failure}")


def main() -> None:
    args = sys.argv[1:]
    if "--front" in args:
        front()
        return
    if "--pyramids" in args:
        pyramids()
        return
    sizes = [a for a in args if a.isdigit()] or ["100", "1000"]
    cargo = ["cargo", "run", "--quiet", "--release"]
    # one thread each: the Rapier project is built without its parallel feature
    commands = [cargo + ["--example", "fast_scenes", "--", "soft", *sizes, "--threads", "1"]]
    if "--exact" in args:
        commands.append(cargo + ["--example", "fast_scenes", "--", "exact", *sizes, "--threads", "1"])
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
    print(f"Measured {time.strftime('%Y-%m-%d')} on {machine()}, one run each "
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
