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
from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from prp3.errors import InputFileError, ParameterError
from prp3.files import read_text
from prp3.model.elements import ELEMENTS, Element
from prp3.validation import check_robot, check_scalar

__all__ = [
    "Friction",
    "JointFriction",
    "Limits",
    "LinkParameters",
    "Load",
    "Payload",
    "PistonParameters",
    "PlatformParameters",
    "Robot",
    "Spring",
    "SpringParameters",
    "robot_template",
]


#: Largest robot file read (bytes).
MAX_ROBOT_FILE_BYTES: int = 1024 * 1024

#: Longest run of digits accepted in a robot file (Python's own limit of integer text).
MAX_TOML_DIGITS: int = 4300


def _number(where: str, value: Any) -> float:
    """Return ``value`` as a finite float or raise a ParameterError naming ``where``."""
    return check_scalar(where, value, subject="robot")


def _positive(where: str, value: Any, unit: str) -> float:
    return check_scalar(where, value, subject="robot", positive=True, unit=unit)


def _non_negative(where: str, value: Any, unit: str) -> float:
    return check_scalar(where, value, subject="robot", non_negative=True, unit=unit)


def _check_parts(robot: object, parts: tuple[tuple[str, type], ...]) -> None:
    """Refuse a robot whose attribute ``name`` is not a ``kind`` for a ``(name, kind)`` of ``parts``."""
    for name, kind in parts:
        if not isinstance(getattr(robot, name), kind):
            raise ParameterError(
                f"{name} must be a {kind.__name__}, got {getattr(robot, name)!r}"[:200],
                subject="robot",
                key=name,
            )


def _pair(where: str, value: Any) -> tuple[float, float]:
    if not isinstance(value, list | tuple | np.ndarray) or len(value) != 2:
        raise ParameterError(
            f"{where} must be a pair of numbers [a, b], got {value!r}"[:200],
            subject="robot",
            key=where,
        )
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
                    "limits.stroke must be [lower, upper] with lower < 0 < upper (m), "
                    f"got {[lower, upper]!r}",
                    subject="robot",
                    key="limits.stroke",
                )
            object.__setattr__(self, "stroke", (lower, upper))
        if self.max_force is not None:
            object.__setattr__(
                self, "max_force", _positive("limits.max_force", self.max_force, "N")
            )


@dataclass(frozen=True)
class Payload:
    """A rigid body fixed to the platform (TOML table ``[payload]``; default: none).

    Attributes
    ----------
    mass : float
        Its mass (kg), >= 0.
    com : tuple of float
        Its mass centre from ``G`` in the platform frame (axes turned by ``φ``) (m).
    inertia : float
        ``I_zz`` about its own mass centre (kg·m²), >= 0.

    >>> Payload(mass=-1.0)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: payload.mass must be a non-negative finite number (kg), got -1.0
    """

    mass: float = 0.0
    com: tuple[float, float] = (0.0, 0.0)
    inertia: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _non_negative("payload.mass", self.mass, "kg"))
        object.__setattr__(self, "com", _pair("payload.com", self.com))
        object.__setattr__(self, "inertia", _non_negative("payload.inertia", self.inertia, "kg·m²"))

    @property
    def present(self) -> bool:
        """Whether the payload changes anything (non-zero mass or inertia)."""
        return self.mass != 0.0 or self.inertia != 0.0


@dataclass(frozen=True)
class Load:
    """A constant wrench of the environment on the platform (TOML table ``[load]``).

    Attributes
    ----------
    force : tuple of float
        Force ``(F_x, F_y)`` acting at ``G``, fixed frame (N).
    moment : float
        Moment about ``z0`` (N·m).
    """

    force: tuple[float, float] = (0.0, 0.0)
    moment: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "force", _pair("load.force", self.force))
        object.__setattr__(self, "moment", _number("load.moment", self.moment))

    @property
    def present(self) -> bool:
        """Whether any component is non-zero."""
        return self.force != (0.0, 0.0) or self.moment != 0.0


