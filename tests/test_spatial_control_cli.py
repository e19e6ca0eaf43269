"""``prp3 control --robot SPATIAL.toml`` (docs/spatial.md §23): tracking.csv checked
against independent computations.

* the reference columns are the built-in motion's closed form, completed (§11);
* the error columns are ``(log(R_ref·Rᵀ), p_ref − p)`` rebuilt from the reported poses
  with scipy's rotations (not prp3's);
* from zero initial error the efforts are the Newton–Euler inverse dynamics of the
  (completed) reference: the computed-torque law's feed-forward;
* from an initial position error the free position components follow the closed-form
  solution of ``ë + Kd·ė + Kp·e = 0`` (critically damped here).
"""

from __future__ import annotations

import csv
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from clitools import cli, one_line
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import SpatialRobot, delta, hexapod, three_rps
from prp3.spatial.motion import spatial_motion
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table

Rotation = pytest.importorskip("scipy.spatial.transform").Rotation

ROOT = Path(__file__).resolve().parents[1]
CASES = [("6-UPS", hexapod, "heave"), ("3-RUU", delta, "circle"), ("3-RPS", three_rps, "tilt")]
DURATION, RATE = 0.3, 20.0  # 7 samples


def _read(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="", encoding="utf-8") as stream:
        rows = list(csv.reader(stream))
    values = np.array(rows[1:], dtype=float)
    return {name: values[:, k] for k, name in enumerate(rows[0])}


def _run(capsys, folder: Path, architecture: str, motion: str, *options: object):
    robot = folder / f"{architecture}.toml"
    robot.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    out = folder / "out"
    status, stdout, err = cli(
        capsys, "control", "--robot", robot, "--motion", motion, "--plant", "prp3",
        "--controller", "computed-torque", "--duration", DURATION, "--rate", RATE,
        *options, "--output", out,
    )  # fmt: skip
    assert status == 0, err
    return _read(out / "tracking.csv"), stdout, out


def _reference(robot: SpatialRobot, motion: str, t: np.ndarray):
    # linspace over one period: the CLI's instants are DURATION·k/(N−1) of the same closed form
    whole = spatial_motion(robot, motion, t.size, DURATION)
    np.testing.assert_allclose(whole.t, t, rtol=0, atol=1e-15)
    return complete_motion(robot, whole)


def _check_error_columns(table: dict[str, np.ndarray]) -> None:
    def pose(suffix: str):
        p = np.stack([table[f"{c}{suffix}"] for c in "xyz"], axis=1)
        r = Rotation.from_rotvec(np.stack([table[f"r{c}{suffix}"] for c in "xyz"], axis=1))
        return p, r

    p_ref, r_ref = pose("_ref")
    p, r = pose("")
    e_rot = (r_ref * r.inv()).as_rotvec()
    np.testing.assert_allclose(np.stack([table[f"e_r{c}"] for c in "xyz"], 1), e_rot,
                               rtol=0, atol=1e-12)  # fmt: skip
    np.testing.assert_allclose(np.stack([table[f"e_{c}"] for c in "xyz"], 1), p_ref - p,
                               rtol=0, atol=1e-15)  # fmt: skip


