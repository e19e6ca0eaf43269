"""The recursive Newton–Euler route and the compiled kernel (docs/spatial.md §19).

Both are held against route (b) solved as one linear system of every unknown
(:func:`prp3.spatial.newton_euler.newton_euler_dynamics`, the reference) to 1e-10,
on random designs of the three architectures and random states (hypothesis); the
compiled kernel's joint values, rates and measures against the numpy kinematics;
refused states raise the numpy route's error.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import prp3
from prp3.errors import SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.newton_euler import newton_euler_dynamics
from spatial_strategies import deltas, hexapods, rps_robots

TOLERANCE = 1e-10


def _close(reference: np.ndarray, value: np.ndarray) -> float:
    return float(np.abs(reference - value).max() / max(np.abs(reference).max(), 1e-300))


@st.composite
def states(draw: st.DrawFn, robot: SpatialRobot, n: int = 4) -> PlatformMotion:
    """``n`` random states near home, completed onto the legs for fewer than 6 DOF."""

    def block(scale: float) -> np.ndarray:
        return np.array([[draw(st.floats(-scale, scale)) for _ in range(3)] for _ in range(n)])

    position = np.array(robot.home_position) + block(0.1 * robot.scale) * [1, 1, 0.5]
    angles = block(0.08)
    if robot.legs[0].pattern == "RUU":
        angles[:] = 0.0
    rotation = Rotation.from_euler("xyz", angles).as_matrix()
    motion = PlatformMotion.of(np.arange(n, dtype=np.float64), position, rotation,
                               block(2.0), block(0.05), block(50.0), block(3.0))  # fmt: skip
    return prp3.complete_motion(robot, motion)


def _check(robot: SpatialRobot, motion: PlatformMotion) -> None:
    try:
        reference = newton_euler_dynamics(robot, motion)
    except (UnreachablePoseError, SingularPoseError):
        return  # a drawn state out of reach: the entries' refusals are tested below
    kin = prp3.spatial_kinematics(robot, motion)
    fast = prp3.recursive_newton_euler(robot, motion)
    compiled = prp3.compile_spatial(robot).solve_batch(motion)
    for name in ("tau", "force", "moment"):
        assert _close(getattr(reference, name), getattr(fast, name)) < TOLERANCE, name
        assert _close(getattr(reference, name), getattr(compiled, name)) < TOLERANCE, name
    for name in ("q", "dq", "ddq", "leg_measure", "parallel_measure"):
        assert _close(getattr(kin, name), getattr(compiled, name)) < TOLERANCE, name
    one = prp3.compile_spatial(robot).solve(
        motion.position[0], motion.rotation[0], motion.omega[0], motion.velocity[0],
        motion.alpha[0], motion.acceleration[0],
    )  # fmt: skip
    assert _close(reference.force[0], one.force) < TOLERANCE
    assert _close(reference.tau[0], one.tau) < TOLERANCE


@settings(max_examples=25, deadline=None)
@given(hexapods(), st.data())
def test_the_hexapod_routes_equal_the_system_route(
    robot: SpatialRobot, data: st.DataObject
) -> None:
    _check(robot, data.draw(states(robot)))


@settings(max_examples=15, deadline=None)
@given(rps_robots(), st.data())
def test_the_3rps_routes_equal_the_system_route(robot: SpatialRobot, data: st.DataObject) -> None:
    _check(robot, data.draw(states(robot)))


@settings(max_examples=15, deadline=None)
@given(deltas(), st.data())
def test_the_delta_routes_equal_the_system_route(robot: SpatialRobot, data: st.DataObject) -> None:
    _check(robot, data.draw(states(robot)))


def test_the_built_in_motions_agree() -> None:
    for robot, name in (
        (prp3.hexapod(), "tilt"),
        (prp3.three_rps(), "tilt"),
        (prp3.delta(), "circle"),
    ):
        motion = prp3.complete_motion(robot, prp3.spatial_motion(robot, name, 31))
        _check(robot, motion)


def test_a_batch_large_enough_for_threads_equals_one_thread() -> None:
    robot = prp3.hexapod()
    motion = prp3.spatial_motion(robot, "tilt", 5000)
    kernel = prp3.compile_spatial(robot)
    threaded = kernel.solve_batch(motion)
    arrays = [np.ascontiguousarray(x) for x in (motion.position, motion.rotation, motion.omega,
              motion.velocity, motion.alpha, motion.acceleration)]  # fmt: skip
    single = kernel.raw(*arrays, threads=False)
    assert np.array_equal(threaded.force, single.force) and not threaded.status.any()


def test_refusals_are_the_numpy_routes() -> None:
    robot = prp3.hexapod()
    kernel = prp3.compile_spatial(robot)
    zero = np.zeros(3)
    with pytest.raises(UnreachablePoseError, match="P2 = "):
        kernel.solve([0.0, 0.0, 0.2], np.eye(3), zero, zero, zero, zero)
    with pytest.raises(TrajectoryError, match="position"):
        kernel.solve([0.0, 0.0, np.nan], np.eye(3), zero, zero, zero, zero)
    with pytest.raises(TrajectoryError, match="rotation"):
        kernel.solve(robot.home_position, 2.0 * np.eye(3), zero, zero, zero, zero)
    with pytest.raises(TrajectoryError, match="shape"):
        kernel.solve(robot.home_position, np.eye(3), np.zeros(2), zero, zero, zero)
    p = np.array([robot.home_position, [0.0, 0.0, 0.2]])
    with pytest.raises(UnreachablePoseError, match="sample 1"):
        kernel.solve_batch(p, np.stack([np.eye(3)] * 2), *(np.zeros((2, 3)),) * 4)
    rps = prp3.three_rps()
    with pytest.raises(UnreachablePoseError, match="degrees of freedom"):
        prp3.compile_spatial(rps).solve([0.01, 0.0, 0.1], np.eye(3), zero, zero, zero, zero)
