"""``prp3 control`` for a spatial robot file (docs/spatial.md §23).

The reference is a built-in motion (``--motion heave|circle|tilt``,
:func:`prp3.spatial.motion.spatial_motion` at each instant from its closed form),
completed for a robot of fewer than 6 DOF (:func:`prp3.spatial.kinematics.complete_motion`);
the law is computed torque (:func:`prp3.apps.spatial_control.spatial_track`) on the
prp3 plant or on MuJoCo running the robot's MJCF.  ``DIR/tracking.csv`` holds
:data:`SPATIAL_TRACKING_COLUMNS` then ``tau_1 .. tau_n``; ``--plots`` adds
``DIR/tracking.png``, written together in the staged output folder.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

import numpy as np

from prp3.apps.spatial_control import SpatialTracking, spatial_track
from prp3.cli._types import emit, files_report, output_folder
from prp3.errors import Prp3Error
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import write_table_csv
from prp3.model.motion import PAPER_DURATION
from prp3.plotting.control import TRACKING_FIGURE  # a constant: matplotlib is not imported
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import SPATIAL_MOTIONS, PlatformMotion, spatial_motion
from prp3.spatial.rotations import exp_rotation, log_rotation

__all__ = ["SPATIAL_TRACKING_COLUMNS", "run_spatial_control", "spatial_reference"]

#: The columns of a spatial robot's ``tracking.csv`` before the efforts ``tau_1 .. tau_n``:
#: the reference's and the plant's pose (position m, rotation vector ``log R`` rad) and the
#: pose error ``(log(R_ref·Rᵀ), p_ref − p)``.
SPATIAL_TRACKING_COLUMNS: tuple[str, ...] = (
    "t",
    "x_ref", "y_ref", "z_ref", "rx_ref", "ry_ref", "rz_ref",
    "x", "y", "z", "rx", "ry", "rz",
    "e_rx", "e_ry", "e_rz", "e_x", "e_y", "e_z",
)  # fmt: skip


def spatial_reference(
    robot: SpatialRobot, name: str, duration: float = PAPER_DURATION
) -> Callable[[float], PlatformMotion]:
    """The built-in motion ``name`` as a reference ``t -> PlatformMotion`` of one sample.

    Its closed form at ``t`` (:func:`~prp3.spatial.motion.spatial_motion` with
    ``times=[t]``), completed (§11) so that its parasitic components are the robot's.
    """
    spatial_motion(robot, name, 2, duration)  # refuses a motion the robot cannot drive

    def reference(t: float) -> PlatformMotion:
        return complete_motion(robot, spatial_motion(robot, name, duration=duration, times=[t]))

    return reference


def _initial(
    robot: SpatialRobot, start: PlatformMotion, error: tuple[float, ...] | None
) -> PlatformMotion | None:
    """The plant's initial state: ``start`` moved so that its pose error is ``error``."""
    if error is None:
        return None
    e = np.asarray(error, dtype=float)
    rotation = exp_rotation(-e[None, :3]) @ start.rotation
    moved = PlatformMotion.of(
        start.t, start.position - e[3:], rotation, start.omega, start.velocity,
        start.alpha, start.acceleration,
    )  # fmt: skip
    return complete_motion(robot, moved)


def _gain_text(value: float | tuple[float, ...]) -> str:
    """``400`` or ``(rx, ry, rz, x, y, z) = (100, 100, 100, 400, 400, 900)``."""
    if isinstance(value, tuple):
        return "(rx, ry, rz, x, y, z) = (" + ", ".join(f"{v:g}" for v in value) + ")"
    return f"{value:g}"


