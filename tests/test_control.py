"""Closed-loop control: ``prp3.apps.control`` (``control_law``, ``plants``) and ``prp3 control``.

Independent checks:

* each control law against the Newton-Euler inverse dynamics
  (``method="newton-euler"``) of the law's arguments, computed here;
* the prp3 plant over one step against :func:`prp3.forward_dynamics` with the
  same constant force; the MuJoCo plant (an independent simulator of the same
  robot) against the prp3 plant along a whole closed-loop run;
* the quintic Hermite reference reproduces a polynomial of degree 5 exactly;
* the remaining error of computed torque with the exact model is the zero
  order hold's: it halves when the rate doubles.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clitools import cli
from prp3 import (
    Motion,
    PlatformParameters,
    Robot,
    forward_dynamics,
    inverse_dynamics,
    platform_dynamics,
)
from prp3.apps.control import check_model, control_times, hermite_reference, track
from prp3.apps.control_law import DEFAULT_KD, DEFAULT_KP, Gains, control_force
from prp3.apps.plants import Prp3Plant
from prp3.cli import main
from prp3.engines.compiled_robot import compile_robot
from prp3.errors import ParameterError, Prp3Error, SingularPoseError
from prp3.model.motion import PAPER_MOTIONS, law_at
from prp3.model.parameters import Friction, JointFriction, Load, Payload
from strategies import poses, robots

COLUMNS = "t,x,y,phi,x_ref,y_ref,phi_ref,f10_A,f10_B,f10_C"


def _newton_euler_f10(robot: Robot, pose, velocity, acceleration) -> np.ndarray:
    motion = Motion(
        t=0.0,
        pose=np.asarray(pose, dtype=float),
        velocity=np.asarray(velocity, dtype=float),
        acceleration=np.asarray(acceleration, dtype=float),
    )
    return inverse_dynamics(robot, motion, method="newton-euler")[1].f10


# ------------------------------------------------------------------ control laws
@settings(max_examples=25)
@given(
    robot=robots(),
    data=st.data(),
    kp=st.floats(0.0, 2000.0),
    kd=st.floats(0.0, 100.0),
)
def test_control_laws_match_newton_euler(robot: Robot, data, kp: float, kd: float) -> None:
    measured_pose = data.draw(poses(robot.l0))
    reference_pose = measured_pose + np.array(data.draw(st.tuples(*[st.floats(-0.01, 0.01)] * 3)))
    rates = [np.array(data.draw(st.tuples(*[st.floats(-1.0, 1.0)] * 3))) for _ in range(3)]
    measured_velocity, reference_velocity, reference_acceleration = rates
    reference = [*reference_pose, *reference_velocity, *reference_acceleration]
    measured = [*measured_pose, *measured_velocity]
    compiled, gains = compile_robot(robot), Gains(kp=kp, kd=kd)
    e, de = reference_pose - measured_pose, reference_velocity - measured_velocity
    expected = {
        "computed-torque": _newton_euler_f10(
            robot, measured_pose, measured_velocity, reference_acceleration + kd * de + kp * e
        ),
        "pd": _newton_euler_f10(robot, measured_pose, np.zeros(3), kd * de + kp * e),
        "feedforward": _newton_euler_f10(
            robot, reference_pose, reference_velocity, reference_acceleration
        ),
    }
    for controller, f10 in expected.items():
        got = np.array(control_force(controller, compiled, gains, reference, measured))
        scale = max(1.0, float(np.abs(f10).max()))
        assert np.abs(got - f10).max() <= 1e-10 * scale, controller


def test_control_force_refuses_an_unknown_law() -> None:
    with pytest.raises(ParameterError, match="controller must be one of"):
        control_force("bang-bang", compile_robot(Robot()), Gains(), [0.0] * 9, [0.0] * 6)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("kp", "kd", "match"),
    [(-1.0, 1.0, "kp"), (1.0, math.nan, "kd"), (math.inf, 1.0, "kp"), (True, 1.0, "kp")],
)
def test_gains_are_validated(kp: float, kd: float, match: str) -> None:
    with pytest.raises(ParameterError, match=f"gains: {match} must be a non-negative"):
        Gains(kp=kp, kd=kd)


# ------------------------------------------------------------------ reference
def test_control_times_cover_the_interval() -> None:
    times = control_times(0.0, 3.0, 1000.0)
    assert times.size == 3001 and times[0] == 0.0 and times[-1] == 3.0
    assert np.allclose(np.diff(times), 1e-3, rtol=1e-9, atol=0.0)
    odd = control_times(0.5, 1.0, 7.0)  # 3.5 periods: the last step is shorter
    assert odd[-1] == 1.0 and np.allclose(np.diff(odd)[:-1], 1.0 / 7.0)
    assert 0.0 < odd[-1] - odd[-2] < 1.0 / 7.0


@pytest.mark.parametrize("rate", [0.0, -5.0, math.nan, math.inf, 1e12])
def test_control_times_refuse_bad_rates(rate: float) -> None:
    with pytest.raises(ParameterError, match="rate"):
        control_times(0.0, 3.0, rate)


def test_hermite_reference_is_exact_for_quintics() -> None:
    coefficients = np.array(
        [[0.01, -0.02, 0.03, 0.01, -0.004, 0.002], [0.0, 0.01, 0.0, -0.01, 0.003, -0.001],
         [0.1, 0.0, -0.05, 0.02, 0.01, -0.003]]
    )  # fmt: skip
    powers = np.arange(6)

    def law(t: np.ndarray, order: int) -> np.ndarray:
        factor = np.array([math.perm(int(k), order) for k in powers], dtype=float)
        exponent = np.clip(powers - order, 0, None)
        return (coefficients * factor) @ (t[None, :] ** exponent[:, None])

    knots = np.linspace(0.0, 2.0, 5)
    motion = Motion(t=knots, pose=law(knots, 0).T, velocity=law(knots, 1).T,
                    acceleration=law(knots, 2).T)  # fmt: skip
    at = np.linspace(0.0, 2.0, 37)
    reference = hermite_reference(motion, at)
    assert np.abs(reference.pose - law(at, 0).T).max() < 1e-13
    assert np.abs(reference.velocity - law(at, 1).T).max() < 1e-12
    assert np.abs(reference.acceleration - law(at, 2).T).max() < 1e-11


def test_model_geometry_must_match() -> None:
    check_model(Robot(), Robot(platform=PlatformParameters(mass=9.0)))  # masses may differ
    with pytest.raises(ParameterError, match=r"l0 = 0\.4 m differs"):
        check_model(Robot(), Robot(l0=0.4))


# ------------------------------------------------------------------ plants
def test_prp3_plant_step_matches_forward_dynamics() -> None:
    robot = Robot(gravity=(1.0, -9.0), platform=PlatformParameters(mass=2.0, inertia=0.05))
    start = Motion(
        t=np.array([0.0, 1.0]),
        pose=np.array([[0.01, -0.02, 0.2]] * 2),
        velocity=np.array([[0.1, 0.05, -0.3]] * 2),
        acceleration=np.zeros((2, 3)),
    )
    plant = Prp3Plant(robot, start)
    force = (40.0, -5.0, -20.0)
    assert plant.advance(0.0, 0.01, force) is None
    expected = forward_dynamics(
        robot, lambda t: np.array(force), [0.0, 0.01], start.pose[0], start.velocity[0],
        rtol=1e-12, atol=1e-14,
    )  # fmt: skip
    state = np.array(plant.measure())
    assert np.abs(state[:3] - expected.motion.pose[-1]).max() < 1e-12
    assert np.abs(state[3:] - expected.motion.velocity[-1]).max() < 1e-10


def _paper_reference(name: str, rate: float = 1000.0, stop: float = 3.0) -> Motion:
    return law_at(PAPER_MOTIONS[name], control_times(0.0, stop, rate))


@pytest.mark.slow
@pytest.mark.parametrize("name", ["vertical", "rotation"])
def test_computed_torque_tracks_the_paper_motions_and_pd_is_worse(name: str) -> None:
    reference = _paper_reference(name)
    ct = track(Robot(), reference, controller="computed-torque")
    pd = track(Robot(), reference, controller="pd")
    assert ct.status == pd.status == "completed"
    assert ct.t.size == 3001 and ct.t[-1] == 3.0
    assert ct.max_error[:2].max() <= 1e-5 and ct.max_error[2] <= 1e-4  # m, rad
    moving = 1 if name == "vertical" else 2  # the coordinate the motion moves
    assert pd.max_error[moving] >= 10.0 * ct.max_error[moving]
    assert pd.max_error.max() >= 10.0 * ct.max_error.max()
    assert np.all(ct.rms_error <= ct.max_error) and np.all(ct.step_time > 0)
    # and what is left is the hold's: over a period the plant misses half the change of
    # the force, a disturbance A⁻¹·ḟ10·h/2 held by KP: e ≈ A⁻¹·ḟ10·h/(2·KP), with A
    # from the forward dynamics and ḟ10 from central differences of the inverse dynamics
    predicted = _hold_error(name, h=1e-3, kp=DEFAULT_KP)
    ratio = ct.max_error / predicted
    assert np.all((0.96 < ratio) & (ratio < 1.01)), ratio  # the loop's lag: about 1 % less


def _hold_error(name: str, h: float, kp: float) -> np.ndarray:
    """Largest ``|A(q)⁻¹·ḟ10|·h/(2·KP)`` along the paper's motion ``name`` (m, m, rad)."""
    t = np.linspace(0.0, 3.0, 301)[5:-5]
    step = 1e-5

    def f10(times: np.ndarray) -> np.ndarray:
        motion = law_at(PAPER_MOTIONS[name], times)
        return inverse_dynamics(Robot(), motion, method="newton-euler")[1].f10

    rate = (f10(t + step) - f10(t - step)) / (2.0 * step)
    reference = law_at(PAPER_MOTIONS[name], t)
    A = platform_dynamics(Robot(), reference.pose, reference.velocity).force_matrix
    return np.abs(np.linalg.solve(A, rate[..., None])[..., 0]).max(axis=0) * h / (2.0 * kp)


