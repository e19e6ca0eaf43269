"""``prp3 export``: write the robot in another program's format.

``prp3 export mjcf [--robot ROBOT.toml] [--output FILE]`` writes the robot as a
MuJoCo MJCF model (:func:`prp3.apps.mjcf.mjcf_model`) on standard output, or
atomically to ``FILE`` and then says on stdout what it wrote, as every command
does.  MuJoCo is not needed to export.

``prp3 export c --output DIR [--robot ROBOT.toml]`` writes the inverse
dynamics as C99 code, ``DIR/prp3_inverse_dynamics.h`` and ``.c``
(:func:`prp3.apps.codegen.c_inverse_dynamics`), together or not at all.

A spatial robot file (docs/spatial.md §13: 6-UPS, 3-RPS, 3-RUU) goes to
:func:`prp3.apps.spatial_mjcf.spatial_mjcf_model` (``export mjcf``; docs/spatial.md §16)
and :func:`prp3.apps.spatial_codegen.spatial_c_inverse_dynamics` (§24).
``prp3 export urdf --robot SPATIAL.toml --output FILE`` writes a spatial robot as the
URDF of its spanning tree (:func:`prp3.apps.spatial_urdf.spatial_urdf_model`) and its loop
closures beside it (``FILE`` with ``.yaml``, the Extended URDF of Gepetto's
example-parallel-robots; docs/spatial.md §25), both atomically.
A family-form robot file (docs/family.md: 3-RPR, 3-RRR, ...) goes to the
family's exporters, :func:`prp3.family.mjcf.family_mjcf_model` and
:func:`prp3.family.codegen.family_c_inverse_dynamics` (docs/family_export.md).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from prp3.apps.codegen import HEADER_NAME, SOURCE_NAME, CSource, c_inverse_dynamics
from prp3.apps.mjcf import mjcf_model
from prp3.apps.spatial_mjcf import spatial_mjcf_model
from prp3.apps.spatial_urdf import closures_path, spatial_urdf_closures, spatial_urdf_model
from prp3.cli._types import (
    add_output_directory,
    add_robot_option,
    emit,
    files_report,
    load_robot_or_spatial,
    output_folder,
    path_name,
)
from prp3.errors import InputFileError, ParameterError
from prp3.family import FamilyRobot
from prp3.family.codegen import FamilyCSource, family_c_inverse_dynamics
from prp3.family.mjcf import family_mjcf_model
from prp3.files import atomic_writer, check_inputs_kept, check_output_directory, read_text
from prp3.io.spatial_robot import SpatialRobotFile, key_line
from prp3.model.robot_toml import MAX_ROBOT_FILE_BYTES

if TYPE_CHECKING:
    from prp3.apps.spatial_codegen import SpatialCSource

__all__ = ["register"]

_MJCF_EXAMPLE = """\
examples:
  prp3 export mjcf > prp3.xml
  prp3 export mjcf --robot robot.toml --output prp3.xml
  python -c "import mujoco; m = mujoco.MjModel.from_xml_path('prp3.xml'); print(m.nq)"

