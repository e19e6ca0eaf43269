"""``prp3 excite``: an exciting trajectory for identification, written as a trajectory file.

::

    prp3 excite [--robot ROBOT.toml] --output DIR [--period S] [--harmonics L]
                [--samples N] [--reach R] [--rotation RAD] [--max-velocity V]
                [--max-force F] [--seed K] [--iterations K]

Writes ``DIR/trajectory.csv`` (columns ``t, x, y, phi, dx, dy, dphi, ddx, ddy,
ddphi``, the analytic derivatives of the series): one period of the finite
Fourier series of :func:`prp3.apps.excitation.exciting_trajectory`, which
minimises the condition number of the stacked base regressor within the
limits.  A family-form ROBOT.toml (docs/family.md) gets the same about its home
pose, for the base regressor of its actuator efforts (``--reach`` a fraction
of its ``leg.scale``, ``--max-velocity`` of its actuated joints' rates,
``--max-force`` of their efforts).  A spatial robot file (docs/spatial.md §13)
gets the best of random Fourier series of its platform about home
(:func:`prp3.apps.spatial_identification.spatial_exciting_trajectory`; ``--reach``
a fraction of its ``scale``, ``--iterations`` the series tried), written as a
spatial trajectory file (§14: ``t, x, y, z, qw, qx, qy, qz`` and the twist
and its derivative).  This module only parses and prints.
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from prp3.apps.base_parameters import base_parameters
from prp3.apps.excitation import ExcitingTrajectory, exciting_trajectory
from prp3.apps.identification import samples_refusal
from prp3.apps.spatial_identification import spatial_base_parameters
from prp3.cli._progress import progress_bar
from prp3.cli._spatial_identify import run_spatial_excite, series_options
from prp3.cli._types import (
    add_output_directory,
    add_robot_option,
    emit,
    files_report,
    integer_at_least,
    load_robot_or_spatial,
    output_folder,
    positive_float,
)
from prp3.errors import ParameterError
from prp3.family.model import FamilyRobot
from prp3.files import check_output_directory
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import write_table_csv

__all__ = ["TRAJECTORY_NAME", "register", "run"]

#: File ``prp3 excite`` writes.
TRAJECTORY_NAME: str = "trajectory.csv"

EXAMPLES = """\
examples:
  prp3 excite --robot robot.toml --output excite
  prp3 excite --period 8 --harmonics 5 --max-velocity 0.3 --max-force 200 --output slow

