"""The figures of merit of designs: their forces over the task, reduced to the columns of a row.

:func:`evaluate_designs` runs the one kernel (:func:`prp3.mechanics.kernel.solve`,
reactions included), traced once per process into numpy code for blocks of
designs × the task's samples — the designs' constants as a column (their
kernel parameters traced the same way from their values, no robot built
per design), the states as a row: the operations of
:func:`prp3.engines.entries.paper_forces`, bit for bit, without its cost of preparing
each new robot — and reduces the forces to the columns of
``designs.parquet`` (:func:`prp3.apps.design.design_columns`):

* ``peak_f10_L``: ``max |f10_L|`` over the samples of all motions (N);
* ``peak_p10_L``: ``max |p10_L|`` (W);
* ``peak_f21_L``: ``max √(f21y_L² + f21z_L²)``, the force on the revolute joint (N);
* ``peak_n32_L``: ``max |n32_L|``, the normal force in the sleeve (N);
* ``energy``: ``Σ_motions ∫ Σ_L p10_L dt`` by the trapezoid rule over each
  motion's samples (J);
* with a stroke (``[limits] stroke``): ``workspace_area``, the area of the
  reachable region of ``G`` at ``φ = 0`` (m², :func:`prp3.workspace_slice`),
  and ``max_condition``, the largest Jacobian condition number over the
  task's poses (:func:`prp3.jacobian_condition`).

A design that cannot perform the task is a row too; its ``status`` says why
and its force columns are NaN:

* ``singular``: a pose of the task is at a singular orientation
  (:class:`~prp3.errors.SingularPoseError`);
* ``stroke``: a pose of the task needs an actuator displacement outside the
  design's ``[limits] stroke`` (:class:`~prp3.errors.UnreachablePoseError`);
* ``unreachable``: the design has no answer for the task: results that
  overflow, or a joint friction that locks (no inverse dynamics reached
  continuously from ``μ = 0``).

Everything here is plain numpy: the distribution over Dask workers and the
Parquet files are in :mod:`prp3.apps.sweep`.

>>> from prp3.apps.sweep_spec import design_values, sweep_spec
>>> spec = sweep_spec({"designs": 3, "sampling": "grid",
...                    "parameters": {"platform.mass": [2.0, 4.0]},
...                    "task": {"motions": ["vertical"], "samples": 31}})
>>> values = design_values(spec)
>>> values[:, 0].tolist()
[2.0, 3.0, 4.0]
>>> columns = evaluate_designs(spec.evaluator, values)
>>> [str(s) for s in columns["status"]], round(float(columns["peak_f10_A"][1]), 6)
(['ok', 'ok', 'ok'], 31.961794)
"""

from __future__ import annotations

import copy
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import fields
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.reachability import jacobian_condition
from prp3.analysis.workspace import workspace_slice
from prp3.apps.design import (
    AGGREGATES,
    DesignEvaluator,
    RowEvaluator,
    design_columns,
    design_robot,
    path_components,
)
from prp3.engines.trace import array_function, broadcast_function, trace
from prp3.errors import ParameterError
from prp3.mechanics.kernel import STATE_SYMBOLS, solve
from prp3.mechanics.ops import NUMPY, Ops
from prp3.mechanics.parameters import INERTIAL_FIELDS, KernelParameters, kernel_parameters
from prp3.model.elements import ELEMENTS
from prp3.model.robot import Robot
from prp3.validation import check_instance, check_real

__all__ = [
    "STATUSES",
    "evaluate_designs",
    "evaluate_rows",
]

FloatArray = NDArray[np.float64]

#: Values of the ``status`` column: the design performs the task, or why it cannot.
STATUSES: tuple[str, ...] = ("ok", "singular", "unreachable", "stroke")


_RESULTS = len(AGGREGATES) * 3 + 1  # peaks and energy


#: Designs × samples of one call of the design kernel: its work blocks stay in the CPU caches.
_BLOCK = 8192

PARAMETER_FIELDS = tuple(f.name for f in fields(KernelParameters))

#: Fields of :class:`~prp3.mechanics.parameters.KernelParameters` that may differ between the designs of
#: one kernel call: the kernel performs the same operations whatever their values (it
#: branches on the others: a zero smoothing is a sign, the mu terms are implicit), as each
#: element says (:attr:`prp3.model.element_base.Element.broadcast`).
BROADCAST_FIELDS: frozenset[str] = frozenset(INERTIAL_FIELDS) | {
    name for element in ELEMENTS for name in element.broadcast
}

