"""Workspace of the family (docs/family.md §5, §6): reachable slices and both measures as maps.

The expected values are written out here from the geometry of each leg
(reach discs, triangle areas, concurrent leg lines), not taken from
``prp3.family.workspace``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clitools import cli, one_line
from prp3.errors import Prp3Error
from prp3.family import ARCHITECTURES, FamilyRobot, family_kinematics
from prp3.family.workspace import family_orientation_scan, family_workspace_slice
from prp3.model.motion import Motion

SIGMA = 2.0 * np.pi * np.arange(3) / 3.0


def rot(angle: float, v: np.ndarray) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def wrist(robot: FamilyRobot, j: int, g: np.ndarray, phi: float) -> np.ndarray:
    """``O_3`` of leg ``j`` for an R joint 3: ``G − Rot(φ + σ_j − γ_P)·(a_P, b_P)``."""
    a, b, gamma = robot.leg.attachment
    return g - rot(phi + SIGMA[j] - gamma, np.array([a, b]))


def heron(a: float, b: float, c: np.ndarray) -> np.ndarray:
    s = 0.5 * (a + b + c)
    return np.sqrt(np.clip(s * (s - a) * (s - b) * (s - c), 0.0, None))


GRID = np.linspace(-0.5, 0.5, 41)


@settings(max_examples=8, deadline=None)
@given(phi=st.floats(-0.6, 0.6))
def test_rrr_reach_discs_and_leg_measure(phi: float) -> None:
    robot = FamilyRobot.default("3-RRR")
    ws = family_workspace_slice(robot, phi, GRID, GRID)
    X, Y = np.meshgrid(GRID, GRID)
    g = np.stack([X, Y], axis=-1)
    l1 = math.hypot(*robot.leg.joint2[:2])
    l2 = math.hypot(*robot.leg.joint3[:2])
    reach_all = np.ones(X.shape, dtype=bool)
    clear_all = np.ones(X.shape, dtype=bool)
    for j in range(3):
        pivot = rot(SIGMA[j], np.array(robot.leg.joint1[:2]))
        d = np.linalg.norm(wrist(robot, j, g, phi) - pivot, axis=-1)
        inside = d <= l1 + l2
        clear = (np.abs(d - (l1 + l2)) > 1e-9) & (d > 1e-9)  # off the circle and the pivot
        assert (np.isfinite(ws.mu_leg[..., j]) == inside)[clear].all()
        reach_all &= inside
        clear_all &= clear
        # |μ_leg| = 2·area(O1 O2 O3)/ℓ², the same for both elbows; the home branch has the home sign
        expected = 2.0 * heron(l1, l2, d) / robot.leg.scale**2
        sign = math.copysign(1.0, robot.home_measures[0][j])
        ok = inside & clear
        np.testing.assert_allclose(ws.mu_leg[..., j][ok], (sign * expected)[ok], atol=1e-12)
    assert (ws.reachable == reach_all)[clear_all].all()
    assert ws.area == pytest.approx(ws.reachable.sum() * (GRID[1] - GRID[0]) ** 2)


@pytest.mark.parametrize("phi", [-0.7, 0.0, 0.4, 0.9])
def test_prp_leg_measure_is_the_model_measure(phi: float) -> None:
    ws = family_workspace_slice(FamilyRobot.default("3-PRP"), phi, GRID, GRID)
    assert ws.reachable.all()
    np.testing.assert_allclose(np.abs(ws.mu_leg), abs(math.sin(phi - math.pi / 3.0)), atol=1e-12)
    assert (np.sign(ws.mu_leg) == 1.0).all() == (phi < math.pi / 3.0)


@settings(max_examples=8, deadline=None)
@given(phi=st.floats(-0.5, 0.5))
def test_rpr_parallel_measure_from_the_leg_lines(phi: float) -> None:
    """3-RPR (joint 2 driven): each leg transmits a force along its line through the pivots."""
    robot = FamilyRobot.default("3-RPR")
    ws = family_workspace_slice(robot, phi, GRID, GRID)
    X, Y = np.meshgrid(GRID, GRID)
    g = np.stack([X, Y], axis=-1)
    rows = []
    for j in range(3):
        pivot = rot(SIGMA[j], np.array(robot.leg.joint1[:2]))
        top = wrist(robot, j, g, phi)
        d = top - pivot
        moment = ((top - g)[..., 0] * d[..., 1] - (top - g)[..., 1] * d[..., 0]) / robot.leg.scale
        w = np.concatenate([d, moment[..., None]], axis=-1)
        rows.append(w / np.linalg.norm(w, axis=-1, keepdims=True))
    expected = np.abs(np.linalg.det(np.stack(rows, axis=-2)))
    np.testing.assert_allclose(np.abs(ws.mu_par), expected, atol=1e-12)


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_regular_points_agree_with_the_kinematics(architecture: str) -> None:
    """Near home the slice's measures are those of the path-following kinematics (§5)."""
    robot = FamilyRobot.default(architecture)
    grid = np.linspace(-0.04, 0.04, 5)
    ws = family_workspace_slice(robot, 0.1, grid, grid)
    assert ws.regular.all()
    X, Y = np.meshgrid(grid, grid)
    pose = np.stack([X.ravel(), Y.ravel(), np.full(X.size, 0.1)], axis=-1)
    for k in range(pose.shape[0]):
        kin = family_kinematics(robot, Motion.at_rest(pose[k]))
        np.testing.assert_allclose(ws.mu_leg.reshape(-1, 3)[k], kin.mu_leg, atol=1e-12)
        np.testing.assert_allclose(ws.mu_par.reshape(-1)[k], kin.mu_par, atol=1e-12)


