"""Bad input, round seven (issue 33).

1. ``prp3 forward --max-evaluations N --max-seconds S``: the bounds of the forward
   integration at the command line, for the 3-PRP, a family robot and the 6-UPS; a run
   stopped by one names the option and its value in one line (exit 2, nothing written);
   bad values of the options are refused by name.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from clitools import cli, one_line

HOLD_3PRP = "t,f10_A,f10_B,f10_C\n0,0,0,0\n0.5,0,0,0\n1,0,0,0\n"


# ------------------------------------------------- 1. the forward bounds at the command line
def _robot_file(tmp_path: Path, kind: str) -> tuple[list[str], str]:
    """(the arguments of ``prp3 forward`` of a robot of ``kind`` over about 1 s, the
    robot file) for the 3-PRP (zero forces: it falls), the stiff 3-RPR of round six (a
    3e11 kg platform) and the 6-UPS holding its home pose."""
    robot = tmp_path / "robot.toml"
    forces = tmp_path / "efforts.csv"
    if kind == "3-PRP":
        robot.write_text("", encoding="utf-8")
        forces.write_text(HOLD_3PRP, encoding="utf-8")
        return ["--robot", str(robot), "--forces", str(forces)], str(forces)
    if kind == "3-RPR":
        robot.write_text(
            'architecture = "3-RPR"\nactuated = 1\n[platform]\nmass = 3e11\n', encoding="utf-8"
        )
        forces.write_text("t,tau_A,tau_B,tau_C\n0,0,0,0\n0.5,0,0,0\n1,0,0,0\n", encoding="utf-8")
        return ["--robot", str(robot), "--forces", str(forces)], str(forces)
    robot.write_text('architecture = "6-UPS"\n', encoding="utf-8")
    return ["--robot", str(robot), "--efforts", "hold", "--duration", "0.5"], str(robot)


KINDS = ["3-PRP", "3-RPR", "6-UPS"]


@pytest.mark.parametrize(("kind", "count"), [("3-PRP", 300), ("3-RPR", 300), ("6-UPS", 5)])
def test_forward_stopped_by_max_evaluations_names_the_option(capsys, tmp_path, kind, count):
    # the 6-UPS holding still takes few steps: a bound of 5 stops it
    argv, _ = _robot_file(tmp_path, kind)
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "forward", *argv, "--max-evaluations", count,
                              "--output", out)  # fmt: skip
    message = one_line(err)
    assert status == 2 and stdout == "", (status, err)
    assert message.startswith(f"prp3 forward: error: --max-evaluations {count}: "), message
    assert f"stopped by its bound max_evaluations = {count}" in message, message
    assert not out.exists()


@pytest.mark.parametrize("kind", KINDS)
def test_forward_stopped_by_max_seconds_names_the_option(capsys, tmp_path, kind):
    argv, _ = _robot_file(tmp_path, kind)
    out = tmp_path / "out"
    status, _, err = cli(capsys, "forward", *argv, "--max-seconds", "1e-9", "--output", out)
    message = one_line(err)
    assert status == 2, (status, err)
    assert message.startswith("prp3 forward: error: --max-seconds 1e-09: "), message
    assert "stopped by its bound max_seconds = 1e-09 s" in message, message
    assert not out.exists()


@pytest.mark.parametrize("kind", ["3-PRP", "6-UPS"])
def test_forward_within_its_bounds_runs_as_before(capsys, tmp_path, kind):
    # the bounds given but not reached: the same files as a run without them
    argv, _ = _robot_file(tmp_path, kind)
    bounded, free = tmp_path / "bounded", tmp_path / "free"
    argv = [*argv, "--samples", "5"]
    status, _, err = cli(capsys, "forward", *argv, "--max-evaluations", "1000000",
                         "--max-seconds", "300", "--output", bounded)  # fmt: skip
    assert status == 0, err
    status, _, err = cli(capsys, "forward", *argv, "--output", free)
    assert status == 0, err
    for name in ("results.csv", "trajectory.csv"):
        assert (bounded / name).read_bytes() == (free / name).read_bytes()


BAD_BOUNDS = [
    ("--max-evaluations", "0"), ("--max-evaluations", "-3"), ("--max-evaluations", "1.5"),
    ("--max-evaluations", "1e3"), ("--max-evaluations", "nan"), ("--max-evaluations", "inf"),
    ("--max-evaluations", "1000000000001"), ("--max-evaluations", "true"),
    ("--max-evaluations", ""), ("--max-seconds", "0"), ("--max-seconds", "-0"),
    ("--max-seconds", "-1"), ("--max-seconds", "nan"), ("--max-seconds", "inf"),
    ("--max-seconds", "-inf"), ("--max-seconds", "1e309"), ("--max-seconds", "ten"),
    ("--max-seconds", ""),
]  # fmt: skip


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize(("option", "value"), BAD_BOUNDS)
def test_bad_forward_bounds_are_refused_by_name(capsys, tmp_path, kind, option, value):
    argv, _ = _robot_file(tmp_path, kind)
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "forward", *argv, option, value, "--output", out)
    message = one_line(err)
    assert status == 2 and stdout == "", (status, err)
    assert message.startswith(f"prp3 forward: error: argument {option}: "), message
    assert repr(value) in message, message
    assert not out.exists()


def test_a_family_run_stopped_by_its_bound_prints_plain_times(capsys, tmp_path):
    argv, _ = _robot_file(tmp_path, "3-RPR")
    status, _, err = cli(capsys, "forward", *argv, "--max-evaluations", "300",
                         "--output", tmp_path / "out")  # fmt: skip
    assert status == 2 and "np.float64" not in one_line(err), err
