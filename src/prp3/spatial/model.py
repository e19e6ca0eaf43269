"""The spatial model: joints R, P, U, S placed in 3-D, legs, bodies, the robot (docs/spatial.md §2, §7).

A :class:`SpatialRobot` is a fixed base (the world frame), a platform
(:class:`Body`) and legs (:class:`Leg`), each leg a chain of placed
:class:`Joint` objects from the base to the platform with a :class:`Body`
between consecutive joints and one actuated joint.  Everything is validated
when built (the project's :class:`~prp3.errors.ParameterError`, naming the
leg, joint and key) and immutable.  :func:`hexapod` builds the 6-UPS
Stewart–Gough platform of docs/spatial.md §7.

>>> robot = hexapod()
>>> robot.name, len(robot.legs), robot.legs[0].pattern, robot.legs[0].actuated
('6-UPS', 6, 'UPS', 1)
>>> robot.dof, [leg.dof for leg in robot.legs][:2]
(6, [6, 6])
>>> Joint("Q", (0, 0, 0))
Traceback (most recent call last):
...
prp3.errors.ParameterError: robot: joint: kind must be one of 'R', 'P', 'U', 'S', got 'Q'
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError
from prp3.model.parameters import (
    ScaleCheck,
    body_scale_checks,
    gravity_scale_check,
    refuse_overflow,
)
from prp3.spatial.rotations import axis_rotation, cross
from prp3.validation import check_finite, check_real, check_scalar

__all__ = [
    "JOINT_DOF",
    "JOINT_KINDS",
    "MAX_DESIGN_LENGTH",
    "Body",
    "Joint",
    "Leg",
    "SpatialRobot",
    "check_rotation",
    "check_vector",
    "delta",
    "design_length",
    "hexapod",
    "three_rps",
]

FloatArray = NDArray[np.float64]
Vector = tuple[float, float, float]
Matrix = tuple[Vector, Vector, Vector]

#: The joint types and their number of coordinates (degrees of freedom).
JOINT_DOF: dict[str, int] = {"R": 1, "P": 1, "U": 2, "S": 3}
JOINT_KINDS: tuple[str, ...] = tuple(JOINT_DOF)

#: A rotation is accepted when ``|RᵀR − I|`` and ``|det R − 1|`` are below this.
ORTHONORMAL_TOLERANCE: float = 1e-9

_IDENTITY: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def check_vector(name: str, value: ArrayLike, subject: str = "robot") -> Vector:
    """Three finite real numbers (a point or a direction), as a tuple."""
    array = check_real(name, value, ParameterError, subject)
    if array.shape != (3,):
        raise ParameterError(
            f"{name} must be three numbers, got shape {array.shape}", subject=subject, key=name
        )
    check_finite(name, array, ParameterError, components=("x", "y", "z"), subject=subject)
    x, y, z = (float(v) for v in array)
    return (x, y, z)


def check_rotation(name: str, value: ArrayLike, subject: str = "robot") -> Matrix:
    """A rotation matrix ``(3, 3)`` (orthonormal, determinant +1 to ``1e-9``), as nested tuples."""
    array = check_real(name, value, ParameterError, subject)
    if array.shape != (3, 3):
        raise ParameterError(
            f"{name} must be a 3 x 3 rotation matrix, got shape {array.shape}",
            subject=subject,
            key=name,
        )
    check_finite(name, array, ParameterError, subject=subject)
    error = float(np.abs(array.T @ array - np.eye(3)).max())
    det = float(np.linalg.det(array))
    if error > ORTHONORMAL_TOLERANCE or abs(det - 1.0) > ORTHONORMAL_TOLERANCE:
        raise ParameterError(
            f"{name} is not a rotation matrix (|R^T R - I| = {error:.3g}, det = {det:.12g})",
            subject=subject,
            key=name,
        )
    rows = [tuple(float(v) for v in row) for row in array]
    return ((rows[0][0], rows[0][1], rows[0][2]), (rows[1][0], rows[1][1], rows[1][2]),
            (rows[2][0], rows[2][1], rows[2][2]))  # fmt: skip


@dataclass(frozen=True)
class Joint:
    """One joint (docs/spatial.md §2): its type and the placement of its joint frame.

    Parameters
    ----------
    kind : {"R", "P", "U", "S"}
        R turns about the joint frame's ``z``, P slides along its ``x``, U turns
        about ``z`` then about the cross's ``y``, S turns about its centre.
    position : three floats
        Origin of the joint frame in the proximal body's frame (m).
    rotation : (3, 3) array, optional
        Axes of the joint frame in the proximal body's frame (identity by default).
    limits : tuple of (low, high) pairs, optional
        One pair per coordinate of R, P, U (rad or m); for S one pair bounding
        the rotation angle ``|φ|`` (rad).  Unbounded by default.
    """

    kind: str
    position: Vector
    rotation: Matrix = _IDENTITY
    limits: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in JOINT_DOF:
            raise ParameterError(
                f"kind must be one of 'R', 'P', 'U', 'S', got {self.kind!r}"[:200],
                subject="robot: joint",
                key="kind",
            )
        object.__setattr__(self, "position", check_vector("joint position", self.position))
        object.__setattr__(self, "rotation", check_rotation("joint rotation", self.rotation))
        count = 1 if self.kind == "S" else JOINT_DOF[self.kind]
        limits = self.limits or tuple((-math.inf, math.inf) for _ in range(count))
        if self.kind == "S" and not self.limits:
            limits = ((0.0, math.inf),)
        if len(limits) != count:
            raise ParameterError(
                f"a {self.kind} joint has {count} pair(s) of limits, got {len(limits)}",
                subject="robot: joint",
                key="limits",
            )
        checked = []
        for low, high in limits:
            lo = float(low) if low == -math.inf else check_scalar("joint limit", low)
            hi = float(high) if high == math.inf else check_scalar("joint limit", high)
            if not lo < hi:
                raise ParameterError(
                    f"joint limits must have low < high, got ({low!r}, {high!r})",
                    subject="robot: joint",
                    key="limits",
                )
            checked.append((lo, hi))
        object.__setattr__(self, "limits", tuple(checked))

    @property
    def dof(self) -> int:
        """Number of coordinates of ``q`` (and of ``dq``, ``ddq``)."""
        return JOINT_DOF[self.kind]

    def coordinates(self, label: str) -> tuple[str, ...]:
        """The names of the coordinates of this joint labelled ``label`` (``U1`` → ``U1_a, U1_b``)."""
        if self.kind == "U":
            return (f"{label}_a", f"{label}_b")
        if self.kind == "S":
            return (f"{label}_x", f"{label}_y", f"{label}_z")
        return (label,)


@dataclass(frozen=True)
class Body:
    """A rigid body: mass (kg), mass centre in its frame (m), inertia about it in its frame (kg·m²)."""

    mass: float
    centre: Vector = (0.0, 0.0, 0.0)
    inertia: Matrix = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    name: str = "body"

    def __post_init__(self) -> None:
        subject = f"robot: {self.name}"
        mass = check_scalar("mass", self.mass, non_negative=True, unit="kg", subject=subject)
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "centre", check_vector("centre", self.centre, subject))
        tensor = check_real("inertia", self.inertia, ParameterError, subject)
        if tensor.shape != (3, 3):
            raise ParameterError(
                f"inertia must be a 3 x 3 matrix, got shape {tensor.shape}",
                subject=subject,
                key="inertia",
            )
        check_finite("inertia", tensor, ParameterError, subject=subject)
        largest = float(np.abs(tensor).max())
        scale = max(largest, 1e-300)
        shift = math.ldexp(1.0, math.frexp(largest)[1] - 1) if largest > 1e300 else 1.0
        unit = tensor / shift  # exact (a power of 2), entries <= 2: no overflow near 1e308
        scale /= shift
        if float(np.abs(unit - unit.T).max()) > 1e-12:
            raise ParameterError("inertia must be symmetric", subject=subject, key="inertia")
        symmetric = 0.5 * (unit + unit.T)
        a, b, c = (float(v) for v in np.linalg.eigvalsh(symmetric))
        if a < -1e-12 * scale or c - a - b > 1e-12 * scale:
            raise ParameterError(
                f"inertia has principal moments {a * shift:.6g}, {b * shift:.6g}, "
                f"{c * shift:.6g}: not those of a "
                "body (each must be >= 0 and at most the sum of the other two)",
                subject=subject,
                key="inertia",
            )
        rows = [tuple(float(v) * shift for v in row) for row in symmetric]
        object.__setattr__(
            self,
            "inertia",
            ((rows[0][0], rows[0][1], rows[0][2]), (rows[1][0], rows[1][1], rows[1][2]),
             (rows[2][0], rows[2][1], rows[2][2])),
        )  # fmt: skip


def body_scale_checks_3d(prefix: str, body: Body, length: float, g: float) -> list[ScaleCheck]:
    """The overflow checks of a spatial body (keys ``prefix.mass``, ``prefix.inertia``).

    Those of :func:`prp3.model.parameters.body_scale_checks`, with the arm
    ``length + |centre|`` and the inertia's largest entry ``max|I_ij|``; the first names
    ``prefix.centre`` when the arm alone overflows.
    """
    largest = float(np.abs(np.array(body.inertia)).max())
    return body_scale_checks(
        prefix, body.mass, body.centre, largest, length, g, centre="centre",
        inertia_text=f"(largest entry {largest!r} kg·m²)",
    )  # fmt: skip


#: The components of a twist ``(ω, v)``, in order.
TWIST_COMPONENTS: tuple[str, ...] = ("wx", "wy", "wz", "vx", "vy", "vz")

#: The leg patterns whose inverse geometry is written in closed form (spatial.geometry).
PATTERNS: tuple[str, ...] = ("UPS", "RPS", "RUU")


@dataclass(frozen=True)
class Leg:
    """One leg: joints from the base to the platform, the bodies between them, the attachment.

    Parameters
    ----------
    joints : tuple of Joint
        ``n`` joints; the first placed in the world frame, joint ``k`` in body ``k − 1``'s frame.
    bodies : tuple of Body
        ``n − 1`` bodies; body ``k`` has the distal frame of joint ``k``.
    attachment_position, attachment_rotation
        The placement of the last joint's distal frame in the platform frame.
    actuated : int
        Index (0-based) of the actuated joint (an R or a P).
    """

    joints: tuple[Joint, ...]
    bodies: tuple[Body, ...]
    attachment_position: Vector
    attachment_rotation: Matrix = _IDENTITY
    actuated: int = 1

    def __post_init__(self) -> None:
        if len(self.bodies) != len(self.joints) - 1 or not self.joints:
            raise ParameterError(
                f"a leg of {len(self.joints)} joints has {len(self.joints) - 1} bodies, "
                f"got {len(self.bodies)}",
                subject="robot: leg",
                key="bodies",
            )
        object.__setattr__(
            self, "attachment_position", check_vector("attachment", self.attachment_position)
        )
        object.__setattr__(
            self,
            "attachment_rotation",
            check_rotation("attachment rotation", self.attachment_rotation),
        )
        if not 0 <= self.actuated < len(self.joints) or self.joints[self.actuated].dof != 1:
            raise ParameterError(
                f"actuated = {self.actuated!r} must name an R or P joint of the leg {self.pattern}",
                subject="robot: leg",
                key="actuated",
            )

    @property
    def pattern(self) -> str:
        """The joint types from base to platform (``"UPS"``)."""
        return "".join(joint.kind for joint in self.joints)

    @property
    def dof(self) -> int:
        """The leg's number of joint coordinates."""
        return sum(joint.dof for joint in self.joints)

    @property
    def labels(self) -> tuple[str, ...]:
        """The joints' labels: type and 1-based position (``U1``, ``P2``, ``S3``)."""
        return tuple(f"{joint.kind}{k + 1}" for k, joint in enumerate(self.joints))

    @property
    def coordinates(self) -> tuple[str, ...]:
        """The names of the leg's coordinates (``U1_a, U1_b, P2, S3_x, S3_y, S3_z``)."""
        return tuple(
            name
            for joint, label in zip(self.joints, self.labels, strict=True)
            for name in joint.coordinates(label)
        )

    @property
    def actuated_coordinate(self) -> int:
        """Index of the actuated coordinate among the leg's coordinates."""
        return sum(joint.dof for joint in self.joints[: self.actuated])


