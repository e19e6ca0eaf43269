"""Velocities and accelerations: leg Jacobians, the parallel Jacobian, every body's motion (§4, §6, §8).

For each leg the Jacobian ``J_i`` (6 × dof) maps the joint rates to the twist
of the leg's end at its last joint point; the joint rates solve
``J_i·dq_i = (ω, v + ω × r_i)`` and the accelerations
``J_i·ddq_i = (α, a + α × r_i + ω × (ω × r_i)) − b_i``, ``b_i`` the end's
acceleration at ``ddq = 0`` from the chain's recursion (:func:`chain_motion`,
which also gives every body's angular velocity and acceleration and the motion
of its frame origin).  The parallel Jacobian ``J_p`` maps the platform twist
to the actuated rates.  Serial and parallel singular poses are refused
(:class:`~prp3.errors.SingularPoseError` naming the sample, time, leg and
measure).

>>> from prp3.spatial.model import hexapod
>>> from prp3.spatial.motion import PlatformMotion
>>> robot = hexapod()
>>> motion = PlatformMotion.of([0.0], [0.0, 0.0, 0.08], np.eye(3), velocity=[0.0, 0.0, 0.01])
>>> kin = spatial_kinematics(robot, motion)
>>> kin.dq.shape, round(float(kin.dq[0, 0, 2]), 6), round(float(kin.parallel_measure[0]), 6)
((1, 6, 6), 0.007779, 2.129476)
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from prp3.errors import SingularPoseError
from prp3.spatial.geometry import CHUNK, Frames, coordinate_kinds, leg_frames
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import cross
from prp3.validation import check_instance

__all__ = [
    "SINGULAR",
    "BodyMotion",
    "ChunkKinematics",
    "SpatialKinematics",
    "chain_motion",
    "chunk_kinematics",
    "home_signs",
    "leg_jacobians",
    "spatial_kinematics",
]

FloatArray = NDArray[np.float64]

#: Threshold of the signed dimensionless singularity measures (docs/spatial.md §6).
SINGULAR: float = 1e-4


@dataclass(frozen=True)
class BodyMotion:
    """The motion of every leg body's frame, ``(N, legs, n, 3)`` each (``n`` joints: body ``k``
    is the distal body of joint ``k``; ``k = n − 1`` is the platform seen from the leg).

    Attributes
    ----------
    omega, alpha : angular velocity and acceleration (world frame)
    origin, velocity, acceleration : the frame origin ``F_k`` (the joint point) and its motion
    """

    omega: FloatArray
    alpha: FloatArray
    origin: FloatArray
    velocity: FloatArray
    acceleration: FloatArray


def _transport(
    v: FloatArray, a: FloatArray, w: FloatArray, al: FloatArray, r: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Velocity and acceleration of the point ``o + r`` of a body (``v, a`` those of ``o``)."""
    return v + cross(w, r), a + cross(al, r) + cross(w, cross(w, r))


def chain_motion(
    robot: SpatialRobot, frames: Frames, dq: FloatArray, ddq: FloatArray
) -> BodyMotion:
    """The chain's recursion from the fixed base (docs/spatial.md §8), ``dq, ddq (N, legs, dof)``.

    Rotation about an axis ``e`` fixed in the proximal body (R, each U axis):
    ``α += e·ddq + ω × e·dq``, ``ω += e·dq``; S (world axes): ``α += ddq``, ``ω += dq``;
    P along ``e``: ``a(F) = a_prox(F) + e·ddq + 2ω × e·dq``, ``v(F) = v_prox(F) + e·dq``.
    """
    shape = dq.shape[:2] + (3,)
    w, al = np.zeros(shape), np.zeros(shape)
    o, vo, ao = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    kinds = coordinate_kinds(robot)
    out: list[list[FloatArray]] = [[], [], [], [], []]
    for k in range(len(robot.legs[0].joints)):
        jo = frames.joint_origin[:, :, k]
        v_j, a_j = _transport(vo, ao, w, al, jo - o)
        o_f = frames.origin[:, :, k]
        v_f, a_f = v_j, a_j
        for c, (kind, owner) in enumerate(kinds):
            if owner != k:
                continue
            e = frames.axes[:, :, c]
            rate, acc = dq[..., c, None], ddq[..., c, None]
            if kind == "r":
                al = al + e * acc + cross(w, e) * rate
                w = w + e * rate
            elif kind == "s":
                al = al + e * acc
                w = w + e * rate
            else:
                v_p, a_p = _transport(v_j, a_j, w, al, o_f - jo)
                v_f = v_p + e * rate
                a_f = a_p + e * acc + 2.0 * cross(w, e) * rate
        o, vo, ao = o_f, v_f, a_f
        for store, value in zip(out, (w, al, o, vo, ao), strict=True):
            store.append(value)
    stacked = [np.stack(values, axis=2) for values in out]
    return BodyMotion(*stacked)


