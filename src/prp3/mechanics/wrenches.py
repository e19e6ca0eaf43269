"""The wrench each body needs to follow the motion: eqs. (19), (20), (22), with every element's force.

:func:`body_wrenches` gives, from the joint motion of
:mod:`prp3.mechanics.joint_motion`, the inertia wrench of each piston, each
link 2 and the platform minus its weight (eq. 22), and subtracts the forces
the elements of :mod:`prp3.model.elements` apply: the constant and the
time-varying load on the platform, the actuators' spring (:func:`_leg_spring`)
and the joint friction (:func:`_leg_friction`, whose laws
:func:`friction_forces` evaluates).  A new effect on a body (a payload, an
external load, a friction force, a spring) is an element; it is applied here,
and every path has it from here.  Plain arithmetic on tuples: the numba
engine compiles :func:`body_wrenches`.
"""

from __future__ import annotations

from typing import NamedTuple

from prp3.mechanics.joint_motion import _H, KernelKinematics
from prp3.mechanics.ops import Legs, Ops, Value
from prp3.mechanics.parameters import KernelParameters
from prp3.model.element_base import is_zero
from prp3.model.elements import FRICTIONS
from prp3.model.joint_elements import spring_force

__all__ = ["BodyWrenches", "KernelFriction", "body_wrenches", "friction_forces"]


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


class KernelFriction(NamedTuple):
    """Friction forces of the joints of one state, each ``(A, B, C)`` (``docs/loads_and_friction.md``).

    ``fric10``: force of the guide on piston i along ``e_i`` (N); ``fric21``:
    moment of piston i on link 2 about ``z0`` (N·m); ``fric32``: force of
    link 2 on the platform along ``d_i`` at ``P_i`` (N).
    """

    fric10: Legs
    fric21: Legs
    fric32: Legs


_zero = is_zero


def friction_forces(
    ops: Ops,
    k: KernelParameters,
    kin: KernelKinematics,
    dphi: Value,
    normals: tuple[Legs, Legs, Legs] | None = None,
) -> KernelFriction | None:
    """The friction forces of the joints, or ``None`` for ideal joints.

    ``fric10_i = −(b_a·λ̇10_i + (c_a + μ_a·|n10_i|)·s(λ̇10_i))``,
    ``fric21_i = −(b_r·φ̇ + (c_r + μ_r·r_r·|F21_i|)·s(φ̇))``,
    ``fric32_i = −(b_s·λ̇32_i + (c_s + μ_s·|n32_i|)·s(λ̇32_i))``.

    ``normals`` are the magnitudes ``(|n10|, |F21|, |n32|)`` of the legs for
    the ``μ`` terms; without them the ``μ`` terms are left out.
    """
    if not any(element.acts(k) for element in FRICTIONS):
        return None
    given = normals if normals is not None else (None, None, None)
    fric10, fric21, fric32 = (
        element.forces(ops, k, kin, dphi, given[a]) for a, element in enumerate(FRICTIONS)
    )
    return KernelFriction(fric10, fric21, fric32)