def _check_ups(index: int, leg: Leg) -> None:
    """The UPS and RPS legs' closed forms need the P's slide and the S centre on the
    cylinder's ``x`` axis."""
    slide, sphere = leg.joints[1], leg.joints[2]
    if (
        slide.rotation != _IDENTITY
        or slide.position[1:] != (0.0, 0.0)
        or sphere.position[1:] != (0.0, 0.0)
    ):
        raise ParameterError(
            f"leg {index + 1}: a {leg.pattern} leg needs the P joint's rotation to be the identity and "
            "the P and S positions on the x axis of their bodies (y = z = 0)",
            subject="robot",
            key="legs",
        )


#: ``Rot_x(−π/2)``: the placement of a RUU leg's second U in the forearm (its ``z`` on the
#: forearm's ``y``).
_Z_TO_Y: Matrix = ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0))


def _check_ruu(index: int, leg: Leg) -> None:
    """The RUU leg's closed form: the first U on the arm's ``x`` axis with the arm's axes (its
    first axis along the R's), the second U on the forearm's ``x`` axis placed by ``Rot_x(−π/2)``
    (its first axis along the first U's second)."""
    first, second = leg.joints[1], leg.joints[2]
    if (
        tuple(row[2] for row in first.rotation) != (0.0, 0.0, 1.0)
        or first.position[1:] != (0.0, 0.0)
        or second.rotation != _Z_TO_Y
        or second.position[1:] != (0.0, 0.0)
        or not second.position[0] > 0.0
    ):
        raise ParameterError(
            f"leg {index + 1}: a RUU leg needs its first U at (a, 0, 0) of the arm turned "
            "about the arm's z only (Rot_z(gamma)) and its second U at (l, 0, 0), l > 0, of the forearm with the "
            "rotation Rot_x(-pi/2)",
            subject="robot",
            key="legs",
        )


