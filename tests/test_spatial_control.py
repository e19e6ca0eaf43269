"""Computed-torque control of the spatial robots (docs/spatial.md §23)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import prp3
from prp3 import PlatformMotion

W = 2.0 * math.pi  # 1 s period


def _hexapod_reference(robot: prp3.SpatialRobot):
    """Heave of 5 mm and roll of 0.05 rad, sinusoidal, exact rates (rpy_motion)."""
    home = np.asarray(robot.home_position)

    def reference(t: float) -> PlatformMotion:
        s, c = math.sin(W * t), math.cos(W * t)
        return prp3.rpy_motion(
            [t], [home + [0.0, 0.0, 0.005 * s]], [[0.05 * s, 0.0, 0.0]],
            velocity=[[0.0, 0.0, 0.005 * W * c]], rpy_rate=[[0.05 * W * c, 0.0, 0.0]],
            acceleration=[[0.0, 0.0, -0.005 * W * W * s]],
            rpy_acceleration=[[-0.05 * W * W * s, 0.0, 0.0]],
        )  # fmt: skip

    return reference


def _delta_reference(robot: prp3.SpatialRobot):
    """A circle of radius 0.02·scale in x–y, exact rates, fixed orientation."""
    home = np.asarray(robot.home_position)
    r = 0.02 * robot.scale

    def reference(t: float) -> PlatformMotion:
        s, c = math.sin(W * t), math.cos(W * t)
        return PlatformMotion.of(
            [t], [home + [r * s, r * (1 - c), 0.0]], np.eye(3)[None],
            np.zeros((1, 3)), [[r * W * c, r * W * s, 0.0]], np.zeros((1, 3)),
            [[-r * W * W * s, r * W * W * c, 0.0]],
        )  # fmt: skip

    return reference


CASES = [(prp3.hexapod, _hexapod_reference), (prp3.delta, _delta_reference)]


@pytest.mark.parametrize(("make", "reference_of"), CASES)
def test_zero_error_stays_at_round_off(make, reference_of) -> None:
    robot = make()
    run = prp3.spatial_track(robot, reference_of(robot), 0.5, samples=11)
    assert float(np.abs(run.error).max()) <= 1e-9
    assert run.effort_residual <= 1e-8 * max(1.0, float(np.abs(run.efforts).max()))


def _closed_form(t: np.ndarray, e0: float, de0: float, kp: float, kd: float) -> np.ndarray:
    """The solution of ë + kd ė + kp e = 0 (underdamped: kd² < 4 kp)."""
    zeta_w = kd / 2.0
    wd = math.sqrt(kp - zeta_w**2)
    return np.exp(-zeta_w * t) * (e0 * np.cos(wd * t) + (de0 + zeta_w * e0) / wd * np.sin(wd * t))


def _check_decay(make, reference_of, dp, dv, kp: float, kd: float) -> None:
    robot = make()
    reference = reference_of(robot)
    ref0 = reference(0.0)
    start = PlatformMotion.of(
        [0.0], ref0.position + dp, ref0.rotation, ref0.omega, ref0.velocity + dv
    )
    run = prp3.spatial_track(robot, reference, 0.4, kp=kp, kd=kd, initial=start, samples=21)
    for k in range(3):
        expected = _closed_form(run.t, -dp[k], -dv[k], kp, kd)
        np.testing.assert_allclose(run.error[:, 3 + k], expected, rtol=0, atol=1e-9)


@pytest.mark.parametrize(("make", "reference_of"), CASES)
def test_position_error_follows_closed_form(make, reference_of) -> None:
    _check_decay(make, reference_of, np.array([1e-3, -2e-3, 1.5e-3]),
                 np.array([0.01, 0.0, -0.02]), 100.0, 10.0)  # fmt: skip


@pytest.mark.slow
@settings(max_examples=4, deadline=None)
@given(
    kp=st.floats(25.0, 400.0),
    ratio=st.floats(0.2, 1.6),
    dp=st.lists(st.floats(-2e-3, 2e-3), min_size=3, max_size=3),
)
def test_decay_hypothesis(kp: float, ratio: float, dp: list[float]) -> None:
    kd = ratio * math.sqrt(kp)  # kd² = ratio²·kp < 4·kp: underdamped
    _check_decay(prp3.hexapod, _hexapod_reference, np.array(dp), np.zeros(3), kp, kd)


def test_orientation_error_decays() -> None:
    robot = prp3.hexapod()
    reference = _hexapod_reference(robot)
    ref0 = reference(0.0)
    tilt = prp3.PlatformMotion.at_rest(
        [0, 0, 0],
        np.array(
            [[1, 0, 0], [0, math.cos(0.02), -math.sin(0.02)], [0, math.sin(0.02), math.cos(0.02)]]
        ),
    )
    start = PlatformMotion.of([0.0], ref0.position, tilt.rotation @ ref0.rotation,
                              ref0.omega, ref0.velocity)  # fmt: skip
    run = prp3.spatial_track(robot, reference, 0.6, kp=100.0, kd=20.0, initial=start, samples=13)
    size = np.linalg.norm(run.error[:, :3], axis=1)
    assert size[0] == pytest.approx(0.02, rel=1e-9)
    assert size[-1] < 0.02 * 0.05


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"kp": -1.0}, "kp"),
        ({"kd": math.nan}, "kd"),
        ({"plant": "nope"}, "plant"),
    ],
)
def test_bad_arguments(kwargs, match) -> None:
    robot = prp3.hexapod()
    with pytest.raises(prp3.ParameterError, match=match):
        prp3.spatial_track(robot, _hexapod_reference(robot), 0.1, **kwargs)


def test_bad_reference() -> None:
    robot = prp3.hexapod()
    with pytest.raises(prp3.ParameterError, match="reference"):
        prp3.spatial_track(robot, 3.0, 0.1)  # type: ignore[arg-type]
    with pytest.raises(prp3.ParameterError, match="reference"):
        prp3.spatial_track(robot, lambda t: 1.0, 0.1)  # type: ignore[arg-type,return-value]


def test_pose_error_refuses_mismatched_lengths() -> None:
    a = PlatformMotion.at_rest([0.0, 0.0, 0.1])
    b = PlatformMotion.of([0.0, 1.0], [[0, 0, 0], [0, 0, 0]], np.stack([np.eye(3)] * 2))
    with pytest.raises(prp3.ParameterError, match="samples"):
        prp3.spatial_pose_error(a, b)


@pytest.mark.parametrize(
    ("make", "motion", "position_tol", "rotation_tol"),
    [
        (prp3.hexapod, "heave", 3e-5, 1e-12),
        (prp3.three_rps, "tilt", 2e-5, 5e-4),
        (prp3.delta, "circle", 2e-5, 1e-5),
    ],
)
def test_mujoco_plant_agrees_with_prp3_plant(make, motion, position_tol, rotation_tol) -> None:
    """From a 2 mm error: MuJoCo (RK4, 1 ms steps, efforts held over a step, its loop
    closures soft equalities of solref (2 ms, 1), solimp 0.9999, a closing U's end body
    of the platform's inverse weight) against prp3's exact plant.  The tolerance (1.5 %
    of the initial error; rotation: the 3-RPS's parasitic turn, the Delta's held
    orientation, measured 6e-7 rad) is MuJoCo's: its soft closures and the held efforts."""
    pytest.importorskip("mujoco")
    robot = make()

    def reference(t: float) -> PlatformMotion:
        return prp3.complete_motion(robot, prp3.spatial_motion(robot, motion, 2, 1.0, times=[t]))

    r0 = reference(0.0)
    start = prp3.complete_motion(robot, PlatformMotion.of(
        [0.0], r0.position + [0.0, 0.0, -0.002], r0.rotation, r0.omega, r0.velocity))  # fmt: skip
    exact = prp3.spatial_track(robot, reference, 0.3, initial=start, samples=7)
    run = prp3.spatial_track(robot, reference, 0.3, initial=start, samples=7, plant="mujoco")
    np.testing.assert_allclose(run.t, exact.t, rtol=0, atol=1e-15)
    assert float(np.abs(run.error[:, 3:] - exact.error[:, 3:]).max()) <= position_tol
    assert float(np.abs(run.error[:, :3] - exact.error[:, :3]).max()) <= rotation_tol
    peak = float(np.abs(exact.efforts).max())
    assert float(np.abs(run.efforts - exact.efforts).max()) <= 3e-3 * peak
    assert float(np.abs(run.error[-1, 5])) < 0.002 * 0.05  # and it converges


@pytest.mark.slow
def test_the_delta_on_mujoco_holds_its_orientation_over_three_periods() -> None:
    """The Delta's platform on MuJoCo over 3 s of a circle of period 1 s from a 2 mm error:
    its rotation stays below 1e-5 rad (measured 9e-7; 0.2 rad in 0.3 s before the closing
    U's end bodies got the platform's inverse weight, docs/spatial.md §23), and the position
    error after the transient is that of the prp3 plant within 2e-5 m."""
    pytest.importorskip("mujoco")
    robot = prp3.delta()

    def reference(t: float) -> PlatformMotion:
        return prp3.complete_motion(robot, prp3.spatial_motion(robot, "circle", 2, 1.0, times=[t]))

    r0 = reference(0.0)
    start = PlatformMotion.of([0.0], r0.position + [0.0, 0.0, -0.002], r0.rotation, r0.omega,
                              r0.velocity)  # fmt: skip
    run = prp3.spatial_track(robot, reference, 3.0, initial=start, samples=31, plant="mujoco")
    exact = prp3.spatial_track(robot, reference, 3.0, initial=start, samples=31)
    assert float(np.linalg.norm(run.error[:, :3], axis=1).max()) <= 1e-5
    assert float(np.abs(run.error[:, 3:] - exact.error[:, 3:]).max()) <= 2e-5


def test_the_delta_end_bodies_inverse_weight_is_why_its_welds_were_soft() -> None:
    """The cause (docs/spatial.md §23): MuJoCo's weld regularisation scales with its bodies'
    inverse weights, and a closing U's end body (1e-12 of the platform's mass, §16) has a
    rotational one about 4e9 times the platform's as compiled."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_string(prp3.spatial_mjcf_model(prp3.delta()))
    platform = model.body_invweight0[model.body("platform").id]
    for i in (1, 2, 3):
        end = model.body_invweight0[model.body(f"leg{i}_end").id]
        assert float(end[1]) > 1e9 * float(platform[1])


# ---------------------------------------------------------------- gains per component
KP6 = np.array([100.0, 225.0, 400.0, 64.0, 144.0, 400.0])  # rx, ry, rz, x, y, z (1/s²)
KD6 = np.array([8.0, 12.0, 30.0, 6.0, 20.0, 24.0])  # each underdamped: kd² < 4·kp


def _exact_rotation_loop(t: np.ndarray, e0: np.ndarray, kp: np.ndarray, kd: np.ndarray):
    """The exact closed loop of the rotation about a still reference ``R_ref = I``, by
    scipy: ``Ṙ = [ω]·R``, ``ω̇ = −Kd·ω + Kp·log(Rᵀ)`` (the law's ``α``), from
    ``log(Rᵀ) = e0`` at rest; returns ``log(R_ref·Rᵀ)`` at ``t``."""
    from scipy.integrate import solve_ivp
    from scipy.spatial.transform import Rotation

    def rhs(_: float, y: np.ndarray) -> np.ndarray:
        rotation, omega = y[:9].reshape(3, 3), y[9:]
        skew = np.array([[0, -omega[2], omega[1]], [omega[2], 0, -omega[0]],
                         [-omega[1], omega[0], 0]])  # fmt: skip
        e = Rotation.from_matrix(rotation.T).as_rotvec()
        return np.concatenate([(skew @ rotation).reshape(9), -kd * omega + kp * e])

    start = Rotation.from_rotvec(-e0).as_matrix()  # log(R_ref·Rᵀ) = e0
    done = solve_ivp(rhs, (0.0, float(t[-1])), np.concatenate([start.reshape(9), np.zeros(3)]),
                     t_eval=t, rtol=1e-12, atol=1e-14, method="DOP853")  # fmt: skip
    return np.array([Rotation.from_matrix(r.reshape(3, 3).T).as_rotvec() for r in done.y[:9].T])


def test_each_component_decays_with_its_own_gains() -> None:
    """Six different gain pairs, an initial error in every component of the 6-UPS about a
    still reference: each position component is ``ë + Kd_c·ė + Kp_c·e = 0``'s closed form
    with its own gains to 1e-9 m; the rotation is scipy's integration of the exact closed
    loop to 1e-11 rad (measured 2e-13), and to 5e-4 of the error (second order in 1e-3 rad)
    the closed form of each component's own ODE."""
    robot = prp3.hexapod()
    still = PlatformMotion.at_rest(robot.home_position)
    e0 = np.array([1e-3, -2e-3, 1.5e-3, 2e-3, -1e-3, 1e-3])
    from scipy.spatial.transform import Rotation

    start = PlatformMotion.of(
        [0.0], still.position - e0[3:], Rotation.from_rotvec(-e0[:3]).as_matrix()[None],
        np.zeros((1, 3)), np.zeros((1, 3)),
    )  # fmt: skip
    run = prp3.spatial_track(robot, lambda t: still, 0.4, kp=KP6, kd=KD6.tolist(),
                             initial=start, samples=21)  # fmt: skip
    np.testing.assert_allclose(run.error[0], e0, rtol=0, atol=1e-15)
    for c in range(6):
        linear = _closed_form(run.t, e0[c], 0.0, KP6[c], KD6[c])
        atol = 1e-9 if c >= 3 else 5e-4 * abs(e0[c])  # rotation: second order in e
        np.testing.assert_allclose(run.error[:, c], linear, rtol=0, atol=atol)
    exact = _exact_rotation_loop(run.t, e0[:3], KP6[:3], KD6[:3])
    np.testing.assert_allclose(run.error[:, :3], exact, rtol=0, atol=1e-11)
    # the rates differ: swapping two components' gains changes their errors
    swapped = prp3.spatial_track(robot, lambda t: still, 0.4, kp=KP6[[0, 1, 2, 4, 3, 5]],
                                 kd=KD6[[0, 1, 2, 4, 3, 5]], initial=start, samples=21)  # fmt: skip
    assert float(np.abs(swapped.error[:, 3] - run.error[:, 3]).max()) > 1e-4


def test_scalar_gains_are_six_equal_gains() -> None:
    robot = prp3.hexapod()
    reference = _hexapod_reference(robot)
    ref0 = reference(0.0)
    start = PlatformMotion.of([0.0], ref0.position + [1e-3, 0, 0], ref0.rotation, ref0.omega,
                              ref0.velocity)  # fmt: skip
    one = prp3.spatial_track(robot, reference, 0.1, kp=100.0, kd=10.0, initial=start, samples=3)
    six = prp3.spatial_track(robot, reference, 0.1, kp=[100.0] * 6, kd=np.full(6, 10.0),
                             initial=start, samples=3)  # fmt: skip
    np.testing.assert_array_equal(one.error, six.error)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (
            {"kp": [1.0] * 5},
            r"kp must be a number or 6 numbers \(rx, ry, rz, x, y, z\), got shape \(5,\)",
        ),
        ({"kd": np.ones((2, 3))}, r"kd must be a number or 6 numbers .* got shape \(2, 3\)"),
        (
            {"kp": [1.0, 1.0, 1.0, -1.0, 1.0, 1.0]},
            r"x of kp must be non-negative \(1/s²\), got -1.0",
        ),
        ({"kd": [1.0, 1.0, math.inf, 1.0, 1.0, 1.0]}, r"rz of kd is not finite \(inf\)"),
        ({"kp": ["a"] * 6}, r"kp must be an array of real numbers"),
        ({"kd": [True] * 6}, r"kd must be an array of real numbers"),
        ({"kp": "400"}, r"kp must be a number"),
    ],
)
def test_bad_component_gains(kwargs, match) -> None:
    robot = prp3.hexapod()
    with pytest.raises(prp3.ParameterError, match=match):
        prp3.spatial_track(robot, _hexapod_reference(robot), 0.1, **kwargs)


