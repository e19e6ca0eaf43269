"""The Delta as a 3-RUU on the same joint types (docs/spatial.md §12): the platform translates.

* :func:`complete_motion` turns any state into a translation (``R = I``, ``ω = α = 0``);
  every leg closes (``|c_U2 − elbow| = forearm``, written out here);
* joint rates and accelerations match finite differences along a translation path;
* routes (a) and (b) agree to 1e-10 on random robots and states;
* the power balance and every body's balance under the reported wrenches, the
  bodies' motion written out here for the RUU leg from ``q, dq, ddq`` (scipy's
  rotations); the actuated R carries ``τ`` about its axis, the U's no moment about theirs.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from prp3.errors import UnreachablePoseError
from prp3.spatial.dynamics import virtual_work_efforts
from prp3.spatial.geometry import inverse_geometry
from prp3.spatial.kinematics import complete_motion, spatial_kinematics
from prp3.spatial.model import SpatialRobot, delta
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.newton_euler import newton_euler_dynamics
from prp3.spatial.outputs import spatial_inverse_dynamics
from spatial_strategies import deltas, derivative, free_states

H = 1e-4
STEPS = np.array([-2.0, -1.0, 0.0, 1.0, 2.0]) * H
E_Z = np.array([0.0, 0.0, 1.0])


def _rot(axis: str, angle: np.ndarray) -> np.ndarray:
    return Rotation.from_euler(axis, np.asarray(angle)[..., None]).as_matrix()


#: The scales of :func:`spatial_strategies.free_states` here.
STATE_SCALES = (0.015, 0.05, 2.0, 0.5, 50.0, 10.0)


def _ruu(robot: SpatialRobot, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, i: int):  # type: ignore[no-untyped-def]
    """Leg ``i``'s arm and forearm: (body, centre, velocity, ω, α, a_G, rotation), the elbow
    and the axes ``e`` (R and U1's first), ``y1`` (U1's second)."""
    leg = robot.legs[i]
    r_joint, u1, _ = leg.joints
    e = np.array(r_joint.rotation)[:, 2]
    arm = np.array(r_joint.rotation) @ _rot("z", q[:, i, 0])
    base = np.array(r_joint.position)
    elbow = base + arm @ np.array(u1.position)
    cross1 = arm @ np.array(u1.rotation) @ _rot("z", q[:, i, 1])
    fore = cross1 @ _rot("y", q[:, i, 2])
    y1 = cross1[:, :, 1]
    w_arm, al_arm = dq[:, i, 0, None] * e, ddq[:, i, 0, None] * e
    w_f = w_arm + dq[:, i, 1, None] * e + dq[:, i, 2, None] * y1
    al_f = (
        al_arm
        + ddq[:, i, 1, None] * e
        + ddq[:, i, 2, None] * y1
        + dq[:, i, 2, None] * np.cross(w_arm + dq[:, i, 1, None] * e, y1)
    )
    r_e = elbow - base
    v_e = np.cross(w_arm, r_e)
    a_e = np.cross(al_arm, r_e) + np.cross(w_arm, np.cross(w_arm, r_e))
    out = []
    for body, rot, w, al, origin, v0, a0 in (
        (leg.bodies[0], arm, w_arm, al_arm, base, 0.0, 0.0),
        (leg.bodies[1], fore, w_f, al_f, elbow, v_e, a_e),
    ):
        offset = rot @ np.array(body.centre) + (origin - origin)
        centre = origin + offset
        v = v0 + np.cross(w, offset)
        a = a0 + np.cross(al, offset) + np.cross(w, np.cross(w, offset))
        out.append((body, centre, v, w, al, a, rot))
    return out, elbow, fore, e, y1


def _inertial(body, omega, alpha, acc, rotation, gravity):  # type: ignore[no-untyped-def]
    world = rotation @ np.array(body.inertia) @ np.swapaxes(rotation, -1, -2)
    force = body.mass * (acc - gravity)
    moment = np.einsum("nij,nj->ni", world, alpha) + np.cross(
        omega, np.einsum("nij,nj->ni", world, omega)
    )
    return force, moment


@given(deltas(), st.data())
def test_completed_states_translate_and_every_leg_closes(
    robot: SpatialRobot, data: st.DataObject
) -> None:
    motion = complete_motion(robot, data.draw(free_states(robot, STATE_SCALES)))
    assert np.abs(motion.rotation - np.eye(3)).max() < 1e-12
    assert np.abs(motion.omega).max() < 1e-12 and np.abs(motion.alpha).max() < 1e-10
    kin = spatial_kinematics(robot, motion)
    for i, leg in enumerate(robot.legs):
        _, elbow, fore, _, _ = _ruu(robot, kin.q, kin.dq, kin.ddq, i)
        c2 = motion.position + np.array(leg.attachment_position)
        assert np.allclose(c2, elbow + fore[:, :, 0] * leg.joints[2].position[0], atol=1e-14)


@given(deltas(), st.lists(st.floats(0.5, 5.0), min_size=6, max_size=6), st.floats(0, 2))
def test_rates_match_finite_differences_along_a_translation(
    robot: SpatialRobot, c: list[float], t0: float
) -> None:
    def path(t: np.ndarray) -> PlatformMotion:
        arg = np.array(c[:3]) * t[:, None] + np.array(c[3:])
        p = np.array(robot.home_position) + 0.01 * np.sin(arg)
        v = 0.01 * np.array(c[:3]) * np.cos(arg)
        a = -0.01 * np.array(c[:3]) ** 2 * np.sin(arg)
        eye = np.broadcast_to(np.eye(3), (len(t), 3, 3))
        return PlatformMotion.of(t, p, eye, velocity=v, acceleration=a)

    t = t0 + STEPS
    q = inverse_geometry(robot, path(t))
    kin = spatial_kinematics(robot, path(np.array([t0])))
    assert np.allclose(derivative(q, H), kin.dq[0], rtol=1e-7, atol=1e-9)
    rates = np.array([spatial_kinematics(robot, path(np.array([s]))).dq[0] for s in t])
    assert np.allclose(derivative(rates, H), kin.ddq[0], rtol=1e-6, atol=1e-8)


@given(deltas(), st.data())
def test_the_routes_agree_and_every_body_balances(robot: SpatialRobot, data: st.DataObject) -> None:
    motion = complete_motion(robot, data.draw(free_states(robot, STATE_SCALES)))
    tau_a = virtual_work_efforts(robot, motion)
    solution = spatial_inverse_dynamics(robot, motion)
    assert float(np.abs(tau_a - solution.tau).max() / np.abs(tau_a).max()) < 1e-10
    assert solution.force is not None and solution.moment is not None
    f, m = solution.force, solution.moment
    kin = solution.kinematics
    g = np.array(robot.gravity)
    scale = np.abs(f).max()
    lever = scale * robot.scale
    rate = np.zeros(len(motion))
    total_f = np.zeros((len(motion), 3))
    p = robot.platform
    pc = motion.position + motion.rotation @ np.array(p.centre)
    total_m = np.zeros((len(motion), 3))
    for i, leg in enumerate(robot.legs):
        bodies, elbow, fore, e, y1 = _ruu(robot, kin.q, kin.dq, kin.ddq, i)
        c2 = motion.position + np.array(leg.attachment_position)
        points = (np.array(leg.joints[0].position), elbow, c2)
        for k, (body, centre, v, w, al, a, rot) in enumerate(bodies):
            force, moment = _inertial(body, w, al, a, rot, g)
            rate += np.einsum("ni,ni->n", v, force) + np.einsum("ni,ni->n", w, moment)
            for sign, j in ((1.0, k), (-1.0, k + 1)):
                force = force - sign * f[:, i, j]
                moment = moment - sign * (m[:, i, j] + np.cross(points[j] - centre, f[:, i, j]))
            assert np.abs(force).max() < 1e-12 * scale
            assert np.abs(moment).max() < 1e-12 * lever
        total_f += f[:, i, 2]
        total_m += m[:, i, 2] + np.cross(c2 - pc, f[:, i, 2])
        assert np.allclose(m[:, i, 0] @ e, solution.tau[:, i], rtol=0, atol=1e-12 * lever)
        assert np.abs(m[:, i, 1] @ e).max() < 1e-12 * lever
        assert np.abs(np.einsum("ni,ni->n", m[:, i, 1], y1)).max() < 1e-12 * lever
        cross2 = fore @ np.array(leg.joints[2].rotation) @ _rot("z", kin.q[:, i, 3])
        assert np.abs(np.einsum("ni,ni->n", m[:, i, 2], cross2[:, :, 2])).max() < 1e-12 * lever
        assert np.abs(np.einsum("ni,ni->n", m[:, i, 2], cross2[:, :, 1])).max() < 1e-12 * lever
    a_p = motion.acceleration
    force, moment = _inertial(p, motion.omega, motion.alpha, a_p, motion.rotation, g)
    rate += np.einsum("ni,ni->n", motion.velocity, force)
    assert np.abs(total_f - force).max() < 1e-12 * scale
    assert np.abs(total_m - moment).max() < 1e-12 * lever
    power = (solution.tau * kin.dq[..., 0]).sum(axis=1)
    assert np.all(
        np.abs(power - rate) < 1e-10 * (np.abs(solution.tau * kin.dq[..., 0]).sum(1) + 1e-12)
    )
    # the command's route (recursive) against the one linear system of every unknown
    reference = newton_euler_dynamics(robot, motion).tau
    assert np.abs(reference - solution.tau).max() <= 1e-10 * np.abs(reference).max()


def test_the_default_delta_at_home() -> None:
    robot = delta()
    solution = spatial_inverse_dynamics(robot, PlatformMotion.at_rest(robot.home_position))
    assert solution.kinematics.q.shape == (1, 3, 5)
    assert np.ptp(solution.tau) < 1e-12
    assert solution.force is not None
    assert np.isclose(solution.force[0, :, 2, 2].sum(), 0.2 * 9.81, rtol=1e-13)


def test_out_of_reach_and_turned_platforms_are_refused() -> None:
    robot = delta()
    import pytest

    far = PlatformMotion.at_rest([[0.0, 0.0, -0.2], [0.0, 0.0, -0.5]])
    with pytest.raises(UnreachablePoseError, match=r"^sample 1, t = 1 s, leg 1: cannot reach"):
        spatial_kinematics(robot, far)
    turned = PlatformMotion.at_rest([0.0, 0.0, -0.2], Rotation.from_euler("z", 0.01).as_matrix())
    with pytest.raises(UnreachablePoseError, match="its second U cannot turn the platform"):
        spatial_kinematics(robot, turned)
