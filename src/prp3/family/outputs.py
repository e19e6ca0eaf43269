"""The 64 result columns of a family robot (docs/family.md §7) and the three routes by name.

>>> len(FAMILY_COLUMNS), FAMILY_COLUMNS[:5], FAMILY_COLUMNS[-1]
(64, ('t', 'x', 'y', 'phi', 'q1_A'), 'm3_C')
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.family.mechanics import FamilySolution, check_inputs, family_kinematics, fast_dynamics
from prp3.family.model import FamilyRobot
from prp3.family.newton_euler import newton_euler_dynamics
from prp3.family.paper import paper_dynamics
from prp3.model.motion import Motion, name_overflow_input
from prp3.validation import LEGS, check_choice

__all__ = [
    "DEFAULT_ENGINE",
    "FAMILY_COLUMNS",
    "FAMILY_ENGINES",
    "FAMILY_METHODS",
    "LEG_COLUMNS",
    "family_inverse_dynamics",
    "family_results_table",
]

FloatArray = NDArray[np.float64]

#: The per-leg columns, in order (``_A``, ``_B``, ``_C`` appended).
LEG_COLUMNS: tuple[str, ...] = (
    *(f"{name}{k}" for k in (1, 2, 3) for name in ("q", "dq", "ddq")),
    "tau",
    "p",
    *(f"{name}{k}" for k in (1, 2, 3) for name in ("fx", "fy", "m")),
)

#: The columns of ``results.csv`` in family form: ``t, x, y, phi``, then leg A's, B's, C's.
FAMILY_COLUMNS: tuple[str, ...] = (
    "t",
    "x",
    "y",
    "phi",
    *(f"{name}_{leg}" for leg in LEGS for name in LEG_COLUMNS),
)

#: The routes of :func:`family_inverse_dynamics`.
FAMILY_METHODS: tuple[str, ...] = ("fast", "paper", "newton-euler")

Method = Literal["fast", "paper", "newton-euler"]

#: The engines of the ``"fast"`` route: compiled by numba (:mod:`prp3.family.compiled`),
#: or on numpy arrays (:mod:`prp3.family.mechanics`).  The same results and refusals.
FAMILY_ENGINES: tuple[str, ...] = ("numba", "numpy")

Engine = Literal["numba", "numpy"]

#: ``"numba"`` when numba is installed (the ``numba`` extra), else ``"numpy"``.
DEFAULT_ENGINE: Engine = "numba" if importlib.util.find_spec("numba") is not None else "numpy"


def family_inverse_dynamics(
    robot: FamilyRobot, motion: Motion, method: Method = "fast", engine: Engine = DEFAULT_ENGINE
) -> FamilySolution:
    """Complete inverse dynamics of a family robot by one of the three routes.

    Parameters
    ----------
    robot : FamilyRobot
    motion : prp3.Motion
        ``N`` samples or one (results then lose the leading axis).
    method : {"fast", "paper", "newton-euler"}
    engine : {"numba", "numpy"}
        The engine of the ``"fast"`` route (the other routes have one):
        ``"numba"`` (:data:`DEFAULT_ENGINE` when numba is installed), one
        compiled loop over the samples, or ``"numpy"``, the same mechanics on
        arrays.  Both give the same results to round-off and the same errors.

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> solution = family_inverse_dynamics(FamilyRobot.default("3-RRR"), paper_motion("vertical", 5))
    >>> solution.tau.shape, solution.force.shape
    ((5, 3), (5, 3, 3, 2))
    """
    check_choice("method", method, FAMILY_METHODS)
    check_choice("engine", engine, FAMILY_ENGINES)
    try:
        if method == "paper":
            return paper_dynamics(robot, motion)
        if method == "newton-euler":
            return newton_euler_dynamics(robot, motion)
        if engine == "numba":
            return _compiled()(*check_inputs(robot, motion))
        return fast_dynamics(family_kinematics(robot, motion))
    except Prp3Error as error:  # results that overflow: the input that made them is named
        if isinstance(motion, Motion):
            raise name_overflow_input(error, motion) from None
        raise


def _compiled() -> Callable[[FamilyRobot, Motion], FamilySolution]:
    """:func:`prp3.family.compiled.compiled_dynamics`, imported (with numba) on first use only."""
    function = _ENGINE_CACHE.get("numba")
    if function is None:
        from prp3.family.compiled import compiled_dynamics

        function = _ENGINE_CACHE["numba"] = compiled_dynamics
    return function


_ENGINE_CACHE: dict[str, Callable[[FamilyRobot, Motion], FamilySolution]] = {}


def family_results_table(solution: FamilySolution) -> dict[str, FloatArray]:
    """The 64 columns of ``results.csv`` (float64 arrays of shape ``(N,)``), in order."""
    motion = solution.kinematics.motion
    pose = motion.pose.reshape(-1, 3)
    n = pose.shape[0]
    table: dict[str, FloatArray] = {
        "t": np.atleast_1d(motion.t).astype(np.float64),
        "x": pose[:, 0],
        "y": pose[:, 1],
        "phi": pose[:, 2],
    }
    q, dq, ddq = (a.reshape(n, 3, 3) for a in (solution.q, solution.dq, solution.ddq))
    tau, power = solution.tau.reshape(n, 3), solution.power.reshape(n, 3)
    force, moment = solution.force.reshape(n, 3, 3, 2), solution.moment.reshape(n, 3, 3)
    for j, leg in enumerate(LEGS):
        for k in range(3):
            table[f"q{k + 1}_{leg}"] = q[:, j, k]
            table[f"dq{k + 1}_{leg}"] = dq[:, j, k]
            table[f"ddq{k + 1}_{leg}"] = ddq[:, j, k]
        table[f"tau_{leg}"] = tau[:, j]
        table[f"p_{leg}"] = power[:, j]
        for k in range(3):
            table[f"fx{k + 1}_{leg}"] = force[:, j, k, 0]
            table[f"fy{k + 1}_{leg}"] = force[:, j, k, 1]
            table[f"m{k + 1}_{leg}"] = moment[:, j, k]
    return {name: np.ascontiguousarray(table[name]) for name in FAMILY_COLUMNS}