#: Outputs of the design kernel: |f10|, |p10|, f21y² + f21z², |n32| (3 legs each; the peaks
#: are their maxima, the square root of the third taken after the maximum: the same
#: number, √ is monotonic), the input power Σ p10, and with a stroke λ10 (3 legs).
_PEAKS = 12
_SQUARED = slice(6, 9)
_POWER_ROW = 12
_LAMBDA_ROWS = slice(13, 16)

#: Inputs of the time-varying load of the samples (the trajectories' fx, fy, mz).
_LOAD_SYMBOLS: tuple[str, str, str] = ("fx", "fy", "mz")

#: The traced design kernels of this process: (varying fields, fixed fields, stroke) -> code.
_KERNELS: dict[tuple[Any, ...], Callable[..., None]] = {}


def _design_kernel(
    varying: tuple[str, ...], fixed: tuple[tuple[str, float], ...], stroke: bool,
    loaded: bool = False,
) -> Callable[..., None]:  # fmt: skip
    """:func:`prp3.mechanics.kernel.solve` traced for designs × samples (built once per process and key).

    The ``varying`` fields of the parameters are inputs of shape ``(B, 1)``
    (one row per design), the ``fixed`` ones constants of the code, the nine
    states inputs of shape ``(1, n)``: the kernel's own operations in its
    order (:func:`prp3.engines.trace.broadcast_function`), each one at the shape of
    what it depends on, so that the constants of a design are combined once
    per design and the functions of the state once per sample.  ``loaded``:
    the time-varying load ``(f_x, f_y, m_z)`` of the samples follows the
    states (three more inputs of shape ``(1, n)``).
    """
    key = (varying, fixed, stroke, loaded)
    function = _KERNELS.get(key)
    if function is None:
        constants = dict(fixed)

        def outputs(ops: Ops, *values: Any) -> tuple[Any, ...]:
            named = dict(zip(varying, values[: len(varying)], strict=True))
            k = KernelParameters(**constants, **named)
            states = values[len(varying) : len(varying) + len(STATE_SYMBOLS)]
            wrench = values[len(varying) + len(STATE_SYMBOLS) :] if loaded else None
            sol = solve(ops, k, *states, reactions=True, load=wrench)
            assert sol.n32 is not None
            p10 = sol.p10
            return (
                *(ops.abs(v) for v in sol.f10),
                *(ops.abs(v) for v in p10),
                *(y * y + z * z for y, z in zip(sol.f21y, sol.f21z, strict=True)),
                *(ops.abs(v) for v in sol.n32),
                p10[0] + p10[1] + p10[2],
                *(sol.lambda10 if stroke else ()),
            )

        inputs = (*STATE_SYMBOLS, *(_LOAD_SYMBOLS if loaded else ()))
        groups = (0,) * len(varying) + (1,) * len(inputs)
        function = broadcast_function(outputs, (*varying, *inputs), groups, "design_kernel")
        if len(_KERNELS) >= 32:  # bounded: a sweep needs one or two
            _KERNELS.clear()
        _KERNELS[key] = function
    return function


