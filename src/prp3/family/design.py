"""Design studies across architectures: which architecture and dimensions carry a task best.

A *family sweep spec* (``SWEEP.toml`` with one or more ``[[study]]`` tables; see
``docs/family_comparison.md``) lists architectures, each with its nominal design (the
default of docs/family.md §3, or a family-form robot file) and the ranges of
some of its ``ROBOT.toml`` values, named by key path as for the 3-PRP
(``"leg.joint2.0"``: the first number of ``[leg] joint2``; ``"link1.mass"``).
A top-level ``[payload]`` (and ``[load]``, ``gravity``) is given to every
study's robot: the same payload along the same task for every architecture.

Each design is run through the family inverse dynamics (the fast route,
:func:`prp3.family.family_inverse_dynamics`) along every motion of the task
and reduced to one row (:data:`FAMILY_DESIGN_COLUMNS`, the varied parameters
before them):

* ``architecture``, ``actuated``, then every parameter of every study (NaN
  where the design's study does not vary it), then ``status``: ``ok``;
  ``singular`` (a singularity measure below 1e-4, or crossed, on the task);
  ``unreachable`` (a leg cannot reach a pose); ``invalid`` (not a valid robot:
  its home configuration is singular, or a value out of its bounds);
* ``peak_tau_L``, ``peak_power_L``: ``max |tau_L|``, ``max |p_L|`` over every
  sample of the task (N or N·m; W);
* ``peak_f1_L``, ``peak_f2_L``, ``peak_f3_L``: ``max |(fx_k, fy_k)|`` (N), the
  force in joint ``k`` of leg ``L``;
* ``peak_joint_force``: the largest of the nine, the figure of merit;
* ``energy``: ``Σ_motions ∫ Σ_L p_L dt`` (trapezoid, J);
* ``min_mu_leg``, ``min_mu_par``: the smallest ``s·μ`` of §6 over the task
  (the singularity margins);
* ``regular_area``: the regular area of the slice ``φ = 0`` (m², grid
  :data:`AREA_POINTS` × :data:`AREA_POINTS` over ``±2ℓ``,
  :func:`prp3.family.workspace.family_workspace_slice`).

>>> spec = family_sweep_spec({"designs": 3, "sampling": "grid",
...     "task": {"motions": ["vertical"], "samples": 21},
...     "study": [{"architecture": "3-RRR", "parameters": {"link1.mass": [0.5, 1.5]}},
...               {"architecture": "3-RPR"}]})
>>> columns = evaluate_family_designs(spec.evaluator, family_design_rows(spec))
>>> [str(a) for a in columns["architecture"]], [str(s) for s in columns["status"]]
(['3-RRR', '3-RRR', '3-RRR', '3-RPR'], ['ok', 'ok', 'ok', 'ok'])
>>> round(float(columns["peak_tau_A"][1]), 6)    # the default 3-RRR
7.558337
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.apps.design import design_mapping, first_row, nominal_design_row, status_columns
from prp3.apps.design_objective import OptimizeSpec, penalized_objective
from prp3.apps.sweep import SweepRun, run_sweep
from prp3.apps.sweep_spec import (
    Parameter,
    parameter_paths,
    read_spec_file,
    refuse_unknown_keys,
    sample_designs,
    spec_digest,
    spec_integer,
    spec_motions,
    spec_sampling,
    spec_table,
)
from prp3.errors import ParameterError, SingularPoseError, UnreachablePoseError
from prp3.family.model import ARCHITECTURES, FamilyRobot
from prp3.family.outputs import family_inverse_dynamics
from prp3.model.motion import Motion
from prp3.validation import LEGS

__all__ = [
    "AREA_POINTS",
    "FAMILY_DESIGN_COLUMNS",
    "FAMILY_STATUSES",
    "FamilyEvaluator",
    "FamilyObjective",
    "FamilyOptimum",
    "FamilySweepRun",
    "FamilySweepSpec",
    "Study",
    "evaluate_family_designs",
    "family_design_robot",
    "family_design_rows",
    "family_sweep_spec",
    "is_family_spec",
    "optimize_family",
    "run_family_sweep",
]

FloatArray = NDArray[np.float64]

#: Values of the ``status`` column.
FAMILY_STATUSES: tuple[str, ...] = ("ok", "singular", "unreachable", "invalid")

#: Grid points per axis of the ``regular_area`` slice.
AREA_POINTS: int = 41

#: The result columns after the parameters and ``status``.
FAMILY_DESIGN_COLUMNS: tuple[str, ...] = (
    *(f"peak_tau_{leg}" for leg in LEGS),
    *(f"peak_power_{leg}" for leg in LEGS),
    *(f"peak_f{k}_{leg}" for k in (1, 2, 3) for leg in LEGS),
    "peak_joint_force",
    "energy",
    "min_mu_leg",
    "min_mu_par",
    "regular_area",
)

_TOP_KEYS = {
    "designs", "sampling", "seed", "chunk", "task", "study", "payload", "load", "gravity",
    "optimize",
}  # fmt: skip
_STUDY_KEYS = {"architecture", "actuated", "robot", "parameters"}
_SHARED = ("payload", "load", "gravity")


def is_family_spec(data: Mapping[str, Any]) -> bool:
    """Whether a parsed ``SWEEP.toml`` is in family form (it has ``[[study]]``)."""
    return "study" in data


@dataclass(frozen=True)
class Study:
    """One architecture of a family sweep: its nominal mapping and varied parameters."""

    architecture: str
    nominal: dict[str, Any]
    parameters: tuple[Parameter, ...]

    @property
    def paths(self) -> tuple[str, ...]:
        """Key paths of the parameters."""
        return tuple(p.path for p in self.parameters)


def family_design_robot(study: Study, values: Sequence[float]) -> FamilyRobot:
    """The robot of a design of ``study`` (:func:`prp3.apps.design.design_mapping`)."""
    return FamilyRobot.from_mapping(design_mapping(study.nominal, study.paths, list(values)))


@dataclass(frozen=True, eq=False)
class FamilyEvaluator:
    """What a worker needs: the studies, every parameter path (column order) and the task."""

    studies: tuple[Study, ...]
    paths: tuple[str, ...]
    motions: tuple[Motion, ...]

    @property
    def columns(self) -> tuple[str, ...]:
        """Column names of ``designs.parquet``."""
        return ("architecture", "actuated", *self.paths, "status", *FAMILY_DESIGN_COLUMNS)

    @property
    def text_columns(self) -> tuple[str, ...]:
        """The columns of text (a :class:`~prp3.apps.design.RowEvaluator`)."""
        return ("architecture", "status")

    def evaluate(self, values: FloatArray) -> dict[str, Any]:
        """The columns of designs ``values (k, 1 + p)``: the study's index, then every
        parameter of :attr:`paths` (NaN where that study lacks it)."""
        values = np.asarray(values, dtype=np.float64).reshape(len(values), -1)
        rows: list[tuple[int, Sequence[float]]] = []
        for row in values:
            index = int(row[0])
            study = self.studies[index]
            rows.append((index, [float(row[1 + self.paths.index(p)]) for p in study.paths]))
        return evaluate_family_designs(self, rows)


def _row(evaluator: FamilyEvaluator, robot: FamilyRobot) -> tuple[str, list[float]]:
    """Status and result values of one design."""
    from prp3.family.workspace import family_workspace_slice

    tau, power, force, energy = [], [], [], 0.0
    margin_leg, margin_par = math.inf, math.inf
    home_leg, home_par = robot.home_measures
    try:
        for motion in evaluator.motions:
            solution = family_inverse_dynamics(robot, motion)
            tau.append(np.abs(solution.tau).max(axis=0))
            power.append(np.abs(solution.power).max(axis=0))
            force.append(np.hypot(solution.force[..., 0], solution.force[..., 1]).max(axis=0))
            total = solution.power.sum(axis=-1)
            energy += float(np.sum(0.5 * (total[1:] + total[:-1]) * np.diff(motion.t)))
            kin = solution.kinematics
            margin_leg = min(margin_leg, float((np.sign(home_leg) * kin.mu_leg).min()))
            margin_par = min(margin_par, float((math.copysign(1.0, home_par) * kin.mu_par).min()))
    except SingularPoseError:
        return "singular", [math.nan] * len(FAMILY_DESIGN_COLUMNS)
    except UnreachablePoseError:
        return "unreachable", [math.nan] * len(FAMILY_DESIGN_COLUMNS)
    peak_tau = np.max(tau, axis=0)
    peak_power = np.max(power, axis=0)
    peak_force = np.max(force, axis=0)  # (3 legs, 3 joints)
    half = 2.0 * robot.leg.scale
    grid = np.linspace(-half, half, AREA_POINTS)
    area = family_workspace_slice(robot, 0.0, grid, grid).regular_area
    values = [
        *peak_tau.tolist(),
        *peak_power.tolist(),
        *(float(peak_force[j, k]) for k in range(3) for j in range(3)),
        float(peak_force.max()),
        energy,
        margin_leg,
        margin_par,
        area,
    ]
    return "ok", values


def evaluate_family_designs(
    evaluator: FamilyEvaluator, rows: Sequence[tuple[int, Sequence[float]]]
) -> dict[str, Any]:
    """Evaluate designs ``rows`` — ``(study index, parameter values)`` — into columns.

    Pure: the same rows give the same numbers on every worker.
    """
    count = len(rows)
    columns: dict[str, Any] = {
        "architecture": np.array([evaluator.studies[s].architecture for s, _ in rows], dtype=str),
        "actuated": np.full(count, np.nan),
        **{path: np.full(count, np.nan) for path in evaluator.paths},
    }
    for i, (index, values) in enumerate(rows):
        for path, value in zip(evaluator.studies[index].paths, values, strict=True):
            columns[path][i] = value

    def row(i: int, robot: FamilyRobot) -> tuple[str, list[float]]:
        columns["actuated"][i] = float(robot.actuated)
        return _row(evaluator, robot)

    builders = [partial(family_design_robot, evaluator.studies[s], v) for s, v in rows]
    return columns | status_columns(builders, row, FAMILY_DESIGN_COLUMNS)


@dataclass(frozen=True, eq=False)
class FamilyObjective:
    """The penalised objective of one study's designs, for differential evolution (picklable)."""

    evaluator: FamilyEvaluator
    study: int
    optimize: OptimizeSpec

    def __call__(self, x: FloatArray) -> float:
        """The objective of the design with parameter values ``x``."""
        return float(self.many(np.asarray(x, dtype=np.float64)[None, :])[0])

    def many(self, xs: FloatArray) -> FloatArray:
        """The objectives of designs ``xs`` ``(k, p)``."""
        rows = [(self.study, list(x)) for x in np.asarray(xs, dtype=np.float64).tolist()]
        return penalized_objective(self.optimize, evaluate_family_designs(self.evaluator, rows))


