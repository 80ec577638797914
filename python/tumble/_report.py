"""The report of what a world's steps cost. Its fields come from the Rust library (``WorldReport::fields``), the one
list of them; this class only gives them attribute access."""

from __future__ import annotations

from typing import Any


class Report:
    """Cost and accuracy of a world's steps (or of one run), read-only.

    Integrator counters (``steps``, ``rejected``, ``rhs_evals``, ``jacobians``, ``factorizations``,
    ``linear_solves``, ``newton_iterations``, ``krylov_iterations``), the smallest and largest accepted step
    (``min_step``, ``max_step``; ``None`` before any step), ``wall_seconds`` (the calls' whole wall time: integrating,
    finding and solving contacts), ``integrator_seconds`` (the integrator's share), the integrator's ``error_estimate``
    (the sum of its local error estimates, ``None`` for methods without one); contact counters (``qp_solves``, the
    contact programs solved, ``collisions``, ``impulses``, ``bisection_steps``, ``collision_checks``, ``islands``,
    ``sleepers`` (actors asleep at the end, either mode),
    ``max_penetration``, ``contact_residual`` (fast mode's soft step: the largest distance in m/s of a step's end
    from the exact contact conditions), ``step_error`` (fast mode with ``step_doubling=True``: the largest difference
    in metres between a step and its two halves; ``None`` without), ``collision_seconds``, ``contact_seconds`` and its share
    ``program_seconds``, building the contact programs: accurate mode's, and fast mode's soft rows: zero wherever a
    stage never ran); ``energy_change`` (J, every mode: the change of kinetic plus gravity's and the
    springs' potential energy over the steps reported; friction, damping and restitution below one take energy out,
    so without loads that do work a rise is the method's error) and ``energy_gain`` (fast mode: the largest rise over
    one step, the energy a step added; ``None`` in the other modes);
    accurate
    mode's contact steps (``contact_steps``, ``contact_rejected``, their largest error estimate ``contact_error`` in
    metres and smallest step ``contact_min_step``; ``None`` before any; ``contact_tolerance``, the tolerance in force in
    metres, the settings' or the default from the scene's size); how often each
    force loop ran (``evaluations``, ``spring_evaluations``, ``load_evaluations``, ``callback_calls``,
    ``projections``); and ``stages_ran``, the stages that ran, in pipeline order (compare with ``World.plan()``).
    ``str(report)`` is the library's table for a person: which mode ran (and when to pick the other), one error
    line in metres, steps, contact, energy and wall time; ``report.details()`` adds the integrator's counters, the
    force loops, the time's split, fast mode's soft-step residual and the stages that ran.
    """

    __slots__ = ("_fields", "_text", "_details")
    _fields: dict[str, Any]
    _text: str
    _details: str

    def __init__(self, fields: dict[str, Any]) -> None:
        fields = dict(fields)
        object.__setattr__(self, "_text", fields.pop("_text", ""))
        object.__setattr__(self, "_details", fields.pop("_details", ""))
        object.__setattr__(self, "_fields", fields)

    def __getattr__(self, name: str) -> Any:
        try:
            return self._fields[name]
        except KeyError:
            raise AttributeError(f"Report has no field {name!r}") from None

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("a Report is read-only")

    def __dir__(self) -> list[str]:
        return sorted(set(super().__dir__()) | set(self._fields))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Report) and self._fields == other._fields

    def __hash__(self) -> int:
        return hash(tuple(sorted((k, str(v)) for k, v in self._fields.items())))

    def __reduce__(self) -> tuple[type[Report], tuple[dict[str, Any]]]:
        return (Report, ({**self._fields, "_text": self._text, "_details": self._details},))

    def fields(self) -> list[str]:
        """The field names, in the library's order."""
        return list(self._fields)

    def as_dict(self) -> dict[str, Any]:
        """The fields as a dict."""
        return dict(self._fields)

    def __repr__(self) -> str:
        return "Report(" + ", ".join(f"{k}={v!r}" for k, v in self._fields.items()) + ")"

    def __str__(self) -> str:
        return self._text

    def details(self) -> str:
        """The long form of ``str(report)``: every counter, the time's split and the stages that ran."""
        return self._details
