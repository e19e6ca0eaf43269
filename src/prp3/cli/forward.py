"""``prp3 forward``: platform motion integrated from actuator force histories.

::

    prp3 forward [--robot ROBOT.toml] --forces FORCES.csv
                 [--initial-pose X Y PHI] [--initial-velocity VX VY OMEGA]
                 [--samples N] [--rtol R] [--atol A] --output DIR

``FORCES.csv`` is either a table ``t,f10_A,f10_B,f10_C`` or the
``results.csv`` of a previous ``prp3 simulate`` (all 46 contract columns; the
initial state then defaults to its first row).  Writes ``DIR/results.csv``
(the contract columns of the integrated motion) and ``DIR/trajectory.csv``
(``t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi``, readable by ``prp3 simulate
--trajectory``), together (:func:`prp3.io.staged_output`).  When the motion
stops early at a singularity or a stroke limit, the files hold the motion up
to the stop, the reason goes to stderr and the exit status is 1.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import Prp3Error
from ..forward import MIN_RTOL, ForwardDynamics, forward_dynamics, forward_velocity
from ..io import (
    FORCE_COLUMNS,
    ForceInput,
    check_inputs_kept,
    check_output_directory,
    read_forces,
    results_table,
    staged_output,
    trajectory_table,
    write_table_csv,
)
from ..runs import check_memory
from ._types import (
    add_output_directory,
    add_robot_option,
    emit,
    files_report,
    finite_float,
    integer_at_least,
    load_robot,
    path_name,
    positive_float,
)

__all__ = ["FORCE_COLUMNS", "ForceInput", "read_forces", "register", "run"]  # from prp3.io

FloatArray = NDArray[np.float64]

#: Exit status when the integration stopped before the last time.
EXIT_STOPPED: int = 1

#: Memory of a run per output sample (bytes): the inverse dynamics of 4 states per
#: sample (the equations of motion), the results and trajectory tables.  tracemalloc
#: measured a peak of 7.3 kB per sample at N = 2000 (14 kB at N = 500), falling with N.
BYTES_PER_SAMPLE: int = 8_000

#: Memory of a run besides its samples (bytes).
BYTES_PER_RUN: int = 200 * 1024**2

EXAMPLES = """\
examples:
  prp3 simulate --motion vertical --output inv
  prp3 forward --forces inv/results.csv --output fwd
      integrate the forces of the paper's vertical motion from its first state; the
      open-loop motion is unstable (errors grow about e^(6 t)): see the docs
  prp3 forward --robot robot.toml --forces push.csv --initial-pose 0 0.01 0 --output run
      push.csv: header t,f10_A,f10_B,f10_C (s, N); starts at rest unless
      --initial-velocity is given

