"""``prp3 robot``: the robot parameters file ``ROBOT.toml``.

``prp3 robot --template`` prints a commented ``ROBOT.toml`` with every key,
its default (the paper's robot, see ``docs/model.md``) and its unit;
``prp3 robot --check ROBOT.toml`` validates a file and prints the parameters
it gives, defaults filled in.
"""

from __future__ import annotations

import argparse
from typing import Any

from prp3.cli._types import emit, path_name
from prp3.errors import Prp3Error
from prp3.family import ARCHITECTURES, FamilyRobot, family_template
from prp3.io.spatial_robot import (
    SPATIAL_ARCHITECTURES,
    SpatialRobotFile,
    read_any_robot,
    spatial_robot_text,
)
from prp3.model.robot import robot_template

__all__ = ["register", "run"]

EXAMPLES = """\
examples:
  prp3 robot --template > robot.toml      then edit robot.toml
  prp3 robot --check robot.toml           validate it, print the parameters it gives
  prp3 simulate --robot robot.toml --motion vertical --output out
  prp3 robot --template --architecture 3-RRR > rrr.toml   a family-form file (docs/family.md)
  prp3 robot --template --architecture 6-UPS > hexapod.toml   a spatial robot (docs/spatial.md)
  prp3 robot --check hexapod.toml         validate a spatial robot file too
"""


def register(subparsers: Any) -> None:
    """Add the ``robot`` subcommand."""
    parser = subparsers.add_parser(
        "robot",
        help="print a commented ROBOT.toml template, or check a ROBOT.toml",
        description=(
            "Robot parameters file ROBOT.toml (SI units). Every key is optional; omitted\n"
            "keys take the defaults: the paper's robot (docs/model.md states the model)."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument(
        "--template",
        action="store_true",
        help="print a commented ROBOT.toml with the defaults and their units",
    )
    action.add_argument(
        "--check",
        metavar="ROBOT.toml",
        type=path_name,
        help="validate ROBOT.toml and print the parameters it gives (defaults filled in)",
    )
    parser.add_argument(
        "--architecture",
        choices=(*ARCHITECTURES, *SPATIAL_ARCHITECTURES),
        help="with --template: a family-form ROBOT.toml of this architecture and its "
        "default design (docs/family.md), or a spatial robot file of the 6-UPS hexapod, "
        "the 3-RPS or the Delta as a 3-RUU (docs/spatial.md §13)",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 robot`` with parsed ``args``; return the exit status."""
    architecture = getattr(args, "architecture", None)
    if args.template:
        if architecture is None:
            emit(robot_template(), end="")
        elif architecture in SPATIAL_ARCHITECTURES:
            emit(spatial_robot_text(architecture), end="")
        else:
            emit(family_template(architecture), end="")
        return 0
    if architecture is not None:
        raise Prp3Error(
            f"--architecture {architecture} applies to --template only (a checked file "
            "names its own architecture)"
        )
    robot = read_any_robot(args.check)
    emit(f"# {args.check}: valid; the parameters it gives, defaults filled in:")
    if isinstance(robot, SpatialRobotFile):
        emit(spatial_robot_text(robot), end="")
    elif isinstance(robot, FamilyRobot):
        emit(family_template(robot), end="")
    else:
        emit(robot_template(robot), end="")
    return 0