The model: per leg i = A, B, C a slider lambda10_i (actuated by the motor
actuator_i, ctrl = f10_i in N), a hinge phi_i (angle = platform angle) and a
slider lambda32_i carrying one third of the platform; the welds weld_AB and
weld_AC close the loops. A [payload] is a body welded to the platform;
viscous and constant Coulomb [friction] are joint damping and frictionloss;
a [spring.actuator] is the lambda10_i sliders' stiffness, springref and damping.
The mu terms, tanh smoothing and a constant [load] are not in the model (a
warning names them; apply the load as xfrc_applied). See docs/mujoco.md.
A family-form ROBOT.toml (3-RPR, 3-RRR, ...: docs/family.md) gives per leg
the joints q1_i, q2_i, q3_i (qpos = the family's q), motors on the actuated
joint, welds weld_AB, weld_AC; see docs/family_export.md.
"""


_C_EXAMPLE = """\
examples:
  prp3 export c --output ccode
  prp3 export c --robot robot.toml --output ccode
  cc -std=c99 -O2 -c ccode/prp3_inverse_dynamics.c

int prp3_inverse_dynamics(const double pose[3], const double velocity[3],
                          const double acceleration[3],
                          double f10[3], double f21y[3], double f21z[3]);
returns 0; 1 for a non-finite input, 2 for a singular pose, 3 outside the
stroke (outputs NaN). See docs/control.md.
A family-form ROBOT.toml (docs/family.md) writes
int prp3_inverse_dynamics(pose, velocity, acceleration, double tau[3],
                          double joint[27]);
with 4 for a pose out of reach; see docs/family_export.md.
A spatial robot file (6-UPS, 3-RPS, 3-RUU: docs/spatial.md §13) writes
int prp3_inverse_dynamics(position, rotation, omega, velocity, alpha,
                          acceleration, q, dq, ddq, tau, force, moment);
every joint's wrench, codes 0-9 of the header; see docs/spatial.md §24.
"""


def register(subparsers: Any) -> None:
    """Add ``export`` and its format ``mjcf``."""
    parser = subparsers.add_parser(
        "export",
        help="write the robot as a model for another program (MuJoCo MJCF, C code)",
        description="Write the robot as a model for another program.",
        epilog="example: prp3 export mjcf --robot robot.toml --output prp3.xml",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    formats = parser.add_subparsers(dest="format", metavar="FORMAT")
    formats.required = True
    mjcf = formats.add_parser(
        "mjcf",
        help="MuJoCo MJCF model (XML): legs as chains, loops closed by welds, 3 motors",
        description=(
            "Write the robot as a MuJoCo MJCF model: the three legs as kinematic chains, "
            "the loops closed by weld equality constraints, motors on the three base "
            "sliders; a spatial robot file (6-UPS, 3-RPS, 3-RUU), its legs as open chains, the "
            "platform a free body, the loops closed by connect or weld constraints "
            "(docs/spatial.md §16). Exporting does not need MuJoCo."
        ),
        epilog=_MJCF_EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    mjcf.add_argument(
        "--robot",
        metavar="ROBOT.toml",
        type=path_name,
        help="robot parameters, planar or spatial (default: the paper's robot)",
    )
    mjcf.add_argument(
        "--output",
        "-o",
        metavar="FILE",
        type=path_name,
        help="write the model to FILE, whole or not at all (default: standard output)",
    )
    mjcf.set_defaults(handler=_export_mjcf)
    _register_urdf(formats)
    code = formats.add_parser(
        "c",
        help="the inverse dynamics as C99 code for an embedded controller (.h and .c)",
        description=(
            f"Write the robot's inverse dynamics as C99 code: DIR/{HEADER_NAME} and\n"
            f"DIR/{SOURCE_NAME}, generated from prp3's kernel with sympy (only <math.h>,\n"
            "the robot's parameters as constants)."
        ),
        epilog=_C_EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_robot_option(code)
    add_output_directory(code)
    code.set_defaults(handler=_export_c)


def _export_mjcf(args: argparse.Namespace) -> int:
    robot = load_robot_or_spatial(args)
    if isinstance(robot, SpatialRobotFile):
        try:
            text = spatial_mjcf_model(robot.robot)
        except ParameterError as error:
            raise _file_key(args.robot, error) from None
        closing = robot.robot.legs[0].joints[-1].kind
        closures = f"{len(robot.robot.legs)} {'connects' if closing == 'S' else 'welds'}"
        what = (
            f"the {robot.architecture} as {len(robot.robot.legs)} open chains and a free platform, "
            f"loops closed by {closures}, motors actuator_1..{len(robot.robot.legs)}"
        )
    elif isinstance(robot, FamilyRobot):
        try:
            text = family_mjcf_model(robot)
        except ParameterError as error:
            raise error.located(file=args.robot) from None
        what = (
            f"the {robot.architecture} (actuated joint {robot.actuated}) as 3 chains, loops closed "
            f"by 2 welds, motors actuator_A/B/C on q{robot.actuated}_A/B/C"
        )
    else:
        text = mjcf_model(robot)
        what = "3 legs as chains, loops closed by 2 welds, motors actuator_A/B/C on the sliders"
    output: Path | None = args.output
    if output is None:
        emit(text, end="")
        return 0
    source = f"the robot of {args.robot}" if args.robot is not None else "the paper's robot"
    with atomic_writer(output) as stream:  # an OSError is an OutputFileError naming the file
        stream.write(text)
        # said before the file is moved in: a failing standard output keeps an older file
        emit(
            f"{args.program}: MuJoCo MJCF model of {source} ({what}), {len(text.encode())} bytes\n"
            f"files written:\n  {output}"
        )
    return 0


def _register_urdf(formats: Any) -> None:
    urdf = formats.add_parser(
        "urdf",
        help="a spatial robot as URDF (its spanning tree) and its loop closures (YAML)",
        description=(
            "Write a spatial robot file (6-UPS, 3-RPS, 3-RUU) as the URDF of its spanning tree "
            "(the legs as open chains from the world, the platform floating, cut at each leg's "
            "closing joint) and, beside it with the suffix .yaml, its loop closures in the "
            "Extended URDF of Gepetto's example-parallel-robots (closed_loop, type, name_mot; "
            "docs/spatial.md §25)."
        ),
        epilog="example: prp3 export urdf --robot hexapod.toml --output hexapod.urdf",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    urdf.add_argument(
        "--robot", metavar="SPATIAL.toml", type=path_name, required=True,
        help="a spatial robot file (docs/spatial.md §13)",
    )  # fmt: skip
    urdf.add_argument(
        "--output", "-o", metavar="FILE", type=path_name, required=True,
        help="the URDF; its closures go to FILE with the suffix .yaml (both whole or not at all)",
    )  # fmt: skip
    urdf.set_defaults(handler=_export_urdf)


def _export_urdf(args: argparse.Namespace) -> int:
    robot = load_robot_or_spatial(args)
    if not isinstance(robot, SpatialRobotFile):
        raise InputFileError(
            "prp3 export urdf takes a spatial robot file (architecture = 6-UPS, 3-RPS or 3-RUU; "
            "docs/spatial.md §13)",
            file=args.robot,
        )
    try:
        text, closures = spatial_urdf_model(robot.robot), spatial_urdf_closures(robot.robot)
    except ParameterError as error:
        raise _file_key(args.robot, error) from None
    output: Path = args.output
    side = closures_path(output)
    if side == output:
        raise InputFileError(f"--output {output} ends in .yaml: its closures would overwrite it",
                             file=args.robot)  # fmt: skip
    legs = len(robot.robot.legs)
    first = robot.robot.legs[0]
    motor = first.coordinates[first.actuated_coordinate]
    kind = "3D (cut S)" if robot.robot.legs[0].joints[-1].kind == "S" else "6D (cut below the U)"
    with atomic_writer(side) as closing, atomic_writer(output) as stream:
        closing.write(closures)
        stream.write(text)
        closing.flush()  # a full disk refuses both here, before either file is moved in
        stream.flush()
        emit(
            f"{args.program}: URDF of the {robot.architecture} of {args.robot} ({legs} open chains "
            f"and a floating platform, {legs} closures {kind}, motors leg{{i}}_{motor}), "
            f"{len(text.encode())} bytes\nfiles written:\n  {output}\n  {side}"
        )
    return 0


#: The table of a spatial robot file of each body name (docs/spatial.md §13).
_BODY_TABLES = {"arm": "arm_body", "forearm": "forearm_body"}


def _file_key(path: Path, error: ParameterError) -> InputFileError:
    """A refusal of a spatial robot's body, naming the file, the body's table key and its line."""
    body, _, attribute = (error.key or "").partition(".")
    key = f"{_BODY_TABLES.get(body, body)}.{attribute}" if attribute else None
    line = None
    if key is not None:
        line = key_line(read_text(path, "robot", MAX_ROBOT_FILE_BYTES), key)
    return InputFileError(error.reason, file=path, line=line, key=key)


def _export_c(args: argparse.Namespace) -> int:
    output: Path = args.output
    check_output_directory(output)
    check_inputs_kept(output, (HEADER_NAME, SOURCE_NAME), (args.robot,))
    robot = load_robot_or_spatial(args)
    code: CSource | FamilyCSource | SpatialCSource
    if isinstance(robot, SpatialRobotFile):
        from prp3.apps.spatial_codegen import spatial_c_inverse_dynamics  # numba: on use

        code = spatial_c_inverse_dynamics(robot.robot)
        legs, dof = len(robot.robot.legs), robot.robot.legs[0].dof
        what = (
            f"(the {robot.architecture}; prp3_inverse_dynamics: position, rotation, omega, velocity, "
            f"alpha, acceleration -> q, dq, ddq[{legs * dof}], tau[{legs}], force, "
            f"moment[{legs * 9}]; returns 0, or a code of the header: 1 non-finite, 2 singular, "
            "4 out of reach, ...)"
        )
    elif isinstance(robot, FamilyRobot):
        code = family_c_inverse_dynamics(robot)
        what = (
            f"the {robot.architecture}, actuated joint {robot.actuated} (prp3_inverse_dynamics: "
            "pose, velocity, acceleration -> tau[3], joint[27]; returns 0, 1 non-finite, "
            "2 singular, 4 out of reach)"
        )
    else:
        code = c_inverse_dynamics(robot)
        what = (
            "(prp3_inverse_dynamics: pose, velocity, acceleration -> f10, f21y, f21z; returns 0, "
            "1 non-finite, 2 singular, 3 outside the stroke)"
        )
    source = f"the robot of {args.robot}" if args.robot is not None else "the paper's robot"
    with output_folder(args, output) as staged:
        staged.path(HEADER_NAME).write_text(code.header, encoding="utf-8")
        staged.path(SOURCE_NAME).write_text(code.source, encoding="utf-8")
        emit(
            f"{args.program}: C99 inverse dynamics of {source} {what}\n"
            + "\n".join(files_report(staged))
        )
    return 0
