"""``prp3 simulate``: complete inverse dynamics of a motion, written to ``DIR/results.csv``.

The command implements the data contract of ``docs/model.md``::

    prp3 simulate [--robot ROBOT.toml] (--motion vertical|rotation | --trajectory TRAJ.csv)
                  [--samples N] [--method fast|paper|newton-euler]
                  [--engine auto|numba|numpy] --output DIR
                  [--format csv|parquet] [--plots] [--animate] [--frames N]
                  [--html FILE.html]

``--engine auto`` (the default) runs the fast route on numba only for runs
long enough to repay its start-up (:mod:`prp3.cli._engine`).

``--format parquet`` writes ``DIR/results.parquet`` (the same columns, float64)
instead of ``DIR/results.csv``.  Everything is computed before anything is written; the output files are
written into a staging folder inside ``DIR`` and moved in place together only
when all of them are complete, so a failed run leaves no output behind (and
no older output changed).  A summary of the run goes to stdout; warnings, the
progress bar (only on a terminal, once a run has lasted a second) and errors
go to stderr.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any, TextIO

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.inverse_dynamics import METHODS
from prp3.apps.runs import (
    RunSummary,
    check_memory,
    simulate_table,
    summarize,
    summary_text,
)
from prp3.cli._engine import add_engine_option, run_engine
from prp3.cli._progress import Progress
from prp3.cli._types import (
    add_output_directory,
    add_robot_option,
    emit,
    files_report,
    integer_at_least,
    load_robot_or_spatial,
    output_folder,
    path_name,
)
from prp3.errors import Prp3Error
from prp3.family import FamilyRobot
from prp3.files import check_inputs_kept, check_output_directory
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import parquet_available, write_table_csv, write_table_parquet
from prp3.io.trajectory import Trajectory, read_trajectory
from prp3.mechanics.implicit_friction import NEAR_LOCK_MU
from prp3.mechanics.kinematics import inverse_kinematics
from prp3.model.motion import PAPER_MOTIONS, Motion, paper_motion
from prp3.model.robot import Robot
from prp3.plotting.animation import MAX_FRAMES  # a constant: matplotlib is not imported
from prp3.spatial.motion import SPATIAL_MOTIONS
from prp3.staged_files import StagedOutput
from prp3.validation import LEGS

__all__ = [
    "DEFAULT_SAMPLES",
    "near_lock_note",
    "register",
    "run",
]  # the run table and summary are built by prp3.apps.runs; re-exported for callers

FloatArray = NDArray[np.float64]

#: Samples of the paper's motions when ``--samples`` is not given.
DEFAULT_SAMPLES: int = 301

#: Memory of a run per sample (bytes): the 46 columns of results.csv, the motion (10
#: columns) and the figures' copies; tracemalloc measured a peak of 1.3 kB per sample
#: at N = 8e4, chunk buffers included (those are BYTES_PER_RUN at large N).
BYTES_PER_SAMPLE: int = 8 * (46 + 10 + 46)

#: Memory of a run besides its samples (bytes): one chunk of intermediate results.
BYTES_PER_RUN: int = 200 * 1024**2

#: File formats of the results (``--format``) and the file each writes.
FORMATS: tuple[str, ...] = ("csv", "parquet")

#: Name of the animation file written by ``--animate``.
ANIMATION_NAME: str = "mechanism.gif"

EXAMPLES = """\
examples:
  prp3 simulate --motion vertical --output out --plots
      the paper's Figs. 3-5: out/results.csv, out/fig3_p10.png, ...
  prp3 simulate --motion rotation --samples 601 --method newton-euler --output rot --animate
  prp3 simulate --robot examples/robot.toml --trajectory examples/trajectory.csv --output run
      TRAJ.csv: header t,x,y,phi[,dx,dy,dphi,ddx,ddy,ddphi] (SI units, rad); the files of
      examples/ are in the repository (docs/cli.md); the columns: docs/model.md

