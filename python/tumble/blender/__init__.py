"""tumble in Blender: ``bake`` runs a scene's rigid body world (as Blender defines it) in tumble and writes the
motion back as keyframes; ``world_from_scene`` gives the tumble world itself. Importable wherever tumble and ``bpy``
share an interpreter (``pip install "tumble[blender]"``, Blender as a module), and an add-on (``register``): a
"Bake with tumble" panel in the Scene properties' Rigid Body World; ``direct`` searches one object's start for an
outcome (a face up, a target's place) and bakes the answer chosen, also from the panel; ``fracture`` cuts an object
into glued pieces ("Fracture with tumble"). Packaged as a Blender extension by
``blender_manifest.toml`` beside this file."""

from ._bake import bake
from ._direct import Directed, direct
from ._fracture import fracture
from ._read import BlenderSceneError, Mapped, world_from_scene
from ._ui import register, unregister

__all__ = ["bake", "direct", "Directed", "fracture", "world_from_scene", "BlenderSceneError", "Mapped", "register", "unregister"]
