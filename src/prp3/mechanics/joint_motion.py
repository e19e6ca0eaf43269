"""The joint motion of a platform state in closed form: eq. (10), eqs. (14) and (17).

:func:`kernel_geometry` solves the closure of each leg for its joint
displacements ``λ10_i, λ32_i`` (eq. 10), :func:`kernel_kinematics` the
conditions of connectivity for their velocities (eq. 14) and accelerations
(eq. 17), on any :class:`~prp3.mechanics.ops.Ops`; the vectors of every
joint and body are added by :mod:`prp3.mechanics.geometry` and
:mod:`prp3.mechanics.kinematics`.  :func:`rate_floor` and :func:`rest_kinematics`
give friction's ``s(v)`` joint rates without round-off.

Closed forms (``J`` the +90° rotation, ``c = (c_x, c_y) = (l0/2)(1/√3, 1)``,
``d_i = Rot(φ)·a_i``, ``D = sin(φ − π/3) = e_i × d_i``, ``C = cos(φ − π/3) = e_i·d_i``
for the three legs, ``(p, q) = Rot(φ)·c``):

* eq. (10): ``λ32_i = (n_i·G + l0/2 − q)/D``,
  ``λ10_i = (G × d_i − l0·cos φ + l0/2)/D − l0/√3``;
* eq. (14): ``λ̇32_i = (n_i·Ġ − φ̇·(C·λ32_i + p))/D``,
  ``λ̇10_i = (Ġ × d_i + φ̇·ρ_i·d_i)/D`` with ``ρ_i·d_i = λ32_i − c_x``;
* eq. (17): ``λ̈32_i = (n_i·G̈ − φ̈·(C·λ32_i + p) + φ̇²·(D·λ32_i + q) − 2φ̇·C·λ̇32_i)/D``,
  ``λ̈10_i = (G̈ × d_i + φ̈·ρ_i·d_i − (l0/2)·φ̇² + 2φ̇·λ̇32_i)/D``.

With ``Rot(π/3)·c = (−c_x, c_y)``, ``(p, q) = (−c_x·C − c_y·D, c_y·C − c_x·D)``, so
``l0/2 − q = c_y·(1 − C) + c_x·D`` and, with ``E = c_y·(1 − C)/D``:
``ρ_i·d_i = n_i·G/D + E``, ``C·λ32_i + p = C·n_i·G/D − E`` and
``D·λ32_i + q = n_i·G + c_y``: ``p`` and ``q`` themselves are never needed.

Every per-leg quantity of the kinematics is a combination ``u_x·n_ix + u_y·n_iy + u_1``
of the leg normal ``n_i``: the kernel computes the three coefficients once per
sample and combines them per leg.

Examples
--------
Two samples at once on arrays, the centre and ``G`` moved 0.1 m along ``x0``:

>>> import numpy as np
>>> from prp3.mechanics.ops import NUMPY
>>> from prp3.mechanics.parameters import kernel_parameters
>>> from prp3.model.robot import Robot
>>> k = kernel_parameters(Robot())
>>> geo = kernel_geometry(NUMPY, k, np.array([0.0, 0.1]), np.zeros(2), np.zeros(2))
>>> np.round(geo.lambda10[2], 4)      # leg C
array([0. , 0.1])
>>> kin = kernel_kinematics(k, geo, np.array([0.2, 0.2]), *np.zeros((5, 2)))
>>> np.round(kin.dlambda10[2], 4)     # ẋ = 0.2 m/s
array([0.2, 0.2])
"""

from __future__ import annotations

import math
from typing import NamedTuple

from prp3.mechanics.ops import Legs, Ops, Value
from prp3.mechanics.parameters import KernelParameters
from prp3.path_validation import joint_rate_floor

__all__ = [
    "PI_3",
    "KernelGeometry",
    "KernelKinematics",
    "kernel_geometry",
    "kernel_kinematics",
    "rate_floor",
    "rest_kinematics",
]

H = math.sqrt(3.0) / 2.0  # sin(π/3)
INV_SQRT3 = 1.0 / math.sqrt(3.0)
#: ``π/3``: the singular orientation of every leg (``φ ≡ π/3 mod π``), rad.
PI_3 = math.pi / 3.0


class KernelGeometry(NamedTuple):
    """Joint displacements of one pose (eq. 10) and the functions of ``φ`` they use."""

    cos_phi: Value
    sin_phi: Value
    D: Value  # sin(φ − π/3), the determinant of every leg's closure
    C: Value  # cos(φ − π/3)
    inv: Value  # 1/D
    E: Value  # c_y·(1 − C)/D: ρ_i·d_i = λ32_i − c_x = lx·n_ix + ly·n_iy + E
    lx: Value  # λ32_i = lx·n_ix + ly·n_iy + l1
    ly: Value
    l1: Value
    lambda10: Legs
    lambda32: Legs
    phi: Value  # the pose's φ (the revolute joints' coordinate: link 2 turns with the platform)


class KernelKinematics(NamedTuple):
    """Joint velocities and accelerations of one state (eqs. 14, 17)."""

    geometry: KernelGeometry
    dlambda10: Legs
    ddlambda10: Legs
    dlambda32: Legs
    ddlambda32: Legs


def _legs(ux: Value, uy: Value, u1: Value) -> Legs:
    """``u_x·n_ix + u_y·n_iy + u_1`` for legs A, B, C (``n_B = (0, −1)``)."""
    hx = H * ux
    half = 0.5 * uy + u1
    return (half - hx, u1 - uy, half + hx)


