"""``prp3 identify``: the robot's dynamic parameters from measured actuator forces.

::

    prp3 identify --robot NOMINAL.toml --measurements M.csv --output DIR
                  [--friction none|viscous|coulomb|both]

``M.csv`` has the columns of a trajectory file (``t, x, y, phi`` and
optionally all of ``dx, dy, dphi, ddx, ddy, ddphi``; derivatives computed as
for a trajectory file when absent) and the measured ``f10_A, f10_B, f10_C``.
Writes, together (:func:`prp3.staged_files.staged_output`), ``DIR/robot.toml`` (the
nominal robot with physical parameters that reproduce the identified base
parameters), ``DIR/parameters.csv`` (``name, combination, estimate, std``) and
``DIR/identification.png`` (measured and fitted forces), and prints a summary.
A family-form NOMINAL.toml (docs/family.md) is identified from its actuator
efforts, the columns ``tau_A, tau_B, tau_C`` in place of ``f10_*`` (no
friction: ``--friction none`` only), and ``DIR/robot.toml`` is in family form.
A spatial robot file (docs/spatial.md §13) is identified from the columns of a
spatial trajectory file (§14) and ``tau_1 .. tau_n`` (:mod:`prp3.cli._spatial_identify`;
no figure).
The computation is :mod:`prp3.apps.identification`; this module only parses and prints.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from prp3.apps.base_parameters import base_parameters
from prp3.apps.family_regressor import (
    FAMILY_PARAMETER_SYMBOLS,
    FAMILY_PARAMETER_UNITS,
    FAMILY_PARAMETERS,
    family_standard_parameters,
)
from prp3.apps.identification import (
    FRICTION_MODELS,
    Identification,
    IdentifiedRobot,
    identified_robot,
    identify,
)
from prp3.apps.regressor import (
    FRICTION_PARAMETERS,
    PARAMETER_SYMBOLS,
    PARAMETER_UNITS,
    STANDARD_PARAMETERS,
    standard_parameters,
)
from prp3.cli._progress import progress_bar
from prp3.cli._spatial_identify import estimate_table, run_spatial_identify, write_parameters
from prp3.cli._types import (
    add_output_directory,
    emit,
    files_report,
    load_robot_or_spatial,
    output_folder,
    path_name,
)
from prp3.errors import (
    ParameterError,
    SingularPoseError,
    TrajectoryError,
    UnreachablePoseError,
)
from prp3.family.mechanics import family_kinematics
from prp3.family.model import FamilyRobot
from prp3.files import atomic_writer, check_inputs_kept, check_output_directory
from prp3.io.measurements import MEASURED_EFFORT_COLUMNS, read_measurements
from prp3.io.spatial_robot import SpatialRobotFile
from prp3.mechanics.geometry import inverse_geometry
from prp3.model.elements import FRICTIONS
from prp3.model.robot import Robot
from prp3.plotting.identification import IDENTIFICATION_FIGURE  # a constant: no matplotlib
from prp3.validation import LEGS

__all__ = ["FRICTION_CHOICES", "PARAMETERS_NAME", "ROBOT_NAME", "register", "run"]

#: Files ``prp3 identify`` writes.
ROBOT_NAME: str = "robot.toml"
PARAMETERS_NAME: str = "parameters.csv"

#: The friction models ``--friction`` offers.
FRICTION_CHOICES: tuple[str, ...] = tuple(FRICTION_MODELS)


def estimated_parameters(nominal: Robot | FamilyRobot, friction: str) -> tuple[str, ...]:
    """The parameters ``prp3 identify`` estimates.

    The inertial ones — the platform's first moment only when NOMINAL has a
    payload to carry it —, the friction coefficients of ``--friction`` and
    the regressor fields of NOMINAL's other elements (a ``[spring.actuator]``:
    its stiffness and damping).  A family robot: its inertial ones
    (:data:`~prp3.apps.family_regressor.FAMILY_PARAMETERS`), likewise.
    """
    if isinstance(nominal, FamilyRobot):
        return tuple(
            name
            for name in FAMILY_PARAMETERS
            if nominal.payload.mass > 0.0 or not name.startswith("platform_moment")
        )
    inertial = tuple(
        name
        for name in STANDARD_PARAMETERS
        if nominal.payload.mass > 0.0 or not name.startswith("platform_moment")
    )
    others = tuple(
        name for element in nominal.elements if element not in FRICTIONS
        for name in element.regressor
    )  # fmt: skip
    return inertial + FRICTION_MODELS[friction] + others


EXAMPLES = """\
examples:
  prp3 excite --robot nominal.toml --output excite
  (drive the robot along excite/trajectory.csv, record f10_A, f10_B, f10_C: m.csv)
  prp3 identify --robot nominal.toml --measurements m.csv --output ident
  prp3 simulate --robot ident/robot.toml --trajectory other.csv --output check

