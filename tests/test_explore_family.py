"""The explorer of a family robot (docs/family.md) without a browser: scene data and command line.

The arrows, the table and the measures of :mod:`prp3.explorer.family_scene`
are held against the library's other routes for the same instant: the
``newton-euler`` route's joint forces and efforts (the 21×21 system, not the
``fast`` route the page solves with), the tails against the joint origins of
:func:`prp3.family.leg_chain`, the measures against
:func:`prp3.family.family_kinematics`; and at rest against the platform's
balance rebuilt here (the three legs' ``F3`` carry the platform's and the
payload's weight).  The browser test is in ``tests/test_explore_browser.py``.
"""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from clitools import cli, one_line
from prp3.errors import ParameterError, Prp3Error, SingularPoseError, UnreachablePoseError
from prp3.explorer.family_scene import (
    FAMILY_DESIGN_PARAMETERS,
    family_arrow_scale,
    family_design_parameters,
    family_design_robot,
    family_design_values,
    family_pose_table,
    family_view,
)
from prp3.explorer.scene import State, empty_view
from prp3.family import (
    ARCHITECTURES,
    FAMILY_COLUMNS,
    FamilyRobot,
    family_inverse_dynamics,
    family_kinematics,
    leg_chain,
)
from prp3.family.chain import SIGMA
from prp3.model.motion import Motion
from prp3.validation import LEGS

pytest.importorskip("bokeh", reason="the explorer needs Bokeh (pip install 'prp3[explore]')")

#: Instants of the platform (pose, velocity, acceleration) every default architecture reaches.
STATES = (
    State(),
    State((0.012, -0.008, 0.05), (0.1, -0.05, 0.3), (0.8, 0.4, -2.0)),
    State((-0.01, 0.015, -0.04), (-0.2, 0.1, -0.5), (-1.0, 2.0, 3.0)),
)


def _motion(state: State) -> Motion:
    return Motion(
        t=np.zeros(()),
        pose=np.array(state.pose),
        velocity=np.array(state.velocity),
        acceleration=np.array(state.acceleration),
    )


def _rows(arrows: dict[str, list[object]], quantity: str) -> list[int]:
    rows = [k for k, q in enumerate(arrows["quantity"]) if q == quantity]
    assert [arrows["leg"][k] for k in rows] == list(LEGS)
    return rows


