"""Design studies: sweeps of robot parameters over a task, and their figures of merit.

A *design* is a robot: the nominal ``ROBOT.toml`` with some of its values
replaced.  A value is named by its *key path* in the ``ROBOT.toml`` mapping —
``"l0"``, ``"platform.mass"``, ``"link.com.0"`` (a number of an array: the
first component of ``link.com``), ``"limits.stroke.1"`` — so that any table of
``ROBOT.toml`` can be swept without code for it: a key the robot does not
know is refused by :meth:`prp3.Robot.from_mapping`, naming it.  The platform
inertia follows a swept ``platform.mass`` or ``l0`` (``m3·l²/12``) unless the
nominal robot gives ``platform.inertia`` or it is swept itself, as in
``ROBOT.toml``.

The *task* is a list of motions (the paper's, or trajectory files).
:func:`evaluate_designs` runs the one kernel (:func:`prp3.mechanics.kernel.solve`,
reactions included), traced once per process into numpy code for blocks of
designs × the task's samples — the designs' constants as a column (their
kernel parameters traced the same way from their values, no robot built
per design), the states as a row: the operations of
:func:`prp3.engines.entries.paper_forces`, bit for bit, without its cost of preparing
each new robot — and reduces the forces to the columns of
``designs.parquet`` (:func:`design_columns`):

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
import hashlib
import itertools
import json
import math
import re
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3 import __version__
from prp3.analysis.reachability import jacobian_condition
from prp3.analysis.workspace import workspace_slice
from prp3.engines.trace import array_function, broadcast_function, trace
from prp3.errors import (
    ParameterError,
    Prp3Error,
    SingularPoseError,
)
from prp3.io.formats import read_trajectory
from prp3.mechanics.geometry import LEGS, check_poses
from prp3.mechanics.kernel import (
    INERTIAL_FIELDS,
    NUMPY,
    STATE_SYMBOLS,
    KernelParameters,
    Ops,
    kernel_parameters,
    solve,
)
from prp3.model.elements import ELEMENTS
from prp3.model.motion import MAX_SAMPLES, PAPER_MOTIONS, Motion, paper_motion
from prp3.model.robot import Robot, read_toml
from prp3.validation import check_finite, check_instance, check_integer, check_real, check_scalar

__all__ = [
    "AGGREGATES",
    "CHUNK_DESIGNS",
    "INFEASIBLE",
    "MAX_DESIGNS",
    "SAMPLINGS",
    "STATUSES",
    "DesignEvaluator",
    "DesignObjective",
    "OptimizeSpec",
    "Parameter",
    "SweepSpec",
    "design_columns",
    "design_mapping",
    "design_robot",
    "design_values",
    "evaluate_designs",
    "nominal_value",
    "pareto_front",
    "penalized_objective",
    "quantity",
    "read_sweep_spec",
    "sweep_spec",
]

FloatArray = NDArray[np.float64]

#: How designs are drawn: full factorial grid (ends included), Latin hypercube, uniform random.
SAMPLINGS: tuple[str, ...] = ("grid", "lhs", "random")

#: Values of the ``status`` column: the design performs the task, or why it cannot.
STATUSES: tuple[str, ...] = ("ok", "singular", "unreachable", "stroke")

#: Designs per Dask task: hundreds, so that the kernel, not Python or Dask, dominates.
CHUNK_DESIGNS: int = 250

#: Up to this many parameters the corners of their box are checked once (2**p robots);
#: with more, every design is built and checked.
_CORNER_PARAMETERS: int = 10

#: Largest number of designs of one sweep (bounds the memory of the design table).
MAX_DESIGNS: int = 10_000_000

#: Per-leg peak quantities; ``peak_f10`` etc. (no leg) means the largest of the three legs.
AGGREGATES: tuple[str, ...] = ("peak_f10", "peak_p10", "peak_f21", "peak_n32")

_PATH = re.compile(r"^[A-Za-z_][A-Za-z0-9_-]*(\.([A-Za-z_][A-Za-z0-9_-]*|[0-9]+))*$")
_TOP_KEYS = {
    "robot", "designs", "sampling", "seed", "chunk", "parameters", "task", "limits", "optimize",
}  # fmt: skip


# ------------------------------------------------------------------ key paths
def _components(path: str) -> list[str | int]:
    return [int(part) if part.isdigit() else part for part in path.split(".")]


def design_mapping(
    nominal: Mapping[str, Any], paths: Sequence[str], values: Sequence[float]
) -> dict[str, Any]:
    """The ``ROBOT.toml`` mapping of a design: ``nominal`` with ``paths`` set to ``values``.

    Missing tables are created (``"payload.mass"`` on a robot without
    ``[payload]``); a numeric component indexes an array of the nominal
    robot (``"link.com.0"``).  ``nominal`` is not changed.

    Raises
    ------
    ParameterError
        A path that indexes something that is not an array, or crosses a
        value that is not a table (names the path).

    >>> design_mapping({"l0": 0.3, "link": {"com": [0.0, 0.0]}}, ["link.com.1", "platform.mass"],
    ...                [0.01, 2.0])
    {'l0': 0.3, 'link': {'com': [0.0, 0.01]}, 'platform': {'mass': 2.0}}
    """
    mapping = dict(nominal)
    for path, value in zip(paths, values, strict=True):
        parts = _components(path)
        node: Any = mapping
        for depth, part in enumerate(parts[:-1]):
            following = parts[depth + 1]
            if isinstance(node, dict) and isinstance(part, str):
                if part not in node:
                    if isinstance(following, int):
                        raise ParameterError(
                            f"{path!r}: the nominal robot gives no {'.'.join(map(str, parts[: depth + 1]))} to index"
                        )
                    node[part] = {}
                # copy on the way down: the nominal mapping is never changed
                child = node[part]
                node[part] = dict(child) if isinstance(child, Mapping) else copy.copy(child)
                node = node[part]
            elif isinstance(node, list) and isinstance(part, int) and part < len(node):
                node[part] = copy.copy(node[part])
                node = node[part]
            else:
                raise ParameterError(f"{path!r}: {part!r} is not a key of the robot here")
        last = parts[-1]
        if isinstance(node, dict) and isinstance(last, str):
            node[last] = float(value)
        elif isinstance(node, list) and isinstance(last, int) and last < len(node):
            node[last] = float(value)
        else:
            raise ParameterError(f"{path!r}: {last!r} is not a key or an index of the robot here")
    return mapping


def design_robot(
    nominal: Mapping[str, Any], paths: Sequence[str], values: Sequence[float]
) -> Robot:
    """The robot of a design (:func:`design_mapping` then :meth:`Robot.from_mapping`)."""
    nominal = check_instance("nominal", nominal, Mapping, "a mapping of ROBOT.toml keys")  # type: ignore[type-abstract]
    if (
        isinstance(paths, str)
        or not isinstance(paths, Sequence)
        or not all(isinstance(path, str) for path in paths)
    ):
        raise ParameterError(f"paths must be a sequence of ROBOT.toml key paths, got {paths!r}")
    numbers = check_real("values", values, ParameterError)
    if numbers.shape != (len(paths),):
        raise ParameterError(
            f"values must have shape ({len(paths)},), one per path, got {numbers.shape}"
        )
    check_finite("values", numbers, ParameterError, components=tuple(paths))
    return Robot.from_mapping(design_mapping(nominal, paths, numbers.tolist()))


def nominal_value(nominal: Mapping[str, Any], path: str) -> float | None:
    """The value at ``path`` in the nominal mapping; ``None`` when it does not give one.

    A missing ``platform.inertia`` is the one the robot computes (``m3·l²/12``).

    >>> nominal_value({"l0": 0.3}, "l0"), nominal_value({"l0": 0.3}, "payload.mass")
    (0.3, None)
    """
    node: Any = nominal
    for part in _components(path):
        if isinstance(node, Mapping) and isinstance(part, str) and part in node:
            node = node[part]
        elif isinstance(node, list) and isinstance(part, int) and part < len(node):
            node = node[part]
        else:
            if path == "platform.inertia":
                return Robot.from_mapping(nominal).platform_inertia
            return None
    if isinstance(node, bool) or not isinstance(node, int | float):
        return None
    return float(node)


# ------------------------------------------------------------------ the task
@dataclass(frozen=True, eq=False)
class DesignEvaluator:
    """What a worker needs to evaluate designs: the nominal robot, the paths and the task.

    Attributes
    ----------
    nominal : dict
        ``ROBOT.toml`` mapping of the nominal robot (``[limits]`` of the sweep merged in).
    paths : tuple of str
        Key paths of the varied parameters, in column order.
    motions : tuple of Motion
        The task: every motion, ``N >= 2`` samples each.
    workspace : bool
        Whether the designs have a stroke (``workspace_area``, ``max_condition`` columns).
    bounds : tuple of (low, high)
        The range of each parameter, if known.  When every corner of this box
        is a valid robot, so is every design inside it (the robot's checks
        bound each value, and the products of masses and sizes that could
        overflow): designs inside are then not built one by one
        (:func:`evaluate_designs`).
    """

    nominal: dict[str, Any]
    paths: tuple[str, ...]
    motions: tuple[Motion, ...]
    workspace: bool
    bounds: tuple[tuple[float, float], ...] = ()
    _pose: FloatArray = field(init=False, repr=False)
    _velocity: FloatArray = field(init=False, repr=False)
    _acceleration: FloatArray = field(init=False, repr=False)
    _load: FloatArray | None = field(init=False, repr=False)
    _segments: tuple[tuple[int, int, FloatArray], ...] = field(init=False, repr=False)
    _singular: bool = field(init=False, repr=False)
    _valid_box: bool = field(init=False, repr=False)

    def __post_init__(self) -> None:
        # the motions one after the other: one block of samples for the kernel
        for name in ("pose", "velocity", "acceleration"):
            joined = np.concatenate([getattr(m, name) for m in self.motions])
            object.__setattr__(self, f"_{name}", joined)
        # the time-varying loads (fx, fy, mz) of the trajectories that give them, zero elsewhere
        loaded = any(m.load is not None for m in self.motions)
        load = (
            np.concatenate(
                [m.load if m.load is not None else np.zeros_like(m.pose) for m in self.motions]
            )
            if loaded
            else None
        )
        object.__setattr__(self, "_load", load)
        segments, start = [], 0
        for motion in self.motions:
            segments.append((start, start + motion.samples, np.diff(motion.t)))
            start += motion.samples
        object.__setattr__(self, "_segments", tuple(segments))
        try:  # singular poses do not depend on the design (φ ≡ π/3 mod π)
            check_poses(self._pose)
            singular = False
        except SingularPoseError:
            singular = True
        object.__setattr__(self, "_singular", singular)
        object.__setattr__(self, "_valid_box", self._corners_valid())

    def _corners_valid(self) -> bool:
        """Whether the robot of every corner of ``bounds`` passes the robot's checks."""
        if not self.bounds or len(self.bounds) > _CORNER_PARAMETERS:
            return False
        for corner in itertools.product(*self.bounds):
            try:
                design_robot(self.nominal, self.paths, corner)
            except ParameterError:
                return False
        return True

    def inside(self, values: FloatArray) -> bool:
        """Whether designs ``(k, p)`` lie in a box of valid robots (see ``bounds``)."""
        if not self._valid_box:
            return False
        low = np.array([lo for lo, _ in self.bounds])
        high = np.array([hi for _, hi in self.bounds])
        return bool(((values >= low) & (values <= high)).all())

    @property
    def columns(self) -> tuple[str, ...]:
        """Column names of the design table (:func:`design_columns`)."""
        return design_columns(self.paths, self.workspace)