M.csv: header t,x,y,phi[,dx,dy,dphi,ddx,ddy,ddphi][,fx,fy,mz],f10_A,f10_B,f10_C
(SI units, rad, N; fx, fy, mz: a known wrench on the platform at G); of a
family-form NOMINAL.toml (docs/family.md): t,x,y,phi[,...],tau_A,tau_B,tau_C
(its actuator efforts, N or N m; no fx, fy, mz: its [load] is constant); of a
spatial robot file (docs/spatial.md): t,x,y,z, qw,qx,qy,qz or roll,pitch,yaw
[,wx,...,az],tau_1..tau_n (docs/identification.md, "Spatial robots").
Exit status 0 on success, 2 on bad input (one line on stderr, nothing written).
"""


def register(subparsers: Any) -> None:
    """Add the ``identify`` subcommand."""
    parser = subparsers.add_parser(
        "identify",
        help="dynamic parameters from measured actuator forces -> DIR/robot.toml",
        description=(
            "Identify the base dynamic parameters from a measured motion and its actuator\n"
            "forces by weighted least squares, and write a robot whose physical parameters\n"
            "reproduce them (docs/identification.md)."
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--robot",
        metavar="NOMINAL.toml",
        type=path_name,
        help="the nominal robot: geometry, gravity, the parameters that cannot be "
        "identified (default: the paper's robot; a family-form file: docs/family.md)",
    )
    parser.add_argument(
        "--measurements",
        metavar="M.csv",
        type=path_name,
        required=True,
        help="the measured motion and actuator efforts (f10_A, f10_B, f10_C of the 3-PRP; "
        "tau_A, tau_B, tau_C of a family robot; tau_1 .. tau_n of a spatial robot)",
    )
    add_output_directory(parser)
    parser.add_argument(
        "--friction",
        choices=FRICTION_CHOICES,
        default="none",
        help="friction coefficients identified with the inertial parameters: viscous "
        "(b_a, b_r, b_s), coulomb (c_a, c_r, c_s) or both (default none: NOMINAL's kept)",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Run ``prp3 identify`` with parsed ``args``; return the exit status."""
    check_output_directory(args.output)
    names = (ROBOT_NAME, PARAMETERS_NAME, IDENTIFICATION_FIGURE)
    check_inputs_kept(args.output, names, (args.robot, args.measurements))
    loaded = load_robot_or_spatial(args)
    if isinstance(loaded, SpatialRobotFile):
        return run_spatial_identify(args, loaded, ROBOT_NAME, PARAMETERS_NAME)
    nominal = loaded
    family = isinstance(nominal, FamilyRobot)
    if family and args.friction != "none":
        raise ParameterError(
            f"--friction {args.friction}: a family robot has no friction model (docs/family.md "
            "§1); identify its inertial parameters with --friction none",
            key="friction",
        )
    if family:
        data = read_measurements(args.measurements, MEASURED_EFFORT_COLUMNS, crossing=False)
    else:
        data = read_measurements(args.measurements)
    trajectory = data.trajectory
    if isinstance(nominal, FamilyRobot) and trajectory.motion.load is not None:
        raise TrajectoryError(
            "the load columns fx, fy, mz belong to a model-form NOMINAL.toml (docs/model.md); "
            f"the {nominal.architecture}'s load is its constant [load] table",
            file=trajectory.path,
        )
    try:
        if isinstance(nominal, FamilyRobot):
            family_kinematics(nominal, trajectory.motion)
        else:
            inverse_geometry(nominal, trajectory.motion.pose)
    except (SingularPoseError, UnreachablePoseError) as error:
        sample = error.sample
        line = int(trajectory.lines[sample]) if sample is not None else None
        when = float(trajectory.motion.t[sample]) if sample is not None else None
        raise error.located(file=trajectory.path, line=line, time=when, subject=None) from None
    estimated = estimated_parameters(nominal, args.friction)
    with progress_bar() as bar:
        try:
            result = identify(
                nominal, trajectory.motion, data.f10, estimated, where=str(args.measurements),
                progress=bar.stage("regressor", "samples"),
            )  # fmt: skip
        except ParameterError as error:  # measured values too large: their line of the file
            if error.key != "measured" or error.sample is None:
                raise
            line = int(trajectory.lines[error.sample])
            when = float(trajectory.motion.t[error.sample])
            raise error.located(file=trajectory.path, line=line, time=when) from None
    robot = identified_robot(nominal, result)
    if trajectory.note is not None:  # only for a run that goes on
        print(f"{args.program}: warning: {trajectory.note}", file=sys.stderr)
    from prp3.plotting.figures import save_figure
    from prp3.plotting.identification import identification_figure

    figure = identification_figure(
        result.t,
        result.measured,
        result.fitted,
        title=f"identification: measured and fitted actuator {'efforts' if family else 'forces'}",
        subtitle=f"{args.measurements}: {result.t.size} samples, {result.base.count} base "
        f"parameters, residual RMS {', '.join(f'{v:.3g}' for v in result.residual_rms)} "
        f"{_effort_unit(nominal)}",
    )
    with output_folder(args, args.output) as staged:
        with atomic_writer(staged.path(ROBOT_NAME)) as stream:
            stream.write(_robot_text(robot, args))
        write_parameters(staged.path(PARAMETERS_NAME), result)
        save_figure(figure, staged.path(IDENTIFICATION_FIGURE))
        # printed before the files are moved in: a failing standard output keeps older results
        emit(_summary(result, robot, nominal, args, files_report(staged)))
    return 0


