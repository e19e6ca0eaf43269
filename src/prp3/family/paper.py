"""The paper's recursive matrix method, generalised to the family's leg chain.

Staicu & Chablat solve the 3-PRP with 3×3 rotation matrices between
successive frames, recursive relations for the velocities and accelerations of
every joint and body (their eqs. 11–18), the virtual-work principle for the
actuator forces (eqs. 19–23) and body balances for the joint forces (eqs.
24–25).  This module writes the same steps for any chain of
:mod:`prp3.family.chain`, in the bodies' own frames:

* ``a_{k,k−1} = R_z(Δθ_k)ᵀ`` with ``Δθ_k = γ_k (+ q_k for R)`` (``+ σ_j`` for
  ``k = 1``): components in ``F_{k−1}`` → components in ``F_k``;
  ``r_{k,k−1} = (a_k, b_k, 0) (+ q_k·(cos γ_k, sin γ_k, 0) for P)``;
* ``ω_k0 = a_{k,k−1}·ω_{k−1,0} + q̇_k·u₃`` (R),
  ``v_k0 = a_{k,k−1}·(v_{k−1,0} + ω̃_{k−1,0}·r_{k,k−1}) + q̇_k·u₁`` (P);
* ``ε_k0 = a_{k,k−1}·ε_{k−1,0} + q̈_k·u₃`` (R),
  ``γ_k0 = a_{k,k−1}·(γ_{k−1,0} + (ε̃_{k−1,0} + ω̃_{k−1,0}²)·r_{k,k−1}) + q̈_k·u₁ + 2q̇_k·ω̃_k0·u₁`` (P);
* the conditions of connectivity: the attachment frame moves with the platform,
  ``(v_E, ω_E) = (a_E0·Ġ, φ̇)``: a 3×3 linear system in ``q̇`` (and in ``q̈``,
  with the same matrix, once the terms in ``q̇`` are known);
* virtual work: for a unit rate of actuator ``L'`` with the two others locked
  (the characteristic virtual velocities), ``τ_L' = Σ_bodies (m(γ_C − g)·v_C^v + I·ε·ω^v)``
  less the virtual power of the load;
* body balances from the platform to the base in each body's frame, the joint
  conditions (``m = 0`` at a passive R, the force along ``u₁`` zero at a passive
  P, ``τ`` at the actuated joint) fixing the leg's wrench on the platform.

Every intermediate quantity is kept in :class:`PaperSteps`.

>>> from prp3.model.motion import Motion
>>> from prp3.family.model import FamilyRobot
>>> steps = paper_steps(FamilyRobot.default("3-RRR"), Motion.at_rest([0.0, 0.0, 0.0]))
>>> steps.rotation[1].shape      # a_{2,0} of every sample and leg
(1, 3, 3, 3)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.family.chain import SIGMA
from prp3.family.mechanics import (
    FamilyKinematics,
    FamilySolution,
    family_kinematics,
    joint_solution,
    motion_batch,
)
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion

__all__ = ["PaperSteps", "paper_dynamics", "paper_steps"]

FloatArray = NDArray[np.float64]

U1 = np.array([1.0, 0.0, 0.0])
U3 = np.array([0.0, 0.0, 1.0])


def rot_z(theta: FloatArray) -> FloatArray:
    """``R_z(θ)``: columns are the turned axes in the old frame, shape ``(..., 3, 3)``."""
    c, s = np.cos(theta), np.sin(theta)
    z, o = np.zeros_like(theta), np.ones_like(theta)
    return np.stack(
        [np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2
    )


def tilde(w: FloatArray) -> FloatArray:
    """The skew matrix ``ω̃`` of ``(..., 3)`` vectors: ``ω̃·r = ω × r``."""
    z = np.zeros(w.shape[:-1])
    x, y, k = w[..., 0], w[..., 1], w[..., 2]
    return np.stack(
        [np.stack([z, -k, y], -1), np.stack([k, z, -x], -1), np.stack([-y, x, z], -1)], -2
    )


def _solve(matrix: FloatArray, rhs: FloatArray) -> FloatArray:
    return np.asarray(np.linalg.solve(matrix, rhs), dtype=np.float64)


def _mv(m: FloatArray, v: FloatArray) -> FloatArray:
    return np.asarray(np.einsum("...ij,...j->...i", m, v))


def _mtv(m: FloatArray, v: FloatArray) -> FloatArray:
    return np.asarray(np.einsum("...ji,...j->...i", m, v))


class Chain:
    """The relative matrices and positions of one configuration (batch ``(N, 3 legs)``)."""

    def __init__(self, robot: FamilyRobot, q: FloatArray) -> None:
        self.types = robot.types
        placements = robot.leg.placements
        batch = q.shape[:-1]
        self.relative: list[FloatArray] = []  # a_{k,k−1}, k = 1, 2, 3, E
        self.offset: list[FloatArray] = []  # r_{k,k−1} in F_{k−1}
        for k in range(4):
            a, b, gamma = placements[k]
            turn = np.full(batch, gamma)
            if k == 0:
                turn = turn + SIGMA
            r = np.broadcast_to(np.array([a, b, 0.0]), (*batch, 3)).copy()
            if k < 3 and self.types[k] == "R":
                turn = turn + q[..., k]
            elif k < 3:
                r[..., 0] += q[..., k] * np.cos(gamma)
                r[..., 1] += q[..., k] * np.sin(gamma)
            self.relative.append(np.swapaxes(rot_z(turn), -1, -2))
            self.offset.append(r)
        self.absolute: list[FloatArray] = []  # a_{k,0}
        current = np.broadcast_to(np.eye(3), (*batch, 3, 3))
        for k in range(4):
            current = self.relative[k] @ current
            self.absolute.append(current)

    def velocities(self, dq: FloatArray) -> tuple[list[FloatArray], list[FloatArray]]:
        """``ω_k0``, ``v_k0`` (own-frame components) of F_1, F_2, F_3 and E, eqs. (11)–(14)."""
        omega = np.zeros((*dq.shape[:-1], 3))
        v = np.zeros((*dq.shape[:-1], 3))
        omegas, vs = [], []
        for k in range(4):
            a = self.relative[k]
            v = _mv(a, v + np.cross(omega, self.offset[k]))
            omega = _mv(a, omega)
            if k < 3 and self.types[k] == "R":
                omega = omega + dq[..., k, None] * U3
            elif k < 3:
                v = v + dq[..., k, None] * U1
            omegas.append(omega)
            vs.append(v)
        return omegas, vs

    def accelerations(
        self, dq: FloatArray, ddq: FloatArray
    ) -> tuple[list[FloatArray], list[FloatArray]]:
        """``ε_k0``, ``γ_k0`` (own-frame components) of F_1, F_2, F_3 and E, eqs. (15)–(18)."""
        omegas, _ = self.velocities(dq)
        omega_prev = np.zeros((*dq.shape[:-1], 3))
        eps = np.zeros_like(omega_prev)
        acc = np.zeros_like(omega_prev)
        epss, accs = [], []
        for k in range(4):
            a, r = self.relative[k], self.offset[k]
            w_tilde = tilde(omega_prev)
            acc = _mv(a, acc + _mv(tilde(eps) + w_tilde @ w_tilde, r))
            eps = _mv(a, eps)
            if k < 3 and self.types[k] == "R":
                eps = eps + ddq[..., k, None] * U3
            elif k < 3:
                slide = dq[..., k, None] * U1
                acc = acc + ddq[..., k, None] * U1 + 2.0 * np.cross(omegas[k], slide)
            omega_prev = omegas[k]
            epss.append(eps)
            accs.append(acc)
        return epss, accs

    def connectivity(self) -> FloatArray:
        """The matrix ``C`` of ``(v_E, ω_E) = C·q̇`` in E's components (x, y, z rows)."""
        columns = []
        for i in range(3):
            rates = np.zeros((*self.offset[0].shape[:-1], 3))
            rates[..., i] = 1.0
            omegas, vs = self.velocities(rates)
            columns.append(np.stack([vs[3][..., 0], vs[3][..., 1], omegas[3][..., 2]], -1))
        return np.stack(columns, -1)


