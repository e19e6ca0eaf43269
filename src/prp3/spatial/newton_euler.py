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
per sample, batched in chunks of ``NE_CHUNK`` samples (:func:`newton_euler_dynamics`, the
reference).

:func:`recursive_newton_euler` solves the same equations by their structure
(docs/spatial.md §19): with each leg's last wrench ``W_n = (M_n, F_n)`` (at the
leg's end ``c_i``) set to zero, the balances of the leg's bodies, taken from the
platform towards the base, give the particular wrenches ``W⁰_k``; the wrench of
joint ``k`` is then ``W⁰_k`` plus ``W_n`` carried to ``o_k``
(``(M_n + (c_i − o_k) × F_n, F_n)``), so that the free-direction equations of the
leg are ``J_iᵀ·W_n = τ_i·e_a − y⁰_i`` (``y⁰_c = e·M⁰_k`` or ``e·F⁰_k``).  Their
solution ``W_n = τ_i·x_i − z_i + λ_i·w_i`` (``x_i = J_i⁻ᵀ·e_a``, ``z_i = J_i⁻ᵀ·y⁰_i``;
``J_i(J_iᵀJ_i)⁻¹`` and the leg's constraint wrench ``w_i`` for a leg of 5 coordinates)
into the platform's balance leaves one ``6 × 6`` system for ``(τ, λ)``; every joint
wrench follows.  Same unknowns, same equations: one ``6 × 6`` solve and a few per leg
instead of one ``114 × 114`` solve per sample.

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

from prp3.spatial.dynamics import BodyWrenches, body_wrenches
from prp3.spatial.geometry import CHUNK, coordinate_kinds
from prp3.spatial.kinematics import ChunkKinematics, chunk_kinematics, transpose_solve
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import cross, skew
from prp3.validation import check_instance

__all__ = [
    "NE_CHUNK",
    "JointWrenches",
    "newton_euler_dynamics",
    "recursive_chunk",
    "recursive_newton_euler",
]

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


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.asarray(np.einsum("...i,...i->...", a, b), dtype=np.float64)


def recursive_chunk(
    robot: SpatialRobot, kin: ChunkKinematics, motion: PlatformMotion, wrenches: BodyWrenches
) -> JointWrenches:
    """Route (b) for one chunk, solved by the structure of its equations (module docstring)."""
    frames = kin.frames
    kinds = coordinate_kinds(robot)
    n, legs, dof = kin.dq.shape
    joints = len(robot.legs[0].joints)
    origin = frames.origin
    # the particular wrenches: W_n = 0, the leg bodies' balances from the platform inwards
    f0 = np.zeros((n, legs, joints, 3))
    m0 = np.zeros((n, legs, joints, 3))
    for k in range(joints - 2, -1, -1):
        g = wrenches.centre[:, :, k]
        f0[:, :, k] = f0[:, :, k + 1] + wrenches.force[:, :, k]
        m0[:, :, k] = (
            m0[:, :, k + 1]
            + cross(origin[:, :, k + 1] - g, f0[:, :, k + 1])
            - cross(origin[:, :, k] - g, f0[:, :, k])
            + wrenches.moment[:, :, k]
        )
    y0 = np.empty((n, legs, dof))
    for c, (kind, owner) in enumerate(kinds):
        part = f0 if kind == "t" else m0
        y0[..., c] = _dot(frames.axes[:, :, c], part[:, :, owner])
    z = transpose_solve(kin.jacobian, y0)  # (M, F) at the leg's end, per unit of nothing
    end = origin[:, :, -1]
    r = end - motion.position[:, None, :]
    # x_i = J_i⁻ᵀ·e_a from the parallel Jacobian's rows (ω part: x_ω + r × x_v)
    x_force = kin.parallel[..., 3:]
    x_moment = kin.parallel[..., :3] - cross(r, x_force)
    # the platform's balance about p: Σ_i T_i·(τ_i·x_i − z_i + λ_i·w_i) = (M_G + (G − p) × F_G, F_G)
    rhs = np.concatenate([z[..., :3] + cross(r, z[..., 3:]), z[..., 3:]], axis=-1).sum(axis=1)
    rg = wrenches.platform_centre - motion.position
    rhs[:, :3] += wrenches.platform_moment + cross(rg, wrenches.platform_force)
    rhs[:, 3:] += wrenches.platform_force
    matrix = (
        kin.parallel
        if kin.constraint is None
        else np.concatenate([kin.parallel, kin.constraint], axis=1)
    )
    solution = np.linalg.solve(np.swapaxes(matrix, -1, -2), rhs[..., None])[..., 0]
    tau = np.asarray(solution[:, :legs], dtype=np.float64)
    moment_n = tau[..., None] * x_moment - z[..., :3]
    force_n = tau[..., None] * x_force - z[..., 3:]
    if kin.null is not None:
        lam = solution[:, legs:, None]
        moment_n = moment_n + lam * kin.null[..., :3]
        force_n = force_n + lam * kin.null[..., 3:]
    force = f0 + force_n[:, :, None, :]
    moment = (
        m0 + moment_n[:, :, None, :] + cross(end[:, :, None, :] - origin, force_n[:, :, None, :])
    )
    return JointWrenches(tau, force, moment)


def recursive_newton_euler(robot: SpatialRobot, motion: PlatformMotion) -> JointWrenches:
    """:func:`newton_euler_dynamics` solved by the structure of its equations, in chunks of ``CHUNK``.

    The same unknowns and equations (every body's balance, every joint's free
    directions), the same results to round-off; a ``6 × 6`` solve per sample for the
    efforts and the constraint multipliers, then every joint wrench by the leg bodies'
    balances (module docstring, docs/spatial.md §19).

    >>> from prp3.spatial.model import hexapod
    >>> robot = hexapod()
    >>> fast = recursive_newton_euler(robot, PlatformMotion.at_rest(robot.home_position))
    >>> round(float(fast.tau[0, 0]), 6), round(float(fast.force[0, 0, 2, 2]), 6)
    (2.804864, 1.635)

    Raises
    ------
    UnreachablePoseError, SingularPoseError, TrajectoryError
        As :func:`~prp3.spatial.kinematics.spatial_kinematics`.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    n, legs, joints = len(motion), len(robot.legs), len(robot.legs[0].joints)
    tau = np.empty((n, legs))
    force, moment = np.empty((n, legs, joints, 3)), np.empty((n, legs, joints, 3))
    for start in range(0, n, CHUNK):
        stop = min(start + CHUNK, n)
        chunk = motion.chunk(start, stop)
        kin = chunk_kinematics(robot, chunk, start)
        part = recursive_chunk(robot, kin, chunk, body_wrenches(robot, kin, chunk))
        tau[start:stop], force[start:stop], moment[start:stop] = part.tau, part.force, part.moment
    return JointWrenches(tau, force, moment)