def leg_jacobians(robot: SpatialRobot, frames: Frames, point: FloatArray) -> FloatArray:
    """Each leg's Jacobian at ``point (N, legs, 3)``: ``(N, legs, 6, dof)`` (§4).

    Column of a rotation about ``e`` through the joint point ``o``: ``(e, e × (point − o))``;
    of a slide along ``e``: ``(0, e)``.
    """
    kinds = coordinate_kinds(robot)
    n, legs = frames.q.shape[:2]
    jac = np.zeros((n, legs, 6, len(kinds)))
    for c, (kind, owner) in enumerate(kinds):
        e = frames.axes[:, :, c]
        if kind == "t":
            jac[..., 3:, c] = e
        else:
            jac[..., :3, c] = e
            jac[..., 3:, c] = cross(e, point - frames.origin[:, :, owner])
    return jac


@dataclass(frozen=True)
class ChunkKinematics:
    """Everything the dynamics needs of one chunk of samples (arrays ``(N, legs, …)``).

    Attributes
    ----------
    frames : Frames
    dq, ddq : (N, legs, dof)
    jacobian : (N, legs, 6, dof), the leg Jacobians at the leg ends
    parallel : (N, legs, 6), the parallel Jacobian ``J_p`` (columns ``ω``, then ``v``)
    bodies : BodyMotion
    leg_measure : (N, legs); parallel_measure : (N,)
    """

    frames: Frames
    dq: FloatArray
    ddq: FloatArray
    jacobian: FloatArray
    parallel: FloatArray
    bodies: BodyMotion
    leg_measure: FloatArray
    parallel_measure: FloatArray


