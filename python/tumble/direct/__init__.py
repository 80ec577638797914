"""Directing the outcome: the physically valid run that lands where the animator wants. ``search`` varies the
starts of chosen bodies within bounds (position, orientation, velocity, spin, friction, restitution) and runs
copies of the world until one meets the goal (a body at rest at a place, a face up, passing through a region,
touching another, at a keyframed pose, or any cost of the run), preferring the smallest change from the user's
start. The motion stays physical: only the start changes."""

from ._found import Alternative, Found, sensitivity
from ._goals import All, Goal, face_up, passes_through, pose_at, rest_at, touches
from ._search import search
from ._vary import Vary

__all__ = ["search", "Vary", "Found", "Alternative", "Goal", "All", "rest_at", "face_up", "passes_through",
           "touches", "pose_at", "sensitivity"]
