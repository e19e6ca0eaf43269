"""Workspace, conditioning and singular loci (``prp3.analysis.workspace``).

Expected values come from the core's inverse geometry (with its stroke check),
from half-plane intersections computed here, and from hand derivations
written beside them.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from prp3 import (
    Limits,
    ParameterError,
    Robot,
    SingularPoseError,
    UnreachablePoseError,
    inverse_geometry,
)
from prp3.analysis.workspace import (
    SINGULAR_ORIENTATIONS,
    jacobian_condition,
    orientation_range,
    orientation_scan,
    reachable,
    reachable_region,
    workspace_slice,
)
from prp3.mechanics.kinematics import jacobian

STROKE = (-0.04, 0.06)
LIMITED = Robot(limits=Limits(stroke=STROKE))
FREE = Robot()
L0 = FREE.l0


def assembles_within_stroke(pose: np.ndarray) -> bool:
    """The core's verdict: inverse geometry with the stroke check accepts the pose."""
    try:
        inverse_geometry(LIMITED, pose)
    except UnreachablePoseError:
        return False
    return True


@pytest.mark.parametrize("phi", [0.0, 0.25, -0.3, 0.5])
def test_reported_reachable_points_assemble_and_others_do_not(phi: float) -> None:
    grid = np.linspace(-0.12, 0.12, 31)
    ws = workspace_slice(LIMITED, phi, grid, grid)
    assert ws.reachable.any() and not ws.reachable.all()
    for j, y in enumerate(grid):
        for i, x in enumerate(grid):
            assert bool(ws.reachable[j, i]) == assembles_within_stroke(np.array([x, y, phi]))


@settings(max_examples=200, deadline=None)
@given(
    pose=st.tuples(st.floats(-0.15, 0.15), st.floats(-0.15, 0.15), st.floats(-1.0, 0.9)).filter(
        lambda p: abs(math.sin(p[2] - math.pi / 3.0)) > 1e-3
    )
)
def test_reachable_agrees_with_the_core_stroke_check(pose: tuple[float, float, float]) -> None:
    assert bool(reachable(LIMITED, pose)) == assembles_within_stroke(np.array(pose))


def _region_by_half_planes(phi: float) -> np.ndarray:
    """The reachable polygon at φ as the intersection of 6 half-planes, vertices (k, 2).

    λ10(G) = λ0 + K·G is affine at fixed φ (the core's inverse geometry at
    G = 0, e_x, e_y gives λ0 and K).  lower ≤ λ10_i ≤ upper are 6 half-planes;
    the vertices are the pairwise intersections of their boundary lines that
    satisfy all 6.
    """
    lam0 = inverse_geometry(FREE, [0.0, 0.0, phi]).lambda10
    K = np.column_stack(
        [
            inverse_geometry(FREE, [1.0, 0.0, phi]).lambda10 - lam0,
            inverse_geometry(FREE, [0.0, 1.0, phi]).lambda10 - lam0,
        ]
    )
    lines = [(K[i], bound - lam0[i]) for i in range(3) for bound in STROKE]  # K_i·G = c
    points = []
    for (a, c), (b, d) in itertools.combinations(lines, 2):
        matrix = np.array([a, b])
        if abs(np.linalg.det(matrix)) < 1e-12:
            continue
        G = np.linalg.solve(matrix, [c, d])
        lam = lam0 + K @ G
        if (lam >= STROKE[0] - 1e-12).all() and (lam <= STROKE[1] + 1e-12).all():
            points.append(G)
    return np.array(points)


@pytest.mark.parametrize("phi", [0.0, 0.2, -0.35, 0.45, 0.68, -0.34])
def test_exact_region_is_the_half_plane_intersection(phi: float) -> None:
    region = reachable_region(LIMITED, phi)
    expected = _region_by_half_planes(phi)
    hull = ConvexHull(expected)
    assert len(region) == len(hull.vertices)
    assert workspace_slice(LIMITED, phi, [0.0, 1.0], [0.0, 1.0]).area == pytest.approx(
        hull.volume, rel=1e-12
    )
    for vertex in region:
        assert np.min(np.linalg.norm(expected - vertex, axis=1)) < 1e-12
    # counter-clockwise: positive shoelace sum
    x, y = region[:, 0], region[:, 1]
    assert np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) > 0


