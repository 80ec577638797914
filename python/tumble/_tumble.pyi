"""Type stubs of tumble's compiled module (the package ``tumble`` re-exports these)."""

from typing import Any, Callable, Sequence

import numpy as np
import numpy.typing as npt

__version__: str

Vec3 = Sequence[float] | npt.ArrayLike
Quat = Sequence[float] | npt.ArrayLike

class SimulationError(RuntimeError):
    """A step could not be completed; the world is unchanged."""

class ParticleHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...

class BodyHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...

class SpringHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...

class LoadHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...

class Shape:
    """A collision and mass shape (base class)."""
    @property
    def kind(self) -> str: ...
    def mass_properties(self, density: float) -> dict[str, Any]: ...
    def triangle_mesh(self, subdivisions: int | None = None, extent: float | None = None) -> tuple[np.ndarray, np.ndarray]: ...

class Sphere(Shape):
    def __init__(self, radius: float) -> None: ...

class Box(Shape):
    def __init__(self, half_extents: Vec3) -> None: ...

class Capsule(Shape):
    """Along z."""
    def __init__(self, half_height: float, radius: float) -> None: ...

class Cylinder(Shape):
    """Along z."""
    def __init__(self, half_height: float, radius: float) -> None: ...

class ConvexHull(Shape):
    def __init__(self, points: npt.ArrayLike) -> None: ...

class TriMesh(Shape):
    """Static bodies only."""
    def __init__(self, vertices: npt.ArrayLike, triangles: npt.ArrayLike) -> None: ...

class World:
    def __init__(
        self,
        gravity: Vec3 | None = None,
        integrator: str | None = None,
        rtol: float | None = None,
        atol: float | None = None,
        dt: float | None = None,
        step_doubling: bool = False,
        tolerance: float | None = None,
        mode: str = "accurate",
        linear_solver: str | None = None,
        newton: bool = False,
        max_steps: int | None = None,
        sleep: bool | None = None,
        threads: int | None = None,
        contact_tolerance: float | None = None,
        solver: str | None = None,
        substeps: int | None = None,
    ) -> None: ...
    def set_integrator(
        self,
        integrator: str | None = None,
        rtol: float | None = None,
        atol: float | None = None,
        dt: float | None = None,
        step_doubling: bool = False,
        tolerance: float | None = None,
        linear_solver: str | None = None,
        newton: bool = False,
        max_steps: int | None = None,
    ) -> None: ...
    def set_mode(
        self,
        mode: str,
        dt: float | None = None,
        sleep: bool | None = None,
        contact_tolerance: float | None = None,
        solver: str | None = None,
        substeps: int | None = None,
    ) -> None: ...
    @property
    def threads(self) -> int: ...
    @threads.setter
    def threads(self, threads: int) -> None: ...
    @property
    def mode(self) -> str: ...
    def add_ground(self, height: float = 0.0, restitution: float | None = None, friction: float | None = None) -> BodyHandle: ...
    def add_particle(
        self,
        mass: float | None = None,
        position: Vec3 | None = None,
        velocity: Vec3 | None = None,
        damping: float = 0.0,
        stiffness: float = 0.0,
        anchor: Vec3 | None = None,
        radius: float = 0.0,
        restitution: float | None = None,
        friction: float | None = None,
    ) -> ParticleHandle: ...
    def add_body(
        self,
        shape: Shape | None = None,
        density: float | None = None,
        mass: float | None = None,
        inertia: npt.ArrayLike | None = None,
        position: Vec3 | None = None,
        orientation: Quat | None = None,
        velocity: Vec3 | None = None,
        angular_velocity: Vec3 | None = None,
        restitution: float | None = None,
        friction: float | None = None,
        static: bool = False,
        linear_damping: float = 0.0,
        angular_damping: float = 0.0,
        colliders: list[tuple[Shape, Vec3] | tuple[Shape, Vec3, Quat]] | None = None,
    ) -> BodyHandle: ...
    def add_spring(
        self,
        a: ParticleHandle | BodyHandle,
        b: ParticleHandle | BodyHandle | None = None,
        stiffness: float | None = None,
        damping: float = 0.0,
        rest_length: float | None = None,
        anchor_a: Vec3 | None = None,
        anchor_b: Vec3 | None = None,
        world_point: Vec3 | None = None,
    ) -> SpringHandle: ...
    def add_force(self, target: ParticleHandle | BodyHandle, force: Vec3, at: Vec3 | None = None) -> LoadHandle: ...
    def add_torque(self, body: BodyHandle, torque: Vec3) -> LoadHandle: ...
    def add_force_callback(
        self, target: ParticleHandle | BodyHandle, callback: Callable[[float, np.ndarray, np.ndarray], Any]
    ) -> LoadHandle: ...
    def remove(self, handle: ParticleHandle | BodyHandle | SpringHandle | LoadHandle) -> None: ...
    def set_particle_state(self, particle: ParticleHandle, position: Vec3 | None = None, velocity: Vec3 | None = None) -> None: ...
    def set_body_state(
        self,
        body: BodyHandle,
        position: Vec3 | None = None,
        orientation: Quat | None = None,
        velocity: Vec3 | None = None,
        angular_velocity: Vec3 | None = None,
    ) -> None: ...
    def step(self, dt: float) -> None: ...
    @property
    def time(self) -> float: ...
    @property
    def gravity(self) -> np.ndarray: ...
    def particle_handles(self) -> list[ParticleHandle]: ...
    def body_handles(self) -> list[BodyHandle]: ...
    def kinetic_energy(self) -> float: ...
    def potential_energy(self) -> float: ...
    def momentum(self) -> np.ndarray: ...
    def angular_momentum(self) -> np.ndarray: ...
    def plan(self) -> dict[str, Any]: ...
    def _run(self, duration: float, frame_interval: float | None = None, progress: Callable[[float], None] | None = None) -> dict[str, Any]: ...
    def _report(self) -> dict[str, Any]: ...
    def _particle_positions(self) -> np.ndarray: ...
    def _particle_velocities(self) -> np.ndarray: ...
    def _body_positions(self) -> np.ndarray: ...
    def _body_orientations(self) -> np.ndarray: ...
    def _body_velocities(self) -> np.ndarray: ...
    def _body_angular_velocities(self) -> np.ndarray: ...
    def _body_shapes(self) -> list[list[tuple[Shape, list[float], list[float]]]]: ...
    @classmethod
    def _rust_scene(cls, name: str, **params: float) -> "World": ...
    @staticmethod
    def _check_scene(name: str, **params: float) -> None: ...
