"""The spatial robot file (docs/spatial.md §13): ``architecture`` and a default design's keys.

A spatial robot file is TOML: ``architecture = "6-UPS" | "3-RPS" | "3-RUU"``
(the names :attr:`prp3.spatial.model.SpatialRobot.name` gives: the hexapod of
§7, the 3-RPS of §11, the Delta of §12) and, every one optional, the
parameters of that architecture's constructor (:func:`~prp3.spatial.model.hexapod`,
:func:`~prp3.spatial.model.three_rps`, :func:`~prp3.spatial.model.delta`):
top-level numbers (lengths, angles, the stroke, gravity, the scale) and one
table per body (``mass``, ``centre``, ``inertia``).  Omitted keys take the
constructor's defaults; an omitted key of a body table takes that body's
default.  :func:`read_spatial_robot` reads a file, :func:`spatial_robot_from_mapping`
a mapping, :func:`spatial_robot_text` writes one back (``prp3 robot --check``
prints it, ``--template`` the defaults).  Every refusal is an
:class:`~prp3.errors.InputFileError` naming the file, the line of the key
(when the key is on a line of its own) and the key.

>>> design = spatial_robot_from_mapping({"architecture": "3-RPS", "home_height": 0.12})
>>> design.robot.name, design.robot.home_position, design.parameters["stroke"]
('3-RPS', (0.0, 0.0, 0.12), (0.06, 0.18))
>>> spatial_robot_from_mapping({"architecture": "6-UPS", "rod": {"mas": 1.0}})
Traceback (most recent call last):
...
prp3.errors.ParameterError: robot: unknown key 'rod.mas' (expected one of: centre, inertia, mass)
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from prp3.errors import InputFileError, ParameterError, Prp3Error
from prp3.family.model import ARCHITECTURES, FamilyRobot, read_robot_file
from prp3.files import read_text
from prp3.model.robot import Robot
from prp3.model.robot_toml import (
    MAX_ROBOT_FILE_BYTES,
    key_line,
    read_toml,
    toml_float,
    toml_line,
    toml_list,
    toml_table,
)
from prp3.spatial.model import (
    Body,
    Matrix,
    SpatialRobot,
    Vector,
    delta,
    hexapod,
    three_rps,
)
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.outputs import spatial_inverse_dynamics
from prp3.validation import check_file_path, check_scalar

__all__ = [
    "BODY_KEYS",
    "SPATIAL_ARCHITECTURES",
    "SpatialRobotFile",
    "is_spatial_mapping",
    "key_line",
    "read_any_robot",
    "read_spatial_mapping",
    "read_spatial_robot",
    "spatial_robot_from_mapping",
    "spatial_robot_text",
]

#: The constructor of each architecture a spatial robot file may name.
CONSTRUCTORS: dict[str, Callable[..., SpatialRobot]] = {
    "6-UPS": hexapod,
    "3-RPS": three_rps,
    "3-RUU": delta,
}

#: The architectures of a spatial robot file (docs/spatial.md §7, §11, §12).
SPATIAL_ARCHITECTURES: tuple[str, ...] = tuple(CONSTRUCTORS)

#: What each architecture is, for the file's comments.
_NOTES: dict[str, str] = {
    "6-UPS": "the Stewart-Gough hexapod of docs/spatial.md §7 (U base, P actuated, S platform)",
    "3-RPS": "the 3-RPS of docs/spatial.md §11 (R base, P actuated, S platform; 3 DOF)",
    "3-RUU": "the Delta as a 3-RUU of docs/spatial.md §12 (R actuated, forearm between two U)",
}

#: The kinds of top-level key: how each is checked and written.
#: ``length``: a positive number (m); ``angle``: a number (rad); ``limit``: a positive angle;
#: ``stroke``: two lengths ``[lower, upper]``, ``0 < lower < upper``; ``vector``: three numbers.
_KINDS = ("length", "angle", "limit", "stroke", "vector")

#: The top-level keys of each architecture: kind and comment, in the file's order.
_KEYS: dict[str, dict[str, tuple[str, str]]] = {
    "6-UPS": {
        "base_radius": ("length", "m, radius of the circle of the U centres"),
        "platform_radius": ("length", "m, radius of the circle of the S centres"),
        "base_half_angle": ("angle", "rad, legs 2k+1, 2k+2 start at 120 deg k -/+ this"),
        "platform_half_angle": ("angle", "rad, and end at 120 deg k -/+ this"),
        "home_height": ("length", "m, height of the platform origin at home (R = I)"),
        "stroke": ("stroke", "m, [lower, upper] of every P length"),
        "u_limit": ("limit", "rad, limit (+/-) of each U angle"),
        "s_limit": ("limit", "rad, limit of the S rotation angle"),
        "gravity": ("vector", "m/s^2, gravity in the world frame (z up)"),
        "scale": ("length", "m, the length scale of the singularity measures"),
    },
    "3-RPS": {
        "base_radius": ("length", "m, radius of the circle of the R centres"),
        "platform_radius": ("length", "m, radius of the circle of the S centres"),
        "home_height": ("length", "m, height of the platform origin at home (R = I)"),
        "stroke": ("stroke", "m, [lower, upper] of every P length"),
        "r_limit": ("limit", "rad, limit (+/-) of each R angle"),
        "s_limit": ("limit", "rad, limit of the S rotation angle"),
        "gravity": ("vector", "m/s^2, gravity in the world frame (z up)"),
        "scale": ("length", "m, the length scale of the singularity measures"),
    },
    "3-RUU": {
        "base_radius": ("length", "m, radius of the circle of the R centres"),
        "arm": ("length", "m, length of each arm (R to the first U)"),
        "forearm": ("length", "m, length of each forearm (first U to second U)"),
        "platform_radius": ("length", "m, radius of the circle of the second U centres"),
        "home_height": ("length", "m, the platform origin is at (0, 0, -home_height) at home"),
        "r_limit": ("limit", "rad, limit (+/-) of each R angle"),
        "u_limit": ("limit", "rad, limit (+/-) of each U angle"),
        "gravity": ("vector", "m/s^2, gravity in the world frame (z up)"),
        "scale": ("length", "m, the length scale of the singularity measures"),
    },
}

#: The body tables of each architecture (the constructor's keyword) and what each body is.
_BODIES: dict[str, dict[str, str]] = {
    "6-UPS": {
        "cylinder": "body 1 of every leg (between U and P), frame at the U centre",
        "rod": "body 2 of every leg (between P and S), frame at the S centre",
        "platform": "the platform, frame (p, R)",
    },
    "3-RPS": {
        "cylinder": "body 1 of every leg (between R and P), frame at the R centre",
        "rod": "body 2 of every leg (between P and S), frame at the S centre",
        "platform": "the platform, frame (p, R)",
    },
    "3-RUU": {
        "arm_body": "body 1 of every leg (between R and U), frame at the R centre",
        "forearm_body": "body 2 of every leg (between the two U), frame at the first U centre",
        "platform": "the platform, frame (p, R)",
    },
}

#: The keys of a body table.
BODY_KEYS: tuple[str, ...] = ("mass", "centre", "inertia")


@dataclass(frozen=True)
class SpatialRobotFile:
    """A spatial robot file read and checked.

    Attributes
    ----------
    architecture : str
        One of :data:`SPATIAL_ARCHITECTURES`.
    parameters : dict
        Every parameter of the architecture's constructor, defaults filled in: floats,
        ``stroke`` a pair, ``gravity`` three floats, each body a :class:`~prp3.spatial.model.Body`.
    robot : SpatialRobot
        The robot the constructor builds of them (its home pose checked reachable and regular).
    path : Path or None
        The file it was read from.
    """

    architecture: str
    parameters: dict[str, Any]
    robot: SpatialRobot
    path: Path | None = None


def is_spatial_mapping(data: Mapping[str, Any]) -> bool:
    """Whether a robot file's mapping is a spatial robot file (its ``architecture`` is spatial).

    >>> is_spatial_mapping({"architecture": "6-UPS"}), is_spatial_mapping({"architecture": "3-RRR"})
    (True, False)
    """
    return data.get("architecture") in SPATIAL_ARCHITECTURES


def _defaults(architecture: str) -> dict[str, Any]:
    """The constructor's defaults of the top-level keys (its signature)."""
    signature = inspect.signature(CONSTRUCTORS[architecture])
    return {name: signature.parameters[name].default for name in _KEYS[architecture]}