def test_symmetric_stroke_gives_a_regular_hexagon_at_phi_zero() -> None:
    # Σλ10 = 0 cuts the cube [−a, a]³ in a regular hexagon of circumradius a√2;
    # eq. (iii) scales it by √(2/3)·|sin(−π/3)| = 1/√2: circumradius a, area (3√3/2)·a².
    a = 0.05
    region = reachable_region(Robot(limits=Limits(stroke=(-a, a))), 0.0)
    assert len(region) == 6
    np.testing.assert_allclose(np.hypot(region[:, 0], region[:, 1]), a, rtol=1e-12)
    ws = workspace_slice(Robot(limits=Limits(stroke=(-a, a))), 0.0, [0.0, 1.0], [0.0, 1.0])
    assert ws.area == pytest.approx(1.5 * math.sqrt(3.0) * a * a, rel=1e-12)


def test_region_is_a_triangle_near_the_ends_of_the_orientation_range() -> None:
    low, high = orientation_range(LIMITED)
    # near Σλ10 = 3·lower the plane cuts off one corner of the cube: a triangle
    assert len(reachable_region(LIMITED, low + 0.01)) == 3
    assert len(reachable_region(LIMITED, high - 0.01)) == 3
    assert len(reachable_region(LIMITED, low - 0.01)) == 0


def test_grid_area_converges_to_the_exact_area() -> None:
    grid = np.linspace(-0.12, 0.12, 241)
    ws = workspace_slice(LIMITED, 0.1, grid, grid)
    cell = (grid[1] - grid[0]) ** 2
    perimeter = np.linalg.norm(np.diff(np.vstack([ws.region, ws.region[:1]]), axis=0), axis=1).sum()
    # counting cells misses at most a strip of one cell width along the boundary
    assert abs(ws.grid_area - ws.area) <= perimeter * (grid[1] - grid[0]) + 4 * cell
    assert abs(ws.grid_area - ws.area) <= 0.05 * ws.area


def test_orientation_range_from_the_sum_of_strokes() -> None:
    low, high = orientation_range(LIMITED)
    # the core's Σλ10 at G = 0 equals 3·lower and 3·upper at the ends of the range
    assert inverse_geometry(FREE, [0.0, 0.0, low]).lambda10.sum() == pytest.approx(
        3 * STROKE[0], abs=1e-13
    )
    assert inverse_geometry(FREE, [0.0, 0.0, high]).lambda10.sum() == pytest.approx(
        3 * STROKE[1], abs=1e-13
    )
    grid = np.linspace(-0.15, 0.15, 31)
    scan = orientation_scan(LIMITED, grid, grid, np.linspace(low - 0.2, high + 0.2, 41))
    inside = (scan.phi >= low) & (scan.phi <= high)
    assert not scan.reachable[~inside].any()
    assert scan.reachable[inside].any(axis=(1, 2)).all()
    np.testing.assert_array_equal(scan.area[~inside], 0.0)
    # the centre G = 0 reaches every orientation of the range (λ10 all equal to Σ/3)
    centre = scan.reachable[:, 15, 15]
    np.testing.assert_array_equal(centre, inside)
    assert scan.phi_min[15, 15] == scan.phi[inside].min()
    assert scan.phi_max[15, 15] == scan.phi[inside].max()


def test_orientation_scan_per_point_summaries() -> None:
    grid = np.linspace(-0.3, 0.3, 7)
    scan = orientation_scan(LIMITED, grid, grid, np.linspace(-0.4, 0.5, 10))
    far = scan.count[0, 0]
    assert far == 0 and math.isnan(scan.phi_min[0, 0]) and math.isnan(scan.phi_max[0, 0])
    np.testing.assert_array_equal(scan.count, scan.reachable.sum(axis=0))
    assert (scan.condition_min[scan.reachable.any(axis=(1, 2))] >= 1.0).all()


def test_condition_number_at_the_central_configuration_is_sqrt6() -> None:
    # J·diag(1, 1, 1/l0) has rows (1/D)·[−d⊥_i, ρ_i·d_i/l0]; at the centre λ32 = 0 and
    # ρ_i·d_i = c·(Rot(−π/3)... ) = −l0/(2√3) for every leg.  Σ d⊥_i = 0 makes the last
    # column orthogonal to the first two, Σ d⊥_i d⊥_iᵀ = (3/2)·1: singular values
    # √(3/2)/|D| (twice) and √3·(1/(2√3))/|D| = (1/2)/|D|, so κ = √(3/2)/(1/2) = √6.
    assert float(jacobian_condition(FREE, [0.0, 0.0, 0.0])) == pytest.approx(
        math.sqrt(6.0), rel=1e-13
    )


