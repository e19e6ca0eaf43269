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
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import (
    InputFileError,
    ParameterError,
    Prp3Error,
    SingularPoseError,
    UnreachablePoseError,
)
from ..forward import (
    MIN_RTOL,
    ActuatorForces,
    ForwardDynamics,
    check_forward_friction,
    forward_dynamics,
    forward_velocity,
    open_loop_growth_rate,
)
from ..geometry import LEGS
from ..io import (
    check_inputs_kept,
    check_output_directory,
    read_table_csv,
    staged_output,
    write_table_csv,
)
from ..results import FRICTION_COLUMNS, RESULT_COLUMNS, results_table
from ._types import (
    add_output_directory,
    add_robot_option,
    files_report,
    finite_float,
    integer_at_least,
    load_robot,
    path_name,
    positive_float,
)

__all__ = [
    "FORCE_COLUMNS",
    "ForceInput",
    "PlanDrift",
    "plan_drift",
    "read_forces",
    "register",
    "run",
]

FloatArray = NDArray[np.float64]

#: Columns of a force history file.
FORCE_COLUMNS: tuple[str, ...] = ("t", "f10_A", "f10_B", "f10_C")

#: Columns of ``trajectory.csv`` (the ``TRAJ.csv`` layout of the data contract).
TRAJECTORY_COLUMNS: tuple[str, ...] = (
    "t", "x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi",
)  # fmt: skip

#: Exit status when the integration stopped before the last time.
EXIT_STOPPED: int = 1

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


@dataclass(frozen=True)
class ForceInput:
    """A force file read by :func:`read_forces`.

    Attributes
    ----------
    path : Path
        The file.
    forces : ActuatorForces
        Its force samples.
    first_pose, first_rates : ndarray (3,) or None
        ``(x, y, phi)`` and ``dlambda10`` of the first row of a ``results.csv``;
        ``None`` for a force table.
    planned_pose : ndarray (N, 3) or None
        ``(x, y, phi)`` of every row of a ``results.csv``: the motion the forces
        were planned for (at the times ``forces.t``); ``None`` for a force table.
    """

    path: Path
    forces: ActuatorForces
    first_pose: FloatArray | None
    first_rates: FloatArray | None
    planned_pose: FloatArray | None = None

    @property
    def results(self) -> bool:
        """Whether the file is a ``results.csv`` (all contract columns)."""
        return self.first_pose is not None


def read_forces(path: Path) -> ForceInput:
    """Read ``t,f10_A,f10_B,f10_C`` or a complete ``results.csv``.

    Raises
    ------
    InputFileError
        A malformed file, unknown columns, or some but not all of the
        ``results.csv`` columns (names the file and the missing columns).
    TrajectoryError
        Fewer than 2 rows or times that do not increase.
    """
    others = [name for name in RESULT_COLUMNS if name not in FORCE_COLUMNS]
    columns = read_table_csv(
        path, required=FORCE_COLUMNS, optional=[*others, *FRICTION_COLUMNS], what="forces"
    )
    extra = [name for name in others if name in columns]
    if extra and len(extra) != len(others):
        missing = [name for name in others if name not in columns]
        raise InputFileError(
            f"{path}: give either the columns {','.join(FORCE_COLUMNS)} or all the columns of a "
            f"results.csv; missing {', '.join(missing[:6])}"
            + (f" and {len(missing) - 6} more" if len(missing) > 6 else "")
        )
    t = columns["t"]
    f10 = np.stack([columns[f"f10_{leg}"] for leg in LEGS], axis=-1)
    try:
        forces = ActuatorForces(t=t, f10=f10)
    except Prp3Error as error:
        raise type(error)(f"{path}: {error}") from None
    if not extra:
        return ForceInput(path, forces, None, None)
    planned = np.stack([columns["x"], columns["y"], columns["phi"]], axis=-1)
    rates = np.array([columns[f"dlambda10_{leg}"][0] for leg in LEGS])
    return ForceInput(path, forces, planned[0].copy(), rates, planned)


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
    try:
        check_forward_friction(robot)
    except ParameterError as error:
        where = args.robot if args.robot is not None else "robot"
        raise ParameterError(f"{where}: {re.sub(r'^robot: ', '', str(error))}") from None
    given = read_forces(args.forces)
    forces = given.forces
    if args.initial_pose is not None:
        pose = np.array(args.initial_pose, dtype=np.float64)
    elif given.first_pose is not None:
        pose = given.first_pose
    else:
        pose = np.zeros(3)
    if args.initial_pose is not None:
        pose_source = "--initial-pose " + " ".join(repr(v) for v in args.initial_pose)
    elif given.first_pose is not None:
        pose_source = f"{given.path}: initial pose from the first row"
    else:
        pose_source = "initial pose 0 0 0 (the central configuration)"
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
    except (SingularPoseError, UnreachablePoseError) as error:  # of the initial pose
        raise type(error)(f"{pose_source}: {re.sub(r'^pose: ', '', str(error))}") from None
    except ParameterError as error:
        if str(error).startswith("forces:"):  # a force above limits.max_force
            raise ParameterError(f"{given.path}: {error}") from None
        raise
    table = results_table(result.kinematics, result.dynamics)
    motion = result.motion
    trajectory = {
        "t": motion.t,
        **{name: motion.pose[:, k] for k, name in enumerate(("x", "y", "phi"))},
        **{name: motion.velocity[:, k] for k, name in enumerate(("dx", "dy", "dphi"))},
        **{name: motion.acceleration[:, k] for k, name in enumerate(("ddx", "ddy", "ddphi"))},
    }
    with staged_output(output) as staged:
        write_table_csv(staged.path("results.csv"), table)
        write_table_csv(staged.path("trajectory.csv"), trajectory)

    growth = open_loop_growth_rate(robot, pose)
    drift = plan_drift(given, result)
    print(
        _summary(given, result, pose, velocity, drift, growth, files_report(staged)),
        file=sys.stdout,
    )
    if result.status != "completed":
        print(f"{args.program}: warning: {result.message}", file=sys.stderr)
        return EXIT_STOPPED
    return 0


