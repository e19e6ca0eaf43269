"""Inverse dynamics by Newton–Euler: the independent check of the other two methods.

It shares nothing with the kernel (:mod:`prp3.mechanics.kernel`) or the paper's matrices
(:mod:`prp3.references.paper`) but the robot and the motion it is given.  Its kinematics
come from numeric solves of each leg's closure and of its first two
derivatives (the 2×2 systems ``[e_i d_i]·u = r``, solved by LU, not in closed
form); its dynamics from the Newton–Euler equations of the 7 bodies in maximal
coordinates:

* unknowns (21): for each leg ``f10, n10, m10, f21y, f21z, n32, m32``;
* equations (21): for each piston and each link 2 the force balance (x, y)
  and the moment balance about ``P_i``; for the platform the force balance and
  the moment balance about ``G``.

One ``21×21`` solve per sample, in chunks (memory bounded for any N).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from prp3.errors import TrajectoryError
from prp3.mechanics.forces import InverseDynamics, checked
from prp3.mechanics.kinematics import Kinematics
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.path_validation import rest_joint_rates
from prp3.validation import check_instance, check_robot

__all__ = ["NEWTON_EULER_CHUNK", "newton_euler"]

FloatArray = NDArray[np.float64]

#: Samples per linear solve of :func:`newton_euler` (bounds its memory for any N).
NEWTON_EULER_CHUNK: int = 8192

#: Order of the 7 unknowns of each leg in the Newton–Euler system.
_UNKNOWNS = ("f10", "n10", "m10", "f21y", "f21z", "n32", "m32")
#: The friction forces of each leg (with a robot's ``[friction]``).
_FRICTION = ("fric10", "fric21", "fric32")

_ALPHA = np.array([math.pi / 3.0, math.pi, -math.pi / 3.0])  # eq. (1)
_E = np.stack([np.cos(_ALPHA), np.sin(_ALPHA)], axis=-1)  # e_i, (3, 2)
_N = np.stack([-np.sin(_ALPHA), np.cos(_ALPHA)], axis=-1)  # n_i = J·e_i


def _perp(v: FloatArray) -> FloatArray:
    """``J·v``: the rotation by +90° of plane vectors ``(..., 2)``."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def _leg_solve(d: FloatArray, rhs: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Solve ``[e_i d_i]·(a, b) = rhs`` per leg by LU: returns ``(a, b)``, each ``(n, 3)``."""
    matrix = np.stack([np.broadcast_to(_E, d.shape), d], axis=-1)  # columns e_i, d_i
    solution = np.linalg.solve(matrix, rhs[..., None])[..., 0]
    return solution[..., 0], solution[..., 1]


def newton_euler(robot: Robot, motion: Motion | Kinematics) -> InverseDynamics:
    """Inverse dynamics by Newton–Euler of the 7 bodies in maximal coordinates.

    Parameters
    ----------
    robot : Robot
    motion : Motion or Kinematics
        The platform motion (of a :class:`~prp3.mechanics.kinematics.Kinematics`, only
        its motion is used).

    Returns
    -------
    InverseDynamics
        Shapes ``(N, 3)`` or ``(3,)`` as the motion; ``method = "newton-euler"``.

    Examples
    --------
    >>> robot = Robot()
    >>> newton_euler(robot, Motion.at_rest([0.0, 0.0, 0.0])).n32.round(4).tolist()
    [19.62, -9.81, -9.81]
    """
    check_robot(robot)
    if isinstance(motion, Kinematics):
        motion = motion.motion
    check_instance("motion", motion, Motion, "a prp3.Motion or prp3.Kinematics")
    with np.errstate(over="ignore", invalid="ignore"):
        load = np.zeros_like(motion.pose) if motion.load is None else motion.load
        flat = [
            np.asarray(a, dtype=np.float64).reshape(-1, 3)
            for a in (motion.pose, motion.velocity, motion.acceleration, load)
        ]
        parts = []
        for start in range(0, flat[0].shape[0], NEWTON_EULER_CHUNK):
            part = _solve(robot, *(a[start : start + NEWTON_EULER_CHUNK] for a in flat))
            if "locked" in part:
                k = start + int(part.pop("locked"))
                raise TrajectoryError(
                    "the joint friction locks: the Newton-Euler balances with the mu terms "
                    "of friction have no consistent solution (self-locking)",
                    subject="motion",
                    sample=k,
                    time=float(motion.t.reshape(-1)[k]),
                )
            parts.append(part)
    shape = motion.pose.shape
    names = (*_UNKNOWNS, "p10") + (_FRICTION if robot.friction is not None else ())
    joined = {
        name: np.concatenate([p[name] for p in parts]).reshape(shape) if parts else np.empty(shape)
        for name in names
    }
    if robot.friction is not None and robot.friction.has_mu:
        joined_it = np.concatenate([p["iterations"][:, 0] for p in parts]) if parts else np.empty(0)
        iterations = joined_it.reshape(shape[:-1])
    else:
        iterations = None
    return checked(
        InverseDynamics(**joined, method="newton-euler", iterations=iterations), motion.t
    )


