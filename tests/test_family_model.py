"""The family robot model and its ROBOT.toml (docs/family.md §1, §3, §9)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from prp3 import Robot
from prp3.errors import InputFileError, ParameterError
from prp3.family import (
    ARCHITECTURES,
    FamilyRobot,
    family_template,
    leg_chain,
    read_robot_file,
    robot_file_form,
)

S2, S3, PI = math.sqrt(2.0), math.sqrt(3.0), math.pi

#: docs/family.md §3, written out again here: actuated, joint1..3, attachment, home.
TABLE = {
    "3-PRP": (1, [S3 / 20, -0.15, PI / 3], [0, 0, -PI / 3], [0, 0, 0], [-S3 / 20, 0.15, 0], [0, 0, 0]),
    "3-RPR": (2, [0, -0.3, PI / 4], [0, 0, 0], [0, 0, -PI / 4], [-0.2, 0.1, 0], [0, 0.2 * S2, 0]),
    "3-RRR": (1, [0, -0.3, 0], [0.2, 0, PI / 2], [0.2, 0, -PI / 2], [-0.2, 0.1, 0], [0, 0, 0]),
    "3-PRR": (1, [0.2, -0.3, PI / 2], [0, 0, 0], [0.2, 0, -PI / 2], [-0.2, 0.1, 0], [0, 0, 0]),
    "3-PPR": (1, [0, -0.3, 0], [0, 0, PI / 2], [0, 0, -PI / 2], [-0.1, 0.2, 0], [0.1, 0.1, 0]),
    "3-RPP": (2, [0, -0.3, 3 * PI / 4], [0, 0, 0], [0, 0, -PI / 2], [0.15 * S2, -0.05 * S2, -PI / 4], [0, 0.2 * S2, 0]),
    "3-RRP": (1, [0, -0.3, PI / 4], [0.2 * S2, 0, -PI / 4], [0, 0, 0], [-0.2, 0.1, 0], [0, 0, 0]),
}  # fmt: skip


@pytest.mark.parametrize("arch", ARCHITECTURES)
def test_defaults_of_the_table(arch: str) -> None:
    robot = FamilyRobot.default(arch)
    act, j1, j2, j3, att, home = TABLE[arch]
    assert robot.actuated == act
    for got, want in zip(
        (
            robot.leg.joint1,
            robot.leg.joint2,
            robot.leg.joint3,
            robot.leg.attachment,
            robot.leg.home,
        ),
        (j1, j2, j3, att, home),
        strict=True,
    ):
        assert got == pytest.approx(want, abs=1e-15)
    assert robot.leg.scale == 0.3 and robot.link1.mass == 1.0 and robot.link2.mass == 0.75
    assert (robot.platform.mass, robot.platform.inertia) == (3.0, 0.0675)
    assert robot.gravity == (0.0, -9.81)
    # the home pose is x = y = phi = 0 for all three legs
    np.testing.assert_allclose(robot.home_poses, 0.0, atol=1e-15)


def test_in_words() -> None:
    """Points stated in words in docs/family.md §3 (leg A at home)."""

    def origins(arch: str) -> np.ndarray:
        robot = FamilyRobot.default(arch)
        return leg_chain(robot.types, robot.leg.placements, 0.0, np.array(robot.leg.home)).origin

    np.testing.assert_allclose(origins("3-RRR")[1], [0.2, -0.3], atol=1e-15)  # the elbow
    np.testing.assert_allclose(origins("3-RRR")[2], [0.2, -0.1], atol=1e-15)  # the platform joint
    np.testing.assert_allclose(origins("3-RPR")[2], [0.2, -0.1], atol=1e-15)
    np.testing.assert_allclose(origins("3-PPR")[2], [0.1, -0.2], atol=1e-15)
    np.testing.assert_allclose(origins("3-RPP")[2], [-0.2, -0.1], atol=1e-15)
    np.testing.assert_allclose(origins("3-RRP")[1], [0.2, -0.1], atol=1e-15)


@pytest.mark.parametrize("arch", ARCHITECTURES)
def test_template_round_trip(arch: str) -> None:
    robot = FamilyRobot.default(arch)
    text = family_template(arch)
    assert "#" in text and f'architecture = "{arch}"' in text
    assert FamilyRobot.from_mapping(tomllib.loads(text)) == robot
    assert FamilyRobot.from_mapping(tomllib.loads(robot.to_toml())) == robot


def test_forms() -> None:
    assert robot_file_form({}) == "model"
    assert robot_file_form({"l0": 0.4, "architecture": "3-PRP"}) == "model"
    for marker in ("actuated", "leg", "link1", "link2"):
        assert robot_file_form({marker: {}}) == "family"
    assert robot_file_form({"architecture": "3-XYZ"}) == "family"


@pytest.mark.parametrize(
    ("data", "key", "words"),
    [
        ({"architecture": "3-RRR", "l0": 0.3}, "l0", "model form"),
        ({"architecture": "3-RRR", "piston": {}}, "piston", "model form"),
        ({"architecture": "3-RRR", "link": {}}, "link", "model form"),
        ({"actuated": 1, "friction": {}}, "friction", "model form"),
        ({"architecture": "3-RRR", "colour": 1}, "colour", "unknown key"),
        ({"architecture": "3-RRR", "leg": {"joint4": [0, 0, 0]}}, "leg.joint4", "unknown key"),
        ({"architecture": "3-XYZ"}, "architecture", "3-XYZ"),
        ({"architecture": "3-RRR", "actuated": 4}, "actuated", "from 1 to 3"),
        ({"architecture": "3-RRR", "actuated": True}, "actuated", "True"),
        ({"architecture": "3-RRR", "leg": {"joint1": [0, 1]}}, "leg.joint1", "three numbers"),
        ({"architecture": "3-RRR", "leg": {"home": [0, 0, "x"]}}, "leg.home[2]", "number"),
        ({"architecture": "3-RRR", "leg": {"scale": 0.0}}, "leg.scale", "positive"),
        ({"architecture": "3-RRR", "link1": {"mass": -1.0}}, "link1.mass", "non-negative"),
        ({"architecture": "3-RRR", "link2": {"inertia": math.inf}}, "link2.inertia", "finite"),
        ({"architecture": "3-RRR", "platform": {"mass": -2}}, "platform.mass", "non-negative"),
        ({"architecture": "3-RRR", "payload": {"com": [0]}}, "payload.com", "pair"),
        ({"architecture": "3-PPR", "actuated": 3}, "actuated", "two passive P"),
        ({"architecture": "3-RPP", "actuated": 1}, "actuated", "two passive P"),
        ({"architecture": "3-PRP", "actuated": 2}, "actuated", "two passive P"),
        ({"architecture": "3-RRP", "actuated": 2}, "actuated", "parallel singularity"),
        ({"architecture": "3-RRR", "leg": {"home": [0.0, -PI / 2, 0.0]}}, "leg.home", "singular"),
    ],
)
def test_refusals_name_the_key(data: dict[str, object], key: str, words: str) -> None:
    with pytest.raises(ParameterError) as info:
        FamilyRobot.from_mapping(data)
    assert info.value.key == key
    assert words in str(info.value)
    assert "\n" not in str(info.value)


def test_partial_leg_table_keeps_the_rest(tmp_path: Path) -> None:
    path = tmp_path / "robot.toml"
    path.write_text('architecture = "3-RRR"\n[leg]\nattachment = [-0.21, 0.1, 0.0]\n')
    robot = read_robot_file(path)
    assert isinstance(robot, FamilyRobot)
    assert robot.leg.joint2 == FamilyRobot.default("3-RRR").leg.joint2
    assert robot.home_poses[0, 0] == pytest.approx(-0.01)  # the home pose moved off the origin


def test_read_either_form(tmp_path: Path) -> None:
    model = tmp_path / "model.toml"
    model.write_text("l0 = 0.4\n")
    assert read_robot_file(model) == Robot(l0=0.4)
    tagged = tmp_path / "tagged.toml"
    tagged.write_text('architecture = "3-PRP"\nl0 = 0.4\n')
    assert read_robot_file(tagged) == Robot(l0=0.4)
    family = tmp_path / "family.toml"
    family.write_text('architecture = "3-PRP"\nactuated = 3\n')
    assert read_robot_file(family) == FamilyRobot.default("3-PRP", 3)
    bad = tmp_path / "bad.toml"
    bad.write_text('architecture = "3-RPR"\n[link1]\nmass = -1\n')
    with pytest.raises(ParameterError, match=r"bad\.toml") as info:
        read_robot_file(bad)
    assert info.value.file == str(bad) and info.value.key == "link1.mass"
    broken = tmp_path / "broken.toml"
    broken.write_text("architecture = \n")
    with pytest.raises(InputFileError):
        read_robot_file(broken)


def test_immutable() -> None:
    robot = FamilyRobot.default("3-RRR")
    with pytest.raises(AttributeError):
        robot.actuated = 2  # type: ignore[misc]
