"""``prp3 robot`` and ``prp3 simulate`` with family-form robot files (docs/family.md)."""

from __future__ import annotations

import csv
import tomllib
from pathlib import Path

import numpy as np
import pytest

from clitools import cli, listing, one_line
from prp3 import paper_motion
from prp3.family import (
    FAMILY_COLUMNS,
    FamilyRobot,
    family_inverse_dynamics,
    family_results_table,
)
from prp3.io.tables import parquet_available


def _robot_file(tmp_path: Path, text: str, name: str = "robot.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_template_of_an_architecture(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = cli(capsys, "robot", "--template", "--architecture", "3-RRR")
    assert status == 0 and err == ""
    assert FamilyRobot.from_mapping(tomllib.loads(out)) == FamilyRobot.default("3-RRR")
    assert "# " in out  # documented


def test_check_a_family_file(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = _robot_file(tmp_path, 'architecture = "3-PRR"\nactuated = 3\n')
    status, out, _ = cli(capsys, "robot", "--check", path)
    assert status == 0 and "valid" in out
    body = "\n".join(line for line in out.splitlines() if not line.startswith("# "))
    assert FamilyRobot.from_mapping(tomllib.loads(body)) == FamilyRobot.default("3-PRR", 3)
    status, _, err = cli(capsys, "robot", "--check", path, "--architecture", "3-RRR")
    assert status == 2 and "--template only" in one_line(err)


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    with path.open() as handle:
        rows = list(csv.reader(handle))
    header, values = rows[0], np.array(rows[1:], dtype=np.float64)
    return {name: values[:, i] for i, name in enumerate(header)}


@pytest.mark.parametrize("method", ["fast", "paper", "newton-euler"])
def test_simulate_writes_the_64_columns(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, method: str
) -> None:
    path = _robot_file(tmp_path, 'architecture = "3-RPR"\n[payload]\nmass = 0.5\n')
    out_dir = tmp_path / "out"
    status, out, err = cli(
        capsys, "simulate", "--robot", path, "--motion", "vertical", "--samples", "21",
        "--method", method, "--output", out_dir,
    )  # fmt: skip
    assert status == 0, err
    assert "3-RPR" in out and "peak |tau| (N)" in out
    table = _read_csv(out_dir / "results.csv")
    assert tuple(table) == FAMILY_COLUMNS
    robot = FamilyRobot.from_toml(path)
    expected = family_results_table(family_inverse_dynamics(robot, paper_motion("vertical", 21)))
    for name in FAMILY_COLUMNS:  # full precision: the written text reads back exactly
        np.testing.assert_allclose(table[name], expected[name], rtol=0, atol=1e-10)


@pytest.mark.skipif(not parquet_available(), reason="pyarrow not installed")
def test_simulate_parquet(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    import pyarrow.parquet as pq

    path = _robot_file(tmp_path, 'architecture = "3-PPR"\n')
    status, _, err = cli(
        capsys, "simulate", "--robot", path, "--motion", "rotation", "--samples", "11",
        "--format", "parquet", "--output", tmp_path / "out",
    )  # fmt: skip
    assert status == 0, err
    table = pq.read_table(tmp_path / "out" / "results.parquet")
    assert tuple(table.column_names) == FAMILY_COLUMNS
    expected = family_results_table(  # the engine --engine auto runs for 11 samples
        family_inverse_dynamics(
            FamilyRobot.default("3-PPR"), paper_motion("rotation", 11), engine="numpy"
        )
    )
    assert np.array_equal(table.column("tau_B").to_numpy(), expected["tau_B"])


def test_simulate_plots(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = _robot_file(tmp_path, 'architecture = "3-RRR"\n')
    status, _, err = cli(
        capsys, "simulate", "--robot", path, "--motion", "vertical", "--samples", "31",
        "--plots", "--output", tmp_path / "out",
    )  # fmt: skip
    assert status == 0, err
    for name in ("tau.png", "power.png", "joint_forces.png"):
        assert (tmp_path / "out" / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_simulate_refuses_model_keys(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = _robot_file(tmp_path, 'architecture = "3-RRR"\nl0 = 0.3\n')
    status, out, err = cli(
        capsys, "simulate", "--robot", path, "--motion", "vertical", "--output", tmp_path / "o"
    )
    line = one_line(err)
    assert status == 2 and out == "" and str(path) in line and "'l0'" in line
    assert not (tmp_path / "o").exists() or listing(tmp_path / "o") == {}


def test_simulate_refuses_a_crossed_singularity(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = _robot_file(tmp_path, 'architecture = "3-PRR"\nactuated = 2\n')
    status, out, err = cli(
        capsys, "simulate", "--robot", path, "--motion", "rotation", "--output", tmp_path / "o"
    )
    line = one_line(err)
    assert status == 2 and out == ""
    assert "--motion rotation" in line and "sample 235, t = 2.35 s" in line and "mu_par" in line
    assert not (tmp_path / "o" / "results.csv").exists()


def test_simulate_refuses_load_columns(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = _robot_file(tmp_path, 'architecture = "3-RRR"\n')
    traj = tmp_path / "traj.csv"
    traj.write_text(
        "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi,fx,fy,mz\n"
        + "".join(f"{t},0,0,0,0,0,0,0,0,0,1,0,0\n" for t in (0.0, 0.5, 1.0))
    )
    status, _, err = cli(
        capsys, "simulate", "--robot", path, "--trajectory", traj, "--output", tmp_path / "o"
    )
    assert status == 2 and "model-form robot files" in one_line(err)


def test_model_form_unchanged(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = _robot_file(tmp_path, "l0 = 0.3\n")
    status, _, err = cli(
        capsys, "simulate", "--robot", path, "--motion", "vertical", "--samples", "5",
        "--output", tmp_path / "o",
    )  # fmt: skip
    assert status == 0, err
    header = (tmp_path / "o" / "results.csv").read_text().splitlines()[0].split(",")
    assert len(header) == 46 and header[4] == "lambda10_A"
