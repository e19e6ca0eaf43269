"""Inverse geometry (eqs. 1, 7–10) against hand derivations and the independent reference.

Expected values come from docs/model.md worked by hand (derivations beside each
test) or from ``strategies.ref_geometry``, an independent solver.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from prp3 import Limits, Robot, SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.mechanics.geometry import (
    ALPHA,
    LEG_AXIS,
    LEG_NORMAL,
    base_vertices,
    inverse_geometry,
    platform_vertices,
)
from prp3.pose_validation import SINGULARITY_THRESHOLD
from prp3.validation import LEGS
from strategies import (
    REF_E,
    SQRT3,
    cross,
    poses,
    ref_base,
    ref_geometry,
    ref_joint,
    ref_platform_offset,
    ref_slide,
    turn,
)

l0_values = st.floats(0.1, 1.0, allow_nan=False)


def test_constants_follow_model() -> None:
    # docs/model.md: α = (π/3, π, −π/3), e = (cos α, sin α), n = (−sin α, cos α), legs A, B, C.
    assert LEGS == ("A", "B", "C")
    np.testing.assert_allclose(ALPHA, [math.pi / 3, math.pi, -math.pi / 3], rtol=0, atol=0)
    half = SQRT3 / 2
    np.testing.assert_allclose(
        LEG_AXIS, [[0.5, half], [-1.0, 0.0], [0.5, -half]], rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(
        LEG_NORMAL, [[-half, 0.5], [0.0, -1.0], [half, 0.5]], rtol=0, atol=1e-15
    )


def test_base_vertices_are_model_values() -> None:
    # A0 = l0(0, −1), B0 = l0(√3/2, 1/2), C0 = l0(−√3/2, 1/2); the base edge i runs
    # from vertex i along e_i to the next vertex, length l = √3·l0.
    l0 = 0.4
    base = base_vertices(Robot(l0=l0))
    np.testing.assert_allclose(
        base, [[0.0, -0.4], [0.2 * SQRT3, 0.2], [-0.2 * SQRT3, 0.2]], atol=1e-16
    )
    following = np.roll(base, -1, axis=0)
    np.testing.assert_allclose(following - base, SQRT3 * l0 * REF_E, atol=1e-15)


@pytest.mark.parametrize("l0", [0.3, 0.7])
def test_central_configuration_by_hand(l0: float) -> None:
    # x = y = φ = 0 ⇒ λ10 = λ32 = 0 (docs/model.md).  P_i = B_i0 + (l0/√3)·e_i:
    #   P_A = l0(0, −1) + (l0/√3)(1/2, √3/2) = (l0/(2√3), −l0/2)
    #   P_B = l0(√3/2, 1/2) + (l0/√3)(−1, 0) = (l0/(2√3), l0/2)
    #   P_C = l0(−√3/2, 1/2) + (l0/√3)(1/2, −√3/2) = (−l0/√3, 0)
    # d_i = unit(α_i − π/3) = unit(0), unit(2π/3), unit(−2π/3); lever ρ = G − P = −P.
    geo = inverse_geometry(Robot(l0=l0), [0.0, 0.0, 0.0])
    assert geo.lambda10.shape == geo.lambda32.shape == (3,)
    np.testing.assert_allclose(geo.lambda10, 0.0, atol=1e-15)
    np.testing.assert_allclose(geo.lambda32, 0.0, atol=1e-15)
    joints = [[l0 / (2 * SQRT3), -l0 / 2], [l0 / (2 * SQRT3), l0 / 2], [-l0 / SQRT3, 0.0]]
    np.testing.assert_allclose(geo.joint, joints, atol=1e-15)
    half = SQRT3 / 2
    np.testing.assert_allclose(geo.slide, [[1.0, 0.0], [-0.5, half], [-0.5, -half]], atol=1e-15)
    np.testing.assert_allclose(
        geo.slide_normal, [[0.0, 1.0], [-half, -0.5], [half, -0.5]], atol=1e-15
    )
    np.testing.assert_allclose(geo.lever, -np.array(joints), atol=1e-15)
    assert float(geo.determinant) == pytest.approx(-half, abs=1e-15)  # sin(−π/3)
    np.testing.assert_array_equal(geo.phi21, 0.0)


@given(x=st.floats(-0.2, 0.2), y=st.floats(-0.2, 0.2), l0=l0_values)
def test_translation_at_zero_orientation_by_hand(x: float, y: float, l0: float) -> None:
    # At φ = 0 the closure is affine in G; for a change (x, y) of G solve
    # s·e_i + λ32·d_i = (x, y) by hand (e_A = (1/2, √3/2), d_A = (1, 0), ...):
    #   leg A: s = 2y/√3,      λ32 = x − y/√3
    #   leg B: s = −x − y/√3,  λ32 = 2y/√3
    #   leg C: s = x − y/√3,   λ32 = −x − y/√3
    geo = inverse_geometry(Robot(l0=l0), [x, y, 0.0])
    np.testing.assert_allclose(
        geo.lambda10, [2 * y / SQRT3, -x - y / SQRT3, x - y / SQRT3], rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(
        geo.lambda32, [x - y / SQRT3, 2 * y / SQRT3, -x - y / SQRT3], rtol=0, atol=1e-15
    )


@given(phi=st.floats(-1.75, 0.75), l0=l0_values)
def test_rotation_about_the_centre_by_hand(phi: float, l0: float) -> None:
    # G = O.  Crossing the closure of leg A with d_A = (cos φ, sin φ):
    #   s·(e × d) = −(A0 + Rot(π/3 + φ)c) × d,  e × d = sin(φ − π/3) =: sin u,
    #   A0 × d = l0·cos φ,  Rot(π/3+φ)c × Rot(φ)(1, 0) = −(Rot(π/3)c)_y = −l0/2,
    # so s = l0(1/2 − cos φ)/sin u, whose derivative simplifies to
    # l0/(4 cos²(u/2)), i.e. s = l0(tan(u/2)/2 + √3/2) (s(0) = l0/√3 fixes the constant).
    # Likewise λ32 = (l0/2)(tan(u/2) + 1/√3); by the 3-fold symmetry all legs agree:
    #   λ10 = λ32 = (l0/2)·(tan((φ − π/3)/2) + 1/√3).
    geo = inverse_geometry(Robot(l0=l0), [0.0, 0.0, phi])
    expected = 0.5 * l0 * (math.tan((phi - math.pi / 3) / 2) + 1 / SQRT3)
    np.testing.assert_allclose(geo.lambda10, expected, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(geo.lambda32, expected, rtol=1e-13, atol=1e-15)


@given(pose=poses(), l0=l0_values)
def test_sum_of_lambda32_depends_on_orientation_only(pose: np.ndarray, l0: float) -> None:
    # Cross the closure of leg i with e_i: λ32_i·sin(φ − π/3) = e_i × (G − B_i0 − Rot(α_i+φ)c).
    # Σ e_i = 0 removes G; e_i × B_i0 = −l0/2 for every leg; e_i × Rot(α_i+φ)c
    # = (Rot(φ)c)_y = (l0/2)(sin φ/√3 + cos φ).  Hence
    #   Σ λ32 = (3 l0/2)·(1 − cos φ − sin φ/√3) / sin(φ − π/3)   (docs/model.md: no other singularity).
    pose = pose * np.array([l0 / 0.3, l0 / 0.3, 1.0])
    phi = pose[2]
    geo = inverse_geometry(Robot(l0=l0), pose)
    expected = 1.5 * l0 * (1 - math.cos(phi) - math.sin(phi) / SQRT3) / math.sin(phi - math.pi / 3)
    assert float(geo.lambda32.sum()) == pytest.approx(expected, rel=1e-12, abs=1e-14 * l0)


@given(pose=poses(), l0=l0_values)
def test_closure_and_leg_geometry_rebuilt_from_outputs(pose: np.ndarray, l0: float) -> None:
    # Eq. (10) with P_i rebuilt from λ10 by the docs/model.md formula:
    #   G = B_i0 + (l0/√3 + λ10_i)·e_i + λ32_i·d_i + Rot(α_i + φ)·c   for every leg.
    pose = pose * np.array([l0 / 0.3, l0 / 0.3, 1.0])
    geo = inverse_geometry(Robot(l0=l0), pose)
    joint = ref_joint(l0, geo.lambda10)
    d = ref_slide(pose[2])
    rebuilt = joint + geo.lambda32[:, None] * d + ref_platform_offset(l0, pose[2])
    scale = l0 + np.abs(geo.lambda10).max() + np.abs(geo.lambda32).max()
    np.testing.assert_allclose(rebuilt, np.broadcast_to(pose[:2], (3, 2)), atol=1e-14 * scale)
    np.testing.assert_allclose(geo.joint, joint, atol=1e-14 * scale)
    np.testing.assert_allclose(geo.slide, d, atol=1e-15)
    np.testing.assert_allclose(geo.slide_normal, turn(d), atol=1e-15)
    np.testing.assert_allclose(geo.lever, pose[:2] - joint, atol=1e-14 * scale)
    # e_i × d_i = sin(φ − π/3) for every leg (docs/model.md); φ21 = φ (eq. 7).
    np.testing.assert_allclose(cross(REF_E, d), math.sin(pose[2] - math.pi / 3), atol=1e-15)
    assert float(geo.determinant) == pytest.approx(math.sin(pose[2] - math.pi / 3), abs=1e-15)
    np.testing.assert_array_equal(geo.phi21, pose[2])


@given(pose=poses(), l0=l0_values)
def test_matches_independent_reference_solver(pose: np.ndarray, l0: float) -> None:
    pose = pose * np.array([l0 / 0.3, l0 / 0.3, 1.0])
    geo = inverse_geometry(Robot(l0=l0), pose)
    ref = ref_geometry(l0, pose)
    np.testing.assert_allclose(geo.lambda10, ref.lambda10, rtol=1e-12, atol=1e-14 * l0)
    np.testing.assert_allclose(geo.lambda32, ref.lambda32, rtol=1e-12, atol=1e-14 * l0)


@given(pose=poses(), l0=l0_values)
def test_platform_vertices_lie_on_the_sliding_lines(pose: np.ndarray, l0: float) -> None:
    # The platform triangle has circumradius l0 about G; its edge i lies on the line
    # through P_i along d_i, at the inradius l0/2 from G.
    pose = pose * np.array([l0 / 0.3, l0 / 0.3, 1.0])
    vertices = platform_vertices(Robot(l0=l0), pose)
    np.testing.assert_allclose(np.linalg.norm(vertices - pose[:2], axis=-1), l0, rtol=1e-14)
    geo = inverse_geometry(Robot(l0=l0), pose)
    for leg in range(3):
        distance = cross(vertices - geo.joint[leg], geo.slide[leg])  # signed, to line i
        on_line = np.abs(distance) < 1e-13 * l0
        assert on_line.sum() == 2, (leg, distance)
        assert abs(float(cross(pose[:2] - geo.joint[leg], geo.slide[leg]))) == pytest.approx(
            l0 / 2, rel=1e-12
        )


def test_platform_vertices_at_central_configuration() -> None:
    # The platform is the base triangle turned by 180°: vertices at 90°, 210°, 330°.
    np.testing.assert_allclose(
        platform_vertices(Robot(), [0.0, 0.0, 0.0]),
        -ref_base(0.3)[[0, 1, 2]],
        atol=1e-15,
    )


# ------------------------------------------------------------------ singular poses
SINGULAR_ORIENTATIONS = [math.pi / 3, math.pi / 3 - math.pi, math.pi / 3 + math.pi]


@pytest.mark.parametrize("phi_singular", SINGULAR_ORIENTATIONS)
@pytest.mark.parametrize("offset", [0.0, 0.9e-4, -0.9e-4, 0.99e-4])
def test_poses_inside_the_threshold_are_refused(phi_singular: float, offset: float) -> None:
    # |sin(φ − π/3)| < 1e-4 is refused: here |sin(offset)| ≤ 0.99e-4.
    robot = Robot()
    phi = phi_singular + offset
    poses_batch = np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.2], [0.02, -0.01, phi]])
    with pytest.raises(SingularPoseError) as info:
        inverse_geometry(robot, poses_batch)
    message = str(info.value)
    assert "sample 2" in message
    assert "x=0.02" in message and "y=-0.01" in message and f"phi={phi!r}" in message
    assert "\n" not in message
    assert info.value.sample == 2 and info.value.pose == (0.02, -0.01, phi)
    with pytest.raises(SingularPoseError, match=r"^pose: singular pose") as single:
        inverse_geometry(robot, [0.0, 0.0, phi])
    assert single.value.sample is None  # one pose: no sample index


@pytest.mark.parametrize("phi_singular", SINGULAR_ORIENTATIONS)
@pytest.mark.parametrize("offset", [1.01e-4, -1.01e-4, 1e-3])
@pytest.mark.parametrize("centre", [(0.0, 0.0), (0.01, -0.02)])
def test_poses_just_outside_the_threshold_are_accepted(
    phi_singular: float, offset: float, centre: tuple[float, float]
) -> None:
    # |sin(offset)| > 1e-4: accepted, finite, and still closing eq. (10) up to the
    # conditioning of the 2×2 system, ε·l0/|sin(φ − π/3)|.  Off the centre the
    # joint displacements are huge (λ ~ |G|/|sin(φ − π/3)|, up to 200 m) but honest;
    # at G = O they stay small (λ = (l0/2)(tan((φ − π/3)/2) + 1/√3), see above).
    assert abs(math.sin(offset)) > SINGULARITY_THRESHOLD
    pose = np.array([*centre, phi_singular + offset])
    geo = inverse_geometry(Robot(), pose)
    assert np.isfinite(geo.lambda10).all() and np.isfinite(geo.lambda32).all()
    determinant = math.sin(pose[2] - math.pi / 3)  # ±sin(offset) on the two branches
    assert abs(determinant) == pytest.approx(abs(math.sin(offset)), rel=1e-9)
    assert float(geo.determinant) == pytest.approx(determinant, rel=1e-9)
    if centre != (0.0, 0.0):
        assert np.abs(geo.lambda32).max() > 1e-3 / abs(determinant)
    rebuilt = ref_joint(0.3, geo.lambda10) + geo.lambda32[:, None] * ref_slide(pose[2])
    rebuilt = rebuilt + ref_platform_offset(0.3, pose[2])
    conditioning = (0.3 + np.abs(geo.lambda32).max()) / abs(determinant)
    np.testing.assert_allclose(rebuilt, np.broadcast_to(centre, (3, 2)), atol=1e-15 * conditioning)


def test_threshold_value() -> None:
    assert SINGULARITY_THRESHOLD == 1e-4


# ------------------------------------------------------------------ strokes
def test_poses_outside_the_stroke_are_unreachable() -> None:
    robot = Robot(limits=Limits(stroke=(-0.01, 0.02)))
    # y = 0.005: λ10 = (2y/√3, −y/√3, −y/√3) = (0.00577, −0.00289, −0.00289): inside.
    inside = inverse_geometry(robot, [0.0, 0.005, 0.0])
    assert np.all(np.abs(inside.lambda10) < 0.01)
    # y = 0.02: λ10_A = 0.0231 > 0.02 (upper bound).
    with pytest.raises(UnreachablePoseError) as info:
        inverse_geometry(robot, [[0.0, 0.0, 0.0], [0.0, 0.02, 0.0]])
    message = str(info.value)
    assert "sample 1" in message and "lambda10_A" in message and "y=0.02" in message
    assert "[-0.01, 0.02]" in message
    # x = 0.015, φ = 0: λ10 = (0, −x, x) = (0, −0.015, 0.015): only leg B below −0.01,
    # named with its value as computed (−0.015 to round-off: repr shows every digit)
    with pytest.raises(
        UnreachablePoseError, match=r"lambda10_B = (-0\.015|-0\.01499999999999\d*) m"
    ) as info:
        inverse_geometry(robot, [0.015, 0.0, 0.0])
    assert info.value.leg == "B" and info.value.sample is None


def test_without_limits_far_poses_are_accepted() -> None:
    geo = inverse_geometry(Robot(), [5.0, -7.0, 0.4])
    assert np.isfinite(geo.lambda10).all()


# ------------------------------------------------------------------ shapes and values
@pytest.mark.parametrize(
    "bad_pose",
    [[0.0, 0.0], np.zeros((4, 2)), np.zeros((2, 2, 3)), 0.0, [[0.0, 0.0, 0.0, 0.0]]],
)
def test_wrong_pose_shapes_are_refused(bad_pose: object) -> None:
    with pytest.raises(TrajectoryError, match=r"shape \(3,\) or \(N, 3\)"):
        inverse_geometry(Robot(), bad_pose)  # type: ignore[arg-type]


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_poses_are_refused(bad: float) -> None:
    with pytest.raises(TrajectoryError, match="sample 1"):
        inverse_geometry(Robot(), [[0.0, 0.0, 0.0], [0.0, bad, 0.0]])


def test_non_numeric_poses_are_refused() -> None:
    with pytest.raises(TrajectoryError, match="array of real numbers"):
        inverse_geometry(Robot(), ["a", "b", "c"])


def test_output_rank_follows_input_rank() -> None:
    robot = Robot()
    batch = np.array([[0.01, 0.02, 0.1], [-0.02, 0.01, -0.3]])
    single = inverse_geometry(robot, batch[1])
    many = inverse_geometry(robot, batch)
    one = inverse_geometry(robot, batch[:1])
    assert single.lambda10.shape == (3,) and single.joint.shape == (3, 2)
    assert single.determinant.shape == ()
    assert one.lambda10.shape == (1, 3) and one.lever.shape == (1, 3, 2)
    assert many.lambda32.shape == (2, 3) and many.determinant.shape == (2,)
    for name in ("lambda10", "lambda32", "phi21", "joint", "slide", "slide_normal", "lever"):
        np.testing.assert_array_equal(getattr(single, name), getattr(many, name)[1], err_msg=name)
