"""Shared test helpers: hypothesis strategies and an independent reference model.

Nothing in this module calls the code under test except the public
constructors :class:`prp3.Robot` and :class:`prp3.Motion` (to build inputs).
The reference model below is written from ``docs/model.md`` alone, with its own
formulas (2×2 solves with ``numpy.linalg.solve`` instead of the core's
Cramer's rule), so that a test comparing it with the core checks two
independent derivations.

Reference geometry (``docs/model.md``):

* ``α = (π/3, π, −π/3)``, ``e_i = (cos α_i, sin α_i)``, ``n_i = J·e_i`` with
  ``J`` the rotation by +90°;
* base vertices ``A0 = l0(0, −1)``, ``B0 = l0(√3/2, 1/2)``, ``C0 = l0(−√3/2, 1/2)``;
* ``P_i = B_i0 + (l0/√3 + λ10_i)·e_i``;
* ``d_i = (cos β_i, sin β_i)``, ``β_i = α_i + φ − π/3``, ``d⊥_i = J·d_i``;
* closure (eq. 10): ``G = P_i + λ32_i·d_i + Rot(α_i + φ)·c``, ``c = (l0/2)(1/√3, 1)``.

Differentiating the closure with ``ρ_i = G − P_i = λ32_i·d_i + Rot(α_i+φ)·c``
(so ``ρ̇_i = λ̇32_i·d_i + φ̇·J·ρ_i`` because ``d_i`` and ``Rot·c`` turn with
the platform), and ``s_i = l0/√3 + λ10_i``:

* ``Ġ = ṡ_i·e_i + λ̇32_i·d_i + φ̇·J·ρ_i``
* ``G̈ = s̈_i·e_i + λ̈32_i·d_i + 2·λ̇32_i·φ̇·J·d_i + φ̈·J·ρ_i − φ̇²·ρ_i``  (``J² = −1``)

each of which is a 2×2 linear system in the unknown rates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st
from numpy.typing import ArrayLike, NDArray

from prp3 import LinkParameters, Motion, PistonParameters, PlatformParameters, Robot
from prp3.errors import ParameterError
from prp3.family import ARCHITECTURES, Body, FamilyRobot, PlatformBody
from prp3.model.parameters import Load, Payload

FloatArray = NDArray[np.float64]

SQRT3 = math.sqrt(3.0)

#: α_i of docs/model.md, written out here on purpose (not imported from prp3.mechanics.geometry).
REF_ALPHA: FloatArray = np.array([math.pi / 3.0, math.pi, -math.pi / 3.0])


# ---------------------------------------------------------------- plane algebra
def unit(angle: ArrayLike) -> FloatArray:
    """``(cos a, sin a)`` for angles ``(...)``, shape ``(..., 2)``."""
    a = np.asarray(angle, dtype=np.float64)
    return np.stack([np.cos(a), np.sin(a)], axis=-1)


def turn(vector: ArrayLike) -> FloatArray:
    """``J·v``: plane vectors ``(..., 2)`` rotated by +90°."""
    v = np.asarray(vector, dtype=np.float64)
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def rotate(angle: ArrayLike, vector: ArrayLike) -> FloatArray:
    """``Rot(angle)·v`` for broadcastable angles ``(...)`` and vectors ``(..., 2)``."""
    a = np.asarray(angle, dtype=np.float64)
    v = np.asarray(vector, dtype=np.float64)
    c, s = np.cos(a), np.sin(a)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def cross(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Scalar cross product ``a_x b_y − a_y b_x`` over the last axis."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def dot(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Dot product over the last axis."""
    return np.asarray(np.sum(np.asarray(a) * np.asarray(b), axis=-1))


#: e_i and n_i of the three legs, shape (3, 2).
REF_E: FloatArray = unit(REF_ALPHA)
REF_N: FloatArray = turn(REF_E)


def ref_base(l0: float) -> FloatArray:
    """Base vertices ``A0, B0, C0`` (docs/model.md), shape (3, 2)."""
    return l0 * np.array([[0.0, -1.0], [SQRT3 / 2.0, 0.5], [-SQRT3 / 2.0, 0.5]])


