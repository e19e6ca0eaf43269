"""Bad input, what was left of issue 33: a family robot's absurd ``[load]`` named in its own
file, the public readers of the spatial and family files fed hostile input, and hostile
values on the family and spatial commands (one line, exit 2, nothing written)."""

from __future__ import annotations

import numpy as np
import pytest

import prp3
from clitools import cli, one_line

FORCES = "t,tau_A,tau_B,tau_C\n0.0,0.0,0.0,0.0\n0.5,0.0,0.0,0.0\n1.0,0.0,0.0,0.0\n"


@pytest.mark.parametrize(
    ("load", "key", "line"),
    [
        ("force = [1e12, 0.0]\nmoment = 0.0\n", "load.force", 4),
        ("force = [0.0, -1e308]\n", "load.force", 4),
        ("moment = 0.0\nforce = [0.0, 0.0]\n", None, None),
        ("force = [1.0, 0.0]\nmoment = 1e300\n", "load.moment", 5),
        ("moment = 1e300\nforce = [1.0, 0.0]\n", "load.moment", 4),
    ],
)
def test_an_absurd_family_load_names_the_robot_file_key_and_line(capsys, tmp_path, load, key, line):
    robot = tmp_path / "rrr.toml"
    robot.write_text(f'architecture = "3-RRR"\nactuated = 1\n[load]\n{load}', encoding="utf-8")
    (tmp_path / "zero.csv").write_text(FORCES, encoding="utf-8")
    status, _, err = cli(capsys, "forward", "--robot", robot, "--forces", tmp_path / "zero.csv",
                         "--samples", 3, "--output", tmp_path / "out")  # fmt: skip
    if key is None:  # no load: the zero efforts only let it fall, no refusal
        assert "beyond the bound" not in err and status in (0, 1), err
        return
    text = one_line(err)
    assert status == 2 and f"rrr.toml:{line}: {key} = " in text, text
    assert f"beyond the bound {prp3.MAX_ACCELERATION:g}" in text and "zero.csv" not in text
    assert not (tmp_path / "out").exists()


def test_an_absurd_family_load_is_refused_by_the_function_too():
    robot = prp3.FamilyRobot.from_mapping({"architecture": "3-RPR", "load": {"moment": -1e9}})
    with pytest.raises(prp3.ParameterError, match=r"load.moment = -1000000000.0 alone") as caught:
        prp3.family_forward_dynamics(robot, [0.0, 1.0], np.zeros((2, 3)), [0.0, 0.5],
                                     robot.home_poses[0], np.zeros(3))  # fmt: skip
    assert caught.value.key == "load.moment"
