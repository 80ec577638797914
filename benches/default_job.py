"""The default job's cost: runs ``python -m tumble`` (or another scene) several times and reports the median of the
whole process's wall time (interpreter start and imports included), of the job's own total (what its last line
says), of each output, and the preview's share of both.

    python3 benches/default_job.py [--scene dominoes] [--repeat 5]
"""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import sys
import tempfile
import time


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0].replace("\n", " "))
    p.add_argument("--scene", default="dominoes", help="The scene to run. The default is dominoes.")
    p.add_argument("--repeat", type=int, default=5, help="How many runs to take the median of. The default is 5.")
    args = p.parse_args()
    walls, parts = [], []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as out:
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "tumble", "--scene", args.scene, "--out", out],
                                  capture_output=True, text=True, check=True)
            walls.append(time.perf_counter() - start)
        line = next(x for x in done.stdout.splitlines() if x.startswith("time "))
        total = float(re.search(r"time\s+([\d.]+) s in all", line).group(1))
        parts.append({"job": total, **{k: float(v) for k, v in re.findall(r"(\w+) ([\d.]+) s(?=[,;]|$)", line)}})
    median = {k: statistics.median(p[k] for p in parts) for k in parts[0]}
    wall = statistics.median(walls)
    print(f"{args.scene}, median of {args.repeat} runs:")
    print(f"  process wall time {wall:.2f} s; the job's own total {median['job']:.2f} s")
    for k, v in median.items():
        if k != "job":
            print(f"  {k:8s} {v:.2f} s")
    if "preview" in median:
        print(f"  the preview is {100 * median['preview'] / median['job']:.0f}% of the job's total and "
              f"{100 * median['preview'] / wall:.0f}% of the process's wall time")


if __name__ == "__main__":
    main()