@pytest.mark.parametrize(("architecture", "make", "motion"), CASES)
def test_zero_error_efforts_are_the_inverse_dynamics(capsys, tmp_path, architecture, make, motion):
    table, stdout, _ = _run(capsys, tmp_path, architecture, motion)
    robot = make()
    reference = _reference(robot, motion, table["t"])
    np.testing.assert_allclose(table["x_ref"], reference.position[:, 0], rtol=0, atol=1e-13)
    np.testing.assert_allclose(table["z_ref"], reference.position[:, 2], rtol=0, atol=1e-13)
    rotvec = Rotation.from_matrix(reference.rotation).as_rotvec()
    np.testing.assert_allclose(table["rx_ref"], rotvec[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(table["rz_ref"], rotvec[:, 2], rtol=0, atol=1e-12)
    _check_error_columns(table)
    expected = spatial_results_table(spatial_inverse_dynamics(robot, reference, "newton-euler"))
    peak = max(float(np.abs(expected[f"tau_{i + 1}"]).max()) for i in range(len(robot.legs)))
    for i in range(len(robot.legs)):
        np.testing.assert_allclose(table[f"tau_{i + 1}"], expected[f"tau_{i + 1}"],
                                   rtol=0, atol=1e-7 * peak)  # fmt: skip
    assert len(stdout.splitlines()[0]) > 0 and "max |error|" in stdout.splitlines()[0]


def _critical(t: np.ndarray, e0: float, rate: float) -> np.ndarray:
    """``ë + 2r·ė + r²·e = 0`` from ``e(0) = e0``, ``ė(0) = 0``."""
    return e0 * (1.0 + rate * t) * np.exp(-rate * t)


@pytest.mark.parametrize(("architecture", "make", "motion"), CASES)
def test_initial_error_decays_as_the_closed_loop(capsys, tmp_path, architecture, make, motion):
    table, stdout, _ = _run(capsys, tmp_path, architecture, motion, "--kp", 400, "--kd", 40,
                            "--initial-error", "0,0,0,0,0,0.002")  # fmt: skip
    _check_error_columns(table)
    np.testing.assert_allclose(table["e_z"], _critical(table["t"], 0.002, 20.0),
                               rtol=0, atol=1e-9)  # fmt: skip
    robot = make()
    if "vx" not in robot.parasitic:
        np.testing.assert_allclose(table["e_x"], 0.0, rtol=0, atol=1e-12)
    final = math.hypot(*(float(table[f"e_{c}"][-1]) for c in "xyz"))
    assert f"{final:.3g} m" in stdout.splitlines()[0]


def test_plots_write_the_figure(capsys, tmp_path) -> None:
    _, stdout, out = _run(capsys, tmp_path, "6-UPS", "heave", "--plots")
    assert (out / "tracking.png").stat().st_size > 10_000
    assert "tracking.png" in stdout


@pytest.mark.parametrize(
    ("options", "match"),
    [
        (("--motion", "tilt"), "the tilt motion drives wx, wy"),
        (("--motion", "heave", "--controller", "pd"), "--controller pd applies to the planar"),
        (("--motion", "heave", "--kp", "1,2,3"), "one gain for every component or six"),
        (("--motion", "heave", "--kd", "1,2,3,4"), "a spatial robot file: or 6 numbers RX,RY,RZ"),
        (("--motion", "heave", "--kp", "1,1,1,-1,1,1"), "expected a non-negative number"),
        (("--motion", "heave", "--initial-error", "1,2"), "expected 6 numbers"),
        (("--trajectory", "t.csv"), "--trajectory applies to the planar robots"),
    ],
)
def test_bad_input_one_line(capsys, tmp_path, options, match) -> None:
    robot = tmp_path / "delta.toml"
    robot.write_text('architecture = "3-RUU"\n', encoding="utf-8")
    args = {"--controller": "computed-torque", "--plant": "prp3"}
    rest = list(options)
    for key in args:
        if key in rest:
            args[key] = rest.pop(rest.index(key) + 1)
            rest.remove(key)
    status, _, err = cli(capsys, "control", "--robot", robot, *rest,
                         *(x for kv in args.items() for x in kv), "--output", tmp_path / "o")  # fmt: skip
    assert status == 2 and match in one_line(err)
    assert not (tmp_path / "o").exists()


def test_planar_refuses_spatial_only_options(capsys, tmp_path) -> None:
    status, _, err = cli(capsys, "control", "--motion", "vertical", "--plant", "prp3",
                         "--controller", "pd", "--initial-error", "0,0,0,0,0,0.001",
                         "--output", tmp_path / "o")  # fmt: skip
    assert status == 2 and "a spatial robot file only" in one_line(err)


def test_subprocess_run(tmp_path) -> None:
    robot = tmp_path / "hexapod.toml"
    robot.write_text('architecture = "6-UPS"\n', encoding="utf-8")
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, "-m", "prp3", "control", "--robot", str(robot), "--motion", "heave",
         "--plant", "prp3", "--controller", "computed-torque", "--duration", str(DURATION),
         "--rate", str(RATE), "--initial-error", "0.01,0,0,0,0,0", "--output", str(out)],
        env={**os.environ, "PYTHONPATH": str(ROOT / "src")}, capture_output=True, text=True,
        check=False, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0].startswith("prp3 control: 6-UPS: computed torque")
    table = _read(out / "tracking.csv")
    assert list(table)[-6:] == [f"tau_{i}" for i in range(1, 7)]
    _check_error_columns(table)
    assert table["e_rx"][0] == pytest.approx(0.01, abs=1e-15)


