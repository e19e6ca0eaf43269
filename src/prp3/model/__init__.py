"""The robot: its parameters (`robot`), its effects as elements (`elements`) and the motion (`motion`)."""

from __future__ import annotations

from prp3.moved_paths import moved_attribute


def __getattr__(name: str) -> object:
    """The names this module had in prp3 0.1, now elsewhere (a DeprecationWarning names where)."""
    return moved_attribute(__name__, name)