@pytest.mark.parametrize("architecture", ARCHITECTURES)
@pytest.mark.parametrize("state", STATES, ids=["rest", "moving", "moving-2"])
def test_the_arrows_and_table_are_the_library_s_joint_forces(
    architecture: str, state: State
) -> None:
    robot = FamilyRobot.default(architecture)
    scale = 0.002
    table = family_pose_table(robot, state)
    assert tuple(table) == FAMILY_COLUMNS and all(v.shape == (1,) for v in table.values())
    view = family_view(robot, table, 0, scale)
    # an independent route of the library: the 21×21 Newton–Euler system of each sample
    other = family_inverse_dynamics(robot, _motion(state), method="newton-euler")
    kin = family_kinematics(robot, _motion(state))
    frames = leg_chain(robot.types, robot.leg.placements, SIGMA, kin.q)
    arrows = view.arrows
    for k in range(3):
        rows = _rows(arrows, f"F{k + 1}")
        force = np.array([[arrows["fx"][r], arrows["fy"][r]] for r in rows])
        np.testing.assert_allclose(force, other.force[:, k, :], rtol=1e-9, atol=1e-9)
        tails = np.array([[arrows["x0"][r], arrows["y0"][r]] for r in rows])
        np.testing.assert_allclose(tails, frames.origin[:, k, :], rtol=0, atol=1e-12)
        heads = np.array([[arrows["x1"][r], arrows["y1"][r]] for r in rows])
        np.testing.assert_allclose(heads, tails + scale * force, rtol=0, atol=1e-12)
    a = robot.actuated - 1
    if robot.types[a] == "P":  # the actuator's share along its slide
        rows = _rows(arrows, "tau")
        share = np.array([[arrows["fx"][r], arrows["fy"][r]] for r in rows])
        np.testing.assert_allclose(share, other.tau[:, None] * frames.axis[:, a, :], atol=1e-9)
        np.testing.assert_allclose(
            [arrows["x0"][r] for r in rows], frames.origin[:, a, 0], atol=1e-12
        )
    else:
        assert "tau" not in arrows["quantity"]
    rows_of = {name: i for i, name in enumerate(view.table["quantity"])}
    for j, leg in enumerate(LEGS):
        assert view.table[leg][rows_of["tau"]] == pytest.approx(other.tau[j], rel=1e-9, abs=1e-9)
        for k in range(3):
            assert view.table[leg][rows_of[f"q{k + 1}"]] == pytest.approx(kin.q[j, k], abs=1e-12)
            assert view.table[leg][rows_of[f"m{k + 1}"]] == pytest.approx(
                other.moment[j, k], rel=1e-9, abs=1e-9
            )
        assert view.table[leg][rows_of["mu_leg"]] == pytest.approx(kin.mu_leg[j], abs=1e-12)
    measures = view.shapes["measures"]
    np.testing.assert_allclose(measures["value"], [*kin.mu_leg, kin.mu_par], atol=1e-12)
    assert all(margin >= 1e-4 for margin in measures["margin"])  # an accepted pose


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_at_rest_the_legs_carry_the_platform_s_weight(architecture: str) -> None:
    robot = family_design_robot(FamilyRobot.default(architecture), {"payload.mass": 1.5})
    view = family_view(robot, family_pose_table(robot, State()), 0, 1.0)
    rows = _rows(view.arrows, "F3")
    total = np.sum([[view.arrows["fx"][r], view.arrows["fy"][r]] for r in rows], axis=0)
    np.testing.assert_allclose(total, [0.0, 9.81 * (robot.platform.mass + 1.5)], atol=1e-9)


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_the_legs_are_drawn_with_their_own_joints(architecture: str) -> None:
    robot = FamilyRobot.default(architecture)
    state = STATES[1]
    view = family_view(robot, family_pose_table(robot, state), 0, 0.001)
    kin = family_kinematics(robot, _motion(state))
    origin, axis = kin.frames.origin.reshape(3, 3, 2), kin.frames.axis.reshape(3, 3, 2)
    shapes = view.shapes
    r_joints = [k for k in range(3) if robot.types[k] == "R"]
    p_joints = [k for k in range(3) if robot.types[k] == "P"]
    assert len(shapes["revolute"]["x"]) == 3 * len(r_joints)
    assert len(shapes["sliders"]["xs"]) == len(shapes["guides"]["xs"]) == 3 * len(p_joints)
    for x, y, leg, joint in zip(*(shapes["revolute"][c] for c in ("x", "y", "leg", "joint")),
                                strict=True):  # fmt: skip
        assert (x, y) == pytest.approx(tuple(origin[LEGS.index(leg), joint - 1]), abs=1e-12)
    for xs, ys, leg, joint in zip(*(shapes["sliders"][c] for c in ("xs", "ys", "leg", "joint")),
                                  strict=True):  # fmt: skip
        j = LEGS.index(leg)
        middle = np.array([sum(xs) / 2, sum(ys) / 2])
        np.testing.assert_allclose(middle, origin[j, joint - 1], atol=1e-12)
        u = axis[j, joint - 1]
        assert abs((xs[1] - xs[0]) * u[1] - (ys[1] - ys[0]) * u[0]) < 1e-12  # along u_k
    np.testing.assert_allclose(
        np.stack([shapes["platform"]["xs"][0], shapes["platform"]["ys"][0]], axis=-1),
        origin[:, 2, :],
        atol=1e-12,
    )
    assert len(shapes["links"]["xs"]) == 6
    driven = robot.actuated - 1
    if robot.types[driven] == "R":
        outlines = [o for o, k in zip(shapes["revolute"]["outline"], shapes["revolute"]["joint"],
                                      strict=True) if k == driven + 1]  # fmt: skip
        assert outlines == ["#000000"] * 3
    else:
        colours = [c for c, k in zip(shapes["sliders"]["colour"], shapes["sliders"]["joint"],
                                     strict=True) if k == driven + 1]  # fmt: skip
        assert colours == ["#000000"] * 3


@pytest.mark.parametrize(
    "architecture, pose, kind, words",
    [
        ("3-RRR", (2.0, 0.0, 0.0), UnreachablePoseError, "cannot reach"),
        ("3-PRR", (0.0, 0.0, -1.1), SingularPoseError, "mu_par"),  # μ_par changed sign
    ],
)
def test_a_refused_pose_is_the_library_s_error_and_draws_nothing(
    architecture: str, pose: tuple[float, float, float], kind: type[Prp3Error], words: str
) -> None:
    robot = FamilyRobot.default(architecture)
    state = State(pose)
    with pytest.raises(kind) as library:
        family_inverse_dynamics(robot, _motion(state))
    with pytest.raises(kind) as caught:
        family_pose_table(robot, state)
    assert str(caught.value) == str(library.value) and words in str(caught.value)
    blank = empty_view(family_view(robot, family_pose_table(robot, State()), 0, 0.001))
    assert blank.arrows["quantity"] == [] and blank.shapes["platform"]["xs"] == []
    assert blank.shapes["measures"]["value"] == [] and blank.table["quantity"] == []


