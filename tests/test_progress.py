"""Progress of long runs: callbacks in the library, a bar (tqdm) only on a terminal.

* Every long library function takes ``progress(done, total)``: the reports
  grow, stay within ``0 .. total`` and end at ``(total, total)``.
* The command line draws a bar with the count and the time left on a
  terminal's stderr (a fake terminal here), and prints nothing on a stderr
  that is not a terminal (a pipe, a file: what the rest of the suite sees).
"""

from __future__ import annotations

import io
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import prp3.cli._progress as progress_module
from prp3 import Robot
from prp3.analysis.forward import forward_dynamics
from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.analysis.workspace import orientation_scan
from prp3.apps.control import control_times, track
from prp3.apps.excitation import exciting_trajectory
from prp3.apps.identification import identify
from prp3.cli import main
from prp3.cli._progress import Progress
from prp3.model.motion import PAPER_MOTIONS, law_at, law_motion

#: A bar of tqdm: ``stage:  50%|#####     | 5/10 [00:01<00:01, 4.2it/s]`` (the ETA after ``<``).
BAR = re.compile(r"(\w[\w.]*): +(\d+)%\|[^|]*\| (\d+)/(\d+) \[\d\d:\d\d<(\d\d:\d\d|\?)")


class FakeTerminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def reports() -> tuple[list[tuple[int, int]], object]:
    seen: list[tuple[int, int]] = []
    return seen, lambda done, total: seen.append((done, total))


def check_reports(seen: list[tuple[int, int]], total: int) -> None:
    assert seen, "no progress reported"
    done = [d for d, _ in seen]
    assert all(t == total for _, t in seen)
    assert done == sorted(done) and 0 <= done[0] and done[-1] == total


# ---------------------------------------------------------------- the library
def test_the_long_library_functions_report_their_progress():
    robot = Robot()
    grid = np.linspace(-0.1, 0.1, 11)
    seen, callback = reports()
    orientation_scan(robot, grid, grid, np.linspace(-0.5, 0.5, 7), progress=callback)
    check_reports(seen, 7)

    times = np.linspace(0.0, 0.2, 21)
    seen, callback = reports()
    forward_dynamics(Robot(gravity=(0.0, 0.0)), lambda t: np.zeros(3), times, [0.0, 0.0, 0.0],
                     [0.01, 0.0, 0.0], progress=callback)  # fmt: skip
    check_reports(seen, 21)

    reference = law_at(PAPER_MOTIONS["vertical"], control_times(0.0, 0.05, 200.0))
    seen, callback = reports()
    run = track(robot, reference, progress=callback)
    check_reports(seen, reference.samples)
    assert len(seen) == run.t.size  # one report per control instant

    motion = law_motion((0.01, 0.02, 0.2), samples=101)
    seen, callback = reports()
    identify(robot, motion, inverse_dynamics(robot, motion)[1].f10, progress=callback)
    check_reports(seen, 101)

    seen, callback = reports()
    exciting_trajectory(robot, samples=40, max_iterations=3, progress=callback)
    check_reports(seen, 3)


# ---------------------------------------------------------------- the bar
def test_the_bar_draws_on_a_terminal_after_the_delay_and_is_erased():
    times = iter([0.0, 0.5, 1.2, 1.25, 1.5, 1.6])
    stream = FakeTerminal()
    bar = Progress(stream, clock=lambda: next(times))  # made at t = 0
    bar.update("computing", 1, 10)  # t = 0.5 s: too early
    assert stream.getvalue() == ""
    bar.update("computing", 5, 10)  # t = 1.2 s: drawn
    assert [m.group(1, 2, 3, 4) for m in BAR.finditer(stream.getvalue())] == [
        ("computing", "50", "5", "10")
    ]
    bar.update("computing", 6, 10)  # t = 1.25 s: throttled
    assert len(BAR.findall(stream.getvalue())) == 1
    bar.update("computing", 10, 10)  # t = 1.5 s: the end of a stage is always drawn
    last = list(BAR.finditer(stream.getvalue()))[-1]
    assert last.group(2, 3, 4) == ("100", "10", "10") and last.group(5) != "?"  # an ETA
    bar.update("writing", 3, 30)  # t = 1.6 s: the next stage replaces the bar
    assert list(BAR.finditer(stream.getvalue()))[-1].group(1, 2) == ("writing", "10")
    bar.close()
    assert stream.getvalue().endswith("\r") and bar.drawn is False  # erased
    quiet = io.StringIO()  # not a terminal: nothing, whatever the time
    silent = Progress(quiet, clock=lambda: 100.0)
    silent.update("computing", 5, 10)
    silent.close()
    assert quiet.getvalue() == ""


