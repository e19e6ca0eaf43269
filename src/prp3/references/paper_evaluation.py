"""The paper's stages run for a chunk of samples, with the effects beyond the paper.

:func:`_evaluate` chains the stages of the paper, each a function named after
it (:mod:`prp3.references.paper_kinematics`: frames and kinematics, eqs. 2–18;
:mod:`prp3.references.paper_wrenches`: dynamics, eqs. 19–25), for ``n``
samples at once and keeps every quantity.  The effects beyond the paper enter
the applied wrenches ``F_k*, M_k*`` of eq. (19) as the weight does: the load on
the platform and the joint friction (``_applied``), the springs with dampers of
the joints (``_springs``), both through ``_joint_wrenches``; :func:`evaluate_loaded` adds the friction's ``μ`` terms by a
fixed point on the reactions.  :mod:`prp3.references.paper` runs them over a
motion in chunks.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import TrajectoryError
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.path_validation import rest_joint_rates
from prp3.references.paper_kinematics import (
    A32,
    U3,
    fixed_frame_kinematics,
    mv,
    paper_accelerations,
    paper_geometry,
    paper_velocities,
    tr,
    virtual_velocities,
)
from prp3.references.paper_wrenches import (
    body_constants,
    chain_wrenches,
    inertia_wrenches,
    other_reactions,
    virtual_work,
    weight_wrenches,
)

__all__: list[str] = []

FloatArray = NDArray[np.float64]

_mv, _T = mv, tr  # ``matrix·vector`` and ``matrixᵀ`` over the last axes

#: Fixed-point iterations allowed for the ``μ`` terms of friction.
MU_MAX_ITERATIONS: int = 500


def evaluate_loaded(
    robot: Robot,
    pose: FloatArray,
    velocity: FloatArray,
    acceleration: FloatArray,
    load: FloatArray | None,
    first: int,
    motion: Motion,
    fixed_frame: bool = False,
) -> dict[str, FloatArray]:
    """:func:`_evaluate` with the load and the joint friction.

    Friction ``fric = −(b·v + (c + μ·N)·s(v))`` with the rates ``v10, ω21 = φ̇,
    v32`` of eq. (14); the ``μ`` terms by fixed-point iteration on the
    reactions ``N = |n10|, |F21|, |n32|`` (from the frictionless ones): the
    paper's method evaluated again with the friction of the last reactions
    until the friction changes by less than round-off.
    """
    chunk = _evaluate(robot, pose, velocity, acceleration, load, None, fixed_frame)
    friction = robot.friction
    if friction is None:
        return chunk
    act, rev, slv = friction.actuator, friction.revolute, friction.sleeve

    def s(rate: FloatArray, smoothing: float) -> FloatArray:
        return np.sign(rate) if smoothing == 0.0 else np.tanh(rate / smoothing)

    v10, v32 = chunk["v10"], chunk["v32"]
    w = np.broadcast_to(velocity[:, 2, None], v10.shape)
    # round-off joint rates are zero for s(v) (path_validation.rest_joint_rates)
    still10 = rest_joint_rates(v10, pose, velocity, robot.l0)
    still32 = rest_joint_rates(v32, pose, velocity, robot.l0)
    s10, s21, s32 = s(still10, act.smoothing), s(w, rev.smoothing), s(still32, slv.smoothing)
    e10 = -(act.viscous * v10 + act.coulomb * s10)
    e21 = -(rev.viscous * w + rev.coulomb * s21)
    e32 = -(slv.viscous * v32 + slv.coulomb * s32)
    k10, k21, k32 = act.mu * s10, rev.mu * rev.pin_radius * s21, slv.mu * s32
    fric = (e10, e21, e32)
    iterations = np.zeros(v10.shape[0])
    settled = np.ones(v10.shape[0], dtype=bool)
    for _ in range(MU_MAX_ITERATIONS if friction.has_mu else 1):
        chunk = _evaluate(robot, pose, velocity, acceleration, load, fric, fixed_frame)
        if not friction.has_mu:
            break
        new = (
            e10 - k10 * np.abs(chunk["n10"]),
            e21 - k21 * np.hypot(chunk["f21y"], chunk["f21z"]),
            e32 - k32 * np.abs(chunk["n32"]),
        )
        change = np.max([np.abs(a - b).max(axis=-1) for a, b in zip(new, fric, strict=True)], 0)
        size = np.max([np.abs(a).max(axis=-1) for a in new], 0) + 1.0
        settled = change <= 1e-15 * size
        iterations[~settled] += 1
        if settled.all():
            break
        fric = new
    if not settled.all():
        k = first + int(np.flatnonzero(~settled)[0])
        raise TrajectoryError(
            "the joint friction locks: the fixed-point iteration of the mu terms does not "
            f"settle in {MU_MAX_ITERATIONS} steps (self-locking)",
            subject="motion",
            sample=k,
            time=float(motion.t.reshape(-1)[k]),
        )
    chunk["fric10"], chunk["fric21"], chunk["fric32"] = fric
    chunk["iterations"] = iterations
    return chunk


def _applied(
    robot: Robot,
    F_star: FloatArray,
    M_star: FloatArray,
    a0: FloatArray,
    position: FloatArray,
    r3G: FloatArray,
    load: FloatArray | None,
    friction: tuple[FloatArray, FloatArray, FloatArray] | None,
) -> tuple[FloatArray, FloatArray]:
    """``F_k*, M_k*`` with the load on the platform and the joint friction added (about ``A_k``).

    The environment's wrench ``(F, M)`` at ``G``: ``a30·F`` and ``r3^G × a30·F + M·a30·u3``
    on body 3.  Friction (``docs/loads_and_friction.md``): ``fric10·u3`` and
    ``−fric21·a10·u3`` on body 1 (at ``A1``); ``−fric32·a32ᵀu3`` and ``fric21·u3``
    on body 2 (at ``A2``); ``fric32_j·d_j`` at ``A2`` of leg ``j`` on body 3.
    """
    a30 = a0[:, :, 2]
    F_star, M_star = F_star.copy(), M_star.copy()
    external = np.zeros((F_star.shape[0], 3))
    external[:, :2] = robot.load.force
    moment = np.full(F_star.shape[0], robot.load.moment)
    if load is not None:
        external[:, :2] += load[:, :2]
        moment = moment + load[:, 2]
    if robot.load.present or load is not None:
        F_ext = _mv(a30, external[:, None, :])  # in T3 of each leg
        F_star[:, :, 2] += F_ext
        M_star[:, :, 2] += np.cross(r3G, F_ext) + moment[:, None, None] * _mv(a30, U3)
    if friction is not None:
        F_star, M_star = _joint_wrenches(F_star, M_star, a0, position, friction)
    return F_star, M_star


def _joint_wrenches(
    F_star: FloatArray,
    M_star: FloatArray,
    a0: FloatArray,
    position: FloatArray,
    forces: tuple[FloatArray, FloatArray, FloatArray],
) -> tuple[FloatArray, FloatArray]:
    """``F_k*, M_k*`` with forces the joints apply added, each ``(n, 3)`` (friction, springs).

    ``fric10·u3`` and ``−fric21·a10·u3`` on body 1 (at ``A1``); ``−fric32·a32ᵀu3`` and
    ``fric21·u3`` on body 2 (at ``A2``); ``fric32_j·d_j`` at ``A2`` of leg ``j`` on body 3.
    """
    a10, a30 = a0[:, :, 0], a0[:, :, 2]
    F_star, M_star = F_star.copy(), M_star.copy()
    fric10, fric21, fric32 = forces
    z0_in_1 = _mv(a10, U3)
    F_star[:, :, 0] += fric10[..., None] * U3
    M_star[:, :, 0] -= fric21[..., None] * z0_in_1
    F_star[:, :, 1] -= fric32[..., None] * _mv(A32.T, U3)
    M_star[:, :, 1] += fric21[..., None] * U3
    d0 = _mv(_T(a30), U3)  # d_j in T0, (n, legs, 3)
    for j in range(3):
        force0 = fric32[:, j, None] * d0[:, j]  # on the platform at A2 of leg j, in T0
        lever0 = position[:, j, 1][:, None, :] - position[:, :, 2]  # from A3 of each leg
        F_star[:, :, 2] += _mv(a30, force0[:, None, :])
        M_star[:, :, 2] += _mv(a30, np.cross(lever0, force0[:, None, :]))
    return F_star, M_star


def _springs(
    robot: Robot,
    F_star: FloatArray,
    M_star: FloatArray,
    geo: Any,
    vel: Any,
    pose: FloatArray,
    velocity: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """``F_k*, M_k*`` with the springs with dampers of the joints added (``[spring.KIND]``).

    Each applies ``−k·(q − q_rest) − c·q̇`` where the joint's friction acts
    (:func:`_joint_wrenches`): along ``z1 = e_i`` on body 1 (``q = λ10``), the moment
    of body 1 on body 2 about ``z0`` (``q = φ21 = φ``), along the sleeve on the
    platform (``q = λ32``).
    """
    if robot.spring is None:
        return F_star, M_star
    n = pose.shape[0]
    phi = np.broadcast_to(pose[:, 2, None], (n, 3))
    dphi = np.broadcast_to(velocity[:, 2, None], (n, 3))
    forces = []
    for spring, q, rate in (
        (robot.spring.actuator, geo.lambda10, vel.v10),
        (robot.spring.revolute, phi, dphi),
        (robot.spring.sleeve, geo.lambda32, vel.v32),
    ):
        forces.append(-spring.stiffness * (q - spring.rest) - spring.damping * rate)
    return _joint_wrenches(F_star, M_star, geo.a0, geo.position, (forces[0], forces[1], forces[2]))


def _evaluate(
    robot: Robot,
    pose: FloatArray,
    velocity: FloatArray,
    acceleration: FloatArray,
    load: FloatArray | None = None,
    friction: tuple[FloatArray, FloatArray, FloatArray] | None = None,
    fixed_frame: bool = False,
) -> dict[str, FloatArray]:
    """Every quantity of the paper for ``n`` samples (arrays ``(n, 3)``), stage by stage.

    With ``fixed_frame`` also the fields of
    :class:`~prp3.references.paper_kinematics.FixedFrameKinematics` (for
    :func:`prp3.references.paper.paper_method`).
    """
    mass, r_C, J, r3G = body_constants(robot)
    geo = paper_geometry(robot.l0, pose)  # eqs. (2)–(10)
    vel = paper_velocities(geo, velocity)  # eqs. (11)–(14)
    acc = paper_accelerations(geo, vel, velocity, acceleration)  # eqs. (17)–(18)
    F_star, M_star = weight_wrenches(robot.gravity, geo, mass, r_C)  # eq. (19)
    # beyond the paper: the applied forces enter F_k*, M_k* as the weight does
    F_star, M_star = _applied(robot, F_star, M_star, geo.a0, geo.position, r3G, load, friction)
    F_star, M_star = _springs(robot, F_star, M_star, geo, vel, pose, velocity)
    F_in, M_in = inertia_wrenches(mass, r_C, J, vel, acc)  # eq. (20)
    F0, M0 = -F_in - F_star, -M_in - M_star  # eq. (22)
    F, M = chain_wrenches(geo, F0, M0)  # eq. (21)
    virtual = virtual_velocities(geo)  # eqs. (15)–(16)
    f10, f21y, f21z = virtual_work(geo, virtual, F, M)  # eqs. (23)–(25)
    n10, m10, n32, m32 = other_reactions(geo, F0, M0, f21y, f21z)
    chunk: dict[str, FloatArray] = {}
    for stage in (geo, vel, acc, virtual):
        chunk.update((f.name, getattr(stage, f.name)) for f in fields(stage))
    chunk.update(
        r_C=r_C, J=J, F_star=F_star, M_star=M_star, F_in=F_in, M_in=M_in, F0=F0, M0=M0, F=F, M=M,
        f10=f10, f21y=f21y, f21z=f21z, n10=n10, m10=m10, n32=n32, m32=m32, p10=f10 * vel.v10,
    )  # fmt: skip
    if fixed_frame:
        plane = fixed_frame_kinematics(geo, vel, acc, r_C[:, 0], r_C[:, 1])
        chunk.update((f.name, getattr(plane, f.name)) for f in fields(plane))
    return chunk
