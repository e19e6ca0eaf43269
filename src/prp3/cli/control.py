"""``prp3 control``: closed-loop tracking of a motion by a model-based controller.

::

    prp3 control [--robot ROBOT.toml] (--motion M | --trajectory TRAJ.csv)
                 --plant prp3|mujoco --controller computed-torque|pd|feedforward
                 [--rate HZ] [--model MODEL.toml] [--kp KP] [--kd KD] --output DIR

Writes ``DIR/tracking.csv`` (one row per control instant: ``t, x, y, phi,
x_ref, y_ref, phi_ref, f10_A, f10_B, f10_C``) and ``DIR/tracking.png``
together (:func:`prp3.staged_files.staged_output`) and prints a summary (max and RMS
tracking errors, the controller's time per step).  The computation is
:func:`prp3.apps.control.track`; this module only parses and prints.  When the
plant stops early (singularity, stroke limit, failed simulation), the files
hold the run up to the stop, the reason goes to stderr and the exit status is 1.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from prp3.apps.control import (
    DEFAULT_RATE,
    LOAD_REFUSAL,
    Tracking,
    check_model,
    control_times,
    hermite_reference,
    track,
)
from prp3.apps.control_law import CONTROLLERS, DEFAULT_KD, DEFAULT_KP, Gains
from prp3.apps.plants import PLANTS
from prp3.cli._progress import progress_bar
from prp3.cli._types import (
    add_output_directory,
    add_robot_option,
    emit,
    files_report,
    finite_float,
    load_any_robot,
    load_robot_or_spatial,
    output_folder,
    path_name,
    positive_float,
)
from prp3.errors import ParameterError, SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.family.model import FamilyRobot, read_robot_file
from prp3.files import check_inputs_kept, check_output_directory
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import write_table_csv
from prp3.io.trajectory import read_trajectory
from prp3.mechanics.geometry import inverse_geometry
from prp3.model.motion import PAPER_DURATION, PAPER_MOTIONS, Motion, law_at
from prp3.model.robot import Robot
from prp3.plotting.control import TRACKING_FIGURE  # a constant: matplotlib is not imported
from prp3.spatial.motion import SPATIAL_MOTIONS
from prp3.validation import LEGS

__all__ = ["EXIT_STOPPED", "TRACKING_COLUMNS", "register", "run", "tracking_table"]

#: Exit status when the plant stopped before the last instant.
EXIT_STOPPED: int = 1

#: Columns of ``tracking.csv``.
TRACKING_COLUMNS: tuple[str, ...] = (
    "t", "x", "y", "phi", "x_ref", "y_ref", "phi_ref", "f10_A", "f10_B", "f10_C",
)  # fmt: skip

EXAMPLES = """\
examples:
  prp3 control --motion rotation --plant prp3 --controller computed-torque --output ct
  prp3 control --motion rotation --plant mujoco --controller pd --kp 900 --kd 60 --output pd
  prp3 control --motion vertical --plant prp3 --controller computed-torque \\
               --robot heavy.toml --model robot.toml --output wrong-mass
      the plant is heavy.toml, the controller believes robot.toml (same l0)

Control laws (e = q_ref - q, q = (x, y, phi), ID = inverse dynamics of the model):
  computed-torque  f10 = ID(q, dq, ddq_ref + KD de + KP e)
  pd               f10 = ID(q, 0, KD de + KP e)   (gravity compensation, no feed-forward)
  feedforward      f10 = ID(q_ref, dq_ref, ddq_ref)   (open loop)