@dataclass(frozen=True)
class SpatialRobot:
    """A spatial parallel robot (docs/spatial.md §2): legs, platform, gravity, home pose, scale.

    Attributes
    ----------
    name : str
    legs : tuple of Leg
    platform : Body
        Its frame is the platform frame ``(p, R)``.
    gravity : three floats (m/s²)
    home_position, home_rotation
        The home pose (the sign of the singularity measures is taken there).
    scale : float
        The length ``ℓ`` of the dimensionless measures (m).
    """

    name: str
    legs: tuple[Leg, ...]
    platform: Body
    gravity: Vector = (0.0, 0.0, -9.81)
    home_position: Vector = (0.0, 0.0, 0.0)
    home_rotation: Matrix = _IDENTITY
    scale: float = 0.1
    parasitic: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.legs:
            raise ParameterError("a robot needs at least one leg", subject="robot", key="legs")
        for i, leg in enumerate(self.legs):
            if leg.pattern != self.legs[0].pattern or leg.actuated != self.legs[0].actuated:
                raise ParameterError(
                    f"leg {i + 1} is a {leg.pattern} actuated at joint {leg.actuated + 1}, leg 1 "
                    f"a {self.legs[0].pattern} actuated at joint {self.legs[0].actuated + 1}: "
                    "every leg has the same pattern and actuation",
                    subject="robot",
                    key="legs",
                )
            if leg.pattern not in PATTERNS:
                raise ParameterError(
                    f"leg {i + 1}: the pattern {leg.pattern} has no inverse geometry yet "
                    f"(known: {', '.join(PATTERNS)})",
                    subject="robot",
                    key="legs",
                )
            if leg.pattern == "RUU":
                _check_ruu(i, leg)
            else:
                _check_ups(i, leg)
        object.__setattr__(self, "gravity", check_vector("gravity", self.gravity))
        object.__setattr__(self, "home_position", check_vector("home", self.home_position))
        object.__setattr__(
            self, "home_rotation", check_rotation("home rotation", self.home_rotation)
        )
        scale = design_length("scale", self.scale)
        object.__setattr__(self, "scale", scale)
        if (
            len(self.parasitic) != 6 - len(self.legs)
            or len(set(self.parasitic)) != len(self.parasitic)
            or not set(self.parasitic) <= set(TWIST_COMPONENTS)
        ):
            raise ParameterError(
                f"parasitic must name the {6 - len(self.legs)} twist components of "
                f"{', '.join(TWIST_COMPONENTS)} that the legs' constraints determine, "
                f"got {self.parasitic!r}"[:200],
                subject="robot",
                key="parasitic",
            )

        self._check_scale()

    @cached_property
    def reach(self) -> float:
        """The longest chain from the world origin to the platform frame (m): over the legs,
        ``Σ|joint positions| + |attachment|``, plus ``|home|``; the arm of the overflow checks."""
        with np.errstate(over="ignore"):
            chains = [
                sum(float(np.linalg.norm(j.position)) for j in leg.joints)
                + float(np.linalg.norm(leg.attachment_position))
                for leg in self.legs
            ]
            return max(chains) + float(np.linalg.norm(self.home_position))

    def _check_scale(self) -> None:
        """Refuse bodies whose weight, inertia or moment of weight overflow float64."""
        g = max(float(np.abs(np.array(self.gravity)).max()), 1.0)
        checks = [gravity_scale_check(self.gravity, self.reach)] + [
            check for body in self.bodies
            for check in body_scale_checks_3d(body.name, body, self.reach, g)
        ]  # fmt: skip
        refuse_overflow(
            checks, f"(reach {self.reach:.6g} m, gravity = {list(self.gravity)!r} m/s²)"
        )

    @property
    def parasitic_index(self) -> tuple[int, ...]:
        """Indices in the twist ``(ω, v)`` of the components the constraints determine."""
        return tuple(TWIST_COMPONENTS.index(name) for name in self.parasitic)

    @property
    def dof(self) -> int:
        """The platform's degrees of freedom (the number of actuated joints)."""
        return len(self.legs)

    @cached_property
    def bodies(self) -> tuple[Body, ...]:
        """Every moving body: each leg's bodies in order, then the platform."""
        return (*(body for leg in self.legs for body in leg.bodies), self.platform)