def ref_slide(phi: ArrayLike) -> FloatArray:
    """``d_i`` for orientations ``φ`` of shape ``(...)``, shape ``(..., 3, 2)``."""
    return unit(np.asarray(phi, dtype=np.float64)[..., None] + REF_ALPHA - math.pi / 3.0)


def ref_platform_offset(l0: float, phi: ArrayLike) -> FloatArray:
    """``Rot(α_i + φ)·c`` with ``c = (l0/2)(1/√3, 1)``, shape ``(..., 3, 2)``."""
    c = 0.5 * l0 * np.array([1.0 / SQRT3, 1.0])
    return rotate(np.asarray(phi, dtype=np.float64)[..., None] + REF_ALPHA, c)


def ref_joint(l0: float, lambda10: ArrayLike) -> FloatArray:
    """``P_i = B_i0 + (l0/√3 + λ10_i)·e_i`` for ``λ10`` of shape ``(..., 3)``."""
    lam = np.asarray(lambda10, dtype=np.float64)
    return np.asarray(ref_base(l0) + (l0 / SQRT3 + lam)[..., None] * REF_E)


@dataclass(frozen=True)
class RefGeometry:
    """Independent inverse geometry (shapes as in prp3: ``(..., 3)``, ``(..., 3, 2)``)."""

    lambda10: FloatArray
    lambda32: FloatArray
    joint: FloatArray
    slide: FloatArray
    lever: FloatArray  # ρ_i = G − P_i


