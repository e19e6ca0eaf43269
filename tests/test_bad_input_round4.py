"""Bad input, round four (issue 33): one line, exit 2, nothing written, never a hang."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from prp3.analysis.forward import MAX_EVALUATIONS, MAX_SECONDS, forward_dynamics
from prp3.cli import main
from prp3.errors import ParameterError, TrajectoryError, UnreachablePoseError
from prp3.mechanics.geometry import check_stroke
from prp3.model.joint_elements import SMOOTHING_FLOOR
from prp3.model.parameters import Friction, JointFriction, Limits
from prp3.model.robot import Robot
from prp3.path_validation import RATE_TOLERANCE

FORCES = "t,f10_A,f10_B,f10_C\n0,0,0,0\n0.1,0,0,0\n0.2,0,0,0\n"


def _error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err  # one line, no traceback
    assert "Traceback" not in err[0]
    return err[0]


def _earlier_output(folder: Path) -> Path:
    folder.mkdir()
    kept = folder / "notes.txt"
    kept.write_text("earlier output\n")
    return kept


def _forward(tmp_path: Path, robot_text: str, forces_text: str, *extra: str) -> tuple[int, Path]:
    robot = tmp_path / "robot.toml"
    robot.write_text(robot_text)
    forces = tmp_path / "forces.csv"
    forces.write_text(forces_text)
    out = tmp_path / "out"
    kept = _earlier_output(out)
    status = main(["forward", "--robot", str(robot), "--forces", str(forces), *extra,
                   "--output", str(out)])  # fmt: skip
    assert kept.read_text() == "earlier output\n"
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]  # nothing written
    return status, robot


def test_huge_constant_load_is_refused_naming_load_time_and_robot_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # was: numpy.linalg.LinAlgError: Singular matrix (A = f10(unit) - b is round-off of b)
    status, robot = _forward(tmp_path, "[load]\nforce = [0, 1e12]\n", FORCES)
    line = _error_line(capsys)
    assert status == 2
    assert line.startswith(f"prp3 forward: error: {robot}: ")
    assert "t = 0.0 s" in line and "lost its meaning" in line
    assert "[load] force = [0.0, 1000000000000.0] N" in line


def test_load_column_that_overflows_its_spline_names_the_column_and_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # was: ValueError: `dydx` must contain only finite values.
    table = (
        "t,f10_A,f10_B,f10_C,fx,fy,mz\n0,0,0,0,1e308,0,0\n0.1,0,0,0,0,0,0\n0.2,0,0,0,-1e308,0,0\n"
    )
    status, _ = _forward(tmp_path, "", table)
    line = _error_line(capsys)
    assert status == 2
    assert str(tmp_path / "forces.csv") in line
    assert "the rate of change of fx overflows" in line


def test_load_spline_overflow_with_finite_slopes_names_the_load() -> None:
    from prp3.analysis.force_histories import ActuatorForces

    # slopes of 1e308 N/s are finite, the spline's derivatives at the knots are not
    with pytest.raises(TrajectoryError, match="load samples cannot be interpolated"):
        ActuatorForces(t=[0.0, 2.0, 4.0, 6.0], f10=np.zeros((4, 3)),
                       load=[[1e308, 0, 0], [-1e308, 0, 0], [1e308, 0, 0], [-1e308, 0, 0]])  # fmt: skip


def test_smoothing_below_float64_resolution_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # was: a hang (the explicit integrator crawls through a stiff ODE)
    text = "[friction.actuator]\ncoulomb = 1.0\nsmoothing = 1e-300\n"
    status, robot = _forward(tmp_path, text, FORCES, "--initial-velocity", "0.01", "0", "0")
    line = _error_line(capsys)
    assert status == 2
    assert line.startswith(f"prp3 forward: error: {robot}: ")
    assert "friction.actuator.smoothing = 1e-300" in line


def test_smoothing_floor_is_the_joint_rate_round_off() -> None:
    assert SMOOTHING_FLOOR == RATE_TOLERANCE
    assert MAX_EVALUATIONS == 1_000_000 and MAX_SECONDS == 600.0  # documented defaults


STIFF = Robot(
    gravity=(0.0, 0.0),
    friction=Friction(actuator=JointFriction(coulomb=1.0, smoothing=1e-11)),
)


def test_evaluation_bound_stops_a_stiff_run_and_says_so() -> None:
    with pytest.raises(TrajectoryError, match=r"bound max_evaluations = 500 after 500 ") as info:
        forward_dynamics(STIFF, lambda t: np.zeros(3), [0.0, 1.0], [0.0, 0.0, 0.0],
                         [0.01, 0.0, 0.0], max_evaluations=500)  # fmt: skip
    assert "smoothing = 1e-11" in str(info.value)
    assert "\n" not in str(info.value)


def test_wall_time_bound_stops_a_stiff_run_and_says_so() -> None:
    with pytest.raises(TrajectoryError, match=r"bound max_seconds = 0.2 s \(wall time\)"):
        forward_dynamics(STIFF, lambda t: np.zeros(3), [0.0, 1.0], [0.0, 0.0, 0.0],
                         [0.01, 0.0, 0.0], max_seconds=0.2)  # fmt: skip


@pytest.mark.parametrize("bad", [{"max_evaluations": 0}, {"max_seconds": -1.0},
                                 {"max_seconds": float("nan")}])  # fmt: skip
def test_bounds_are_validated(bad: dict[str, float]) -> None:
    with pytest.raises(ParameterError, match=next(iter(bad))):
        forward_dynamics(Robot(), lambda t: np.zeros(3), [0.0, 1.0], [0.0, 0.0, 0.0],
                         [0.0, 0.0, 0.0], **bad)  # type: ignore[arg-type]  # fmt: skip


@pytest.mark.parametrize(
    ("text", "key"),
    [
        (
            "[payload]\nmass = 1e308\ncom = [1e200, 0]\n",
            "payload.com = [1e+200, 0.0] m with mass = 1e+308",
        ),
        (
            "[payload]\nmass = 1.0\ncom = [1e200, 0]\n",
            "payload.com = [1e+200, 0.0] m with mass = 1.0",
        ),
        # I + m·r² = 1.7e308 + 1e308 (1.7e308 alone is finite, and accepted)
        ("[payload]\nmass = 1.0\ninertia = 1.7e308\ncom = [1e154, 0]\n", "payload.inertia"),
        ("[load]\nforce = [1e308, 1e308]\n", "load.force"),
        ("[spring.actuator]\nstiffness = 1e308\nrest = 1e10\n", "spring.actuator"),
        ("[friction.actuator]\nviscous = 1e308\n", "friction.actuator"),
    ],
)
def test_robot_check_refuses_effects_that_overflow(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, key: str
) -> None:
    path = tmp_path / "robot.toml"
    path.write_text(text)
    assert main(["robot", "--check", str(path)]) == 2
    line = _error_line(capsys)
    assert re.match(rf"prp3 robot: error: {re.escape(str(path))}:\d+: robot: ", line), line
    assert key in line and "overflow" in line


def test_workspace_statics_overflow_names_load_and_robot_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "robot.toml"
    path.write_text("[load]\nforce = [0, 1e307]\nmoment = 1e307\n")
    out = tmp_path / "ws"
    kept = _earlier_output(out)
    status = main(["workspace", "--robot", str(path), "--statics", "--points", "5",
                   "--orientations", "3", "--phi", "1.0469", "--extent", "-30", "30", "-30",
                   "30", "--output", str(out)])  # fmt: skip
    line = _error_line(capsys)
    assert status == 2
    assert line.startswith(f"prp3 workspace: error: {path}: robot: the statics overflow")
    assert "[load] force = [0.0, 1e+307] N, moment = 1e+307" in line
    assert kept.read_text() == "earlier output\n"
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")])
def test_the_stroke_check_refuses_a_displacement_that_is_not_a_number(value: float) -> None:
    # a comparison with NaN is False both ways: "outside" must be "not within"
    robot = Robot(limits=Limits(stroke=(-0.1, 0.1)))
    check_stroke(robot, np.array([[0.0, 0.05, -0.05]]))  # within: no error
    with pytest.raises(UnreachablePoseError, match="lambda10_C") as info:
        check_stroke(robot, np.array([[0.0, 0.05, -0.05], [0.0, 0.0, value]]))
    assert info.value.sample == 1
    assert "stroke [-0.1, 0.1] m" in str(info.value)


def test_an_integration_that_fails_at_its_first_step_reports_failed_not_an_axis_error() -> None:
    """Found by the thorough fuzz: ``atol = 4.7e-291`` stops solve_ivp before its first step.

    Its ``y`` is then an empty 1-D array, whose second axis the family's route
    indexed (numpy's AxisError); the 3-PRP's refuses the run as integrating nothing.
    """
    import prp3

    robot = prp3.FamilyRobot.default("3-RRR")
    home = robot.home_poses[0]
    times = np.array([0.0, 0.01])
    family = prp3.family_forward_dynamics(  # the family reports the failure with its first state
        robot, None, lambda t: np.zeros(3), times, home, np.zeros(3), atol=4.7e-291
    )
    assert family.status == "failed" and "step size" in family.message
    np.testing.assert_array_equal(family.motion.pose, [home])
    with pytest.raises(TrajectoryError, match="fails at its first step"):  # nothing integrated
        forward_dynamics(
            Robot(), lambda t: np.zeros(3), times, [0.01, 0.0, 0.05], np.zeros(3), atol=4.7e-291
        )


def test_an_initial_velocity_whose_squares_overflow_is_refused_as_the_initial_state() -> None:
    """Found by the thorough fuzz: ``ω = 1.5e154`` rad/s overflowed with numpy's warning."""
    import prp3

    robot = prp3.FamilyRobot.default("3-RRR")
    with pytest.raises(TrajectoryError, match=r"initial pose: .*the results overflow"):
        prp3.family_forward_dynamics(
            robot, None, lambda t: np.zeros(3), np.array([0.0, 0.01]), robot.home_poses[0],
            [0.0, 0.0, 1.5482003035190314e154],
        )  # fmt: skip


# ------------------------------------------------ family forward (issue 33, gap 1 and 2)
FAMILY_FORWARD_DOCS = "docs/family.md §7"


def _family_efforts_csv(path: Path, rows: list[list[float]]) -> Path:
    body = "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows)
    path.write_text("t,tau_A,tau_B,tau_C\n" + body, encoding="utf-8")
    return path


def _family_forward_cli(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, robot_text: str, rows: list[list[float]]
) -> tuple[int, str]:
    robot = tmp_path / "family.toml"
    robot.write_text(robot_text, encoding="utf-8")
    table = _family_efforts_csv(tmp_path / "efforts.csv", rows)
    out = tmp_path / "out"
    kept = _earlier_output(out)
    status = main(["forward", "--robot", str(robot), "--forces", str(table),
                   "--output", str(out)])  # fmt: skip
    assert kept.read_text() == "earlier output\n"
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]  # nothing written
    return status, _error_line(capsys)