@dataclass(frozen=True, eq=False)
class FamilySweepSpec:
    """A validated family ``SWEEP.toml``.

    Attributes
    ----------
    source : str
    designs : int
        Designs per study (``lhs``, ``random``) or points per parameter (``grid``).
    sampling : str
    seed, chunk : int
    motions : tuple of str
    evaluator : FamilyEvaluator
    optimize : OptimizeSpec
    """

    source: str
    designs: int
    sampling: str
    seed: int
    chunk: int
    motions: tuple[str, ...]
    evaluator: FamilyEvaluator
    optimize: OptimizeSpec

    @property
    def studies(self) -> tuple[Study, ...]:
        """The architectures of the study."""
        return self.evaluator.studies

    # ---- what prp3.apps.sweep.run_sweep needs (a Sweepable): resume, manifest, metadata
    @property
    def paths(self) -> tuple[str, ...]:
        """Every parameter's key path, in column order."""
        return self.evaluator.paths

    @property
    def parameters(self) -> tuple[Parameter, ...]:
        """Every study's parameters, the first of each path."""
        seen: dict[str, Parameter] = {}
        for study in self.studies:
            for parameter in study.parameters:
                seen.setdefault(parameter.path, parameter)
        return tuple(seen.values())

    @property
    def count(self) -> int:
        """Number of rows (:func:`family_design_rows`)."""
        return len(family_design_rows(self))

    def design_values(self) -> FloatArray:
        """The rows' designs ``(count, 1 + p)``: the study's index, then every parameter of
        :attr:`paths` (NaN where the study lacks it), in the order of :func:`family_design_rows`."""
        rows = family_design_rows(self)
        values = np.full((len(rows), 1 + len(self.paths)), np.nan)
        for i, (index, given) in enumerate(rows):
            values[i, 0] = index
            for path, value in zip(self.studies[index].paths, given, strict=True):
                values[i, 1 + self.paths.index(path)] = value
        return values

    def nominal_row(self) -> dict[str, Any]:
        """The row of the first study's nominal design (the file's metadata)."""
        study = replace(self.studies[0], parameters=())
        alone = replace(self.evaluator, studies=(study,), paths=())
        columns = evaluate_family_designs(alone, [(0, [])])
        return nominal_design_row(study.nominal, self.paths, columns, self.evaluator.text_columns)

    def described(self) -> dict[str, Any]:
        """The spec as ``designs.parquet``'s metadata records it."""
        return {
            "source": self.source,
            "studies": [
                {
                    "architecture": study.architecture,
                    "parameters": {p.path: [p.low, p.high] for p in study.parameters},
                }
                for study in self.studies
            ],
            "designs": self.designs,
            "sampling": self.sampling,
            "seed": self.seed,
            "motions": list(self.motions),
        }

    def digest(self) -> str:
        """SHA-256 of everything the rows depend on (keys the staging folder of a resume)."""
        described = {
            "format": "family-1",
            "chunk": self.chunk,
            "nominal": [study.nominal for study in self.studies],
            **{k: v for k, v in self.described().items() if k != "source"},
        }
        fields = ("t", "pose", "velocity", "acceleration")
        return spec_digest(described, self.evaluator.motions, fields)