@pytest.mark.slow
@settings(max_examples=4, deadline=None)
@given(
    kp=st.lists(st.floats(25.0, 400.0), min_size=6, max_size=6),
    ratio=st.lists(st.floats(0.2, 1.6), min_size=6, max_size=6),
    e0=st.lists(st.floats(-2e-3, 2e-3), min_size=6, max_size=6),
)
def test_component_gains_hypothesis(kp: list[float], ratio: list[float], e0: list[float]) -> None:
    """Random gains per component (underdamped) and errors: positions against each
    component's closed form to 1e-9 m, the rotation against scipy's exact loop to 1e-10 rad."""
    from scipy.spatial.transform import Rotation

    robot = prp3.hexapod()
    still = PlatformMotion.at_rest(robot.home_position)
    p_gain, error = np.array(kp), np.array(e0)
    d_gain = np.array(ratio) * np.sqrt(p_gain)
    start = PlatformMotion.of(
        [0.0], still.position - error[3:], Rotation.from_rotvec(-error[:3]).as_matrix()[None],
        np.zeros((1, 3)), np.zeros((1, 3)),
    )  # fmt: skip
    run = prp3.spatial_track(robot, lambda t: still, 0.3, kp=p_gain, kd=d_gain, initial=start,
                             samples=11)  # fmt: skip
    for c in range(3, 6):
        expected = _closed_form(run.t, error[c], 0.0, p_gain[c], d_gain[c])
        np.testing.assert_allclose(run.error[:, c], expected, rtol=0, atol=1e-9)
    exact = _exact_rotation_loop(run.t, error[:3], p_gain[:3], d_gain[:3])
    np.testing.assert_allclose(run.error[:, :3], exact, rtol=0, atol=1e-10)
