"""Design sweeps and optimisation of the spatial robots (docs/spatial.md §21).

A *spatial sweep spec* is a ``SWEEP.toml`` with a top-level ``spatial`` key: one
spatial robot (an architecture of docs/spatial.md §13, ``"6-UPS"``, ``"3-RPS"``,
``"3-RUU"``, for its default design, or a spatial robot file) or a list of them,
evaluated on the same task.  Its ``[parameters]`` vary values of the robot file
by key path (``base_radius``, ``"platform.mass"``, ``"stroke.1"``: the upper end
of the stroke, ``"rod.centre.0"``), each over ``[low, high]``; a key path applies
to every listed robot whose file has it, and is refused when none has it.  The
designs are drawn once (``sampling``, ``designs``, ``seed``: as for the 3-PRP,
:func:`prp3.apps.sweep_spec.sample_designs`) and every robot is evaluated at the
same values, robot by robot: the rows of a comparison of architectures are
paired.  The task is ``[task] motions``: the built-in motions of §15 (``heave``,
``circle``, ``tilt``, made for each design about its own home pose, ``samples``
samples over ``duration`` s) or spatial trajectory files (§14), completed for a
robot of fewer than 6 DOF (§11).

Each design is one row (:attr:`SpatialEvaluator.columns`): ``robot`` (as the spec
names it), ``architecture``, the parameters (NaN where the robot does not have
that key), ``status`` (:data:`SPATIAL_STATUSES`) and the objective columns
:data:`SPATIAL_DESIGN_COLUMNS`, reduced from
:func:`prp3.spatial.outputs.spatial_inverse_dynamics` (the Newton–Euler route,
every joint's wrench) of every motion of the task, the samples of the motions
taken together:

* ``peak_effort``: ``max |tau|`` over the samples and the legs (N for a P actuator,
  N·m for an R: the Delta's);
* ``peak_power``: ``max |power|``, ``power = tau·dq_act`` (W);
* ``rms_power``: ``sqrt(mean(power²))`` over the samples and the legs (W);
* ``energy``: ``Σ_motions ∫ Σ_legs power dt`` (trapezoid rule, J);
* ``peak_joint_force``, ``peak_joint_moment``: the largest ``|F|`` (N) and ``|M|``
  (N·m) of any joint of any leg (§9: the wrench through the joint, the actuator's
  effort included);
* ``min_mu_leg``, ``min_mu_par``: the smallest serial and parallel measure of §6
  times its sign at home over the task (the singularity margins: at least
  ``SINGULAR = 1e-4`` for a design that performs the task);
* ``reachable``: the fraction of the task's samples at which every leg reaches the
  pose within its limits and both measures are on their home side
  (:func:`prp3.spatial.workspace.pose_reasons`, the ``regular`` of §17); computed
  for every valid design, 1 for those whose status is ``ok``.

A design that cannot perform the task has the status that says why and NaN in
every other objective column: ``unreachable`` (a pose out of a leg's reach or
limits), ``singular`` (reachable, but a measure below ``SINGULAR`` on its home
side) or ``invalid`` (the values are not a robot: its home pose is out of reach or
singular).

>>> spec = spatial_sweep_spec({"spatial": ["6-UPS", "3-RPS"], "designs": 2,
...     "sampling": "grid", "parameters": {"platform.mass": [1.0, 2.0]},
...     "task": {"motions": ["heave"], "samples": 11}})
>>> values = spec.design_values()
>>> values.tolist()
[[0.0, 1.0], [0.0, 2.0], [1.0, 1.0], [1.0, 2.0]]
>>> columns = spec.evaluator.evaluate(values)
>>> [str(s) for s in columns["architecture"]], [str(s) for s in columns["status"]]
(['6-UPS', '6-UPS', '3-RPS', '3-RPS'], ['ok', 'ok', 'ok', 'ok'])
>>> round(float(columns["peak_effort"][0]), 6), float(columns["reachable"][0])
(2.990694, 1.0)
"""

from __future__ import annotations