def _study(source: str, base: Path, index: int, table: Any, shared: dict[str, Any]) -> Study:
    where = f"study[{index}]"
    table = spec_table(source, where, table)
    refuse_unknown_keys(source, f"{where}.", table, _STUDY_KEYS)
    if "robot" in table:
        name = str(table["robot"])
        _, nominal_robot = read_spec_file(
            source, f"{where}.robot", name, base, FamilyRobot.from_toml
        )
        architecture = table.get("architecture", nominal_robot.architecture)
        if architecture != nominal_robot.architecture:
            raise ParameterError(
                f"{source}: {where}: architecture {architecture!r} but the robot file is a "
                f"{nominal_robot.architecture}"
            )
    else:
        architecture = table.get("architecture")
        if architecture not in ARCHITECTURES:
            raise ParameterError(
                f"{source}: {where}.architecture must be one of {', '.join(ARCHITECTURES)}, got "
                f"{architecture!r}"[:300]
            )
        nominal_robot = FamilyRobot.default(str(architecture))
    nominal: dict[str, Any] = tomllib.loads(nominal_robot.to_toml())
    if "actuated" in table:
        nominal["actuated"] = table["actuated"]
    nominal.update(shared)
    try:
        FamilyRobot.from_mapping(nominal)
    except ParameterError as error:
        raise ParameterError(f"{source}: {where}: {error}") from None
    parameters: list[Parameter] = []
    given = spec_table(source, f"{where}.parameters", table.get("parameters", {}))
    for path, value in parameter_paths(given, f"{source}: {where}.parameters"):
        key = f"{source}: {where}.parameters {path!r}"
        if not (isinstance(value, list) and len(value) == 2):
            raise ParameterError(f"{key}: the range must be [low, high], got {value!r}"[:300])
        try:
            parameter = Parameter(path, value[0], value[1])
        except ParameterError as error:
            raise ParameterError(f"{key}: {error}") from None
        for end in (parameter.low, parameter.high):
            try:
                FamilyRobot.from_mapping(design_mapping(nominal, [path], [end]))
            except ParameterError as error:
                if "home configuration" not in str(error):  # a singular home is a row
                    raise ParameterError(f"{key} = {end!r}: {error}") from None
        parameters.append(parameter)
    return Study(architecture=str(architecture), nominal=nominal, parameters=tuple(parameters))


