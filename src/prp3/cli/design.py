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
import contextlib
import importlib.util
import sys
import time
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from prp3.apps.design import AGGREGATES, design_robot
from prp3.apps.design_objective import quantity
from prp3.apps.sweep_spec import SweepSpec, read_sweep_spec
from prp3.cli._progress import Progress
from prp3.cli._types import emit, files_report, integer_at_least, output_folder, path_name
from prp3.errors import Prp3Error
from prp3.files import atomic_writer, check_inputs_kept, check_output_directory
from prp3.io.tables import format_float

if TYPE_CHECKING:
    from dask.distributed import Client

    from prp3.family.design import FamilySweepSpec

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


@contextlib.contextmanager
def _client(args: argparse.Namespace) -> Iterator[Client]:
    from prp3.apps.cluster import dask_client

    with dask_client(args.workers, args.scheduler) as client:
        yield client


def _axis(spec: SweepSpec, text: str) -> tuple[str, bool]:
    name, _, sense = text.strip().partition(":")
    if sense not in ("", "min", "max"):
        raise Prp3Error(f"--pareto: {text!r}: a column may end with :min or :max, not :{sense}")
    return name, (sense == "max" or (not sense and name == "workspace_area"))


def _pareto_axes(spec: SweepSpec, text: str | None) -> tuple[tuple[str, bool], tuple[str, bool]]:
    if text is None:
        first = "workspace_area" if spec.evaluator.workspace else spec.paths[0]
        return _axis(spec, first), _axis(spec, "peak_f10")
    parts = text.split(",")
    if len(parts) != 2:
        raise Prp3Error(f"--pareto must be two columns X,Y, got {text!r}")
    return _axis(spec, parts[0]), _axis(spec, parts[1])


def _check_quantity(spec: SweepSpec, name: str, option: str) -> None:
    known = {c for c in spec.evaluator.columns if c != "status"} | set(AGGREGATES)
    if name not in known:
        raise Prp3Error(
            f"{option}: unknown column {name!r} (expected one of: {', '.join(sorted(known))})"
        )


def _read_spec(args: argparse.Namespace) -> SweepSpec:
    spec = read_sweep_spec(args.spec)
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
    args.sensitivity = args.sensitivity or "peak_f10"
    spec = _read_spec(args)
    output: Path = args.output
    check_output_directory(output)
    check_inputs_kept(output, (sweep.DESIGNS_FILE,), (args.spec,))
    axes = _pareto_axes(spec, args.pareto)
    for name, _ in axes:
        _check_quantity(spec, name, "--pareto")
    _check_quantity(spec, args.sensitivity, "--sensitivity")
    sweep.check_sweep_folder(output, spec, force=args.force)  # before any warning
    for _, described in sweep.stale_staging_folders(output, spec):
        print(
            f"{args.program}: warning: {described}: an unfinished sweep of another spec; "
            "it is removed when this sweep finishes (resume it first to keep it)",
            file=sys.stderr,
        )
    progress = Progress(sys.stderr)
    start = time.monotonic()
    try:
        result = sweep.run_sweep(
            spec,
            output,
            lambda: _client(args),
            progress=progress.stage("designs"),
            force=args.force,
        )
    finally:
        progress.close()
    elapsed = time.monotonic() - start
    statuses = ", ".join(f"{count} {name}" for name, count in sorted(result.status.items()))
    reused = result.chunks - result.computed
    lines = [
        f"prp3 sweep: {result.rows} designs ({spec.sampling}, {_count(len(spec.parameters))}) "
        f"on {', '.join(spec.motions)}: {statuses}",
        f"  {result.computed} of {result.chunks} chunks computed"
        + (f", {reused} found done" if reused else "")
        + f", {elapsed:.3g} s",
        *(f"  removed {described}: superseded by this sweep" for described in result.removed),
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
    """``history.csv``: the generation as an integer, every other number in full precision."""
    names = list(history)
    columns = [np.asarray(history[name], dtype=np.float64).tolist() for name in names]
    with atomic_writer(path) as stream:
        stream.write(",".join(names) + "\n")
        for row in zip(*columns, strict=True):
            cells = [
                str(int(value)) if name == "generation" else format_float(value)
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
    check_inputs_kept(output, ("ROBOT.toml", "history.csv"), (args.spec,))
    start = time.monotonic()
    progress = Progress(sys.stderr)
    try:
        outcome = optimization.optimize_design(
            spec, lambda: _client(args), progress=progress.stage("generations")
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
    if outcome.feasible:
        lines.append(f"  best {settings.objective} = {outcome.objective:.9g}")
    else:
        lines.append("  no design satisfies the constraints and the task; the least violating:")
    lines += [
        f"  {path} = {value!r}" for path, value in zip(spec.paths, outcome.x.tolist(), strict=True)
    ]
    columns = {k: [v] for k, v in outcome.row.items()}
    lines.append(f"  status {outcome.row['status']}")
    for name, low, high in settings.constraints:
        value = float(quantity(columns, name)[0])
        lines.append(f"  {name} = {value:.9g}  (required {low:g} .. {high:g})")
    with output_folder(args, output) as staged:
        staged.path("ROBOT.toml").write_text(robot.to_toml(), encoding="utf-8")
        _write_history(staged.path("history.csv"), outcome.history)
        # the summary goes out before the files are moved in: a failing standard
        # output then leaves the earlier results in place
        emit("\n".join(lines + files_report(staged)))
    return 0 if outcome.feasible else 1