import copy
import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from prp3.apps.design import (
    design_mapping,
    first_row,
    nominal_design_row,
    nominal_value,
    status_columns,
)
from prp3.apps.design_objective import OptimizeSpec
from prp3.apps.sweep_spec import (
    MAX_DESIGNS,
    Parameter,
    parameter_paths,
    read_spec_file,
    refuse_unknown_keys,
    sample_designs,
    spec_digest,
    spec_integer,
    spec_number,
    spec_optimize,
    spec_sampling,
    spec_table,
)
from prp3.errors import ParameterError, Prp3Error, SingularPoseError
from prp3.io.spatial_robot import (
    SPATIAL_ARCHITECTURES,
    SpatialRobotFile,
    read_spatial_robot,
    spatial_robot_from_mapping,
    spatial_robot_text,
)
from prp3.io.spatial_trajectory import read_spatial_trajectory
from prp3.model.robot_toml import read_toml
from prp3.spatial.kinematics import complete_motion, home_signs
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import SPATIAL_MOTIONS, PlatformMotion, spatial_motion
from prp3.spatial.outputs import spatial_inverse_dynamics
from prp3.spatial.workspace import pose_reasons
from prp3.validation import check_file_path

if TYPE_CHECKING:
    from prp3.apps.cluster import ClientOrFactory, Progress
    from prp3.apps.optimization import OptimizeOutcome

__all__ = [
    "SPATIAL_CHUNK",
    "SPATIAL_DESIGN_COLUMNS",
    "SPATIAL_STATUSES",
    "SpatialEvaluator",
    "SpatialStudy",
    "SpatialSweepSpec",
    "is_spatial_spec",
    "optimize_spatial",
    "read_spatial_sweep_spec",
    "spatial_design_file",
    "spatial_sweep_spec",
]

FloatArray = NDArray[np.float64]

#: Values of the ``status`` column.
SPATIAL_STATUSES: tuple[str, ...] = ("ok", "unreachable", "singular", "invalid")

#: The objective columns, after ``status`` (see the module's description).
SPATIAL_DESIGN_COLUMNS: tuple[str, ...] = (
    "peak_effort",
    "peak_power",
    "rms_power",
    "energy",
    "peak_joint_force",
    "peak_joint_moment",
    "min_mu_leg",
    "min_mu_par",
    "reachable",
)

#: Designs per Dask task by default (a design takes about 0.1 s per 100 samples).
SPATIAL_CHUNK: int = 10

_TOP_KEYS = {"spatial", "designs", "sampling", "seed", "chunk", "parameters", "task", "optimize"}
_TASK_KEYS = {"motions", "samples", "duration"}


def is_spatial_spec(data: Mapping[str, Any]) -> bool:
    """Whether a parsed ``SWEEP.toml`` is a spatial sweep spec (it has ``spatial``).

    >>> is_spatial_spec({"spatial": "6-UPS"}), is_spatial_spec({"robot": "ROBOT.toml"})
    (True, False)
    """
    return "spatial" in data


@dataclass(frozen=True)
class SpatialStudy:
    """One robot of a spatial sweep.

    Attributes
    ----------
    name : str
        As the spec names it (an architecture, or the robot file's path).
    architecture : str
    nominal : dict
        The mapping the designs start from: the robot file's keys as it gives them
        (``{"architecture": ...}`` for a default design), so that a key it leaves out
        keeps following the others as in the file (the Delta's arm centre follows a
        swept ``arm``); with the arrays a parameter indexes (``stroke.1``) filled in.
    values : dict
        Every key of the robot file, defaults filled in (:func:`~prp3.io.spatial_robot.spatial_robot_text`).
    paths : tuple of str
        The key paths of the spec's parameters it has, in the spec's order.
    """

    name: str
    architecture: str
    nominal: dict[str, Any]
    values: dict[str, Any]
    paths: tuple[str, ...]


def spatial_design_file(study: SpatialStudy, values: Sequence[float]) -> Any:
    """The spatial robot file (:class:`~prp3.io.spatial_robot.SpatialRobotFile`) of a design:
    ``study``'s nominal mapping with its ``paths`` set to ``values``.

    Raises
    ------
    ParameterError
        The values are not a robot (names the key, or the home pose's refusal).
    """
    return spatial_robot_from_mapping(design_mapping(study.nominal, study.paths, list(values)))


