"""``SWEEP.toml``: the parameters of a sweep, its sampling, its task and its optimization.

:func:`read_sweep_spec` reads and validates a sweep file into a
:class:`SweepSpec` (:func:`sweep_spec` validates its mapping): the varied
parameters (:class:`Parameter`, a key path of ``ROBOT.toml`` and its range,
:mod:`prp3.apps.design`), the number of designs and how they are drawn
(:data:`SAMPLINGS`), the task's motions and the ``[optimize]`` table
(:class:`~prp3.apps.design_objective.OptimizeSpec`).  :func:`design_values`
gives the designs of a sweep, in the order they are generated.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from prp3 import __version__
from prp3.apps.design import AGGREGATES, DesignEvaluator, design_robot, nominal_design_row
from prp3.apps.design_evaluation import evaluate_designs
from prp3.apps.design_objective import OptimizeSpec
from prp3.errors import (
    ParameterError,
    Prp3Error,
)
from prp3.io.trajectory import read_trajectory
from prp3.model.motion import MAX_SAMPLES, PAPER_MOTIONS, Motion, paper_motion
from prp3.model.robot import Robot
from prp3.model.robot_toml import read_toml
from prp3.validation import check_instance, check_scalar

__all__ = [
    "CHUNK_DESIGNS",
    "MAX_DESIGNS",
    "SAMPLINGS",
    "Parameter",
    "SweepSpec",
    "design_values",
    "parameter_paths",
    "read_sweep_spec",
    "sample_designs",
    "spec_number",
    "sweep_spec",
]

FloatArray = NDArray[np.float64]
T = TypeVar("T")

#: How designs are drawn: full factorial grid (ends included), Latin hypercube, uniform random.
SAMPLINGS: tuple[str, ...] = ("grid", "lhs", "random")

#: Designs per Dask task: hundreds, so that the kernel, not Python or Dask, dominates.
CHUNK_DESIGNS: int = 250

#: Largest number of designs of one sweep (bounds the memory of the design table).
MAX_DESIGNS: int = 10_000_000

_PATH = re.compile(r"^[A-Za-z_][A-Za-z0-9_-]*(\.([A-Za-z_][A-Za-z0-9_-]*|[0-9]+))*$")
_TOP_KEYS = {
    "robot", "designs", "sampling", "seed", "chunk", "parameters", "task", "limits", "optimize",
}  # fmt: skip


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

    @property
    def quantities(self) -> tuple[str, ...]:
        """What an objective, a constraint or a figure may name: the numeric columns and the
        per-leg aggregates (``peak_f10``: the largest of legs A, B, C)."""
        return (*(c for c in self.evaluator.columns if c != "status"), *AGGREGATES)

    def design_values(self) -> FloatArray:
        """The designs, ``(count, p)`` (:func:`design_values`)."""
        return design_values(self)

    def nominal_row(self) -> dict[str, Any]:
        """The row of the nominal robot itself (parameter values as it gives them, else NaN)."""
        evaluator = self.evaluator
        alone = DesignEvaluator(
            nominal=evaluator.nominal,
            paths=(),
            motions=evaluator.motions,
            workspace=evaluator.workspace,
        )
        columns = evaluate_designs(alone, np.zeros((1, 0)))
        return nominal_design_row(evaluator.nominal, self.paths, columns, ("status",))

    def described(self) -> dict[str, Any]:
        """The spec as ``designs.parquet``'s metadata records it (``prp3.spec``)."""
        return {
            "source": self.source,
            "parameters": {p.path: [p.low, p.high] for p in self.parameters},
            "designs": self.designs,
            "sampling": self.sampling,
            "seed": self.seed,
            "motions": list(self.motions),
            "samples": self.samples,
        }

    def digest(self) -> str:
        """SHA-256 of everything the rows depend on (keys the staging folder of a resume)."""
        described = {
            "format": 1,
            "chunk": self.chunk,
            "nominal": self.evaluator.nominal,
            "parameters": [[p.path, p.low, p.high] for p in self.parameters],
            "designs": self.designs,
            "sampling": self.sampling,
            "seed": self.seed,
            "workspace": self.evaluator.workspace,
        }
        fields = ("t", "pose", "velocity", "acceleration")
        return spec_digest(described, self.evaluator.motions, fields)