def _numbers(name: str, value: Any, count: int, unit: str) -> tuple[float, ...]:
    """``count`` finite numbers (a TOML array), each checked as :func:`check_scalar` checks."""
    if not isinstance(value, list | tuple) or len(value) != count:
        raise ParameterError(
            f"{name} must be an array of {count} numbers ({unit}), got {value!r}"[:200],
            subject="robot",
            key=name,
        )
    return tuple(check_scalar(f"{name}[{k}]", v, subject="robot") for k, v in enumerate(value))


def _vector(name: str, value: Any, unit: str) -> Vector:
    x, y, z = _numbers(name, value, 3, unit)
    return (x, y, z)


def _check_key(name: str, kind: str, value: Any) -> Any:
    subject = "robot"
    if kind == "vector":
        return _vector(name, value, "m/s^2")
    if kind == "stroke":
        low, high = _numbers(name, value, 2, "m: [lower, upper]")
        if not 0.0 < low < high:
            raise ParameterError(
                f"{name} must have 0 < lower < upper (m), got [{low!r}, {high!r}]",
                subject=subject,
                key=name,
            )
        return (low, high)
    unit = "rad" if kind in ("angle", "limit") else "m"
    return check_scalar(name, value, positive=kind != "angle", unit=unit, subject=subject)