@dataclass(frozen=True)
class PlanDrift:
    """How far the integrated motion is from the motion the forces were planned for.

    Attributes
    ----------
    position, orientation : ndarray (M,)
        ``|ΔG| = |G − G_plan|`` (m) and ``|Δφ|`` (rad) at the integrated samples.
    t : ndarray (M,)
        Their times (s).
    interpolated : bool
        Whether the planned poses were interpolated (cubic spline through the
        rows of the ``results.csv``) because the integrated times are not its times.
    """

    position: FloatArray
    orientation: FloatArray
    t: FloatArray
    interpolated: bool


def plan_drift(given: ForceInput, result: ForwardDynamics) -> PlanDrift | None:
    """The drift of ``result`` from the planned poses of a ``results.csv`` (``None`` without).

    >>> import numpy as np
    >>> from prp3.forward import ActuatorForces
    >>> from prp3.motion import Motion
    >>> t = np.array([0.0, 1.0, 2.0])
    >>> given = ForceInput(Path("r.csv"), ActuatorForces(t=t, f10=np.zeros((3, 3))),
    ...                    np.zeros(3), np.zeros(3), np.zeros((3, 3)))
    >>> moved = Motion(t=t, pose=[[0, 0, 0], [3e-3, 4e-3, 0], [0, 0, -0.1]],
    ...                velocity=np.zeros((3, 3)), acceleration=np.zeros((3, 3)))
    >>> class Result:
    ...     motion = moved
    >>> drift = plan_drift(given, Result())
    >>> drift.position.tolist(), drift.orientation.tolist(), drift.interpolated
    ([0.0, 0.005, 0.0], [0.0, 0.0, 0.1], False)
    """
    if given.planned_pose is None:
        return None
    t = np.asarray(result.motion.t, dtype=np.float64)
    plan_t = np.asarray(given.forces.t, dtype=np.float64)
    interpolated = not (t.size <= plan_t.size and np.array_equal(t, plan_t[: t.size]))
    if interpolated:
        from scipy.interpolate import CubicSpline

        planned = np.asarray(CubicSpline(plan_t, given.planned_pose, axis=0)(t))
    else:
        planned = given.planned_pose[: t.size]
    error = np.asarray(result.motion.pose, dtype=np.float64) - planned
    return PlanDrift(
        position=np.hypot(error[:, 0], error[:, 1]),
        orientation=np.abs(error[:, 2]),
        t=t,
        interpolated=interpolated,
    )


def _drift_lines(given: ForceInput, drift: PlanDrift | None, growth: float) -> list[str]:
    lines = []
    if drift is not None:
        how = ", interpolated by a cubic spline" if drift.interpolated else ""
        kG, kphi = int(drift.position.argmax()), int(drift.orientation.argmax())
        lines += [
            f"  drift from the planned motion (x, y, phi of {given.path}{how}):",
            f"    max |dG| = {drift.position[kG]:.3g} m at t = {drift.t[kG]:.6g} s, "
            f"max |dphi| = {drift.orientation[kphi]:.3g} rad at t = {drift.t[kphi]:.6g} s",
            f"    final (t = {drift.t[-1]:.6g} s): |dG| = {drift.position[-1]:.3g} m, "
            f"|dphi| = {drift.orientation[-1]:.3g} rad",
        ]
    if growth > 0.0:
        lines.append(
            f"  open-loop force control diverges: near the initial pose errors grow like "
            f"e^({growth:.3g} t) (the linearised motion at rest); the forces do not hold the "
            "motion on its plan, feedback does (prp3 control)"
        )
    else:
        lines.append(
            "  open-loop force control: no exponential growth of errors near the initial pose "
            "(the linearised motion at rest), but nothing pulls the motion back to a plan"
        )
    return lines


def _summary(
    given: ForceInput,
    result: ForwardDynamics,
    pose: FloatArray,
    velocity: FloatArray,
    drift: PlanDrift | None,
    growth: float,
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
        f"  self-check of the integration: the inverse dynamics of the integrated motion "
        f"gives back the input forces to {result.force_residual:.3g} N",
        f"  final pose x = {motion.pose[-1, 0]:.9g} m, y = {motion.pose[-1, 1]:.9g} m, "
        f"phi = {motion.pose[-1, 2]:.9g} rad",
        *_drift_lines(given, drift, growth),
        *files,
    ]
    return "\n".join(lines)
