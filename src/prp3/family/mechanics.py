"""The family's mechanics on arrays: inverse geometry, rates, body wrenches, virtual work.

The default (``"fast"``) route of docs/family.md §5–§7, vectorised over the samples
(time on the leading axis, then the legs A, B, C, then the joints 1–3):

1. :func:`inverse_geometry` — each leg's closed-form closure solutions
   (:mod:`prp3.family.legs`), the one whose ``μ_leg`` has its home sign (§5),
   R angles unwrapped continuously from home; the measures ``μ_leg``,
   ``μ_par`` (§6) and the refusals (unreachable, singular, crossed);
2. :func:`family_kinematics` — the joint rates ``q̇ = J⁻¹·t`` and
   accelerations ``q̈ = J⁻¹·(ṫ − J̇·q̇)`` from each leg's Jacobian ``J`` at ``G``
   (columns: the joint twists ``(perp(G − O_k), 1)`` (R), ``(u_k, 0)`` (P));
3. :func:`fast_dynamics` — the wrench each body needs, ``(m(a_C − g), I·θ̈)``
   taken about ``G``; virtual work for the actuator efforts
   ``Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L`` (``K_L = J_L⁻¹``, ``B_L[k]``
   the power of the links distal to joint ``k`` through its twist); the leg's
   wrench on the platform ``w_L = K_Lᵀ·(τ_L·e_a − B_L)``; then every joint force
   ``W_3 = w_L``, ``W_2 = N_2 + W_3``, ``W_1 = N_1 + W_2``.

>>> from prp3.model.motion import Motion
>>> from prp3.family.model import FamilyRobot
>>> robot = FamilyRobot.default("3-RRR")
>>> kin = family_kinematics(robot, Motion.at_rest([0.0, 0.0, 0.0]))
>>> kin.q.shape, [round(float(v), 3) for v in kin.mu_leg]
((3, 3), [0.444, 0.444, 0.444])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.errors import SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.family.chain import (
    SIGMA,
    SINGULAR,
    ChainFrames,
    cross,
    inv3,
    leg_chain,
    leg_jacobian,
    leg_measure,
    parallel_measure,
    perp,
    rotate,
    transmitted_wrench,
)
from prp3.family.legs import LEG_GEOMETRY, LegGeometry
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.pose_validation import MAX_ORIENTATION, POSE_BOUND
from prp3.validation import LEGS, check_instance, require_finite

__all__ = [
    "FamilyKinematics",
    "FamilySolution",
    "body_wrenches",
    "family_kinematics",
    "fast_dynamics",
    "inverse_geometry",
    "joint_forces",
    "joint_rates",
    "virtual_work",
]

FloatArray = NDArray[np.float64]


def solve3(matrix: FloatArray, rhs: FloatArray) -> FloatArray:
    """``matrix⁻¹·rhs`` for stacks of 3×3 matrices ``(..., 3, 3)`` and vectors ``(..., 3)``.

    In closed form (:func:`~prp3.family.chain.inv3`); the matrices are far from
    singular here (the measures of §6 are refused below 1e-4).
    """
    return np.asarray(np.einsum("...ij,...j->...i", inv3(matrix), rhs))


def _pose_tuple(pose: FloatArray) -> tuple[float, float, float]:
    return (float(pose[0]), float(pose[1]), float(pose[2]))


def pose_bound_error(
    robot: FamilyRobot, pose: FloatArray, t: FloatArray, k: int
) -> TrajectoryError:
    """The error of sample ``k`` beyond ``POSE_BOUND`` robot lengths or ``MAX_ORIENTATION``."""
    bound = POSE_BOUND * robot_length(robot)
    return TrajectoryError(
        f"the pose {_pose_tuple(pose[k])} lies beyond {POSE_BOUND:g} robot lengths "
        f"({bound:.6g} m) of the centre, or |phi| > {MAX_ORIENTATION:g} rad",
        subject="motion",
        sample=k,
        time=float(t[k]),
        pose=_pose_tuple(pose[k]),
    )


def on_the_way(t: FloatArray, k: int) -> str:
    """`` on the way from sample k − 1 (t = … s) to sample k (t = … s)`` (from home for ``k = 0``).

    A pose of the followed path (§5) between two samples, named by both.

    >>> on_the_way(np.array([0.0, 0.5]), 1)
    ' on the way from sample 0 (t = 0 s) to sample 1 (t = 0.5 s)'
    """
    start = "home" if k == 0 else f"sample {k - 1} (t = {float(t[k - 1]):.6g} s)"
    return f" on the way from {start} to sample {k} (t = {float(t[k]):.6g} s)"


def unreachable_error(
    robot: FamilyRobot, leg: int, where: FloatArray, note: str, k: int, t: FloatArray
) -> UnreachablePoseError:
    """The error of leg ``leg`` whose closure has no solution at the pose ``where``
    (sample ``k``, or ``note`` says on the way to it: :func:`on_the_way`)."""
    return UnreachablePoseError(
        f"leg {LEGS[leg]} cannot reach the pose {_pose_tuple(where)}{note} "
        f"(the {robot.architecture}'s closure has no real solution)",
        sample=k,
        time=float(t[k]),
        leg=LEGS[leg],
        pose=_pose_tuple(where),
    )


def singular_error(
    name: str,
    measure: float,
    where: FloatArray,
    pose: FloatArray,
    t: FloatArray,
    k: int,
    leg: str | None,
    at_home: float,
) -> SingularPoseError:
    """The error of the measure ``name`` (``measure``, sign ``at_home`` at home) below
    :data:`SINGULAR` at the pose ``where``: sample ``k`` of ``pose`` or on the way to it.

    The samples before ``k`` passed, so a measure of the wrong sign (beyond
    :data:`SINGULAR`) was crossed between sample ``k − 1`` (home for ``k = 0``)
    and ``where``: the message names both samples.
    """
    between = "" if np.array_equal(where[:3], pose[k]) else on_the_way(t, k)
    if abs(measure) >= SINGULAR and between:  # the wrong sign: a singularity crossed
        what = "a singularity crossed"
    elif abs(measure) >= SINGULAR:
        start = "home" if k == 0 else f"sample {k - 1} (t = {float(t[k - 1]):.6g} s)"
        what = f"a singularity crossed between {start} and sample {k} (t = {float(t[k]):.6g} s)"
    else:
        what = "a singular pose"
    return SingularPoseError(
        f"{name} = {measure:.6g} at the pose {_pose_tuple(where)}{between}: {what} (its "
        f"sign at home is {'+' if at_home > 0 else '-'}; refused below {SINGULAR:g})",
        sample=k,
        time=float(t[k]),
        leg=leg,
        pose=_pose_tuple(where),
    )


@dataclass(frozen=True)
class Geometry:
    """The reported closure solution of every leg and the measures (batch ``N``)."""

    q: FloatArray  # (N, 3 legs, 3 joints)
    frames: ChainFrames  # (N, 3 legs, ...) in the fixed frame
    mu_leg: FloatArray  # (N, 3)
    mu_par: FloatArray  # (N,)


#: Largest change of ``φ`` (rad) between two points of the followed path (§5).
MAX_TURN: float = 0.25

#: Largest move of ``G`` between two points of the followed path, in robot lengths.
MAX_MOVE: float = 0.1


def robot_length(robot: FamilyRobot) -> float:
    """A length of the robot (m): the placements' lengths and P home values summed, or ``ℓ``."""
    placements = robot.leg.placements
    reach = float(np.hypot(placements[:, 0], placements[:, 1]).sum())
    reach += sum(abs(robot.leg.home[k]) for k in range(3) if robot.types[k] == "P")
    return max(reach, robot.leg.scale)