Exit status 0; 1 when the plant stopped early; 2 on bad input (one line, nothing written).
"""


def non_negative_float(text: str) -> float:
    """A finite float >= 0 (a gain)."""
    value = finite_float(text)
    if value < 0.0:
        raise argparse.ArgumentTypeError(f"expected a non-negative number, got {text!r}")
    return value


def axis_gains(text: str) -> float | tuple[float, ...]:
    """A gain for every axis (``400``), one per axis ``x,y,phi`` (``400,400,900``), or, for a
    spatial robot file, one per pose component ``RX,RY,RZ,X,Y,Z`` (docs/spatial.md §23).

    >>> axis_gains("400"), axis_gains("400,400,900")
    (400.0, (400.0, 400.0, 900.0))
    >>> axis_gains("1,2")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected a number or 3 numbers X,Y,PHI, got '1,2' (a spatial robot file: or 6 numbers RX,RY,RZ,X,Y,Z)
    """
    parts = text.split(",")
    if len(parts) == 1:
        return non_negative_float(text)
    if len(parts) not in (3, 6):
        raise argparse.ArgumentTypeError(
            f"expected a number or 3 numbers X,Y,PHI, got {text!r} (a spatial robot file: or 6 "
            "numbers RX,RY,RZ,X,Y,Z)"
        )
    return tuple(non_negative_float(part) for part in parts)


def pose_error(text: str) -> tuple[float, ...]:
    """Six numbers ``RX,RY,RZ,X,Y,Z`` (rad, m): an initial pose error.

    >>> pose_error("0,0,0.01,0,0,0.002")
    (0.0, 0.0, 0.01, 0.0, 0.0, 0.002)
    """
    parts = text.split(",")
    if len(parts) != 6:
        raise argparse.ArgumentTypeError(f"expected 6 numbers RX,RY,RZ,X,Y,Z, got {text!r}")
    return tuple(finite_float(part) for part in parts)


def gains_text(value: float | tuple[float, ...]) -> str:
    """``400`` or ``(400, 400, 900)`` for the summary and the figure.

    >>> gains_text(400.0), gains_text((400.0, 400.0, 900.0))
    ('400', '(400, 400, 900)')
    """
    if isinstance(value, tuple):
        return "(" + ", ".join(f"{v:g}" for v in value) + ")"
    return f"{value:g}"


def register(subparsers: Any) -> None:
    """Add the ``control`` subcommand."""
    parser = subparsers.add_parser(
        "control",
        help="closed-loop tracking by computed torque, PD or feed-forward -> DIR/tracking.csv",
        description=(
            "Simulate a model-based controller tracking a platform motion: the plant is\n"
            "prp3's forward dynamics or MuJoCo running the exported MJCF; the controller\n"
            "runs at --rate with zero-order hold and uses prp3's inverse dynamics of\n"
            "--model. Writes DIR/tracking.csv and DIR/tracking.png (docs/control.md)."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(parser, "; the plant, the robot simulated")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument(
        "--motion",
        choices=(*PAPER_MOTIONS, *SPATIAL_MOTIONS),
        help="one of the paper's motions (eq. 4, t = 0..3 s), the analytic law as reference; "
        f"for a spatial robot file: {', '.join(SPATIAL_MOTIONS)} (docs/spatial.md §23)",
    )
    source.add_argument(
        "--trajectory",
        metavar="TRAJ.csv",
        type=path_name,
        help="platform motion file (header t,x,y,phi[,dx,dy,dphi,ddx,ddy,ddphi]); the "
        "reference is its quintic Hermite interpolation",
    )
    parser.add_argument("--plant", choices=PLANTS, required=True, help="the simulated robot")
    parser.add_argument("--controller", choices=CONTROLLERS, required=True, help="the control law")
    parser.add_argument(
        "--rate",
        metavar="HZ",
        type=positive_float,
        default=DEFAULT_RATE,
        help=f"control rate, zero-order hold between instants (default {DEFAULT_RATE:g} Hz)",
    )
    parser.add_argument(
        "--model",
        metavar="MODEL.toml",
        type=path_name,
        help="the controller's model of the robot (default: the plant's robot); same l0",
    )
    parser.add_argument(
        "--kp",
        metavar="KP",
        type=axis_gains,
        default=DEFAULT_KP,
        help=f"position gain (1/s^2, default {DEFAULT_KP:g}): one for every axis, or "
        "KP_X,KP_Y,KP_PHI; a spatial robot file: one, or KP_RX,KP_RY,KP_RZ,KP_X,KP_Y,KP_Z",
    )
    parser.add_argument(
        "--kd",
        metavar="KD",
        type=axis_gains,
        default=DEFAULT_KD,
        help=f"velocity gain (1/s, default {DEFAULT_KD:g}): one for every axis, or "
        "KD_X,KD_Y,KD_PHI; a spatial robot file: one, or KD_RX,KD_RY,KD_RZ,KD_X,KD_Y,KD_Z",
    )
    parser.add_argument(
        "--initial-error",
        metavar="RX,RY,RZ,X,Y,Z",
        type=pose_error,
        help="a spatial robot file only: the plant starts with this pose error "
        "(log(R_ref R^T) rad, p_ref - p m) from the reference (docs/spatial.md §23)",
    )
    parser.add_argument(
        "--duration",
        metavar="T",
        type=positive_float,
        help="a spatial robot file only: the motion's period and the run's length (s, default 3)",
    )
    parser.add_argument(
        "--plots",
        action="store_true",
        help="a spatial robot file: also write DIR/tracking.png (a planar robot writes it always)",
    )
    add_output_directory(parser)
    parser.set_defaults(handler=run)


def tracking_table(run: Tracking, effort: str = "f10") -> dict[str, np.ndarray]:
    """The columns of ``tracking.csv`` of a run (``effort``: ``f10``, or ``tau`` of a family robot)."""
    columns = [
        run.t,
        *run.pose.T,
        *run.reference.pose.T,
        *run.f10.T,
    ]
    names = [*TRACKING_COLUMNS[:7], *(f"{effort}_{leg}" for leg in LEGS)]
    return dict(zip(names, columns, strict=True))


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 control`` with parsed ``args``; return the exit status."""
    output: Path = args.output
    check_output_directory(output)
    names = ("tracking.csv", TRACKING_FIGURE)
    check_inputs_kept(output, names, (args.trajectory, args.robot, args.model))
    loaded = load_robot_or_spatial(args)
    if isinstance(loaded, SpatialRobotFile):  # docs/spatial.md §23
        from prp3.cli._spatial_control import run_spatial_control

        return run_spatial_control(args, loaded)
    for option in ("initial_error", "duration"):
        if getattr(args, option) is not None:
            raise ParameterError(
                f"--{option.replace('_', '-')} applies to a spatial robot file only "
                "(docs/spatial.md §23)"
            )
    if args.motion is not None and args.motion not in PAPER_MOTIONS:
        raise ParameterError(
            f"--motion {args.motion} is a motion of the spatial robots (docs/spatial.md §23); "
            f"the planar robots take --motion {' | '.join(PAPER_MOTIONS)} or --trajectory"
        )
    robot = load_any_robot(args)  # either form: docs/family.md for the other architectures
    model = _checked_model(args, robot)
    family = isinstance(robot, FamilyRobot)
    effort, unit = ("tau", "N") if family else ("f10", "N")
    if isinstance(robot, FamilyRobot) and robot.types[robot.actuated - 1] == "R":
        unit = "N m"
    if args.model is not None:
        model_text = f"model {args.model}"
    else:
        model_text = "model = the plant's robot"
    reference, what, note = _reference(args, robot)
    with progress_bar() as bar:
        result = track(
            robot,
            reference,
            controller=args.controller,
            plant=args.plant,
            model=model,
            gains=Gains(kp=args.kp, kd=args.kd),
            progress=bar.stage("tracking", "steps"),
        )
    if note is not None:  # only for a run that goes on: a refused input gets its one line
        print(f"{args.program}: warning: {note}", file=sys.stderr)
    table = tracking_table(result, effort)
    title = f"{args.controller} control, {args.plant} plant, {args.rate:g} Hz"
    if isinstance(robot, FamilyRobot):
        title = f"{robot.architecture}: {title}"
    subtitle = f"{what}; {model_text}" + (
        ""
        if args.controller == "feedforward"
        else f"; KP = {gains_text(args.kp)} 1/s², KD = {gains_text(args.kd)} 1/s"
    )
    with output_folder(args, output) as staged:
        write_table_csv(staged.path("tracking.csv"), table)
        if result.t.size >= 2:
            from prp3.plotting.control import tracking_figure
            from prp3.plotting.figures import save_figure

            save_figure(
                tracking_figure(
                    table,
                    title=title,
                    subtitle=subtitle,
                    stop=None if result.status == "completed" else result.message,
                    end=float(reference.t[-1]),
                ),
                staged.path(TRACKING_FIGURE),
            )
        # printed before the files are moved in: a failing standard output keeps older results
        emit(_summary(result, title, what, model_text, args, files_report(staged), effort, unit))
    if isinstance(robot, Robot):
        _force_warnings(args.program, robot, result)
    if result.status != "completed":
        print(f"{args.program}: warning: {result.message}", file=sys.stderr)
        return EXIT_STOPPED
    return 0


