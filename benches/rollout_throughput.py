"""Batch throughput (issue 15): simulated seconds per wall second of ``tumble.rollout`` against the number of worlds,
and the batch of 8 against the same 8 runs one after another, on the built-in dominoes (fast mode) and spinning top
(Radau5 at 1e-8). Prints one markdown table.

    python3 benches/rollout_throughput.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import copy
import os
import time

import numpy as np

import tumble


def states_of(w: tumble.World, count: int) -> list:
    """The world's state with ``count`` different pushes of its body of row 1 (or row 0 when it has one)."""
    s = w.get_state()
    out = []
    for k in range(count):
        push = np.zeros_like(s.body_momenta)
        push[min(1, len(push) - 1)] = (0.02 * k, 0.0, 0.0)
        out.append(s.replace(body_momenta=s.body_momenta + push))
    return out


def best(f, repeats: int) -> float:
    """The least wall time of ``repeats`` calls (the machine's noise only adds)."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"{os.cpu_count()} cores; least of {args.repeats} runs each\n")
    print("| scene | worlds | simulated s | one after another (s) | rollout (s) | rollout / sequential | sim s per wall s |")
    print("|---|---|---|---|---|---|---|")
    for name, build, duration in [("dominoes (fast)", tumble.scenes.dominoes, 6.0),
                                  ("spinning top (Radau5)", tumble.scenes.spinning_top, 2.0)]:
        w = build()
        for n in (1, 2, 4, 8, 16):
            states = states_of(w, n)

            def sequential() -> None:
                one = copy.deepcopy(w)
                for s in states:
                    one.set_state(s)
                    one.run(duration)

            seq = best(sequential, args.repeats)
            par = best(lambda: tumble.rollout(w, states, duration), args.repeats)
            print(f"| {name} | {n} | {n * duration:g} | {seq:.3f} | {par:.3f} | {par / seq:.2f} | {n * duration / par:.1f} |")


if __name__ == "__main__":
    main()