@dataclass(frozen=True, eq=False)
class SpatialEvaluator:
    """What a worker needs to evaluate spatial designs (a :class:`~prp3.apps.design.RowEvaluator`).

    Attributes
    ----------
    studies : tuple of SpatialStudy
    paths : tuple of str
        Every parameter's key path, in column order.
    motions : tuple of str
        The task's motions as the spec names them.
    trajectories : tuple of PlatformMotion or None
        The motion of each trajectory file; ``None`` for a built-in motion.
    samples : int; duration : float
        Samples and duration (s) of the built-in motions.
    indexed : bool
        Whether a design's values begin with its study's index (a sweep); otherwise
        there is one study and the values are its parameters' (an optimisation).
    """

    studies: tuple[SpatialStudy, ...]
    paths: tuple[str, ...]
    motions: tuple[str, ...]
    trajectories: tuple[PlatformMotion | None, ...]
    samples: int
    duration: float
    indexed: bool = True

    @property
    def columns(self) -> tuple[str, ...]:
        """Column names of ``designs.parquet``."""
        return ("robot", "architecture", *self.paths, "status", *SPATIAL_DESIGN_COLUMNS)

    @property
    def text_columns(self) -> tuple[str, ...]:
        """The columns of text."""
        return ("robot", "architecture", "status")

    def task(self, robot: SpatialRobot) -> list[PlatformMotion]:
        """The task's motions for ``robot`` (the built-in ones about its home pose)."""
        return [
            spatial_motion(robot, name, self.samples, self.duration) if given is None else given
            for name, given in zip(self.motions, self.trajectories, strict=True)
        ]

    def row(self, robot: SpatialRobot) -> tuple[str, list[float]]:
        """The status and the :data:`SPATIAL_DESIGN_COLUMNS` of one robot on the task."""
        nan = [math.nan] * len(SPATIAL_DESIGN_COLUMNS)
        motions = self.task(robot)
        regular, reasons, count = 0, 0, 0
        for motion in motions:
            poses = pose_reasons(robot, motion.position, motion.rotation)
            regular += int(poses.regular.sum())
            reasons += int((poses.reason != 0).sum())
            count += len(motion)
        reachable = regular / count
        if regular < count:
            return ("unreachable" if reasons else "singular"), [*nan[:-1], reachable]
        tau, power, force, moment, leg, par = [], [], [], [], [], []
        energy = 0.0
        sign_leg, sign_par = home_signs(robot)
        try:
            with np.errstate(all="ignore"):  # an overflow is a row that cannot be computed
                for motion in motions:
                    solution = spatial_inverse_dynamics(robot, complete_motion(robot, motion))
                    assert solution.force is not None and solution.moment is not None
                    tau.append(solution.tau)
                    power.append(solution.power)
                    force.append(np.linalg.norm(solution.force, axis=-1))
                    moment.append(np.linalg.norm(solution.moment, axis=-1))
                    energy += float(np.trapezoid(solution.power.sum(axis=-1), solution.t))
                    leg.append(solution.kinematics.leg_measure * sign_leg)
                    par.append(solution.kinematics.parallel_measure * sign_par)
        except SingularPoseError:
            return "singular", [*nan[:-1], reachable]
        except Prp3Error:  # UnreachablePoseError, or no completion of the motion
            return "unreachable", [*nan[:-1], reachable]
        all_power = np.concatenate(power)
        values = [
            float(np.abs(np.concatenate(tau)).max()),
            float(np.abs(all_power).max()),
            float(np.sqrt(np.mean(all_power**2))),
            energy,
            float(np.concatenate(force).max()),
            float(np.concatenate(moment).max()),
            float(np.concatenate(leg).min()),
            float(np.concatenate(par).min()),
            1.0,
        ]
        if not all(math.isfinite(v) for v in values):
            return "unreachable", [*nan[:-1], reachable]
        return "ok", values

    def evaluate(self, values: FloatArray) -> dict[str, Any]:
        """The columns of designs ``values``: ``(k, 1 + p)`` (study index, then every
        parameter, NaN where that study lacks it) when ``indexed``, else ``(k, p)``."""
        values = np.asarray(values, dtype=np.float64).reshape(len(values), -1)
        count = len(values)
        index = values[:, 0].astype(np.int64) if self.indexed else np.zeros(count, np.int64)
        xs = values[:, 1:] if self.indexed else values
        studies = [self.studies[i] for i in index.tolist()]
        columns: dict[str, Any] = {
            "robot": np.array([s.name for s in studies], dtype=str),
            "architecture": np.array([s.architecture for s in studies], dtype=str),
            **{path: xs[:, j].copy() for j, path in enumerate(self.paths)},
        }
        builders = [
            partial(_design_robot, study, [float(xs[i, self.paths.index(p)]) for p in study.paths])
            for i, study in enumerate(studies)
        ]
        return columns | status_columns(
            builders, lambda _, robot: self.row(robot), SPATIAL_DESIGN_COLUMNS
        )


