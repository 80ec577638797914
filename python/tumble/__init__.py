"""tumble: particles and rigid bodies for physically based animation, with honest error reports.

>>> import tumble
>>> w = tumble.World(gravity=(0.0, 0.0, -9.81), integrator="dopri5", rtol=1e-8, atol=1e-10)
>>> p = w.add_particle(mass=1.0, position=(0, 0, 1), velocity=(1, 0, 0))
>>> b = w.add_body(tumble.Box(half_extents=(0.5, 0.5, 0.5)), density=1000.0, position=(0, 0, 2))
>>> run = w.run(duration=1.0, frame_interval=1 / 60)
>>> run.particle_positions.shape, run.body_positions.shape
((61, 1, 3), (61, 1, 3))

State comes back as read-only numpy arrays (``w.particles.positions`` is (P, 3); ``w.bodies.row(handle)`` is a
body's row); ``w.get_state()`` / ``w.set_state(state)`` take and put back the whole state (the world then continues
bit for bit) and ``w.reset()`` returns to the start; runs return a :class:`Run` with frames,
energy, momenta, every accepted step size and a :class:`Report` of what the run cost. Bad arguments raise
``ValueError`` naming the argument; a step that cannot be completed raises :class:`SimulationError` (a
``RuntimeError``) and leaves the world as it was before the call. The names of integrators, modes and solvers
are typed (``IntegratorName``, ``ModeName``, ``SolverName``, ``LinearSolverName``), so a type checker flags a
misspelt one.
"""

from __future__ import annotations

from ._tumble import (
    BodyHandle,
    Box,
    Capsule,
    ConvexHull,
    Cylinder,
    JointHandle,
    LoadHandle,
    Mesh,
    ParticleHandle,
    Shape,
    SimulationError,
    Sphere,
    SpringHandle,
    State,
    TriMesh,
    __version__,
    shared_faces,
    bonds,
)
from ._report import Report
from ._run import Run
from ._geometry import EulerOrder, quaternion_to_euler, quaternion_to_matrix, up_axis
from ._batch import Batch, rollout
from ._sweep import sweep
from ._kinematic import keyframes_from
from .usd._shapes import UsdSceneError
from .usd._values import UsdImportWarning
from ._joints import Ball, Breaking, Distance, Drive, Hinge, JointSpring, Motor, Piston, Slider, Weld
from ._names import CombineName, IntegratorName, LinearSolverName, ModeName, SolverName
from ._world import BodiesView, ParticlesView, World
from . import direct, scenes

__all__ = [
    "World",
    "Run",
    "shared_faces",
    "bonds",
    "Batch",
    "rollout",
    "sweep",
    "keyframes_from",
    "UsdSceneError",
    "UsdImportWarning",
    "Report",
    "ParticlesView",
    "BodiesView",
    "Shape",
    "Sphere",
    "Box",
    "Capsule",
    "Cylinder",
    "ConvexHull",
    "TriMesh",
    "Mesh",
    "ParticleHandle",
    "BodyHandle",
    "SpringHandle",
    "LoadHandle",
    "JointHandle",
    "Ball",
    "Hinge",
    "Slider",
    "Piston",
    "Drive",
    "Weld",
    "Distance",
    "Motor",
    "Breaking",
    "JointSpring",
    "State",
    "SimulationError",
    "scenes",
    "direct",
    "IntegratorName",
    "ModeName",
    "SolverName",
    "LinearSolverName",
    "CombineName",
    "quaternion_to_matrix",
    "quaternion_to_euler",
    "up_axis",
    "EulerOrder",
    "__version__",
]
