"""Draws error against wall time from `target/contact_precision.csv` (written by
`cargo run --release --example contact_precision`): one panel per friction problem, accurate mode over contact
tolerances and fast mode over steps. Writes `examples/contact_precision/contact_precision.png` (the README shows it).

    python3 examples/plot_contact_precision.py
"""

import csv
from collections import defaultdict
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

root = Path(__file__).resolve().parent.parent
rows = list(csv.DictReader(open(root / "target" / "contact_precision.csv")))
problems = list(dict.fromkeys(r["problem"] for r in rows))
fig = Figure(figsize=(5 * len(problems), 4.5), layout="constrained")
FigureCanvasAgg(fig)
for ax, problem in zip(fig.subplots(1, len(problems), squeeze=False)[0], problems):
    series = defaultdict(list)
    for r in rows:
        if r["problem"] == problem:
            series[r["mode"]].append((float(r["wall_seconds"]), max(float(r["relative_error"]), 1e-16), r["setting"]))
    for mode, points in series.items():
        ax.loglog([p[0] for p in points], [p[1] for p in points], "o-", label=mode)
        for wall, error, setting in points:
            ax.annotate(f"{float(setting):.0e}", (wall, error), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_title(problem, fontsize=9)
    ax.set_xlabel("wall time (s, fastest of 3)")
    ax.set_ylabel("relative error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
out = root / "examples" / "contact_precision" / "contact_precision.png"
fig.savefig(out, dpi=100)
print(f"written to {out}")
