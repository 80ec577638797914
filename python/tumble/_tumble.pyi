"""Type stubs of tumble's compiled module (the package ``tumble`` re-exports these)."""

import os
from typing import Any, Callable, Literal, Self, Sequence, TypedDict, final

import numpy as np
import numpy.typing as npt

from tumble._names import CombineName, IntegratorName, LinearSolverName, ModeName, SolverName
from tumble._run import Run

__version__: str

Vec3 = Sequence[float] | npt.ArrayLike
Quat = Sequence[float] | npt.ArrayLike

class SimulationError(RuntimeError):
    """A step could not be completed; the world is unchanged."""

    run: Run  # set by ``World.run``: the frames recorded up to the failure

@final
class ParticleHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...
    @property
    def world(self) -> int: ...

@final
class BodyHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...
    @property
    def world(self) -> int: ...

@final
class State:
    """A world's whole state: read-only arrays (rows as in ``World.bodies`` and ``World.particles``), the time
    and, hidden, the engine's memory; ``World.set_state`` puts it back and the world continues bit for bit."""

    @property
    def time(self) -> float: ...
    @property
    def particle_positions(self) -> np.ndarray: ...
    @property
    def particle_velocities(self) -> np.ndarray: ...
    @property
    def body_positions(self) -> np.ndarray: ...
    @property
    def body_orientations(self) -> np.ndarray: ...
    @property
    def body_momenta(self) -> np.ndarray: ...
    @property
    def body_angular_momenta(self) -> np.ndarray: ...
    @property
    def has_memory(self) -> bool: ...
    def replace(self, **changes: float | npt.ArrayLike) -> "State": ...

def _shape_from_json(text: str) -> Shape: ...
def shared_faces(
    pieces: list[Mesh],
) -> list[tuple[int, int, float, list[float], list[float]]]:
    """The faces closed meshes in one frame share: ``(a, b, area, centre, normal)`` for each touching pair."""
def bonds(
    pieces: list[Mesh], strength: float
) -> list[tuple[int, int, float, list[float], list[float], float, float]]:
    """The bonds that glue ``pieces`` at ``strength`` Pa: ``(a, b, area, centre, normal, force, torque)``."""
def _handle(
    kind: str, world: int, index: int, generation: int
) -> ParticleHandle | BodyHandle | SpringHandle | LoadHandle | JointHandle: ...
def _rollout(
    world: World,
    states: list[State],
    duration: float,
    frame_interval: float | None = None,
    threads: int | None = None,
    progress: Callable[[float], None] | None = None,
) -> list[dict[str, Any]]: ...

@final
class SpringHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...
    @property
    def world(self) -> int: ...

@final
class LoadHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...
    @property
    def world(self) -> int: ...

@final
class JointHandle:
    @property
    def index(self) -> int: ...
    @property
    def generation(self) -> int: ...
    @property
    def world(self) -> int: ...

class Shape:
    """A collision and mass shape (base class)."""
    @property
    def kind(self) -> str: ...
    def __reduce__(self) -> tuple[Callable[[str], Shape], tuple[str]]: ...
    def mass_properties(self, density: float) -> dict[str, Any]: ...
    def distance(self, position: Vec3, orientation: Quat, other: Shape, other_position: Vec3,
                 other_orientation: Quat) -> float:
        """The distance (m) between this shape and ``other``, each posed (zero where they overlap)."""
    def triangle_mesh(
        self, subdivisions: int | None = None, extent: float | None = None
    ) -> tuple[np.ndarray, np.ndarray]: ...

@final
class Sphere(Shape):
    def __new__(cls, radius: float) -> Self: ...

@final
class Box(Shape):
    def __new__(cls, half_extents: Vec3) -> Self: ...

@final
class Capsule(Shape):
    """Along z."""
    def __new__(cls, half_height: float, radius: float) -> Self: ...

@final
class Cylinder(Shape):
    """Along z."""
    def __new__(cls, half_height: float, radius: float) -> Self: ...

@final
class ConvexHull(Shape):
    def __new__(cls, points: npt.ArrayLike) -> Self: ...

@final
class TriMesh(Shape):
    """Static bodies only."""
    def __new__(cls, vertices: npt.ArrayLike, triangles: npt.ArrayLike) -> Self: ...

