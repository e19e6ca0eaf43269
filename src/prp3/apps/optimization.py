"""Optimization of designs on Dask: differential evolution, each generation on the workers.

:func:`optimize_design` minimises an objective under constraints
(:func:`prp3.apps.design_objective.penalized_objective`) with
:func:`scipy.optimize.differential_evolution`, the population of every
generation evaluated on the Dask workers through its ``workers`` map
(:class:`DaskMap`).

dask and scipy are imported inside the functions (the ``design`` extra).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from prp3.apps.cluster import ClientOrFactory, Progress, using, worker_count
from prp3.apps.design import DesignEvaluator, RowEvaluator
from prp3.apps.design_evaluation import evaluate_rows
from prp3.apps.design_objective import INFEASIBLE, DesignObjective, OptimizeSpec

if TYPE_CHECKING:
    from dask.distributed import Client

__all__ = [
    "DaskMap",
    "Optimizable",
    "OptimizeOutcome",
    "optimize_design",
]

FloatArray = NDArray[np.float64]


# ------------------------------------------------------------------ optimization
class Optimizable(Protocol):
    """What :func:`optimize_design` needs of a spec: :class:`~prp3.apps.sweep_spec.SweepSpec`
    (the 3-PRP), or one robot of a :class:`~prp3.apps.spatial_design.SpatialSweepSpec`."""

    @property
    def seed(self) -> int:
        """Seed of the differential evolution."""
        ...

    @property
    def evaluator(self) -> DesignEvaluator | RowEvaluator:
        """Evaluates designs ``(k, p)``."""
        ...

    @property
    def optimize(self) -> OptimizeSpec:
        """The objective, its constraints and the settings."""
        ...

    @property
    def paths(self) -> tuple[str, ...]:
        """Key paths of the parameters."""
        ...

    @property
    def bounds(self) -> list[tuple[float, float]]:
        """``(low, high)`` of every parameter."""
        ...


class DaskMap:
    """A ``map(func, iterable)`` for ``differential_evolution(workers=...)`` on Dask.

    The members of a generation are split into one part per worker, each
    evaluated by a Dask task; every evaluation is recorded in :attr:`history`
    as ``(generation, x, value)``.  The function goes to the workers once
    (scattered to every worker on its first use, ``broadcast=True``), and
    every task refers to that copy: a generation sends only its members.
    With ``batch``, a part is evaluated by one call ``batch.many(members)``
    (``(k, p)`` -> ``(k,)``, the same values as ``func`` one by one) instead
    of ``func`` member by member.
    """

    def __init__(
        self,
        client: Client,
        batch: DesignObjective | None = None,
        progress: Callable[[int], None] | None = None,
    ) -> None:
        self.client = client
        self.batch = batch
        self.progress = progress
        self.generation = 0
        self.history: list[tuple[int, FloatArray, float]] = []
        self._scattered: tuple[object, Any] | None = None  # (function, its future)

    def _shared(self, func: object) -> Any:
        """The future of ``func`` on the workers, scattered the first time it is seen."""
        if self._scattered is None or self._scattered[0] is not func:
            future = self.client.scatter(func, broadcast=True, hash=False)
            self._scattered = (func, future)
        return self._scattered[1]

    def __call__(self, func: Callable[[Any], float], iterable: Iterable[Any]) -> list[float]:
        """Evaluate ``func`` on every member of ``iterable`` on the workers, in order."""
        members = [np.asarray(x, dtype=np.float64) for x in iterable]
        parts = max(1, min(len(members), worker_count(self.client)))
        split = [list(part) for part in np.array_split(np.arange(len(members)), parts)]
        if self.batch is not None:
            shared = self._shared(self.batch)
            futures = [
                self.client.submit(_apply_many, shared, np.stack([members[k] for k in part]),
                                   pure=False)
                for part in split
                if part
            ]  # fmt: skip
        else:
            shared = self._shared(func)
            futures = [
                self.client.submit(_apply, shared, [members[k] for k in part], pure=False)
                for part in split
                if part
            ]
        values = [float(v) for part in self.client.gather(futures) for v in part]
        for x, value in zip(members, values, strict=True):
            self.history.append((self.generation, x, value))
        self.generation += 1
        if self.progress is not None:
            self.progress(self.generation)
        return values


def _apply(func: Callable[[Any], float], members: list[FloatArray]) -> list[float]:
    return [float(func(x)) for x in members]


def _apply_many(objective: DesignObjective, members: FloatArray) -> list[float]:
    return [float(v) for v in objective.many(members)]


@dataclass(frozen=True)
class OptimizeOutcome:
    """Result of :func:`optimize_design`.

    Attributes
    ----------
    x : ndarray (p,)
        Parameter values of the best design.
    objective : float
        Its objective (``>= INFEASIBLE`` when no feasible design was found).
    feasible : bool
    row : dict
        Its row of the design table (every column).
    generations, evaluations : int
    message : str
        scipy's message.
    history : dict
        Columns ``generation``, the parameters, ``objective`` (NaN when
        infeasible), ``violation`` (0 when feasible) of every evaluation.
    """

    x: FloatArray
    objective: float
    feasible: bool
    row: dict[str, Any]
    generations: int
    evaluations: int
    message: str
    history: dict[str, FloatArray]


def optimize_design(
    spec: Optimizable, client: ClientOrFactory, *, progress: Progress | None = None
) -> OptimizeOutcome:
    """Minimise ``spec.optimize.objective`` subject to its constraints over the parameter ranges.

    ``client`` is a Dask client (used, left open) or a callable of no
    argument that makes one or a context manager giving one (as
    :func:`~prp3.apps.sweep.run_sweep` takes it).  ``progress(generations_done, maxiter + 1)``
    is called after every generation (the initial population counts as one;
    the run may stop before the last one when it converges).

    :func:`scipy.optimize.differential_evolution` (``best1bin``, Latin-hypercube
    initial population, ``rng = seed``, no polishing, deferred updating) with
    the population of each generation evaluated on the Dask workers.
    Infeasible designs (a failed task or a violated constraint) get the
    objective ``INFEASIBLE + violation`` (:func:`prp3.apps.design_objective.penalized_objective`).
    """
    from scipy.optimize import differential_evolution

    settings = spec.optimize
    objective = DesignObjective(spec.evaluator, settings)
    total = settings.maxiter + 1
    report = None if progress is None else (lambda done: progress(min(done, total), total))
    with using(client, "client") as dask:
        mapper = DaskMap(dask, batch=objective, progress=report)
        result = differential_evolution(
            objective,
            spec.bounds,
            maxiter=settings.maxiter,
            popsize=settings.popsize,
            tol=settings.tol,
            rng=spec.seed,
            polish=False,
            init="latinhypercube",
            updating="deferred",
            workers=mapper,
        )
    if progress is not None:
        progress(total, total)
    x = np.asarray(result.x, dtype=np.float64)
    columns = evaluate_rows(spec.evaluator, x[None, :])
    text = spec.evaluator.text_columns
    row = {name: (str(v[0]) if name in text else float(v[0])) for name, v in columns.items()}
    generation = np.array([g for g, _, _ in mapper.history], dtype=np.float64)
    xs = np.array([x for _, x, _ in mapper.history]).reshape(-1, len(spec.paths))
    value = np.array([v for _, _, v in mapper.history])
    feasible = value < INFEASIBLE
    history: dict[str, FloatArray] = {"generation": generation}
    history |= {path: xs[:, j] for j, path in enumerate(spec.paths)}
    history["objective"] = np.where(feasible, value, np.nan)
    history["violation"] = np.where(feasible, 0.0, value - INFEASIBLE)
    return OptimizeOutcome(
        x=x,
        objective=float(result.fun),
        feasible=bool(result.fun < INFEASIBLE),
        row=row,
        generations=int(result.nit),
        evaluations=int(result.nfev),
        message=str(result.message),
        history=history,
    )