def _frame(x_axis: FloatArray, up: FloatArray) -> Matrix:
    """The rotation with ``x`` along ``x_axis``, ``z`` along ``up × x`` (normalised), ``y = z × x``."""
    x = x_axis / np.linalg.norm(x_axis)
    z = cross(up, x)
    z = z / np.linalg.norm(z)
    y = cross(z, x)
    return check_rotation("joint rotation", np.stack([x, y, z], axis=1))


#: The largest length a default design takes (m): the squares of its lengths stay far from
#: float64's overflow and their round-off far below a micrometre's.
MAX_DESIGN_LENGTH: float = 1e6


def design_length(name: str, value: object) -> float:
    """A design length (a default design's, the scale): positive, finite, at most MAX_DESIGN_LENGTH (m)."""
    number = check_scalar(name, value, positive=True, unit="m", subject="robot")
    if number > MAX_DESIGN_LENGTH:
        raise ParameterError(
            f"{name} must be at most {MAX_DESIGN_LENGTH:g} m, got {number!r}",
            subject="robot",
            key=name,
        )
    return number


def _angle(name: str, value: object, *, limit: bool = False) -> float:
    """An angle of a default design (rad): within ``[-π, π]``, or in ``(0, π]`` for a limit."""
    number = check_scalar(name, value, positive=limit, unit="rad", subject="robot")
    if abs(number) > math.pi:
        raise ParameterError(
            f"{name} must be at most pi rad in magnitude, got {number!r}",
            subject="robot",
            key=name,
        )
    return number


