"""Validation helpers shared by the library's public functions (internal).

>>> real_array("pose", [0, 1.5, 2], TrajectoryError).dtype
dtype('float64')
>>> real_array("pose", ["0", "1"], TrajectoryError)
Traceback (most recent call last):
...
prp3.errors.TrajectoryError: pose must be an array of real numbers, got text (dtype <U1)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .errors import Prp3Error, TrajectoryError

__all__ = ["first_non_finite", "real_array", "require_finite"]

_KINDS = {"b": "booleans", "c": "complex numbers", "U": "text", "S": "bytes", "O": "objects"}


def real_array(name: str, value: Any, error: type[Prp3Error]) -> NDArray[np.float64]:
    """A new float64 array of ``value``; text, booleans, complex numbers and objects are refused."""
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raise error(f"{name} must be an array of real numbers, got {value!r}") from None
    if raw.dtype.kind not in "iuf":
        what = _KINDS.get(raw.dtype.kind, "values")
        raise error(
            f"{name} must be an array of real numbers, got {what} (dtype {raw.dtype})"
        ) from None
    return raw.astype(np.float64)


def first_non_finite(
    arrays: Mapping[str, NDArray[np.float64]], batch: tuple[int, ...]
) -> tuple[int, str] | None:
    """``(sample, name)`` of the first non-finite value of per-sample ``arrays``, or None."""
    samples = int(np.prod(batch)) if batch else 1
    first: tuple[int, str] | None = None
    for name, array in arrays.items():
        flat = np.asarray(array).reshape(samples, -1)
        bad = ~np.isfinite(flat).all(axis=1)
        if bad.any():
            index = int(np.argmax(bad))
            if first is None or index < first[0]:
                first = (index, name)
    return first


def require_finite(
    arrays: Mapping[str, NDArray[np.float64]],
    batch: tuple[int, ...],
    what: str,
    times: NDArray[np.float64] | None = None,
) -> None:
    """Raise :class:`TrajectoryError` naming the first sample whose results overflowed.

    The inputs are validated finite, so a non-finite result means that the
    motion or the parameters are too large for float64.
    """
    found = first_non_finite(arrays, batch)
    if found is None:
        return
    index, name = found
    when = f", t = {float(np.asarray(times).reshape(-1)[index]):.9g} s" if times is not None else ""
    raise TrajectoryError(
        f"{what}: the results overflow at sample {index}{when}: {name} is not finite; "
        "the motion or the robot's parameters are too large for double precision"
    )