def _measures(
    robot: SpatialRobot, jacobian: FloatArray, parallel: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """``μ_leg = det J̃_i`` and ``μ_par = det J̃_p`` (§6), every length in units of ``ℓ``.

    ``J̃_i``: the translation rows divided by ``ℓ``, the slide columns multiplied by
    ``ℓ``; ``J̃_p``: for P actuators the ``ω`` columns divided by ``ℓ``, for R
    actuators the ``v`` columns multiplied by ``ℓ``.
    """
    kinds = coordinate_kinds(robot)
    scaled = jacobian.copy()
    scaled[..., 3:, :] /= robot.scale
    for c, (kind, _) in enumerate(kinds):
        if kind == "t":
            scaled[..., c] *= robot.scale
    leg = np.linalg.det(scaled)
    par = parallel.copy()
    if kinds[robot.legs[0].actuated_coordinate][0] == "t":
        par[..., :3] /= robot.scale
    else:
        par[..., 3:] *= robot.scale
    return leg, np.linalg.det(par)


def _leg_geometry(
    robot: SpatialRobot, motion: PlatformMotion, offset: int
) -> tuple[Frames, FloatArray, FloatArray, FloatArray]:
    frames = leg_frames(robot, motion, offset)
    end = frames.origin[:, :, -1]
    jacobian = leg_jacobians(robot, frames, end)
    actuated = robot.legs[0].actuated_coordinate
    unit = np.zeros(jacobian.shape[-1])
    unit[actuated] = 1.0
    with np.errstate(all="ignore"):
        x = np.linalg.solve(
            np.swapaxes(jacobian, -1, -2),
            np.broadcast_to(unit[:, None], jacobian.shape[:2] + (unit.shape[0], 1)),
        )[..., 0]
    r = end - motion.position[:, None, :]
    parallel = np.concatenate([x[..., :3] + cross(r, x[..., 3:]), x[..., 3:]], axis=-1)
    return frames, jacobian, parallel, r


@lru_cache(maxsize=32)
def home_signs(robot: SpatialRobot) -> tuple[FloatArray, float]:
    """The signs of ``μ_leg`` (per leg) and ``μ_par`` at the robot's home pose."""
    home = PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    _, jacobian, parallel, _ = _leg_geometry(robot, home, 0)
    leg, par = _measures(robot, jacobian, parallel)
    return np.sign(leg[0]), float(np.sign(par[0]))


def _check_singular(
    robot: SpatialRobot,
    motion: PlatformMotion,
    leg: FloatArray,
    par: FloatArray,
    offset: int,
) -> None:
    leg_sign, par_sign = home_signs(robot)
    bad_leg = ~(leg * leg_sign >= SINGULAR)
    bad_par = ~(par * par_sign >= SINGULAR)
    first_leg = int(np.argmax(bad_leg.any(axis=1))) if bad_leg.any() else None
    first_par = int(np.argmax(bad_par)) if bad_par.any() else None
    if first_leg is not None and (first_par is None or first_leg <= first_par):
        k = first_leg
        i = int(np.argmax(bad_leg[k]))
        where = "p = (" + ", ".join(f"{float(v):.6g}" for v in motion.position[k]) + ") m"
        raise SingularPoseError(
            f"serial singular: mu_leg = {float(leg[k, i]):.6g} at the pose {where} (its sign "
            f"at home is {'+' if leg_sign[i] > 0 else '-'}; refused below {SINGULAR:g})",
            sample=offset + k,
            time=float(motion.t[k]),
            leg=str(i + 1),
        )
    if first_par is not None:
        k = first_par
        where = "p = (" + ", ".join(f"{float(v):.6g}" for v in motion.position[k]) + ") m"
        raise SingularPoseError(
            f"parallel singular: mu_par = {float(par[k]):.6g} at the pose {where} (its sign "
            f"at home is {'+' if par_sign > 0 else '-'}; refused below {SINGULAR:g})",
            sample=offset + k,
            time=float(motion.t[k]),
        )


def chunk_kinematics(
    robot: SpatialRobot, motion: PlatformMotion, offset: int = 0
) -> ChunkKinematics:
    """The kinematics of one chunk (samples numbered from ``offset``), refusals included (§4, §6)."""
    frames, jacobian, parallel, r = _leg_geometry(robot, motion, offset)
    leg, par = _measures(robot, jacobian, parallel)
    _check_singular(robot, motion, leg, par, offset)
    omega = np.broadcast_to(motion.omega[:, None, :], r.shape)
    alpha = np.broadcast_to(motion.alpha[:, None, :], r.shape)
    v_end, a_end = _transport(
        motion.velocity[:, None, :], motion.acceleration[:, None, :], omega, alpha, r
    )
    dq = np.linalg.solve(jacobian, np.concatenate([omega, v_end], axis=-1)[..., None])[..., 0]
    bias = chain_motion(robot, frames, dq, np.zeros_like(dq))
    rhs = np.concatenate(
        [alpha - bias.alpha[:, :, -1], a_end - bias.acceleration[:, :, -1]], axis=-1
    )
    ddq = np.linalg.solve(jacobian, rhs[..., None])[..., 0]
    bodies = chain_motion(robot, frames, dq, ddq)
    return ChunkKinematics(frames, dq, ddq, jacobian, parallel, bodies, leg, par)


@dataclass(frozen=True)
class SpatialKinematics:
    """Joint values, rates, accelerations, the parallel Jacobian and the measures (§4, §6).

    Attributes
    ----------
    q, dq, ddq : (N, legs, dof)
        rad, m; per s; per s² (S: relative angular velocity and its derivative, world frame).
    parallel_jacobian : (N, legs, 6)
        ``dq_act = J_p·(ω, v)``.
    leg_measure : (N, legs); parallel_measure : (N,)
    """

    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    parallel_jacobian: FloatArray
    leg_measure: FloatArray
    parallel_measure: FloatArray


def spatial_kinematics(robot: SpatialRobot, motion: PlatformMotion) -> SpatialKinematics:
    """The inverse kinematics of ``motion`` for ``robot``, computed in chunks of ``CHUNK`` samples.

    Raises
    ------
    UnreachablePoseError
        A leg cannot reach a pose (names the sample, time and leg).
    SingularPoseError
        A serial (``μ_leg``) or parallel (``μ_par``) measure below ``SINGULAR`` times its
        sign at home (names the sample, time, leg and measure).
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    n, legs, dof = len(motion), len(robot.legs), robot.legs[0].dof
    q, dq, ddq = (np.empty((n, legs, dof)) for _ in range(3))
    jp, leg, par = np.empty((n, legs, 6)), np.empty((n, legs)), np.empty(n)
    for start in range(0, n, CHUNK):
        stop = min(start + CHUNK, n)
        kin = chunk_kinematics(robot, motion.chunk(start, stop), start)
        q[start:stop], dq[start:stop], ddq[start:stop] = kin.frames.q, kin.dq, kin.ddq
        jp[start:stop], leg[start:stop] = kin.parallel, kin.leg_measure
        par[start:stop] = kin.parallel_measure
    return SpatialKinematics(q, dq, ddq, jp, leg, par)