def _design_robot(study: SpatialStudy, values: Sequence[float]) -> SpatialRobot:
    design: SpatialRobotFile = spatial_design_file(study, values)
    return design.robot


@dataclass(frozen=True, eq=False)
class SpatialRobotSpec:
    """One robot of a spatial sweep spec, to optimise (:func:`optimize_spatial`; a
    :class:`~prp3.apps.optimization.Optimizable`)."""

    study: SpatialStudy
    parameters: tuple[Parameter, ...]
    evaluator: SpatialEvaluator
    optimize: OptimizeSpec
    seed: int

    @property
    def paths(self) -> tuple[str, ...]:
        """Key paths of its parameters."""
        return tuple(p.path for p in self.parameters)

    @property
    def bounds(self) -> list[tuple[float, float]]:
        """``(low, high)`` of every parameter."""
        return [(p.low, p.high) for p in self.parameters]


@dataclass(frozen=True, eq=False)
class SpatialSweepSpec:
    """A validated spatial ``SWEEP.toml`` (a :class:`~prp3.apps.sweep.Sweepable`).

    Attributes
    ----------
    source : str
    parameters : tuple of Parameter
    designs, sampling, seed, chunk
        As in :class:`~prp3.apps.sweep_spec.SweepSpec`.
    evaluator : SpatialEvaluator
    optimize : OptimizeSpec
    notes : tuple of str
        Warnings (a trajectory file's rates derived from its poses).
    files : tuple of Path
        The robot and trajectory files it reads.
    """

    source: str
    parameters: tuple[Parameter, ...]
    designs: int
    sampling: str
    seed: int
    chunk: int
    evaluator: SpatialEvaluator
    optimize: OptimizeSpec
    notes: tuple[str, ...] = ()
    files: tuple[Path, ...] = ()

    @property
    def studies(self) -> tuple[SpatialStudy, ...]:
        """The robots of the sweep."""
        return self.evaluator.studies

    @property
    def motions(self) -> tuple[str, ...]:
        """The task's motions as given."""
        return self.evaluator.motions

    @property
    def paths(self) -> tuple[str, ...]:
        """Key paths of the parameters."""
        return tuple(p.path for p in self.parameters)

    @property
    def quantities(self) -> tuple[str, ...]:
        """What an objective, a constraint or a figure may name."""
        return (*self.paths, *SPATIAL_DESIGN_COLUMNS)

    @property
    def count(self) -> int:
        """Number of rows: the designs of every robot (one for a robot without parameters)."""
        per = self.designs ** len(self.parameters) if self.sampling == "grid" else self.designs
        return sum(per if study.paths else 1 for study in self.studies)

    def design_values(self) -> FloatArray:
        """The rows' designs ``(count, 1 + p)``: the robot's index, then every parameter
        (NaN where the robot lacks it); the same designs for every robot, robot by robot."""
        sample = sample_designs(self.parameters, self.designs, self.sampling, self.seed)
        blocks = []
        for index, study in enumerate(self.studies):
            have = np.array([path in study.paths for path in self.paths], dtype=bool)
            part = (
                np.where(have, sample, np.nan) if study.paths else np.full((1, have.size), np.nan)
            )
            blocks.append(np.column_stack([np.full(len(part), float(index)), part]))
        return np.concatenate(blocks)

    def nominal_row(self) -> dict[str, Any]:
        """The row of the first robot's nominal design."""
        study = self.studies[0]
        alone = replace(
            self.evaluator, studies=(replace(study, paths=()),), paths=(), indexed=False
        )
        columns = alone.evaluate(np.zeros((1, 0)))
        return nominal_design_row(study.values, self.paths, columns, self.evaluator.text_columns)

    def described(self) -> dict[str, Any]:
        """The spec as ``designs.parquet``'s metadata records it."""
        return {
            "source": self.source,
            "spatial": [study.name for study in self.studies],
            "parameters": {p.path: [p.low, p.high] for p in self.parameters},
            "designs": self.designs,
            "sampling": self.sampling,
            "seed": self.seed,
            "motions": list(self.motions),
            "samples": self.evaluator.samples,
            "duration": self.evaluator.duration,
        }

    def digest(self) -> str:
        """SHA-256 of everything the rows depend on (keys the staging folder of a resume)."""
        described = {
            "format": "spatial-1",
            "chunk": self.chunk,
            "nominal": [[s.name, s.nominal] for s in self.studies],
            **{k: v for k, v in self.described().items() if k != "source"},
        }
        motions = [m for m in self.evaluator.trajectories if m is not None]
        fields = ("t", "position", "rotation", "omega", "velocity", "alpha", "acceleration")
        return spec_digest(described, motions, fields)

    def robot_spec(self, index: int) -> SpatialRobotSpec:
        """Robot ``index`` alone with its parameters, to optimise (seed ``seed + index``)."""
        study = self.studies[index]
        evaluator = replace(self.evaluator, studies=(study,), paths=study.paths, indexed=False)
        parameters = tuple(p for p in self.parameters if p.path in study.paths)
        return SpatialRobotSpec(study, parameters, evaluator, self.optimize, self.seed + index)