def test_regular_means_every_measure_on_its_home_side() -> None:
    robot = FamilyRobot.default("3-RPR")
    ws = family_workspace_slice(robot, 0.0, GRID, GRID)
    home_leg, home_par = robot.home_measures
    with np.errstate(invalid="ignore"):
        expected = (np.sign(home_leg) * ws.mu_leg >= 1e-4).all(axis=-1) & (
            np.sign(home_par) * ws.mu_par >= 1e-4
        )
    assert (ws.regular == expected).all()
    assert 0 < ws.regular.sum() < ws.reachable.sum()  # the μ_par = 0 circle cuts the window
    scan = family_orientation_scan(robot, GRID, GRID, [0.0, 0.3])
    assert scan.regular_area[0] == pytest.approx(ws.regular_area)


def test_bad_grids_are_named() -> None:
    robot = FamilyRobot.default("3-RRR")
    with pytest.raises(Prp3Error, match="x must be a strictly increasing"):
        family_workspace_slice(robot, 0.0, [0.0, 0.0], GRID)
    with pytest.raises(Prp3Error, match="phi"):
        family_workspace_slice(robot, math.nan, GRID, GRID)


def _read(path: Path) -> dict[str, np.ndarray]:
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    values = np.array([line.split(",") for line in lines[1:]], dtype=np.float64)
    return {name: values[:, i] for i, name in enumerate(header)}


@pytest.mark.parametrize(("architecture", "actuated"), [("3-RRR", 1), ("3-PRR", 3)])
def test_cli_workspace_of_a_family_robot(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, architecture: str, actuated: int
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text(f'architecture = "{architecture}"\nactuated = {actuated}\n')
    out = tmp_path / "ws"
    status, text, err = cli(
        capsys, "workspace", "--robot", robot_file, "--points", "41", "--orientations", "5",
        "--output", out,
    )  # fmt: skip
    assert status == 0, err
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "orientations.csv", "workspace.csv", "workspace.png",
    ]  # fmt: skip
    table = _read(out / "workspace.csv")
    assert list(table) == [
        "x", "y", "reachable", "regular", "mu_leg_A", "mu_leg_B", "mu_leg_C", "mu_par",
    ]  # fmt: skip
    cell = (table["x"][1] - table["x"][0]) ** 2
    assert f"regular area {table['regular'].sum() * cell:.6g} m^2" in text
    assert architecture in text.splitlines()[0]
    scan = _read(out / "orientations.csv")
    assert scan["phi"].size == 5


@pytest.mark.parametrize(("architecture", "option"), [("3-RPP", "--statics"), ("3-RRR", None)])
def test_cli_workspace_statics_of_a_family_robot(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, architecture: str, option: str | None
) -> None:
    """--statics (or a payload) writes statics.csv: the efforts of the library at rest."""
    from prp3.family.workspace import family_workspace_statics

    robot_file = tmp_path / "robot.toml"
    payload = "" if option else "[payload]\nmass = 1.5\ncom = [0.01, 0.0]\n"
    robot_file.write_text(f'architecture = "{architecture}"\n{payload}')
    out = tmp_path / "ws"
    words = ["workspace", "--robot", robot_file, "--points", "21", "--orientations", "3"]
    status, text, err = cli(capsys, *words, *([option] if option else []), "--output", out)
    assert status == 0, err
    assert {"statics.csv", "statics.png"} <= {p.name for p in out.iterdir()}
    table = _read(out / "statics.csv")
    assert list(table) == ["x", "y", "regular", "tau_A", "tau_B", "tau_C", "tau_peak"]
    robot = FamilyRobot.from_toml(robot_file)
    x = np.unique(table["x"])
    statics = family_workspace_statics(robot, 0.0, x, np.unique(table["y"]))
    tau = np.stack([table[f"tau_{leg}"] for leg in "ABC"], axis=-1)
    regular = table["regular"] == 1.0
    assert regular.any() and np.isnan(tau[~regular]).all()
    np.testing.assert_array_equal(tau[regular], statics.tau.reshape(-1, 3)[regular])
    assert "statics (at rest): largest |tau|" in text
    status, text, err = cli(capsys, *words, "--no-statics", "--output", tmp_path / "none")
    assert status == 0 and not (tmp_path / "none" / "statics.csv").exists()