def _kernel_results(
    evaluator: DesignEvaluator, fixed: tuple[tuple[str, float], ...], varying: tuple[str, ...],
    table: FloatArray, stroke: bool,
) -> tuple[FloatArray, FloatArray, FloatArray]:  # fmt: skip
    """Peaks + energy ``(B, 13)`` and the least and largest ``λ10`` ``(B,)`` of designs.

    ``table`` ``(B, len(varying))`` holds the ``varying`` parameters of each
    design, ``fixed`` the others.  The design kernel (:func:`_design_kernel`)
    on blocks of at most :data:`_BLOCK` designs × samples, into work blocks
    allocated once; the peaks are the maxima over the samples, the energy the
    trapezoid rule over each motion.  Overflowing forces give ``inf`` or NaN,
    left to the caller.
    """
    count, samples = len(table), len(evaluator._pose)
    if not varying and count > 1:  # the same parameters: one design's results for all
        results, low, high = _kernel_results(evaluator, fixed, varying, table[:1], stroke)
        return np.repeat(results, count, axis=0), np.repeat(low, count), np.repeat(high, count)
    function = _design_kernel(varying, fixed, stroke, evaluator._load is not None)
    blocks_of = [evaluator._pose, evaluator._velocity, evaluator._acceleration]
    if evaluator._load is not None:
        blocks_of.append(evaluator._load)
    states = np.ascontiguousarray(np.concatenate(blocks_of, axis=1).T)
    width = min(samples, _BLOCK)
    designs = min(count, max(1, _BLOCK // width))
    shapes = {1: (designs, 1), 2: (1, width), 3: (designs, width)}
    blocks = function.blocks  # type: ignore[attr-defined]
    work = [np.empty((rows, *shapes[mask])) for mask, rows in blocks]
    out = np.empty((_POWER_ROW + 1 + (3 if stroke else 0), designs, width))  # rows as above
    power = np.empty((designs, samples))
    results = np.empty((count, _RESULTS))
    low = np.empty(count)
    high = np.empty(count)
    with np.errstate(all="ignore"):  # overflowing forces make the design "unreachable"
        for start in range(0, count, designs):
            b = min(designs, count - start)
            parameters = [table[start : start + b, j : j + 1] for j in range(len(varying))]
            peaks = np.full((_PEAKS, b), -np.inf)
            least = np.full(b, np.inf)
            largest = np.full(b, -np.inf)
            for first_sample in range(0, samples, width):
                n = min(width, samples - first_sample)
                views = [
                    w[:, :b, :n] if mask == 3 else w[:, :b] if mask == 1 else w[:, :, :n]
                    for (mask, _), w in zip(blocks, work, strict=True)
                ]
                o = out[:, :b, :n]
                state = [row[None, first_sample : first_sample + n] for row in states]
                function(*parameters, *state, out=o, work=views)
                np.maximum(peaks, o[:_PEAKS].max(axis=2), out=peaks)
                power[:b, first_sample : first_sample + n] = o[_POWER_ROW]
                if stroke:
                    lam = o[_LAMBDA_ROWS]
                    np.fmin(least, np.fmin.reduce(lam, axis=(0, 2)), out=least)
                    np.fmax(largest, np.fmax.reduce(lam, axis=(0, 2)), out=largest)
            np.sqrt(peaks[_SQUARED], out=peaks[_SQUARED])
            results[start : start + b, :-1] = peaks.T
            results[start : start + b, -1] = _energy(evaluator, power[:b])
            low[start : start + b] = least
            high[start : start + b] = largest
    return results, low, high


def _energy(evaluator: DesignEvaluator, power: FloatArray) -> FloatArray:
    """``Σ_motions ∫ Σ p10 dt`` of designs from their input power ``(B, N)``: trapezoid rule.

    Summed along each row (numpy's pairwise sum), so that the energy of a
    design does not depend on the other rows.
    """
    energy = np.zeros(power.shape[0])
    for start, stop, dt in evaluator._segments:  # trapezoid rule over each motion
        energy += 0.5 * ((power[:, start + 1 : stop] + power[:, start : stop - 1]) * dt).sum(axis=1)
    return energy


def _one_design(evaluator: DesignEvaluator, robot: Robot) -> tuple[FloatArray, FloatArray, bool]:
    """Peaks + energy ``(1, 13)``, the ``λ10`` ``(3, N)`` and whether the friction locks.

    :func:`prp3.mechanics.kernel.solve` on the task's samples (1-D arrays), as
    :func:`prp3.engines.entries.paper_forces` calls it: for designs whose loads and
    friction make the kernel branch differently (its implicit ``μ`` terms
    solved sample by sample).
    """
    samples = len(evaluator._pose)
    states = [
        np.ascontiguousarray(array[:, j])
        for array in (evaluator._pose, evaluator._velocity, evaluator._acceleration)
        for j in range(3)
    ]
    load = evaluator._load
    wrench = (
        None
        if load is None
        else (
            np.ascontiguousarray(load[:, 0]),
            np.ascontiguousarray(load[:, 1]),
            np.ascontiguousarray(load[:, 2]),
        )
    )
    with np.errstate(all="ignore"):
        solution = solve(NUMPY, kernel_parameters(robot), *states, reactions=True, load=wrench)
        assert solution.n32 is not None

        def peak(legs: Sequence[Any]) -> list[float]:
            return [float(np.broadcast_to(leg, (samples,)).max()) for leg in legs]

        p10 = solution.p10
        values = [
            *peak([np.abs(v) for v in solution.f10]),
            *peak([np.abs(v) for v in p10]),
            *np.sqrt(
                peak([y * y + z * z for y, z in zip(solution.f21y, solution.f21z, strict=True)])
            ),
            *peak([np.abs(v) for v in solution.n32]),
        ]
        energy = float(
            _energy(evaluator, np.broadcast_to(p10[0] + p10[1] + p10[2], (1, samples)))[0]
        )
    lam = np.array([np.broadcast_to(v, (samples,)) for v in solution.lambda10])
    locked = solution.iterations is not None and bool(
        (np.broadcast_to(solution.iterations, (samples,)) < 0).any()
    )
    return np.array([[*values, energy]]), lam, locked


class _UntraceableError(Exception):
    """A key path that :func:`_parameter_function` cannot follow on the robot's objects."""


def _with_value(node: Any, parts: Sequence[str | int], value: Any) -> Any:
    """A copy of ``node`` (a robot, a part of it, a pair) with ``value`` at ``parts``.

    Not validated: the value is a traced one (:mod:`prp3.engines.trace`); the
    copies share everything else with ``node``.
    """
    head, rest = parts[0], parts[1:]
    if isinstance(node, tuple):
        if not isinstance(head, int) or head >= len(node):
            raise _UntraceableError(head)
        items = list(node)
        items[head] = _with_value(items[head], rest, value) if rest else value
        return tuple(items)
    if not isinstance(head, str) or head not in {f.name for f in fields(node)}:
        raise _UntraceableError(head)
    child = getattr(node, head)
    if rest and child is None:  # a table the nominal robot leaves out ([friction])
        raise _UntraceableError(head)
    copied = copy.copy(node)
    object.__setattr__(copied, head, _with_value(child, rest, value) if rest else value)
    return copied


#: The traced parameter functions of this process: (nominal, paths) -> (function, outputs).
_PARAMETERS: dict[tuple[str, tuple[str, ...]], tuple[Callable[..., None], list[int | float]] | None]
_PARAMETERS = {}


def _parameter_function(
    nominal: dict[str, Any], paths: tuple[str, ...]
) -> tuple[Callable[..., None], list[int | float]] | None:
    """:func:`prp3.mechanics.parameters.kernel_parameters` of the designs, traced over their values.

    The nominal robot with the values of the designs at ``paths``, through
    the robot's own properties (the platform inertia that follows ``l0`` and
    the mass) and ``kernel_parameters``: straight-line code
    (:func:`prp3.engines.trace.array_function`) from the ``(k,)`` columns of the
    values to every field of :class:`~prp3.mechanics.parameters.KernelParameters`, then the
    lower and upper stroke.  Returns the function and the trace's outputs (a
    line, or the float of a field that no parameter changes); ``None`` when a
    path cannot be followed (the designs are then built one by one).
    """
    key = (json.dumps(nominal, sort_keys=True), paths)
    if key not in _PARAMETERS:
        base = Robot.from_mapping(nominal)

        def parameters(ops: Ops, *values: Any) -> tuple[Any, ...]:
            robot = base
            for path, value in zip(paths, values, strict=True):
                robot = _with_value(robot, path_components(path), value)
            k = kernel_parameters(robot)
            stroke = robot.limits.stroke
            lower, upper = stroke if stroke is not None else (-math.inf, math.inf)
            return (*(getattr(k, n) for n in PARAMETER_FIELDS), lower, upper)

        names = tuple(f"v{j}" for j in range(len(paths)))
        try:
            _, outputs = trace(parameters, len(paths))
            function = array_function(parameters, names, "design_parameters")
        except (_UntraceableError, TypeError):  # e.g. a comparison of a traced value
            _PARAMETERS[key] = None
        else:
            if len(_PARAMETERS) >= 32:
                _PARAMETERS.clear()
            _PARAMETERS[key] = (function, outputs)
    return _PARAMETERS[key]


def design_parameter_columns(
    evaluator: DesignEvaluator, values: FloatArray, robots: Sequence[Robot] | None
) -> tuple[dict[str, float], dict[str, FloatArray], FloatArray, FloatArray] | None:
    """The kernel's parameters of designs: the fixed ones, the ``(k,)`` columns, the strokes.

    By the traced :func:`_parameter_function` when it can follow the paths,
    else from ``robots``; ``None`` when it cannot and no robots are given.
    """
    count = len(values)
    traced = _parameter_function(evaluator.nominal, evaluator.paths) if evaluator.paths else None
    if traced is not None:
        function, outputs = traced
        out = np.empty((len(outputs), count))
        function(*(np.ascontiguousarray(values[:, j]) for j in range(values.shape[1])), out)
        constant = dict(zip(PARAMETER_FIELDS, outputs[: len(PARAMETER_FIELDS)], strict=True))
        given = {n: float(o) for n, o in constant.items() if not isinstance(o, int)}
        traced_columns = {n: out[i] for i, n in enumerate(PARAMETER_FIELDS) if n not in given}
        return given, traced_columns, out[-2], out[-1]
    if robots is None:
        return None
    each = [kernel_parameters(robot) for robot in robots]
    fixed: dict[str, float] = {}
    columns: dict[str, FloatArray] = {}
    for name in PARAMETER_FIELDS:
        per_design = [getattr(p, name) for p in each]
        if all(v == per_design[0] for v in per_design):
            fixed[name] = per_design[0]
        else:
            columns[name] = np.array(per_design, dtype=np.float64)
    lower = np.array([r.limits.stroke[0] if r.limits.stroke else -np.inf for r in robots])
    upper = np.array([r.limits.stroke[1] if r.limits.stroke else np.inf for r in robots])
    return fixed, columns, lower, upper


def _block_results(
    evaluator: DesignEvaluator, values: FloatArray, robots: Sequence[Robot] | None
) -> tuple[list[str], FloatArray]:
    """Status and peaks + energy (NaN unless ``ok``) of designs ``values`` ``(k, p)``.

    The kernel does not validate; here, as in ``paper_forces``: a singular
    task (checked once), then the stroke, then non-finite results.  The
    designs go through the design kernel together (:func:`_kernel_results`)
    unless their loads or friction make the kernel branch differently
    (:func:`_one_design`, one at a time, on their robots: ``robots``, or
    built here).
    """
    count = len(values)
    result = np.full((count, _RESULTS), np.nan)
    if evaluator._singular:
        return ["singular"] * count, result
    described = design_parameter_columns(evaluator, values, robots)
    if described is None:
        robots = _robots(evaluator, values)
        described = design_parameter_columns(evaluator, values, robots)
        assert described is not None
    fixed, columns, lower, upper = described
    stroke = bool(np.isfinite(lower).any() or np.isfinite(upper).any())
    locked = np.zeros(count, dtype=bool)
    # the mu terms are implicit, a zero smoothing is a sign: the kernel branches on them
    branching = KernelParameters(**{n: fixed.get(n, 1.0) for n in PARAMETER_FIELDS}).has_mu
    if branching or not BROADCAST_FIELDS.issuperset(columns):
        robots = robots if robots is not None else _robots(evaluator, values)
        results = np.empty((count, _RESULTS))
        least, largest = np.empty(count), np.empty(count)
        for k, robot in enumerate(robots):
            results[k : k + 1], lam, locked[k] = _one_design(evaluator, robot)
            least[k], largest[k] = np.fmin.reduce(lam, axis=None), np.fmax.reduce(lam, axis=None)
    else:
        varying = tuple(n for n in PARAMETER_FIELDS if n in columns)
        table = np.empty((count, len(varying)))
        for j, name in enumerate(varying):
            table[:, j] = columns[name]
        constants = tuple((n, fixed[n]) for n in PARAMETER_FIELDS if n in fixed)
        results, least, largest = _kernel_results(evaluator, constants, varying, table, stroke)
    outside = (least < lower) | (largest > upper)
    finite = np.isfinite(results).all(axis=1) & ~locked
    status = [
        "stroke" if o else "ok" if f else "unreachable"
        for o, f in zip(outside.tolist(), finite.tolist(), strict=True)
    ]
    good = ~outside & finite
    result[good] = results[good]
    return status, result


def _robots(evaluator: DesignEvaluator, values: FloatArray) -> list[Robot]:
    """The robot of every design, built and checked (:func:`~prp3.apps.design.design_robot`)."""
    robots = []
    for row in values.tolist():
        try:
            robots.append(design_robot(evaluator.nominal, evaluator.paths, row))
        except ParameterError as error:
            described = ", ".join(f"{p} = {v!r}" for p, v in zip(evaluator.paths, row, strict=True))
            raise ParameterError(f"design {described}: {error}") from None
    return robots


def _design_values(evaluator: DesignEvaluator, values: object) -> FloatArray:
    """``values`` as float64 ``(k, p)``, one column per path of ``evaluator``, all finite."""
    width = len(evaluator.paths)
    array = check_real("values", values, ParameterError)  # type: ignore[arg-type]
    if array.ndim == 1 and width == 1:
        array = array.reshape(-1, 1)
    if array.ndim != 2 or array.shape[1] != width:
        raise ParameterError(
            f"values must have shape (k, {width}), one column per design path "
            f"({', '.join(evaluator.paths)}), got shape {array.shape}",
            key="values",
        )
    bad = np.argwhere(~np.isfinite(array))
    if bad.size:
        row, column = bad[0].tolist()
        raise ParameterError(
            f"{evaluator.paths[column]} = {float(array[row, column])!r} is not a finite number",
            subject="values",
            key="values",
            sample=row,
        )
    return array


def evaluate_designs(evaluator: DesignEvaluator, values: FloatArray) -> dict[str, Any]:
    """Evaluate designs ``values`` of shape ``(k, p)``: the columns of their rows.

    Pure: the same values give the same numbers whatever the worker.  A
    design that fails the task is a row with its ``status`` and NaN forces.
    The robots of the designs are built and checked one by one only where
    it is needed: designs outside a box of valid robots
    (:class:`~prp3.apps.design.DesignEvaluator`), the workspace columns, loads and friction
    that make the kernel branch; the kernel's parameters of the designs come
    from :func:`prp3.mechanics.parameters.kernel_parameters` traced over their values.

    Returns
    -------
    dict
        Column name -> ndarray of shape ``(k,)``: float64, and ``status`` as
        an array of ``str``.

    Raises
    ------
    ParameterError
        ``evaluator`` not a :class:`~prp3.apps.design.DesignEvaluator`; ``values`` not
        real numbers (booleans and text are refused), not of shape ``(k, p)`` or not
        finite (names the design and the path); a design that is not a valid robot
        (names the design's values).
    """
    evaluator = check_instance("evaluator", evaluator, DesignEvaluator, "a prp3 DesignEvaluator")
    values = _design_values(evaluator, values)
    count = values.shape[0]
    results = np.full((count, _RESULTS), np.nan)
    status: list[str] = []
    area = np.full(count, np.nan)
    condition = np.full(count, np.nan)
    robots = None
    if evaluator.workspace or not evaluator.inside(values):
        robots = _robots(evaluator, values)
    if evaluator.workspace and robots is not None:
        areas: dict[tuple[float, float], float] = {}
        conditions: dict[float, float] = {}
        for k, robot in enumerate(robots):
            stroke = robot.limits.stroke
            if stroke is None:
                continue
            if stroke not in areas:  # the area at φ = 0 depends on the stroke alone
                areas[stroke] = workspace_slice(robot, 0.0, [-1.0, 1.0], [-1.0, 1.0]).area
            area[k] = areas[stroke]
            if robot.l0 not in conditions:  # κ depends on l0 and the poses alone
                conditions[robot.l0] = float(jacobian_condition(robot, evaluator._pose).max())
            condition[k] = conditions[robot.l0]
    if count:
        status, results = _block_results(evaluator, values, robots)
    columns: dict[str, Any] = {path: values[:, j].copy() for j, path in enumerate(evaluator.paths)}
    columns["status"] = np.array(status, dtype=str)
    names = design_columns(evaluator.paths, evaluator.workspace)
    first = len(evaluator.paths) + 1
    for j, name in enumerate(names[first : first + _RESULTS]):
        columns[name] = results[:, j].copy()
    if evaluator.workspace:
        columns["workspace_area"] = area
        columns["max_condition"] = condition
    return columns


def evaluate_rows(evaluator: DesignEvaluator | RowEvaluator, values: FloatArray) -> dict[str, Any]:
    """The columns of designs ``values (k, p)``: :func:`evaluate_designs` for the 3-PRP's
    :class:`~prp3.apps.design.DesignEvaluator`, ``evaluator.evaluate(values)`` for another
    :class:`~prp3.apps.design.RowEvaluator` (the spatial robots')."""
    if isinstance(evaluator, DesignEvaluator):
        return evaluate_designs(evaluator, values)
    return evaluator.evaluate(values)
