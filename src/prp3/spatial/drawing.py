"""What every drawing of a spatial robot shows, as plain arrays: joint points, legs, force arrows.

docs/spatial.md §15 and §22.  The animation (:mod:`prp3.plotting.spatial_animation`, matplotlib)
and the 3-D explorer's page (:mod:`prp3.explorer.spatial_page`, plotly) draw the same
:class:`SpatialFrame` of a sample: computed by :func:`spatial_frame` from the joint values ``q``
of a spatial ``results.csv`` (docs/spatial.md §9) through the chain of frames of §2
(:func:`prp3.spatial.geometry.chain_frames`), and the same arrows' scale
(:func:`force_scale`).  No drawing library is imported here.

>>> from prp3.spatial.model import hexapod
>>> from prp3.spatial.motion import PlatformMotion
>>> from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table
>>> robot = hexapod()
>>> table = spatial_results_table(
...     spatial_inverse_dynamics(robot, PlatformMotion.at_rest(robot.home_position)))
>>> t, q, force = spatial_samples(robot, table)
>>> frame = spatial_frame(robot, q[0], force[0])
>>> frame.points.shape, frame.labels, frame.centre.round(12).tolist()  # 6 legs, U1 P2 S3
((6, 3, 3), ('U1', 'P2', 'S3'), [0.0, 0.0, 0.08])
>>> force_scale(force, 0.2)   # largest |F| 3.78 N (U1) in at most 0.3 × 0.2 m: 63 -> 100 N/m
100.0
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import ParameterError
from prp3.spatial.geometry import chain_frames
from prp3.spatial.model import SpatialRobot
from prp3.validation import check_instance

__all__ = [
    "ARROW_FRACTION",
    "AXIS_HALF",
    "JOINT_COLOURS",
    "JOINT_NAMES",
    "LEG_COLOURS",
    "SLEEVE_FRACTION",
    "VIEW",
    "SpatialFrame",
    "axis_segments",
    "force_scale",
    "platform_path",
    "robot_size",
    "scene_extent",
    "sleeve_lengths",
    "spatial_frame",
    "spatial_samples",
    "view_direction",
]

FloatArray = NDArray[np.float64]

#: The colours of the legs 1 to 6 (a colour-blind-safe palette), in every spatial figure.
LEG_COLOURS: tuple[str, ...] = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9")

#: The largest force of a run is drawn at most this fraction of the robot's size long.
ARROW_FRACTION: float = 0.3

#: A P joint's sleeve is this fraction of the smallest joint value ``q_P`` over the run.
SLEEVE_FRACTION: float = 0.6

#: The view of the 3-D axes: elevation and azimuth (degrees), as matplotlib's ``view_init``.
VIEW: tuple[float, float] = (22.0, -58.0)

#: The colours of the force arrows by the joint's place in the leg (1st, 2nd, 3rd joint): a
#: colour-blind-safe dark red, dark blue and dark green, apart from the legs' colours.
JOINT_COLOURS: tuple[str, ...] = ("#B2182B", "#2A3F9E", "#1B7837", "#7B3294")

#: A joint's axis segment (R, U) is drawn this fraction of the robot's size either side.
AXIS_HALF: float = 0.07

#: The joint types' names.
JOINT_NAMES: dict[str, str] = {
    "R": "revolute", "P": "prismatic", "U": "universal", "S": "spherical"
}  # fmt: skip


@dataclass(frozen=True)
class SpatialFrame:
    """What one frame shows (world frame, m; forces in N).

    Attributes
    ----------
    t : float
        Time of the sample (s).
    labels, kinds : tuple of str
        The joints of a leg (``U1, P2, S3``) and their types (``U, P, S``), base to platform.
    actuated : int
        Index of the actuated joint in the leg.
    points : ndarray (legs, n, 3)
        The joint points (docs/spatial.md §2: the origin of each joint's distal frame).
    axes : ndarray (legs, n, 2, 3)
        The unit rotation axes of each R (one, then NaN) and U (two) joint; NaN for P and S.
    chain : ndarray (legs, 2 n, 3)
        Each leg from the base to the platform: joint frame origin and joint point of every
        joint in turn (a P's rod joins them; body ``k`` joins joint ``k``'s point to joint
        ``k + 1``'s frame origin).
    sleeves : ndarray (legs, n, 2, 3)
        Each P joint's sleeve (from its joint frame's origin along its slide); NaN otherwise.
    base, platform : ndarray (legs, 3)
        The base polygon (the legs' first joint points) and the platform polygon (their last
        joint points), in order around their centres.
    centre : ndarray (3,)
        The platform origin ``p``.
    forces : ndarray (legs, n, 3)
        The reaction force of every joint (N).
    """

    t: float
    labels: tuple[str, ...]
    kinds: tuple[str, ...]
    actuated: int
    points: FloatArray
    axes: FloatArray
    chain: FloatArray
    sleeves: FloatArray
    base: FloatArray
    platform: FloatArray
    centre: FloatArray
    forces: FloatArray


def spatial_samples(
    robot: SpatialRobot, table: Mapping[str, NDArray[Any]]
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The times ``t (N,)``, joint values ``q (N, legs, dof)`` and joint forces
    ``(N, legs, joints, 3)`` of the columns of a spatial results table (docs/spatial.md §9)."""
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    if not isinstance(table, Mapping):
        raise ParameterError(
            f"table must be a mapping of column names to arrays, got {type(table).__name__}",
            key="table",
        )
    leg = robot.legs[0]
    names = ["t"]
    names += [f"q_{i + 1}_{c}" for i in range(len(robot.legs)) for c in leg.coordinates]
    names += [
        f"F{c}_{i + 1}_{label}"
        for i in range(len(robot.legs))
        for label in leg.labels
        for c in "xyz"
    ]
    missing = [name for name in names if name not in table]
    if missing:
        raise ParameterError(
            f"table: no column {missing[0]} (the columns of a {robot.name} run by the "
            "Newton-Euler route, docs/spatial.md §9)",
            key="table",
        )
    try:
        columns = [np.asarray(table[name], dtype=np.float64) for name in names]
        values = np.stack(columns, axis=1)
    except (TypeError, ValueError) as error:
        raise ParameterError(
            f"table: columns of numbers of one length each, got {error}", key="table"
        ) from None
    if values.ndim != 2 or values.shape[0] < 1:
        raise ParameterError(
            f"table: columns of one value per sample, got {values.shape}", key="table"
        )
    bad = np.flatnonzero(~np.isfinite(values).all(axis=0))
    if bad.size:
        raise ParameterError(
            f"table: column {names[int(bad[0])]} is not finite (NaN or infinity)", key="table"
        )
    n, legs, dof, joints = values.shape[0], len(robot.legs), leg.dof, len(leg.joints)
    q = values[:, 1 : 1 + legs * dof].reshape(n, legs, dof)
    force = values[:, 1 + legs * dof :].reshape(n, legs, joints, 3)
    return values[:, 0].copy(), q, force


def _around(points: FloatArray) -> NDArray[np.int64]:
    """The order of ``points (m, 3)`` around their centroid, seen along the normal of their best
    plane."""
    middle = points.mean(axis=0)
    spread = points - middle
    _, _, vt = np.linalg.svd(spread)
    u, v = vt[0], vt[1]
    return np.argsort(np.arctan2(spread @ v, spread @ u), kind="stable")


def spatial_frame(
    robot: SpatialRobot,
    q: FloatArray,
    forces: FloatArray,
    *,
    t: float = 0.0,
    sleeve: FloatArray | None = None,
) -> SpatialFrame:
    """The frame of joint values ``q (legs, dof)`` with the joint forces ``(legs, joints, 3)``.

    ``sleeve``: the sleeve length of each P joint of a leg, ``(n,)`` m (NaN for the other
    joints); by default :data:`SLEEVE_FRACTION` of this frame's ``q_P``.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    leg = robot.legs[0]
    legs, n = len(robot.legs), len(leg.joints)
    values = np.asarray(q, dtype=np.float64)
    force = np.asarray(forces, dtype=np.float64)
    if values.shape != (legs, leg.dof) or force.shape != (legs, n, 3):
        raise ParameterError(
            f"q must have the shape ({legs}, {leg.dof}) and forces ({legs}, {n}, 3), got "
            f"{values.shape} and {force.shape}",
            key="q",
        )
    frames = chain_frames(robot, values[None])
    origin, rotation = frames.origin[0], frames.rotation[0]
    j_origin, j_rotation = frames.joint_origin[0], frames.joint_rotation[0]
    axes = np.full((legs, n, 2, 3), np.nan)
    sleeves = np.full((legs, n, 2, 3), np.nan)
    lengths = np.full(n, np.nan) if sleeve is None else np.asarray(sleeve, dtype=np.float64)
    column = 0
    for k, joint in enumerate(leg.joints):
        if joint.kind in ("R", "U"):
            axes[:, k, 0] = frames.axes[0, :, column]
        if joint.kind == "U":
            axes[:, k, 1] = frames.axes[0, :, column + 1]
        if joint.kind == "P":
            length = (
                SLEEVE_FRACTION * values[:, column] if sleeve is None else np.full(legs, lengths[k])
            )
            slide = j_rotation[:, k, :, 0]
            sleeves[:, k, 0] = j_origin[:, k]
            sleeves[:, k, 1] = j_origin[:, k] + length[:, None] * slide
        column += joint.dof
    chain = np.stack([j_origin, origin], axis=2).reshape(legs, 2 * n, 3)
    # the platform origin from leg 1's end: F_n = (p + R c_A, R R_A)
    r_p = rotation[0, -1] @ np.asarray(leg.attachment_rotation).T
    centre = origin[0, -1] - r_p @ np.asarray(leg.attachment_position)
    base, platform = origin[:, 0], origin[:, -1]
    return SpatialFrame(
        t=float(t),
        labels=leg.labels,
        kinds=tuple(joint.kind for joint in leg.joints),
        actuated=leg.actuated,
        points=origin.copy(),
        axes=axes,
        chain=chain,
        sleeves=sleeves,
        base=base[_around(base)],
        platform=platform[_around(platform)],
        centre=centre,
        forces=force.copy(),
    )


def force_scale(forces: FloatArray, size: float) -> float:
    """The arrows' scale ``k`` (N per m): the largest ``|F|`` of ``forces (..., 3)`` drawn at
    most :data:`ARROW_FRACTION` × ``size`` (m) long, ``k`` rounded up to 1, 2 or 5 × 10ⁿ.

    ``0.0`` when every force is zero (no arrows).

    >>> force_scale(np.array([[3.0, 0.0, 4.0]]), 0.1)    # 5 N at most 0.03 m: 166.7 -> 200
    200.0
    """
    largest = float(np.sqrt(np.einsum("...i,...i->...", forces, forces)).max(initial=0.0))
    if not largest > 0.0 or not math.isfinite(largest):
        return 0.0
    raw = largest / (ARROW_FRACTION * size)
    power = 10.0 ** math.floor(math.log10(raw))
    for step in (1.0, 2.0, 5.0, 10.0):
        if step * power >= raw * (1.0 - 1e-12):
            return float(step * power)
    return float(10.0 * power)  # pragma: no cover (the loop ends at 10)


def platform_path(robot: SpatialRobot, q: FloatArray) -> FloatArray:
    """The platform origin ``p (N, 3)`` at the joint values ``q (N, legs, dof)``, from leg 1's
    end (docs/spatial.md §2: ``F_n = (p + R·c_A, R·R_A)``)."""
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    leg = robot.legs[0]
    frames = chain_frames(robot, np.asarray(q, dtype=np.float64))
    end, turn = frames.origin[:, 0, -1], frames.rotation[:, 0, -1]
    r_p = turn @ np.asarray(leg.attachment_rotation).T
    centre: FloatArray = end - r_p @ np.asarray(leg.attachment_position)
    return centre


def robot_size(frames: list[SpatialFrame]) -> float:
    """The robot's size (m): the largest side of the box of its legs over ``frames``."""
    points = np.concatenate([frame.chain.reshape(-1, 3) for frame in frames])
    return float((points.max(axis=0) - points.min(axis=0)).max())


def sleeve_lengths(robot: SpatialRobot, q: FloatArray) -> FloatArray:
    """Per joint of a leg: :data:`SLEEVE_FRACTION` of the smallest ``q_P`` over ``q (N, legs,
    dof)`` for a P, NaN otherwise."""
    lengths = np.full(len(robot.legs[0].joints), np.nan)
    column = 0
    for k, joint in enumerate(robot.legs[0].joints):
        if joint.kind == "P":
            lengths[k] = SLEEVE_FRACTION * max(float(q[..., column].min()), 0.0)
        column += joint.dof
    return lengths


def axis_segments(axes: FloatArray, points: FloatArray, half: float) -> FloatArray:
    """Segments ``point ± half·axis`` of every leg's axes, NaN-separated, ``(m, 3)``."""
    rows = []
    for leg in range(points.shape[0]):
        for a in range(axes.shape[1]):
            if np.isnan(axes[leg, a]).any():
                continue
            rows.extend(
                [points[leg] - half * axes[leg, a], points[leg] + half * axes[leg, a], [np.nan] * 3]
            )
    return np.array(rows, dtype=np.float64).reshape(-1, 3)


def scene_extent(frames: list[SpatialFrame], scale: float) -> tuple[FloatArray, float]:
    """The middle and half side of the cube that holds everything drawn over ``frames``."""
    parts = []
    for frame in frames:
        parts += [frame.chain.reshape(-1, 3), frame.centre[None]]
        if scale > 0.0:
            parts.append((frame.points + frame.forces / scale).reshape(-1, 3))
    points = np.concatenate(parts)
    low, high = points.min(axis=0), points.max(axis=0)
    return 0.5 * (low + high), 0.55 * float((high - low).max())


def view_direction() -> FloatArray:
    """The unit vector from the scene towards the viewer of :data:`VIEW`."""
    elev, azim = (math.radians(v) for v in VIEW)
    return np.array(
        [math.cos(elev) * math.cos(azim), math.cos(elev) * math.sin(azim), math.sin(elev)]
    )