# ------------------------------------------------------------------ SWEEP.toml
def read_spatial_sweep_spec(path: str | Path) -> SpatialSweepSpec:
    """Read and validate a spatial ``SWEEP.toml`` (:func:`spatial_sweep_spec`)."""
    path = check_file_path("path", path)
    return spatial_sweep_spec(read_toml(path, "sweep"), base=path.parent, source=str(path))


def _leaves(table: Mapping[str, Any], prefix: str = "") -> list[str]:
    """The key paths of the numbers of a mapping (arrays indexed: ``stroke.0``)."""
    out: list[str] = []
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out += _leaves(value, f"{path}.")
        elif isinstance(value, list):
            out += _leaves({str(k): v for k, v in enumerate(value)}, f"{path}.")
        elif isinstance(value, int | float) and not isinstance(value, bool):
            out.append(path)
    return out


def _robot_file(file: Path) -> tuple[SpatialRobotFile, dict[str, Any]]:
    """A spatial robot file and its mapping as it gives it."""
    return read_spatial_robot(file), dict(read_toml(file, "robot"))


def _studies(source: str, base: Path, spatial: Any) -> tuple[list[SpatialStudy], list[Path]]:
    names = [spatial] if isinstance(spatial, str) else spatial
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise ParameterError(
            f"{source}: spatial must be an architecture ({', '.join(SPATIAL_ARCHITECTURES)}), "
            f"the path of a spatial robot file, or a non-empty list of them, got {spatial!r}"[:300]
        )
    studies, files = [], []
    for name in names:
        if name in SPATIAL_ARCHITECTURES:
            given: dict[str, Any] = {"architecture": name}
            text = spatial_robot_text(name, comments=False)
        else:
            file, (design, given) = read_spec_file(source, "spatial", name, base, _robot_file)
            text = spatial_robot_text(design, comments=False)
            files.append(file)
        values = tomllib.loads(text)
        studies.append(SpatialStudy(name, str(values["architecture"]), given, values, ()))
    return studies, files


def _with_array(nominal: dict[str, Any], values: Mapping[str, Any], path: str) -> dict[str, Any]:
    """``nominal`` with the array ``path`` indexes (``stroke.1``: ``stroke``) taken from
    ``values`` where ``nominal`` leaves it out."""
    out = copy.deepcopy(nominal)
    node, full = out, values
    for part in path.split(".")[:-1]:
        if not isinstance(full, Mapping) or part not in full:
            break
        if part not in node:
            node[part] = copy.deepcopy(full[part]) if isinstance(full[part], list) else {}
        if isinstance(full[part], list):
            break
        node, full = node[part], full[part]
    return out


