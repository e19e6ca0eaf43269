"""The robot model: immutable, validated parameters of the 3-PRP robot.

The defaults are those of the paper's application (section 3: ``l0 = 0.3 m``,
``m1 = 1 kg``, ``m2 = 0.75 kg``, ``m3 = 3 kg``) completed by the project's
model (``docs/model.md``): centres of mass at the joint centres, link
inertia ``6.25e-4 kg·m²``, platform inertia of a uniform equilateral plate
``m3·l²/12`` with ``l = l0·√3``, gravity ``(0, -9.81) m/s²``.

The model is a frozen dataclass; algorithms are pure functions that take it
as their first argument (model and algorithms apart, as in Pinocchio).

>>> robot = Robot()
>>> robot.l0, robot.platform.mass
(0.3, 3.0)
>>> round(robot.platform_inertia, 6)
0.0675
>>> Robot(l0=-1.0)
Traceback (most recent call last):
...
prp3.errors.ParameterError: robot: l0 must be a positive finite number (m), got -1.0
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputFileError, ParameterError

__all__ = [
    "Limits",
    "LinkParameters",
    "PistonParameters",
    "PlatformParameters",
    "Robot",
    "check_robot",
    "robot_template",
]


def _number(where: str, value: Any) -> float:
    """Return ``value`` as a finite float or raise a ParameterError naming ``where``."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise ParameterError(
            f"robot: {where} must be a number, got {value!r} ({type(value).__name__})"
        )
    try:
        number = float(value)
    except OverflowError:
        raise ParameterError(f"robot: {where} is too large, got {value!r}") from None
    if not math.isfinite(number):
        raise ParameterError(f"robot: {where} must be a finite number, got {value!r}")
    return number


def _positive(where: str, value: Any, unit: str) -> float:
    number = _number(where, value)
    if not number > 0.0:
        raise ParameterError(
            f"robot: {where} must be a positive finite number ({unit}), got {value!r}"
        )
    return number


def _non_negative(where: str, value: Any, unit: str) -> float:
    number = _number(where, value)
    if not number >= 0.0:
        raise ParameterError(
            f"robot: {where} must be a non-negative finite number ({unit}), got {value!r}"
        )
    return number


def _pair(where: str, value: Any) -> tuple[float, float]:
    if not isinstance(value, list | tuple | np.ndarray) or len(value) != 2:
        raise ParameterError(f"robot: {where} must be a pair of numbers [a, b], got {value!r}")
    return (_number(f"{where}[0]", value[0]), _number(f"{where}[1]", value[1]))


@dataclass(frozen=True)
class PistonParameters:
    """Piston 1 of each leg (the actuated slider).

    Attributes
    ----------
    mass : float
        ``m1`` (kg), > 0.
    inertia : float
        ``I_zz`` about its centre of mass (kg·m²), >= 0; irrelevant to the
        dynamics because the piston only translates.
    com : tuple of float
        Centre of mass offset ``(c1[0], c1[1])`` from the joint centre ``P_i``
        along ``e_i`` and ``n_i`` (m).
    """

    mass: float = 1.0
    inertia: float = 0.0
    com: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _positive("piston.mass", self.mass, "kg"))
        object.__setattr__(self, "inertia", _non_negative("piston.inertia", self.inertia, "kg·m²"))
        object.__setattr__(self, "com", _pair("piston.com", self.com))


@dataclass(frozen=True)
class LinkParameters:
    """Link 2 of each leg (the sleeve that turns about ``P_i``).

    Attributes
    ----------
    mass : float
        ``m2`` (kg), > 0.
    inertia : float
        ``I_zz`` about its centre of mass (kg·m²), >= 0.
    com : tuple of float
        Centre of mass offset ``(c2[0], c2[1])`` from ``P_i`` along ``d_i`` and
        ``d⊥_i`` (m).
    """

    mass: float = 0.75
    inertia: float = 6.25e-4
    com: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _positive("link.mass", self.mass, "kg"))
        object.__setattr__(self, "inertia", _non_negative("link.inertia", self.inertia, "kg·m²"))
        object.__setattr__(self, "com", _pair("link.com", self.com))


@dataclass(frozen=True)
class PlatformParameters:
    """The moving platform; its centre of mass is ``G`` by definition.

    Attributes
    ----------
    mass : float
        ``m3`` (kg), > 0.
    inertia : float or None
        ``I_zz`` about ``G`` (kg·m²), >= 0; ``None`` means the uniform
        equilateral plate ``m3·l²/12`` (see :attr:`Robot.platform_inertia`).
    """

    mass: float = 3.0
    inertia: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _positive("platform.mass", self.mass, "kg"))
        if self.inertia is not None:
            object.__setattr__(
                self, "inertia", _non_negative("platform.inertia", self.inertia, "kg·m²")
            )