def test_condition_number_at_the_centre_for_every_orientation() -> None:
    # At G = 0 the legs are alike: λ32_i equal, so c_i = ρ_i·d_i/l0 = c with
    # Σρ_i·d_i = (3·l0/2)·tan(ψ/2) ⇒ c = τ/2, τ = tan(ψ/2).  The Gram matrix of
    # J·diag(1, 1, 1/l0) is then diag(3/2, 3/2, 3c²)/D² (Σ d⊥_i = 0), so
    # κ² = max(a/b, b/a) with a/b = 1/(2c²):  κ = max(√2/|τ|, |τ|/√2).
    phi = np.linspace(-3.0, 3.0, 601)
    phi = phi[np.abs(np.sin(phi - math.pi / 3.0)) > 1e-3]
    tau = np.abs(np.tan((phi - math.pi / 3.0) / 2.0))
    expected = np.maximum(math.sqrt(2.0) / tau, tau / math.sqrt(2.0))
    got = jacobian_condition(FREE, np.column_stack([0 * phi, 0 * phi, phi]))
    np.testing.assert_allclose(got, expected, rtol=1e-9)
    isotropic = math.pi / 3.0 - 2.0 * math.atan(math.sqrt(2.0))  # τ = −√2
    assert float(jacobian_condition(FREE, [0.0, 0.0, isotropic])) == pytest.approx(1.0, abs=1e-7)


@settings(max_examples=50, deadline=None)
@given(
    pose=st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2), st.floats(-math.pi, math.pi)).filter(
        lambda p: abs(math.sin(p[2] - math.pi / 3.0)) > 0.05
    )
)
def test_condition_number_matches_finite_differences(pose: tuple[float, float, float]) -> None:
    # central differences of the core's λ10 give J; scale the φ column by 1/l0
    h = 1e-6
    columns = []
    for k in range(3):
        step = np.zeros(3)
        step[k] = h
        plus = inverse_geometry(FREE, np.array(pose) + step).lambda10
        minus = inverse_geometry(FREE, np.array(pose) - step).lambda10
        columns.append((plus - minus) / (2 * h))
    J = np.column_stack(columns) * np.array([1.0, 1.0, 1.0 / L0])
    expected = np.linalg.cond(J)
    assert float(jacobian_condition(FREE, pose)) == pytest.approx(expected, rel=1e-5)


def test_jacobian_determinant_never_vanishes() -> None:
    # det J = (3√3·l0/4)·tan(ψ/2)/sin³ψ, ψ = φ − π/3 (conventions.md: the only singularity
    # is φ ≡ π/3 mod π).  tan(ψ/2) and sin ψ share their sign on (−π, π): det J > 0.
    rng = np.random.default_rng(3)
    pose = np.column_stack(
        [
            rng.uniform(-0.3, 0.3, 2000),
            rng.uniform(-0.3, 0.3, 2000),
            rng.uniform(-math.pi, math.pi, 2000),
        ]
    )
    pose = pose[np.abs(np.sin(pose[:, 2] - math.pi / 3.0)) > 1e-2]
    psi = pose[:, 2] - math.pi / 3.0
    det = np.linalg.det(jacobian(inverse_geometry(FREE, pose)))
    expected = 3.0 * math.sqrt(3.0) * L0 / 4.0 * np.tan(psi / 2.0) / np.sin(psi) ** 3
    np.testing.assert_allclose(det, expected, rtol=1e-9)
    assert (det > 0).all()


def test_singular_orientations_are_refused_and_never_reachable() -> None:
    for phi in SINGULAR_ORIENTATIONS:
        assert math.sin(phi - math.pi / 3.0) == pytest.approx(0.0, abs=1e-15)
        with pytest.raises(SingularPoseError, match="every"):
            workspace_slice(FREE, phi, [0.0, 0.1], [0.0, 0.1])
        assert not reachable(FREE, [[0.0, 0.0, phi], [0.1, -0.2, phi]]).any()
        assert np.isinf(jacobian_condition(FREE, [0.05, 0.0, phi]))
    scan = orientation_scan(FREE, [0.0, 0.1], [0.0, 0.1], [0.0, math.pi / 3.0, 1.5])
    np.testing.assert_array_equal(scan.reachable.all(axis=(1, 2)), [True, False, True])


def test_without_stroke_every_regular_pose_is_reachable() -> None:
    grid = np.linspace(-1.0, 1.0, 5)
    ws = workspace_slice(FREE, 0.3, grid, grid)
    assert ws.reachable.all() and ws.region is None and math.isinf(ws.area)
    assert orientation_range(FREE) == pytest.approx((-2 * math.pi / 3, 4 * math.pi / 3))
    with pytest.raises(ParameterError, match="no \\[limits\\] stroke"):
        reachable_region(FREE, 0.0)


def test_bad_grids_are_refused() -> None:
    with pytest.raises(ParameterError, match="strictly increasing"):
        workspace_slice(LIMITED, 0.0, [0.0, 0.0], [0.0, 1.0])
    with pytest.raises(ParameterError, match="phi must be a finite number"):
        workspace_slice(LIMITED, math.nan, [0.0, 1.0], [0.0, 1.0])
