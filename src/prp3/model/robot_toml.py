"""``ROBOT.toml``: read with bounds, its tables laid out, written back.

The file of the data contract (``docs/model.md``): every key optional, unknown
keys and wrong types refused naming the key, the file read with a bound on
its size and every TOML error named by file, line and column
(:func:`read_toml`, :func:`parse_located`); the keyword arguments of
:class:`prp3.model.robot.Robot` from its tables (:func:`robot_arguments`) and
the text of a robot's file (:func:`robot_text`, with or without the meaning
and unit of every key).  :meth:`prp3.model.robot.Robot.from_toml`,
:meth:`~prp3.model.robot.Robot.to_toml` and
:func:`prp3.model.robot.robot_template` are built on them; the family-form
files of :mod:`prp3.family.model` share the table reader and the writers.

>>> robot_arguments({"l0": 0.4, "load": {"moment": 1.0}})
{'l0': 0.4, 'load': Load(force=(0.0, 0.0), moment=1.0)}
>>> robot_arguments({"piston": {"mas": 1.0}})
Traceback (most recent call last):
...
prp3.errors.ParameterError: robot: unknown key 'piston.mas' (expected one of: com, inertia, mass)
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Callable, Collection, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from prp3.errors import InputFileError, ParameterError
from prp3.files import read_text
from prp3.model.parameters import (
    FRICTION_UNITS,
    SPRING_UNITS,
    Friction,
    JointFriction,
    Limits,
    LinkParameters,
    Load,
    Payload,
    PistonParameters,
    PlatformParameters,
    Spring,
    SpringParameters,
    check_pair,
)

if TYPE_CHECKING:
    from prp3.model.robot import Robot

__all__ = ["key_line", "parse_located", "read_toml", "robot_arguments", "robot_text"]


#: Largest robot file read (bytes).
MAX_ROBOT_FILE_BYTES: int = 1024 * 1024

#: Longest run of digits accepted in a robot file (Python's own limit of integer text).
MAX_TOML_DIGITS: int = 4300

#: The top-level keys and tables of a robot file.
_TOP_KEYS: set[str] = {
    "l0",
    "gravity",
    "piston",
    "link",
    "platform",
    "limits",
    "payload",
    "load",
    "friction",
    "spring",
}

#: Keys of each ``[friction.KIND]`` table.
_FRICTION_KEYS: dict[str, set[str]] = {
    "actuator": {"viscous", "coulomb", "mu", "smoothing"},
    "revolute": {"viscous", "coulomb", "mu", "pin_radius", "smoothing"},
    "sleeve": {"viscous", "coulomb", "mu", "smoothing"},
}

#: What each ``[friction.KIND]`` table's heading says of the joint.
_FRICTION_WHERE = {
    "actuator": "base guide on piston i, along e_i",
    "revolute": "piston i on link 2 at P_i (rate dphi)",
    "sleeve": "link 2 on the platform, along d_i",
}

#: Keys of each ``[spring.KIND]`` table.
_SPRING_KEYS: dict[str, set[str]] = {
    kind: {"stiffness", "rest", "damping"} for kind in ("actuator", "revolute", "sleeve")
}

#: What each ``[spring.KIND]`` table's heading says of the joint.
_SPRING_WHERE = {
    "actuator": "linear spring with damper on each lambda10_i",
    "revolute": "torsion spring with damper of piston i on link 2, on phi",
    "sleeve": "linear spring with damper on each lambda32_i",
}


def read_toml(path: Path, what: str) -> dict[str, Any]:
    """The mapping of a UTF-8 TOML file (a BOM allowed), read with a bound on its size.

    ``what`` names the kind of file in the messages (``"robot"``, ``"sweep"``);
    every failure is an :class:`~prp3.errors.InputFileError` naming the file
    (and the line and column where TOML gives them).
    """
    return _parse_toml(path, read_text(path, what, MAX_ROBOT_FILE_BYTES))


_Parsed = TypeVar("_Parsed")


def parse_located(
    path: Path, parse: Callable[[dict[str, Any]], _Parsed], data: dict[str, Any]
) -> _Parsed:
    """``parse(data)`` for the mapping ``data`` read from ``path``: a ParameterError names the file
    and, when its key is set on a line of the file (:func:`key_line`), that line."""
    try:
        return parse(data)
    except ParameterError as error:
        line = None
        if error.key:
            try:
                line = key_line(
                    read_text(path, "robot", MAX_ROBOT_FILE_BYTES), error.key.split("[")[0]
                )
            except InputFileError:
                line = None
        raise error.located(file=path, line=line) from None


#: A top-level key at the start of a line: ``name =`` (bare or quoted).
_LINE_KEY = re.compile(
    r"""\s*["']?([A-Za-z0-9_-]+)["']?\s*(?:\.\s*["']?([A-Za-z0-9_-]+)["']?\s*)?="""
)
_LINE_TABLE = re.compile(r"""\s*\[\s*["']?([A-Za-z0-9_-]+(?:\s*\.\s*[A-Za-z0-9_-]+)*)["']?\s*\]""")