def test_cli_family_statics_that_overflow_name_the_load_and_the_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text('architecture = "3-RPP"\n[load]\nforce = [1e308, 1e308]\n')
    (tmp_path / "ws").mkdir()
    (tmp_path / "ws" / "workspace.csv").write_text("earlier")
    status, out, err = cli(
        capsys, "workspace", "--robot", robot_file, "--points", "11", "--output", tmp_path / "ws"
    )
    line = one_line(err)
    assert status == 2 and out == "" and "Traceback" not in err
    # refused up front, on reading the robot file: its [load]'s wrench overflows (issue 33)
    assert "overflow" in line and "load.force = [1e+308, 1e+308]" in line
    assert f"{robot_file}:3: " in line
    assert (tmp_path / "ws" / "workspace.csv").read_text() == "earlier"


# ---------------------------------------------------------------- random designs
from test_family_dynamics import designs  # noqa: E402


@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_random_designs_agree_with_the_kinematics(data: st.DataObject) -> None:
    """Near a random design's home pose, the slice's measures are the kinematics' ones."""
    from hypothesis import assume

    robot = data.draw(designs())
    centre = robot.home_poses[0]
    offset = np.array([data.draw(st.floats(-0.01, 0.01)) for _ in range(2)])
    phi = float(centre[2]) + data.draw(st.floats(-0.05, 0.05))
    point = centre[:2] + offset
    try:
        kin = family_kinematics(robot, Motion.at_rest([point[0], point[1], phi]))
    except Prp3Error:
        assume(False)
        raise
    ws = family_workspace_slice(
        robot, phi, [point[0], point[0] + 1e-3], [point[1], point[1] + 1e-3]
    )
    assert ws.reachable[0, 0] and ws.regular[0, 0]
    np.testing.assert_allclose(ws.mu_leg[0, 0], kin.mu_leg, atol=1e-12)
    np.testing.assert_allclose(ws.mu_par[0, 0], kin.mu_par, atol=1e-12)


# ---------------------------------------------------------------- statics maps
from prp3 import Robot  # noqa: E402
from prp3.analysis.workspace import workspace_statics  # noqa: E402
from prp3.family import family_inverse_dynamics  # noqa: E402
from prp3.family.workspace import family_workspace_statics  # noqa: E402


def test_the_3prp_statics_map_is_the_model_forms() -> None:
    """docs/family.md §8: tau = f10, here from the 3-PRP's own kernel (another code)."""
    grid = np.linspace(-0.05, 0.05, 11)
    family = family_workspace_statics(FamilyRobot.default("3-PRP"), 0.1, grid, grid)
    model = workspace_statics(Robot(), 0.1, grid, grid)
    assert family.workspace.regular.all()
    np.testing.assert_allclose(family.tau, model.f10, rtol=0, atol=1e-11)
    np.testing.assert_allclose(family.peak, model.peak, rtol=0, atol=1e-11)


@settings(max_examples=20, deadline=None)
@given(data=st.data())
def test_statics_map_is_newton_euler_at_rest(data: st.DataObject) -> None:
    """Near a random design's home, each grid point's tau is an independent Newton–Euler solve.

    The Newton–Euler route (docs/family.md §7, every body's balance) at the
    same pose with zero rates, reached along the path from home: near home
    both judge the same branch.
    """
    from hypothesis import assume

    robot = data.draw(designs())
    centre = robot.home_poses[0]
    phi = float(centre[2]) + data.draw(st.floats(-0.05, 0.05))
    x = centre[0] + np.array([-0.01, 0.0, 0.008])
    y = centre[1] + np.array([-0.006, 0.0, 0.01])
    try:
        statics = family_workspace_statics(robot, phi, x, y)
    except Prp3Error:
        assume(False)
        raise
    for i in range(3):
        for j in range(3):
            pose = [x[j], y[i], phi]
            try:
                solution = family_inverse_dynamics(
                    robot, Motion.at_rest(pose), method="newton-euler"
                )
            except Prp3Error:
                continue  # a singularity on the way from home: the map judges the point alone
            if not statics.workspace.regular[i, j]:
                continue
            scale = 1.0 + float(np.abs(solution.tau).max())
            np.testing.assert_allclose(statics.tau[i, j], solution.tau, rtol=0, atol=1e-10 * scale)


def test_statics_map_is_nan_where_not_regular() -> None:
    robot = FamilyRobot.default("3-RRR")
    grid = np.linspace(-0.3, 0.3, 31)
    statics = family_workspace_statics(robot, 0.0, grid, grid)
    regular = statics.workspace.regular
    assert 0 < regular.sum() < regular.size
    assert np.isfinite(statics.tau[regular]).all() and np.isnan(statics.tau[~regular]).all()
    assert np.isnan(statics.peak[~regular]).all()
    np.testing.assert_array_equal(statics.peak[regular], np.abs(statics.tau[regular]).max(-1))