Exit status 0 on success, 2 on bad input (one line on stderr, nothing written).
"""


# ------------------------------------------------------------------ command line


def register(subparsers: Any) -> None:
    """Add the ``simulate`` subcommand."""
    parser = subparsers.add_parser(
        "simulate",
        help="inverse dynamics of a motion -> DIR/results.csv (+ figures, animation)",
        description=(
            "Compute the kinematics and complete inverse dynamics of the 3-PRP robot along a\n"
            "platform motion and write DIR/results.csv: columns t,x,y,phi, then for each leg\n"
            "A, B, C: lambda10, dlambda10, ddlambda10, lambda32, dlambda32, ddlambda32, f10,\n"
            "p10, f21y, f21z, n10, m10, n32, m32 (SI units, full precision). The meaning and\n"
            "sign of every column: docs/model.md; every option: docs/cli.md.\n"
            "A family-form ROBOT.toml (3-RPR, 3-RRR, ...: docs/family.md) writes its 64\n"
            "columns instead: t,x,y,phi, then per leg q1..q3 with rates, tau, p and every\n"
            "joint force fx{k},fy{k},m{k}."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(parser, "; `prp3 robot --template` prints one")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument(
        "--motion",
        choices=(*PAPER_MOTIONS, *SPATIAL_MOTIONS),
        help="one of the paper's motions (eq. 4, t = 0..3 s): vertical (Figs. 3-5) or "
        "rotation (Figs. 6-8); for a spatial robot file (docs/spatial.md §15): heave, "
        "circle or tilt about its home pose",
    )
    source.add_argument(
        "--trajectory",
        metavar="TRAJ.csv",
        type=path_name,
        help="platform motion file: header t,x,y,phi[,dx,dy,dphi,ddx,ddy,ddphi]; with "
        "positions only the derivatives come from a quintic spline (a warning says so)",
    )
    parser.add_argument(
        "--samples",
        metavar="N",
        type=integer_at_least(2),
        help=f"samples of --motion over 0..3 s (default {DEFAULT_SAMPLES})",
    )
    parser.add_argument(
        "--method",
        choices=METHODS,
        default=None,
        help="fast: the kernel's closed form of the paper's method (eqs. 10-25, default); "
        "paper: the paper's recursive 3x3 matrices as printed; "
        "newton-euler: the independent Newton-Euler solver (a spatial robot file runs it "
        "always: docs/spatial.md §8)",
    )
    add_engine_option(parser)
    add_output_directory(parser)
    _add_output_options(parser)
    parser.set_defaults(handler=run)


def _add_output_options(parser: argparse.ArgumentParser) -> None:
    """Add what a run writes besides its table: ``--format``, ``--plots``, ``--animate``,
    ``--frames`` and ``--html``."""
    parser.add_argument(
        "--format",
        choices=FORMATS,
        default="csv",
        help="file format of the results: csv (DIR/results.csv, the default) or parquet "
        "(DIR/results.parquet: the same columns as float64; needs pyarrow, the extra "
        "prp3[parquet])",
    )
    parser.add_argument(
        "--plots",
        action="store_true",
        help="also write PNG figures: p10, f21y, f21z (the paper's Figs. 3-5 or 6-8), "
        "f10 and lambda10 of legs A, B, C against time",
    )
    parser.add_argument(
        "--animate",
        action="store_true",
        help=f"also write {ANIMATION_NAME}, an animated GIF of the mechanism (a spatial robot: "
        "in 3-D with every joint's reaction force, docs/spatial.md §15)",
    )
    parser.add_argument(
        "--frames",
        metavar="N",
        type=integer_at_least(2),
        help=f"largest number of frames of the animation (default {MAX_FRAMES}); fewer when "
        "the motion has fewer samples or frames would last under 30 ms (real time; a warning "
        "says so; a spatial robot refuses more frames than samples); only with --animate",
    )
    parser.add_argument(
        "--html",
        metavar="FILE.html",
        type=path_name,
        help="also write one self-contained HTML file of the run: the robot with its force "
        "arrows, a scrubber, a play button and linked plots; opens offline (needs Bokeh, the "
        "extra prp3[explore]; docs/explore.md); a spatial robot: in 3-D with every joint's "
        "reaction force (plotly, the same extra; docs/spatial.md §22)",
    )


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 simulate`` with parsed ``args``; return the exit status."""
    stderr = sys.stderr
    progress = Progress(stderr)
    try:
        return _run(args, progress, stderr)
    finally:
        progress.close()


