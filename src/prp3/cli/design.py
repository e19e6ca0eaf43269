"""``prp3 sweep`` and ``prp3 optimize``: design studies on Dask.

::

    prp3 sweep --spec SWEEP.toml --output DIR [--workers N | --scheduler ADDRESS]
               [--plots] [--pareto X,Y] [--sensitivity COLUMN]
    prp3 optimize --spec SWEEP.toml --output DIR [--workers N | --scheduler ADDRESS]

``sweep`` writes ``DIR/designs.parquet`` (one row per design; an interrupted
sweep run again recomputes only what it lacks) and, with ``--plots``,
``DIR/pareto.png`` and ``DIR/sensitivity.png``.  ``optimize`` writes the best
design as ``DIR/ROBOT.toml`` and every evaluation in ``DIR/history.csv``.
The format of ``SWEEP.toml`` is in ``docs/design.md``.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from prp3.apps.design import AGGREGATES, design_robot
from prp3.apps.design_objective import quantity
from prp3.apps.sweep_spec import SweepSpec, sweep_spec
from prp3.cli._progress import Progress
from prp3.cli._sweep_run import client_of, swept
from prp3.cli._types import emit, files_report, integer_at_least, output_folder, path_name
from prp3.errors import Prp3Error
from prp3.files import atomic_writer, check_inputs_kept, check_output_directory
from prp3.io.tables import format_float

if TYPE_CHECKING:
    from prp3.apps.spatial_design import SpatialSweepSpec
    from prp3.family.design import FamilySweepSpec

    AnySpec = SweepSpec | SpatialSweepSpec

__all__ = ["register", "run_optimize", "run_sweep"]

SWEEP_EXAMPLES = """\
examples:
  prp3 sweep --spec sweep.toml --output study --plots
      sweep.toml:  designs = 1000
                   sampling = "lhs"            # or "grid", "random"
                   [parameters]
                   l0 = [0.25, 0.35]
                   "platform.mass" = [2.0, 4.0]
                   [task]
                   motions = ["vertical", "rotation"]
  prp3 sweep --spec sweep.toml --output study --workers 2
  prp3 sweep --spec sweep.toml --output study --scheduler tcp://10.0.0.5:8786
  prp3 sweep --spec sweep.toml --output study --plots --pareto workspace_area,peak_f21

Run again after an interruption: only the missing chunks are computed.
A SWEEP.toml with [[study]] tables (one per architecture of docs/family.md, each
with its [study.parameters]) compares architectures: designs.parquet then has the
columns architecture, actuated, the parameters, status, peak_tau_L, peak_power_L,
peak_f1_L .. peak_f3_L, peak_joint_force, energy, min_mu_leg, min_mu_par,
regular_area, and --plots writes family_designs.png (docs/family_comparison.md).
A SWEEP.toml with spatial = "6-UPS" | "3-RPS" | "3-RUU" | "SPATIAL.toml" (or a list
of them, compared on the same task) sweeps spatial robots (docs/spatial.md §21):
                   spatial = ["6-UPS", "3-RPS"]
                   [parameters]
                   base_radius = [0.08, 0.12]
                   "platform.mass" = [0.5, 2.0]
                   [task]
                   motions = ["heave"]        # heave, circle, tilt or TRAJ.csv files
designs.parquet then has robot, architecture, the parameters, status, peak_effort,
peak_power, rms_power, energy, peak_joint_force, peak_joint_moment, min_mu_leg,
min_mu_par, reachable.
Exit status 0 on success, 2 on bad input (one line on stderr).
"""

OPTIMIZE_EXAMPLES = """\
examples:
  prp3 optimize --spec synthesis.toml --output best
      synthesis.toml: the sweep's [parameters] and [task], and
                   [optimize]
                   objective = "peak_f10"
                   [optimize.constraints]
                   workspace_area = { min = 0.004 }
                   peak_f21 = { max = 60.0 }
      best/ROBOT.toml is the best design, best/history.csv every evaluation
  prp3 optimize --spec study.toml --output best
      study.toml with [[study]] tables: the best design of each architecture
      (objective peak_joint_force by default); best/ROBOT.toml is the best of all
  prp3 optimize --spec spatial.toml --output best
      spatial.toml with spatial = [...]: the best design of each spatial robot
      (objective peak_effort by default); best/ROBOT.toml is the best of all, a
      spatial robot file (docs/spatial.md §21)
