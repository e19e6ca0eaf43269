"""Forward dynamics of the family: the equations of motion from the inverse dynamics.

Checks: the forward solution driven by the inverse dynamics' efforts (from the
path-following route, or Newton–Euler) reproduces the motion; ``τ = A·ẍ + b``
holds against the independent Newton–Euler route at random states; the
energy balance ``∫(Σ p + P_ext) dt = Δ(T + V)`` holds along a free run.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import simpson

from clitools import cli, one_line
from prp3.errors import Prp3Error
from prp3.family import ARCHITECTURES, FamilyRobot, family_inverse_dynamics, family_kinematics
from prp3.family.forward import family_energy, family_forward_dynamics, platform_dynamics
from prp3.model.motion import Motion, law_at
from prp3.model.parameters import Load, Payload


def _law(t: float, amplitude: list[float]) -> Motion:
    return law_at(amplitude, [t])


AMPLITUDE = [0.01, 0.025, 0.1]


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_forward_reproduces_the_motion_of_the_inverse_dynamics(architecture: str) -> None:
    robot = replace(FamilyRobot.default(architecture), payload=Payload(0.5, (0.02, 0.01), 1e-3))

    def efforts(t: float) -> np.ndarray:
        return np.asarray(family_inverse_dynamics(robot, _law(t, AMPLITUDE)).tau[0])

    times = np.linspace(0.0, 0.6, 7)
    planned = law_at(AMPLITUDE, times)
    result = family_forward_dynamics(
        robot, None, efforts, times, planned.pose[0], planned.velocity[0], rtol=1e-11, atol=1e-13
    )
    assert result.status == "completed"
    np.testing.assert_allclose(result.motion.pose, planned.pose, atol=1e-9)
    np.testing.assert_allclose(result.motion.velocity, planned.velocity, atol=1e-8)
    assert result.solution is not None
    np.testing.assert_allclose(
        result.solution.tau, [efforts(t) for t in times.tolist()], rtol=1e-7, atol=1e-7
    )


@settings(max_examples=10, deadline=None)
@given(
    architecture=st.sampled_from(ARCHITECTURES),
    state=st.lists(st.floats(-1.0, 1.0), min_size=9, max_size=9),
)
def test_equations_of_motion_against_newton_euler(architecture: str, state: list[float]) -> None:
    robot = replace(FamilyRobot.default(architecture), gravity=(1.5, -9.0))
    pose = np.array(state[:3]) * [0.03, 0.03, 0.2]
    velocity = np.array(state[3:6]) * [0.2, 0.2, 1.0]
    acceleration = np.array(state[6:]) * [2.0, 2.0, 5.0]
    a, b = platform_dynamics(robot, pose, velocity)
    motion = Motion(t=np.array(0.0), pose=pose, velocity=velocity, acceleration=acceleration)
    expected = family_inverse_dynamics(robot, motion, method="newton-euler").tau
    np.testing.assert_allclose(a @ acceleration + b, expected, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("architecture", ["3-RRR", "3-RPR", "3-PPR", "3-RRP"])
def test_energy_balance_of_a_free_run(architecture: str) -> None:
    robot = replace(
        FamilyRobot.default(architecture),
        payload=Payload(0.4, (0.03, -0.02), 2e-3),
        load=Load((1.5, -2.0), 0.3),
    )
    rest = family_inverse_dynamics(robot, Motion.at_rest([0.0, 0.0, 0.0])).tau

    def efforts(t: float) -> np.ndarray:
        return np.asarray(rest * (1.0 + 0.05 * math.sin(5.0 * t)) + 0.2 * math.cos(3.0 * t))

    times = np.linspace(0.0, 0.4, 401)
    result = family_forward_dynamics(
        robot, None, efforts, times, [0.0, 0.0, 0.0], [0.02, -0.01, 0.1], rtol=1e-12, atol=1e-14
    )
    assert result.status == "completed"
    solution = result.solution
    assert solution is not None
    kinetic, potential = family_energy(solution.kinematics)
    energy = kinetic + potential
    motion = result.motion
    external = motion.velocity[:, :2] @ np.asarray(robot.load.force)
    external = external + robot.load.moment * motion.velocity[:, 2]
    power = solution.power.sum(axis=-1) + external
    work = simpson(power, x=motion.t)
    assert abs(work) > 1e-3  # the balance is not trivial
    assert work == pytest.approx(energy[-1] - energy[0], rel=1e-8, abs=1e-10)


def test_energy_is_the_one_of_the_bodies() -> None:
    """T from finite differences of every mass centre's position (independent of the rates)."""
    robot = FamilyRobot.default("3-RRR")
    h = 1e-6
    t = np.array([0.5 - h, 0.5, 0.5 + h])
    motion = law_at(AMPLITUDE, t)
    kin = family_kinematics(robot, motion)
    from prp3.family import leg_chain
    from prp3.family.chain import SIGMA

    frames = leg_chain(robot.types, robot.leg.placements, SIGMA[None, :], kin.q)
    kinetic = 0.0
    for k, body in ((0, robot.link1), (1, robot.link2)):
        angle = frames.angle[..., k]
        c, s = np.cos(angle), np.sin(angle)
        com = frames.origin[..., k, :] + np.stack(
            [c * body.com[0] - s * body.com[1], s * body.com[0] + c * body.com[1]], axis=-1
        )
        v = (com[2] - com[0]) / (2 * h)
        w = (angle[2] - angle[0]) / (2 * h)
        kinetic += float((0.5 * body.mass * (v * v).sum(-1) + 0.5 * body.inertia * w * w).sum())
    vg = (motion.pose[2] - motion.pose[0]) / (2 * h)
    kinetic += 0.5 * robot.platform.mass * float(vg[:2] @ vg[:2])
    kinetic += 0.5 * robot.platform.inertia * float(vg[2] ** 2)
    computed, _ = family_energy(kin)
    assert computed[1] == pytest.approx(kinetic, rel=1e-7)


