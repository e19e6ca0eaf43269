"""Inverse geometry of the 3-PRP robot (paper eqs. 1, 7–10).

Conventions (``docs/model.md``): fixed frame ``O x0 y0``, legs ``i = A, B, C`` with
``α = (π/3, π, −π/3)`` (eq. 1), actuator axis ``e_i = (cos α_i, sin α_i)``,
normal ``n_i = (−sin α_i, cos α_i)``, revolute joint centre
``P_i = B_i0 + (l0/√3 + λ10_i)·e_i`` and platform edge direction
``d_i = (cos β_i, sin β_i)``, ``β_i = α_i + φ − π/3``.  The closure (eq. 10)

    G = P_i + λ32_i·d_i + Rot(α_i + φ)·c,    c = (l0/2)·(1/√3, 1),

is, per leg, the 2×2 linear system ``[e_i d_i]·[l0/√3 + λ10_i, λ32_i]ᵀ = r_i``
with ``r_i = G − B_i0 − Rot(α_i + φ)·c``, solved in closed form by the kernel
(:func:`prp3.mechanics.joint_motion.kernel_geometry`); this module adds the vectors of each leg.  Its
determinant ``e_i × d_i = sin(φ − π/3)`` is the same for the three legs: the
robot is singular at ``φ ≡ π/3 (mod π)``.  Poses with
``|sin(φ − π/3)| < SINGULARITY_THRESHOLD`` are refused.

The forward geometry in closed form (:func:`forward_geometry`).
Per leg, with ``s_i = l0/√3 + λ10_i``, the closure (eq. 10)
``G − B_i0 − s_i·e_i − Rot(α_i+φ)·c = λ32_i·d_i`` crossed with ``d_i`` removes
the passive ``λ32_i``:

    G × d_i = B_i0 × d_i + s_i·(e_i × d_i) + Rot(α_i+φ)c × d_i
            = l0·cos φ + s_i·sin(φ − π/3) − l0/2                      (i)

(``B_i0 × d_i = l0·cos φ`` and ``Rot(α_i+φ)c × d_i = c × u(−π/3) = −l0/2``
for the three legs).  The three ``d_i`` are unit vectors 120° apart, so
``Σ d_i = 0`` and the sum of (i) eliminates ``G``:
``3·l0·cos φ + Σs_i·sin(φ − π/3) − 3·l0/2 = 0``.  With ``ψ = φ − π/3`` this
factors as

    2·sin(ψ/2)·[(Σs_i − 3√3·l0/2)·cos(ψ/2) − (3·l0/2)·sin(ψ/2)] = 0,

so either ``ψ = 0`` (the singular orientation, see below) or

    tan(ψ/2) = 2·Σλ10/(3·l0) − 1/√3,      φ = π/3 + 2·atan(…)        (ii)

— one orientation per 2π, in closed form (no iteration, nothing to miss).  With
``d⊥_i = J·d_i``, ``G × d_i = −d⊥_i·G`` and ``Σ d⊥_i d⊥_iᵀ = (3/2)·1``, the
three equations (i) give

    G = −(2/3)·sin(φ − π/3)·Σ_i λ10_i·d⊥_i                              (iii)

Assembly modes.  For every ``λ10`` there is exactly one regular assembly (ii,
iii).  Its *aspect* — the sign of ``sin(φ − π/3)`` — is ``−1`` when
``Σλ10 < √3·l0/2`` (the aspect of the central configuration) and ``+1`` above.
Besides it, the singular pose ``(0, 0, π/3)`` — the platform triangle lying on
the base triangle, every sleeve on its actuator's line — assembles for *every*
``λ10`` (:data:`DEGENERATE_ASSEMBLY`): it is the root ``ψ = 0`` of the factored
equation; it is not a pose prp3 computes with (``|sin(φ − π/3)| = 0``).

Array conventions: a pose is ``(..., 3)`` = ``(x, y, φ)``; per-leg scalars are
``(..., 3)`` (legs A, B, C on the last axis); per-leg plane vectors are
``(..., 3, 2)``.  A single pose ``(3,)`` gives per-leg arrays ``(3,)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.mechanics.joint_motion import kernel_geometry
from prp3.mechanics.ops import NUMPY
from prp3.mechanics.parameters import kernel_parameters
from prp3.model.parameters import Limits
from prp3.model.robot import Robot
from prp3.pose_validation import POSE_BOUND, SINGULARITY_THRESHOLD, check_poses, singularity_measure
from prp3.validation import (
    LEGS,
    check_finite,
    check_per_leg,
    check_real,
    check_robot,
    check_scalar,
    require_finite,
)

__all__ = [
    "ALPHA",
    "DEGENERATE_ASSEMBLY",
    "LEG_AXIS",
    "LEG_NORMAL",
    "ForwardGeometry",
    "InverseGeometry",
    "base_vertices",
    "check_stroke",
    "cross2",
    "dot2",
    "forward_geometry",
    "inverse_geometry",
    "orientation_from_sum",
    "perp",
    "platform_vertices",
    "sum_from_orientation",
]

FloatArray = NDArray[np.float64]

#: Orientation angles ``α_i`` of the base edges (eq. 1), rad.
ALPHA: FloatArray = np.array([math.pi / 3.0, math.pi, -math.pi / 3.0])
ALPHA.flags.writeable = False

#: Actuator axes ``e_i = (cos α_i, sin α_i)``, shape (3, 2).
LEG_AXIS: FloatArray = np.stack([np.cos(ALPHA), np.sin(ALPHA)], axis=-1)
LEG_AXIS.flags.writeable = False

#: Normals ``n_i = (−sin α_i, cos α_i)`` of the actuator axes, shape (3, 2).
LEG_NORMAL: FloatArray = np.stack([-np.sin(ALPHA), np.cos(ALPHA)], axis=-1)
LEG_NORMAL.flags.writeable = False


def cross2(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Scalar cross product ``a × b = a_x b_y − a_y b_x`` of plane vectors ``(..., 2)``.

    >>> float(cross2([1.0, 0.0], [0.0, 1.0]))
    1.0
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def dot2(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Dot product of plane vectors ``(..., 2)`` over the last axis.

    >>> float(dot2([1.0, 2.0], [3.0, 4.0]))
    11.0
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return np.asarray(a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1])


def perp(a: ArrayLike) -> FloatArray:
    """Rotate plane vectors ``(..., 2)`` by +90°: ``J·a = (−a_y, a_x)`` (``ũ3`` of eq. 9).

    >>> perp([1.0, 0.0]).tolist()
    [-0.0, 1.0]
    """
    a = np.asarray(a, dtype=np.float64)
    return np.stack([-a[..., 1], a[..., 0]], axis=-1)


def _unit(angle: FloatArray) -> FloatArray:
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def base_vertices(robot: Robot) -> FloatArray:
    """Base vertices ``A0, B0, C0`` (eq. 9, ``r00^i``), shape (3, 2), m.

    >>> base_vertices(Robot()).round(4).tolist()
    [[0.0, -0.3], [0.2598, 0.15], [-0.2598, 0.15]]
    """
    s3 = math.sqrt(3.0)
    return check_robot(robot).l0 * np.array([[0.0, -1.0], [s3 / 2.0, 0.5], [-s3 / 2.0, 0.5]])


def platform_vertices(robot: Robot, pose: ArrayLike) -> FloatArray:
    """Vertices of the platform triangle for poses ``(..., 3)``, shape ``(..., 3, 2)``.

    The platform edge of leg ``i`` lies on the line through ``P_i`` along
    ``d_i``; at the central configuration the platform is the base triangle
    turned by 180° (vertices at angles 90°, 210°, 330° at distance ``l0``).

    >>> platform_vertices(Robot(), [0.0, 0.0, 0.0]).round(4).tolist()
    [[0.0, 0.3], [-0.2598, -0.15], [0.2598, -0.15]]
    """
    check_robot(robot)
    pose = check_real("pose", pose)
    if pose.ndim < 1 or pose.shape[-1] != 3 or pose.size == 0:
        raise TrajectoryError(f"pose must have shape (..., 3), got {pose.shape}")
    check_poses(pose.reshape(-1, 3) if pose.ndim > 1 else pose, robot, singular=False)
    angles = np.array([math.pi / 2.0, 7.0 * math.pi / 6.0, 11.0 * math.pi / 6.0])
    corner = robot.l0 * _unit(pose[..., None, 2] + angles)
    return np.asarray(pose[..., None, :2] + corner)


@dataclass(frozen=True)
class InverseGeometry:
    """Joint displacements and leg geometry for a batch of poses.

    All per-leg arrays have shape ``(..., 3)`` (legs A, B, C last) and
    per-leg vectors ``(..., 3, 2)``, where ``...`` is the batch shape of the
    poses (``()`` for one pose, ``(N,)`` for N samples).

    Attributes
    ----------
    pose : ndarray (..., 3)
        Platform poses ``(x, y, φ)`` (m, m, rad).
    lambda10 : ndarray (..., 3)
        Actuator displacements ``λ10`` (m), eq. (10).
    lambda32 : ndarray (..., 3)
        Passive displacements ``λ32`` of the platform in the sleeves (m), eq. (10).
    phi21 : ndarray (..., 3)
        Rotations ``φ21`` of the links relative to the pistons (rad), eq. (7).
    joint : ndarray (..., 3, 2)
        Revolute joint centres ``P_i`` (m).
    slide : ndarray (..., 3, 2)
        Platform edge directions ``d_i`` (unit).
    slide_normal : ndarray (..., 3, 2)
        ``d⊥_i = J·d_i`` (unit).
    lever : ndarray (..., 3, 2)
        ``ρ_i = G − P_i = λ32_i·d_i + Rot(α_i + φ)·c`` (m).
    determinant : ndarray (...)
        ``D = sin(φ − π/3)``, the determinant of every leg's system.
    """

    pose: FloatArray
    lambda10: FloatArray
    lambda32: FloatArray
    phi21: FloatArray
    joint: FloatArray
    slide: FloatArray
    slide_normal: FloatArray
    lever: FloatArray
    determinant: FloatArray


def inverse_geometry(robot: Robot, pose: ArrayLike) -> InverseGeometry:
    """Solve the inverse geometric problem (eqs. 7–10) for poses ``(..., 3)``.

    Parameters
    ----------
    robot : Robot
        Robot parameters (only ``l0`` and ``limits.stroke`` are used).
    pose : array_like, shape (3,) or (N, 3)
        Platform poses ``(x, y, φ)``: mass centre ``G`` (m) and orientation (rad).

    Returns
    -------
    InverseGeometry
        Implements eq. (7) (``φ21 = φ``) and eq. (10) solved by Cramer's rule.

    Raises
    ------
    SingularPoseError
        If a pose is at or near ``φ ≡ π/3 (mod π)``.
    UnreachablePoseError
        If ``robot.limits.stroke`` is set and some ``λ10`` falls outside it.

    Examples
    --------
    >>> geo = inverse_geometry(Robot(), [0.0, 0.0, 0.0])   # central configuration
    >>> bool(np.abs(geo.lambda10).max() < 1e-15), bool(np.abs(geo.lambda32).max() < 1e-15)
    (True, True)
    >>> inverse_geometry(Robot(), [[0.0, 0.05, 0.0]]).lambda10.shape
    (1, 3)
    """
    check_robot(robot)
    pose = check_poses(pose, robot)
    with np.errstate(over="ignore", invalid="ignore"):
        geometry = _inverse_geometry(robot, pose)
    require_finite(
        {"lambda10": geometry.lambda10, "lambda32": geometry.lambda32},
        pose.shape[:-1],
        "pose",
    )
    check_stroke(robot, geometry.lambda10, pose)
    return geometry


def _inverse_geometry(robot: Robot, pose: FloatArray) -> InverseGeometry:
    l0 = robot.l0
    x, y, phi = pose[..., 0], pose[..., 1], pose[..., 2]
    # eq. (10) in closed form: the kernel's, the one place it is written
    closed = kernel_geometry(NUMPY, kernel_parameters(robot), x, y, phi)
    lambda10 = np.stack(closed.lambda10, axis=-1)
    lambda32 = np.stack(closed.lambda32, axis=-1)
    theta = ALPHA + phi[..., None]  # α_i + φ, (..., 3)
    d = _unit(theta - math.pi / 3.0)  # d_i, eq. (9) q32ᵀu3 in the fixed frame
    joint = base_vertices(robot) + (l0 / math.sqrt(3.0) + lambda10)[..., None] * LEG_AXIS  # P_i
    lever = pose[..., None, :2] - joint  # ρ_i = G − P_i
    phi21 = np.broadcast_to(phi[..., None], lambda10.shape).copy()  # eq. (7)
    return InverseGeometry(
        pose=pose,
        lambda10=lambda10,
        lambda32=lambda32,
        phi21=phi21,
        joint=joint,
        slide=d,
        slide_normal=perp(d),
        lever=lever,
        determinant=np.asarray(closed.D, dtype=np.float64),
    )


def check_stroke(robot: Robot, lambda10: FloatArray, pose: FloatArray | None = None) -> None:
    """Refuse actuator displacements ``(..., 3)`` outside ``robot.limits.stroke``.

    The message names the first sample, the leg and the value, and the pose
    when ``pose`` is given.  A NaN displacement lies in no stroke: it is refused
    too (``not lower <= λ <= upper``), never let through by a comparison.

    >>> from prp3.model.parameters import Limits
    >>> check_stroke(Robot(limits=Limits(stroke=(-0.1, 0.1))), np.array([0.0, 0.2, 0.0]))
    Traceback (most recent call last):
    ...
    prp3.errors.UnreachablePoseError: lambda10: lambda10_B = 0.2 m is outside the stroke [-0.1, 0.1] m
    """
    stroke = robot.limits.stroke
    if stroke is None:
        return
    lower, upper = stroke
    flat = lambda10.reshape(-1, 3)
    outside = ~((flat >= lower) & (flat <= upper))
    if not outside.any():
        return
    index, leg = np.argwhere(outside)[0].tolist()
    found = float(flat[index, leg])
    value = (
        f"lambda10_{LEGS[leg]} = {found!r} m is outside the stroke [{lower!r}, {upper!r}] m"
        if not math.isnan(found)
        else f"lambda10_{LEGS[leg]} is not a number, so not within the stroke "
        f"[{lower!r}, {upper!r}] m"
    )
    sample = index if lambda10.ndim >= 2 else None
    if pose is None:
        raise UnreachablePoseError(value, subject="lambda10", sample=sample, leg=LEGS[leg])
    x, y, phi = pose.reshape(-1, 3)[index].tolist()
    raise UnreachablePoseError(
        f"unreachable pose (x={x!r}, y={y!r}, phi={phi!r}): {value}",
        subject="pose",
        sample=sample,
        leg=LEGS[leg],
        pose=(x, y, phi),
    )


#: The singular pose ``(x, y, φ) = (0, 0, π/3)`` that assembles for every ``λ10``.
DEGENERATE_ASSEMBLY: tuple[float, float, float] = (0.0, 0.0, math.pi / 3.0)

_SQRT3 = math.sqrt(3.0)


def _free(robot: Robot) -> Robot:
    """The same robot without stroke or force limits (the forward geometry checks them itself)."""
    return robot if robot.limits == Limits() else replace(robot, limits=Limits())


# ------------------------------------------------------------ forward geometry
def orientation_from_sum(l0: float, sum_lambda10: ArrayLike) -> FloatArray:
    """Platform orientation ``φ`` from ``Σλ10``, eq. (ii) of the module notes.

    ``φ = π/3 + 2·atan(2·Σλ10/(3·l0) − 1/√3)``, wrapped to ``(−π, π]`` (rad).
    The orientation depends on the sum of the three actuator displacements
    only; ``Σλ10 = √3·l0/2`` gives the singular orientation ``π/3``.

    Parameters
    ----------
    l0 : float
        Circumradius of the triangles (m).
    sum_lambda10 : array_like, shape (...)
        ``λ10_A + λ10_B + λ10_C`` (m).

    Returns
    -------
    ndarray, shape (...)
        ``φ`` (rad).

    >>> round(float(orientation_from_sum(0.3, 0.0)), 15)   # central configuration
    0.0
    """
    l0 = check_scalar("l0", l0, positive=True)
    total = check_real("sum_lambda10", sum_lambda10)
    check_finite("sum_lambda10", total.reshape(-1, 1), components=("sum_lambda10",))
    with np.errstate(over="ignore"):  # a huge sum: atan(±inf) = ±π/2, the exact limit
        psi = 2.0 * np.arctan(2.0 * total / (3.0 * l0) - 1.0 / _SQRT3)  # (ii), ψ in (−π, π)
    phi = math.pi / 3.0 + psi  # in (−2π/3, 4π/3)
    return np.asarray(np.where(phi > math.pi, phi - 2.0 * math.pi, phi))


def sum_from_orientation(l0: float, phi: ArrayLike) -> FloatArray:
    """``Σλ10 = (3·l0/2)·(tan((φ − π/3)/2) + 1/√3)``, the inverse of :func:`orientation_from_sum`.

    Infinite at ``φ ≡ −2π/3 (mod 2π)``, the other singular orientation.

    >>> round(float(sum_from_orientation(0.3, math.pi / 3.0)), 12)   # √3·l0/2
    0.259807621135
    """
    l0 = check_scalar("l0", l0, positive=True)
    phi = check_real("phi", phi)
    check_finite("phi", phi.reshape(-1, 1), components=("phi",))
    return np.asarray(1.5 * l0 * (np.tan((phi - math.pi / 3.0) / 2.0) + 1.0 / _SQRT3))


@dataclass(frozen=True)
class ForwardGeometry:
    """The regular assembly of the platform for given actuator displacements.

    Shapes follow the input: ``...`` is ``()`` for one sample ``(3,)``, ``(N,)``
    for ``(N, 3)``.

    Attributes
    ----------
    lambda10 : ndarray (..., 3)
        The given actuator displacements (m).
    pose : ndarray (..., 3)
        ``(x, y, φ)`` of the regular assembly (m, m, rad), ``φ`` in ``(−π, π]``.
    aspect : ndarray of int (...)
        Assembly mode: the sign of ``sin(φ − π/3)``; ``−1`` for
        ``Σλ10 < √3·l0/2`` (the aspect of the central configuration), ``+1``
        above.  (The singular :data:`DEGENERATE_ASSEMBLY` also assembles; it
        is not listed.)
    geometry : InverseGeometry
        Inverse geometry of :attr:`pose` (``λ32``, joints, levers, ...); its
        ``lambda10`` reproduces the input to round-off.
    """

    lambda10: FloatArray
    pose: FloatArray
    aspect: NDArray[np.int64]
    geometry: InverseGeometry


def forward_geometry(robot: Robot, lambda10: ArrayLike) -> ForwardGeometry:
    """Solve the forward geometric problem in closed form: ``λ10`` → ``(x, y, φ)``.

    Parameters
    ----------
    robot : Robot
        Robot parameters (``l0`` and ``limits.stroke`` are used).
    lambda10 : array_like, shape (3,) or (N, 3)
        Actuator displacements ``λ10_A, λ10_B, λ10_C`` (m).

    Returns
    -------
    ForwardGeometry
        The unique regular assembly: ``φ`` from eq. (ii), ``G`` from eq. (iii)
        of the module notes (both from the closure, eq. 10).

    Raises
    ------
    TrajectoryError
        Wrong shape or non-finite value.
    UnreachablePoseError
        A displacement outside ``robot.limits.stroke`` (names sample and leg).
    SingularPoseError
        The assembly is singular, ``|sin(φ − π/3)| < 1e-4`` (``Σλ10`` within
        about ``1e-4·l0`` of ``√3·l0/2``).

    Examples
    --------
    >>> robot = Robot()
    >>> lam = inverse_geometry(robot, [0.01, -0.02, 0.1]).lambda10
    >>> solution = forward_geometry(robot, lam)
    >>> solution.pose.round(12).tolist(), int(solution.aspect)
    ([0.01, -0.02, 0.1], -1)
    """
    check_robot(robot)
    lam = check_per_leg("lambda10", lambda10)
    reach = POSE_BOUND * robot.l0 / SINGULARITY_THRESHOLD  # beyond: no pose within the bounds
    far = np.abs(lam) > reach
    if far.any():
        index, leg = np.argwhere(far.reshape(-1, 3))[0].tolist()
        raise TrajectoryError(
            f"|lambda10_{LEGS[leg]}| = {abs(float(lam.reshape(-1, 3)[index, leg]))!r} m is beyond "
            f"{POSE_BOUND:g}*l0/{SINGULARITY_THRESHOLD:g} = {reach:g} m (l0 = {robot.l0:g} m): "
            "no pose within the bounds assembles",
            subject="lambda10",
            sample=index if lam.ndim == 2 else None,
            leg=LEGS[leg],
        )
    check_stroke(robot, lam)
    l0 = robot.l0
    total = lam.sum(axis=-1)
    phi = orientation_from_sum(l0, total)  # eq. (ii)
    D = singularity_measure(phi)  # sin(φ − π/3)
    near = np.abs(D.reshape(-1)) < SINGULARITY_THRESHOLD
    if near.any():
        index = int(np.argmax(near))
        raise SingularPoseError(
            f"lambda10: sample {index} {lam.reshape(-1, 3)[index].tolist()!r} assembles only "
            f"at a singular pose (phi = {float(phi.reshape(-1)[index])!r}, "
            f"|sin(phi - pi/3)| = {abs(float(D.reshape(-1)[index])):.3g} < "
            f"{SINGULARITY_THRESHOLD:g}): sum of lambda10 = {float(total.reshape(-1)[index])!r} m "
            f"is at the singular value sqrt(3)*l0/2 = {_SQRT3 * l0 / 2.0!r} m"
        )
    theta = np.asarray(phi)[..., None] + np.array([math.pi / 3.0, math.pi, -math.pi / 3.0])
    d_perp = perp(np.stack([np.cos(theta - math.pi / 3.0), np.sin(theta - math.pi / 3.0)], -1))
    G = -(2.0 / 3.0) * D[..., None] * (lam[..., None] * d_perp).sum(axis=-2)  # eq. (iii)
    pose = np.concatenate([G, np.asarray(phi)[..., None]], axis=-1)
    return ForwardGeometry(
        lambda10=lam,
        pose=pose,
        aspect=np.sign(D).astype(np.int64),
        geometry=inverse_geometry(_free(robot), pose),
    )
