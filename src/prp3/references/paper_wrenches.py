"""The paper's dynamics, as printed (Staicu & Chablat, eqs. 19–25).

The second half of :mod:`prp3.references.paper`, after the kinematics of
:mod:`prp3.references.paper_kinematics`: one function per stage, each citing its
equations, on the quantities in the frames ``T_k`` of each leg:

* :func:`body_constants` — the masses, centres of mass ``r_k^C`` and the
  inertia tensors ``Ĵ_k`` of eq. (20) (a payload makes body 3 the platform
  with the payload);
* :func:`weight_wrenches` — eq. (19);
* :func:`inertia_wrenches` — eq. (20);
* :func:`chain_wrenches` — eq. (21), after eq. (22)'s ``F_k0, M_k0``;
* :func:`virtual_work` — eqs. (23)–(25), with the virtual velocities of eqs. (15)–(16);
* :func:`other_reactions` — the balances of piston 1 and link 2.

Arrays as in :mod:`prp3.references.paper_kinematics`: ``n`` samples, legs, bodies,
components (``(n, 3, 3, 3)`` for a vector).

>>> from prp3.model.robot import Robot
>>> mass, r_C, J, r3G = body_constants(Robot())
>>> mass[0].tolist(), r_C.shape, J.shape
([1.0, 0.75, 3.0], (3, 3, 3), (3, 3, 3, 3))
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from prp3.model.robot import Robot
from prp3.references.paper_kinematics import (
    A10,
    A32,
    SQRT3,
    THETA_1,
    U2,
    U3,
    PaperAccelerations,
    PaperGeometry,
    PaperVelocities,
    VirtualVelocities,
    mv,
    tr,
)

__all__ = [
    "body_constants",
    "chain_wrenches",
    "inertia_wrenches",
    "other_reactions",
    "virtual_work",
    "weight_wrenches",
]

FloatArray = NDArray[np.float64]

#: The platform belongs to chain A (eq. 21): 1 for leg A, 0 for legs B and C.
_CHAIN_A: FloatArray = np.array([1.0, 0.0, 0.0])
_CHAIN_A.flags.writeable = False

_mv, _T = mv, tr  # ``matrix·vector`` and ``matrixᵀ`` over the last axes


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    """``aᵀ·b`` over the last axis."""
    return np.asarray(np.sum(a * b, axis=-1))


def body_constants(robot: Robot) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Masses ``m_k``, ``r_k^C``, ``Ĵ_k`` (legs, bodies) and ``r3^G`` (frames ``T_k``).

    A payload makes body 3 the platform with the payload: their mass, mass
    centre and inertia about ``A3``.
    """
    l0 = robot.l0
    r3G = 0.5 * l0 * np.array([0.0, 1.0, -1.0 / SQRT3])  # eq. (9), A3 → G in T3
    c1, c2 = robot.piston.com, robot.link.com
    r1C = c1[0] * U3 + c1[1] * U2  # along z1 = e_i and y1 = n_i
    r2C = c2[0] * (A32.T @ U3) + c2[1] * (A32.T @ U2)  # along d_i = z3 and d⊥_i = y3, in T2
    r_C = np.stack([r1C, r2C, r3G])  # (3 bodies, 3)
    mass = np.array([robot.piston.mass, robot.link.mass, robot.platform.mass])
    inertia = np.array([robot.piston.inertia, robot.link.inertia, robot.platform_inertia])
    # the plane normal z0 in T_k: a10·u3 = a30·u3 = −u1, a20·u3 = u3 for every leg and pose
    normal = np.stack([A10[0] @ U3, U3, A32 @ U3])

    def parallel_axes(m: FloatArray, r: FloatArray) -> FloatArray:  # m(|r|²·1 − r rᵀ)
        return np.asarray(
            m[..., None, None]
            * (np.einsum("...i,...i->...", r, r)[..., None, None] * np.eye(3)
               - np.einsum("...i,...j->...ij", r, r))
        )  # fmt: skip

    # Ĵ_k (eq. 20): I_zz about the centre of mass, moved to A_k, per unit mass
    about_joint = np.einsum("k,ki,kj->kij", inertia, normal, normal) + parallel_axes(mass, r_C)
    legs = (3, 3, 3)
    r_C = np.broadcast_to(r_C, legs).copy()
    about = np.broadcast_to(about_joint, (*legs, 3)).copy()
    masses = np.broadcast_to(mass, (3, 3)).copy()  # (legs, bodies)
    payload = robot.payload
    if payload.present:  # a body fixed to the platform: body 3 is the platform and it
        # its centre from A3 in T3 of each leg: r3^G + (a30 at φ = 0)·(c_p, 0)
        a30_still = A32 @ THETA_1.T @ A10  # (3 legs, 3, 3)
        r_p = r3G + a30_still @ np.array([payload.com[0], payload.com[1], 0.0])
        total = robot.platform.mass + payload.mass
        about[:, 2] += payload.inertia * np.outer(normal[2], normal[2]) + parallel_axes(
            np.full(3, payload.mass), r_p
        )
        r_C[:, 2] = (robot.platform.mass * r3G + payload.mass * r_p) / total
        masses[:, 2] = total
    J = about / masses[..., None, None]
    return masses, r_C, J, r3G


