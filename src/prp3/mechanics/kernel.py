"""The one numeric kernel: the paper's closed form, written once for every fast path.

:func:`solve` evaluates, for one platform state, the inverse geometry (eq. 10),
the conditions of connectivity (eqs. 14, 17), the wrench each body needs
(eqs. 19, 20, 22) and the principle of virtual work with the recursion of
chain A and the virtual velocities (eqs. 15, 16, 21, 23–25), plus the
remaining joint reactions from the balance of each piston and link 2.  It uses
only ``+ − × ÷`` and the functions of an :class:`Ops` namespace, so the very
same source runs on

* plain floats with :data:`MATH` — one sample of the numpy engine;
* 1-D float64 arrays with :data:`NUMPY` — the numpy engine
  (:func:`prp3.engines.select.run_numpy`: chunks of samples, memory bounded);
* machine code: :mod:`prp3.engines.numba` compiles these very functions with
  numba (the default engine), so the stages it compiles
  (:func:`kernel_geometry`, :func:`kernel_kinematics`, :func:`body_wrenches`,
  :func:`joint_forces`) keep to arithmetic, the :class:`Ops` functions,
  tuples and named tuples — no lists, generators, ``isinstance`` or
  ``getattr`` by name (a test of each engine against the kernel on arrays
  fails otherwise);
* sympy expressions with :func:`sympy_ops` — :func:`symbolic_solution`, from
  which the regressor and generated C code are derived.

It does not validate: callers check their input first (finite, not singular,
inside the stroke).  The independent references are :mod:`prp3.references.paper` (the
paper's 3×3 matrices as printed) and :func:`prp3.references.newton_euler.newton_euler`.

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

A new effect on a body (a payload, an external load, a friction force, a
spring) is an element of :mod:`prp3.model.elements`; :func:`body_wrenches` applies
it through the element, and every path has it from there.

Examples
--------
>>> from prp3.model.robot import Robot
>>> params = kernel_parameters(Robot())
>>> sol = solve(MATH, params, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
>>> [round(f, 4) for f in sol.f10]      # static central configuration
[31.8589, -8.4957, -23.3632]
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from prp3.model import elements as _elements
from prp3.model.element_base import is_zero, rate_sign
from prp3.model.elements import FRICTIONS, LOAD, PAYLOAD
from prp3.model.robot import Robot
from prp3.path_validation import joint_rate_floor

__all__ = [
    "EFFECT_FIELDS",
    "INERTIAL_FIELDS",
    "MATH",
    "MU_STEPS",
    "NEAR_LOCK_MU",
    "NUMPY",
    "PI_3",
    "STATE_SYMBOLS",
    "BodyWrenches",
    "KernelFriction",
    "KernelGeometry",
    "KernelKinematics",
    "KernelParameters",
    "KernelSolution",
    "Ops",
    "body_wrenches",
    "dynamics",
    "friction_forces",
    "joint_forces",
    "kernel_geometry",
    "kernel_kinematics",
    "kernel_parameters",
    "rate_floor",
    "rest_kinematics",
    "solve",
    "solve_mu",
    "symbolic_parameters",
    "symbolic_solution",
    "sympy_ops",
]

FloatArray = np.ndarray[Any, np.dtype[np.float64]]
BoolArray = np.ndarray[Any, np.dtype[np.bool_]]
#: A number of the kernel: a float, a 1-D float64 array or a sympy expression.
Value = Any
#: One value per leg, ``(A, B, C)``.
Legs = tuple[Value, Value, Value]

_H = math.sqrt(3.0) / 2.0  # sin(π/3)
_INV_SQRT3 = 1.0 / math.sqrt(3.0)
#: ``π/3``: the singular orientation of every leg (``φ ≡ π/3 mod π``), rad.
PI_3 = math.pi / 3.0

#: ``α_i`` of legs A, B, C (eq. 1), rad.
ALPHA_LEGS: tuple[float, float, float] = (PI_3, math.pi, -PI_3)


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
    load_x, load_y, load_moment : Value
        The constant wrench of the environment on the platform (``[load]``):
        force at ``G`` in the fixed frame (N), moment about ``z0`` (N·m).
    actuator_viscous, actuator_coulomb, actuator_mu, actuator_smoothing : Value
        Friction of the base guide on piston i (``b_a, c_a, μ_a, v_s``).
    revolute_viscous, revolute_coulomb, revolute_mu, revolute_pin_radius, revolute_smoothing : Value
        Friction of the revolute joint at ``P_i`` (``b_r, c_r, μ_r, r_r``, smoothing).
    sleeve_viscous, sleeve_coulomb, sleeve_mu, sleeve_smoothing : Value
        Friction of the sleeve of link 2 on the platform (``b_s, c_s, μ_s``, smoothing).
    spring_stiffness, spring_rest, spring_damping : Value
        The spring with damper of each actuated joint (``k``, ``λ_rest``, ``c``).

    Every field after ``platform_inertia`` belongs to one element of
    :mod:`prp3.model.elements` (:data:`EFFECT_FIELDS`) and defaults to ``0.0``; a
    field that is the number zero adds no operation at all (the results are
    bit for bit those without it).
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
    load_x: Value = 0.0
    load_y: Value = 0.0
    load_moment: Value = 0.0
    actuator_viscous: Value = 0.0
    actuator_coulomb: Value = 0.0
    actuator_mu: Value = 0.0
    actuator_smoothing: Value = 0.0
    revolute_viscous: Value = 0.0
    revolute_coulomb: Value = 0.0
    revolute_mu: Value = 0.0
    revolute_pin_radius: Value = 0.0
    revolute_smoothing: Value = 0.0
    sleeve_viscous: Value = 0.0
    sleeve_coulomb: Value = 0.0
    sleeve_mu: Value = 0.0
    sleeve_smoothing: Value = 0.0
    spring_stiffness: Value = 0.0
    spring_rest: Value = 0.0
    spring_damping: Value = 0.0

    @property
    def has_mu(self) -> bool:
        """Whether a load-dependent friction term acts: the inverse dynamics is implicit."""
        return any(element.has_mu(self) for element in FRICTIONS)

    @property
    def has_friction(self) -> bool:
        """Whether a friction element acts (its forces read the joint rates' signs)."""
        return any(element.acts(self) for element in FRICTIONS)


#: The inertial (and geometric) fields of :class:`KernelParameters`: those of the paper's model.
INERTIAL_FIELDS: tuple[str, ...] = (
    "l0", "gravity_x", "gravity_y", "piston_mass", "piston_moment_x", "piston_moment_y",
    "link_mass", "link_moment_x", "link_moment_y", "link_inertia", "platform_mass",
    "platform_moment_x", "platform_moment_y", "platform_inertia",
)  # fmt: skip

#: The fields of :class:`KernelParameters` that the elements own (``0.0`` unless given).
EFFECT_FIELDS: tuple[str, ...] = _elements.effect_fields()

_zero = is_zero


def kernel_parameters(robot: Robot) -> KernelParameters:
    """The constants of ``robot`` for :func:`solve` (floats).

    >>> kernel_parameters(Robot()).platform_inertia   # m3·l²/12, l = l0·√3
    0.0675
    """
    m1, m2 = robot.piston.mass, robot.link.mass
    c1x, c1y = robot.piston.com
    c2x, c2y = robot.link.com
    m3, h3x, h3y, j3 = PAYLOAD.inertial(robot)  # a payload adds to the platform's parameters
    effects: dict[str, float] = {}
    for element in robot.elements:
        effects.update(element.parameters(robot))
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
        platform_mass=m3,
        platform_moment_x=h3x,
        platform_moment_y=h3y,
        platform_inertia=j3,
        **effects,
    )


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


