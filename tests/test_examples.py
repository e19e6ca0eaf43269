"""The example input files of ``examples/`` are what the docs say, and the docs' commands
that use them run as they stand (in a copy of the folder, from its parent)."""

from __future__ import annotations

import contextlib
import io
import re
import shlex
import shutil
from pathlib import Path

import numpy as np
import pytest

import prp3
from prp3.cli import main
from prp3.io.formats import read_forces, read_trajectory

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def _section_commands(document: Path, heading: str) -> list[str]:
    text = document.read_text(encoding="utf-8")
    body = text.split(heading, 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```sh\n(.*?)```", body, re.S)
    return [line.split("#")[0].strip() for block in blocks for line in block.splitlines()
            if line.split("#")[0].strip()]  # fmt: skip


def test_the_example_files_are_what_the_docs_say():
    trajectory = read_trajectory(EXAMPLES / "trajectory.csv")
    assert trajectory.note is not None  # positions only: the derivatives are computed
    assert trajectory.motion.samples == 201 and float(trajectory.motion.t[-1]) == 2.0
    robot = prp3.Robot.from_toml(EXAMPLES / "robot.toml")
    assert robot.limits.stroke == (-0.04, 0.04) and robot.limits.max_force == 60.0
    # the tool is a payload (its own mass and inertia), not a heavier plate
    assert robot.platform == prp3.Robot().platform
    assert (robot.payload.mass, robot.payload.com, robot.payload.inertia) == (
        0.5,
        (0.0, 0.0),
        2.25e-4,
    )
    forces = read_forces(EXAMPLES / "forces.csv")
    assert not forces.results and forces.forces.t.size == 9
    # at t = 0 they hold the robot of robot.toml still at the centre (to their 4 decimals)
    still = prp3.Motion(t=0.0, pose=np.zeros(3), velocity=np.zeros(3), acceleration=np.zeros(3))
    holding = prp3.inverse_dynamics(robot, still, method="newton-euler")[1].f10
    assert np.abs(forces.forces.f10[0] - holding).max() <= 5e-5
    for document in (ROOT / "README.md", ROOT / "docs" / "cli.md", ROOT / "docs" / "model.md"):
        text = document.read_text(encoding="utf-8")
        assert "examples/" in text, document


def test_the_commands_of_the_docs_on_the_examples_run(tmp_path, monkeypatch):
    shutil.copytree(EXAMPLES, tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    commands = _section_commands(ROOT / "docs" / "cli.md", "## Example input files")
    assert len(commands) >= 4 and all("examples/" in line for line in commands)
    for line in commands:
        argv = shlex.split(line)
        assert argv[0] == "prp3"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            assert main(argv[1:]) == 0, line
    assert (tmp_path / "circle" / "results.csv").is_file()
    assert (tmp_path / "circle" / "f10.png").is_file()
    assert (tmp_path / "push" / "trajectory.csv").is_file()
    assert (tmp_path / "ws" / "workspace.png").is_file()


@pytest.mark.parametrize("name", ["trajectory.csv", "robot.toml", "forces.csv"])
def test_every_example_file_is_linked_from_the_docs(name):
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    assert f"examples/{name}" in text
