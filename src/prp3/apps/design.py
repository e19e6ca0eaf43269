"""Designs: robots named by key paths of ``ROBOT.toml``, and the task they are evaluated on.

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
:class:`DesignEvaluator` holds what a worker needs to evaluate designs (the
nominal robot, the paths, the task), and :func:`design_columns` names the
columns of their rows; the evaluation is
:func:`prp3.apps.design_evaluation.evaluate_designs`.
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

import numpy as np
from numpy.typing import NDArray

from prp3.errors import (
    ParameterError,
    Prp3Error,
    SingularPoseError,
)
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.pose_validation import check_poses
from prp3.validation import LEGS, check_finite, check_instance, check_real

__all__ = [
    "AGGREGATES",
    "DesignEvaluator",
    "RowEvaluator",
    "design_columns",
    "design_mapping",
    "design_robot",
    "nominal_design_row",
    "nominal_value",
]

R = TypeVar("R")

FloatArray = NDArray[np.float64]

#: Up to this many parameters the corners of their box are checked once (2**p robots);
#: with more, every design is built and checked.
_CORNER_PARAMETERS: int = 10

#: Per-leg peak quantities; ``peak_f10`` etc. (no leg) means the largest of the three legs.
AGGREGATES: tuple[str, ...] = ("peak_f10", "peak_p10", "peak_f21", "peak_n32")


# ------------------------------------------------------------------ key paths
def path_components(path: str) -> list[str | int]:
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
        parts = path_components(path)
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


def nominal_design_row(
    nominal: Mapping[str, Any],
    paths: Sequence[str],
    columns: Mapping[str, Any],
    text_columns: Sequence[str],
) -> dict[str, Any]:
    """The nominal row of a designs file's metadata: each parameter's nominal value (NaN
    where the nominal mapping gives none), then the first row of the evaluated ``columns``.

    >>> nominal_design_row({"l0": 0.3}, ["l0", "payload.mass"], {"status": ["ok"]}, ["status"])
    {'l0': 0.3, 'payload.mass': nan, 'status': 'ok'}
    """
    row: dict[str, Any] = {}
    for path in paths:
        try:
            value = nominal_value(nominal, path)
        except Prp3Error:  # not a 3-PRP mapping: no computed default
            value = None
        row[path] = math.nan if value is None else value
    return row | first_row(columns, text_columns)


def first_row(columns: Mapping[str, Any], text_columns: Sequence[str]) -> dict[str, Any]:
    """The first row of evaluated ``columns``: ``str`` of the ``text_columns``, else ``float``.

    >>> first_row({"status": ["ok"], "energy": [2.5]}, ["status"])
    {'status': 'ok', 'energy': 2.5}
    """
    return {n: (str(v[0]) if n in text_columns else float(v[0])) for n, v in columns.items()}


def status_columns(
    builders: Sequence[Callable[[], R]],
    row: Callable[[int, R], tuple[str, Sequence[float]]],
    names: Sequence[str],
) -> dict[str, FloatArray]:
    """The ``status`` column and the result columns ``names`` of designs, for every robot.

    Design ``i`` is the robot ``builders[i]()``: ``invalid`` (NaN results) when that raises
    :class:`~prp3.errors.ParameterError`, else the status and the ``len(names)`` values of
    ``row(i, robot)``.

    >>> def build(): return 2.0
    >>> def bad(): raise ParameterError("not a robot")
    >>> columns = status_columns([build, bad], lambda i, r: ("ok", [r, 3 * r]), ["a", "b"])
    >>> columns["status"].tolist(), columns["b"].tolist()
    (['ok', 'invalid'], [6.0, nan])
    """
    status: list[str] = []
    results = np.full((len(builders), len(names)), np.nan)
    for i, build in enumerate(builders):
        try:
            robot = build()
        except ParameterError:
            status.append("invalid")
            continue
        state, numbers = row(i, robot)
        status.append(state)
        results[i] = numbers
    columns: dict[str, Any] = {"status": np.array(status, dtype=str)}
    for j, name in enumerate(names):
        columns[name] = results[:, j].copy()
    return columns


def nominal_value(nominal: Mapping[str, Any], path: str) -> float | None:
    """The value at ``path`` in the nominal mapping; ``None`` when it does not give one.

    A missing ``platform.inertia`` is the one the robot computes (``m3·l²/12``).

    >>> nominal_value({"l0": 0.3}, "l0"), nominal_value({"l0": 0.3}, "payload.mass")
    (0.3, None)
    """
    node: Any = nominal
    for part in path_components(path):
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
class RowEvaluator(Protocol):
    """What the sweep and the optimization of designs need of an evaluator (picklable).

    :class:`~prp3.apps.spatial_design.SpatialEvaluator` (the spatial robots) is one;
    :class:`DesignEvaluator` (the 3-PRP) has the columns, its rows are
    :func:`~prp3.apps.design_evaluation.evaluate_designs`' (both:
    :func:`~prp3.apps.design_evaluation.evaluate_rows`).
    :func:`prp3.apps.sweep.run_sweep` sends it to the Dask workers once and evaluates
    each chunk of designs there.
    """

    @property
    def columns(self) -> tuple[str, ...]:
        """The columns of the design table, in order."""
        ...

    @property
    def text_columns(self) -> tuple[str, ...]:
        """The columns of text (``status``, ...); the others are float64."""
        ...

    def evaluate(self, values: FloatArray) -> dict[str, Any]:
        """The columns of the rows of designs ``values (k, p)``."""
        ...


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
        (:func:`~prp3.apps.design_evaluation.evaluate_designs`).
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

    @property
    def text_columns(self) -> tuple[str, ...]:
        """The column of text: ``status``."""
        return ("status",)


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
