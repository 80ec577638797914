"""Blender's own rigid bodies (Bullet, at the scene's defaults) against tumble's bake of the same Blender scenes,
headless with Blender as a module: bounce apexes and impact times, an incline's slide against its closed form, a
stack's drift, dominoes' fall time, and the time a frame of piles of 100 and 1,000 cubes. Each scene is built
through Blender's operators once; Blender plays it frame by frame (its simulation, from a freed cache), then
``tumble.blender.bake`` bakes it and the keyframes are read back the same way. Prints a markdown table.

    target/blender-env/bin/python benches/peers/blender_bake.py [--substeps N] [--quick]

(the environment ``.ci/run`` makes: tumble's wheel with the ``blender`` and ``usd`` extras). Dampings are set to
zero where a closed form is compared (Blender's defaults, 0.04 and 0.1, slow every body)."""

from __future__ import annotations

import math
import sys
import time

import bpy
import numpy as np

import tumble.blender as tb

G = 9.81
FPS = 60


def scene_of(frames: int, substeps: int) -> bpy.types.Scene:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = FPS, 1.0
    bpy.ops.rigidbody.world_add()
    world = scene.rigidbody_world
    world.point_cache.frame_start, world.point_cache.frame_end = 1, frames
    world.substeps_per_frame = substeps
    return scene


def body(kind: str, location, shape: str, size: float, passive: bool = False, **settings):
    add = {"cube": bpy.ops.mesh.primitive_cube_add, "sphere": bpy.ops.mesh.primitive_uv_sphere_add,
           "plane": bpy.ops.mesh.primitive_plane_add}[kind]
    add(**({"radius": size} if kind == "sphere" else {"size": size}), location=location)
    obj = bpy.context.active_object
    bpy.ops.rigidbody.object_add(type="PASSIVE" if passive else "ACTIVE")
    obj.rigid_body.collision_shape = shape
    for k, v in settings.items():
        setattr(obj.rigid_body, k, v)
    return obj


def _slab(**settings):
    """The ground: a passive 40 x 40 x 1 m box, its top at z = 0."""
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0, 0, -0.5))
    obj = bpy.context.active_object
    obj.scale = (40.0, 40.0, 1.0)
    bpy.ops.rigidbody.object_add(type="PASSIVE")
    obj.rigid_body.collision_shape = "BOX"
    for k, v in settings.items():
        setattr(obj.rigid_body, k, v)
    return obj


def play(scene, objects, frames):
    """Blender's simulation: every frame from the start, each object's world location (F, N, 3) and rotation
    (F, N, 3, 3), and the seconds a frame took."""
    bpy.ops.ptcache.free_bake_all()
    scene.rigidbody_world.enabled = True
    scene.frame_set(1)
    where, turns = [], []
    clock = time.perf_counter()
    for f in range(1, frames + 1):
        scene.frame_set(f)
        where.append([tuple(o.matrix_world.translation) for o in objects])
        turns.append([np.array(o.matrix_world.to_3x3()) for o in objects])
    return np.array(where), np.array(turns), (time.perf_counter() - clock) / frames


def both(build, frames, substeps, **bake_options):
    """(Blender's (where, turns, s/frame), tumble's) for the scene ``build`` makes (it returns the objects)."""
    scene = scene_of(frames, substeps)
    objects = build()
    blender = play(scene, objects, frames)
    clock = time.perf_counter()
    report = tb.bake(scene, **bake_options)
    baked_seconds = (time.perf_counter() - clock) / frames
    where, turns = [], []
    for f in range(1, frames + 1):
        scene.frame_set(f)
        where.append([tuple(o.matrix_world.translation) for o in objects])
        turns.append([np.array(o.matrix_world.to_3x3()) for o in objects])
    return blender, (np.array(where), np.array(turns), baked_seconds, report)


def bounce(substeps):
    """A ball of radius 0.1 m dropped from 1 m (its bottom) with restitution 0.8 (0.8 x 1.0 with the ground)."""
    def build():
        _slab(restitution=1.0)
        ball = body("sphere", (0, 0, 1.1), "SPHERE", 0.1, restitution=0.8, linear_damping=0.0, angular_damping=0.0)
        return [ball]
    (bw, _, _), (tw, _, _, _) = both(build, 90, substeps)
    out = []
    for name, z in (("Blender (Bullet)", bw[:, 0, 2] - 0.1), ("tumble", tw[:, 0, 2] - 0.1)):
        rising = np.nonzero(np.diff(z) > 0)[0]  # the first frame after which it rises: the first impact
        impact = int(rising[0]) if len(rising) else len(z) - 1
        falling = np.nonzero(np.diff(z[impact:]) < 0)[0]
        apex = float(z[impact + int(falling[0])]) if len(falling) else float(z[impact:].max())
        out.append((name, impact / FPS, apex))
    return out, (math.sqrt(2 / G), 0.64)