def _stroke(value: ArrayLike) -> tuple[float, float]:
    """The P stroke of a default design: two lengths (m), the first below the second."""
    array = check_real("stroke", value, ParameterError, "robot")
    if array.shape != (2,):
        raise ParameterError(
            f"stroke must be two lengths (shortest, longest) in m, got shape {array.shape}",
            subject="robot",
            key="stroke",
        )
    low, high = (design_length(f"stroke[{i}]", float(v)) for i, v in enumerate(array))
    if not low < high:
        raise ParameterError(
            f"stroke must be (shortest, longest) with shortest < longest, got ({low!r}, {high!r})",
            subject="robot",
            key="stroke",
        )
    return (low, high)


def _body(name: str, value: object, default: Body) -> Body:
    """A body of a default design: a :class:`Body`, or ``None`` for the default."""
    if value is None:
        return default
    if not isinstance(value, Body):
        raise ParameterError(
            f"{name} must be a prp3 spatial Body or None, got {value!r} ({type(value).__name__})",
            subject="robot",
            key=name,
        )
    return value


def _cylinder() -> Body:
    """The default cylinder of a UPS or RPS leg (docs/spatial.md §7)."""
    return Body(0.12, (0.025, 0.0, 0.0),
                ((8.64e-6, 0, 0), (0, 4.032e-5, 0), (0, 0, 4.032e-5)), "cylinder")  # fmt: skip


