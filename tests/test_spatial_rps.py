"""The 3-RPS on the same joint types (docs/spatial.md §11): 3 DOF, legs of 5 coordinates.

* :func:`complete_motion` gives poses every leg closes on, and the parasitic twist and
  acceleration components of a path (against five-point differences of the path);
* rates match finite differences of the inverse geometry along a path;
* routes (a) and (b) agree to 1e-10 on random robots and states;
* the power balance ``Σ τ·dq_P = Σ_b (m·v_G·(a_G − g) + ω·(I·α + ω × I·ω))`` and every
  body's balance under the reported wrenches, the bodies' motion written out here for
  the RPS leg from ``q, dq, ddq`` (scipy's rotations);
* poses off a leg's plane, and twists the legs do not allow, are refused naming the
  sample and the leg.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from prp3.errors import TrajectoryError, UnreachablePoseError
from prp3.spatial.dynamics import virtual_work_efforts
from prp3.spatial.geometry import inverse_geometry
from prp3.spatial.kinematics import complete_motion, spatial_kinematics
from prp3.spatial.model import SpatialRobot, three_rps
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.newton_euler import newton_euler_dynamics
from prp3.spatial.outputs import spatial_inverse_dynamics
from spatial_strategies import derivative, free_states, rps_robots

H = 1e-4
STEPS = np.array([-2.0, -1.0, 0.0, 1.0, 2.0]) * H


#: The scales of :func:`spatial_strategies.free_states` here.
STATE_SCALES = (0.008, 0.15, 2.0, 0.05, 50.0, 3.0)


def _path(robot: SpatialRobot, t: np.ndarray, c: np.ndarray) -> PlatformMotion:
    """A smooth path of poses at rest: ``z`` and the tilts as sines, completed."""
    z = robot.home_position[2] + 0.006 * np.sin(c[0] * t + c[1])
    roll = 0.1 * np.sin(c[2] * t + c[3])
    pitch = 0.08 * np.sin(c[4] * t + c[5])
    rotation = Rotation.from_euler("xyz", np.stack([roll, pitch, 0 * t], 1)).as_matrix()
    position = np.stack([0 * t, 0 * t, z], 1)
    return complete_motion(robot, PlatformMotion.of(t, position, rotation))


def _frame_rates(motions: PlatformMotion) -> tuple[np.ndarray, np.ndarray]:
    """Twist ``(ω, v)`` at the middle of five poses by differences."""
    r = motions.rotation
    w = derivative(r, H) @ r[2].T
    omega = np.array([w[2, 1], w[0, 2], w[1, 0]])
    return omega, derivative(motions.position, H)


@given(rps_robots(), st.data())
def test_completed_poses_close_every_leg(robot: SpatialRobot, data: st.DataObject) -> None:
    motion = complete_motion(robot, data.draw(free_states(robot, STATE_SCALES)))
    q = inverse_geometry(robot, motion)
    for i, leg in enumerate(robot.legs):
        joint = leg.joints[0]
        arm = np.array(joint.rotation) @ Rotation.from_euler("z", q[:, i, 0, None]).as_matrix()
        centre = np.array(joint.position) + q[:, i, 1, None] * arm[:, :, 0]
        attach = motion.position + motion.rotation @ np.array(leg.attachment_position)
        assert np.allclose(centre, attach, atol=1e-14)
        sphere = Rotation.from_rotvec(q[:, i, 2:]).as_matrix()
        target = motion.rotation @ np.array(leg.attachment_rotation)
        assert np.allclose(arm @ sphere, target, atol=1e-13)


@given(rps_robots(), st.lists(st.floats(0.5, 5.0), min_size=6, max_size=6), st.floats(0, 2))
def test_the_parasitic_rates_and_joint_rates_are_those_of_a_path(
    robot: SpatialRobot, c: list[float], t0: float
) -> None:
    path = _path(robot, t0 + STEPS, np.array(c))
    omega, velocity = _frame_rates(path)
    # the free components of the path's twist, the parasitic ones left out
    given_twist = np.concatenate([omega, velocity])
    index = list(robot.parasitic_index)
    given_twist[index] = 0.0
    state = PlatformMotion.of(
        [t0], path.position[2], path.rotation[2], given_twist[:3], given_twist[3:]
    )
    completed = complete_motion(robot, state)
    assert np.allclose(completed.position, path.position[2], atol=1e-15)
    twist = np.concatenate([completed.omega[0], completed.velocity[0]])
    assert np.allclose(twist, np.concatenate([omega, velocity]), rtol=1e-7, atol=1e-9)
    # joint rates against the path's joint values
    q = inverse_geometry(robot, path)
    kin = spatial_kinematics(robot, completed)
    assert np.allclose(derivative(q[..., :2], H), kin.dq[0, :, :2], rtol=1e-7, atol=1e-9)


@given(rps_robots(), st.lists(st.floats(0.5, 5.0), min_size=6, max_size=6), st.floats(0, 2))
def test_a_completed_motion_is_the_derivative_of_its_completed_poses(
    robot: SpatialRobot, c: list[float], t0: float
) -> None:
    """Regression: completion turns the poses (a yaw), so the free ``ω`` turns with them.

    A smooth roll–pitch path with its own exact rates (:func:`rpy_motion`), not yet
    completed: the completed twist and its derivative must be the time derivatives
    (five-point differences) of the completed poses and twist.  Before the fix the
    kept ``ωx, ωy`` were those of the uncompleted poses (1.2e-3 rad/s off in the
    default 3-RPS's tilt, 0.6 %).
    """
    from prp3.spatial.motion import rpy_motion

    t = t0 + STEPS
    a = np.array(c)
    rpy = np.stack([0.1 * np.sin(a[2] * t + a[3]), 0.08 * np.sin(a[4] * t + a[5]), 0 * t], 1)
    rate = np.stack(
        [0.1 * a[2] * np.cos(a[2] * t + a[3]), 0.08 * a[4] * np.cos(a[4] * t + a[5]), 0 * t], 1
    )
    second = np.stack([-0.1 * a[2] ** 2 * np.sin(a[2] * t + a[3]),
                       -0.08 * a[4] ** 2 * np.sin(a[4] * t + a[5]), 0 * t], 1)  # fmt: skip
    z = robot.home_position[2] + 0.006 * np.sin(a[0] * t + a[1])
    vz = 0.006 * a[0] * np.cos(a[0] * t + a[1])
    az = -0.006 * a[0] ** 2 * np.sin(a[0] * t + a[1])
    zero = 0 * t
    motion = rpy_motion(
        t, np.stack([zero, zero, z], 1), rpy,
        velocity=np.stack([zero, zero, vz], 1), rpy_rate=rate,
        acceleration=np.stack([zero, zero, az], 1), rpy_acceleration=second,
    )  # fmt: skip
    completed = complete_motion(robot, motion)
    omega, velocity = _frame_rates(completed)
    assert np.allclose(completed.omega[2], omega, rtol=1e-7, atol=1e-9)
    assert np.allclose(completed.velocity[2], velocity, rtol=1e-7, atol=1e-9)
    assert np.allclose(completed.alpha[2], derivative(completed.omega, H), rtol=1e-6, atol=1e-8)
    assert np.allclose(
        completed.acceleration[2], derivative(completed.velocity, H), rtol=1e-6, atol=1e-8
    )


def _rps_bodies(robot: SpatialRobot, motion: PlatformMotion):  # type: ignore[no-untyped-def]
    """Each leg body's (body, centre, velocity, ω, α, a_G, rotation) from ``q, dq, ddq``."""
    kin = spatial_kinematics(robot, motion)
    q, dq, ddq = kin.q, kin.dq, kin.ddq
    legs = []
    for i, leg in enumerate(robot.legs):
        joint = leg.joints[0]
        e = np.array(joint.rotation)[:, 2]
        r = np.array(joint.rotation) @ Rotation.from_euler("z", q[:, i, 0, None]).as_matrix()
        u = r[:, :, 0]
        omega, alpha = dq[:, i, 0, None] * e, ddq[:, i, 0, None] * e
        assert np.allclose(motion.omega - omega, dq[:, i, 2:], atol=1e-12 * (1 + np.abs(dq).max()))
        base = np.array(joint.position)
        bodies = []
        for body, slide in zip(leg.bodies, (False, True), strict=True):
            length = q[:, i, 1, None] if slide else 0.0
            offset = length * u + r @ np.array(body.centre)
            velocity = np.cross(omega, offset)
            acc = np.cross(alpha, offset) + np.cross(omega, np.cross(omega, offset))
            if slide:
                velocity = velocity + dq[:, i, 1, None] * u
                acc = acc + ddq[:, i, 1, None] * u + 2.0 * dq[:, i, 1, None] * np.cross(omega, u)
            bodies.append((body, base + offset, velocity, omega, alpha, acc, r))
        legs.append(bodies)
    return kin, legs


def _inertial(body, omega, alpha, acc, rotation, gravity):  # type: ignore[no-untyped-def]
    world = rotation @ np.array(body.inertia) @ np.swapaxes(rotation, -1, -2)
    force = body.mass * (acc - gravity)
    moment = np.einsum("nij,nj->ni", world, alpha) + np.cross(
        omega, np.einsum("nij,nj->ni", world, omega)
    )
    return force, moment


@given(rps_robots(), st.data())
def test_the_routes_agree_and_the_power_balances(robot: SpatialRobot, data: st.DataObject) -> None:
    motion = complete_motion(robot, data.draw(free_states(robot, STATE_SCALES)))
    tau_a = virtual_work_efforts(robot, motion)
    tau_b = newton_euler_dynamics(robot, motion).tau
    assert float(np.abs(tau_a - tau_b).max() / np.abs(tau_a).max()) < 1e-10
    kin, legs = _rps_bodies(robot, motion)
    g = np.array(robot.gravity)
    rate = np.zeros(len(motion))
    for bodies in legs:
        for body, _, velocity, omega, alpha, acc, r in bodies:
            force, moment = _inertial(body, omega, alpha, acc, r, g)
            rate += np.einsum("ni,ni->n", velocity, force) + np.einsum("ni,ni->n", omega, moment)
    p = robot.platform
    rp = motion.rotation @ np.array(p.centre)
    velocity = motion.velocity + np.cross(motion.omega, rp)
    acc = motion.acceleration + np.cross(motion.alpha, rp)
    acc = acc + np.cross(motion.omega, np.cross(motion.omega, rp))
    force, moment = _inertial(p, motion.omega, motion.alpha, acc, motion.rotation, g)
    rate += np.einsum("ni,ni->n", velocity, force) + np.einsum("ni,ni->n", motion.omega, moment)
    power = (tau_a * kin.dq[..., 1]).sum(axis=1)
    scale = (np.abs(tau_a * kin.dq[..., 1])).sum(axis=1) + 1e-12
    assert np.all(np.abs(power - rate) < 1e-10 * scale)


@given(rps_robots(), st.data())
def test_every_body_balances_under_the_reported_wrenches(
    robot: SpatialRobot, data: st.DataObject
) -> None:
    motion = complete_motion(robot, data.draw(free_states(robot, STATE_SCALES)))
    kin, legs = _rps_bodies(robot, motion)
    solution = spatial_inverse_dynamics(robot, motion)
    assert solution.force is not None and solution.moment is not None
    f, m = solution.force, solution.moment
    g = np.array(robot.gravity)
    scale = np.abs(f).max()
    total_f = np.zeros((len(motion), 3))
    total_m = np.zeros((len(motion), 3))
    p = robot.platform
    pc = motion.position + motion.rotation @ np.array(p.centre)
    for i, leg in enumerate(robot.legs):
        base = np.array(leg.joints[0].position)
        sphere = motion.position + motion.rotation @ np.array(leg.attachment_position)
        u = legs[i][0][6][:, :, 0]
        points = (base, base + kin.q[:, i, 1, None] * u, sphere)
        for k, (body, centre, _, omega, alpha, acc, r) in enumerate(legs[i]):
            force, moment = _inertial(body, omega, alpha, acc, r, g)
            for sign, j in ((1.0, k), (-1.0, k + 1)):
                force = force - sign * f[:, i, j]
                moment = moment - sign * (m[:, i, j] + np.cross(points[j] - centre, f[:, i, j]))
            assert np.abs(force).max() < 1e-12 * scale
            assert np.abs(moment).max() < 1e-12 * scale * robot.scale
        total_f += f[:, i, 2]
        total_m += m[:, i, 2] + np.cross(sphere - pc, f[:, i, 2])
        e = np.array(leg.joints[0].rotation)[:, 2]
        assert np.abs(m[:, i, 0] @ e).max() < 1e-12 * scale * robot.scale  # R: no moment about e
        assert np.allclose(
            np.einsum("ni,ni->n", f[:, i, 1], u), solution.tau[:, i], atol=1e-12 * scale
        )
        assert np.abs(m[:, i, 2]).max() < 1e-12 * scale * robot.scale  # S
    rp = pc - motion.position
    acc = motion.acceleration + np.cross(motion.alpha, rp)
    acc = acc + np.cross(motion.omega, np.cross(motion.omega, rp))
    force, moment = _inertial(p, motion.omega, motion.alpha, acc, motion.rotation, g)
    assert np.abs(total_f - force).max() < 1e-12 * scale
    assert np.abs(total_m - moment).max() < 1e-12 * scale * robot.scale


def test_the_default_3rps_at_home() -> None:
    robot = three_rps()
    solution = spatial_inverse_dynamics(robot, PlatformMotion.at_rest(robot.home_position))
    assert solution.kinematics.q.shape == (1, 3, 5)
    assert np.allclose(solution.kinematics.q[0, :, 1], math.hypot(0.04, 0.1), rtol=1e-15)
    assert np.ptp(solution.tau) < 1e-12
    assert solution.force is not None
    assert np.allclose(solution.force[0, :, 2, 2], 9.81 / 3, rtol=1e-13)  # a third of the platform


def test_a_pose_off_a_legs_plane_is_refused() -> None:
    robot = three_rps()
    z = np.full(4, 0.1)
    x = np.array([0.0, 0.0, 1e-3, 0.0])
    motion = PlatformMotion.at_rest(np.stack([x, 0 * x, z], 1))
    with pytest.raises(UnreachablePoseError) as caught:
        spatial_kinematics(robot, motion)
    assert (caught.value.sample, caught.value.leg) == (2, "1")
    assert "off the plane of its R joint" in str(caught.value)


def test_a_twist_the_legs_do_not_allow_is_refused() -> None:
    robot = three_rps()
    motion = PlatformMotion.of([0.0, 1.0], [[0, 0, 0.1]] * 2, np.eye(3)[None].repeat(2, 0),
                               omega=[[0, 0, 0], [0, 0, 0.5]])  # fmt: skip
    with pytest.raises(TrajectoryError) as caught:
        spatial_kinematics(robot, motion)
    assert caught.value.sample == 1 and "twist is not one the legs allow" in str(caught.value)
    fixed = complete_motion(robot, motion)
    assert np.allclose(fixed.omega[1], 0.0, atol=1e-15)
    assert spatial_kinematics(robot, fixed).dq.shape == (2, 3, 5)
