"""Workspace of a family robot: reachable slices and the loci of both singularity measures.

At one platform orientation ``φ`` and on a grid of ``G = (x, y)``, each leg's
closure solutions (:mod:`prp3.family.legs`, docs/family.md §5) are solved in
closed form and the one on the leg's *home branch* is kept: the solution whose
``μ_leg`` (§6) has the sign it has in the home configuration (the largest
``s_L·μ_leg`` of the solutions).  On it:

* ``reachable``: every leg has a closure solution at the point (any branch);
* ``mu_leg`` ``(ny, nx, 3)``: the signed leg measure of the home-branch
  solution of each leg (NaN where the leg cannot reach the point);
* ``mu_par`` ``(ny, nx)``: the signed parallel measure of the three
  home-branch solutions;
* ``regular``: reachable, and every measure has its home sign with
  ``|μ| ≥ 1e-4`` (§6's threshold): the poses at which the §5 working mode is
  regular.  The loci ``μ_leg,L = 0`` and ``μ_par = 0`` bound it.

``area`` and ``regular_area`` are the grid counts times the cell area (m²).
Without joint limits the workspace of an architecture with a base slide is
unbounded: the areas are then those inside the grid window.  A regular point
is one where the working mode is not singular; ``prp3 simulate`` follows the
straight path from home (§5), which may still cross a singularity on the way
to a regular point.

>>> from prp3.family.model import FamilyRobot
>>> ws = family_workspace_slice(FamilyRobot.default("3-RRR"), 0.0,
...                             np.linspace(-0.3, 0.3, 61), np.linspace(-0.3, 0.3, 61))
>>> bool(ws.regular[30, 30]), [round(float(v), 3) for v in ws.mu_leg[30, 30]]
(True, [0.444, 0.444, 0.444])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError, TrajectoryError
from prp3.family.chain import (
    SIGMA,
    SINGULAR,
    leg_chain,
    leg_jacobian,
    leg_measure,
    parallel_measure,
    rotate,
    transmitted_wrench,
)
from prp3.family.legs import LEG_GEOMETRY
from prp3.family.mechanics import Geometry, fast_dynamics, joint_rates
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.pose_validation import MAX_ORIENTATION
from prp3.validation import check_finite, check_instance, check_real, check_scalar

__all__ = [
    "FamilyOrientationScan",
    "FamilyStatics",
    "FamilyWorkspace",
    "family_measures_at",
    "family_orientation_scan",
    "family_workspace_slice",
    "family_workspace_statics",
    "home_branch",
]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Points solved together (bounds the memory of a slice).
_CHUNK: int = 65_536


def home_branch(
    robot: FamilyRobot, points: FloatArray, phi: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Each leg's home-branch closure solution at ``G`` ``(n, 2)``, ``φ`` ``(n,)`` (§5).

    The solution whose ``s_L·μ_leg`` is largest (R angles modulo 2π).

    Returns
    -------
    q : ndarray, shape (n, 3, 3)
        Joint values of legs A, B, C (NaN where the leg cannot reach).
    mu_leg : ndarray, shape (n, 3)
    wrenches : ndarray, shape (n, 3, 3)
        ``w_L`` of §6 of each leg (fixed frame).
    """
    n = points.shape[0]
    types, placements, scale = robot.types, robot.leg.placements, robot.leg.scale
    geometry = LEG_GEOMETRY[types](placements)
    signs = np.sign(np.asarray(robot.home_measures[0]))  # (3,)
    local = rotate(-SIGMA, points[:, None, :])  # (n, 3 legs, 2): each leg's own frame
    phis = np.broadcast_to(np.asarray(phi, dtype=np.float64)[:, None], (n, 3))
    best = np.full((n, 3), -np.inf)
    chosen = np.full((n, 3, 3), np.nan)
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        for candidate in geometry.candidates(local, phis):
            frames = leg_chain(types, placements, 0.0, candidate)
            value = signs * leg_measure(leg_jacobian(types, frames, local, scale))
            better = np.isfinite(value) & (value > best)
            best = np.where(better, value, best)
            chosen[better] = candidate[better]
        frames = leg_chain(types, placements, SIGMA, chosen)
        hat = leg_jacobian(types, frames, points[:, None, :], scale)
        mu_leg = leg_measure(hat)
        wrenches = transmitted_wrench(hat, robot.actuated)
    return chosen, np.asarray(mu_leg), np.asarray(wrenches)


