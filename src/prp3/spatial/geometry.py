"""Inverse geometry of the legs: the chain of frames, closed forms per leg pattern, branch, limits.

The chain of docs/spatial.md §2 (:func:`chain_frames`: the joint frames and
distal frames of every joint of every leg for given joint values), the closed
form of each leg pattern on the branch of §5 (:func:`leg_coordinates`), and
the refusal of unreachable poses (§6: :class:`~prp3.errors.UnreachablePoseError`
naming the sample, its time and the leg).  Arrays have the batch on the leading
axis, then the legs: ``q (N, legs, dof)``.

>>> from prp3.spatial.model import hexapod
>>> from prp3.spatial.motion import PlatformMotion
>>> robot = hexapod()
>>> q = inverse_geometry(robot, PlatformMotion.at_rest([0.0, 0.0, 0.08]))
>>> q.shape, round(float(q[0, 0, 2]), 5), float(abs(q[0, :, [0, 1, 3, 4, 5]]).max()) < 1e-15
((1, 6, 6), 0.10284, True)
>>> inverse_geometry(robot, PlatformMotion.at_rest([0.0, 0.0, 0.2]))
Traceback (most recent call last):
...
prp3.errors.UnreachablePoseError: sample 0, t = 0 s, leg 1: P2 = 0.210179 m is outside its limits [0.085, 0.12] at the pose p = (0, 0, 0.2) m
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.errors import UnreachablePoseError
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import axis_rotation, exp_rotation, log_rotation
from prp3.validation import check_instance

__all__ = [
    "CHUNK",
    "Frames",
    "JointLimit",
    "attachments",
    "chain_frames",
    "coordinate_kinds",
    "end_frames",
    "inverse_geometry",
    "joint_limits",
    "leg_coordinates",
    "leg_frames",
    "limit_margin",
    "placements",
    "plane_offsets",
]

FloatArray = NDArray[np.float64]

#: Samples computed at once by the chunked entries (memory stays bounded for any ``N``).
CHUNK: int = 4096


@dataclass(frozen=True)
class Frames:
    """The chain of every leg for ``N`` samples (docs/spatial.md §2).

    Attributes
    ----------
    q : (N, legs, dof)
        Joint values.
    joint_origin, joint_rotation : (N, legs, n, 3), (N, legs, n, 3, 3)
        The joint frames ``J_k`` in the world frame.
    origin, rotation : (N, legs, n, 3), (N, legs, n, 3, 3)
        The distal frames ``F_k`` (origin = the joint point); ``F_n`` is the leg's end.
    axes : (N, legs, dof, 3)
        The unit axis of each coordinate's free motion in the world frame (R, U: the
        rotation axes; P: the slide; S: the world ``x, y, z``).
    """

    q: FloatArray
    joint_origin: FloatArray
    joint_rotation: FloatArray
    origin: FloatArray
    rotation: FloatArray
    axes: FloatArray


def coordinate_kinds(robot: SpatialRobot) -> tuple[tuple[str, int], ...]:
    """Per coordinate of a leg: its kind (``"r"`` axis fixed in a body, ``"t"`` slide,
    ``"s"`` world axis of an S) and the index of its joint."""
    kinds: list[tuple[str, int]] = []
    for k, joint in enumerate(robot.legs[0].joints):
        kind = {"R": "r", "U": "r", "P": "t", "S": "s"}[joint.kind]
        kinds.extend((kind, k) for _ in range(joint.dof))
    return tuple(kinds)


def placements(robot: SpatialRobot) -> tuple[list[FloatArray], list[FloatArray]]:
    """Per joint ``k``: its placement position ``(legs, 3)`` and rotation ``(legs, 3, 3)``."""
    n = len(robot.legs[0].joints)
    positions = [np.array([leg.joints[k].position for leg in robot.legs]) for k in range(n)]
    rotations = [np.array([leg.joints[k].rotation for leg in robot.legs]) for k in range(n)]
    return positions, rotations


def chain_frames(robot: SpatialRobot, q: FloatArray) -> Frames:
    """The frames of every joint of every leg for joint values ``q (N, legs, dof)`` (§2)."""
    positions, rotations = placements(robot)
    n_samples, n_legs = q.shape[:2]
    origin = np.zeros((n_samples, n_legs, 3))
    rotation = np.broadcast_to(np.eye(3), (n_samples, n_legs, 3, 3))
    j_origin, j_rotation, f_origin, f_rotation, axes = [], [], [], [], []
    column = 0
    for k, joint in enumerate(robot.legs[0].joints):
        jo = origin + np.einsum("nlij,lj->nli", rotation, positions[k])
        jr = rotation @ rotations[k]
        if joint.kind == "R":
            axes.append(jr[..., :, 2])
            fo, fr = jo, jr @ axis_rotation(2, q[..., column])
        elif joint.kind == "P":
            axes.append(jr[..., :, 0])
            fo, fr = jo + q[..., column, None] * jr[..., :, 0], jr
        elif joint.kind == "U":
            cross_frame = jr @ axis_rotation(2, q[..., column])
            axes.extend([jr[..., :, 2], cross_frame[..., :, 1]])
            fo, fr = jo, cross_frame @ axis_rotation(1, q[..., column + 1])
        else:  # S
            axes.extend(np.broadcast_to(np.eye(3)[i], (n_samples, n_legs, 3)) for i in range(3))
            fo, fr = jo, jr @ exp_rotation(q[..., column : column + 3])
        column += joint.dof
        j_origin.append(jo)
        j_rotation.append(jr)
        f_origin.append(fo)
        f_rotation.append(fr)
        origin, rotation = fo, fr
    return Frames(
        q,
        np.stack(j_origin, axis=2),
        np.stack(j_rotation, axis=2),
        np.stack(f_origin, axis=2),
        np.stack(f_rotation, axis=2),
        np.stack(axes, axis=2),
    )


def attachments(robot: SpatialRobot) -> tuple[FloatArray, FloatArray]:
    """The legs' attachments in the platform frame: positions ``(legs, 3)``, rotations ``(legs, 3, 3)``."""
    return (
        np.array([leg.attachment_position for leg in robot.legs]),
        np.array([leg.attachment_rotation for leg in robot.legs]),
    )


