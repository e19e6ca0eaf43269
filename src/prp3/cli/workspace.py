"""``prp3 workspace``: reachable region, Jacobian conditioning and singular loci.

::

    prp3 workspace [--robot ROBOT.toml] [--phi VALUE] [--extent XMIN XMAX YMIN YMAX]
                   [--points N] [--orientations M] [--statics | --no-statics] --output DIR

writes ``DIR/workspace.csv`` (the grid at ``φ``), ``DIR/orientations.csv``
(the scan of ``φ``) and ``DIR/workspace.png`` (the map), and with the statics
map (``--statics``; by default when the robot has a ``[payload]``, a
``[load]`` or ``[limits] max_force``) ``DIR/statics.csv`` and
``DIR/statics.png``, together or not at all (:func:`prp3.staged_files.staged_output`).
The columns are documented in
``docs/forward_and_workspace.md`` and in ``--help``.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np

from prp3.analysis.reachability import orientation_range, reachable_region
from prp3.analysis.workspace import (
    OrientationScan,
    WorkspaceSlice,
    WorkspaceStatics,
    orientation_scan,
    workspace_slice,
    workspace_statics,
)
from prp3.apps.runs import check_memory
from prp3.cli._progress import progress_bar
from prp3.cli._types import (
    add_output_directory,
    add_robot_option,
    check_extent,
    emit,
    files_report,
    finite_float,
    integer_at_least,
    load_robot_or_spatial,
    output_folder,
)
from prp3.errors import ParameterError
from prp3.family import FamilyRobot
from prp3.files import check_output_directory
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.io.tables import write_table_csv
from prp3.model.robot import Robot
from prp3.pose_validation import POSE_BOUND, SINGULARITY_THRESHOLD
from prp3.spatial.workspace import DEFAULT_POINTS as SPATIAL_DEFAULT_POINTS
from prp3.spatial.workspace import MAX_POINTS as SPATIAL_MAX_POINTS

__all__ = [
    "DEFAULT_ORIENTATIONS",
    "DEFAULT_POINTS",
    "default_extent",
    "register",
    "run",
    "wants_statics",
]

#: Grid points per axis when ``--points`` is not given.
DEFAULT_POINTS: int = 201

#: Orientations of the φ-scan when ``--orientations`` is not given.
DEFAULT_ORIENTATIONS: int = 91

#: Memory per grid point (bytes) besides one byte per scanned orientation: the slice's
#: arrays and the 10 columns of workspace.csv.
BYTES_PER_POINT: int = 8 * 40

#: Memory per grid point of the statics map (bytes): the kernel's work arrays (eqs. 19-25
#: on a chunk of poses) and the 8 columns of statics.csv.
BYTES_PER_STATICS_POINT: int = 8 * 60

#: Memory of a run besides its grid (bytes).
BYTES_PER_RUN: int = 200 * 1024**2

#: Margin added around the reachable region by the default extent (fraction of its size).
EXTENT_MARGIN: float = 0.1

EXAMPLES = """\
examples:
  prp3 workspace --robot robot.toml --output ws
      robot.toml with [limits] stroke = [-0.05, 0.05]: the region at phi = 0, its
      conditioning, the reachable orientations; ws/workspace.png is the map
  prp3 workspace --phi 0.3 --extent -0.2 0.2 -0.2 0.2 --points 101 --output ws03
  prp3 robot --template --architecture 6-UPS > hexapod.toml
  prp3 workspace --robot hexapod.toml --plane rp --statics --output ws_hexapod
      a spatial robot file: the roll-pitch slice at the home height, with the
      efforts that hold the robot's own weight