def body_wrenches(
    k: KernelParameters,
    kin: KernelKinematics,
    ddx: Value,
    ddy: Value,
    dphi: Value,
    ddphi: Value,
    *,
    load: tuple[Value, Value, Value] | None = None,
    friction: KernelFriction | None = None,
    inertia: bool = True,
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

    The forces the elements of :mod:`prp3.model.elements` apply are subtracted here,
    in plain arithmetic that the numba engine compiles (tuples, no objects):
    the constant load of ``k`` (:class:`~prp3.model.elements.LoadElement`) and the
    time-varying ``load = (f_x, f_y, m_z)`` on the platform at ``G``
    (:class:`~prp3.model.elements.WrenchElement`), the spring of the actuators
    (:func:`_leg_spring`, :class:`~prp3.model.elements.SpringElement`) and the joint
    ``friction`` (:func:`_leg_friction`, :class:`~prp3.model.elements.FrictionElement`,
    whose laws :func:`friction_forces` evaluates).  ``inertia=False``
    leaves the inertia wrenches, the weights, the constant load and the
    spring out (the wrenches of the friction forces alone: linear in them).
    """
    geo = kin.geometry
    c, s, D, C = geo.cos_phi, geo.sin_phi, geo.D, geo.C
    w2 = dphi * dphi
    h2x, h2y = k.link_moment_x, k.link_moment_y
    ka = h2x * D + h2y * C  # h2·n_i = −h2 × e_i
    kb = h2x * C - h2y * D  # h2·e_i
    link_e_motion = ddphi * ka + w2 * kb  # −(φ̈·J·h2 − φ̇²·h2)·e_i
    link_n_motion = ddphi * kb - w2 * ka  # (φ̈·J·h2 − φ̇²·h2)·n_i
    motion = (c, s, ka, link_e_motion, link_n_motion, ddphi)
    legs = (
        _leg_wrenches(k, _LEGS[0], kin.ddlambda10[0], motion, inertia),
        _leg_wrenches(k, _LEGS[1], kin.ddlambda10[1], motion, inertia),
        _leg_wrenches(k, _LEGS[2], kin.ddlambda10[2], motion, inertia),
    )
    # platform: F3 = m3·(G̈ − g) + φ̈·J·h − φ̇²·h, M3 = J3·φ̈ + h × (G̈ − g) about G, h = Rot(φ)·h3
    gx, gy = k.gravity_x, k.gravity_y
    hx = c * k.platform_moment_x - s * k.platform_moment_y
    hy = s * k.platform_moment_x + c * k.platform_moment_y
    ax, ay = ddx - gx, ddy - gy
    if inertia:
        platform_x = k.platform_mass * ax - ddphi * hy - w2 * hx  # eq. (22)
        platform_y = k.platform_mass * ay + ddphi * hx - w2 * hy
        platform_moment = k.platform_inertia * ddphi + hx * ay - hy * ax
    else:
        platform_x = platform_y = platform_moment = 0.0
    # the environment's wrench on the platform at G: constant [load] + time-varying load
    ext_x, ext_y, ext_m = (k.load_x, k.load_y, k.load_moment) if inertia else (0.0, 0.0, 0.0)
    if load is not None:
        ext_x = load[0] if _zero(ext_x) else ext_x + load[0]
        ext_y = load[1] if _zero(ext_y) else ext_y + load[1]
        ext_m = load[2] if _zero(ext_m) else ext_m + load[2]
    if not _zero(ext_x):
        platform_x = platform_x - ext_x
    if not _zero(ext_y):
        platform_y = platform_y - ext_y
    if not _zero(ext_m):
        platform_moment = platform_moment - ext_m
    if inertia and not (_zero(k.spring_stiffness) and _zero(k.spring_damping)):
        geo_lambda10, rate = kin.geometry.lambda10, kin.dlambda10
        legs = (
            _leg_spring(k, legs[0], geo_lambda10[0], rate[0]),
            _leg_spring(k, legs[1], geo_lambda10[1], rate[1]),
            _leg_spring(k, legs[2], geo_lambda10[2], rate[2]),
        )
    if friction is not None:
        half = 0.5 * k.l0
        for j in range(3):
            f32, dxl, dyl = friction.fric32[j], legs[j][6], legs[j][7]
            platform_x = platform_x - f32 * dxl
            platform_y = platform_y - f32 * dyl
            platform_moment = platform_moment - half * f32
        legs = (
            _leg_friction(legs[0], friction, 0, C, D),
            _leg_friction(legs[1], friction, 1, C, D),
            _leg_friction(legs[2], friction, 2, C, D),
        )
    A, B, L = legs
    return BodyWrenches(
        piston_e=(A[0], B[0], L[0]),
        piston_n=(A[1], B[1], L[1]),
        piston_moment=(A[2], B[2], L[2]),
        link_e=(A[3], B[3], L[3]),
        link_n=(A[4], B[4], L[4]),
        link_moment=(A[5], B[5], L[5]),
        platform_x=platform_x,
        platform_y=platform_y,
        platform_moment=platform_moment,
    )


#: The wrenches of one leg's piston and link 2, and ``d_i``: :func:`_leg_wrenches`.
_LegWrenches = tuple[Value, Value, Value, Value, Value, Value, Value, Value]


def _leg_wrenches(
    k: KernelParameters,
    leg: _Leg,
    gamma: Value,
    motion: tuple[Value, Value, Value, Value, Value, Value],
    inertia: bool,
) -> _LegWrenches:
    """Piston i's and link 2's wrench (eqs. 19, 20, 22) and ``d_i``, for :func:`body_wrenches`.

    ``gamma = λ̈10_i``; ``motion = (cos φ, sin φ, h2·n_i, link 2's motion terms
    along e_i and n_i, φ̈)``.  Returns the piston's force along ``e_i, n_i``
    and moment about ``P_i``, link 2's force along ``e_i, n_i`` and moment
    about ``P_i``, and ``d_i = (d_ix, d_iy)`` (zero wrenches without ``inertia``).
    """
    c, s, ka, link_e_motion, link_n_motion, ddphi = motion
    gx, gy = k.gravity_x, k.gravity_y
    m1, m2 = k.piston_mass, k.link_mass
    h1x, h1y, h2x, h2y = k.piston_moment_x, k.piston_moment_y, k.link_moment_x, k.link_moment_y
    g_e = gx * leg.ex + gy * leg.ey  # g·e_i
    g_n = gx * leg.nx + gy * leg.ny  # g·n_i
    dxl = c * leg.ax - s * leg.ay  # d_i = Rot(φ)·a_i
    dyl = s * leg.ax + c * leg.ay
    if not inertia:
        return (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, dxl, dyl)
    # piston: F10 = m1·(λ̈10·e − g), M10 = h1 × (λ̈10·e − g) about P_i
    piston_e = m1 * (gamma - g_e)
    piston_n = -m1 * g_n
    piston_moment = h1y * g_e - h1x * g_n - h1y * gamma
    # link 2: F20 = m2·(a_P − g) + φ̈·J·h2 − φ̇²·h2, M20 = J2·φ̈ + h2 × (a_P − g) about P_i
    link_e = m2 * (gamma - g_e) - link_e_motion
    link_n = link_n_motion - m2 * g_n
    h2_cross_g = h2x * (dxl * gy - dyl * gx) - h2y * (dxl * gx + dyl * gy)
    link_moment = k.link_inertia * ddphi - ka * gamma - h2_cross_g
    return (piston_e, piston_n, piston_moment, link_e, link_n, link_moment, dxl, dyl)


def _leg_spring(k: KernelParameters, w: _LegWrenches, lam: Value, rate: Value) -> _LegWrenches:
    """One leg's wrenches minus the force of the actuator's spring with damper on its piston.

    The element :class:`prp3.model.elements.SpringElement` (``[spring.actuator]``):
    ``s_i = −k·(λ10_i − λ_rest) − c·λ̇10_i`` along ``e_i`` through ``P_i``; it helps
    the actuator, as the guide's friction does.
    """
    force = spring_force(k.spring_stiffness, k.spring_rest, k.spring_damping, lam, rate)
    return (w[0] - force, w[1], w[2], w[3], w[4], w[5], w[6], w[7])


def _leg_friction(
    w: _LegWrenches, friction: KernelFriction, j: int, C: Value, D: Value
) -> _LegWrenches:
    """One leg's wrenches of :func:`_leg_wrenches` minus the friction forces on them."""
    f10, f21, f32 = friction.fric10[j], friction.fric21[j], friction.fric32[j]
    return (
        w[0] - f10,  # the guide's friction helps the actuator
        w[1],
        w[2] + f21,  # the piston receives −fric21
        w[3] + f32 * C,  # link 2 receives −fric32·d_i, d_i·e_i = C
        w[4] + f32 * D,  # d_i·n_i = D
        w[5] - f21,
        w[6],
        w[7],
    )
