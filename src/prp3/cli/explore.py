"""``prp3 explore``: the robot and every joint force in the browser (a local Bokeh server).

::

    prp3 explore [--robot ROBOT.toml] [--results DIR] [--port 8765] [--host 127.0.0.1]
                 [--no-browser] [--export FILE.html]

Serves the explorer (``docs/explore.md``) on ``127.0.0.1`` unless ``--host``
says otherwise, until Ctrl-C (exit 130, one line).  The robot file and the
results folder are read, and a results folder checked against the robot,
before the server starts; a busy port is one line naming it and exit 2.
Nothing is written, except with ``--export FILE.html``: then one
self-contained HTML file of the run (``--results DIR``, else the paper's
vertical motion) is written and no server is started.  A spatial ``--robot`` file gets the
3-D explorer (docs/spatial.md §22, plotly): one page of the run of ``--results DIR`` (else the
robot's heave motion), served as it is by the standard library's HTTP server, or written by
``--export``; a spatial run folder with a planar robot (or none) is refused in one line.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from prp3.cli._types import (
    add_robot_option,
    emit,
    integer_at_least,
    load_robot_or_spatial,
    path_name,
)
from prp3.errors import Prp3Error
from prp3.family import FamilyRobot
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.model.robot import Robot

__all__ = ["register", "run"]

EXAMPLES = """\
examples:
  prp3 explore                                   # the paper's robot, http://127.0.0.1:8765/
  prp3 simulate --motion rotation --output rot && prp3 explore --results rot
  prp3 explore --results rot --export rot.html   # one HTML file of the run, opens offline
  prp3 explore --robot rrr.toml                  # a family-form robot file (docs/family.md)
  prp3 simulate --robot rrr.toml --output r && prp3 explore --robot rrr.toml --results r
  ssh -L 8765:127.0.0.1:8765 HOST 'prp3 explore --no-browser'   # on a remote machine
  prp3 simulate --robot hexapod.toml --motion tilt --output t && \
    prp3 explore --robot hexapod.toml --results t --export t.html   # a spatial run in 3-D

Exit status 2 on bad input (one line, before the server starts), 130 on Ctrl-C.
The model and the columns of a results folder: docs/model.md; the page: docs/explore.md;
a spatial robot's 3-D page (plotly): docs/spatial.md §22.
"""


def register(subparsers: Any) -> None:
    """Add the ``explore`` subcommand."""
    parser = subparsers.add_parser(
        "explore",
        help="the robot and every joint force in the browser (Bokeh server; --export: HTML)",
        description=(
            "Serve an interactive explorer of the 3-PRP robot: the robot to scale, every joint\n"
            "force as an arrow, sliders for the pose, velocity and acceleration of the platform,\n"
            "editable design parameters, the workspace statics map and, with --results, a run\n"
            "of `prp3 simulate` with a time scrubber. Forces come from prp3's kernel.\n"
            "A family-form --robot file (3-RRR, 3-PRR, ...: docs/family.md) gets its own\n"
            "legs, joint forces and singularity measures (prp3.family), and --results of\n"
            "its runs (`prp3 simulate --robot FILE --output DIR`).\n"
            "A spatial --robot file (docs/spatial.md) gets the 3-D explorer (plotly): the run of\n"
            "--results (else its heave motion) with every joint's reaction force, one page."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(parser, "; with --results: the robot of the run")
    parser.add_argument(
        "--results",
        metavar="DIR",
        type=path_name,
        help="a folder written by `prp3 simulate --output DIR` (results.csv or results.parquet)",
    )
    parser.add_argument(
        "--port",
        type=integer_at_least(1, 65535),
        default=8765,
        help="port to listen on (default 8765)",
    )
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default 127.0.0.1, this machine only)",
    )
    parser.add_argument(
        "--no-browser", action="store_true", help="do not open a browser, only print the address"
    )
    parser.add_argument(
        "--export",
        metavar="FILE.html",
        type=path_name,
        help="write one self-contained HTML file of the run (--results, else the paper's "
        "vertical motion) and exit; no server",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 explore`` with parsed ``args``; return the exit status."""
    from prp3.explorer.app import require_bokeh
    from prp3.explorer.html_file import write_run_html
    from prp3.explorer.server import serve

    loaded = load_robot_or_spatial(args)
    if isinstance(loaded, SpatialRobotFile):  # the 3-D explorer: docs/spatial.md §22
        return _run_spatial(args, loaded)
    if args.results is not None:
        from prp3.explorer.spatial_run import run_kind

        if run_kind(args.results) == "spatial":
            raise Prp3Error(
                f"{args.results} holds a spatial robot's run: give its spatial robot file, "
                f"prp3 explore --robot SPATIAL.toml --results {args.results} (docs/spatial.md §22)"
            )
    require_bokeh()
    from prp3.explorer.run_folder import read_run, run_motion

    robot = loaded
    if isinstance(robot, FamilyRobot):  # a family-form robot file: docs/family.md
        return _run_family(args, robot)
    results = read_run(args.results) if args.results is not None else None
    if results is not None:
        run_motion(robot, results)  # the run must be the robot's: refused before anything starts
    if args.export is not None:
        export: Path = args.export
        if results is not None:
            table, title = results.table, f"prp3 run {results.path}"
        else:
            table, title = _paper_run(robot), "prp3: the paper's vertical motion"
        write_run_html(export, robot, table, title)
        emit(f"{args.program}: wrote {export}")
        return 0

    def announce(url: str) -> None:
        emit(f"{args.program}: serving {url} (Ctrl-C stops)")

    serve(
        robot,
        results,
        host=args.host,
        port=args.port,
        open_browser=not args.no_browser,
        announce=announce,
    )
    return 0  # pragma: no cover - the server stops by a signal


