"""The one numeric kernel: the paper's closed form, written once for every fast path.

:func:`solve` evaluates, for one platform state, the inverse geometry (eq. 10),
the conditions of connectivity (eqs. 14, 17), the wrench each body needs
(eqs. 19, 20, 22) and the principle of virtual work with the recursion of
chain A and the virtual velocities (eqs. 15, 16, 21, 23–25), plus the
remaining joint reactions from the balance of each piston and link 2.  It uses
only ``+ − × ÷`` and the functions of an :class:`Ops` namespace, so the very
same source runs on

* plain floats with :data:`MATH` — the single-sample path of :mod:`prp3.fast`;
* 1-D float64 arrays with :data:`NUMPY` — the batch path of :mod:`prp3.fast`
  (chunks of samples, memory bounded) and :func:`prp3.dynamics.inverse_dynamics`;
* sympy expressions with :func:`sympy_ops` — :func:`symbolic_solution`, from
  which the regressor and generated C code are derived.

It does not validate: callers check their input first (finite, not singular,
inside the stroke).  The independent references are :mod:`prp3.paper` (the
paper's 3×3 matrices as printed) and :func:`prp3.newton_euler_solver.newton_euler`.

Closed forms (``J`` the +90° rotation, ``c = (c_x, c_y) = (l0/2)(1/√3, 1)``,
``d_i = Rot(φ)·a_i``, ``D = sin(φ − π/3) = e_i × d_i``, ``C = cos(φ − π/3) = e_i·d_i``
for the three legs, ``(p, q) = Rot(φ)·c``):

* eq. (10): ``λ32_i = (n_i·G + l0/2 − q)/D``,
  ``λ10_i = (G × d_i − l0·cos φ + l0/2)/D − l0/√3``;
* eq. (14): ``λ̇32_i = (n_i·Ġ − φ̇·(C·λ32_i + p))/D``,
  ``λ̇10_i = (Ġ × d_i + φ̇·ρ_i·d_i)/D`` with ``ρ_i·d_i = λ32_i − c_x``;
* eq. (17): ``λ̈32_i = (n_i·G̈ − φ̈·(C·λ32_i + p) + φ̇²·(D·λ32_i + q) − 2φ̇·C·λ̇32_i)/D``,
  ``λ̈10_i = (G̈ × d_i + φ̈·ρ_i·d_i − (l0/2)·φ̇² + 2φ̇·λ̇32_i)/D``.

Every per-leg quantity of the kinematics is a combination ``u_x·n_ix + u_y·n_iy + u_1``
of the leg normal ``n_i``: the kernel computes the three coefficients once per
sample and combines them per leg.

Virtual work (eqs. 15, 16, 21, 23–25), with the wrenches each body needs,
``F10_i, M10_i`` (piston, about ``P_i``), ``F20_i, M20_i`` (link 2, about
``P_i``), ``F3, M3`` (platform, about ``G``), ``T = d_A·F3``,
``M2 = Σ_i M20_i + M3 + ρ_A × F3`` (eq. 21, the platform in chain A),
``S·D = 3l0/2 − 3q − (√3/2)·l0·D`` and ``Z = (M2 + K·T)/S``,
``K = (2/3)·d_A·Σ_i d⊥_i(ρ_i·d_i) + l0/2``:

* ``f21z_j = F20_j·e_j + D·Z + κ_j`` (eq. 25), ``f21y_j = F20_j·n_j − C·Z + ν_j`` (eq. 24),
  with the chain-A terms ``κ_A = F3·e_A − C·T``, ``ν_A = F3·n_A − D·T`` and the
  leg terms ``κ_B = −κ_C = D·T/√3``, ``ν_B = −ν_C = −C·T/√3``;
* ``f10_j = F10_j·e_j + f21z_j`` (eq. 23);
* reactions: ``n10_j = F10_j·n_j + f21y_j``, ``m10_j = M10_j``,
  ``n32_j = C·(f21y_j − F20_j·n_j) − D·(f21z_j − F20_j·e_j)``, ``m32_j = −M20_j``.

A new effect on a body (a payload, an external load, a friction force) enters
:func:`body_wrenches` once and reaches every path from there.

Examples
--------
>>> from prp3.model import Robot
>>> params = kernel_parameters(Robot())
>>> sol = solve(MATH, params, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
>>> [round(f, 4) for f in sol.f10]      # static central configuration
[31.8589, -8.4957, -23.3632]
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any, NamedTuple

import numpy as np

from .model import Robot

__all__ = [
    "MATH",
    "NUMPY",
    "STATE_SYMBOLS",
    "BodyWrenches",
    "KernelGeometry",
    "KernelKinematics",
    "KernelParameters",
    "KernelSolution",
    "Ops",
    "body_wrenches",
    "joint_forces",
    "kernel_geometry",
    "kernel_kinematics",
    "kernel_parameters",
    "solve",
    "symbolic_parameters",
    "symbolic_solution",
    "sympy_ops",
]

#: A number of the kernel: a float, a 1-D float64 array or a sympy expression.
Value = Any
#: One value per leg, ``(A, B, C)``.
Legs = tuple[Value, Value, Value]

_H = math.sqrt(3.0) / 2.0  # sin(π/3)
_INV_SQRT3 = 1.0 / math.sqrt(3.0)

#: ``α_i`` of legs A, B, C (eq. 1), rad.
ALPHA_LEGS: tuple[float, float, float] = (math.pi / 3.0, math.pi, -math.pi / 3.0)


class _Leg(NamedTuple):
    ex: float  # e_i = (cos α_i, sin α_i)
    ey: float
    nx: float  # n_i = (−sin α_i, cos α_i)
    ny: float
    ax: float  # a_i = d_i at φ = 0: angle α_i − π/3
    ay: float


#: Exact constants of the three legs (the legs are turned by 120°).
_LEGS: tuple[_Leg, _Leg, _Leg] = (
    _Leg(0.5, _H, -_H, 0.5, 1.0, 0.0),
    _Leg(-1.0, 0.0, 0.0, -1.0, -0.5, _H),
    _Leg(0.5, -_H, _H, 0.5, -0.5, -_H),
)


@dataclass(frozen=True)
class Ops:
    """The functions the kernel needs, for one kind of number."""

    name: str
    cos: Callable[[Value], Value]
    sin: Callable[[Value], Value]
    sqrt: Callable[[Value], Value]
    tanh: Callable[[Value], Value]
    abs: Callable[[Value], Value]
    sign: Callable[[Value], Value]


def _sign_float(value: float) -> float:
    return (value > 0.0) - (value < 0.0)


#: Plain Python floats (:mod:`math`).
MATH = Ops("math", math.cos, math.sin, math.sqrt, math.tanh, abs, _sign_float)
#: 1-D float64 arrays (numpy ufuncs).
NUMPY = Ops("numpy", np.cos, np.sin, np.sqrt, np.tanh, np.abs, np.sign)


def sympy_ops() -> Ops:
    """The kernel's functions for sympy expressions (sympy imported on demand)."""
    import sympy

    return Ops("sympy", sympy.cos, sympy.sin, sympy.sqrt, sympy.tanh, sympy.Abs, sympy.sign)