def family_measures_at(
    robot: FamilyRobot, points: ArrayLike, phi: float
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """The home-branch measures at points ``G`` ``(n, 2)`` and orientation ``φ``.

    Returns
    -------
    mu_leg : ndarray, shape (n, 3)
        ``μ_leg`` of legs A, B, C on their home branch (NaN where out of reach).
    mu_par : ndarray, shape (n,)
        ``μ_par`` of the three home-branch solutions (NaN where a leg is out of reach).
    reachable : ndarray of bool, shape (n,)
        Every leg has a closure solution.
    """
    g = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    _, mu_leg, wrenches = home_branch(robot, g, np.full(g.shape[0], float(phi)))
    reachable = np.asarray(np.isfinite(mu_leg).all(axis=1))
    with np.errstate(invalid="ignore"):
        mu_par = np.where(reachable, parallel_measure(np.nan_to_num(wrenches)), np.nan)
    return mu_leg, np.asarray(mu_par, dtype=np.float64), reachable


def _regular(robot: FamilyRobot, mu_leg: FloatArray, mu_par: FloatArray) -> BoolArray:
    home_leg, home_par = robot.home_measures
    signs = np.sign(np.asarray(home_leg))
    with np.errstate(invalid="ignore"):
        legs = (signs * mu_leg >= SINGULAR).all(axis=-1)
        return np.asarray(legs & (math.copysign(1.0, home_par) * mu_par >= SINGULAR))


def _grid(name: str, values: ArrayLike) -> FloatArray:
    grid = check_real(name, values, ParameterError)
    if grid.ndim == 1:
        check_finite(name, grid[None, :], ParameterError, components=(name,) * grid.size)
    if grid.ndim != 1 or grid.size < 2 or not (np.diff(grid) > 0).all():
        raise ParameterError(
            f"{name} must be a strictly increasing 1-D grid of at least 2 values, got shape "
            f"{grid.shape}"
        )
    return grid


def _phi(value: object) -> float:
    phi = check_scalar("phi", value)
    if abs(phi) > MAX_ORIENTATION:
        raise ParameterError(f"phi must be within ±{MAX_ORIENTATION:g} rad, got {phi!r}")
    return phi


@dataclass(frozen=True)
class FamilyWorkspace:
    """A slice of a family robot's workspace at orientation ``phi`` (grid ``(ny, nx)``).

    Attributes
    ----------
    robot : FamilyRobot
    phi : float
        Platform orientation (rad).
    x, y : ndarray, shapes (nx,), (ny,)
        The grid (m).
    reachable, regular : ndarray of bool, shape (ny, nx)
    mu_leg : ndarray, shape (ny, nx, 3)
    mu_par : ndarray, shape (ny, nx)
    """

    robot: FamilyRobot
    phi: float
    x: FloatArray
    y: FloatArray
    reachable: BoolArray
    regular: BoolArray
    mu_leg: FloatArray
    mu_par: FloatArray

    @property
    def cell(self) -> float:
        """Area of one grid cell (m²)."""
        return float(np.diff(self.x).mean() * np.diff(self.y).mean())

    @property
    def area(self) -> float:
        """Reachable area counted on the grid (m²)."""
        return float(self.reachable.sum()) * self.cell

    @property
    def regular_area(self) -> float:
        """Regular area counted on the grid (m²)."""
        return float(self.regular.sum()) * self.cell


def family_workspace_slice(
    robot: FamilyRobot, phi: float, x: ArrayLike, y: ArrayLike
) -> FamilyWorkspace:
    """Reachable and regular grid points and both measures at orientation ``phi``.

    Parameters
    ----------
    robot : FamilyRobot
    phi : float
        Platform orientation (rad), ``|φ| ≤`` ``MAX_ORIENTATION``.
    x, y : array_like, shapes (nx,), (ny,)
        Strictly increasing grid values of ``G`` (m).

    Raises
    ------
    ParameterError
        A bad grid or orientation (names it).
    """
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    angle = _phi(phi)
    gx, gy = _grid("x", x), _grid("y", y)
    X, Y = np.meshgrid(gx, gy)
    points = np.stack([X.reshape(-1), Y.reshape(-1)], axis=-1)
    mu_leg = np.empty((points.shape[0], 3))
    mu_par = np.empty(points.shape[0])
    reach = np.empty(points.shape[0], dtype=bool)
    for start in range(0, points.shape[0], _CHUNK):
        part = slice(start, start + _CHUNK)
        mu_leg[part], mu_par[part], reach[part] = family_measures_at(robot, points[part], angle)
    shape = X.shape
    return FamilyWorkspace(
        robot=robot,
        phi=angle,
        x=gx,
        y=gy,
        reachable=reach.reshape(shape),
        regular=_regular(robot, mu_leg, mu_par).reshape(shape),
        mu_leg=mu_leg.reshape(*shape, 3),
        mu_par=mu_par.reshape(shape),
    )


@dataclass(frozen=True)
class FamilyStatics:
    """The actuator efforts holding a family robot at rest over a workspace slice (``(ny, nx)``).

    Attributes
    ----------
    workspace : FamilyWorkspace
        The slice (its ``regular`` points are those computed).
    tau : ndarray, shape (ny, nx, 3)
        ``tau_L`` of legs A, B, C (N for a P actuator, N·m for an R one) holding
        the pose at rest on the home branch: the weights of every body and the
        payload, and the constant ``[load]`` (docs/family.md §7 at zero rates);
        NaN where the pose is not regular.
    peak : ndarray, shape (ny, nx)
        ``max_L |tau_L|`` (NaN where not regular).
    """

    workspace: FamilyWorkspace
    tau: FloatArray
    peak: FloatArray


def family_workspace_statics(
    robot: FamilyRobot, phi: float, x: ArrayLike, y: ArrayLike
) -> FamilyStatics:
    """The actuator efforts that hold the platform still at the regular points of a slice.

    At each regular grid point the legs take their home-branch solution
    (:func:`home_branch`, as :func:`family_workspace_slice` judges them) and the
    inverse dynamics of docs/family.md §7 runs at zero velocity and
    acceleration (:func:`~prp3.family.mechanics.fast_dynamics`): the body
    wrenches are the weights and the load, and virtual work gives ``tau``.
    A point is judged on its own, not along a path from home.

    Parameters
    ----------
    robot : FamilyRobot
    phi : float
        Platform orientation (rad).
    x, y : array_like, shapes (nx,), (ny,)
        Strictly increasing grid values of ``G`` (m).

    Examples
    --------
    The 3-PRP in family form at home holds the same forces as the model form
    (docs/family.md §8; ``tests/test_family_workspace.py`` holds both against
    an independent Newton–Euler solve):

    >>> statics = family_workspace_statics(FamilyRobot.default("3-PRP"), 0.0, [0, 0.01], [0, 0.01])
    >>> [round(float(v), 4) for v in statics.tau[0, 0]]
    [31.8589, -8.4957, -23.3632]
    """
    ws = family_workspace_slice(robot, phi, x, y)
    X, Y = np.meshgrid(ws.x, ws.y)
    points = np.stack([X.reshape(-1), Y.reshape(-1)], axis=-1)[ws.regular.reshape(-1)]
    flat = np.full((X.size, 3), np.nan)
    rows = np.flatnonzero(ws.regular.reshape(-1))
    for start in range(0, points.shape[0], _CHUNK):
        part = points[start : start + _CHUNK]
        with np.errstate(all="ignore"):  # an overflow is refused, naming the loads
            flat[rows[start : start + _CHUNK]] = _rest_efforts(ws.robot, part, ws.phi)
    tau = flat.reshape(*X.shape, 3)
    with np.errstate(invalid="ignore"):
        peak = np.abs(tau).max(axis=-1)
    return FamilyStatics(workspace=ws, tau=tau, peak=peak)


def _overflow(robot: FamilyRobot, point: FloatArray) -> ParameterError:
    """The statics overflowed float64 at ``point``: name the loads that cause them."""
    load, payload = robot.load, robot.payload
    return ParameterError(
        f"the statics overflow float64 at G = ({point[0]:.6g}, {point[1]:.6g}) m: the actuator "
        f"efforts that hold [load] force = {list(load.force)} N, moment = {load.moment!r} N m, "
        f"[payload] mass = {payload.mass!r} kg and gravity = {list(robot.gravity)} m/s^2 "
        "are too large for double precision",
        subject="robot",
    )


def _rest_efforts(robot: FamilyRobot, points: FloatArray, phi: float) -> FloatArray:
    """``tau`` ``(n, 3)`` at rest at regular points ``G`` ``(n, 2)`` and orientation ``φ``."""
    n = points.shape[0]
    phis = np.full(n, phi)
    q, _, _ = home_branch(robot, points, phis)
    frames = leg_chain(robot.types, robot.leg.placements, SIGMA, q)
    pose = np.column_stack([points, phis])
    hat = leg_jacobian(robot.types, frames, pose[:, None, :2], robot.leg.scale)
    geometry = Geometry(
        q=q,
        frames=frames,
        mu_leg=leg_measure(hat),
        mu_par=parallel_measure(transmitted_wrench(hat, robot.actuated)),
    )
    rest = np.zeros_like(pose)
    motion = Motion(t=np.arange(n, dtype=np.float64), pose=pose, velocity=rest, acceleration=rest)
    try:
        return fast_dynamics(joint_rates(robot, motion, geometry)).tau.reshape(n, 3)
    except TrajectoryError as error:  # an effort or a joint force overflowed
        raise _overflow(robot, points[error.sample or 0]) from None


@dataclass(frozen=True)
class FamilyOrientationScan:
    """Areas of the slices over orientations ``phi`` ``(m,)`` on one grid.

    Attributes
    ----------
    phi : ndarray (m,)
    area, regular_area : ndarray (m,)
        Reachable and regular areas counted on the grid (m²).
    min_mu_par : ndarray (m,)
        ``min s_par·μ_par`` over the reachable points (NaN when none).
    """

    phi: FloatArray
    area: FloatArray
    regular_area: FloatArray
    min_mu_par: FloatArray


def family_orientation_scan(
    robot: FamilyRobot, x: ArrayLike, y: ArrayLike, phi: ArrayLike
) -> FamilyOrientationScan:
    """The slice areas at every orientation of ``phi`` (rad) on the grid ``x``, ``y``."""
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    angles = check_real("phi", phi, ParameterError)
    if angles.ndim != 1 or angles.size == 0:
        raise ParameterError(f"phi must be a 1-D array of orientations, got shape {angles.shape}")
    for value in angles.tolist():
        _phi(value)
    area, regular, margin = (np.empty(angles.size) for _ in range(3))
    sign = math.copysign(1.0, robot.home_measures[1])
    for k, value in enumerate(angles.tolist()):
        ws = family_workspace_slice(robot, value, x, y)
        area[k], regular[k] = ws.area, ws.regular_area
        values = sign * ws.mu_par[ws.reachable]
        margin[k] = float(values.min()) if values.size else math.nan
    return FamilyOrientationScan(phi=angles, area=area, regular_area=regular, min_mu_par=margin)