class KernelFriction(NamedTuple):
    """Friction forces of the joints of one state, each ``(A, B, C)`` (``docs/loads_and_friction.md``).

    ``fric10``: force of the guide on piston i along ``e_i`` (N); ``fric21``:
    moment of piston i on link 2 about ``z0`` (N·m); ``fric32``: force of
    link 2 on the platform along ``d_i`` at ``P_i`` (N).
    """

    fric10: Legs
    fric21: Legs
    fric32: Legs


class KernelSolution(NamedTuple):
    """Joint motion and joint forces of one state; every field ``(A, B, C)``.

    Reactions are ``None`` unless requested.  Units and signs as
    :class:`prp3.mechanics.forces.InverseDynamics`.
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
    friction: KernelFriction | None = None
    iterations: Value | None = None
    near_lock: Value | None = None


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
    psi = phi - PI_3  # φ − π/3: d_i = C·e_i + D·n_i for every leg
    D = ops.sin(psi)  # e_i × d_i = sin(φ − π/3), eq. (10)'s determinant
    C = ops.cos(psi)  # e_i·d_i = cos(φ − π/3)
    c = 0.5 * C - _H * D  # cos φ = cos(ψ + π/3) (the directions d_i, the platform's offsets)
    s = _H * C + 0.5 * D  # sin φ
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


_s = rate_sign


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
    force = -(k.spring_stiffness * (lam - k.spring_rest)) - k.spring_damping * rate
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
    tilt = P * _INV_SQRT3
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
    load: tuple[Value, Value, Value] | None = None,
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
    load : (f_x, f_y, m_z) or None
        A time-varying wrench of the environment on the platform (force at
        ``G``, fixed frame, N; moment about ``z0``, N·m), added to ``k``'s
        constant load.

    Returns
    -------
    KernelSolution
        No validation: a singular pose divides by ``sin(φ − π/3) ≈ 0``.  With
        friction, :attr:`KernelSolution.friction` holds its forces; with
        ``μ`` terms (implicit, :func:`solve_mu`) :attr:`KernelSolution.iterations`
        the Newton iterations per sample, ``-1`` where no solution is reached
        continuously from ``μ = 0`` (a self-locking joint), and
        :attr:`KernelSolution.near_lock` whether each sample is near a lock
        (:data:`NEAR_LOCK_MU`).
    """
    geo = kernel_geometry(ops, k, x, y, phi)
    kin = kernel_kinematics(k, geo, dx, dy, dphi, ddx, ddy, ddphi)
    numeric = ops.name in ("math", "numpy")  # sympy: no friction in the generated code
    floor = rate_floor(ops, k, geo, x, y, dx, dy, dphi) if numeric and k.has_friction else None
    f10, f21y, f21z, rest, friction, iterations, near_lock = dynamics(
        ops, k, kin, ddx, ddy, dphi, ddphi, reactions=reactions, load=load, floor=floor
    )
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
        friction=friction,
        iterations=iterations,
        near_lock=near_lock,
    )