def test_the_arrow_scale_draws_the_largest_force_at_rest_a_third_of_the_scale() -> None:
    robot = FamilyRobot.default("3-PRR")
    view = family_view(robot, family_pose_table(robot, State()), 0, family_arrow_scale(robot))
    lengths = [math.hypot(x1 - x0, y1 - y0) for x0, y0, x1, y1 in
               zip(*(view.arrows[c] for c in ("x0", "y0", "x1", "y1")), strict=True)]  # fmt: skip
    assert max(lengths) == pytest.approx(0.35 * robot.leg.scale, rel=1e-12)


#: A change every design value takes without a singular home (1 cm, 0.01 rad, 0.01 kg ...).
STEP = 0.01
COMPONENT = {"x": 0, "y": 1, "a": 0, "b": 1, "gamma": 2}


@pytest.mark.parametrize("key", list(FAMILY_DESIGN_PARAMETERS))
def test_each_design_parameter_changes_only_itself(key: str) -> None:
    robot = FamilyRobot.default("3-RPR")
    before = family_design_values(robot)
    changed = family_design_robot(robot, {key: before[key] + STEP})
    after = family_design_values(changed)
    assert after == {**before, key: before[key] + STEP}
    assert changed.architecture == robot.architecture and changed.actuated == robot.actuated


def _file_with(robot: FamilyRobot, key: str, value: float) -> FamilyRobot:
    """The robot file of ``robot`` (its TOML text) with the file's entry of ``key`` set to
    ``value``, read back by the family's TOML reader: the independent route to the edit."""
    data = tomllib.loads(robot.to_toml())
    defaults = {"payload": {"mass": 0.0, "com": [0.0, 0.0], "inertia": 0.0},
                "load": {"force": [0.0, 0.0], "moment": 0.0}}  # fmt: skip
    *path, last = key.split(".")
    where: Any = data
    for part in path:
        if part not in where:
            where[part] = defaults[part]
        where = where[part]
    if isinstance(where, list):
        where[COMPONENT[last]] = value
    else:
        where[last] = value
    return FamilyRobot.from_mapping(data)


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_a_design_edit_is_the_robot_file_with_that_value(architecture: str) -> None:
    """Every design field of every architecture gives the robot its file gives with that
    value (read by the TOML reader), and the page's joint forces are that robot's."""
    robot = FamilyRobot.default(architecture)
    before = family_design_values(robot)
    state = State((0.004, -0.003, 0.02), (0.05, -0.02, 0.1), (0.3, 0.2, -0.5))
    for key in FAMILY_DESIGN_PARAMETERS:
        value = before[key] + STEP
        edited = family_design_robot(robot, {key: value})
        from_file = _file_with(robot, key, value)
        assert edited == from_file, key
        page, direct = family_pose_table(edited, state), family_pose_table(from_file, state)
        assert all(np.array_equal(page[c], direct[c]) for c in direct), key


def test_the_home_coordinates_carry_their_joints_units() -> None:
    units = family_design_parameters(FamilyRobot.default("3-RPR"))
    assert [units[f"leg.home.{p}"][1] for p in ("a", "b", "gamma")] == ["rad", "m", "rad"]
    units = family_design_parameters(FamilyRobot.default("3-PPR", actuated=1))
    assert [units[f"leg.home.{p}"][1] for p in ("a", "b", "gamma")] == ["m", "m", "rad"]


def test_a_bad_geometry_or_body_value_is_refused_naming_it() -> None:
    robot = FamilyRobot.default("3-RPR")
    with pytest.raises(ParameterError, match=r"leg\.scale"):
        family_design_robot(robot, {"leg.scale": 0.0})
    with pytest.raises(ParameterError, match=r"link1\.com"):
        family_design_robot(robot, {"link1.com.x": math.nan})


def test_a_bad_design_value_is_refused_naming_its_key() -> None:
    with pytest.raises(ParameterError, match=r"link2\.mass"):
        family_design_robot(FamilyRobot.default("3-RRR"), {"link2.mass": -1.0})
    with pytest.raises(Prp3Error, match="unknown design parameter 'l0'"):
        family_design_robot(FamilyRobot.default("3-RRR"), {"l0": 0.3})


# ---------------------------------------------------------------- command line
@pytest.fixture
def rrr_file(tmp_path: Path) -> Path:
    path = tmp_path / "rrr.toml"
    path.write_text(FamilyRobot.default("3-RRR").to_toml(), encoding="utf-8")
    return path


