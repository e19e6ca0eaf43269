"""Faults and bad input: each test pins down one class of defect and fails without its fix.

* output failures: standard output full or closed (with ``PYTHONUNBUFFERED``
  unset), standard output failing after the files were written, a full disk
  while a file is written, bursts of SIGINT/SIGTERM;
* numbers that lose their meaning: poses far beyond the robot's size,
  parameters whose derived quantities overflow, force tables with time steps
  so small that their spline overflows;
* input files: huge CSV cells, quoted cells spanning lines, huge and deeply
  nested TOML, ``/dev/zero``;
* memory: runs that cannot fit are refused before anything is allocated.

Every refusal is one line, exit status 2 (130/143 for signals), and the files
of an earlier run are left as they were.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import prp3.cli.simulate as simulate_cli
import prp3.files as prp3_files
import prp3.staged_files as staged_files
from clitools import cli, listing, one_line
from prp3 import Motion, Robot, paper_motion
from prp3.analysis.force_histories import ActuatorForces
from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.apps.control import track
from prp3.apps.runs import check_memory
from prp3.cli import main
from prp3.engines.compiled_robot import compile_robot
from prp3.engines.entries import paper_forces
from prp3.engines.sample_entries import sample_forces
from prp3.errors import InputFileError, OutputFileError, ParameterError, TrajectoryError
from prp3.files import MAX_LINE_BYTES, atomic_writer
from prp3.io.trajectory import read_trajectory
from prp3.model.motion import differentiate_positions
from prp3.pose_validation import POSE_BOUND

ROBOT = Robot()
ENV = {key: value for key, value in os.environ.items() if key != "PYTHONUNBUFFERED"}


def prp3(*argv: str, **kwargs: object) -> subprocess.CompletedProcess[str]:
    """``python -m prp3 argv`` with PYTHONUNBUFFERED unset (stdout block-buffered)."""
    return subprocess.run(  # type: ignore[call-overload, no-any-return]
        [sys.executable, "-m", "prp3", *argv],
        stderr=subprocess.PIPE,
        text=True,
        env=ENV,
        timeout=120,
        **kwargs,
    )


# ====================================================================== output
@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_standard_output_is_one_line_with_buffered_output():
    # was: exit 120 and "Exception ignored ... OSError" (stdout flushed after main returned)
    with open("/dev/full", "w") as full:
        run = prp3("robot", "--template", stdout=full)
    assert (run.returncode, run.stderr) == (
        2,
        "prp3 robot: error: standard output: No space left on device\n",
    )


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize(
    ("argv", "program"),
    [
        (["--help"], "prp3"),
        (["--version"], "prp3"),
        (["export", "mjcf", "--help"], "prp3 export mjcf"),
    ],
)
def test_help_and_version_on_a_full_standard_output_are_one_line(argv, program):
    # was: exit 120 and "Exception ignored ... OSError" (argparse exits before main's flush)
    with open("/dev/full", "w") as full:
        run = prp3(*argv, stdout=full)
    assert (run.returncode, run.stderr) == (
        2,
        f"{program}: error: standard output: No space left on device\n",
    )


def test_a_closed_standard_output_is_one_line():
    # was: AttributeError: 'NoneType' object has no attribute 'write', with a traceback
    run = prp3("robot", "--template", stdout=subprocess.DEVNULL, preexec_fn=lambda: os.close(1))
    assert (run.returncode, run.stderr) == (2, "prp3 robot: error: standard output: closed\n")


@pytest.mark.slow  # a subprocess per command
def test_help_and_runs_on_a_closed_standard_output_are_one_line(earlier_run):
    # was: --help printed on stderr with exit 0; a run moved its files in, then failed
    run = prp3("--help", stdout=subprocess.DEVNULL, preexec_fn=lambda: os.close(1))
    assert (run.returncode, run.stderr) == (2, "prp3: error: standard output: closed\n")
    before = listing(earlier_run)
    run = prp3(
        "simulate", "--motion", "vertical", "--samples", "5", "-o", str(earlier_run),
        stdout=subprocess.DEVNULL, preexec_fn=lambda: os.close(1),
    )  # fmt: skip
    assert (run.returncode, run.stderr) == (2, "prp3 simulate: error: standard output: closed\n")
    assert listing(earlier_run) == before


class _FullStream:
    """A standard output on a full disk."""

    def write(self, text: str) -> int:
        raise OSError(28, "No space left on device")

    def flush(self) -> None:
        raise OSError(28, "No space left on device")


@pytest.mark.parametrize(
    ("program", "argv"),
    [
        ("prp3 simulate", ["simulate", "--motion", "vertical", "--samples", "5"]),
        ("prp3 forward", ["forward", "--forces", "FORCES", "--samples", "5"]),
        ("prp3 control", ["control", "--motion", "vertical", "--plant", "prp3",
                          "--controller", "pd", "--rate", "50"]),
        ("prp3 export mjcf", ["export", "mjcf"]),
    ],
)  # fmt: skip
def test_standard_output_failing_after_the_files_leaves_the_earlier_run(
    capsys, monkeypatch, earlier_run, program, argv
):
    # was: the files were moved in first, then the summary failed: results replaced, exit 2
    forces = earlier_run.parent / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C\n0,31.86,-8.50,-23.36\n0.1,31.86,-8.50,-23.36\n")
    target = earlier_run / "prp3.xml" if argv[-1] == "mjcf" else earlier_run
    before = listing(earlier_run)
    monkeypatch.setattr(sys, "stdout", _FullStream())
    argv = [str(forces) if a == "FORCES" else a for a in argv]
    status = main([*argv, "-o", str(target)])
    err = capsys.readouterr().err
    assert status == 2
    assert one_line(err) == f"{program}: error: standard output: No space left on device"
    assert listing(earlier_run) == before


def test_a_full_disk_names_the_file_being_written(capsys, monkeypatch, earlier_run):
    # was: "standard output: No space left on device" while results.csv was being written
    before = listing(earlier_run)

    def full_disk(path: object, table: object, **kwargs: object) -> None:
        raise OSError(28, "No space left on device")  # what a write on a full disk raises

    monkeypatch.setattr(simulate_cli, "write_table_csv", full_disk)
    status, out, err = cli(
        capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", earlier_run
    )
    assert (status, out) == (2, "")
    assert one_line(err) == (
        f"prp3 simulate: error: {earlier_run / 'results.csv'}: cannot write "
        "(No space left on device)"
    )
    assert listing(earlier_run) == before


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_atomic_writer_on_a_full_disk_names_the_file(tmp_path, monkeypatch):
    def onto_a_full_disk(_path: object, *args: object, **kwargs: object) -> object:
        return open("/dev/full", *args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr(prp3_files, "open", onto_a_full_disk, raising=False)
    target = tmp_path / "model.xml"
    with pytest.raises(OutputFileError) as info:
        with atomic_writer(target) as stream:
            stream.write("x" * 100_000)
    assert info.value.file == str(target)
    assert str(info.value) == f"{target}: cannot write (No space left on device)"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("burst", "status", "word"),
    [
        ((signal.SIGINT, signal.SIGINT, signal.SIGTERM), 130, "interrupted"),
        ((signal.SIGTERM, signal.SIGTERM, signal.SIGINT), 143, "terminated"),
    ],
)
def test_a_burst_of_signals_is_one_line_and_keeps_the_earlier_run(
    capsys, monkeypatch, earlier_run, burst, status, word
):
    # was: the second signal interrupted the clean-up: a traceback, a staging folder left
    before = listing(earlier_run)
    written = simulate_cli.write_table_csv
    real_rmtree = staged_files.shutil.rmtree

    def write_then_signal(path: object, table: object, **kwargs: object) -> None:
        written(path, table, **kwargs)  # type: ignore[arg-type]
        os.kill(os.getpid(), burst[0])

    def rmtree_under_fire(path: object, **kwargs: object) -> None:
        for number in burst[1:]:
            os.kill(os.getpid(), number)  # more signals while the staging folder goes
        real_rmtree(path, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(simulate_cli, "write_table_csv", write_then_signal)
    monkeypatch.setattr(staged_files.shutil, "rmtree", rmtree_under_fire)
    previous = {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}
    result = cli(capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", earlier_run)
    assert result == (status, "", f"prp3 simulate: {word}\n")
    assert {number: signal.getsignal(number) for number in previous} == previous
    assert listing(earlier_run) == before


# ====================================================================== numbers
FAR = 1e3  # m: more than POSE_BOUND robot sizes (l0 = 0.3 m) from the centre


@pytest.mark.parametrize("far", [FAR, 1e6, 1e60, 1e300])
@pytest.mark.parametrize("method", ["fast", "paper", "newton-euler"])
def test_poses_far_beyond_the_robot_are_refused_by_every_method(method, far):
    # was: accepted; the forces were round-off noise and the methods disagreed (even in sign);
    # at 1e60 m Newton-Euler raised LinAlgError
    motion = Motion(
        t=[0.0, 1.0],
        pose=[[0.0, 0.0, 0.0], [0.0, -far, 0.0]],
        velocity=np.zeros((2, 3)),
        acceleration=np.zeros((2, 3)),
    )
    with pytest.raises(TrajectoryError, match=r"too far from the centre") as info:
        inverse_dynamics(ROBOT, motion, method)
    assert info.value.sample == 1 and info.value.pose == (0.0, -far, 0.0)
    assert f"{POSE_BOUND:g}*l0 = 30 m" in str(info.value)


def test_fast_paths_refuse_far_poses_too():
    compiled = compile_robot(ROBOT)
    with pytest.raises(TrajectoryError, match="too far from the centre"):
        paper_forces(
            compiled, [[0.0, 0.0, 0.0], [0.0, 1e60, 0.0]], np.zeros((2, 3)), np.zeros((2, 3))
        )
    with pytest.raises(TrajectoryError, match="too far from the centre"):
        sample_forces(compiled, [1e300, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])


def test_a_pose_at_the_bound_is_still_computed_and_the_methods_agree():
    reach = POSE_BOUND * ROBOT.l0
    motion = Motion.at_rest([reach, -reach, 0.2])
    forces = [inverse_dynamics(ROBOT, motion, m)[1].f10 for m in ("fast", "paper", "newton-euler")]
    scale = np.abs(forces[0]).max()
    assert np.abs(forces[1] - forces[0]).max() <= 1e-11 * scale
    assert np.abs(forces[2] - forces[0]).max() <= 1e-11 * scale


def test_far_trajectory_rows_are_refused_naming_file_and_line(tmp_path, capsys, earlier_run):
    before = listing(earlier_run)
    traj = tmp_path / "far.csv"
    traj.write_text("t,x,y,phi\n0,0,0,0\n0.5,0,0,0\n1,0,1e6,0\n")
    status, _, err = cli(capsys, "simulate", "--trajectory", traj, "-o", earlier_run)
    line = one_line(err)
    assert status == 2
    assert line.startswith(f"prp3 simulate: error: {traj}:4: sample 2, t = 1 s: pose too far")
    assert listing(earlier_run) == before


@pytest.mark.parametrize("text", ["l0 = 1e200\n", "l0 = 1e150\n[link]\nmass = 1e10\n"])
def test_derived_parameters_that_overflow_are_refused(tmp_path, capsys, text):
    # was: OverflowError in every command, or inf inertias in the MJCF
    (tmp_path / "big.toml").write_text(text)
    forces = tmp_path / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C\n0,0,0,0\n1,0,0,0\n")
    out = ["-o", tmp_path / "out", "--robot"]
    for argv in (
        ["robot", "--check"],
        ["export", "mjcf", "--robot"],
        ["export", "c", *out],
        ["simulate", "--motion", "vertical", *out],
        ["workspace", *out],
        ["forward", "--forces", forces, *out],
        ["control", "--motion", "vertical", "--plant", "prp3", "--controller", "pd", *out],
        ["excite", *out],
        ["identify", "--measurements", forces, *out],
    ):
        status, out, err = cli(capsys, *argv, tmp_path / "big.toml")
        assert (status, out) == (2, "")
        line = one_line(err)
        assert f"{tmp_path / 'big.toml'}:1: robot: l0 = " in line and "overflow float64" in line
    assert not (tmp_path / "out").exists()
    with pytest.raises(ParameterError, match="overflow float64") as info:
        Robot(l0=1e200)
    assert info.value.key == "l0"


def test_force_tables_with_tiny_time_steps_are_refused(tmp_path, capsys):
    # was: the spline's coefficients overflowed and the forces were NaN (not in the file)
    t = [0.0, 1e-300, 2e-300, 3e-300]
    f10 = [[1.0, 2.0, 3.0], [1.0, 2.0, 3.5], [1.0, 2.0, 4.0], [2.0, 2.0, 3.0]]
    with pytest.raises(TrajectoryError, match="cannot be interpolated"):
        ActuatorForces(t=t, f10=f10)
    table = tmp_path / "tiny.csv"
    table.write_text(
        "t,f10_A,f10_B,f10_C\n"
        + "".join(f"{a!r},{b},{c},{d}\n" for a, (b, c, d) in zip(t, f10, strict=True))
    )
    status, _, err = cli(capsys, "forward", "--forces", table, "-o", tmp_path / "out")
    assert status == 2
    assert one_line(err).startswith(
        f"prp3 forward: error: {table}:2: forces: sample 0, t = 0 s: the force samples cannot "
        "be interpolated"  # the interval's first sample, by its line
    )
    assert not (tmp_path / "out").exists()


def test_derivatives_of_positions_that_overflow_are_refused():
    # was: differentiate_positions returned inf and nan for time steps of 1e-300 s
    t = np.array([0.0, 1e-300, 2e-300, 3e-300])
    pose = np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.02, 0.0, 0.0]])
    with pytest.raises(TrajectoryError, match="the results overflow") as info:
        differentiate_positions(t, pose)
    assert info.value.sample == 0 and info.value.subject == "pose"


def test_a_plant_driven_into_the_singularity_stops_with_a_status():
    # was: numpy.linalg.LinAlgError from the plant's mass matrix, with a traceback
    result = track(ROBOT, paper_motion("vertical", 3), controller="pd", plant="prp3")
    assert result.status == "singular"
    assert "the plant reached the singularity" in result.message


# ====================================================================== input files
def test_a_huge_csv_cell_is_refused_naming_file_and_line(tmp_path):
    # was: _csv.Error "field larger than field limit (131072)" with a traceback
    path = tmp_path / "big.csv"
    path.write_text("t,x,y,phi\n0,0,0,0\n1,0," + "1" * 200_000 + ",0\n")
    with pytest.raises(InputFileError) as info:
        read_trajectory(path)
    assert (info.value.file, info.value.line) == (str(path), 3)
    assert f"longer than {MAX_LINE_BYTES} bytes" in str(info.value)


def test_a_quoted_cell_spanning_lines_keeps_the_line_numbers(tmp_path):
    # was: the records were counted, not the lines: the error named line 4 for line 5
    path = tmp_path / "quoted.csv"
    path.write_text('t,x,y,phi\n0,0,0,0\n0.5,"0\n",0,0\n1,0,zero,0\n')
    with pytest.raises(InputFileError) as info:
        read_trajectory(path)
    assert str(info.value) == f"{path}:5: column 'y': not a number: 'zero'"
    assert info.value.key == "y"
    path.write_text('t,x,y,phi\n0,0,0,0\n0.5,"0' + "\n" * 3 + '",0\n')
    with pytest.raises(InputFileError) as info:
        read_trajectory(path)
    assert info.value.line == 3  # the record starts on line 3


def test_an_unterminated_quoted_cell_is_one_error_not_a_traceback(tmp_path):
    path = tmp_path / "open.csv"
    path.write_text('t,x,y,phi\n0,0,0,0\n1,"' + ("0" * 60_000 + "\n") * 4)
    with pytest.raises(InputFileError, match="malformed CSV") as info:
        read_trajectory(path)
    assert info.value.line == 3


@pytest.mark.parametrize(
    ("text", "fragment", "line"),
    [
        ("# big\nl0 = 1" + "0" * 5000 + "\n", "a number with more than 4300 digits", 2),
        ("gravity = " + "[" * 5000 + "]" * 5000 + "\n", "nested too deeply", None),
    ],
)
def test_absurd_toml_is_one_error_naming_the_file(tmp_path, capsys, text, fragment, line):
    # was: ValueError (4300-digit limit) and RecursionError with tracebacks
    path = tmp_path / "robot.toml"
    path.write_text(text)
    with pytest.raises(InputFileError) as info:
        Robot.from_toml(path)
    assert fragment in str(info.value)
    assert (info.value.file, info.value.line) == (str(path), line)
    status, _, err = cli(capsys, "robot", "--check", path)
    assert status == 2 and fragment in one_line(err)


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--trajectory", "/dev/zero"],
        ["simulate", "--motion", "vertical", "--robot", "/dev/zero"],
        ["forward", "--forces", "/dev/zero"],
        ["identify", "--measurements", "/dev/zero"],
        ["control", "--trajectory", "/dev/zero", "--plant", "prp3", "--controller", "pd"],
        ["workspace", "--robot", "/dev/zero"],
        ["sweep", "--spec", "/dev/zero"],
    ],
)
def test_dev_zero_is_refused_at_once_naming_it(tmp_path, capsys, argv):
    # was: read until memory ran out, then reported without its name
    status, _, err = cli(capsys, *argv, "-o", tmp_path / "out")
    assert status == 2
    line = one_line(err)
    assert "/dev/zero:1: " in line and "NUL bytes" in line
    assert not (tmp_path / "out").exists()


def test_input_larger_than_the_limit_is_refused(tmp_path, monkeypatch):
    path = tmp_path / "long.csv"
    path.write_text("t,x,y,phi\n" + "".join(f"{k},0,0,0\n" for k in range(100)))
    monkeypatch.setattr(prp3_files, "MAX_INPUT_BYTES", 200)
    with pytest.raises(InputFileError, match="larger than 200 bytes"):
        read_trajectory(path)


# ====================================================================== memory
@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--motion", "vertical", "--samples", "1000000000"],
        ["forward", "--forces", "FORCES", "--samples", "1000000000"],
        ["workspace", "--points", "100000"],
    ],
)
def test_runs_too_big_for_the_memory_are_refused_before_allocating(
    tmp_path, capsys, monkeypatch, argv
):
    # was: killed by the kernel (forward), or MemoryError after minutes
    monkeypatch.setattr("prp3.apps.runs.available_memory", lambda: 16 * 1024**3)
    forces = tmp_path / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C\n0,0,0,0\n1,0,0,0\n")
    argv = [str(forces) if a == "FORCES" else a for a in argv]
    status, _, err = cli(capsys, *argv, "-o", tmp_path / "out")
    assert status == 2
    line = one_line(err)
    assert "of memory, 16 GiB are available" in line and "the run needs about " in line
    assert not (tmp_path / "out").exists()


def test_check_memory_says_how_much():
    check_memory("small", 1e3, available=10**6)
    with pytest.raises(Exception, match=r"needs about 9\.31 GiB of memory, 1 GiB are available"):
        check_memory("--samples 10", 1e10, available=1024**3)


def test_fast_paths_refuse_infinite_powers_as_inverse_dynamics_does():
    # p10 = f10·λ̇10 overflows for an absurd speed: refused by every path, never returned as inf
    velocity = np.array([5e307, 0.0, 0.0])
    motion = Motion(t=0.0, pose=ZERO3, velocity=velocity, acceleration=ZERO3)
    with pytest.raises(TrajectoryError, match="the results overflow"):
        inverse_dynamics(ROBOT, motion)
    with pytest.raises(TrajectoryError, match="the results overflow"):
        paper_forces(ROBOT, ZERO3, velocity, ZERO3)
    with pytest.raises(TrajectoryError, match="the results overflow"):
        sample_forces(compile_robot(ROBOT), ZERO3, velocity, ZERO3)


ZERO3 = np.zeros(3)