def follow(points: FloatArray, length: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The straight segments between ``points (n, 3)`` in sub-steps (§5).

    Each segment is cut in as many equal steps as needed for ``|Δφ| ≤``
    :data:`MAX_TURN` and ``|ΔG| ≤`` :data:`MAX_MOVE` robot lengths.

    Returns
    -------
    path : ndarray, shape (m, 3)
        ``points[0]``, then every step; the points themselves are on it.
    owner : ndarray of int, shape (m,)
        For each point of the path, the index of the point its segment ends at.
    at : ndarray of int, shape (n,)
        Where each of ``points`` lies on the path.

    >>> path, owner, at = follow(np.array([[0, 0, 0], [0, 0, 0.6], [0, 0, 0.61]]), 1.0)
    >>> path[:, 2].round(2).tolist(), owner.tolist(), at.tolist()
    ([0.0, 0.2, 0.4, 0.6, 0.61], [0, 1, 1, 1, 2], [0, 3, 4])
    """
    delta = np.diff(points, axis=0)
    move = np.hypot(delta[:, 0], delta[:, 1]) / (MAX_MOVE * length)
    steps = np.maximum(1, np.ceil(np.maximum(np.abs(delta[:, 2]) / MAX_TURN, move))).astype(int)
    segment = np.repeat(np.arange(delta.shape[0]), steps)
    first = np.repeat(np.cumsum(steps) - steps, steps)
    fraction = (np.arange(segment.size) - first + 1) / steps[segment]
    path = np.concatenate([points[:1], points[segment] + fraction[:, None] * delta[segment]])
    path[np.cumsum(steps)] = points[1:]  # the points exactly
    owner = np.concatenate([[0], segment + 1])
    at = np.concatenate([[0], np.cumsum(steps)])
    return path, owner, at


def check_poses(robot: FamilyRobot, pose: FloatArray, t: FloatArray) -> None:
    """Refuse poses beyond ``POSE_BOUND`` robot lengths or ``MAX_ORIENTATION`` rad (named)."""
    bound = POSE_BOUND * robot_length(robot)
    bad = (np.abs(pose[:, :2]) > bound).any(axis=1) | (np.abs(pose[:, 2]) > MAX_ORIENTATION)
    if bad.any():
        raise pose_bound_error(robot, pose, t, int(np.argmax(bad)))


def _best_branch(
    robot: FamilyRobot, geometry: LegGeometry, local_g: FloatArray, phi: FloatArray, sign: float
) -> tuple[FloatArray, FloatArray]:
    """The closure solution of one leg that keeps the home branch, at every path point.

    Among the candidates of docs/family.md §5 at the leg-frame points ``local_g``
    ``(M, 2)`` [m] and angles ``phi`` ``(M,)`` [rad], picks the one with the largest
    finite ``sign·μ_leg``; returns the joint values ``(M, 3)`` and its scaled
    ``Ĵ`` ``(M, 3, 3)`` in the leg frame (NaN rows where no candidate is finite).
    """
    types, placements, scale = robot.types, robot.leg.placements, robot.leg.scale
    best = np.full(phi.shape[0], -np.inf)
    chosen = np.full((phi.shape[0], 3), np.nan)
    hat = np.full((phi.shape[0], 3, 3), np.nan)  # Ĵ of the chosen solution, leg frame
    with np.errstate(invalid="ignore", over="ignore"):
        for candidate in geometry.candidates(local_g, phi):
            frames = leg_chain(types, placements, 0.0, candidate)
            scaled = leg_jacobian(types, frames, local_g, scale)
            value = sign * leg_measure(scaled)
            better = np.isfinite(value) & (value > best)
            best = np.where(better, value, best)
            chosen[better] = candidate[better]
            hat[better] = scaled[better]
    return chosen, hat


def _unwrap_revolute(
    robot: FamilyRobot, geometry: LegGeometry, j: int, chosen: FloatArray, phi: FloatArray
) -> None:
    """Make leg ``j``'s R angles in ``chosen`` ``(M, 3)`` continuous from home, in place.

    All R angles but the last are unwrapped along the path from their home values;
    the last one closes ``Σ angles = φ − total`` (docs/family.md §5) with the whole
    turns the leg has at home.
    """
    types, home = robot.types, np.asarray(robot.leg.home)
    revolute = [k for k in range(3) if types[k] == "R"]
    turns = home[revolute].sum() - (robot.home_poses[j, 2] - geometry.total)
    offset = 2.0 * math.pi * round(turns / (2.0 * math.pi))
    for k in revolute[:-1]:
        chosen[:, k] = np.unwrap(np.concatenate([[home[k]], chosen[:, k]]))[1:]
    last = revolute[-1]
    others = chosen[:, revolute[:-1]].sum(axis=1) if len(revolute) > 1 else 0.0
    chosen[:, last] = phi - geometry.total + offset - others


def inverse_geometry(robot: FamilyRobot, pose: FloatArray, t: FloatArray) -> Geometry:
    """Closure solutions of docs/family.md §5 at poses ``(N, 3)`` and the refusals of §6.

    Each leg follows the path from its home pose through the samples in
    sub-steps (:func:`follow`): the branch keeps the sign of ``μ_leg`` it has at
    home, the R angles are unwrapped along the path, and the measures are
    checked at every sub-step too, so a singularity crossed between two
    samples is refused (naming both samples).

    Raises
    ------
    UnreachablePoseError
        A leg cannot reach a pose (names the sample, time, leg and pose).
    SingularPoseError
        ``s_L·μ_leg,L < 1e-4`` or ``s_par·μ_par < 1e-4`` at a sample or on the way
        to it: a singular pose, or a singularity crossed since home (names the measure).
    """
    check_poses(robot, pose, t)
    types, placements, scale = robot.types, robot.leg.placements, robot.leg.scale
    geometry = LEG_GEOMETRY[types](placements)
    home_leg, home_par = robot.home_measures
    revolute = [k for k in range(3) if types[k] == "R"]
    length = robot_length(robot)
    n = pose.shape[0]
    q = np.empty((n, 3, 3))
    failures: list[tuple[int, str, float, FloatArray, str | None, float]] = []
    shared_wrench: list[FloatArray] = []
    shared_owner = np.zeros(0, dtype=int)
    shared_path = np.zeros((0, 3))
    for j in range(3):
        path, owner, at = follow(np.concatenate([robot.home_poses[j : j + 1], pose]), length)
        sample_of = np.maximum(owner - 1, 0)
        local_g = rotate(-SIGMA[j], path[:, :2])
        phi = path[:, 2]
        sign = math.copysign(1.0, home_leg[j])
        chosen, hat = _best_branch(robot, geometry, local_g, phi, sign)
        lost = ~np.isfinite(chosen).all(axis=1)
        if lost.any():
            i = int(np.argmax(lost))
            k = int(sample_of[i])
            note = "" if i in at else on_the_way(t, k)
            raise unreachable_error(robot, j, path[i], note, k, t)
        if revolute:  # R angles: continuous from home along the path (docs/family.md §5)
            _unwrap_revolute(robot, geometry, j, chosen, phi)
        q[:, j, :] = chosen[at[1:]]
        mu = leg_measure(hat)  # det Ĵ does not change when the leg is turned by σ_j
        bad = ~(sign * mu >= SINGULAR)
        if bad.any():
            i = int(np.argmax(bad))
            failures.append(
                (int(sample_of[i]), f"mu_leg of leg {LEGS[j]}", float(mu[i]), path[i], LEGS[j],
                 home_leg[j])
            )  # fmt: skip
        start = int(at[1])  # the path from sample 0 on is the same for the three legs
        wrench = transmitted_wrench(hat[start:], robot.actuated)  # leg frame: turn by σ_j
        turned = rotate(SIGMA[j], wrench[:, :2])
        shared_wrench.append(np.concatenate([turned, wrench[:, 2:]], axis=-1))
        shared_owner, shared_path = sample_of[start:], path[start:]
    mu_path = parallel_measure(np.stack(shared_wrench, axis=-2))
    bad = ~(math.copysign(1.0, home_par) * mu_path >= SINGULAR)
    if bad.any():
        i = int(np.argmax(bad))
        failures.append(
            (int(shared_owner[i]), "mu_par", float(mu_path[i]), shared_path[i], None, home_par)
        )
    if failures:
        k, name, measure, where, leg, at_home = min(failures, key=lambda item: item[0])
        raise singular_error(name, measure, where, pose, t, k, leg, at_home)
    frames = leg_chain(types, placements, SIGMA, q)
    hat = leg_jacobian(types, frames, pose[:, None, :2], scale)
    mu_leg = leg_measure(hat)
    mu_par = parallel_measure(transmitted_wrench(hat, robot.actuated))
    return Geometry(q=q, frames=frames, mu_leg=mu_leg, mu_par=mu_par)


@dataclass(frozen=True)
class FamilyKinematics:
    """Joint values, rates and accelerations of every leg, the frames and the measures.

    Arrays have the batch shape of the motion (``(N,)`` or ``()``) in front;
    per-leg arrays then have the legs A, B, C, per-joint arrays then the joints 1–3.

    Attributes
    ----------
    robot : FamilyRobot
    motion : prp3.Motion
    q, dq, ddq : ndarray, shape ``(..., 3, 3)``
        ``q{k}`` of each leg (m or rad) and its derivatives.
    mu_leg : ndarray, shape ``(..., 3)``
    mu_par : ndarray, shape ``(...)``
    frames : ChainFrames
        The chain frames of every leg, fixed-frame components, shapes ``(..., 3, ...)``.
    jacobian : ndarray, shape ``(..., 3, 3, 3)``
        Each leg's ``J`` at ``G`` (ℓ = 1): ``(ẋ, ẏ, φ̇) = J·q̇``.
    jacobian_inverse : ndarray, shape ``(..., 3, 3, 3)``
        ``K = J⁻¹`` (closed form).
    """

    robot: FamilyRobot
    motion: Motion
    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    mu_leg: FloatArray
    mu_par: FloatArray
    frames: ChainFrames
    jacobian: FloatArray
    jacobian_inverse: FloatArray


def motion_batch(motion: Motion) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    t = np.atleast_1d(motion.t)
    return (
        t,
        motion.pose.reshape(-1, 3),
        motion.velocity.reshape(-1, 3),
        motion.acceleration.reshape(-1, 3),
    )


def check_inputs(robot: object, motion: object) -> tuple[FamilyRobot, Motion]:
    """The public entry's checks: a FamilyRobot, a Motion without a time-varying load."""
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    motion = check_instance("motion", motion, Motion, "a prp3.Motion")
    if motion.load is not None:
        raise TrajectoryError(
            "a time-varying load (trajectory columns fx, fy, mz) belongs to model-form robot files (docs/model.md) only; "
            "use the robot's [load] table",
            subject="motion",
        )
    return robot, motion


def family_kinematics(robot: FamilyRobot, motion: Motion) -> FamilyKinematics:
    """Inverse geometry and kinematics of every leg along ``motion`` (docs/family.md §5, §6).

    ``q̇ = J⁻¹·(ẋ, ẏ, φ̇)``, ``q̈ = J⁻¹·((ẍ, ÿ, φ̈) − J̇·q̇)`` with ``J̇``'s columns
    ``(perp(Ġ − Ȯ_k), 0)`` (R) and ``(ω_{J_k}·perp(u_k), 0)`` (P).
    """
    robot, motion = check_inputs(robot, motion)
    t, pose, _, _ = motion_batch(motion)
    return joint_rates(robot, motion, inverse_geometry(robot, pose, t))


def joint_rates(robot: FamilyRobot, motion: Motion, geo: Geometry) -> FamilyKinematics:
    """:func:`family_kinematics` after the inverse geometry ``geo`` of ``motion``'s poses."""
    t, pose, velocity, acceleration = motion_batch(motion)
    frames = geo.frames
    jac = leg_jacobian(robot.types, frames, pose[:, None, :2])
    twist = np.broadcast_to(velocity[:, None, :], (t.size, 3, 3))
    inverse = inv3(jac)
    dq = np.einsum("nlij,nlj->nli", inverse, twist)
    bias = jacobian_rate(robot.types, frames, jac, dq, velocity)
    rhs = acceleration[:, None, :] - np.einsum("nlij,nlj->nli", bias, dq)
    ddq = np.einsum("nlij,nlj->nli", inverse, rhs)
    require_finite({"dq": dq, "ddq": ddq}, (t.size,), "motion", t)
    shape = motion.t.shape
    return FamilyKinematics(
        robot=robot,
        motion=motion,
        q=geo.q.reshape(*shape, 3, 3),
        dq=dq.reshape(*shape, 3, 3),
        ddq=ddq.reshape(*shape, 3, 3),
        mu_leg=geo.mu_leg.reshape(*shape, 3),
        mu_par=geo.mu_par.reshape(shape),
        frames=frames,
        jacobian=jac,
        jacobian_inverse=inverse,
    )


def body_rates_before(types: str, dq: FloatArray, upto: int) -> FloatArray:
    """``Σ_{i < upto, R} q̇_i``: the angular rate of the body before joint ``upto``."""
    out = np.zeros(dq.shape[:-1])
    for i in range(upto):
        if types[i] == "R":
            out = out + dq[..., i]
    return out


def point_velocity(
    types: str, frames: ChainFrames, dq: FloatArray, body: int, point: FloatArray
) -> FloatArray:
    """Velocity of the point ``point`` fixed in body ``body`` (1..3: link 1, link 2, platform)."""
    v = np.zeros(point.shape)
    for i in range(body):
        if types[i] == "R":
            v = v + dq[..., i, None] * perp(point - frames.origin[..., i, :])
        else:
            v = v + dq[..., i, None] * frames.axis[..., i, :]
    return v


def jacobian_rate(
    types: str, frames: ChainFrames, jac: FloatArray, dq: FloatArray, velocity: FloatArray
) -> FloatArray:
    """``J̇`` of every leg, shape ``(N, 3, 3, 3)``."""
    out = np.zeros_like(jac)
    vg = velocity[:, None, :2]
    for k in range(3):
        if types[k] == "R":
            o_dot = point_velocity(types, frames, dq, k + 1, frames.origin[..., k, :])
            out[..., :2, k] = perp(vg - o_dot)
        else:
            out[..., :2, k] = body_rates_before(types, dq, k)[..., None] * perp(
                frames.axis[..., k, :]
            )
    return out


def _point_acceleration(
    types: str,
    frames: ChainFrames,
    dq: FloatArray,
    ddq: FloatArray,
    body: int,
    point: FloatArray,
) -> FloatArray:
    """Acceleration of a point fixed in body ``body``: ``Σ_i q̈_i·s_i + q̇_i·ṡ_i``."""
    v = point_velocity(types, frames, dq, body, point)
    a = np.zeros(point.shape)
    for i in range(body):
        if types[i] == "R":
            o_dot = point_velocity(types, frames, dq, i + 1, frames.origin[..., i, :])
            a = a + ddq[..., i, None] * perp(point - frames.origin[..., i, :])
            a = a + dq[..., i, None] * perp(v - o_dot)
        else:
            u = frames.axis[..., i, :]
            a = (
                a
                + ddq[..., i, None] * u
                + (dq[..., i] * body_rates_before(types, dq, i))[..., None] * perp(u)
            )
    return a


def body_wrenches(kin: FamilyKinematics) -> tuple[FloatArray, FloatArray]:
    """The wrench each body needs, ``(m(a_C − g), I·θ̈)`` about ``G``.

    Returns
    -------
    links : ndarray, shape ``(N, 3 legs, 2 links, 3)``
        ``(f_x, f_y, m_G)`` of link 1 and link 2 of each leg.
    platform : ndarray, shape ``(N, 3)``
        The wrench the legs must give the platform: its need (with the payload)
        minus the load (docs/family.md §4).
    """
    robot = kin.robot
    types, frames = robot.types, kin.frames
    _, pose, velocity, acceleration = motion_batch(kin.motion)
    dq, ddq = kin.dq.reshape(-1, 3, 3), kin.ddq.reshape(-1, 3, 3)
    g = np.asarray(robot.gravity)
    centre = pose[:, None, :2]
    links = np.empty((pose.shape[0], 3, 2, 3))
    for body in (1, 2):
        params = robot.link1 if body == 1 else robot.link2
        c = frames.origin[..., body - 1, :] + rotate(frames.angle[..., body - 1], params.com)
        a = _point_acceleration(types, frames, dq, ddq, body, c)
        alpha = body_rates_before(types, ddq, body)
        force = params.mass * (a - g)
        links[..., body - 1, :2] = force
        links[..., body - 1, 2] = params.inertia * alpha + cross(c - centre, force)
    platform = np.empty((pose.shape[0], 3))
    omega, alpha = velocity[:, 2], acceleration[:, 2]
    force = robot.platform.mass * (acceleration[:, :2] - g)
    moment = robot.platform.inertia * alpha
    payload = robot.payload
    r = rotate(pose[:, 2], payload.com)
    a_pl = acceleration[:, :2] + alpha[:, None] * perp(r) - (omega * omega)[:, None] * r
    f_pl = payload.mass * (a_pl - g)
    platform[:, :2] = force + f_pl - np.asarray(robot.load.force)
    platform[:, 2] = moment + payload.inertia * alpha + cross(r, f_pl) - robot.load.moment
    return links, platform


@dataclass(frozen=True)
class FamilySolution:
    """The complete inverse dynamics of a family robot (docs/family.md §7), one type for every route.

    Batch shape ``(N,)`` or ``()`` in front; legs A, B, C; joints 1–3.

    Attributes
    ----------
    kinematics : FamilyKinematics
    q, dq, ddq : ndarray, shape ``(..., 3, 3)``
        As computed by the route (the paper route recomputes ``q̇``, ``q̈``).
    tau, power : ndarray, shape ``(..., 3)``
        ``tau_L`` (N or N·m) and ``p_L = tau_L·dq{a}_L`` (W).
    force : ndarray, shape ``(..., 3, 3, 2)``
        ``(fx{k}, fy{k})``: the total force of the proximal on the distal body (N).
    moment : ndarray, shape ``(..., 3, 3)``
        ``m{k}``: its moment about ``z0`` taken about ``O_k`` (N·m).
    method : str
    """

    kinematics: FamilyKinematics
    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    tau: FloatArray
    power: FloatArray
    force: FloatArray
    moment: FloatArray
    method: str


def joint_forces(
    kin: FamilyKinematics, tau: FloatArray, links: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Every joint's wrench from the actuator efforts: ``(force (N,3,3,2), moment (N,3,3))``.

    ``w_L = K_Lᵀ·(τ_L·e_a − B_L)``, ``W_3 = w_L``, ``W_2 = N_2 + W_3``,
    ``W_1 = N_1 + W_2`` (about ``G``), then the moment about ``O_k``.
    """
    jac = kin.jacobian
    a = kin.robot.actuated - 1
    b = _link_powers(jac, links)
    e = np.zeros_like(b)
    e[..., a] = tau
    w = np.einsum("nlji,nlj->nli", kin.jacobian_inverse, e - b)
    wrench = np.stack([links[:, :, 0] + links[:, :, 1] + w, links[:, :, 1] + w, w], axis=2)
    centre = kin.motion.pose.reshape(-1, 3)[:, None, None, :2]
    force = wrench[..., :2]
    moment = wrench[..., 2] + cross(centre - kin.frames.origin, force)
    return force, moment


def _link_powers(jac: FloatArray, links: FloatArray) -> FloatArray:
    """``B_L[k] = J[:, k]·Σ_{links i ≥ k} N_i`` (the link wrenches about G), shape ``(N, 3, 3)``."""
    distal = np.stack(
        [links[:, :, 0] + links[:, :, 1], links[:, :, 1], np.zeros_like(links[:, :, 0])], axis=2
    )
    return np.asarray(np.einsum("nlik,nlki->nlk", jac, distal))


def fast_dynamics(kin: FamilyKinematics) -> FamilySolution:
    """The default route: actuator efforts by virtual work, then every joint force.

    ``Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L`` with ``K_L = J_L⁻¹``:
    the power of the actuators equals the power the bodies need for every
    platform twist.
    """
    links, platform = body_wrenches(kin)
    return virtual_work(kin, links, platform)


def virtual_work(kin: FamilyKinematics, links: FloatArray, platform: FloatArray) -> FamilySolution:
    """:func:`fast_dynamics` after the body wrenches ``(links, platform)`` of :func:`body_wrenches`."""
    jac = kin.jacobian
    a = kin.robot.actuated - 1
    inverse = kin.jacobian_inverse  # K_L, (N, 3, 3, 3)
    b = _link_powers(jac, links)
    rhs = platform + np.einsum("nlki,nlk->ni", inverse, b)
    matrix = np.swapaxes(inverse[:, :, a, :], -1, -2)  # columns K_L[a, :]
    tau = solve3(matrix, rhs)
    force, moment = joint_forces(kin, tau, links)
    return joint_solution(kin, kin.dq, kin.ddq, tau, force, moment, "fast")


def joint_solution(
    kin: FamilyKinematics,
    dq: FloatArray,
    ddq: FloatArray,
    tau: FloatArray,
    force: FloatArray,
    moment: FloatArray,
    method: str,
) -> FamilySolution:
    shape = kin.motion.t.shape
    t = np.atleast_1d(kin.motion.t)
    a = kin.robot.actuated - 1
    tau = tau.reshape(-1, 3)
    with np.errstate(over="ignore"):  # p = τ·q̇a may overflow: refused below, named
        power = tau * dq.reshape(-1, 3, 3)[..., a]
    finite = {"tau": tau, "p": power, "force": force, "moment": moment}
    require_finite(finite, (t.size,), "motion", t)
    return FamilySolution(
        kinematics=kin,
        q=kin.q,
        dq=dq.reshape(*shape, 3, 3),
        ddq=ddq.reshape(*shape, 3, 3),
        tau=tau.reshape(*shape, 3),
        power=power.reshape(*shape, 3),
        force=force.reshape(*shape, 3, 3, 2),
        moment=moment.reshape(*shape, 3, 3),
        method=method,
    )