def _symbol(name: str) -> str:
    return FAMILY_PARAMETER_SYMBOLS.get(name) or PARAMETER_SYMBOLS[name]


def _effort_unit(robot: Robot | FamilyRobot) -> str:
    """``N`` of the 3-PRP's forces; a family robot's effort unit (``N m`` for an R joint)."""
    if isinstance(robot, FamilyRobot) and robot.types[robot.actuated - 1] == "R":
        return "N m"
    return "N"


def _robot_text(robot: IdentifiedRobot, args: argparse.Namespace) -> str:
    solved = ", ".join(_symbol(name) for name in robot.solved)
    return (
        f"# identified by prp3 identify from {args.measurements}\n"
        f"# solved from the base parameters: {solved}; every other parameter is the\n"
        f"# nominal robot's ({args.robot or 'the paper robot'})\n" + robot.robot.to_toml()
    )


def _summary(
    result: Identification,
    robot: IdentifiedRobot,
    nominal: Robot | FamilyRobot,
    args: argparse.Namespace,
    files: list[str],
) -> str:
    if isinstance(nominal, FamilyRobot):
        return _family_summary(result, robot, nominal, args, files)
    base = result.base
    lines = [
        f"prp3 identify: {args.measurements}, {result.t.size} samples, "
        f"{base.count} base parameters of f10 (weighted least squares, 2 passes)",
        *estimate_table(result, PARAMETER_UNITS.__getitem__),
    ]
    lines += [
        f"  condition number of the base regressor: {result.condition:.4g}",
        "  residual RMS per actuator (N): "
        + ", ".join(
            f"{leg} {v:.4g}" for leg, v in zip(LEGS, result.residual_rms.tolist(), strict=True)
        ),
        "  weights, first-pass residual std (N): "
        + ", ".join(f"{leg} {v:.4g}" for leg, v in zip(LEGS, result.sigma.tolist(), strict=True)),
        "  not identifiable from f10 (kept at the nominal values):",
    ]
    for name in base.unidentifiable:
        lines.append(f"    {PARAMETER_SYMBOLS[name]} ({name}): {base.reason(name)}")
    lines.append("    piston inertia: never enters (the piston only translates)")
    nominal_values = (
        dict(zip(result.fixed, standard_parameters(nominal, result.fixed).tolist(), strict=True))
        if result.fixed
        else {}
    )
    for name in result.fixed:
        if name.startswith("platform_moment"):
            why = (
                "not estimated: NOMINAL has no [payload] to carry a first moment of the "
                "platform (give one with its mass to identify its centre of mass)"
            )
        elif name in FRICTION_PARAMETERS:
            why = f"not estimated (--friction {args.friction}), {nominal_values[name]!r} kept"
        else:
            continue
        lines.append(f"    {PARAMETER_SYMBOLS[name]} ({name}): {why}")
    lines.append("  identifiable only in a combination:")
    for name in base.dependent():
        lines.append(f"    {PARAMETER_SYMBOLS[name]} ({name}): {base.reason(name)}")
    joint = base_parameters(nominal, ("f10", "f21y", "f21z"), base.parameters)
    lines.append(
        f"  with the joint forces f21y, f21z measured too: {joint.count} base parameters "
        f"({', '.join(joint.labels)})"
    )
    lines.append(
        "  robot.toml: solved "
        + ", ".join(
            f"{PARAMETER_SYMBOLS[name]} from {base.label(b)}" for b, name in enumerate(robot.solved)
        )
        + "; every other parameter is NOMINAL's"
    )
    for name in robot.clamped:
        why = (
            "estimated within 3 standard deviations of 0 (the nominal robot has no payload)"
            if name in ("platform_moment_x", "platform_moment_y")
            else "estimated below 0, within 3 standard deviations of 0"
        )
        lines.append(f"  {PARAMETER_SYMBOLS[name]} {why}: written as 0")
    lines += files
    return "\n".join(lines)