@pytest.mark.parametrize(("architecture", "motion"), [("6-UPS", "heave"), ("3-RUU", "circle")])
def test_mujoco_plant_on_the_cli(capsys, tmp_path, architecture, motion) -> None:
    """``prp3 control --plant mujoco`` of the hexapod and the Delta: ``e_z`` the closed loop's
    within MuJoCo's 4 %; the Delta's platform orientation held (below 1e-5 rad,
    docs/spatial.md §23)."""
    pytest.importorskip("mujoco")
    robot = tmp_path / "robot.toml"
    robot.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    status, stdout, err = cli(
        capsys, "control", "--robot", robot, "--motion", motion, "--plant", "mujoco",
        "--controller", "computed-torque", "--duration", DURATION, "--rate", RATE,
        "--initial-error", "0,0,0,0,0,0.002", "--output", tmp_path / "out",
    )  # fmt: skip
    assert status == 0, err
    assert "mujoco plant" in stdout.splitlines()[0]
    table = _read(tmp_path / "out" / "tracking.csv")
    _check_error_columns(table)
    if architecture == "3-RUU":
        for column in ("e_rx", "e_ry", "e_rz", "rx", "ry", "rz"):
            assert float(np.abs(table[column]).max()) <= 1e-5, column
    # MuJoCo's soft closures and held efforts, on a motion of period 0.3 s
    # (not 1 s): 4 % of the initial error (1.5 % for a period of 1 s, test_spatial_control.py)
    np.testing.assert_allclose(table["e_z"], _critical(table["t"], 0.002, 20.0),
                               rtol=0, atol=8e-5)  # fmt: skip


def test_gains_per_component(capsys, tmp_path) -> None:
    """``--kp``, ``--kd`` of six numbers: each position component decays critically with its
    own rate ``√Kp_c`` (``Kd_c = 2·√Kp_c``), the closed form of its own ODE."""
    table, stdout, _ = _run(capsys, tmp_path, "6-UPS", "heave", "--kp", "100,100,100,64,144,400",
                            "--kd", "20,20,20,16,24,40", "--initial-error",
                            "0,0,0,0.001,-0.002,0.002")  # fmt: skip
    for column, e0, rate in (("e_x", 0.001, 8.0), ("e_y", -0.002, 12.0), ("e_z", 0.002, 20.0)):
        np.testing.assert_allclose(table[column], _critical(table["t"], e0, rate),
                                   rtol=0, atol=1e-9)  # fmt: skip
    assert "KP = (rx, ry, rz, x, y, z) = (100, 100, 100, 64, 144, 400) 1/s^2" in stdout


def test_planar_refuses_six_gains(capsys, tmp_path) -> None:
    status, _, err = cli(capsys, "control", "--motion", "vertical", "--plant", "prp3",
                         "--controller", "pd", "--kp", "1,1,1,1,1,1",
                         "--output", tmp_path / "o")  # fmt: skip
    assert status == 2 and "kp must be a number or 3 numbers (x, y, phi)" in one_line(err)
    assert not (tmp_path / "o").exists()
