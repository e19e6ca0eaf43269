"""Inverse geometry of the 3-PRP robot (paper eqs. 1, 7–10).

Conventions (``docs/model.md``): fixed frame ``O x0 y0``, legs ``i = A, B, C`` with
``α = (π/3, π, −π/3)`` (eq. 1), actuator axis ``e_i = (cos α_i, sin α_i)``,
normal ``n_i = (−sin α_i, cos α_i)``, revolute joint centre
``P_i = B_i0 + (l0/√3 + λ10_i)·e_i`` and platform edge direction
``d_i = (cos β_i, sin β_i)``, ``β_i = α_i + φ − π/3``.  The closure (eq. 10)

    G = P_i + λ32_i·d_i + Rot(α_i + φ)·c,    c = (l0/2)·(1/√3, 1),

is, per leg, the 2×2 linear system ``[e_i d_i]·[l0/√3 + λ10_i, λ32_i]ᵀ = r_i``
with ``r_i = G − B_i0 − Rot(α_i + φ)·c``, solved in closed form by the kernel
(:func:`prp3.kernel.kernel_geometry`); this module adds the vectors of each leg.  Its
determinant ``e_i × d_i = sin(φ − π/3)`` is the same for the three legs: the
robot is singular at ``φ ≡ π/3 (mod π)``.  Poses with
``|sin(φ − π/3)| < SINGULARITY_THRESHOLD`` are refused.

Array conventions: a pose is ``(..., 3)`` = ``(x, y, φ)``; per-leg scalars are
``(..., 3)`` (legs A, B, C on the last axis); per-leg plane vectors are
``(..., 3, 2)``.  A single pose ``(3,)`` gives per-leg arrays ``(3,)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import UnreachablePoseError
from .kernel import NUMPY, kernel_geometry, kernel_parameters
from .model import Robot
from .validation import (
    LEGS,
    SINGULARITY_THRESHOLD,
    check_poses,
    check_robot,
    require_finite,
    singularity_measure,
)

__all__ = [
    "ALPHA",
    "LEGS",
    "LEG_AXIS",
    "LEG_NORMAL",
    "SINGULARITY_THRESHOLD",
    "InverseGeometry",
    "base_vertices",
    "check_poses",
    "check_stroke",
    "cross2",
    "dot2",
    "inverse_geometry",
    "perp",
    "platform_vertices",
    "singularity_measure",
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
    return robot.l0 * np.array([[0.0, -1.0], [s3 / 2.0, 0.5], [-s3 / 2.0, 0.5]])


def platform_vertices(robot: Robot, pose: ArrayLike) -> FloatArray:
    """Vertices of the platform triangle for poses ``(..., 3)``, shape ``(..., 3, 2)``.

    The platform edge of leg ``i`` lies on the line through ``P_i`` along
    ``d_i``; at the central configuration the platform is the base triangle
    turned by 180° (vertices at angles 90°, 210°, 330° at distance ``l0``).

    >>> platform_vertices(Robot(), [0.0, 0.0, 0.0]).round(4).tolist()
    [[0.0, 0.3], [-0.2598, -0.15], [0.2598, -0.15]]
    """
    pose = np.asarray(pose, dtype=np.float64)
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
    when ``pose`` is given.

    >>> from prp3.model import Limits
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
    outside = (flat < lower) | (flat > upper)
    if not outside.any():
        return
    index, leg = np.argwhere(outside)[0].tolist()
    value = (
        f"lambda10_{LEGS[leg]} = {float(flat[index, leg])!r} m is outside the stroke "
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