def _rod() -> Body:
    """The default rod of a UPS or RPS leg (docs/spatial.md §7)."""
    return Body(0.05, (-0.03, 0.0, 0.0),
                ((6.25e-7, 0, 0), (0, 1.53125e-5, 0), (0, 0, 1.53125e-5)), "rod")  # fmt: skip


def hexapod(
    *,
    base_radius: float = 0.1,
    platform_radius: float = 0.07,
    base_half_angle: float = math.radians(10.0),
    platform_half_angle: float = math.radians(50.0),
    home_height: float = 0.08,
    stroke: tuple[float, float] = (0.085, 0.12),
    u_limit: float = math.pi / 3,
    s_limit: float = math.pi / 3,
    cylinder: Body | None = None,
    rod: Body | None = None,
    platform: Body | None = None,
    gravity: Vector = (0.0, 0.0, -9.81),
    scale: float = 0.1,
) -> SpatialRobot:
    """The 6-UPS Stewart–Gough hexapod of docs/spatial.md §7 (defaults: a precision positioner).

    Parameters
    ----------
    base_radius, platform_radius : float
        Radii of the circles of the U and S centres (m).
    base_half_angle, platform_half_angle : float
        Legs ``2k + 1, 2k + 2`` start at ``120°k ∓ base_half_angle`` and end at
        ``120°k ∓ platform_half_angle`` (rad).
    home_height : float
        Height of the platform origin at home (m); home orientation ``I``.
    stroke : (float, float)
        Limits of every P length (m).
    u_limit, s_limit : float
        Limits of each U angle (``±``) and of the S rotation angle (rad).
    cylinder, rod, platform : Body, optional
        The bodies (each leg's cylinder and rod alike); the defaults of §7.
    gravity : three floats
    scale : float
        ``ℓ`` of the measures (m).
    """
    r_b = design_length("base_radius", base_radius)
    r_p = design_length("platform_radius", platform_radius)
    h = design_length("home_height", home_height)
    half_b = _angle("base_half_angle", base_half_angle)
    half_p = _angle("platform_half_angle", platform_half_angle)
    stroke = _stroke(stroke)
    u_limit = _angle("u_limit", u_limit, limit=True)
    s_limit = _angle("s_limit", s_limit, limit=True)
    cylinder = _body("cylinder", cylinder, _cylinder())
    rod = _body("rod", rod, _rod())
    platform = _body("platform", platform, Body(1.0, (0.0, 0.0, 0.0),
                                ((1.225e-3, 0, 0), (0, 1.225e-3, 0), (0, 0, 2.45e-3)), "platform"))  # fmt: skip
    legs = []
    up = np.array([0.0, 0.0, 1.0])
    home = np.array([0.0, 0.0, h])
    for i in range(6):
        k, sign = divmod(i, 2)
        side = -1.0 if sign == 0 else 1.0
        theta_b = 2.0 * math.pi * k / 3.0 + side * half_b
        theta_p = 2.0 * math.pi * k / 3.0 + side * half_p
        base = np.array([r_b * math.cos(theta_b), r_b * math.sin(theta_b), 0.0])
        attach = np.array([r_p * math.cos(theta_p), r_p * math.sin(theta_p), 0.0])
        u_rotation = _frame(home + attach - base, up)
        joints = (
            Joint("U", tuple(base), u_rotation, ((-u_limit, u_limit), (-u_limit, u_limit))),
            Joint("P", (0.0, 0.0, 0.0), limits=(stroke,)),
            Joint("S", (0.0, 0.0, 0.0), limits=((0.0, s_limit),)),
        )
        # φ = 0 at home: R_A = R_homeᵀ·(rod frame at home) = the U's joint frame
        legs.append(Leg(joints, (cylinder, rod), tuple(attach), u_rotation, actuated=1))
    return SpatialRobot(
        "6-UPS", tuple(legs), platform, gravity, (0.0, 0.0, h), _IDENTITY, scale,
    )  # fmt: skip


