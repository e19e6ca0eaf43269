"""``prp3 workspace`` and ``prp3 forward`` for a family-form ``ROBOT.toml`` (docs/family.md).

Called by :mod:`prp3.cli.workspace` and :mod:`prp3.cli.forward` when the robot
file is in family form.

``workspace`` writes ``DIR/workspace.csv`` (one row per grid point at ``φ``:
``x, y, reachable, regular, mu_leg_A, mu_leg_B, mu_leg_C, mu_par``),
``DIR/orientations.csv`` (``phi, area, regular_area, min_mu_par``) and
``DIR/workspace.png`` (:mod:`prp3.plotting.family_workspace`).

``forward`` reads the actuator efforts (``t,tau_A,tau_B,tau_C`` or a family
``results.csv``), integrates :func:`prp3.family.forward.family_forward_dynamics`
and writes ``DIR/results.csv`` (the 64 family columns of the integrated
motion) and ``DIR/trajectory.csv``.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from prp3.apps.runs import check_memory
from prp3.cli._types import bound_stopped, check_extent, emit, files_report, forward_bounds
from prp3.errors import ParameterError, Prp3Error
from prp3.family import FamilyRobot, family_results_table
from prp3.files import check_inputs_kept, check_output_directory
from prp3.io.tables import Table, read_table, write_table_csv
from prp3.io.trajectory import trajectory_table
from prp3.model.motion import Motion
from prp3.staged_files import StagedOutput, staged_output
from prp3.validation import LEGS, OVERFLOW_REASON

__all__ = [
    "family_spec_of",
    "run_family_forward",
    "run_family_optimize",
    "run_family_sweep",
    "run_family_workspace",
]

if TYPE_CHECKING:
    from prp3.family.design import FamilySweepSpec
    from prp3.family.workspace import FamilyStatics

FloatArray = NDArray[np.float64]

#: Orientations of the φ-scan are spread over ``±SCAN_RANGE`` rad.
SCAN_RANGE: float = math.pi / 2.0

#: Largest grid per axis of the φ-scan (the grid of the map, thinned).
SCAN_POINTS: int = 101

#: Memory per grid point of a slice (bytes) and of a run besides its grid.
BYTES_PER_POINT: int = 8 * 200
BYTES_PER_RUN: int = 200 * 1024**2


def run_family_workspace(args: argparse.Namespace, robot: FamilyRobot) -> int:
    """``prp3 workspace`` of a family robot; return the exit status."""
    from prp3.family.workspace import (
        family_orientation_scan,
        family_workspace_slice,
        family_workspace_statics,
    )

    statics_wanted = family_wants_statics(robot, args.statics)
    x, y = _workspace_grid(args, robot, statics_wanted)
    ws = family_workspace_slice(robot, args.phi, x, y)
    step = max(1, -(-args.points // SCAN_POINTS))
    phis = np.linspace(-SCAN_RANGE, SCAN_RANGE, args.orientations)
    scan = family_orientation_scan(robot, x[::step], y[::step], phis)
    X, Y = np.meshgrid(x, y)
    table: dict[str, FloatArray] = {
        "x": X.reshape(-1),
        "y": Y.reshape(-1),
        "reachable": ws.reachable.reshape(-1).astype(np.float64),
        "regular": ws.regular.reshape(-1).astype(np.float64),
    }
    for j, leg in enumerate(LEGS):
        table[f"mu_leg_{leg}"] = ws.mu_leg[..., j].reshape(-1)
    table["mu_par"] = ws.mu_par.reshape(-1)
    statics = None
    if statics_wanted:
        try:
            statics = family_workspace_statics(robot, ws.phi, x, y)
        except ParameterError as error:
            raise error.located(file=args.robot) from None
    scan_table = {
        "phi": scan.phi,
        "area": scan.area,
        "regular_area": scan.regular_area,
        "min_mu_par": scan.min_mu_par,
    }
    from prp3.plotting.family_workspace import save_family_workspace_map

    with staged_output(args.output) as staged:
        write_table_csv(staged.path("workspace.csv"), table)
        write_table_csv(staged.path("orientations.csv"), scan_table)
        save_family_workspace_map(staged.path("workspace.png"), ws, scan)
        statics_lines: list[str] = []
        if statics is not None:
            statics_lines = _write_statics(staged, table, statics, ws.regular, robot)
        home_leg, home_par = robot.home_measures
        lines = [
            f"prp3 workspace: {robot.architecture} (joint {robot.actuated} driven), phi = "
            f"{ws.phi:.9g} rad, grid {x.size} x {y.size} over x = {x[0]:.6g} .. {x[-1]:.6g} m, "
            f"y = {y[0]:.6g} .. {y[-1]:.6g} m",
            f"  reachable area {ws.area:.6g} m^2, regular area {ws.regular_area:.6g} m^2 "
            f"(grid counts; {int(ws.regular.sum())} of {ws.regular.size} points regular)",
            "  home measures: mu_leg " + ", ".join(f"{v:.6g}" for v in home_leg)
            + f"; mu_par {home_par:.6g}",
            f"  orientation scan: {phis.size} orientations over +-{SCAN_RANGE:.6g} rad on a "
            f"{x[::step].size} x {y[::step].size} grid",
            *statics_lines,
            *files_report(staged),
        ]  # fmt: skip
        emit("\n".join(lines))
    return 0


def _workspace_grid(
    args: argparse.Namespace, robot: FamilyRobot, statics_wanted: bool
) -> tuple[FloatArray, FloatArray]:
    """The grid values ``x``, ``y`` of ``--extent`` (default ``±2·scale``) and ``--points``,
    its memory checked; a grid whose neighbouring values are equal is refused."""
    if args.extent is not None:
        xmin, xmax, ymin, ymax = check_extent(args.extent)
    else:
        half = 2.0 * robot.leg.scale
        xmin, xmax, ymin, ymax = -half, half, -half, half
    per_point = BYTES_PER_POINT * (2 if statics_wanted else 1)
    check_memory(f"--points {args.points}", BYTES_PER_RUN + args.points**2 * per_point)
    x = np.linspace(xmin, xmax, args.points)
    y = np.linspace(ymin, ymax, args.points)
    for axis, values in (("x", x), ("y", y)):
        if not (np.diff(values) > 0).all():
            raise ParameterError(
                f"--extent is too narrow in {axis} for --points {args.points}: neighbouring grid "
                "values are equal"
            )
    return x, y


def _write_statics(
    staged: StagedOutput,
    table: dict[str, FloatArray],
    statics: FamilyStatics,
    regular: NDArray[np.bool_],
    robot: FamilyRobot,
) -> list[str]:
    """Stage ``statics.csv`` and ``statics.png``; return the summary's line of them."""
    from prp3.plotting.family_workspace import save_family_statics_map

    statics_table = {key: table[key] for key in ("x", "y", "regular")}
    for j, leg in enumerate(LEGS):
        statics_table[f"tau_{leg}"] = statics.tau[..., j].reshape(-1)
    statics_table["tau_peak"] = statics.peak.reshape(-1)
    write_table_csv(staged.path("statics.csv"), statics_table)
    save_family_statics_map(staged.path("statics.png"), statics)
    unit = "N" if robot.types[robot.actuated - 1] == "P" else "N m"
    held = statics.peak[regular]
    return [
        f"  statics (at rest): largest |tau| over the legs {held.min():.6g} .. "
        f"{held.max():.6g} {unit} over the regular points"
        if held.size
        else "  statics: no regular grid point"
    ]