@dataclass(frozen=True)
class KernelParameters:
    """The robot's constants as the closed form uses them (floats or sympy symbols).

    The inertial parameters of each body are its standard (barycentric-free)
    parameters: mass, first moments ``m·c`` and the inertia about the body's
    reference point.  The joint forces are linear in them (the regressor of
    identification), and a payload adds to the platform's.

    Attributes
    ----------
    l0 : Value
        Circumradius of base and platform (m).
    gravity_x, gravity_y : Value
        Gravity ``g`` (m/s²).
    piston_mass : Value
        ``m1`` (kg).
    piston_moment_x, piston_moment_y : Value
        ``m1·c1`` along ``(e_i, n_i)`` (kg·m), about ``P_i``.
    link_mass : Value
        ``m2`` (kg).
    link_moment_x, link_moment_y : Value
        ``m2·c2`` along ``(d_i, d⊥_i)`` (kg·m), about ``P_i``.
    link_inertia : Value
        ``I2 + m2·|c2|²``: link 2's inertia about ``P_i`` (kg·m²).
    platform_mass : Value
        ``m3`` (kg).
    platform_moment_x, platform_moment_y : Value
        First moment about ``G`` in the platform frame (kg·m): zero for the
        platform alone (``G`` is its mass centre).
    platform_inertia : Value
        Inertia about ``G`` (kg·m²).
    """

    l0: Value
    gravity_x: Value
    gravity_y: Value
    piston_mass: Value
    piston_moment_x: Value
    piston_moment_y: Value
    link_mass: Value
    link_moment_x: Value
    link_moment_y: Value
    link_inertia: Value
    platform_mass: Value
    platform_moment_x: Value
    platform_moment_y: Value
    platform_inertia: Value