def test_bad_inputs_are_named() -> None:
    robot = FamilyRobot.default("3-RRR")
    with pytest.raises(Prp3Error, match=r"efforts must have shape \(2, 3\)"):
        family_forward_dynamics(
            robot, [0.0, 1.0], np.zeros((2, 2)), [0.0, 1.0], [0, 0, 0], [0, 0, 0]
        )
    with pytest.raises(Prp3Error, match="outside the efforts"):
        family_forward_dynamics(
            robot, [0.0, 1.0], np.zeros((2, 3)), [0.0, 2.0], [0, 0, 0], [0, 0, 0]
        )
    massless = replace(
        robot, link1=replace(robot.link1, mass=0.0, inertia=0.0),
        link2=replace(robot.link2, mass=0.0, inertia=0.0),
        platform=replace(robot.platform, mass=0.0, inertia=0.0),
    )  # fmt: skip
    with pytest.raises(Prp3Error, match="equations of motion of this 3-RRR are singular"):
        family_forward_dynamics(
            massless, [0.0, 1.0], np.zeros((2, 3)), [0.0, 1.0], [0, 0, 0], [0, 0, 0]
        )
    with pytest.raises(Prp3Error, match="cannot reach"):
        family_forward_dynamics(
            robot, [0.0, 1.0], np.zeros((2, 3)), [0.0, 1.0], [0.5, 0.5, 0.0], [0, 0, 0]
        )


def test_a_run_into_a_singularity_stops_there() -> None:
    """3-RRR, no gravity, moving fast to the edge of its reach: the event stops it."""
    robot = replace(FamilyRobot.default("3-RRR"), gravity=(0.0, 0.0))
    result = family_forward_dynamics(
        robot, [0.0, 2.0], np.zeros((2, 3)), np.linspace(0.0, 2.0, 21), [0, 0, 0], [0.3, 0.0, 0.0]
    )
    assert result.status == "singular"
    assert "stopped at t" in result.message
    assert result.motion.t[-1] < 2.0


def _read(path: Path) -> dict[str, np.ndarray]:
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    values = np.array([line.split(",") for line in lines[1:]], dtype=np.float64)
    return {name: values[:, i] for i, name in enumerate(header)}


