"""The equations of motion as plain functions: ``jacobian``, ``mass_matrix``,
``bias_forces``, ``gravity_forces``; per-axis gains; ``identify`` then
``identified_robot`` with the defaults.

The references are computed here, outside the code under test: the joint
rates of the closure (``tests/strategies.py``: ``ref_rates``), the kinetic
energy of the 7 bodies rebuilt from their centre-of-mass velocities
(``body_states``), and the independent Newton–Euler solver of the 7 bodies
(``method="newton-euler"``), on random robots, poses and rates.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import prp3
from clitools import cli, one_line
from prp3 import Motion, Robot
from prp3.apps.control_law import Gains, control_force
from prp3.apps.identification import identified_robot, identify
from prp3.apps.regressor import standard_parameters
from prp3.engines.compiled_robot import compile_robot
from prp3.errors import ParameterError, SingularPoseError
from prp3.model.motion import law_motion
from prp3.model.parameters import Limits, Payload
from strategies import body_states, platform_inertia, poses, ref_geometry, ref_rates, robots

rates = st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3).map(np.array)


def newton_euler_f10(robot: Robot, pose, velocity, acceleration) -> np.ndarray:
    """``f10`` of one state by the independent Newton–Euler solver (N)."""
    still = Motion(t=0.0, pose=pose, velocity=velocity, acceleration=acceleration)
    return prp3.inverse_dynamics(robot, still, method="newton-euler")[1].f10


def kinetic_energy(robot: Robot, pose, velocity) -> float:
    """``T`` of the 7 bodies from their centre-of-mass velocities (J), rebuilt here."""
    l0, zero = robot.l0, np.zeros(3)
    geo, joint = ref_geometry(l0, pose), ref_rates(l0, pose, velocity, zero)
    bodies = body_states(robot, geo.lambda10, joint.dlambda10, zero, pose, velocity, zero)
    omega = float(velocity[2])  # link 2 turns with the platform, the pistons do not turn
    return float(
        0.5 * robot.piston.mass * (bodies.piston_velocity**2).sum()
        + 0.5 * robot.link.mass * (bodies.link_velocity**2).sum()
        + 1.5 * robot.link.inertia * omega**2
        + 0.5 * robot.platform.mass * (bodies.platform_velocity**2).sum()
        + 0.5 * platform_inertia(robot) * omega**2
    )


# ---------------------------------------------------------------- the Jacobian
@settings(max_examples=60, deadline=None)
@given(robot=robots(), data=st.data(), velocity=rates)
def test_jacobian_of_a_robot_and_a_pose_maps_the_platform_rates_to_the_actuator_rates(
    robot, data, velocity
):
    pose = data.draw(poses(robot.l0))
    J = prp3.jacobian(robot, pose)
    expected = ref_rates(robot.l0, pose, velocity, np.zeros(3)).dlambda10
    assert J.shape == (3, 3)
    np.testing.assert_allclose(J @ velocity, expected, rtol=1e-11, atol=1e-12 * robot.l0)
    # a batch: the rank follows the input, each row as alone; the old form agrees
    batch = np.stack([pose, pose * 0.5])
    Js = prp3.jacobian(robot, batch)
    assert Js.shape == (2, 3, 3)
    np.testing.assert_array_equal(Js[0], J)
    np.testing.assert_array_equal(prp3.jacobian(prp3.inverse_geometry(robot, batch)), Js)


def test_jacobian_is_validated_and_ignores_the_strokes_like_jacobian_condition():
    tight = Robot(limits=Limits(stroke=(-0.001, 0.001)))
    far = [0.05, 0.0, 0.2]  # outside the strokes: still a Jacobian (as its condition number)
    np.testing.assert_array_equal(prp3.jacobian(tight, far), prp3.jacobian(Robot(), far))
    assert math.isfinite(float(prp3.jacobian_condition(tight, far)))
    with pytest.raises(SingularPoseError, match="pose: singular pose"):
        prp3.jacobian(Robot(), [0.0, 0.0, math.pi / 3.0])
    with pytest.raises(ParameterError, match="pose is missing"):
        prp3.jacobian(Robot())
    with pytest.raises(ParameterError, match=r"robot must be a prp3\.Robot"):
        prp3.jacobian("robot", [0.0, 0.0, 0.0])  # type: ignore[arg-type]


# ---------------------------------------------------------------- M(q), b(q, q̇), g(q)
@settings(max_examples=40, deadline=None)
@given(robot=robots(), data=st.data(), velocity=rates, acceleration=rates,
       payload=st.floats(0.0, 2.0))  # fmt: skip
def test_mass_matrix_and_bias_rebuild_the_newton_euler_forces(
    robot, data, velocity, acceleration, payload
):
    robot = replace(robot, payload=Payload(mass=payload, com=(0.01, -0.02), inertia=0.1 * payload))
    pose = data.draw(poses(robot.l0))
    A = prp3.mass_matrix(robot, pose)
    b = prp3.bias_forces(robot, pose, velocity)
    expected = newton_euler_f10(robot, pose, velocity, acceleration)
    scale = np.abs(expected).max() + np.abs(A).max() * 2.0 + np.abs(b).max()
    np.testing.assert_allclose(A @ acceleration + b, expected, rtol=0, atol=1e-11 * scale)
    # at rest: the gravity forces alone (no load, no friction here)
    g = prp3.gravity_forces(robot, pose)
    at_rest = newton_euler_f10(robot, pose, np.zeros(3), np.zeros(3))
    np.testing.assert_allclose(g, at_rest, rtol=0, atol=1e-11 * (np.abs(at_rest).max() + 1.0))
    # platform space: M = Jᵀ·A, Jᵀ·b, Jᵀ·g, as platform_dynamics gives them
    J = prp3.jacobian(robot, pose)
    eq = prp3.platform_dynamics(robot, pose, velocity)
    np.testing.assert_allclose(prp3.mass_matrix(robot, pose, space="platform"), J.T @ A,
                               rtol=1e-13, atol=1e-13 * np.abs(J.T @ A).max())  # fmt: skip
    np.testing.assert_array_equal(prp3.bias_forces(robot, pose, velocity, space="platform"),
                                  eq.bias)  # fmt: skip
    np.testing.assert_allclose(prp3.gravity_forces(robot, pose, space="platform"), J.T @ g,
                               rtol=1e-13, atol=1e-13 * (np.abs(J.T @ g).max() + 1.0))  # fmt: skip


@settings(max_examples=40, deadline=None)
@given(robot=robots(), data=st.data(), velocity=rates)
def test_the_platform_mass_matrix_gives_the_kinetic_energy_of_the_seven_bodies(
    robot, data, velocity
):
    pose = data.draw(poses(robot.l0))
    M = prp3.mass_matrix(robot, pose, space="platform")
    np.testing.assert_allclose(M, M.T, rtol=0, atol=1e-12 * np.abs(M).max())
    assert (np.linalg.eigvalsh(0.5 * (M + M.T)) > 0).all()
    energy = kinetic_energy(robot, pose, velocity)
    assert 0.5 * velocity @ M @ velocity == pytest.approx(energy, rel=1e-10, abs=1e-14)


def test_the_functions_keep_the_rank_and_leave_the_load_out_of_gravity():
    poses_ = np.array([[0.0, 0.0, 0.0], [0.01, -0.02, 0.3]])
    robot = Robot.from_mapping({"load": {"force": [3.0, -1.0], "moment": 0.2}})
    assert prp3.mass_matrix(robot, poses_).shape == (2, 3, 3)
    assert prp3.bias_forces(robot, poses_, np.zeros((2, 3))).shape == (2, 3)
    assert prp3.gravity_forces(robot, poses_[0]).shape == (3,)
    # the load is in b at rest, not in g: g equals the forces of the robot without it
    without = Robot()
    np.testing.assert_array_equal(prp3.gravity_forces(robot, poses_),
                                  prp3.gravity_forces(without, poses_))  # fmt: skip
    at_rest = newton_euler_f10(robot, poses_[1], np.zeros(3), np.zeros(3))
    np.testing.assert_allclose(prp3.bias_forces(robot, poses_[1], np.zeros(3)), at_rest,
                               rtol=1e-12)  # fmt: skip
    assert not np.allclose(prp3.gravity_forces(robot, poses_[1]), at_rest)
    with pytest.raises(ParameterError, match="space must be one of"):
        prp3.mass_matrix(robot, poses_, space="joint")


# ---------------------------------------------------------------- gains per axis
@settings(max_examples=30, deadline=None)
@given(kp=st.lists(st.floats(0.0, 1e3), min_size=3, max_size=3),
       kd=st.lists(st.floats(0.0, 1e2), min_size=3, max_size=3),
       error=st.lists(st.floats(-0.01, 0.01), min_size=6, max_size=6))  # fmt: skip
def test_per_axis_gains_act_on_their_own_axis(kp, kd, error):
    robot = Robot()
    reference = [0.01, 0.02, 0.1, 0.1, -0.05, 0.2, 0.3, 0.1, -0.4]
    measured = [r + e for r, e in zip(reference[:6], error, strict=True)]
    gains = Gains(kp=tuple(kp), kd=tuple(kd))
    f10 = control_force("computed-torque", compile_robot(robot), gains, reference, measured)
    command = [reference[6 + k] + kd[k] * (reference[3 + k] - measured[3 + k])
               + kp[k] * (reference[k] - measured[k]) for k in range(3)]  # fmt: skip
    expected = newton_euler_f10(robot, measured[:3], measured[3:], command)
    np.testing.assert_allclose(f10, expected, rtol=1e-11, atol=1e-11)
    # equal gains on every axis: the same as one number
    same = Gains(kp=(kp[0],) * 3, kd=(kd[0],) * 3)
    one = Gains(kp=kp[0], kd=kd[0])
    assert control_force("pd", compile_robot(robot), same, reference, measured) == control_force(
        "pd", compile_robot(robot), one, reference, measured
    )


def test_per_axis_gains_are_validated_and_on_the_command_line(tmp_path, capsys):
    with pytest.raises(ParameterError, match=r"gains: kp must be a number or 3 numbers"):
        Gains(kp=(1.0, 2.0))
    with pytest.raises(ParameterError, match=r"gains: kd\[1\] must be a non-negative"):
        Gains(kd=[1.0, -2.0, 3.0])
    args = ("control", "--motion", "vertical", "--plant", "prp3", "--controller", "pd",
            "--rate", "20", "-o", tmp_path / "c")  # fmt: skip
    status, out, err = cli(capsys, *args, "--kp", "400,400,900", "--kd", "40")
    assert status == 0, err
    assert "gains KP = (400, 400, 900) 1/s^2, KD = 40 1/s" in out
    status, out, err = cli(capsys, *args, "--kp", "1,2")
    assert (status, out) == (2, "")
    assert "--kp" in one_line(err) and "expected a number or 3 numbers X,Y,PHI, got '1,2'" in err


# ---------------------------------------------------------------- identify, then the robot
@pytest.mark.parametrize("noise", [0.0, 0.05])
def test_identify_then_identified_robot_works_with_the_defaults(noise):
    # was: "h3 = (9.7e-15, 4.3e-14) kg m: a first moment of the platform about G needs a
    # payload" — round-off (or noise) refused for a robot without a payload
    robot = Robot()
    motion = law_motion((0.05, 0.05, 0.5), samples=301)
    f10 = prp3.inverse_dynamics(robot, motion, method="newton-euler")[1].f10
    f10 = f10 + noise * np.random.default_rng(3).standard_normal(f10.shape)
    result = identify(robot, motion, f10)
    identified = identified_robot(robot, result)
    assert set(identified.clamped) == {"platform_moment_x", "platform_moment_y"}
    assert identified.robot.payload == robot.payload  # still none
    base = result.base
    values = base.values(standard_parameters(identified.robot, base.parameters))
    estimate = result.estimate.copy()
    for b, name in enumerate(base.names):
        if name in identified.clamped:
            estimate[b] = 0.0
    # the robot reproduces the estimate; the estimate the true robot within 4 sigma
    np.testing.assert_allclose(values, estimate, rtol=1e-9, atol=1e-12)
    truth = base.values(standard_parameters(robot, base.parameters))
    assert (np.abs(result.estimate - truth) <= 4.0 * result.std + 1e-9).all()


def test_a_first_moment_far_from_zero_without_a_payload_is_still_refused():
    true = Robot(payload=Payload(mass=0.5, com=(0.05, 0.0)))
    motion = law_motion((0.01, 0.02, 0.2), samples=101)
    f10 = prp3.inverse_dynamics(true, motion, method="newton-euler")[1].f10
    result = identify(Robot(), motion, f10)  # the nominal robot knows of no payload
    with pytest.raises(ParameterError, match="needs a payload"):
        identified_robot(Robot(), result)
    # with a payload in the nominal robot, its centre of mass is found
    nominal = Robot(payload=Payload(mass=0.5))
    found = identified_robot(nominal, identify(nominal, motion, f10)).robot
    assert found.payload.com == pytest.approx((0.05, 0.0), abs=1e-9)
