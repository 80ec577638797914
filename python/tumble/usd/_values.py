"""Values read from a stage, as they were typed. USD stores most physics attributes (frictions, masses, velocities,
limits, drives, joint frames) and mesh points as float32, so a friction typed as 0.7 is stored as 0.699999988079071.
The shortest decimal that is the same float32 is what was typed (any decimal of up to 6 significant digits comes back
as itself) and, for a value that was computed instead, lies in the same float32 rounding interval as the stored one:
it carries no less than the stage holds. So every float32 attribute is read as that decimal (tumble's friction is 0.7
itself), and every number from a stage in a message is shown as it (``shown``). Double attributes (UsdGeom's sizes
and radii) and the transforms USD composes (in double, from float or double ops) are taken as they are."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

# the element types (C++ names) of float32 attributes, alone or in arrays
_FLOAT32 = {"float", "GfVec2f", "GfVec3f", "GfVec4f", "GfQuatf"}


class UsdImportWarning(UserWarning):
    """An approximation ``World.from_usd`` made in taking a stage (the stage is read all the same): its message is
    "prim path: attribute: what was taken"."""


def typed(values: Any) -> Any:
    """float32 values (a number or an array) as the shortest decimals that are the same float32s, in float64: 0.7
    for the stored 0.699999988079071 (numpy's shortest round-trip printing, then parsing); a float for a number,
    else an array."""
    out = np.asarray(values, dtype=np.float32).astype(str).astype(float)
    return float(out) if out.ndim == 0 else out


def value(attr: Any, default: Any = None) -> Any:
    """An attribute's value, ``default`` where it has none (or the attribute is not there). A float32 one as
    ``typed``; a quaternion (float or double) as an array (w, x, y, z), any other vector as it is in USD."""
    got = attr.Get() if attr and attr.IsValid() else None
    if got is None:
        return default
    element = attr.GetTypeName().scalarType.cppTypeName
    if element.startswith("GfQuat"):
        got = [got.GetReal(), *got.GetImaginary()]
    if element in _FLOAT32:
        return typed(got)
    return np.array(got, dtype=float) if element.startswith("GfQuat") else got


def shown(number: float) -> str:
    """A number read from a stage for a message: the shortest decimal that is its float32 ("0.7", not
    "0.699999988079071")."""
    return str(np.float32(number))


def note(notes: list[str]) -> None:
    """Each distinct note as a ``UsdImportWarning`` (a UserWarning), attributed to the caller of
    ``World.from_usd``."""
    for text in dict.fromkeys(notes):
        warnings.warn(text, UsdImportWarning, stacklevel=4)