def _solve_legs(d: FloatArray, rhs: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Solve ``a·e_i + b·d_i = rhs_i`` for every leg with ``numpy.linalg.solve``."""
    e = np.broadcast_to(REF_E, d.shape)
    matrix = np.stack([e, d], axis=-1)  # columns e_i, d_i: (..., 3, 2, 2)
    solution = np.asarray(np.linalg.solve(matrix, rhs[..., None])[..., 0], dtype=np.float64)
    return solution[..., 0], solution[..., 1]


def ref_geometry(l0: float, pose: ArrayLike) -> RefGeometry:
    """Inverse geometry from the closure (eq. 10) for poses ``(..., 3)``."""
    q = np.asarray(pose, dtype=np.float64)
    G = q[..., None, :2]
    d = ref_slide(q[..., 2])
    s, lambda32 = _solve_legs(d, G - ref_base(l0) - ref_platform_offset(l0, q[..., 2]))
    lambda10 = s - l0 / SQRT3
    joint = ref_joint(l0, lambda10)
    return RefGeometry(lambda10, lambda32, joint, d, np.asarray(G - joint))


@dataclass(frozen=True)
class RefRates:
    """Independent joint rates ``λ̇10, λ̇32, λ̈10, λ̈32``, each ``(..., 3)``."""

    dlambda10: FloatArray
    dlambda32: FloatArray
    ddlambda10: FloatArray
    ddlambda32: FloatArray


def ref_rates(l0: float, pose: ArrayLike, velocity: ArrayLike, acceleration: ArrayLike) -> RefRates:
    """Joint rates from the differentiated closure (see the module docstring)."""
    q = np.asarray(pose, dtype=np.float64)
    qd = np.asarray(velocity, dtype=np.float64)
    qdd = np.asarray(acceleration, dtype=np.float64)
    geo = ref_geometry(l0, q)
    d, rho = geo.slide, geo.lever
    phid, phidd = qd[..., 2, None, None], qdd[..., 2, None, None]
    ds, dlambda32 = _solve_legs(d, qd[..., None, :2] - phid * turn(rho))
    rhs = (
        qdd[..., None, :2]
        - 2.0 * dlambda32[..., None] * phid * turn(d)
        - phidd * turn(rho)
        + phid**2 * rho
    )
    dds, ddlambda32 = _solve_legs(d, rhs)
    return RefRates(ds, dlambda32, dds, ddlambda32)


@dataclass(frozen=True)
class BodyStates:
    """Centre-of-mass position, velocity and acceleration of the 7 bodies.

    Per-leg bodies ``(..., 3, 2)``; the platform ``(..., 2)``; its angle rates ``(...)``.
    """

    piston: FloatArray
    piston_velocity: FloatArray
    piston_acceleration: FloatArray
    link: FloatArray
    link_velocity: FloatArray
    link_acceleration: FloatArray
    link_offset: FloatArray  # r2 = C2 − P
    piston_offset: FloatArray  # r1 = C1 − P
    joint: FloatArray
    platform: FloatArray
    platform_velocity: FloatArray
    platform_acceleration: FloatArray
    omega: FloatArray
    epsilon: FloatArray


def body_states(
    robot: Robot,
    lambda10: ArrayLike,
    dlambda10: ArrayLike,
    ddlambda10: ArrayLike,
    pose: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
) -> BodyStates:
    """Body states rebuilt from the actuator columns and the platform motion.

    The piston translates along ``e_i`` (``ω10 = 0``): ``Ṗ = λ̇10·e``,
    ``P̈ = λ̈10·e``.  Link 2 turns with the platform (``φ21 = φ``, eq. 7): its
    centre of mass ``C2 = P + r2``, ``r2 = c2[0]·d + c2[1]·d⊥`` has
    ``v2 = Ṗ + φ̇·J·r2`` and ``a2 = P̈ + φ̈·J·r2 − φ̇²·r2``.
    """
    lam = np.asarray(lambda10, dtype=np.float64)
    dlam = np.asarray(dlambda10, dtype=np.float64)
    ddlam = np.asarray(ddlambda10, dtype=np.float64)
    q = np.asarray(pose, dtype=np.float64)
    qd = np.asarray(velocity, dtype=np.float64)
    qdd = np.asarray(acceleration, dtype=np.float64)
    joint = ref_joint(robot.l0, lam)
    joint_velocity = dlam[..., None] * REF_E
    joint_acceleration = ddlam[..., None] * REF_E
    c1x, c1y = robot.piston.com
    piston_offset = np.broadcast_to(c1x * REF_E + c1y * REF_N, joint.shape)
    d = ref_slide(q[..., 2])
    c2x, c2y = robot.link.com
    link_offset = c2x * d + c2y * turn(d)
    phid, phidd = qd[..., 2, None, None], qdd[..., 2, None, None]
    return BodyStates(
        piston=joint + piston_offset,
        piston_velocity=joint_velocity,
        piston_acceleration=joint_acceleration,
        link=joint + link_offset,
        link_velocity=joint_velocity + phid * turn(link_offset),
        link_acceleration=joint_acceleration + phidd * turn(link_offset) - phid**2 * link_offset,
        link_offset=link_offset,
        piston_offset=np.asarray(piston_offset),
        joint=joint,
        platform=q[..., :2],
        platform_velocity=qd[..., :2],
        platform_acceleration=qdd[..., :2],
        omega=qd[..., 2],
        epsilon=qdd[..., 2],
    )


def platform_inertia(robot: Robot) -> float:
    """Platform ``I_zz`` (docs/model.md): the given value or ``m3·l²/12``, ``l = √3·l0``."""
    if robot.platform.inertia is not None:
        return robot.platform.inertia
    return robot.platform.mass * 3.0 * robot.l0**2 / 12.0


def total_mass(robot: Robot) -> float:
    """Mass of the 7 bodies (kg)."""
    return 3.0 * (robot.piston.mass + robot.link.mass) + robot.platform.mass


# ---------------------------------------------------------- finite differences
#: Central-difference weights on offsets −3..3 (6th order): first and second derivative.
FD_OFFSETS: FloatArray = np.arange(-3.0, 4.0)
FD_FIRST: FloatArray = np.array([-1.0, 9.0, -45.0, 0.0, 45.0, -9.0, 1.0]) / 60.0
FD_SECOND: FloatArray = np.array([2.0, -27.0, 270.0, -490.0, 270.0, -27.0, 2.0]) / 180.0


def stencil_times(t: ArrayLike, h: float) -> FloatArray:
    """Times ``t_k + j·h`` for ``j = −3..3``, flattened sample-major (increasing if
    the samples are more than ``6h`` apart), shape ``(7·N,)``."""
    times = np.asarray(t, dtype=np.float64)[:, None] + h * FD_OFFSETS
    return np.asarray(times.reshape(-1))


def differentiate(values: ArrayLike, h: float, samples: int) -> tuple[FloatArray, FloatArray]:
    """First and second derivatives from values on :func:`stencil_times` ``(7·N, ...)``."""
    v = np.asarray(values, dtype=np.float64)
    v = v.reshape(samples, 7, *v.shape[1:])
    first = np.tensordot(FD_FIRST, np.moveaxis(v, 1, 0), axes=1) / h
    second = np.tensordot(FD_SECOND, np.moveaxis(v, 1, 0), axes=1) / h**2
    return np.asarray(first), np.asarray(second)


# ---------------------------------------------------------- analytic motions
@dataclass(frozen=True)
class AnalyticMotion:
    """A smooth platform motion with exact derivatives.

    Each coordinate ``q_k(t) = centre_k + span_k·u_k(t)`` with
    ``u_k(t) = Σ_j a_kj·sin(w_kj·t + p_kj) + Σ_m b_km·(t/T)^m`` (m = 1, 2, 3),
    the weights normalised so that ``Σ|a| + Σ|b| ≤ 1``: ``|q_k − centre_k| ≤ span_k``
    for ``t ∈ [0, T]`` (and ``≤ 1.01·span_k`` slightly beyond).
    """

    centre: FloatArray  # (3,)
    span: FloatArray  # (3,)
    sine_weight: FloatArray  # (3, 2)
    frequency: FloatArray  # (3, 2) rad/s
    phase: FloatArray  # (3, 2) rad
    poly_weight: FloatArray  # (3, 3) weights of τ, τ², τ³
    duration: float

    def evaluate(self, t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Pose, velocity and acceleration at times ``t`` (shape ``(...)``) → ``(..., 3)``."""
        time = np.asarray(t, dtype=np.float64)[..., None, None]  # (..., 1, 1)
        arg = self.frequency * time + self.phase  # (..., 3, 2)
        w = self.frequency
        u = (self.sine_weight * np.sin(arg)).sum(-1)
        du = (self.sine_weight * w * np.cos(arg)).sum(-1)
        ddu = -(self.sine_weight * w * w * np.sin(arg)).sum(-1)
        tau = time[..., 0] / self.duration  # (..., 1)
        b1, b2, b3 = self.poly_weight[:, 0], self.poly_weight[:, 1], self.poly_weight[:, 2]
        u = u + b1 * tau + b2 * tau**2 + b3 * tau**3
        du = du + (b1 + 2.0 * b2 * tau + 3.0 * b3 * tau**2) / self.duration
        ddu = ddu + (2.0 * b2 + 6.0 * b3 * tau) / self.duration**2
        return self.centre + self.span * u, self.span * du, self.span * ddu

    def motion(self, t: ArrayLike) -> Motion:
        """The :class:`prp3.Motion` sampled at ``t`` (``(N,)`` or ``()``)."""
        pose, velocity, acceleration = self.evaluate(t)
        return Motion(
            t=np.asarray(t, dtype=np.float64),
            pose=pose,
            velocity=velocity,
            acceleration=acceleration,
        )


def _floats(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


#: Orientation range kept away from the singularity φ ≡ π/3 (mod π):
#: φ ∈ [−1.3 − 0.46, 0.3 + 0.46] = [−1.76, 0.76] gives |sin(φ − π/3)| ≥ 0.27.
PHI_CENTRE = (-1.3, 0.3)
PHI_SPAN = 0.45


@st.composite
def analytic_motions(
    draw: st.DrawFn, l0: float, rotation: bool = True, translation: bool = True
) -> AnalyticMotion:
    """Smooth motions inside the workspace, scaled by ``l0``.

    ``G`` stays within ``0.45·l0`` of ``O``; ``φ`` within the range above.
    """
    centre = np.array(
        [
            draw(_floats(-0.2, 0.2)) * l0,
            draw(_floats(-0.2, 0.2)) * l0,
            draw(_floats(*PHI_CENTRE)),
        ]
    )
    span = np.array(
        [
            draw(_floats(0.0, 0.25)) * l0 if translation else 0.0,
            draw(_floats(0.0, 0.25)) * l0 if translation else 0.0,
            draw(_floats(0.0, PHI_SPAN)) if rotation else 0.0,
        ]
    )
    raw = np.array([[draw(_floats(-1.0, 1.0)) for _ in range(5)] for _ in range(3)])
    norm = np.abs(raw).sum(axis=1, keepdims=True)
    weights = np.divide(raw, norm, out=np.zeros_like(raw), where=norm > 0)
    frequency = np.array([[draw(_floats(0.3, 5.0)) for _ in range(2)] for _ in range(3)])
    phase = np.array([[draw(_floats(0.0, 2.0 * math.pi)) for _ in range(2)] for _ in range(3)])
    return AnalyticMotion(
        centre=centre,
        span=span,
        sine_weight=weights[:, :2],
        frequency=frequency,
        phase=phase,
        poly_weight=weights[:, 2:],
        duration=draw(_floats(0.5, 2.0)),
    )


def gravities(allow_zero: bool = True) -> st.SearchStrategy[tuple[float, float]]:
    """Any gravity vector with components in [−20, 20] m/s², zero often."""
    any_vector = st.tuples(_floats(-20.0, 20.0), _floats(-20.0, 20.0))
    if allow_zero:
        return st.one_of(st.just((0.0, 0.0)), st.just((0.0, -9.81)), any_vector)
    return any_vector


@st.composite
def robots(
    draw: st.DrawFn,
    gravity: st.SearchStrategy[tuple[float, float]] | None = None,
    offsets: bool = True,
) -> Robot:
    """Random valid robots: ``l0 ∈ [0.1, 1]`` m, masses ``[0.05, 10]`` kg, inertias,
    centre-of-mass offsets up to ``0.5·l0`` (when ``offsets``), any gravity."""
    l0 = draw(_floats(0.1, 1.0))

    def offset() -> tuple[float, float]:
        if not offsets:
            return (0.0, 0.0)
        return (draw(_floats(-0.5, 0.5)) * l0, draw(_floats(-0.5, 0.5)) * l0)

    platform_inertia = draw(st.one_of(st.none(), _floats(0.0, 2.0)))
    return Robot(
        l0=l0,
        gravity=draw(gravity if gravity is not None else gravities()),
        piston=PistonParameters(
            mass=draw(_floats(0.05, 10.0)), inertia=draw(_floats(0.0, 1.0)), com=offset()
        ),
        link=LinkParameters(
            mass=draw(_floats(0.05, 10.0)), inertia=draw(_floats(0.0, 0.5)), com=offset()
        ),
        platform=PlatformParameters(mass=draw(_floats(0.05, 10.0)), inertia=platform_inertia),
    )


@st.composite
def scenarios(
    draw: st.DrawFn,
    gravity: st.SearchStrategy[tuple[float, float]] | None = None,
    offsets: bool = True,
) -> tuple[Robot, AnalyticMotion]:
    """A random robot and a random smooth motion inside its workspace."""
    robot = draw(robots(gravity=gravity, offsets=offsets))
    return robot, draw(analytic_motions(robot.l0))


@st.composite
def poses(draw: st.DrawFn, l0: float = 0.3) -> FloatArray:
    """Single non-singular poses ``(x, y, φ)``: ``|G| ≲ 0.6·l0``, ``|sin(φ − π/3)| ≥ 0.27``."""
    return np.array(
        [
            draw(_floats(-0.4, 0.4)) * l0,
            draw(_floats(-0.4, 0.4)) * l0,
            draw(_floats(PHI_CENTRE[0] - PHI_SPAN, PHI_CENTRE[1] + PHI_SPAN)),
        ]
    )


# ---------------------------------------------------------------- family robots (docs/family.md)
#: The actuations docs/family.md allows (two passive P joints refused; 3-RRP 2 singular at home).
FAMILY_ALLOWED = [
    (arch, act)
    for arch in ARCHITECTURES
    for act in (1, 2, 3)
    if [arch[2 + k] for k in range(3) if k != act - 1] != ["P", "P"] and (arch, act) != ("3-RRP", 2)
]


def loaded_family_robot(arch: str, act: int) -> FamilyRobot:
    """The default robot of ``arch`` actuated at ``act`` with a payload off centre and a load."""
    return replace(
        FamilyRobot.default(arch, act),
        payload=Payload(0.5, (0.02, -0.01), 1e-3),
        load=Load((3.0, -2.0), 0.4),
    )


def _family_float(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


@st.composite
def family_designs(draw: st.DrawFn, mujoco: bool = False) -> FamilyRobot:
    """A random design near an architecture's default, random inertias, payload, load, gravity.

    ``mujoco``: positive masses and inertias, the default leg scale (what an MJCF
    model can hold); otherwise zero masses are allowed and the leg is rescaled.
    """
    arch, act = draw(st.sampled_from(FAMILY_ALLOWED))
    base = FamilyRobot.default(arch, act)
    f = _family_float

    def jitter(p: tuple[float, float, float], size: float) -> tuple[float, float, float]:
        return (
            p[0] + draw(f(-size, size)),
            p[1] + draw(f(-size, size)),
            p[2] + draw(f(-3 * size, 3 * size)),
        )

    size = draw(st.sampled_from([0.0, 0.01, 0.03]))
    leg = replace(
        base.leg,
        joint1=jitter(base.leg.joint1, size),
        joint2=jitter(base.leg.joint2, size),
        joint3=jitter(base.leg.joint3, size),
        attachment=jitter(base.leg.attachment, size),
        scale=base.leg.scale if mujoco else draw(f(0.1, 1.0)),
    )
    least_mass, least_inertia = (0.05, 1e-4) if mujoco else (0.0, 0.0)

    def body(name: str) -> Body:
        com = (draw(f(-0.2, 0.2)), draw(f(-0.2, 0.2)))
        return Body(draw(f(least_mass, 3.0)), com, draw(f(least_inertia, 0.01)), name=name)

    platform = (0.1, 1e-3) if mujoco else (0.0, 0.0)
    try:
        return FamilyRobot(
            architecture=arch,
            actuated=act,
            leg=leg,
            link1=body("link1"),
            link2=body("link2"),
            platform=PlatformBody(draw(f(platform[0], 5.0)), draw(f(platform[1], 0.1))),
            payload=Payload(
                draw(f(0.0, 2.0)), (draw(f(-0.1, 0.1)), draw(f(-0.1, 0.1))), draw(f(0.0, 0.01))
            ),
            load=Load((draw(f(-20, 20)), draw(f(-20, 20))), draw(f(-2, 2))),
            gravity=(draw(f(-10, 10)), draw(f(-10, 10))),
        )
    except ParameterError:
        assume(False)
        raise


@st.composite
def family_motions(draw: st.DrawFn, centre: FloatArray, samples: int = 7) -> Motion:
    """``pose(t) = centre + A·sin(ωt + c)`` with its exact derivatives, t in [0, 1]."""
    amp = np.array([draw(_family_float(0.0, high)) for high in (0.02, 0.02, 0.1)])
    w = np.array([draw(_family_float(0.5, 4.0)) for _ in range(3)])
    c = np.array([draw(_family_float(-3.0, 3.0)) for _ in range(3)])
    t = np.linspace(0.0, 1.0, samples)[:, None]
    return Motion(
        t=t[:, 0],
        pose=centre + amp * np.sin(w * t + c),
        velocity=amp * w * np.cos(w * t + c),
        acceleration=-amp * w * w * np.sin(w * t + c),
    )
