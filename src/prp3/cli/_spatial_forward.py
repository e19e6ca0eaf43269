"""``prp3 forward`` for a spatial robot file (docs/spatial.md §18).

The robot of a spatial robot file, the efforts of ``--efforts hold`` (those that
hold the home pose at rest: :func:`prp3.spatial.forward.hold_efforts`) or of a
file (:func:`prp3.io.spatial_efforts.read_spatial_efforts`: ``t, tau_1 … tau_L``
or a ``results.csv`` of ``prp3 simulate``, whose first row is then the initial
state), :func:`prp3.spatial.forward.spatial_forward_dynamics`, and
``DIR/results.csv`` (the columns of §9, as ``prp3 simulate`` writes them) with
``DIR/trajectory.csv`` (§14: readable by ``prp3 simulate --trajectory``), written
together in the staged output folder; ``--plots`` adds ``platform.png``,
``efforts.png`` and ``joint_reactions.png``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from prp3.apps.runs import check_memory
from prp3.cli._progress import progress_bar
from prp3.cli._types import bound_stopped, emit, files_report, forward_bounds, output_folder
from prp3.errors import Prp3Error
from prp3.files import check_inputs_kept
from prp3.io.spatial_efforts import SpatialEfforts, read_spatial_efforts
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import write_table_csv
from prp3.spatial.forward import SpatialForward, hold_efforts, spatial_forward_dynamics
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.outputs import spatial_results_table
from prp3.spatial.rotations import matrix_quaternion, matrix_rpy
from prp3.staged_files import StagedOutput

__all__ = ["HOLD", "run_spatial_forward", "trajectory_columns"]

#: The word of ``--efforts`` for the efforts that hold the home pose at rest.
HOLD = "hold"

#: Output samples of ``--efforts hold`` when ``--samples`` is not given.
HOLD_SAMPLES = 101

#: Duration of ``--efforts hold`` when ``--duration`` is not given (s).
HOLD_DURATION = 1.0

#: Memory of a run per output sample (bytes): the §9 columns (229 for the hexapod).
BYTES_PER_SAMPLE = 8 * 2000

#: Memory of a run besides its samples (bytes).
BYTES_PER_RUN = 200 * 1024**2


def _refuse_options(args: argparse.Namespace, name: str) -> None:
    for option, given in (
        ("--initial-pose", args.initial_pose is not None),
        ("--initial-velocity", args.initial_velocity is not None),
    ):
        if given:
            raise Prp3Error(
                f"{option} applies to the planar robots; the {name} of a spatial robot file "
                "starts at its home pose at rest, or at the first row of a results.csv given "
                "by --efforts (docs/spatial.md §18)"
            )
    if args.forces is None:
        raise Prp3Error(
            "--efforts is required: 'hold' (the efforts that hold the home pose at rest) or a "
            "file t,tau_1..tau_L (or a results.csv of prp3 simulate)"
        )


def trajectory_columns(motion: PlatformMotion) -> dict[str, np.ndarray]:
    """The columns of a spatial trajectory file (docs/spatial.md §14) of ``motion``:
    ``t, x, y, z, qw, qx, qy, qz`` and the twelve rates."""
    q = matrix_quaternion(motion.rotation)
    columns = {"t": motion.t}
    for c, name in enumerate("xyz"):
        columns[name] = motion.position[:, c]
    for c, name in enumerate(("qw", "qx", "qy", "qz")):
        columns[name] = q[:, c]
    rates = (motion.omega, motion.velocity, motion.alpha, motion.acceleration)
    names = (("wx", "wy", "wz"), ("vx", "vy", "vz"), ("dwx", "dwy", "dwz"), ("ax", "ay", "az"))
    for values, triple in zip(rates, names, strict=True):
        for c, name in enumerate(triple):
            columns[name] = values[:, c]
    return columns


def _drift(given: SpatialEfforts | None, result: SpatialForward, scale: float) -> list[str]:
    """How far the integrated motion is from the planned one of a ``results.csv``."""
    if given is None or given.planned is None:
        return []
    from scipy.interpolate import CubicSpline

    planned = given.planned
    t = result.motion.t
    exact = t.size <= planned.t.size and np.array_equal(t, planned.t[: t.size])
    if exact:
        position = planned.position[: t.size]
        rotation = planned.rotation[: t.size]
    else:
        position = np.asarray(CubicSpline(planned.t, planned.position, axis=0)(t))
        quaternion = matrix_quaternion(planned.rotation)
        flips = np.sign(np.einsum("ij,ij->i", quaternion[1:], quaternion[:-1]))
        quaternion[1:] *= np.cumprod(np.where(flips == 0, 1.0, flips))[:, None]
        from prp3.spatial.rotations import quaternion_matrix

        rotation = quaternion_matrix(np.asarray(CubicSpline(planned.t, quaternion, axis=0)(t)))
    dp = np.linalg.norm(result.motion.position - position, axis=1)
    relative = np.einsum("nji,njk->nik", rotation, result.motion.rotation)
    cosine = 0.5 * (np.trace(relative, axis1=1, axis2=2) - 1.0)
    vee = relative - np.swapaxes(relative, 1, 2)
    sine = 0.5 * np.sqrt(vee[:, 2, 1] ** 2 + vee[:, 0, 2] ** 2 + vee[:, 1, 0] ** 2)
    angle = np.arctan2(sine, cosine)  # accurate for small angles too
    k, j = int(np.argmax(dp)), int(np.argmax(angle))
    how = "" if exact else ", interpolated by a cubic spline"
    return [
        f"  drift from the planned motion (the joint columns of {given.path}{how}):",
        f"    max |dp| = {dp[k]:.3g} m ({dp[k] / scale:.3g} of the scale) at t = {t[k]:.6g} s, "
        f"max rotation {angle[j]:.3g} rad at t = {t[j]:.6g} s (open loop: errors grow)",
    ]


def run_spatial_forward(args: argparse.Namespace, design: SpatialRobotFile) -> int:
    """``prp3 forward`` of a spatial robot file; return the exit status."""
    robot = design.robot
    _refuse_options(args, robot.name)
    output: Path = args.output
    hold = str(args.forces) == HOLD
    inputs = [design.path] if hold else [design.path, args.forces]
    if not hold:
        check_inputs_kept(output, ("results.csv", "trajectory.csv"), (args.forces, args.robot))
    given: SpatialEfforts | None = None
    if hold:
        tau = hold_efforts(robot)
        duration = args.duration if args.duration is not None else HOLD_DURATION
        samples = args.samples if args.samples is not None else HOLD_SAMPLES
        source = "hold (the efforts that hold the home pose at rest)"
        initial = None
        t_efforts = None
        efforts: np.ndarray = tau
    else:
        given = read_spatial_efforts(args.forces, robot)
        span = float(given.t[-1] - given.t[0])
        duration = args.duration if args.duration is not None else span
        samples = args.samples if args.samples is not None else given.t.size
        kind = "results.csv" if given.planned is not None else "efforts table"
        source = f"{given.path} ({kind}, {given.t.size} samples, cubic spline between them)"
        initial = given.planned.chunk(0, 1) if given.planned is not None else None
        if initial is None:  # home at rest at the file's first time
            initial = PlatformMotion.of(given.t[:1], robot.home_position, robot.home_rotation)
        t_efforts = given.t
        efforts = given.tau
    check_memory(f"{samples} output samples", BYTES_PER_RUN + BYTES_PER_SAMPLE * samples)
    try:
        with progress_bar() as bar:
            result = spatial_forward_dynamics(
                robot, efforts, initial, duration, t_efforts=t_efforts, samples=samples,
                rtol=args.rtol, atol=args.atol, progress=bar.stage("integrating", "samples"),
                **forward_bounds(args),
            )  # fmt: skip
    except Prp3Error as error:
        stopped = bound_stopped(error, args)
        if stopped is not None:  # --max-evaluations or --max-seconds
            raise stopped from None
        if error.key == "duration" and args.duration is not None:
            raise error.located(origin=f"--duration {args.duration!r}", subject=None) from None
        if error.subject == "initial state" and given is not None and given.planned is not None:
            raise error.located(file=given.path, line=int(given.lines[0])) from None
        if given is not None and error.key == "efforts" and error.sample is not None:
            k = error.sample  # a sample of the efforts table: its line and time
            raise error.located(
                file=given.path, line=int(given.lines[k]), time=float(given.t[k])
            ) from None
        if given is not None:
            raise error.located(file=given.path) from None
        raise error.located(origin="--efforts hold") from None
    table = spatial_results_table(result.solution)
    leg = robot.legs[0]
    unit = "N" if leg.joints[leg.actuated].kind == "P" else "N·m"
    motion = result.motion
    what = f"efforts {'hold' if hold else given.path if given else ''}"
    with output_folder(args, output, inputs) as staged:
        write_table_csv(staged.path("results.csv"), table)
        write_table_csv(staged.path("trajectory.csv"), trajectory_columns(motion))
        if args.plots:
            _save_plots(staged, table, result.motion, robot, what, given)
        p0, p1 = motion.position[0], motion.position[-1]
        lines = [
            f"prp3 forward: {robot.name} ({design.path}), efforts {source}",
            "  initial pose p = (" + ", ".join(f"{v:.9g}" for v in p0 + 0.0) + ") m, rpy = ("
            + ", ".join(f"{v:.9g}" for v in matrix_rpy(motion.rotation[0]) + 0.0) + ") rad",
            f"  {result.message}; {motion.t.size} samples written",
            "  self-check of the integration: the inverse dynamics (Newton-Euler) of the "
            f"integrated motion gives back the efforts to {result.effort_residual:.3g} {unit}",
            "  final pose p = (" + ", ".join(f"{v:.9g}" for v in p1 + 0.0) + ") m, rpy = ("
            + ", ".join(f"{v:.9g}" for v in matrix_rpy(motion.rotation[-1]) + 0.0) + ") rad",
            *_drift(given, result, robot.scale),
            *files_report(staged),
        ]  # fmt: skip
        emit("\n".join(lines))
    return 0


def _save_plots(
    staged: StagedOutput,
    table: dict[str, NDArray[np.float64]],
    motion: PlatformMotion,
    robot: SpatialRobot,
    what: str,
    given: SpatialEfforts | None,
) -> None:
    """Stage ``platform.png`` (the integrated pose, beside the planned one of a results
    table over the same times) and the spatial run's figures of ``table``."""
    from prp3.plotting.figures import save_figure
    from prp3.plotting.spatial import platform_motion_figure, spatial_figures

    planned = None
    if given is not None and given.planned is not None:
        p = given.planned
        if motion.t.size <= p.t.size and np.array_equal(motion.t, p.t[: motion.t.size]):
            n = motion.t.size
            planned = (p.position[:n], matrix_rpy(p.rotation[:n]))
    figures = {
        "platform.png": platform_motion_figure(
            motion.t, motion.position, matrix_rpy(motion.rotation), robot, what, planned
        ),
        **spatial_figures(table, robot, what=what),
    }
    for name, figure in figures.items():
        save_figure(figure, staged.path(name))