@final
class Mesh(Shape):
    """A closed triangle mesh (counter-clockwise seen from outside). A moving body carries its convex
    decomposition (or its hull, ``shape="hull"``), a static one the exact triangles; its mass properties are the
    solid's. Raises ValueError naming the mesh when it does not bound a solid."""
    def __new__(cls, vertices: npt.ArrayLike | Any, triangles: npt.ArrayLike | None = None, name: str = "") -> Self: ...
    @staticmethod
    def load(path: str | os.PathLike[str], scale: float = 1.0, up: Literal["y", "z"] | None = None) -> Mesh:
        """An OBJ, STL, PLY, glTF or GLB file's meshes merged, placed by the file's transforms, scaled by ``scale``
        (file units to metres), the file's ``up`` axis turned to +z; by default the format's own (+y for glTF and GLB,
        by their specification; the coordinates as given for OBJ, STL and PLY)."""
    @staticmethod
    def revolve(profile: npt.ArrayLike, segments: int = 48, name: str = "") -> Mesh:
        """The solid swept by turning (r, z) points about z: axis to axis bounds a solid, else the loop is closed."""
    @staticmethod
    def load_all(path: str | os.PathLike[str], scale: float = 1.0, up: Literal["y", "z"] | None = None) -> list[Mesh]:
        """A file's meshes one by one (as ``load``, not merged)."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def triangles(self) -> npt.NDArray[np.uint32]: ...
    @property
    def volume(self) -> float: ...
    @property
    def name(self) -> str: ...
    @property
    def is_convex(self) -> bool:
        """Whether the solid is convex (every vertex on or below every triangle's plane)."""
    def fracture(
        self,
        pieces: int | None = None,
        seed: int | None = None,
        points: npt.ArrayLike | None = None,
        near: Vec3 | None = None,
    ) -> list[Mesh]:
        """The mesh cut into pieces at the Voronoi cells of ``pieces`` seeded points inside it (more near ``near``)
        or of the given ``points``: closed meshes in its frame, named after it, their volumes adding up to its own."""
    def hull(self) -> ConvexHull: ...
    def pieces(
        self, resolution: int | None = None, max_pieces: int | None = None, concavity: float | None = None
    ) -> list[ConvexHull]:
        """The convex pieces a moving body of this mesh collides with (defaults: 64, 32, 0.01)."""

MeshShapeName = Literal["decomposed", "hull", "exact"]

class Decomposition(TypedDict, total=False):
    resolution: int
    max_pieces: int
    concavity: float

class World:
    def __new__(
        cls,
        gravity: Vec3 | None = None,
        integrator: IntegratorName | None = None,
        rtol: float | None = None,
        atol: float | None = None,
        dt: float | None = None,
        step_doubling: bool = False,
        tolerance: float | None = None,
        mode: ModeName = "accurate",
        linear_solver: LinearSolverName | None = None,
        newton: bool = False,
        max_steps: int | None = None,
        sleep: bool | None = None,
        threads: int | None = None,
        contact_tolerance: float | None = None,
        solver: SolverName | None = None,
        substeps: int | None = None,
        friction_combine: CombineName | None = None,
        restitution_combine: CombineName | None = None,
    ) -> Self: ...
    def set_integrator(
        self,
        integrator: IntegratorName | None = None,
        rtol: float | None = None,
        atol: float | None = None,
        dt: float | None = None,
        step_doubling: bool = False,
        tolerance: float | None = None,
        linear_solver: LinearSolverName | None = None,
        newton: bool = False,
        max_steps: int | None = None,
    ) -> None: ...
    def set_mode(
        self,
        mode: ModeName,
        dt: float | None = None,
        sleep: bool | None = None,
        contact_tolerance: float | None = None,
        solver: SolverName | None = None,
        substeps: int | None = None,
    ) -> None: ...
    @property
    def threads(self) -> int: ...
    @threads.setter
    def threads(self, threads: int) -> None: ...
    @property
    def mode(self) -> ModeName: ...
    def add_ground(
        self,
        height: float = 0.0,
        restitution: float | None = None,
        friction: float | None = None,
        rolling_resistance: float | None = None,
        torsional_resistance: float | None = None,
        friction_combine: CombineName | None = None,
        restitution_combine: CombineName | None = None,
    ) -> BodyHandle: ...
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
        friction_combine: CombineName | None = None,
        restitution_combine: CombineName | None = None,
    ) -> ParticleHandle: ...
    def add_body(
        self,
        geometry: Shape | None = None,
        /,
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
        shape: Shape | MeshShapeName | None = None,
        decomposition: Decomposition | None = None,
        name: str | None = None,
        color: tuple[float, float, float] | tuple[float, float, float, float] | npt.ArrayLike | None = None,
        collision_groups: int | None = None,
        keyframes: tuple[npt.ArrayLike, npt.ArrayLike] | tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike] | None = None,
        rolling_resistance: float | None = None,
        torsional_resistance: float | None = None,
        friction_combine: CombineName | None = None,
        restitution_combine: CombineName | None = None,
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
    def _add_joint(
        self,
        kind: str,
        a: BodyHandle | None,
        b: BodyHandle | None,
        anchor_a: Vec3 | None = None,
        anchor_b: Vec3 | None = None,
        axis: Vec3 | None = None,
        limits: tuple[float, float] | None = None,
        motor: tuple[float, float] | None = None,
        spring: tuple[float, float, float] | None = None,
        softness: tuple[float, float] | None = None,
        length: float | None = None,
        breaking: tuple[float, float] | None = None,
        break_window: float = 0.0,
        collide: bool = False,
        turn_limits: tuple[float, float] | None = None,
        cluster: bool = False,
    ) -> JointHandle: ...
    def remove_joint(self, joint: JointHandle) -> None:
        """Removes a joint."""
    def joint_broken(self, joint: JointHandle) -> bool:
        """Whether ``joint`` has broken (past its ``breaking`` bounds; it then holds nothing)."""
    def broken_joints(self) -> list[JointHandle]:
        """The joints that have broken, in the order they were added."""
    def joint_breaking(self, joint: JointHandle) -> tuple[float, float, float] | None:
        """When ``joint`` breaks: (force N, torque N m, window s), or None for a joint that never breaks."""
    @property
    def joint_handles(self) -> list[JointHandle]:
        """The joints, in the order they were added."""
    def add_fractured(
        self,
        mesh: Mesh,
        pieces: list[Mesh],
        density: float | None = None,
        strength: float | None = None,
        position: Vec3 | None = None,
        orientation: Quat | None = None,
        friction: float | None = None,
        restitution: float | None = None,
        window: float | None = None,
    ) -> list[BodyHandle]:
        """Adds the pieces of fractured ``mesh`` as bodies where they were modelled, each pair that shares a face
        glued by a weld that breaks past the face's area times ``strength`` (Pa), its load averaged over ``window``
        seconds (0.01 by default); returns the pieces' handles."""
    @property
    def joint_count(self) -> int: ...
    def set_particle_state(
        self, particle: ParticleHandle, position: Vec3 | None = None, velocity: Vec3 | None = None
    ) -> None: ...
    def set_body_state(
        self,
        body: BodyHandle,
        position: Vec3 | None = None,
        orientation: Quat | None = None,
        velocity: Vec3 | None = None,
        angular_velocity: Vec3 | None = None,
    ) -> None: ...
    def set_material(
        self,
        handle: ParticleHandle | BodyHandle,
        friction: float | None = None,
        restitution: float | None = None,
        rolling_resistance: float | None = None,
        torsional_resistance: float | None = None,
        friction_combine: CombineName | Literal["world"] | None = None,
        restitution_combine: CombineName | Literal["world"] | None = None,
    ) -> None: ...
    def release(self, body: BodyHandle, density: float | None = None) -> None: ...
    def hold(
        self,
        body: BodyHandle,
        keyframes: tuple[npt.ArrayLike, npt.ArrayLike] | tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike] | None = None,
    ) -> None: ...
    def set_combine_rules(self, friction: CombineName | None = None, restitution: CombineName | None = None) -> None: ...
    @property
    def combine_rules(self) -> dict[str, CombineName]: ...
    def step(self, dt: float) -> None: ...
    @property
    def time(self) -> float: ...
    @property
    def gravity(self) -> np.ndarray: ...
    def particle_handles(self) -> list[ParticleHandle]: ...
    def body_handles(self) -> list[BodyHandle]: ...
    def get_state(self) -> State: ...
    def set_state(self, state: State) -> None: ...
    def reset(self) -> None: ...
    def _assign_from(self, other: World) -> None: ...
    def to_json(self, memory: bool = True) -> str: ...
    def _to_bytes(self, memory: bool = True) -> bytes: ...
    def _assign_from_json(self, text: str) -> None: ...
    def _assign_from_bytes(self, data: bytes) -> None: ...
    def contacts(self) -> dict[str, Any]: ...
    def _particle_row(self, handle: ParticleHandle) -> int: ...
    def _body_row(self, handle: BodyHandle) -> int: ...
    def kinetic_energy(self) -> float: ...
    def potential_energy(self) -> float: ...
    def momentum(self) -> np.ndarray: ...
    def angular_momentum(self) -> np.ndarray: ...
    def plan(self) -> dict[str, Any]: ...
    def _run(
        self, duration: float, frame_interval: float | None = None, progress: Callable[[float], None] | None = None,
        hint: Callable[[str], None] | None = None,
    ) -> dict[str, Any]: ...
    def _report(self) -> dict[str, Any]: ...
    def _particle_positions(self) -> np.ndarray: ...
    def _particle_velocities(self) -> np.ndarray: ...
    def _body_positions(self) -> np.ndarray: ...
    def _body_origins(self) -> np.ndarray: ...
    def _body_names(self) -> list[str | None]: ...
    def _body_collision_groups(self) -> list[int]: ...
    def _body_kinematic(self) -> list[bool]: ...
    def _body_colors(self) -> list[tuple[float, float, float, float] | None]: ...
    def _body_orientations(self) -> np.ndarray: ...
    def _body_masses(self) -> np.ndarray: ...
    def _link_joints(self) -> list[JointHandle | None]: ...
    def _body_inertias(self) -> np.ndarray: ...
    def _body_velocities(self) -> np.ndarray: ...
    def _body_angular_velocities(self) -> np.ndarray: ...
    def _links(self) -> list[tuple[str, tuple[str, int, list[float]], tuple[str, int, list[float]]]]: ...
    def _body_shapes(self) -> list[list[tuple[Shape, list[float], list[float]]]]: ...
    @classmethod
    def _rust_scene(cls, name: str, **params: float) -> Self: ...
    @staticmethod
    def _check_scene(name: str, **params: float) -> None: ...