def _parameters(
    source: str, table: Mapping[str, Any], studies: list[SpatialStudy]
) -> tuple[tuple[Parameter, ...], list[SpatialStudy]]:
    parameters: list[Parameter] = []
    have: list[list[str]] = [[] for _ in studies]
    for path, value in parameter_paths(table, f"{source}: [parameters]"):
        where = f"{source}: [parameters] {path!r}"
        if not (isinstance(value, list) and len(value) == 2):
            raise ParameterError(f"{where}: the range must be [low, high], got {value!r}"[:300])
        low = spec_number(source, f"[parameters] {path!r} low", value[0])
        high = spec_number(source, f"[parameters] {path!r} high", value[1])
        if not low < high:
            raise ParameterError(f"{where}: low must be below high, got [{low!r}, {high!r}]")
        applies = [i for i, s in enumerate(studies) if nominal_value(s.values, path) is not None]
        if not applies:
            known: dict[str, None] = {}  # the leaves, array indices shown as N, in order
            for study in studies:
                for leaf in _leaves(study.values):
                    known[".".join("N" if p.isdigit() else p for p in leaf.split("."))] = None
            robots = ", ".join(dict.fromkeys(s.architecture for s in studies))
            raise ParameterError(
                f"{where}: not a key path of the spatial robot file of {robots} (expected one "
                f"of: {', '.join(known)}; N an index from 0)"
            )
        for i in applies:
            studies[i] = replace(
                studies[i], nominal=_with_array(studies[i].nominal, studies[i].values, path)
            )
            for end in (low, high):
                try:
                    spatial_design_file(replace(studies[i], paths=(path,)), [end])
                except ParameterError as error:
                    if error.key is not None:  # the key's own check; a home pose is a row
                        raise ParameterError(
                            f"{where} = {end!r} ({studies[i].name}): {error.reason}"
                        ) from None
            have[i].append(path)
        parameters.append(Parameter(path, low, high))
    studies = [replace(s, paths=tuple(paths)) for s, paths in zip(studies, have, strict=True)]
    return tuple(parameters), studies


def _task(
    source: str, base: Path, task: Mapping[str, Any], studies: list[SpatialStudy]
) -> tuple[tuple[str, ...], tuple[PlatformMotion | None, ...], int, float, list[str], list[Path]]:
    refuse_unknown_keys(source, "task.", task, _TASK_KEYS)
    names = task.get("motions", ["heave"])
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise ParameterError(
            f"{source}: task.motions must be a non-empty list of built-in motions "
            f"({', '.join(SPATIAL_MOTIONS)}) or spatial trajectory files, got {names!r}"[:300]
        )
    samples = spec_integer(source, "task.samples", task.get("samples", 101), 2, 100_000)
    duration = spec_number(source, "task.duration", task.get("duration", 3.0))
    if not duration > 0.0:
        raise ParameterError(f"{source}: task.duration must be positive (s), got {duration!r}")
    motions: list[PlatformMotion | None] = []
    notes, files = [], []
    for name in names:
        if name in SPATIAL_MOTIONS:
            for study in studies:
                robot = spatial_robot_from_mapping(study.values).robot
                try:
                    spatial_motion(robot, name, 2, duration)
                except ParameterError as error:
                    raise ParameterError(
                        f"{source}: task.motions {name!r} for {study.name}: {error.reason}"
                    ) from None
            motions.append(None)
            continue
        file, trajectory = read_spec_file(
            source, "task.motions", name, base, read_spatial_trajectory
        )
        motions.append(trajectory.motion)
        files.append(file)
        if trajectory.note is not None:
            notes.append(trajectory.note)
    return tuple(names), tuple(motions), samples, duration, notes, files