def _family_summary(
    result: Identification,
    robot: IdentifiedRobot,
    nominal: FamilyRobot,
    args: argparse.Namespace,
    files: list[str],
) -> str:
    """:func:`_summary` of a family robot: its efforts ``tau``, no friction, no joint forces."""
    base = result.base
    unit = _effort_unit(nominal)
    lines = [
        f"prp3 identify: {nominal.architecture} (actuated joint {nominal.actuated}), "
        f"{args.measurements}, {result.t.size} samples, {base.count} base parameters of tau "
        "(weighted least squares, 2 passes)",
        *estimate_table(result, FAMILY_PARAMETER_UNITS.__getitem__),
    ]
    lines += [
        f"  condition number of the base regressor: {result.condition:.4g}",
        f"  residual RMS per actuator ({unit}): "
        + ", ".join(
            f"{leg} {v:.4g}" for leg, v in zip(LEGS, result.residual_rms.tolist(), strict=True)
        ),
        f"  weights, first-pass residual std ({unit}): "
        + ", ".join(f"{leg} {v:.4g}" for leg, v in zip(LEGS, result.sigma.tolist(), strict=True)),
        "  not identifiable from tau (kept at the nominal values):",
    ]
    for name in base.unidentifiable:
        lines.append(f"    {_symbol(name)} ({name}): {base.reason(name)}")
    if result.fixed:
        nominal_values = family_standard_parameters(nominal, result.fixed).tolist()
        for name, value in zip(result.fixed, nominal_values, strict=True):
            lines.append(
                f"    {_symbol(name)} ({name}): not estimated: NOMINAL has no [payload] to carry "
                f"a first moment of the platform, {value!r} kept"
            )
    lines.append("  identifiable only in a combination:")
    for name in base.dependent():
        lines.append(f"    {_symbol(name)} ({name}): {base.reason(name)}")
    lines.append(
        "  robot.toml: solved "
        + ", ".join(f"{_symbol(name)} from {base.label(b)}" for b, name in enumerate(robot.solved))
        + "; every other parameter is NOMINAL's"
    )
    for name in robot.clamped:
        lines.append(
            f"  {_symbol(name)} estimated within 3 standard deviations of 0 (the nominal robot "
            "has no payload): written as 0"
        )
    lines += files
    return "\n".join(lines)