def spec_digest(described: Mapping[str, Any], motions: Sequence[Any], fields: Sequence[str]) -> str:
    """SHA-256 of a sweep spec: the JSON of ``described`` (with prp3's version), then the
    float64 bytes of the arrays ``fields`` of every motion, in order.

    >>> len(spec_digest({"designs": 2}, [], ()))
    64
    """
    hasher = hashlib.sha256()
    hasher.update(
        json.dumps({"prp3": __version__, **described}, sort_keys=True, default=repr).encode()
    )
    for motion in motions:
        for name in fields:
            hasher.update(np.ascontiguousarray(getattr(motion, name), dtype=np.float64).tobytes())
    return hasher.hexdigest()


def read_spec_file(
    source: str, key: str, name: str, base: Path, read: Callable[[Path], T]
) -> tuple[Path, T]:
    """File ``name`` of a spec (relative to ``base``) and what ``read`` makes of it; its error
    names ``source``, ``key`` and ``name`` (``SWEEP.toml: robot 'r.toml': ...``)."""
    file = Path(name) if Path(name).is_absolute() else base / name
    try:
        return file, read(file)
    except Prp3Error as error:
        raise type(error)(f"{source}: {key} {name!r}: {error}") from None


def read_sweep_spec(path: str | Path) -> SweepSpec:
    """Read and validate ``SWEEP.toml`` (see :func:`sweep_spec`); errors name the file."""
    path = Path(path)
    data = read_toml(path, "sweep")
    return sweep_spec(data, base=path.parent, source=str(path))