def _run_family(args: argparse.Namespace, robot: FamilyRobot) -> int:
    """``prp3 explore`` of a family robot: its page (with ``--results``, of a run of
    ``prp3 simulate --robot``), or ``--export`` of that run or of the paper's vertical motion."""
    from prp3.explorer.html_file import write_run_html
    from prp3.explorer.run_folder import family_run_motion, read_family_run
    from prp3.explorer.server import serve

    results = read_family_run(args.results) if args.results is not None else None
    if results is not None:
        family_run_motion(robot, results)  # the run must be the robot's: refused before anything
    if args.export is not None:
        export: Path = args.export
        if results is not None:
            table, title = results.table, f"prp3 run {results.path} of the {robot.architecture}"
        else:
            from prp3.family import family_inverse_dynamics, family_results_table
            from prp3.model.motion import paper_motion

            solution = family_inverse_dynamics(robot, paper_motion("vertical", 301))
            table = family_results_table(solution)
            title = f"prp3: the paper's vertical motion of the {robot.architecture}"
        write_run_html(export, robot, table, title)
        emit(f"{args.program}: wrote {export}")
        return 0

    def announce(url: str) -> None:
        emit(f"{args.program}: serving {url} (Ctrl-C stops)")

    serve(robot, results, host=args.host, port=args.port, open_browser=not args.no_browser,
          announce=announce)  # fmt: skip
    return 0  # pragma: no cover - the server stops by a signal


def _run_spatial(args: argparse.Namespace, design: SpatialRobotFile) -> int:
    """``prp3 explore`` of a spatial robot file: the 3-D explorer's page (docs/spatial.md §22)
    of the run of ``--results`` (else of its heave motion), written by ``--export`` or served."""
    from prp3.explorer.spatial_page import require_plotly, spatial_run_html, write_spatial_run_html
    from prp3.explorer.spatial_run import read_spatial_run, serve_page

    require_plotly("prp3 explore of a spatial robot (the 3-D explorer, docs/spatial.md §22)")
    robot = design.robot
    if args.results is not None:
        run = read_spatial_run(args.results, robot)
        table, title = run.table, f"prp3 run {run.path} of the {robot.name}"
        note = f"{run.path}, robot {design.path}"
    else:
        from prp3.spatial.kinematics import complete_motion
        from prp3.spatial.motion import spatial_motion
        from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table

        motion = complete_motion(robot, spatial_motion(robot, "heave", 301))
        table = spatial_results_table(spatial_inverse_dynamics(robot, motion, "newton-euler"))
        title = f"prp3: the heave motion of the {robot.name}"
        note = f"the heave motion of docs/spatial.md §15, robot {design.path}"
    if args.export is not None:
        export: Path = args.export
        write_spatial_run_html(export, robot, table, title, note=note)
        emit(f"{args.program}: wrote {export}")
        return 0
    page = spatial_run_html(robot, table, title, note=note)

    def announce(url: str) -> None:
        emit(f"{args.program}: serving {url} (Ctrl-C stops)")

    serve_page(page, host=args.host, port=args.port, open_browser=not args.no_browser,
               announce=announce)  # fmt: skip
    return 0  # pragma: no cover - the server stops by a signal


def _paper_run(robot: Robot) -> dict[str, Any]:
    from prp3.apps.runs import simulate_table
    from prp3.model.motion import paper_motion

    return dict(simulate_table(robot, paper_motion("vertical", 301), "fast"))
