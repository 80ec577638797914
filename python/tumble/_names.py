"""The names that ``World``, ``set_integrator`` and ``set_mode`` accept, as ``Literal`` types for type checkers (a
misspelt name is an error there, not only a ValueError at run time). One list for the package and the compiled
module's stub (_tumble.pyi), taken from the Rust library: the integrators from ``Method::name``
(crates/integrate/src/method.rs), the modes, fast mode's contact solvers and implicit Euler's linear solvers from
``mode_from`` and ``IntegratorOptions::settings`` (src/options.rs), the combine rules from ``Combine::ALL``
(src/collider.rs)."""

from typing import Literal

IntegratorName = Literal[
    "euler",
    "euler-variable",
    "midpoint",
    "rk4",
    "ab4",
    "am4",
    "implicit-euler",
    "dopri5",
    "symplectic-euler",
    "verlet",
    "rodas4",
    "radau5",
    "dop853",
]
ModeName = Literal["accurate", "fast"]
SolverName = Literal["soft", "exact", "newton", "clarabel"]
LinearSolverName = Literal["direct", "iterative"]
# how two surfaces' frictions and restitutions combine (`Combine::ALL`, src/collider.rs)
CombineName = Literal["average", "geometric_mean", "min", "product", "max"]
