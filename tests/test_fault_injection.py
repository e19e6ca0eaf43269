"""Real faults for every writing command: a full disk, a read-only folder, a kill at any moment.

``tests/test_faults.py`` simulates a full disk by patching the writer; here the
faults are real.  Each command runs in a mount namespace of its own
(``unshare --map-root-user --mount``, see ``tests/fault_volume.py``) whose output
folder is a small tmpfs: it succeeds once, then the volume is filled to its
last byte (or remounted read-only) and the same command runs again, and once
more into a folder that did not exist.  Every faulty run must end in one line
on stderr naming the file it could not write, exit status 2, no traceback, the
earlier run's files byte for byte as they were and no new file or folder.

The kill test sends SIGTERM or SIGINT to a long command at a random moment
(seeded; the seed is in the failure message) and checks the folder holds
either the earlier run, byte for byte, or the whole new one, never a half file
or a staging folder.

The moment is drawn after the kernel shows the handlers installed (SigCgt): before
that (Python's start and the import of ``prp3.cli``) Python's own
handlers act, which end the process with nothing written — SIGINT with
Python's KeyboardInterrupt traceback.

The tests skip, with one line, where user namespaces are not allowed.
"""

from __future__ import annotations

import contextlib
import csv
import functools
import hashlib
import io
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

import prp3
from read_only import NAMESPACES

HERE = Path(__file__).parent
EXAMPLES = HERE.parent / "examples"
MANIFEST = ".prp3-manifest.json"  # the output folder's record of its runs (docs/cli.md)
ENV = {key: value for key, value in os.environ.items() if key != "PYTHONUNBUFFERED"}


pytestmark = NAMESPACES

FAMILY_ROBOT = 'architecture = "3-RRR"\nactuated = 1\n'
SPATIAL_ROBOT = 'architecture = "6-UPS"\n'
SWEEP_SPEC = """designs = 3
sampling = "grid"
seed = 1
[parameters]
"platform.mass" = [2.0, 4.0]
[task]
motions = ["vertical"]
samples = 21
[optimize]
objective = "peak_f10"
maxiter = 1
popsize = 2
"""


SPATIAL_SWEEP_SPEC = """spatial = "6-UPS"
designs = 3
sampling = "grid"
[parameters]
"platform.mass" = [2.0, 4.0]
[task]
motions = ["heave"]
samples = 21
"""
FAMILY_SWEEP_SPEC = """designs = 3
sampling = "grid"
[task]
motions = ["vertical"]
samples = 21
[[study]]
architecture = "3-RRR"
[study.parameters]
"link2.mass" = [0.5, 1.0]
"""


def _columns(table: Path, names: list[str]) -> list[list[str]]:
    with table.open(newline="") as handle:
        return [[row[name] for name in names] for row in csv.DictReader(handle)]


@functools.cache
def _measurements() -> dict[str, str]:
    """Measurement tables a family and a spatial ``prp3 identify`` accept, made once.

    Each is an exciting trajectory of ``prp3 excite`` whose efforts come from
    ``prp3 simulate`` on it (the identification's own correctness is tested in
    tests/test_family_identify*.py and tests/test_spatial_identify*.py).
    """
    from prp3.cli import main

    made: dict[str, str] = {}
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        (folder / "rrr.toml").write_text(FAMILY_ROBOT)
        (folder / "hexapod.toml").write_text(SPATIAL_ROBOT)
        for robot, samples, efforts in (
            ("rrr.toml", "101", ["tau_A", "tau_B", "tau_C"]),
            ("hexapod.toml", "201", [f"tau_{i}" for i in range(1, 7)]),
        ):
            ex, sim = folder / f"ex-{robot}", folder / f"sim-{robot}"
            with contextlib.redirect_stdout(io.StringIO()):
                assert main(["excite", "--robot", str(folder / robot), "--samples", samples,
                             "--iterations", "2", "--output", str(ex)]) == 0  # fmt: skip
                assert main(["simulate", "--robot", str(folder / robot), "--trajectory",
                             str(ex / "trajectory.csv"), "--output", str(sim)]) == 0  # fmt: skip
            with (ex / "trajectory.csv").open() as handle:
                pose = [name for name in handle.readline().strip().split(",")
                        if robot == "hexapod.toml" or name in ("t", "x", "y", "phi")]  # fmt: skip
            rows = [a + b for a, b in zip(_columns(ex / "trajectory.csv", pose),
                                          _columns(sim / "results.csv", efforts), strict=True)]  # fmt: skip
            made[robot] = "\n".join(",".join(row) for row in [pose + efforts, *rows]) + "\n"
        with contextlib.redirect_stdout(io.StringIO()):  # a motion prp3 forward follows
            assert main(["simulate", "--robot", str(folder / "rrr.toml"), "--motion", "vertical",
                         "--samples", "101", "--output", str(folder / "vertical")]) == 0  # fmt: skip
        made["forces"] = (folder / "vertical" / "results.csv").read_text()
    return made


