"""The workspace of the 3-PRP robot over grids of poses: slices, orientation scans, statics.

Maps of the closed forms of :mod:`prp3.analysis.reachability` (reachability,
the reachable region, the Jacobian's condition number) over a grid of
``(x, y)`` at one orientation (:func:`workspace_slice`) and over a scan of
orientations (:func:`orientation_scan`).

Statics: :func:`workspace_statics` maps the actuator forces ``f10`` that hold
the platform still (with its payload, against gravity and the constant
``[load]``) over the grid of a slice: the kernel's inverse dynamics
(:func:`prp3.engines.entries.paper_forces`, eqs. 19–25) at zero velocity and
acceleration, compared with ``[limits] max_force``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.analysis.reachability import (
    checked_orientation,
    checked_stroke,
    condition_from_geometry,
    free,
    reachable_region,
)
from prp3.engines.entries import paper_forces
from prp3.errors import ParameterError, Prp3Error
from prp3.mechanics.geometry import inverse_geometry
from prp3.model.robot import Robot
from prp3.pose_validation import SINGULARITY_THRESHOLD
from prp3.validation import check_real, check_robot

__all__ = [
    "OrientationScan",
    "WorkspaceSlice",
    "WorkspaceStatics",
    "orientation_scan",
    "workspace_slice",
    "workspace_statics",
]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


def _polygon_area(xy: FloatArray) -> float:
    if len(xy) < 3:
        return 0.0
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _grid(name: str, values: ArrayLike) -> FloatArray:
    array = check_real(name, values, ParameterError)
    if array.ndim != 1 or array.size < 2 or not np.isfinite(array).all():
        raise ParameterError(
            f"{name} must be at least 2 finite grid values, got shape {array.shape}"
        )
    if (np.diff(array) <= 0).any():
        k = int(np.argmax(np.diff(array) <= 0)) + 1
        raise ParameterError(
            f"{name} grid values must be strictly increasing, got {name}[{k}] = "
            f"{float(array[k])!r} after {float(array[k - 1])!r}"
        )
    return array


@dataclass(frozen=True)
class WorkspaceSlice:
    """The workspace at one orientation on a grid of ``(x, y)``.

    Grid arrays have shape ``(ny, nx)``: row ``j`` is ``y[j]``, column ``i`` is ``x[i]``.

    Attributes
    ----------
    phi : float
        Orientation (rad), regular.
    x, y : ndarray (nx,), (ny,)
        Grid coordinates of ``G`` (m).
    lambda10 : ndarray (ny, nx, 3)
        Actuator displacements of every grid pose (m), eq. (10), computed
        whether within the stroke or not.
    reachable : ndarray of bool (ny, nx)
        Within the strokes (every point without a stroke).
    condition : ndarray (ny, nx)
        :func:`~prp3.analysis.reachability.jacobian_condition` of every grid pose.
    determinant : float
        ``sin(φ − π/3)``, the same at every ``(x, y)``.
    region : ndarray (k, 2) or None
        Exact boundary (:func:`~prp3.analysis.reachability.reachable_region`); ``None`` without a stroke.
    area : float
        Exact area of the region (m², shoelace formula); ``inf`` without a stroke.
    """

    phi: float
    x: FloatArray
    y: FloatArray
    lambda10: FloatArray
    reachable: BoolArray
    condition: FloatArray
    determinant: float
    region: FloatArray | None
    area: float

    @property
    def grid_area(self) -> float:
        """Area estimated from the grid: reachable points times the cell area (m²)."""
        cell = float(np.mean(np.diff(self.x)) * np.mean(np.diff(self.y)))
        return float(np.count_nonzero(self.reachable)) * cell


def workspace_slice(robot: Robot, phi: float, x: ArrayLike, y: ArrayLike) -> WorkspaceSlice:
    """Reachability and conditioning on a grid of ``(x, y)`` at orientation ``phi``.

    Parameters
    ----------
    robot : Robot
    phi : float
        Orientation (rad); refused when singular.
    x, y : array_like, shape (nx,), (ny,)
        Strictly increasing grid coordinates (m).

    Returns
    -------
    WorkspaceSlice

    Examples
    --------
    >>> from prp3.model.parameters import Limits
    >>> robot = Robot(limits=Limits(stroke=(-0.05, 0.05)))
    >>> grid = np.linspace(-0.1, 0.1, 41)
    >>> ws = workspace_slice(robot, 0.0, grid, grid)
    >>> ws.reachable.shape, bool(ws.reachable[20, 20]), round(ws.area, 6)
    ((41, 41), True, 0.006495)
    """
    check_robot(robot)
    phi = checked_orientation(phi)
    xs, ys = _grid("x", x), _grid("y", y)
    X, Y = np.meshgrid(xs, ys)
    pose = np.stack([X, Y, np.full_like(X, phi)], axis=-1)
    geo = inverse_geometry(free(robot), pose.reshape(-1, 3))  # φ is regular
    lam = geo.lambda10.reshape(*X.shape, 3)
    condition = condition_from_geometry(robot, geo).reshape(X.shape)
    stroke = checked_stroke(robot)
    inside: BoolArray
    if stroke is None:
        inside = np.ones(X.shape, dtype=bool)
        region, area = None, math.inf
    else:
        inside = np.asarray(((lam >= stroke[0]) & (lam <= stroke[1])).all(axis=-1))
        region = reachable_region(robot, phi)
        area = _polygon_area(region)
    return WorkspaceSlice(
        phi=phi,
        x=xs,
        y=ys,
        lambda10=lam,
        reachable=inside,
        condition=condition,
        determinant=math.sin(phi - math.pi / 3.0),
        region=region,
        area=area,
    )


@dataclass(frozen=True)
class WorkspaceStatics:
    """The actuator forces that hold the platform still, over a slice of the workspace.

    Grid arrays have shape ``(ny, nx)`` as in :class:`WorkspaceSlice`.

    Attributes
    ----------
    phi : float
        Orientation (rad), regular.
    x, y : ndarray (nx,), (ny,)
        Grid coordinates of ``G`` (m).
    reachable : ndarray of bool (ny, nx)
        Within the strokes (every point without a stroke).
    f10 : ndarray (ny, nx, 3)
        Force of actuator i on its piston along ``+e_i`` (N) holding the pose
        at rest (zero velocity and acceleration): the weights of every body,
        the payload and the constant ``[load]``, eq. (23); computed at every
        grid pose, whether within the stroke or not.
    peak : ndarray (ny, nx)
        ``max_i |f10_i|`` (N), the largest actuator force of the pose.
    max_force : float or None
        ``[limits] max_force`` of the robot (N), ``None`` without it.
    region : ndarray (k, 2) or None
        Exact boundary of the reachable region (:func:`~prp3.analysis.reachability.reachable_region`).
    """

    phi: float
    x: FloatArray
    y: FloatArray
    reachable: BoolArray
    f10: FloatArray
    peak: FloatArray
    max_force: float | None
    region: FloatArray | None

    @property
    def held(self) -> BoolArray:
        """Reachable poses held within ``max_force`` (every reachable pose without it), (ny, nx)."""
        if self.max_force is None:
            return self.reachable
        return np.asarray(self.reachable & (self.peak <= self.max_force))

    @property
    def unheld_fraction(self) -> float | None:
        """Share of the reachable grid points where ``peak > max_force``.

        ``None`` without ``max_force`` or without a reachable grid point.
        """
        count = int(np.count_nonzero(self.reachable))
        if self.max_force is None or count == 0:
            return None
        return float(count - np.count_nonzero(self.held)) / count


def _statics_overflow(robot: Robot, pose: FloatArray, error: Prp3Error) -> ParameterError:
    """The statics left float64 at a grid point: name the loads that cause them."""
    load, payload = robot.load, robot.payload
    k = error.sample if error.sample is not None and error.sample < pose.shape[0] else 0
    x, y, _ = pose[k].tolist()
    return ParameterError(
        f"the statics overflow float64 at G = ({x:.6g}, {y:.6g}) m (grid point {k}): the "
        f"actuator forces that hold [load] force = {list(load.force)!r} N, moment = "
        f"{load.moment!r} N·m, [payload] mass = {payload.mass!r} kg, com = "
        f"{list(payload.com)!r} m and gravity = {list(robot.gravity)!r} m/s² are too large "
        f"for double precision ({error.reason})",
        subject="robot",
    )


def workspace_statics(robot: Robot, phi: float, x: ArrayLike, y: ArrayLike) -> WorkspaceStatics:
    """The actuator forces holding the platform at rest over a grid of ``(x, y)`` at ``phi``.

    The kernel's inverse dynamics (:func:`prp3.engines.entries.paper_forces`,
    eqs. 10, 19–25) at zero velocity and acceleration: the forces that hold
    the weights of the bodies and of the ``[payload]`` and resist the
    constant ``[load]``.  The friction of the model vanishes at rest
    (``s(0) = 0``, no viscous force), so it neither helps nor hinders here.

    Parameters
    ----------
    robot : Robot
        Its ``[limits] max_force`` is the limit of :attr:`WorkspaceStatics.held`.
    phi : float
        Orientation (rad); refused when singular.
    x, y : array_like, shape (nx,), (ny,)
        Strictly increasing grid coordinates (m).

    Returns
    -------
    WorkspaceStatics

    Examples
    --------
    The paper's robot at the central pose holds its 3 kg platform with
    ``f10 = ((√3/2)·t_i − (m1 + m2)·g·e_i)``, ``t = (2/3)·m3·g·(1, −1/2, −1/2)``
    (``tests/test_statics.py`` derives it):

    >>> from prp3.model.parameters import Limits
    >>> robot = Robot(limits=Limits(stroke=(-0.05, 0.05), max_force=30.0))
    >>> grid = np.linspace(-0.1, 0.1, 41)
    >>> statics = workspace_statics(robot, 0.0, grid, grid)
    >>> statics.f10[20, 20].round(4).tolist()
    [31.8589, -8.4957, -23.3632]
    >>> round(statics.unheld_fraction, 3)      # of the reachable hexagon, above 30 N
    0.73
    """
    ws = workspace_slice(robot, phi, x, y)  # validates robot, φ and the grid
    X, Y = np.meshgrid(ws.x, ws.y)
    pose = np.stack([X, Y, np.full_like(X, ws.phi)], axis=-1).reshape(-1, 3)
    rest = np.zeros_like(pose)
    try:
        f10 = paper_forces(free(robot), pose, rest, rest).f10.reshape(*X.shape, 3)
    except Prp3Error as error:  # the poses are validated: only the results can fail
        raise _statics_overflow(robot, pose, error) from None
    return WorkspaceStatics(
        phi=ws.phi,
        x=ws.x,
        y=ws.y,
        reachable=ws.reachable,
        f10=f10,
        peak=np.abs(f10).max(axis=-1),
        max_force=robot.limits.max_force,
        region=ws.region,
    )


@dataclass(frozen=True)
class OrientationScan:
    """Reachable orientations over a grid of ``(x, y)``: a scan of ``φ``.

    Attributes
    ----------
    phi : ndarray (m,)
        Scanned orientations (rad); singular ones are never reachable.
    x, y : ndarray (nx,), (ny,)
        Grid coordinates (m).
    reachable : ndarray of bool (m, ny, nx)
        Reachability of every ``(x, y, φ)``.
    area : ndarray (m,)
        Exact reachable area at each ``φ`` (m²; ``inf`` without a stroke, 0 when
        singular or out of :func:`~prp3.analysis.reachability.orientation_range`).
    grid_area : ndarray (m,)
        The same, estimated from the grid (m²).
    condition_min, condition_max : ndarray (m,)
        Extremes of :func:`~prp3.analysis.reachability.jacobian_condition` over the reachable grid points
        (NaN where none is reachable).
    """

    phi: FloatArray
    x: FloatArray
    y: FloatArray
    reachable: BoolArray
    area: FloatArray
    grid_area: FloatArray
    condition_min: FloatArray
    condition_max: FloatArray

    @property
    def count(self) -> NDArray[np.int64]:
        """Number of scanned orientations reachable at each ``(x, y)``, shape (ny, nx)."""
        return np.asarray(self.reachable.sum(axis=0), dtype=np.int64)

    @property
    def phi_min(self) -> FloatArray:
        """Smallest reachable scanned ``φ`` at each ``(x, y)`` (NaN if none), shape (ny, nx)."""
        values = np.where(self.reachable, self.phi[:, None, None], np.inf).min(axis=0)
        return np.asarray(np.where(np.isfinite(values), values, np.nan))

    @property
    def phi_max(self) -> FloatArray:
        """Largest reachable scanned ``φ`` at each ``(x, y)`` (NaN if none), shape (ny, nx)."""
        values = np.where(self.reachable, self.phi[:, None, None], -np.inf).max(axis=0)
        return np.asarray(np.where(np.isfinite(values), values, np.nan))


def orientation_scan(
    robot: Robot,
    x: ArrayLike,
    y: ArrayLike,
    phi: ArrayLike,
    *,
    progress: Callable[[int, int], None] | None = None,
) -> OrientationScan:
    """Reachability of every ``(x, y, φ)`` of a grid, slice by slice.

    Parameters
    ----------
    robot : Robot
    x, y : array_like, shape (nx,), (ny,)
        Strictly increasing grid coordinates (m).
    phi : array_like, shape (m,)
        Orientations to scan (rad), strictly increasing; singular ones are
        kept and reported unreachable.
    progress : callable, optional
        ``progress(orientations_done, m)`` after every slice.

    Returns
    -------
    OrientationScan

    >>> from prp3.model.parameters import Limits
    >>> robot = Robot(limits=Limits(stroke=(-0.05, 0.05)))
    >>> grid = np.linspace(-0.1, 0.1, 21)
    >>> scan = orientation_scan(robot, grid, grid, np.linspace(-0.5, 0.5, 11))
    >>> scan.reachable.shape, scan.count[10, 10].tolist()    # all but φ = -0.5 at the centre
    ((11, 21, 21), 10)
    """
    check_robot(robot)
    xs, ys = _grid("x", x), _grid("y", y)
    phis = _grid("phi", phi)
    reach = np.zeros((phis.size, ys.size, xs.size), dtype=bool)
    area = np.zeros(phis.size)
    grid_area = np.zeros(phis.size)
    cmin = np.full(phis.size, np.nan)
    cmax = np.full(phis.size, np.nan)
    for k, angle in enumerate(phis.tolist()):
        if progress is not None:
            progress(k, phis.size)
        if abs(math.sin(angle - math.pi / 3.0)) < SINGULARITY_THRESHOLD:
            continue
        ws = workspace_slice(robot, angle, xs, ys)
        reach[k] = ws.reachable
        area[k] = ws.area
        grid_area[k] = ws.grid_area
        if ws.reachable.any():
            cmin[k] = ws.condition[ws.reachable].min()
            cmax[k] = ws.condition[ws.reachable].max()
    if progress is not None:
        progress(phis.size, phis.size)
    return OrientationScan(
        phi=phis,
        x=xs,
        y=ys,
        reachable=reach,
        area=area,
        grid_area=grid_area,
        condition_min=cmin,
        condition_max=cmax,
    )