@pytest.mark.parametrize("push", [1e6, 1e20, 1e308, -1e308])
def test_prp3_forward_of_a_family_robot_refuses_absurd_efforts(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, push: float
) -> None:
    """Before the check these ran past 100 s (the explicit integrator crawling)."""
    rows = [[0.0, push, push, push], [0.1, push, push, push]]
    status, line = _family_forward_cli(capsys, tmp_path, 'architecture = "3-RRR"\n', rows)
    assert status == 2
    assert "efforts.csv:2: sample 0, t = 0 s" in line and "beyond the bound 1e+06" in line
    assert f"tau_A = {push!r}" in line and "3-RRR" in line


def test_prp3_forward_of_a_family_robot_refuses_an_efforts_column_swinging_across_floats(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    rows = [[0.0, 1e308, 0.0, 0.0], [0.1, -1e308, 0.0, 0.0]]
    status, line = _family_forward_cli(capsys, tmp_path, 'architecture = "3-RRR"\n', rows)
    assert status == 2 and "beyond the bound" in line and "tau_A = 1e+308" in line


def test_prp3_forward_of_a_family_robot_refuses_a_huge_load(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    text = 'architecture = "3-RRR"\n[load]\nforce = [0.0, 1e12]\n'
    status, line = _family_forward_cli(capsys, tmp_path, text, [[0.0, 0, 0, 0], [0.1, 0, 0, 0]])
    assert status == 2 and "family.toml:3: load.force" in line  # the robot file's key and line
    assert "beyond the bound 1e+06" in line


def test_prp3_forward_of_a_family_robot_refuses_model_form_friction(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Coulomb friction smoothed over 1e-300 m/s is a key the family form does not have."""
    text = 'architecture = "3-RRR"\n[friction.revolute]\ncoulomb = 0.1\nsmoothing = 1e-300\n'
    status, line = _family_forward_cli(capsys, tmp_path, text, [[0.0, 0, 0, 0], [0.1, 0, 0, 0]])
    assert status == 2 and "[friction]" in line


def _family_efforts_for(robot: object, pose: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
    """``τ`` of the robot at rest at ``pose`` accelerating by ``acceleration`` (Newton–Euler,
    another route than the forward dynamics' unit-acceleration samples)."""
    import prp3
    from prp3.model.motion import Motion

    motion = Motion(
        t=np.array([0.0]), pose=pose[None], velocity=np.zeros((1, 3)),
        acceleration=acceleration[None],
    )  # fmt: skip
    return np.asarray(prp3.newton_euler_dynamics(robot, motion).tau)[0]


@pytest.mark.parametrize("architecture", ["3-RRR", "3-RPR", "3-PRR"])
def test_the_family_bound_is_the_acceleration_of_the_equations_of_motion(
    architecture: str,
) -> None:
    """Efforts asking for half the bound run; efforts asking for twice it are refused."""
    import prp3
    from prp3.family.forward import MAX_ACCELERATION

    robot = prp3.FamilyRobot.default(architecture)
    home = np.asarray(robot.home_poses[0], dtype=np.float64)
    direction = np.array([0.6, -0.8, 0.0])
    for scale, accepted in ((0.5, True), (2.0, False)):
        tau = _family_efforts_for(robot, home, scale * MAX_ACCELERATION * direction)
        efforts = np.vstack([tau, tau])

        def run(efforts: np.ndarray = efforts) -> prp3.FamilyForward:
            return prp3.family_forward_dynamics(
                robot, [0.0, 1e-9], efforts, [0.0, 1e-9], home, np.zeros(3)
            )

        if accepted:
            result = run()
            np.testing.assert_allclose(
                result.motion.acceleration[0], 0.5 * MAX_ACCELERATION * direction,
                rtol=1e-6, atol=1e-6 * MAX_ACCELERATION,
            )  # fmt: skip
        else:
            with pytest.raises(ParameterError, match="beyond the bound") as refused:
                run()
            assert refused.value.key == "efforts" and refused.value.sample == 0
            assert f"{2.0 * MAX_ACCELERATION * 0.8:.3g}" in str(refused.value)  # max |ẍ_i|


def test_family_efforts_turning_absurd_during_the_motion_stop_naming_the_time() -> None:
    import prp3

    robot = prp3.FamilyRobot.default("3-RRR")
    home = robot.home_poses[0]

    def efforts(t: float) -> np.ndarray:
        return np.full(3, 1e300 if 1e-3 < t < 9e-3 else 0.0)  # between the output times

    with pytest.raises(TrajectoryError, match=r"at t = .* s, not below 1e\+12"):
        prp3.family_forward_dynamics(robot, None, efforts, [0.0, 0.01], home, np.zeros(3))
