"""``prp3 forward``: platform motion integrated from actuator force histories.

::

    prp3 forward [--robot ROBOT.toml] --forces FORCES.csv
                 [--initial-pose X Y PHI] [--initial-velocity VX VY OMEGA]
                 [--samples N] [--rtol R] [--atol A]
                 [--max-evaluations N] [--max-seconds S] --output DIR

``FORCES.csv`` is either a table ``t,f10_A,f10_B,f10_C`` or the
``results.csv`` of a previous ``prp3 simulate`` (all 46 contract columns; the
initial state then defaults to its first row); either may add ``fx, fy, mz``,
a time-varying load on the platform interpolated like the forces (a
``results.csv`` of a trajectory with a load has them).  Writes ``DIR/results.csv``
(the contract columns of the integrated motion) and ``DIR/trajectory.csv``
(``t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi``, readable by ``prp3 simulate
--trajectory``), together (:func:`prp3.staged_files.staged_output`).  When the motion
stops early at a singularity or a stroke limit, the files hold the motion up
to the stop, the reason goes to stderr and the exit status is 1.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.equations_of_motion import check_forward_friction, open_loop_growth_rate
from prp3.analysis.forward import MIN_RTOL, ForwardDynamics, forward_dynamics
from prp3.analysis.forward_kinematics import forward_velocity
from prp3.apps.runs import check_memory
from prp3.cli._progress import progress_bar
from prp3.cli._types import (
    add_forward_bounds,
    add_output_directory,
    add_robot_option,
    bound_stopped,
    emit,
    files_report,
    finite_float,
    forward_bounds,
    integer_at_least,
    load_robot_or_spatial,
    output_folder,
    path_name,
    positive_float,
)
from prp3.errors import Prp3Error
from prp3.family import FamilyRobot
from prp3.files import check_inputs_kept, check_output_directory
from prp3.io.forces import ForceInput, read_forces
from prp3.io.results import results_table
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import write_table_csv
from prp3.io.trajectory import trajectory_table

__all__ = ["PlanDrift", "plan_drift", "register", "run"]

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
      --initial-velocity is given; optional columns fx, fy, mz (N, N, N*m): a
      time-varying wrench of the environment on the platform at G (fixed frame),
      added to the robot's [load]

The forces (and the load) between samples follow the not-a-knot cubic spline
through them.

A family-form ROBOT.toml (3-RPR, 3-RRR, ...: docs/family.md) takes the efforts
t,tau_A,tau_B,tau_C (N or N*m) or the results.csv of its prp3 simulate, and
writes its 64 columns; it starts at its home pose at rest (or the first row of
a results.csv) and stops when a singularity measure falls to 1e-3
(docs/family.md).

A spatial robot file (6-UPS, 3-RPS, 3-RUU: docs/spatial.md §18) takes
--efforts hold (the efforts that hold its home pose at rest) or a table
t,tau_1..tau_L or its results.csv (which also gives the initial state), and
--duration T; it writes DIR/results.csv (the columns of its prp3 simulate) and
DIR/trajectory.csv (readable by prp3 simulate --trajectory), --plots the figures;
reaching a singularity or a joint limit, or a bound of the integration, is
refused (exit 2, nothing written):
  prp3 forward --robot hexapod.toml --efforts hold --duration 0.5 --output still
--max-evaluations N and --max-seconds S bound the integration of every robot kind
(default 1000000 evaluations of the equations of motion, 600 s of wall time): a
run stopped by one is refused naming the option (exit 2, nothing written):
  prp3 forward --robot stiff.toml --forces zero.csv --max-seconds 10 --output run
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
            "and DIR/trajectory.csv. See docs/forward_and_workspace.md; a spatial robot file:\n"
            "--efforts hold|FILE --duration T (docs/spatial.md §18)."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(parser)
    parser.add_argument(
        "--forces",
        "--efforts",
        dest="forces",
        metavar="FORCES.csv",
        type=path_name,
        help="actuator forces: header t,f10_A,f10_B,f10_C (s, N), or a results.csv of "
        "prp3 simulate; optionally fx, fy, mz: a time-varying load on the platform "
        "(required). A spatial robot file: t,tau_1..tau_L or its results.csv, or "
        "'hold' (the efforts that hold the home pose at rest)",
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
    parser.add_argument(
        "--duration",
        metavar="T",
        type=positive_float,
        help="a spatial robot file: the time integrated (s; default: the span of the efforts "
        "file, 1 s for hold)",
    )
    parser.add_argument(
        "--plots",
        action="store_true",
        help="a spatial robot file: also write platform.png, efforts.png, joint_reactions.png",
    )
    add_forward_bounds(parser)
    add_output_directory(parser)
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 forward`` with parsed ``args``; return the exit status."""
    output: Path = args.output
    check_output_directory(output)
    loaded = load_robot_or_spatial(args)
    if isinstance(loaded, SpatialRobotFile):  # docs/spatial.md §18
        from prp3.cli._spatial_forward import run_spatial_forward

        return run_spatial_forward(args, loaded)
    _check_planar_options(args)
    robot = loaded
    if isinstance(robot, FamilyRobot):  # a family-form robot file: docs/family.md
        from prp3.cli._family_analysis import run_family_forward

        return run_family_forward(args, robot)
    check_inputs_kept(output, ("results.csv", "trajectory.csv"), (args.forces, args.robot))
    try:
        check_forward_friction(robot)
    except Prp3Error as error:
        if args.robot is None:
            raise
        raise error.located(file=args.robot, subject=None) from None
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
        with progress_bar() as bar:
            result = forward_dynamics(
                robot, forces, times, pose, velocity, rtol=args.rtol, atol=args.atol,
                progress=bar.stage("integrating", "samples"), **forward_bounds(args),
            )  # fmt: skip
    except Prp3Error as error:
        located = bound_stopped(error, args) or _located(error, args, robot, given)
        if located is None:
            raise
        raise located from None
    table = results_table(result.kinematics, result.dynamics)
    with output_folder(args, output) as staged:
        write_table_csv(staged.path("results.csv"), table)
        write_table_csv(staged.path("trajectory.csv"), trajectory_table(result.motion))
        growth = open_loop_growth_rate(robot, pose)
        drift = plan_drift(given, result)
        # printed before the files are moved in: a failing standard output keeps older results
        emit(_summary(given, result, pose, velocity, drift, growth, files_report(staged)))
    if result.status != "completed":
        print(f"{args.program}: warning: {result.message}", file=sys.stderr)
        return EXIT_STOPPED
    return 0