def family_wants_statics(robot: FamilyRobot, option: bool | None) -> bool:
    """Whether ``prp3 workspace`` writes a family robot's statics map.

    ``--statics``/``--no-statics``, else when the robot carries a ``[payload]``
    or a ``[load]`` (as for the model form).
    """
    if option is not None:
        return option
    load = robot.load
    return robot.payload.mass != 0.0 or any(v != 0.0 for v in (*load.force, load.moment))


def _read_efforts(path: Path) -> tuple[Table, bool]:
    """The efforts table: ``t,tau_A,tau_B,tau_C`` or a family ``results.csv`` (64 columns),
    with the line of each row (an error about a sample names it)."""
    from prp3.family import FAMILY_COLUMNS

    try:
        with path.open(encoding="utf-8", errors="replace") as handle:
            header = handle.readline(100_000).strip().split(",")
    except OSError:
        header = []  # read_table names the file and the reason
    if len(header) == len(FAMILY_COLUMNS) and set(header) == set(FAMILY_COLUMNS):
        return read_table(path, FAMILY_COLUMNS, (), "results"), True
    return read_table(path, ("t", "tau_A", "tau_B", "tau_C"), (), "efforts"), False


def _drift(columns: dict[str, FloatArray], motion: Motion, results: bool) -> list[str]:
    """How far the integrated motion is from the one of a ``results.csv`` (at its own times)."""
    if not results:
        return []
    planned = np.stack(
        [np.interp(motion.t, columns["t"], columns[k]) for k in ("x", "y", "phi")], -1
    )
    position = float(np.hypot(*(motion.pose[:, :2] - planned[:, :2]).T).max())
    orientation = float(np.abs(motion.pose[:, 2] - planned[:, 2]).max())
    return [
        f"  largest drift from the motion of {len(columns['t'])} samples the efforts came from: "
        f"|dG| {position:.3g} m, |dphi| {orientation:.3g} rad (open-loop: errors of the samples "
        "and their spline grow)"
    ]


