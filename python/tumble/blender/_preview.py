"""An answer of a search shown in the viewport: the frame handler that poses the objects, and what it changed, put
back when the preview stops (by hand, by a bake, or by reading the scene again)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable


@dataclass
class Preview:
    """A preview shown on a scene: the answer's index, the frame handler that poses the objects, each moving
    object's own transform before it and whether the rigid body world was on."""

    answer: int
    handler: Callable[..., None]
    transforms: dict[str, Any]
    enabled: bool


# The preview shown on each scene, by the scene's name.
previews: dict[str, Preview] = {}


def stop_preview(scene: Any) -> None:
    """Ends ``scene``'s preview, if one is shown: the frame handler removed, each object's own transform and the
    rigid body world's switch as they were."""
    import bpy  # noqa: PLC0415

    shown = previews.pop(scene.name, None)
    if shown is None:
        return
    if shown.handler in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.remove(shown.handler)
    for name, transform in shown.transforms.items():
        obj = scene.objects.get(name)
        if obj is not None:
            obj.matrix_basis = transform
    if scene.rigidbody_world is not None:
        scene.rigidbody_world.enabled = shown.enabled
    scene.frame_set(scene.frame_current)
