"""The independent check: Newton–Euler of the 7 bodies, 21 unknowns per sample (docs/family.md §7).

Unknowns of each leg, joint by joint: an R joint's force ``(F_x, F_y)`` at
``O_k`` (and the actuator couple ``τ`` when it is driven); a P joint's normal
force ``N`` along ``n_k = perp(u_k)`` and couple ``M`` (and ``τ`` along ``u_k``
when it is driven) — 7 per leg.  Equations: ``ΣF = m(a_C − g)`` and
``ΣM_C = I·θ̈`` of link 1 and link 2 of each leg and of the platform (payload
welded on, load added): 21.  One ``numpy.linalg.solve`` per sample, batched.

The mass-centre accelerations come from this module's own recursion over the
chain's frame origins, ``p̈_{J_k} = p̈_{F_{k−1}} + α·perp(r) − ω²·r`` and, for
a P joint, ``p̈_{F_k} = p̈_{J_k} + q̈·u + 2q̇·ω·perp(u) + q·(α·perp(u) − ω²·u)``;
only the joint values and rates of :func:`~prp3.family.mechanics.family_kinematics`
are shared with the other routes.

>>> from prp3.model.motion import Motion
>>> from prp3.family.model import FamilyRobot
>>> solution = newton_euler_dynamics(FamilyRobot.default("3-PPR"), Motion.at_rest([0, 0, 0.0]))
>>> round(float(solution.tau.sum()), 6) == round(float(solution.tau[0] * 3), 6)  # symmetric
True
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from prp3.family.chain import cross, perp, rotate
from prp3.family.mechanics import (
    FamilyKinematics,
    FamilySolution,
    family_kinematics,
    joint_solution,
    motion_batch,
)
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion

__all__ = ["link_accelerations", "newton_euler_dynamics"]

FloatArray = NDArray[np.float64]


def link_accelerations(kin: FamilyKinematics) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Mass centres ``(N, 3, 2, 2)``, their accelerations, and the links' ``θ̈`` ``(N, 3, 2)``."""
    robot, frames = kin.robot, kin.frames
    types = robot.types
    n = frames.origin.shape[0]
    q, dq, ddq = (x.reshape(n, 3, 3) for x in (kin.q, kin.dq, kin.ddq))
    p_acc = np.zeros((n, 3, 2))
    omega = np.zeros((n, 3))
    alpha = np.zeros((n, 3))
    origin_prev = frames.origin[..., 0, :] * 0.0
    centres, accs, alphas = [], [], []
    for k in range(3):
        r = frames.joint_origin[..., k, :] - origin_prev
        p_acc = p_acc + alpha[..., None] * perp(r) - (omega**2)[..., None] * r
        if types[k] == "P":
            u = frames.axis[..., k, :]
            p_acc = (
                p_acc
                + ddq[..., k, None] * u
                + 2.0 * (dq[..., k] * omega)[..., None] * perp(u)
                + q[..., k, None] * (alpha[..., None] * perp(u) - (omega**2)[..., None] * u)
            )
        else:
            omega = omega + dq[..., k]
            alpha = alpha + ddq[..., k]
        origin_prev = frames.origin[..., k, :]
        if k < 2:
            body = robot.link1 if k == 0 else robot.link2
            rc = rotate(frames.angle[..., k], body.com)
            centres.append(origin_prev + rc)
            accs.append(p_acc + alpha[..., None] * perp(rc) - (omega**2)[..., None] * rc)
            alphas.append(alpha)
    return np.stack(centres, 2), np.stack(accs, 2), np.stack(alphas, 2)