# ---------------------------------------------------------------- eqs. (19)–(25)
def weight_wrenches(
    gravity: tuple[float, float], geo: PaperGeometry, mass: FloatArray, r_C: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Eq. (19): ``F_k* = m_k·q_k0·g``, ``M_k* = r̃_k^C·F_k*`` (about ``A_k``, in ``T_k``).

    ``mass (3 legs, 3 bodies)``, ``r_C (3, 3, 3)``; returns ``(n, 3, 3, 3)`` each.
    """
    g0 = np.array([gravity[0], gravity[1], 0.0])
    F_star = mass[..., None] * _mv(geo.a0, g0)
    return F_star, np.cross(r_C, F_star)


def inertia_wrenches(
    mass: FloatArray, r_C: FloatArray, J: FloatArray, vel: PaperVelocities, acc: PaperAccelerations
) -> tuple[FloatArray, FloatArray]:
    """Eq. (20): the inertia force and the moment of the inertia forces about ``A_k``.

    ``F_k^in = −m_k{γ_k0 + (ω̃²_k0 + ε̃_k0)·r_k^C}``,
    ``M_k^in = −m_k{r̃_k^C·γ_k0 + Ĵ_k·ε_k0 + ω̃_k0·Ĵ_k·ω_k0}``, in ``T_k``.
    """
    m = mass[..., None]
    F_in = -m * (acc.gamma + _mv(acc.omega2_epsilon, r_C))
    M_in = -m * (
        np.cross(r_C, acc.gamma) + _mv(J, acc.epsilon) + _mv(vel.omega_tilde, _mv(J, vel.omega))
    )
    return F_in, M_in


def chain_wrenches(
    geo: PaperGeometry, F0: FloatArray, M0: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Eq. (21): the wrenches accumulated along each chain, from the platform down.

    ``F_k = F_k0 + a_k+1,kᵀ·F_k+1``,
    ``M_k = M_k0 + a_k+1,kᵀ·M_k+1 + r̃_k+1,k·a_k+1,kᵀ·F_k+1``; the platform belongs
    to chain A: ``F_3 = F_30``, ``M_3 = M_30`` for leg A, ``0`` for legs B and C.
    ``F0, M0`` are eq. (22)'s ``F_k0 = −F_k^in − F_k*``, ``M_k0 = −M_k^in − M_k*``.
    """
    a21, a32, r21, r32 = geo.a[:, :, 1], geo.a[:, :, 2], geo.r[:, :, 1], geo.r[:, :, 2]
    F3 = _CHAIN_A[:, None] * F0[:, :, 2]
    M3 = _CHAIN_A[:, None] * M0[:, :, 2]
    F2 = F0[:, :, 1] + _mv(_T(a32), F3)
    M2 = M0[:, :, 1] + _mv(_T(a32), M3) + np.cross(r32, _mv(_T(a32), F3))
    F1 = F0[:, :, 0] + _mv(_T(a21), F2)
    M1 = M0[:, :, 0] + _mv(_T(a21), M2) + np.cross(r21, _mv(_T(a21), F2))
    return np.stack([F1, F2, F3], axis=2), np.stack([M1, M2, M3], axis=2)


def virtual_work(
    geo: PaperGeometry, virtual: VirtualVelocities, F: FloatArray, M: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Eqs. (23)–(25): ``f10``, ``f21y``, ``f21z`` of every leg ``l``, shape ``(n, 3)`` each.

    ``f10 = u3ᵀF1 + u3ᵀ{ω21a^Av·M2^A + v32a^Av·F3^A + ω21a^Bv·M2^B + ω21a^Cv·M2^C}``;
    ``f21y``, ``f21z`` alike with ``u2ᵀa21ᵀF2``, ``u3ᵀa21ᵀF2`` and the virtual
    velocities of their own sets of eq. (16); the braces sum over the chains.
    """
    F1, F2, F3, M2 = F[:, :, 0], F[:, :, 1], F[:, :, 2], M[:, :, 1]
    braces = np.einsum("nsli,ni->nsl", virtual.omega21_virtual, M2[..., 2]) + np.einsum(
        "nsli,ni->nsl", virtual.v32_virtual, F3[..., 2]
    )
    a21T_F2 = _mv(_T(geo.a[:, :, 1]), F2)
    f10 = F1[..., 2] + braces[:, 0]  # eq. (23)
    f21y = a21T_F2[..., 1] + braces[:, 1]  # eq. (24)
    f21z = a21T_F2[..., 2] + braces[:, 2]  # eq. (25)
    return f10, f21y, f21z


def other_reactions(
    geo: PaperGeometry, F0: FloatArray, M0: FloatArray, f21y: FloatArray, f21z: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """``n10, m10, n32, m32`` from the balances of piston 1 and link 2, shape ``(n, 3)`` each.

    Piston 1 in ``T1``: ``F10 = f10·u3 + n10·u2 − (f21y·u2 + f21z·u3)``, every
    force through ``A1``, the guide's moment ``m10`` about ``z0 = a10·u3``.
    Link 2 in ``T2``: ``F20 = a21·F21 − n32·a32ᵀu2``, ``M20 = −m32·u3`` (``z2 = z0``),
    about ``A2``.
    """
    a10, a21 = geo.a[:, :, 0], geo.a[:, :, 1]
    n10 = F0[:, :, 0, 1] + f21y
    m10 = _dot(_mv(_T(a10), M0[:, :, 0]), U3)  # u3ᵀ a10ᵀ M10
    F21 = f21y[..., None] * U2 + f21z[..., None] * U3  # in T1
    n32 = _dot(_mv(_T(A32), U2), _mv(a21, F21) - F0[:, :, 1])
    m32 = -M0[:, :, 1, 2]
    return n10, m10, n32, m32
