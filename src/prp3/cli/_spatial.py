"""``prp3 simulate`` for a spatial robot file (docs/spatial.md §13–§15).

The robot of a spatial robot file (:mod:`prp3.io.spatial_robot`), the motion of
``--trajectory`` (a spatial trajectory file, :mod:`prp3.io.spatial_trajectory`)
or of ``--motion heave|circle|tilt`` (:func:`prp3.spatial.motion.spatial_motion`),
completed for a robot of fewer than 6 DOF (:func:`prp3.spatial.kinematics.complete_motion`),
its inverse dynamics by the Newton–Euler route (every joint's wrench), and
``DIR/results.csv`` with the columns of docs/spatial.md §9, written atomically in
the staged output folder (all of the run's files or none); ``--plots`` adds
:func:`prp3.plotting.spatial.spatial_figures`, ``--animate`` the animated GIF of
:func:`prp3.plotting.spatial_animation.save_spatial_animation` (at most ``--frames``
frames, real time), ``--html FILE.html`` the 3-D explorer's page of the run
(:func:`prp3.explorer.spatial_page.spatial_run_html`, docs/spatial.md §22).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from prp3.apps.runs import check_memory
from prp3.cli._progress import Progress
from prp3.cli._types import emit, files_report, output_folder
from prp3.errors import Prp3Error, TrajectoryError
from prp3.files import atomic_writer
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.spatial_trajectory import SpatialTrajectory, read_spatial_trajectory
from prp3.io.tables import write_table_csv, write_table_parquet
from prp3.plotting.animation import MAX_FRAMES  # a constant: matplotlib is not imported
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import SPATIAL_MOTIONS, PlatformMotion, spatial_motion
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table
from prp3.staged_files import StagedOutput

__all__ = ["ANIMATION_NAME", "SPATIAL_BYTES_PER_RUN", "SPATIAL_BYTES_PER_SAMPLE", "run_spatial"]

#: The animation ``--animate`` writes (the name the planar robots' animation has).
ANIMATION_NAME: str = "mechanism.gif"

#: Memory of a spatial run per sample (bytes): results.csv's columns (229 for the hexapod),
#: the kinematics and the wrenches kept, and the figures' copies.
SPATIAL_BYTES_PER_SAMPLE: int = 8 * 2000

#: Memory of a spatial run besides its samples (bytes): one chunk of the Newton–Euler systems.
SPATIAL_BYTES_PER_RUN: int = 600 * 1024**2

#: How far (in units of the robot's scale, rad) the completed motion may move a given
#: component before the run says so.
_CHANGED = 1e-9


def _refuse_options(args: argparse.Namespace, robot: str) -> None:
    """The options of ``prp3 simulate`` that a spatial robot does not take, refused by name."""
    what = f"the {robot} of a spatial robot file"
    if args.method not in (None, "newton-euler"):
        raise Prp3Error(
            f"--method {args.method} applies to the planar robots; {what} runs the Newton-Euler "
            "route, which gives every joint's wrench (docs/spatial.md §8): leave --method out "
            "or give --method newton-euler"
        )
    if args.engine != "auto":
        raise Prp3Error(f"--engine {args.engine} applies to the planar robots, not to {what}")
    if args.motion is not None and args.motion not in SPATIAL_MOTIONS:
        raise Prp3Error(
            f"--motion {args.motion} is a motion of the 3-PRP (paper eq. 4); {what} takes "
            f"--motion {' | '.join(SPATIAL_MOTIONS)} (docs/spatial.md §15) or --trajectory"
        )
    if args.trajectory is not None and args.samples is not None:
        raise Prp3Error(
            "--samples applies to --motion only (a trajectory file has its own samples), "
            f"got --samples {args.samples} with --trajectory {args.trajectory}"
        )


def _located(
    error: Prp3Error, motion: PlatformMotion, source: str, trajectory: SpatialTrajectory | None
) -> Prp3Error:
    """The error at its source: the file's line of its sample, or ``--motion NAME``; its time."""
    sample = error.sample
    time_ = float(motion.t[sample]) if sample is not None and sample < len(motion) else None
    subject = None if error.subject == "spatial inverse dynamics" else error.subject  # the run's
    if trajectory is None:
        return error.located(origin=source, time=time_, subject=subject)
    line = int(trajectory.lines[sample]) if sample is not None and time_ is not None else None
    return error.located(file=trajectory.path, line=line, time=time_, subject=subject)


