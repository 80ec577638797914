"""A Blender scene's rigid body world read into a tumble world: bodies (active, passive), their shapes from the
evaluated mesh and the object's scale, mass, friction, bounciness and damping, the constraints tumble has, gravity,
unit scale, frame rate and frame range. What tumble cannot take as Blender defines it is collected, each item
naming the object and the setting, and raised together (``BlenderSceneError``): never a silent guess.

How Blender's settings map (Blender's rigid bodies are Bullet's):
- Friction and bounciness: Bullet combines a pair's as their product; the world is made with tumble's product rule
  for both (``friction_combine="product"``, ``restitution_combine="product"``), so each body keeps Blender's numbers
  and every pair gets Bullet's coefficients. Blender has no rolling resistance: none is given.
- Damping: Bullet scales velocities by (1 - d) each second, an exponential decay at -ln(1 - d) per second; tumble's
  damping forces give exactly that decay with c = -m ln(1 - d) (linear) and, for a body whose principal moments are
  equal, c = -I ln(1 - d) (angular). A body of unequal moments with angular damping gets the mean moment: said in
  the notes.
- Shapes: box, sphere, capsule, cylinder (along the object's z, sized by its dimensions, centred at its origin, as
  Blender builds them), convex hull and mesh (the evaluated mesh's vertices, scaled); a cone as the convex hull of a
  64-sided cone (said in the notes). Bullet's collision margin is not copied: tumble's shapes are exact.
- Collision collections: tumble's collision groups, a bit each (two bodies touch if they share one, as in Blender).
- Time: a frame is time_scale / fps seconds; the frame range is the rigid body cache's."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from tumble._geometry import rotation_matrix

from ._constraints import _to_body, constraints
from ._preview import stop_preview

Array = npt.NDArray[np.float64]

CONE_SIDES = 64


class BlenderSceneError(ValueError):
    """The scene's rigid body world has settings tumble cannot take as Blender defines them; ``problems`` lists each
    as "object: setting: why"."""

    def __init__(self, problems: list[str]) -> None:
        self.problems = problems
        super().__init__("tumble cannot bake this rigid body world as Blender defines it:\n- " + "\n- ".join(problems))


@dataclass
class Mapped:
    """What ``world_from_scene`` gives: the world, each rigid body object's handle (by object name), the moving
    objects in bake order, each body's offset from its centre of mass to the object's origin (body frame), the frame
    range and the time of a frame, and the notes on approximations made."""

    world: Any
    handles: dict[str, Any]
    moving: list[str]
    origins: dict[str, Array]
    frame_start: int
    frame_end: int
    frame_time: float
    notes: list[str] = field(default_factory=list)
    #: objects whose "Animated" is switched during the range: each frame it changes at, with whether it is on from
    #: there (the bake lets a body go where it goes off, ``World.release``, and takes it over where it goes on,
    #: ``World.hold``, to follow its animation)
    switches: dict[str, list[tuple[int, bool]]] = field(default_factory=dict)
    #: for those objects: the density that gives the object's mass, and its animation's poses (times from the
    #: range's start, its origin's places, turns (w, x, y, z)) at every frame
    densities: dict[str, float] = field(default_factory=dict)
    paths: dict[str, tuple[Array, Array, Array]] = field(default_factory=dict)


def _decay(d: float) -> float:
    """Bullet's damping d (velocity kept each second: 1 - d) as an exponential decay rate (1/s)."""
    return -math.log(1.0 - d)


