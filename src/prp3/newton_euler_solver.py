"""Inverse dynamics by Newton–Euler: the independent check of the other two methods.

It shares nothing with the kernel (:mod:`prp3.kernel`) or the paper's matrices
(:mod:`prp3.paper`) but the robot and the motion it is given.  Its kinematics
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

from .forces import InverseDynamics, checked
from .kinematics import Kinematics
from .model import Robot, check_robot
from .motion import Motion

__all__ = ["NEWTON_EULER_CHUNK", "newton_euler"]

FloatArray = NDArray[np.float64]

#: Samples per linear solve of :func:`newton_euler` (bounds its memory for any N).
NEWTON_EULER_CHUNK: int = 8192

#: Order of the 7 unknowns of each leg in the Newton–Euler system.
_UNKNOWNS = ("f10", "n10", "m10", "f21y", "f21z", "n32", "m32")

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
        The platform motion (of a :class:`~prp3.kinematics.Kinematics`, only
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
    with np.errstate(over="ignore", invalid="ignore"):
        flat = [
            np.asarray(a, dtype=np.float64).reshape(-1, 3)
            for a in (motion.pose, motion.velocity, motion.acceleration)
        ]
        parts = [
            _solve(robot, *(a[start : start + NEWTON_EULER_CHUNK] for a in flat))
            for start in range(0, flat[0].shape[0], NEWTON_EULER_CHUNK)
        ]
    shape = motion.pose.shape
    joined = {
        name: np.concatenate([p[name] for p in parts]).reshape(shape) if parts else np.empty(shape)
        for name in (*_UNKNOWNS, "p10")
    }
    return checked(InverseDynamics(**joined, method="newton-euler"), motion.t)


def _solve(
    robot: Robot, pose: FloatArray, velocity: FloatArray, acceleration: FloatArray
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
    s, _ = _leg_solve(d, G - base - Rc)
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
    x = np.linalg.solve(A, b[..., None])[..., 0].reshape(n, 3, 7)
    result = {name: x[..., k].copy() for name, k in u.items()}
    result["p10"] = result["f10"] * sd  # input power f10·λ̇10
    return result
