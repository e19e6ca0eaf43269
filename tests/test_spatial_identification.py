"""Identification of the spatial robots (docs/identification.md, "Spatial robots").

* ``Y·π`` equals the actuator efforts of the Newton–Euler route (docs/spatial.md §8
  route (b), which the regressor does not run: it is built on route (a)) on random
  hexapods, 3-RPS and Deltas along random smooth motions, with ``π`` written out here
  from the bodies (``m``, ``m·c``, ``J = I + m(|c|²·1 − c·cᵀ)`` about the frame origin);
* noise-free efforts give back the base parameters (``combination·π`` of those ``π``);
* with seeded noise the estimate lies within a few of its standard deviations;
* the command line round trip excite → simulate → identify, and its refusals.
"""

from __future__ import annotations

import csv
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from clitools import cli, listing, one_line
from prp3.apps.spatial_identification import (
    spatial_base_parameters,
    spatial_identified_robot,
    spatial_identify,
    spatial_parameter_names,
    spatial_random_motion,
    spatial_regressor,
    spatial_standard_parameters,
)
from prp3.errors import ParameterError, TrajectoryError
from prp3.io.spatial_robot import read_spatial_robot, spatial_robot_from_mapping
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import Body, SpatialRobot, delta, hexapod, three_rps
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.outputs import spatial_inverse_dynamics
from spatial_strategies import deltas, hexapods, rps_robots, waves

