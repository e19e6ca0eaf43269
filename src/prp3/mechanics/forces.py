"""The one result type of the inverse dynamics, whatever the method.

:class:`InverseDynamics` holds the actuator forces, input powers and every
joint reaction of the three legs; :mod:`prp3.analysis.inverse_dynamics` (the kernel),
:mod:`prp3.references.paper` (the paper's matrices as printed) and
:mod:`prp3.references.newton_euler` all return it.

Sign conventions (``docs/model.md``): ``f10_i`` acts on piston i along ``+e_i``;
``f21y_i, f21z_i`` are the components along ``n_i`` and ``e_i`` of the force of
piston i on link 2 at ``P_i``; ``n10_i`` (along ``n_i``) and ``m10_i`` (about
``P_i``) are the guide's reaction on piston i; ``n32_i`` (along ``d⊥_i``) and
``m32_i`` (about ``P_i``) are the reaction of link 2 on the platform.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.validation import require_finite

__all__ = ["FORCE_NAMES", "FRICTION_NAMES", "InverseDynamics", "checked"]

FloatArray = NDArray[np.float64]

#: Names of the per-leg force quantities, in the order of the results table.
FORCE_NAMES: tuple[str, ...] = ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32")
#: Names of the per-leg friction forces (with a robot's ``[friction]``).
FRICTION_NAMES: tuple[str, ...] = ("fric10", "fric21", "fric32")


@dataclass(frozen=True)
class InverseDynamics:
    """Actuator forces, input powers and joint reactions of every leg.

    Every array has shape ``(..., 3)``: the batch shape of the motion, legs
    A, B, C last.

    Attributes
    ----------
    f10 : ndarray
        Force of actuator i on its piston along ``+e_i`` (N), eq. (23).
    p10 : ndarray
        Input power ``f10·λ̇10`` of actuator i (W).
    f21y, f21z : ndarray
        Force of piston i on link 2 at ``P_i`` along ``n_i`` and ``e_i`` (N), eqs. (24), (25).
    n10 : ndarray
        Reaction of the base guide on piston i along ``n_i`` (N).
    m10 : ndarray
        Reaction moment of the base guide on piston i about ``P_i`` (N·m).
    n32 : ndarray
        Reaction of link 2 on the platform along ``d⊥_i`` (N).
    m32 : ndarray
        Reaction moment of link 2 on the platform about ``P_i`` (N·m).
    method : str
        ``"fast"``, ``"paper"`` or ``"newton-euler"``.
    fric10, fric21, fric32 : ndarray or None
        With a robot's ``[friction]``: the force of the guide on piston i along
        ``e_i`` (N), the moment of piston i on link 2 about ``z0`` (N·m), the
        force of link 2 on the platform along ``d_i`` (N); else ``None``.
    iterations : ndarray or None
        With ``μ`` terms of friction: the iterations of the implicit solve of
        each sample (batch shape); else ``None``.
    near_lock : ndarray of bool or None
        With ``μ`` terms, by the kernel (``method="fast"``): whether each
        sample is near a lock of the joint friction (batch shape): the
        solution reached continuously from ``μ = 0`` would end with ``μ``
        coefficients :data:`prp3.mechanics.implicit_friction.NEAR_LOCK_MU` times larger, and a
        second solution may lie close by; else ``None``.
    """

    f10: FloatArray
    p10: FloatArray
    f21y: FloatArray
    f21z: FloatArray
    n10: FloatArray
    m10: FloatArray
    n32: FloatArray
    m32: FloatArray
    method: str
    fric10: FloatArray | None = None
    fric21: FloatArray | None = None
    fric32: FloatArray | None = None
    iterations: FloatArray | None = None
    near_lock: NDArray[Any] | None = (
        None  # of bool (Any: the methods build results from dicts of float arrays)
    )


def checked(result: InverseDynamics, times: FloatArray) -> InverseDynamics:
    """``result`` if every force is finite, else a TrajectoryError naming the sample."""
    names = FORCE_NAMES + (FRICTION_NAMES if result.fric10 is not None else ())
    require_finite({name: getattr(result, name) for name in names}, times.shape, "motion", times)
    return result