def kernel_geometry(
    ops: Ops, k: KernelParameters, x: Value, y: Value, phi: Value
) -> KernelGeometry:
    """Joint displacements of a pose: eqs. (7)–(10) in closed form."""
    cx, cy = k.l0 * (0.5 * INV_SQRT3), k.l0 * 0.5
    psi = phi - PI_3  # φ − π/3: d_i = C·e_i + D·n_i for every leg
    D = ops.sin(psi)  # e_i × d_i = sin(φ − π/3), eq. (10)'s determinant
    C = ops.cos(psi)  # e_i·d_i = cos(φ − π/3)
    c = 0.5 * C - H * D  # cos φ = cos(ψ + π/3) (the directions d_i, the platform's offsets)
    s = H * C + 0.5 * D  # sin φ
    inv = 1 / D
    # eq. (10): λ32_i = (n_i·G + l0/2 − q)/D, (p, q) = Rot(φ)·c (eq. 8), l0/2 − q = c_y·(1 − C) + c_x·D
    E = cy * (1 - C) * inv
    lx = x * inv
    ly = y * inv
    l1 = E + cx
    # eq. (10): λ10_i = (G × d_i − l0·cos φ + l0/2)/D − l0/√3, G × d_i = (Rot(5π/6 − φ)·G) × n_i
    # and (l0/2 − l0·cos φ)/D − l0/√3 = E + c_x = l1
    ax = -(C * x + D * y) * inv
    ay = (D * x - C * y) * inv
    return KernelGeometry(
        cos_phi=c,
        sin_phi=s,
        D=D,
        C=C,
        inv=inv,
        E=E,
        lx=lx,
        ly=ly,
        l1=l1,
        lambda10=_legs(ax, ay, l1),
        lambda32=_legs(lx, ly, l1),
        phi=phi,
    )


def kernel_kinematics(
    k: KernelParameters,
    geo: KernelGeometry,
    dx: Value,
    dy: Value,
    dphi: Value,
    ddx: Value,
    ddy: Value,
    ddphi: Value,
) -> KernelKinematics:
    """Joint velocities and accelerations: eqs. (14) and (17) in closed form."""
    cy = k.l0 * 0.5
    D, C, inv, E = geo.D, geo.C, geo.inv, geo.E
    lx, ly = geo.lx, geo.ly
    # eq. (14): λ̇32_i = (n_i·Ġ − φ̇·(C·λ32_i + p))/D, C·λ32_i + p = C·n_i·G/D − E
    u = dphi * C
    vx = (dx - u * lx) * inv
    vy = (dy - u * ly) * inv
    v1 = dphi * E * inv
    # eq. (14): λ̇10_i = (Ġ × d_i + φ̇·ρ_i·d_i)/D, ρ_i·d_i = λ32_i − c_x = n_i·G/D + E
    rx = (dphi * lx - C * dx - D * dy) * inv
    ry = (dphi * ly + D * dx - C * dy) * inv
    r1 = v1
    # eq. (17): λ̈10_i = (G̈ × d_i + φ̈·ρ_i·d_i − (l0/2)·φ̇² + 2φ̇·λ̇32_i)/D
    tx = D * ddx - C * ddy  # Rot(5π/6 − φ)·G̈
    ty = C * ddx + D * ddy
    dphi2 = dphi + dphi
    w2 = dphi * dphi
    gx = (ddphi * lx + dphi2 * vx - ty) * inv
    gy = (ddphi * ly + dphi2 * vy + tx) * inv
    g1 = (ddphi * E + dphi2 * v1 - cy * w2) * inv
    # eq. (17): λ̈32_i = (n_i·G̈ − φ̈·(C·λ32_i + p) + φ̇²·(D·λ32_i + q) − 2φ̇·C·λ̇32_i)/D,
    # D·λ32_i + q = n_i·G + c_y
    b = w2 * D - ddphi * C
    e2 = dphi2 * C
    hx = (ddx + b * lx - e2 * vx) * inv
    hy = (ddy + b * ly - e2 * vy) * inv
    h1 = (cy * w2 + ddphi * E - e2 * v1) * inv
    return KernelKinematics(
        geometry=geo,
        dlambda10=_legs(rx, ry, r1),
        ddlambda10=_legs(gx, gy, g1),
        dlambda32=_legs(vx, vy, v1),
        ddlambda32=_legs(hx, hy, h1),
    )


def rate_floor(
    ops: Ops,
    k: KernelParameters,
    geo: KernelGeometry,
    x: Value,
    y: Value,
    dx: Value,
    dy: Value,
    dphi: Value,
) -> Value:
    """The size below which a joint rate is round-off (:func:`prp3.path_validation.joint_rate_floor`)."""
    speed = ops.sqrt(dx * dx + dy * dy)
    return joint_rate_floor(speed, dphi, k.l0 + ops.sqrt(x * x + y * y), geo.D)


def rest_kinematics(kin: KernelKinematics, floor: Value) -> KernelKinematics:
    """``kin`` with the joint rates ``λ̇10, λ̇32`` of at most ``floor`` zero (for friction's ``s(v)``).

    A joint rate can vanish by cancellation while the platform moves (leg B's
    ``λ̇32`` at ``φ = 0``, ``ẏ = φ̇ = 0``); each method computes that zero with
    its own round-off, and an exact-sign law would read its random sign
    (:func:`prp3.path_validation.rest_joint_rates`, which the paper and Newton–Euler apply).
    """

    def rest(rates: Legs) -> Legs:
        a, b, c = (v * (abs(v) > floor) for v in rates)
        return (a, b, c)

    return kin._replace(dlambda10=rest(kin.dlambda10), dlambda32=rest(kin.dlambda32))