def test_computed_torque_error_is_the_zero_order_holds() -> None:
    """Exact model: the only error left is the hold's, of first order in the period."""
    coarse = track(Robot(), _paper_reference("rotation", 500.0, 0.5))
    fine = track(Robot(), _paper_reference("rotation", 2000.0, 0.5))
    ratio = coarse.max_error / fine.max_error
    assert np.all((3.6 < ratio) & (ratio < 4.4)), ratio


def test_feedforward_diverges_and_stops_at_the_singularity() -> None:
    run = track(Robot(), _paper_reference("rotation", 200.0), controller="feedforward")
    assert run.status == "singular" and "singularity" in run.message
    assert run.t[-1] < 3.0 and run.max_error[2] > 0.1  # open loop: unstable
    early = run.t <= 0.5
    assert np.abs(run.error[early]).max() < 1e-3  # it starts on the path


def test_model_errors_cost_accuracy_but_feedback_keeps_the_path() -> None:
    heavy = Robot(platform=PlatformParameters(mass=3.6))  # the model believes m3 = 3 kg
    reference = _paper_reference("vertical", 1000.0, 1.0)
    exact = track(Robot(), reference)
    wrong = track(heavy, reference, model=Robot())
    assert wrong.status == "completed"
    assert wrong.max_error[1] > 10.0 * exact.max_error[1]
    # the uncompensated weight 0.6 kg·g through KP = 400 1/s²: a steady error of mm, not more
    assert wrong.max_error[1] < 5e-3


