"""The add-on's panel and operators: "Bake with tumble" under the Scene properties' Rigid Body World, with the
mode, the contact tolerance (accurate) or time step (fast, 0: Blender's own step) and the frame range; a bake that
cannot map the scene reports each object and setting, and a bake that ran reports tumble's summary. The bake's
progress shows in the terminal and in Blender's progress indicator. "Direct with tumble" searches the active
object's start for a face up and/or a target's place, shows the best answer in the viewport and lists them all,
each with a button that previews it and one that bakes it as keyframes."""


from typing import Any, Callable

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

    class TUMBLE_OT_direct(bpy.types.Operator):
        """Search the active object's start (within the bounds) for the outcome asked for, and preview the best"""

        bl_idname = "tumble.direct"
        bl_label = "Direct with tumble"
        bl_options = {"REGISTER", "UNDO"}

        face: bpy.props.EnumProperty(name="Face up", items=[("NONE", "Any", "no face asked for")] + [
            (f, f, f"the object's local {f} axis ends pointing up") for f in ("+X", "-X", "+Y", "-Y", "+Z", "-Z")])
        target: bpy.props.StringProperty(name="Target", description="An object (an empty) whose place it ends at")
        within: bpy.props.FloatProperty(name="Within", default=0.01, min=1e-6, description="metres of the target")
        angle: bpy.props.FloatProperty(name="Turned within", default=0.0, min=0.0, max=180.0,
                                       description="degrees of the target's turn (0: its place only)")
        orientation: bpy.props.FloatProperty(name="Turn", default=15.0, min=0.0, max=180.0, description="degrees")
        velocity: bpy.props.FloatProperty(name="Velocity", default=0.5, min=0.0, description="m/s")
        spin: bpy.props.FloatProperty(name="Spin", default=2.0, min=0.0, description="rad/s")
        position: bpy.props.FloatProperty(name="Position", default=0.0, min=0.0, description="m")
        tries: bpy.props.IntProperty(name="Tries", default=256, min=1)

        def execute(self, context: Any) -> Any:
            import tumble.direct as td  # noqa: PLC0415

            from ._direct import direct  # noqa: PLC0415
            from ._read import BlenderSceneError  # noqa: PLC0415

            target = context.scene.objects.get(self.target) if self.target else None
            try:
                vary = td.Vary(position=self.position, orientation=self.orientation, velocity=self.velocity,
                               spin=self.spin)
                directed = direct(context.active_object, None if self.face == "NONE" else self.face, target,
                                  self.within, vary, self.tries, scene=context.scene, progress=True,
                                  angle=self.angle or None)
            except BlenderSceneError as error:
                for problem in error.problems:
                    self.report({"ERROR"}, problem)
                return {"CANCELLED"}
            except ValueError as error:
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            directed.preview(0)
            for line in directed.found.report.splitlines():
                self.report({"INFO"}, line)
            return {"FINISHED"}

    class TUMBLE_OT_direct_bake(bpy.types.Operator):
        """Bake one of the last search's answers as keyframes (0: the best)"""

        bl_idname = "tumble.direct_bake"
        bl_label = "Bake answer"
        bl_options = {"REGISTER", "UNDO"}

        choice: bpy.props.IntProperty(name="Answer", default=0, min=0)

        def execute(self, context: Any) -> Any:
            return _with_answer(self, context, lambda directed: directed.bake(self.choice))

    class TUMBLE_OT_direct_preview(bpy.types.Operator):
        """Show one of the last search's answers in the viewport (nothing is keyed); scrub the timeline to see it"""

        bl_idname = "tumble.direct_preview"
        bl_label = "Preview answer"

        choice: bpy.props.IntProperty(name="Answer", default=0, min=0)

        def execute(self, context: Any) -> Any:
            return _with_answer(self, context, lambda directed: directed.preview(self.choice))

    class TUMBLE_OT_direct_stop_preview(bpy.types.Operator):
        """Put every object back as it was before the preview"""

        bl_idname = "tumble.direct_stop_preview"
        bl_label = "Stop preview"

        def execute(self, context: Any) -> Any:
            from ._preview import stop_preview  # noqa: PLC0415

            stop_preview(context.scene)
            return {"FINISHED"}

    class TUMBLE_OT_fracture(bpy.types.Operator):
        """Cut the active mesh object into glued pieces: rigid bodies joined by Fixed constraints that break at
        each shared face's area times the strength"""

        bl_idname = "tumble.fracture"
        bl_label = "Fracture with tumble"
        bl_options = {"REGISTER", "UNDO"}

        pieces: bpy.props.IntProperty(name="Pieces", default=20, min=1, max=4096)
        seed: bpy.props.IntProperty(name="Seed", default=0, min=0)
        strength: bpy.props.FloatProperty(name="Strength", default=1e6, min=1e-3, description="Pa: the glue's")

        def execute(self, context: Any) -> Any:
            from ._fracture import fracture  # noqa: PLC0415

            try:
                made = fracture(context.active_object, self.pieces, self.seed, self.strength, context.scene)
            except ValueError as error:
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            self.report({"INFO"}, f"{len(made)} pieces")
            return {"FINISHED"}

    class TUMBLE_PT_bake(bpy.types.Panel):
        bl_label = "tumble"
        bl_space_type = "PROPERTIES"
        bl_region_type = "WINDOW"
        bl_context = "scene"
        bl_parent_id = "SCENE_PT_rigid_body_world"

        def draw(self, context: Any) -> None:
            from ._direct import last  # noqa: PLC0415

            self.layout.operator(TUMBLE_OT_bake.bl_idname)
            self.layout.operator(TUMBLE_OT_direct.bl_idname)
            self.layout.operator(TUMBLE_OT_fracture.bl_idname)
            from ._preview import previews  # noqa: PLC0415

            directed = last.get(context.scene.name)
            shown = previews.get(context.scene.name)
            for k, a in enumerate(directed.found.alternatives if directed else []):
                row = self.layout.row()
                label = f"{k}: {'met' if a.met else f'{a.cost:.3g} m off'}, change {a.change:.2f}"
                row.label(text=label + ("  (shown)" if shown is not None and shown.answer == k else ""))
                row.operator(TUMBLE_OT_direct_preview.bl_idname, text="Preview").choice = k
                row.operator(TUMBLE_OT_direct_bake.bl_idname, text="Bake").choice = k
            if shown is not None:
                self.layout.operator(TUMBLE_OT_direct_stop_preview.bl_idname)

    return [TUMBLE_OT_bake, TUMBLE_OT_direct, TUMBLE_OT_direct_bake, TUMBLE_OT_direct_preview,
            TUMBLE_OT_direct_stop_preview, TUMBLE_OT_fracture, TUMBLE_PT_bake]


def _with_answer(operator: Any, context: Any, act: Callable[[Any], Any]) -> Any:
    """Runs ``act`` on the last search's answers on the operator's scene, or reports that there is no such answer."""
    from ._direct import last  # noqa: PLC0415

    directed = last.get(context.scene.name)
    if directed is None or operator.choice >= len(directed.found.alternatives):
        operator.report({"ERROR"}, "no such answer: search first (Direct with tumble)")
        return {"CANCELLED"}
    act(directed)
    return {"FINISHED"}


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
