"""The results table of the command line's data contract (``docs/model.md``).

Columns ``t, x, y, phi``, then for each leg ``L`` in ``A, B, C`` (all of A's
columns first) ``lambda10_L, dlambda10_L, ddlambda10_L, lambda32_L,
dlambda32_L, ddlambda32_L, f10_L, p10_L, f21y_L, f21z_L, n10_L, m10_L, n32_L,
m32_L``; with a robot's ``[friction]`` 9 more: ``fric10_L, fric21_L, fric32_L``
for each leg (:data:`FRICTION_COLUMNS`).

>>> RESULT_COLUMNS[:5]
('t', 'x', 'y', 'phi', 'lambda10_A')
>>> len(RESULT_COLUMNS)
46
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .dynamics import InverseDynamics
from .geometry import LEGS
from .kinematics import Kinematics

__all__ = [
    "FRICTION_COLUMNS",
    "PER_LEG_COLUMNS",
    "RESULT_COLUMNS",
    "result_columns",
    "results_table",
]

#: Per-leg quantities, in the contract's order.
PER_LEG_COLUMNS: tuple[str, ...] = (
    "lambda10",
    "dlambda10",
    "ddlambda10",
    "lambda32",
    "dlambda32",
    "ddlambda32",
    "f10",
    "p10",
    "f21y",
    "f21z",
    "n10",
    "m10",
    "n32",
    "m32",
)

#: Every column of ``results.csv``, in order.
RESULT_COLUMNS: tuple[str, ...] = ("t", "x", "y", "phi") + tuple(
    f"{quantity}_{leg}" for leg in LEGS for quantity in PER_LEG_COLUMNS
)


#: The 9 columns after the 46 when the robot has ``[friction]``, legs A, B, C in order.
FRICTION_COLUMNS: tuple[str, ...] = tuple(
    f"{quantity}_{leg}" for leg in LEGS for quantity in ("fric10", "fric21", "fric32")
)


def result_columns(friction: bool) -> tuple[str, ...]:
    """The columns of ``results.csv``: the 46, and the 9 friction columns with ``friction``.

    >>> len(result_columns(True)), result_columns(True)[46:49]
    (55, ('fric10_A', 'fric21_A', 'fric32_A'))
    """
    return RESULT_COLUMNS + (FRICTION_COLUMNS if friction else ())


def results_table(kin: Kinematics, dyn: InverseDynamics) -> dict[str, NDArray[np.float64]]:
    """Every column of ``results.csv`` as a named array ``(N,)`` (or ``()``), in order.

    >>> from prp3 import Robot, inverse_dynamics, paper_motion
    >>> table = results_table(*inverse_dynamics(Robot(), paper_motion("vertical", samples=4)))
    >>> list(table) == list(RESULT_COLUMNS), table["f10_A"].shape
    (True, (4,))
    """
    motion, geo = kin.motion, kin.geometry
    per_leg = {
        "lambda10": geo.lambda10,
        "dlambda10": kin.dlambda10,
        "ddlambda10": kin.ddlambda10,
        "lambda32": geo.lambda32,
        "dlambda32": kin.dlambda32,
        "ddlambda32": kin.ddlambda32,
        "f10": dyn.f10,
        "p10": dyn.p10,
        "f21y": dyn.f21y,
        "f21z": dyn.f21z,
        "n10": dyn.n10,
        "m10": dyn.m10,
        "n32": dyn.n32,
        "m32": dyn.m32,
    }
    table: dict[str, NDArray[np.float64]] = {
        "t": motion.t,
        "x": motion.pose[..., 0],
        "y": motion.pose[..., 1],
        "phi": motion.pose[..., 2],
    }
    for j, leg in enumerate(LEGS):
        for quantity in PER_LEG_COLUMNS:
            table[f"{quantity}_{leg}"] = per_leg[quantity][..., j]
    if dyn.fric10 is not None and dyn.fric21 is not None and dyn.fric32 is not None:
        friction = {"fric10": dyn.fric10, "fric21": dyn.fric21, "fric32": dyn.fric32}
        for j, leg in enumerate(LEGS):
            for quantity, values in friction.items():
                table[f"{quantity}_{leg}"] = values[..., j]
    return table