def _check_planar_options(args: argparse.Namespace) -> None:
    """Refuse the options of a spatial robot file (``--duration``, ``--plots``,
    ``--forces hold``) and a missing ``--forces`` in a planar run."""
    for option, given in (("--duration", args.duration is not None), ("--plots", args.plots)):
        if given:
            raise Prp3Error(
                f"{option} applies to a spatial robot file (docs/spatial.md §18); the planar "
                "robots integrate over the times of --forces"
            )
    if args.forces is None:
        raise Prp3Error("--forces FORCES.csv is required (the actuator forces over time)")
    if str(args.forces) == "hold":
        raise Prp3Error(
            "--forces hold applies to a spatial robot file (docs/spatial.md §18); give a "
            "table of forces t,f10_A,f10_B,f10_C"
        )


def _located(
    error: Prp3Error, args: argparse.Namespace, robot: Any, given: ForceInput
) -> Prp3Error | None:
    """The integration's ``error`` laid to where its cause was given: the initial pose's
    option or row, the forces file, or the robot file (:func:`_cause_file`); None for another
    error (raised as it is)."""
    if error.subject in ("initial_pose", "pose"):  # the initial pose: say where it came from
        if args.initial_pose is not None:
            origin = "--initial-pose " + " ".join(repr(v) for v in args.initial_pose)
            return error.located(origin=origin, subject=None)
        if given.first_pose is not None:
            return error.located(file=given.path, subject="initial pose from the first row")
        return error.located(origin="initial pose 0 0 0 (the central configuration)", subject=None)
    if error.subject == "forces":  # a force above limits.max_force
        k = error.sample  # a sample of the forces table: its line and time
        if k is None or given.lines is None:
            return error.located(file=given.path)
        when = float(given.forces.t[k])
        return error.located(file=given.path, line=int(given.lines[k]), time=when)
    if error.subject == "forward dynamics":  # a bound, or the equations lost meaning
        return error.located(file=_cause_file(args, robot, given))
    return None


def _cause_file(args: argparse.Namespace, robot: Any, given: ForceInput) -> Path:
    """The file a run's failure is laid to: the robot file when it has effects, else the forces."""
    effects = robot.load.present or robot.payload.present or robot.friction or robot.spring
    return Path(args.robot) if args.robot is not None and effects else given.path


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
    >>> from prp3.analysis.force_histories import ActuatorForces
    >>> from prp3.model.motion import Motion
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
    if given.forces.load is not None:
        kind += ", with the load fx, fy, mz"
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