def three_rps(
    *,
    base_radius: float = 0.1,
    platform_radius: float = 0.06,
    home_height: float = 0.1,
    stroke: tuple[float, float] = (0.06, 0.18),
    r_limit: float = math.pi / 2,
    s_limit: float = math.pi / 3,
    cylinder: Body | None = None,
    rod: Body | None = None,
    platform: Body | None = None,
    gravity: Vector = (0.0, 0.0, -9.81),
    scale: float = 0.1,
) -> SpatialRobot:
    """The 3-RPS of docs/spatial.md §11: R at the base (axis tangent to the base circle), P
    actuated, S at the platform; legs at ``90°, 210°, 330°``; 3 DOF (``v_z, ω_x, ω_y`` free,
    ``ω_z, v_x, v_y`` parasitic).

    Parameters as :func:`hexapod`; ``r_limit`` bounds each R angle (``±``, rad).
    """
    r_b = design_length("base_radius", base_radius)
    r_p = design_length("platform_radius", platform_radius)
    h = design_length("home_height", home_height)
    stroke = _stroke(stroke)
    r_limit = _angle("r_limit", r_limit, limit=True)
    s_limit = _angle("s_limit", s_limit, limit=True)
    cylinder = _body("cylinder", cylinder, _cylinder())
    rod = _body("rod", rod, _rod())
    platform = _body("platform", platform, Body(1.0, (0.0, 0.0, 0.0),
                                ((9e-4, 0, 0), (0, 9e-4, 0), (0, 0, 1.8e-3)), "platform"))  # fmt: skip
    legs = []
    for i in range(3):
        angle = math.pi / 2 + 2.0 * math.pi * i / 3.0
        radial = np.array([math.cos(angle), math.sin(angle), 0.0])
        tangent = np.array([-math.sin(angle), math.cos(angle), 0.0])
        base, attach = r_b * radial, r_p * radial
        x = np.array([0.0, 0.0, h]) + attach - base
        x = x / np.linalg.norm(x)
        r_rotation = check_rotation("joint rotation", np.stack([x, cross(tangent, x), tangent], 1))
        joints = (
            Joint("R", tuple(base), r_rotation, ((-r_limit, r_limit),)),
            Joint("P", (0.0, 0.0, 0.0), limits=(stroke,)),
            Joint("S", (0.0, 0.0, 0.0), limits=((0.0, s_limit),)),
        )
        legs.append(Leg(joints, (cylinder, rod), tuple(attach), r_rotation, actuated=1))
    return SpatialRobot(
        "3-RPS", tuple(legs), platform, gravity, (0.0, 0.0, h), _IDENTITY, scale,
        ("wz", "vx", "vy"),
    )  # fmt: skip


def _delta_leg(
    i: int,
    lengths: tuple[float, float, float, float, float],
    r_limit: float,
    u_limit: float,
    arm_body: Body,
    forearm_body: Body,
) -> Leg:
    """Leg ``i`` of :func:`delta` (at ``−90° + 120°·i``); ``lengths``: ``base_radius, arm,
    forearm, platform_radius, home_height`` (m)."""
    r_b, l_a, l_f, r_p, h = lengths
    angle = -math.pi / 2 + 2.0 * math.pi * i / 3.0
    radial = np.array([math.cos(angle), math.sin(angle), 0.0])
    tangent = np.array([-math.sin(angle), math.cos(angle), 0.0])
    r_rotation = check_rotation(
        "joint rotation", np.stack([radial, cross(tangent, radial), tangent], axis=1)
    )
    # home: the arm's angle solves |c2 − c_R − l_a·u(θ)| = l_f in the leg's plane
    d_x, d_z = r_p - r_b, -h  # c2 − c_R: radial and vertical parts
    k = (d_x * d_x + d_z * d_z + l_a * l_a - l_f * l_f) / (2.0 * l_a)
    a, b = d_x, -d_z  # D·u(θ) = a cos θ + b sin θ (u = cos θ·radial − sin θ·e_z)
    if not abs(k) < math.hypot(a, b):
        raise ParameterError(
            f"the home pose (0, 0, -{h:g}) m is out of reach of an arm of {l_a:g} m and a "
            f"forearm of {l_f:g} m from the base radius {r_b:g} m",
            subject="robot",
            key="home_height",
        )
    theta = math.atan2(b, a) - math.acos(k / math.hypot(a, b))
    elbow = r_b * radial + l_a * (
        math.cos(theta) * radial - math.sin(theta) * np.array([0, 0, 1.0])
    )
    f = (np.array([0.0, 0.0, -h]) + r_p * radial - elbow) / l_f
    arm_x = math.cos(theta) * radial - math.sin(theta) * np.array([0.0, 0.0, 1.0])
    gamma = math.atan2(float(f @ cross(tangent, arm_x)), float(f @ arm_x))
    fore_x = f
    fore_y = cross(tangent, fore_x)
    # the second U's joint frame at home: the forearm's frame turned by Rot_x(−π/2)
    forearm_frame = np.stack([fore_x, fore_y, tangent], axis=1)
    attach_rotation = check_rotation("attachment rotation", forearm_frame @ np.array(_Z_TO_Y))
    joints = (
        Joint("R", tuple(r_b * radial), r_rotation, ((-r_limit, r_limit),)),
        Joint(
            "U",
            (l_a, 0.0, 0.0),
            check_rotation("joint rotation", axis_rotation(2, gamma)),
            ((-u_limit, u_limit), (-u_limit, u_limit)),
        ),
        Joint("U", (l_f, 0.0, 0.0), _Z_TO_Y, ((-u_limit, u_limit), (-u_limit, u_limit))),
    )
    return Leg(joints, (arm_body, forearm_body), tuple(r_p * radial), attach_rotation, 0)