def design_columns(paths: Sequence[str], workspace: bool) -> tuple[str, ...]:
    """Columns of ``designs.parquet``: the parameters, ``status``, the peaks, ``energy``, ...

    >>> design_columns(["l0"], False)[:5]
    ('l0', 'status', 'peak_f10_A', 'peak_f10_B', 'peak_f10_C')
    >>> design_columns(["l0"], True)[-3:]
    ('energy', 'workspace_area', 'max_condition')
    """
    peaks = tuple(f"{name}_{leg}" for name in AGGREGATES for leg in LEGS)
    extra = ("workspace_area", "max_condition") if workspace else ()
    return (*paths, "status", *peaks, "energy", *extra)


_RESULTS = len(AGGREGATES) * 3 + 1  # peaks and energy


#: Designs × samples of one call of the design kernel: its work blocks stay in the CPU caches.
_BLOCK = 8192

_PARAMETER_FIELDS = tuple(f.name for f in fields(KernelParameters))

#: Fields of :class:`~prp3.mechanics.kernel.KernelParameters` that may differ between the designs of
#: one kernel call: the kernel performs the same operations whatever their values (it
#: branches on the others: a zero smoothing is a sign, the mu terms are implicit), as each
#: element says (:attr:`prp3.model.elements.Element.broadcast`).
_BROADCAST_FIELDS: frozenset[str] = frozenset(INERTIAL_FIELDS) | {
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
    """:func:`prp3.mechanics.kernel.kernel_parameters` of the designs, traced over their values.

    The nominal robot with the values of the designs at ``paths``, through
    the robot's own properties (the platform inertia that follows ``l0`` and
    the mass) and ``kernel_parameters``: straight-line code
    (:func:`prp3.engines.trace.array_function`) from the ``(k,)`` columns of the
    values to every field of :class:`~prp3.mechanics.kernel.KernelParameters`, then the
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
                robot = _with_value(robot, _components(path), value)
            k = kernel_parameters(robot)
            stroke = robot.limits.stroke
            lower, upper = stroke if stroke is not None else (-math.inf, math.inf)
            return (*(getattr(k, n) for n in _PARAMETER_FIELDS), lower, upper)

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


def _design_parameters(
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
        constant = dict(zip(_PARAMETER_FIELDS, outputs[: len(_PARAMETER_FIELDS)], strict=True))
        given = {n: float(o) for n, o in constant.items() if not isinstance(o, int)}
        traced_columns = {n: out[i] for i, n in enumerate(_PARAMETER_FIELDS) if n not in given}
        return given, traced_columns, out[-2], out[-1]
    if robots is None:
        return None
    each = [kernel_parameters(robot) for robot in robots]
    fixed: dict[str, float] = {}
    columns: dict[str, FloatArray] = {}
    for name in _PARAMETER_FIELDS:
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
    described = _design_parameters(evaluator, values, robots)
    if described is None:
        robots = _robots(evaluator, values)
        described = _design_parameters(evaluator, values, robots)
        assert described is not None
    fixed, columns, lower, upper = described
    stroke = bool(np.isfinite(lower).any() or np.isfinite(upper).any())
    locked = np.zeros(count, dtype=bool)
    # the mu terms are implicit, a zero smoothing is a sign: the kernel branches on them
    branching = KernelParameters(**{n: fixed.get(n, 1.0) for n in _PARAMETER_FIELDS}).has_mu
    if branching or not _BROADCAST_FIELDS.issuperset(columns):
        robots = robots if robots is not None else _robots(evaluator, values)
        results = np.empty((count, _RESULTS))
        least, largest = np.empty(count), np.empty(count)
        for k, robot in enumerate(robots):
            results[k : k + 1], lam, locked[k] = _one_design(evaluator, robot)
            least[k], largest[k] = np.fmin.reduce(lam, axis=None), np.fmax.reduce(lam, axis=None)
    else:
        varying = tuple(n for n in _PARAMETER_FIELDS if n in columns)
        table = np.empty((count, len(varying)))
        for j, name in enumerate(varying):
            table[:, j] = columns[name]
        constants = tuple((n, fixed[n]) for n in _PARAMETER_FIELDS if n in fixed)
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
    """The robot of every design, built and checked (:func:`design_robot`)."""
    robots = []
    for row in values.tolist():
        try:
            robots.append(design_robot(evaluator.nominal, evaluator.paths, row))
        except ParameterError as error:
            described = ", ".join(f"{p} = {v!r}" for p, v in zip(evaluator.paths, row, strict=True))
            raise ParameterError(f"design {described}: {error}") from None
    return robots


def evaluate_designs(evaluator: DesignEvaluator, values: FloatArray) -> dict[str, Any]:
    """Evaluate designs ``values`` of shape ``(k, p)``: the columns of their rows.

    Pure: the same values give the same numbers whatever the worker.  A
    design that fails the task is a row with its ``status`` and NaN forces.
    The robots of the designs are built and checked one by one only where
    it is needed: designs outside a box of valid robots
    (:class:`DesignEvaluator`), the workspace columns, loads and friction
    that make the kernel branch; the kernel's parameters of the designs come
    from :func:`prp3.mechanics.kernel.kernel_parameters` traced over their values.

    Returns
    -------
    dict
        Column name -> ndarray of shape ``(k,)``: float64, and ``status`` as
        an array of ``str``.

    Raises
    ------
    ParameterError
        A design that is not a valid robot (names the design's values).
    """
    values = np.asarray(values, dtype=np.float64).reshape(len(values), len(evaluator.paths))
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

    evaluator: DesignEvaluator
    optimize: OptimizeSpec

    def __call__(self, x: FloatArray) -> float:
        """``penalized_objective`` of the design with parameter values ``x`` (shape (p,))."""
        return float(self.many(np.asarray(x, dtype=np.float64)[None, :])[0])

    def many(self, xs: FloatArray) -> FloatArray:
        """``penalized_objective`` of designs ``xs`` ``(k, p)``, evaluated together: ``(k,)``.

        The value of each design is the one :meth:`__call__` gives it alone.
        """
        columns = evaluate_designs(self.evaluator, np.asarray(xs, dtype=np.float64))
        return penalized_objective(self.optimize, columns)


# ------------------------------------------------------------------ SWEEP.toml
@dataclass(frozen=True)
class Parameter:
    """A varied parameter: a ``ROBOT.toml`` key path and its range ``[low, high]``."""

    path: str
    low: float
    high: float

    def __post_init__(self) -> None:
        if not isinstance(self.path, str):
            raise ParameterError(f"path must be a ROBOT.toml key path, got {self.path!r}")
        low = check_scalar("low", self.low, subject=self.path)
        high = check_scalar("high", self.high, subject=self.path)
        if not low < high:
            raise ParameterError(
                f"low must be below high, got [{low!r}, {high!r}]", subject=self.path
            )
        object.__setattr__(self, "low", low)
        object.__setattr__(self, "high", high)


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


@dataclass(frozen=True, eq=False)
class SweepSpec:
    """A validated ``SWEEP.toml``.

    Attributes
    ----------
    source : str
        Where it came from (the file, for messages).
    parameters : tuple of Parameter
    designs : int
        Number of designs (``lhs``, ``random``), or points per parameter (``grid``).
    sampling : str
        One of :data:`SAMPLINGS`.
    seed : int
    chunk : int
        Designs per Dask task (default :data:`CHUNK_DESIGNS`).
    motions : tuple of str
        The task's motion names or trajectory files, as given.
    samples : int
        Samples of the paper's motions.
    evaluator : DesignEvaluator
        The nominal robot and the task, for the workers.
    optimize : OptimizeSpec
    notes : tuple of str
        Warnings for the user (a trajectory file of positions only: how its
        derivatives were computed).
    files : tuple of Path
        The files the spec reads besides itself (its robot file, trajectory
        files), as a run's manifest records them.
    """

    source: str
    parameters: tuple[Parameter, ...]
    designs: int
    sampling: str
    seed: int
    chunk: int
    motions: tuple[str, ...]
    samples: int
    evaluator: DesignEvaluator
    optimize: OptimizeSpec
    notes: tuple[str, ...] = ()
    files: tuple[Path, ...] = ()

    @property
    def paths(self) -> tuple[str, ...]:
        """Key paths of the parameters."""
        return tuple(p.path for p in self.parameters)

    @property
    def count(self) -> int:
        """Number of rows of the sweep."""
        return self.designs ** len(self.parameters) if self.sampling == "grid" else self.designs

    @property
    def bounds(self) -> list[tuple[float, float]]:
        """``(low, high)`` of every parameter."""
        return [(p.low, p.high) for p in self.parameters]

    def digest(self) -> str:
        """SHA-256 of everything the rows depend on (keys the staging folder of a resume)."""
        hasher = hashlib.sha256()
        described = {
            "format": 1,
            "prp3": __version__,
            "chunk": self.chunk,
            "nominal": self.evaluator.nominal,
            "parameters": [[p.path, p.low, p.high] for p in self.parameters],
            "designs": self.designs,
            "sampling": self.sampling,
            "seed": self.seed,
            "workspace": self.evaluator.workspace,
        }
        hasher.update(json.dumps(described, sort_keys=True).encode())
        for motion in self.evaluator.motions:
            for array in (motion.t, motion.pose, motion.velocity, motion.acceleration):
                hasher.update(np.ascontiguousarray(array, dtype=np.float64).tobytes())
        return hasher.hexdigest()


def read_sweep_spec(path: str | Path) -> SweepSpec:
    """Read and validate ``SWEEP.toml`` (see :func:`sweep_spec`); errors name the file."""
    path = Path(path)
    data = read_toml(path, "sweep")
    return sweep_spec(data, base=path.parent, source=str(path))


def _integer(source: str, key: str, value: Any, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise ParameterError(
            f"{source}: {key} must be an integer from {low} to {high}, got {value!r}"
        )
    return value


def _number(source: str, key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ParameterError(f"{source}: {key} must be a finite number, got {value!r}")
    return float(value)


def _table(source: str, name: str, value: Any) -> dict[str, Any]:
    if not isinstance(value, Mapping):
        raise ParameterError(f"{source}: [{name}] must be a table, got {value!r}"[:300])
    return dict(value)


def _unknown(source: str, where: str, table: Mapping[str, Any], allowed: set[str]) -> None:
    for key in table:
        if key not in allowed:
            raise ParameterError(
                f"{source}: unknown key {where}{key!r} (expected one of: {', '.join(sorted(allowed))})"
            )


def _sampling(source: str, data: Mapping[str, Any]) -> str:
    """The ``sampling`` of a sweep file (default ``"lhs"``), one of :data:`SAMPLINGS`."""
    sampling = data.get("sampling", "lhs")
    if sampling not in SAMPLINGS:
        raise ParameterError(
            f"{source}: unknown sampling {sampling!r} (expected one of: {', '.join(SAMPLINGS)})"
        )
    return str(sampling)


def _flatten(table: Mapping[str, Any], prefix: str = "") -> list[tuple[str, Any]]:
    """``{"platform": {"mass": [2, 4]}}`` (TOML ``platform.mass = ...``) -> dotted paths."""
    items: list[tuple[str, Any]] = []
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, Mapping):
            items += _flatten(value, f"{path}.")
        else:
            items.append((path, value))
    return items


def _parameters(
    source: str, table: Mapping[str, Any], nominal: dict[str, Any]
) -> tuple[Parameter, ...]:
    parameters: list[Parameter] = []
    for path, value in _flatten(table):
        where = f"{source}: [parameters] {path!r}"
        if not _PATH.match(path):
            raise ParameterError(f"{where}: not a key path of ROBOT.toml (like 'platform.mass')")
        if not isinstance(value, list) or not value:
            raise ParameterError(
                f"{where}: the range must be [low, high], got an empty range {value!r}"
                if isinstance(value, list)
                else f"{where}: the range must be [low, high], got {value!r}"
            )
        if len(value) != 2:
            raise ParameterError(f"{where}: the range must be [low, high], got {value!r}")
        low = _number(source, f"[parameters] {path!r} low", value[0])
        high = _number(source, f"[parameters] {path!r} high", value[1])
        if low > high:
            raise ParameterError(f"{where}: low > high in [{low!r}, {high!r}]")
        if low == high:
            raise ParameterError(
                f"{where}: empty range [{low!r}, {high!r}] (low == high): give a fixed value in "
                "the robot file instead"
            )
        for other in parameters:
            if path.startswith(f"{other.path}.") or other.path.startswith(f"{path}."):
                raise ParameterError(f"{where}: overlaps the parameter {other.path!r}")
        for end in (low, high):
            try:
                design_robot(nominal, [path], [end])
            except ParameterError as error:
                reason = re.sub(r"^robot: ", "", str(error))
                raise ParameterError(f"{where} = {end!r}: {reason}") from None
        parameters.append(Parameter(path, low, high))
    if not parameters:
        raise ParameterError(
            f"{source}: [parameters] must give at least one key path = [low, high]"
        )
    return tuple(parameters)


def _motions(
    source: str, base: Path, task: Mapping[str, Any]
) -> tuple[tuple[str, ...], int, tuple[Motion, ...], tuple[str, ...]]:
    _unknown(source, "task.", task, {"motions", "samples"})
    names = task.get("motions", ["vertical", "rotation"])
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise ParameterError(
            f"{source}: task.motions must be a non-empty list of paper motions "
            f"({', '.join(PAPER_MOTIONS)}) or TRAJ.csv paths, got {names!r}"[:300]
        )
    samples = _integer(source, "task.samples", task.get("samples", 301), 2, MAX_SAMPLES)
    motions: list[Motion] = []
    notes: list[str] = []
    for name in names:
        if name in PAPER_MOTIONS:
            motions.append(paper_motion(name, samples))
        else:
            file = Path(name) if Path(name).is_absolute() else base / name
            try:
                trajectory = read_trajectory(file)
            except Prp3Error as error:
                raise type(error)(f"{source}: task.motions {name!r}: {error}") from None
            motions.append(trajectory.motion)
            if trajectory.note is not None:
                notes.append(trajectory.note)
    return tuple(names), samples, tuple(motions), tuple(notes)


def _optimize(source: str, table: Mapping[str, Any], columns: Sequence[str]) -> OptimizeSpec:
    _unknown(source, "optimize.", table, {"objective", "constraints", "maxiter", "popsize", "tol"})
    known = {c for c in columns if c != "status"} | set(AGGREGATES)

    def name_of(key: str, value: Any) -> str:
        if not isinstance(value, str) or value not in known:
            raise ParameterError(
                f"{source}: {key}: unknown quantity {value!r} (expected one of: {', '.join(sorted(known))})"
            )
        return value

    objective = name_of("optimize.objective", table.get("objective", "peak_f10"))
    constraints: list[tuple[str, float, float]] = []
    for key, bounds in _table(source, "optimize.constraints", table.get("constraints", {})).items():
        name = name_of("optimize.constraints", key)
        where = f"optimize.constraints.{key}"
        bounds = _table(source, where, bounds)
        _unknown(source, f"{where}.", bounds, {"min", "max"})
        if not bounds:
            raise ParameterError(f"{source}: {where} must give min and/or max")
        low = _number(source, f"{where}.min", bounds["min"]) if "min" in bounds else -math.inf
        high = _number(source, f"{where}.max", bounds["max"]) if "max" in bounds else math.inf
        if low > high:
            raise ParameterError(f"{source}: {where}: min > max ({low!r} > {high!r})")
        constraints.append((name, low, high))
    tol = _number(source, "optimize.tol", table.get("tol", 0.01))
    if not tol > 0.0:
        raise ParameterError(f"{source}: optimize.tol must be positive, got {tol!r}")
    return OptimizeSpec(
        objective=objective,
        constraints=tuple(constraints),
        maxiter=_integer(source, "optimize.maxiter", table.get("maxiter", 30), 1, 100_000),
        popsize=_integer(source, "optimize.popsize", table.get("popsize", 10), 1, 10_000),
        tol=tol,
    )


def sweep_spec(
    data: Mapping[str, Any], *, base: str | Path = ".", source: str = "SWEEP.toml"
) -> SweepSpec:
    """Validate the mapping of a ``SWEEP.toml``; paths in it are relative to ``base``.

    Raises
    ------
    ParameterError, InputFileError, TrajectoryError
        One line naming ``source``, the key and the value: an unknown key or
        key path, ``low > high``, an empty range, an unknown sampling, a
        missing robot or trajectory file, too many designs, ...
    """
    check_instance("data", data, Mapping, "a mapping (a parsed SWEEP.toml)")  # type: ignore[type-abstract]
    base = Path(base)
    _unknown(source, "", data, _TOP_KEYS)
    robot_file = data.get("robot")
    if robot_file is None:
        robot = Robot()
    elif isinstance(robot_file, str) and robot_file:
        file = Path(robot_file) if Path(robot_file).is_absolute() else base / robot_file
        try:
            robot = Robot.from_toml(file)
        except Prp3Error as error:
            raise type(error)(f"{source}: robot {robot_file!r}: {error}") from None
    else:
        raise ParameterError(
            f"{source}: robot must be the path of a ROBOT.toml, got {robot_file!r}"
        )
    nominal: dict[str, Any] = tomllib.loads(robot.to_toml())
    if "limits" in data:
        limits = _table(source, "limits", data["limits"])
        nominal["limits"] = {**nominal.get("limits", {}), **limits}
        try:
            Robot.from_mapping(nominal)
        except ParameterError as error:
            raise ParameterError(
                f"{source}: [limits]: {re.sub(r'^robot: ', '', str(error))}"
            ) from None
    sampling = _sampling(source, data)
    designs = _integer(
        source, "designs", data.get("designs", 100), 2 if sampling == "grid" else 1, MAX_DESIGNS
    )
    seed = _integer(source, "seed", data.get("seed", 0), 0, 2**63 - 1)
    parameters = _parameters(
        source, _table(source, "parameters", data.get("parameters", {})), nominal
    )
    if sampling == "grid" and designs ** len(parameters) > MAX_DESIGNS:
        raise ParameterError(
            f"{source}: a grid of {designs} points per parameter over {len(parameters)} "
            f"parameters has {designs}^{len(parameters)} designs, more than {MAX_DESIGNS}"
        )
    names, samples, motions, notes = _motions(
        source, base, _table(source, "task", data.get("task", {}))
    )
    workspace = "stroke" in nominal.get("limits", {})
    paths = tuple(p.path for p in parameters)
    evaluator = DesignEvaluator(
        nominal=nominal,
        paths=paths,
        motions=motions,
        workspace=workspace,
        bounds=tuple((p.low, p.high) for p in parameters),
    )
    optimize = _optimize(
        source, _table(source, "optimize", data.get("optimize", {})), evaluator.columns
    )
    return SweepSpec(
        source=source,
        parameters=parameters,
        designs=designs,
        sampling=sampling,
        seed=seed,
        chunk=_integer(source, "chunk", data.get("chunk", CHUNK_DESIGNS), 1, 1_000_000),
        motions=names,
        samples=samples,
        evaluator=evaluator,
        optimize=optimize,
        notes=notes,
        files=tuple(
            Path(name) if Path(name).is_absolute() else base / name
            for name in [*names, *([robot_file] if isinstance(robot_file, str) else [])]
            if name not in PAPER_MOTIONS
        ),
    )


def design_values(spec: SweepSpec) -> FloatArray:
    """The designs of a sweep, shape ``(count, p)``, in the order they are generated.

    ``grid``: full factorial with ``designs`` points per parameter, ends
    included, the first parameter varying slowest; ``lhs``: a Latin hypercube
    (:class:`scipy.stats.qmc.LatinHypercube`, ``seed``); ``random``: uniform
    (:func:`numpy.random.default_rng`, ``seed``).
    """
    low = np.array([p.low for p in spec.parameters])
    high = np.array([p.high for p in spec.parameters])
    dims = len(spec.parameters)
    if spec.sampling == "grid":
        axes = [np.linspace(p.low, p.high, spec.designs) for p in spec.parameters]
        mesh = np.meshgrid(*axes, indexing="ij")
        return np.stack([m.reshape(-1) for m in mesh], axis=-1)
    if spec.sampling == "lhs":
        from scipy.stats import qmc

        unit = qmc.LatinHypercube(d=dims, rng=np.random.default_rng(spec.seed)).random(spec.designs)
    else:
        unit = np.random.default_rng(spec.seed).random((spec.designs, dims))
    return np.asarray(low + unit * (high - low))
