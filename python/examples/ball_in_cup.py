"""A rubber ball dropped into a cup: the cup is one non-convex mesh (built here as a solid of revolution and
written to an OBJ file, then read back as a user's asset would be), moving as its convex decomposition. Prints where
the ball ends, and where it ends when the cup is given its convex hull instead (on the lid).

    python python/examples/ball_in_cup.py [--duration 3] [--out tumble-out] [--no-gif]
"""

import numpy as np
from _common import arguments, run_and_write

import tumble

args = arguments(__doc__.split("\n\n")[0], duration=3.0)
args.out.mkdir(parents=True, exist_ok=True)
# A cup's profile, (radius, height) in metres from the axis at the bottom round to the axis at the inner floor,
# turned about z; written to an OBJ file and read back, as a modelled asset would be.
profile = [(0.0, 0.0), (0.05, 0.0), (0.05, 0.08), (0.045, 0.08), (0.045, 0.005), (0.0, 0.005)]
made = tumble.Mesh.revolve(profile, segments=48, name="cup")
path = args.out / "cup.obj"
path.write_text("o cup\n" + "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in made.vertices.tolist())
                + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in made.triangles.tolist()))
cup = tumble.Mesh.load(path, scale=1.0, up="z")
com = cup.mass_properties(2400.0)["center_of_mass"]
print(f"cup: {len(cup.triangles)} triangles, {cup.volume * 1e6:.1f} cm^3, {cup.mass_properties(2400.0)['mass']:.3f} kg")

for shape in ("decomposed", "hull"):
    world = tumble.World()
    world.add_ground(friction=0.5)
    world.add_body(cup, density=2400.0, position=(0.0, 0.0, 1e-4 + com[2]), shape=shape)
    ball = world.add_body(tumble.Sphere(0.015), density=1100.0, position=(0.01, 0.0, 0.15), restitution=0.3)
    if shape == "decomposed":
        run = run_and_write(world, "ball-in-cup", args)
        print(f"the cup in {world.report.mesh_pieces} convex pieces")
    else:
        world.step(args.duration)
    x, y, z = world.bodies.positions[2]
    inside = np.hypot(x, y) < 0.03 and 0.005 < z < 0.08
    print(f"{shape:>10}: the ball ends at ({x:+.4f}, {y:+.4f}, {z:.4f}) m, {'in the cup' if inside else 'out of it'}")