"""


def _add_cluster_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--spec", metavar="SWEEP.toml", type=path_name, required=True,
        help="parameters, ranges, sampling and task of the study (docs/design.md)",
    )  # fmt: skip
    parser.add_argument(
        "--output", "-o", metavar="DIR", type=path_name, required=True,
        help="output directory, created if missing",
    )  # fmt: skip
    cluster = parser.add_mutually_exclusive_group()
    cluster.add_argument(
        "--workers", metavar="N", type=integer_at_least(1, 1024),
        help="worker processes of a local Dask cluster (default: the machine's cores)",
    )  # fmt: skip
    cluster.add_argument(
        "--scheduler", metavar="ADDRESS",
        help="address of a running Dask scheduler, e.g. tcp://HOST:8786, instead of a local cluster",
    )  # fmt: skip


def register(subparsers: Any) -> None:
    """Add the ``sweep`` and ``optimize`` subcommands."""
    sweep = subparsers.add_parser(
        "sweep",
        help="evaluate many designs over a task on Dask -> DIR/designs.parquet",
        description=(
            "Evaluate designs (robots with some ROBOT.toml values varied over ranges) on a task\n"
            "(motions) with the batch kernel, in chunks on Dask workers, and write\n"
            "DIR/designs.parquet: the parameters, status (ok, singular, unreachable, stroke),\n"
            "peak_f10_L, peak_p10_L, peak_f21_L, peak_n32_L (L = A, B, C), energy, and with a\n"
            "stroke workspace_area, max_condition (docs/design.md)."
        ),
        epilog=SWEEP_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    _add_cluster_options(sweep)
    sweep.add_argument(
        "--plots", action="store_true",
        help="also write DIR/pareto.png and DIR/sensitivity.png",
    )  # fmt: skip
    sweep.add_argument(
        "--pareto", metavar="X,Y",
        help="columns of the Pareto front, each may end with :max or :min (default: "
        "workspace_area:max,peak_f10 with a stroke, else the first parameter and peak_f10); "
        "only with --plots",
    )  # fmt: skip
    sweep.add_argument(
        "--sensitivity", metavar="COLUMN",
        help="quantity of the sensitivity plots (default peak_f10, the largest of legs A, B, C); "
        "only with --plots",
    )  # fmt: skip
    sweep.add_argument(
        "--force", action="store_true",
        help="replace the designs.parquet of another spec in DIR (refused otherwise)",
    )  # fmt: skip
    sweep.set_defaults(handler=run_sweep)

    optimize = subparsers.add_parser(
        "optimize",
        help="dimensional synthesis by differential evolution on Dask -> DIR/ROBOT.toml",
        description=(
            "Minimise [optimize] objective subject to [optimize.constraints] over the ranges of\n"
            "[parameters] with scipy's differential evolution, every generation evaluated on\n"
            "Dask workers; write the best design DIR/ROBOT.toml and DIR/history.csv."
        ),
        epilog=OPTIMIZE_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    _add_cluster_options(optimize)
    optimize.set_defaults(handler=run_optimize)


def _require_design_extra() -> None:
    missing = [m for m in ("dask", "distributed", "pyarrow") if importlib.util.find_spec(m) is None]
    if missing:
        raise Prp3Error(f"design studies need {', '.join(missing)}: pip install 'prp3[design]'")


#: The columns of which larger is better (``--pareto`` takes them as ``:max`` by default).
MAXIMIZED: frozenset[str] = frozenset({"workspace_area", "min_mu_leg", "min_mu_par", "reachable"})


def _axis(text: str) -> tuple[str, bool]:
    name, _, sense = text.strip().partition(":")
    if sense not in ("", "min", "max"):
        raise Prp3Error(f"--pareto: {text!r}: a column may end with :min or :max, not :{sense}")
    return name, (sense == "max" or (not sense and name in MAXIMIZED))


def _spatial(spec: AnySpec) -> bool:
    from prp3.apps.spatial_design import SpatialSweepSpec

    return isinstance(spec, SpatialSweepSpec)


def _pareto_axes(spec: AnySpec, text: str | None) -> tuple[tuple[str, bool], tuple[str, bool]]:
    if text is None:
        if isinstance(spec, SweepSpec):
            first = "workspace_area" if spec.evaluator.workspace else spec.paths[0]
            return _axis(first), _axis("peak_f10")
        if len(spec.studies) == 1:
            return _axis("min_mu_par"), _axis("peak_effort")
        # several robots: quantities of the same unit for every architecture (a measure's
        # scale and an effort's unit differ from one architecture to another)
        return _axis(spec.paths[0] if spec.paths else "peak_power"), _axis("peak_joint_force")
    parts = text.split(",")
    if len(parts) != 2:
        raise Prp3Error(f"--pareto must be two columns X,Y, got {text!r}")
    return _axis(parts[0]), _axis(parts[1])


def _check_quantity(spec: AnySpec, name: str, option: str) -> None:
    known = set(spec.quantities)
    if name not in known:
        raise Prp3Error(
            f"{option}: unknown column {name!r} (expected one of: {', '.join(sorted(known))})"
        )


def _read_spec(args: argparse.Namespace) -> AnySpec:
    """The spec of ``--spec``: spatial (``spatial = ...``) or of the 3-PRP."""
    from prp3.apps.spatial_design import is_spatial_spec, spatial_sweep_spec
    from prp3.model.robot_toml import read_toml

    path = Path(args.spec)
    data = read_toml(path, "sweep")
    spec: AnySpec = (
        spatial_sweep_spec(data, base=path.parent, source=str(path))
        if is_spatial_spec(data)
        else sweep_spec(data, base=path.parent, source=str(path))
    )
    for note in spec.notes:
        print(f"{args.program}: warning: {note}", file=sys.stderr)
    return spec


def _family_spec(args: argparse.Namespace) -> FamilySweepSpec | None:
    """The spec of ``--spec`` when it is in family form (``[[study]]``), else ``None``."""
    from prp3.cli._family_analysis import family_spec_of

    return family_spec_of(Path(args.spec))


def run_sweep(args: argparse.Namespace) -> int:
    """Run ``prp3 sweep``; return the exit status."""
    from prp3.apps import sweep

    _require_design_extra()
    for option, value in (("--pareto", args.pareto), ("--sensitivity", args.sensitivity)):
        if value is not None and not args.plots:
            raise Prp3Error(
                f"{option} {value} applies to the figures only: add --plots, or leave {option} out"
            )
    family = _family_spec(args)
    if family is not None:  # [[study]]: architectures of docs/family.md
        from prp3.cli._family_analysis import run_family_sweep

        return run_family_sweep(args, family)
    spec = _read_spec(args)
    args.sensitivity = args.sensitivity or ("peak_effort" if _spatial(spec) else "peak_f10")
    output: Path = args.output
    check_output_directory(output)
    check_inputs_kept(output, (sweep.DESIGNS_FILE,), (args.spec,))
    axes = _pareto_axes(spec, args.pareto)
    for name, _ in axes:
        _check_quantity(spec, name, "--pareto")
    _check_quantity(spec, args.sensitivity, "--sensitivity")
    result, chunks = swept(args, spec, output)
    statuses = ", ".join(f"{count} {name}" for name, count in sorted(result.status.items()))
    robots = (
        f" of {', '.join(s.name for s in spec.studies)}" if not isinstance(spec, SweepSpec) else ""
    )
    lines = [
        f"prp3 sweep: {result.rows} designs{robots} ({spec.sampling}, "
        f"{_count(len(spec.parameters))}) on {', '.join(spec.motions)}: {statuses}",
        *chunks,
    ]
    # designs.parquet is written in place (resumable); the figures are staged with it, and
    # the manifest records them: a later sweep without --plots removes its stale figures
    with output_folder(args, output, [args.spec, *spec.files]) as staged:
        staged.adopt(sweep.DESIGNS_FILE)
        if args.plots:
            from prp3.plotting.design import pareto_figure, sensitivity_figure
            from prp3.plotting.figures import save_figure

            (x, max_x), (y, max_y) = axes
            wanted = {*spec.paths, "status"}
            for name in (x, y, args.sensitivity):  # an aggregate reads its three legs
                wanted |= {f"{name}_{leg}" for leg in "ABC"} if name in AGGREGATES else {name}
            columns = [c for c in spec.evaluator.columns if c in wanted]
            table = sweep.read_designs(result.path, columns)
            figure = pareto_figure(
                table.columns, x, y, maximize_x=max_x, maximize_y=max_y, nominal=table.nominal
            )
            save_figure(figure, staged.path("pareto.png"))
            if table.parameters:  # a spatial comparison of nominal robots varies none
                figure = sensitivity_figure(
                    table.columns, table.parameters, args.sensitivity, nominal=table.nominal
                )
                save_figure(figure, staged.path("sensitivity.png"))
        emit("\n".join(lines + files_report(staged)))
    return 0


def _count(parameters: int) -> str:
    """``"1 parameter"``, ``"2 parameters"``.

    >>> _count(1), _count(3)
    ('1 parameter', '3 parameters')
    """
    return f"{parameters} parameter{'' if parameters == 1 else 's'}"


def _write_history(path: Path, history: Mapping[str, Any]) -> None:
    """``history.csv``: the generation (and a spatial robot's index) as an integer, every
    other number in full precision."""
    names = list(history)
    columns = [np.asarray(history[name], dtype=np.float64).tolist() for name in names]
    with atomic_writer(path) as stream:
        stream.write(",".join(names) + "\n")
        for row in zip(*columns, strict=True):
            cells = [
                str(int(value)) if name in ("generation", "robot") else format_float(value)
                for name, value in zip(names, row, strict=True)
            ]
            stream.write(",".join(cells) + "\n")


def run_optimize(args: argparse.Namespace) -> int:
    """Run ``prp3 optimize``; return the exit status."""
    from prp3.apps import optimization

    _require_design_extra()
    family = _family_spec(args)
    if family is not None:  # [[study]]: architectures of docs/family.md
        from prp3.cli._family_analysis import run_family_optimize

        return run_family_optimize(args, family)
    spec = _read_spec(args)
    output: Path = args.output
    check_output_directory(output)
    check_inputs_kept(output, ("ROBOT.toml", "history.csv"), (args.spec, *spec.files))
    if not isinstance(spec, SweepSpec):
        return _run_spatial_optimize(args, spec)
    start = time.monotonic()
    progress = Progress(sys.stderr)
    try:
        outcome = optimization.optimize_design(
            spec, lambda: client_of(args), progress=progress.stage("generations")
        )
    finally:
        progress.close()
    elapsed = time.monotonic() - start
    robot = design_robot(spec.evaluator.nominal, spec.paths, outcome.x.tolist())
    settings = spec.optimize
    lines = [
        f"prp3 optimize: minimise {settings.objective} over {_count(len(spec.parameters))}, "
        f"{outcome.generations} generations, {outcome.evaluations} designs, {elapsed:.3g} s "
        f"({outcome.message})",
    ]
    lines += _outcome_lines(settings, spec.paths, outcome)
    with output_folder(args, output) as staged:
        staged.path("ROBOT.toml").write_text(robot.to_toml(), encoding="utf-8")
        _write_history(staged.path("history.csv"), outcome.history)
        # the summary goes out before the files are moved in: a failing standard
        # output then leaves the earlier results in place
        emit("\n".join(lines + files_report(staged)))
    return 0 if outcome.feasible else 1


def _outcome_lines(
    settings: Any, paths: tuple[str, ...], outcome: Any, indent: str = "  "
) -> list[str]:
    """The best design of an optimisation: its objective, values, status and constraints."""
    lines = (
        [f"{indent}best {settings.objective} = {outcome.objective:.9g}"]
        if outcome.feasible
        else [f"{indent}no design satisfies the constraints and the task; the least violating:"]
    )
    lines += [
        f"{indent}{path} = {value!r}" for path, value in zip(paths, outcome.x.tolist(), strict=True)
    ]
    columns = {k: [v] for k, v in outcome.row.items()}
    lines.append(f"{indent}status {outcome.row['status']}")
    for name, low, high in settings.constraints:
        value = float(quantity(columns, name)[0])
        lines.append(f"{indent}{name} = {value:.9g}  (required {low:g} .. {high:g})")
    return lines


def _run_spatial_optimize(args: argparse.Namespace, spec: SpatialSweepSpec) -> int:
    """``prp3 optimize`` of a spatial spec: the best design of every robot, the best of all
    as ``DIR/ROBOT.toml`` (a spatial robot file); exit status 1 when none is feasible."""
    from prp3.apps.design_objective import INFEASIBLE
    from prp3.apps.spatial_design import optimize_spatial, spatial_design_file
    from prp3.io.spatial_robot import spatial_robot_from_mapping, spatial_robot_text

    start = time.monotonic()
    progress = Progress(sys.stderr)
    try:
        results = optimize_spatial(
            spec, lambda: client_of(args), progress=progress.stage("generations")
        )
    finally:
        progress.close()
    elapsed = time.monotonic() - start
    settings = spec.optimize
    evaluations = sum(outcome.evaluations for _, outcome in results)
    lines = [
        f"prp3 optimize: minimise {settings.objective} for {len(results)} spatial "
        f"robot{'s' if len(results) > 1 else ''}, {evaluations} designs, {elapsed:.3g} s",
    ]
    history: dict[str, list[float]] = {"robot": [], "generation": []}
    for path in spec.paths:
        history[path] = []
    history |= {"objective": [], "violation": []}
    for index, (single, outcome) in enumerate(results):
        refused = int(np.sum(outcome.history["violation"] >= 1000.0))
        lines.append(
            f"  {single.study.name} ({single.study.architecture}, "
            f"{_count(len(single.parameters))}): {outcome.generations} generation"
            f"{'' if outcome.generations == 1 else 's'}, "
            f"{outcome.evaluations} designs ({outcome.message}); {refused} refused "
            "(unreachable, singular or invalid)"
        )
        lines += _outcome_lines(settings, single.paths, outcome, indent="    ")
        rows = len(outcome.history["generation"])
        history["robot"] += [float(index)] * rows
        for name in ("generation", "objective", "violation"):
            history[name] += np.asarray(outcome.history[name], dtype=np.float64).tolist()
        for path in spec.paths:
            given = outcome.history.get(path)
            history[path] += [math.nan] * rows if given is None else given.tolist()
    feasible = [(s, o) for s, o in results if o.feasible]
    best_spec, best = min(feasible or results, key=lambda pair: pair[1].objective)
    kinds = set()
    for single, _ in results:  # the kind of joint each robot actuates: P (N) or R (N·m)
        leg = spatial_robot_from_mapping(single.study.nominal).robot.legs[0]
        kinds.add(leg.joints[leg.actuated].kind)
    mixed = (
        " (efforts of P and R actuators, N and N·m: compare like with like)"
        if settings.objective == "peak_effort" and len(kinds) > 1
        else ""
    )
    lines.append(
        f"  best: {best_spec.study.name} ({settings.objective} = {best.objective:.9g}){mixed}"
        if best.objective < INFEASIBLE
        else f"  no design is feasible; the least violating: {best_spec.study.name}"
    )
    design = spatial_design_file(best_spec.study, best.x.tolist())
    with output_folder(args, args.output) as staged:
        staged.path("ROBOT.toml").write_text(spatial_robot_text(design), encoding="utf-8")
        _write_history(staged.path("history.csv"), history)
        emit("\n".join(lines + files_report(staged)))
    return 0 if feasible else 1