@dataclass(frozen=True)
class JointFriction:
    """Friction of one kind of joint (the three legs alike); ``docs/loads_and_friction.md``.

    The friction force (or moment) opposes the joint's relative rate ``v``:
    ``−(viscous·v + (coulomb + mu·N)·s(v))`` with ``N`` the magnitude of the
    joint's normal reaction (times ``pin_radius`` for the revolute joint) and
    ``s(v) = sign(v)`` when ``smoothing = 0``, else ``tanh(v/smoothing)``.

    Attributes
    ----------
    viscous : float
        ``b`` (N·s/m, or N·m·s/rad for the revolute joint), >= 0.
    coulomb : float
        ``c`` (N, or N·m), >= 0.
    mu : float
        ``μ``, >= 0 (dimensionless).
    smoothing : float
        ``v_s`` (m/s, or rad/s), >= 0.
    pin_radius : float
        ``r_r`` (m), >= 0: the revolute joint's pin (only ``[friction.revolute]``).
    kind : str
        ``"actuator"``, ``"revolute"`` or ``"sleeve"`` (set by :class:`Friction`).
    """

    viscous: float = 0.0
    coulomb: float = 0.0
    mu: float = 0.0
    smoothing: float = 0.0
    pin_radius: float = 0.0
    kind: str = ""

    def __post_init__(self) -> None:
        where = f"friction.{self.kind}" if self.kind else "friction"
        units = _FRICTION_UNITS.get(self.kind or "actuator")
        if units is None:
            raise ParameterError(
                f"robot: friction kind must be one of {', '.join(_FRICTION_UNITS)}, got {self.kind!r}"
            )
        for name, unit in zip(("viscous", "coulomb", "mu", "smoothing"), units, strict=True):
            value = _non_negative(f"{where}.{name}", getattr(self, name), unit)
            object.__setattr__(self, name, value)
        radius = _non_negative(f"{where}.pin_radius", self.pin_radius, "m")
        if radius != 0.0 and self.kind not in ("revolute", ""):
            raise ParameterError(f"robot: {where}.pin_radius applies to friction.revolute only")
        object.__setattr__(self, "pin_radius", radius)

    @property
    def has_mu(self) -> bool:
        """Whether the load-dependent term acts (``μ > 0``, and ``r_r > 0`` for the pin)."""
        return self.mu != 0.0 and (self.kind in ("actuator", "sleeve") or self.pin_radius != 0.0)


#: Units of viscous, coulomb, mu, smoothing per kind of joint.
_FRICTION_UNITS: dict[str, tuple[str, str, str, str]] = {
    "actuator": ("N·s/m", "N", "1", "m/s"),
    "revolute": ("N·m·s/rad", "N·m", "1", "rad/s"),
    "sleeve": ("N·s/m", "N", "1", "m/s"),
}

#: Keys of each ``[friction.KIND]`` table.
_FRICTION_KEYS: dict[str, set[str]] = {
    "actuator": {"viscous", "coulomb", "mu", "smoothing"},
    "revolute": {"viscous", "coulomb", "mu", "pin_radius", "smoothing"},
    "sleeve": {"viscous", "coulomb", "mu", "smoothing"},
}


@dataclass(frozen=True)
class Friction:
    """Friction in the joints (TOML table ``[friction]``); ``Robot.friction`` is ``None`` without.

    Attributes
    ----------
    actuator : JointFriction
        Base guide on piston i, along ``e_i`` (rate ``λ̇10_i``).
    revolute : JointFriction
        Piston i on link 2 at ``P_i`` (rate ``φ̇``).
    sleeve : JointFriction
        Link 2 on the platform along ``d_i`` (rate ``λ̇32_i``).

    >>> Friction(actuator=JointFriction(viscous=2.0)).actuator.viscous
    2.0
    """

    actuator: JointFriction = field(default_factory=lambda: JointFriction(kind="actuator"))
    revolute: JointFriction = field(default_factory=lambda: JointFriction(kind="revolute"))
    sleeve: JointFriction = field(default_factory=lambda: JointFriction(kind="sleeve"))

    def __post_init__(self) -> None:
        for kind in ("actuator", "revolute", "sleeve"):
            value = getattr(self, kind)
            if not isinstance(value, JointFriction):
                raise ParameterError(
                    f"robot: friction.{kind} must be a JointFriction, got {value!r}"[:200]
                )
            if value.kind != kind:
                object.__setattr__(
                    self,
                    kind,
                    JointFriction(
                        value.viscous,
                        value.coulomb,
                        value.mu,
                        value.smoothing,
                        value.pin_radius,
                        kind,
                    ),
                )

    @property
    def has_mu(self) -> bool:
        """Whether a load-dependent (``μ``) term acts: the inverse dynamics is implicit."""
        return self.actuator.has_mu or self.revolute.has_mu or self.sleeve.has_mu


