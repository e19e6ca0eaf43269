"""What the command line says: one prefix for every message, one line per refusal.

Every message on stderr starts with the command that was run
(``prp3 simulate: error: ...``), whether argparse or prp3 found the error.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from clitools import cli


@pytest.mark.parametrize(
    ("argv", "program"),
    [
        # usage errors found by argparse
        (["simulate", "--motion", "vertical", "--samples", "1", "-o", "{tmp}/o"], "prp3 simulate"),
        (["workspace", "--points", "x", "-o", "{tmp}/o"], "prp3 workspace"),
        (["forward", "--rtol", "0", "--forces", "f.csv", "-o", "{tmp}/o"], "prp3 forward"),
        (["robot"], "prp3 robot"),
        (["export", "mjcf", "--bogus"], "prp3 export mjcf"),
        (["export", "sdf"], "prp3 export"),
        (["export", "urdf"], "prp3 export urdf"),  # --robot and --output are required
        (["--bogus"], "prp3"),
        # errors found by prp3 after parsing
        (["simulate", "--trajectory", "{tmp}/none.csv", "-o", "{tmp}/o"], "prp3 simulate"),
        (["workspace", "--robot", "{tmp}/none.toml", "-o", "{tmp}/o"], "prp3 workspace"),
        (["forward", "--forces", "{tmp}/none.csv", "-o", "{tmp}/o"], "prp3 forward"),
        (["robot", "--check", "{tmp}/none.toml"], "prp3 robot"),
        (["export", "mjcf", "--robot", "{tmp}/none.toml"], "prp3 export mjcf"),
    ],
)
def test_every_error_has_the_same_prefix(tmp_path, capsys, argv, program):
    # was: "prp3: error: ..." from prp3 but "prp3 simulate: error: ..." from argparse
    status, out, err = cli(capsys, *(a.replace("{tmp}", str(tmp_path)) for a in argv))
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"{program}: error: "), err
    assert re.match(r"^prp3( [a-z]+){0,2}: error: ", err)


def test_frames_without_animate_is_refused(tmp_path, capsys):
    # was: silently ignored
    status, out, err = cli(capsys, "simulate", "--motion", "vertical", "--frames", "12",
                           "-o", tmp_path / "o")  # fmt: skip
    assert (status, out) == (2, "")
    assert err == (
        "prp3 simulate: error: --frames 12 applies to the animation only: add --animate, "
        "or leave --frames out\n"
    )
    assert not (tmp_path / "o").exists()


def test_a_positions_only_trajectory_refused_as_singular_prints_one_line(tmp_path, capsys):
    # was: the warning "positions only; velocities ... computed" and then the error
    traj = tmp_path / "traj.csv"
    rows = [f"{k / 10},0,0,{0.5 + k * (math.pi / 3 - 0.5) / 6!r}" for k in range(7)]
    traj.write_text("t,x,y,phi\n" + "\n".join(rows) + "\n")
    status, out, err = cli(capsys, "simulate", "--trajectory", traj, "-o", tmp_path / "o")
    assert (status, out) == (2, "")
    assert err.count("\n") == 1 and "positions only" not in err
    assert err.startswith(f"prp3 simulate: error: {traj}:8: sample 6, t = 0.6 s: singular pose")


def test_a_positions_only_trajectory_that_runs_still_warns_once(tmp_path, capsys):
    traj = tmp_path / "traj.csv"
    traj.write_text("t,x,y,phi\n" + "".join(f"{k / 10},0,{k / 1000},0\n" for k in range(7)))
    status, out, err = cli(capsys, "simulate", "--trajectory", traj, "-o", tmp_path / "o")
    assert status == 0 and "files written:" in out
    assert err.count("\n") == 1
    assert err.startswith(f"prp3 simulate: warning: {traj}: positions only")


def test_export_to_a_file_reports_what_it_wrote(tmp_path: Path, capsys):
    # was: nothing on stdout (every other command reports its files)
    status, out, err = cli(capsys, "export", "mjcf", "-o", tmp_path / "m.xml")
    assert (status, err) == (0, "")
    size = (tmp_path / "m.xml").stat().st_size
    assert out == (
        "prp3 export mjcf: MuJoCo MJCF model of the paper's robot (3 legs as chains, loops "
        f"closed by 2 welds, motors actuator_A/B/C on the sliders), {size} bytes\n"
        f"files written:\n  {tmp_path / 'm.xml'}\n"
    )