FEW = settings(max_examples=4, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def reference_parameters(body: Body) -> list[float]:
    """The ten standard parameters of ``body``, written out here."""
    m = body.mass
    cx, cy, cz = body.centre
    i = body.inertia
    return [
        m, m * cx, m * cy, m * cz,
        i[0][0] + m * (cy * cy + cz * cz), i[0][1] - m * cx * cy, i[0][2] - m * cx * cz,
        i[1][1] + m * (cx * cx + cz * cz), i[1][2] - m * cy * cz,
        i[2][2] + m * (cx * cx + cy * cy),
    ]  # fmt: skip


def reference_vector(robot: SpatialRobot, per_leg: bool = False) -> np.ndarray:
    """``π`` in the documented order: the platform, then the leg bodies from the platform in."""
    values = reference_parameters(robot.platform)
    legs = robot.legs if per_leg else robot.legs[:1]
    for leg in legs:
        for body in reversed(leg.bodies):
            values += reference_parameters(body)
    return np.array(values)


def _efforts(robot: SpatialRobot, motion: PlatformMotion) -> np.ndarray:
    return spatial_inverse_dynamics(robot, motion, "newton-euler").tau


@FEW
@given(st.sampled_from(["6-UPS", "3-RPS", "3-RUU"]), st.data())
def test_the_regressor_times_the_parameters_is_the_newton_euler_efforts(
    kind: str, data: st.DataObject
) -> None:
    strategy = {"6-UPS": hexapods(), "3-RPS": rps_robots(), "3-RUU": deltas()}[kind]
    robot = data.draw(strategy)
    motion = complete_motion(robot, data.draw(waves(robot)).motion(np.linspace(0.0, 1.5, 9)))
    tau = _efforts(robot, motion)
    scale = max(float(np.abs(tau).max()), 1.0)
    for per_leg in (False, True):
        Y = spatial_regressor(robot, motion, per_leg=per_leg)
        assert Y.tau.shape == (
            9,
            len(robot.legs),
            len(spatial_parameter_names(robot, per_leg=per_leg)),
        )
        np.testing.assert_allclose(
            Y.tau @ reference_vector(robot, per_leg), tau, rtol=0, atol=1e-10 * scale
        )
        np.testing.assert_allclose(
            spatial_standard_parameters(robot, per_leg=per_leg), reference_vector(robot, per_leg),
            rtol=1e-12, atol=1e-15,
        )  # fmt: skip


def test_per_leg_columns_sum_to_the_shared_ones() -> None:
    robot = three_rps()
    motion = spatial_random_motion(robot, 12, seed=4)
    shared = spatial_regressor(robot, motion).tau
    each = spatial_regressor(robot, motion, per_leg=True).tau
    legs = len(robot.legs)
    platform, rest = each[..., :10], each[..., 10:].reshape(12, legs, legs, -1)
    np.testing.assert_allclose(shared[..., :10], platform, atol=1e-14)
    np.testing.assert_allclose(shared[..., 10:], rest.sum(axis=2), atol=1e-13)


@pytest.mark.parametrize("robot", [hexapod(), three_rps(), delta()], ids=lambda r: r.name)
def test_noise_free_efforts_give_the_base_parameters(robot: SpatialRobot) -> None:
    motion = spatial_random_motion(robot, 150, seed=7)
    result = spatial_identify(robot, motion, _efforts(robot, motion))
    true = result.base.combination @ reference_vector(robot)
    np.testing.assert_allclose(result.estimate, true, rtol=1e-8, atol=1e-8 * np.abs(true).max())
    # the base regressor reproduces the efforts: the combinations are those of this robot
    assert np.abs(result.fitted - result.measured).max() < 1e-10 * np.abs(result.measured).max()


def test_an_off_axis_design_is_recovered_too() -> None:
    rod = Body(
        0.07, (-0.02, 0.004, -0.003), ((2e-5, 1e-6, 0), (1e-6, 3e-5, 0), (0, 0, 3.5e-5)), "rod"
    )
    platform = Body(1.3, (0.004, -0.006, 0.01), ((2e-3, 1e-4, 0), (1e-4, 1.5e-3, 0), (0, 0, 3e-3)), "platform")  # fmt: skip
    robot = hexapod(rod=rod, platform=platform, gravity=(0.5, -0.3, -9.7))
    motion = spatial_random_motion(robot, 150, seed=2)
    result = spatial_identify(robot, motion, _efforts(robot, motion))
    true = result.base.combination @ reference_vector(robot)
    np.testing.assert_allclose(result.estimate, true, rtol=1e-8, atol=1e-8 * np.abs(true).max())


def test_the_estimate_of_noisy_efforts_lies_within_its_standard_deviations() -> None:
    robot = three_rps()
    motion = spatial_random_motion(robot, 400, seed=11)
    tau = _efforts(robot, motion)
    rng = np.random.default_rng(5)
    noise = rng.normal(size=tau.shape) * 0.02 * np.array([1.0, 2.0, 0.5])
    result = spatial_identify(robot, motion, tau + noise)
    true = result.base.combination @ reference_vector(robot)
    z = (result.estimate - true) / result.std
    assert np.abs(z).max() < 5.0, z
    # the weights are the actuators' noise levels
    np.testing.assert_allclose(result.sigma, [0.02, 0.04, 0.01], rtol=0.15)


def test_the_identified_robot_reproduces_the_base_parameters() -> None:
    design = spatial_robot_from_mapping({"architecture": "3-RUU"})
    motion = spatial_random_motion(design.robot, 120, seed=1)
    tau = _efforts(design.robot, motion)
    result = spatial_identify(design.robot, motion, tau * 1.1)  # every body 10 % heavier
    identified = spatial_identified_robot(design, result)
    np.testing.assert_allclose(_efforts(identified.robot, motion), 1.1 * tau, rtol=1e-8, atol=1e-10)


def test_refusals() -> None:
    robot = hexapod()
    motion = spatial_random_motion(robot, 150, seed=0)
    with pytest.raises(TrajectoryError, match=r"tau must be an array of shape \(150, 6\)"):
        spatial_identify(robot, motion, np.zeros((150, 3)))
    with pytest.raises(TrajectoryError, match="too few"):
        short = spatial_random_motion(robot, 20, seed=0)
        spatial_identify(robot, short, np.zeros((20, 6)))
    rest = PlatformMotion.at_rest(np.repeat([robot.home_position], 150, axis=0))
    with pytest.raises(TrajectoryError, match="does not excite"):
        spatial_identify(robot, rest, _efforts(robot, rest))
    with pytest.raises(ParameterError, match="per_leg must be True or False"):
        spatial_regressor(robot, motion, per_leg="yes")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="robot must be"):
        spatial_regressor("robot", motion)  # type: ignore[arg-type]
    legs = list(robot.legs)
    heavy = Body(0.2, (0.02, 0.0, 0.0), ((1e-5, 0, 0), (0, 4e-5, 0), (0, 0, 4e-5)), "cylinder")
    legs[2] = type(legs[2])(legs[2].joints, (heavy, legs[2].bodies[1]), legs[2].attachment_position, legs[2].attachment_rotation, 1)  # fmt: skip
    odd = SpatialRobot(robot.name, tuple(legs), robot.platform, robot.gravity, robot.home_position)
    with pytest.raises(ParameterError, match=r"leg 3's body 1 .* differs"):
        spatial_standard_parameters(odd)
    assert spatial_standard_parameters(odd, per_leg=True).shape == (130,)


