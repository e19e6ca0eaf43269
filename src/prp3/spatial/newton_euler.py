"""Inverse dynamics, route (b): Newton–Euler of every body, one linear system (docs/spatial.md §8).

Unknowns, leg by leg: the wrench ``(F_k, M_k)`` (world frame, at the joint
point ``o_k``) that joint ``k``'s proximal body exerts on its distal body, six
per joint, then the leg's actuator effort ``τ``.  Equations: the force and
moment balance of every leg body,

``F_k − F_{k+1} + m·g = m·a_G``,
``M_k + (o_k − G) × F_k − M_{k+1} − (o_{k+1} − G) × F_{k+1} = I·α + ω × I·ω``,

and of the platform (the last joint of every leg acting on it); and for every
joint coordinate, the component of the wrench along its free motion: ``e·M_k``
for a rotation about ``e`` (R, U; ``e_x, e_y, e_z`` for S), ``e·F_k`` for a
slide along ``e`` — zero, or ``τ`` for the actuated coordinate.  For the
hexapod: 114 equations in 114 unknowns per sample, one ``numpy.linalg.solve``
per sample, batched in chunks of ``NE_CHUNK`` samples.

The platform's mass-centre acceleration is taken from the motion itself, the
leg bodies' from the chain's recursion; nothing of route (a)'s projections
(``G_b``, ``J_i⁻¹``, ``J_p``) is used.

>>> from prp3.spatial.model import hexapod
>>> from prp3.spatial.motion import PlatformMotion
>>> robot = hexapod()
>>> solution = newton_euler_dynamics(robot, PlatformMotion.at_rest(robot.home_position))
>>> solution.tau.shape, solution.force.shape, round(float(solution.tau[0, 0]), 6)
((1, 6), (1, 6, 3, 3), 2.804864)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.spatial.dynamics import body_wrenches
from prp3.spatial.geometry import coordinate_kinds
from prp3.spatial.kinematics import chunk_kinematics
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import skew
from prp3.validation import check_instance

__all__ = ["NE_CHUNK", "JointWrenches", "newton_euler_dynamics"]

FloatArray = NDArray[np.float64]

#: Samples per batched solve (the hexapod's matrices are 114 × 114: 26 MB per chunk).
NE_CHUNK: int = 256


@dataclass(frozen=True)
class JointWrenches:
    """Route (b)'s results: ``tau (N, legs)``; ``force, moment (N, legs, joints, 3)`` (§9)."""

    tau: FloatArray
    force: FloatArray
    moment: FloatArray


def _chunk(robot: SpatialRobot, motion: PlatformMotion, offset: int) -> JointWrenches:
    kin = chunk_kinematics(robot, motion, offset)
    wrenches = body_wrenches(robot, kin, motion)
    frames = kin.frames
    kinds = coordinate_kinds(robot)
    legs = len(robot.legs)
    joints = len(robot.legs[0].joints)
    per_leg = 6 * joints + 1
    size = legs * per_leg
    n = len(motion)
    a = np.zeros((n, size, size))
    b = np.zeros((n, size))
    eye = np.eye(3)
    row = 0
    actuated = robot.legs[0].actuated_coordinate

    def f_col(i: int, k: int) -> int:
        return i * per_leg + 6 * k

    for i in range(legs):
        # the balances of leg i's bodies
        for k in range(joints - 1):
            g = wrenches.centre[:, i, k]
            for j, sign in ((k, 1.0), (k + 1, -1.0)):
                col = f_col(i, j)
                lever = skew(frames.origin[:, i, j] - g)
                a[:, row : row + 3, col : col + 3] += sign * eye
                a[:, row + 3 : row + 6, col : col + 3] += sign * lever
                a[:, row + 3 : row + 6, col + 3 : col + 6] += sign * eye
            b[:, row : row + 3] = wrenches.force[:, i, k]
            b[:, row + 3 : row + 6] = wrenches.moment[:, i, k]
            row += 6
        # the free directions of leg i's joints
        for c, (kind, owner) in enumerate(kinds):
            col = f_col(i, owner)
            e = frames.axes[:, i, c]
            if kind == "t":
                a[:, row, col : col + 3] = e
            else:
                a[:, row, col + 3 : col + 6] = e
            if c == actuated:
                a[:, row, i * per_leg + 6 * joints] = -1.0
            row += 1
    # the platform's balance, every leg's last joint acting on it
    for i in range(legs):
        col = f_col(i, joints - 1)
        lever = skew(frames.origin[:, i, joints - 1] - wrenches.platform_centre)
        a[:, row : row + 3, col : col + 3] = eye
        a[:, row + 3 : row + 6, col : col + 3] = lever
        a[:, row + 3 : row + 6, col + 3 : col + 6] = eye
    b[:, row : row + 3] = wrenches.platform_force
    b[:, row + 3 : row + 6] = wrenches.platform_moment
    row += 6
    x = np.asarray(np.linalg.solve(a, b[..., None])[..., 0], dtype=np.float64)
    x = x.reshape(n, legs, per_leg)
    wrench = x[..., : 6 * joints].reshape(n, legs, joints, 6)
    return JointWrenches(x[..., -1], wrench[..., :3], wrench[..., 3:])


def newton_euler_dynamics(robot: SpatialRobot, motion: PlatformMotion) -> JointWrenches:
    """Every joint's wrench and the actuator efforts of ``motion`` by route (b).

    Returns
    -------
    JointWrenches
        ``tau (N, legs)`` (N or N·m); ``force (N, legs, joints, 3)`` (N) and
        ``moment (N, legs, joints, 3)`` (N·m): the wrench of each joint's proximal
        body on its distal body at the joint point, world frame (docs/spatial.md §9).

    Raises
    ------
    UnreachablePoseError, SingularPoseError
        As :func:`~prp3.spatial.kinematics.spatial_kinematics`.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    n, legs, joints = len(motion), len(robot.legs), len(robot.legs[0].joints)
    tau = np.empty((n, legs))
    force, moment = np.empty((n, legs, joints, 3)), np.empty((n, legs, joints, 3))
    for start in range(0, n, NE_CHUNK):
        stop = min(start + NE_CHUNK, n)
        part = _chunk(robot, motion.chunk(start, stop), start)
        tau[start:stop], force[start:stop], moment[start:stop] = part.tau, part.force, part.moment
    return JointWrenches(tau, force, moment)
