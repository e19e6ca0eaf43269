"""The robot model: :class:`Robot`, the immutable, validated parameters of the 3-PRP robot.

The defaults are those of the paper's application (section 3: ``l0 = 0.3 m``,
``m1 = 1 kg``, ``m2 = 0.75 kg``, ``m3 = 3 kg``) completed by the project's
model (``docs/model.md``): centres of mass at the joint centres, link
inertia ``6.25e-4 kg·m²``, platform inertia of a uniform equilateral plate
``m3·l²/12`` with ``l = l0·√3``, gravity ``(0, -9.81) m/s²``.

The model is a frozen dataclass; algorithms are pure functions that take it
as their first argument (model and algorithms apart, as in Pinocchio).  Its
parts are the dataclasses of :mod:`prp3.model.parameters`; its file
``ROBOT.toml`` is read and written by :mod:`prp3.model.robot_toml`.

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
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from prp3.errors import ParameterError
from prp3.model.element_base import Element
from prp3.model.elements import ELEMENTS
from prp3.model.parameters import (
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
    body_scale_checks,
    check_pair,
    check_parts,
    load_scale_check,
    refuse_overflow,
)
from prp3.model.robot_toml import parse_located, read_toml, robot_arguments, robot_text
from prp3.validation import check_robot, check_scalar

__all__ = ["Robot", "robot_template"]


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
        object.__setattr__(
            self, "l0", check_scalar("l0", self.l0, subject="robot", positive=True, unit="m")
        )
        object.__setattr__(self, "gravity", check_pair("gravity", self.gravity))
        if self.friction is not None and not isinstance(self.friction, Friction):
            raise ParameterError(f"robot: friction must be a Friction, got {self.friction!r}"[:200])
        if self.spring is not None and not isinstance(self.spring, Spring):
            raise ParameterError(f"robot: spring must be a Spring, got {self.spring!r}"[:200])
        check_parts(
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
        self._check_effects_scale(g)

    def _check_effects_scale(self, g: float) -> None:
        """Refuse a payload, load, spring or friction whose effects overflow float64.

        Each effect's derived quantities as the kernel forms them, without a
        margin (:func:`prp3.model.parameters.refuse_overflow`): the payload's weight
        ``m·g``, its inertia about the far end of a leg ``I + m·(l0 + |c|)²`` and the
        moment of its weight ``m·g·(l0 + |c|)``; the load's ``|F|·l0 + |M|``; the three
        legs' alike summed: the spring's force
        ``k·(|λ_rest| + l0)`` and damping ``b·l0``; the friction's viscous
        ``b·l0`` and ``μ``-scaled reactions ``μ·(1 + r)``.  A refusal names the key.
        """
        l0 = np.float64(self.l0)
        payload = self.payload
        checks = [
            *body_scale_checks("payload", payload.mass, payload.com, payload.inertia, l0, g),
            load_scale_check(self.load, l0),
        ]
        if self.spring is not None:
            for name in ("actuator",):
                spring = getattr(self.spring, name, None)
                if spring is None:
                    continue
                checks.append(
                    (
                        f"spring.{name}.stiffness",
                        f"spring.{name}: stiffness = {spring.stiffness!r} N/m, rest = "
                        f"{spring.rest!r} m, damping = {spring.damping!r} N·s/m: its force overflows",
                        _spring_force(spring, l0),
                    )
                )
        if self.friction is not None:
            for name in ("actuator", "revolute", "sleeve"):
                joint = getattr(self.friction, name, None)
                if joint is None:
                    continue
                checks.append(
                    (
                        f"friction.{name}",
                        f"friction.{name}: viscous = {joint.viscous!r}, coulomb = "
                        f"{joint.coulomb!r}, mu = {joint.mu!r}, pin_radius = {joint.pin_radius!r}: "
                        "its forces overflow",
                        _friction_forces(joint, l0),
                    )
                )
        refuse_overflow(checks, f"(l0 = {self.l0!r} m, gravity = {list(self.gravity)!r} m/s²)")

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
        return cls(**robot_arguments(data))

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
        return robot_text(self, comments=False)


def robot_template(robot: Robot | None = None, *, comments: bool = True) -> str:
    """Return a ``ROBOT.toml`` text for ``robot`` (default: the paper's robot).

    With ``comments=True`` every key carries its meaning and unit; this is what
    ``prp3 robot --template`` prints (:func:`prp3.model.robot_toml.robot_text`).

    >>> Robot.from_mapping(tomllib.loads(robot_template())) == Robot()
    True
    """
    robot = Robot() if robot is None else check_robot(robot)
    return robot_text(robot, comments=comments)


def _spring_force(spring: SpringParameters, l0: np.float64) -> Callable[[], Any]:
    """The spring's force and damping at the scale ``l0``, the three actuators' in one sum
    (an overflow check's quantity)."""
    return lambda: (
        3.0
        * (
            np.float64(spring.stiffness) * (abs(np.float64(spring.rest)) + l0)
            + np.float64(spring.damping) * l0
        )
    )


def _friction_forces(joint: JointFriction, l0: np.float64) -> Callable[[], Any]:
    """A joint's friction forces at the scale ``l0``, the three legs' in one sum (an overflow
    check's quantity)."""
    return lambda: (
        3.0
        * (
            (np.float64(joint.viscous) * l0 + np.float64(joint.coulomb)) * 3.0
            + np.float64(joint.mu) * (1.0 + np.float64(joint.pin_radius)) * 3.0
        )
    )
