"""The joint forces by the principle of virtual work: eqs. (15), (16), (21), (23)–(25).

:func:`joint_forces` turns the wrench each body needs
(:func:`prp3.mechanics.wrenches.body_wrenches`) into the actuator forces
``f10``, the forces ``f21y, f21z`` of the revolute joints and, from the
balance of each piston and link 2, the remaining joint reactions.  Plain
arithmetic on tuples: the numba engine compiles it.

Virtual work (eqs. 15, 16, 21, 23–25), with the wrenches each body needs,
``F10_i, M10_i`` (piston, about ``P_i``), ``F20_i, M20_i`` (link 2, about
``P_i``), ``F3, M3`` (platform, about ``G``).  The virtual velocities of eqs.
(15), (16) are the rows of the Jacobian of eq. (14),
``λ̇10_i = J_i·(Ġ, φ̇)``, ``J_i = (d_iy, −d_ix, r_i)/D``, ``r_i = ρ_i·d_i = λ32_i − c_x``,
and virtual work (eq. 23) is ``Jᵀ·z = (F3, M)`` for
``z_i = f10_i − (F10_i + F20_i)·e_i``, with ``M = Σ_i M20_i + M3`` (eq. 21: the
links turn with the platform).  The legs are turned by 120°, so
``Σ_i d_i = 0`` and ``Σ_i d_i·d_iᵀ = (3/2)·I``; in the frame turned by
``ψ = φ − π/3``, in which each ``d_i`` has the direction of ``e_i``
(``d_i = Rot(ψ)·e_i``), the platform's force is ``F̃ = Rot(−ψ)·F3``, and the
solution is ``z_i = D·ν_i`` with

``ν_i = ν₀ − (2/3)·n_i·F̃``,  ``ν₀ = (M + (lx, ly)·F̃)/(3·E)``  (``(lx, ly) = G/D``,
``Σ_i r_i = 3·E``).

Then

* ``f21z_j = F20_j·e_j + D·ν_j`` (eq. 25), ``f21y_j = F20_j·n_j − C·ν_j`` (eq. 24);
* ``f10_j = F10_j·e_j + f21z_j`` (eq. 23);
* reactions: ``n10_j = F10_j·n_j + f21y_j``, ``m10_j = M10_j``, ``n32_j = −ν_j``
  (the balance of link 2 across its sleeve, ``d⊥_j = C·n_j − D·e_j``),
  ``m32_j = −M20_j``.


Examples
--------
>>> from prp3.mechanics.joint_motion import kernel_geometry, kernel_kinematics
>>> from prp3.mechanics.ops import MATH
>>> from prp3.mechanics.parameters import kernel_parameters
>>> from prp3.mechanics.wrenches import body_wrenches
>>> from prp3.model.robot import Robot
>>> k = kernel_parameters(Robot())
>>> kin = kernel_kinematics(k, kernel_geometry(MATH, k, 0.0, 0.0, 0.0), *[0.0] * 6)
>>> f10, f21y, f21z, _ = joint_forces(k, kin, body_wrenches(k, kin, 0.0, 0.0, 0.0, 0.0))
>>> [round(f, 4) for f in f10]      # static central configuration
[31.8589, -8.4957, -23.3632]
"""

from __future__ import annotations

from prp3.mechanics.joint_motion import INV_SQRT3, KernelKinematics
from prp3.mechanics.ops import Legs
from prp3.mechanics.parameters import KernelParameters
from prp3.mechanics.wrenches import BodyWrenches

__all__ = ["joint_forces"]


def joint_forces(
    k: KernelParameters, kin: KernelKinematics, w: BodyWrenches, reactions: bool = True
) -> tuple[Legs, Legs, Legs, tuple[Legs, Legs, Legs, Legs] | None]:
    """``f10, f21y, f21z`` by virtual work (eqs. 15, 16, 21, 23–25), and the reactions.

    Returns ``(f10, f21y, f21z, (n10, m10, n32, m32) or None)``.
    """
    geo = kin.geometry
    D, C, lx, ly = geo.D, geo.C, geo.lx, geo.ly
    F3x, F3y = w.platform_x, w.platform_y
    # eq. (21): the moment the platform and the links need about z0 (the links turn with φ)
    M = w.link_moment[0] + w.link_moment[1] + w.link_moment[2] + w.platform_moment
    # eqs. (15), (16), (23): virtual work with λ̇10_i = J_i·(Ġ, φ̇), J_i = (d_iy, −d_ix, r_i)/D,
    # r_i = ρ_i·d_i = λ32_i − c_x, is Jᵀ·z = (F3, M) for z_i = f10_i − (F10_i + F20_i)·e_i.
    # With Σ d_i = 0 and Σ d_i·d_iᵀ = (3/2)·I, in the frame turned by ψ = φ − π/3 (d_i = Rot(ψ)·e_i)
    # with F̃ = (P, Q) = Rot(−ψ)·F3: z_i = D·ν_i, ν_i = ν₀ − (2/3)·n_i·F̃, ν₀ = (M + (lx, ly)·F̃)/(3E)
    P = C * F3x + D * F3y
    Q = C * F3y - D * F3x
    common = (M + (lx * P + ly * Q)) / (3 * geo.E)  # ν₀, Σ_i r_i = 3·E (Σ n_i = 0)
    third = common - Q * (1.0 / 3.0)
    tilt = P * INV_SQRT3
    # ν_i = −n32_i: (ν₀ + P/√3 − Q/3, ν₀ + 2Q/3, ν₀ − P/√3 − Q/3), n_A, n_B, n_C as _LEGS
    normal = (third + tilt, common + Q * (2.0 / 3.0), third - tilt)
    # eq. (25): f21z_j = F20_j·e_j + z_j; eq. (24): f21y_j = F20_j·n_j − C·ν_j
    f21z = (w.link_e[0] + D * normal[0], w.link_e[1] + D * normal[1], w.link_e[2] + D * normal[2])
    f21y = (w.link_n[0] - C * normal[0], w.link_n[1] - C * normal[1], w.link_n[2] - C * normal[2])
    # eq. (23)
    f10 = (w.piston_e[0] + f21z[0], w.piston_e[1] + f21z[1], w.piston_e[2] + f21z[2])
    if not reactions:
        return f10, f21y, f21z, None
    # balance of each piston (along n_i, moment about P_i) and link 2 (about P_i)
    n10 = (w.piston_n[0] + f21y[0], w.piston_n[1] + f21y[1], w.piston_n[2] + f21y[2])
    n32 = (-normal[0], -normal[1], -normal[2])
    m32 = (-w.link_moment[0], -w.link_moment[1], -w.link_moment[2])
    return (
        f10,
        f21y,
        f21z,
        (
            (n10[0], n10[1], n10[2]),
            w.piston_moment,
            (n32[0], n32[1], n32[2]),
            (m32[0], m32[1], m32[2]),
        ),
    )
