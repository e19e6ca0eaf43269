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

from prp3.errors import ParameterError
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
from prp3.family.model import FamilyRobot
from prp3.pose_validation import MAX_ORIENTATION
from prp3.validation import check_instance, check_real, check_scalar

__all__ = [
    "FamilyOrientationScan",
    "FamilyWorkspace",
    "family_measures_at",
    "family_orientation_scan",
    "family_workspace_slice",
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
    angles = check_real("phi", phi, ParameterError).reshape(-1)
    area, regular, margin = (np.empty(angles.size) for _ in range(3))
    sign = math.copysign(1.0, robot.home_measures[1])
    for k, value in enumerate(angles.tolist()):
        ws = family_workspace_slice(robot, value, x, y)
        area[k], regular[k] = ws.area, ws.regular_area
        values = sign * ws.mu_par[ws.reachable]
        margin[k] = float(values.min()) if values.size else math.nan
    return FamilyOrientationScan(phi=angles, area=area, regular_area=regular, min_mu_par=margin)
