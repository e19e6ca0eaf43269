"""Reachability, conditioning and singularities of the 3-PRP robot, in closed form.

A pose is *reachable* when it is not singular (``|sin(φ − π/3)| >=
SINGULARITY_THRESHOLD``) and, with ``[limits] stroke = [lower, upper]``, its
three actuator displacements ``λ10`` (eq. 10) lie within the stroke.

Structure of the workspace (derived in :mod:`prp3.mechanics.geometry`):

* The orientation depends on ``Σλ10`` alone: ``Σλ10 = (3·l0/2)·(tan((φ −
  π/3)/2) + 1/√3)``.  The reachable orientations are therefore the interval
  of ``φ`` whose ``Σλ10`` lies in ``[3·lower, 3·upper]``
  (:func:`orientation_range`), whatever ``(x, y)``.
* At a fixed ``φ`` the displacements are affine in ``G`` and, by eq. (iii),
  ``G = −(2/3)·sin(φ − π/3)·Σ λ10_i·d⊥_i``: the reachable ``(x, y)`` form the
  image of the cross-section of the stroke cube ``[lower, upper]³`` by the
  plane ``Σλ10 = const`` — a convex polygon (triangle or hexagon, up to six
  vertices) scaled by ``√(2/3)·|sin(φ − π/3)|`` (:func:`reachable_region`).
* Singular loci: the Jacobian ``J = ∂λ10/∂(x, y, φ)`` has
  ``det J = (3√3·l0/4)·tan(ψ/2)/sin³ψ``, ``ψ = φ − π/3``: positive, never zero,
  infinite at ``ψ = 0`` and ``ψ = ±π``.  The only singular configurations are
  the orientations ``φ ≡ π/3 (mod π)`` (:data:`SINGULAR_ORIENTATIONS`), for
  every ``(x, y)``: the singular set of a slice at a regular ``φ`` is empty.

Conditioning: :func:`jacobian_condition` is the 2-norm condition number of
``J·diag(1, 1, 1/l0)`` — the Jacobian with respect to ``(x, y, l0·φ)``, all in
metres, so that the number does not depend on the units.  It is ``√6`` at the
central configuration; it grows with the distance of ``G`` from the centre and
without bound as ``φ`` approaches a singular orientation (the sliding
displacements ``λ32`` grow like ``1/sin(φ − π/3)``).

The maps of these over grids of poses are in :mod:`prp3.analysis.workspace`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError, SingularPoseError, TrajectoryError
from prp3.mechanics.geometry import InverseGeometry, forward_geometry, inverse_geometry
from prp3.model.parameters import Limits
from prp3.model.robot import Robot
from prp3.pose_validation import (
    MAX_ORIENTATION,
    POSE_BOUND,
    SINGULARITY_THRESHOLD,
    check_poses,
    singularity_measure,
)
from prp3.validation import check_real, check_robot, check_scalar

__all__ = [
    "SINGULAR_ORIENTATIONS",
    "jacobian_condition",
    "orientation_range",
    "reachable",
    "reachable_region",
]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: The singular orientations in ``(−π, π]``: ``φ ≡ π/3 (mod π)`` (rad).
SINGULAR_ORIENTATIONS: tuple[float, float] = (-2.0 * math.pi / 3.0, math.pi / 3.0)

_SQRT3 = math.sqrt(3.0)


def free(robot: Robot) -> Robot:
    check_robot(robot)
    return robot if robot.limits == Limits() else replace(robot, limits=Limits())


def _poses(robot: Robot, value: ArrayLike) -> FloatArray:
    """Poses ``(..., 3)`` validated as everywhere (:func:`prp3.pose_validation.check_poses`).

    Singular poses are accepted here (they are reported unreachable, κ = ∞).
    """
    check_robot(robot)
    pose = check_real("pose", value)
    if pose.ndim < 1 or pose.shape[-1] != 3 or pose.size == 0:
        raise TrajectoryError(f"pose must have shape (..., 3), got {pose.shape}")
    check_poses(pose.reshape(-1, 3) if pose.ndim > 1 else pose, robot, singular=False)
    return pose


def _displacements(robot: Robot, pose: FloatArray) -> tuple[FloatArray, BoolArray]:
    """``λ10`` (NaN at singular poses) and the regular mask, for poses ``(..., 3)``."""
    batch = pose.shape[:-1]
    flat = pose.reshape(-1, 3)
    regular = np.abs(singularity_measure(flat[:, 2])) >= SINGULARITY_THRESHOLD
    lam = np.full(flat.shape, np.nan)
    if regular.any():
        lam[regular] = inverse_geometry(free(robot), flat[regular]).lambda10
    return lam.reshape(*batch, 3), regular.reshape(batch)


def reachable(robot: Robot, pose: ArrayLike) -> BoolArray:
    """Whether poses ``(..., 3)`` are reachable: regular and within the strokes.

    Parameters
    ----------
    robot : Robot
        ``l0`` and ``limits.stroke`` are used (no stroke: every regular pose).
    pose : array_like, shape (..., 3)
        ``(x, y, φ)`` (m, m, rad).

    Returns
    -------
    ndarray of bool, shape (...)

    >>> robot = Robot(limits=Limits(stroke=(-0.05, 0.05)))
    >>> reachable(robot, [[0.0, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, math.pi / 3]]).tolist()
    [True, False, False]
    """
    pose = _poses(robot, pose)
    lam, regular = _displacements(robot, pose)
    stroke = checked_stroke(robot)
    if stroke is None:
        return regular
    with np.errstate(invalid="ignore"):
        inside = ((lam >= stroke[0]) & (lam <= stroke[1])).all(axis=-1)
    return np.asarray(regular & inside)


def jacobian_condition(robot: Robot, pose: ArrayLike) -> FloatArray:
    """Condition number of the Jacobian w.r.t. ``(x, y, l0·φ)``, shape ``(...)``.

    ``κ = σ_max/σ_min`` of ``J_n = J·diag(1, 1, 1/l0)`` (dimensionless, ``>= 1``),
    ``J = ∂λ10/∂(x, y, φ)`` from eq. (14).  Infinite at singular poses.

    Computed in closed form: the rows of ``J_n`` are ``[−d⊥_i, c_i]/D`` with
    ``c_i = ρ_i·d_i/l0``, and ``Σ d⊥_i d⊥_iᵀ = (3/2)·1``, so
    ``D²·J_nᵀJ_n = [[a·1, v], [vᵀ, b]]`` with ``a = 3/2``,
    ``v = −Σ c_i d⊥_i``, ``b = Σ c_i²``.  Its eigenvalues are ``a`` and
    ``μ± = (a + b)/2 ± √(((a − b)/2)² + |v|²)``, which bracket ``a``; so
    ``κ = √(μ+/μ−)``.  ``μ+`` is a sum of positive terms; ``μ−`` is not taken
    from ``a·b − |v|²``, which cancels near the singularity (28 % wrong at
    ``|sin(φ − π/3)| = 1e-4``), but from the product of the eigenvalues,
    ``a·μ+·μ− = det(D·J_n)²`` with the closed form
    ``det(D·J_n) = (3√3/4)·tan(ψ/2)``, ``ψ = φ − π/3`` (``det J`` in the notes of
    this module): ``κ = √a·μ+/|det(D·J_n)|``, accurate to round-off up to the
    singularity (the tests hold it to 50-digit singular values).

    >>> round(float(jacobian_condition(Robot(), [0.0, 0.0, 0.0])) ** 2, 12)   # √6
    6.0
    """
    pose = _poses(robot, pose)
    batch = pose.shape[:-1]
    flat = pose.reshape(-1, 3)
    regular = np.abs(singularity_measure(flat[:, 2])) >= SINGULARITY_THRESHOLD
    kappa = np.full(flat.shape[0], np.inf)
    if regular.any():
        kappa[regular] = condition_from_geometry(
            robot, inverse_geometry(free(robot), flat[regular])
        )
    return kappa.reshape(batch)


def condition_from_geometry(robot: Robot, geo: InverseGeometry) -> FloatArray:
    """κ of :func:`jacobian_condition` from an inverse geometry, shape ``geo.lambda10.shape[:-1]``."""
    c = (geo.lever * geo.slide).sum(axis=-1) / robot.l0  # ρ_i·d_i / l0
    v = -(c[..., None] * geo.slide_normal).sum(axis=-2)
    a, b, vv = 1.5, (c * c).sum(axis=-1), (v * v).sum(axis=-1)
    mu_plus = 0.5 * (a + b) + np.sqrt((0.5 * (a - b)) ** 2 + vv)
    psi = geo.pose[..., 2] - math.pi / 3.0
    det = (3.0 * _SQRT3 / 4.0) * np.tan(0.5 * psi)  # det(D·J_n), no cancellation
    return np.asarray(math.sqrt(a) * mu_plus / np.abs(det))


def orientation_range(robot: Robot) -> tuple[float, float]:
    """The interval of reachable orientations ``(φ_min, φ_max)`` (rad), all ``(x, y)`` together.

    ``φ`` is reachable somewhere iff ``Σλ10(φ) ∈ [3·lower, 3·upper]``, i.e.
    ``φ = π/3 + 2·atan(2·Σλ10/(3·l0) − 1/√3)`` for such a sum.  The interval
    is given on the continuous branch ``(−2π/3, 4π/3)`` (so ``φ_max`` may
    exceed ``π`` for very long strokes) and contains ``0``.  When it contains
    ``π/3`` (``upper > l0/(2√3)``) the singular orientation splits it in two
    (see :data:`SINGULAR_ORIENTATIONS`).  Without a stroke every orientation
    but the singular ones is reachable: ``(−2π/3, 4π/3)``.

    >>> [round(v, 6) for v in orientation_range(Robot(limits=Limits(stroke=(-0.05, 0.05))))]
    [-0.430175, 0.568518]
    """
    check_robot(robot)
    stroke = checked_stroke(robot)
    if stroke is None:
        return (-2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0)
    lower, upper = stroke
    l0 = robot.l0

    def phi_of(total: float) -> float:
        return math.pi / 3.0 + 2.0 * math.atan(2.0 * total / (3.0 * l0) - 1.0 / _SQRT3)

    return (phi_of(3.0 * lower), phi_of(3.0 * upper))


def reachable_region(robot: Robot, phi: float) -> FloatArray:
    """Vertices of the reachable region of ``(x, y)`` at orientation ``phi``, shape ``(k, 2)``.

    The exact boundary: the cross-section of the stroke cube by the plane
    ``Σλ10 = Σλ10(φ)`` mapped to ``G`` by the forward geometry (eq. iii), a
    convex polygon listed counter-clockwise (``k <= 6``; ``k = 0`` when ``φ``
    is not reachable).

    Raises
    ------
    ParameterError
        If the robot has no stroke (the region is then the whole plane).
    SingularPoseError
        If ``phi`` is singular.

    >>> region = reachable_region(Robot(limits=Limits(stroke=(-0.05, 0.05))), 0.0)
    >>> region.shape, round(float(np.hypot(*region.T).max()), 12)   # a regular hexagon
    ((6, 2), 0.05)
    """
    check_robot(robot)
    stroke = checked_stroke(robot)
    if stroke is None:
        raise ParameterError(
            "robot: no [limits] stroke: the reachable region is the whole plane at every "
            "regular orientation"
        )
    phi = checked_orientation(phi)
    lower, upper = stroke
    total = 1.5 * robot.l0 * (math.tan((phi - math.pi / 3.0) / 2.0) + 1.0 / _SQRT3)
    points = []
    corners = np.array(
        [[a, b, c] for a in (lower, upper) for b in (lower, upper) for c in (lower, upper)]
    )
    for i in range(8):
        for j in range(i + 1, 8):
            p, q = corners[i], corners[j]
            if np.count_nonzero(p != q) != 1:
                continue  # not an edge of the cube
            sp, sq = p.sum(), q.sum()
            if (sp - total) * (sq - total) > 0.0 or sp == sq:
                continue
            points.append(p + (total - sp) / (sq - sp) * (q - p))
    if len(points) < 3:
        return np.zeros((0, 2))
    lam = np.array(points)
    lam += (total - lam.sum(axis=1))[:, None] / 3.0  # exactly on the plane
    xy = forward_geometry(free(robot), lam).pose[:, :2]  # eq. (iii)
    centre = xy.mean(axis=0)
    order = np.argsort(np.arctan2(xy[:, 1] - centre[1], xy[:, 0] - centre[0]))
    xy = xy[order]
    keep = np.ones(len(xy), dtype=bool)  # drop repeated vertices (plane through a corner)
    keep[1:] = np.linalg.norm(np.diff(xy, axis=0), axis=1) > 1e-15
    return np.asarray(xy[keep])


def checked_stroke(robot: Robot) -> tuple[float, float] | None:
    """``robot.limits.stroke``, refused when an end lies beyond ``POSE_BOUND·l0``.

    prp3 computes poses and displacements up to ``POSE_BOUND·l0``
    (:func:`prp3.pose_validation.check_poses`); a longer stroke reaches nothing
    more there, and its cube's sums overflow float64 near ``1e308``.
    """
    stroke = robot.limits.stroke
    if stroke is None:
        return None
    reach = POSE_BOUND * robot.l0
    if max(abs(stroke[0]), abs(stroke[1])) > reach:
        raise ParameterError(
            f"limits.stroke [{stroke[0]!r}, {stroke[1]!r}] reaches beyond {POSE_BOUND:g}*l0 = "
            f"{reach:g} m (l0 = {robot.l0:g} m), farther than prp3 computes poses: give a stroke "
            "within that bound",
            key="limits.stroke",
        )
    return stroke


def checked_orientation(phi: float) -> float:
    phi = check_scalar("phi", phi, unit="rad")
    if abs(phi) > MAX_ORIENTATION:
        raise ParameterError(
            f"phi = {phi!r} rad: |phi| must be at most {MAX_ORIENTATION:g} rad "
            "(give the angle modulo 2*pi)"
        )
    if abs(math.sin(phi - math.pi / 3.0)) < SINGULARITY_THRESHOLD:
        raise SingularPoseError(
            f"phi = {phi!r} rad is singular (|sin(phi - pi/3)| < {SINGULARITY_THRESHOLD:g}): at "
            "phi = pi/3 mod pi the robot is singular at every (x, y), no pose is reachable"
        )
    return phi