def dynamics(
    ops: Ops,
    k: KernelParameters,
    kin: KernelKinematics,
    ddx: Value,
    ddy: Value,
    dphi: Value,
    ddphi: Value,
    *,
    reactions: bool = True,
    load: tuple[Value, Value, Value] | None = None,
    floor: Value | None = None,
) -> tuple[
    Legs, Legs, Legs, tuple[Legs, Legs, Legs, Legs] | None, KernelFriction | None, Value, Value
]:
    """The joint forces of a state of known kinematics (what :func:`solve` adds to them).

    Returns ``(f10, f21y, f21z, (n10, m10, n32, m32) or None, friction,
    iterations, near_lock)``: body wrenches (:func:`body_wrenches`, with the
    load and the explicit friction), virtual work (:func:`joint_forces`) and,
    with ``μ`` terms, the implicit friction by :func:`solve_mu`
    (``iterations`` and ``near_lock`` ``None`` without).  ``floor``
    (:func:`rate_floor`): the joint rates friction reads are those of
    :func:`rest_kinematics` (round-off rates are zero for ``s(v)``).
    """
    rates = kin if floor is None else rest_kinematics(kin, floor)
    friction = friction_forces(ops, k, rates, dphi)
    wrenches = body_wrenches(k, kin, ddx, ddy, dphi, ddphi, load=load, friction=friction)
    implicit = k.has_mu
    f10, f21y, f21z, rest = joint_forces(k, kin, wrenches, reactions or implicit)
    iterations: Value | None = None
    near_lock: Value | None = None
    if implicit:
        if ops.name not in ("math", "numpy"):
            raise ValueError("the μ terms of friction are implicit: no closed form for sympy")
        assert rest is not None and friction is not None
        friction, iterations, near_lock = solve_mu(
            ops, k, rates, friction, (rest[0], f21y, f21z, rest[2]), dphi
        )
        wrenches = body_wrenches(k, kin, ddx, ddy, dphi, ddphi, load=load, friction=friction)
        f10, f21y, f21z, rest = joint_forces(k, kin, wrenches, reactions)
    return f10, f21y, f21z, rest, friction, iterations, near_lock


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


#: Steps of the continuation in ``μ`` of :func:`solve_mu` (fractions of the full ``μ``).
MU_STEPS: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0)
#: Newton iterations allowed per continuation step.
MU_MAX_ITERATIONS: int = 40
#: A sample is *near a lock* when the branch of :func:`solve_mu` reached continuously from
#: ``μ = 0`` does not extend to this multiple of the ``μ`` coefficients: friction 20 %
#: higher (well within the uncertainty of a friction coefficient) would lock it.  Every
#: sample with a second solution close by (the branch folds back before ``1.2·μ``) is one.
NEAR_LOCK_MU: float = 1.2