def key_line(text: str, key: str) -> int | None:
    """The line (1-based) of ``text`` where the dotted ``key`` (``stroke``, ``rod.mass``) is set.

    Found for a key on a line of its own (``mass = 1.0`` under ``[rod]``, or
    ``rod.mass = 1.0``), a table's heading for the table's own key (``rod``),
    or the line of an inline table ``rod = {...}``; ``None`` otherwise.

    >>> key_line("architecture = '6-UPS'\\n[rod]\\nmass = -1\\n", "rod.mass")
    3
    >>> key_line("stroke = [1]\\n", "stroke"), key_line("x = 1\\n", "y")
    (1, None)
    >>> key_line("[spring.actuator]\\nstiffness = 1e308\\n", "spring.actuator.stiffness")
    2
    """
    parts = key.split(".")
    table: list[str] = []
    fallback: int | None = None
    for number, line in enumerate(text.splitlines(), 1):
        header = _LINE_TABLE.match(line)
        if header is not None:
            table = [part.strip() for part in header.group(1).split(".")]
            if parts == table:
                return number
            if len(parts) > len(table) and parts[: len(table)] == table and fallback is None:
                fallback = number
            continue
        found = _LINE_KEY.match(line)
        if found is None:
            continue
        spelled = [found.group(1)] + ([found.group(2)] if found.group(2) else [])
        path = table + spelled
        if path == parts:
            return number
        if path == parts[: len(path)] and fallback is None:
            fallback = number  # an inline table holding the key
    return fallback


def _parse_toml(path: Path, text: str) -> dict[str, Any]:
    """``tomllib.loads(text)``; every failure an InputFileError naming the file and line."""
    long_number = re.search(rf"\d{{{MAX_TOML_DIGITS + 1},}}", text)
    if long_number is not None:  # Python refuses > 4300 digits with a ValueError
        line = text.count("\n", 0, long_number.start()) + 1
        raise InputFileError(
            f"invalid TOML: a number with more than {MAX_TOML_DIGITS} digits", file=path, line=line
        )
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        message = str(error)  # tomllib of Python 3.11 to 3.13 gives the place in the text only
        where = re.search(r"\(at line (\d+), column (\d+)\)", message)
        if where is None:
            raise InputFileError(f"invalid TOML: {message}", file=path) from None
        reason = message[: where.start()].rstrip()
        if reason == "Cannot overwrite a value":
            reason = _overwritten(text, int(where.group(1))) or reason
        raise InputFileError(
            f"invalid TOML: {reason}",
            file=path,
            line=int(where.group(1)),
            column=int(where.group(2)),
        ) from None
    except RecursionError:  # arrays or inline tables nested thousands deep
        raise InputFileError(
            "invalid TOML: arrays or tables nested too deeply", file=path
        ) from None
    except ValueError as error:  # a number tomllib cannot convert
        raise InputFileError(f"invalid TOML: {error}", file=path) from None


#: One TOML key: bare, "basic" or 'literal'.
_KEY_PART = r"""(?:[A-Za-z0-9_-]+|"(?:[^"\\]|\\.)*"|'[^']*')"""
_KEY = re.compile(rf"\s*({_KEY_PART}(?:\s*\.\s*{_KEY_PART})*)\s*=")
_HEADER = re.compile(rf"\s*\[\[?\s*({_KEY_PART}(?:\s*\.\s*{_KEY_PART})*)\s*\]")


