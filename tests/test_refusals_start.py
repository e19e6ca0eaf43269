"""Numbers that lose their meaning at the start are refused in one line (issue 21).

* an integration that fails at its first step has integrated nothing: an
  error (exit 2), not a warning with a one-sample result;
* a workspace window or a stroke of ±1e308 overflows numpy: one line naming
  the option or the key, no numpy warning.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from clitools import cli, one_line
from prp3 import Robot
from prp3.analysis.forward import forward_dynamics
from prp3.analysis.reachability import orientation_range, reachable_region
from prp3.analysis.workspace import workspace_slice
from prp3.errors import ParameterError, TrajectoryError
from prp3.model.parameters import Limits


def force_file(folder: Path, value: float) -> Path:
    path = folder / "forces.csv"
    rows = "".join(f"{t},{value!r},{value!r},{-value!r}\n" for t in (0.0, 0.1, 0.2))
    path.write_text("t,f10_A,f10_B,f10_C\n" + rows)
    return path


def test_an_integration_that_fails_at_the_start_is_an_error() -> None:
    # forces of 1e300 N are refused before the integration (issue 33: MAX_ACCELERATION)
    with pytest.raises(ParameterError, match=r"at t = 0.0 s ask for a platform acceleration"):
        forward_dynamics(Robot(), lambda t: np.array([1e300, 1e300, -1e300]), [0.0, 0.2],
                         [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])  # fmt: skip
    with pytest.raises(TrajectoryError, match="initial velocity"):
        forward_dynamics(Robot(), lambda t: np.zeros(3), [0.0, 0.2],
                         [0.0, 0.0, 0.0], [1e300, 0.0, 0.0])  # fmt: skip


@pytest.mark.parametrize(
    ("forces", "options"),
    [(1e300, ()), (30.0, ("--initial-velocity", "1e300", "0", "0"))],
)
def test_forward_command_refuses_a_start_that_fails(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], forces: float, options: tuple[str, ...]
) -> None:
    file = force_file(tmp_path, forces)
    status, out, err = cli(capsys, "forward", "--forces", file, *options, "-o", tmp_path / "o")
    line = one_line(err)
    words = "beyond the bound 1e+06" if forces > 1e6 else "fails at its first step"
    assert status == 2 and out == "" and words in line
    assert not (tmp_path / "o").exists()


def test_a_start_that_works_is_still_a_result() -> None:
    result = forward_dynamics(Robot(), lambda t: np.array([31.8589, -8.4957, -23.3632]),
                              [0.0, 0.1], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])  # fmt: skip
    assert result.status == "completed" and result.motion.samples == 2


# ------------------------------------------------------------------ workspace
@pytest.mark.parametrize(
    "extent",
    [("-1e308", "1e308", "-1", "1"), ("-1", "1", "-1e308", "1e308"), ("0", "1e308", "0", "1")],
)
def test_workspace_refuses_a_huge_extent_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extent: tuple[str, ...]
) -> None:
    status, _out, err = cli(capsys, "workspace", "--extent", *extent, "-o", tmp_path / "o")
    line = one_line(err)  # no numpy warning
    assert status == 2 and line.startswith("prp3 workspace: error: --extent ")
    assert "100*l0 = 30 m" in line


def test_workspace_refuses_a_huge_stroke_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text("[limits]\nstroke = [-1e308, 1e308]\n")
    status, _out, err = cli(capsys, "workspace", "--robot", robot, "-o", tmp_path / "o")
    line = one_line(err)
    assert status == 2 and "limits.stroke" in line and "100*l0 = 30 m" in line


def test_the_library_refuses_a_huge_stroke_too() -> None:
    robot = Robot(limits=Limits(stroke=(-1e308, 1e308)))
    for call in (
        lambda: reachable_region(robot, 0.0),
        lambda: orientation_range(robot),
        lambda: workspace_slice(robot, 0.0, [-0.1, 0.1], [-0.1, 0.1]),
    ):
        with pytest.raises(ParameterError, match=r"limits\.stroke"):
            call()
    # a stroke within the bound is a workspace as before
    assert reachable_region(Robot(limits=Limits(stroke=(-30.0, 30.0))), 0.0).shape == (6, 2)