def kernel_parameters(robot: Robot) -> KernelParameters:
    """The constants of ``robot`` for :func:`solve` (floats).

    >>> kernel_parameters(Robot()).platform_inertia   # m3·l²/12, l = l0·√3
    0.0675
    """
    m1, m2 = robot.piston.mass, robot.link.mass
    c1x, c1y = robot.piston.com
    c2x, c2y = robot.link.com
    return KernelParameters(
        l0=robot.l0,
        gravity_x=robot.gravity[0],
        gravity_y=robot.gravity[1],
        piston_mass=m1,
        piston_moment_x=m1 * c1x,
        piston_moment_y=m1 * c1y,
        link_mass=m2,
        link_moment_x=m2 * c2x,
        link_moment_y=m2 * c2y,
        link_inertia=robot.link.inertia + m2 * (c2x * c2x + c2y * c2y),
        platform_mass=robot.platform.mass,
        platform_moment_x=0.0,
        platform_moment_y=0.0,
        platform_inertia=robot.platform_inertia,
    )


class KernelGeometry(NamedTuple):
    """Joint displacements of one pose (eq. 10) and the functions of ``φ`` they use."""

    cos_phi: Value
    sin_phi: Value
    D: Value  # sin(φ − π/3), the determinant of every leg's closure
    C: Value  # cos(φ − π/3)
    inv: Value  # 1/D
    p: Value  # (p, q) = Rot(φ)·c
    q: Value
    lx: Value  # λ32_i = lx·n_ix + ly·n_iy + l1
    ly: Value
    l1: Value
    lambda10: Legs
    lambda32: Legs


class KernelKinematics(NamedTuple):
    """Joint velocities and accelerations of one state (eqs. 14, 17)."""

    geometry: KernelGeometry
    dlambda10: Legs
    ddlambda10: Legs
    dlambda32: Legs
    ddlambda32: Legs


class BodyWrenches(NamedTuple):
    """Wrench each body needs (eq. 22: inertia wrench minus weight and applied loads).

    Per leg: the piston's force along ``e_i, n_i`` and moment about ``P_i``,
    link 2's force along ``e_i, n_i`` and moment about ``P_i``; the platform's
    force ``(x, y)`` and moment about ``G``.
    """

    piston_e: Legs
    piston_n: Legs
    piston_moment: Legs
    link_e: Legs
    link_n: Legs
    link_moment: Legs
    platform_x: Value
    platform_y: Value
    platform_moment: Value


