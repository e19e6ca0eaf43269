"""``prp3 simulate --animate`` of a family robot draws the robot's own legs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from clitools import cli
from prp3.family import ARCHITECTURES, FamilyRobot
from prp3.plotting.family_animation import family_frame

S2 = np.sqrt(2.0)


@pytest.mark.parametrize(
    ("architecture", "revolute", "slider"),
    [  # leg A at home, docs/family.md §3 "in words"
        ("3-RRR", [(0.0, -0.3), (0.2, -0.3), (0.2, -0.1)], []),
        ("3-RPR", [(0.0, -0.3), (0.2, -0.1)], [(0.2, -0.1)]),
        ("3-PRR", [(0.2, -0.3), (0.2, -0.1)], [(0.2, -0.3)]),
        ("3-PPR", [(0.1, -0.2)], [(0.1, -0.3), (0.1, -0.2)]),
    ],
)
def test_joints_at_home(
    architecture: str, revolute: list[tuple[float, float]], slider: list[tuple[float, float]]
) -> None:
    robot = FamilyRobot.default(architecture)
    frame = family_frame(robot, np.tile(robot.leg.home, (3, 1)), np.zeros(3))
    mine = [i for i, j in enumerate(frame.revolute_leg) if j == 0]
    np.testing.assert_allclose(frame.revolute[mine], np.array(revolute), atol=1e-12)
    bars = [i for i, j in enumerate(frame.slider_leg) if j == 0]
    centres = frame.sliders[bars].mean(axis=1) if bars else np.zeros((0, 2))
    np.testing.assert_allclose(centres, np.array(slider).reshape(-1, 2), atol=1e-12)
    types = robot.types
    assert len(frame.revolute) == 3 * types.count("R")
    assert len(frame.sliders) == 3 * types.count("P")
    assert sum(frame.revolute_driven) + sum(frame.slider_driven) == 3  # one per leg
    # legs B and C are leg A turned by 120° and 240°
    c, s = np.cos(2 * np.pi / 3), np.sin(2 * np.pi / 3)
    turned = frame.platform[0] @ np.array([[c, s], [-s, c]])
    np.testing.assert_allclose(frame.platform[1], turned, atol=1e-12)


@pytest.mark.parametrize("architecture", ["3-RRP", "3-RPP"])
def test_cli_animate_writes_the_gif(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, architecture: str
) -> None:
    robot_file = tmp_path / "robot.toml"
    robot_file.write_text(f'architecture = "{architecture}"\n')
    status, out, err = cli(
        capsys, "simulate", "--robot", robot_file, "--motion", "rotation", "--samples", "31",
        "--animate", "--frames", "6", "--output", tmp_path / "out",
    )  # fmt: skip
    assert status == 0, err
    with Image.open(tmp_path / "out" / "mechanism.gif") as image:
        assert image.n_frames == 6
    assert "mechanism.gif" in out


def test_every_architecture_has_a_frame() -> None:
    for architecture in ARCHITECTURES:
        robot = FamilyRobot.default(architecture)
        frame = family_frame(robot, np.tile(robot.leg.home, (3, 1)), np.zeros(3))
        assert np.isfinite(frame.links).all() and frame.links.shape == (3, 2, 2, 2)
