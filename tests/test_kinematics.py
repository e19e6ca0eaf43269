"""Inverse kinematics (eqs. 11–18) against finite differences, hand formulas and the reference.

Expected values: 6th-order central differences of the positions along analytic
motions (whose exact derivatives are known), closed forms derived by hand for
the paper's two motions, and ``strategies.ref_rates`` (an independent solver).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from prp3 import (
    LinkParameters,
    Motion,
    PistonParameters,
    Robot,
    SingularPoseError,
    inverse_geometry,
    inverse_kinematics,
)
from prp3.mechanics.kinematics import jacobian
from prp3.model.motion import law_motion, paper_motion
from strategies import (
    FD_FIRST,
    FD_OFFSETS,
    REF_E,
    SQRT3,
    AnalyticMotion,
    body_states,
    differentiate,
    poses,
    ref_platform_offset,
    ref_rates,
    ref_slide,
    scenarios,
    stencil_times,
    turn,
)


def _scale(*arrays: np.ndarray) -> float:
    return float(max(np.abs(a).max() for a in arrays))


@given(scenario=scenarios())
def test_joint_rates_against_finite_differences(scenario: tuple[Robot, AnalyticMotion]) -> None:
    # λ10, λ32 and the joint centres P_i from inverse_geometry at t + j·h (j = −3..3)
    # along a motion with exact derivatives; 6th-order differences with h = 4 ms have
    # truncation error O(h⁶) and round-off O(ε/h²): measured ≲ 1e-12 (first) and
    # ≲ 6e-11 (second derivative) of the scale over a few hundred random cases.
    robot, analytic = scenario
    T = analytic.duration
    t = np.linspace(0.1 * T, 0.9 * T, 5)
    h = 4e-3
    pose, _, _ = analytic.evaluate(stencil_times(t, h))
    geo = inverse_geometry(robot, pose)
    kin = inverse_kinematics(robot, analytic.motion(t))
    for name, rate, acceleration, value in [
        ("lambda10", kin.dlambda10, kin.ddlambda10, geo.lambda10),
        ("lambda32", kin.dlambda32, kin.ddlambda32, geo.lambda32),
        ("joint", kin.joint_velocity, kin.joint_acceleration, geo.joint),
    ]:
        first, second = differentiate(value, h, len(t))
        scale = _scale(value) + _scale(rate) + _scale(acceleration) + robot.l0
        np.testing.assert_allclose(rate, first, rtol=0, atol=1e-10 * scale, err_msg=name)
        np.testing.assert_allclose(acceleration, second, rtol=0, atol=1e-8 * scale, err_msg=name)


@given(scenario=scenarios())
def test_body_velocities_against_finite_differences(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    # Centres of mass of pistons and links (offsets ≠ 0): positions checked against
    # docs/model.md's formulas, velocities and accelerations against finite differences.
    robot, analytic = scenario
    T = analytic.duration
    t = np.linspace(0.1 * T, 0.9 * T, 4)
    h = 4e-3
    stencil = analytic.motion(stencil_times(t, h))
    moving = inverse_kinematics(robot, stencil)
    kin = inverse_kinematics(robot, analytic.motion(t))
    bodies = body_states(
        robot,
        kin.geometry.lambda10,
        kin.dlambda10,
        kin.ddlambda10,
        kin.motion.pose,
        kin.motion.velocity,
        kin.motion.acceleration,
    )
    scale = robot.l0 + _scale(kin.geometry.lambda10)
    np.testing.assert_allclose(kin.piston_com, bodies.piston, rtol=0, atol=1e-14 * scale)
    np.testing.assert_allclose(kin.link_com, bodies.link, rtol=0, atol=1e-14 * scale)
    for name, velocity, acceleration, position in [
        ("piston", kin.piston_velocity, kin.piston_acceleration, moving.piston_com),
        ("link", kin.link_velocity, kin.link_acceleration, moving.link_com),
    ]:
        first, second = differentiate(position, h, len(t))
        scale = _scale(position) + _scale(velocity) + _scale(acceleration)
        np.testing.assert_allclose(velocity, first, rtol=0, atol=1e-10 * scale, err_msg=name)
        np.testing.assert_allclose(acceleration, second, rtol=0, atol=1e-8 * scale, err_msg=name)
    # link 2 turns with the platform (eq. 12), the piston does not turn (ω10 = 0)
    np.testing.assert_array_equal(kin.dphi21, np.broadcast_to(kin.motion.velocity[:, 2:], (4, 3)))
    np.testing.assert_array_equal(
        kin.ddphi21, np.broadcast_to(kin.motion.acceleration[:, 2:], (4, 3))
    )


@given(scenario=scenarios())
def test_rates_match_the_independent_reference(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 9))
    kin = inverse_kinematics(robot, motion)
    ref = ref_rates(robot.l0, motion.pose, motion.velocity, motion.acceleration)
    for name in ("dlambda10", "dlambda32", "ddlambda10", "ddlambda32"):
        value, expected = getattr(kin, name), getattr(ref, name)
        scale = _scale(expected) + robot.l0
        np.testing.assert_allclose(value, expected, rtol=0, atol=1e-12 * scale, err_msg=name)


@given(scenario=scenarios())
def test_platform_motion_rebuilt_from_each_leg(scenario: tuple[Robot, AnalyticMotion]) -> None:
    # From the reported columns of any one leg (λ, λ̇, λ̈ of both joints) and φ, φ̇, φ̈:
    #   ρ = λ32·d + Rot(α+φ)c,
    #   Ġ = λ̇10·e + λ̇32·d + φ̇·Jρ,
    #   G̈ = λ̈10·e + λ̈32·d + 2λ̇32·φ̇·Jd + φ̈·Jρ − φ̇²·ρ   (closure differentiated twice).
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 7))
    kin = inverse_kinematics(robot, motion)
    phi = motion.pose[:, 2]
    phid, phidd = motion.velocity[:, 2:3, None], motion.acceleration[:, 2:3, None]
    d = ref_slide(phi)
    geo = kin.geometry
    rho = geo.lambda32[..., None] * d + ref_platform_offset(robot.l0, phi)
    velocity = kin.dlambda10[..., None] * REF_E + kin.dlambda32[..., None] * d + phid * turn(rho)
    acceleration = (
        kin.ddlambda10[..., None] * REF_E
        + kin.ddlambda32[..., None] * d
        + 2.0 * kin.dlambda32[..., None] * phid * turn(d)
        + phidd * turn(rho)
        - phid**2 * rho
    )
    scale_v = _scale(kin.dlambda10, kin.dlambda32) + robot.l0 * _scale(phid)
    scale_a = _scale(kin.ddlambda10, kin.ddlambda32) + robot.l0 * (
        _scale(phidd) + _scale(phid) ** 2
    )
    expected_v = np.broadcast_to(motion.velocity[:, None, :2], velocity.shape)
    expected_a = np.broadcast_to(motion.acceleration[:, None, :2], acceleration.shape)
    np.testing.assert_allclose(velocity, expected_v, rtol=0, atol=1e-13 * scale_v + 1e-300)
    scale_a += scale_v * _scale(phid)
    np.testing.assert_allclose(acceleration, expected_a, rtol=0, atol=1e-13 * scale_a + 1e-300)


@given(pose=poses(), l0=st.floats(0.1, 1.0))
def test_jacobian_against_finite_differences(pose: np.ndarray, l0: float) -> None:
    # ∂λ10/∂q_j by 6th-order central differences of inverse_geometry in each pose
    # coordinate (x, y in m, φ in rad), h = 1e-3.
    robot = Robot(l0=l0)
    pose = pose * np.array([l0 / 0.3, l0 / 0.3, 1.0])
    h = 4e-3
    expected = np.empty((3, 3))
    for j in range(3):
        shifted = pose + h * FD_OFFSETS[:, None] * np.eye(3)[j]
        expected[:, j] = FD_FIRST @ inverse_geometry(robot, shifted).lambda10 / h
    J = jacobian(inverse_geometry(robot, pose))
    assert J.shape == (3, 3)
    np.testing.assert_allclose(J, expected, rtol=0, atol=1e-9 * (np.abs(expected).max() + 1))
    velocity = np.array([0.3, -0.2, 0.7])
    still = Motion(t=np.array(0.0), pose=pose, velocity=velocity, acceleration=np.zeros(3))
    kin = inverse_kinematics(robot, still)
    np.testing.assert_allclose(kin.jacobian, J, rtol=1e-15, atol=0)
    np.testing.assert_allclose(kin.dlambda10, J @ velocity, rtol=1e-12, atol=1e-15)


def test_jacobian_at_the_central_configuration_by_hand() -> None:
    # At φ = 0 (test_geometry): λ10 = (2y/√3, −x − y/√3, x − y/√3) + O(φ) ⇒ the x, y
    # columns.  The φ column from the rotation about O: dλ10/dφ = l0/(2(1 + cos u)),
    # u = −π/3 ⇒ l0/3 for every leg.
    J = jacobian(inverse_geometry(Robot(l0=0.3), [0.0, 0.0, 0.0]))
    expected = [[0.0, 2 / SQRT3, 0.1], [-1.0, -1 / SQRT3, 0.1], [1.0, -1 / SQRT3, 0.1]]
    np.testing.assert_allclose(J, expected, rtol=0, atol=1e-15)


def test_vertical_paper_motion_by_hand() -> None:
    # x = φ = 0, y = y*(1 − cos(πt/3)), y* = 0.025: pure translation, so (test_geometry)
    #   λ10 = (2y, −y, −y)/√3 and λ32 = (−y, 2y, −y)/√3, and the same for the rates.
    motion = paper_motion("vertical", samples=301)
    kin = inverse_kinematics(Robot(), motion)
    w = math.pi / 3
    t = motion.t
    y = 0.025 * (1 - np.cos(w * t))
    yd = 0.025 * w * np.sin(w * t)
    ydd = 0.025 * w * w * np.cos(w * t)
    leg10 = np.array([2.0, -1.0, -1.0]) / SQRT3
    leg32 = np.array([-1.0, 2.0, -1.0]) / SQRT3
    for value, expected in [
        (kin.geometry.lambda10, y[:, None] * leg10),
        (kin.dlambda10, yd[:, None] * leg10),
        (kin.ddlambda10, ydd[:, None] * leg10),
        (kin.geometry.lambda32, y[:, None] * leg32),
        (kin.dlambda32, yd[:, None] * leg32),
        (kin.ddlambda32, ydd[:, None] * leg32),
    ]:
        np.testing.assert_allclose(value, expected, rtol=0, atol=1e-15)
    # end of the motion: y = 0.05 m ⇒ λ10_A = 0.1/√3 = 0.0577350... m
    assert float(kin.geometry.lambda10[-1, 0]) == pytest.approx(0.1 / SQRT3, abs=1e-15)


def test_rotation_paper_motion_by_hand() -> None:
    # G = O, φ = φ*(1 − cos(πt/3)), φ* = π/12.  With u = φ − π/3 (test_geometry):
    #   λ10 = λ32 = (l0/2)(tan(u/2) + 1/√3) for every leg,
    #   d/dt:  (l0/4)·sec²(u/2)·φ̇,
    #   d²/dt²: (l0/4)·sec²(u/2)·(φ̈ + tan(u/2)·φ̇²).
    l0 = 0.3
    motion = paper_motion("rotation", samples=301)
    kin = inverse_kinematics(Robot(l0=l0), motion)
    w, star = math.pi / 3, math.pi / 12
    t = motion.t
    phi = star * (1 - np.cos(w * t))
    phid = star * w * np.sin(w * t)
    phidd = star * w * w * np.cos(w * t)
    half = (phi - math.pi / 3) / 2
    sec2 = 1 / np.cos(half) ** 2
    value = 0.5 * l0 * (np.tan(half) + 1 / SQRT3)
    rate = 0.25 * l0 * sec2 * phid
    acceleration = 0.25 * l0 * sec2 * (phidd + np.tan(half) * phid**2)
    for computed, expected in [
        (kin.geometry.lambda10, value),
        (kin.geometry.lambda32, value),
        (kin.dlambda10, rate),
        (kin.dlambda32, rate),
        (kin.ddlambda10, acceleration),
        (kin.ddlambda32, acceleration),
    ]:
        expected_per_leg = np.broadcast_to(expected[:, None], (301, 3))
        np.testing.assert_allclose(computed, expected_per_leg, rtol=0, atol=1e-15)
    # the motion ends at φ = π/6: u/2 = −π/12, λ10 = 0.15·(tan(−π/12) + 1/√3) = 0.0464102 m
    assert float(kin.geometry.lambda10[-1, 1]) == pytest.approx(
        0.15 * (math.tan(-math.pi / 12) + 1 / SQRT3), abs=1e-15
    )


def test_output_rank_follows_input_rank() -> None:
    robot = Robot(piston=PistonParameters(com=(0.01, -0.02)), link=LinkParameters(com=(0.03, 0.01)))
    batch = law_motion([0.01, -0.02, 0.2], samples=4, duration=2.0)
    many = inverse_kinematics(robot, batch)
    single = inverse_kinematics(robot, batch[2])
    one = inverse_kinematics(robot, batch[2:3])
    assert single.dlambda10.shape == (3,) and single.link_velocity.shape == (3, 2)
    assert single.jacobian.shape == (3, 3)
    assert one.dlambda10.shape == (1, 3) and one.jacobian.shape == (1, 3, 3)
    assert many.ddlambda32.shape == (4, 3) and many.piston_acceleration.shape == (4, 3, 2)
    names = (
        "dlambda10 ddlambda10 dlambda32 ddlambda32 dphi21 ddphi21 joint_velocity "
        "joint_acceleration piston_com piston_velocity piston_acceleration link_com "
        "link_velocity link_acceleration jacobian"
    ).split()
    for name in names:
        np.testing.assert_array_equal(getattr(single, name), getattr(many, name)[2], err_msg=name)
        np.testing.assert_array_equal(getattr(one, name)[0], getattr(many, name)[2], err_msg=name)


def test_singular_motion_is_refused_with_the_sample() -> None:
    phi = np.array([0.0, 0.5, math.pi / 3, 0.5])
    pose = np.stack([np.zeros(4), np.zeros(4), phi], axis=-1)
    zeros = np.zeros((4, 3))
    motion = Motion(t=np.arange(4.0), pose=pose, velocity=zeros, acceleration=zeros)
    with pytest.raises(
        SingularPoseError, match=r"sample 2: singular pose \(x=0\.0, y=0\.0, phi=1\.047"
    ):
        inverse_kinematics(Robot(), motion)