def _completed_note(
    robot_name: str,
    parasitic: tuple[str, ...],
    given: PlatformMotion,
    done: PlatformMotion,
    scale: float,
    trajectory: SpatialTrajectory | None,
) -> str | None:
    """A warning when completing the motion changed the given parasitic components."""
    if not parasitic or trajectory is None:  # a built-in motion is completed as documented
        return None
    change = max(
        float(np.abs(done.position - given.position).max()) / scale,
        float(np.abs(done.rotation - given.rotation).max()),
    )
    if change <= _CHANGED:
        return None
    k = int(
        np.argmax(
            np.abs(done.position - given.position).max(axis=1) / scale
            + np.abs(done.rotation - given.rotation).max(axis=(1, 2))
        )
    )
    where = f"line {int(trajectory.lines[k])}"
    return (
        f"the {robot_name} determines {', '.join(parasitic)} itself: the motion's pose and "
        "rates were completed so that every leg closes (docs/spatial.md §11), moving the "
        f"pose by up to {change:.3g} (of the scale, or of the rotation matrix) at {where} of "
        f"{trajectory.path}; "
        "results.csv gives the joint motion of the completed motion"
    )


def _check_frames(args: argparse.Namespace, samples: int, trajectory: str | None) -> None:
    """``--frames N`` beyond the motion's samples, refused (one frame a sample at most)."""
    if args.frames is not None and args.frames > samples:
        more = (
            f"a trajectory file of more samples than {trajectory}"
            if trajectory is not None
            else "more --samples"
        )
        raise Prp3Error(
            f"--frames {args.frames} is more than the motion's {samples} samples (one frame "
            f"a sample at most): give --frames {samples} or fewer, or {more}"
        )


def _fewer_frames(asked: int, t: np.ndarray, made: int) -> str:
    """Why the animation has ``made`` frames, fewer than ``--frames asked`` (real time).

    >>> print(_fewer_frames(301, np.linspace(0.0, 3.0, 301), 101))
    ... # doctest: +NORMALIZE_WHITESPACE
    --frames 301: the animation has 101 frames: it plays the motion in real time (3 s) and
    shows a frame for 30 ms on average at least (a GIF counts hundredths of a second)
    """
    return (
        f"--frames {asked}: the animation has {made} frames: it plays the motion in real time "
        f"({float(t[-1] - t[0]):.6g} s) and shows a frame for 30 ms on average at least (a GIF "
        "counts hundredths of a second)"
    )


def _summary(
    heading: str, table: dict[str, np.ndarray], legs: int, unit: str, files: list[str]
) -> str:
    t = table["t"]
    lines = [heading, f"peak |tau| ({unit}) and peak |power| (W) of each leg:"]
    for i in range(legs):
        tau = np.abs(table[f"tau_{i + 1}"])
        power = np.abs(table[f"power_{i + 1}"])
        k = int(np.argmax(tau))
        lines.append(
            f"  leg {i + 1}: |tau| {float(tau[k]):.6g} at t = {float(t[k]):.6g} s, "
            f"|power| {float(power.max()):.6g}"
        )
    return "\n".join([*lines, *files])


def run_spatial(
    args: argparse.Namespace,
    design: SpatialRobotFile,
    progress: Progress,
    stderr: TextIO,
    default_samples: int,
) -> int:
    """``prp3 simulate`` of a spatial robot file; return the exit status.

    ``default_samples``: the samples of ``--motion`` when ``--samples`` is not given.
    """
    robot = design.robot
    _refuse_options(args, robot.name)
    html: Path | None = getattr(args, "html", None)
    if html is not None:
        from prp3.explorer.spatial_page import require_plotly

        require_plotly("--html of a spatial robot (the 3-D explorer, docs/spatial.md §22)")
    output: Path = args.output  # --format parquet without pyarrow: refused by prp3 simulate
    given, source, heading, trajectory = _given_motion(args, design, default_samples)
    check_memory(
        f"{len(given)} samples", SPATIAL_BYTES_PER_RUN + SPATIAL_BYTES_PER_SAMPLE * len(given)
    )
    _check_frames(args, len(given), str(trajectory.path) if trajectory is not None else None)
    heading += (
        f", {len(given)} samples over t = {float(given.t[0]):g} .. {float(given.t[-1]):g} s, "
        "Newton-Euler route"
    )
    progress.update("computing", 0, 1)
    try:
        motion = complete_motion(robot, given)
        with np.errstate(all="ignore"):  # an overflow is refused below, naming the sample
            solution = spatial_inverse_dynamics(robot, motion, "newton-euler")
    except Prp3Error as error:
        raise _located(error, given, source, trajectory) from None
    table = spatial_results_table(solution)
    overflow = _overflow(table)
    if overflow is not None:
        raise _located(overflow, given, source, trajectory)
    progress.update("computing", 1, 1)
    if trajectory is not None and trajectory.note is not None:
        print(f"{args.program}: warning: {trajectory.note}", file=stderr)
    note = _completed_note(robot.name, robot.parasitic, given, motion, robot.scale, trajectory)
    if note is not None:
        print(f"{args.program}: warning: {note}", file=stderr)
    leg = robot.legs[0]
    unit = "N" if leg.joints[leg.actuated].kind == "P" else "N·m"
    results_name = f"results.{args.format}"
    what = f"trajectory {trajectory.path}" if trajectory is not None else f"{args.motion} motion"
    page = None
    if html is not None:  # built before anything is written: a failure leaves no file
        from prp3.explorer.spatial_page import spatial_run_html

        page = spatial_run_html(
            robot, table, f"{robot.name}: {what}", note=heading.removeprefix("prp3 simulate: ")
        )
    with output_folder(args, output) as staged:
        if args.format == "parquet":
            write_table_parquet(staged.path(results_name), table)
        else:
            write_table_csv(staged.path(results_name), table, progress=progress.stage(results_name))
        _write_figures(args, staged, robot, table, what, progress, stderr)
        progress.close()
        emit(_summary(heading, table, len(robot.legs), unit, files_report(staged)))
    if html is not None and page is not None:  # as the planar robots' page: after the folder
        with atomic_writer(html) as stream:
            stream.write(page)
        emit(f"html file written: {html}")
    return 0


