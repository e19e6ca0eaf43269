"""Inverse dynamics, route (a): virtual work on the recursive matrices (docs/spatial.md §8).

Every body's twist at its mass centre is a linear map of its leg's joint rates,
``ξ_b = G_b·dq_i`` (the columns of the chain up to the body), and the joint
rates of leg ``i`` are ``J_i⁻¹·T_i·(ω, v)``; the virtual work of the actuator
efforts balances that of the bodies' inertial wrenches
``W_b = (I·α + ω × I·ω, m(a_G − g))``:

``J_pᵀ·τ = Σ_i T_iᵀ·J_i⁻ᵀ·Σ_{b ∈ leg i} G_bᵀ·W_b + T_Gᵀ·W_platform``,

one ``6 × 6`` solve per sample (as in Staicu's recursive matrix method).  The
body motions and inertial wrenches (:func:`body_wrenches`) are shared with
:mod:`prp3.spatial.newton_euler`, which solves the same dynamics body by body.

>>> from prp3.spatial.model import hexapod
>>> from prp3.spatial.motion import PlatformMotion
>>> robot = hexapod()
>>> tau = virtual_work_efforts(robot, PlatformMotion.at_rest(robot.home_position))
>>> tau.shape, round(float(tau[0, 0]), 6), bool(np.ptp(tau) < 1e-12)
((1, 6), 2.804864, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.spatial.geometry import CHUNK, coordinate_kinds
from prp3.spatial.kinematics import ChunkKinematics, chunk_kinematics, transpose_solve
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import cross
from prp3.validation import check_instance

__all__ = [
    "BodyWrenches",
    "body_wrenches",
    "chunk_efforts",
    "virtual_work_efforts",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class BodyWrenches:
    """The bodies' mass centres, their motion and their inertial wrenches for one chunk.

    Leg bodies: ``(N, legs, n − 1, 3)``; the platform: ``(N, 3)``.

    Attributes
    ----------
    centre, omega, centre_velocity, centre_acceleration
        Mass centre (m), angular velocity (rad/s), its velocity (m/s) and acceleration (m/s²).
    force, moment
        ``m(a_G − g)`` (N) and ``I·α + ω × I·ω`` about the mass centre (N·m), world frame.
    platform_centre, platform_velocity, platform_force, platform_moment
        The same of the platform.
    """

    centre: FloatArray
    omega: FloatArray
    centre_velocity: FloatArray
    centre_acceleration: FloatArray
    force: FloatArray
    moment: FloatArray
    platform_centre: FloatArray
    platform_velocity: FloatArray
    platform_force: FloatArray
    platform_moment: FloatArray


def _inertial(
    mass: FloatArray,
    inertia: FloatArray,
    rotation: FloatArray,
    omega: FloatArray,
    alpha: FloatArray,
    acceleration: FloatArray,
    gravity: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """``(m(a − g), I·α + ω × I·ω)`` with ``I = R·I_body·Rᵀ``; ``mass`` and ``inertia``
    broadcast against the batch."""
    world = rotation @ inertia @ np.swapaxes(rotation, -1, -2)
    i_alpha = np.einsum("...ij,...j->...i", world, alpha)
    i_omega = np.einsum("...ij,...j->...i", world, omega)
    return mass[..., None] * (acceleration - gravity), i_alpha + cross(omega, i_omega)


def body_wrenches(
    robot: SpatialRobot, kin: ChunkKinematics, motion: PlatformMotion
) -> BodyWrenches:
    """Mass centres, velocities, accelerations and inertial wrenches of every moving body."""
    gravity = np.array(robot.gravity)
    bodies, frames = kin.bodies, kin.frames
    count = len(robot.legs[0].bodies)
    local = np.array([[body.centre for body in leg.bodies] for leg in robot.legs])
    mass = np.array([[body.mass for body in leg.bodies] for leg in robot.legs])
    inertia = np.array([[body.inertia for body in leg.bodies] for leg in robot.legs])
    rotation = frames.rotation[:, :, :count]
    origin = bodies.origin[:, :, :count]
    omega, alpha = bodies.omega[:, :, :count], bodies.alpha[:, :, :count]
    r = np.einsum("nlkij,lkj->nlki", rotation, local)
    centre = origin + r
    velocity = bodies.velocity[:, :, :count] + cross(omega, r)
    acceleration = (
        bodies.acceleration[:, :, :count] + cross(alpha, r) + cross(omega, cross(omega, r))
    )
    force, moment = _inertial(mass, inertia, rotation, omega, alpha, acceleration, gravity)
    platform = robot.platform
    rp = np.einsum("nij,j->ni", motion.rotation, np.array(platform.centre))
    p_velocity = motion.velocity + cross(motion.omega, rp)
    p_acceleration = (
        motion.acceleration + cross(motion.alpha, rp) + cross(motion.omega, cross(motion.omega, rp))
    )
    p_force, p_moment = _inertial(
        np.array(platform.mass),
        np.array(platform.inertia),
        motion.rotation,
        motion.omega,
        motion.alpha,
        p_acceleration,
        gravity,
    )
    return BodyWrenches(
        centre, omega, velocity, acceleration, force, moment,
        motion.position + rp, p_velocity, p_force, p_moment,
    )  # fmt: skip


def chunk_efforts(
    robot: SpatialRobot, kin: ChunkKinematics, motion: PlatformMotion, wrenches: BodyWrenches
) -> FloatArray:
    """Route (a) for one chunk: the actuator efforts ``τ (N, legs)`` (N or N·m)."""
    frames = kin.frames
    kinds = coordinate_kinds(robot)
    n, legs, dof = kin.dq.shape
    y = np.zeros((n, legs, dof))
    for k in range(len(robot.legs[0].bodies)):
        c = wrenches.centre[:, :, k]
        f, m = wrenches.force[:, :, k], wrenches.moment[:, :, k]
        for col, (kind, owner) in enumerate(kinds):
            if owner > k:
                continue
            e = frames.axes[:, :, col]
            if kind == "t":  # G_b column (0, e)
                y[..., col] += np.einsum("nli,nli->nl", e, f)
            else:  # (e, e × (c − o)):  e·M + (e × (c − o))·F
                lever = cross(e, c - frames.origin[:, :, owner])
                y[..., col] += np.einsum("nli,nli->nl", e, m) + np.einsum("nli,nli->nl", lever, f)
    z = transpose_solve(kin.jacobian, y)
    r = frames.origin[:, :, -1] - motion.position[:, None, :]
    rhs = np.concatenate([z[..., :3] + cross(r, z[..., 3:]), z[..., 3:]], axis=-1).sum(axis=1)
    rg = wrenches.platform_centre - motion.position
    rhs[:, :3] += wrenches.platform_moment + cross(rg, wrenches.platform_force)
    rhs[:, 3:] += wrenches.platform_force
    # Kᵀ·(τ, λ) = rhs with K = [J_p; C]: the constraints' multipliers λ (legs of 5 coordinates)
    matrix = (
        kin.parallel
        if kin.constraint is None
        else np.concatenate([kin.parallel, kin.constraint], 1)
    )
    solution = np.linalg.solve(np.swapaxes(matrix, -1, -2), rhs[..., None])[..., 0]
    return np.asarray(solution[:, : len(robot.legs)])


def virtual_work_efforts(robot: SpatialRobot, motion: PlatformMotion) -> FloatArray:
    """The actuator efforts ``τ (N, legs)`` of ``motion`` by route (a), in chunks of ``CHUNK``.

    Raises
    ------
    UnreachablePoseError, SingularPoseError
        As :func:`~prp3.spatial.kinematics.spatial_kinematics`.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    n = len(motion)
    tau = np.empty((n, len(robot.legs)))
    for start in range(0, n, CHUNK):
        stop = min(start + CHUNK, n)
        chunk = motion.chunk(start, stop)
        kin = chunk_kinematics(robot, chunk, start)
        tau[start:stop] = chunk_efforts(robot, kin, chunk, body_wrenches(robot, kin, chunk))
    return tau
