"""Workspace slices and singularity maps of a spatial robot (docs/spatial.md §17).

A slice is a grid of platform poses in one plane of the pose space: two
position coordinates (``"xy"``, ``"xz"``, ``"yz"``; the third, ``offset``, and
the orientation ``rpy`` fixed) or the roll and pitch (``"rp"``; the height
``offset`` and the yaw fixed).  At each grid point, evaluated in chunks of
``CHUNK`` points (memory bounded for any grid): the pose the robot takes there
(for a robot of fewer than 6 DOF its parasitic components solved, §11), whether
every leg reaches it within its limits and, if not, why (:data:`WORKSPACE_REASONS`,
and the first leg that fails), the signed serial and parallel measures of §6 and
§11, whether the pose is regular (reachable, every measure on its home side by at
least ``SINGULAR``), and with ``statics`` the actuator efforts that hold the robot
at rest there (route (a) of §8 at zero rates: the weight of every body).

>>> from prp3.spatial.model import hexapod
>>> ws = spatial_workspace(hexapod(), points=5)
>>> ws.plane, ws.axes, ws.reason.shape, ws.mu_leg.shape
('xy', ('x', 'y'), (5, 5), (5, 5, 6))
>>> int(ws.reason[2, 2]), bool(ws.regular[2, 2]), round(float(ws.mu_par[2, 2]), 6)
(0, True, 2.129476)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError
from prp3.spatial.dynamics import virtual_work_efforts
from prp3.spatial.geometry import (
    CHUNK,
    PLANE_TOLERANCE,
    attachments,
    leg_coordinates,
    placements,
    plane_offsets,
)
from prp3.spatial.kinematics import SINGULAR, frame_measures, parasitic_moved
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import matrix_rpy, rpy_matrix
from prp3.validation import check_choice, check_instance, check_integer, check_real, check_scalar

__all__ = [
    "DEFAULT_POINTS",
    "MAX_POINTS",
    "SPATIAL_PLANES",
    "WORKSPACE_REASONS",
    "PoseReasons",
    "SpatialWorkspace",
    "pose_reasons",
    "regular_poses",
    "spatial_planes",
    "spatial_statics_table",
    "spatial_workspace",
    "spatial_workspace_table",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: The planes of a slice: the two coordinates of the grid, then the one ``offset`` gives.
SPATIAL_PLANES: dict[str, tuple[str, str, str]] = {
    "xy": ("x", "y", "z"),
    "xz": ("x", "z", "y"),
    "yz": ("y", "z", "x"),
    "rp": ("roll", "pitch", "z"),
}

#: Why a grid point is not reachable, by code (the ``reason`` column): 0 reachable;
#: 1 a leg's closure has no real solution (too far, or a zero-length leg); 2 a P joint
#: beyond its stroke; 3 an R, U or S joint beyond its limit; 4 not a pose of the robot's
#: degrees of freedom (its parasitic components have no solution near the given pose).
WORKSPACE_REASONS: tuple[str, ...] = (
    "reachable",
    "no closure",
    "stroke",
    "joint limit",
    "not a pose of the robot",
)

#: Grid points per axis by default, and at most (the grid has ``points²`` points).
DEFAULT_POINTS: int = 101
MAX_POINTS: int = 1000

#: Points per axis of the coarse grid that finds the default window, and its margin
#: (fraction of the reachable box's size, at least one coarse cell).
COARSE_POINTS: int = 61
EXTENT_MARGIN: float = 0.1

#: How far a position (m, in units of the robot's scale ``ℓ``) may be from the base.
POSITION_SPAN: float = 1000.0

#: The twist component of each pose coordinate (a robot's parasitic ones, §11).
_COMPONENT = {"x": "vx", "y": "vy", "z": "vz", "roll": "wx", "pitch": "wy", "yaw": "wz"}
_POSITION = {"x": 0, "y": 1, "z": 2}
_RPY = ("roll", "pitch", "yaw")

#: The order in which a leg's reasons are reported (the most basic first).
_PRIORITY = (1, 4, 2, 3)


def spatial_planes(robot: SpatialRobot) -> tuple[str, ...]:
    """The planes of :data:`SPATIAL_PLANES` whose three coordinates the robot moves freely.

    A robot of fewer than 6 DOF determines its parasitic components itself (§11): the
    3-RPS its ``x, y`` and yaw (its plane is ``"rp"``), the Delta its orientation (its
    planes are the position planes).  The first plane is the default.

    >>> from prp3.spatial.model import delta, three_rps
    >>> spatial_planes(three_rps()), spatial_planes(delta())
    (('rp',), ('xy', 'xz', 'yz'))
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    free = [name for name in SPATIAL_PLANES if not _parasitic(robot, SPATIAL_PLANES[name])]
    return tuple(free)