def test_simulate_html_of_a_family_robot(
    tmp_path: Path, rrr_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    page = tmp_path / "run.html"
    status, out, err = cli(capsys, "simulate", "--robot", rrr_file, "--motion", "vertical",
                           "--samples", "31", "--output", tmp_path / "out", "--html", page)  # fmt: skip
    assert status == 0, err
    assert f"html file written: {page}" in out
    text = page.read_text(encoding="utf-8")
    assert "3-RRR" in text and "frames:revolute" in text and "frames:measures" in text
    assert not re.search(r"<script[^>]*\bsrc=", text)


def test_explore_export_of_a_family_robot(
    tmp_path: Path, rrr_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    page = tmp_path / "rrr.html"
    status, out, err = cli(capsys, "explore", "--robot", rrr_file, "--export", page)
    assert (status, err) == (0, "")
    assert out.strip() == f"prp3 explore: wrote {page}"
    assert "3-RRR" in page.read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def rrr_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A 3-RRR robot file and its run of the paper's rotation (``prp3 simulate --robot``)."""
    from prp3.cli import main

    folder = tmp_path_factory.mktemp("rrr_run")
    robot_file = folder / "rrr.toml"
    robot_file.write_text(FamilyRobot.default("3-RRR").to_toml(), encoding="utf-8")
    status = main(["simulate", "--robot", str(robot_file), "--motion", "rotation",
                   "--samples", "41", "--output", str(folder / "run")])  # fmt: skip
    assert status == 0
    return robot_file, folder / "run"


def test_the_motion_of_a_family_run_is_the_simulated_one(rrr_run: tuple[Path, Path]) -> None:
    from prp3.explorer.run_folder import family_run_motion, read_family_run
    from prp3.model.motion import paper_motion

    run = read_family_run(rrr_run[1])
    motion = family_run_motion(FamilyRobot.default("3-RRR"), run)
    simulated = paper_motion("rotation", 41)  # what prp3 simulate --motion rotation solved
    np.testing.assert_array_equal(motion.pose, simulated.pose)
    np.testing.assert_allclose(motion.velocity, simulated.velocity, rtol=0, atol=1e-12)
    np.testing.assert_allclose(motion.acceleration, simulated.acceleration, rtol=0, atol=1e-11)


def test_a_family_run_of_another_robot_is_one_line(
    tmp_path: Path, rrr_run: tuple[Path, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    other = tmp_path / "other.toml"
    text = rrr_run[0].read_text(encoding="utf-8")
    longer = text.replace("joint2 = [0.2, 0.0,", "joint2 = [0.21, 0.0,")  # link 1 1 cm longer
    assert longer != text
    other.write_text(longer, encoding="utf-8")
    status, out, err = cli(capsys, "explore", "--robot", other, "--results", rrr_run[1],
                           "--no-browser", "--port", 1)  # fmt: skip
    assert status == 2 and out == ""
    line = one_line(err)
    assert line.startswith("prp3 explore: error: ") and "give the --robot of the run" in line


def test_a_3prp_run_with_a_family_robot_is_one_line(
    tmp_path: Path, rrr_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from prp3.cli import main

    assert main(["simulate", "--motion", "rotation", "--samples", "11",
                 "--output", str(tmp_path / "prp")]) == 0  # fmt: skip
    capsys.readouterr()
    status, out, err = cli(capsys, "explore", "--robot", rrr_file, "--results", tmp_path / "prp")
    assert status == 2 and out == ""
    line = one_line(err)
    assert line.startswith("prp3 explore: error: ") and "results.csv" in line


def test_a_family_run_exports_its_html(
    tmp_path: Path, rrr_run: tuple[Path, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    page = tmp_path / "run.html"
    status, out, err = cli(capsys, "explore", "--robot", rrr_run[0], "--results", rrr_run[1],
                           "--export", page)  # fmt: skip
    assert (status, err) == (0, "")
    assert out.strip() == f"prp3 explore: wrote {page}"
    text = page.read_text(encoding="utf-8")
    assert "3-RRR" in text and "frames:revolute" in text


def test_a_family_robot_file_that_does_not_parse_is_one_line(
    tmp_path: Path, rrr_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    broken = tmp_path / "broken.toml"
    broken.write_text(
        rrr_file.read_text().replace('architecture = "3-RRR"', 'architecture = "3-XYZ"')
    )
    status, out, err = cli(capsys, "explore", "--robot", broken, "--no-browser", "--port", 1)
    assert status == 2 and out == ""
    line = one_line(err)
    assert line.startswith("prp3 explore: error: ") and "3-XYZ" in line
