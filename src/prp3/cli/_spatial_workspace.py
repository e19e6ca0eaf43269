"""``prp3 workspace`` for a spatial robot file (docs/spatial.md §17).

A slice of the platform's pose space (:func:`prp3.spatial.workspace.spatial_workspace`):
``DIR/workspace.csv`` (the pose, reachability and its reason, both singularity
measures at every grid point) and ``DIR/workspace.png`` (the reachability map and
both measures' maps), and with ``--statics`` ``DIR/statics.csv`` and
``DIR/statics.png`` (the actuator efforts holding the robot at rest), together or
not at all in the staged output folder.
"""

from __future__ import annotations

import argparse

import numpy as np

from prp3.apps.runs import check_memory
from prp3.cli._types import emit, files_report, output_folder
from prp3.errors import ParameterError, Prp3Error
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import write_table_csv
from prp3.spatial.workspace import (
    DEFAULT_POINTS,
    MAX_POINTS,
    SPATIAL_PLANES,
    WORKSPACE_REASONS,
    SpatialWorkspace,
    spatial_statics_table,
    spatial_workspace,
    spatial_workspace_table,
)

__all__ = ["SPATIAL_BYTES_PER_POINT", "run_spatial_workspace"]

#: Memory per grid point (bytes): the slice's arrays (pose, reasons, measures, efforts),
#: the chunk's share and the columns of the two tables.
SPATIAL_BYTES_PER_POINT: int = 8 * 120

#: Memory of a run besides its grid (bytes): one chunk of the kinematics and the figures.
SPATIAL_BYTES_PER_RUN: int = 400 * 1024**2


def _refuse_options(args: argparse.Namespace, robot: str) -> None:
    """The options of the planar robots' ``prp3 workspace`` that a slice does not take."""
    for option, given in (("--phi", args.phi), ("--orientations", args.orientations)):
        if given is not None:
            raise Prp3Error(
                f"{option} applies to the planar robots, not to the {robot} of a spatial robot "
                "file: its slice is given by --plane, --offset and --rpy (docs/spatial.md §17)"
            )
    if args.plane is not None and args.plane not in SPATIAL_PLANES:
        raise Prp3Error(
            f"--plane {args.plane} is not a plane of a slice: give one of "
            f"{', '.join(SPATIAL_PLANES)} (docs/spatial.md §17)"
        )
    if args.points is not None and args.points > MAX_POINTS:
        raise Prp3Error(
            f"--points {args.points} is more than the {MAX_POINTS} grid points per axis of a "
            f"spatial robot's slice ({MAX_POINTS}² poses): give fewer"
        )


def run_spatial_workspace(args: argparse.Namespace, design: SpatialRobotFile) -> int:
    """``prp3 workspace`` of a spatial robot file; return the exit status."""
    robot = design.robot
    _refuse_options(args, robot.name)
    points = DEFAULT_POINTS if args.points is None else args.points
    statics = bool(args.statics)
    check_memory(f"--points {points}", SPATIAL_BYTES_PER_RUN + points**2 * SPATIAL_BYTES_PER_POINT)
    ws = spatial_workspace(
        robot, plane=args.plane, offset=args.offset, rpy=args.rpy, extent=args.extent,
        points=points, statics=statics,
    )  # fmt: skip
    tables = {"workspace.csv": spatial_workspace_table(ws)}
    if statics:
        tables["statics.csv"] = spatial_statics_table(ws)
    for name, table in tables.items():
        for column, values in table.items():
            bad = ~np.isfinite(values) & ~np.isnan(values)
            if bad.any():  # NaN marks what is not defined; an infinity is an overflow
                raise ParameterError(
                    f"{name}: {column} overflows ({float(values[bad][0])!r}) at a grid point: "
                    "the robot's parameters are out of range",
                    file=design.path,
                )
    from prp3.plotting.spatial_workspace import (
        save_spatial_statics_map,
        save_spatial_workspace_map,
    )

    with output_folder(args, args.output) as staged:
        for name, table in tables.items():
            write_table_csv(staged.path(name), table)
        save_spatial_workspace_map(staged.path("workspace.png"), ws)
        if statics:
            save_spatial_statics_map(staged.path("statics.png"), ws)
        emit(_summary(ws, design, files_report(staged)))
    return 0


def _summary(ws: SpatialWorkspace, design: SpatialRobotFile, files: list[str]) -> str:
    first, second, third = SPATIAL_PLANES[ws.plane]
    unit = "rad" if ws.plane == "rp" else "m"
    rpy = ", ".join(f"{v:.6g}" for v in ws.rpy)
    lines = [
        f"prp3 workspace: {ws.robot.name} ({design.path}), plane {ws.plane} at {third} = "
        f"{ws.offset:.6g} m, rpy = ({rpy}) rad, grid {ws.u.size} x {ws.v.size} over "
        f"{first} = {ws.u[0]:.6g} .. {ws.u[-1]:.6g} {unit}, {second} = {ws.v[0]:.6g} .. "
        f"{ws.v[-1]:.6g} {unit}",
    ]
    counts = np.bincount(ws.reason.reshape(-1), minlength=len(WORKSPACE_REASONS))
    lines.append(
        "  points: "
        + ", ".join(
            f"{name} {int(count)}" for name, count in zip(WORKSPACE_REASONS, counts, strict=True)
        )
        + f"; regular {int(ws.regular.sum())}"
    )
    lines.append(
        "  home measures: mu_leg " + ", ".join(f"{v:.6g}" for v in ws.home_leg)
        + f"; mu_par {ws.home_par:.6g}"
    )  # fmt: skip
    reached = ws.reachable
    if reached.any():
        signed = ws.mu_par[reached] * np.sign(ws.home_par)
        lines.append(
            f"  mu_par x its home sign over the reachable points: {signed.min():.6g} .. "
            f"{signed.max():.6g}"
        )
    peak = ws.peak
    if peak is not None:
        held = peak[np.isfinite(peak)]
        lines.append(
            f"  statics (at rest): largest |tau| over the legs {held.min():.6g} .. "
            f"{held.max():.6g} {ws.unit} over the regular points"
            if held.size
            else "  statics: no regular grid point"
        )
    return "\n".join([*lines, *files])