output files:
  workspace.csv     one row per grid point (x, y) at phi: x, y, reachable (1/0),
                    lambda10_A, lambda10_B, lambda10_C (m), condition (condition number of
                    the Jacobian w.r.t. (x, y, l0*phi)), phi_min, phi_max (extreme reachable
                    scanned orientations at (x, y), nan if none), orientation_fraction
                    (share of the scanned orientations reachable at (x, y))
  orientations.csv  one row per scanned phi: phi, determinant (sin(phi - pi/3)), area
                    (exact reachable area, m^2, inf without stroke), grid_area (counted on
                    the grid), reachable_points, condition_min, condition_max (over the
                    reachable grid points, nan if none)
  workspace.png     the map at phi and the scan of phi
  statics.csv       with the statics map: one row per grid point (x, y) at phi: x, y,
                    reachable (1/0), f10_A, f10_B, f10_C (N: the actuator forces that hold
                    the platform at rest against gravity, the payload and the constant
                    [load]), f10_peak (max |f10| over the legs, N), held (1 when reachable
                    and f10_peak <= [limits] max_force, or reachable without max_force)
  statics.png       the map of f10_peak over the reachable points, the max_force contour
                    and the region where the robot cannot hold its load

The statics map is written with --statics, and by default when the robot has a
[payload], a [load] or [limits] max_force (--no-statics leaves it out).

The only singular configurations of this robot are the orientations phi = pi/3 mod pi,
at every (x, y): a slice at a regular phi has no singular point; --phi at a singular
orientation is refused.

A family-form ROBOT.toml (3-RPR, 3-RRR, ...: docs/family.md) writes workspace.csv
with the columns x, y, reachable, regular (every singularity measure on its home
side, |mu| >= 1e-4), mu_leg_A, mu_leg_B, mu_leg_C, mu_par (the signed measures of
the home branch), orientations.csv with phi, area, regular_area, min_mu_par (over
+-pi/2), and workspace.png (both measures as maps, their zero loci drawn); the
default window is +-2 [leg] scale.  Its statics map (--statics; by default with a
[payload] or a [load]) is statics.csv with x, y, regular, tau_A, tau_B, tau_C,
tau_peak (the actuator efforts at rest on the home branch, empty where not
regular) and statics.png.

A spatial robot file (6-UPS, 3-RPS, 3-RUU Delta: docs/spatial.md §17) takes
--plane xy|xz|yz|rp (the planes its free coordinates span; the first is the
default), --offset, --rpy ROLL PITCH YAW, --extent and --points (default 101)
instead of --phi, and writes workspace.csv with x, y, z, roll, pitch, yaw (the
pose, completed for fewer than 6 DOF), reachable, regular, reason, reason_leg,
mu_leg_<leg>, mu_par and workspace.png; with --statics, statics.csv with the pose,
regular, tau_<leg>, tau_peak (the efforts at rest) and statics.png.