def _checked_model(args: argparse.Namespace, robot: Robot | FamilyRobot) -> Robot | FamilyRobot:
    """The controller's model: ``--model`` (else the plant's robot), checked against it."""
    model: Robot | FamilyRobot = robot
    if args.model is not None:
        try:
            model = read_robot_file(args.model)
        except ParameterError as error:
            raise error.located(file=args.model) from None
    try:
        check_model(robot, model)
    except ParameterError as error:
        raise error.located(file=args.model) from None
    return model


def _reference(
    args: argparse.Namespace, robot: Robot | FamilyRobot
) -> tuple[Motion, str, str | None]:
    """The reference at the control times (``--trajectory`` or ``--motion``), what the summary
    calls it and the trajectory file's note (or ``None``)."""
    if args.trajectory is None:
        times = control_times(0.0, PAPER_DURATION, args.rate)
        return (
            law_at(PAPER_MOTIONS[args.motion], times),
            f"{args.motion} motion (paper eq. 4)",
            None,
        )
    family = isinstance(robot, FamilyRobot)
    trajectory = read_trajectory(args.trajectory, crossing=not family)
    if trajectory.motion.load is not None:
        raise TrajectoryError(
            f"prp3 control does not use the load columns: {LOAD_REFUSAL}",
            file=trajectory.path,
        )
    motion = trajectory.motion
    try:
        if isinstance(robot, Robot):  # a family robot's: checked along its path by track
            inverse_geometry(robot, motion.pose)
    except (SingularPoseError, UnreachablePoseError) as error:
        sample = error.sample
        line = int(trajectory.lines[sample]) if sample is not None else None
        when = float(motion.t[sample]) if sample is not None else None
        raise error.located(file=trajectory.path, line=line, time=when, subject=None) from None
    times = control_times(float(motion.t[0]), float(motion.t[-1]), args.rate)
    reference = hermite_reference(motion, times, crossing=not family)
    return reference, f"trajectory {args.trajectory} (quintic Hermite reference)", trajectory.note


