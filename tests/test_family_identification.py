"""Identification and excitation of a family robot (docs/family.md, docs/identification.md).

The regressor (built from the family kernel's fast route) is held against the
Newton–Euler route of :func:`prp3.family.family_inverse_dynamics` (its own
recursion, body by body) on random designs — random masses, centres of mass,
inertias, payloads, loads and gravities — and random motions.  The fit is held
to synthetic measurements of a known robot: exact without noise, on the
identification motion and on another one.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from numpy.typing import NDArray

from clitools import cli, one_line
from prp3.apps.base_parameters import FAMILY_FORCES, base_parameters
from prp3.apps.family_regressor import (
    FAMILY_PARAMETERS,
    family_known_forces,
    family_random_motion,
    family_regressor,
    family_standard_parameters,
)
from prp3.apps.identification import identified_robot, identify, robot_from_standard
from prp3.errors import ParameterError, SingularPoseError, TrajectoryError, UnreachablePoseError
from prp3.family import Body, FamilyRobot, PlatformBody, family_inverse_dynamics
from prp3.io.trajectory import read_trajectory
from prp3.model.motion import Motion, paper_motion
from prp3.model.parameters import Load, Payload
from prp3.model.robot import Robot
from strategies import FAMILY_ALLOWED, family_designs, family_motions

FloatArray = NDArray[np.float64]


def _reference(robot: FamilyRobot, motion: Motion) -> FloatArray:
    """The actuator efforts by the Newton–Euler route (not the regressor's fast route)."""
    return np.asarray(family_inverse_dynamics(robot, motion, "newton-euler").tau)


def _scale(tau: FloatArray) -> float:
    return 1.0 + float(np.abs(tau).max())


# ------------------------------------------------------------------ the regressor
@given(data=st.data())
def test_regressor_reproduces_the_efforts(data: st.DataObject) -> None:
    """``Y·π + τ_known`` is the Newton–Euler route's ``τ`` to 1e-10, any design and motion."""
    robot = data.draw(family_designs())
    motion = data.draw(family_motions(robot.home_poses.mean(axis=0)))
    try:
        tau = _reference(robot, motion)
    except (SingularPoseError, UnreachablePoseError):
        assume(False)
        raise
    Y = family_regressor(robot, motion)
    assert Y.tau.shape == (motion.samples, 3, len(FAMILY_PARAMETERS))
    predicted = Y.tau @ family_standard_parameters(robot) + family_known_forces(robot, motion)
    np.testing.assert_allclose(predicted, tau, rtol=0, atol=1e-10 * _scale(tau))


@given(data=st.data())
def test_columns_of_a_subset(data: st.DataObject) -> None:
    """The columns of chosen parameters, in their order, are those of the full regressor."""
    robot = FamilyRobot.default(*data.draw(st.sampled_from(FAMILY_ALLOWED)))
    chosen = data.draw(st.permutations(FAMILY_PARAMETERS).map(lambda p: tuple(p[:4])))
    motion = family_random_motion(robot, 5, data.draw(st.integers(0, 100)))
    full = family_regressor(robot, motion)
    part = family_regressor(robot, motion, chosen)
    assert part.parameters == chosen
    np.testing.assert_array_equal(
        part.tau, full.tau[..., [FAMILY_PARAMETERS.index(n) for n in chosen]]
    )


def test_one_sample_and_joint_values() -> None:
    """One sample loses the leading axis; ``q``, ``dq`` are the actuated joint's."""
    robot = FamilyRobot.default("3-RRR", 2)
    motion = paper_motion("rotation", 11)
    Y = family_regressor(robot, motion)
    kinematics = family_inverse_dynamics(robot, motion).kinematics
    np.testing.assert_allclose(Y.q, kinematics.q[..., 1], rtol=0, atol=1e-14)
    np.testing.assert_allclose(Y.dq, kinematics.dq[..., 1], rtol=0, atol=1e-14)
    single = Motion(
        t=motion.t[3], pose=motion.pose[3], velocity=motion.velocity[3],
        acceleration=motion.acceleration[3],
    )  # fmt: skip
    one = family_regressor(robot, single)
    assert one.tau.shape == (3, 12)
    np.testing.assert_allclose(one.tau, Y.tau[3], rtol=0, atol=1e-12)


def test_standard_parameters_by_hand() -> None:
    """``h = m·c``, ``J = I + m·|c|²`` about the frame's origin; the platform with its payload."""
    robot = replace(
        FamilyRobot.default("3-RPR"),
        link1=Body(2.0, (0.1, -0.2), 0.01, name="link1"),
        link2=Body(0.5, (0.0, 0.3), 0.02, name="link2"),
        platform=PlatformBody(3.0, 0.06),
        payload=Payload(1.5, (0.2, 0.1), 0.004),
    )
    values = dict(zip(FAMILY_PARAMETERS, family_standard_parameters(robot).tolist(), strict=True))
    expected = {
        "link1_mass": 2.0, "link1_moment_x": 0.2, "link1_moment_y": -0.4,
        "link1_inertia": 0.01 + 2.0 * 0.05, "link2_mass": 0.5, "link2_moment_x": 0.0,
        "link2_moment_y": 0.15, "link2_inertia": 0.02 + 0.5 * 0.09, "platform_mass": 4.5,
        "platform_moment_x": 0.3, "platform_moment_y": 0.15,
        "platform_inertia": 0.06 + 0.004 + 1.5 * 0.05,
    }  # fmt: skip
    assert values == pytest.approx(expected, rel=1e-14, abs=1e-15)


# ------------------------------------------------------------------ base parameters and the fit
def _nominal(truth: FamilyRobot) -> FamilyRobot:
    """The truth's geometry, gravity, load and payload mass; other inertial parameters wrong."""
    return replace(
        truth,
        link1=Body(1.0, (0.0, 0.0), 0.001, name="link1"),
        link2=Body(1.0, (0.0, 0.0), 0.001, name="link2"),
        platform=PlatformBody(2.0, 0.05),
        payload=replace(truth.payload, com=(0.0, 0.0)),
    )


@given(data=st.data())
def test_identification_recovers_the_efforts(data: st.DataObject) -> None:
    """Noise-free efforts: the base parameters, and the efforts of another motion, to 1e-9."""
    truth = data.draw(family_designs())
    seed = data.draw(st.integers(0, 1000))
    try:
        motion = family_random_motion(truth, 60, seed)
        other = family_random_motion(truth, 20, seed + 1)
        tau = _reference(truth, motion)
        tau_other = _reference(truth, other)
    except (ParameterError, SingularPoseError, UnreachablePoseError):
        assume(False)
        raise
    nominal = _nominal(truth)
    result = identify(nominal, motion, tau)
    assert result.base.forces == FAMILY_FORCES
    np.testing.assert_allclose(result.fitted, tau, rtol=0, atol=1e-9 * _scale(tau))
    truth_base = result.base.values(family_standard_parameters(truth))
    np.testing.assert_allclose(
        result.estimate, truth_base, rtol=0, atol=1e-9 * (1.0 + np.abs(truth_base).max())
    )
    W = family_regressor(nominal, other).tau[..., list(result.base.independent)]
    predicted = W @ result.estimate + family_known_forces(nominal, other)
    np.testing.assert_allclose(predicted, tau_other, rtol=0, atol=1e-9 * _scale(tau_other))


@pytest.mark.parametrize(("architecture", "actuated"), [("3-RPR", 1), ("3-RRR", 3), ("3-PRR", 2)])
def test_identified_robot_reproduces_the_efforts(architecture: str, actuated: int) -> None:
    """The family robot of the estimate has the measured efforts (Newton–Euler) to 1e-9."""
    truth = replace(
        FamilyRobot.default(architecture, actuated),
        link1=Body(1.3, (0.05, -0.02), 0.004, name="link1"),
        link2=Body(0.7, (-0.03, 0.04), 0.002, name="link2"),
        payload=Payload(0.4, (0.02, 0.01), 0.001),
        load=Load((3.0, -2.0), 0.5),
        gravity=(1.0, -9.0),
    )
    motion = family_random_motion(truth, 80, 3)
    tau = _reference(truth, motion)
    nominal = _nominal(truth)
    identified = identified_robot(nominal, identify(nominal, motion, tau))
    assert isinstance(identified.robot, FamilyRobot)
    assert identified.robot.leg == truth.leg and identified.robot.load == truth.load
    np.testing.assert_allclose(
        _reference(identified.robot, motion), tau, rtol=0, atol=1e-9 * _scale(tau)
    )


def test_fixed_parameters_are_subtracted() -> None:
    """Parameters not estimated keep the nominal values and their efforts are known."""
    truth = replace(FamilyRobot.default("3-RRR"), link1=Body(0.8, (0.1, 0.0), 0.003, name="link1"))
    motion = family_random_motion(truth, 60, 0)
    tau = _reference(truth, motion)
    chosen = tuple(name for name in FAMILY_PARAMETERS if not name.startswith("link1"))
    nominal = replace(truth, link2=Body(2.0, (0.0, 0.0), 0.01, name="link2"))
    result = identify(nominal, motion, tau, chosen)
    assert set(result.fixed) == {n for n in FAMILY_PARAMETERS if n.startswith("link1")}
    np.testing.assert_allclose(result.fitted, tau, rtol=0, atol=1e-9 * _scale(tau))


def test_robot_from_standard_round_trip() -> None:
    """The standard parameters of another robot give that robot's bodies back."""
    nominal = replace(FamilyRobot.default("3-RPR"), payload=Payload(0.5, (0.0, 0.0), 0.002))
    other = replace(
        nominal,
        link1=Body(1.2, (0.03, 0.01), 0.004, name="link1"),
        link2=Body(0.4, (-0.02, 0.05), 0.001, name="link2"),
        platform=PlatformBody(2.5, 0.04),
        payload=Payload(0.5, (0.01, -0.03), 0.002),
    )
    values = dict(zip(FAMILY_PARAMETERS, family_standard_parameters(other).tolist(), strict=True))
    rebuilt = robot_from_standard(nominal, values)
    assert isinstance(rebuilt, FamilyRobot)
    for part in ("link1", "link2"):
        got, want = getattr(rebuilt, part), getattr(other, part)
        assert got.mass == pytest.approx(want.mass, rel=1e-14)
        assert got.com == pytest.approx(want.com, rel=1e-12)
        assert got.inertia == pytest.approx(want.inertia, rel=1e-10)
    assert rebuilt.platform.mass == pytest.approx(2.5, rel=1e-14)
    assert rebuilt.platform.inertia == pytest.approx(0.04, rel=1e-10)
    assert rebuilt.payload.com == pytest.approx((0.01, -0.03), rel=1e-12)


# ------------------------------------------------------------------ misuse
def test_misuse_is_refused() -> None:
    robot = FamilyRobot.default("3-RPR")
    motion = family_random_motion(robot, 60, 0)
    with pytest.raises(ParameterError, match="piston_mass"):
        family_regressor(robot, motion, ("piston_mass",))
    with pytest.raises(ParameterError, match="FamilyRobot"):
        family_regressor(Robot(), motion)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="FamilyRobot"):
        family_standard_parameters(Robot())  # type: ignore[arg-type]
    loaded = replace(motion, load=np.zeros((60, 3)))
    with pytest.raises(TrajectoryError, match="time-varying load"):
        family_regressor(robot, loaded)
    with pytest.raises(ParameterError, match="samples"):
        family_random_motion(robot, 0, 0)
    with pytest.raises(ParameterError, match="seed"):
        family_random_motion(robot, 5, -1)
    with pytest.raises(ParameterError, match="progress"):
        family_regressor(robot, motion, progress=3)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="motion must be"):
        family_known_forces(robot, None)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="a single string"):
        family_regressor(robot, motion, "platform_mass")
    with pytest.raises(ParameterError, match="forces must be"):
        base_parameters(robot, ("f21y",))
    tau = _reference(robot, motion)
    with pytest.raises(TrajectoryError, match=r"tau must have shape \(60, 3\)"):
        identify(robot, motion, tau[:-1])
    with pytest.raises(TrajectoryError, match="too few"):
        short = family_random_motion(robot, 8, 0)
        identify(robot, short, _reference(robot, short))
    with pytest.raises(ParameterError, match="link_mass"):
        identify(robot, motion, tau, ("link_mass",))
    result = identify(robot, motion, tau)
    with pytest.raises(ParameterError, match="nominal is a 3-PRP"):
        identified_robot(Robot(), result)
    with pytest.raises(ParameterError, match=r"m1 = -1\.0 kg"):
        robot_from_standard(robot, {"link1_mass": -1.0})
    with pytest.raises(ParameterError, match="piston_mass"):
        robot_from_standard(robot, {"piston_mass": 1.0})
    still = Motion(
        t=motion.t, pose=np.broadcast_to(motion.pose[0], motion.pose.shape).copy(),
        velocity=np.zeros_like(motion.pose), acceleration=np.zeros_like(motion.pose),
    )  # fmt: skip
    with pytest.raises(TrajectoryError, match="does not excite"):
        identify(robot, still, _reference(robot, still))