@dataclass(frozen=True)
class Limits:
    """Optional working limits of the actuators (TOML table ``[limits]``).

    Attributes
    ----------
    stroke : tuple of float or None
        ``(lower, upper)`` bounds of every actuator displacement ``λ10`` (m),
        ``lower < 0 < upper`` so that the central configuration is reachable.
    max_force : float or None
        Largest admissible ``|f10|`` of every actuator (N), > 0.
    """

    stroke: tuple[float, float] | None = None
    max_force: float | None = None

    def __post_init__(self) -> None:
        if self.stroke is not None:
            lower, upper = _pair("limits.stroke", self.stroke)
            if not lower < 0.0 < upper:
                raise ParameterError(
                    "robot: limits.stroke must be [lower, upper] with lower < 0 < upper (m), "
                    f"got {[lower, upper]!r}"
                )
            object.__setattr__(self, "stroke", (lower, upper))
        if self.max_force is not None:
            object.__setattr__(
                self, "max_force", _positive("limits.max_force", self.max_force, "N")
            )


@dataclass(frozen=True)
class Robot:
    """Parameters of a 3-PRP planar parallel robot (immutable, validated).

    Attributes
    ----------
    l0 : float
        Circumradius of the base and platform triangles, ``OA0`` (m), > 0.
    gravity : tuple of float
        Gravity acceleration ``(g_x, g_y)`` in the fixed frame (m/s²).
    piston, link, platform : parameter dataclasses
        Inertial parameters of the bodies (see their docstrings).
    limits : Limits
        Optional actuator strokes and force limit; no limits by default.

    Examples
    --------
    >>> Robot(gravity=(0.0, 0.0)).gravity
    (0.0, 0.0)
    >>> Robot.from_mapping({"platform": {"mass": 2.0}}).platform.mass
    2.0
    >>> Robot.from_mapping({"platfrom": {}})
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: unknown key 'platfrom' (expected one of: gravity, l0, limits, link, piston, platform)
    """

    l0: float = 0.3
    gravity: tuple[float, float] = (0.0, -9.81)
    piston: PistonParameters = field(default_factory=PistonParameters)
    link: LinkParameters = field(default_factory=LinkParameters)
    platform: PlatformParameters = field(default_factory=PlatformParameters)
    limits: Limits = field(default_factory=Limits)

    def __post_init__(self) -> None:
        object.__setattr__(self, "l0", _positive("l0", self.l0, "m"))
        object.__setattr__(self, "gravity", _pair("gravity", self.gravity))
        for name, kind in (
            ("piston", PistonParameters),
            ("link", LinkParameters),
            ("platform", PlatformParameters),
            ("limits", Limits),
        ):
            if not isinstance(getattr(self, name), kind):
                raise ParameterError(
                    f"robot: {name} must be a {kind.__name__}, got {getattr(self, name)!r}"
                )

    @property
    def edge(self) -> float:
        """Edge length ``l = l0·√3`` of the base and platform triangles (m)."""
        return self.l0 * math.sqrt(3.0)

    @property
    def platform_inertia(self) -> float:
        """Platform ``I_zz`` about ``G`` (kg·m²): the given value or ``m3·l²/12``."""
        if self.platform.inertia is not None:
            return self.platform.inertia
        return self.platform.mass * self.edge**2 / 12.0

    # ------------------------------------------------------------------ TOML
    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> Robot:
        """Build a robot from a mapping with the layout of ``ROBOT.toml``.

        Every key is optional; unknown keys and wrong types raise
        :class:`ParameterError` naming the key.
        """
        top = _table("", data, {"l0", "gravity", "piston", "link", "platform", "limits"})
        kwargs: dict[str, Any] = {}
        if "l0" in top:
            kwargs["l0"] = top["l0"]
        if "gravity" in top:
            kwargs["gravity"] = _pair("gravity", top["gravity"])
        if "piston" in top:
            kwargs["piston"] = PistonParameters(
                **_table("piston", top["piston"], {"mass", "inertia", "com"})
            )
        if "link" in top:
            kwargs["link"] = LinkParameters(
                **_table("link", top["link"], {"mass", "inertia", "com"})
            )
        if "platform" in top:
            kwargs["platform"] = PlatformParameters(
                **_table("platform", top["platform"], {"mass", "inertia"})
            )
        if "limits" in top:
            kwargs["limits"] = Limits(**_table("limits", top["limits"], {"stroke", "max_force"}))
        return cls(**kwargs)

    @classmethod
    def from_toml(cls, path: str | Path) -> Robot:
        """Read a robot from a ``ROBOT.toml`` file (spec layout, every key optional).

        Raises
        ------
        InputFileError
            If the file cannot be read or is not valid TOML (names file, line, column).
        ParameterError
            If a key is unknown or a value invalid (names file and key).
        """
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8-sig")
        except OSError as error:
            raise InputFileError(f"{path}: cannot read robot file ({error.strerror})") from None
        except UnicodeDecodeError:
            raise InputFileError(f"{path}: robot file is not UTF-8 text") from None
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as error:
            message = str(error)
            where = re.search(r"\(at line (\d+), column (\d+)\)", message)
            if where is None:
                raise InputFileError(f"{path}: invalid TOML: {message}") from None
            reason = message[: where.start()].rstrip()
            raise InputFileError(
                f"{path}:{where.group(1)}:{where.group(2)}: invalid TOML: {reason}"
            ) from None
        try:
            return cls.from_mapping(data)
        except ParameterError as error:
            raise ParameterError(f"{path}: {error}") from None

    def to_toml(self) -> str:
        """Return the robot as ``ROBOT.toml`` text (round-trips through :meth:`from_toml`).

        >>> Robot.from_mapping(tomllib.loads(Robot(l0=0.4).to_toml())) == Robot(l0=0.4)
        True
        """
        return robot_template(self, comments=False)


