"""What designs are compared by: a quantity of their rows, the Pareto front, the objective.

:func:`quantity` is a column of the design table or an aggregate over the legs,
:func:`pareto_front` the non-dominated designs of two quantities, and
:func:`penalized_objective` the objective of the ``[optimize]`` table
(:class:`OptimizeSpec`) with its constraints as penalties: the function
:class:`DesignObjective` that the optimization of designs minimises
(:func:`prp3.apps.optimization.optimize_design`).  Plain numpy, as
:func:`prp3.apps.design_evaluation.evaluate_designs` that gives the rows of the 3-PRP
(any :class:`~prp3.apps.design.RowEvaluator`'s rows: those of the spatial robots too).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.apps.design import AGGREGATES, DesignEvaluator, RowEvaluator
from prp3.apps.design_evaluation import evaluate_rows
from prp3.errors import (
    ParameterError,
    Prp3Error,
)
from prp3.validation import LEGS, check_integer, check_real, check_scalar

__all__ = [
    "INFEASIBLE",
    "DesignObjective",
    "OptimizeSpec",
    "pareto_front",
    "penalized_objective",
    "quantity",
]

FloatArray = NDArray[np.float64]


def quantity(columns: Mapping[str, Any], name: str) -> FloatArray:
    """A column of the design table, or an aggregate ``peak_f10`` = max over legs A, B, C.

    Raises
    ------
    Prp3Error
        An unknown name (lists the known ones).

    >>> quantity({"peak_f10_A": np.array([1.0]), "peak_f10_B": np.array([3.0]),
    ...           "peak_f10_C": np.array([2.0])}, "peak_f10").tolist()
    [3.0]
    """
    if name in AGGREGATES and all(f"{name}_{leg}" in columns for leg in LEGS):
        return np.asarray(
            np.max([np.asarray(columns[f"{name}_{leg}"], dtype=np.float64) for leg in LEGS], axis=0)
        )
    if name in columns and name != "status":
        return np.asarray(columns[name], dtype=np.float64)
    known = [c for c in columns if c != "status"] + [a for a in AGGREGATES if f"{a}_A" in columns]
    raise Prp3Error(f"unknown column {name!r} (expected one of: {', '.join(known)})")


def pareto_front(
    x: FloatArray, y: FloatArray, *, maximize_x: bool = False, maximize_y: bool = False
) -> NDArray[np.int64]:
    """Indices of the non-dominated points of ``(x, y)``, sorted by ``x``.

    A point is dominated when another one is at least as good in both
    coordinates and better in one (smaller, or larger with ``maximize_*``).
    NaN points are never on the front.

    >>> pareto_front(np.array([1.0, 2.0, 3.0, 2.5]), np.array([3.0, 1.0, 0.5, 2.0])).tolist()
    [0, 1, 2]
    """
    x, y = check_real("x", x, ParameterError), check_real("y", y, ParameterError)
    if x.ndim != 1 or x.shape != y.shape:
        raise ParameterError(f"x and y must have the same shape (N,), got {x.shape} and {y.shape}")
    sx = -x if maximize_x else x
    sy = -y if maximize_y else y
    valid = np.flatnonzero(np.isfinite(sx) & np.isfinite(sy))
    order = valid[np.lexsort((sy[valid], sx[valid]))]
    front: list[int] = []
    best = math.inf
    for index in order.tolist():
        if sy[index] < best:
            front.append(index)
            best = float(sy[index])
    result = np.array(front, dtype=np.int64)
    return result[np.argsort(x[result], kind="stable")]


# ------------------------------------------------------------------ optimization
#: Objective of an infeasible design: this plus its total relative violation, so that
#: every feasible design is better and, among infeasible ones, the less violating.
INFEASIBLE: float = 1e12


@dataclass(frozen=True)
class OptimizeSpec:
    """The ``[optimize]`` table: objective, constraints and differential-evolution settings.

    Attributes
    ----------
    objective : str
        A column of the design table, or an aggregate (``peak_f10``: max over legs).
    constraints : tuple of (name, low, high)
        Each quantity must lie in ``[low, high]`` (``±inf`` when not given).
    maxiter, popsize : int
        Generations and population multiplier of
        :func:`scipy.optimize.differential_evolution`.
    tol : float
        Its relative tolerance of convergence.
    """

    objective: str = "peak_f10"
    constraints: tuple[tuple[str, float, float], ...] = ()
    maxiter: int = 30
    popsize: int = 10
    tol: float = 0.01

    def __post_init__(self) -> None:
        check_integer("maxiter", self.maxiter, 1, 100_000, subject="optimize")
        check_integer("popsize", self.popsize, 1, 10**4, subject="optimize")
        object.__setattr__(
            self, "tol", check_scalar("tol", self.tol, positive=True, subject="optimize")
        )


def penalized_objective(optimize: OptimizeSpec, columns: Mapping[str, Any]) -> FloatArray:
    """The objective of designs, infeasible ones replaced by ``INFEASIBLE + violation``.

    The violation of a constraint ``low <= q <= high`` is ``(low − q)/|low|`` or
    ``(q − high)/|high|`` (relative; absolute when the bound is 0); a design
    whose ``status`` is not ``ok`` has violation ``1000``.

    >>> spec = OptimizeSpec("peak_f10", constraints=(("energy", -math.inf, 2.0),))
    >>> columns = {"status": np.array(["ok", "ok", "stroke"]), "energy": np.array([1.0, 3.0, 1.0]),
    ...            **{f"peak_f10_{leg}": np.array([5.0, 4.0, np.nan]) for leg in LEGS}}
    >>> (penalized_objective(spec, columns) - [0.0, INFEASIBLE, INFEASIBLE]).tolist()
    [5.0, 0.5, 1000.0]
    """
    value = quantity(columns, optimize.objective)
    violation = np.zeros_like(value)
    for name, low, high in optimize.constraints:
        q = quantity(columns, name)
        with np.errstate(invalid="ignore"):
            below = np.where(q < low, (low - q) / (abs(low) or 1.0), 0.0)
            above = np.where(q > high, (q - high) / (abs(high) or 1.0), 0.0)
        violation += np.where(np.isnan(q), 1.0, below + above)
    failed = (np.asarray(columns["status"]) != "ok") | ~np.isfinite(value)
    violation = np.where(failed, 1000.0, violation)
    return np.asarray(np.where(violation > 0.0, INFEASIBLE + violation, value))


@dataclass(frozen=True, eq=False)
class DesignObjective:
    """The objective of :func:`penalized_objective` for one design ``x`` (picklable).

    This is the function :func:`scipy.optimize.differential_evolution`
    minimises; its ``workers`` map calls it on the Dask workers.
    """

    evaluator: DesignEvaluator | RowEvaluator
    optimize: OptimizeSpec

    def __call__(self, x: FloatArray) -> float:
        """``penalized_objective`` of the design with parameter values ``x`` (shape (p,))."""
        return float(self.many(np.asarray(x, dtype=np.float64)[None, :])[0])

    def many(self, xs: FloatArray) -> FloatArray:
        """``penalized_objective`` of designs ``xs`` ``(k, p)``, evaluated together: ``(k,)``.

        The value of each design is the one :meth:`__call__` gives it alone.
        """
        columns = evaluate_rows(self.evaluator, np.asarray(xs, dtype=np.float64))
        return penalized_objective(self.optimize, columns)
