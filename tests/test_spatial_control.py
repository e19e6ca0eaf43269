"""Computed-torque control of the spatial robots (docs/spatial.md §23)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import prp3
from prp3 import PlatformMotion
from prp3.errors import ParameterError

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
    [(prp3.hexapod, "heave", 3e-5, 1e-12), (prp3.three_rps, "tilt", 2e-5, 5e-4)],
)
def test_mujoco_plant_agrees_with_prp3_plant(make, motion, position_tol, rotation_tol) -> None:
    """From a 2 mm error: MuJoCo (RK4, 1 ms steps, efforts held over a step, its loop
    closures soft equalities of solref (2 ms, 1)) against prp3's exact plant.  The
    tolerance (1.5 % of the initial error; rotation: the 3-RPS's parasitic turn) is
    MuJoCo's: its soft closures and the held efforts."""
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


def test_the_delta_on_the_mujoco_plant_is_refused_naming_the_plant() -> None:
    from prp3 import delta, spatial_track

    robot = delta()
    with pytest.raises(ParameterError, match=r"plant='mujoco' is refused for the 3-RUU"):
        spatial_track(robot, lambda t: None, 0.1, plant="mujoco")  # type: ignore[arg-type,return-value]