def _shape(obj: Any, depsgraph: Any, problems: list[str], notes: list[str]) -> Any:
    """The tumble shape of ``obj``'s collision shape, in the object's frame (scaled, unrotated), or (shape, offset)
    where it does not sit at the origin."""
    import tumble  # noqa: PLC0415

    rb = obj.rigid_body
    scale = np.array(obj.matrix_world.to_scale(), dtype=float)
    # Blender sizes primitive shapes by the object's bounding box (with its scale), centred at its origin
    corners = np.array([tuple(c) for c in obj.bound_box], dtype=float) * scale if obj.bound_box else np.zeros((8, 3))
    size = corners.max(axis=0) - corners.min(axis=0)
    kind = rb.collision_shape
    if kind == "BOX":
        flat = size < 1e-9
        if flat.sum() == 1 and rb.type == "PASSIVE":  # a plane as the ground: solid below its face, 1 m deep
            notes.append(f"{obj.name}: collision shape: the flat box is a 1 m deep slab under its face")
            axis = int(np.argmax(flat))
            half = np.where(flat, 0.5, size / 2)
            offset = np.zeros(3)
            offset[axis] = -0.5
            return tumble.Box(half_extents=tuple(half)), tuple(offset)
        return tumble.Box(half_extents=tuple(size / 2))
    if kind == "SPHERE":
        return tumble.Sphere(radius=float(size.max() / 2))
    radius, height = float(max(size[0], size[1]) / 2), float(size[2])
    if kind == "CAPSULE":
        return tumble.Capsule(half_height=max(height / 2 - radius, 1e-9), radius=radius)
    if kind == "CYLINDER":
        return tumble.Cylinder(half_height=height / 2, radius=radius)
    if kind == "CONE":
        notes.append(f"{obj.name}: collision shape: the cone is a {CONE_SIDES}-sided pyramid's hull")
        angles = np.linspace(0.0, 2 * np.pi, CONE_SIDES, endpoint=False)
        base = np.c_[radius * np.cos(angles), radius * np.sin(angles), np.full(CONE_SIDES, -height / 2)]
        return tumble.ConvexHull(np.vstack([base, [0.0, 0.0, height / 2]]))
    if kind in ("CONVEX_HULL", "MESH"):
        evaluated = obj.evaluated_get(depsgraph) if rb.mesh_source != "BASE" else obj
        mesh = evaluated.to_mesh()
        try:
            vertices = np.array([tuple(v.co) for v in mesh.vertices], dtype=float) * scale
            mesh.calc_loop_triangles()
            triangles = np.array([tuple(t.vertices) for t in mesh.loop_triangles], dtype=np.int64)
        finally:
            evaluated.to_mesh_clear()
        if kind == "CONVEX_HULL":
            return tumble.ConvexHull(vertices)
        return tumble.Mesh(vertices, triangles, name=obj.name)
    problems.append(f"{obj.name}: collision shape: {kind} is not one tumble takes (box, sphere, capsule, cylinder, "
                    "cone, convex hull, mesh)")
    return None


def _damping(obj: Any, shape: Any, mass: float, notes: list[str]) -> dict[str, float]:
    """tumble's damping coefficients for Bullet's linear and angular damping of ``obj`` (module docstring)."""
    rb = obj.rigid_body
    unit = shape.mass_properties(1.0)
    moments = np.linalg.eigvalsh(np.asarray(unit["inertia"], dtype=float) * (mass / unit["mass"]))
    if rb.angular_damping > 0 and moments.max() - moments.min() > 1e-9 * moments.max():
        notes.append(f"{obj.name}: angular damping: its principal moments differ, so tumble's damping torque "
                     "decays each axis's spin at its own rate about Bullet's (the mean moment taken)")
    return {"linear_damping": mass * _decay(rb.linear_damping),
            "angular_damping": float(moments.mean()) * _decay(rb.angular_damping)}


