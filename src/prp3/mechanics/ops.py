"""The kinds of number the kernel runs on, each as an :class:`Ops` of the functions it needs.

The stages of the kernel (:mod:`prp3.mechanics.joint_motion`,
:mod:`prp3.mechanics.wrenches`, :mod:`prp3.mechanics.virtual_work`) use only
``+ − × ÷`` and the functions of an :class:`Ops`, so the very same source runs on

* plain floats with :data:`MATH` — one sample;
* 1-D float64 arrays with :data:`NUMPY` — the numpy engine;
* sympy expressions with :func:`sympy_ops` — the symbolic solution, the
  regressor and the generated C code;
* machine code: :mod:`prp3.engines.numba` gives numba an ``Ops`` of
  :mod:`math`'s functions of its own.

>>> MATH.sqrt(4.0), float(NUMPY.tanh(0.0)), MATH.atan2(0.0, -1.0)
(2.0, 0.0, 3.141592653589793)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["MATH", "NUMPY", "Legs", "Ops", "Value", "sympy_ops"]

#: A number of the kernel: a float, a 1-D float64 array or a sympy expression.
Value = Any
#: One value per leg, ``(A, B, C)``.
Legs = tuple[Value, Value, Value]


@dataclass(frozen=True)
class Ops:
    """The functions the kernel needs, for one kind of number."""

    name: str
    cos: Callable[[Value], Value]
    sin: Callable[[Value], Value]
    sqrt: Callable[[Value], Value]
    tanh: Callable[[Value], Value]
    abs: Callable[[Value], Value]
    sign: Callable[[Value], Value]
    #: ``atan2(y, x)``: the angle of ``(x, y)`` in ``[−π, π]``, signed zeros as C's ``atan2``.
    atan2: Callable[[Value, Value], Value]


def _sign_float(value: float) -> float:
    return (value > 0.0) - (value < 0.0)


#: Plain Python floats (:mod:`math`).
MATH = Ops("math", math.cos, math.sin, math.sqrt, math.tanh, abs, _sign_float, math.atan2)
#: 1-D float64 arrays (numpy ufuncs).
NUMPY = Ops("numpy", np.cos, np.sin, np.sqrt, np.tanh, np.abs, np.sign, np.arctan2)


def sympy_ops() -> Ops:
    """The kernel's functions for sympy expressions (sympy imported on demand)."""
    import sympy

    return Ops(
        "sympy", sympy.cos, sympy.sin, sympy.sqrt, sympy.tanh, sympy.Abs, sympy.sign, sympy.atan2
    )
