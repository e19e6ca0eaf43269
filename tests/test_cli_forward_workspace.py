"""End-to-end tests of ``prp3 workspace`` and ``prp3 forward`` (in-process, ``tmp_path``).

Expected values: the core's inverse geometry with its stroke check decides
reachability; the area of the symmetric-stroke hexagon is derived by hand;
uniform translation with no force and no gravity is an exact solution of the
dynamics (every body translates at constant velocity, λ10 is affine in G at a
fixed φ, so no acceleration anywhere and no force needed).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from clitools import cli
from prp3 import (
    Limits,
    Robot,
    UnreachablePoseError,
    inverse_dynamics,
    inverse_geometry,
    paper_motion,
)
from prp3.io.results import results_table
from prp3.io.tables import write_table_csv

#: The contract's columns (docs/model.md), written out here rather than imported.
PER_LEG = (
    "lambda10 dlambda10 ddlambda10 lambda32 dlambda32 ddlambda32 f10 p10 f21y f21z n10 m10 n32 m32"
).split()
CONTRACT = ["t", "x", "y", "phi"] + [f"{q}_{leg}" for leg in "ABC" for q in PER_LEG]
WORKSPACE_COLUMNS = (
    "x,y,reachable,lambda10_A,lambda10_B,lambda10_C,condition,phi_min,phi_max,orientation_fraction"
).split(",")
ORIENTATION_COLUMNS = (
    "phi,determinant,area,grid_area,reachable_points,condition_min,condition_max".split(",")
)


def read_csv(path: Path) -> tuple[list[str], dict[str, np.ndarray]]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return rows[0], {name: values[:, j] for j, name in enumerate(rows[0])}


def robot_file(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "robot.toml"
    path.write_text(text)
    return path


# ------------------------------------------------------------------ workspace
def test_workspace_writes_grid_scan_and_map(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = robot_file(tmp_path, "[limits]\nstroke = [-0.05, 0.05]\n")
    out = tmp_path / "ws"
    status, stdout, stderr = cli(
        capsys,
        "workspace",
        "--robot",
        robot,
        "--extent",
        -0.1,
        0.1,
        -0.1,
        0.1,
        "--points",
        41,
        "--orientations",
        11,
        "--output",
        out,
    )
    assert status == 0, stderr
    assert sorted(p.name for p in out.iterdir()) == [
        ".prp3-manifest.json",
        "orientations.csv",
        "workspace.csv",
        "workspace.png",
    ]
    assert (out / "workspace.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header, grid = read_csv(out / "workspace.csv")
    assert header == WORKSPACE_COLUMNS
    assert len(grid["x"]) == 41 * 41
    limited = Robot(limits=Limits(stroke=(-0.05, 0.05)))
    for k in range(len(grid["x"])):
        pose = np.array([grid["x"][k], grid["y"][k], 0.0])
        try:
            lam = inverse_geometry(limited, pose).lambda10
            assembles = True
        except UnreachablePoseError:
            lam = inverse_geometry(Robot(), pose).lambda10
            assembles = False
        assert grid["reachable"][k] == float(assembles)
        np.testing.assert_allclose([grid[f"lambda10_{leg}"][k] for leg in "ABC"], lam, atol=1e-15)
        if grid["orientation_fraction"][k] > 0.0:  # within the range [−0.430, 0.569] rad
            assert -0.4302 < grid["phi_min"][k] <= grid["phi_max"][k] < 0.5686
        else:
            assert math.isnan(grid["phi_min"][k]) and math.isnan(grid["phi_max"][k])
    # G = 0 reaches every orientation of the range (λ10 all equal to Σλ10/3, in the stroke);
    # at the two ends of the range the region is that single point, reached up to round-off
    centre = int(np.argmin(np.hypot(grid["x"], grid["y"])))
    assert grid["x"][centre] == 0.0 and grid["y"][centre] == 0.0
    assert grid["orientation_fraction"][centre] >= 9 / 11
    # the hexagon of a symmetric stroke at φ = 0: area (3√3/2)·a² (see test_workspace)
    assert "reachable area 0.00649519 m^2" in stdout
    header, scan = read_csv(out / "orientations.csv")
    assert header == ORIENTATION_COLUMNS
    assert len(scan["phi"]) == 11
    # at the ends of the orientation range the region shrinks to a corner of the cube
    assert scan["area"][0] == pytest.approx(0.0, abs=1e-12)
    assert scan["area"][-1] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(scan["determinant"], np.sin(scan["phi"] - math.pi / 3.0), atol=1e-15)


def test_workspace_without_stroke_covers_plus_minus_l0(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    status, stdout, _ = cli(
        capsys,
        "workspace",
        "--phi",
        0.2,
        "--points",
        11,
        "--orientations",
        5,
        "--output",
        tmp_path / "w",
    )
    assert status == 0
    _, grid = read_csv(tmp_path / "w" / "workspace.csv")
    assert grid["x"].min() == -0.3 and grid["x"].max() == 0.3  # ±l0 of the paper's robot
    assert (grid["reachable"] == 1.0).all()
    assert "no stroke limits" in stdout


def test_workspace_refuses_a_singular_orientation(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "ws"
    status, _, stderr = cli(capsys, "workspace", "--phi", math.pi / 3.0, "--output", out)
    assert status == 2
    assert stderr.count("\n") == 1 and "singular" in stderr and "Traceback" not in stderr
    assert not out.exists()


def test_workspace_refuses_an_empty_extent(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    status, _, stderr = cli(
        capsys, "workspace", "--extent", 0.1, -0.1, 0, 1, "--output", tmp_path / "w"
    )
    assert status == 2 and "--extent" in stderr
    assert not (tmp_path / "w").exists()


def test_workspace_help_has_an_example(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = cli(capsys, "workspace", "--help")
    assert status == 0 and "prp3 workspace --robot robot.toml --output ws" in out


# -------------------------------------------------------------------- forward
def test_forward_from_a_results_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    motion = paper_motion("vertical")
    kin, dyn = inverse_dynamics(Robot(), motion)
    source = tmp_path / "results.csv"
    write_table_csv(source, results_table(kin, dyn))
    out = tmp_path / "fwd"
    status, stdout, stderr = cli(capsys, "forward", "--forces", source, "--output", out)
    assert status == 0, stderr
    header, table = read_csv(out / "results.csv")
    assert header == CONTRACT
    np.testing.assert_array_equal(table["t"], motion.t)
    # the forces are reproduced at the samples (the spline passes through them)
    for j, leg in enumerate("ABC"):
        np.testing.assert_allclose(table[f"f10_{leg}"], dyn.f10[:, j], atol=1e-9)
    # the motion: close while the open-loop instability (≈ e^{6.2 t}) has not grown
    early = motion.t <= 2.0
    assert np.abs(table["y"][early] - motion.pose[early, 1]).max() < 1e-5
    assert np.abs(table["y"] - motion.pose[:, 1]).max() < 1e-3
    header, trajectory = read_csv(out / "trajectory.csv")
    assert header == "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi".split(",")
    np.testing.assert_array_equal(trajectory["y"], table["y"])
    assert "completed" in stdout


def test_forward_force_table_uniform_drift(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = robot_file(tmp_path, "gravity = [0.0, 0.0]\n")
    forces = tmp_path / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C\n0,0,0,0\n1,0,0,0\n2,0,0,0\n")
    status, _, stderr = cli(
        capsys,
        "forward",
        "--robot",
        robot,
        "--forces",
        forces,
        "--initial-pose",
        0.0,
        0.01,
        0.1,
        "--initial-velocity",
        0.02,
        -0.01,
        0.0,
        "--samples",
        5,
        "--output",
        tmp_path / "out",
    )
    assert status == 0, stderr
    _, trajectory = read_csv(tmp_path / "out" / "trajectory.csv")
    t = np.linspace(0.0, 2.0, 5)
    np.testing.assert_array_equal(trajectory["t"], t)
    np.testing.assert_allclose(trajectory["x"], 0.02 * t, atol=1e-10)
    np.testing.assert_allclose(trajectory["y"], 0.01 - 0.01 * t, atol=1e-10)
    np.testing.assert_allclose(trajectory["phi"], 0.1, atol=1e-10)
    np.testing.assert_allclose(trajectory["ddx"], 0.0, atol=1e-9)


def test_forward_stops_at_the_stroke_with_status_1(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = robot_file(tmp_path, "gravity = [0.0, 0.0]\n[limits]\nstroke = [-0.05, 0.05]\n")
    forces = tmp_path / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C\n0,10,10,10\n1,10,10,10\n")
    out = tmp_path / "out"
    status, _, stderr = cli(
        capsys, "forward", "--robot", robot, "--forces", forces, "--samples", 11, "--output", out
    )
    assert status == 1
    assert stderr.count("\n") == 1 and "upper stroke limit 0.05 m" in stderr
    _, table = read_csv(out / "results.csv")
    assert 2 <= len(table["t"]) < 11  # the motion up to the stop, the stop instant last
    assert table["lambda10_A"][-1] == pytest.approx(0.05, abs=1e-9)
    assert (table["lambda10_A"][:-1] < 0.05).all()


def test_forward_refuses_partial_results_columns(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    forces = tmp_path / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C,x\n0,0,0,0,0\n1,0,0,0,0\n")
    out = tmp_path / "out"
    status, _, stderr = cli(capsys, "forward", "--forces", forces, "--output", out)
    assert status == 2 and "give either the columns" in stderr and str(forces) in stderr
    assert not out.exists()


def test_forward_refuses_forces_beyond_max_force(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = robot_file(tmp_path, "[limits]\nmax_force = 5.0\n")
    forces = tmp_path / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C\n0,0,0,0\n1,0,-6,0\n")
    status, _, stderr = cli(
        capsys, "forward", "--robot", robot, "--forces", forces, "--output", tmp_path / "o"
    )
    assert status == 2 and "|f10_B| = 6.0 N at t = 1.0 s exceeds limits.max_force = 5.0 N" in stderr
    assert not (tmp_path / "o").exists()


def test_forward_help_has_an_example(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = cli(capsys, "forward", "--help")
    assert status == 0 and "prp3 forward --forces inv/results.csv --output fwd" in out


def test_the_spatial_example_of_workspace_help_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    # the two lines of `prp3 workspace --help` for a spatial robot, run as written (a
    # coarser grid added to keep it short): the template, then its roll-pitch slice
    status, out, _ = cli(capsys, "workspace", "--help")
    lines = [line.strip() for line in out.splitlines() if "hexapod.toml" in line]
    assert lines[0] == "prp3 robot --template --architecture 6-UPS > hexapod.toml"
    monkeypatch.chdir(tmp_path)
    status, template, _ = cli(capsys, *lines[0].split()[1:-2])
    assert status == 0
    (tmp_path / "hexapod.toml").write_text(template, encoding="utf-8")
    status, report, stderr = cli(capsys, *lines[1].split()[1:], "--points", "11")
    assert status == 0, stderr
    assert "6-UPS" in report and "plane rp" in report
    header = (tmp_path / "ws_hexapod" / "statics.csv").read_text().splitlines()[0].split(",")
    assert header[:7] == ["x", "y", "z", "roll", "pitch", "yaw", "regular"]
    assert "tau_peak" in header