def _refuse_options(args: argparse.Namespace, robot: SpatialRobot) -> None:
    """The options of ``prp3 control`` a spatial robot does not take, refused by name."""
    what = f"the {robot.name} of a spatial robot file"
    if args.motion is None or args.motion not in SPATIAL_MOTIONS:
        given = f"--motion {args.motion}" if args.motion is not None else "--trajectory"
        raise Prp3Error(
            f"{given} applies to the planar robots; {what} takes --motion "
            f"{' | '.join(SPATIAL_MOTIONS)} (docs/spatial.md §23)"
        )
    if args.controller != "computed-torque":
        raise Prp3Error(
            f"--controller {args.controller} applies to the planar robots; {what} runs "
            "--controller computed-torque (docs/spatial.md §23)"
        )
    if args.model is not None:
        raise Prp3Error(f"--model applies to the planar robots, not to {what}")
    for name in ("kp", "kd"):
        value = getattr(args, name)
        if isinstance(value, tuple) and len(value) != 6:
            raise Prp3Error(
                f"--{name} of {what} is one gain for every component or six "
                f"{name.upper()}_RX,..,{name.upper()}_Z (docs/spatial.md §23), got "
                f"{len(value)} numbers (X,Y,PHI of a planar robot)"
            )


def tracking_table(run: SpatialTracking) -> dict[str, np.ndarray]:
    """The columns of a spatial robot's ``tracking.csv`` of ``run``."""
    columns = [
        run.t,
        *run.reference.position.T, *log_rotation(run.reference.rotation).T,
        *run.actual.position.T, *log_rotation(run.actual.rotation).T,
        *run.error.T,
    ]  # fmt: skip
    table = dict(zip(SPATIAL_TRACKING_COLUMNS, columns, strict=True))
    for leg in range(run.efforts.shape[1]):
        table[f"tau_{leg + 1}"] = run.efforts[:, leg]
    return table


def run_spatial_control(args: argparse.Namespace, design: SpatialRobotFile) -> int:
    """``prp3 control`` of a spatial robot file; return the exit status."""
    robot = design.robot
    _refuse_options(args, robot)
    output: Path = args.output
    source = f"--motion {args.motion}"
    duration = args.duration if args.duration is not None else PAPER_DURATION
    try:
        reference = spatial_reference(robot, args.motion, duration)
        initial = _initial(robot, reference(0.0), args.initial_error)
    except Prp3Error as error:
        raise error.located(origin=source, subject=None) from None
    samples = max(2, round(duration * args.rate) + 1)
    run = spatial_track(
        robot, reference, duration, kp=args.kp, kd=args.kd, initial=initial,
        samples=samples, plant=args.plant,
    )  # fmt: skip
    table = tracking_table(run)
    norm = {
        "rotation": np.linalg.norm(run.error[:, :3], axis=1),
        "position": np.linalg.norm(run.error[:, 3:], axis=1),
    }
    title = f"{robot.name}: computed torque, {args.plant} plant, {args.motion} motion"
    line = (
        f"prp3 control: {title} ({design.path}), {samples} samples over t = 0 .. "
        f"{duration:g} s, KP = {_gain_text(args.kp)} 1/s^2, KD = {_gain_text(args.kd)} 1/s: "
        "max |error| "
        f"{float(norm['rotation'].max()):.3g} rad, {float(norm['position'].max()):.3g} m; "
        f"final {float(norm['rotation'][-1]):.3g} rad, {float(norm['position'][-1]):.3g} m"
    )
    with output_folder(args, output) as staged:
        write_table_csv(staged.path("tracking.csv"), table)
        if args.plots:
            from prp3.plotting.control import spatial_tracking_figure
            from prp3.plotting.figures import save_figure

            apart = isinstance(args.kp, tuple) or isinstance(args.kd, tuple)  # a long line
            kp, kd = (
                ",".join(f"{v:g}" for v in g) if isinstance(g, tuple) else f"{g:g}"
                for g in (args.kp, args.kd)
            )
            per = " (rx, ry, rz, x, y, z)" if apart else ""
            gains = f"KP{per} = {kp} 1/s², KD = {kd} 1/s"
            subtitle = f"{SPATIAL_MOTIONS[args.motion]}{chr(10) if apart else '; '}{gains}"
            figure = spatial_tracking_figure(table, len(robot.legs), title=title, subtitle=subtitle)
            save_figure(figure, staged.path(TRACKING_FIGURE))
        emit("\n".join([line, *files_report(staged)]))
    return 0