def _matrix(name: str, value: Any) -> Matrix:
    if not isinstance(value, list | tuple) or len(value) != 3:
        raise ParameterError(
            f"{name} must be a 3 x 3 matrix [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]] "
            f"(kg m^2), got {value!r}"[:200],
            subject="robot",
            key=name,
        )
    a, b, c = (_vector(f"{name}[{k}]", row, "kg m^2") for k, row in enumerate(value))
    return (a, b, c)


def _body(name: str, value: Any, default: Body) -> Body:
    table = toml_table(name, value, BODY_KEYS)
    mass = default.mass
    if "mass" in table:
        mass = check_scalar(f"{name}.mass", table["mass"], non_negative=True, unit="kg")
    centre = default.centre
    if "centre" in table:
        centre = _vector(f"{name}.centre", table["centre"], "m")
    inertia = default.inertia
    if "inertia" in table:
        inertia = _matrix(f"{name}.inertia", table["inertia"])
    try:
        return Body(mass, centre, inertia, default.name)
    except ParameterError as error:  # the body's own checks (symmetry, principal moments)
        raise ParameterError(error.reason, subject="robot", key=f"{name}.{error.key}") from None


def _largest(given: dict[str, Any]) -> tuple[str, str]:
    """The key of the given number of the largest magnitude and ``key = value`` (to name in an
    overflow)."""
    leaves: list[tuple[str, float]] = []
    for name, value in given.items():
        if isinstance(value, Body):
            leaves.append((f"{name}.mass", value.mass))
            leaves += [(f"{name}.centre[{k}]", v) for k, v in enumerate(value.centre)]
            leaves += [
                (f"{name}.inertia[{i}][{j}]", v)
                for i, row in enumerate(value.inertia)
                for j, v in enumerate(row)
            ]
        elif isinstance(value, tuple):
            leaves += [(f"{name}[{k}]", v) for k, v in enumerate(value)]
        else:
            leaves.append((name, value))
    name, value = max(leaves, key=lambda leaf: abs(leaf[1]))
    return name, f"{name} = {value!r}"