The forces between samples follow the not-a-knot cubic spline through them.
Exit status 0 when the motion reached the last time; 1 when it stopped early at a
singularity (|sin(phi - pi/3)| = 2e-4) or at a stroke limit, or the integrator gave
up (the files hold the motion up to the stop; the reason is on stderr); 2 on bad
input (one line on stderr, nothing written).
"""


def _relative_tolerance(text: str) -> float:
    """``--rtol``: a number >= MIN_RTOL (scipy would raise a smaller one with a warning)."""
    value = positive_float(text)
    if value < MIN_RTOL:
        raise argparse.ArgumentTypeError(f"expected a number >= {MIN_RTOL:.3g}, got {text!r}")
    return value


def register(subparsers: Any) -> None:
    """Add the ``forward`` subcommand."""
    parser = subparsers.add_parser(
        "forward",
        help="forward dynamics: platform motion from actuator forces -> DIR/results.csv",
        description=(
            "Integrate the platform motion of the 3-PRP robot driven by given actuator forces\n"
            "(scipy solve_ivp, DOP853) and write DIR/results.csv (the columns of prp3 simulate)\n"
            "and DIR/trajectory.csv. See docs/forward_and_workspace.md."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(parser)
    parser.add_argument(
        "--forces",
        metavar="FORCES.csv",
        type=path_name,
        required=True,
        help="actuator forces: header t,f10_A,f10_B,f10_C (s, N), or a results.csv of "
        "prp3 simulate",
    )
    parser.add_argument(
        "--initial-pose",
        metavar=("X", "Y", "PHI"),
        type=finite_float,
        nargs=3,
        help="pose at the first time (m, m, rad); default: the first row of a results.csv, "
        "else the central configuration 0 0 0",
    )
    parser.add_argument(
        "--initial-velocity",
        metavar=("VX", "VY", "OMEGA"),
        type=finite_float,
        nargs=3,
        help="platform velocity at the first time (m/s, m/s, rad/s); default: from the "
        "dlambda10 of the first row of a results.csv by the inverse Jacobian (unless "
        "--initial-pose is given), else at rest",
    )
    parser.add_argument(
        "--samples",
        metavar="N",
        type=integer_at_least(2),
        help="output samples evenly over the time span of the forces (default: the times "
        "of the force file)",
    )
    parser.add_argument(
        "--rtol",
        metavar="R",
        type=_relative_tolerance,
        default=1e-10,
        help=f"relative tolerance, at least {MIN_RTOL:.3g} (default 1e-10)",
    )
    parser.add_argument(
        "--atol",
        metavar="A",
        type=positive_float,
        default=1e-12,
        help="absolute tolerance on m, rad, m/s, rad/s (1e-12)",
    )
    add_output_directory(parser)
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 forward`` with parsed ``args``; return the exit status."""
    output: Path = args.output
    check_output_directory(output)
    check_inputs_kept(output, ("results.csv", "trajectory.csv"), (args.forces, args.robot))
    robot = load_robot(args)
    given = read_forces(args.forces)
    forces = given.forces
    if args.initial_pose is not None:
        pose = np.array(args.initial_pose, dtype=np.float64)
    elif given.first_pose is not None:
        pose = given.first_pose
    else:
        pose = np.zeros(3)
    samples = args.samples if args.samples is not None else forces.t.size
    check_memory(f"{samples} output samples", BYTES_PER_RUN + BYTES_PER_SAMPLE * samples)
    try:
        if args.initial_velocity is not None:
            velocity = np.array(args.initial_velocity, dtype=np.float64)
        elif given.first_rates is not None and args.initial_pose is None:
            velocity = forward_velocity(robot, pose, given.first_rates)
        else:
            velocity = np.zeros(3)
        if args.samples is not None:
            times = np.linspace(float(forces.t[0]), float(forces.t[-1]), args.samples)
        else:
            times = np.asarray(forces.t)
        result = forward_dynamics(
            robot, forces, times, pose, velocity, rtol=args.rtol, atol=args.atol
        )
    except Prp3Error as error:
        if error.subject in ("initial_pose", "pose"):  # the initial pose: say where it came from
            if args.initial_pose is not None:
                origin = "--initial-pose " + " ".join(repr(v) for v in args.initial_pose)
                raise error.located(origin=origin, subject=None) from None
            if given.first_pose is not None:
                raise error.located(
                    file=given.path, subject="initial pose from the first row"
                ) from None
            raise error.located(
                origin="initial pose 0 0 0 (the central configuration)", subject=None
            ) from None
        if error.subject == "forces":  # a force above limits.max_force
            raise error.located(file=given.path) from None
        raise
    table = results_table(result.kinematics, result.dynamics)
    with staged_output(output) as staged:
        write_table_csv(staged.path("results.csv"), table)
        write_table_csv(staged.path("trajectory.csv"), trajectory_table(result.motion))
        # printed before the files are moved in: a failing standard output keeps older results
        emit(_summary(given, result, pose, velocity, files_report(staged)))
    if result.status != "completed":
        print(f"{args.program}: warning: {result.message}", file=sys.stderr)
        return EXIT_STOPPED
    return 0


def _summary(
    given: ForceInput,
    result: ForwardDynamics,
    pose: FloatArray,
    velocity: FloatArray,
    files: list[str],
) -> str:
    kind = "results.csv" if given.results else "force table"
    motion = result.motion
    lines = [
        f"prp3 forward: forces from {given.path} ({kind}, {given.forces.t.size} samples, "
        "cubic spline between them)",
        f"  initial pose {(pose + 0.0).tolist()!r}, velocity {(velocity + 0.0).tolist()!r}",
        f"  {result.message}; {motion.samples} samples written, "
        f"{result.evaluations} evaluations of the equations of motion",
        f"  self-check: f10 of the integrated motion matches the input forces to "
        f"{result.force_residual:.3g} N",
        f"  final pose x = {motion.pose[-1, 0]:.9g} m, y = {motion.pose[-1, 1]:.9g} m, "
        f"phi = {motion.pose[-1, 2]:.9g} rad",
        *files,
    ]
    return "\n".join(lines)