def test_cli_forward_of_a_family_robot(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-PRR"\n')
    status, _, err = cli(
        capsys, "simulate", "--robot", robot_file, "--motion", "vertical", "--samples", "61",
        "--output", tmp_path / "sim",
    )  # fmt: skip
    assert status == 0, err
    planned = _read(tmp_path / "sim" / "results.csv")
    efforts = tmp_path / "efforts.csv"
    keep = planned["t"] <= 1.0
    rows = ["t,tau_A,tau_B,tau_C"] + [
        ",".join(repr(float(planned[c][i])) for c in ("t", "tau_A", "tau_B", "tau_C"))
        for i in np.flatnonzero(keep)
    ]
    efforts.write_text("\n".join(rows) + "\n")
    status, out, err = cli(
        capsys, "forward", "--robot", robot_file, "--forces", efforts, "--output", tmp_path / "fw"
    )
    assert status == 0, err
    assert "3-PRR" in out.splitlines()[0]
    table = _read(tmp_path / "fw" / "results.csv")
    assert len(table) == 64
    np.testing.assert_allclose(table["y"], planned["y"][keep], atol=1e-6)  # spline of 21 samples
    np.testing.assert_allclose(table["tau_A"], planned["tau_A"][keep], rtol=1e-9, atol=1e-9)
    status, out, err = cli(
        capsys, "forward", "--robot", robot_file, "--forces", tmp_path / "sim" / "results.csv",
        "--output", tmp_path / "fw2", "--samples", "5",
    )  # fmt: skip
    assert status == 0, err
    assert "largest drift" in out


def test_cli_forward_bad_efforts_file(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-RRR"\n')
    efforts = tmp_path / "efforts.csv"
    efforts.write_text("t,f10_A,f10_B,f10_C\n0,1,2,3\n1,1,2,3\n")
    status, out, err = cli(
        capsys, "forward", "--robot", robot_file, "--forces", efforts, "--output", tmp_path / "fw"
    )
    line = one_line(err)
    assert status == 2 and out == "" and str(efforts) in line and "tau_A" in line


# ---------------------------------------------------------------- every actuation, random designs
from test_family_dynamics import ALLOWED, designs  # noqa: E402


@pytest.mark.parametrize(("arch", "act"), ALLOWED)
def test_every_allowed_actuation_reproduces_its_motion(arch: str, act: int) -> None:
    robot = FamilyRobot.default(arch, act)

    def efforts(t: float) -> np.ndarray:
        return np.asarray(family_inverse_dynamics(robot, _law(t, AMPLITUDE)).tau[0])

    times = np.linspace(0.0, 0.25, 3)
    planned = law_at(AMPLITUDE, times)
    result = family_forward_dynamics(
        robot, None, efforts, times, planned.pose[0], planned.velocity[0], rtol=1e-10, atol=1e-12
    )
    assert result.status == "completed"
    np.testing.assert_allclose(result.motion.pose, planned.pose, atol=1e-9)


@settings(max_examples=6, deadline=None)
@given(data=st.data())
def test_random_designs_reproduce_their_motion(data: st.DataObject) -> None:
    """Random placements, inertias, payload, load and gravity (tests/test_family_dynamics.py)."""
    robot = data.draw(designs())
    from hypothesis import assume

    assume(robot.platform.mass >= 0.5 and robot.platform.inertia >= 1e-3)
    centre = robot.home_poses[0]
    star = np.array([data.draw(st.floats(-0.01, 0.01)) for _ in range(2)] +
                    [data.draw(st.floats(-0.05, 0.05))])  # fmt: skip

    def motion_at(t: float) -> Motion:
        m = law_at(star, [t])
        return Motion(t=m.t, pose=m.pose + centre, velocity=m.velocity,
                      acceleration=m.acceleration)  # fmt: skip

    try:
        motion_at(0.3)  # the path from home stays regular
        family_inverse_dynamics(robot, motion_at(0.3))
    except Prp3Error:
        assume(False)

    def efforts(t: float) -> np.ndarray:
        return np.asarray(family_inverse_dynamics(robot, motion_at(t)).tau[0])

    times = np.array([0.0, 0.15, 0.3])
    planned = [motion_at(t) for t in times.tolist()]
    pose = np.array([m.pose[0] for m in planned])
    result = family_forward_dynamics(
        robot, None, efforts, times, pose[0], planned[0].velocity[0], rtol=1e-11, atol=1e-13
    )
    assert result.status == "completed"
    np.testing.assert_allclose(result.motion.pose, pose, atol=1e-8)


def test_cli_forward_unreachable_initial_pose_is_located(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-RRR"\n')
    efforts = tmp_path / "efforts.csv"
    efforts.write_text("t,tau_A,tau_B,tau_C\n0,1,2,3\n1,1,2,3\n")
    status, out, err = cli(
        capsys, "forward", "--robot", robot_file, "--forces", efforts, "--initial-pose",
        "0.5", "0.5", "0", "--output", tmp_path / "fw",
    )  # fmt: skip
    line = one_line(err)
    assert status == 2 and out == ""
    assert "--initial-pose 0.5 0.5 0.0" in line and "cannot reach" in line
    assert not (tmp_path / "fw").exists()