def family_sweep_spec(
    data: Mapping[str, Any], *, base: str | Path = ".", source: str = "SWEEP.toml"
) -> FamilySweepSpec:
    """Validate a family ``SWEEP.toml`` mapping; paths in it are relative to ``base``.

    Raises
    ------
    ParameterError, InputFileError, TrajectoryError
        One line naming ``source`` and the key.
    """
    from prp3.apps.sweep_spec import spec_optimize

    base = Path(base)
    refuse_unknown_keys(source, "", data, _TOP_KEYS)
    shared = {key: data[key] for key in _SHARED if key in data}
    studies_table = data.get("study")
    if not isinstance(studies_table, list) or not studies_table:
        raise ParameterError(f"{source}: [[study]] must be a non-empty array of tables")
    studies = tuple(_study(source, base, i, t, shared) for i, t in enumerate(studies_table))
    sampling = spec_sampling(source, data)
    designs = spec_integer(source, "designs", data.get("designs", 20), 2 if sampling == "grid" else 1,
                       100_000)  # fmt: skip
    paths: list[str] = []
    for study in studies:
        paths += [p for p in study.paths if p not in paths]
    names, _, motions, _ = spec_motions(
        source, base, spec_table(source, "task", data.get("task", {}))
    )
    evaluator = FamilyEvaluator(studies=studies, paths=tuple(paths), motions=motions)
    optimize_table = spec_table(source, "optimize", data.get("optimize", {}))
    optimize_table.setdefault("objective", "peak_joint_force")
    optimize = spec_optimize(source, optimize_table, evaluator.columns)
    known = [c for c in evaluator.columns if c not in ("architecture", "status")]
    for name in (optimize.objective, *(c for c, _, _ in optimize.constraints)):
        if name not in known:  # the 3-PRP's aggregates (peak_f10, ...) are not columns here
            raise ParameterError(
                f"{source}: optimize: unknown quantity {name!r} (expected one of: "
                f"{', '.join(sorted(known))})"
            )
    return FamilySweepSpec(
        source=source,
        designs=designs,
        sampling=str(sampling),
        seed=spec_integer(source, "seed", data.get("seed", 0), 0, 2**63 - 1),
        chunk=spec_integer(source, "chunk", data.get("chunk", 20), 1, 100_000),
        motions=names,
        evaluator=evaluator,
        optimize=optimize,
    )