def _force_warnings(program: str, robot: Robot, result: Tracking) -> None:
    """A warning for each actuator whose force the controller asks above ``limits.max_force``."""
    limit = robot.limits.max_force
    if limit is not None:  # the plant's actuators: the controller asked for more than they give
        peak = np.abs(result.f10).max(axis=0)
        for j, leg in enumerate(LEGS):
            if peak[j] > limit:
                when = float(result.t[int(np.abs(result.f10[:, j]).argmax())])
                print(
                    f"{program}: warning: the controller asks |f10_{leg}| = {peak[j]:.6g} N "
                    f"at t = {when:.6g} s, above limits.max_force = {limit:g} N (the plant does "
                    "not saturate)",
                    file=sys.stderr,
                )


def _summary(
    result: Tracking,
    title: str,
    what: str,
    model_text: str,
    args: argparse.Namespace,
    files: list[str],
    effort: str = "f10",
    unit: str = "N",
) -> str:
    def row(label: str, values: np.ndarray) -> str:
        return f"  {label:<18}" + "".join(f"{v:>14.4g}" for v in values.tolist())

    peak = np.abs(result.f10).max(axis=0)
    lines = [
        f"prp3 control: {title}",
        f"  reference: {what}, {result.reference.t.size} instants over "
        f"t = {float(result.t[0]):g} .. {float(result.t[-1]):g} s",
        f"  {model_text}"
        + (
            "; no gains (open loop)"
            if args.controller == "feedforward"
            else f"; gains KP = {gains_text(args.kp)} 1/s^2, KD = {gains_text(args.kd)} 1/s"
        ),
        *([f"  {result.message}"] if result.status == "completed" else []),  # else a warning
        f"  {'tracking error':<18}" + "".join(f"{h:>14}" for h in ("x (m)", "y (m)", "phi (rad)")),
        row("max |error|", result.max_error),
        row("RMS error", result.rms_error),
        f"  controller step (inverse dynamics + control law, Python): median "
        f"{result.step_time_median * 1e6:.2f} us, 99th percentile "
        f"{result.step_time_p99 * 1e6:.2f} us",
        f"  peak |{effort}| ({unit}):  "
        + ", ".join(f"{leg} {v:.6g}" for leg, v in zip(LEGS, peak.tolist(), strict=True)),
        *files,
    ]
    return "\n".join(lines)
