"""``prp3 identify`` and ``prp3 excite`` of a spatial robot file (docs/identification.md,
"Spatial robots"); the computation is :mod:`prp3.apps.spatial_identification`."""

from __future__ import annotations

import argparse
import csv
import sys
from collections.abc import Callable
from typing import Any

import numpy as np

from prp3.apps.identification import Identification
from prp3.apps.spatial_identification import (
    spatial_exciting_trajectory,
    spatial_identified_robot,
    spatial_identify,
    spatial_parameter_unit,
)
from prp3.cli._types import emit, files_report, output_folder
from prp3.errors import ParameterError, Prp3Error
from prp3.files import atomic_writer
from prp3.io.spatial_robot import SpatialRobotFile, spatial_robot_text
from prp3.io.spatial_trajectory import read_spatial_measurements
from prp3.io.tables import format_float, write_table_csv
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.rotations import matrix_quaternion

__all__ = [
    "SERIES_OPTIONS",
    "estimate_table",
    "run_spatial_excite",
    "run_spatial_identify",
    "series_options",
    "write_parameters",
]

#: The candidates ``prp3 excite`` tries for a spatial robot when ``--iterations`` is not given.
SPATIAL_CANDIDATES: int = 10


def _unit(design: SpatialRobotFile) -> str:
    leg = design.robot.legs[0]
    return "N" if leg.joints[leg.actuated].kind == "P" else "N m"


def run_spatial_identify(
    args: argparse.Namespace, design: SpatialRobotFile, robot_name: str, parameters_name: str
) -> int:
    """``prp3 identify`` of a spatial robot file; return the exit status."""
    robot = design.robot
    if args.friction != "none":
        raise ParameterError(
            f"--friction {args.friction}: the spatial robots have no friction model "
            "(docs/spatial.md); identify their inertial parameters with --friction none",
            key="friction",
        )
    data = read_spatial_measurements(args.measurements, len(robot.legs))
    trajectory = data.trajectory
    try:
        motion = complete_motion(robot, trajectory.motion)
        result = spatial_identify(robot, motion, data.tau, where=str(args.measurements))
    except Prp3Error as error:
        sample = error.sample
        line = int(trajectory.lines[sample]) if sample is not None else None
        when = float(trajectory.motion.t[sample]) if sample is not None else None
        located = error.located(file=trajectory.path, line=line, time=when)
        located.reason = error.reason.removeprefix(f"{args.measurements}: ")  # named once
        located.args = (str(located),)
        raise located from None
    try:
        identified: SpatialRobotFile | None = spatial_identified_robot(design, result)
        refusal = None
    except ParameterError as error:
        identified, refusal = None, error.reason
    if trajectory.note is not None:
        print(f"{args.program}: warning: {trajectory.note}", file=sys.stderr)
    with output_folder(args, args.output) as staged:
        if identified is not None:
            with atomic_writer(staged.path(robot_name)) as stream:
                stream.write(
                    f"# identified by prp3 identify from {args.measurements}: the bodies solved "
                    f"from the base parameters,\n# every other parameter {args.robot}'s\n"
                    + spatial_robot_text(identified)
                )
        write_parameters(staged.path(parameters_name), result)
        lines = _summary(result, design, args)
        if refusal is not None:
            lines.append(f"  {robot_name} not written: {refusal}")
        emit("\n".join(lines + files_report(staged)))
    return 0


def write_parameters(path: Any, result: Identification) -> None:
    """Write ``parameters.csv`` of ``prp3 identify``: ``name, combination, estimate, std``."""
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


def estimate_table(result: Identification, unit: Callable[[str], str]) -> list[str]:
    """The summary's table of the base parameters: a heading, then one line each (its
    combination, estimate, std and ``unit(name)`` of its leading standard parameter)."""
    base = result.base
    width = max(len(label) for label in base.labels)
    return [
        f"  {'base parameter':<{width}}  {'estimate':>14}  {'std':>10}  unit",
        *(
            f"  {base.label(b):<{width}}  {result.estimate[b]:>14.6g}  {result.std[b]:>10.3g}  "
            f"{unit(base.names[b])}"
            for b in range(base.count)
        ),
    ]


def _summary(
    result: Identification, design: SpatialRobotFile, args: argparse.Namespace
) -> list[str]:
    base, unit = result.base, _unit(design)
    lines = [
        f"prp3 identify: {design.robot.name}, {args.measurements}, {result.t.size} samples, "
        f"{base.count} base parameters of tau (shared by the legs; weighted least squares, "
        "2 passes)",
        *estimate_table(result, spatial_parameter_unit),
    ]
    lines += [
        f"  condition number of the base regressor: {result.condition:.4g}",
        f"  residual RMS per actuator ({unit}): "
        + ", ".join(f"{i + 1} {v:.4g}" for i, v in enumerate(result.residual_rms.tolist())),
        "  not identifiable from tau (kept at the nominal values): "
        + (", ".join(base.unidentifiable) or "none"),
    ]
    return lines


#: The options of ``prp3 excite`` that every robot's excitation takes as they are.
SERIES_OPTIONS: tuple[str, ...] = (
    "period", "harmonics", "reach", "rotation", "max_velocity", "max_force", "seed",
)  # fmt: skip


def series_options(args: argparse.Namespace) -> dict[str, Any]:
    """The options :data:`SERIES_OPTIONS` of ``prp3 excite``, by name."""
    return {name: getattr(args, name) for name in SERIES_OPTIONS}


def run_spatial_excite(args: argparse.Namespace, design: SpatialRobotFile, name: str) -> int:
    """``prp3 excite`` of a spatial robot file; return the exit status."""
    robot = design.robot
    candidates = args.iterations if args.iterations is not None else SPATIAL_CANDIDATES
    result = spatial_exciting_trajectory(
        robot, **series_options(args), samples=args.samples, candidates=candidates
    )
    m = result.motion
    q = matrix_quaternion(m.rotation)
    columns = {"t": m.t}
    for k, axis in enumerate("xyz"):
        columns[axis] = m.position[:, k]
    for k, label in enumerate(("qw", "qx", "qy", "qz")):
        columns[label] = q[:, k]
    for prefix, values in (
        ("w", m.omega),
        ("v", m.velocity),
        ("dw", m.alpha),
        ("a", m.acceleration),
    ):
        for k, axis in enumerate("xyz"):
            columns[prefix + axis] = values[:, k]
    leg = robot.legs[0]
    prismatic = leg.joints[leg.actuated].kind == "P"
    value, rate = ("m", "m/s") if prismatic else ("rad", "rad/s")
    with output_folder(args, args.output) as staged:
        write_table_csv(staged.path(name), {k: np.asarray(v) for k, v in columns.items()})
        lines = [
            f"prp3 excite: {robot.name}, Fourier series, {args.harmonics} harmonics, period "
            f"{args.period:g} s, best of {candidates} random series (seed {args.seed})",
            f"  condition number of the base regressor's unit columns of tau: {result.condition:.4g}",
            f"  limits: offsets from home |x|, |y|, |z| <= {args.reach:g} scale, roll, pitch, yaw "
            f"<= {args.rotation:g} rad (the driven components; the parasitic ones completed), "
            f"the joints' limits, |dq| <= {args.max_velocity:g} {rate}"
            + (f", |tau| <= {args.max_force:g} {_unit(design)}" if args.max_force else ""),
            f"  peaks (nominal robot): |q| {result.peak_q:.4g} {value}, |dq| "
            f"{result.peak_dq:.4g} {rate}, |tau| {result.peak_tau:.4g} {_unit(design)}",
            *files_report(staged),
        ]
        emit("\n".join(lines))
    return 0