Exit status 0 on success, 2 on bad input (one line on stderr, nothing written).
"""


def default_extent(robot: Robot, samples: int = 721) -> tuple[float, float, float, float]:
    """The grid window: the bounding box of every reachable ``(x, y)``, with a margin.

    With ``[limits] stroke`` the box covers the exact regions of
    ``samples`` orientations spread over :func:`~prp3.analysis.reachability.orientation_range`,
    enlarged by :data:`EXTENT_MARGIN` of its size; without a stroke the
    workspace is unbounded and the window is ``±l0`` in both directions.

    >>> from prp3.model.parameters import Limits
    >>> [round(v, 4) for v in default_extent(Robot())]
    [-0.3, 0.3, -0.3, 0.3]
    """
    if robot.limits.stroke is None:
        return (-robot.l0, robot.l0, -robot.l0, robot.l0)
    low, high = orientation_range(robot)
    points = []
    for phi in np.linspace(low, high, samples).tolist():
        if abs(math.sin(phi - math.pi / 3.0)) < SINGULARITY_THRESHOLD:
            continue
        region = reachable_region(robot, phi)
        if len(region):
            points.append(region)
    xy = np.vstack(points)
    xmin, ymin = xy.min(axis=0).tolist()
    xmax, ymax = xy.max(axis=0).tolist()
    pad = EXTENT_MARGIN * max(xmax - xmin, ymax - ymin)
    return (xmin - pad, xmax + pad, ymin - pad, ymax + pad)


def register(subparsers: Any) -> None:
    """Add the ``workspace`` subcommand."""
    parser = subparsers.add_parser(
        "workspace",
        help="reachable region, Jacobian conditioning and singular loci -> CSV + PNG map",
        description=(
            "Map the workspace of the 3-PRP robot at one platform orientation phi: which\n"
            "(x, y) are reachable within the actuator strokes ([limits] stroke in ROBOT.toml),\n"
            "the condition number of the Jacobian there, and which orientations each point\n"
            "reaches (a scan of phi). See docs/forward_and_workspace.md."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(parser, ", no limits; give [limits] stroke for a bounded workspace")
    parser.add_argument(
        "--phi",
        metavar="VALUE",
        type=finite_float,
        default=None,
        help="platform orientation of the map (rad, default 0: the central orientation)",
    )
    parser.add_argument(
        "--extent",
        metavar=("XMIN", "XMAX", "YMIN", "YMAX"),
        type=finite_float,
        nargs=4,
        help="grid window (m); default: the bounding box of every reachable (x, y) over all "
        f"orientations plus {EXTENT_MARGIN * 100:g}%% of its size, or +-l0 without stroke limits",
    )
    parser.add_argument(
        "--points",
        metavar="N",
        type=integer_at_least(2, 100_000),
        default=None,
        help=f"grid points per axis (default {DEFAULT_POINTS}; a spatial robot: "
        f"{SPATIAL_DEFAULT_POINTS}, at most {SPATIAL_MAX_POINTS})",
    )
    parser.add_argument(
        "--orientations",
        metavar="M",
        type=integer_at_least(2, 100_000),
        default=None,
        help="orientations of the scan of phi, evenly over the reachable orientation range "
        f"(over -pi..pi without stroke limits; default {DEFAULT_ORIENTATIONS})",
    )
    parser.add_argument(
        "--statics",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="also write the statics map (statics.csv, statics.png): the actuator forces "
        "that hold the platform at rest at every grid point, against [limits] max_force; "
        "default: when the robot has a [payload], a [load] or [limits] max_force",
    )
    spatial = parser.add_argument_group(
        "a spatial robot file (6-UPS, 3-RPS, 3-RUU: docs/spatial.md §17)"
    )
    spatial.add_argument(
        "--plane",
        metavar="PLANE",
        help="the plane of the slice: xy, xz, yz (positions) or rp (roll and pitch); default xy, "
        "or rp for the 3-RPS (its x, y and yaw are parasitic)",
    )
    spatial.add_argument(
        "--offset",
        metavar="VALUE",
        type=finite_float,
        help="the plane's third coordinate (m: z of xy and rp, y of xz, x of yz); default: the "
        "home pose's",
    )
    spatial.add_argument(
        "--rpy",
        metavar=("ROLL", "PITCH", "YAW"),
        type=finite_float,
        nargs=3,
        help="the fixed orientation (rad, default 0 0 0; for --plane rp the yaw only)",
    )
    add_output_directory(parser)
    parser.set_defaults(handler=run)


def _grid_columns(x: np.ndarray, y: np.ndarray, reachable: np.ndarray) -> dict[str, np.ndarray]:
    """The columns ``x, y, reachable`` of a grid table, one row per grid point."""
    X, Y = np.meshgrid(x, y)
    return {
        "x": X.reshape(-1),
        "y": Y.reshape(-1),
        "reachable": reachable.reshape(-1).astype(np.float64),
    }


def _grid_table(ws: WorkspaceSlice, scan: OrientationScan) -> dict[str, np.ndarray]:
    table = _grid_columns(ws.x, ws.y, ws.reachable)
    for j, leg in enumerate("ABC"):
        table[f"lambda10_{leg}"] = ws.lambda10[..., j].reshape(-1)
    table["condition"] = ws.condition.reshape(-1)
    table["phi_min"] = scan.phi_min.reshape(-1)
    table["phi_max"] = scan.phi_max.reshape(-1)
    table["orientation_fraction"] = (scan.count / scan.phi.size).reshape(-1)
    return table


def _scan_table(scan: OrientationScan) -> dict[str, np.ndarray]:
    return {
        "phi": scan.phi,
        "determinant": np.sin(scan.phi - math.pi / 3.0),
        "area": scan.area,
        "grid_area": scan.grid_area,
        "reachable_points": scan.reachable.sum(axis=(1, 2)).astype(np.float64),
        "condition_min": scan.condition_min,
        "condition_max": scan.condition_max,
    }


def _statics_table(statics: WorkspaceStatics) -> dict[str, np.ndarray]:
    table = _grid_columns(statics.x, statics.y, statics.reachable)
    for j, leg in enumerate("ABC"):
        table[f"f10_{leg}"] = statics.f10[..., j].reshape(-1)
    table["f10_peak"] = statics.peak.reshape(-1)
    table["held"] = statics.held.reshape(-1).astype(np.float64)
    return table


def wants_statics(robot: Robot, option: bool | None) -> bool:
    """Whether ``prp3 workspace`` writes the statics map: ``--statics``/``--no-statics``, else
    when ``robot`` has an element that changes the forces at rest (a payload, a load, a
    spring: :meth:`prp3.model.element_base.Element.changes_statics`) or ``[limits] max_force``.

    >>> wants_statics(Robot(), None), wants_statics(Robot(), True)
    (False, True)
    >>> wants_statics(Robot.from_mapping({"spring": {"actuator": {"stiffness": 50.0}}}), None)
    True
    """
    if option is not None:
        return option
    statics = any(element.changes_statics(robot) for element in robot.elements)
    return statics or robot.limits.max_force is not None


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 workspace`` with parsed ``args``; return the exit status."""
    output: Path = args.output
    check_output_directory(output)
    robot = load_robot_or_spatial(args)
    if isinstance(robot, SpatialRobotFile):  # docs/spatial.md §17
        from prp3.cli._spatial_workspace import run_spatial_workspace

        return run_spatial_workspace(args, robot)
    _planar_options(args)
    if isinstance(robot, FamilyRobot):  # a family-form robot file: docs/family.md
        from prp3.cli._family_analysis import run_family_workspace

        return run_family_workspace(args, robot)
    try:
        orientation_range(robot)  # refuses a stroke beyond the bounds of the poses
    except ParameterError as error:
        if args.robot is None:
            raise
        raise error.located(file=args.robot) from None
    statics_wanted = wants_statics(robot, args.statics)
    x, y = _grid(args, robot, statics_wanted)
    ws = workspace_slice(robot, args.phi, x, y)  # refuses a singular phi
    if robot.limits.stroke is not None:
        low, high = orientation_range(robot)
    else:
        low, high = -math.pi, math.pi
    with progress_bar() as bar:  # one bar for the run: its delay counts from here
        orientations = np.linspace(low, high, args.orientations)
        scan = orientation_scan(robot, x, y, orientations, progress=bar.stage("orientations"))
        statics = None
        if statics_wanted:
            bar.update("statics", 0, 1)
            try:
                statics = workspace_statics(robot, ws.phi, x, y)
            except ParameterError as error:  # forces that overflow: laid to the robot file
                if args.robot is None:
                    raise
                raise error.located(file=args.robot) from None

        from prp3.plotting.workspace import save_statics_map, save_workspace_map

        with output_folder(args, output) as staged:
            for name, table in (
                ("workspace.csv", _grid_table(ws, scan)),
                ("orientations.csv", _scan_table(scan)),
            ):
                write_table_csv(staged.path(name), table, progress=bar.stage(name, "rows"))
            bar.update("workspace.png", 0, 1)
            save_workspace_map(staged.path("workspace.png"), robot, ws, scan)
            if statics is not None:
                write_table_csv(
                    staged.path("statics.csv"),
                    _statics_table(statics),
                    progress=bar.stage("statics.csv", "rows"),
                )
                bar.update("statics.png", 0, 1)
                save_statics_map(staged.path("statics.png"), robot, statics)
            bar.close()
            # printed before the files are moved in: a failing standard output keeps older
            # results
            emit(_summary(robot, ws, (low, high), files_report(staged), statics))
    return 0