def _located(
    error: Prp3Error, motion: Motion, source: str, trajectory: Trajectory | None
) -> Prp3Error:
    """The same error, located at its source: the file line or ``--motion NAME``, and the time."""
    sample = error.sample
    time_ = float(motion.t[sample]) if sample is not None else None
    if trajectory is None:
        return error.located(origin=source, subject=None, time=time_)
    line = int(trajectory.lines[sample]) if sample is not None else None
    return error.located(file=trajectory.path, line=line, subject=None, time=time_)


def near_lock_note(samples: list[int], motion: Motion, trajectory: Trajectory | None) -> str:
    """The warning of ``prp3 simulate`` for samples near a friction lock (one line).

    Names the first three samples (file lines of a trajectory) with their
    times, the last one and the count.

    >>> from prp3.model.motion import paper_motion
    >>> print(near_lock_note([5, 6, 7, 8, 9], paper_motion("rotation", 11), None))
    ... # doctest: +NORMALIZE_WHITESPACE
    5 samples near a lock of the joint friction (mu coefficients 1.2 times larger would lock
    them; a second solution may lie close to the one reported, which is reached continuously
    from mu = 0): sample 5 (t = 1.5 s), sample 6 (t = 1.8 s), sample 7 (t = 2.1 s), ...,
    sample 9 (t = 2.7 s); see docs/loads_and_friction.md
    """

    def where(k: int) -> str:
        place = f"line {int(trajectory.lines[k])}" if trajectory is not None else f"sample {k}"
        return f"{place} (t = {float(motion.t[k]):.6g} s)"

    shown = [where(k) for k in samples[:3]]
    if len(samples) > 4:
        shown.append("...")
    if len(samples) > 3:
        shown.append(where(samples[-1]))
    count = f"{len(samples)} sample{'s' if len(samples) > 1 else ''}"
    return (
        f"{count} near a lock of the joint friction (mu coefficients {NEAR_LOCK_MU:g} times "
        f"larger would lock {'them' if len(samples) > 1 else 'it'}; a second solution may lie "
        "close to the one reported, which is reached continuously from mu = 0): "
        + ", ".join(shown)
        + "; see docs/loads_and_friction.md"
    )


def _fewer_frames(asked: int, motion: Motion, made: int) -> str:
    """Why the animation has ``made`` frames, fewer than ``--frames asked``.

    >>> from prp3.model.motion import paper_motion
    >>> print(_fewer_frames(301, paper_motion("vertical", 301), 101))
    ... # doctest: +NORMALIZE_WHITESPACE
    --frames 301: the animation has 101 frames: it plays the motion in real time (3 s) and
    shows a frame for 30 ms on average at least (a GIF counts hundredths of a second)
    """
    duration = float(motion.t[-1] - motion.t[0])
    if motion.samples < asked and made >= motion.samples:
        why = f"the motion has {motion.samples} samples"
    else:
        why = (
            f"it plays the motion in real time ({duration:.6g} s) and shows a frame for 30 ms on "
            "average at least (a GIF counts hundredths of a second)"
        )
    return f"--frames {asked}: the animation has {made} frames: {why}"