def _robot_key(path: Path, error: Prp3Error) -> Prp3Error:
    """``error`` located at the robot file's line of its key (``load.force``)."""
    from prp3.files import read_text
    from prp3.io.spatial_robot import key_line
    from prp3.model.robot_toml import MAX_ROBOT_FILE_BYTES

    line = key_line(read_text(path, "robot", MAX_ROBOT_FILE_BYTES), str(error.key))
    return error.located(file=path, line=line)


def run_family_forward(args: argparse.Namespace, robot: FamilyRobot) -> int:
    """``prp3 forward`` of a family robot; return the exit status."""
    from prp3.family.forward import family_forward_dynamics

    check_inputs_kept(args.output, ("results.csv", "trajectory.csv"), (args.forces, args.robot))
    given, results = _read_efforts(Path(args.forces))
    columns = given.columns
    t = columns["t"]
    tau = np.stack([columns[f"tau_{leg}"] for leg in LEGS], axis=-1)
    if args.initial_pose is not None:
        pose = np.array(args.initial_pose, dtype=np.float64)
    elif results:
        pose = np.array([columns["x"][0], columns["y"][0], columns["phi"][0]])
    else:
        pose = np.asarray(robot.home_poses[0], dtype=np.float64).copy()
    velocity = np.zeros(3)
    if args.initial_velocity is not None:
        velocity = np.array(args.initial_velocity, dtype=np.float64)
    elif results and args.initial_pose is None:
        from prp3.family import family_kinematics
        from prp3.model.motion import Motion

        kin = family_kinematics(robot, Motion.at_rest(pose))
        a = robot.actuated - 1
        rates = np.array([columns[f"dq{a + 1}_{leg}"][0] for leg in LEGS])
        # (ẋ, ẏ, φ̇) from the actuated rates: K[a, :]·t = q̇_a for every leg
        velocity = np.linalg.solve(np.asarray(kin.jacobian_inverse)[0, :, a, :], rates)
    samples = args.samples if args.samples is not None else t.size
    check_memory(f"{samples} output samples", 200 * 1024**2 + 8 * 200 * samples)
    times = np.linspace(float(t[0]), float(t[-1]), samples) if args.samples else t
    try:
        result = family_forward_dynamics(
            robot, t, tau, times, pose, velocity, rtol=args.rtol, atol=args.atol,
            **forward_bounds(args),
        )  # fmt: skip
    except Prp3Error as error:
        stopped = bound_stopped(error, args)
        if stopped is not None:  # --max-evaluations or --max-seconds
            raise stopped from None
        if error.subject == "initial pose" and error.reason.startswith(OVERFLOW_REASON):
            raise error.located(file=args.robot, subject="robot at the initial pose") from None
        if error.subject == "initial pose":  # say where the initial pose came from
            if args.initial_pose is not None:
                origin = "--initial-pose " + " ".join(repr(v) for v in args.initial_pose)
                raise error.located(origin=origin) from None
            where = "the first row of the results" if results else "the home pose"
            raise error.located(file=args.forces, subject=f"initial pose ({where})") from None
        if error.subject == "robot" and args.robot is not None:  # its masses: the file's
            raise error.located(file=args.robot) from None
        if error.key in ("load.force", "load.moment") and args.robot is not None:
            raise _robot_key(Path(args.robot), error) from None  # the robot file's [load]
        if error.key == "efforts" and error.sample is not None:  # a row: its line and time
            k = error.sample
            raise error.located(
                file=args.forces, line=int(given.lines[k]), time=float(t[k])
            ) from None
        if error.key == "efforts" or error.subject == "forward dynamics":
            raise error.located(file=args.forces) from None  # the efforts' file
        raise
    table = family_results_table(result.solution) if result.solution is not None else None
    with staged_output(args.output) as staged:
        if table is not None:
            write_table_csv(staged.path("results.csv"), table)
        write_table_csv(staged.path("trajectory.csv"), trajectory_table(result.motion))
        lines = [
            f"prp3 forward: {robot.architecture} (joint {robot.actuated} driven), "
            f"{result.motion.samples} samples, t = {result.motion.t[0]:.6g} .. "
            f"{result.motion.t[-1]:.6g} s ({result.status}), {result.evaluations} evaluations",
            "  final pose " + ", ".join(f"{v:.9g}" for v in result.motion.pose[-1].tolist()),
            *_drift(columns, result.motion, results),
            *files_report(staged),
        ]
        emit("\n".join(lines))
    if result.status != "completed":
        print(f"{args.program}: warning: {result.message}", file=sys.stderr)
        return 1
    return 0


def family_spec_of(path: Path) -> FamilySweepSpec | None:
    """The family sweep spec of ``SWEEP.toml`` at ``path``, or ``None`` for a model-form spec."""
    from prp3.family.design import is_family_spec, read_family_sweep_spec
    from prp3.model.robot_toml import read_toml

    if not is_family_spec(read_toml(path, "sweep")):
        return None
    return read_family_sweep_spec(path)


