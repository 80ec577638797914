"""The add-on's panel and operator: "Bake with tumble" under the Scene properties' Rigid Body World, with the
mode, the contact tolerance (accurate) or time step (fast, 0: Blender's own step) and the frame range; a bake that
cannot map the scene reports each object and setting, and a bake that ran reports tumble's summary. The bake's
progress shows in the terminal and in Blender's progress indicator."""


from typing import Any

_classes: list[Any] = []


def _define() -> list[Any]:
    import bpy  # noqa: PLC0415

    class TUMBLE_OT_bake(bpy.types.Operator):
        """Bake the rigid body world with tumble: keyframes on every active body, the world then switched off"""

        bl_idname = "tumble.bake"
        bl_label = "Bake with tumble"
        bl_options = {"REGISTER", "UNDO"}

        mode: bpy.props.EnumProperty(name="Mode", items=[("fast", "Fast", "fixed steps, soft contacts"),
                                                          ("accurate", "Accurate", "error-controlled")])
        contact_tolerance: bpy.props.FloatProperty(name="Contact tolerance", default=1e-4, min=1e-9, precision=6)
        time_step: bpy.props.FloatProperty(name="Time step", default=0.0, min=0.0, precision=6,
                                           description="Fast mode's step in seconds (0: Blender's own step)")
        frame_start: bpy.props.IntProperty(name="Start", default=1)
        frame_end: bpy.props.IntProperty(name="End", default=250)

        def invoke(self, context: Any, event: Any) -> Any:
            cache = context.scene.rigidbody_world.point_cache
            self.frame_start, self.frame_end = cache.frame_start, cache.frame_end
            return context.window_manager.invoke_props_dialog(self)

        def execute(self, context: Any) -> Any:
            from ._bake import bake  # noqa: PLC0415
            from ._read import BlenderSceneError  # noqa: PLC0415

            options: dict[str, Any] = {"mode": self.mode}
            if self.mode == "accurate":
                options["contact_tolerance"] = self.contact_tolerance
            elif self.time_step > 0:
                options["dt"] = self.time_step
            try:
                # the progress on the terminal (a bar, or lines in a log) and in Blender's progress indicator
                report = bake(context.scene, self.frame_start, self.frame_end, progress=True,
                              window_manager=context.window_manager, **options)
            except BlenderSceneError as error:
                for problem in error.problems:
                    self.report({"ERROR"}, problem)
                return {"CANCELLED"}
            for line in str(report).splitlines():
                self.report({"INFO"}, line)
            return {"FINISHED"}

    class TUMBLE_PT_bake(bpy.types.Panel):
        bl_label = "tumble"
        bl_space_type = "PROPERTIES"
        bl_region_type = "WINDOW"
        bl_context = "scene"
        bl_parent_id = "SCENE_PT_rigid_body_world"

        def draw(self, context: Any) -> None:
            self.layout.operator(TUMBLE_OT_bake.bl_idname)

    return [TUMBLE_OT_bake, TUMBLE_PT_bake]


def register() -> None:
    """Registers the operator and the panel (Blender calls it when the add-on is enabled)."""
    import bpy  # noqa: PLC0415

    if not _classes:
        _classes.extend(_define())
        for cls in _classes:
            bpy.utils.register_class(cls)


def unregister() -> None:
    """Unregisters them."""
    import bpy  # noqa: PLC0415

    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
    _classes.clear()
