"""A trajectory is a table of independent states (issue 31 item 8, issue 33).

Each row of ``TRAJ.csv`` is the state of the platform at its time: nothing in
the model asks that the rates integrate to the steps between samples.  So a
static grid of poses with zero rates, or measured data with noisy rates, runs
through ``prp3 simulate``; what stays refused between two samples is a
singularity crossed on the straight path from one pose to the next (named by
both samples), for the 3-PRP and for a family robot (whose own measures, not
the 3-PRP's ``φ = π/3``, decide).  Rates so large that the results overflow are
refused naming the column; time steps of ``1e-300`` s and subnormal ones run.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from clitools import cli, one_line
from prp3 import Motion, Robot, inverse_dynamics, inverse_geometry
from prp3.apps.control import control_times, hermite_reference
from prp3.errors import TrajectoryError
from prp3.family import FamilyRobot, family_inverse_dynamics, read_robot_file
from prp3.io.trajectory import read_trajectory
from prp3.model.motion import paper_motion

HEADER = "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi"

#: A static grid of poses (m, m, rad): far apart, far from φ = π/3 mod π.
GRID = [
    (0.0, 0.0, 0.0),
    (0.04, 0.0, 0.0),
    (0.04, 0.03, 0.2),
    (-0.02, 0.01, -0.3),
    (0.0, -0.03, 0.1),
]


def write(path: Path, rows: list[list[float]], header: str = HEADER) -> Path:
    text = header + "\n" + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows)
    path.write_text(text)
    return path


def read_results(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return {name: values[:, j] for j, name in enumerate(rows[0])}


def grid_file(folder: Path, dt: float = 0.1) -> Path:
    return write(folder / "grid.csv", [[k * dt, *pose] + [0.0] * 6 for k, pose in enumerate(GRID)])


def family_robot_file(folder: Path, architecture: str, actuated: int = 1) -> Path:
    path = folder / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\nactuated = {actuated}\n')
    return path


# ------------------------------------------------------------------ a static grid
def test_a_static_grid_runs_and_gives_the_statics_of_each_pose(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    file = grid_file(tmp_path)
    status, _, err = cli(capsys, "simulate", "--trajectory", file, "-o", tmp_path / "out")
    assert status == 0, err
    table = read_results(tmp_path / "out" / "results.csv")
    for k, pose in enumerate(GRID):
        # each pose alone, held still, by another method (Newton-Euler, not the kernel)
        _, alone = inverse_dynamics(Robot(), Motion.at_rest(pose), "newton-euler")
        for i, leg in enumerate("ABC"):
            assert table[f"f10_{leg}"][k] == pytest.approx(alone.f10[i], rel=1e-12, abs=1e-12)
            assert table[f"p10_{leg}"][k] == 0.0  # at rest: no power
    # a static pose needs force: the weight is carried (the grid is not trivially zero)
    assert np.abs(table["f10_A"]).max() > 1.0


def test_a_static_grid_balances_the_weight_by_virtual_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # at rest the actuators' virtual work is the rise of the potential: for a robot
    # whose weight is the platform's (legs of 1e-12 kg), sum_i f10_i·dλ10_i/dy = m·g
    light = tmp_path / "light.toml"
    light.write_text("[platform]\nmass = 2.0\n[piston]\nmass = 1e-12\n"
                     "[link]\nmass = 1e-12\ninertia = 0.0\n")  # fmt: skip
    robot = Robot.from_toml(light)
    file = grid_file(tmp_path)
    status, _, err = cli(
        capsys, "simulate", "--robot", light, "--trajectory", file, "-o", tmp_path / "o"
    )
    assert status == 0, err
    table = read_results(tmp_path / "o" / "results.csv")
    h = 1e-6  # dλ10/dy by central differences of the inverse geometry (eq. 10)
    for k, pose in enumerate(GRID):
        f10 = np.array([table[f"f10_{leg}"][k] for leg in "ABC"])
        up = inverse_geometry(robot, np.add(pose, [0.0, h, 0.0])).lambda10
        down = inverse_geometry(robot, np.add(pose, [0.0, -h, 0.0])).lambda10
        assert float(f10 @ ((up - down) / (2 * h))) == pytest.approx(2.0 * 9.81, rel=1e-7)


def test_a_static_grid_runs_for_a_family_robot(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot_file = family_robot_file(tmp_path, "3-RRR")
    file = grid_file(tmp_path)
    status, _, err = cli(
        capsys, "simulate", "--robot", robot_file, "--trajectory", file, "-o", tmp_path / "out"
    )
    assert status == 0, err
    table = read_results(tmp_path / "out" / "results.csv")
    robot = read_robot_file(robot_file)
    assert isinstance(robot, FamilyRobot)
    for k, pose in enumerate(GRID):
        # each pose alone (its own path from home), by the Newton-Euler route
        alone = family_inverse_dynamics(robot, Motion.at_rest(pose), "newton-euler")
        for i, leg in enumerate("ABC"):
            assert table[f"tau_{leg}"][k] == pytest.approx(alone.tau[i], rel=1e-10, abs=1e-10)
            assert table[f"p_{leg}"][k] == 0.0


# ------------------------------------------------------------------ measured data
def test_measured_data_with_noisy_rates_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    motion = paper_motion("rotation", 31)
    noise = np.random.default_rng(7)
    velocity = motion.velocity * (1.0 + 0.5 * noise.standard_normal((31, 3)))
    acceleration = motion.acceleration + 0.3 * noise.standard_normal((31, 3))
    # the rates miss the steps by far more than round-off (the old refusal's 25 %)
    h = np.diff(motion.t)[:, None]
    trapezoid = h * (velocity[1:] + velocity[:-1]) / 2
    misfit = np.abs(np.diff(motion.pose, axis=0) - trapezoid)[:, 2]
    assert misfit.max() > 0.25 * np.abs(np.diff(motion.pose, axis=0)[:, 2]).max()
    rows = np.column_stack([motion.t, motion.pose, velocity, acceleration]).tolist()
    file = write(tmp_path / "measured.csv", rows)
    status, _, err = cli(capsys, "simulate", "--trajectory", file, "-o", tmp_path / "out")
    assert status == 0, err
    assert "consistent derivatives" not in err and "jumps" not in err
    table = read_results(tmp_path / "out" / "results.csv")
    # every sample is the library's answer for that state (another method)
    read = read_trajectory(file).motion
    _, dyn = inverse_dynamics(Robot(), read, "newton-euler")
    np.testing.assert_allclose(table["f10_B"], dyn.f10[:, 1], rtol=1e-10, atol=1e-10)


# ------------------------------------------------------------------ crossings
def crossing_rows() -> list[list[float]]:
    # φ = 2t every 0.2 s: φ passes π/3 between t = 0.4 and 0.6 s (lines 4 and 5)
    return [[0.2 * k, 0.01, 0.0, 0.4 * k, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0] for k in range(6)]


def test_a_crossing_between_two_static_samples_is_refused_naming_both(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    file = write(tmp_path / "cross.csv", crossing_rows())  # zero rates: judged from the poses
    status, out, err = cli(capsys, "simulate", "--trajectory", file, "-o", tmp_path / "out")
    line = one_line(err)
    assert status == 2 and out == ""
    assert line.startswith(f"prp3 simulate: error: {file}:5: sample 3, t = 0.6 s: ")
    assert "crosses the singular orientation phi = 1.0472 rad" in line
    assert "line 4 (t = 0.4 s, phi = 0.8)" in line and "line 5 (t = 0.6 s, phi = 1.2)" in line
    assert not (tmp_path / "out").exists()


def test_a_family_crossing_between_two_samples_is_refused_naming_both(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # the 3-PRR actuated at joint 2 has a parallel singularity at φ = atan(1/2) = 0.4636
    robot_file = family_robot_file(tmp_path, "3-PRR", 2)
    rows = [[t, 0.0, 0.0, phi] + [0.0] * 6 for t, phi in ((0.0, 0.0), (1.0, 0.3), (2.0, 0.7))]
    file = write(tmp_path / "prr.csv", rows)
    status, _, err = cli(
        capsys, "simulate", "--robot", robot_file, "--trajectory", file, "-o", tmp_path / "out"
    )
    line = one_line(err)
    assert status == 2
    assert line.startswith(f"prp3 simulate: error: {file}:4: sample 2, t = 2 s: mu_par = ")
    assert "on the way from sample 1 (t = 1 s) to sample 2 (t = 2 s)" in line
    assert "a singularity crossed" in line
    assert math.atan(0.5) == pytest.approx(0.4636, abs=1e-4)
    assert not (tmp_path / "out").exists()


def test_a_family_crossing_at_the_later_sample_names_both(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # the family's 3-PRP takes only the home side of φ = π/3: the sample beyond it
    # is named with the sample before it
    robot_file = family_robot_file(tmp_path, "3-PRP")
    file = write(tmp_path / "cross.csv", crossing_rows())
    status, _, err = cli(
        capsys, "simulate", "--robot", robot_file, "--trajectory", file, "-o", tmp_path / "out"
    )
    line = one_line(err)
    assert status == 2 and f"{file}:5: sample 3, t = 0.6 s, leg " in line
    assert "between sample 2 (t = 0.4 s) and sample 3 (t = 0.6 s)" in line


def test_a_family_robot_is_not_held_to_the_3_prp_crossing_rule(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # φ passes π/3 between two samples: refused for the 3-PRP, not a singularity of the
    # default 3-RPR (its own measures are checked along the path)
    robot_file = family_robot_file(tmp_path, "3-RPR")
    file = write(tmp_path / "cross.csv", crossing_rows())
    status, _, err = cli(
        capsys, "simulate", "--robot", robot_file, "--trajectory", file, "-o", tmp_path / "out"
    )
    assert status == 0, err
    motion = read_trajectory(file, crossing=False).motion
    robot = read_robot_file(robot_file)
    assert isinstance(robot, FamilyRobot)
    solution = family_inverse_dynamics(robot, motion, "newton-euler")
    assert np.abs(solution.kinematics.mu_leg).min() > 1e-4  # regular all along
    table = read_results(tmp_path / "out" / "results.csv")
    np.testing.assert_allclose(table["tau_C"], solution.tau[:, 2], rtol=1e-10, atol=1e-10)
    with pytest.raises(Exception, match="crosses the singular orientation"):
        read_trajectory(file)  # the 3-PRP's rule, by default


# ------------------------------------------------------------------ overflow
@pytest.mark.parametrize(
    ("rates", "result", "column"),
    [
        ([1e200] * 3, "ddlambda10", "dx"),  # φ̇² terms overflow λ̈10
        ([0.0, 0.0, 1e200], "ddlambda10", "dphi"),
        ([1e307, 0.0, 0.0], "p10", "dx"),  # λ̇10 finite, p10 = f10·λ̇10 beyond float64
    ],
)
def test_rates_that_overflow_the_results_name_the_column(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], rates: list[float], result: str,
    column: str,
) -> None:  # fmt: skip
    rows = [[0.1 * k, 0.01 * k, 0.0, 0.0, *rates, 0.0, 0.0, 0.0] for k in range(4)]
    file = write(tmp_path / "big.csv", rows)
    status, _, err = cli(capsys, "simulate", "--trajectory", file, "-o", tmp_path / "out")
    line = one_line(err)
    assert status == 2
    assert line.startswith(
        f"prp3 simulate: error: {file}:2: sample 0, t = 0 s: the results overflow"
    )
    assert f"{result} is not finite" in line and f"(column {column})" in line
    assert "step" not in line  # not "a step the rates do not explain"
    with pytest.raises(TrajectoryError) as caught:
        inverse_dynamics(Robot(), read_trajectory(file).motion)
    assert caught.value.key == column and caught.value.sample == 0


@pytest.mark.parametrize("engine", ["numpy", "numba"])
def test_a_family_power_that_overflows_is_refused(engine: str) -> None:
    # p = τ·q̇a overflows while τ and q̇ are finite (was: inf in results.csv)
    motion = Motion(t=[0.0, 1.0], pose=[[0.0, 0.0, 0.0], [0.01, 0.0, 0.0]],
                    velocity=[[1e307, 0.0, 0.0]] * 2, acceleration=np.zeros((2, 3)))  # fmt: skip
    with pytest.raises(TrajectoryError, match="p is not finite") as caught:
        family_inverse_dynamics(FamilyRobot.default("3-PRP"), motion, engine=engine)  # type: ignore[arg-type]
    assert caught.value.key == "dx" and "(column dx)" in str(caught.value)


def test_family_rates_that_overflow_name_the_column(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot_file = family_robot_file(tmp_path, "3-RRR")
    rows = [[0.1 * k, 0.01 * k, 0.0, 0.0, 1e200, 1e200, 1e200, 0.0, 0.0, 0.0] for k in range(4)]
    file = write(tmp_path / "big.csv", rows)
    status, _, err = cli(
        capsys, "simulate", "--robot", robot_file, "--trajectory", file, "-o", tmp_path / "out"
    )
    line = one_line(err)
    assert status == 2 and "the results overflow" in line and "(column dx)" in line


# ------------------------------------------------------------------ tiny time steps
@pytest.mark.parametrize("dt", [1e-300, 5e-324, 2.0**-1060])
@pytest.mark.parametrize("robot", ["3-PRP model", "3-RRR"])
def test_tiny_time_steps_are_accepted(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], dt: float, robot: str
) -> None:
    file = grid_file(tmp_path, dt)  # static poses, with their rates (zero)
    robot_args = [] if robot == "3-PRP model" else ["--robot", family_robot_file(tmp_path, robot)]
    status, _, err = cli(
        capsys, "simulate", *robot_args, "--trajectory", file, "-o", tmp_path / "out"
    )
    assert status == 0, err
    table = read_results(tmp_path / "out" / "results.csv")
    assert table["t"].tolist() == [k * dt for k in range(len(GRID))]
    assert all(np.isfinite(column).all() for column in table.values())


@pytest.mark.parametrize("dt", [1e-300, 5e-324])
def test_tiny_time_steps_of_positions_only(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], dt: float
) -> None:
    # the platform held still (positions only): the spline's rates are exactly zero
    # (was: velocities of 1e282 from round-off over 1e-300 s, a scipy ValueError when subnormal)
    rows = [[k * dt, 0.01, 0.02, 0.1] for k in range(8)]
    file = write(tmp_path / "still.csv", rows, "t,x,y,phi")
    motion = read_trajectory(file).motion
    assert not motion.velocity.any() and not motion.acceleration.any()
    status, _, err = cli(capsys, "simulate", "--trajectory", file, "-o", tmp_path / "out")
    assert status == 0, err
    # moving positions over 1e-300 s need rates beyond float64: refused, named (no traceback)
    moving = write(tmp_path / "moving.csv", [[k * dt, 0.001 * k, 0.0, 0.0] for k in range(8)],
                   "t,x,y,phi")  # fmt: skip
    status, _, err = cli(capsys, "simulate", "--trajectory", moving, "-o", tmp_path / "o2")
    line = one_line(err)
    assert status == 2 and "computed from the positions is not finite" in line


def test_a_control_run_over_1e_300_s(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    rows = [[k * 1e-300, 0.01, 0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0] for k in range(4)]
    file = write(tmp_path / "tiny.csv", rows)
    status, _, err = cli(capsys, "control", "--controller", "computed-torque", "--plant", "prp3",
                         "--trajectory", file, "-o", tmp_path / "out")  # fmt: skip
    assert status == 0, err
    assert "warning" not in err  # was: overflow encountered in divide
    assert control_times(0.0, 3e-300, 100.0).tolist() == [0.0, 3e-300]


def test_the_hermite_reference_at_tiny_steps_is_the_quintic() -> None:
    # x = t/2 is a quintic: reproduced exactly between samples 2^-996 s apart
    h = 2.0**-996
    t = np.arange(4) * h
    motion = Motion(t=t, pose=np.stack([0.5 * t, 0 * t, 0 * t], -1),
                    velocity=np.tile([0.5, 0.0, 0.0], (4, 1)), acceleration=np.zeros((4, 3)))  # fmt: skip
    at = np.array([0.25, 1.5, 2.75]) * h
    reference = hermite_reference(motion, at)
    assert reference.pose[:, 0].tolist() == (0.5 * at).tolist()
    assert reference.velocity[:, 0].tolist() == [0.5] * 3
    assert reference.acceleration.tolist() == [[0.0] * 3] * 3


def test_the_hermite_reference_is_scipy_s_quintic() -> None:
    # an independent construction of the same polynomials (BPoly.from_derivatives)
    from scipy.interpolate import BPoly

    motion = paper_motion("rotation", 13)
    at = np.linspace(0.0, 3.0, 97)
    reference = hermite_reference(motion, at)
    knots = np.stack([motion.pose, motion.velocity, motion.acceleration], axis=1)
    for axis in range(3):
        spline = BPoly.from_derivatives(motion.t, knots[:, :, axis])
        for order, got in enumerate((reference.pose, reference.velocity, reference.acceleration)):
            expected = spline.derivative(order)(at) if order else spline(at)
            np.testing.assert_allclose(got[:, axis], expected, rtol=1e-10, atol=1e-12)