def read_family_sweep_spec(path: str | Path) -> FamilySweepSpec:
    """Read and validate a family ``SWEEP.toml`` (:func:`family_sweep_spec`; errors name the
    file).  A spec without ``[[study]]`` tables is not a family spec and is refused."""
    from prp3.model.robot_toml import read_toml
    from prp3.validation import check_file_path

    path = check_file_path("path", path)
    data = read_toml(path, "sweep")
    if not is_family_spec(data):
        raise ParameterError(
            f"{path}: not a family sweep spec (it has no [[study]] table; docs/family_comparison.md)"
        )
    return family_sweep_spec(data, base=path.parent, source=str(path))


def family_design_rows(spec: FamilySweepSpec) -> list[tuple[int, list[float]]]:
    """Every design of the sweep as ``(study index, values)``, study by study.

    A study without parameters is its nominal design, one row; the others are
    :func:`~prp3.apps.sweep_spec.sample_designs` of their parameters, with the
    seed ``seed + study index``.
    """
    rows: list[tuple[int, list[float]]] = []
    for index, study in enumerate(spec.studies):
        values = sample_designs(study.parameters, spec.designs, spec.sampling, spec.seed + index)
        rows += [(index, v) for v in values.tolist()]
    return rows


# ------------------------------------------------------------------ on Dask
#: What :func:`run_family_sweep` did (the 3-PRP's and the spatial sweeps' record).
FamilySweepRun = SweepRun