def _run(args: argparse.Namespace, progress: Progress, stderr: TextIO) -> int:
    output: Path = args.output
    if args.frames is not None and not args.animate:
        raise Prp3Error(
            f"--frames {args.frames} applies to the animation only: add --animate, or leave "
            "--frames out"
        )
    results_name = f"results.{args.format}"
    if args.format == "parquet" and not parquet_available():
        raise Prp3Error(
            "--format parquet needs pyarrow, which is not installed: "
            "pip install 'prp3[parquet]' (or pyarrow), or leave --format out for CSV"
        )
    html: Path | None = getattr(args, "html", None)
    check_output_directory(output)
    check_inputs_kept(output, (results_name,), (args.trajectory, args.robot))
    spatial_or_planar = load_robot_or_spatial(args)
    if isinstance(spatial_or_planar, SpatialRobotFile):  # docs/spatial.md §13
        from prp3.cli._spatial import run_spatial

        return run_spatial(args, spatial_or_planar, progress, stderr, DEFAULT_SAMPLES)
    if html is not None:
        from prp3.explorer.app import require_bokeh

        require_bokeh("--html")
    loaded = spatial_or_planar
    if args.method is None:
        args.method = "fast"
    if args.motion is not None and args.motion not in PAPER_MOTIONS:
        raise Prp3Error(
            f"--motion {args.motion} is a motion of the spatial robots (docs/spatial.md §15); "
            f"the planar robots take --motion {' | '.join(PAPER_MOTIONS)} or --trajectory"
        )
    family = isinstance(loaded, FamilyRobot)
    motion, heading, trajectory = _planar_motion(args, family)
    args.engine = run_engine(args.engine, motion.samples, "family" if family else "3-PRP")
    heading += (
        f", {motion.samples} samples over t = {float(motion.t[0]):g} .. "
        f"{float(motion.t[-1]):g} s, {args.method} method"
        + (f" ({args.engine} engine)" if args.method == "fast" else "")
    )

    source = str(args.trajectory) if trajectory is not None else f"--motion {args.motion}"
    if isinstance(loaded, FamilyRobot):  # a family-form robot file: docs/family.md
        from prp3.cli._family import run_family

        def note() -> None:
            if trajectory is not None and trajectory.note is not None:
                print(f"{args.program}: warning: {trajectory.note}", file=stderr)

        return run_family(
            args,
            loaded,
            motion,
            heading,
            located=lambda error: _located(error, motion, source, trajectory),
            progress=progress,
            note=note,
        )
    return _run_prp(args, loaded, motion, heading, trajectory, source, progress, stderr)


def _run_prp(
    args: argparse.Namespace,
    robot: Robot,
    motion: Motion,
    heading: str,
    trajectory: Trajectory | None,
    source: str,
    progress: Progress,
    stderr: TextIO,
) -> int:
    """``prp3 simulate`` of the 3-PRP along ``motion`` (``source`` names it in messages)."""
    output: Path = args.output
    results_name = f"results.{args.format}"
    html: Path | None = getattr(args, "html", None)
    near_lock: list[int] = []
    try:
        table = simulate_table(
            robot,
            motion,
            args.method,
            progress=progress.stage("computing"),
            near_lock=near_lock,
            engine=args.engine,
        )
    except Prp3Error as error:
        raise _located(error, motion, source, trajectory) from None
    if trajectory is not None and trajectory.note is not None:
        # only for a run that goes on: a refused trajectory gets its one error line
        print(f"{args.program}: warning: {trajectory.note}", file=stderr)
    if near_lock:
        print(
            f"{args.program}: warning: {near_lock_note(near_lock, motion, trajectory)}", file=stderr
        )
    summary = summarize(table, motion.velocity[:, 2])
    page = None
    if html is not None:  # built before anything is written: a failure leaves no file
        from prp3.explorer.html_file import run_html

        page = run_html(robot, table, heading.removeprefix("prp3 simulate: "))

    trajectory_file = str(trajectory.path) if trajectory is not None else None
    with output_folder(args, output) as staged:
        if args.format == "parquet":
            progress.update(results_name, 0, 1)
            write_table_parquet(staged.path(results_name), table)
        else:
            write_table_csv(staged.path(results_name), table, progress=progress.stage(results_name))
        _write_figures(args, staged, robot, table, motion, trajectory_file, progress, stderr)
        progress.close()
        # the summary goes out before the files are moved in: a failing standard
        # output then leaves the earlier results in place
        emit(summary_text(summary, heading, files_report(staged)))
    if html is not None and page is not None:
        from prp3.files import atomic_writer

        with atomic_writer(html) as stream:
            stream.write(page)
        emit(f"html file written: {html}")
    _force_warnings(args.program, robot, summary, stderr)
    return 0