def solve_mu(
    ops: Ops,
    k: KernelParameters,
    kin: KernelKinematics,
    explicit: KernelFriction,
    reactions: tuple[Legs, Legs, Legs, Legs],
    dphi: Value,
) -> tuple[KernelFriction, Value, Value]:
    """The friction forces with their ``μ`` terms: the implicit problem solved per sample.

    The velocities are given, so ``s(v)`` is known and every friction force is
    ``fric = fric_e − μ·s(v)·N`` with ``fric_e`` its explicit (viscous and
    Coulomb) part and ``N`` the magnitude of its joint's reaction
    (``|n10|``, ``r_r·|F21|``, ``|n32|``).  The reactions are affine in the
    friction forces (the virtual work is linear in the body wrenches):
    ``r = r_e + R·(fric − fric_e)``, the 9 columns of ``R`` from
    :func:`joint_forces` of unit friction forces.  The 9 magnitudes ``u`` of
    the three legs solve ``u = g(r_e + R·C·u)``, ``C = diag(−μ·s)``,
    ``g = (|n10|, |F21|, |n32|)``: by Newton's method (the Jacobian
    ``I − g'·R·C`` exactly), from the solution without ``μ`` terms, the ``μ``
    raised in the steps :data:`MU_STEPS` (continuation: the branch reached
    continuously from ``μ = 0``), to round-off.  A sample whose Newton
    iteration does not converge, or whose Jacobian determinant changes sign
    on the way (a fold: the friction cone swallows the drive), has no such
    solution: ``-1`` iterations.

    Near a lock: from the solution, the continuation goes on to
    :data:`NEAR_LOCK_MU` times the ``μ`` coefficients (a discarded stage); a
    sample whose branch ends before (no convergence, a fold, a magnitude
    driven through zero) is *near a lock*: coefficients 20 % higher would lock
    it, and a second solution may lie close to the one reported (the branch
    folds back: two solutions merge at the lock).

    Returns
    -------
    (KernelFriction, iterations, near_lock)
        The friction forces, the Newton iterations of each sample (``-1``: it
        locks) and whether it is near a lock (floats and a bool for
        :data:`MATH`, arrays for :data:`NUMPY`).
    """
    single = ops.name == "math"

    def arr(value: Value) -> FloatArray:
        return np.atleast_1d(np.asarray(value, dtype=np.float64))

    n10, f21y, f21z, n32 = (np.stack([arr(v) for v in legs], axis=-1) for legs in reactions)
    samples = n10.shape[0]
    r0 = np.concatenate([n10, f21y, f21z, n32], axis=-1)  # (N, 12)
    # R: the reactions of unit friction forces (fric10_A..C, fric21_A..C, fric32_A..C)
    R = np.empty((samples, 12, 9))
    for q in range(9):
        unit = [0.0] * 9
        unit[q] = 1.0
        fr = KernelFriction(
            (unit[0], unit[1], unit[2]), (unit[3], unit[4], unit[5]), (unit[6], unit[7], unit[8])
        )
        w = body_wrenches(k, kin, 0.0, 0.0, 0.0, 0.0, friction=fr, inertia=False)
        _, fy, fz, rest = joint_forces(k, kin, w, True)
        assert rest is not None
        columns = [*rest[0], *fy, *fz, *rest[2]]
        for row, value in enumerate(columns):
            R[:, row, q] = arr(value) if not isinstance(value, float) else value
    # C = diag(−μ·s(v)) of the 9 friction forces
    mus = tuple(element.mu(k) for element in FRICTIONS)
    smooth = tuple(element.smoothing(k) for element in FRICTIONS)
    rates = tuple(element.rates(kin, dphi) for element in FRICTIONS)
    coefficient = np.empty((samples, 9))
    for a in range(3):
        for j in range(3):
            sv = arr(_s(NUMPY, arr(rates[a][j]), smooth[a]))
            coefficient[:, 3 * a + j] = -float(mus[a]) * sv
    scale = np.abs(r0).max(axis=-1) + 1.0
    u = _magnitudes(r0)[0]
    iterations = np.zeros(samples)
    failed = np.zeros(samples, dtype=bool)
    with np.errstate(all="ignore"):
        for step in MU_STEPS:
            failed |= _newton_stage(r0, R * (step * coefficient)[:, None, :], u, scale, failed,
                                    iterations)  # fmt: skip
        # near a lock: the branch ends before NEAR_LOCK_MU·μ (its result is discarded)
        beyond = u.copy()
        B = R * (NEAR_LOCK_MU * coefficient)[:, None, :]
        near = ~failed & _newton_stage(r0, B, beyond, scale, failed.copy(), None)
    iterations[failed] = -1.0
    u[failed] = 0.0
    fric = coefficient * u  # the μ terms
    values: list[Value] = []
    explicit_all = (*explicit.fric10, *explicit.fric21, *explicit.fric32)
    for q in range(9):
        total = explicit_all[q] + (float(fric[0, q]) if single else fric[:, q])
        values.append(total)
    result = KernelFriction(
        (values[0], values[1], values[2]), (values[3], values[4], values[5]),
        (values[6], values[7], values[8]),
    )  # fmt: skip
    if single:
        return result, float(iterations[0]), bool(near[0])
    return result, iterations, near


