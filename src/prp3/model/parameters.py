"""The parameters of the robot model: immutable, validated dataclasses.

The bodies of each leg (:class:`PistonParameters`, :class:`LinkParameters`),
the platform (:class:`PlatformParameters`), the actuators' working limits
(:class:`Limits`), a payload fixed to the platform (:class:`Payload`), a
constant wrench of the environment (:class:`Load`), the friction of each kind
of joint (:class:`JointFriction`, :class:`Friction`) and the actuators'
spring with damper (:class:`SpringParameters`, :class:`Spring`): the parts
:class:`prp3.model.robot.Robot` is made of, each one a ``ROBOT.toml`` table
(:mod:`prp3.model.robot_toml`).  Every value is checked on construction and
a refusal names its key.

>>> LinkParameters().mass, Payload(mass=2.0).present
(0.75, True)
>>> PistonParameters(mass=0.0)
Traceback (most recent call last):
...
prp3.errors.ParameterError: robot: piston.mass must be a positive finite number (kg), got 0.0
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from prp3.errors import ParameterError
from prp3.validation import check_scalar

__all__ = [
    "SPRING_UNITS",
    "Friction",
    "JointFriction",
    "Limits",
    "LinkParameters",
    "Load",
    "Payload",
    "PistonParameters",
    "PlatformParameters",
    "Spring",
    "SpringParameters",
]


def _number(where: str, value: Any) -> float:
    """Return ``value`` as a finite float or raise a ParameterError naming ``where``."""
    return check_scalar(where, value, subject="robot")


def _positive(where: str, value: Any, unit: str) -> float:
    return check_scalar(where, value, subject="robot", positive=True, unit=unit)


def _non_negative(where: str, value: Any, unit: str) -> float:
    return check_scalar(where, value, subject="robot", non_negative=True, unit=unit)


def check_parts(robot: object, parts: tuple[tuple[str, type], ...]) -> None:
    """Refuse a robot whose attribute ``name`` is not a ``kind`` for a ``(name, kind)`` of ``parts``."""
    for name, kind in parts:
        if not isinstance(getattr(robot, name), kind):
            raise ParameterError(
                f"{name} must be a {kind.__name__}, got {getattr(robot, name)!r}"[:200],
                subject="robot",
                key=name,
            )


def check_pair(where: str, value: Any) -> tuple[float, float]:
    """``value`` as a pair of finite floats ``(a, b)``, or a ParameterError naming ``where``."""
    if (
        not isinstance(value, list | tuple | np.ndarray)
        or (isinstance(value, np.ndarray) and value.ndim != 1)
        or len(value) != 2
    ):
        raise ParameterError(
            f"{where} must be a pair of numbers [a, b], got {value!r}"[:200],
            subject="robot",
            key=where,
        )
    return (_number(f"{where}[0]", value[0]), _number(f"{where}[1]", value[1]))


@dataclass(frozen=True)
class _LegBody:
    """A body of each leg: its mass, inertia and centre-of-mass offset, validated.

    The fields of :class:`PistonParameters` and :class:`LinkParameters` (which
    give their defaults and meanings); ``TABLE`` names the ``ROBOT.toml`` table
    in the messages.
    """

    TABLE: ClassVar[str] = ""

    mass: float
    inertia: float
    com: tuple[float, float]

    def __post_init__(self) -> None:
        table = self.TABLE
        object.__setattr__(self, "mass", _positive(f"{table}.mass", self.mass, "kg"))
        inertia = _non_negative(f"{table}.inertia", self.inertia, "kg·m²")
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "com", check_pair(f"{table}.com", self.com))


@dataclass(frozen=True)
class PistonParameters(_LegBody):
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

    TABLE: ClassVar[str] = "piston"

    mass: float = 1.0
    inertia: float = 0.0
    com: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class LinkParameters(_LegBody):
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

    TABLE: ClassVar[str] = "link"

    mass: float = 0.75
    inertia: float = 6.25e-4
    com: tuple[float, float] = (0.0, 0.0)


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
            lower, upper = check_pair("limits.stroke", self.stroke)
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
        object.__setattr__(self, "com", check_pair("payload.com", self.com))
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
        object.__setattr__(self, "force", check_pair("load.force", self.force))
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
        units = FRICTION_UNITS.get(self.kind or "actuator")
        if units is None:
            raise ParameterError(
                f"robot: friction kind must be one of {', '.join(FRICTION_UNITS)}, got {self.kind!r}"
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
FRICTION_UNITS: dict[str, tuple[str, str, str, str]] = {
    "actuator": ("N·s/m", "N", "1", "m/s"),
    "revolute": ("N·m·s/rad", "N·m", "1", "rad/s"),
    "sleeve": ("N·s/m", "N", "1", "m/s"),
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


#: The units of a spring on each kind of joint: (stiffness, rest, damping).
SPRING_UNITS: dict[str, tuple[str, str, str]] = {
    "actuator": ("N/m", "m", "N·s/m"),
    "revolute": ("N·m/rad", "rad", "N·m·s/rad"),
    "sleeve": ("N/m", "m", "N·s/m"),
}


@dataclass(frozen=True)
class SpringParameters:
    """A linear spring with damper on a joint; ``docs/loads_and_friction.md``.

    The force (or moment, on the revolute joint) on the joint's outer body is
    ``−stiffness·(q − rest) − damping·q̇``, ``q`` the joint's coordinate
    (``λ10_i``, ``φ`` or ``λ32_i``; its element: :func:`prp3.model.joint_elements.spring_element`).

    Attributes
    ----------
    stiffness : float
        ``k`` (N/m; N·m/rad on the revolute joint), >= 0.
    rest : float
        ``q_rest``: the coordinate at which the spring is relaxed (m; rad).
    damping : float
        ``c`` (N·s/m; N·m·s/rad), >= 0.
    kind : str
        The joint: ``"actuator"`` (``λ10_i``), ``"revolute"`` (``φ``), ``"sleeve"`` (``λ32_i``).

    >>> SpringParameters(stiffness=-1.0)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: spring.actuator.stiffness must be a non-negative finite number (N/m), got -1.0
    >>> SpringParameters(damping=-1.0, kind="revolute")
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: spring.revolute.damping must be a non-negative finite number (N·m·s/rad), got -1.0
    """

    stiffness: float = 0.0
    rest: float = 0.0
    damping: float = 0.0
    kind: str = "actuator"

    def __post_init__(self) -> None:
        if self.kind not in SPRING_UNITS:
            raise ParameterError(
                f"robot: a spring's joint must be one of {', '.join(SPRING_UNITS)}, got {self.kind!r}"[
                    :200
                ]
            )
        where, (stiffness, _, damping) = f"spring.{self.kind}", SPRING_UNITS[self.kind]
        object.__setattr__(
            self, "stiffness", _non_negative(f"{where}.stiffness", self.stiffness, stiffness)
        )
        object.__setattr__(self, "rest", _number(f"{where}.rest", self.rest))
        object.__setattr__(
            self, "damping", _non_negative(f"{where}.damping", self.damping, damping)
        )

    @property
    def is_zero(self) -> bool:
        """Whether it applies no force at all (stiffness and damping zero)."""
        return self.stiffness == 0.0 and self.damping == 0.0


@dataclass(frozen=True)
class Spring:
    """Springs with dampers of the joints (TOML ``[spring.KIND]``); ``Robot.spring`` is ``None`` without.

    Attributes
    ----------
    actuator : SpringParameters
        Along the guide of piston i, on ``λ10_i`` (the three legs alike).
    revolute : SpringParameters
        A torsion spring of piston i on link 2 at ``P_i``, on ``φ`` (link 2 turns with
        the platform, eq. 7).
    sleeve : SpringParameters
        Along the sleeve of link 2 on the platform, on ``λ32_i``.

    >>> Spring(sleeve=SpringParameters(stiffness=20.0)).sleeve.kind
    'sleeve'
    """

    actuator: SpringParameters = field(default_factory=SpringParameters)
    revolute: SpringParameters = field(default_factory=lambda: SpringParameters(kind="revolute"))
    sleeve: SpringParameters = field(default_factory=lambda: SpringParameters(kind="sleeve"))

    def __post_init__(self) -> None:
        for kind in SPRING_UNITS:
            value = getattr(self, kind)
            if not isinstance(value, SpringParameters):
                raise ParameterError(
                    f"robot: spring.{kind} must be a SpringParameters, got {value!r}"[:200]
                )
            if value.kind != kind:
                object.__setattr__(
                    self,
                    kind,
                    SpringParameters(value.stiffness, value.rest, value.damping, kind),
                )


#: One overflow check of :func:`refuse_overflow`: the key it names, what the message says of
#: it, the quantity (a float64 that is ``inf`` or NaN when it overflows) and, for a body's
#: contribution to a total the model forms, the total's name (``"weight"``, ``"moment"``,
#: ``"inertia"``: :func:`refuse_overflow` sums these over the bodies).
ScaleCheck = tuple[str, str, Callable[[], Any]] | tuple[str, str, Callable[[], Any], str]


def body_scale_checks(
    prefix: str,
    mass: float,
    com: tuple[float, ...],
    inertia: float,
    length: float,
    g: float,
    centre: str = "com",
    inertia_text: str | None = None,
    count: int = 1,
) -> list[ScaleCheck]:
    """The overflow checks of a body fixed to a leg or the platform (``payload``, ``link1``).

    ``length`` (m) is the robot's reach: the body's arm about the far end of a leg is
    ``r = length + |com|`` (``com`` of two or three coordinates), ``g = max(|g_x|, |g_y|, 1)``.
    The products the model forms of the body must be finite float64, no margin: its
    weight ``m·g``, the moment of its weight ``m·g·r`` (which bounds its first moment
    ``m·r``: ``g ≥ 1``) and its inertia about that end ``I + m·r²`` (``I`` the inertia, or a
    spatial body's largest entry), and so must their totals over the robot's bodies
    (:func:`refuse_overflow`; ``count`` bodies alike, the legs' bodies of a family robot).
    An arm whose square ``r²`` or moment ``r·g`` alone overflows names ``prefix.com``
    (``prefix.<centre>``) whatever the mass; else the weight and moment name the larger
    of their factors, ``prefix.mass`` (``m ≥ g``) or ``gravity``, and the inertia
    ``prefix.inertia``.  ``inertia_text`` replaces
    ``= inertia kg·m²`` in the message.

    >>> [check[0] for check in body_scale_checks("payload", 10.0, (0.0, 0.0), 0.0, 0.3, 9.81)]
    ['payload.mass', 'payload.mass', 'payload.inertia']
    """
    with np.errstate(over="ignore"):
        arm = np.float64(length) + np.float64(math.hypot(*(float(c) for c in com)))
        far = not (np.isfinite(arm * arm) and np.isfinite(arm * np.float64(g)))
    where = f"{list(com)!r} m"
    if far:  # the com alone: r² or r·g is beyond float64
        return [
            (
                f"{prefix}.{centre}",
                f"{prefix}.{centre} = {where} with mass = {mass!r} kg: its arm "
                f"{length!r} m + |{centre}| squared overflows",
                lambda: np.float64(math.inf),
            )
        ]
    m, n = np.float64(mass), np.float64(count)
    alike = f" ({count} bodies alike)" if count > 1 else ""
    weight = f"{prefix}.mass = {mass!r} kg with {centre} = {where}{alike}: its weight"
    heavy = f"{prefix}.mass"
    if g > abs(mass):  # gravity is the larger factor of the weight: name it
        heavy = "gravity"
        weight = f"gravity |g| = {g!r} m/s² with {prefix}.mass = {mass!r} kg{alike}: the weight"
    return [
        (heavy, f"{weight} m·g overflows", lambda: n * m * g, "weight"),
        (heavy, f"{weight}'s moment m·g·r overflows", lambda: n * m * g * arm, "moment"),
        (
            f"{prefix}.inertia",
            f"{prefix}.inertia {inertia_text or f'= {inertia!r} kg·m²'} with mass = {mass!r} kg: "
            "its inertia I + m·r² overflows",
            lambda: n * (np.float64(inertia) + m * arm * arm),
            "inertia",
        ),
    ]


def gravity_scale_check(gravity: tuple[float, ...], length: float) -> ScaleCheck:
    """The overflow check of gravity alone: a unit mass's weight and its moment,
    ``|g|·max(length, 1)`` (``|g|`` the largest component)."""
    g = np.float64(max(abs(float(v)) for v in gravity))
    return (
        "gravity",
        f"gravity = {list(gravity)!r} m/s²: a unit mass's weight and its moment overflow",
        lambda: g * max(np.float64(length), np.float64(1.0)),
    )


def load_scale_check(load: Load, length: float) -> ScaleCheck:
    """The overflow check of the load's wrench: its force ``|F_x| + |F_y|`` and its moment about
    the far end of a leg ``(|F_x| + |F_y|)·length + |M|`` (the larger must be finite)."""
    fx, fy, moment = (np.float64(v) for v in (*load.force, load.moment))
    return (
        "load.force",
        f"load.force = {list(load.force)!r} N and load.moment = {load.moment!r} N·m: "
        "the load's wrench overflows",
        lambda: max(abs(fx) + abs(fy), (abs(fx) + abs(fy)) * np.float64(length) + abs(moment)),
    )


#: The totals of :func:`refuse_overflow`: a check's total name → what the message calls it.
TOTALS: dict[str, str] = {
    "weight": "the weights m·g of the bodies",
    "moment": "the moments m·g·r of their weights",
    "inertia": "their inertias I + m·r²",
}


def refuse_overflow(checks: list[ScaleCheck], context: str) -> None:
    """Raise a ParameterError naming the key of the first check whose quantity is not a
    finite float64, or of the largest part of a total (:data:`TOTALS`: the sum over the
    bodies of the checks that name it) that is not; ``context`` (the robot's scale) ends
    the message.  No margin: what float64 holds is accepted.

    >>> check = body_scale_checks("payload", 1e308, (0.0, 0.0), 0.0, 0.3, 9.81)
    >>> refuse_overflow(check, "(l0 = 0.3 m)")
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: payload.mass = 1e+308 kg with com = [0.0, 0.0] m: its weight m·g overflows float64 (l0 = 0.3 m)
    >>> refuse_overflow(body_scale_checks("payload", 1.8e307, (0.0, 0.0), 0.0, 0.3, 9.81), "")
    >>> twice = body_scale_checks("link1", 1.8e307, (0.0, 0.0), 0.0, 0.3, 9.81, count=3)
    >>> refuse_overflow(twice, "(reach 0.3 m)")
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: link1.mass = 1.8e+307 kg with com = [0.0, 0.0] m (3 bodies alike): its weight m·g overflows float64 (reach 0.3 m)
    """
    parts: dict[str, list[tuple[float, str, str]]] = {}
    for check in checks:
        key, what, quantity = check[0], check[1], check[2]
        with np.errstate(over="ignore", invalid="ignore"):
            value = np.float64(quantity())
        if not np.isfinite(value):
            raise ParameterError(f"{what} float64 {context}".rstrip(), subject="robot", key=key)
        if len(check) == 4:
            parts.setdefault(check[3], []).append((float(abs(value)), key, what))
    for total, terms in parts.items():
        with np.errstate(over="ignore"):
            summed = np.sum(np.array([value for value, _, _ in terms], dtype=np.float64))
        if not np.isfinite(summed):
            _, key, what = max(terms)
            raise ParameterError(
                f"{what.rsplit(': ', 1)[0]}: {TOTALS[total]} overflow float64 in their sum "
                f"{context}".rstrip(),
                subject="robot",
                key=key,
            )
