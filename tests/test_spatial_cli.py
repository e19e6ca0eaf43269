"""The spatial robot file, the spatial trajectory file and ``prp3 simulate`` of a spatial robot
(docs/spatial.md §13–§15).

The columns of ``results.csv`` are held against what they must be from first principles
(the platform's Newton–Euler balance under the reported wrenches of its joints, the actuator's
length, rate and effort from the geometry) and against the library's route on the robot the
constructor builds; the readers on good and bad files.
"""

from __future__ import annotations

import csv
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clitools import cli, one_line
from prp3.errors import InputFileError, TrajectoryError
from prp3.io.spatial_robot import (
    SPATIAL_ARCHITECTURES,
    read_spatial_robot,
    spatial_robot_text,
)
from prp3.io.spatial_trajectory import read_spatial_trajectory
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import Body, delta, hexapod, three_rps
from prp3.spatial.motion import spatial_motion
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table
from prp3.spatial.rotations import matrix_quaternion

ROOT = Path(__file__).resolve().parents[1]

CONSTRUCTORS = {"6-UPS": hexapod, "3-RPS": three_rps, "3-RUU": delta}


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return {name: values[:, c] for c, name in enumerate(rows[0])}


def _robot_file(folder: Path, architecture: str, extra: str = "") -> Path:
    path = folder / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\n{extra}', encoding="utf-8")
    return path


def _simulate(capsys, folder: Path, robot: Path, *options: object) -> dict[str, np.ndarray]:
    out = folder / "out"
    status, stdout, err = cli(capsys, "simulate", "--robot", robot, *options, "--output", out)
    assert status == 0, err
    assert "files written:" in stdout
    return _read_csv(out / "results.csv")


# ------------------------------------------------------------ results.csv from first principles