# ------------------------------------------------------------------ prp3 excite / prp3 identify
def _measurements(path: Path, motion: Motion, tau: FloatArray, names: tuple[str, ...]) -> None:
    header = ("t", "x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi", *names)
    rows = np.column_stack([motion.t, motion.pose, motion.velocity, motion.acceleration, tau])
    lines = [",".join(header), *(",".join(repr(float(v)) for v in row) for row in rows)]
    path.write_text("\n".join(lines) + "\n")


def test_excite_then_identify_a_family_robot(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """``prp3 excite`` designs a motion of a 3-RPR, ``prp3 identify`` recovers its efforts."""
    truth = replace(
        FamilyRobot.default("3-RPR", 2),
        link1=Body(1.3, (0.05, -0.02), 0.004, name="link1"),
        link2=Body(0.7, (-0.03, 0.04), 0.002, name="link2"),
        payload=Payload(0.4, (0.02, 0.01), 0.001),
    )
    nominal = _nominal(truth)
    robot_file = tmp_path / "nominal.toml"
    robot_file.write_text(nominal.to_toml())
    status, out, err = cli(
        capsys, "excite", "--robot", robot_file, "--output", tmp_path / "ex",
        "--iterations", "3", "--samples", "101",
    )  # fmt: skip
    assert status == 0, err
    assert "3-RPR" in out and "base regressor of tau" in out
    motion = read_trajectory(tmp_path / "ex" / "trajectory.csv", crossing=False).motion
    assert motion.samples == 101
    centre = truth.home_poses.mean(axis=0)
    assert np.abs(motion.pose[:, :2] - centre[:2]).max() <= 0.2 * truth.leg.scale * (1 + 1e-9)
    assert np.abs(motion.pose[:, 2] - centre[2]).max() <= 0.5 * (1 + 1e-9)
    tau = _reference(truth, motion)
    measured = tmp_path / "m.csv"
    _measurements(measured, motion, tau, ("tau_A", "tau_B", "tau_C"))
    status, out, err = cli(
        capsys, "identify", "--robot", robot_file, "--measurements", measured,
        "--output", tmp_path / "id",
    )  # fmt: skip
    assert status == 0, err
    assert "base parameters of tau" in out
    assert sorted(p.name for p in (tmp_path / "id").iterdir() if p.name[0] != ".") == [
        "identification.png", "parameters.csv", "robot.toml",
    ]  # fmt: skip
    identified = FamilyRobot.from_toml(tmp_path / "id" / "robot.toml")
    assert identified.architecture == "3-RPR" and identified.leg == truth.leg
    np.testing.assert_allclose(_reference(identified, motion), tau, rtol=0, atol=1e-9 * _scale(tau))
    rows = (tmp_path / "id" / "parameters.csv").read_text().splitlines()
    assert rows[0] == "name,combination,estimate,std"
    assert len(rows) - 1 == base_parameters(nominal).count


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["identify", "--measurements", "m.csv", "--friction", "viscous"], "no friction model"),
        (
            ["identify", "--measurements", "f10.csv"],
            "unknown column 'f10_A' (expected t, x, y, phi, tau_A",
        ),
        (["identify", "--measurements", "load.csv"], "load.csv: the load columns fx, fy, mz"),
        (["identify", "--measurements", "far.csv"], "far.csv:32: sample 30"),
        (["excite", "--rotation", "4"], "rotation must be in (0, pi)"),
        (["excite", "--samples", "20"], "too few to identify"),
    ],
)
def test_family_bad_input(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str], message: str
) -> None:
    """Exit 2, one line naming the problem, nothing written."""
    robot = FamilyRobot.default("3-RPR")
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text(robot.to_toml())
    motion = family_random_motion(robot, 60, 0)
    tau = _reference(robot, motion)
    _measurements(tmp_path / "m.csv", motion, tau, ("tau_A", "tau_B", "tau_C"))
    _measurements(tmp_path / "f10.csv", motion, tau, ("f10_A", "f10_B", "f10_C"))
    loads = np.column_stack([tau, np.zeros((60, 3))])
    _measurements(
        tmp_path / "load.csv", motion, loads, ("tau_A", "tau_B", "tau_C", "fx", "fy", "mz")
    )
    pose = motion.pose.copy()
    pose[30, 0] = 5.0  # out of reach
    far = replace(motion, pose=pose)
    _measurements(tmp_path / "far.csv", far, tau, ("tau_A", "tau_B", "tau_C"))
    argv = [a if not a.endswith(".csv") else str(tmp_path / a) for a in argv]
    status, out, err = cli(capsys, *argv, "--robot", robot_file, "--output", tmp_path / "out")
    assert status == 2 and out == ""
    assert message in one_line(err)
    assert not (tmp_path / "out").exists()


def test_noise_within_the_standard_deviations() -> None:
    """Seeded noise on the efforts: every base parameter within 4 standard deviations."""
    truth = replace(
        FamilyRobot.default("3-RRR", 1),
        link1=Body(1.3, (0.05, -0.02), 0.004, name="link1"),
        link2=Body(0.7, (-0.03, 0.04), 0.002, name="link2"),
        payload=Payload(0.4, (0.02, 0.01), 0.001),
    )
    motion = family_random_motion(truth, 400, 5)
    tau = _reference(truth, motion)
    rng = np.random.default_rng(7)
    noisy = tau + rng.normal(size=tau.shape) * 0.01 * np.abs(tau).max(axis=0)
    done: list[tuple[int, int]] = []
    result = identify(_nominal(truth), motion, noisy, progress=lambda d, n: done.append((d, n)))
    assert done[-1] == (400, 400)
    truth_base = result.base.values(family_standard_parameters(truth))
    assert (np.abs(result.estimate - truth_base) <= 4.0 * result.std).all()
    assert (result.std > 0.0).all()
