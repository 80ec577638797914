"""Directing a Blender scene's outcome: the scene's rigid body world read as ``bake`` reads it, the search of
``tumble.direct`` over one object's start (a face up, or the pose of a target object at the end), any of the
answers previewed in the viewport (the objects posed at each frame shown, nothing written) and any baked as
keyframes, as ``bake`` writes them."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from tumble._geometry import rotation_matrix

from ._bake import object_poses, write_keyframes
from ._preview import Preview, previews, stop_preview
from ._read import Mapped, world_from_scene

# Faces by name: the object's local axis that ends pointing up.
FACES = {"+X": (1, 0, 0), "-X": (-1, 0, 0), "+Y": (0, 1, 0), "-Y": (0, -1, 0), "+Z": (0, 0, 1), "-Z": (0, 0, -1)}

# The answers of the last search on each scene, by the scene's name (for the add-on's "bake answer" operator).
last: dict[str, Directed] = {}




@dataclass
class Directed:
    """A search's answer on a scene: ``found`` (``tumble.direct.Found``: ``met``, ``alternatives`` and their costs,
    ``report``), the world it searched (``mapped``) and the frame range; ``preview(k)`` shows answer ``k`` in the
    viewport, ``bake(k)`` writes it."""

    found: Any
    mapped: Mapped
    scene: Any
    frame_start: int

    def bake(self, k: int = 0) -> Any:
        """Writes the ``k``-th answer's run (0: the best) as keyframes on every moving object and switches the rigid
        body world off, as ``bake`` does; returns the answer."""
        self._check(k)
        self.stop_preview()
        answer = self.found.alternatives[k]
        write_keyframes(self.scene, self.mapped, answer.run, self.frame_start)
        self.scene.rigidbody_world.enabled = False
        return answer

    def preview(self, k: int = 0) -> Any:
        """Shows the ``k``-th answer (0: the best) in the viewport: at every frame the timeline shows, each moving
        object is posed as that answer's run has it (before the range as at its start, after as at its end), with
        the rigid body world off; nothing is keyed or saved. ``stop_preview`` (or a bake) puts every object back as
        it was. Returns the answer."""
        import bpy  # noqa: PLC0415
        from mathutils import Matrix, Quaternion, Vector  # noqa: PLC0415

        self._check(k)
        self.stop_preview()
        answer = self.found.alternatives[k]
        poses = {name: object_poses(self.scene, self.mapped, answer.run, name) for name in self.mapped.moving}
        objects = {name: self.scene.objects[name] for name in poses}
        scene_name = self.scene.name

        def pose(scene: Any, *_: Any) -> None:
            if scene.name != scene_name:
                return
            i = min(max(scene.frame_current - self.frame_start, 0), len(answer.run.times) - 1)
            for name, (location, wxyz) in poses.items():
                obj = objects[name]
                obj.matrix_world = Matrix.LocRotScale(Vector(tuple(location[i])), Quaternion(tuple(wxyz[i])),
                                                      obj.matrix_world.to_scale())

        rbw = self.scene.rigidbody_world
        previews[scene_name] = Preview(k, pose, {name: o.matrix_basis.copy() for name, o in objects.items()},
                                        bool(rbw.enabled))
        rbw.enabled = False
        bpy.app.handlers.frame_change_post.append(pose)
        pose(self.scene)
        return answer

    def stop_preview(self) -> None:
        """Ends this scene's preview, if one is shown: every object and the rigid body world's switch as they were."""
        stop_preview(self.scene)

    def _check(self, k: Any) -> None:
        if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < len(self.found.alternatives):
            raise ValueError(f"invalid argument `k`: expected 0 to {len(self.found.alternatives) - 1}, got {k!r}")


def direct(obj: Any, face: str | None = None, target: Any = None, within: float = 0.01, vary: Any = None,
           tries: int = 256, seed: int = 0, keep: int = 8, scene: Any = None, angle: float | None = None,
           progress: bool | Callable[[float], None] | None = None, **world_options: Any) -> Directed:
    """Searches the start of ``obj`` (a rigid body object of ``scene``, the current one by default) within ``vary``
    (a ``tumble.direct.Vary``; by default 15 degrees, 0.5 m/s and 2 rad/s) for a run over the rigid body cache's
    frame range that ends with ``face`` ("+X", "-X", "+Y", "-Y", "+Z", "-Z": the object's local axis pointing up)
    and/or at rest at ``target``'s location (an object, an empty say; within ``within`` metres), and, given an
    ``angle`` (degrees), turned as the target is, within that angle. Nothing is written
    until ``Directed.bake``. Raises ``BlenderSceneError`` as ``bake`` does, and ValueError naming a bad argument."""
    import bpy  # noqa: PLC0415

    import tumble.direct as td  # noqa: PLC0415

    scene = scene or bpy.context.scene
    if obj is None or getattr(obj, "rigid_body", None) is None:
        raise ValueError(f"invalid argument `obj`: expected a rigid body object, got {obj!r}")
    if face is None and target is None:
        raise ValueError("invalid argument `face`: give a face to end up, a target to end at, or both")
    if face is not None and face not in FACES:
        raise ValueError(f"invalid argument `face`: expected one of {sorted(FACES)}, got {face!r}")
    mapped = world_from_scene(scene, **world_options)
    if obj.name not in mapped.moving:
        raise ValueError(f"invalid argument `obj`: {obj.name} is not a moving body of the scene's rigid body world")
    if mapped.switches:
        raise ValueError(f"invalid argument `scene`: {', '.join(sorted(mapped.switches))} switch \"Animated\" during "
                         "the range; the search runs the scene in one piece (bake it, or key the switch off)")
    body = mapped.handles[obj.name]
    goals = []
    if face is not None:
        goals.append(td.face_up(body, FACES[face]))
    if target is not None:
        unit = float(scene.unit_settings.scale_length) or 1.0
        location, rotation, _ = target.matrix_world.decompose()
        # the body's centre of mass where the object's origin would be at the target's location
        turn = rotation_matrix(np.array(tuple(rotation), dtype=float))
        place = np.array(tuple(location)) * unit - turn @ mapped.origins[obj.name]
        pose = None if angle is None else tuple(float(x) for x in rotation)  # (w, x, y, z), the object's own turn
        goals.append(td.rest_at(body, place, within, angle=angle, orientation=pose))
    goal = goals[0] if len(goals) == 1 else goals[0] & goals[1]
    vary = vary or td.Vary(orientation=15.0, velocity=0.5, spin=2.0)
    duration = (mapped.frame_end - mapped.frame_start) * mapped.frame_time
    found = td.search(mapped.world, {body: vary}, goal, duration, tries=tries, seed=seed, keep=keep,
                      frame_interval=mapped.frame_time, progress=progress)
    directed = Directed(found, mapped, scene, mapped.frame_start)
    last[scene.name] = directed
    return directed