def _inputs(folder: Path) -> None:
    """The input files the commands read, in ``folder`` (outside the faulty volume)."""
    (folder / "rps.toml").write_text('architecture = "3-RPS"\n')
    (folder / "delta.toml").write_text('architecture = "3-RUU"\n')
    (folder / "spatial-sweep.toml").write_text(SPATIAL_SWEEP_SPEC)
    (folder / "family-sweep.toml").write_text(FAMILY_SWEEP_SPEC)
    measured = _measurements()
    (folder / "fm.csv").write_text(measured["rrr.toml"])
    (folder / "sm.csv").write_text(measured["hexapod.toml"])
    (folder / "family-forces.csv").write_text(measured["forces"])
    shutil.copy(EXAMPLES / "robot.toml", folder / "robot.toml")
    shutil.copy(EXAMPLES / "forces.csv", folder / "forces.csv")
    (folder / "rrr.toml").write_text(FAMILY_ROBOT)
    (folder / "hexapod.toml").write_text(SPATIAL_ROBOT)
    (folder / "sweep.toml").write_text(SWEEP_SPEC)
    t = np.linspace(0.0, 2.0, 201)[:, None]  # a multi-sine that moves every coordinate
    w = 2.0 * np.pi * np.array([1.0, 1.5, 2.5])
    amplitude = np.array([0.02, 0.02, 0.2])
    motion = prp3.Motion(
        t[:, 0],
        amplitude * np.sin(w * t),
        amplitude * w * np.cos(w * t),
        -amplitude * w**2 * np.sin(w * t),
    )
    _, dyn = prp3.inverse_dynamics(prp3.Robot(), motion)
    rows = np.column_stack([motion.t, motion.pose, dyn.f10])
    header = "t,x,y,phi,f10_A,f10_B,f10_C"
    np.savetxt(folder / "m.csv", rows, delimiter=",", header=header, comments="", fmt="%.17g")