def test_the_base_parameters_are_the_documented_ones() -> None:
    # docs/identification.md, "Spatial robots": the counts and what stays unidentifiable
    counts = {}
    for robot in (hexapod(), three_rps(), delta()):
        base = spatial_base_parameters(robot)
        counts[robot.name] = (base.count, spatial_base_parameters(robot, per_leg=True).count)
    assert counts == {"6-UPS": (22, 82), "3-RPS": (15, 25), "3-RUU": (12, 34)}
    # the fixed centre of the U (6-UPS) carries no mass
    assert spatial_base_parameters(hexapod()).unidentifiable == ("cylinder_mass",)


# ------------------------------------------------------------ command line


def _measurements(trajectory: Path, results: Path, out: Path, legs: int) -> None:
    rows = list(csv.reader(trajectory.read_text().splitlines()))
    simulated = list(csv.reader(results.read_text().splitlines()))
    columns = [simulated[0].index(f"tau_{i + 1}") for i in range(legs)]
    with out.open("w", newline="") as stream:
        writer = csv.writer(stream)
        for row, sim in zip(rows, simulated, strict=True):
            writer.writerow(row + [sim[c] for c in columns])


def test_excite_simulate_identify_round_trip(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text(
        'architecture = "3-RPS"\n[platform]\nmass = 1.4\ncentre = [0.003, -0.002, 0.01]\n'
    )
    status, out, err = cli(
        capsys, "excite", "--robot", robot_file, "--output", tmp_path / "ex",
        "--samples", "301", "--iterations", "3", "--rotation", "0.3",
    )  # fmt: skip
    assert status == 0, err
    assert "condition number" in out
    header = (tmp_path / "ex" / "trajectory.csv").read_text().splitlines()[0]
    assert header.startswith("t,x,y,z,qw,qx,qy,qz,wx,wy,wz")
    status, out, err = cli(
        capsys, "simulate", "--robot", robot_file, "--trajectory", tmp_path / "ex" / "trajectory.csv",
        "--output", tmp_path / "sim",
    )  # fmt: skip
    assert status == 0, err
    measured = tmp_path / "m.csv"
    _measurements(tmp_path / "ex" / "trajectory.csv", tmp_path / "sim" / "results.csv", measured, 3)
    status, out, err = cli(
        capsys, "identify", "--robot", robot_file, "--measurements", measured,
        "--output", tmp_path / "id",
    )  # fmt: skip
    assert status == 0, err
    nominal = read_spatial_robot(robot_file).robot
    base = spatial_base_parameters(nominal)
    true = dict(zip(base.names, base.combination @ reference_vector(nominal), strict=True))
    with (tmp_path / "id" / "parameters.csv").open() as stream:
        rows = list(csv.DictReader(stream))
    assert [row["name"] for row in rows] == list(base.names)
    top = max(abs(v) for v in true.values())
    for row in rows:
        # the file's rates carry the float64 round-off of its 17-digit numbers
        assert abs(float(row["estimate"]) - true[row["name"]]) < 1e-8 * top, row
    identified = tomllib.loads((tmp_path / "id" / "robot.toml").read_text())
    assert identified["architecture"] == "3-RPS"
    assert identified["platform"]["mass"] == pytest.approx(1.4, rel=1e-8)
    assert identified["platform"]["centre"] == pytest.approx([0.003, -0.002, 0.01], abs=1e-9)


@pytest.mark.parametrize(
    ("command", "extra", "message"),
    [
        ("identify", ["--friction", "viscous"], "the spatial robots have no friction model"),
        ("identify", [], "missing column(s) tau_1, tau_2, tau_3"),
        ("excite", ["--samples", "20"], "too few to identify"),
        ("excite", ["--max-force", "1e-6", "--iterations", "1"], "no exciting motion of the 3-RUU"),
    ],
)
def test_refusals_leave_earlier_results(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, command: str, extra: list[str], message: str
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-RUU"\n')
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "old.txt").write_text("earlier")
    trajectory = tmp_path / "t.csv"
    trajectory.write_text(
        "t,x,y,z,roll,pitch,yaw\n" + "".join(f"{k},0,0,-0.2,0,0,0\n" for k in range(40))
    )
    argv = [command, "--robot", robot_file, "--output", out_dir, *extra]
    if command == "identify":
        argv += ["--measurements", trajectory]
    before = listing(out_dir)
    status, _out, err = cli(capsys, *argv)
    assert status == 2
    assert message in one_line(err)
    assert listing(out_dir) == before


def _write_measurements(path: Path, motion: PlatformMotion, tau: np.ndarray) -> None:
    """A spatial trajectory file with the rates and the efforts ``tau`` (written out here)."""
    from scipy.spatial.transform import Rotation

    xyzw = Rotation.from_matrix(motion.rotation).as_quat()
    columns = {"t": motion.t, "x": motion.position[:, 0], "y": motion.position[:, 1]}
    columns["z"] = motion.position[:, 2]
    for k, name in enumerate(("qx", "qy", "qz", "qw")):
        columns[name] = xyzw[:, k]
    for prefix, values in (
        ("w", motion.omega), ("v", motion.velocity), ("dw", motion.alpha), ("a", motion.acceleration),
    ):  # fmt: skip
        for k, axis in enumerate("xyz"):
            columns[prefix + axis] = values[:, k]
    for i in range(tau.shape[1]):
        columns[f"tau_{i + 1}"] = tau[:, i]
    names = list(columns)
    rows = [",".join(names)]
    rows += [",".join(repr(float(columns[n][k])) for n in names) for k in range(len(motion))]
    path.write_text("\n".join(rows) + "\n")


def test_an_estimate_of_no_body_writes_no_robot_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "6-UPS"\n')
    robot = read_spatial_robot(robot_file).robot
    motion = spatial_random_motion(robot, 130, seed=9)
    tau = _efforts(robot, motion)
    measured = tmp_path / "m.csv"
    _write_measurements(measured, motion, tau)
    status, out, err = cli(
        capsys, "identify", "--robot", robot_file, "--measurements", measured, "--output", tmp_path / "id"
    )  # fmt: skip
    assert status == 0, err
    assert (tmp_path / "id" / "robot.toml").exists()
    identified = read_spatial_robot(tmp_path / "id" / "robot.toml").robot
    np.testing.assert_allclose(_efforts(identified, motion), tau, rtol=1e-8, atol=1e-10)
    # negative efforts: negative masses, no body has them; the stale robot.toml goes too
    _write_measurements(measured, motion, -tau)
    status, out, err = cli(
        capsys, "identify", "--robot", robot_file, "--measurements", measured, "--output", tmp_path / "id"
    )  # fmt: skip
    assert status == 0, err
    assert "robot.toml not written: the identified rod parameters are not those of a body" in out
    assert "files removed" in out
    assert not (tmp_path / "id" / "robot.toml").exists()
    assert (tmp_path / "id" / "parameters.csv").exists()