def _paths(scene: Any, rbw: Any, objects: list[Any], unit: float, frame_time: float) -> dict[str, Any]:
    """The pose at every frame of the cache's range of each object that is animated at some frame of it ("Animated"
    on at the start, or keyed on later), as (times, locations, orientations (w, x, y, z), switches: each frame
    where "Animated" changes, with whether it is on from there); read with the rigid body world off, so Bullet does
    not step while the frames are set."""
    import bpy  # noqa: PLC0415

    def keyed(o: Any) -> bool:
        action = o.animation_data.action if o.animation_data else None
        if action is None:
            return False
        return any(c.data_path == "rigid_body.kinematic" for layer in action.layers for strip in layer.strips
                   for bag in strip.channelbags for c in bag.fcurves)

    animated = [o for o in objects if o.rigid_body.kinematic or keyed(o)]
    if not animated:
        return {}
    cache = rbw.point_cache
    frames = range(cache.frame_start, cache.frame_end + 1)
    layer = bpy.context.view_layer if scene == bpy.context.scene else scene.view_layers[0]
    poses: dict[str, tuple[list[Any], list[Any]]] = {o.name: ([], []) for o in animated}
    switches: dict[str, list[tuple[int, bool]]] = {o.name: [] for o in animated}
    was = {o.name: bool(o.rigid_body.kinematic) for o in animated}
    enabled = rbw.enabled
    rbw.enabled = False
    try:
        for f in frames:
            scene.frame_set(f)
            layer.update()
            for o in animated:
                if bool(o.rigid_body.kinematic) != was[o.name]:
                    was[o.name] = bool(o.rigid_body.kinematic)
                    switches[o.name].append((f, was[o.name]))
                location, rotation, _ = o.matrix_world.decompose()
                poses[o.name][0].append([float(x) * unit for x in location])
                poses[o.name][1].append([float(x) for x in rotation])
    finally:
        rbw.enabled = enabled
        scene.frame_set(cache.frame_start)
        layer.update()
    times = np.array([(f - cache.frame_start) * frame_time for f in frames])
    return {name: (times, np.array(x), np.array(q), switches[name]) for name, (x, q) in poses.items()}