def _planar_options(args: argparse.Namespace) -> None:
    """Refuse the options of a spatial robot file's slice (``--plane``, ``--offset``,
    ``--rpy``) and fill in the planar defaults of ``--phi``, ``--points``, ``--orientations``."""
    for option, given in (("--plane", args.plane), ("--offset", args.offset), ("--rpy", args.rpy)):
        if given is not None:
            raise ParameterError(
                f"{option} applies to a spatial robot file (docs/spatial.md §17); the planar "
                "robots' slice is given by --phi"
            )
    args.phi = 0.0 if args.phi is None else args.phi
    args.points = DEFAULT_POINTS if args.points is None else args.points
    args.orientations = DEFAULT_ORIENTATIONS if args.orientations is None else args.orientations


def _grid(
    args: argparse.Namespace, robot: Robot, statics_wanted: bool
) -> tuple[np.ndarray, np.ndarray]:
    """The grid values ``x``, ``y`` of ``--extent`` (within the bound of the poses; default:
    :func:`default_extent`) and ``--points``, the run's memory checked; a grid whose
    neighbouring values are equal is refused."""
    if args.extent is not None:
        xmin, xmax, ymin, ymax = check_extent(args.extent)
        reach = POSE_BOUND * robot.l0
        if max(abs(v) for v in args.extent) > reach:
            raise ParameterError(
                f"--extent {' '.join(repr(v) for v in args.extent)} reaches beyond "
                f"{POSE_BOUND:g}*l0 = {reach:g} m (l0 = {robot.l0:g} m), farther than prp3 "
                "computes poses: give a window within that bound"
            )
    else:
        xmin, xmax, ymin, ymax = default_extent(robot)
    points = args.points * args.points
    per_point = BYTES_PER_POINT + (BYTES_PER_STATICS_POINT if statics_wanted else 0)
    check_memory(
        f"--points {args.points} --orientations {args.orientations}",
        BYTES_PER_RUN + points * (per_point + args.orientations),
    )
    x = np.linspace(xmin, xmax, args.points)
    y = np.linspace(ymin, ymax, args.points)
    for axis, values in (("x", x), ("y", y)):
        if not (np.diff(values) > 0).all():
            window = " ".join(repr(v) for v in (xmin, xmax, ymin, ymax))
            what = "--extent" if args.extent is not None else "the default extent (stroke)"
            raise ParameterError(
                f"{what} {window} is too narrow in {axis} for --points {args.points}: "
                "neighbouring grid values are equal"
            )
    return x, y