#: Every command that writes files: its arguments with ``{out}`` for the output folder.
COMMANDS: dict[str, str] = {
    "simulate": "simulate --motion vertical --samples 40 --plots --output {out}",
    "simulate-family": "simulate --robot rrr.toml --motion vertical --samples 40 --plots --output {out}",
    "simulate-spatial": "simulate --robot hexapod.toml --motion tilt --samples 40 --plots --output {out}",
    "forward-spatial": "forward --robot hexapod.toml --efforts hold --duration 0.05 --plots --output {out}",
    "workspace": "workspace --robot robot.toml --points 9 --orientations 5 --output {out}",
    "forward": "forward --robot robot.toml --forces forces.csv --samples 20 --output {out}",
    "control": "control --motion vertical --plant prp3 --controller pd --rate 200 --output {out}",
    "excite": "excite --samples 101 --iterations 2 --output {out}",
    "identify": "identify --measurements m.csv --output {out}",
    "export-c": "export c --output {out}",
    "export-mjcf": "export mjcf --output {out}.xml",
    "export-urdf-spatial": "export urdf --robot hexapod.toml --output {out}.urdf",
    "sweep": "sweep --spec sweep.toml --workers 1 --output {out}",
    "explore-export": "explore --export {out}.html",
    # the family and spatial forms of every writing command (issue 33)
    "workspace-family": "workspace --robot rrr.toml --points 9 --orientations 5 --output {out}",
    "workspace-spatial": "workspace --robot hexapod.toml --output {out}",
    "workspace-3-RPS": "workspace --robot rps.toml --output {out}",
    "forward-family": "forward --robot rrr.toml --forces family-forces.csv --samples 20 --output {out}",
    "forward-3-RPS": "forward --robot rps.toml --efforts hold --duration 0.05 --output {out}",
    "forward-Delta": "forward --robot delta.toml --efforts hold --duration 0.05 --output {out}",
    "control-family": "control --robot rrr.toml --motion vertical --plant prp3 --controller pd --rate 200 --output {out}",
    "control-spatial": "control --robot hexapod.toml --motion heave --plant prp3 --controller computed-torque --rate 100 --duration 0.2 --output {out}",
    "excite-family": "excite --robot rrr.toml --samples 101 --iterations 2 --output {out}",
    "excite-spatial": "excite --robot hexapod.toml --samples 201 --iterations 2 --output {out}",
    "identify-family": "identify --robot rrr.toml --measurements fm.csv --output {out}",
    "identify-spatial": "identify --robot hexapod.toml --measurements sm.csv --output {out}",
    "export-c-family": "export c --robot rrr.toml --output {out}",
    "export-c-spatial": "export c --robot hexapod.toml --output {out}",
    "export-mjcf-family": "export mjcf --robot rrr.toml --output {out}.xml",
    "export-mjcf-spatial": "export mjcf --robot hexapod.toml --output {out}.xml",
    "export-mjcf-Delta": "export mjcf --robot delta.toml --output {out}.xml",
    "sweep-family": "sweep --spec family-sweep.toml --workers 1 --output {out}",
    "sweep-spatial": "sweep --spec spatial-sweep.toml --workers 1 --output {out}",
    "explore-export-spatial": "explore --robot hexapod.toml --export {out}.html",
    "explore-export-family": "explore --robot rrr.toml --export {out}.html",
}


def _argv(name: str, out: str) -> list[str]:
    return COMMANDS[name].format(out=out).split()