def spatial_sweep_spec(
    data: Mapping[str, Any], *, base: str | Path = ".", source: str = "SWEEP.toml"
) -> SpatialSweepSpec:
    """Validate a spatial ``SWEEP.toml`` mapping; paths in it are relative to ``base``.

    Raises
    ------
    ParameterError, InputFileError, TrajectoryError
        One line naming ``source``, the key and the value: an unknown key, a key path no
        listed robot has, a range that is not ``[low, high]`` with ``low < high``, an end
        that is not a valid value of its key, a built-in motion a robot cannot make (the
        Delta's tilt), a missing file, too many designs.
    """
    if not isinstance(data, Mapping):
        raise ParameterError(f"{source}: a sweep spec is a table, got {data!r}"[:200])
    base = Path(base)
    refuse_unknown_keys(source, "", data, _TOP_KEYS)
    studies, robot_files = _studies(source, base, data.get("spatial"))
    sampling = spec_sampling(source, data)
    designs = spec_integer(
        source, "designs", data.get("designs", 20), 2 if sampling == "grid" else 1, MAX_DESIGNS
    )
    seed = spec_integer(source, "seed", data.get("seed", 0), 0, 2**63 - 1)
    parameters, studies = _parameters(
        source, spec_table(source, "parameters", data.get("parameters", {})), studies
    )
    if sampling == "grid" and designs ** len(parameters) * len(studies) > MAX_DESIGNS:
        raise ParameterError(
            f"{source}: a grid of {designs} points per parameter over {len(parameters)} "
            f"parameters for {len(studies)} robots has more than {MAX_DESIGNS} designs"
        )
    names, motions, samples, duration, notes, files = _task(
        source, base, spec_table(source, "task", data.get("task", {})), studies
    )
    evaluator = SpatialEvaluator(
        studies=tuple(studies),
        paths=tuple(p.path for p in parameters),
        motions=names,
        trajectories=motions,
        samples=samples,
        duration=duration,
    )
    optimize = spec_optimize(
        source,
        spec_table(source, "optimize", data.get("optimize", {})),
        evaluator.columns,
        quantities=(*evaluator.paths, *SPATIAL_DESIGN_COLUMNS),
        objective="peak_effort",
    )
    return SpatialSweepSpec(
        source=source,
        parameters=parameters,
        designs=designs,
        sampling=sampling,
        seed=seed,
        chunk=spec_integer(source, "chunk", data.get("chunk", SPATIAL_CHUNK), 1, 1_000_000),
        evaluator=evaluator,
        optimize=optimize,
        notes=tuple(notes),
        files=(*robot_files, *files),
    )


# ------------------------------------------------------------------ optimisation
def optimize_spatial(
    spec: SpatialSweepSpec, client: ClientOrFactory, *, progress: Progress | None = None
) -> list[tuple[SpatialRobotSpec, OptimizeOutcome]]:
    """Minimise ``spec.optimize.objective`` under its constraints for every robot of ``spec``.

    Each robot with parameters runs :func:`prp3.apps.optimization.optimize_design`
    (scipy's differential evolution over the ranges of its parameters, each
    generation on the Dask workers, seed ``seed + index``); a design that cannot
    perform the task (unreachable, singular, invalid) or violates a constraint is
    infeasible (:func:`prp3.apps.design_objective.penalized_objective`).  A robot
    without parameters is its nominal design.  ``client`` as for
    :func:`~prp3.apps.optimization.optimize_design` (a factory is called once).
    """
    from prp3.apps.cluster import using
    from prp3.apps.design_objective import INFEASIBLE, penalized_objective
    from prp3.apps.optimization import OptimizeOutcome, optimize_design

    results = []
    with using(client, "client") as dask:
        for index in range(len(spec.studies)):
            single = spec.robot_spec(index)
            if single.parameters:
                outcome = optimize_design(single, dask, progress=progress)
            else:
                columns = single.evaluator.evaluate(np.zeros((1, 0)))
                value = float(penalized_objective(spec.optimize, columns)[0])
                row = first_row(columns, single.evaluator.text_columns)
                feasible = value < INFEASIBLE
                history = {
                    "generation": np.zeros(1),
                    "objective": np.array([value if feasible else math.nan]),
                    "violation": np.array([0.0 if feasible else value - INFEASIBLE]),
                }
                outcome = OptimizeOutcome(
                    np.zeros(0), value, feasible, row, 0, 1, "nominal design", history
                )
            results.append((single, outcome))
    return results