def test_track_validates_its_inputs() -> None:
    reference = _paper_reference("vertical", 100.0, 0.1)
    with pytest.raises(ParameterError, match="plant must be one of"):
        track(Robot(), reference, plant="gazebo")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="controller must be one of"):
        track(Robot(), reference, controller="lqr")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="differs from the plant robot"):
        track(Robot(), reference, model=Robot(l0=0.2))
    singular = Motion.at_rest([0.0, 0.0, math.pi / 3.0], t=0.0)
    path = Motion(
        t=np.array([0.0, 0.01]),
        pose=np.stack([np.zeros(3), singular.pose]),
        velocity=np.zeros((2, 3)),
        acceleration=np.zeros((2, 3)),
    )
    with pytest.raises(
        SingularPoseError, match=r"reference: pose: sample 1, t = 0\.01 s: singular pose"
    ):
        track(Robot(), path)


def test_plants_refuse_what_they_would_not_simulate() -> None:
    reference = _paper_reference("vertical", 100.0, 0.05)
    for kind, key, value in (("actuator", "coulomb", 1.0), ("sleeve", "mu", 0.1)):
        robot = Robot(friction=Friction(**{kind: JointFriction(**{key: value})}))
        with pytest.raises(
            ParameterError, match=rf"plant 'mujoco': friction\.{kind}\.{key} = {value}: MuJoCo"
        ):
            track(robot, reference, plant="mujoco")
    sticky = Robot(friction=Friction(actuator=JointFriction(mu=0.1)))
    with pytest.raises(ParameterError, match="plant 'prp3': a friction proportional"):
        track(sticky, reference, plant="prp3")


