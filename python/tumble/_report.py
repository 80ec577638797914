"""The report of what a world's steps cost: a plain dataclass."""

from __future__ import annotations

from dataclasses import asdict, dataclass


@dataclass(frozen=True)
class Report:
    """Cost and accuracy of a world's steps (or of one run).

    Integrator counters (accepted and rejected steps, right-hand-side evaluations, Jacobians, LU factorizations,
    linear solves, Newton and Krylov iterations), the smallest and largest accepted step, wall time, and the
    integrator's error estimate (the sum of its local error estimates, ``None`` for methods without one); contact
    counters (clarabel solves, collisions resolved, contacts given an impulse, bisection steps, narrow-phase pair
    checks, islands solved, actors asleep, the largest penetration, and the time spent finding and solving
    contacts: zero wherever a stage never ran); and how often each force loop ran.
    """

    method: str
    steps: int
    rejected: int
    rhs_evals: int
    jacobians: int
    factorizations: int
    linear_solves: int
    newton_iterations: int
    krylov_iterations: int
    min_step: float | None
    max_step: float | None
    wall_seconds: float
    error_estimate: float | None
    qp_solves: int
    collisions: int
    impulses: int
    bisection_steps: int
    collision_checks: int
    islands: int
    sleepers: int
    max_penetration: float
    collision_seconds: float
    contact_seconds: float
    evaluations: int
    spring_evaluations: int
    load_evaluations: int
    callback_calls: int
    projections: int

    def as_dict(self) -> dict:
        """The fields as a dict."""
        return asdict(self)

    def __str__(self) -> str:
        def step(h: float | None) -> str:
            return "-" if h is None else f"{h:.3e}"

        estimate = "none (the method has no estimate)" if self.error_estimate is None else f"{self.error_estimate:.3e}"
        return "\n".join(
            [
                f"method           {self.method}",
                f"steps            {self.steps} accepted, {self.rejected} rejected",
                f"rhs evaluations  {self.rhs_evals}",
                f"linear algebra   {self.jacobians} jacobians, {self.factorizations} factorizations, "
                f"{self.linear_solves} solves, {self.newton_iterations} newton / {self.krylov_iterations} krylov iterations",
                f"step size        {step(self.min_step)} .. {step(self.max_step)}",
                f"wall time        {self.wall_seconds:.6f} s",
                f"error estimate   {estimate}",
                f"force loops      {self.evaluations} evaluations: {self.spring_evaluations} spring, "
                f"{self.load_evaluations} load, {self.callback_calls} callback; {self.projections} projections",
                f"contact          {self.collision_checks} collision checks, {self.collisions} collisions, "
                f"{self.impulses} impulses, {self.bisection_steps} bisection steps, {self.qp_solves} qp solves "
                f"over {self.islands} islands",
                f"                 max penetration {self.max_penetration:.3e} m, {self.sleepers} asleep; "
                f"{self.collision_seconds:.3f} s finding contacts, {self.contact_seconds:.3f} s solving them",
            ]
        )
