"""Fracturing a Blender object with tumble: its mesh cut into pieces (``tumble.Mesh.fracture``), each a new rigid
body object where it was modelled, and each face two pieces share glued by a Fixed rigid body constraint that
breaks at the face's bound (``tumble.bonds``: its area times the strength), as Blender's Cell Fracture add-on and a
constraint network would make them. The bake maps those constraints back to tumble's glue (docs/blender.md)."""

from __future__ import annotations

from typing import Any

import numpy as np


def fracture(obj: Any, pieces: int = 20, seed: int = 0, strength: float = 1e6, scene: Any = None) -> list[Any]:
    """Cuts mesh object ``obj`` into ``pieces`` pieces drawn from ``seed`` and glues them at ``strength`` Pa: the
    pieces become new mesh objects (rigid bodies of ``obj``'s settings and density, each ``obj.name`` + ".001", ...,
    in ``obj``'s collections), each shared face a Fixed constraint between its two pieces at the face's centre,
    breaking at its force bound (Blender's threshold: that impulse over a substep); ``obj`` is hidden and taken out
    of the rigid body world. Returns the new objects. ValueError naming a bad argument (``obj`` not a closed mesh,
    ``pieces``, ``strength``)."""
    import bpy  # noqa: PLC0415
    from mathutils import Matrix, Vector  # noqa: PLC0415

    import tumble  # noqa: PLC0415

    scene = scene or bpy.context.scene
    if obj is None or obj.type != "MESH":
        raise ValueError(f"invalid argument `obj`: expected a mesh object, got {obj!r}")
    if not (isinstance(strength, (int, float)) and strength > 0):
        raise ValueError(f"invalid argument `strength`: expected a number of pascals > 0, got {strength!r}")
    rbw = scene.rigidbody_world
    if rbw is None:
        raise ValueError("invalid argument `scene`: it has no rigid body world (Scene properties, Rigid Body World)")
    unit = float(scene.unit_settings.scale_length) or 1.0
    location, rotation, scale = obj.matrix_world.decompose()
    data = obj.data
    data.calc_loop_triangles()
    # the mesh in metres, scaled as the object is, in a frame at its origin turned as it is
    vertices = np.array([tuple(v.co) for v in data.vertices], dtype=float) * np.array(tuple(scale)) * unit
    triangles = np.array([tuple(t.vertices) for t in data.loop_triangles], dtype=np.int64)
    mesh = tumble.Mesh(vertices, triangles, name=obj.name)
    parts = mesh.fracture(pieces=pieces, seed=seed)
    rb = obj.rigid_body
    density = float(rb.mass) / mesh.volume if rb is not None else 1000.0
    substep = rbw.time_scale / (scene.render.fps / scene.render.fps_base) / rbw.substeps_per_frame
    frame = Matrix.LocRotScale(location, rotation, Vector((1.0, 1.0, 1.0)))
    layer = bpy.context.view_layer
    made = []
    for part in parts:
        mesh_data = bpy.data.meshes.new(part.name)
        mesh_data.from_pydata((np.asarray(part.vertices) / unit).tolist(), [], np.asarray(part.triangles).tolist())
        mesh_data.update()
        piece = bpy.data.objects.new(part.name, mesh_data)
        for collection in obj.users_collection:
            collection.objects.link(piece)
        piece.matrix_world = frame
        _make_rigid(piece, layer, "CONVEX_HULL" if part.is_convex else "MESH", density * part.volume, rb)
        made.append(piece)
    for a, b, _, centre, _, force, _ in tumble.bonds(parts, float(strength)):
        bpy.ops.object.empty_add(location=tuple(frame @ Vector(np.asarray(centre) / unit)))
        glue = bpy.context.active_object
        glue.name = f"{obj.name}.glue"
        bpy.ops.rigidbody.constraint_add(type="FIXED")
        c = glue.rigid_body_constraint
        c.object1, c.object2 = made[a], made[b]
        c.use_breaking, c.breaking_threshold = True, force * substep
        c.disable_collisions = True
    if rb is not None:
        rbw.collection.objects.unlink(obj)
    obj.hide_set(True)
    obj.hide_render = True
    return made


def _make_rigid(piece: Any, layer: Any, shape: str, mass: float, like: Any) -> None:
    """``piece`` made an active rigid body of ``mass`` kg and collision ``shape``, with ``like``'s surface and
    damping where given."""
    import bpy  # noqa: PLC0415

    for other in layer.objects:
        other.select_set(False)
    layer.objects.active = piece
    piece.select_set(True)
    bpy.ops.rigidbody.object_add(type="ACTIVE")
    rb = piece.rigid_body
    rb.collision_shape, rb.mass = shape, mass
    if like is not None:
        for setting in ("friction", "restitution", "linear_damping", "angular_damping", "collision_margin",
                        "use_margin"):
            setattr(rb, setting, getattr(like, setting))