def check_robot(robot: object) -> Robot:
    """Return ``robot`` if it is a :class:`Robot`, else raise :class:`ParameterError`.

    >>> check_robot(None)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot must be a prp3.Robot, got None
    """
    if not isinstance(robot, Robot):
        raise ParameterError(f"robot must be a prp3.Robot, got {robot!r}"[:200])
    return robot


def _table(name: str, value: Any, allowed: set[str]) -> dict[str, Any]:
    if not isinstance(value, Mapping):
        what = f"[{name}]" if name else "the robot description"
        raise ParameterError(f"robot: {what} must be a table of keys, got {value!r}")
    for key in value:
        if key not in allowed:
            dotted = f"{name}.{key}" if name else key
            raise ParameterError(
                f"robot: unknown key {dotted!r} (expected one of: {', '.join(sorted(allowed))})"
            )
    return dict(value)


def _fmt(value: float) -> str:
    return repr(float(value))


def robot_template(robot: Robot | None = None, *, comments: bool = True) -> str:
    """Return a ``ROBOT.toml`` text for ``robot`` (default: the paper's robot).

    With ``comments=True`` every key carries its meaning and unit; this is what
    ``prp3 robot --template`` prints.

    >>> Robot.from_mapping(tomllib.loads(robot_template())) == Robot()
    True
    """
    robot = robot or Robot()

    def line(key: str, value: str, comment: str) -> str:
        return f"{key} = {value}" + (f"  # {comment}" if comments else "")

    def pair(values: tuple[float, float]) -> str:
        return f"[{_fmt(values[0])}, {_fmt(values[1])}]"

    out: list[str] = []
    if comments:
        out += [
            "# prp3 robot parameters (SI units). Every key is optional; omitted keys take",
            "# the defaults shown here (the paper's robot; docs/model.md states the model).",
        ]
    out += [
        line("l0", _fmt(robot.l0), "m, circumradius OA0 of base and platform triangles"),
        line("gravity", pair(robot.gravity), "m/s^2, gravity in the fixed frame (y0 up)"),
        "",
        "[piston]" + ("  # piston 1 of each leg (actuated slider)" if comments else ""),
        line("mass", _fmt(robot.piston.mass), "kg, m1"),
        line("inertia", _fmt(robot.piston.inertia), "kg m^2, I_zz about its centre of mass"),
        line("com", pair(robot.piston.com), "m, centre of mass from P_i along e_i, n_i"),
        "",
        "[link]" + ("  # link 2 of each leg (sleeve turning about P_i)" if comments else ""),
        line("mass", _fmt(robot.link.mass), "kg, m2"),
        line("inertia", _fmt(robot.link.inertia), "kg m^2, I_zz about its centre of mass"),
        line("com", pair(robot.link.com), "m, centre of mass from P_i along d_i, d_perp_i"),
        "",
        "[platform]" + ("  # moving platform, centre of mass G" if comments else ""),
        line("mass", _fmt(robot.platform.mass), "kg, m3"),
    ]
    if robot.platform.inertia is not None:
        out.append(line("inertia", _fmt(robot.platform.inertia), "kg m^2, I_zz about G"))
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
            out.append(line("max_force", _fmt(robot.limits.max_force), "N, largest |f10|"))
        elif comments:
            out.append("# max_force = 500.0  # N, largest admissible |f10|")
    return "\n".join(out) + "\n"