def _newton_stage(
    r0: FloatArray,
    B: FloatArray,
    u: FloatArray,
    scale: FloatArray,
    skip: BoolArray,
    iterations: FloatArray | None,
) -> BoolArray:
    """One stage of the continuation of :func:`solve_mu`: Newton on ``u = g(r0 + B·u)``.

    Updates ``u`` (and ``iterations``) in place for the samples not in
    ``skip``; returns the samples that fail: no convergence to round-off, a
    Jacobian determinant ``det(I − g'·B)`` not positive at the solution (a
    fold), or magnitudes that are not finite or negative.
    """
    eye = np.eye(9)
    done = skip.copy()
    for _ in range(MU_MAX_ITERATIONS):
        r = r0 + np.einsum("nrq,nq->nr", B, u)
        g, dg = _magnitudes(r)
        residual = u - g
        size = np.abs(residual).max(axis=-1)
        done |= size <= 8e-16 * (np.abs(u).max(axis=-1) + scale)
        active = ~done
        if not active.any():
            break
        jac = eye - np.einsum("nur,nrq->nuq", dg[active], B[active])
        u[active] = u[active] - np.linalg.solve(jac, residual[active][..., None])[..., 0]
        if iterations is not None:
            iterations[active] += 1
    r = r0 + np.einsum("nrq,nq->nr", B, u)
    _, dg = _magnitudes(r)
    det = np.linalg.det(eye - np.einsum("nur,nrq->nuq", dg, B))
    converged = done & ~skip
    bad = ~converged | ~(det > 0.0) | ~np.isfinite(u).all(axis=-1) | (u < 0.0).any(axis=-1)
    return np.asarray(bad & ~skip)


def _magnitudes(r: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``g = (|n10|, |F21|, |n32|)`` of reactions ``r (N, 12)`` and its Jacobian ``(N, 9, 12)``."""
    n10, f21y, f21z, n32 = r[:, 0:3], r[:, 3:6], r[:, 6:9], r[:, 9:12]
    f21 = np.hypot(f21y, f21z)
    g = np.concatenate([np.abs(n10), f21, np.abs(n32)], axis=-1)
    dg = np.zeros((r.shape[0], 9, 12))
    safe = np.where(f21 > 0.0, f21, 1.0)
    for j in range(3):
        dg[:, j, j] = np.sign(n10[:, j])
        dg[:, 3 + j, 3 + j] = f21y[:, j] / safe[:, j]
        dg[:, 3 + j, 6 + j] = f21z[:, j] / safe[:, j]
        dg[:, 6 + j, 9 + j] = np.sign(n32[:, j])
    return g, dg


#: Names of the state symbols of :func:`symbolic_solution`.
STATE_SYMBOLS: tuple[str, ...] = ("x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")


def symbolic_parameters(*, effects: bool = False) -> KernelParameters:
    """The parameters of :class:`KernelParameters` as sympy symbols of their fields' names.

    The inertial fields (:data:`INERTIAL_FIELDS`) are symbols; with
    ``effects=True`` also the constant load and the regressor fields of the
    elements (:attr:`prp3.model.elements.Element.regressor`: the viscous and Coulomb
    coefficients, exact sign, the spring's stiffness and damping), the other
    fields staying ``0`` (the ``μ`` terms are implicit, no closed form).
    """
    import sympy

    names = INERTIAL_FIELDS
    if effects:  # the constant load and the fields the joint forces are linear in
        names += LOAD.fields + tuple(n for e in _elements.ELEMENTS for n in e.regressor)
    return KernelParameters(**{name: sympy.Symbol(name, real=True) for name in names})


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
