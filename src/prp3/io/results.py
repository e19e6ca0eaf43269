"""The results table ``results.csv``: the registry of its quantities, its columns, the table.

The one place the name, unit, meaning and symbol of every output quantity is
given (:data:`OUTPUT_QUANTITIES`).  The columns of ``results.csv`` and Parquet
(:data:`RESULT_COLUMNS`, :data:`FRICTION_COLUMNS`, :data:`LOAD_RESULT_COLUMNS`,
:func:`result_columns`), the labels of the figures (:mod:`prp3.plotting.figures`)
and the units of the run summary (:func:`prp3.apps.runs.summary_text`) are derived
from it; :func:`results_table` fills the columns from a method's kinematics and
forces.  The file formats themselves are :mod:`prp3.io.tables` (CSV, Parquet),
:mod:`prp3.io.trajectory`, :mod:`prp3.io.measurements` and :mod:`prp3.io.forces`.

>>> RESULT_COLUMNS[:5]
('t', 'x', 'y', 'phi', 'lambda10_A')
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.errors import ParameterError
from prp3.mechanics.forces import InverseDynamics
from prp3.mechanics.kinematics import Kinematics
from prp3.validation import LEGS

__all__ = [
    "FRICTION_COLUMNS",
    "LOAD_RESULT_COLUMNS",
    "OUTPUT_QUANTITIES",
    "PER_LEG_COLUMNS",
    "RESULT_COLUMNS",
    "OutputQuantity",
    "output_quantity",
    "result_columns",
    "results_table",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class OutputQuantity:
    """One quantity of ``results.csv``: the one place its name, unit and meaning are given.

    The columns of ``results.csv`` and Parquet (:data:`RESULT_COLUMNS`,
    :data:`FRICTION_COLUMNS`), the labels of the figures
    (:mod:`prp3.plotting.figures`) and the units of the run summary
    (:func:`prp3.apps.runs.summary_text`) are derived from :data:`OUTPUT_QUANTITIES`.

    Attributes
    ----------
    name : str
        The column (``t``) or, for a per-leg quantity, the stem of its three
        columns ``name_A, name_B, name_C``.
    unit : str
        SI unit of the column.
    description : str
        Meaning and sign (``docs/model.md``, section *Quantities and signs*).
    per_leg : bool
        One column per leg A, B, C.
    symbol : str
        The paper's symbol (matplotlib mathtext), for labels.
    friction : bool
        Written only when the robot has ``[friction]`` (after the 46 columns).
    load : bool
        Written only when the motion has a time-varying load (a trajectory's
        ``fx, fy, mz``; the last columns).
    """

    name: str
    unit: str
    description: str
    per_leg: bool
    symbol: str
    friction: bool = False
    load: bool = False

    def columns(self) -> tuple[str, ...]:
        """Its columns: ``(name,)``, or ``name_A, name_B, name_C``.

        >>> OUTPUT_QUANTITIES["f10"].columns()
        ('f10_A', 'f10_B', 'f10_C')
        """
        return tuple(f"{self.name}_{leg}" for leg in LEGS) if self.per_leg else (self.name,)


def _quantities(*items: OutputQuantity) -> dict[str, OutputQuantity]:
    return {item.name: item for item in items}


#: Every output quantity of ``results.csv``, in the order of its columns.
OUTPUT_QUANTITIES: dict[str, OutputQuantity] = _quantities(
    OutputQuantity("t", "s", "time", False, "t"),
    OutputQuantity("x", "m", "x of the platform centre G, fixed frame", False, "x"),
    OutputQuantity("y", "m", "y of the platform centre G, fixed frame", False, "y"),
    OutputQuantity("phi", "rad", "orientation of the platform", False, "\\varphi"),
    OutputQuantity("lambda10", "m", "actuator displacement", True, "\\lambda_{10}"),
    OutputQuantity("dlambda10", "m/s", "actuator velocity", True, "\\dot\\lambda_{10}"),
    OutputQuantity("ddlambda10", "m/s²", "actuator acceleration", True, "\\ddot\\lambda_{10}"),
    OutputQuantity("lambda32", "m", "slide of the platform along link 2", True, "\\lambda_{32}"),
    OutputQuantity("dlambda32", "m/s", "its rate", True, "\\dot\\lambda_{32}"),
    OutputQuantity("ddlambda32", "m/s²", "its second rate", True, "\\ddot\\lambda_{32}"),
    OutputQuantity(
        "f10", "N", "force of actuator i on its piston along +e_i, through P_i", True, "f_{10}"
    ),
    OutputQuantity("p10", "W", "input power of actuator i, f10·dlambda10", True, "p_{10}"),
    OutputQuantity(
        "f21y", "N", "force of piston i on link 2 at P_i, along n_i", True, "f_{21y}"
    ),
    OutputQuantity(
        "f21z", "N", "force of piston i on link 2 at P_i, along e_i", True, "f_{21z}"
    ),
    OutputQuantity(
        "n10", "N", "reaction of the base guide on piston i, along n_i", True, "n_{10}"
    ),
    OutputQuantity(
        "m10", "N·m", "moment of that reaction about z0, taken about P_i", True, "m_{10}"
    ),
    OutputQuantity(
        "n32", "N", "reaction of link 2 on the platform, along d⊥_i", True, "n_{32}"
    ),
    OutputQuantity(
        "m32", "N·m", "moment of that reaction about z0, taken about P_i", True, "m_{32}"
    ),
    OutputQuantity(
        "fric10", "N", "friction force of the guide on piston i, along e_i", True,
        "f_{10}^{fr}", friction=True,
    ),
    OutputQuantity(
        "fric21", "N·m", "friction moment of piston i on link 2 about z0", True,
        "m_{21}^{fr}", friction=True,
    ),
    OutputQuantity(
        "fric32", "N", "friction force of link 2 on the platform, along d_i", True,
        "f_{32}^{fr}", friction=True,
    ),
    OutputQuantity(
        "fx", "N", "time-varying force of the environment on the platform at G, along x0",
        False, "f_x", load=True,
    ),
    OutputQuantity(
        "fy", "N", "time-varying force of the environment on the platform at G, along y0",
        False, "f_y", load=True,
    ),
    OutputQuantity(
        "mz", "N·m", "time-varying moment of the environment on the platform about z0",
        False, "m_z", load=True,
    ),
)  # fmt: skip

#: Per-leg quantities of the 46 columns, in the contract's order.
PER_LEG_COLUMNS: tuple[str, ...] = tuple(
    q.name for q in OUTPUT_QUANTITIES.values() if q.per_leg and not q.friction
)

#: Every column of ``results.csv``, in order.
RESULT_COLUMNS: tuple[str, ...] = tuple(
    q.name for q in OUTPUT_QUANTITIES.values() if not q.per_leg and not q.load
) + tuple(f"{quantity}_{leg}" for leg in LEGS for quantity in PER_LEG_COLUMNS)


#: The 9 columns after the 46 when the robot has ``[friction]``, legs A, B, C in order.
FRICTION_COLUMNS: tuple[str, ...] = tuple(
    f"{q.name}_{leg}" for leg in LEGS for q in OUTPUT_QUANTITIES.values() if q.friction
)


#: The 3 last columns when the motion has a time-varying load (the trajectory's ``fx, fy, mz``).
LOAD_RESULT_COLUMNS: tuple[str, ...] = tuple(q.name for q in OUTPUT_QUANTITIES.values() if q.load)


def output_quantity(column: str) -> OutputQuantity:
    """The quantity of a ``results.csv`` column (``f10_A`` or ``f10``).

    >>> q = output_quantity("m32_B")
    >>> q.name, q.unit
    ('m32', 'N·m')
    """
    stem, _, leg = column.rpartition("_")
    if stem in OUTPUT_QUANTITIES and leg in LEGS and OUTPUT_QUANTITIES[stem].per_leg:
        return OUTPUT_QUANTITIES[stem]
    if column in OUTPUT_QUANTITIES:
        return OUTPUT_QUANTITIES[column]
    raise ParameterError(f"{column!r} is not a column of results.csv")


def result_columns(friction: bool, load: bool = False) -> tuple[str, ...]:
    """The columns of ``results.csv``: the 46, the 9 friction columns with ``friction``,
    then ``fx, fy, mz`` with a time-varying ``load`` (a trajectory's load columns).

    >>> len(result_columns(True)), result_columns(True)[46:49]
    (55, ('fric10_A', 'fric21_A', 'fric32_A'))
    >>> result_columns(False, load=True)[46:]
    ('fx', 'fy', 'mz')
    """
    return (
        RESULT_COLUMNS
        + (FRICTION_COLUMNS if friction else ())
        + (LOAD_RESULT_COLUMNS if load else ())
    )


def results_table(kin: Kinematics, dyn: InverseDynamics) -> dict[str, NDArray[np.float64]]:
    """Every column of ``results.csv`` as a named array ``(N,)`` (or ``()``), in order.

    >>> from prp3 import Robot, inverse_dynamics, paper_motion
    >>> table = results_table(*inverse_dynamics(Robot(), paper_motion("vertical", samples=4)))
    >>> len(table), list(table)[:6], list(table)[-1], table["f10_A"].shape
    (46, ['t', 'x', 'y', 'phi', 'lambda10_A', 'dlambda10_A'], 'm32_C', (4,))
    """
    motion, geo = kin.motion, kin.geometry
    per_leg: dict[str, FloatArray | None] = {
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
        "fric10": dyn.fric10,
        "fric21": dyn.fric21,
        "fric32": dyn.fric32,
    }
    single = {
        "t": motion.t,
        "x": motion.pose[..., 0],
        "y": motion.pose[..., 1],
        "phi": motion.pose[..., 2],
    }
    table: dict[str, NDArray[np.float64]] = {}
    for quantity in OUTPUT_QUANTITIES.values():
        if not quantity.per_leg and not quantity.load:
            table[quantity.name] = single[quantity.name]
    friction = all(per_leg[q.name] is not None for q in OUTPUT_QUANTITIES.values() if q.friction)
    for group in (False, True) if friction else (False,):
        for j, leg in enumerate(LEGS):
            for quantity in OUTPUT_QUANTITIES.values():
                values = per_leg.get(quantity.name)
                if quantity.per_leg and quantity.friction == group and values is not None:
                    table[f"{quantity.name}_{leg}"] = values[..., j]
    if motion.load is not None:  # the time-varying load of the motion, last
        for k, name in enumerate(LOAD_RESULT_COLUMNS):
            table[name] = motion.load[..., k]
    return table
