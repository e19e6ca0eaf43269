"""``prp3 simulate`` for a family-form ``ROBOT.toml`` (docs/family.md): the 64 columns.

Called by :mod:`prp3.cli.simulate` when the robot file is in family form; the
motion, the options and the staged output are those of the 3-PRP run.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.cli._types import emit, files_report
from prp3.errors import Prp3Error
from prp3.family import FamilyRobot, family_inverse_dynamics, family_results_table
from prp3.io.tables import write_table_csv, write_table_parquet
from prp3.model.motion import Motion
from prp3.staged_files import staged_output
from prp3.validation import LEGS

__all__ = ["family_summary_text", "run_family"]

FloatArray = NDArray[np.float64]


def family_summary_text(
    table: Mapping[str, FloatArray], robot: FamilyRobot, heading: str, files: list[str]
) -> str:
    """Peaks and energies of a family run, per leg, then the ``files`` lines.

    >>> from prp3.family import FamilyRobot, family_inverse_dynamics, family_results_table
    >>> from prp3.model.motion import paper_motion
    >>> robot = FamilyRobot.default("3-RRR")
    >>> table = family_results_table(family_inverse_dynamics(robot, paper_motion("vertical", 31)))
    >>> print(family_summary_text(table, robot, "run", []).splitlines()[2])
      peak |tau| (N m)         7.55834       3.77351       4.15043
    """
    t = np.asarray(table["t"], dtype=np.float64)
    unit = "N" if robot.types[robot.actuated - 1] == "P" else "N m"

    def legs(name: str) -> FloatArray:
        return np.stack([np.asarray(table[f"{name}_{leg}"]) for leg in LEGS], -1)

    def row(label: str, values: FloatArray, extra: str = "") -> str:
        return f"  {label:<18}" + "".join(f"{v:>14.6g}" for v in values.tolist()) + extra

    energy = (
        np.sum(0.5 * (legs("p")[1:] + legs("p")[:-1]) * np.diff(t)[:, None], axis=0)
        if t.size > 1
        else np.zeros(3)
    )
    lines = [
        heading,
        f"  {'':<18}" + "".join(f"{'leg ' + leg:>14}" for leg in LEGS),
        row(f"peak |tau| ({unit})", np.abs(legs("tau")).max(axis=0)),
        row("peak |p| (W)", np.abs(legs("p")).max(axis=0)),
    ]
    for k in (1, 2, 3):
        magnitude = np.hypot(legs(f"fx{k}"), legs(f"fy{k}"))
        lines.append(row(f"peak |F{k}| (N)", magnitude.max(axis=0)))
    lines.append(row("energy (J)", energy, f"   total {float(energy.sum()):.6g} J"))
    return "\n".join([*lines, *files])


def run_family(
    args: argparse.Namespace,
    robot: FamilyRobot,
    motion: Motion,
    heading: str,
    *,
    located: Callable[[Prp3Error], Prp3Error],
    progress: Any,
    note: Callable[[], None],
) -> int:
    """Compute, write and summarise a family run; ``located`` places an error at its source."""
    try:
        solution = family_inverse_dynamics(robot, motion, args.method, args.engine)
    except Prp3Error as error:
        raise located(error) from None
    note()
    table = family_results_table(solution)
    results_name = f"results.{args.format}"
    html = getattr(args, "html", None)
    page = None
    if html is not None:  # built before anything is written: a failure leaves no file
        from prp3.explorer.html_file import run_html

        title = heading.removeprefix("prp3 simulate: ")
        page = run_html(robot, table, f"{robot.architecture}: {title}")
    with staged_output(args.output) as staged:
        if args.format == "parquet":
            write_table_parquet(staged.path(results_name), table)
        else:
            write_table_csv(staged.path(results_name), table, progress=progress.stage(results_name))
        if args.plots:
            from prp3.plotting.family import family_figures
            from prp3.plotting.figures import save_figure

            figures = family_figures(
                table,
                architecture=robot.architecture,
                actuated=robot.actuated,
                motion=args.motion,
                source=str(args.trajectory) if args.trajectory is not None else None,
            )
            for name, figure in figures.items():
                save_figure(figure, staged.path(name))
        if args.animate:  # the robot's own legs (prp3.plotting.family_animation)
            from prp3.plotting.animation import MAX_FRAMES
            from prp3.plotting.family_animation import save_family_animation

            save_family_animation(
                robot,
                solution.kinematics,
                staged.path("mechanism.gif"),
                max_frames=args.frames if args.frames is not None else MAX_FRAMES,
                progress=progress.stage("animation"),
            )
        progress.close()
        heading = heading.replace("prp3 simulate:", f"prp3 simulate: {robot.architecture}", 1)
        emit(family_summary_text(table, robot, heading, files_report(staged)))
    if html is not None and page is not None:
        from prp3.files import atomic_writer

        with atomic_writer(html) as stream:
            stream.write(page)
        emit(f"html file written: {html}")
    return 0
