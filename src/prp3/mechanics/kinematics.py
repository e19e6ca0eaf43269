"""Inverse kinematics: velocities and accelerations of every joint and body (eqs. 11–18).

Differentiating the closure (eq. 10) with ``ρ_i = G − P_i`` turning with the
platform gives, per leg, the conditions of connectivity

    ṡ_i·e_i + λ̇32_i·d_i = Ġ − φ̇·J·ρ_i                                  (eq. 14)
    s̈_i·e_i + λ̈32_i·d_i = G̈ − φ̈·J·ρ_i + φ̇²·ρ_i − 2·λ̇32_i·φ̇·J·d_i       (eq. 17)

with ``s_i = l0/√3 + λ10_i`` and ``J`` the rotation by +90° (``ũ3``).  Both
are the 2×2 system of eq. (10) with other right-hand sides; their closed-form
solution is the kernel's (:func:`prp3.mechanics.joint_motion.kernel_kinematics`), and this
module adds the velocities and accelerations of every joint and body.  The angular velocities and accelerations of eqs. (11), (12)
and (18) are ``ω10 = 0``, ``ω20 = ω30 = φ̇`` and ``ε10 = 0``, ``ε20 = ε30 = φ̈``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError, TrajectoryError
from prp3.mechanics.geometry import (
    LEG_AXIS,
    LEG_NORMAL,
    InverseGeometry,
    dot2,
    inverse_geometry,
    perp,
)
from prp3.mechanics.joint_motion import kernel_geometry, kernel_kinematics
from prp3.mechanics.ops import NUMPY
from prp3.mechanics.parameters import kernel_parameters
from prp3.model.motion import Motion
from prp3.model.parameters import Limits
from prp3.model.robot import Robot
from prp3.validation import check_instance, check_robot, require_finite

__all__ = ["Kinematics", "inverse_kinematics", "jacobian"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Kinematics:
    """Positions, velocities and accelerations of every joint and body.

    Shapes: ``...`` is the batch shape of the motion (``(N,)`` or ``()``);
    per-leg scalars ``(..., 3)``, per-leg plane vectors ``(..., 3, 2)``.

    Attributes
    ----------
    motion : Motion
        The platform motion the kinematics were computed for.
    geometry : InverseGeometry
        Joint displacements and leg geometry (eqs. 7–10).
    dlambda10, ddlambda10 : ndarray (..., 3)
        Actuator velocities ``v10`` (m/s) and accelerations ``γ10`` (m/s²), eqs. (14), (17).
    dlambda32, ddlambda32 : ndarray (..., 3)
        Sleeve sliding velocities ``v32`` and accelerations ``γ32``, eqs. (14), (17).
    dphi21, ddphi21 : ndarray (..., 3)
        Link rotation rates ``ω21 = φ̇`` and ``ε21 = φ̈`` (rad/s, rad/s²), eqs. (12), (18).
    joint_velocity, joint_acceleration : ndarray (..., 3, 2)
        Velocity and acceleration of the revolute joint centres ``P_i``, eqs. (13), (18).
    piston_com, piston_velocity, piston_acceleration : ndarray (..., 3, 2)
        Centre of mass of each piston and its velocity and acceleration.
    link_com, link_velocity, link_acceleration : ndarray (..., 3, 2)
        Centre of mass of each link 2 and its velocity and acceleration.
    jacobian : ndarray (..., 3, 3)
        ``∂λ10/∂(x, y, φ)``: ``λ̇10 = jacobian @ (ẋ, ẏ, φ̇)``, from eq. (14).
    """

    motion: Motion
    geometry: InverseGeometry
    dlambda10: FloatArray
    ddlambda10: FloatArray
    dlambda32: FloatArray
    ddlambda32: FloatArray
    dphi21: FloatArray
    ddphi21: FloatArray
    joint_velocity: FloatArray
    joint_acceleration: FloatArray
    piston_com: FloatArray
    piston_velocity: FloatArray
    piston_acceleration: FloatArray
    link_com: FloatArray
    link_velocity: FloatArray
    link_acceleration: FloatArray
    jacobian: FloatArray


def jacobian(robot: Robot | InverseGeometry, pose: ArrayLike | None = None) -> FloatArray:
    """Jacobian ``∂λ10/∂(x, y, φ)`` of the actuator displacements, shape ``(..., 3, 3)``.

    ``jacobian(robot, pose)``, as :func:`prp3.jacobian_condition` takes them
    (poses ``(3,)`` or ``(..., 3)``, validated; the strokes do not matter),
    or ``jacobian(geometry)`` of an inverse geometry computed already.  The
    rank follows the input: ``(3,)`` gives ``(3, 3)``, ``(N, 3)`` gives
    ``(N, 3, 3)``.  ``λ̇10 = J·(ẋ, ẏ, φ̇)``.

    Row ``i`` is ``[d_iy, −d_ix, ρ_i·d_i] / sin(φ − π/3)``: eq. (14) solved for
    ``v10`` (the cross product of eq. (14) with ``d_i`` removes ``v32``).

    Raises
    ------
    SingularPoseError
        A pose at the singularity ``sin(φ − π/3) = 0`` (where ``J`` is infinite).
    TrajectoryError, ParameterError
        Poses of the wrong shape, non-finite or out of bounds; a missing
        pose; not a robot (nor an inverse geometry).

    >>> from prp3.model.robot import Robot
    >>> from prp3.mechanics.geometry import inverse_geometry
    >>> jacobian(inverse_geometry(Robot(), [0.0, 0.0, 0.0])).shape
    (3, 3)
    >>> jacobian(Robot(), [[0.0, 0.0, 0.0], [0.01, 0.0, 0.1]]).shape
    (2, 3, 3)
    """
    if isinstance(robot, InverseGeometry) and pose is None:
        geometry = robot
    else:
        check_instance(
            "robot", robot, Robot, "a prp3.Robot (with a pose) or a prp3.InverseGeometry"
        )
        if pose is None:
            raise ParameterError("pose is missing: jacobian(robot, pose)", key="pose")
        assert isinstance(robot, Robot)
        free = robot if robot.limits == Limits() else replace(robot, limits=Limits())
        geometry = inverse_geometry(free, pose)
    d = geometry.slide
    D = geometry.determinant[..., None]
    rows = np.stack(
        [d[..., 1], -d[..., 0], dot2(geometry.lever, d)],
        axis=-1,
    )
    return np.asarray(rows / D[..., None])


def inverse_kinematics(robot: Robot, motion: Motion) -> Kinematics:
    """Velocities and accelerations of every joint and body (eqs. 11–18).

    Parameters
    ----------
    robot : Robot
        Robot parameters (``l0``, centres of mass of pistons and links).
    motion : Motion
        Platform motion, ``N`` samples or one.

    Returns
    -------
    Kinematics
        Implements eqs. (12)–(14) and (17)–(18) in closed form.

    Raises
    ------
    SingularPoseError, UnreachablePoseError
        From :func:`~prp3.mechanics.geometry.inverse_geometry`.

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> kin = inverse_kinematics(Robot(), paper_motion("vertical", samples=5))
    >>> kin.dlambda10.shape, kin.jacobian.shape
    ((5, 3), (5, 3, 3))
    """
    check_robot(robot)
    if not isinstance(motion, Motion):
        raise TrajectoryError(f"motion must be a prp3.Motion, got {motion!r}"[:200])
    geo = inverse_geometry(robot, motion.pose)
    with np.errstate(over="ignore", invalid="ignore"):
        kin = _inverse_kinematics(robot, motion, geo)
    require_finite(
        {
            "dlambda10": kin.dlambda10,
            "dlambda32": kin.dlambda32,
            "ddlambda10": kin.ddlambda10,
            "ddlambda32": kin.ddlambda32,
            "link_acceleration": kin.link_acceleration,
        },
        motion.t.shape,
        "motion",
        motion.t,
    )
    return kin


def _inverse_kinematics(robot: Robot, motion: Motion, geo: InverseGeometry) -> Kinematics:
    d = geo.slide
    phidot = motion.velocity[..., 2, None]  # (..., 1)
    phiddot = motion.acceleration[..., 2, None]

    # eqs. (14), (17) in closed form: the kernel's, the one place they are written
    pose = geo.pose
    params = kernel_parameters(robot)
    closed = kernel_kinematics(
        params,
        kernel_geometry(NUMPY, params, pose[..., 0], pose[..., 1], pose[..., 2]),
        *(motion.velocity[..., k] for k in range(3)),
        *(motion.acceleration[..., k] for k in range(3)),
    )
    dlambda10, ddlambda10, dlambda32, ddlambda32 = (
        np.stack(legs, axis=-1)
        for legs in (closed.dlambda10, closed.ddlambda10, closed.dlambda32, closed.ddlambda32)
    )

    shape = dlambda10.shape
    dphi21 = np.broadcast_to(phidot, shape).copy()  # eq. (12): ω21 = φ̇
    ddphi21 = np.broadcast_to(phiddot, shape).copy()  # eq. (18): ε21 = φ̈

    # eqs. (13), (18): the joint P_i moves with the piston along e_i
    joint_velocity = dlambda10[..., None] * LEG_AXIS
    joint_acceleration = ddlambda10[..., None] * LEG_AXIS

    c1x, c1y = robot.piston.com
    piston_offset = c1x * LEG_AXIS + c1y * LEG_NORMAL  # (3, 2), the piston only translates
    c2x, c2y = robot.link.com
    link_offset = c2x * d + c2y * perp(d)  # turns with φ
    link_velocity = joint_velocity + phidot[..., None] * perp(link_offset)
    link_acceleration = (
        joint_acceleration
        + phiddot[..., None] * perp(link_offset)
        - (phidot**2)[..., None] * link_offset
    )
    return Kinematics(
        motion=motion,
        geometry=geo,
        dlambda10=dlambda10,
        ddlambda10=ddlambda10,
        dlambda32=dlambda32,
        ddlambda32=ddlambda32,
        dphi21=dphi21,
        ddphi21=ddphi21,
        joint_velocity=joint_velocity,
        joint_acceleration=joint_acceleration,
        piston_com=geo.joint + piston_offset,
        piston_velocity=joint_velocity.copy(),
        piston_acceleration=joint_acceleration.copy(),
        link_com=geo.joint + link_offset,
        link_velocity=link_velocity,
        link_acceleration=link_acceleration,
        jacobian=jacobian(geo),
    )