def run_family_sweep(
    spec: FamilySweepSpec,
    output: str | Path,
    client: Any,
    *,
    progress: Any = None,
    force: bool = False,
) -> SweepRun:
    """Evaluate every design of ``spec`` on Dask and write ``output/designs.parquet``.

    The sweep of every robot (:func:`prp3.apps.sweep.run_sweep`): one task per chunk of
    ``spec.chunk`` designs, each chunk kept in the staging folder as it is done, so a run
    again after an interruption computes only the missing chunks; the rows keep the order
    of :func:`family_design_rows` whatever the workers; the file is written atomically
    with the spec's digest, parameters and nominal row in its metadata.  ``client``: a
    Dask client, or a factory of one (:func:`prp3.apps.cluster.dask_client`).
    """
    return run_sweep(spec, output, client, progress=progress, force=force)


@dataclass(frozen=True)
class FamilyOptimum:
    """The best design of one study (:func:`optimize_family`).

    Attributes
    ----------
    study : int
    architecture : str
    x : ndarray (p,)
        Its parameter values (empty for a study without parameters).
    objective : float
        Its penalised objective (``>= INFEASIBLE`` when infeasible).
    feasible : bool
    row : dict
        Its row of the design table.
    evaluations : int
    """

    study: int
    architecture: str
    x: FloatArray
    objective: float
    feasible: bool
    row: dict[str, Any]
    evaluations: int


def optimize_family(
    spec: FamilySweepSpec, client: Any
) -> tuple[list[FamilyOptimum], dict[str, FloatArray]]:
    """Minimise the objective of ``spec.optimize`` within every study, on Dask.

    Each study with parameters runs :func:`scipy.optimize.differential_evolution`
    (as :func:`prp3.apps.optimization.optimize_design`: Latin-hypercube start, ``rng = seed``,
    deferred updating, each generation on the workers); a study without
    parameters is its nominal design.  Returns the best design of each study
    (compare them for the best architecture) and the history of every
    evaluation (columns ``study``, ``generation``, the parameters, ``objective``).
    """
    from scipy.optimize import differential_evolution

    from prp3.apps.design_objective import INFEASIBLE
    from prp3.apps.optimization import DaskMap

    settings = spec.optimize
    optima: list[FamilyOptimum] = []
    history: dict[str, list[float]] = {"study": [], "generation": [], "objective": []}
    for path in spec.evaluator.paths:
        history[path] = []
    for index, study in enumerate(spec.studies):
        objective = FamilyObjective(spec.evaluator, index, settings)
        if study.parameters:
            mapper = DaskMap(client, batch=objective)  # type: ignore[arg-type]
            result = differential_evolution(
                objective, [(p.low, p.high) for p in study.parameters],
                maxiter=settings.maxiter, popsize=settings.popsize, tol=settings.tol,
                rng=spec.seed + index, polish=False, init="latinhypercube",
                updating="deferred", workers=mapper,
            )  # fmt: skip
            x = np.asarray(result.x, dtype=np.float64)
            evaluations = int(result.nfev)
            records = mapper.history
        else:
            x = np.zeros(0)
            evaluations = 1
            records = [(0, x, float(objective.many(x[None, :])[0]))]
        columns = evaluate_family_designs(spec.evaluator, [(index, x.tolist())])
        row = first_row(columns, spec.evaluator.text_columns)
        value = float(penalized_objective(settings, columns)[0])
        optima.append(
            FamilyOptimum(index, study.architecture, x, value, value < INFEASIBLE, row, evaluations)
        )
        for generation, member, result_value in records:
            history["study"].append(float(index))
            history["generation"].append(float(generation))
            history["objective"].append(result_value if result_value < INFEASIBLE else math.nan)
            given = dict(zip(study.paths, np.asarray(member).tolist(), strict=True))
            for path in spec.evaluator.paths:
                history[path].append(given.get(path, math.nan))
    return optima, {k: np.asarray(v, dtype=np.float64) for k, v in history.items()}
