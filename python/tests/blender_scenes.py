"""Helpers of the Blender tests (imported once ``bpy`` is known to be there): scenes built through Blender's own
operators, the same worlds in Python, and the baked keyframes read back. Keyframes are float32 in Blender."""

import math

import bpy
import numpy as np

import tumble

FPS, SUBSTEPS = 60, 10
DT = 1.0 / FPS / SUBSTEPS
FLOAT32 = 2e-7  # relative: a keyframe value rounded to float32 (half an ulp is 6e-8 of it), with margin


def f32(x: float) -> float:
    """``x`` as Blender holds it (its properties, locations and vertices are float32)."""
    return float(np.float32(x))


def empty_scene(frames: int = 60):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = FPS, 1.0
    bpy.ops.rigidbody.world_add()
    scene.rigidbody_world.point_cache.frame_start = 1
    scene.rigidbody_world.point_cache.frame_end = frames
    scene.rigidbody_world.substeps_per_frame = SUBSTEPS
    return scene


def blender_body(kind, name, location, shape, size=1.0, **settings):
    """A mesh made by Blender's primitive operator, made a rigid body by Blender's operator."""
    add = {"cube": bpy.ops.mesh.primitive_cube_add, "plane": bpy.ops.mesh.primitive_plane_add,
           "sphere": bpy.ops.mesh.primitive_uv_sphere_add}[kind]
    add(**({"radius": size} if kind == "sphere" else {"size": size}), location=location)
    obj = bpy.context.active_object
    obj.name = name
    bpy.ops.rigidbody.object_add(type="PASSIVE" if kind == "plane" else "ACTIVE")
    obj.rigid_body.collision_shape = shape
    for key, value in settings.items():
        setattr(obj.rigid_body, key, value)
    return obj


def ground(restitution=0.0, friction=0.5):
    return blender_body("plane", "ground", (0, 0, 0), "BOX", size=20.0, restitution=restitution, friction=friction)


def python_world():
    # Blender's gravity, in float32, and Bullet's products of a pair's frictions and restitutions
    return tumble.World(mode="fast", dt=DT, gravity=(0.0, 0.0, f32(-9.81)), friction_combine="product",
                        restitution_combine="product")


def python_ground(w, restitution=0.0, friction=0.5):
    # Blender's 20 m plane as a box collider: a 1 m slab under the face
    return w.add_body(tumble.Box(half_extents=(10.0, 10.0, 0.5)), static=True, position=(0.0, 0.0, -0.5),
                      restitution=restitution, friction=friction)


def damping(mass, inertia_moment, linear=0.04, angular=0.1):
    """Blender's default damping, as exponential decays (Bullet: v *= (1 - d) each second)."""
    return {"linear_damping": -mass * math.log(1 - linear), "angular_damping": -inertia_moment * math.log(1 - angular)}


def keyed(obj, frames):
    """The object's baked world positions at ``frames``."""
    scene = bpy.context.scene
    out = []
    for f in frames:
        scene.frame_set(int(f))
        out.append(tuple(obj.matrix_world.translation))
    return np.array(out)


def assert_keyed_like(obj, run, column, frames):
    got = keyed(obj, frames)
    want = run.body_positions[np.asarray(frames) - 1, column]
    np.testing.assert_allclose(got, want, rtol=0, atol=FLOAT32 * max(1.0, np.abs(want).max()))