def _key_path(spelled: str) -> str:
    """A TOML key as written (``"platform" . 'mass'``) as its dotted path (``platform.mass``)."""
    parts = re.findall(_KEY_PART, spelled)
    return ".".join(
        part[1:-1] if part[0] in "'\"" else part for part in parts
    )  # fmt: skip


def _overwritten(text: str, line: int) -> str | None:
    """tomllib's "Cannot overwrite a value" at ``line`` with the key it names.

    The key at the start of that line, and the table it is in (the last
    ``[header]`` above): ``the key 'mass' of [parameters] is set twice (a
    quoted and a bare key, or a dotted key and a table, are one key)``;
    ``None`` when the line does not start with a key.
    """
    lines = text.splitlines()
    if not 1 <= line <= len(lines):
        return None
    found = _KEY.match(lines[line - 1])
    if found is None:
        return None
    table = next(
        (
            _key_path(header.group(1))
            for header in (_HEADER.match(above) for above in reversed(lines[: line - 1]))
            if header is not None
        ),
        None,
    )
    where = f" of [{table}]" if table else ""
    return (
        f"the key {_key_path(found.group(1))!r}{where} is set twice (a quoted and a bare key, "
        "or a dotted key and a table, are one key in TOML): give it once"
    )


def toml_table(
    name: str,
    value: Any,
    allowed: Collection[str],
    refuse: Callable[[str, str], None] | None = None,
) -> dict[str, Any]:
    """``value`` as the table ``[name]`` of a robot file, whose keys are ``allowed``.

    ``refuse(key, dotted)``, when given, is called on each key first (it raises for a
    key it refuses with a message of its own).
    """
    if not isinstance(value, Mapping):
        what = f"[{name}]" if name else "the robot description"
        raise ParameterError(
            f"{what} must be a table of keys, got {value!r}"[:200], subject="robot", key=name
        )
    for key in value:
        dotted = f"{name}.{key}" if name else str(key)
        if refuse is not None:
            refuse(key, dotted)
        if key not in allowed:
            raise ParameterError(
                f"unknown key {dotted[:60]!r} (expected one of: {', '.join(sorted(allowed))})",
                subject="robot",
                key=dotted,
            )
    return dict(value)


def toml_float(value: float) -> str:
    """A float as TOML text that reads back to the same float (``repr``)."""
    return repr(float(value))


def toml_line(key: str, value: str, comment: str, comments: bool) -> str:
    """``key = value`` of a robot file, with ``# comment`` when ``comments``."""
    return f"{key} = {value}" + (f"  # {comment}" if comments else "")


def toml_list(values: tuple[float, ...]) -> str:
    """A TOML array of floats that read back exactly."""
    return "[" + ", ".join(toml_float(v) for v in values) + "]"


def payload_load_toml(payload: Payload, load: Load, comments: bool) -> list[str]:
    """The ``[payload]`` and ``[load]`` tables of a robot file (each left out when it is the
    default and ``comments`` is false)."""
    out: list[str] = []
    if payload != Payload() or comments:
        out += ["", "[payload]" + ("  # a rigid body fixed to the platform" if comments else "")]
        out.append(toml_line("mass", toml_float(payload.mass), "kg", comments))
        where = "m, its mass centre from G, platform frame"
        out.append(toml_line("com", toml_list(payload.com), where, comments))
        out.append(
            toml_line(
                "inertia",
                toml_float(payload.inertia),
                "kg m^2, I_zz about its mass centre",
                comments,
            )
        )
    if load != Load() or comments:
        heading = "  # constant wrench of the environment on the platform" if comments else ""
        out += ["", "[load]" + heading]
        out.append(toml_line("force", toml_list(load.force), "N, at G, fixed frame", comments))
        out.append(toml_line("moment", toml_float(load.moment), "N m, about z0", comments))
    return out


