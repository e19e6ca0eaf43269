"""Platform motions: validation with precise messages, the paper's law (eq. 4), indexing."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from prp3 import Motion, TrajectoryError
from prp3.model.motion import PAPER_DURATION, PAPER_MOTIONS, law_motion, paper_motion
from strategies import FD_FIRST, FD_OFFSETS, FD_SECOND


def _motion(n: int = 4, **override: Any) -> Motion:
    fields: dict[str, Any] = {
        "t": np.arange(float(n)),
        "pose": np.zeros((n, 3)),
        "velocity": np.zeros((n, 3)),
        "acceleration": np.zeros((n, 3)),
    }
    fields.update(override)
    return Motion(**fields)


# ------------------------------------------------------------------ valid motions
def test_batch_and_single_sample_shapes() -> None:
    batch = _motion(5)
    assert batch.samples == 5 and batch.t.shape == (5,) and batch.pose.shape == (5, 3)
    single = Motion(
        t=np.array(0.5), pose=np.ones(3), velocity=np.zeros(3), acceleration=np.zeros(3)
    )
    assert single.samples == 1 and single.t.shape == () and single.pose.shape == (3,)
    one = _motion(1)
    assert one.samples == 1 and one.pose.shape == (1, 3)


def test_arrays_are_float64_read_only_copies() -> None:
    pose = np.zeros((3, 3), dtype=np.int64)
    motion = _motion(3, pose=pose, t=[0, 1, 2])
    for name in ("t", "pose", "velocity", "acceleration"):
        array = getattr(motion, name)
        assert array.dtype == np.float64, name
        assert not array.flags.writeable, name
    pose[0, 0] = 7  # the caller's array is not shared
    assert motion.pose[0, 0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        motion.pose[0, 0] = 1.0


def test_indexing() -> None:
    motion = law_motion([0.01, 0.02, 0.3], samples=6)
    single = motion[2]
    assert single.t.shape == () and single.pose.shape == (3,)
    np.testing.assert_array_equal(single.pose, motion.pose[2])
    np.testing.assert_array_equal(single.acceleration, motion.acceleration[2])
    part = motion[1:4]
    assert part.samples == 3 and float(part.t[0]) == float(motion.t[1])
    with pytest.raises(TrajectoryError, match="single-sample motion cannot be indexed"):
        single[0]


def test_at_rest() -> None:
    still = Motion.at_rest([0.01, -0.02, 0.3])
    assert still.t.shape == () and float(still.t) == 0.0
    np.testing.assert_array_equal(still.pose, [0.01, -0.02, 0.3])
    np.testing.assert_array_equal(still.velocity, 0.0)
    np.testing.assert_array_equal(still.acceleration, 0.0)
    batch = Motion.at_rest(np.zeros((3, 3)), t=[0.0, 1.0, 2.0])
    assert batch.samples == 3 and batch.velocity.shape == (3, 3)
    with pytest.raises(TrajectoryError, match="pose must have shape"):
        Motion.at_rest([0.0, 0.0])


# ------------------------------------------------------------------ refusals
@pytest.mark.parametrize(
    ("override", "fragment"),
    [
        ({"t": np.zeros((2, 2))}, "t must have shape (N,) or ()"),
        ({"pose": np.zeros((4, 2))}, "pose must have shape (4, 3) to match t, got (4, 2)"),
        ({"velocity": np.zeros((3, 3))}, "velocity must have shape (4, 3) to match t, got (3, 3)"),
        ({"acceleration": np.zeros(3)}, "acceleration must have shape (4, 3) to match t, got (3,)"),
        ({"t": np.array(0.0)}, "pose must have shape (3,) to match t, got (4, 3)"),
        ({"pose": "abc"}, "pose must be an array of real numbers"),
        ({"velocity": [[0, 0, 0]] * 3 + [[0, 0]]}, "velocity must be an array of real numbers"),
    ],
)
def test_wrong_shapes_are_refused(override: dict[str, Any], fragment: str) -> None:
    with pytest.raises(TrajectoryError) as info:
        _motion(4, **override)
    assert fragment in str(info.value), str(info.value)


@pytest.mark.parametrize("name", ["pose", "velocity", "acceleration"])
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_values_are_refused(name: str, bad: float) -> None:
    array = np.zeros((4, 3))
    array[2, 1] = bad
    with pytest.raises(TrajectoryError) as info:
        _motion(4, **{name: array})
    component = {"pose": "y", "velocity": "dy", "acceleration": "ddy"}[name]
    assert str(info.value) == f"motion: sample 2: {component} of {name} is not finite ({bad!r})"
    assert (info.value.sample, info.value.subject) == (2, "motion")


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_non_finite_times_are_refused(bad: float) -> None:
    with pytest.raises(TrajectoryError, match=rf"^motion: sample 1: t is not finite \({bad!r}\)$"):
        _motion(3, t=[0.0, bad, 2.0])


@pytest.mark.parametrize(
    ("t", "fragment"),
    [
        ([0.0, 1.0, 1.0, 2.0], "t[2] = 1.0 follows t[1] = 1.0"),
        ([0.0, 1.0, 0.5, 2.0], "t[2] = 0.5 follows t[1] = 1.0"),
        ([3.0, 2.0, 1.0, 0.0], "t[1] = 2.0 follows t[0] = 3.0"),
    ],
)
def test_time_must_increase_strictly(t: list[float], fragment: str) -> None:
    with pytest.raises(TrajectoryError) as info:
        _motion(4, t=t)
    assert "strictly increasing" in str(info.value) and fragment in str(info.value)


# ------------------------------------------------------------------ the paper's law
def test_law_of_motion_eq4_by_hand() -> None:
    # q = q*(1 − cos(πt/3)): at t = 0 rest at 0; t = 1.5 s q = q*, q̇ = q*·π/3, q̈ = 0;
    # t = 3 s rest at 2q*, q̈ = −q*(π/3)².
    star = np.array([0.01, 0.025, math.pi / 12])
    motion = law_motion(star, samples=301)
    assert motion.samples == 301 and float(motion.t[-1]) == 3.0
    np.testing.assert_allclose(np.diff(motion.t), 0.01, rtol=1e-12)
    w = math.pi / 3
    for index, pose, velocity, acceleration in [
        (0, 0.0 * star, 0.0 * star, star * w * w),
        (150, star, star * w, 0.0 * star),
        (300, 2 * star, 0.0 * star, -star * w * w),
    ]:
        np.testing.assert_allclose(motion.pose[index], pose, rtol=0, atol=1e-15)
        np.testing.assert_allclose(motion.velocity[index], velocity, rtol=0, atol=1e-15)
        np.testing.assert_allclose(motion.acceleration[index], acceleration, rtol=0, atol=1e-15)


@given(
    star=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)),
    duration=st.floats(0.5, 5.0),
)
def test_law_derivatives_against_finite_differences(
    star: tuple[float, float, float], duration: float
) -> None:
    # The velocity and acceleration columns are the derivatives of the pose law
    # q*(1 − cos(πt/3)) (eq. 4): 6th-order central differences at every sample.
    h = 1e-3
    motion = law_motion(star, samples=5, duration=duration)
    np.testing.assert_allclose(np.diff(motion.t), duration / 4, rtol=1e-12)
    shifted = motion.t[:, None, None] + h * FD_OFFSETS[None, :, None]  # (5, 7, 1)
    law = np.array(star) * (1 - np.cos(math.pi / 3 * shifted))  # (5, 7, 3)
    np.testing.assert_allclose(motion.pose, law[:, 3], rtol=1e-14, atol=1e-15)
    velocity = np.einsum("j,njk->nk", FD_FIRST, law) / h
    acceleration = np.einsum("j,njk->nk", FD_SECOND, law) / h**2
    np.testing.assert_allclose(motion.velocity, velocity, rtol=0, atol=1e-11)
    np.testing.assert_allclose(motion.acceleration, acceleration, rtol=0, atol=1e-8)


@pytest.mark.parametrize(
    ("name", "end"), [("vertical", (0.0, 0.05, 0.0)), ("rotation", (0.0, 0.0, math.pi / 6))]
)
def test_paper_motions(name: str, end: tuple[float, float, float]) -> None:
    # docs/model.md: 301 samples over [0, 3] s; vertical y* = 0.025 m, rotation φ* = π/12;
    # both end at 2·q* at rest.
    motion = paper_motion(name)
    assert motion.samples == 301 and PAPER_DURATION == 3.0
    assert float(motion.t[0]) == 0.0 and float(motion.t[-1]) == 3.0
    np.testing.assert_allclose(motion.pose[-1], end, rtol=0, atol=1e-15)
    np.testing.assert_allclose(motion.velocity[[0, -1]], 0.0, atol=1e-15)
    moving = [k for k in range(3) if end[k] != 0.0]
    still = [k for k in range(3) if end[k] == 0.0]
    assert np.all(motion.pose[:, still] == 0.0)
    assert np.all(np.diff(motion.pose[:, moving], axis=0) > 0.0)  # monotone rise
    assert paper_motion(name, samples=11).samples == 11
    assert PAPER_MOTIONS[name] == tuple(0.5 * value for value in end)


def test_unknown_paper_motion_is_refused() -> None:
    with pytest.raises(TrajectoryError, match=r"unknown motion 'spiral'.*'vertical'.*'rotation'"):
        paper_motion("spiral")


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"amplitude": [0.0, 0.0]}, "amplitude must have shape (3,), got (2,)"),
        ({"amplitude": [0.0, math.nan, 0.0]}, "motion: y* of amplitude is not finite (nan)"),
        ({"amplitude": "abc"}, "amplitude must be an array of real numbers"),
        ({"samples": 1}, "samples must be an integer from 2 to 1e+09, got 1"),
        ({"samples": 10.0}, "samples must be an integer from 2 to 1e+09, got 10.0"),
        ({"samples": True}, "samples must be an integer from 2 to 1e+09, got True"),
        ({"duration": 0.0}, "duration must be a positive finite number (s), got 0.0"),
        ({"duration": -3.0}, "duration must be a positive finite number (s), got -3.0"),
        ({"duration": math.inf}, "duration must be a finite number, got inf"),
        ({"duration": math.nan}, "duration must be a finite number, got nan"),
    ],
)
def test_law_arguments_are_validated(kwargs: dict[str, Any], fragment: str) -> None:
    arguments: dict[str, Any] = {"amplitude": [0.0, 0.025, 0.0]} | kwargs
    with pytest.raises(TrajectoryError) as info:
        law_motion(**arguments)
    assert fragment in str(info.value), str(info.value)