def world_from_scene(scene: Any = None, **world_options: Any) -> Mapped:
    """The tumble world of ``scene``'s rigid body world (the current scene by default). ``world_options`` go to
    ``tumble.World`` (default: fast mode at Blender's own step, ``time_scale / fps / substeps_per_frame``). Raises
    ``BlenderSceneError`` listing everything that cannot be mapped."""
    import bpy  # noqa: PLC0415

    import tumble  # noqa: PLC0415

    scene = scene or bpy.context.scene
    stop_preview(scene)  # the scene as the user set it up, not as a search's answer poses it
    rbw = scene.rigidbody_world
    if rbw is None or rbw.collection is None:
        raise BlenderSceneError([f"{scene.name}: rigid body world: the scene has none (or no collection in it)"])
    # the scene as it starts: at the cache's first frame Blender's simulation (or an earlier bake's keyframes) puts
    # the bodies where they were set up, wherever the timeline stood; transforms set since the last redraw are in
    # the objects' matrices only after an update
    scene.frame_set(rbw.point_cache.frame_start)
    (bpy.context.view_layer if scene == bpy.context.scene else scene.view_layers[0]).update()
    problems: list[str] = []
    notes: list[str] = []
    unit = float(scene.unit_settings.scale_length) or 1.0
    fps = scene.render.fps / scene.render.fps_base
    frame_time = rbw.time_scale / fps
    weights = rbw.effector_weights
    gravity = np.array(scene.gravity, dtype=float) * unit * weights.gravity * weights.all if scene.use_gravity \
        else np.zeros(3)
    options = {"mode": "fast", "dt": frame_time / rbw.substeps_per_frame, "friction_combine": "product",
               "restitution_combine": "product", **world_options}
    objects = sorted((o for o in rbw.collection.objects if o.rigid_body is not None), key=lambda o: o.name)
    sleeping = {o.rigid_body.use_deactivation for o in objects if o.rigid_body.type == "ACTIVE"}
    if len(sleeping) > 1:
        problems.append(f"{scene.name}: deactivation: some bodies may sleep and others not (tumble sleeps a whole "
                        "world or none)")
    if sleeping == {True} and options.get("mode") == "fast" and "sleep" not in world_options:
        options["sleep"] = True
    world = tumble.World(gravity=tuple(gravity), **options)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    handles, moving, origins = {}, [], {}
    switches: dict[str, list[tuple[int, bool]]] = {}
    densities: dict[str, float] = {}
    held: dict[str, tuple[Array, Array, Array]] = {}
    paths = _paths(scene, rbw, objects, unit, frame_time)
    for obj in objects:
        rb = obj.rigid_body
        animated = rb.kinematic
        static = rb.type == "PASSIVE" and not animated
        for setting, bad in (("dynamic", not rb.enabled and not static and not animated),
                             ("start deactivated", rb.use_start_deactivated and not static),
                             ("parent", obj.parent is not None)):
            if bad:
                problems.append(f"{obj.name}: {setting}: not taken yet (tumble bakes active, passive and animated bodies)")
        try:
            shape = _shape(obj, depsgraph, problems, notes)
        except ValueError as error:
            problems.append(f"{obj.name}: collision shape: {error}")
            continue
        if shape is None:
            continue
        shape, offset = shape if isinstance(shape, tuple) else (shape, (0.0, 0.0, 0.0))
        location, rotation, _ = obj.matrix_world.decompose()
        position = tuple(float(x) * unit for x in location)
        orientation = tuple(float(x) for x in rotation)  # (w, x, y, z)
        groups = sum(1 << k for k, on in enumerate(rb.collision_collections) if on)
        material: dict[str, Any] = {"friction": float(rb.friction), "restitution": float(rb.restitution),
                                    "collision_groups": groups}
        if not static and not animated:
            material.update(_damping(obj, shape, float(rb.mass), notes))
        try:
            # Blender places its shapes by the object's origin; tumble a mesh by its own origin, any other shape by
            # its centre of mass (the shape's, plus its offset), so that is put where the origin places it
            if isinstance(shape, tumble.Mesh):
                centre = np.zeros(3)
            else:
                centre = np.asarray(shape.mass_properties(1.0)["center_of_mass"], dtype=float) + np.array(offset)
            at = np.array(position) + rotation_matrix(np.array(orientation)) @ centre
            kwargs: dict[str, Any] = dict(position=tuple(at), orientation=orientation, **material)
            if obj.name in paths:
                # its animation sampled at every frame; its shapes' frame is where the origin places them
                times, locations, rotations, changes = paths[obj.name]
                shapes_at = locations + np.einsum("kij,j->ki", np.array([rotation_matrix(q) for q in rotations]),
                                                  centre)
                if changes:
                    # let go where "Animated" goes off (at the density that gives the object's mass), taken over
                    # where it goes on again
                    switches[obj.name] = changes
                    densities[obj.name] = float(rb.mass) / float(shape.mass_properties(1.0)["mass"])
                    held[obj.name] = (times, locations, rotations)
            if animated:
                # an animated object follows its own animation
                handle = world.add_body(shape, keyframes=(times, shapes_at, rotations), **material)
                handles[obj.name] = handle
                if obj.name in switches:
                    moving.append(obj.name)
                    origins[obj.name] = -np.asarray(centre, dtype=float)  # in the frame the keyframes pose
                continue
            if static:
                handle = world.add_body(shape, static=True, **kwargs)
            else:
                handle = world.add_body(shape, mass=float(rb.mass), **kwargs)
            row = world.bodies.row(handle)
            if np.abs(np.asarray(world.bodies.positions[row]) - at).max() > 1e-9 * (1 + np.abs(at).max()):
                raise ValueError("the body could not be placed at the object's origin")
        except ValueError as error:
            problems.append(f"{obj.name}: {error}")
            continue
        handles[obj.name] = handle
        if not static:
            moving.append(obj.name)
            row = world.bodies.row(handle)
            com = world.bodies.positions[row]
            # the object's origin from the centre of mass, in the body frame
            origins[obj.name] = _to_body(orientation, np.array(position) - np.asarray(com))
    constraints(world, scene, rbw, handles, problems, notes)
    if problems:
        raise BlenderSceneError(problems)
    cache = rbw.point_cache
    return Mapped(world, handles, moving, origins, cache.frame_start, cache.frame_end, frame_time, notes, switches,
                  densities, held)