def incline(substeps, mu=0.3, degrees=35.0):
    """A 0.2 m box sliding down a 35 degree incline, friction 0.3 (sqrt(0.3) on each, Bullet's product 0.3);
    its travel over 1 s against 1/2 g (sin - mu cos) t^2."""
    theta = math.radians(degrees)

    def build():
        bpy.ops.mesh.primitive_cube_add(size=1.0)
        slope = bpy.context.active_object
        slope.scale = (20.0, 4.0, 1.0)
        slope.rotation_euler = (0.0, -theta, 0.0)
        bpy.context.view_layer.update()
        # its top face through the origin
        slope.location = tuple(np.array(slope.matrix_world.to_3x3()) @ np.array([0.0, 0.0, -0.5]))
        bpy.context.view_layer.update()
        bpy.ops.rigidbody.object_add(type="PASSIVE")
        slope.rigid_body.collision_shape = "BOX"
        slope.rigid_body.friction = math.sqrt(mu)
        normal = np.array(slope.matrix_world.to_3x3()) @ np.array([0.0, 0.0, 1.0])
        at = tuple(normal * 0.1)
        box = body("cube", at, "BOX", 0.2, friction=math.sqrt(mu), linear_damping=0.0, angular_damping=0.0)
        box.rotation_euler = (0.0, -theta, 0.0)
        return [box]
    (bw, _, _), (tw, _, _, _) = both(build, 61, substeps)
    exact = 0.5 * G * (math.sin(theta) - mu * math.cos(theta)) * 1.0**2
    return [(n, float(np.linalg.norm(w[60, 0] - w[0, 0]))) for n, w in (("Blender (Bullet)", bw),
                                                                         ("tumble", tw))], exact


def stack(substeps, seconds=10):
    """Ten 0.5 m cubes stacked: the largest displacement of any over ``seconds``."""
    def build():
        _slab()
        return [body("cube", (0, 0, 0.25 + 0.5 * k), "BOX", 0.5, linear_damping=0.0, angular_damping=0.0)
                for k in range(10)]
    frames = seconds * FPS
    (bw, _, _), (tw, _, _, _) = both(build, frames, substeps)
    return [(n, float(np.linalg.norm(w - w[0], axis=2).max())) for n, w in (("Blender (Bullet)", bw),
                                                                              ("tumble", tw))]


def dominoes(substeps, n=10):
    """Ten dominoes 0.1 x 0.5 x 1 m, 0.6 m apart, the first tilted 10 degrees: when the last has turned 45
    degrees."""
    def build():
        _slab()
        out = []
        for k in range(n):
            bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.6 * k, 0, 0.5))
            d = bpy.context.active_object
            d.scale = (0.1, 0.5, 1.0)
            if k == 0:
                d.rotation_euler = (0.0, math.radians(10), 0.0)
                d.location = (0.5 * math.sin(math.radians(10)), 0, 0.5 * math.cos(math.radians(10)) + 0.05 *
                              math.sin(math.radians(10)))
            bpy.ops.rigidbody.object_add(type="ACTIVE")
            d.rigid_body.collision_shape = "BOX"
            out.append(d)
        return out
    frames = 4 * FPS
    (_, bt, _), (_, tt, _, _) = both(build, frames, substeps)
    out = []
    for name, turns in (("Blender (Bullet)", bt), ("tumble", tt)):
        up = turns[:, -1, :, 2]  # the last domino's z axis
        fallen = np.nonzero(up[:, 2] < math.cos(math.radians(45)))[0]
        out.append((name, fallen[0] / FPS if len(fallen) else float("nan")))
    return out


def pile(substeps, n, frames=120):
    """``n`` cubes of 0.5 m in 10 x 10 layers 0.6 m apart, dropped: seconds a frame."""
    def build():
        _slab()
        return [body("cube", (0.6 * ((k % 100) // 10), 0.6 * (k % 10), 1.0 + 0.6 * (k // 100)), "BOX", 0.5)
                for k in range(n)]
    (_, _, b_seconds), (_, _, t_seconds, report) = both(build, frames, substeps)
    return b_seconds, t_seconds, report


def main() -> None:
    substeps = int(sys.argv[sys.argv.index("--substeps") + 1]) if "--substeps" in sys.argv else 10
    quick = "--quick" in sys.argv
    print(f"| scene (Blender scene at {FPS} fps, {substeps} substeps a frame) | Blender (Bullet) | tumble bake | "
          "closed form |\n|---|---|---|---|")
    rows, exact = bounce(substeps)
    print(f"| ball, e = 0.8, from 1 m: first impact (s, to a frame) | {rows[0][1]:.4f} | {rows[1][1]:.4f} | "
          f"{exact[0]:.4f} |")
    print(f"| ball: rebound apex (m) | {rows[0][2]:.4f} | {rows[1][2]:.4f} | {exact[1]:.4f} |")
    rows, exact = incline(substeps)
    print(f"| box on a 35 degree incline, mu 0.3: travel in 1 s (m) | {rows[0][1]:.4f} "
          f"({(rows[0][1] / exact - 1) * 100:+.2f}%) | {rows[1][1]:.4f} ({(rows[1][1] / exact - 1) * 100:+.2f}%) | "
          f"{exact:.4f} |")
    rows = stack(substeps, 2 if quick else 10)
    print(f"| stack of 10: largest displacement in {2 if quick else 10} s (mm) | {rows[0][1] * 1e3:.3f} | "
          f"{rows[1][1] * 1e3:.3f} | 0 |")
    rows = dominoes(substeps)
    print(f"| 10 dominoes: the last at 45 degrees (s) | {rows[0][1]:.3f} | {rows[1][1]:.3f} | - |")
    for n in ((100,) if quick else (100, 1000)):
        b, t, _ = pile(substeps, n)
        print(f"| pile of {n} cubes: ms a frame (tumble: reading, simulating, writing) | {b * 1e3:.2f} | "
              f"{t * 1e3:.2f} | - |")


if __name__ == "__main__":
    main()
