"""Directing the outcome, measured: five dice thrown onto a table, die 1 made to show each face in turn (only its
start varied: orientation within 180 degrees, spin within 10 rad/s), in fast and in accurate mode; then a box thrown
to tumble and rest within 1 cm of a place 2 m away, the search against the animator's way (random re-throws within
the same bounds, the same seed, until one meets the goal). Prints each search's tries, wall time and whether it met
the goal; and the ball-in-cup scene's ball thrown from 1.5 m into the cup.

    python python/examples/direct.py [--faces 6] [--modes fast,accurate] [--tries 256] [--seeds 6] [--budget 2048] [--random-budget 8192] [--pose-seeds 3]
        [--cup-seeds 3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import tumble
import tumble.direct as td

# a die's faces by the body axis through them (1 opposite 6, 2 opposite 5, 3 opposite 4)
FACES = {1: (0, 0, 1), 6: (0, 0, -1), 2: (1, 0, 0), 5: (-1, 0, 0), 3: (0, 1, 0), 4: (0, -1, 0)}


def dice(mode: str) -> tuple[tumble.World, list[tumble.BodyHandle]]:
    """Five 2 cm dice thrown from a hand's height along a table."""
    w = tumble.World(mode=mode) if mode == "fast" else tumble.World()
    w.add_ground(friction=0.5, restitution=0.3)
    rng = np.random.default_rng(7)
    dice = []
    for k in range(5):
        dice.append(w.add_body(tumble.Box((0.01, 0.01, 0.01)), density=1200.0, friction=0.5, restitution=0.3,
                               position=(0.03 * k, 0.04 * (k % 2), 0.15 + 0.03 * k),
                               orientation=tuple(rng.normal(size=4)), velocity=(0.6, 0.0, 0.0),
                               angular_velocity=tuple(rng.normal(0.0, 8.0, 3))))
    return w, dice


def thrown_box() -> tuple[tumble.World, tumble.BodyHandle]:
    w = tumble.World(mode="fast")
    w.add_ground(friction=0.6)
    box = w.add_body(tumble.Box((0.05, 0.05, 0.05)), position=(0, 0, 0.3), velocity=(3.0, 0.0, 1.0),
                     angular_velocity=(0.0, 4.0, 0.0), friction=0.6)
    return w, box


def cup_and_ball(mode: str) -> tuple[tumble.World, tumble.BodyHandle]:
    """The ball-in-cup scene's cup (a solid of revolution, moving as its convex pieces) and its ball thrown from
    1.5 m away."""
    profile = [(0.0, 0.0), (0.05, 0.0), (0.05, 0.08), (0.045, 0.08), (0.045, 0.005), (0.0, 0.005)]
    cup = tumble.Mesh.revolve(profile, segments=48, name="cup")
    w = tumble.World(mode=mode) if mode == "fast" else tumble.World()
    w.add_ground(friction=0.5)
    w.add_body(cup, density=2400.0, position=(0.0, 0.0, 1e-4 + cup.mass_properties(2400.0)["center_of_mass"][2]))
    ball = w.add_body(tumble.Sphere(0.015), density=1100.0, position=(-1.5, 0.0, 0.3), velocity=(3.0, 0.0, 2.0),
                      restitution=0.3)
    return w, ball


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--faces", type=int, default=6)
    p.add_argument("--modes", default="fast,accurate")
    p.add_argument("--tries", type=int, default=256)
    p.add_argument("--seeds", type=int, default=6)
    p.add_argument("--budget", type=int, default=2048)
    p.add_argument("--random-budget", type=int, default=8192)
    p.add_argument("--pose-seeds", type=int, default=3)
    p.add_argument("--cup-seeds", type=int, default=3)
    args = p.parse_args()
    for mode in args.modes.split(","):
        for face, axis in list(FACES.items())[:args.faces]:
            w, ds = dice(mode)
            clock = time.perf_counter()
            found = td.search(w, {ds[0]: td.Vary(orientation=180.0, spin=10.0)}, td.face_up(ds[0], axis),
                              duration=2.0, tries=args.tries, seed=face)
            print(f"{mode:>8} dice, face {face}: {'met' if found.met else 'NOT met'} in {found.tries} tries, "
                  f"{time.perf_counter() - clock:.2f} s")
    for mode in args.modes.split(","):
        w, ball = cup_and_ball(mode)
        for seed in range(args.cup_seeds):
            clock = time.perf_counter()
            found = td.search(w, {ball: td.Vary(velocity=1.5)}, td.rest_at(ball, (0.0, 0.0, 0.02), within=0.03),
                              duration=2.0, tries=2 * args.tries, seed=seed)
            print(f"{mode:>8} ball into the cup from 1.5 m, seed {seed}: {'met' if found.met else 'NOT met'} in "
                  f"{found.tries} tries, {time.perf_counter() - clock:.2f} s, best cost {found.cost:.3g} m")
    w, box = thrown_box()
    # to a pose: within 1 cm and 5 degrees of upright 2 m away (its start's orientation may change too)
    pose = td.rest_at(box, (2.0, 0.0, 0.05), within=0.01, angle=5.0, orientation=(1, 0, 0, 0))
    for seed in range(args.pose_seeds):
        found = td.search(w, {box: td.Vary(velocity=3.0, spin=6.0, orientation=30.0)}, pose, duration=3.0,
                          tries=args.budget, seed=seed)
        print(f"box to a pose 2 m away, seed {seed}: {'met' if found.met else 'NOT met'} in {found.tries} tries, "
              f"{found.seconds:.2f} s, best cost {found.cost:.3g} m")
    vary = {box: td.Vary(velocity=3.0, spin=6.0)}
    target = td.rest_at(box, (2.0, 0.0, 0.05), within=0.01)
    # the search against the animator's way on the same target: random re-throws within the same bounds
    totals = {"search": [0, 0], "random": [0, 0]}  # tries, goals met
    for seed in range(args.seeds):
        clock = time.perf_counter()
        searched = td.search(w, vary, target, duration=3.0, tries=args.budget, seed=seed)
        took = time.perf_counter() - clock
        rethrown = td.search(w, vary, target, duration=3.0, tries=args.random_budget, seed=seed, method="random")
        for name, found in (("search", searched), ("random", rethrown)):
            totals[name][0] += found.tries
            totals[name][1] += found.met
        print(f"box to rest 2 m away within 1 cm, seed {seed}: the search "
              f"{'met' if searched.met else 'NOT met'} in {searched.tries} tries ({took:.2f} s), random re-throws "
              f"{'met' if rethrown.met else 'NOT met'} in {rethrown.tries}")
    if args.seeds:
        (tries, met), (random_tries, random_met) = totals["search"], totals["random"]
        print(f"the search: {met} of {args.seeds} met, {tries} tries; random re-throws: {random_met} met, "
              f"{random_tries} tries")
        if met and random_met:
            from scipy.stats import chi2

            # random's successes a Poisson count: its rate's 95% interval, and the ratio of tries an answer with it
            low, high = chi2.ppf(0.025, 2 * random_met) / 2, chi2.ppf(0.975, 2 * random_met + 2) / 2
            each = tries / met
            print(f"tries an answer: the search {each:.0f}, random {random_tries / random_met:.0f}: "
                  f"{random_tries / random_met / each:.1f} times fewer (95%: "
                  f"{random_tries / high / each:.1f} to {random_tries / low / each:.1f})")

if __name__ == "__main__":
    main()
