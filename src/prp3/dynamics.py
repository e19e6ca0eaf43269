"""Complete inverse dynamics: actuator forces, input powers and every joint reaction.

Two independent methods give the same numbers:

* :func:`paper_method` — the paper's recursive matrix method with the principle
  of virtual work (eqs. 19–25), written for the plane: the wrench of each body
  (eqs. 19, 20, 22) is accumulated along each leg (eq. 21, the platform in
  chain A), the virtual velocities of eqs. (15)–(16) weight the accumulated
  wrenches, and eqs. (23)–(25) give ``f10``, ``f21y`` and ``f21z``.  The
  remaining reactions ``n10, m10, n32, m32`` follow from the balance of the
  piston and of link 2 of each leg.
* :func:`newton_euler` — Newton–Euler equations of the 7 bodies in maximal
  coordinates, all 21 unknowns (3 actuator forces and 18 reaction components)
  from one 21×21 linear solve per sample.

Sign conventions (``docs/model.md``): ``f10_i`` acts on piston i along ``+e_i``;
``f21y_i, f21z_i`` are the components along ``n_i`` and ``e_i`` of the force of
piston i on link 2 at ``P_i``; ``n10_i`` (along ``n_i``) and ``m10_i`` (about
``P_i``) are the guide's reaction on piston i; ``n32_i`` (along ``d⊥_i``) and
``m32_i`` (about ``P_i``) are the reaction of link 2 on the platform.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from ._checks import require_finite
from .errors import Prp3Error
from .geometry import LEG_AXIS, LEG_NORMAL, cross2, dot2
from .kinematics import Kinematics, inverse_kinematics
from .model import Robot, check_robot
from .motion import Motion

__all__ = [
    "METHODS",
    "BodyWrenches",
    "InverseDynamics",
    "body_wrenches",
    "inverse_dynamics",
    "newton_euler",
    "paper_method",
]

FloatArray = NDArray[np.float64]
Method = Literal["paper", "newton-euler"]

#: Names accepted by :func:`inverse_dynamics`'s ``method``.
METHODS: tuple[str, str] = ("paper", "newton-euler")

#: Names of the per-leg force quantities, in the order of the results table.
FORCE_NAMES: tuple[str, ...] = ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32")


@dataclass(frozen=True)
class InverseDynamics:
    """Actuator forces, input powers and joint reactions of every leg.

    Every array has shape ``(..., 3)``: the batch shape of the motion, legs
    A, B, C last.

    Attributes
    ----------
    f10 : ndarray
        Force of actuator i on its piston along ``+e_i`` (N), eq. (23).
    p10 : ndarray
        Input power ``f10·λ̇10`` of actuator i (W).
    f21y, f21z : ndarray
        Force of piston i on link 2 at ``P_i`` along ``n_i`` and ``e_i`` (N), eqs. (24), (25).
    n10 : ndarray
        Reaction of the base guide on piston i along ``n_i`` (N).
    m10 : ndarray
        Reaction moment of the base guide on piston i about ``P_i`` (N·m).
    n32 : ndarray
        Reaction of link 2 on the platform along ``d⊥_i`` (N).
    m32 : ndarray
        Reaction moment of link 2 on the platform about ``P_i`` (N·m).
    method : str
        ``"paper"`` or ``"newton-euler"``.
    """

    f10: FloatArray
    p10: FloatArray
    f21y: FloatArray
    f21z: FloatArray
    n10: FloatArray
    m10: FloatArray
    n32: FloatArray
    m32: FloatArray
    method: str


@dataclass(frozen=True)
class BodyWrenches:
    """Wrench ``(F_k0, M_k0)`` that each body needs (eq. 22): inertia minus weight.

    ``F = m·(a_C − g)`` and ``M = I·ε + r_C × F`` about the body's first joint
    (eq. 20 with the weight of eq. 19 moved to the same side): the resultant
    of all the joint forces acting on the body.

    Attributes
    ----------
    piston_force, link_force : ndarray (..., 3, 2)
        ``F10`` of each piston and ``F20`` of each link 2 (N).
    piston_moment, link_moment : ndarray (..., 3)
        ``M10`` and ``M20`` about ``P_i`` (N·m).
    platform_force : ndarray (..., 2)
        ``F30`` of the platform (N).
    platform_moment : ndarray (...)
        ``M30`` of the platform about its mass centre ``G`` (N·m).
    """

    piston_force: FloatArray
    piston_moment: FloatArray
    link_force: FloatArray
    link_moment: FloatArray
    platform_force: FloatArray
    platform_moment: FloatArray


def body_wrenches(robot: Robot, kin: Kinematics) -> BodyWrenches:
    """Wrench each body needs to follow the motion: eqs. (19), (20) and (22).

    The weight ``m_k·g`` (eq. 19) and the inertia wrench (eq. 20) of each body
    combine into ``F_k0 = m_k·(a_Ck − g)`` and
    ``M_k0 = I_k·ε_k0 + (C_k − P_i) × F_k0`` (eq. 22).

    Examples
    --------
    At rest the bodies need their weight carried: ``F30 = −m3·g``.

    >>> from prp3.motion import Motion
    >>> robot = Robot()
    >>> w = body_wrenches(robot, inverse_kinematics(robot, Motion.at_rest([0.0, 0.0, 0.0])))
    >>> w.platform_force.round(4).tolist(), w.link_force.shape
    ([0.0, 29.43], (3, 2))
    """
    g = np.asarray(robot.gravity)
    phiddot = kin.motion.acceleration[..., 2]
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    piston_force = m1 * (kin.piston_acceleration - g)  # eq. (22), ε10 = 0
    piston_moment = cross2(kin.piston_com - kin.geometry.joint, piston_force)
    link_force = m2 * (kin.link_acceleration - g)  # eq. (22)
    link_moment = robot.link.inertia * phiddot[..., None] + cross2(
        kin.link_com - kin.geometry.joint, link_force
    )
    platform_force = m3 * (kin.motion.acceleration[..., :2] - g)  # eq. (22), about G
    platform_moment = robot.platform_inertia * phiddot
    return BodyWrenches(
        piston_force=piston_force,
        piston_moment=piston_moment,
        link_force=link_force,
        link_moment=link_moment,
        platform_force=platform_force,
        platform_moment=np.asarray(platform_moment),
    )


def paper_method(robot: Robot, kin: Kinematics) -> InverseDynamics:
    """Inverse dynamics by the paper's recursive method and virtual work (eqs. 19–25).

    Parameters
    ----------
    robot : Robot
        Robot parameters.
    kin : Kinematics
        Output of :func:`~prp3.kinematics.inverse_kinematics` for ``robot``.

    Returns
    -------
    InverseDynamics
        ``f10`` (eq. 23), ``f21y`` (eq. 24), ``f21z`` (eq. 25), ``p10``, and
        ``n10, m10, n32, m32`` from the balance of pistons and links.

    Notes
    -----
    Planar form of the paper's relations.  With ``J`` the +90° rotation:

    * eq. (21) in chain A (piston A, link 2A, platform), the platform's wrench
      carried from ``A3 = P_A + λ32_A·d_A`` to ``P_A`` by ``r32 = λ32_A·d_A``;
      chains B and C hold the piston and link 2 only.
    * eq. (15) for a unit virtual velocity ``u`` of the joint ``P_j`` (the
      other joints held): projecting each leg's loop on ``d⊥_i`` and summing
      (``Σ d⊥_i = 0``) gives ``ω^v = −(d⊥_j·u)/Σ_i ρ_i·d_i``;
      ``Σ d⊥_i d⊥_iᵀ = (3/2)·1`` gives the platform's virtual velocity and
      leg A's loop along ``d_A`` gives ``v32^Av``.  The sets of eq. (16) are
      ``u = e_j`` for ``f10_j`` and ``f21z_j``, ``u = n_j`` for ``f21y_j``.
    * Eqs. (24)–(25) print ``ω21^Bv`` where ``ω21a^Bv`` is meant: every
      virtual velocity belongs to the set of eq. (16) of the force computed.
      In eq. (17) ``a20`` stands for ``a20ᵀ``.  Both slips are corrected here.

    Examples
    --------
    >>> from prp3.motion import Motion
    >>> from prp3.kinematics import inverse_kinematics
    >>> robot = Robot()
    >>> dyn = paper_method(robot, inverse_kinematics(robot, Motion.at_rest([0.0, 0.0, 0.0])))
    >>> dyn.f10.round(4).tolist()    # static central configuration, see tests
    [31.8589, -8.4957, -23.3632]
    """
    check_robot(robot)
    with np.errstate(over="ignore", invalid="ignore"):
        result = _paper_method(robot, kin)
    return _checked(result, kin)


def _checked(result: InverseDynamics, kin: Kinematics) -> InverseDynamics:
    """``result`` if every force is finite, else a TrajectoryError naming the sample."""
    require_finite(
        {name: getattr(result, name) for name in FORCE_NAMES},
        kin.motion.t.shape,
        "motion",
        kin.motion.t,
    )
    return result


def _paper_method(robot: Robot, kin: Kinematics) -> InverseDynamics:
    geo = kin.geometry
    w = body_wrenches(robot, kin)
    d, dn, rho = geo.slide, geo.slide_normal, geo.lever
    lam32_A = geo.lambda32[..., 0]
    d_A, rho_A = d[..., 0, :], rho[..., 0, :]

    # eq. (21), chain A: F3 = F30, M3 = M30 carried to A3, then to P_A through r32
    F3 = w.platform_force
    G_minus_A3 = rho_A - lam32_A[..., None] * d_A
    M3 = w.platform_moment + cross2(G_minus_A3, F3)  # about A3
    F2 = w.link_force.copy()
    M2 = w.link_moment.copy()
    F2[..., 0, :] += F3  # F2^A = F20^A + a32ᵀ F3^A
    M2[..., 0] += M3 + cross2(lam32_A[..., None] * d_A, F3)  # M2^A = M20 + M3 + r̃32 F3
    F1 = w.piston_force + F2  # F1 = F10 + a21ᵀ F2  (r21 = 0)

    # eqs. (15)-(16): virtual velocities for a unit virtual velocity of joint P_j
    rho_d = dot2(rho, d)  # ρ_i·d_i
    S = rho_d.sum(axis=-1)[..., None, None]  # Σ ρ_i·d_i
    grad_omega = -dn / S  # ω^v = grad_omega_j · u
    Q = (dn * rho_d[..., None]).sum(axis=-2)[..., None, :]  # Σ d⊥_i (ρ_i·d_i)
    dA = d_A[..., None, :]
    grad_vG_dA = (2.0 / 3.0) * (  # d_A · v_G^v, as a gradient in u
        dot2(dA, dn)[..., None] * dn + dot2(dA, Q)[..., None] * grad_omega
    )
    leg_A = np.zeros(3)
    leg_A[0] = 1.0
    grad_v32 = (
        grad_vG_dA - leg_A[:, None] * dA - cross2(rho_A, d_A)[..., None, None] * grad_omega
    )  # v32^Av = d_A·(v_G − v_PA) − ω·(ρ_A × d_A)
    omega_e, omega_n = dot2(grad_omega, LEG_AXIS), dot2(grad_omega, LEG_NORMAL)
    v32_e, v32_n = dot2(grad_v32, LEG_AXIS), dot2(grad_v32, LEG_NORMAL)

    M2_sum = M2.sum(axis=-1)[..., None]  # M2^A + M2^B + M2^C
    F3_along = dot2(F3, d_A)[..., None]  # u3ᵀ F3^A: along z3 = d_A
    f10 = dot2(F1, LEG_AXIS) + omega_e * M2_sum + v32_e * F3_along  # eq. (23)
    f21y = dot2(F2, LEG_NORMAL) + omega_n * M2_sum + v32_n * F3_along  # eq. (24)
    f21z = dot2(F2, LEG_AXIS) + omega_e * M2_sum + v32_e * F3_along  # eq. (25)

    # remaining reactions from the balance of piston and link 2 of each leg
    F21 = f21y[..., None] * LEG_NORMAL + f21z[..., None] * LEG_AXIS
    n10 = dot2(w.piston_force, LEG_NORMAL) + f21y  # piston along n_i
    m10 = w.piston_moment  # piston moments about P_i
    n32 = dot2(F21 - w.link_force, dn)  # link 2 along d⊥_i
    m32 = -w.link_moment  # link 2 moments about P_i
    return InverseDynamics(
        f10=f10,
        p10=f10 * kin.dlambda10,
        f21y=f21y,
        f21z=f21z,
        n10=n10,
        m10=np.broadcast_to(m10, f10.shape).copy(),
        n32=n32,
        m32=m32,
        method="paper",
    )


#: Samples per linear solve of :func:`newton_euler` (bounds its memory for any N).
NEWTON_EULER_CHUNK: int = 8192

#: Order of the 7 unknowns of each leg in the Newton–Euler system.
_NE_UNKNOWNS = ("f10", "n10", "m10", "f21y", "f21z", "n32", "m32")


def newton_euler(robot: Robot, kin: Kinematics) -> InverseDynamics:
    """Inverse dynamics by Newton–Euler of the 7 bodies in maximal coordinates.

    Unknowns (21): for each leg ``f10, n10, m10, f21y, f21z, n32, m32``.
    Equations (21): for each piston and each link 2 the force balance (x, y)
    and the moment balance about ``P_i``; for the platform the force balance
    and the moment balance about ``G``.  One ``21×21`` solve per sample; this
    solver shares only the kinematics with :func:`paper_method`.

    Examples
    --------
    >>> from prp3.motion import Motion
    >>> robot = Robot()
    >>> kin = inverse_kinematics(robot, Motion.at_rest([0.0, 0.0, 0.0]))
    >>> newton_euler(robot, kin).n32.round(4).tolist()
    [19.62, -9.81, -9.81]
    """
    check_robot(robot)
    with np.errstate(over="ignore", invalid="ignore"):
        result = _newton_euler(robot, kin)
    return _checked(result, kin)


def _newton_euler(robot: Robot, kin: Kinematics) -> InverseDynamics:
    geo = kin.geometry
    w = body_wrenches(robot, kin)
    batch = geo.lambda10.shape[:-1]
    u = {name: k for k, name in enumerate(_NE_UNKNOWNS)}
    template = np.zeros((21, 21))  # the entries that do not depend on the pose
    for j in range(3):
        col = 7 * j
        e, n = LEG_AXIS[j], LEG_NORMAL[j]
        # piston j: f10·e + n10·n − F21 = F10 ; m10 = M10 (about P_j)
        template[3 * j : 3 * j + 2, col + u["f10"]] = e
        template[3 * j : 3 * j + 2, col + u["n10"]] = n
        template[3 * j : 3 * j + 2, col + u["f21y"]] = -n
        template[3 * j : 3 * j + 2, col + u["f21z"]] = -e
        template[3 * j + 2, col + u["m10"]] = 1.0
        # link j: F21 − n32·d⊥ = F20 ; −m32 = M20 (about P_j)
        template[9 + 3 * j : 9 + 3 * j + 2, col + u["f21y"]] = n
        template[9 + 3 * j : 9 + 3 * j + 2, col + u["f21z"]] = e
        template[9 + 3 * j + 2, col + u["m32"]] = -1.0
        # platform: Σ m32 + (P_j − G) × n32·d⊥ = I3·φ̈
        template[20, col + u["m32"]] = 1.0
    b = np.concatenate(
        [
            np.concatenate([w.piston_force, w.piston_moment[..., None]], axis=-1).reshape(
                *batch, 9
            ),
            np.concatenate([w.link_force, w.link_moment[..., None]], axis=-1).reshape(*batch, 9),
            w.platform_force,
            w.platform_moment[..., None],
        ],
        axis=-1,
    ).reshape(-1, 21)
    dn = geo.slide_normal.reshape(-1, 3, 2)
    moment_arm = cross2(-geo.lever, geo.slide_normal).reshape(-1, 3)  # (P_j − G) × d⊥_j
    x = np.empty_like(b)
    for first in range(0, b.shape[0], NEWTON_EULER_CHUNK):  # bounded memory for any N
        rows = slice(first, first + NEWTON_EULER_CHUNK)
        A = np.broadcast_to(template, (len(b[rows]), 21, 21)).copy()
        for j in range(3):
            n32 = 7 * j + u["n32"]
            A[:, 9 + 3 * j : 9 + 3 * j + 2, n32] = -dn[rows, j]  # link j: − n32·d⊥
            A[:, 18:20, n32] = dn[rows, j]  # platform: Σ n32·d⊥ = F30
            A[:, 20, n32] = moment_arm[rows, j]
        x[rows] = np.linalg.solve(A, b[rows, :, None])[..., 0]
    per_leg = x.reshape(*batch, 3, 7)
    q = {name: per_leg[..., k].copy() for name, k in u.items()}
    return InverseDynamics(
        f10=q["f10"],
        p10=q["f10"] * kin.dlambda10,
        f21y=q["f21y"],
        f21z=q["f21z"],
        n10=q["n10"],
        m10=q["m10"],
        n32=q["n32"],
        m32=q["m32"],
        method="newton-euler",
    )


def inverse_dynamics(
    robot: Robot, motion: Motion, method: Method = "paper"
) -> tuple[Kinematics, InverseDynamics]:
    """Kinematics and complete inverse dynamics of a platform motion.

    Parameters
    ----------
    robot : Robot
    motion : Motion
        ``N`` samples or a single one.
    method : {"paper", "newton-euler"}
        :func:`paper_method` (eqs. 19–25) or :func:`newton_euler`.

    Returns
    -------
    (Kinematics, InverseDynamics)

    Examples
    --------
    >>> from prp3.motion import paper_motion
    >>> kin, dyn = inverse_dynamics(Robot(), paper_motion("vertical", samples=3))
    >>> dyn.f10.shape
    (3, 3)
    """
    if method not in METHODS:
        raise Prp3Error(f"method must be 'paper' or 'newton-euler', got {method!r}")
    kin = inverse_kinematics(robot, motion)
    solver = paper_method if method == "paper" else newton_euler
    return kin, solver(robot, kin)