def _parasitic(robot: SpatialRobot, names: tuple[str, ...]) -> list[str]:
    return [name for name in names if _COMPONENT[name] in robot.parasitic]


@dataclass(frozen=True)
class SpatialWorkspace:
    """A slice of a spatial robot's pose space on a grid ``(nv, nu)`` (docs/spatial.md §17).

    Attributes
    ----------
    robot : SpatialRobot
    plane : str
        A key of :data:`SPATIAL_PLANES`; ``axes`` its two grid coordinates.
    offset : float
        The third coordinate of the plane (m).
    rpy : tuple of 3 floats
        The fixed orientation (rad; for ``"rp"`` its yaw only).
    u, v : (nu,), (nv,)
        The grid values of the two coordinates (m, or rad for ``"rp"``).
    position : (nv, nu, 3) m; rotation : (nv, nu, 3, 3)
        The pose at each grid point (parasitic components solved).
    reason, reason_leg : (nv, nu) int
        The code of :data:`WORKSPACE_REASONS` (0 reachable) and the first leg (1-based)
        that has it (0 when reachable).
    mu_leg : (nv, nu, legs); mu_par : (nv, nu)
        The signed measures of §6, §11 (``NaN`` where a leg has no closure).
    home_leg : (legs,); home_par : float
        The measures at the home pose (their signs are the working mode's sides).
    tau : (nv, nu, legs) or None
        With statics: the actuator efforts at rest (N or N·m), ``NaN`` where not regular.
    """

    robot: SpatialRobot
    plane: str
    offset: float
    rpy: tuple[float, float, float]
    u: FloatArray
    v: FloatArray
    position: FloatArray
    rotation: FloatArray
    reason: IntArray
    reason_leg: IntArray
    mu_leg: FloatArray
    mu_par: FloatArray
    home_leg: FloatArray
    home_par: float
    tau: FloatArray | None = None

    @property
    def axes(self) -> tuple[str, str]:
        """The names of the grid's two coordinates."""
        first, second, _ = SPATIAL_PLANES[self.plane]
        return first, second

    @property
    def reachable(self) -> BoolArray:
        """Every leg reaches the grid point within its limits, ``(nv, nu)``."""
        return np.asarray(self.reason == 0)

    @property
    def regular(self) -> BoolArray:
        """Reachable and every measure on its home side by at least ``SINGULAR``."""
        return regular_poses(self.reason, self.mu_leg, self.mu_par, self.home_leg, self.home_par)

    @property
    def peak(self) -> FloatArray | None:
        """The largest ``|tau|`` over the legs, ``(nv, nu)`` (``NaN`` where not regular)."""
        if self.tau is None:
            return None
        peak = np.full(self.mu_par.shape, np.nan)
        regular = self.regular
        peak[regular] = np.abs(self.tau[regular]).max(axis=-1)
        return peak

    @property
    def unit(self) -> str:
        """The unit of the actuator efforts: ``"N"`` (P actuators) or ``"N·m"`` (R)."""
        leg = self.robot.legs[0]
        return "N" if leg.joints[leg.actuated].kind == "P" else "N·m"


def _vector(name: str, value: ArrayLike, size: int, bound: float, unit: str) -> FloatArray:
    array = check_real(name, value, ParameterError).reshape(-1)
    if array.shape != (size,):
        raise ParameterError(f"{name} must be {size} numbers ({unit}), got {array.size}", key=name)
    bad = ~(np.abs(array) <= bound)
    if bad.any():
        k = int(np.argmax(bad))
        raise ParameterError(
            f"{name}[{k}] = {float(array[k])!r} {unit} must be finite and within +-{bound:.6g}",
            key=name,
        )
    return array


def _reach(robot: SpatialRobot) -> float:
    """A bound on how far from its base centre a leg's end can be (m)."""
    positions, _ = placements(robot)
    c_a, _ = attachments(robot)
    span = sum(float(np.linalg.norm(p, axis=-1).max()) for p in positions)
    for k, joint in enumerate(robot.legs[0].joints):
        if joint.kind == "P":
            span += max(abs(v) for leg in robot.legs for v in leg.joints[k].limits[0])
    return span + float(np.linalg.norm(c_a, axis=-1).max())