@dataclass(frozen=True)
class SpringParameters:
    """A linear spring with damper along a joint; ``docs/loads_and_friction.md``.

    The force on the joint's body is ``−stiffness·(λ − rest) − damping·λ̇``
    (its element: :data:`prp3.model.elements.SPRING`).

    Attributes
    ----------
    stiffness : float
        ``k`` (N/m), >= 0.
    rest : float
        ``λ_rest``: the displacement at which the spring is relaxed (m).
    damping : float
        ``c`` (N·s/m), >= 0.

    >>> SpringParameters(stiffness=-1.0)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: spring.actuator.stiffness must be a non-negative finite number (N/m), got -1.0
    """

    stiffness: float = 0.0
    rest: float = 0.0
    damping: float = 0.0

    def __post_init__(self) -> None:
        where = "spring.actuator"
        object.__setattr__(
            self, "stiffness", _non_negative(f"{where}.stiffness", self.stiffness, "N/m")
        )
        object.__setattr__(self, "rest", _number(f"{where}.rest", self.rest))
        object.__setattr__(
            self, "damping", _non_negative(f"{where}.damping", self.damping, "N·s/m")
        )


@dataclass(frozen=True)
class Spring:
    """Springs of the joints (TOML table ``[spring]``); ``Robot.spring`` is ``None`` without.

    Attributes
    ----------
    actuator : SpringParameters
        Along the guide of piston i, on ``λ10_i`` (the three legs alike).
    """

    actuator: SpringParameters = field(default_factory=SpringParameters)

    def __post_init__(self) -> None:
        if not isinstance(self.actuator, SpringParameters):
            raise ParameterError(
                f"robot: spring.actuator must be a SpringParameters, got {self.actuator!r}"[:200]
            )