def _planar_motion(args: argparse.Namespace, family: bool) -> tuple[Motion, str, Trajectory | None]:
    """The motion of ``prp3 simulate`` of a planar robot (``--trajectory`` or ``--motion``),
    the summary's heading and the trajectory file read (or ``None``)."""
    if args.trajectory is None:
        samples = args.samples or DEFAULT_SAMPLES
        check_memory(f"--samples {samples}", BYTES_PER_RUN + BYTES_PER_SAMPLE * samples)
        return (
            paper_motion(args.motion, samples),
            f"prp3 simulate: {args.motion} motion (paper eq. 4)",
            None,
        )
    if args.samples is not None:
        raise Prp3Error(
            "--samples applies to --motion only (a trajectory file has its own samples), "
            f"got --samples {args.samples} with --trajectory {args.trajectory}"
        )
    # a family robot refuses its own crossings as its legs follow the path
    trajectory = read_trajectory(args.trajectory, crossing=not family)
    return trajectory.motion, f"prp3 simulate: trajectory {trajectory.path}", trajectory


def _write_figures(
    args: argparse.Namespace,
    staged: StagedOutput,
    robot: Robot,
    table: dict[str, FloatArray],
    motion: Motion,
    trajectory_file: str | None,
    progress: Progress,
    stderr: TextIO,
) -> None:
    """The figures (``--plots``) and the animation (``--animate``) of a 3-PRP run."""
    frames: int = args.frames if args.frames is not None else MAX_FRAMES
    if args.plots:
        from prp3.plotting.figures import results_figures, save_figure

        figures = results_figures(table, motion=args.motion, source=trajectory_file)
        for done, (name, figure) in enumerate(figures.items(), start=1):
            save_figure(figure, staged.path(name))
            progress.update("figures", done, len(figures))
    if args.animate:
        from prp3.plotting.animation import frame_schedule, save_animation

        indices, durations = frame_schedule(motion.t, frames)
        if args.frames is not None and len(indices) < args.frames:
            print(f"{args.program}: warning: {_fewer_frames(args.frames, motion, len(indices))}",
                  file=stderr)  # fmt: skip
        shown = Motion(
            t=motion.t[indices],
            pose=motion.pose[indices],
            velocity=motion.velocity[indices],
            acceleration=motion.acceleration[indices],
        )
        title = (
            f"3-PRP robot: {args.motion} motion"
            if args.motion
            else f"3-PRP robot: {trajectory_file}"
        )
        save_animation(
            robot,
            inverse_kinematics(robot, shown),
            staged.path(ANIMATION_NAME),
            max_frames=frames,
            durations=durations,
            title=title,
            progress=progress.stage("animation"),
        )


def _force_warnings(program: str, robot: Robot, summary: RunSummary, stderr: TextIO) -> None:
    """A warning for each leg whose peak ``|f10|`` is above the robot's ``limits.max_force``."""
    limit = robot.limits.max_force
    if limit is not None:
        for j, leg in enumerate(LEGS):
            if summary.peak_f10[j] > limit:
                print(
                    f"{program}: warning: |f10_{leg}| reaches {summary.peak_f10[j]:.6g} N at "
                    f"t = {summary.peak_f10_time[j]:.6g} s, above limits.max_force = {limit:g} N",
                    file=stderr,
                )