def spec_integer(source: str, key: str, value: Any, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise ParameterError(
            f"{source}: {key} must be an integer from {low} to {high}, got {value!r}"
        )
    return value


def spec_number(source: str, key: str, value: Any) -> float:
    """A finite number of a spec file (``source: key must be a finite number``)."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ParameterError(f"{source}: {key} must be a finite number, got {value!r}")
    return float(value)


def spec_table(source: str, name: str, value: Any) -> dict[str, Any]:
    if not isinstance(value, Mapping):
        raise ParameterError(f"{source}: [{name}] must be a table, got {value!r}"[:300])
    return dict(value)


def refuse_unknown_keys(
    source: str, where: str, table: Mapping[str, Any], allowed: set[str]
) -> None:
    for key in table:
        if key not in allowed:
            raise ParameterError(
                f"{source}: unknown key {where}{key!r} (expected one of: {', '.join(sorted(allowed))})"
            )


def spec_sampling(source: str, data: Mapping[str, Any]) -> str:
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


def parameter_paths(table: Mapping[str, Any], where: str) -> list[tuple[str, Any]]:
    """The key paths and values of a ``[parameters]`` table, each path given once.

    TOML keeps ``"platform.mass"`` (one quoted key with a dot) and
    ``platform.mass`` (a dotted key, or ``mass`` in ``[parameters.platform]``)
    apart, but both are the key path ``platform.mass``; tomllib itself refuses
    the same key twice (``"mass"`` and ``mass``).

    Parameters
    ----------
    table : mapping
        The parsed ``[parameters]`` table.
    where : str
        Names the table in messages (``"SWEEP.toml: [parameters]"``).

    Raises
    ------
    ParameterError
        A key path given twice, named with ``where``.

    >>> parameter_paths({"platform.mass": [2, 4], "l0": [0.2, 0.3]}, "s.toml: [parameters]")
    [('platform.mass', [2, 4]), ('l0', [0.2, 0.3])]
    >>> twice = {"platform.mass": [2, 4], "platform": {"mass": [2, 5]}}
    >>> parameter_paths(twice, "s.toml: [parameters]")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: s.toml: [parameters] 'platform.mass' is given twice: ...
    """
    items = _flatten(table)
    seen: set[str] = set()
    for path, _ in items:
        if path in seen:
            raise ParameterError(
                f'{where} {path!r} is given twice: as the quoted key "{path}" and as the '
                f"dotted key {path} (or a table), which name the same parameter: give it once"
            )
        seen.add(path)
    return items


def _parameters(
    source: str, table: Mapping[str, Any], nominal: dict[str, Any]
) -> tuple[Parameter, ...]:
    parameters: list[Parameter] = []
    for path, value in parameter_paths(table, f"{source}: [parameters]"):
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
        low = spec_number(source, f"[parameters] {path!r} low", value[0])
        high = spec_number(source, f"[parameters] {path!r} high", value[1])
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


def spec_motions(
    source: str, base: Path, task: Mapping[str, Any]
) -> tuple[tuple[str, ...], int, tuple[Motion, ...], tuple[str, ...]]:
    refuse_unknown_keys(source, "task.", task, {"motions", "samples"})
    names = task.get("motions", ["vertical", "rotation"])
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise ParameterError(
            f"{source}: task.motions must be a non-empty list of paper motions "
            f"({', '.join(PAPER_MOTIONS)}) or TRAJ.csv paths, got {names!r}"[:300]
        )
    samples = spec_integer(source, "task.samples", task.get("samples", 301), 2, MAX_SAMPLES)
    motions: list[Motion] = []
    notes: list[str] = []
    for name in names:
        if name in PAPER_MOTIONS:
            motions.append(paper_motion(name, samples))
        else:
            _, trajectory = read_spec_file(source, "task.motions", name, base, read_trajectory)
            motions.append(trajectory.motion)
            if trajectory.note is not None:
                notes.append(trajectory.note)
    return tuple(names), samples, tuple(motions), tuple(notes)


def spec_optimize(
    source: str,
    table: Mapping[str, Any],
    columns: Sequence[str],
    *,
    quantities: Sequence[str] | None = None,
    objective: str = "peak_f10",
) -> OptimizeSpec:
    """The ``[optimize]`` table; its quantities are ``quantities`` (default: the numeric
    ``columns`` and the 3-PRP's :data:`~prp3.apps.design.AGGREGATES`)."""
    refuse_unknown_keys(
        source, "optimize.", table, {"objective", "constraints", "maxiter", "popsize", "tol"}
    )
    known = (
        {c for c in columns if c != "status"} | set(AGGREGATES)
        if quantities is None
        else set(quantities)
    )

    def name_of(key: str, value: Any) -> str:
        if not isinstance(value, str) or value not in known:
            raise ParameterError(
                f"{source}: {key}: unknown quantity {value!r} (expected one of: {', '.join(sorted(known))})"
            )
        return value

    objective = name_of("optimize.objective", table.get("objective", objective))
    constraints: list[tuple[str, float, float]] = []
    for key, bounds in spec_table(
        source, "optimize.constraints", table.get("constraints", {})
    ).items():
        name = name_of("optimize.constraints", key)
        where = f"optimize.constraints.{key}"
        bounds = spec_table(source, where, bounds)
        refuse_unknown_keys(source, f"{where}.", bounds, {"min", "max"})
        if not bounds:
            raise ParameterError(f"{source}: {where} must give min and/or max")
        low = spec_number(source, f"{where}.min", bounds["min"]) if "min" in bounds else -math.inf
        high = spec_number(source, f"{where}.max", bounds["max"]) if "max" in bounds else math.inf
        if low > high:
            raise ParameterError(f"{source}: {where}: min > max ({low!r} > {high!r})")
        constraints.append((name, low, high))
    tol = spec_number(source, "optimize.tol", table.get("tol", 0.01))
    if not tol > 0.0:
        raise ParameterError(f"{source}: optimize.tol must be positive, got {tol!r}")
    return OptimizeSpec(
        objective=objective,
        constraints=tuple(constraints),
        maxiter=spec_integer(source, "optimize.maxiter", table.get("maxiter", 30), 1, 100_000),
        popsize=spec_integer(source, "optimize.popsize", table.get("popsize", 10), 1, 10_000),
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
    refuse_unknown_keys(source, "", data, _TOP_KEYS)
    robot_file = data.get("robot")
    nominal = _nominal(data, base, source)
    sampling = spec_sampling(source, data)
    designs = spec_integer(
        source, "designs", data.get("designs", 100), 2 if sampling == "grid" else 1, MAX_DESIGNS
    )
    seed = spec_integer(source, "seed", data.get("seed", 0), 0, 2**63 - 1)
    parameters = _parameters(
        source, spec_table(source, "parameters", data.get("parameters", {})), nominal
    )
    if sampling == "grid" and designs ** len(parameters) > MAX_DESIGNS:
        raise ParameterError(
            f"{source}: a grid of {designs} points per parameter over {len(parameters)} "
            f"parameters has {designs}^{len(parameters)} designs, more than {MAX_DESIGNS}"
        )
    names, samples, motions, notes = spec_motions(
        source, base, spec_table(source, "task", data.get("task", {}))
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
    optimize = spec_optimize(
        source, spec_table(source, "optimize", data.get("optimize", {})), evaluator.columns
    )
    return SweepSpec(
        source=source,
        parameters=parameters,
        designs=designs,
        sampling=sampling,
        seed=seed,
        chunk=spec_integer(source, "chunk", data.get("chunk", CHUNK_DESIGNS), 1, 1_000_000),
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


def _nominal(data: Mapping[str, Any], base: Path, source: str) -> dict[str, Any]:
    """The nominal robot's mapping: the spec's ``robot`` file (relative to ``base``) or the
    paper's robot, with the spec's ``[limits]`` over its own (the result checked)."""
    robot_file = data.get("robot")
    if robot_file is None:
        robot = Robot()
    elif isinstance(robot_file, str) and robot_file:
        _, robot = read_spec_file(source, "robot", robot_file, base, Robot.from_toml)
    else:
        raise ParameterError(
            f"{source}: robot must be the path of a ROBOT.toml, got {robot_file!r}"
        )
    nominal: dict[str, Any] = tomllib.loads(robot.to_toml())
    if "limits" in data:
        limits = spec_table(source, "limits", data["limits"])
        nominal["limits"] = {**nominal.get("limits", {}), **limits}
        try:
            Robot.from_mapping(nominal)
        except ParameterError as error:
            raise ParameterError(
                f"{source}: [limits]: {re.sub(r'^robot: ', '', str(error))}"
            ) from None
    return nominal


def design_values(spec: SweepSpec) -> FloatArray:
    """The designs of a sweep, shape ``(count, p)``, in the order they are generated
    (:func:`sample_designs` of its parameters, ``designs``, ``sampling`` and ``seed``)."""
    return sample_designs(spec.parameters, spec.designs, spec.sampling, spec.seed)


def sample_designs(
    parameters: Sequence[Parameter], designs: int, sampling: str, seed: int
) -> FloatArray:
    """Designs over the ranges of ``parameters``, shape ``(count, p)``, in order.

    ``grid``: full factorial with ``designs`` points per parameter, ends
    included, the first parameter varying slowest; ``lhs``: a Latin hypercube
    (:class:`scipy.stats.qmc.LatinHypercube`, ``seed``); ``random``: uniform
    (:func:`numpy.random.default_rng`, ``seed``).  No parameters: one design of
    no value, ``(1, 0)``.
    """
    dims = len(parameters)
    if dims == 0:
        return np.zeros((1, 0))
    low = np.array([p.low for p in parameters])
    high = np.array([p.high for p in parameters])
    if sampling == "grid":
        axes = [np.linspace(p.low, p.high, designs) for p in parameters]
        mesh = np.meshgrid(*axes, indexing="ij")
        return np.stack([m.reshape(-1) for m in mesh], axis=-1)
    if sampling == "lhs":
        from scipy.stats import qmc

        unit = qmc.LatinHypercube(d=dims, rng=np.random.default_rng(seed)).random(designs)
    else:
        unit = np.random.default_rng(seed).random((designs, dims))
    return np.asarray(low + unit * (high - low))