def _poses(
    robot: SpatialRobot, plane: str, offset: float, rpy: FloatArray, a: FloatArray, b: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The poses of grid values ``a, b (n,)``: positions ``(n, 3)``, rotations ``(n, 3, 3)``."""
    first, second, third = SPATIAL_PLANES[plane]
    n = a.shape[0]
    position = np.broadcast_to(np.array(robot.home_position), (n, 3)).copy()
    if plane == "rp":
        position[:, 2] = offset
        angles = np.stack([a, b, np.full(n, rpy[2])], axis=-1)
        return position, rpy_matrix(angles)
    position[:, _POSITION[first]] = a
    position[:, _POSITION[second]] = b
    position[:, _POSITION[third]] = offset
    return position, np.broadcast_to(rpy_matrix(rpy), (n, 3, 3)).copy()


def _complete(
    robot: SpatialRobot, position: FloatArray, rotation: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The parasitic pose components solved by Newton's method on the closure residuals
    (as :func:`~prp3.spatial.kinematics.complete_motion`, point by point robust: a point
    without a solution keeps its last iterate); returns the poses and ``|residual| (n, legs)``."""
    index = list(robot.parasitic_index)
    with np.errstate(all="ignore"):
        off = plane_offsets(robot, position, rotation)
    if not index:
        return position, rotation, np.abs(off)

    def moved(p: FloatArray, r: FloatArray, steps: FloatArray) -> tuple[FloatArray, FloatArray]:
        return parasitic_moved(index, p, r, steps)

    h = 1e-6
    n, k = position.shape[0], len(index)
    target = 1e-3 * PLANE_TOLERANCE * robot.scale
    units = np.array([1.0 if c < 3 else robot.scale for c in index])
    with np.errstate(all="ignore"):
        for _ in range(30):
            active = np.isfinite(off).all(axis=1) & (np.abs(off).max(axis=1) > target)
            if not active.any():
                break
            columns = []
            for j, c in enumerate(index):
                step = np.zeros((n, k))
                step[:, j] = h * (1.0 if c < 3 else robot.scale)
                plus = plane_offsets(robot, *moved(position, rotation, step))
                minus = plane_offsets(robot, *moved(position, rotation, -step))
                columns.append((plus - minus) / (2.0 * step[:, j, None]))
            matrix = np.stack(columns, axis=-1)
            good = active & np.isfinite(matrix).all(axis=(1, 2))
            good &= np.abs(np.linalg.det(np.where(good[:, None, None], matrix, np.eye(k)))) > 0.0
            safe = np.where(good[:, None, None], matrix, np.eye(k))
            newton = np.linalg.solve(safe, -np.where(good[:, None], off, 0.0)[..., None])[..., 0]
            newton = np.where(np.isfinite(newton), newton, 0.0)
            # damped: at most half the robot's scale (or half a radian) per step
            size = np.abs(newton / units).max(axis=1, keepdims=True)
            newton = newton * np.minimum(1.0, 0.5 / np.maximum(size, 1e-300))
            position, rotation = moved(position, rotation, newton)
            off = plane_offsets(robot, position, rotation)
    return position, rotation, np.abs(off)


def _leg_reasons(robot: SpatialRobot, q: FloatArray, residual: FloatArray) -> IntArray:
    """The code of :data:`WORKSPACE_REASONS` of each leg, ``(n, legs)`` (as
    :func:`~prp3.spatial.geometry.check_reach` and the closure check of ``leg_frames``)."""
    n, legs = q.shape[:2]
    codes = np.zeros((n, legs), dtype=np.int64)
    for i, leg in enumerate(robot.legs):
        column = 0
        stroke, joint_limit = np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
        for joint in leg.joints:
            if joint.kind == "S":
                part = q[:, i, column : column + 3]
                values = [np.sqrt(np.einsum("ni,ni->n", part, part))]
            else:
                values = [q[:, i, column + c] for c in range(joint.dof)]
            for value, (low, high) in zip(values, joint.limits, strict=True):
                bad = (value < low) | (value > high)
                if joint.kind == "P":
                    stroke |= bad
                else:
                    joint_limit |= bad
            column += joint.dof
        no_closure = ~np.isfinite(q[:, i]).all(axis=1)
        off = ~(residual[:, i] <= PLANE_TOLERANCE * robot.scale)
        codes[:, i] = np.select([no_closure, off, stroke, joint_limit], [1, 4, 2, 3], 0)
    return codes


def _point_reasons(codes: IntArray) -> tuple[IntArray, IntArray]:
    """Per point the most basic reason over the legs and the first leg (1-based) with it."""
    reason = np.zeros(codes.shape[0], dtype=np.int64)
    leg = np.zeros(codes.shape[0], dtype=np.int64)
    for code in reversed(_PRIORITY):
        hit = codes == code
        some = hit.any(axis=1)
        reason[some] = code
        leg[some] = np.argmax(hit[some], axis=1) + 1
    return reason, leg


def _default_window(
    robot: SpatialRobot, plane: str, offset: float, rpy: FloatArray
) -> tuple[float, float, float, float]:
    """The box of the reachable points of a coarse grid over the search window, with a margin."""
    if plane == "rp":
        search = (-math.pi / 2.0, math.pi / 2.0, -math.pi / 2.0, math.pi / 2.0)
    else:
        first, second, _ = SPATIAL_PLANES[plane]
        reach = _reach(robot)
        centre = robot.home_position
        a0, b0 = centre[_POSITION[first]], centre[_POSITION[second]]
        search = (a0 - reach, a0 + reach, b0 - reach, b0 + reach)
    ws = _evaluate(robot, plane, offset, rpy, search, COARSE_POINTS, statics=False)
    reachable = ws.reachable
    if not reachable.any():
        first, second, third = SPATIAL_PLANES[plane]
        raise ParameterError(
            f"no pose of the {robot.name} in the plane {plane} at {third} = {offset:.6g} "
            f"(rpy = {', '.join(f'{v:.6g}' for v in rpy)} rad) is reachable on a "
            f"{COARSE_POINTS} x {COARSE_POINTS} search grid over {first}, {second} in "
            f"[{search[0]:.6g}, {search[1]:.6g}] x [{search[2]:.6g}, {search[3]:.6g}]: give an "
            "offset nearer the home pose's, or the window (extent)",
            key="offset",
        )
    cols, rows = np.flatnonzero(reachable.any(axis=0)), np.flatnonzero(reachable.any(axis=1))
    du, dv = ws.u[1] - ws.u[0], ws.v[1] - ws.v[0]
    lo_u, hi_u = ws.u[cols[0]] - du, ws.u[cols[-1]] + du
    lo_v, hi_v = ws.v[rows[0]] - dv, ws.v[rows[-1]] + dv
    pad = EXTENT_MARGIN * max(hi_u - lo_u, hi_v - lo_v)
    return (
        float(max(lo_u - pad, search[0])),
        float(min(hi_u + pad, search[1])),
        float(max(lo_v - pad, search[2])),
        float(min(hi_v + pad, search[3])),
    )


@dataclass(frozen=True)
class PoseReasons:
    """Reachability, its reason and both measures at given poses (:func:`pose_reasons`).

    Attributes
    ----------
    position : (n, 3) m; rotation : (n, 3, 3)
        The poses, their parasitic components solved (§11).
    reason, reason_leg : (n,) int
        The code of :data:`WORKSPACE_REASONS` (0 reachable) and the first leg (1-based)
        with it (0 when reachable).
    mu_leg : (n, legs); mu_par : (n,)
        The signed measures of §6, §11 (``NaN`` where a leg has no closure).
    home_leg : (legs,); home_par : float
        The measures at the home pose.
    """

    position: FloatArray
    rotation: FloatArray
    reason: IntArray
    reason_leg: IntArray
    mu_leg: FloatArray
    mu_par: FloatArray
    home_leg: FloatArray
    home_par: float

    @property
    def regular(self) -> BoolArray:
        """Reachable and every measure on its home side by at least ``SINGULAR``, ``(n,)``."""
        return regular_poses(self.reason, self.mu_leg, self.mu_par, self.home_leg, self.home_par)


def regular_poses(
    reason: IntArray, mu_leg: FloatArray, mu_par: FloatArray, home_leg: FloatArray,
    home_par: float,
) -> BoolArray:  # fmt: skip
    """Where ``reason == 0`` and every measure is on its home side by at least ``SINGULAR``:
    what :func:`~prp3.spatial.kinematics.spatial_kinematics` accepts (shapes ``(...)``,
    ``mu_leg (..., legs)``)."""
    leg = (mu_leg * np.sign(home_leg) >= SINGULAR).all(axis=-1)
    return np.asarray((reason == 0) & leg & (mu_par * np.sign(home_par) >= SINGULAR))


def pose_reasons(robot: SpatialRobot, position: ArrayLike, rotation: ArrayLike) -> PoseReasons:
    """Whether the legs reach each pose, why not, and both measures (no refusal; §6, §17).

    ``position (n, 3)`` m, ``rotation (n, 3, 3)``; evaluated in chunks of ``CHUNK`` poses.
    For a robot of fewer than 6 DOF each pose is first completed (its parasitic
    components solved by Newton's method from it, as §17's grid poses are).

    >>> from prp3.spatial.model import hexapod
    >>> robot = hexapod()
    >>> poses = pose_reasons(robot, [[0.0, 0.0, 0.08], [0.0, 0.0, 0.3]], np.eye(3)[None].repeat(2, 0))
    >>> poses.reason.tolist(), poses.regular.tolist()
    ([0, 2], [True, False])
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    given_p = check_real("position", position, ParameterError).reshape(-1, 3)
    given_r = check_real("rotation", rotation, ParameterError).reshape(-1, 3, 3)
    m, legs = given_p.shape[0], len(robot.legs)
    out_p, out_r = np.empty((m, 3)), np.empty((m, 3, 3))
    reason, reason_leg = np.empty(m, dtype=np.int64), np.empty(m, dtype=np.int64)
    mu_leg, mu_par = np.empty((m, legs)), np.empty(m)
    for start in range(0, m, CHUNK):
        part = slice(start, min(start + CHUNK, m))
        p, r, residual = _complete(robot, given_p[part].copy(), given_r[part].copy())
        with np.errstate(all="ignore"):
            frames = leg_coordinates(robot, p, r)
        reason[part], reason_leg[part] = _point_reasons(_leg_reasons(robot, frames.q, residual))
        mu_leg[part], mu_par[part] = frame_measures(robot, frames, p)
        out_p[part], out_r[part] = p, r
    home = np.array([robot.home_position])
    with np.errstate(all="ignore"):
        home_frames = leg_coordinates(robot, home, np.array([robot.home_rotation]))
    home_leg, home_par = frame_measures(robot, home_frames, home)
    return PoseReasons(
        out_p, out_r, reason, reason_leg, mu_leg, mu_par, home_leg[0], float(home_par[0])
    )


def _evaluate(
    robot: SpatialRobot,
    plane: str,
    offset: float,
    rpy: FloatArray,
    window: tuple[float, float, float, float],
    points: int,
    statics: bool,
) -> SpatialWorkspace:
    u = np.linspace(window[0], window[1], points)
    v = np.linspace(window[2], window[3], points)
    a, b = (grid.reshape(-1) for grid in np.meshgrid(u, v))
    m = a.shape[0]
    position, rotation = np.empty((m, 3)), np.empty((m, 3, 3))
    for start in range(0, m, CHUNK):
        part = slice(start, min(start + CHUNK, m))
        position[part], rotation[part] = _poses(robot, plane, offset, rpy, a[part], b[part])
    poses = pose_reasons(robot, position, rotation)
    legs = len(robot.legs)
    shape = (v.size, u.size)
    ws = SpatialWorkspace(
        robot, plane, offset, (float(rpy[0]), float(rpy[1]), float(rpy[2])), u, v,
        poses.position.reshape(*shape, 3), poses.rotation.reshape(*shape, 3, 3),
        poses.reason.reshape(shape), poses.reason_leg.reshape(shape),
        poses.mu_leg.reshape(*shape, legs), poses.mu_par.reshape(shape),
        poses.home_leg, poses.home_par,
    )  # fmt: skip
    position, rotation = poses.position, poses.rotation
    if not statics:
        return ws
    regular = ws.regular.reshape(-1)
    tau = np.full((m, legs), np.nan)
    if regular.any():
        rest = PlatformMotion.at_rest(position[regular], rotation[regular])
        with np.errstate(all="ignore"):  # an overflow is refused by the caller's checks
            tau[regular] = virtual_work_efforts(robot, rest)
    return SpatialWorkspace(**{**ws.__dict__, "tau": tau.reshape(*shape, legs)})


def spatial_workspace(
    robot: SpatialRobot,
    plane: str | None = None,
    offset: float | None = None,
    rpy: ArrayLike | None = None,
    extent: ArrayLike | None = None,
    points: int = DEFAULT_POINTS,
    statics: bool = False,
) -> SpatialWorkspace:
    """Reachability, the reason it fails, both singularity measures and (``statics``) the
    actuator efforts at rest on a grid of poses in one plane (docs/spatial.md §17).

    Parameters
    ----------
    robot : SpatialRobot
    plane : str, optional
        ``"xy"``, ``"xz"``, ``"yz"`` (two position coordinates) or ``"rp"`` (roll and
        pitch), one of :func:`spatial_planes` of the robot (default: its first).
    offset : float, optional
        The third coordinate of the plane (m: ``z`` for ``"xy"`` and ``"rp"``, ``y`` for
        ``"xz"``, ``x`` for ``"yz"``); default: the home pose's.
    rpy : array_like (3,), optional
        The fixed orientation, roll–pitch–yaw (rad, §3); default 0.  For ``"rp"`` only its
        yaw is used (roll and pitch must be 0); a parasitic component must be 0.
    extent : array_like (4,), optional
        The window ``(umin, umax, vmin, vmax)`` of the two coordinates; default: the box of
        the reachable points of a ``COARSE_POINTS²`` search grid, with ``EXTENT_MARGIN``.
    points : int
        Grid points per axis, ``2 … MAX_POINTS``.
    statics : bool
        Also the actuator efforts holding the robot at rest at every regular point.

    Returns
    -------
    SpatialWorkspace
        Arrays ``(nv, nu, …)``: row ``j`` is ``v[j]``, column ``i`` is ``u[i]``.

    Raises
    ------
    ParameterError
        A bad argument (names it); a plane with a coordinate the robot determines itself;
        no reachable point in the default window.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    plane = _checked_plane(robot, plane)
    offset = _checked_offset(robot, plane, offset)
    angles = _checked_rpy(robot, plane, rpy)
    points = check_integer("points", points, 2, MAX_POINTS)
    if not isinstance(statics, bool):
        raise ParameterError(f"statics must be True or False, got {statics!r}"[:200], key="statics")
    window = _checked_window(robot, plane, offset, angles, extent, points)
    return _evaluate(robot, plane, offset, angles, window, points, statics)


def _checked_plane(robot: SpatialRobot, plane: str | None) -> str:
    """``plane`` of :func:`spatial_workspace` checked: one of the robot's planes."""
    planes = spatial_planes(robot)
    plane = planes[0] if plane is None else check_choice("plane", plane, tuple(SPATIAL_PLANES))
    if plane not in planes:
        raise ParameterError(
            f"plane {plane!r} moves {', '.join(_parasitic(robot, SPATIAL_PLANES[plane]))}, which "
            f"the {robot.name} determines itself ({', '.join(robot.parasitic)}, docs/spatial.md "
            f"§11): its planes are {', '.join(repr(p) for p in planes)}",
            key="plane",
        )
    return plane


def _checked_offset(robot: SpatialRobot, plane: str, offset: float | None) -> float:
    """``offset`` of :func:`spatial_workspace` checked (default: the home pose's)."""
    if offset is None:
        return float(robot.home_position[_POSITION[SPATIAL_PLANES[plane][2]]])
    span = POSITION_SPAN * robot.scale
    offset = check_scalar("offset", offset, unit="m")
    if abs(offset) > span:
        raise ParameterError(
            f"offset = {offset!r} m is beyond +-{span:.6g} m ({POSITION_SPAN:g} times the "
            f"robot's scale {robot.scale:g} m)",
            key="offset",
        )
    return offset


def _checked_rpy(robot: SpatialRobot, plane: str, rpy: ArrayLike | None) -> FloatArray:
    """``rpy`` of :func:`spatial_workspace` checked (default 0): no parasitic component."""
    angles = np.zeros(3) if rpy is None else _vector("rpy", rpy, 3, 2.0 * math.pi, "rad")
    fixed = ["roll", "pitch", "yaw"] if plane != "rp" else ["yaw"]
    if plane == "rp" and (angles[:2] != 0.0).any():
        raise ParameterError(
            f"rpy = {tuple(float(v) for v in angles)}: on the plane 'rp' the grid gives the roll "
            "and pitch; give only the yaw (roll = pitch = 0)",
            key="rpy",
        )
    determined = [name for name in _parasitic(robot, tuple(fixed)) if angles[_RPY.index(name)]]
    if determined:
        raise ParameterError(
            f"rpy = {tuple(float(v) for v in angles)} gives {', '.join(determined)}, which the "
            f"{robot.name} determines itself ({', '.join(robot.parasitic)}, docs/spatial.md §11): "
            "give 0",
            key="rpy",
        )
    return angles


def _checked_window(
    robot: SpatialRobot,
    plane: str,
    offset: float,
    angles: FloatArray,
    extent: ArrayLike | None,
    points: int,
) -> tuple[float, float, float, float]:
    """The window of :func:`spatial_workspace`: ``extent`` checked, or the default one."""
    first, second, _ = SPATIAL_PLANES[plane]
    if extent is None:
        window = _default_window(robot, plane, offset, angles)
    else:
        bound = math.pi if plane == "rp" else POSITION_SPAN * robot.scale
        unit = "rad" if plane == "rp" else "m"
        box = _vector("extent", extent, 4, bound, unit)
        if not (box[0] < box[1] and box[2] < box[3]):
            raise ParameterError(
                f"extent = {tuple(float(v) for v in box)} must be ({first}min, {first}max, "
                f"{second}min, {second}max) with min < max",
                key="extent",
            )
        window = (float(box[0]), float(box[1]), float(box[2]), float(box[3]))
    for name, (low, high) in ((first, window[:2]), (second, window[2:])):
        if not (np.diff(np.linspace(low, high, points)) > 0.0).all():
            raise ParameterError(
                f"extent {low!r} .. {high!r} of {name} is too narrow for points = {points}: "
                "neighbouring grid values are equal",
                key="extent",
            )
    return window


def _pose_columns(ws: SpatialWorkspace) -> dict[str, FloatArray]:
    rpy = matrix_rpy(ws.rotation.reshape(-1, 3, 3))
    table = {name: ws.position[..., k].reshape(-1) for k, name in enumerate("xyz")}
    table.update({name: rpy[:, k] + 0.0 for k, name in enumerate(_RPY)})  # no -0
    return table


def spatial_workspace_table(ws: SpatialWorkspace) -> dict[str, FloatArray]:
    """The columns of ``workspace.csv`` (docs/spatial.md §17), one row per grid point.

    ``x, y, z, roll, pitch, yaw`` (the pose), ``reachable``, ``regular`` (1/0), ``reason``
    (the code of :data:`WORKSPACE_REASONS`), ``reason_leg`` (0 or the leg), ``mu_leg_<leg>``
    and ``mu_par`` (the signed measures).
    """
    check_instance("ws", ws, SpatialWorkspace, "a SpatialWorkspace")
    table = _pose_columns(ws)
    table["reachable"] = ws.reachable.reshape(-1).astype(np.float64)
    table["regular"] = ws.regular.reshape(-1).astype(np.float64)
    table["reason"] = ws.reason.reshape(-1).astype(np.float64)
    table["reason_leg"] = ws.reason_leg.reshape(-1).astype(np.float64)
    for i in range(ws.mu_leg.shape[-1]):
        table[f"mu_leg_{i + 1}"] = ws.mu_leg[..., i].reshape(-1)
    table["mu_par"] = ws.mu_par.reshape(-1)
    return table


def spatial_statics_table(ws: SpatialWorkspace) -> dict[str, FloatArray]:
    """The columns of ``statics.csv``: the pose, ``regular``, ``tau_<leg>`` and ``tau_peak``
    (N or N·m, empty where not regular).

    Raises
    ------
    ParameterError
        ``ws`` was computed without statics.
    """
    check_instance("ws", ws, SpatialWorkspace, "a SpatialWorkspace")
    if ws.tau is None or (peak := ws.peak) is None:
        raise ParameterError("ws has no efforts: compute it with statics=True", key="ws")
    table = _pose_columns(ws)
    table["regular"] = ws.regular.reshape(-1).astype(np.float64)
    for i in range(ws.tau.shape[-1]):
        table[f"tau_{i + 1}"] = ws.tau[..., i].reshape(-1)
    table["tau_peak"] = peak.reshape(-1)
    return table