def robot_arguments(data: Mapping[str, Any]) -> dict[str, Any]:
    """The keyword arguments of :class:`~prp3.model.robot.Robot` of a mapping laid out as ``ROBOT.toml``.

    Every key is optional (an absent one is not among the arguments); unknown
    keys and wrong types raise :class:`ParameterError` naming the key.
    """
    top = toml_table("", data, _TOP_KEYS)
    kwargs: dict[str, Any] = {}
    if "l0" in top:
        kwargs["l0"] = top["l0"]
    if "gravity" in top:
        kwargs["gravity"] = check_pair("gravity", top["gravity"])
    if "piston" in top:
        kwargs["piston"] = PistonParameters(
            **toml_table("piston", top["piston"], {"mass", "inertia", "com"})
        )
    if "link" in top:
        kwargs["link"] = LinkParameters(
            **toml_table("link", top["link"], {"mass", "inertia", "com"})
        )
    if "platform" in top:
        kwargs["platform"] = PlatformParameters(
            **toml_table("platform", top["platform"], {"mass", "inertia"})
        )
    if "limits" in top:
        kwargs["limits"] = Limits(**toml_table("limits", top["limits"], {"stroke", "max_force"}))
    if "payload" in top:
        payload = toml_table("payload", top["payload"], {"mass", "com", "inertia"})
        if "com" in payload:
            payload["com"] = check_pair("payload.com", payload["com"])
        kwargs["payload"] = Payload(**payload)
    if "load" in top:
        load = toml_table("load", top["load"], {"force", "moment"})
        if "force" in load:
            load["force"] = check_pair("load.force", load["force"])
        kwargs["load"] = Load(**load)
    if "friction" in top:
        tables = toml_table("friction", top["friction"], set(_FRICTION_KEYS))
        kwargs["friction"] = Friction(
            **{
                kind: JointFriction(
                    **toml_table(f"friction.{kind}", tables[kind], _FRICTION_KEYS[kind]),
                    kind=kind,
                )
                for kind in tables
            }
        )
    if "spring" in top:
        tables = toml_table("spring", top["spring"], set(_SPRING_KEYS))
        kwargs["spring"] = Spring(
            **{
                kind: SpringParameters(
                    **toml_table(f"spring.{kind}", tables[kind], _SPRING_KEYS[kind]), kind=kind
                )
                for kind in tables
            }
        )
    return kwargs


def robot_text(robot: Robot, *, comments: bool) -> str:
    """The ``ROBOT.toml`` text of ``robot`` (a validated robot), read back to the same robot.

    With ``comments`` every key carries its meaning and unit and the optional
    tables absent from the robot are shown commented out (what
    :func:`prp3.model.robot.robot_template` gives); without, the keys only.
    """

    def line(key: str, value: str, comment: str) -> str:
        return toml_line(key, value, comment, comments)

    pair = toml_list

    out: list[str] = []
    if comments:
        out += [
            "# prp3 robot parameters (SI units). Every key is optional; omitted keys take",
            "# the defaults shown here (the paper's robot; docs/model.md states the model).",
        ]
    out += [
        line("l0", toml_float(robot.l0), "m, circumradius OA0 of base and platform triangles"),
        line("gravity", pair(robot.gravity), "m/s^2, gravity in the fixed frame (y0 up)"),
        "",
        "[piston]" + ("  # piston 1 of each leg (actuated slider)" if comments else ""),
        line("mass", toml_float(robot.piston.mass), "kg, m1"),
        line("inertia", toml_float(robot.piston.inertia), "kg m^2, I_zz about its centre of mass"),
        line("com", pair(robot.piston.com), "m, centre of mass from P_i along e_i, n_i"),
        "",
        "[link]" + ("  # link 2 of each leg (sleeve turning about P_i)" if comments else ""),
        line("mass", toml_float(robot.link.mass), "kg, m2"),
        line("inertia", toml_float(robot.link.inertia), "kg m^2, I_zz about its centre of mass"),
        line("com", pair(robot.link.com), "m, centre of mass from P_i along d_i, d_perp_i"),
        "",
        "[platform]" + ("  # moving platform, centre of mass G" if comments else ""),
        line("mass", toml_float(robot.platform.mass), "kg, m3"),
    ]
    if robot.platform.inertia is not None:
        out.append(line("inertia", toml_float(robot.platform.inertia), "kg m^2, I_zz about G"))
    elif comments:
        out.append(
            f"# inertia = {robot.platform_inertia:.6g}  # kg m^2, I_zz about G; when omitted, the"
            " uniform plate m3*l^2/12 with l = l0*sqrt(3), recomputed from m3 and l0"
        )
    if robot.limits.stroke is not None or robot.limits.max_force is not None or comments:
        out += ["", "[limits]" + ("  # optional working limits" if comments else "")]
        if robot.limits.stroke is not None:
            out.append(line("stroke", pair(robot.limits.stroke), "m, [lower, upper] of lambda10"))
        elif comments:
            out.append("# stroke = [-0.2, 0.2]  # m, [lower, upper] of every lambda10")
        if robot.limits.max_force is not None:
            out.append(line("max_force", toml_float(robot.limits.max_force), "N, largest |f10|"))
        elif comments:
            out.append("# max_force = 500.0  # N, largest admissible |f10|")
    out += payload_load_toml(robot.payload, robot.load, comments)
    out += _friction_toml(robot.friction, comments)
    out += _spring_toml(robot.spring, comments)
    return "\n".join(out) + "\n"