def delta(
    *,
    base_radius: float = 0.1,
    arm: float = 0.1,
    forearm: float = 0.25,
    platform_radius: float = 0.03,
    home_height: float = 0.2,
    r_limit: float = math.pi / 2,
    u_limit: float = math.pi / 2 - 0.1,
    arm_body: Body | None = None,
    forearm_body: Body | None = None,
    platform: Body | None = None,
    gravity: Vector = (0.0, 0.0, -9.81),
    scale: float = 0.1,
) -> SpatialRobot:
    """The Delta as a 3-RUU (docs/spatial.md §12): R actuated at the base (axis tangent), the
    parallelogram simplified to one forearm between two U joints; legs at ``−90°, 30°, 150°``;
    the platform translates (``wx, wy, wz`` parasitic).

    Parameters
    ----------
    base_radius, arm, forearm, platform_radius : float
        The R centres' radius, the arm's and the forearm's lengths, the second U centres'
        radius on the platform (m).
    home_height : float
        The platform origin is at ``(0, 0, −home_height)`` at home (m).
    r_limit, u_limit : float
        Limits of the R angle and of each U angle (``±``, rad).
    arm_body, forearm_body, platform : Body, optional
    gravity, scale
    """
    r_b = design_length("base_radius", base_radius)
    l_a = design_length("arm", arm)
    l_f = design_length("forearm", forearm)
    r_p = design_length("platform_radius", platform_radius)
    h = design_length("home_height", home_height)
    r_limit = _angle("r_limit", r_limit, limit=True)
    u_limit = _angle("u_limit", u_limit, limit=True)
    arm_body = _body("arm_body", arm_body, Body(0.1, (l_a / 2, 0.0, 0.0),
                                ((2e-6, 0, 0), (0, 8.5e-5, 0), (0, 0, 8.5e-5)), "arm"))  # fmt: skip
    forearm_body = _body("forearm_body", forearm_body, Body(0.06, (l_f / 2, 0.0, 0.0),
                                        ((1e-6, 0, 0), (0, 3.1e-4, 0), (0, 0, 3.1e-4)), "forearm"))  # fmt: skip
    platform = _body("platform", platform, Body(0.2, (0.0, 0.0, 0.0),
                                ((4.5e-5, 0, 0), (0, 4.5e-5, 0), (0, 0, 9e-5)), "platform"))  # fmt: skip
    lengths = (r_b, l_a, l_f, r_p, h)
    legs = [_delta_leg(i, lengths, r_limit, u_limit, arm_body, forearm_body) for i in range(3)]
    return SpatialRobot(
        "3-RUU", tuple(legs), platform, gravity, (0.0, 0.0, -h), _IDENTITY, scale,
        ("wx", "wy", "wz"),
    )  # fmt: skip