def _build(
    constructor: Callable[..., SpatialRobot],
    given: dict[str, Any],
    tables: Mapping[str, str] | None = None,
) -> SpatialRobot:
    """``constructor(**given)``; a failure not of one key (an overflow) names the largest.

    ``tables`` maps a body's name to its table (``arm`` → ``arm_body``): a refusal of a
    body's key (``arm.mass``) is named by its table's key (``arm_body.mass``).
    """
    try:
        with np.errstate(all="ignore"):
            return constructor(**given)
    except ValueError as error:  # ParameterError, or math's domain error of an overflow
        if isinstance(error, ParameterError) and error.key in given:
            raise
        if isinstance(error, ParameterError) and error.key and tables:
            body, _, attribute = error.key.partition(".")
            if tables.get(body) in given:
                raise ParameterError(
                    error.reason.replace(f"{body}.", f"{tables[body]}.", 1),
                    subject="robot",
                    key=f"{tables[body]}.{attribute}",
                ) from None
        reason = error.reason if isinstance(error, Prp3Error) else str(error)
        key, shown = _largest(given) if given else (None, "")
        raise ParameterError(
            f"the parameters do not give a robot ({reason}): out of range together; the "
            f"largest is {shown}",
            subject="robot",
            key=key,
        ) from None


def spatial_robot_from_mapping(data: Mapping[str, Any]) -> SpatialRobotFile:
    """The robot of a spatial robot file's mapping (see the module's description).

    Raises
    ------
    ParameterError
        An unknown architecture or key, a wrong type, a non-finite or out-of-range
        number (naming the key: ``stroke``, ``rod.inertia``), parameters whose
        home pose is out of reach or singular, or whose effects overflow float64.
    """
    if not isinstance(data, Mapping):
        raise ParameterError(
            f"a spatial robot file is a table, got {data!r}"[:200], subject="robot"
        )
    architecture = data.get("architecture")
    if architecture not in CONSTRUCTORS:
        raise ParameterError(
            f"architecture must be one of {', '.join(SPATIAL_ARCHITECTURES)}, got {architecture!r}"[
                :200
            ],
            subject="robot",
            key="architecture",
        )
    keys, bodies = _KEYS[architecture], _BODIES[architecture]
    top = toml_table("", data, {"architecture", *keys, *bodies})
    given: dict[str, Any] = {
        name: _check_key(name, keys[name][0], top[name]) for name in keys if name in top
    }
    constructor = CONSTRUCTORS[architecture]
    shaped = _build(constructor, given)  # the geometry: the bodies' defaults may depend on it
    defaults = dict(zip(bodies, (*shaped.legs[0].bodies, shaped.platform), strict=True))
    for name in bodies:
        if name in top:
            given[name] = _body(name, top[name], defaults[name])
    robot = _build(constructor, given, {body.name: name for name, body in defaults.items()})
    home = PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    try:
        with np.errstate(all="ignore"):  # an overflow is refused below, naming the largest key
            solution = spatial_inverse_dynamics(robot, home)
    except Prp3Error as error:  # unreachable or singular at home
        raise ParameterError(
            f"the home pose {list(robot.home_position)!r} m is not a pose of this "
            f"design: {error.reason}",
            subject="robot",
        ) from None
    finite = all(
        np.isfinite(values).all()
        for values in (solution.tau, solution.force, solution.moment)
        if values is not None
    )
    if not finite:
        key, shown = _largest(given)
        raise ParameterError(
            "the parameters' effects overflow float64 (the home pose's joint wrenches are "
            f"not finite); the largest is {shown}",
            subject="robot",
            key=key,
        )
    parameters = {**_defaults(architecture), **defaults, **given}
    return SpatialRobotFile(architecture, parameters, robot)


def _located(path: Path, error: ParameterError) -> InputFileError:
    line = None
    if error.key:
        try:
            text = read_text(path, "robot", MAX_ROBOT_FILE_BYTES)
            line = key_line(text, error.key.split("[")[0])
        except InputFileError:
            line = None
    return InputFileError(error.reason, file=path, line=line, key=error.key)


