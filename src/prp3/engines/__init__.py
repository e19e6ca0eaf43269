"""How the mechanics runs: the engine choice and the numpy engine (`select`), the numba engine (`numba`), the validated entries (`entries`), the straight-line tracer of the design sweeps (`trace`)."""

from __future__ import annotations

from prp3.moved_paths import moved_attribute


def __getattr__(name: str) -> object:
    """The names this module had in prp3 0.1, now elsewhere (a DeprecationWarning names where)."""
    return moved_attribute(__name__, name)
