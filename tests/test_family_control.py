"""Closed-loop control of every architecture of the family (docs/control.md, docs/family.md).

The expected values do not come from the loop under test: the 3-PRP in family
form must track exactly as the model form's own loop (another kernel, §8); the
plant's motion under the held efforts is held against the energy the efforts
put in (``Σ_k τ_k·Δq_a,k = Δ(T + V)`` for efforts constant over each step,
:func:`prp3.family.forward.family_energy` an independent sum over the bodies).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from clitools import cli, one_line
from prp3 import Robot
from prp3.apps.control import control_times, track
from prp3.apps.control_law import Gains
from prp3.errors import ParameterError
from prp3.family import ARCHITECTURES, FamilyRobot, family_kinematics
from prp3.family.forward import family_energy
from prp3.model.motion import PAPER_MOTIONS, Motion, law_at

SHORT = control_times(0.0, 0.12, 500.0)


def test_the_3prp_in_family_form_tracks_as_the_model_form() -> None:
    reference = law_at(PAPER_MOTIONS["rotation"], control_times(0.0, 0.3, 1000.0))
    for controller in ("computed-torque", "pd", "feedforward"):
        family = track(FamilyRobot.default("3-PRP"), reference, controller=controller)
        model = track(Robot(), reference, controller=controller)
        assert family.status == model.status == "completed"
        np.testing.assert_allclose(family.pose, model.pose, rtol=0, atol=1e-12)
        np.testing.assert_allclose(family.f10, model.f10, rtol=0, atol=1e-9)


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_every_architecture_tracks_and_its_plant_keeps_the_energy_balance(
    architecture: str,
) -> None:
    robot = FamilyRobot.default(architecture)
    home = robot.home_poses[0]
    target = [float(home[0]) + 0.01, float(home[1]) - 0.005, float(home[2]) + 0.05]
    reference = law_at(target, SHORT)
    run = track(robot, reference, controller="computed-torque")
    assert run.status == "completed"
    assert run.max_error.max() < 1e-5  # critically damped loop at 500 Hz, exact model
    # the plant under the held efforts: work in = change of T + V (no dissipation, no load)
    states = Motion(
        t=run.t, pose=run.pose, velocity=run.velocity, acceleration=np.zeros_like(run.pose)
    )
    kin = family_kinematics(robot, states)
    kinetic, potential = family_energy(kin)
    qa = kin.q[:, :, robot.actuated - 1]
    work = np.cumsum((run.f10[:-1] * np.diff(qa, axis=0)).sum(axis=1))
    energy = (kinetic + potential)[1:] - (kinetic + potential)[0]
    scale = float(np.abs(run.f10).max() * np.abs(np.diff(qa, axis=0)).sum(axis=0).max()) + 1e-3
    np.testing.assert_allclose(work, energy, rtol=0, atol=1e-8 * scale)


def test_a_wrong_mass_model_tracks_worse_than_the_exact_one() -> None:
    robot = FamilyRobot.default("3-RPR")
    heavy = FamilyRobot.from_mapping({"architecture": "3-RPR", "platform": {"mass": 4.5}})
    reference = law_at([0.01, 0.0, 0.05], SHORT)
    exact = track(heavy, reference, model=heavy, gains=Gains(kp=100.0, kd=20.0))
    wrong = track(heavy, reference, model=robot, gains=Gains(kp=100.0, kd=20.0))
    assert exact.status == wrong.status == "completed"
    assert wrong.max_error.max() > 10.0 * exact.max_error.max()


def test_a_model_of_another_architecture_is_refused() -> None:
    robot = FamilyRobot.default("3-RRR")
    reference = law_at([0.01, 0.0, 0.0], SHORT)
    with pytest.raises(ParameterError, match="architecture differs"):
        track(robot, reference, model=FamilyRobot.default("3-RPR"))
    with pytest.raises(ParameterError, match="FamilyRobot"):
        track(robot, reference, model=Robot())


MUJOCO_REFERENCE = law_at(PAPER_MOTIONS["rotation"], control_times(0.0, 0.3, 1000.0))


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_the_mujoco_plant_agrees_with_the_prp3_plant(architecture: str) -> None:
    """Two simulators of one closed loop: MuJoCo's MJCF (soft welds, RK4) and prp3's."""
    pytest.importorskip("mujoco")
    robot = FamilyRobot.default(architecture)
    engine = track(robot, MUJOCO_REFERENCE, plant="mujoco")
    ours = track(robot, MUJOCO_REFERENCE, plant="prp3")
    assert engine.status == ours.status == "completed"
    assert engine.max_error.max() < 1e-5
    np.testing.assert_allclose(engine.pose, ours.pose, rtol=0, atol=1e-8)
    np.testing.assert_allclose(engine.f10, ours.f10, rtol=0, atol=1e-5)


def test_the_mujoco_plant_carries_the_payload_and_the_load() -> None:
    pytest.importorskip("mujoco")
    robot = FamilyRobot.from_mapping(
        {
            "architecture": "3-RPR",
            "payload": {"mass": 1.2, "com": [0.02, -0.01], "inertia": 2e-3},
            "load": {"force": [3.0, -2.0], "moment": 0.4},
        }
    )
    engine = track(robot, MUJOCO_REFERENCE, plant="mujoco")
    ours = track(robot, MUJOCO_REFERENCE, plant="prp3")
    bare = track(FamilyRobot.default("3-RPR"), MUJOCO_REFERENCE, plant="mujoco", model=robot)
    np.testing.assert_allclose(engine.pose, ours.pose, rtol=0, atol=1e-8)
    assert np.abs(bare.pose - engine.pose).max() > 1e-4  # without them the plant moves otherwise


def test_cli_control_of_a_family_robot(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-PRR"\nactuated = 1\n')
    out = tmp_path / "ctl"
    status, text, err = cli(
        capsys, "control", "--robot", robot_file, "--motion", "vertical", "--plant", "prp3",
        "--controller", "computed-torque", "--rate", "200", "--output", out,
    )  # fmt: skip
    assert status == 0, err
    lines = (out / "tracking.csv").read_text().splitlines()
    assert lines[0] == "t,x,y,phi,x_ref,y_ref,phi_ref,tau_A,tau_B,tau_C"
    assert (out / "tracking.png").stat().st_size > 10_000
    assert "peak |tau| (N)" in text
    values = np.array([line.split(",") for line in lines[1:]], dtype=np.float64)
    reference = law_at(PAPER_MOTIONS["vertical"], values[:, 0])
    run = track(FamilyRobot.from_toml(robot_file), reference)
    np.testing.assert_array_equal(values[:, 7:], run.f10)


def test_cli_control_refusals_are_one_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-RRR"\n')
    model_file = tmp_path / "model.toml"
    model_file.write_text('architecture = "3-RPR"\n')
    status, out, err = cli(
        capsys, "control", "--robot", robot_file, "--motion", "vertical", "--plant", "prp3",
        "--controller", "pd", "--model", model_file, "--output", tmp_path / "no",
    )  # fmt: skip
    line = one_line(err)
    assert status == 2 and out == "" and "architecture differs" in line, err
    assert not (tmp_path / "no").exists()
    assert str(model_file) in one_line(
        cli(
            capsys, "control", "--robot", robot_file, "--motion", "vertical", "--plant", "prp3",
            "--controller", "pd", "--model", model_file, "--output", tmp_path / "no",
        )[2]
    )  # fmt: skip


def test_cli_control_of_a_family_robot_follows_a_trajectory_past_phi_pi_3(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """The 3-PRP's φ = π/3 rule is not a family robot's (the 3-RPR turns through it)."""
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-RPR"\n')
    t = np.linspace(0.0, 0.2, 21)
    phi = np.pi / 3 - 0.021 + 0.2 * t  # through π/3 at t = 0.105 s, between two samples
    rows = [
        f"{a!r},0.0,0.0,{b!r},0.0,0.0,0.2,0.0,0.0,0.0"
        for a, b in zip(t.tolist(), phi.tolist(), strict=True)
    ]
    trajectory = tmp_path / "traj.csv"
    trajectory.write_text("t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi\n" + "\n".join(rows) + "\n")
    status, text, err = cli(
        capsys, "control", "--robot", robot_file, "--trajectory", trajectory, "--plant", "prp3",
        "--controller", "computed-torque", "--rate", "200", "--output", tmp_path / "ctl",
    )  # fmt: skip
    assert status == 0, err
    assert "completed" in text