def _rate_sign(rate: FloatArray, smoothing: float) -> FloatArray:
    """``s(v)``: the sign of ``v`` (0 at 0) for zero smoothing, else ``tanh(v / smoothing)``."""
    return np.sign(rate) if smoothing == 0.0 else np.tanh(rate / smoothing)


def _solve(
    robot: Robot,
    pose: FloatArray,
    velocity: FloatArray,
    acceleration: FloatArray,
    load: FloatArray,
) -> dict[str, FloatArray]:
    n = pose.shape[0]
    l0 = robot.l0
    G, Gd, Gdd = pose[:, None, :2], velocity[:, None, :2], acceleration[:, None, :2]
    w, eps = velocity[:, 2, None, None], acceleration[:, 2, None, None]  # (n, 1, 1)
    angle = _ALPHA + pose[:, 2, None]  # α_i + φ
    d = np.stack([np.cos(angle - math.pi / 3.0), np.sin(angle - math.pi / 3.0)], axis=-1)
    c = 0.5 * l0 * np.array([1.0 / math.sqrt(3.0), 1.0])
    Rc = np.stack(  # Rot(α_i + φ)·c: from the sleeve's point A3 to G
        [np.cos(angle) * c[0] - np.sin(angle) * c[1], np.sin(angle) * c[0] + np.cos(angle) * c[1]],
        axis=-1,
    )
    base = l0 * np.stack([np.sin(_ALPHA - math.pi / 3.0), -np.cos(_ALPHA - math.pi / 3.0)], -1)
    # closure G = B_i0 + s_i·e_i + λ32_i·d_i + Rot(α_i + φ)·c and its derivatives
    s, lam32 = _leg_solve(d, G - base - Rc)
    rho = G - base - s[..., None] * _E  # G − P_i
    sd, lam32d = _leg_solve(d, Gd - w * _perp(rho))
    sdd, _ = _leg_solve(
        d, Gdd - eps * _perp(rho) + w * w * rho - 2.0 * (lam32d[..., None] * w) * _perp(d)
    )
    # accelerations of the mass centres
    g = np.asarray(robot.gravity)
    a_piston = sdd[..., None] * _E  # the piston translates along e_i
    c2x, c2y = robot.link.com
    o = c2x * d + c2y * _perp(d)  # link 2's mass centre from P_i, turning with φ
    a_link = a_piston + eps * _perp(o) - w * w * o
    c1x, c1y = robot.piston.com
    o1 = c1x * _E + c1y * _N
    # the force and the moment (about P_i, or G) each body needs: m·(a − g), I·ε + r × F
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    F1 = m1 * (a_piston - g)
    M1 = _cross(np.broadcast_to(o1, F1.shape), F1)
    F2 = m2 * (a_link - g)
    M2 = robot.link.inertia * eps[..., 0] + _cross(o, F2)
    F3 = m3 * (acceleration[:, :2] - g)
    M3 = robot.platform_inertia * acceleration[:, 2]
    payload = robot.payload
    if payload.present:  # a body fixed to the platform, its mass centre G + Rot(φ)·c_p
        phi = pose[:, 2]
        cp = np.asarray(payload.com)
        r_p = np.stack(
            [np.cos(phi) * cp[0] - np.sin(phi) * cp[1], np.sin(phi) * cp[0] + np.cos(phi) * cp[1]],
            axis=-1,
        )
        wz, ez = velocity[:, 2, None], acceleration[:, 2, None]
        a_p = acceleration[:, :2] + ez * _perp(r_p) - wz * wz * r_p
        F_p = payload.mass * (a_p - g)
        F3 = F3 + F_p
        M3 = M3 + payload.inertia * acceleration[:, 2] + _cross(r_p, F_p)
    # the environment's wrench on the platform at G: constant [load] + time-varying load
    F3 = F3 - (np.asarray(robot.load.force) + load[:, :2])
    M3 = M3 - (robot.load.moment + load[:, 2])

    u = {name: k for k, name in enumerate(_UNKNOWNS)}
    A = np.zeros((n, 21, 21))
    dn = _perp(d)
    for j in range(3):
        col = 7 * j
        piston, link = slice(3 * j, 3 * j + 2), slice(9 + 3 * j, 9 + 3 * j + 2)
        # piston j: f10·e + n10·n − F21 = F1; m10 = M1 (about P_j)
        A[:, piston, col + u["f10"]] = _E[j]
        A[:, piston, col + u["n10"]] = _N[j]
        A[:, piston, col + u["f21y"]] = -_N[j]
        A[:, piston, col + u["f21z"]] = -_E[j]
        A[:, 3 * j + 2, col + u["m10"]] = 1.0
        # link j: F21 − n32·d⊥ = F2; −m32 = M2 (about P_j)
        A[:, link, col + u["f21y"]] = _N[j]
        A[:, link, col + u["f21z"]] = _E[j]
        A[:, link, col + u["n32"]] = -dn[:, j]
        A[:, 9 + 3 * j + 2, col + u["m32"]] = -1.0
        # platform: Σ n32·d⊥ = F3; Σ m32 + (P_j − G) × n32·d⊥ = M3 (about G)
        A[:, 18:20, col + u["n32"]] = dn[:, j]
        A[:, 20, col + u["m32"]] = 1.0
        A[:, 20, col + u["n32"]] = _cross(-rho[:, j], dn[:, j])
    b = np.concatenate(
        [
            np.concatenate([F1, M1[..., None]], axis=-1).reshape(n, 9),
            np.concatenate([F2, M2[..., None]], axis=-1).reshape(n, 9),
            F3,
            M3[:, None],
        ],
        axis=-1,
    )
    if robot.spring is not None:  # the springs with dampers of the joints: −k·(q − q_rest) − c·q̇
        actuator, revolute, sleeve = (
            robot.spring.actuator,
            robot.spring.revolute,
            robot.spring.sleeve,
        )
        lambda10 = s - l0 / math.sqrt(3.0)  # P_j = B_j0 + s_j·e_j, P_j(λ10 = 0) at l0/√3
        force = -actuator.stiffness * (lambda10 - actuator.rest) - actuator.damping * sd
        # the torsion spring of piston j on link j about z0 (q = φ, link j turns with the platform)
        torque = (
            -revolute.stiffness * (pose[:, 2] - revolute.rest) - revolute.damping * velocity[:, 2]
        )
        # the sleeve's spring: link j on the platform along d_j at P_j (q = λ32_j)
        pull = -sleeve.stiffness * (lam32 - sleeve.rest) - sleeve.damping * lam32d
        arm = _cross(-rho, d)  # (P_j − G) × d_j
        b = b.copy()
        for j in range(3):
            b[:, 3 * j : 3 * j + 2] -= force[:, j, None] * _E[j]  # on piston j along e_j
            b[:, 3 * j + 2] += torque  # the piston receives −torque
            b[:, 9 + 3 * j + 2] -= torque  # link j receives +torque
            b[:, 9 + 3 * j : 9 + 3 * j + 2] += pull[:, j, None] * d[:, j]  # link j: −pull·d_j
            b[:, 18:20] -= pull[:, j, None] * d[:, j]  # the platform: +pull·d_j at P_j
            b[:, 20] -= pull[:, j] * arm[:, j]
    friction = robot.friction
    if friction is None:
        x = np.linalg.solve(A, b[..., None])[..., 0].reshape(n, 3, 7)
        result = {name: x[..., k].copy() for name, k in u.items()}
        result["p10"] = result["f10"] * sd  # input power f10·λ̇10
        return result
    # joint friction: fric10·e_j on piston j and −fric21 about z0; fric21 and −fric32·d_j
    # on link j; fric32·d_j at P_j on the platform.  fric = −(b·v + (c + μ·N)·s(v)), with
    # v = λ̇10, φ̇, λ̇32; its explicit part goes to the right-hand side, its μ part
    # (μ·s·|N|, |N| = σ·N with the sign σ of the last iterate, |F21| = û·F21 with its
    # direction û) into the matrix, iterated until the signs and directions settle.
    act, rev, slv = friction.actuator, friction.revolute, friction.sleeve
    w_legs = np.broadcast_to(velocity[:, 2, None], sd.shape)
    s10, s21, s32 = (  # round-off joint rates are zero for s(v) (rest_joint_rates)
        _rate_sign(rest_joint_rates(sd, pose, velocity, l0), act.smoothing),
        _rate_sign(w_legs, rev.smoothing),
        _rate_sign(rest_joint_rates(lam32d, pose, velocity, l0), slv.smoothing),
    )
    e10 = -(act.viscous * sd + act.coulomb * s10)
    e21 = -(rev.viscous * w_legs + rev.coulomb * s21)
    e32 = -(slv.viscous * lam32d + slv.coulomb * s32)
    lever = _cross(-rho, d)  # (P_j − G) × d_j
    b = b.copy()
    for j in range(3):
        b[:, 3 * j : 3 * j + 2] -= e10[:, j, None] * _E[j]
        b[:, 3 * j + 2] += e21[:, j]
        b[:, 9 + 3 * j : 9 + 3 * j + 2] += e32[:, j, None] * d[:, j]
        b[:, 9 + 3 * j + 2] -= e21[:, j]
        b[:, 18:20] -= e32[:, j, None] * d[:, j]
        b[:, 20] -= e32[:, j] * lever[:, j]
    k10, k21, k32 = act.mu * s10, rev.mu * rev.pin_radius * s21, slv.mu * s32  # (n, 3)
    implicit = friction.has_mu
    x = np.linalg.solve(A, b[..., None])[..., 0].reshape(n, 3, 7)
    iterations = np.zeros((n, 1))
    locked: int | None = None
    if implicit:
        for _ in range(60):
            sig10 = np.sign(x[..., u["n10"]])
            sig32 = np.sign(x[..., u["n32"]])
            f21 = np.hypot(x[..., u["f21y"]], x[..., u["f21z"]])
            safe = np.where(f21 > 0.0, f21, 1.0)
            uy, uz = x[..., u["f21y"]] / safe, x[..., u["f21z"]] / safe
            M = A.copy()
            for j in range(3):
                col = 7 * j
                # piston j: the μ part of fric10·e_j, −μ_a·s·σ·n10·e_j
                M[:, 3 * j : 3 * j + 2, col + u["n10"]] += (-k10[:, j] * sig10[:, j])[:, None] * _E[
                    j
                ]
                # −fric21 on the piston, +fric21 on link j: fric21 ∋ −μ_r r_r s (û·F21)
                for name, comp in (("f21y", uy), ("f21z", uz)):
                    term = -k21[:, j] * comp[:, j]
                    M[:, 3 * j + 2, col + u[name]] -= term
                    M[:, 9 + 3 * j + 2, col + u[name]] += term
                # −fric32·d_j on link j, +fric32·d_j on the platform: fric32 ∋ −μ_s s σ n32
                term = -k32[:, j] * sig32[:, j]
                M[:, 9 + 3 * j : 9 + 3 * j + 2, col + u["n32"]] -= term[:, None] * d[:, j]
                M[:, 18:20, col + u["n32"]] += term[:, None] * d[:, j]
                M[:, 20, col + u["n32"]] += term * lever[:, j]
            x_new = np.linalg.solve(M, b[..., None])[..., 0].reshape(n, 3, 7)
            change = np.abs(x_new - x).max(axis=(-1, -2))
            settled = change <= 1e-14 * (np.abs(x_new).max(axis=(-1, -2)) + 1.0)
            iterations[~settled] += 1
            x = x_new
            if settled.all():
                break
        consistent = (
            (np.sign(x[..., u["n10"]]) * sig10 >= 0) & (np.sign(x[..., u["n32"]]) * sig32 >= 0)
        ).all(axis=-1) & settled
        if not consistent.all():
            locked = int(np.flatnonzero(~consistent)[0])
    result = {name: x[..., k].copy() for name, k in u.items()}
    result["p10"] = result["f10"] * sd  # input power f10·λ̇10
    n21 = np.hypot(result["f21y"], result["f21z"])
    result["fric10"] = e10 - k10 * np.abs(result["n10"])
    result["fric21"] = e21 - k21 * n21
    result["fric32"] = e32 - k32 * np.abs(result["n32"])
    result["iterations"] = iterations
    if locked is not None:
        result["locked"] = np.asarray(locked)
    return result