def _measurements(path: Path) -> Path:
    robot = Robot()
    motion = law_motion((0.01, 0.02, 0.2), samples=101)
    f10 = inverse_dynamics(robot, motion)[1].f10
    columns = [motion.t, *motion.pose.T, *motion.velocity.T, *motion.acceleration.T, *f10.T]
    header = "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi,f10_A,f10_B,f10_C"
    rows = np.column_stack(columns).tolist()
    path.write_text(header + "\n" + "".join(",".join(map(repr, r)) + "\n" for r in rows))
    return path


def _commands(tmp: Path) -> list[tuple[list[str], list[str]]]:
    """(argv, stages that must show a bar) of each long subcommand, on small inputs."""
    forces = tmp / "forces"
    return [
        (["simulate", "--motion", "vertical", "--samples", "41", "-o", str(forces)],
         ["computing", "results.csv"]),
        (["workspace", "--points", "11", "--orientations", "5", "-o", str(tmp / "w")],
         ["orientations", "workspace.csv", "orientations.csv"]),
        (["forward", "--forces", str(forces / "results.csv"), "--samples", "11",
          "-o", str(tmp / "f")], ["integrating"]),
        (["control", "--motion", "vertical", "--plant", "prp3", "--controller", "pd",
          "--rate", "20", "-o", str(tmp / "c")],
         ["tracking"]),
        (["identify", "--measurements", str(_measurements(tmp / "m.csv")), "-o", str(tmp / "i")],
         ["regressor"]),
        (["excite", "--iterations", "2", "--samples", "40", "-o", str(tmp / "e")],
         ["optimising"]),
    ]  # fmt: skip


@pytest.mark.slow  # every long command, on a terminal and off it
def test_every_long_command_draws_a_bar_on_a_terminal_and_nothing_elsewhere(tmp_path, monkeypatch):
    monkeypatch.setattr(progress_module, "DELAY", 0.0)  # small inputs: draw at once
    for terminal in (True, False):
        out = tmp_path / ("tty" if terminal else "pipe")
        out.mkdir()
        commands = _commands(out)
        # not a terminal: the rest of the suite sees that in every command (stderr == "")
        for argv, stages in commands if terminal else commands[:2]:
            stream = FakeTerminal() if terminal else io.StringIO()
            monkeypatch.setattr(sys, "stderr", stream)
            status = main(argv)
            monkeypatch.undo()
            monkeypatch.setattr(progress_module, "DELAY", 0.0)
            assert status in (0, 1), (argv, stream.getvalue())  # forward may stop: exit 1
            text = stream.getvalue()
            if terminal:
                drawn = {m.group(1) for m in BAR.finditer(text)}
                assert set(stages) <= drawn, (argv[0], drawn, text)
            else:
                assert "\r" not in text and not BAR.search(text), (argv[0], text)


@pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals are POSIX")
def test_a_real_terminal_of_unknown_size_shows_the_bar(tmp_path):
    # was: a new pseudo-terminal reports 0 x 0 and tqdm drew an empty bar, hidden below
    # row 0: nothing on the screen
    import os
    import pty
    import subprocess

    code = (
        "import sys, prp3.cli._progress as p; p.DELAY = 0.0; from prp3.cli import main; "
        "sys.exit(main(['workspace', '--points', '21', '--orientations', '9', '-o', 'w']))"
    )
    master, slave = pty.openpty()
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.DEVNULL,
                             stderr=slave, cwd=tmp_path, env=env)  # fmt: skip
    os.close(slave)
    received = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the child closed its end
            break
        if not chunk:
            break
        received += chunk
    os.close(master)
    assert child.wait(timeout=300) == 0
    text = received.decode("utf-8", "replace")
    assert {m.group(1) for m in BAR.finditer(text)} >= {"orientations", "workspace.csv"}, text
    assert text.endswith("\r")  # erased at the end
