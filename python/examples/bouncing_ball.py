"""A ball dropped from 1 m onto the floor with restitution 0.8, in accurate mode: each bounce is located by bisection
on the integrator's dense output and the n-th apex is 0.64^n m. Prints the impact times and apex heights against
their closed forms, then writes the animation, plot and preview.

    python python/examples/bouncing_ball.py [--duration 5] [--out tumble-out] [--no-gif]
"""

import numpy as np
from _common import arguments, run_and_write

import tumble

G, E, R, H = 9.81, 0.8, 0.1, 1.0

args = arguments(__doc__.split("\n\n")[0], duration=5.0)
world = tumble.World(integrator="dopri5", rtol=1e-10, atol=1e-12)
world.add_ground(restitution=E, friction=0.0)
world.add_body(tumble.Sphere(R), density=1000.0, position=(0, 0, H + R), restitution=E, friction=0.0)
run = run_and_write(world, "bouncing-ball", args, frame_interval=1 / 240)

# Closed form: first impact at sqrt(2 H / g), then flights of 2 e^n v1 / g; the n-th apex at e^(2n) H.
v1 = np.sqrt(2 * G * H)
exact = np.cumsum([v1 / G] + [2 * E**n * v1 / G for n in range(1, 5)])
print("impact   time (s)          closed form        error")
for n, (t, x) in enumerate(zip(run.contact_events, exact), start=1):
    print(f"{n:6d}   {t:.12f}    {x:.12f}    {t - x:+.1e}")
# The apex between impacts n and n + 1 (the frames' highest, every 1/240 s: within g (1/480)^2 / 2 = 2.1e-5 m of
# the true apex) against e^(2n) H.
print("apex     height (m)        closed form        error")
z = run.body_positions[:, 1, 2] - R
for n, (a, b) in enumerate(zip(run.contact_events[:4], run.contact_events[1:5]), start=1):
    between = (run.times > a) & (run.times < b)
    if between.any():
        top = z[between].max()
        print(f"{n:6d}   {top:.12f}    {E ** (2 * n) * H:.12f}    {top - E ** (2 * n) * H:+.1e}")
print(f"{run.report.collisions} collisions, then at rest: z = {run.body_positions[-1, 1, 2]:.9f} m "
      f"(radius {R}), max penetration {run.report.max_penetration:.1e} m")
