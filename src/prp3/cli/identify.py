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
The computation is :mod:`prp3.apps.identification`; this module only parses and prints.
"""

from __future__ import annotations

import argparse
import csv
import sys
from typing import Any

from prp3.apps.base_parameters import base_parameters
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
from prp3.cli._types import (
    add_output_directory,
    emit,
    files_report,
    load_robot,
    output_folder,
    path_name,
)
from prp3.errors import SingularPoseError, UnreachablePoseError
from prp3.files import atomic_writer, check_inputs_kept, check_output_directory
from prp3.io.measurements import read_measurements
from prp3.io.tables import format_float
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


def estimated_parameters(nominal: Robot, friction: str) -> tuple[str, ...]:
    """The parameters ``prp3 identify`` estimates.

    The inertial ones — the platform's first moment only when NOMINAL has a
    payload to carry it —, the friction coefficients of ``--friction`` and
    the regressor fields of NOMINAL's other elements (a ``[spring.actuator]``:
    its stiffness and damping).
    """
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
(SI units, rad, N; fx, fy, mz: a known wrench on the platform at G).
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
        "identified (default: the paper's robot)",
    )
    parser.add_argument(
        "--measurements",
        metavar="M.csv",
        type=path_name,
        required=True,
        help="the measured motion and actuator forces f10_A, f10_B, f10_C",
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
    nominal = load_robot(args)
    data = read_measurements(args.measurements)
    trajectory = data.trajectory
    try:
        inverse_geometry(nominal, trajectory.motion.pose)
    except (SingularPoseError, UnreachablePoseError) as error:
        sample = error.sample
        line = int(trajectory.lines[sample]) if sample is not None else None
        when = float(trajectory.motion.t[sample]) if sample is not None else None
        raise error.located(file=trajectory.path, line=line, time=when, subject=None) from None
    estimated = estimated_parameters(nominal, args.friction)
    with progress_bar() as bar:
        result = identify(
            nominal, trajectory.motion, data.f10, estimated, where=str(args.measurements),
            progress=bar.stage("regressor", "samples"),
        )  # fmt: skip
    robot = identified_robot(nominal, result)
    if trajectory.note is not None:  # only for a run that goes on
        print(f"{args.program}: warning: {trajectory.note}", file=sys.stderr)
    from prp3.plotting.figures import save_figure
    from prp3.plotting.identification import identification_figure

    figure = identification_figure(
        result.t,
        result.measured,
        result.fitted,
        title="identification: measured and fitted actuator forces",
        subtitle=f"{args.measurements}: {result.t.size} samples, {result.base.count} base "
        f"parameters, residual RMS {', '.join(f'{v:.3g}' for v in result.residual_rms)} N",
    )
    with output_folder(args, args.output) as staged:
        with atomic_writer(staged.path(ROBOT_NAME)) as stream:
            stream.write(_robot_text(robot, args))
        _write_parameters(staged.path(PARAMETERS_NAME), result)
        save_figure(figure, staged.path(IDENTIFICATION_FIGURE))
        # printed before the files are moved in: a failing standard output keeps older results
        emit(_summary(result, robot, nominal, args, files_report(staged)))
    return 0


def _robot_text(robot: IdentifiedRobot, args: argparse.Namespace) -> str:
    solved = ", ".join(PARAMETER_SYMBOLS[name] for name in robot.solved)
    return (
        f"# identified by prp3 identify from {args.measurements}\n"
        f"# solved from the base parameters: {solved}; every other parameter is the\n"
        f"# nominal robot's ({args.robot or 'the paper robot'})\n" + robot.robot.to_toml()
    )


def _write_parameters(path: Any, result: Identification) -> None:
    with atomic_writer(path) as stream:
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow(("name", "combination", "estimate", "std"))
        for b in range(result.base.count):
            writer.writerow(
                (
                    result.base.names[b],
                    result.base.label(b),
                    format_float(float(result.estimate[b])),
                    format_float(float(result.std[b])),
                )
            )


def _summary(
    result: Identification,
    robot: IdentifiedRobot,
    nominal: Robot,
    args: argparse.Namespace,
    files: list[str],
) -> str:
    base = result.base
    width = max(len(label) for label in base.labels)
    lines = [
        f"prp3 identify: {args.measurements}, {result.t.size} samples, "
        f"{base.count} base parameters of f10 (weighted least squares, 2 passes)",
        f"  {'base parameter':<{width}}  {'estimate':>14}  {'std':>10}  unit",
    ]
    for b in range(base.count):
        unit = PARAMETER_UNITS[base.names[b]]
        lines.append(
            f"  {base.label(b):<{width}}  {result.estimate[b]:>14.6g}  {result.std[b]:>10.3g}  "
            f"{unit}"
        )
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