def _best_lines(columns: dict[str, Any], spec: FamilySweepSpec, objective: str) -> list[str]:
    """Per architecture: designs that carry the task and the best of them by ``objective``."""
    lines = []
    architecture = np.asarray(columns["architecture"]).astype(str)
    status = np.asarray(columns["status"]).astype(str)
    value = np.asarray(columns[objective], dtype=np.float64)
    for index, study in enumerate(spec.studies):
        mine = architecture == study.architecture
        ok = mine & (status == "ok") & np.isfinite(value)
        head = (
            f"  {study.architecture}: {int(ok.sum())} of {int(mine.sum())} designs carry the task"
        )
        if not ok.any():
            lines.append(head)
            continue
        best = int(np.flatnonzero(ok)[np.argmin(value[ok])])
        params = ", ".join(f"{p} = {float(columns[p][best]):.6g}" for p in study.paths)
        lines.append(
            f"{head}; least {objective} {value[best]:.6g}" + (f" at {params}" if params else "")
        )
        del index
    return lines


def run_family_sweep(args: argparse.Namespace, spec: FamilySweepSpec) -> int:
    """``prp3 sweep`` of a family spec (``[[study]]``); return the exit status.

    The sweep of every robot (:func:`prp3.apps.sweep.run_sweep`): resumed after an
    interruption, ``--force`` to replace the designs of another spec.
    """
    from prp3.apps import sweep
    from prp3.cli._sweep_run import swept
    from prp3.cli._types import output_folder

    for option, given in (("--pareto", args.pareto is not None),
                          ("--sensitivity", args.sensitivity is not None)):  # fmt: skip
        if given:
            raise ParameterError(
                f"{option} applies to model-form sweeps (docs/design.md); a family sweep "
                "([[study]]) writes family_designs.png with --plots"
            )
    output: Path = args.output
    check_output_directory(output)
    check_inputs_kept(output, (sweep.DESIGNS_FILE,), (args.spec,))
    result, chunks = swept(args, spec, output)
    columns = sweep.read_designs(result.path, list(spec.evaluator.columns)).columns
    statuses = ", ".join(f"{count} {name}" for name, count in sorted(result.status.items()))
    lines = [
        f"prp3 sweep: {result.rows} designs of {len(spec.studies)} architectures "
        f"({spec.sampling}) on {', '.join(spec.motions)}: {statuses}",
        *chunks,
        *_best_lines(columns, spec, "peak_joint_force"),
    ]
    with output_folder(args, output, [args.spec]) as staged:
        staged.adopt(sweep.DESIGNS_FILE)
        if args.plots:
            from prp3.plotting.family_design import family_designs_figure
            from prp3.plotting.figures import save_figure

            figure = family_designs_figure(columns)
            save_figure(figure, staged.path("family_designs.png"))
        emit("\n".join(lines + files_report(staged)))
    return 0


def run_family_optimize(args: argparse.Namespace, spec: FamilySweepSpec) -> int:
    """``prp3 optimize`` of a family spec; return the exit status (1 when nothing is feasible)."""
    from prp3.cli._sweep_run import client_of
    from prp3.family.design import family_design_robot, optimize_family

    output: Path = args.output
    check_output_directory(output)
    check_inputs_kept(output, ("ROBOT.toml", "history.csv"), (args.spec,))
    with client_of(args) as client:
        optima, history = optimize_family(spec, client)
    settings = spec.optimize
    lines = [
        f"prp3 optimize: minimise {settings.objective} within {len(optima)} architectures "
        f"({sum(o.evaluations for o in optima)} designs)"
    ]
    for optimum in optima:
        study = spec.studies[optimum.study]
        where = ", ".join(
            f"{p} = {v!r}" for p, v in zip(study.paths, optimum.x.tolist(), strict=True)
        )
        value = optimum.row.get(settings.objective, math.nan)
        state = "feasible" if optimum.feasible else f"infeasible ({optimum.row['status']})"
        lines.append(
            f"  {optimum.architecture}: {settings.objective} = {value:.9g}, {state}"
            + (f" at {where}" if where else "")
        )
    feasible = [o for o in optima if o.feasible]
    best = min(feasible or optima, key=lambda o: o.objective)
    robot = family_design_robot(spec.studies[best.study], best.x.tolist())
    lines.append(
        f"  best: {best.architecture}"
        if feasible
        else "  no design is feasible; the least violating:" + f" {best.architecture}"
    )
    with staged_output(output) as staged:
        staged.path("ROBOT.toml").write_text(robot.to_toml(), encoding="utf-8")
        write_table_csv(staged.path("history.csv"), history)
        emit("\n".join(lines + files_report(staged)))
    return 0 if feasible else 1