#: Keys of each ``[spring.KIND]`` table.
_SPRING_KEYS: dict[str, set[str]] = {"actuator": {"stiffness", "rest", "damping"}}


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
    payload : Payload
        A rigid body fixed to the platform; none by default.
    load : Load
        A constant wrench of the environment on the platform; none by default.
    friction : Friction or None
        Joint friction; ``None`` (ideal joints, the paper's model) by default.
    spring : Spring or None
        Linear springs with dampers of the actuated joints; ``None`` by default.

    Examples
    --------
    >>> Robot(gravity=(0.0, 0.0)).gravity
    (0.0, 0.0)
    >>> Robot.from_mapping({"platform": {"mass": 2.0}}).platform.mass
    2.0
    >>> Robot.from_mapping({"platfrom": {}})
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: unknown key 'platfrom' (expected one of: friction, gravity, l0, limits, link, load, payload, piston, platform, spring)
    """

    l0: float = 0.3
    gravity: tuple[float, float] = (0.0, -9.81)
    piston: PistonParameters = field(default_factory=PistonParameters)
    link: LinkParameters = field(default_factory=LinkParameters)
    platform: PlatformParameters = field(default_factory=PlatformParameters)
    limits: Limits = field(default_factory=Limits)
    payload: Payload = field(default_factory=Payload)
    load: Load = field(default_factory=Load)
    friction: Friction | None = None
    spring: Spring | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "l0", _positive("l0", self.l0, "m"))
        object.__setattr__(self, "gravity", _pair("gravity", self.gravity))
        if self.friction is not None and not isinstance(self.friction, Friction):
            raise ParameterError(f"robot: friction must be a Friction, got {self.friction!r}"[:200])
        if self.spring is not None and not isinstance(self.spring, Spring):
            raise ParameterError(f"robot: spring must be a Spring, got {self.spring!r}"[:200])
        _check_parts(
            self,
            (
                ("piston", PistonParameters),
                ("link", LinkParameters),
                ("platform", PlatformParameters),
                ("limits", Limits),
                ("payload", Payload),
                ("load", Load),
            ),
        )
        self._check_scale()

    def _check_scale(self) -> None:
        """Refuse parameters whose derived quantities overflow float64 (``l0 = 1e200``).

        The dynamics and the exports use ``m·l0²`` (inertias), ``m·g`` and
        ``l0/√3``; they must all be finite numbers, else every command would
        crash or write ``inf``.
        """
        g = max(abs(self.gravity[0]), abs(self.gravity[1]), 1.0)
        for body, mass in (
            ("piston", self.piston.mass),
            ("link", self.link.mass),
            ("platform", self.platform.mass),
        ):
            with np.errstate(over="ignore"):
                scale = np.float64(mass) * np.float64(self.l0) ** 2 * 3.0 * g
            if not np.isfinite(scale):
                raise ParameterError(
                    f"l0 = {self.l0!r} m and {body}.mass = {mass!r} kg are too large "
                    f"together: the {body}'s inertia m*l0^2 and its weight overflow float64",
                    subject="robot",
                    key="l0",
                )

    @property
    def elements(self) -> tuple[Element, ...]:
        """The effects this robot has, as elements (:mod:`prp3.model.elements`).

        >>> [e.name for e in Robot().elements]
        ['gravity']
        >>> [e.name for e in Robot(spring=Spring()).elements]
        ['gravity', 'spring.actuator']
        """
        return tuple(element for element in ELEMENTS if element.present(self))

    def with_keys(self, keys: Mapping[str, float]) -> Robot:
        """This robot with the ``ROBOT.toml`` keys ``keys`` (dotted paths) set, validated.

        >>> Robot().with_keys({"spring.actuator.stiffness": 50.0}).spring.actuator.stiffness
        50.0
        """
        data = tomllib.loads(self.to_toml())
        for path, value in keys.items():
            node = data
            *tables, key = path.split(".")
            for name in tables:
                node = node.setdefault(name, {})
            node[key] = value
        return Robot.from_mapping(data)

    @property
    def edge(self) -> float:
        """Edge length ``l = l0·√3`` of the base and platform triangles (m)."""
        return self.l0 * math.sqrt(3.0)

    @property
    def platform_inertia(self) -> float:
        """Platform ``I_zz`` about ``G`` (kg·m²): the given value or ``m3·l²/12``."""
        if self.platform.inertia is not None:
            return self.platform.inertia
        return self.platform.mass * self.edge * self.edge / 12.0

    # ------------------------------------------------------------------ TOML
    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> Robot:
        """Build a robot from a mapping with the layout of ``ROBOT.toml``.

        Every key is optional; unknown keys and wrong types raise
        :class:`ParameterError` naming the key.
        """
        top = _table(
            "",
            data,
            {
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
            },
        )
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
        if "payload" in top:
            payload = _table("payload", top["payload"], {"mass", "com", "inertia"})
            if "com" in payload:
                payload["com"] = _pair("payload.com", payload["com"])
            kwargs["payload"] = Payload(**payload)
        if "load" in top:
            load = _table("load", top["load"], {"force", "moment"})
            if "force" in load:
                load["force"] = _pair("load.force", load["force"])
            kwargs["load"] = Load(**load)
        if "friction" in top:
            tables = _table("friction", top["friction"], set(_FRICTION_KEYS))
            kwargs["friction"] = Friction(
                **{
                    kind: JointFriction(
                        **_table(f"friction.{kind}", tables[kind], _FRICTION_KEYS[kind]),
                        kind=kind,
                    )
                    for kind in tables
                }
            )
        if "spring" in top:
            tables = _table("spring", top["spring"], set(_SPRING_KEYS))
            kwargs["spring"] = Spring(
                **{
                    kind: SpringParameters(
                        **_table(f"spring.{kind}", tables[kind], _SPRING_KEYS[kind])
                    )
                    for kind in tables
                }
            )
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
        return parse_located(path, cls.from_mapping, read_toml(path, "robot"))

    def to_toml(self) -> str:
        """Return the robot as ``ROBOT.toml`` text (round-trips through :meth:`from_toml`).

        >>> Robot.from_mapping(tomllib.loads(Robot(l0=0.4).to_toml())) == Robot(l0=0.4)
        True
        """
        return robot_template(self, comments=False)


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
    """``parse(data)`` for the mapping ``data`` read from ``path``: a ParameterError names the file."""
    try:
        return parse(data)
    except ParameterError as error:
        raise error.located(file=path) from None


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


def _table(
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


def _fmt(value: float) -> str:
    return repr(float(value))


def _toml_line(key: str, value: str, comment: str, comments: bool) -> str:
    """``key = value`` of a robot file, with ``# comment`` when ``comments``."""
    return f"{key} = {value}" + (f"  # {comment}" if comments else "")


def _toml_list(values: tuple[float, ...]) -> str:
    """A TOML array of floats that read back exactly."""
    return "[" + ", ".join(_fmt(v) for v in values) + "]"


def _payload_load_toml(payload: Payload, load: Load, comments: bool) -> list[str]:
    """The ``[payload]`` and ``[load]`` tables of a robot file (each left out when it is the
    default and ``comments`` is false)."""
    out: list[str] = []
    if payload != Payload() or comments:
        out += ["", "[payload]" + ("  # a rigid body fixed to the platform" if comments else "")]
        out.append(_toml_line("mass", _fmt(payload.mass), "kg", comments))
        where = "m, its mass centre from G, platform frame"
        out.append(_toml_line("com", _toml_list(payload.com), where, comments))
        out.append(
            _toml_line(
                "inertia", _fmt(payload.inertia), "kg m^2, I_zz about its mass centre", comments
            )
        )
    if load != Load() or comments:
        heading = "  # constant wrench of the environment on the platform" if comments else ""
        out += ["", "[load]" + heading]
        out.append(_toml_line("force", _toml_list(load.force), "N, at G, fixed frame", comments))
        out.append(_toml_line("moment", _fmt(load.moment), "N m, about z0", comments))
    return out


def robot_template(robot: Robot | None = None, *, comments: bool = True) -> str:
    """Return a ``ROBOT.toml`` text for ``robot`` (default: the paper's robot).

    With ``comments=True`` every key carries its meaning and unit; this is what
    ``prp3 robot --template`` prints.

    >>> Robot.from_mapping(tomllib.loads(robot_template())) == Robot()
    True
    """
    robot = Robot() if robot is None else check_robot(robot)

    def line(key: str, value: str, comment: str) -> str:
        return _toml_line(key, value, comment, comments)

    pair = _toml_list

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
    out += _payload_load_toml(robot.payload, robot.load, comments)
    friction = robot.friction
    if friction is not None:
        for kind in ("actuator", "revolute", "sleeve"):
            joint: JointFriction = getattr(friction, kind)
            units = _FRICTION_UNITS[kind]
            out += ["", f"[friction.{kind}]" + (f"  # {_FRICTION_WHERE[kind]}" if comments else "")]
            out.append(line("viscous", _fmt(joint.viscous), units[0].replace("·", " ")))
            out.append(line("coulomb", _fmt(joint.coulomb), units[1].replace("·", " ")))
            out.append(line("mu", _fmt(joint.mu), "friction coefficient of the reaction"))
            if kind == "revolute":
                out.append(line("pin_radius", _fmt(joint.pin_radius), "m"))
            out.append(line("smoothing", _fmt(joint.smoothing), f"{units[3]}, 0: exact sign"))
    elif comments:
        out += [
            "",
            "# [friction.actuator]  # optional joint friction (also [friction.revolute] with",
            "# viscous = 0.0        # pin_radius, and [friction.sleeve]); docs/loads_and_friction.md",
            "# coulomb = 0.0",
            "# mu = 0.0",
            "# smoothing = 0.0",
        ]
    if robot.spring is not None:
        spring = robot.spring.actuator
        heading = "  # linear spring with damper on each lambda10_i" if comments else ""
        out += ["", "[spring.actuator]" + heading]
        out.append(line("stiffness", _fmt(spring.stiffness), "N/m, k"))
        out.append(line("rest", _fmt(spring.rest), "m, lambda10 at which the spring is relaxed"))
        out.append(line("damping", _fmt(spring.damping), "N s/m, c"))
    elif comments:
        out += [
            "",
            "# [spring.actuator]  # optional spring with damper on each lambda10_i: force on",
            "# stiffness = 0.0    # the piston -k*(lambda10 - rest) - c*dlambda10 along e_i, N/m",
            "# rest = 0.0         # m",
            "# damping = 0.0      # N s/m; docs/loads_and_friction.md",
        ]
    return "\n".join(out) + "\n"


_FRICTION_WHERE = {
    "actuator": "base guide on piston i, along e_i",
    "revolute": "piston i on link 2 at P_i (rate dphi)",
    "sleeve": "link 2 on the platform, along d_i",
}