def _statics_summary(statics: WorkspaceStatics) -> list[str]:
    held = statics.peak[statics.reachable]
    if not held.size:
        return ["  statics: no reachable grid point"]
    lines = [
        f"  statics (at rest): largest |f10| over the legs {held.min():.6g} .. "
        f"{held.max():.6g} N over the reachable points"
    ]
    fraction = statics.unheld_fraction
    if fraction is not None:
        lines.append(
            f"  above limits.max_force = {statics.max_force:g} N (cannot hold its load): "
            f"{100.0 * fraction:.4g} % of the reachable grid points"
        )
    return lines


def _summary(
    robot: Robot,
    ws: WorkspaceSlice,
    phi_range: tuple[float, float],
    files: list[str],
    statics: WorkspaceStatics | None = None,
) -> str:
    stroke = robot.limits.stroke
    lines = [
        f"prp3 workspace: phi = {ws.phi:.9g} rad, grid {ws.x.size} x {ws.y.size} over "
        f"x = {ws.x[0]:.6g} .. {ws.x[-1]:.6g} m, y = {ws.y[0]:.6g} .. {ws.y[-1]:.6g} m",
    ]
    if stroke is None:
        lines.append("  no stroke limits: every (x, y) is reachable at a regular phi")
    else:
        lines.append(
            f"  stroke [{stroke[0]:g}, {stroke[1]:g}] m: reachable area {ws.area:.6g} m^2 "
            f"(grid {ws.grid_area:.6g} m^2, {int(ws.reachable.sum())} of {ws.reachable.size} points)"
        )
        inside = phi_range[0] < math.pi / 3.0 < phi_range[1]
        lines.append(
            f"  reachable orientations: {phi_range[0]:.9g} .. {phi_range[1]:.9g} rad"
            + (" (split by the singular orientation pi/3)" if inside else "")
        )
    reached = ws.condition[ws.reachable]
    if reached.size:
        lines.append(
            f"  condition number over the reachable points: {reached.min():.6g} .. "
            f"{reached.max():.6g}"
        )
    lines.append(
        f"  singular points at this phi: none (|sin(phi - pi/3)| = {abs(ws.determinant):.6g}); "
        "singular orientations: phi = pi/3 mod pi"
    )
    if statics is not None:
        lines += _statics_summary(statics)
    lines += files
    return "\n".join(lines)