class KernelSolution(NamedTuple):
    """Joint motion and joint forces of one state; every field ``(A, B, C)``.

    Reactions are ``None`` unless requested.  Units and signs as
    :class:`prp3.dynamics.InverseDynamics`.
    """

    lambda10: Legs
    dlambda10: Legs
    ddlambda10: Legs
    lambda32: Legs
    dlambda32: Legs
    ddlambda32: Legs
    f10: Legs
    p10: Legs
    f21y: Legs
    f21z: Legs
    n10: Legs | None
    m10: Legs | None
    n32: Legs | None
    m32: Legs | None


def _legs(ux: Value, uy: Value, u1: Value) -> Legs:
    """``u_x·n_ix + u_y·n_iy + u_1`` for legs A, B, C (``n_B = (0, −1)``)."""
    hx = _H * ux
    half = 0.5 * uy + u1
    return (half - hx, u1 - uy, half + hx)


def kernel_geometry(
    ops: Ops, k: KernelParameters, x: Value, y: Value, phi: Value
) -> KernelGeometry:
    """Joint displacements of a pose: eqs. (7)–(10) in closed form."""
    cx, cy = k.l0 * (0.5 * _INV_SQRT3), k.l0 * 0.5
    c = ops.cos(phi)
    s = ops.sin(phi)
    D = 0.5 * s - _H * c  # e_i × d_i = sin(φ − π/3), eq. (10)'s determinant
    C = 0.5 * c + _H * s  # e_i·d_i = cos(φ − π/3)
    inv = 1 / D
    p = cx * c - cy * s  # (p, q) = Rot(φ)·c, eq. (8)
    q = cx * s + cy * c
    # eq. (10): λ32_i = (n_i·G + l0/2 − q)/D
    lx = x * inv
    ly = y * inv
    l1 = (cy - q) * inv
    # eq. (10): λ10_i = (G × d_i − l0·cos φ + l0/2)/D − l0/√3, G × d_i = (Rot(5π/6 − φ)·G) × n_i
    ax = -(C * x + D * y) * inv
    ay = (D * x - C * y) * inv
    a1 = (cy - k.l0 * c) * inv - 2 * cx
    return KernelGeometry(
        cos_phi=c,
        sin_phi=s,
        D=D,
        C=C,
        inv=inv,
        p=p,
        q=q,
        lx=lx,
        ly=ly,
        l1=l1,
        lambda10=_legs(ax, ay, a1),
        lambda32=_legs(lx, ly, l1),
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
    cx, cy = k.l0 * (0.5 * _INV_SQRT3), k.l0 * 0.5
    D, C, inv, p, q = geo.D, geo.C, geo.inv, geo.p, geo.q
    lx, ly, l1 = geo.lx, geo.ly, geo.l1
    # eq. (14): λ̇32_i = (n_i·Ġ − φ̇·(C·λ32_i + p))/D
    u = dphi * C
    vx = (dx - u * lx) * inv
    vy = (dy - u * ly) * inv
    v1 = -(u * l1 + dphi * p) * inv
    # eq. (14): λ̇10_i = (Ġ × d_i + φ̇·ρ_i·d_i)/D, ρ_i·d_i = λ32_i − c_x
    rx = (dphi * lx - C * dx - D * dy) * inv
    ry = (dphi * ly + D * dx - C * dy) * inv
    r1 = dphi * (l1 - cx) * inv
    # eq. (17): λ̈10_i = (G̈ × d_i + φ̈·ρ_i·d_i − (l0/2)·φ̇² + 2φ̇·λ̇32_i)/D
    tx = D * ddx - C * ddy  # Rot(5π/6 − φ)·G̈
    ty = C * ddx + D * ddy
    dphi2 = dphi + dphi
    w2 = dphi * dphi
    gx = (ddphi * lx + dphi2 * vx - ty) * inv
    gy = (ddphi * ly + dphi2 * vy + tx) * inv
    g1 = (ddphi * (l1 - cx) + dphi2 * v1 - cy * w2) * inv
    # eq. (17): λ̈32_i = (n_i·G̈ − φ̈·(C·λ32_i + p) + φ̇²·(D·λ32_i + q) − 2φ̇·C·λ̇32_i)/D
    b = w2 * D - ddphi * C
    e2 = dphi2 * C
    hx = (ddx + b * lx - e2 * vx) * inv
    hy = (ddy + b * ly - e2 * vy) * inv
    h1 = (b * l1 + w2 * q - ddphi * p - e2 * v1) * inv
    return KernelKinematics(
        geometry=geo,
        dlambda10=_legs(rx, ry, r1),
        ddlambda10=_legs(gx, gy, g1),
        dlambda32=_legs(vx, vy, v1),
        ddlambda32=_legs(hx, hy, h1),
    )


def body_wrenches(
    k: KernelParameters,
    kin: KernelKinematics,
    ddx: Value,
    ddy: Value,
    dphi: Value,
    ddphi: Value,
) -> BodyWrenches:
    """Wrench each body needs to follow the motion: eqs. (19), (20), (22).

    ``F = m·(a_C − g)`` and ``M = I·ε + (C − P) × m·(a_C − g)`` about the
    body's reference point (the weight of eq. 19 moved to the inertia side,
    eq. 22), written in the body's standard parameters (mass ``m``, first
    moment ``h = m·(C − P)``, inertia ``J`` about ``P``):
    ``F = m·(a_P − g) + ε·J·h − ω²·h`` and ``M = J·ε + h × (a_P − g)``.
    The piston's first moment is ``h1x·e_i + h1y·n_i`` (it only translates),
    link 2's ``h2x·d_i + h2y·d⊥_i`` and the platform's ``Rot(φ)·h3`` (they turn
    with ``φ``).  Linear in the parameters: identification's regressor.
    """
    gx, gy = k.gravity_x, k.gravity_y
    m1, m2 = k.piston_mass, k.link_mass
    h1x, h1y, h2x, h2y = k.piston_moment_x, k.piston_moment_y, k.link_moment_x, k.link_moment_y
    geo = kin.geometry
    c, s, D, C = geo.cos_phi, geo.sin_phi, geo.D, geo.C
    w2 = dphi * dphi
    ka = h2x * D + h2y * C  # h2·n_i = −h2 × e_i
    kb = h2x * C - h2y * D  # h2·e_i
    link_e_motion = ddphi * ka + w2 * kb  # −(φ̈·J·h2 − φ̇²·h2)·e_i
    link_n_motion = ddphi * kb - w2 * ka  # (φ̈·J·h2 − φ̇²·h2)·n_i
    piston_e, piston_n, piston_moment = [], [], []
    link_e, link_n, link_moment = [], [], []
    for leg, gamma in zip(_LEGS, kin.ddlambda10, strict=True):
        g_e = gx * leg.ex + gy * leg.ey  # g·e_i
        g_n = gx * leg.nx + gy * leg.ny  # g·n_i
        dxl = c * leg.ax - s * leg.ay  # d_i = Rot(φ)·a_i
        dyl = s * leg.ax + c * leg.ay
        # piston: F10 = m1·(λ̈10·e − g), M10 = h1 × (λ̈10·e − g) about P_i
        piston_e.append(m1 * (gamma - g_e))
        piston_n.append(-m1 * g_n)
        piston_moment.append(h1y * g_e - h1x * g_n - h1y * gamma)
        # link 2: F20 = m2·(a_P − g) + φ̈·J·h2 − φ̇²·h2, M20 = J2·φ̈ + h2 × (a_P − g) about P_i
        link_e.append(m2 * (gamma - g_e) - link_e_motion)
        link_n.append(link_n_motion - m2 * g_n)
        h2_cross_g = h2x * (dxl * gy - dyl * gx) - h2y * (dxl * gx + dyl * gy)
        link_moment.append(k.link_inertia * ddphi - ka * gamma - h2_cross_g)
    # platform: F3 = m3·(G̈ − g) + φ̈·J·h − φ̇²·h, M3 = J3·φ̈ + h × (G̈ − g) about G, h = Rot(φ)·h3
    hx = c * k.platform_moment_x - s * k.platform_moment_y
    hy = s * k.platform_moment_x + c * k.platform_moment_y
    ax, ay = ddx - gx, ddy - gy
    return BodyWrenches(
        piston_e=(piston_e[0], piston_e[1], piston_e[2]),
        piston_n=(piston_n[0], piston_n[1], piston_n[2]),
        piston_moment=(piston_moment[0], piston_moment[1], piston_moment[2]),
        link_e=(link_e[0], link_e[1], link_e[2]),
        link_n=(link_n[0], link_n[1], link_n[2]),
        link_moment=(link_moment[0], link_moment[1], link_moment[2]),
        platform_x=k.platform_mass * ax - ddphi * hy - w2 * hx,  # eq. (22)
        platform_y=k.platform_mass * ay + ddphi * hx - w2 * hy,
        platform_moment=k.platform_inertia * ddphi + hx * ay - hy * ax,
    )


def joint_forces(
    k: KernelParameters, kin: KernelKinematics, w: BodyWrenches, reactions: bool = True
) -> tuple[Legs, Legs, Legs, tuple[Legs, Legs, Legs, Legs] | None]:
    """``f10, f21y, f21z`` by virtual work (eqs. 15, 16, 21, 23–25), and the reactions.

    Returns ``(f10, f21y, f21z, (n10, m10, n32, m32) or None)``.
    """
    geo = kin.geometry
    c, s, D, C, p, q = geo.cos_phi, geo.sin_phi, geo.D, geo.C, geo.p, geo.q
    cy = 0.5 * k.l0
    F3x, F3y = w.platform_x, w.platform_y
    T = c * F3x + s * F3y  # d_A·F3, d_A = (cos φ, sin φ)
    # eq. (21): M2 = Σ M20_i + M3 + ρ_A × F3, ρ_A = λ32_A·d_A + Rot(α_A + φ)·c
    rho_cross_F3 = (
        geo.lambda32[0] * (c * F3y - s * F3x) + (0.5 * p - _H * q) * F3y - (_H * p + 0.5 * q) * F3x
    )
    M2 = w.link_moment[0] + w.link_moment[1] + w.link_moment[2] + w.platform_moment + rho_cross_F3
    # eqs. (15)-(16): Z = (M2 + K·T)/S, K = (2/3)·d_A·Σ d⊥_i(ρ_i·d_i) + l0/2
    SD = 1.5 * k.l0 - 3 * q - (_H * k.l0) * D  # S·D, S = Σ ρ_i·d_i
    Z = (M2 + (0.5 * geo.lx + _H * geo.ly + cy) * T) * D / SD
    DZ = D * Z
    CZ = C * Z
    DT3 = D * T * _INV_SQRT3
    CT3 = C * T * _INV_SQRT3
    # eq. (25)
    f21z = (
        w.link_e[0] + DZ + 0.5 * F3x + _H * F3y - C * T,
        w.link_e[1] + DZ + DT3,
        w.link_e[2] + DZ - DT3,
    )
    # eq. (24)
    f21y = (
        w.link_n[0] - CZ + 0.5 * F3y - _H * F3x - D * T,
        w.link_n[1] - CZ - CT3,
        w.link_n[2] - CZ + CT3,
    )
    # eq. (23)
    f10 = (w.piston_e[0] + f21z[0], w.piston_e[1] + f21z[1], w.piston_e[2] + f21z[2])
    if not reactions:
        return f10, f21y, f21z, None
    # balance of each piston (along n_i, moment about P_i) and link 2 (along d⊥_i, about P_i)
    n10 = tuple(w.piston_n[j] + f21y[j] for j in range(3))
    n32 = tuple(C * (f21y[j] - w.link_n[j]) - D * (f21z[j] - w.link_e[j]) for j in range(3))
    m32 = tuple(-w.link_moment[j] for j in range(3))
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


def solve(
    ops: Ops,
    k: KernelParameters,
    x: Value,
    y: Value,
    phi: Value,
    dx: Value,
    dy: Value,
    dphi: Value,
    ddx: Value,
    ddy: Value,
    ddphi: Value,
    *,
    reactions: bool = True,
) -> KernelSolution:
    """Joint motion and joint forces of one state (or of a chunk of states).

    Parameters
    ----------
    ops : Ops
        :data:`MATH`, :data:`NUMPY` or :func:`sympy_ops`.
    k : KernelParameters
        From :func:`kernel_parameters` (or :func:`symbolic_parameters`).
    x, y, phi, dx, dy, dphi, ddx, ddy, ddphi : Value
        Pose ``(x, y, φ)`` of the platform and its first two derivatives
        (m, rad, s): floats, equal-length 1-D arrays, or sympy expressions.
    reactions : bool
        Also compute ``n10, m10, n32, m32``.

    Returns
    -------
    KernelSolution
        No validation: a singular pose divides by ``sin(φ − π/3) ≈ 0``.
    """
    geo = kernel_geometry(ops, k, x, y, phi)
    kin = kernel_kinematics(k, geo, dx, dy, dphi, ddx, ddy, ddphi)
    wrenches = body_wrenches(k, kin, ddx, ddy, dphi, ddphi)
    f10, f21y, f21z, rest = joint_forces(k, kin, wrenches, reactions)
    v = kin.dlambda10
    p10 = (f10[0] * v[0], f10[1] * v[1], f10[2] * v[2])  # input power f10·λ̇10
    n10, m10, n32, m32 = rest if rest is not None else (None, None, None, None)
    return KernelSolution(
        lambda10=geo.lambda10,
        dlambda10=kin.dlambda10,
        ddlambda10=kin.ddlambda10,
        lambda32=geo.lambda32,
        dlambda32=kin.dlambda32,
        ddlambda32=kin.ddlambda32,
        f10=f10,
        p10=p10,
        f21y=f21y,
        f21z=f21z,
        n10=n10,
        m10=m10,
        n32=n32,
        m32=m32,
    )


#: Names of the state symbols of :func:`symbolic_solution`.
STATE_SYMBOLS: tuple[str, ...] = ("x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")


def symbolic_parameters() -> KernelParameters:
    """Every parameter of :class:`KernelParameters` as a sympy symbol of its field's name."""
    import sympy

    return KernelParameters(
        **{f.name: sympy.Symbol(f.name, real=True) for f in fields(KernelParameters)}
    )


def symbolic_solution(
    parameters: KernelParameters | Robot | None = None, reactions: bool = True
) -> tuple[tuple[Any, ...], KernelSolution]:
    """The kernel evaluated on sympy symbols: the same source as the numeric paths.

    Parameters
    ----------
    parameters : KernelParameters, Robot or None
        Numbers of a robot (its constants appear as floats), symbols of your
        own, or ``None`` for :func:`symbolic_parameters`.

    Returns
    -------
    (symbols, KernelSolution)
        The nine state symbols ``x, y, phi, dx, dy, dphi, ddx, ddy, ddphi``
        (real) and the solution as sympy expressions of them.

    Examples
    --------
    >>> import sympy
    >>> state, sol = symbolic_solution(Robot())
    >>> at_rest = dict.fromkeys(state, 0)
    >>> round(float(sol.f10[0].subs(at_rest)), 4)
    31.8589
    """
    import sympy

    if parameters is None:
        parameters = symbolic_parameters()
    elif isinstance(parameters, Robot):
        parameters = kernel_parameters(parameters)
    state = sympy.symbols(STATE_SYMBOLS, real=True)
    return tuple(state), solve(sympy_ops(), parameters, *state, reactions=reactions)
