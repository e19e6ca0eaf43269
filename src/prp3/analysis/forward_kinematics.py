"""Forward kinematics: the platform's velocity and acceleration from the actuators'.

The paper solves the inverse problems only (pose → actuators → forces).  This
module solves the direct kinematics by a route that the tests hold against the
inverse problems of :mod:`prp3.mechanics.geometry` and
:mod:`prp3.mechanics.kinematics`; the forward geometry (closed form, eqs.
(i)–(iii)) is in :mod:`prp3.mechanics.geometry`, next to the inverse one.

With the Jacobian ``J = ∂λ10/∂(x, y, φ)`` (:func:`prp3.mechanics.kinematics.jacobian`,
from eq. 14), ``q̇ = J⁻¹·λ̇10`` and ``q̈ = J⁻¹·(λ̈10 − J̇·q̇)``, where ``J̇·q̇`` is
the ``λ̈10`` of eq. (17) at zero platform acceleration.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import TrajectoryError
from prp3.mechanics.geometry import forward_geometry, inverse_geometry
from prp3.mechanics.kinematics import inverse_kinematics, jacobian
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.pose_validation import check_poses
from prp3.validation import check_per_leg, check_real, check_robot, check_same_shape

__all__ = [
    "forward_acceleration",
    "forward_kinematics",
    "forward_velocity",
]

FloatArray = NDArray[np.float64]


def _float_array(name: str, value: ArrayLike) -> FloatArray:
    """``value`` as a new float64 array (:func:`prp3.validation.check_real`)."""
    return check_real(name, value, TrajectoryError)


def _dummy_times(batch: tuple[int, ...]) -> FloatArray:
    """Strictly increasing placeholder times for a Motion used as a batch of states."""
    if batch == ():
        return np.asarray(0.0)
    return np.arange(float(batch[0]))


def forward_velocity(robot: Robot, pose: ArrayLike, dlambda10: ArrayLike) -> FloatArray:
    """Platform velocity ``(ẋ, ẏ, φ̇) = J⁻¹·λ̇10`` (eq. 14 solved for the platform).

    Parameters
    ----------
    robot : Robot
    pose : array_like, shape (3,) or (N, 3)
        Platform poses (m, m, rad).
    dlambda10 : array_like, same shape as ``pose``
        Actuator velocities (m/s).

    Returns
    -------
    ndarray, same shape as ``pose``
        ``(ẋ, ẏ, φ̇)`` (m/s, m/s, rad/s).

    Equal actuator speeds turn the platform about ``G`` (``Σλ̇10 = l0·φ̇`` at ``φ = 0``):

    >>> (forward_velocity(Robot(), [0.0, 0.0, 0.0], [0.01, 0.01, 0.01]).round(12) + 0.0).tolist()
    [0.0, 0.0, 0.1]
    """
    geo = inverse_geometry(robot, pose)
    rates = check_per_leg("dlambda10", dlambda10)
    check_same_shape("dlambda10", rates, geo.pose, "pose")
    return np.asarray(np.linalg.solve(jacobian(geo), rates[..., None])[..., 0])


def forward_acceleration(
    robot: Robot, pose: ArrayLike, velocity: ArrayLike, ddlambda10: ArrayLike
) -> FloatArray:
    """Platform acceleration ``q̈ = J⁻¹·(λ̈10 − J̇·q̇)`` (eq. 17 solved for the platform).

    ``J̇·q̇`` is the actuator acceleration of eq. (17) at zero platform
    acceleration (:func:`~prp3.mechanics.kinematics.inverse_kinematics` with ``q̈ = 0``).

    Parameters
    ----------
    robot : Robot
    pose, velocity : array_like, shape (3,) or (N, 3)
        Platform poses and velocities ``(ẋ, ẏ, φ̇)``.
    ddlambda10 : array_like, same shape
        Actuator accelerations (m/s²).

    Returns
    -------
    ndarray, same shape as ``pose``
        ``(ẍ, ÿ, φ̈)`` (m/s², m/s², rad/s²).
    """
    check_robot(robot)
    pose_array = check_poses(pose, robot)
    accelerations = check_per_leg("ddlambda10", ddlambda10)
    speed = check_per_leg("velocity", velocity)
    check_same_shape("velocity", speed, pose_array, "pose")
    check_same_shape("ddlambda10", accelerations, pose_array, "pose")
    still = Motion(
        t=_dummy_times(pose_array.shape[:-1]),
        pose=pose_array,
        velocity=speed,
        acceleration=np.zeros_like(pose_array),
    )
    kin = inverse_kinematics(robot, still)
    bias = kin.ddlambda10  # J̇·q̇, eq. (17) with q̈ = 0
    return np.asarray(np.linalg.solve(kin.jacobian, (accelerations - bias)[..., None])[..., 0])


def forward_kinematics(
    robot: Robot,
    t: ArrayLike,
    lambda10: ArrayLike,
    dlambda10: ArrayLike,
    ddlambda10: ArrayLike,
) -> Motion:
    """Platform motion from the actuator displacements, velocities and accelerations.

    Chains :func:`forward_geometry`, :func:`forward_velocity` and
    :func:`forward_acceleration`; the inverse of
    :func:`~prp3.mechanics.kinematics.inverse_kinematics` (their round trip is tested).

    Parameters
    ----------
    robot : Robot
    t : array_like, shape (N,) or ()
        Sample times (s), strictly increasing.
    lambda10, dlambda10, ddlambda10 : array_like, shape (N, 3) or (3,)
        Actuator displacements (m), velocities (m/s), accelerations (m/s²).

    Returns
    -------
    Motion

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> robot = Robot()
    >>> kin = inverse_kinematics(robot, paper_motion("rotation", samples=5))
    >>> motion = forward_kinematics(robot, kin.motion.t, kin.geometry.lambda10,
    ...                             kin.dlambda10, kin.ddlambda10)
    >>> bool(np.allclose(motion.acceleration, kin.motion.acceleration, atol=1e-12))
    True
    """
    solution = forward_geometry(robot, lambda10)
    velocity = forward_velocity(robot, solution.pose, dlambda10)
    acceleration = forward_acceleration(robot, solution.pose, velocity, ddlambda10)
    return Motion(
        t=_float_array("t", t), pose=solution.pose, velocity=velocity, acceleration=acceleration
    )