def end_frames(
    robot: SpatialRobot, position: FloatArray, rotation: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Where each leg's end must be (closure, §2): origins ``(N, legs, 3)``, rotations ``(N, legs, 3, 3)``."""
    c_a, r_a = attachments(robot)
    origin = position[:, None, :] + np.einsum("nij,lj->nli", rotation, c_a)
    return origin, np.einsum("nij,ljk->nlik", rotation, r_a)


def leg_coordinates(robot: SpatialRobot, position: FloatArray, rotation: FloatArray) -> Frames:
    """The closed-form inverse geometry of every leg on the branch of §5 (no limits checked).

    ``position (N, 3)``, ``rotation (N, 3, 3)``; the legs' pattern is ``UPS`` or ``RPS``
    (the RPS's S centre is taken projected on its R joint's plane: :func:`plane_offsets`
    says how far off it is).  A leg whose base-to-S distance is zero gets ``NaN``
    (refused by :func:`check_reach`).
    """
    positions, rotations = placements(robot)
    c_end, r_end = end_frames(robot, position, rotation)
    n_samples, n_legs = c_end.shape[:2]
    q = np.zeros((n_samples, n_legs, robot.legs[0].dof))
    d = np.einsum("lji,nlj->nli", rotations[0], c_end - positions[0][None])
    pattern = robot.legs[0].pattern
    if pattern == "RUU":
        return _ruu_coordinates(robot, q, d, c_end, r_end)
    if pattern == "UPS":
        rho = np.sqrt(np.einsum("nli,nli->nl", d, d))
        with np.errstate(invalid="ignore", divide="ignore"):
            q[..., 0] = np.where(rho > 0.0, np.arctan2(d[..., 1], d[..., 0]), np.nan)
            q[..., 1] = np.arctan2(-d[..., 2], np.hypot(d[..., 0], d[..., 1]))
        slide = 2
    else:  # RPS: the leg turns in the plane of the R's x and y
        rho = np.hypot(d[..., 0], d[..., 1])
        q[..., 0] = np.where(rho > 0.0, np.arctan2(d[..., 1], d[..., 0]), np.nan)
        slide = 1
    q[..., slide] = rho - positions[1][None, :, 0] - positions[2][None, :, 0]
    frames = chain_frames(robot, q)
    s_rotation = frames.joint_rotation[:, :, 2]
    q[..., slide + 1 : slide + 4] = log_rotation(np.swapaxes(s_rotation, -1, -2) @ r_end)
    return chain_frames(robot, q)


def _direction_angles(d: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The U angles ``(a, b)`` with ``Rot_z(a)·Rot_y(b)·e_x`` along ``d (..., 3)`` (``cos b > 0``)."""
    return np.arctan2(d[..., 1], d[..., 0]), np.arctan2(-d[..., 2], np.hypot(d[..., 0], d[..., 1]))


def _ruu_coordinates(
    robot: SpatialRobot, q: FloatArray, d: FloatArray, c_end: FloatArray, r_end: FloatArray
) -> Frames:
    """RUU (docs/spatial.md §12): the arm's angle from ``d_x cos θ + d_y sin θ = K`` (the
    elbow-out branch ``θ = atan2(d_y, d_x) − acos(K/ρ)``), the first U from the forearm's
    direction, the second U from the end's orientation (its ``x`` column)."""
    positions, _ = placements(robot)
    arm = positions[1][None, :, 0]
    forearm = positions[2][None, :, 0]
    k = (np.einsum("nli,nli->nl", d, d) + arm * arm - forearm * forearm) / (2.0 * arm)
    rho = np.hypot(d[..., 0], d[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(np.abs(k) <= rho, k / rho, np.nan)  # NaN: out of reach
        q[..., 0] = np.arctan2(d[..., 1], d[..., 0]) - np.arccos(ratio)
    frames = chain_frames(robot, q)
    u1 = frames.joint_rotation[:, :, 1]
    f = np.einsum("nlji,nlj->nli", u1, c_end - frames.joint_origin[:, :, 1])
    q[..., 1], q[..., 2] = _direction_angles(f)
    frames = chain_frames(robot, q)
    m = np.swapaxes(frames.joint_rotation[:, :, 2], -1, -2) @ r_end
    q[..., 3], q[..., 4] = _direction_angles(m[..., :, 0])
    return chain_frames(robot, q)


#: An RPS leg's S centre may be this far (times ``ℓ``) off its R joint's plane.
PLANE_TOLERANCE: float = 1e-9


def plane_offsets(robot: SpatialRobot, position: FloatArray, rotation: FloatArray) -> FloatArray:
    """Each leg's closure residual (m), ``(N, legs)``: for RPS how far its S centre is off the
    plane its R joint turns in; for RUU ``ℓ`` times the component ``M_zy`` of the end's
    orientation in the second U's joint frame, which a U cannot turn (§12); zeros for UPS."""
    pattern = robot.legs[0].pattern
    if pattern == "UPS":
        return np.zeros((position.shape[0], len(robot.legs)))
    if pattern == "RUU":
        frames = leg_coordinates(robot, position, rotation)
        _, r_end = end_frames(robot, position, rotation)
        m = np.swapaxes(frames.joint_rotation[:, :, 2], -1, -2) @ r_end
        return np.asarray(robot.scale * m[..., 2, 1])
    positions, rotations = placements(robot)
    c_end, _ = end_frames(robot, position, rotation)
    return np.asarray(np.einsum("li,nli->nl", rotations[0][..., 2], c_end - positions[0][None]))


def _pose_text(position: FloatArray) -> str:
    return "p = (" + ", ".join(f"{float(v):.6g}" for v in position) + ") m"


@dataclass(frozen=True)
class JointLimit:
    """One bounded coordinate of one leg, over the samples of ``q`` (§6).

    ``values (N,)`` are the coordinate (rad, m; for an S joint its angle ``|φ|``, which
    its ``low = 0`` bounds only in form), ``low < high`` its limits, ``unit`` ``"m"`` or
    ``"rad"``, ``kind`` the joint's.
    """

    kind: str
    leg: int
    name: str
    unit: str
    values: FloatArray
    low: float
    high: float


def joint_limits(robot: SpatialRobot, q: FloatArray) -> Iterator[JointLimit]:
    """Every coordinate of every leg with its limits, for the joint values ``q (N, legs, dof)``."""
    leg0 = robot.legs[0]
    for i, leg in enumerate(robot.legs):
        column = 0
        for joint, label in zip(leg.joints, leg0.labels, strict=True):
            if joint.kind == "S":
                angle = np.sqrt(np.einsum("ni,ni->n", q[:, i, column : column + 3],
                                          q[:, i, column : column + 3]))  # fmt: skip
                values, names, units = [angle], [f"|{label}|"], ["rad"]
            else:
                values = [q[:, i, column + c] for c in range(joint.dof)]
                names = list(joint.coordinates(label))
                units = ["m" if joint.kind == "P" else "rad"] * joint.dof
            for value, name, unit, (low, high) in zip(
                values, names, units, joint.limits, strict=True
            ):
                yield JointLimit(joint.kind, i, name, unit, value, low, high)
            column += joint.dof


def limit_margin(robot: SpatialRobot, q: FloatArray) -> tuple[FloatArray, list[JointLimit]]:
    """How far each sample of ``q (N, legs, dof)`` stays within the joints' limits (§6).

    The margin of a coordinate is ``min(value − low, high − value)`` (an S joint's angle:
    ``high − |φ|``), in rad, and in units of the robot's scale for a length; negative
    beyond a limit, ``inf`` for an unbounded coordinate.  Returns the smallest over every coordinate of every leg,
    ``(N,)``, and the bounded coordinates (:class:`JointLimit`).

    >>> from prp3.spatial.model import hexapod
    >>> robot = hexapod()
    >>> margin, bounded = limit_margin(robot, inverse_geometry(robot, PlatformMotion.of(
    ...     [0.0], robot.home_position, robot.home_rotation)))
    >>> bool(margin[0] > 0), sorted({limit.name for limit in bounded})
    (True, ['P2', 'U1_a', 'U1_b', '|S3|'])
    """
    margin = np.full(q.shape[0], np.inf)
    bounded = []
    for limit in joint_limits(robot, q):
        low = -np.inf if limit.kind == "S" else limit.low
        if not (np.isfinite(low) or np.isfinite(limit.high)):
            continue
        bounded.append(limit)
        unit = robot.scale if limit.unit == "m" else 1.0
        distance = np.minimum(limit.values - low, limit.high - limit.values) / unit
        margin = np.minimum(margin, np.where(np.isnan(distance), -np.inf, distance))
    return margin, bounded


def check_reach(
    robot: SpatialRobot, frames: FloatArray, position: FloatArray, t: FloatArray, offset: int = 0
) -> None:
    """Refuse the first sample where a leg cannot reach or a joint is beyond its limits (§6).

    ``frames`` is :attr:`Frames.q` ``(N, legs, dof)``; ``offset`` is the index of the
    chunk's first sample in the motion.
    """
    q = frames
    refusals: list[tuple[int, int, str]] = []
    for i in range(len(robot.legs)):
        unreachable = ~np.isfinite(q[:, i]).all(axis=1)
        if unreachable.any():
            k = int(np.argmax(unreachable))
            refusals.append((k, i, "cannot reach: the leg's closure has no real solution"))
    for limit in joint_limits(robot, q):
        bad = (limit.values < limit.low) | (limit.values > limit.high)
        if bad.any():
            k = int(np.argmax(bad))
            refusals.append(
                (
                    k,
                    limit.leg,
                    f"{limit.name} = {float(limit.values[k]):.6g} {limit.unit} is outside its "
                    f"limits [{limit.low:.6g}, {limit.high:.6g}]",
                )
            )
    if refusals:
        k, i, reason = min(refusals, key=lambda r: (r[0], r[1]))
        raise UnreachablePoseError(
            f"{reason} at the pose {_pose_text(position[k])}",
            sample=offset + k,
            time=float(t[k]),
            leg=str(i + 1),
        )


def leg_frames(robot: SpatialRobot, motion: PlatformMotion, offset: int = 0) -> Frames:
    """The frames of one chunk of ``motion`` (its samples numbered from ``offset``), limits checked."""
    frames = leg_coordinates(robot, motion.position, motion.rotation)
    check_reach(robot, frames.q, motion.position, motion.t, offset)
    off = np.abs(plane_offsets(robot, motion.position, motion.rotation))
    bad = off > PLANE_TOLERANCE * robot.scale
    if bad.any():
        k = int(np.argmax(bad.any(axis=1)))
        i = int(np.argmax(bad[k]))
        what = (
            "its S centre is off the plane of its R joint by"
            if robot.legs[0].pattern == "RPS"
            else "its second U cannot turn the platform to this orientation: off by"
        )
        raise UnreachablePoseError(
            f"{what} {float(off[k, i]):.3g} m at the pose "
            f"{_pose_text(motion.position[k])}: not a pose of the {robot.name}'s "
            f"{len(robot.legs)} degrees of freedom (complete_motion solves its parasitic {', '.join(robot.parasitic)})",
            sample=offset + k,
            time=float(motion.t[k]),
            leg=str(i + 1),
        )
    return frames


def inverse_geometry(robot: SpatialRobot, motion: PlatformMotion) -> FloatArray:
    """The joint values of every leg, ``q (N, legs, dof)`` (rad, m), on the branch of §5.

    Parameters
    ----------
    robot : SpatialRobot
    motion : PlatformMotion
        Only the poses are used.

    Raises
    ------
    UnreachablePoseError
        A leg cannot reach a pose or a joint is beyond its limits (names the sample,
        its time and the leg).
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    n = len(motion)
    q = np.empty((n, len(robot.legs), robot.legs[0].dof))
    for start in range(0, n, CHUNK):
        stop = min(start + CHUNK, n)
        q[start:stop] = leg_frames(robot, motion.chunk(start, stop), start).q
    return q
