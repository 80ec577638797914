"""``tumble.World``: the Rust world with numpy views of its state, reports as dataclasses and runs as ``Run``."""

from __future__ import annotations

import copy
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from ._errors import as_path, named_arguments, renamed
from ._progress import Progress, progress as _progress
from ._report import Report
from ._run import Run, looks_of
from ._joints import Joint
from ._tumble import BodyHandle, JointHandle, ParticleHandle, SimulationError, World as _World

if TYPE_CHECKING:
    from .viewer._viewer import Viewer

class ParticlesView:
    """The particles' state as (P, 3) arrays, in the order of ``handles``. The arrays are read-only copies
    (writing to one raises ValueError): change state with ``World.set_particle_state`` or ``World.set_state``."""

    def __init__(self, world: "World") -> None:
        self._world = world

    @property
    def positions(self) -> np.ndarray:
        """(P, 3) positions."""
        return self._world._particle_positions()

    @property
    def velocities(self) -> np.ndarray:
        """(P, 3) velocities."""
        return self._world._particle_velocities()

    @property
    def handles(self) -> list[ParticleHandle]:
        """The particles' handles, in row order."""
        return self._world.particle_handles()

    def row(self, handle: ParticleHandle) -> int:
        """The row of a particle in these arrays (it changes when a particle before it is removed). Raises
        ValueError for a removed particle or a handle of another world."""
        return self._world._particle_row(handle)

    def __len__(self) -> int:
        return len(self._world.particle_handles())


class BodiesView:
    """The bodies' state as arrays, in the order of ``handles`` (static bodies included). The arrays are read-only
    copies (writing to one raises ValueError): change state with ``World.set_body_state`` or ``World.set_state``."""

    def __init__(self, world: "World") -> None:
        self._world = world

    @property
    def positions(self) -> np.ndarray:
        """(B, 3) centre-of-mass positions."""
        return self._world._body_positions()

    @property
    def origins(self) -> np.ndarray:
        """(B, 3) positions of the modelled frames' origins: where a mesh's (or a hull's, or the first collider's)
        coordinates have their origin. A body of a mesh or of several colliders is placed by it."""
        return self._world._body_origins()

    @property
    def names(self) -> list[str | None]:
        """Each body's name as given to ``add_body(name=...)`` (None where none was given)."""
        return self._world._body_names()

    @property
    def collision_groups(self) -> list[int]:
        """Each body's collision groups (32 bits; two bodies touch only if theirs share a bit)."""
        return self._world._body_collision_groups()

    @property
    def kinematic(self) -> list[bool]:
        """Whether each body is kinematic (``add_body(keyframes=...)``): it follows its keyframes."""
        return self._world._body_kinematic()

    @property
    def colors(self) -> list[tuple[float, float, float, float] | None]:
        """Each body's linear RGBA colour as given to ``add_body(color=...)`` (None where none was given)."""
        from ._run import rgba  # noqa: PLC0415

        return [None if c is None else rgba(c) for c in self._world._body_colors()]

    @property
    def masses(self) -> np.ndarray:
        """(B,) masses in kg (infinite for static and kinematic bodies)."""
        return self._world._body_masses()

    @property
    def inertias(self) -> np.ndarray:
        """(B, 3, 3) inertia tensors about the centres of mass, in world axes (kg m^2)."""
        return self._world._body_inertias()

    @property
    def orientations(self) -> np.ndarray:
        """(B, 4) orientations as quaternions (w, x, y, z)."""
        return self._world._body_orientations()

    @property
    def velocities(self) -> np.ndarray:
        """(B, 3) velocities."""
        return self._world._body_velocities()

    @property
    def angular_velocities(self) -> np.ndarray:
        """(B, 3) angular velocities (world axes)."""
        return self._world._body_angular_velocities()

    @property
    def handles(self) -> list[BodyHandle]:
        """The bodies' handles, in row order."""
        return self._world.body_handles()

    def row(self, handle: BodyHandle) -> int:
        """The row of a body in these arrays (it changes when a body before it is removed). Raises ValueError for
        a removed body or a handle of another world."""
        return self._world._body_row(handle)

    def __len__(self) -> int:
        return len(self._world.body_handles())