def read_spatial_robot(path: str | Path) -> SpatialRobotFile:
    """Read a spatial robot file (TOML, bounded: :func:`prp3.model.robot_toml.read_toml`).

    Raises
    ------
    InputFileError
        An unreadable file or invalid TOML (file, line and column), and every refusal of
        :func:`spatial_robot_from_mapping`, naming the file, the key and its line.
    """
    path = check_file_path("path", path)
    data = read_toml(path, "robot")
    return read_spatial_mapping(path, data)


def read_any_robot(path: str | Path) -> Robot | FamilyRobot | SpatialRobotFile:
    """A robot file of any form: spatial (:func:`read_spatial_robot`), or the planar forms of
    :func:`prp3.family.read_robot_file` (docs/model.md, docs/family.md)."""
    path = check_file_path("path", path)
    data = read_toml(path, "robot")
    if is_spatial_mapping(data):
        return read_spatial_mapping(path, data)
    architecture = data.get("architecture", "3-PRP")
    if architecture not in ARCHITECTURES:
        raise InputFileError(
            f"architecture must be one of {', '.join(ARCHITECTURES)} (planar: docs/family.md) "
            f"or {', '.join(SPATIAL_ARCHITECTURES)} (spatial: docs/spatial.md), got "
            f"{architecture!r}"[:300],
            file=path,
            line=key_line(read_text(path, "robot", MAX_ROBOT_FILE_BYTES), "architecture"),
            key="architecture",
        )
    return read_robot_file(path)


def read_spatial_mapping(path: Path, data: Mapping[str, Any]) -> SpatialRobotFile:
    """:func:`spatial_robot_from_mapping` of the mapping ``data`` read from ``path``; its
    refusals as :class:`~prp3.errors.InputFileError` naming the file and the key's line."""
    try:
        design = spatial_robot_from_mapping(data)
    except ParameterError as error:
        raise _located(path, error) from None
    return SpatialRobotFile(design.architecture, design.parameters, design.robot, path)


def _body_lines(name: str, body: Body, note: str, comments: bool) -> list[str]:
    out = ["", f"[{name}]" + (f"  # {note}" if comments else "")]
    out.append(toml_line("mass", toml_float(body.mass), "kg", comments))
    out.append(
        toml_line("centre", toml_list(body.centre), "m, mass centre in the body's frame", comments)
    )
    rows = ", ".join(toml_list(row) for row in body.inertia)
    out.append(
        toml_line(
            "inertia", f"[{rows}]", "kg m^2, about the mass centre, in the body's frame", comments
        )
    )
    return out


def spatial_robot_text(design: SpatialRobotFile | str, *, comments: bool = True) -> str:
    """The text of a spatial robot file (an architecture's name: its defaults), read back to
    the same robot.

    >>> import tomllib
    >>> text = spatial_robot_text("3-RUU")
    >>> spatial_robot_from_mapping(tomllib.loads(text)).robot == delta()
    True
    """
    if isinstance(design, str):
        design = spatial_robot_from_mapping({"architecture": design})
    architecture, values = design.architecture, design.parameters
    out: list[str] = []
    if comments:
        out += [
            f"# prp3 spatial robot: {architecture}, {_NOTES[architecture]}.",
            "# SI units, angles in rad. Every key but architecture is optional; omitted keys",
            "# take the defaults shown here; an omitted key of a body table, that body's default.",
        ]
    out.append(
        toml_line("architecture", f'"{architecture}"', " | ".join(SPATIAL_ARCHITECTURES), comments)
    )
    for name, (kind, comment) in _KEYS[architecture].items():
        value = values[name]
        text = toml_list(tuple(value)) if kind in ("stroke", "vector") else toml_float(value)
        out.append(toml_line(name, text, comment, comments))
    for name, note in _BODIES[architecture].items():
        out += _body_lines(name, values[name], note, comments)
    return "\n".join(out) + "\n"