def _given_motion(
    args: argparse.Namespace, design: SpatialRobotFile, default_samples: int
) -> tuple[PlatformMotion, str, str, SpatialTrajectory | None]:
    """The motion ``prp3 simulate`` is given (``--trajectory`` or ``--motion``), what names it
    in messages, the summary's heading and the trajectory file read (or ``None``)."""
    robot = design.robot
    if args.trajectory is not None:
        trajectory = read_spatial_trajectory(args.trajectory)
        heading = f"prp3 simulate: {robot.name} ({design.path}), trajectory {trajectory.path}"
        return trajectory.motion, str(trajectory.path), heading, trajectory
    samples = args.samples or default_samples
    check_memory(f"--samples {samples}", SPATIAL_BYTES_PER_RUN + SPATIAL_BYTES_PER_SAMPLE * samples)
    source = f"--motion {args.motion}"
    try:
        given = spatial_motion(robot, args.motion, samples)
    except Prp3Error as error:
        raise error.located(origin=source, subject=None) from None
    heading = (
        f"prp3 simulate: {robot.name} ({design.path}), {args.motion} motion "
        f"({SPATIAL_MOTIONS[args.motion]})"
    )
    return given, source, heading, None


def _overflow(table: dict[str, Any]) -> TrajectoryError | None:
    """The refusal of results that are not finite (naming the first column and sample)."""
    values = np.stack(list(table.values()), axis=1)
    bad = ~np.isfinite(values)
    if not bad.any():
        return None
    k, c = (int(v) for v in np.argwhere(bad)[0])
    name = list(table)[c]
    return TrajectoryError(
        f"the results overflow: {name} is not finite ({float(values[k, c])!r}); the "
        "motion's rates or the robot's parameters are out of range",
        sample=k,
        key=name,
    )


def _write_figures(
    args: argparse.Namespace,
    staged: StagedOutput,
    robot: SpatialRobot,
    table: dict[str, Any],
    what: str,
    progress: Progress,
    stderr: TextIO,
) -> None:
    """The figures (``--plots``) and the animation (``--animate``) of ``prp3 simulate``."""
    if args.plots:
        from prp3.plotting.figures import save_figure
        from prp3.plotting.spatial import spatial_figures

        figures = spatial_figures(table, robot, what=what)
        for done, (name, figure) in enumerate(figures.items(), start=1):
            save_figure(figure, staged.path(name))
            progress.update("figures", done, len(figures))
    if args.animate:
        from prp3.plotting.animation import frame_schedule
        from prp3.plotting.spatial_animation import save_spatial_animation

        frames = args.frames if args.frames is not None else MAX_FRAMES
        indices, _ = frame_schedule(table["t"], frames)
        if args.frames is not None and len(indices) < args.frames:
            note = _fewer_frames(args.frames, table["t"], len(indices))
            print(f"{args.program}: warning: {note}", file=stderr)
        save_spatial_animation(
            robot,
            table,
            staged.path(ANIMATION_NAME),
            max_frames=frames,
            title=f"{robot.name}: {what}",
            progress=progress.stage("animation"),
        )