def _faulty_runs(tmp_path: Path, name: str, fault: str) -> dict[str, object]:
    _inputs(tmp_path)
    volume = tmp_path / "vol"
    volume.mkdir()
    spec = {
        "volume": str(volume),
        "size": 48 * 2**20,
        "fault": fault,
        "cwd": str(tmp_path),
        "argv": _argv(name, "vol/out"),
        "fresh_argv": _argv(name, "vol/new"),
    }
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    done = subprocess.run(
        [
            "unshare",
            "--map-root-user",
            "--mount",
            sys.executable,
            str(HERE / "fault_volume.py"),
            str(tmp_path / "spec.json"),
        ],
        capture_output=True,
        text=True,
        env=ENV,
        timeout=300,
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    report: dict[str, object] = json.loads(done.stdout.strip().splitlines()[-1])
    return report


def _one_line_naming_a_file(run: dict[str, object], program: str) -> str:
    assert run["raised"] is None, run
    assert run["status"] == 2, run
    stderr = str(run["stderr"])
    assert stderr.endswith("\n") and "Traceback" not in stderr, stderr
    *warnings, error = stderr.splitlines()  # a warning about the inputs may come first
    assert all(line.startswith(f"prp3 {program}: warning: ") for line in warnings), stderr
    assert error.startswith(f"prp3 {program}: error: "), stderr
    assert "vol/" in error, stderr  # the file or folder it could not write
    return error


@pytest.mark.slow
@pytest.mark.parametrize("fault", ["full", "read-only"])
@pytest.mark.parametrize("name", list(COMMANDS))
def test_a_real_fault_is_one_line_and_loses_nothing(tmp_path: Path, name: str, fault: str) -> None:
    report = _faulty_runs(tmp_path, name, fault)
    first = report["first"]
    assert first == {"status": 0, "stderr": first["stderr"], "raised": None}, first  # type: ignore[index]
    before = report["before"]
    assert isinstance(before, dict) and any(not key.endswith("/") for key in before), before
    words = COMMANDS[name].split()
    program = " ".join(words[:2]) if name.startswith("export") else words[0]
    message = _one_line_naming_a_file(report["again"], program)  # type: ignore[arg-type]
    if fault == "full":
        assert "No space left on device" in message or "disk is full" in message, message
    else:
        assert "not writable" in message or "Read-only file system" in message, message
    assert report["after_again"] == before  # the earlier run, byte for byte
    _one_line_naming_a_file(report["fresh"], program)  # type: ignore[arg-type]
    assert report["after_fresh"] == before  # no new folder, no half file


#: The long commands and a size that keeps each busy for about a second or more.
LONG_COMMANDS: dict[str, str] = {
    "simulate": "simulate --motion rotation --samples 200000 --output {out}",
    "simulate-plots": "simulate --motion vertical --samples 3000 --plots --output {out}",
    "workspace": "workspace --robot robot.toml --points 101 --orientations 31 --output {out}",
    "forward": "forward --robot robot.toml --forces forces.csv --samples 4000 --output {out}",
    "excite": "excite --samples 401 --iterations 20 --output {out}",
    "sweep": "sweep --spec sweep.toml --workers 1 --output {out}",
    "control": "control --motion rotation --plant prp3 --controller pd --rate 2000 --output {out}",
    "identify": "identify --measurements m.csv --output {out}",
    "simulate-family": "simulate --robot rrr.toml --motion vertical --samples 20000 --output {out}",
    "workspace-family": "workspace --robot rrr.toml --points 41 --orientations 9 --output {out}",
    "export-c": "export c --output {out}",
    "simulate-spatial": "simulate --robot hexapod.toml --motion circle --samples 20000 --output {out}",
    "forward-spatial": "forward --robot hexapod.toml --efforts hold --duration 0.3 --output {out}",
    "forward-family": "forward --robot rrr.toml --forces family-forces.csv --samples 400 --output {out}",
    "forward-Delta": "forward --robot delta.toml --efforts hold --duration 0.3 --output {out}",
    "control-spatial": "control --robot hexapod.toml --motion heave --plant prp3 --controller computed-torque --rate 200 --duration 0.5 --output {out}",
    "excite-spatial": "excite --robot hexapod.toml --samples 201 --iterations 5 --output {out}",
    "identify-spatial": "identify --robot hexapod.toml --measurements sm.csv --output {out}",
    "sweep-family": "sweep --spec family-sweep.toml --workers 1 --output {out}",
    "sweep-spatial": "sweep --spec spatial-sweep.toml --workers 1 --output {out}",
    "workspace-Delta": "workspace --robot delta.toml --output {out}",
}


def _digests(folder: Path) -> dict[str, str]:
    return {
        str(path.relative_to(folder)) + ("/" if path.is_dir() else ""): (
            "" if path.is_dir() else hashlib.sha256(path.read_bytes()).hexdigest()
        )
        for path in sorted(folder.rglob("*"))
    }


def _handlers_installed(run: subprocess.Popen[str], timeout: float = 60.0) -> float:
    """Wait until ``run`` catches SIGINT and SIGTERM (its ``SigCgt`` in ``/proc``); the seconds waited.

    Before that moment Python's own handlers act (the known window, see the
    module's docstring): SIGTERM ends the process with nothing written, SIGINT
    with Python's KeyboardInterrupt traceback.  The wait is read from the
    kernel, not estimated from another process's start, so a machine under
    load cannot put the signal inside the window.
    """
    wanted = (1 << (signal.SIGINT - 1)) | (1 << (signal.SIGTERM - 1))
    started = time.monotonic()
    status = Path(f"/proc/{run.pid}/status")
    while time.monotonic() - started < timeout and run.poll() is None:
        try:
            fields = dict(
                line.split(":\t", 1) for line in status.read_text().splitlines() if ":\t" in line
            )
        except OSError:
            break
        if int(fields.get("SigCgt", "0"), 16) & wanted == wanted:
            break
        time.sleep(0.002)
    return time.monotonic() - started


def _cli(argv: list[str], cwd: Path, **kwargs: object) -> subprocess.Popen[str]:
    return subprocess.Popen(  # type: ignore[call-overload, no-any-return]
        [sys.executable, "-m", "prp3", *argv],
        cwd=cwd,
        env=ENV,
        text=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        **kwargs,
    )


@pytest.mark.slow
@pytest.mark.parametrize("name", list(LONG_COMMANDS))
def test_a_command_killed_at_a_random_moment_leaves_the_earlier_run_or_the_whole_new_one(
    tmp_path: Path, name: str
) -> None:
    _inputs(tmp_path)
    argv = LONG_COMMANDS[name].format(out="out").split()
    started = time.monotonic()
    first = _cli(argv, tmp_path)
    _, stderr = first.communicate(timeout=600)
    assert first.returncode == 0, stderr
    duration = time.monotonic() - started
    earlier = _digests(tmp_path / "out")
    seed = int(os.environ.get("PRP3_FAULT_SEED", random.randrange(2**32)))
    chooser = random.Random(seed)
    number = chooser.choice([signal.SIGTERM, signal.SIGINT])
    fraction = chooser.random()
    shutil.copy(EXAMPLES / "robot.toml", tmp_path / "robot.toml")  # same inputs, same outputs
    started_again = time.monotonic()
    run = _cli(argv, tmp_path)
    waited = _handlers_installed(run)
    time.sleep(fraction * max(duration - waited, 0.0))
    delay = time.monotonic() - started_again
    run.send_signal(number)
    _, stderr = run.communicate(timeout=600)
    where = f"seed {seed}: {number.name} after {delay:.3f} s of a {duration:.3f} s run"
    now = _digests(tmp_path / "out")
    assert "Traceback" not in stderr, (where, stderr)
    if run.returncode == 0:  # it finished before the signal: the whole new run
        assert set(now) == set(earlier), (where, set(now) ^ set(earlier))
    else:
        assert run.returncode in (130, 143), (where, run.returncode, stderr)
        # one line for the interruption, after the run's warnings if it printed any
        lines = [line for line in stderr.splitlines() if "warning:" not in line]
        assert len(lines) <= 1, (where, stderr)
        # the earlier run, or the whole new one when the signal came after its files were in
        # (the same inputs give the same files; only the manifest's record of the run differs)
        kept = {key: value for key, value in now.items() if not key.endswith(MANIFEST)}
        assert kept == {k: v for k, v in earlier.items() if not k.endswith(MANIFEST)}, (where, now)
        assert set(now) == set(earlier), (where, set(now) ^ set(earlier))
    assert not [key for key in now if ".prp3-sweep-" in key or key.endswith(".tmp")], (where, now)


SIGNAL_IN_A_CALLBACK = """
import ctypes, signal, sys, time
import prp3.cli.robot
from prp3.cli import main

template = prp3.cli.robot.robot_template

def in_callback() -> None:  # as numba's compiler calls llvmlite's object-cache hook
    signal.raise_signal(signal.SIGINT)
    for _ in range(1000):  # the handler runs here, inside the callback
        pass

def robot_template(*args):
    ctypes.CFUNCTYPE(None)(in_callback)()
    time.sleep(2)  # the signal is delivered again while this runs
    return template(*args)

prp3.cli.robot.robot_template = robot_template
sys.exit(main())
"""


def test_a_signal_that_a_c_callback_swallows_still_stops_the_command_with_one_line(
    tmp_path: Path,
) -> None:
    """Regression (CI, SIGINT during numba's compile): no "Exception ignored" traceback.

    A Python exception raised inside a ctypes callback cannot propagate; the
    command line delivers the signal again and ends with its one line.
    """
    run = subprocess.run(
        [sys.executable, "-c", SIGNAL_IN_A_CALLBACK, "robot", "--template"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 130, run.stderr
    assert run.stderr == "prp3 robot: interrupted\n"
    assert run.stdout == ""
