"""A pyramid of 55 cubes in 10 layers, each on two below, standing for 10 s in fast mode; prints how far any cube
moved and how soon the pyramid fell asleep.

    python python/examples/pyramid.py [--duration 10] [--layers 10] [--out tumble-out] [--no-gif]
"""

import numpy as np
from _common import arguments, run_and_write

import tumble

args = arguments(__doc__.split("\n\n")[0], layers=(10, "layers the pyramid has"), duration=10.0)
world = tumble.World(mode="fast", dt=1 / 240)
world.add_ground(restitution=0.0, friction=0.6)
for layer in range(args.layers):
    for k in range(args.layers - layer):
        x = (k + 0.5 * layer) * 0.5
        world.add_body(tumble.Box((0.25, 0.25, 0.25)), density=500.0, position=(x, 0, 0.25 + 0.5 * layer),
                       restitution=0.0, friction=0.6)
run = run_and_write(world, "pyramid", args, frame_interval=1 / 30)
moved = np.linalg.norm(run.body_positions[:, 1:] - run.body_positions[0, 1:], axis=2).max()
# A sleeping body's velocity is exactly zero: the pyramid is asleep from the first frame after which no cube moves.
still = (run.body_velocities[:, 1:] == 0).all(axis=(1, 2)) & (run.body_angular_velocities[:, 1:] == 0).all(axis=(1, 2))
awake = np.flatnonzero(~still)
asleep = "never" if not still[-1] else f"from t = {run.times[awake[-1] + 1 if len(awake) else 0]:.2f} s"
print(f"{len(run.body_positions[0]) - 1} cubes; the largest displacement of any cube: {moved:.2e} m; "
      f"all asleep {asleep} ({run.report.sleepers} asleep at the end)")
