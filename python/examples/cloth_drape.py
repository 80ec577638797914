"""A 12 x 12 cloth of particles (springs between neighbours and across diagonals) dropped over a ball resting on the
floor: particles with a radius collide with the ball and the floor (fast mode, 1/480 s).

    python python/examples/cloth_drape.py [--duration 3] [--out tumble-out] [--no-gif]
"""

import numpy as np
from _common import arguments, run_and_write

import tumble

args = arguments(__doc__.split("\n\n")[0], duration=3.0)
n, size = 12, 1.2
world = tumble.World()
world.set_mode("fast", dt=1 / 480, sleep=False)  # springs are explicit in fast mode: 1/480 s keeps them stable
world.add_ground(restitution=0.0, friction=0.5)
world.add_body(tumble.Sphere(0.3), position=(0, 0, 0.3), static=True, restitution=0.0, friction=0.5)
spacing, mass = size / (n - 1), 0.3 / n**2
ps = [[world.add_particle(mass, position=(i * spacing - size / 2, j * spacing - size / 2, 0.9), radius=0.01,
                          restitution=0.0, friction=0.5) for i in range(n)] for j in range(n)]
for j in range(n):
    for i in range(n):
        for (i0, j0), (i1, j1) in (((i, j), (i + 1, j)), ((i, j), (i, j + 1)), ((i, j), (i + 1, j + 1)),
                                   ((i + 1, j), (i, j + 1))):
            if max(i0, i1) < n and max(j0, j1) < n:
                world.add_spring(ps[j0][i0], ps[j1][i1], stiffness=60.0, damping=0.05)
run = run_and_write(world, "cloth-drape", args)
x = run.particle_positions[-1]
r = np.linalg.norm(x - np.array([0, 0, 0.3]), axis=1)
print(f"lowest particle z = {x[:, 2].min():.4f} m (floor 0, radius 0.01); closest to the ball's centre "
      f"{r.min():.4f} m (ball radius 0.3 + particle 0.01); max penetration {run.report.max_penetration:.1e} m")