@dataclass(frozen=True)
class PaperSteps:
    """Every intermediate quantity of the paper route (batch ``(N, 3 legs)`` in front).

    Attributes
    ----------
    rotation : list of ndarray
        ``a_{k,0}`` of F_1, F_2, F_3, E, shape ``(N, 3, 3, 3)``.
    relative, offset : list of ndarray
        ``a_{k,k−1}`` and ``r_{k,k−1}`` of F_1, F_2, F_3, E.
    connectivity : ndarray, shape ``(N, 3, 3, 3)``
        ``C`` with ``(v_E, ω_E) = C·q̇``.
    dq, ddq : ndarray, shape ``(N, 3, 3)``
    omega, velocity, epsilon, acceleration : list of ndarray
        ``ω_k0, v_k0, ε_k0, γ_k0`` of F_1, F_2, F_3, E (own-frame components).
    virtual_twist : ndarray, shape ``(N, 3, 3)``
        The platform's virtual twist ``(v_x, v_y, ω)`` of a unit rate of
        actuator ``L'`` (index 1), fixed frame.
    virtual_rates : ndarray, shape ``(N, 3 L', 3 legs, 3 joints)``
    tau : ndarray, shape ``(N, 3)``
    joint_force, joint_moment : ndarray, shapes ``(N, 3, 3, 3)``, ``(N, 3, 3)``
        Each joint's force (in the distal frame ``F_k``) and moment about ``O_k``.
    link_force, link_moment : ndarray, shapes ``(N, 3, 2 links, 3)``, ``(N, 3, 2)``
        What link 1 and link 2 need, ``m(γ_C − g)`` in their own frames and the
        moment about their frame origin (``I·ε + c × m(γ_C − g)``).
    platform_force, platform_moment : ndarray, shapes ``(N, 3)``, ``(N,)``
        What the legs must give the platform (payload included, load taken
        off), fixed frame, moment about ``G``.
    """

    rotation: list[FloatArray]
    relative: list[FloatArray]
    offset: list[FloatArray]
    connectivity: FloatArray
    dq: FloatArray
    ddq: FloatArray
    omega: list[FloatArray]
    velocity: list[FloatArray]
    epsilon: list[FloatArray]
    acceleration: list[FloatArray]
    virtual_twist: FloatArray
    virtual_rates: FloatArray
    tau: FloatArray
    joint_force: FloatArray
    joint_moment: FloatArray
    link_force: FloatArray
    link_moment: FloatArray
    platform_force: FloatArray
    platform_moment: FloatArray


