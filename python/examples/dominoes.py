"""Twenty dominoes in a row, the first tipped toward the others (fast mode, 1/240 s). Prints when each one falls.

    python python/examples/dominoes.py [--duration 6] [--count 20] [--out tumble-out] [--no-gif]
"""

import numpy as np
from _common import arguments, run_and_write

import tumble

args = arguments(__doc__.split("\n\n")[0], count=(20, "dominoes"), duration=6.0)
world = tumble.World(mode="fast", dt=1 / 240)
world.add_ground(restitution=0.1, friction=0.6)
half = (0.04, 0.2, 0.4)
for k in range(args.count):
    world.add_body(tumble.Box(half), density=700.0, position=(0.5 * k, 0, half[2]), restitution=0.1, friction=0.4,
                   angular_velocity=(0, 2.0, 0) if k == 0 else (0, 0, 0))
run = run_and_write(world, "dominoes", args)
# A domino has fallen once its centre is below half its standing height (0.2 m); body 0 is the ground.
heights = run.body_positions[:, 1:, 2]
fell = [run.times[np.argmax(h < 0.2)] if (h < 0.2).any() else None for h in heights.T]
print("fell at (s): " + " ".join("-" if t is None else f"{t:.2f}" for t in fell))