def test_prp3_plant_payload_at_g_is_a_heavier_platform() -> None:
    """The table's payload: a [payload] at G is the platform m3 + m, I3 + I, exactly."""
    reference = _paper_reference("rotation", 1000.0, 0.2)
    carried = Robot(payload=Payload(mass=0.5, com=(0.0, 0.0), inertia=1e-3))
    heavier = Robot(platform=PlatformParameters(mass=3.5, inertia=Robot().platform_inertia + 1e-3))
    a = track(carried, reference, model=Robot())
    b = track(heavier, reference, model=Robot())
    assert np.abs(a.pose - b.pose).max() < 1e-13 and np.abs(a.f10 - b.f10).max() < 1e-10
    assert a.max_error[1] > 1e-6  # the unknown payload shows


def test_mujoco_plant_refused_without_mujoco(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco raises ImportError
    with pytest.raises(Prp3Error, match="needs MuJoCo"):
        track(Robot(), _paper_reference("vertical", 100.0, 0.1), plant="mujoco")


def test_mujoco_plant_agrees_with_the_prp3_plant() -> None:
    pytest.importorskip("mujoco")
    reference = _paper_reference("rotation", 1000.0, 1.0)
    engine = track(Robot(), reference, plant="mujoco")
    ours = track(Robot(), reference, plant="prp3")
    assert engine.status == "completed"
    assert engine.max_error[:2].max() <= 1e-5 and engine.max_error[2] <= 1e-4
    # two simulators of the same closed loop: the soft welds differ by ~1e-10
    assert np.abs(engine.pose - ours.pose).max() < 1e-8
    assert np.abs(engine.f10 - ours.f10).max() < 1e-5


def test_mujoco_plant_carries_the_payload_the_load_and_viscous_friction() -> None:
    """The MJCF's payload body, joint damping and the load as xfrc_applied, against prp3's plant."""
    pytest.importorskip("mujoco")
    robot = Robot(
        payload=Payload(mass=0.5, com=(0.02, -0.01), inertia=1e-3),
        load=Load(force=(3.0, -5.0), moment=0.2),
        friction=Friction(
            actuator=JointFriction(viscous=20.0),
            revolute=JointFriction(viscous=0.05),
            sleeve=JointFriction(viscous=4.0),
        ),
    )
    reference = _paper_reference("rotation", 1000.0, 0.5)
    engine = track(robot, reference, plant="mujoco")
    ours = track(robot, reference, plant="prp3")
    bare = track(Robot(), reference, plant="mujoco", model=robot)
    assert engine.status == ours.status == "completed"
    assert np.abs(engine.pose - ours.pose).max() < 1e-8
    assert np.abs(engine.f10 - ours.f10).max() < 1e-5
    # the extras matter: MuJoCo without them, driven by the same controller, ends elsewhere
    assert np.abs(bare.pose - engine.pose).max() > 1e-6


# ------------------------------------------------------------------ command line


def _trajectory(folder: Path, stop: float = 0.2) -> Path:
    motion = law_at(PAPER_MOTIONS["rotation"], np.linspace(0.0, stop, 21))
    path = folder / "traj.csv"
    rows = [
        ",".join(repr(float(v)) for v in (t, *p, *v, *a))
        for t, p, v, a in zip(motion.t, motion.pose, motion.velocity, motion.acceleration,
                              strict=True)
    ]  # fmt: skip
    path.write_text("t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi\n" + "\n".join(rows) + "\n")
    return path


def test_cli_writes_tracking_csv_and_figure(tmp_path: Path, capsys) -> None:
    trajectory = _trajectory(tmp_path)
    out = tmp_path / "out"
    args = ["control", "--trajectory", str(trajectory), "--plant", "prp3"]
    status = main([*args, "--controller", "computed-torque", "--rate", "500", "-o", str(out)])
    assert status == 0
    text = (out / "tracking.csv").read_text().splitlines()
    assert text[0] == COLUMNS and len(text) == 1 + 101  # 0 .. 0.2 s at 500 Hz
    table = np.loadtxt(out / "tracking.csv", delimiter=",", skiprows=1)
    expected = law_at(PAPER_MOTIONS["rotation"], table[:, 0]).pose
    assert np.abs(table[:, 4:7] - expected).max() < 1e-9  # Hermite of the analytic law
    assert (out / "tracking.png").stat().st_size > 10_000
    summary = capsys.readouterr().out
    assert "max |error|" in summary and "median" in summary and "99th percentile" in summary


def test_cli_paper_motion_default_gains(tmp_path: Path, capsys) -> None:
    out = tmp_path / "pd"
    args = ["control", "--motion", "vertical", "--plant", "prp3", "--controller", "pd"]
    assert main([*args, "--rate", "100", "-o", str(out)]) == 0
    rows = (out / "tracking.csv").read_text().splitlines()
    assert len(rows) == 1 + 301
    assert f"KP = {DEFAULT_KP:g}" in capsys.readouterr().out and DEFAULT_KD == 40.0


def test_cli_stopped_run_keeps_its_rows_and_exits_1(tmp_path: Path, capsys) -> None:
    out = tmp_path / "ff"
    args = ["control", "--motion", "rotation", "--plant", "prp3", "--controller", "feedforward"]
    assert main([*args, "--rate", "100", "-o", str(out)]) == 1
    rows = (out / "tracking.csv").read_text().splitlines()
    assert 2 < len(rows) < 1 + 301
    assert "singularity" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--rate", "0"], "--rate: expected a positive number"),
        (["--rate", "-10"], "--rate: expected a positive number"),
        (["--kp", "-1"], "--kp: expected a non-negative number"),
        (["--kd", "nan"], "--kd: expected a finite number"),
        (["--rate", "1e9"], "more than 1000000"),
    ],
)
def test_cli_bad_options(tmp_path: Path, capsys, extra: list[str], message: str) -> None:
    out = tmp_path / "out"
    args = ["control", "--motion", "vertical", "--plant", "prp3", "--controller", "pd"]
    status, _, err = cli(capsys, *args, *extra, "-o", out)
    assert status == 2
    assert message in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_cli_warns_when_the_controller_asks_more_than_max_force(tmp_path: Path, capsys) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text("[limits]\nmax_force = 30.0\n")  # the static force of leg A is 31.9 N
    args = ["control", "--motion", "vertical", "--plant", "prp3", "--controller", "pd"]
    status, _, err = cli(capsys, *args, "--robot", robot, "--rate", "50", "-o", tmp_path / "o")
    assert status == 0
    assert "warning: the controller asks |f10_A| = " in err and "max_force = 30 N" in err
    assert "f10_B" not in err and (tmp_path / "o" / "tracking.csv").exists()