def paper_steps(
    robot: FamilyRobot, motion: Motion, kin: FamilyKinematics | None = None
) -> PaperSteps:
    """Run the paper's method; ``kin`` (the joint values ``q``) is computed when not given."""
    if kin is None:
        kin = family_kinematics(robot, motion)
    robot = kin.robot
    _, pose, velocity, acceleration = motion_batch(kin.motion)
    n = pose.shape[0]
    q = kin.q.reshape(n, 3, 3)
    chain = Chain(robot, q)
    c = chain.connectivity()
    a_e = chain.absolute[3]

    def platform_in_e(vector: FloatArray) -> FloatArray:
        planar = np.concatenate([vector[:, :2], np.zeros((n, 1))], -1)[:, None, :]
        lin = _mv(a_e, np.broadcast_to(planar, (n, 3, 3)))
        return np.stack([lin[..., 0], lin[..., 1], np.broadcast_to(vector[:, None, 2], (n, 3))], -1)

    dq = _solve(c, platform_in_e(velocity)[..., None])[..., 0]
    eps0, acc0 = chain.accelerations(dq, np.zeros_like(dq))
    bias = np.stack([acc0[3][..., 0], acc0[3][..., 1], eps0[3][..., 2]], -1)
    ddq = _solve(c, (platform_in_e(acceleration) - bias)[..., None])[..., 0]
    omegas, vs = chain.velocities(dq)
    epss, accs = chain.accelerations(dq, ddq)

    # ---- the wrench each body needs, own-frame components, moment about its frame origin
    g3 = np.array([*robot.gravity, 0.0])
    need_f, need_m = [], []
    for k, body in ((0, robot.link1), (1, robot.link2)):
        com = np.array([*body.com, 0.0])
        a_c = accs[k] + np.cross(epss[k], com) + np.cross(omegas[k], np.cross(omegas[k], com))
        force = body.mass * (a_c - _mv(chain.absolute[k], g3))
        need_f.append(force)
        need_m.append(body.inertia * epss[k][..., 2] + np.cross(com, force)[..., 2])

    # ---- the platform (fixed frame, about G) with the payload, less the load
    phi, omega, alpha = pose[:, 2], velocity[:, 2], acceleration[:, 2]
    r = _mv(rot_z(phi), np.array([*robot.payload.com, 0.0]))
    a_g = np.concatenate([acceleration[:, :2], np.zeros((n, 1))], -1)
    a_pl = a_g + np.cross(alpha[:, None] * U3, r) - (omega**2)[:, None] * r
    f_pl = robot.payload.mass * (a_pl - g3)
    plat_f = robot.platform.mass * (a_g - g3) + f_pl - np.array([*robot.load.force, 0.0])
    plat_m = (
        (robot.platform.inertia + robot.payload.inertia) * alpha
        + np.cross(r, f_pl)[:, 2]
        - robot.load.moment
    )

    # ---- characteristic virtual velocities: a unit rate of actuator L', the others locked
    act = robot.actuated - 1
    influence = np.empty((n, 3, 3))  # q̇_a of leg L for a unit platform twist component i
    for i in range(3):
        unit_twist = np.zeros((n, 3))
        unit_twist[:, i] = 1.0
        rates = _solve(c, platform_in_e(unit_twist)[..., None])[..., 0]
        influence[:, :, i] = rates[..., act]
    virtual_twist = np.asarray(
        np.linalg.inv(influence), dtype=np.float64
    )  # column L': the twist of a unit rate of L'
    tau = np.zeros((n, 3))
    virtual_rates = np.empty((n, 3, 3, 3))
    for lp in range(3):
        twist = virtual_twist[:, :, lp]
        rates = _solve(c, platform_in_e(twist)[..., None])[..., 0]
        virtual_rates[:, lp] = rates
        v_om, v_v = chain.velocities(rates)
        work = np.zeros(n)
        for k in (0, 1):
            # the power of the need about the frame origin: f·v_origin + m_origin·ω
            work = work + np.sum(need_f[k] * v_v[k], -1).sum(-1)
            work = work + (need_m[k] * v_om[k][..., 2]).sum(-1)
        work = work + np.sum(plat_f[:, :2] * twist[:, :2], -1) + plat_m * twist[:, 2]
        tau[:, lp] = work

    # ---- joint forces: balances from the platform to the base, own frames
    def backward(w: FloatArray) -> tuple[list[FloatArray], list[FloatArray]]:
        """Joint wrenches (force in F_k, moment about O_k) for the platform-side wrench ``w``."""
        f3 = np.concatenate([w[..., :2], np.zeros((*w.shape[:-1], 1))], -1)
        forces, moments = [f3], [w[..., 2]]
        for k in (1, 0):  # link 2, then link 1
            a_next, r_next = chain.relative[k + 1], chain.offset[k + 1]
            f_next = _mtv(a_next, forces[0])
            forces.insert(0, need_f[k] + f_next)
            moments.insert(0, need_m[k] + moments[0] + np.cross(r_next, f_next)[..., 2])
        return forces, moments

    def conditions(forces: list[FloatArray], moments: list[FloatArray]) -> FloatArray:
        return np.stack(
            [moments[k] if robot.types[k] == "R" else forces[k][..., 0] for k in range(3)], -1
        )

    zero = conditions(*backward(np.zeros((n, 3, 3))))
    columns = []
    for i in range(3):
        basis = np.zeros((n, 3, 3))
        basis[..., i] = 1.0
        columns.append(conditions(*backward(basis)) - zero)
    target = np.zeros((n, 3, 3))
    target[..., act] = tau
    w = _solve(np.stack(columns, -1), (target - zero)[..., None])[..., 0]
    forces, moments = backward(w)
    return PaperSteps(
        rotation=chain.absolute,
        relative=chain.relative,
        offset=chain.offset,
        connectivity=c,
        dq=dq,
        ddq=ddq,
        omega=omegas,
        velocity=vs,
        epsilon=epss,
        acceleration=accs,
        virtual_twist=virtual_twist,
        virtual_rates=virtual_rates,
        tau=tau,
        joint_force=np.stack(forces, 2),
        joint_moment=np.stack(moments, 2),
        link_force=np.stack(need_f, 2),
        link_moment=np.stack(need_m, 2),
        platform_force=plat_f,
        platform_moment=plat_m,
    )


def paper_dynamics(robot: FamilyRobot, motion: Motion) -> FamilySolution:
    """The paper route: :func:`paper_steps`, the joint forces turned into the fixed frame."""
    kin = family_kinematics(robot, motion)
    steps = paper_steps(kin.robot, kin.motion, kin)
    force = np.stack(
        [_mtv(steps.rotation[k], steps.joint_force[:, :, k])[..., :2] for k in range(3)], 2
    )
    return joint_solution(kin, steps.dq, steps.ddq, steps.tau, force, steps.joint_moment, "paper")