def _rot_x(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rot_y(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _hexapod_tilt(t: float) -> tuple[np.ndarray, ...]:
    """docs/spatial.md §15's tilt of the default hexapod at ``t``, written out here: the pose,
    ``ω`` and ``α`` of ``R = Rot_y(pitch)·Rot_x(roll)``, ``roll = 0.1 sin θ``,
    ``pitch = 0.1 (1 − cos θ)``, ``θ = 2πt/3``; ``p`` fixed at home."""
    w = 2.0 * math.pi / 3.0
    th = w * t
    roll, pitch = 0.1 * math.sin(th), 0.1 * (1.0 - math.cos(th))
    droll, dpitch = 0.1 * w * math.cos(th), 0.1 * w * math.sin(th)
    ddroll, ddpitch = -0.1 * w * w * math.sin(th), 0.1 * w * w * math.cos(th)
    ey = np.array([0.0, 1.0, 0.0])
    ex = _rot_y(pitch) @ np.array([1.0, 0.0, 0.0])  # the roll axis, turned by the pitch
    omega = dpitch * ey + droll * ex
    alpha = ddpitch * ey + ddroll * ex + droll * np.cross(dpitch * ey, ex)
    rotation = _rot_y(pitch) @ _rot_x(roll)
    zero = np.zeros(3)
    return np.array([0.0, 0.0, 0.08]), rotation, omega, zero, alpha, zero


def test_the_hexapod_platform_balances_under_the_reported_wrenches(capsys, tmp_path):
    """Σ F (S joints on the platform) = m (a − g), Σ r × F = I α + ω × I ω (world frame, I
    turned by R), at every sample of the tilt; the platform's numbers are docs/spatial.md §7's.
    The P joint's force along the leg is τ, its length the distance from U to S centre and its
    rate the leg's end velocity along the leg."""
    table = _simulate(
        capsys, tmp_path, _robot_file(tmp_path, "6-UPS"), "--motion", "tilt", "--samples", 13
    )
    robot = hexapod()
    mass, inertia = 1.0, np.diag([1.225e-3, 1.225e-3, 2.45e-3])
    g = np.array([0.0, 0.0, -9.81])
    assert len(table["t"]) == 13
    for k, t in enumerate(table["t"]):
        p, rotation, omega, v, alpha, a = _hexapod_tilt(float(t))
        force = np.zeros(3)
        moment = np.zeros(3)
        for i, leg in enumerate(robot.legs):
            f = np.array([table[f"F{c}_{i + 1}_S3"][k] for c in "xyz"])
            m = np.array([table[f"M{c}_{i + 1}_S3"][k] for c in "xyz"])
            centre = p + rotation @ np.array(leg.attachment_position)
            force += f
            moment += np.cross(centre - p, f) + m
            base = np.array(leg.joints[0].position)
            length = float(np.linalg.norm(centre - base))
            along = (centre - base) / length
            assert table[f"q_{i + 1}_P2"][k] == pytest.approx(length, rel=1e-12)
            end_velocity = v + np.cross(omega, centre - p)
            assert table[f"dq_{i + 1}_P2"][k] == pytest.approx(
                float(along @ end_velocity), rel=1e-9, abs=1e-12
            )
            slide = np.array([table[f"F{c}_{i + 1}_P2"][k] for c in "xyz"])
            assert float(slide @ along) == pytest.approx(table[f"tau_{i + 1}"][k], rel=1e-9)
            assert table[f"power_{i + 1}"][k] == pytest.approx(
                table[f"tau_{i + 1}"][k] * table[f"dq_{i + 1}_P2"][k], rel=1e-12, abs=1e-15
            )
        world_inertia = rotation @ inertia @ rotation.T
        np.testing.assert_allclose(force, mass * (a - g), rtol=1e-9, atol=1e-9)
        expected = world_inertia @ alpha + np.cross(omega, world_inertia @ omega)
        np.testing.assert_allclose(moment, expected, rtol=1e-7, atol=1e-9)


def test_the_delta_platform_balances_on_the_circle(capsys, tmp_path):
    """The Delta's circle: ``p = home + 0.01·(cos θ − 1, sin θ, 0)`` m, ``R = I``; the U3
    joints' forces give ``m (a − g)`` (0.2 kg) and no moment about ``p`` in all (ω = α = 0)."""
    table = _simulate(
        capsys, tmp_path, _robot_file(tmp_path, "3-RUU"), "--motion", "circle", "--samples", 9
    )
    w = 2.0 * math.pi / 3.0
    for k, t in enumerate(table["t"]):
        th = w * float(t)
        a = -0.01 * w * w * np.array([math.cos(th), math.sin(th), 0.0])
        force, moment = np.zeros(3), np.zeros(3)
        for i in range(3):
            angle = -math.pi / 2 + 2.0 * math.pi * i / 3.0
            r = 0.03 * np.array([math.cos(angle), math.sin(angle), 0.0])
            f = np.array([table[f"F{c}_{i + 1}_U3"][k] for c in "xyz"])
            force += f
            moment += np.cross(r, f) + np.array([table[f"M{c}_{i + 1}_U3"][k] for c in "xyz"])
        np.testing.assert_allclose(force, 0.2 * (a - np.array([0.0, 0.0, -9.81])), atol=1e-10)
        np.testing.assert_allclose(moment, 0.0, atol=1e-11)


@pytest.mark.parametrize(
    "architecture, motion",
    [("6-UPS", "heave"), ("6-UPS", "circle"), ("3-RPS", "tilt"), ("3-RUU", "heave")],
)
def test_results_are_the_library_route_on_the_constructors_robot(
    capsys, tmp_path, architecture, motion
):
    """Every column of §9, in its order, equal to spatial_inverse_dynamics on the robot the
    constructor builds (an empty file: the defaults), the motion completed (§11)."""
    table = _simulate(
        capsys,
        tmp_path,
        _robot_file(tmp_path, architecture),
        "--motion",
        motion,
        "--samples",
        7,
    )
    robot = CONSTRUCTORS[architecture]()
    solution = spatial_inverse_dynamics(
        robot, complete_motion(robot, spatial_motion(robot, motion, 7))
    )
    expected = spatial_results_table(solution)
    assert list(table) == list(expected)
    assert len(table) == {"6-UPS": 229, "3-RPS": 106, "3-RUU": 106}[architecture]  # §15
    for name, values in expected.items():
        np.testing.assert_array_equal(table[name], values, err_msg=name)


def test_a_file_s_parameters_reach_the_results(capsys, tmp_path):
    """A heavier platform (2 kg, its other keys the defaults) and another stroke: the robot of
    ``hexapod(platform=Body(2, ...), stroke=...)``."""
    extra = "stroke = [0.08, 0.13]\n[platform]\nmass = 2.0\n"
    table = _simulate(
        capsys, tmp_path, _robot_file(tmp_path, "6-UPS", extra), "--motion", "heave",
        "--samples", 5,
    )  # fmt: skip
    default = hexapod().platform
    robot = hexapod(
        stroke=(0.08, 0.13), platform=Body(2.0, default.centre, default.inertia, "platform")
    )
    expected = spatial_results_table(
        spatial_inverse_dynamics(robot, spatial_motion(robot, "heave", 5))
    )
    np.testing.assert_array_equal(table["tau_1"], expected["tau_1"])
    # at rest at t = 0 the six legs carry the weight of 2 kg, more than the default 1 kg's
    assert table["tau_1"][0] > _tau_at_home(capsys, tmp_path)


def _tau_at_home(capsys, tmp_path: Path) -> float:
    folder = tmp_path / "default"
    folder.mkdir()
    table = _simulate(capsys, folder, _robot_file(folder, "6-UPS"), "--motion", "heave",
                      "--samples", 5)  # fmt: skip
    return float(table["tau_1"][0])


# ------------------------------------------------------------ the trajectory file


def _write_motion(path: Path, motion, orientation: str, rates: bool) -> None:
    header = ["t", "x", "y", "z"]
    if orientation == "quaternion":
        header += ["qw", "qx", "qy", "qz"]
        angles = matrix_quaternion(motion.rotation)
    else:
        header += ["roll", "pitch", "yaw"]
        r = motion.rotation
        angles = np.stack(
            [np.arctan2(r[:, 2, 1], r[:, 2, 2]), -np.arcsin(r[:, 2, 0]),
             np.arctan2(r[:, 1, 0], r[:, 0, 0])], axis=-1,
        )  # fmt: skip
    columns = [motion.t[:, None], motion.position, angles]
    if rates:
        header += ["wx", "wy", "wz", "vx", "vy", "vz", "dwx", "dwy", "dwz", "ax", "ay", "az"]
        columns += [motion.omega, motion.velocity, motion.alpha, motion.acceleration]
    values = np.concatenate(columns, axis=1)
    lines = [",".join(header)] + [",".join(repr(float(v)) for v in row) for row in values]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def test_a_trajectory_with_its_rates_gives_the_motion_s_results(capsys, tmp_path):
    """The tilt written as quaternions and twists: the results of ``--motion tilt``."""
    robot = hexapod()
    motion = spatial_motion(robot, "tilt", 9)
    path = tmp_path / "tilt.csv"
    _write_motion(path, motion, "quaternion", rates=True)
    table = _simulate(capsys, tmp_path, _robot_file(tmp_path, "6-UPS"), "--trajectory", path)
    expected = spatial_results_table(spatial_inverse_dynamics(robot, motion))
    for name, values in expected.items():
        np.testing.assert_allclose(table[name], values, rtol=1e-10, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("orientation", ["quaternion", "rpy"])
def test_rates_derived_from_the_poses_are_close_to_the_exact_ones(tmp_path, orientation):
    """Poses only, 201 samples of the tilt: ω and α from the spline within 1e-6 of the exact
    ones away from the ends (they are ``0.1·w`` and ``0.1·w²`` in size)."""
    motion = spatial_motion(hexapod(), "tilt", 201)
    path = tmp_path / "poses.csv"
    _write_motion(path, motion, orientation, rates=False)
    read = read_spatial_trajectory(path)
    assert read.note is not None and "spline" in read.note
    inside = slice(20, -20)
    np.testing.assert_allclose(read.motion.rotation, motion.rotation, atol=1e-14)
    np.testing.assert_allclose(read.motion.omega[inside], motion.omega[inside], atol=1e-8)
    np.testing.assert_allclose(read.motion.alpha[inside], motion.alpha[inside], atol=1e-6)


@pytest.mark.parametrize(
    "text, error, line, words",
    [
        ("t,x,y,z\n0,0,0,0.08\n", InputFileError, 1, "either the columns"),
        ("t,x,y,z,qw,qx,qy,qz,roll,pitch,yaw\n0,0,0,0.08,1,0,0,0,0,0,0\n", InputFileError, 1,
         "not both"),
        ("t,x,y,z,qw,qx,qy\n0,0,0,0.08,1,0,0\n", InputFileError, 1, "missing qz"),
        ("t,x,y,z,roll,pitch,yaw,wx\n0,0,0,0.08,0,0,0,0\n", InputFileError, 1, "rate columns"),
        ("t,x,y,z,roll,pitch,yaw\n0,0,0,0.08,0,0,0\n0.1,0,0,nan,0,0,0\n", InputFileError, 3,
         "'z'"),
        ("t,x,y,z,roll,pitch,yaw\n0,0,0,0.08,0,0,0\n0,0,0,0.08,0,0,0\n", TrajectoryError, 3,
         "time must increase"),
        ("t,x,y,z,qw,qx,qy,qz\n0,0,0,0.08,1,0,0,0\n0.1,0,0,0.08,0.9,0,0,0\n", TrajectoryError,
         3, "not a unit quaternion"),
        ("t,x,y,z,roll,pitch,yaw\n0,0,0,0.08,0,0,0\n", TrajectoryError, 2, "at least 2"),
        # a roll of 1e300 rad is a rotation float64 cannot name (unwrap made it 0 before)
        ("t,x,y,z,roll,pitch,yaw\n0,0,0,0.08,0,0,0\n1,0,0,0.08,1e300,0,0\n", TrajectoryError,
         3, "roll = 1e+300 rad is beyond +-1e+06 rad"),
        ("t,x,y,z,rol,pitch,yaw\n", InputFileError, 1, "unknown column 'rol'"),
    ],
)  # fmt: skip
def test_a_bad_trajectory_is_refused_naming_file_and_line(tmp_path, text, error, line, words):
    path = tmp_path / "traj.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(error) as raised:
        read_spatial_trajectory(path)
    assert str(raised.value).startswith(f"{path}:{line}:"), str(raised.value)
    assert words in str(raised.value)


def test_a_trajectory_of_the_3rps_is_completed_with_a_warning(capsys, tmp_path):
    """x, y and yaw of the file are the 3-RPS's to decide: the run replaces them and says so."""
    robot = three_rps()
    motion = spatial_motion(robot, "tilt", 5)  # x, y, yaw at zero: not closed
    path = tmp_path / "tilt.csv"
    _write_motion(path, motion, "rpy", rates=True)
    out = tmp_path / "out"
    status, _, err = cli(capsys, "simulate", "--robot", _robot_file(tmp_path, "3-RPS"),
                         "--trajectory", path, "--output", out)  # fmt: skip
    assert status == 0, err
    assert "determines wz, vx, vy itself" in err and str(path) in err
    expected = spatial_results_table(
        spatial_inverse_dynamics(robot, complete_motion(robot, motion))
    )
    np.testing.assert_allclose(_read_csv(out / "results.csv")["tau_2"], expected["tau_2"],
                               rtol=1e-10)  # fmt: skip


# ------------------------------------------------------------ the robot file


@pytest.mark.parametrize("architecture", SPATIAL_ARCHITECTURES)
def test_the_template_reads_back_to_the_constructor_s_robot(tmp_path, architecture):
    path = tmp_path / "robot.toml"
    path.write_text(spatial_robot_text(architecture), encoding="utf-8")
    design = read_spatial_robot(path)
    assert design.robot == CONSTRUCTORS[architecture]()
    assert design.architecture == architecture and design.path == path


def test_a_body_table_keeps_the_defaults_it_does_not_give(tmp_path):
    path = _robot_file(tmp_path, "3-RUU", "arm = 0.12\n[forearm_body]\nmass = 0.08\n")
    robot = read_spatial_robot(path).robot
    default = delta(arm=0.12).legs[0].bodies[1]
    assert robot == delta(
        arm=0.12, forearm_body=Body(0.08, default.centre, default.inertia, default.name)
    )
    assert robot.legs[0].bodies[0].centre == (0.06, 0.0, 0.0)  # the arm's centre follows arm


@pytest.mark.parametrize(
    "extra, line, words",
    [
        ("extra = 1.0\n", 2, "unknown key 'extra'"),
        ("[rod]\nmas = 1.0\n", 3, "unknown key 'rod.mas'"),
        ("stroke = [0.12, 0.085]\n", 2, "stroke must have 0 < lower < upper"),
        ("stroke = 0.1\n", 2, "stroke must be an array of 2 numbers"),
        ("home_height = 0.5\n", None, "the home pose [0.0, 0.0, 0.5] m is not a pose"),
        ("[platform]\nmass = 1e308\n", 3, "platform.mass = 1e+308"),
        ("base_radius = 1e300\n", 2, "base_radius must be at most 1e+06 m, got 1e+300"),
        ("[rod]\ninertia = [[1, 0, 0], [0, 1, 0], [0, 0, 5]]\n", 3, "principal moments"),
        ("[rod]\ninertia = [[1, 0, 0], [0, 1, 0]]\n", 3, "rod.inertia must be a 3 x 3 matrix"),
        ("cylinder = 3\n", 2, "[cylinder] must be a table"),
        ("gravity = [0, 0, true]\n", 2, "gravity[2] must be a number, got True"),
    ],
)
def test_a_bad_robot_file_is_refused_naming_file_key_and_line(tmp_path, extra, line, words):
    path = _robot_file(tmp_path, "6-UPS", extra)
    with pytest.raises(InputFileError) as raised:
        read_spatial_robot(path)
    where = f"{path}:{line}:" if line is not None else f"{path}:"
    assert str(raised.value).startswith(where), str(raised.value)
    assert words in str(raised.value)


#: Numbers no key accepts: not finite, beyond float64, not a number at all.
BAD_NUMBERS = ("nan", "-nan", "inf", "-inf", "1e400", "-1e999", "9" * 400, "true", '"0.1"',
               "[]", "{}")  # fmt: skip

#: Each architecture's keys, as ``(table, key, where the bad number goes)``.
_GOOD = {
    "6-UPS": {"base_radius": "0.1", "platform_radius": "0.07", "base_half_angle": "0.2",
              "home_height": "0.08", "stroke": "[0.085, 0.12]", "u_limit": "1.0",
              "s_limit": "1.0", "gravity": "[0.0, 0.0, -9.81]", "scale": "0.1"},
    "3-RPS": {"base_radius": "0.1", "platform_radius": "0.06", "home_height": "0.1",
              "stroke": "[0.06, 0.18]", "r_limit": "1.5", "s_limit": "1.0", "scale": "0.1"},
    "3-RUU": {"base_radius": "0.1", "arm": "0.1", "forearm": "0.25", "platform_radius": "0.03",
              "home_height": "0.2", "r_limit": "1.5", "u_limit": "1.4", "scale": "0.1"},
}  # fmt: skip
_BODY_TABLES = {"6-UPS": ("cylinder", "rod", "platform"), "3-RPS": ("cylinder", "rod", "platform"),
                "3-RUU": ("arm_body", "forearm_body", "platform")}  # fmt: skip


def _spoiled(value: str, bad: str, slot: int) -> str:
    """``value`` (a number or an array of them) with one number replaced by ``bad``."""
    if not value.startswith("["):
        return bad
    parts = value[1:-1].split(",")
    parts[slot % len(parts)] = bad
    return "[" + ", ".join(parts) + "]"


@settings(deadline=None)
@given(
    architecture=st.sampled_from(SPATIAL_ARCHITECTURES),
    bad=st.sampled_from(BAD_NUMBERS),
    choice=st.integers(0, 10**6),
    slot=st.integers(0, 8),
)
def test_a_bad_number_is_refused_naming_file_key_and_line(architecture, bad, choice, slot):
    """Any key, top-level or of a body table, one of its numbers bad: InputFileError whose
    message starts with ``file:line:`` of that key and names it."""
    good = _GOOD[architecture]
    body_keys = [(table, key) for table in _BODY_TABLES[architecture]
                 for key in ("mass", "centre", "inertia")]  # fmt: skip
    targets = [(None, key) for key in good] + body_keys
    table, key = targets[choice % len(targets)]
    lines = [f'architecture = "{architecture}"']
    if table is None:
        for name, value in good.items():
            lines.append(f"{name} = {_spoiled(value, bad, slot) if name == key else value}")
        line = lines.index(next(x for x in lines if x.startswith(f"{key} ="))) + 1
        named = key
    else:
        values = {"mass": "0.1", "centre": "[0.0, 0.0, 0.0]",
                  "inertia": "[[1e-4, 0.0, 0.0], [0.0, 1e-4, 0.0], [0.0, 0.0, 1e-4]]"}  # fmt: skip
        lines += ["", f"[{table}]"]
        value = values[key]
        if key == "inertia":
            rows = [f"[{row}]" for row in value[2:-2].split("], [")]
            rows[slot % 3] = _spoiled(rows[slot % 3], bad, slot // 3)
            spoiled = "[" + ", ".join(rows) + "]"
        else:
            spoiled = _spoiled(value, bad, slot)
        lines += [f"{name} = {spoiled if name == key else v}" for name, v in values.items()]
        line = lines.index(next(x for x in lines if x.startswith(f"{key} ="))) + 1
        named = f"{table}.{key}"
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "robot.toml"
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        with pytest.raises(InputFileError) as raised:
            read_spatial_robot(path)
    message = str(raised.value)
    assert message.startswith(f"{path}:{line}:"), message
    assert named in message and "\n" not in message


# ------------------------------------------------------------ the command line


def test_robot_check_and_template_of_a_spatial_file(capsys, tmp_path):
    path = _robot_file(tmp_path, "3-RPS", "home_height = 0.12\n")
    status, out, err = cli(capsys, "robot", "--check", path)
    assert status == 0, err
    assert out.startswith(f"# {path}: valid") and "home_height = 0.12" in out
    assert 'architecture = "3-RPS"' in out and "[cylinder]" in out
    status, out, _ = cli(capsys, "robot", "--template", "--architecture", "6-UPS")
    assert status == 0 and out == spatial_robot_text("6-UPS")


@pytest.mark.parametrize(
    "options, words",
    [
        (["--motion", "circle"], "the circle motion drives vx, vy, which the 3-RPS"),
        (["--motion", "vertical"], "--motion vertical is a motion of the 3-PRP"),
        (["--motion", "heave", "--method", "fast"], "--method fast applies to the planar"),
    ],
)
def test_simulate_refuses_what_a_spatial_robot_does_not_take(capsys, tmp_path, options, words):
    out = tmp_path / "out"
    status, _, err = cli(capsys, "simulate", "--robot", _robot_file(tmp_path, "3-RPS"),
                         *options, "--output", out)  # fmt: skip
    assert status == 2
    assert words in one_line(err)
    assert not out.exists()


def test_the_planar_robots_refuse_a_spatial_motion_and_other_commands_a_spatial_file(
    capsys, tmp_path
):
    status, _, err = cli(capsys, "simulate", "--motion", "heave", "--output", tmp_path / "o")
    assert status == 2 and "a motion of the spatial robots" in one_line(err)
    # prp3 control takes a spatial robot file (docs/spatial.md §23), with a spatial motion
    status, _, err = cli(capsys, "control", "--robot", _robot_file(tmp_path, "6-UPS"),
                         "--motion", "vertical", "--plant", "prp3", "--controller", "pd",
                         "--output", tmp_path / "ctl")  # fmt: skip
    assert status == 2 and "--motion vertical applies to the planar robots" in one_line(err)
    assert "heave | circle | tilt" in one_line(err)
    assert not (tmp_path / "ctl").exists()
    status, _, err = cli(capsys, "control", "--motion", "heave", "--plant", "prp3",
                         "--controller", "pd", "--output", tmp_path / "ctl")  # fmt: skip
    assert status == 2 and "a motion of the spatial robots" in one_line(err)


def test_a_subprocess_run_writes_results_and_figures_or_nothing(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    robot = _robot_file(tmp_path, "6-UPS")
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, "-m", "prp3", "simulate", "--robot", robot, "--motion", "tilt",
         "--samples", "31", "--output", out, "--plots"],
        capture_output=True, text=True, timeout=300, env=env,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""
    header = (out / "results.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "t" and len(header) == 1 + 3 * 36 + 12 + 2 * 6 * 3 * 3
    for name in ("efforts.png", "joint_reactions.png"):
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    bad = _robot_file(tmp_path, "3-RUU", "[arm_body]\nmass = -1.0\n")
    refused = subprocess.run(
        [sys.executable, "-m", "prp3", "simulate", "--robot", bad, "--motion", "heave",
         "--output", tmp_path / "b"],
        capture_output=True, text=True, timeout=300, env=env,
    )  # fmt: skip
    assert refused.returncode == 2
    assert refused.stderr.count("\n") == 1 and "Traceback" not in refused.stderr
    assert f"{bad}:3:" in refused.stderr and "arm_body.mass" in refused.stderr
    assert not (tmp_path / "b").exists()


@pytest.mark.parametrize(
    "row, words",
    [
        ("0.1,0,0,0.5,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0", "P2 = 0.504158 m is outside its limits"),
        ("0.1,0,0,0.08,0,0,0,0,0,0,0,0,0,0,0,1e307,0,0,1e308", "the results overflow"),
    ],
)
def test_a_refused_sample_names_its_line_and_time_and_writes_nothing(capsys, tmp_path, row, words):
    """An unreachable pose (a leg of 0.504 m, stroke up to 0.12 m) or rates whose results
    overflow: the line of the sample, its time, nothing written."""
    path = tmp_path / "traj.csv"
    header = "t,x,y,z,roll,pitch,yaw,wx,wy,wz,vx,vy,vz,dwx,dwy,dwz,ax,ay,az"
    path.write_text(f"{header}\n0,0,0,0.08" + ",0" * 15 + f"\n{row}\n", encoding="utf-8")
    out = tmp_path / "out"
    status, _, err = cli(capsys, "simulate", "--robot", _robot_file(tmp_path, "6-UPS"),
                         "--trajectory", path, "--output", out)  # fmt: skip
    assert status == 2
    line = one_line(err)
    assert line.startswith(f"prp3 simulate: error: {path}:3: sample 1, t = 0.1 s")
    assert words in line
    assert not out.exists()


def test_the_reaction_figure_draws_the_magnitudes_of_the_columns():
    """joint_reactions.png's curve of leg 2's P2 force is |(Fx, Fy, Fz)_2_P2| of the table."""
    from prp3.plotting.spatial import spatial_figures

    robot = hexapod()
    table = spatial_results_table(
        spatial_inverse_dynamics(robot, spatial_motion(robot, "circle", 11))
    )
    figures = spatial_figures(table, robot, what="circle motion")
    assert list(figures) == ["efforts.png", "joint_reactions.png", "pose.png"]
    axes = figures["joint_reactions.png"].axes
    top_p2 = next(ax for ax in axes if ax.get_title().startswith("P2"))
    curve = top_p2.get_lines()[1]  # leg 2
    magnitude = np.sqrt(sum(table[f"F{c}_2_P2"] ** 2 for c in "xyz"))
    np.testing.assert_allclose(curve.get_ydata(), magnitude, rtol=1e-15)
    efforts = figures["efforts.png"].axes[0].get_lines()
    np.testing.assert_array_equal(efforts[5].get_ydata(), table["tau_6"])