def test_cli_model_of_another_geometry_is_refused(tmp_path: Path, capsys) -> None:
    model = tmp_path / "model.toml"
    model.write_text("l0 = 0.31\n")
    out = tmp_path / "out"
    args = ["control", "--motion", "vertical", "--plant", "prp3", "--controller", "pd"]
    assert main([*args, "--model", str(model), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "l0 = 0.31 m differs from the plant robot's l0 = 0.3 m" in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()


def test_cli_mujoco_missing_is_one_line(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)
    out = tmp_path / "out"
    args = ["control", "--motion", "vertical", "--plant", "mujoco", "--controller", "pd"]
    assert main([*args, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "needs MuJoCo" in err and len(err.strip().splitlines()) == 1 and not out.exists()


def test_cli_in_a_subprocess(tmp_path: Path) -> None:
    trajectory = _trajectory(tmp_path, stop=0.05)
    done = subprocess.run(
        [sys.executable, "-m", "prp3", "control", "--trajectory", str(trajectory),
         "--plant", "prp3", "--controller", "computed-torque", "-o", str(tmp_path / "o")],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "o" / "tracking.csv").read_text().startswith(COLUMNS + "\n")


def test_the_plants_integrator_is_named_as_it_runs() -> None:
    """The prp3 plant's ``solve_ivp`` method is the one its docs name (not forward's DOP853)."""
    import inspect

    from prp3.apps import control, plants

    assert plants.PLANT_METHOD == "RK45"
    docs = (Path(__file__).resolve().parents[1] / "docs" / "control.md").read_text()
    assert "`scipy.integrate.solve_ivp` (`RK45`" in " ".join(docs.split())
    assert "scipy.integrate.solve_ivp`` (``RK45``" in " ".join(inspect.getdoc(control).split())