def _platform_rhs(
    kin: FamilyKinematics, pose: FloatArray, acceleration: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Right-hand side of the platform's balance (payload welded on, load added).

    Returns ``ΣF`` ``(N, 2)`` [N] and ``ΣM_C`` ``(N,)`` [N·m] the three legs' joint
    wrenches must supply: ``m(a_C − g)`` of platform and payload less the load force,
    and ``I·θ̈`` plus the payload's moment about ``C`` less the load moment.
    """
    robot = kin.robot
    g = np.asarray(robot.gravity)
    omega, alpha = kin.motion.velocity.reshape(-1, 3)[:, 2], acceleration[:, 2]
    payload = robot.payload
    r = rotate(pose[:, 2], payload.com)
    a_pl = acceleration[:, :2] + alpha[:, None] * perp(r) - (omega**2)[:, None] * r
    f_pl = payload.mass * (a_pl - g)
    force = robot.platform.mass * (acceleration[:, :2] - g) + f_pl - np.asarray(robot.load.force)
    moment = (robot.platform.inertia + payload.inertia) * alpha + cross(r, f_pl) - robot.load.moment
    return force, moment


def _joint_wrenches(
    joint_wrench: Callable[[int, int], tuple[FloatArray, FloatArray, FloatArray]],
    x: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """Every joint's force ``(N, 3, 3, 2)`` [N] and moment ``(N, 3, 3)`` [N·m] from the solved unknowns ``x``.

    ``joint_wrench(leg, k)`` gives the linear maps unknowns → ``(F_x, F_y, m)`` of joint k.
    """
    n = x.shape[0]
    force = np.empty((n, 3, 3, 2))
    moment = np.empty((n, 3, 3))
    for leg in range(3):
        for k in range(3):
            fx, fy, m = joint_wrench(leg, k)
            force[:, leg, k, 0] = np.einsum("ni,ni->n", fx, x)
            force[:, leg, k, 1] = np.einsum("ni,ni->n", fy, x)
            moment[:, leg, k] = np.einsum("ni,ni->n", m, x)
    return force, moment


def newton_euler_dynamics(robot: FamilyRobot, motion: Motion) -> FamilySolution:
    """Every joint force from the 21×21 balance of the 7 bodies, one solve per sample."""
    kin = family_kinematics(robot, motion)
    robot = kin.robot
    frames = kin.frames
    _, pose, _, acceleration = motion_batch(kin.motion)
    n = pose.shape[0]
    types, act = robot.types, robot.actuated - 1
    centres, accs, alphas = link_accelerations(kin)
    g = np.asarray(robot.gravity)

    # unknown layout: leg L occupies 7 columns; joint k's unknowns in order, τ last
    size = 21
    matrix = np.zeros((n, size, size))
    rhs = np.zeros((n, size))

    def joint_wrench(leg: int, k: int) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Linear maps unknowns → (F_x, F_y, m about O_k) of joint k of leg: (n, 3, 21)."""
        block = np.zeros((n, 3, size))
        base = 7 * leg + 2 * k
        tau_col = 7 * leg + 6
        u = frames.axis[:, leg, k, :]
        if types[k] == "R":
            block[:, 0, base] = 1.0
            block[:, 1, base + 1] = 1.0
            if k == act:
                block[:, 2, tau_col] = 1.0
        else:
            nrm = perp(u)
            block[:, 0, base] = nrm[:, 0]
            block[:, 1, base] = nrm[:, 1]
            block[:, 2, base + 1] = 1.0
            if k == act:
                block[:, 0, tau_col] = u[:, 0]
                block[:, 1, tau_col] = u[:, 1]
        return block[:, 0], block[:, 1], block[:, 2]

    def moment_about(point: FloatArray, leg: int, k: int) -> tuple[FloatArray, FloatArray]:
        """(force rows, moment-about-point row) of joint k's wrench on its distal body."""
        fx, fy, m = joint_wrench(leg, k)
        lever = frames.origin[:, leg, k, :] - point
        return np.stack([fx, fy], 1), m + lever[:, 0, None] * fy - lever[:, 1, None] * fx

    row = 0
    for leg in range(3):
        for body in (0, 1):
            params = robot.link1 if body == 0 else robot.link2
            c = centres[:, leg, body]
            f_in, m_in = moment_about(c, leg, body)
            f_out, m_out = moment_about(c, leg, body + 1)
            matrix[:, row : row + 2] = f_in - f_out
            matrix[:, row + 2] = m_in - m_out
            rhs[:, row : row + 2] = params.mass * (accs[:, leg, body] - g)
            rhs[:, row + 2] = params.inertia * alphas[:, leg, body]
            row += 3
    centre = pose[:, :2]
    for leg in range(3):
        f3, m3 = moment_about(centre, leg, 2)
        matrix[:, row : row + 2] += f3
        matrix[:, row + 2] += m3
    rhs[:, row : row + 2], rhs[:, row + 2] = _platform_rhs(kin, pose, acceleration)
    x = np.asarray(np.linalg.solve(matrix, rhs[..., None])[..., 0], dtype=np.float64)
    force, moment = _joint_wrenches(joint_wrench, x)
    tau = x[:, 6::7]
    return joint_solution(kin, kin.dq, kin.ddq, tau, force, moment, "newton-euler")