class World(_World):
    """A world of particles and rigid bodies.

    ``World(gravity=(0, 0, -9.81), integrator=None, rtol=None, atol=None, dt=None, step_doubling=False,
    tolerance=None, mode="accurate", linear_solver=None, newton=False, max_steps=None, sleep=None, threads=None,
    contact_tolerance=None, solver=None, substeps=None)``

    ``integrator`` is one of "euler", "euler-variable", "midpoint", "rk4", "ab4", "am4", "implicit-euler", "dopri5",
    "dop853", "symplectic-euler", "verlet", "rodas4", "radau5" (``tumble.IntegratorName``). Methods with an error
    estimate (dopri5, dop853, rodas4, radau5, am4) control it to ``rtol``/``atol`` (default 1e-6/1e-9) unless only
    ``dt`` is given; the others take fixed steps of ``dt`` (default 1/240 s); ``integrator`` defaults to "dopri5".
    ``step_doubling=True`` wraps a one-step method in the chapter's step doubling with per-step error ``tolerance``.
    ``linear_solver="iterative"`` solves implicit Euler's sparse systems by BiCGSTAB (for large cloths); ``newton=True``
    iterates implicit Euler to convergence.

    Contact: ``mode="accurate"`` (the default): the integrator carries free flight under its error control; frictionless
    collisions are located by bisection on its dense output and resolved by impulses (restitution); while bodies touch
    (and at any impact with friction), convex contact steps with Coulomb friction carry them, their size set by step
    doubling so that each step's error stays within ``contact_tolerance`` metres (default 1e-4 of the scene's size); the
    report gives their count and largest error estimate. Their programs are solved by ``solver="newton"`` (the default:
    tumble's own Newton method, warm started from the last step) or ``solver="clarabel"`` (the interior point, the
    reference); frames come from the steps' interpolation, so recording never changes the result; resting islands
    sleep (``sleep=False`` keeps them awake) and wake when something awake reaches them. ``mode="fast"`` steps at ``dt`` (default 1/240 s) with
    contacts, Coulomb friction and restitution solved by ``solver="soft"`` (the default: Catto's soft step, in
    ``substeps`` substeps a step, default 8, iterative and warm-started, as fast as the game engines with a small
    penetration under load) or ``solver="exact"`` (one conic program per island each step with clarabel: no penetration,
    many times slower, as docs/benchmarks.md measures); ``step_doubling=True`` in fast mode also takes every step as two
    halves and reports their largest difference as ``report.step_error`` (metres; the run itself is unchanged, the cost
    tripled), and resting islands sleep (``sleep=False`` keeps them awake); it always steps by ``dt``: ``step`` and
    ``run`` durations must be whole numbers of steps, and a frame is the state of the first step that reaches its
    time. An option that does not
    apply to the mode (an integrator option or ``contact_tolerance`` in fast mode, ``substeps`` in accurate mode or with
    the exact solver, a solver of the other mode) raises ValueError naming it.
    Arguments left as ``None`` take the library's defaults: particles of 1 kg, restitution 0 and friction 0.5, spring
    stiffness 1 N/m, bodies of density 1000 kg/m^3 when given only a shape, frames every 1/60 s.
    ``threads`` sets how many threads the contact solves use (0, the default: one per core); results do not depend
    on it. Bodies collide through their shapes (``add_body(shape, ...)``, ``colliders=[(shape, position,
    orientation), ...]`` for more), particles through ``add_particle(radius=...)``; ``add_ground()`` adds a
    static floor. Two surfaces combine to the larger restitution and the geometric mean of the frictions, unless
    ``friction_combine=`` / ``restitution_combine=`` name another rule ("average", "geometric_mean", "min",
    "product" as Blender and Bullet, "max"), for the world here or for one surface in ``add_body``, ``add_particle``,
    ``add_ground`` and ``set_material`` (a surface's own rule comes first; of two own rules, the later in that list).
    ``rolling_resistance=`` and ``torsional_resistance=`` (dimensionless, default 0) resist a body's turn across and
    about a contact's normal with a torque of at most the coefficient times the normal force times the rolling
    radius (a ball's radius): a solid ball rolling on a floor slows at 5/7 of it times g; a pair takes the larger.
    """

    if not TYPE_CHECKING:  # type checkers check calls against the compiled World's signature (in its stub)

        def __new__(cls, *args, **kwargs):
            try:
                return super().__new__(cls, *args, **kwargs)
            except (TypeError, OverflowError) as error:
                better = renamed(error)
                if better is None:
                    raise
                raise better from error

    @property
    def particles(self) -> ParticlesView:
        """The particles' state as arrays."""
        return ParticlesView(self)

    @property
    def bodies(self) -> BodiesView:
        """The bodies' state as arrays."""
        return BodiesView(self)

    def add_joint(self, joint: "Joint") -> "JointHandle":
        """Adds a joint (``tumble.Ball``, ``Hinge``, ``Slider``, ``Weld`` or ``Distance``); returns its handle.

        ``w.add_joint(tumble.Hinge(a, b, anchor_a=(0, 0, 0.5), anchor_b=(0, 0, -0.5), axis=(1, 0, 0),
        limits=(-1.0, 1.0), motor=tumble.Motor(speed=2.0, max_torque=50.0)))``. Remove it with
        ``remove_joint(handle)``. The plan gains a "joints" stage; the report counts joint rows and the largest joint
        error (``joint_error`` in m, ``joint_angle_error`` in rad). A joint given ``breaking=tumble.Breaking(force=...,
        torque=...)`` breaks once it carries more (``joint_broken(handle)``, ``broken_joints()``,
        ``Run.joint_breaks``).
        """
        if not isinstance(joint, Joint):
            raise ValueError(
                f"invalid argument `joint`: expected tumble.Ball, Hinge, Slider, Weld or Distance, got {joint!r}"
            )
        return self._add_joint(**joint._fields())

    def __copy__(self) -> "World":
        """A copy: objects, settings, state, the engine's memory and report; it answers to this world's handles
        and continues bit for bit as this world would (force callbacks are shared)."""
        copy = type(self)()
        copy._assign_from(self)
        return copy

    def __deepcopy__(self, memo: dict[int, Any]) -> "World":
        """The same as ``copy.copy``: a world shares nothing with its copy but its force callbacks."""
        return self.__copy__()

    def save(self, path: str | os.PathLike[str], memory: bool = True) -> Path:
        """Saves the world: readable JSON if ``path`` ends in ``.json``, else the versioned binary format. Every
        object and its state are kept to the bit, with the settings and the start ``reset`` returns to, and (unless
        ``memory=False``) the engine's memory (fast mode's warm starts, kept manifolds and sleep; accurate mode's
        integration, resting contacts and touching phase): a loaded world continues bit for bit as this one, in
        both modes and from either format. With ``memory=False`` the file holds the scene alone (in JSON, one a
        person can read and edit), and a world loaded from it starts its engine afresh from the saved state. A world
        with force callbacks cannot be saved (ValueError naming ``loads``). Returns the path."""
        path = as_path(path)
        if path.suffix.lower() == ".json":
            path.write_text(self.to_json(memory=memory))
        else:
            path.write_bytes(self._to_bytes(memory=memory))
        return path

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "World":
        """Loads a world written by ``save`` (JSON if ``path`` ends in ``.json``, else binary). A truncated file,
        another version, an unknown field or a bad value raises ValueError naming it; nothing is half-built."""
        path = as_path(path)
        world = cls()
        if path.suffix.lower() == ".json":
            world._assign_from_json(path.read_text())
        else:
            world._assign_from_bytes(path.read_bytes())
        return world

    @classmethod
    def from_usd(cls, path: str | os.PathLike[str], **world_options: Any) -> tuple["World", dict[str, BodyHandle]]:
        """A world from a USD stage's physics (the UsdPhysics schema, through usd-core: ``pip install
        "./python[usd]"``), and its bodies' handles by prim path: the physics scene's gravity; rigid bodies with
        their velocities, mass, density, centre of mass and inertia, kinematic ones following their animation;
        colliders on Cube, Sphere, Capsule, Cylinder, Cone and Mesh prims (MeshCollisionAPI's approximation), alone
        as static bodies; physics materials; revolute, prismatic, spherical, fixed and distance joints with limits
        and drives; metersPerUnit, kilogramsPerUnit and upAxis (to tumble's metres and z up). Each body is named by
        its prim path, so ``Run.export_usd(path, over=source)`` writes a run back onto the stage's prims.
        ``world_options`` go to ``World``. What cannot be mapped raises ``tumble.UsdSceneError`` (a ValueError)
        listing each prim and attribute."""
        from .usd._read import read_stage  # noqa: PLC0415

        return read_stage(as_path(path), cls, **world_options)

    @classmethod
    def from_json(cls, text: str) -> "World":
        """A world from a scene in JSON (``to_json``'s output, or written by hand: most fields have defaults)."""
        world = cls()
        world._assign_from_json(text)
        return world

    def __reduce__(self) -> tuple[Callable[[type[World], bytes], World], tuple[type[World], bytes]]:
        """Pickles through the binary format (see ``save``)."""
        return (_from_bytes, (type(self), self._to_bytes()))

    @property
    def report(self) -> Report:
        """Everything the world's steps have cost so far."""
        return Report(self._report())

    def run(
        self,
        duration: float,
        frame_interval: float | None = None,
        progress: bool | Callable[[float], None] | None = None,
        sensitivity: int = 0,
    ) -> Run:
        """Runs for ``duration`` seconds, recording a frame every ``frame_interval`` (default 1/60 s) and at the end.

        The interpreter lock is released while the world steps. ``progress``: None (the default) shows a tqdm bar on
        a terminal once the run has taken two seconds, with the time left, and nothing in a log; True shows it
        from the start (plain lines with the time left, where standard error is a log); False nothing; a callable
        is called with the fraction done (about a hundred times a run, and every 50 ms of work in between). When
        accurate mode projects more than ten times the simulated time, one line (once a world) says so and names
        fast mode with its time measured on a copy; the run goes on as asked.

        Ctrl-C stops the run within 50 ms of work at its last whole frame: the world is left at that frame, so the
        next ``run`` carries on from it, and the frames done come with the KeyboardInterrupt as ``error.run`` (a
        ``Run`` with ``interrupted`` True). Any other exception from the callable fails the run: the world is left as
        it was, the frames done on ``error.run``. ``step`` answers Ctrl-C too, leaving the world as it was. Raises
        SimulationError, leaving the world unchanged, if a step cannot be completed; the frames recorded up to the
        failure come with it as ``error.run`` (its report covering the steps taken).

        ``sensitivity=N`` (0: none) also runs ``N`` twins, every moving body started a contact tolerance away (1e-6 m
        in fast mode) in a random direction, and gives the report ``outcome_sensitivity``: how many times farther
        apart than that they end (``tumble.direct.sensitivity``): near 1 the outcome holds, thousands and more it is
        chaotic, whatever the local error says.
        """
        if isinstance(sensitivity, bool) or not isinstance(sensitivity, int) or sensitivity < 0:
            raise ValueError(f"invalid argument `sensitivity`: expected a whole number >= 0, got {sensitivity!r}")
        start = copy.copy(self) if sensitivity else None
        shown = _progress(progress)
        hint = shown.write if isinstance(shown, Progress) else None
        try:
            data = self._run(duration, frame_interval, shown, hint)
        except BaseException as error:
            partial = getattr(error, "_partial", None)
            if partial is not None:
                error.run = Run.from_dict(partial, self._body_shapes(), self._links(),  # type: ignore[attr-defined]
                                          looks=looks_of(self), link_joints=self._link_joints())
            raise
        finally:
            if isinstance(shown, Progress):
                shown.close()
        run = Run.from_dict(data, self._body_shapes(), self._links(), looks=looks_of(self),
                            link_joints=self._link_joints())
        if start is not None:
            run.report = _with_sensitivity(run.report, start, duration, sensitivity)
        return run

    def show(
        self,
        duration: float | None = None,
        port: int = 8080,
        block: bool = True,
        frame_interval: float | None = None,
        host: str = "127.0.0.1",
    ) -> Viewer:
        """Shows the world in the interactive 3-D viewer (``Run.show``; ``pip install "./python[viewer]"``). With a
        ``duration`` it runs that long (frames every ``frame_interval``) and shows the run; without, it shows the
        world as it is now, with its current contacts, and leaves it unchanged. Returns the ``Viewer``."""
        from .viewer._viewer import check_arguments, snapshot  # noqa: PLC0415

        check_arguments(port, block, host)  # before a run that a bad port would waste
        if duration is None:
            run = snapshot(self)
        else:
            run = self.run(duration, frame_interval)
        return run.show(port, block, host)


def _with_sensitivity(report: Report, start: World, duration: float, twins: int) -> Report:
    """``report`` with the outcome sensitivity of ``twins`` twins of ``start`` (``World.run``'s ``sensitivity``)."""
    from .direct import sensitivity  # noqa: PLC0415

    size = report.contact_tolerance or 1e-6
    figure = sensitivity(start, duration, twins=twins, size=size)
    line = (f"outcome          twins started {size:.1e} m apart end up to {figure['spread']:.3e} m apart "
            f"({figure['ratio']:.3g} times: near 1 the outcome holds, thousands and more it is chaotic)")
    return Report({**report.as_dict(), "outcome_sensitivity": figure["ratio"], "_text": str(report) + "\n" + line,
                   "_details": report.details() + "\n" + line})


def _from_bytes(cls: type[World], data: bytes) -> World:
    """Unpickles a world (``World.__reduce__``)."""
    world = cls()
    world._assign_from_bytes(data)
    return world


# Every compiled method names its argument in a type error (the compiled module only notes it).
for _name, _method in vars(_World).items():
    if type(_method).__name__ == "method_descriptor" and not _name.startswith("__") and _name not in vars(World):
        setattr(World, _name, named_arguments(_method))