Then drive the robot along DIR/trajectory.csv, record the actuator forces as
f10_A, f10_B, f10_C next to t, x, y, phi, and run prp3 identify on that file.
Exit status 0 on success, 2 on bad input (one line on stderr, nothing written),
among it limits so tight that no motion within them excites every base
parameter as prp3 identify requires (the limit that binds is named).
"""


def register(subparsers: Any) -> None:
    """Add the ``excite`` subcommand."""
    parser = subparsers.add_parser(
        "excite",
        help="an exciting trajectory for identification -> DIR/trajectory.csv",
        description=(
            "Design a periodic platform motion (finite Fourier series) that minimises the\n"
            "condition number of the base regressor of f10 within the workspace, stroke,\n"
            "velocity and force limits (docs/identification.md)."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(
        parser, "; its [limits] stroke and max_force are obeyed; a family-form file: docs/family.md"
    )
    add_output_directory(parser)
    parser.add_argument(
        "--period", type=positive_float, default=5.0, help="period of the series (s, default 5)"
    )
    parser.add_argument(
        "--harmonics",
        type=integer_at_least(1, 20),
        default=4,
        help="harmonics per coordinate (default 4)",
    )
    parser.add_argument(
        "--samples",
        type=integer_at_least(2, 10**7),
        default=1001,
        help="samples written over one period, both ends included (default 1001)",
    )
    parser.add_argument(
        "--reach",
        type=positive_float,
        default=0.2,
        help="largest |x|, |y| as a fraction of l0 (default 0.2)",
    )
    parser.add_argument(
        "--rotation",
        metavar="RAD",
        type=positive_float,
        default=0.5,
        help="largest |phi| (rad, below 1: phi = pi/3 is singular; default 0.5)",
    )
    parser.add_argument(
        "--max-velocity",
        metavar="V",
        type=positive_float,
        default=0.5,
        help="largest actuator velocity |dlambda10| (m/s, default 0.5)",
    )
    parser.add_argument(
        "--max-force",
        metavar="F",
        type=positive_float,
        help="largest |f10| of the robot (N; default its limits.max_force, else none)",
    )
    parser.add_argument(
        "--seed", type=integer_at_least(0), default=0, help="seed of the starting guess"
    )
    parser.add_argument(
        "--iterations",
        type=integer_at_least(1, 10_000),
        default=None,
        help="most SLSQP iterations (default 150); of a spatial robot file the random "
        "series tried (default 10)",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 excite`` with parsed ``args``; return the exit status."""
    check_output_directory(args.output)
    loaded = load_robot_or_spatial(args)
    if isinstance(loaded, SpatialRobotFile):
        base = spatial_base_parameters(loaded.robot)
    else:
        base = base_parameters(loaded)
    too_few = samples_refusal(base, args.samples)
    if too_few is not None:  # prp3 identify would refuse the trajectory written
        raise ParameterError(f"--samples {args.samples}: {too_few}, which prp3 identify needs")
    if isinstance(loaded, SpatialRobotFile):
        return run_spatial_excite(args, loaded, TRAJECTORY_NAME)
    robot = loaded
    with progress_bar() as bar:
        result = exciting_trajectory(
            robot,
            **series_options(args),
            max_iterations=args.iterations if args.iterations is not None else 150,
            progress=bar.stage("optimising", "iterations"),
        )
    motion = result.series.motion(np.linspace(0.0, args.period, args.samples))
    names = ("t", "x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")
    columns = [motion.t, *motion.pose.T, *motion.velocity.T, *motion.acceleration.T]
    if isinstance(robot, FamilyRobot):
        return _write_family(args, robot, result, names, columns)
    force = args.max_force if args.max_force is not None else robot.limits.max_force
    with output_folder(args, args.output) as staged:
        write_table_csv(staged.path(TRAJECTORY_NAME), dict(zip(names, columns, strict=True)))
        lines = [
            f"prp3 excite: Fourier series, {args.harmonics} harmonics, period {args.period:g} s",
            f"  condition number of the base regressor of f10: {result.condition:.4g} "
            f"(starting guess {result.initial_condition:.4g}, {result.iterations} SLSQP iterations)",
            f"  limits: |x|, |y| <= {args.reach:g} l0, |phi| <= {args.rotation:g} rad, "
            f"|dlambda10| <= {args.max_velocity:g} m/s"
            + (f", |f10| <= {force:g} N" if force is not None else "")
            + (
                f", stroke {list(robot.limits.stroke)} m" if robot.limits.stroke is not None else ""
            ),
            f"  peaks (nominal robot): |lambda10| {result.peak_lambda10:.4g} m, "
            f"|dlambda10| {result.peak_dlambda10:.4g} m/s, |f10| {result.peak_f10:.4g} N",
            *files_report(staged),
        ]
        # printed before the files are moved in: a failing standard output keeps older results
        emit("\n".join(lines))
    return 0


def _write_family(
    args: argparse.Namespace,
    robot: FamilyRobot,
    result: ExcitingTrajectory,
    names: tuple[str, ...],
    columns: list[np.ndarray],
) -> int:
    """Write and summarise the exciting trajectory of a family robot."""
    prismatic = robot.types[robot.actuated - 1] == "P"
    value, rate, effort = ("m", "m/s", "N") if prismatic else ("rad", "rad/s", "N m")
    x0, y0, phi0 = (round(float(v), 12) + 0.0 for v in robot.home_poses.mean(axis=0))
    with output_folder(args, args.output) as staged:
        write_table_csv(staged.path(TRAJECTORY_NAME), dict(zip(names, columns, strict=True)))
        lines = [
            f"prp3 excite: {robot.architecture} (actuated joint {robot.actuated}), Fourier "
            f"series, {args.harmonics} harmonics, period {args.period:g} s",
            f"  condition number of the base regressor of tau: {result.condition:.4g} "
            f"(starting guess {result.initial_condition:.4g}, {result.iterations} SLSQP iterations)",
            f"  limits about the home pose ({x0:.6g}, {y0:.6g}, {phi0:.6g}): |x - x0|, |y - y0| "
            f"<= {args.reach:g} leg.scale, |phi - phi0| <= {args.rotation:g} rad, |dq| <= "
            f"{args.max_velocity:g} {rate}"
            + (f", |tau| <= {args.max_force:g} {effort}" if args.max_force is not None else "")
            + ", singularity measures above a quarter of their home values",
            f"  peaks (nominal robot): |q| {result.peak_lambda10:.4g} {value}, "
            f"|dq| {result.peak_dlambda10:.4g} {rate}, |tau| {result.peak_f10:.4g} {effort}",
            *files_report(staged),
        ]
        # printed before the files are moved in: a failing standard output keeps older results
        emit("\n".join(lines))
    return 0
