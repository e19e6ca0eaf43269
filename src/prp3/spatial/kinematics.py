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

from dataclasses import dataclass, fields
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from prp3.errors import SingularPoseError, TrajectoryError
from prp3.spatial.geometry import (
    CHUNK,
    PLANE_TOLERANCE,
    Frames,
    coordinate_kinds,
    leg_frames,
    plane_offsets,
)
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import cross, exp_rotation
from prp3.validation import check_instance

__all__ = [
    "SINGULAR",
    "BodyMotion",
    "ChunkKinematics",
    "SpatialKinematics",
    "chain_motion",
    "chunk_kinematics",
    "complete_motion",
    "frame_measures",
    "home_signs",
    "leg_jacobians",
    "pseudo_solve",
    "spatial_kinematics",
    "transpose_solve",
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
    constraint : (N, legs, 6) or None
        Legs of 5 coordinates: the constraint rows ``C_i`` with ``C_i·(ω, v) = 0`` (§11).
    null : (N, legs, 6) or None
        Their left null vectors ``w_i`` (``w_iᵀ·J_i = 0``), pairing with ``(ω, v_end)``.
    """

    frames: Frames
    dq: FloatArray
    ddq: FloatArray
    jacobian: FloatArray
    parallel: FloatArray
    bodies: BodyMotion
    leg_measure: FloatArray
    parallel_measure: FloatArray
    constraint: FloatArray | None = None
    null: FloatArray | None = None


def _scaled_jacobian(robot: SpatialRobot, jacobian: FloatArray) -> FloatArray:
    """``J̃_i``: the translation rows divided by ``ℓ``, the slide columns multiplied by ``ℓ``."""
    scaled = jacobian.copy()
    scaled[..., 3:, :] /= robot.scale
    for c, (kind, _) in enumerate(coordinate_kinds(robot)):
        if kind == "t":
            scaled[..., c] *= robot.scale
    return scaled


def _left_null(matrix: FloatArray) -> FloatArray:
    """The generalised cross product of the 5 columns of ``matrix (..., 6, 5)``: ``w`` with
    ``wᵀ·matrix = 0`` and ``|w| = sqrt(det(matrixᵀ·matrix))``, ``(..., 6)``."""
    rows = [(-1.0) ** j * np.linalg.det(np.delete(matrix, j, axis=-2)) for j in range(6)]
    return np.stack(rows, axis=-1)


def _measures(
    robot: SpatialRobot, scaled: FloatArray, parallel: FloatArray, constraint: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """``μ_leg`` and ``μ_par`` (§6, §11), every length in units of ``ℓ``.

    ``μ_leg = det J̃_i`` for a 6-coordinate leg, ``|w̃_i| = sqrt(det J̃_iᵀ·J̃_i)`` for a
    5-coordinate one; ``μ_par = det [J̃_p; C̃]`` in the twist ``(ω, v/ℓ)``: for P
    actuators the rows of ``J_p`` with their ``ω`` columns divided by ``ℓ``, for R
    actuators their ``v`` columns multiplied by ``ℓ``; the constraint rows ``C`` with
    their ``v`` columns multiplied by ``ℓ``.
    """
    kinds = coordinate_kinds(robot)
    if scaled.shape[-1] == 6:
        leg = np.linalg.det(scaled)
    else:
        w = _left_null(scaled)
        leg = np.sqrt(np.einsum("...i,...i->...", w, w))
    par = parallel.copy()
    if kinds[robot.legs[0].actuated_coordinate][0] == "t":
        par[..., :3] /= robot.scale
    else:
        par[..., 3:] *= robot.scale
    if constraint is not None:
        c = constraint.copy()
        c[..., 3:] *= robot.scale
        par = np.concatenate([par, c], axis=-2)
    return leg, np.linalg.det(par)


def pseudo_solve(jacobian: FloatArray, rhs: FloatArray) -> FloatArray:
    """``J⁻¹·rhs`` for square leg Jacobians, ``(JᵀJ)⁻¹Jᵀ·rhs`` otherwise; ``rhs (..., 6)``."""
    if jacobian.shape[-1] == 6:
        return np.asarray(np.linalg.solve(jacobian, rhs[..., None])[..., 0], dtype=np.float64)
    jt = np.swapaxes(jacobian, -1, -2)
    return np.asarray(np.linalg.solve(jt @ jacobian, jt @ rhs[..., None])[..., 0], dtype=np.float64)


def transpose_solve(jacobian: FloatArray, y: FloatArray) -> FloatArray:
    """``J⁻ᵀ·y`` for square leg Jacobians, ``J(JᵀJ)⁻¹·y`` otherwise; ``y (..., dof)``."""
    if jacobian.shape[-1] == 6:
        solved = np.linalg.solve(np.swapaxes(jacobian, -1, -2), y[..., None])[..., 0]
        return np.asarray(solved, dtype=np.float64)
    jt = np.swapaxes(jacobian, -1, -2)
    return (jacobian @ np.linalg.solve(jt @ jacobian, y[..., None]))[..., 0]


def _leg_geometry(
    robot: SpatialRobot, motion: PlatformMotion, offset: int
) -> tuple[Frames, FloatArray, FloatArray, FloatArray | None, FloatArray, FloatArray | None]:
    """Frames, leg Jacobians, ``J_p``, the constraint rows ``C`` (or None), ``r_i`` and the
    leg's left null vectors ``w_i`` (or None)."""
    frames = leg_frames(robot, motion, offset)
    return (frames, *_frames_geometry(robot, frames, motion.position))


def _frames_geometry(
    robot: SpatialRobot, frames: Frames, position: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray | None, FloatArray, FloatArray | None]:
    """:func:`_leg_geometry` of frames already solved (no refusal): ``J_i``, ``J_p``, ``C``,
    ``r_i``, ``w_i``."""
    end = frames.origin[:, :, -1]
    jacobian = leg_jacobians(robot, frames, end)
    actuated = robot.legs[0].actuated_coordinate
    unit = np.zeros(jacobian.shape[-1])
    unit[actuated] = 1.0
    with np.errstate(all="ignore"):
        x = transpose_solve(jacobian, np.broadcast_to(unit, jacobian.shape[:2] + unit.shape))
    r = end - position[:, None, :]
    parallel = np.concatenate([x[..., :3] + cross(r, x[..., 3:]), x[..., 3:]], axis=-1)
    constraint = null = None
    if jacobian.shape[-1] < 6:
        scaled = _left_null(_scaled_jacobian(robot, jacobian))
        null = np.concatenate([scaled[..., :3], scaled[..., 3:] / robot.scale], axis=-1)
        constraint = np.concatenate(
            [null[..., :3] + cross(r, null[..., 3:]), null[..., 3:]], axis=-1
        )
    return jacobian, parallel, constraint, r, null


def frame_measures(
    robot: SpatialRobot, frames: Frames, position: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The signed measures ``μ_leg (N, legs)`` and ``μ_par (N,)`` of solved frames, no refusal.

    ``frames`` from :func:`~prp3.spatial.geometry.leg_coordinates` at the platform origins
    ``position (N, 3)`` (limits and closure not checked); the measures are those of §6 and
    §11 that :func:`spatial_kinematics` refuses below :data:`SINGULAR` times their sign at
    home (:func:`home_signs`).  A leg whose closure has no real solution (``NaN`` joint
    values) gives ``NaN``; a singular leg Jacobian gives a measure of 0 or ``NaN``, never
    a warning.

    >>> from prp3.spatial.geometry import leg_coordinates
    >>> from prp3.spatial.model import hexapod
    >>> robot = hexapod()
    >>> p = np.array([robot.home_position])
    >>> leg, par = frame_measures(robot, leg_coordinates(robot, p, np.eye(3)[None]), p)
    >>> leg.shape, round(float(par[0]), 6)
    ((1, 6), 2.129476)
    """
    n, legs = frames.q.shape[:2]
    leg, par = np.full((n, legs), np.nan), np.full(n, np.nan)
    solved = np.asarray(np.isfinite(frames.q).all(axis=(1, 2)), dtype=bool)
    with np.errstate(all="ignore"):
        try:
            some = _frame_subset(frames, solved)
            leg[solved], par[solved] = _subset_measures(robot, some, position[solved])
        except np.linalg.LinAlgError:  # an exactly singular leg Jacobian: point by point
            for k in np.flatnonzero(solved).tolist():
                try:
                    one = _frame_subset(frames, np.asarray(np.arange(n) == k))
                    leg[k], par[k] = (
                        v[0] for v in _subset_measures(robot, one, position[k : k + 1])
                    )
                except np.linalg.LinAlgError:
                    leg[k], par[k] = 0.0, 0.0  # singular: the measure vanishes
    return leg, par


def _frame_subset(frames: Frames, mask: NDArray[np.bool_]) -> Frames:
    return Frames(*(np.asarray(getattr(frames, f.name))[mask] for f in fields(Frames)))


def _subset_measures(
    robot: SpatialRobot, frames: Frames, position: FloatArray
) -> tuple[FloatArray, FloatArray]:
    jacobian, parallel, constraint, _, _ = _frames_geometry(robot, frames, position)
    return _measures(robot, _scaled_jacobian(robot, jacobian), parallel, constraint)


@lru_cache(maxsize=32)
def home_signs(robot: SpatialRobot) -> tuple[FloatArray, float]:
    """The signs of ``μ_leg`` (per leg) and ``μ_par`` at the robot's home pose."""
    home = PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    _, jacobian, parallel, constraint, _, _ = _leg_geometry(robot, home, 0)
    leg, par = _measures(robot, _scaled_jacobian(robot, jacobian), parallel, constraint)
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


#: A twist or acceleration is refused when a leg's constraint is off by more than this
#: fraction of it (docs/spatial.md §11).
COMPATIBILITY: float = 1e-8


def _check_compatible(
    null: FloatArray | None,
    target: FloatArray,
    motion: PlatformMotion,
    what: str,
    offset: int,
    scale: float,
    reference: FloatArray | None = None,
) -> None:
    """Refuse a leg end's twist or acceleration ``target (N, legs, 6)`` outside the leg's reach.

    The tolerance is relative to ``6·max|w̃|`` times the larger of ``max|target|`` and
    ``max|reference|`` (the acceleration's terms before the bias is taken off), all in
    units of ``ℓ``.
    """
    if null is None:
        return

    def norm(x: FloatArray) -> FloatArray:
        scaled = np.concatenate([x[..., :3], x[..., 3:] / scale], axis=-1)
        return np.asarray(np.abs(scaled).max(axis=-1), dtype=np.float64)  # no underflow

    scaled = np.concatenate([target[..., :3], target[..., 3:] / scale], axis=-1)
    w = np.concatenate([null[..., :3], null[..., 3:] * scale], axis=-1)
    off = np.abs(np.einsum("nli,nli->nl", w, scaled))
    magnitude = norm(target) if reference is None else np.maximum(norm(target), norm(reference))
    size = 6.0 * np.abs(w).max(axis=-1) * magnitude  # bounds |w·target| (maximum norms)
    bad = off > COMPATIBILITY * np.maximum(size, np.finfo(np.float64).tiny)
    if bad.any():
        k = int(np.argmax(bad.any(axis=1)))
        i = int(np.argmax(bad[k]))
        raise TrajectoryError(
            f"the platform's {what} is not one the legs allow (off the leg's constraint by "
            f"{float(off[k, i] / max(size[k, i], 1e-300)):.3g} of it; complete_motion gives the "
            "parasitic components)",
            subject="motion",
            sample=offset + k,
            time=float(motion.t[k]),
            leg=str(i + 1),
        )


def chunk_kinematics(
    robot: SpatialRobot, motion: PlatformMotion, offset: int = 0
) -> ChunkKinematics:
    """The kinematics of one chunk (samples numbered from ``offset``), refusals included (§4, §6)."""
    frames, jacobian, parallel, constraint, r, null = _leg_geometry(robot, motion, offset)
    leg, par = _measures(robot, _scaled_jacobian(robot, jacobian), parallel, constraint)
    _check_singular(robot, motion, leg, par, offset)
    omega = np.broadcast_to(motion.omega[:, None, :], r.shape)
    alpha = np.broadcast_to(motion.alpha[:, None, :], r.shape)
    v_end, a_end = _transport(
        motion.velocity[:, None, :], motion.acceleration[:, None, :], omega, alpha, r
    )
    twist = np.concatenate([omega, v_end], axis=-1)
    _check_compatible(null, twist, motion, "twist", offset, robot.scale)
    dq = pseudo_solve(jacobian, twist)
    bias = chain_motion(robot, frames, dq, np.zeros_like(dq))
    rhs = np.concatenate(
        [alpha - bias.alpha[:, :, -1], a_end - bias.acceleration[:, :, -1]], axis=-1
    )
    reference = np.concatenate([bias.alpha[:, :, -1], bias.acceleration[:, :, -1]], axis=-1)
    _check_compatible(null, rhs, motion, "acceleration", offset, robot.scale, reference)
    ddq = pseudo_solve(jacobian, rhs)
    bodies = chain_motion(robot, frames, dq, ddq)
    return ChunkKinematics(frames, dq, ddq, jacobian, parallel, bodies, leg, par, constraint, null)


def _solved_or_nan(matrix: FloatArray, rhs: FloatArray) -> FloatArray:
    try:
        return np.asarray(np.linalg.solve(matrix, rhs), dtype=np.float64)
    except np.linalg.LinAlgError:
        return np.full_like(rhs, np.nan)


def _newton_step(jacobian: FloatArray, off: FloatArray, position: FloatArray) -> FloatArray:
    """The Newton step of :func:`complete_motion`, refusing a pose it cannot complete.

    A pose far beyond the robot (a position of 1e308 m) gives closure residuals or a
    Jacobian that are not finite, or a singular Jacobian: refused naming the first such
    sample (``TrajectoryError``, ``sample`` set).
    """
    with np.errstate(all="ignore"):
        finite = np.isfinite(off).all(axis=-1) & np.isfinite(jacobian).all(axis=(-2, -1))
        if finite.all():
            try:
                step = np.linalg.solve(jacobian, -off[..., None])[..., 0]
            except np.linalg.LinAlgError:  # find the singular sample(s)
                step = np.array([_solved_or_nan(a, -o) for a, o in zip(jacobian, off, strict=True)])
            finite = np.isfinite(step).all(axis=-1)
            if finite.all():
                return np.asarray(step, dtype=np.float64)
    k = int(np.argmin(finite))
    raise TrajectoryError(
        f"the pose of sample {k} (position {position[k].tolist()!r} m) cannot be completed for "
        "the legs (docs/spatial.md §11): its closure residuals are not finite or their "
        "Jacobian is singular; give poses within the robot's reach",
        sample=k,
    )


def complete_motion(robot: SpatialRobot, motion: PlatformMotion) -> PlatformMotion:
    """``motion`` with its parasitic components solved so that every leg can follow it (§11).

    For a robot of fewer than 6 degrees of freedom (``robot.parasitic``, e.g. the 3-RPS's
    ``wz, vx, vy``): the pose's parasitic coordinates (for ``vx, vy, vz`` the position's
    ``x, y, z``; for ``wx, wy, wz`` turns about the world axes) by Newton's method on the
    legs' closure residuals (:func:`~prp3.spatial.geometry.plane_offsets`, its Jacobian by
    central differences), then the twist's and
    the acceleration's parasitic components from the legs' constraints (linear).  The
    other components are kept.  A robot of 6 degrees of freedom gets ``motion`` back.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    index = list(robot.parasitic_index)
    if not index:
        return motion
    position, rotation = _parasitic_pose(robot, motion, index)
    # the twist: C·ξ = 0 for the parasitic components
    staged = PlatformMotion(motion.t, position, rotation, motion.omega, motion.velocity,
                            motion.alpha, motion.acceleration)  # fmt: skip
    frames, jacobian, _, constraint, r, null = _leg_geometry(robot, staged, 0)
    if constraint is None or null is None:  # legs of 6 coordinates: nothing to complete
        return staged
    free = [c for c in range(6) if c not in index]
    # the completed rotation is E·R0 (E: the parasitic turns): its angular velocity is
    # E·ω0 + ω_E with ω_E along the parasitic axes (one or all three of them), so its
    # free components are E·ω0's, not ω0's; the position only moves along parasitic axes
    turn = rotation @ np.swapaxes(motion.rotation, -1, -2)
    turned = np.einsum("nij,nj->ni", turn, motion.omega)
    twist = np.concatenate([turned, motion.velocity], axis=1)
    twist[:, index] = np.linalg.solve(
        constraint[..., index],
        -np.einsum("nlj,nj->nl", constraint[..., free], twist[:, free])[..., None],
    )[..., 0]
    # the acceleration: wᵀ·(end acceleration − bias) = 0
    with np.errstate(all="ignore"):  # rates of 1e308: PlatformMotion.of refuses the result
        omega = np.broadcast_to(twist[:, None, :3], r.shape)
        v_end = twist[:, None, 3:] + cross(omega, r)
        dq = pseudo_solve(jacobian, np.concatenate([omega, v_end], axis=-1))
        bias = chain_motion(robot, frames, dq, np.zeros_like(dq))
        centripetal = cross(omega, cross(omega, r))
        target = np.einsum("nli,nli->nl", null[..., :3], bias.alpha[:, :, -1]) + np.einsum(
            "nli,nli->nl", null[..., 3:], bias.acceleration[:, :, -1] - centripetal
        )
        # α = E·α0 + ω_E × E·ω0 + (ω_E)˙, the last along the parasitic axes
        turn_rate = np.zeros_like(turned)
        rotations = [c for c in index if c < 3]
        turn_rate[:, rotations] = twist[:, rotations] - turned[:, rotations]
        turned_alpha = np.einsum("nij,nj->ni", turn, motion.alpha) + cross(turn_rate, turned)
        acc = np.concatenate([turned_alpha, motion.acceleration], axis=1)
        acc[:, index] = np.linalg.solve(
            constraint[..., index],
            (target - np.einsum("nlj,nj->nl", constraint[..., free], acc[:, free]))[..., None],
        )[..., 0]
    return PlatformMotion.of(
        motion.t, position, rotation, twist[:, :3], twist[:, 3:], acc[:, :3], acc[:, 3:]
    )


def parasitic_moved(
    index: list[int], position: FloatArray, rotation: FloatArray, steps: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The poses ``position`` (n, 3), ``rotation`` (n, 3, 3) moved by ``steps`` (n, k) along
    the parasitic coordinates ``index`` (k): ``c < 3`` a turn about the world axis ``c``
    (applied on the left, in order), else a shift of the position's ``c − 3``; new arrays."""
    p, r = position.copy(), rotation
    for j, c in enumerate(index):
        if c < 3:  # a turn about the world axis c
            r = exp_rotation(steps[:, j, None] * _AXES[c]) @ r
        else:
            p[:, c - 3] += steps[:, j]
    return p, r


_AXES = np.eye(3)


def _parasitic_pose(
    robot: SpatialRobot, motion: PlatformMotion, index: list[int]
) -> tuple[FloatArray, FloatArray]:
    """The positions ``(N, 3)`` and rotations ``(N, 3, 3)`` of ``motion`` with the parasitic
    coordinates ``index`` solved by Newton's method on the legs' closure residuals
    (:func:`complete_motion`; the Jacobian by central differences)."""
    position, rotation = motion.position.copy(), motion.rotation.copy()

    def moved(steps: FloatArray) -> tuple[FloatArray, FloatArray]:
        return parasitic_moved(index, position, rotation, steps)

    h = 1e-6
    zero = np.zeros((len(motion), len(index)))
    polished = False  # one more step once within tolerance takes the residual to round-off
    for _ in range(30):
        off = plane_offsets(robot, position, rotation)
        if np.abs(off).max() <= 1e-3 * PLANE_TOLERANCE * robot.scale:
            if polished:
                break
            polished = True
        columns = []
        for j, c in enumerate(index):
            step = zero.copy()
            step[:, j] = h * (1.0 if c < 3 else robot.scale)
            plus = plane_offsets(robot, *moved(step))
            minus = plane_offsets(robot, *moved(np.asarray(-step, dtype=np.float64)))
            columns.append((plus - minus) / (2.0 * step[:, j, None]))
        newton = _newton_step(np.stack(columns, axis=-1), off, position)
        position, rotation = moved(newton)
    return position, rotation


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
