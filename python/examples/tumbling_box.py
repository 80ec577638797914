"""A box thrown spinning onto the floor, where friction (0.6) and restitution (0.3) bring it to rest: fast mode,
fixed steps of 1/240 s, the soft contact step with Coulomb friction, the box asleep once still. Prints its final
speed, the energy it lost, whether it sleeps and the largest penetration.

    python python/examples/tumbling_box.py [--duration 4] [--out tumble-out] [--no-gif]
"""

import numpy as np
from _common import arguments, energy_change, run_and_write

import tumble

args = arguments(__doc__.split("\n\n")[0], duration=4.0)
world = tumble.World(mode="fast", dt=1 / 240)
world.add_ground(restitution=0.3, friction=0.6)
# orientation as a quaternion (w, x, y, z): a tilt of about 0.55 rad
tilt = np.array([0.96, 0.2, 0.15, 0.1])
world.add_body(tumble.Box((0.3, 0.2, 0.15)), density=600.0, position=(-1.5, 0, 1.5),
               orientation=tilt / np.linalg.norm(tilt), velocity=(2.0, 0.3, 1.0), angular_velocity=(4.0, 6.0, 2.0),
               restitution=0.3, friction=0.6)
run = run_and_write(world, "tumbling-box", args)
speed = np.linalg.norm(run.body_velocities[-1, 1])
print(f"final speed {speed:.2e} m/s, energy change {100 * energy_change(run):+.1f}%, "
      f"{run.report.sleepers} asleep, max penetration {run.report.max_penetration:.1e} m")