def _friction_toml(friction: Friction | None, comments: bool) -> list[str]:
    """The ``[friction.actuator]``, ``[friction.revolute]``, ``[friction.sleeve]`` tables
    (with ``comments``: commented out when the robot has no friction)."""

    def line(key: str, value: str, comment: str) -> str:
        return toml_line(key, value, comment, comments)

    out: list[str] = []
    if friction is not None:
        for kind in ("actuator", "revolute", "sleeve"):
            joint: JointFriction = getattr(friction, kind)
            units = FRICTION_UNITS[kind]
            out += ["", f"[friction.{kind}]" + (f"  # {_FRICTION_WHERE[kind]}" if comments else "")]
            out.append(line("viscous", toml_float(joint.viscous), units[0].replace("·", " ")))
            out.append(line("coulomb", toml_float(joint.coulomb), units[1].replace("·", " ")))
            out.append(line("mu", toml_float(joint.mu), "friction coefficient of the reaction"))
            if kind == "revolute":
                out.append(line("pin_radius", toml_float(joint.pin_radius), "m"))
            out.append(line("smoothing", toml_float(joint.smoothing), f"{units[3]}, 0: exact sign"))
    elif comments:
        out += [
            "",
            "# [friction.actuator]  # optional joint friction (also [friction.revolute] with",
            "# viscous = 0.0        # pin_radius, and [friction.sleeve]); docs/loads_and_friction.md",
            "# coulomb = 0.0",
            "# mu = 0.0",
            "# smoothing = 0.0",
        ]
    return out


def _spring_toml(springs: Spring | None, comments: bool) -> list[str]:
    """The ``[spring.<joint>]`` tables: the actuator's always, another joint's when it has a
    spring (with ``comments``: the actuator's commented out when the robot has none)."""

    def line(key: str, value: str, comment: str) -> str:
        return toml_line(key, value, comment, comments)

    out: list[str] = []
    if springs is not None:
        for kind, spring_units in SPRING_UNITS.items():
            stiffness, rest, damping = (unit.replace("·", " ") for unit in spring_units)
            spring = getattr(springs, kind)
            if kind != "actuator" and spring.is_zero and spring.rest == 0.0:
                continue  # the actuator's table is always written (the table [spring] exists)
            heading = f"  # {_SPRING_WHERE[kind]}" if comments else ""
            out += ["", f"[spring.{kind}]" + heading]
            out.append(line("stiffness", toml_float(spring.stiffness), f"{stiffness}, k"))
            coordinate = {"actuator": "lambda10", "revolute": "phi", "sleeve": "lambda32"}[kind]
            out.append(
                line(
                    "rest",
                    toml_float(spring.rest),
                    f"{rest}, {coordinate} at which the spring is relaxed",
                )
            )
            out.append(line("damping", toml_float(spring.damping), f"{damping}, c"))
    elif comments:
        out += [
            "",
            "# [spring.actuator]  # optional spring with damper on each lambda10_i: force on",
            "# stiffness = 0.0    # the piston -k*(lambda10 - rest) - c*dlambda10 along e_i, N/m",
            "# rest = 0.0         # m",
            "# damping = 0.0      # N s/m; docs/loads_and_friction.md",
        ]
    return out
