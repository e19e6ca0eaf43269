"""Bad input gets a clear error, and nothing is lost: the defects found by a robustness sweep.

Each test pins down one defect that a sweep of bad inputs found (command line,
input files, output paths, interrupted runs and the Python API), so that it
stays fixed: a one-line message naming the file/line/column, key, argument or
value, exit status 2 from the command line (no traceback), a ``Prp3Error``
from the library, no output file created or half written, and the files of an
earlier run untouched.

The last group covers the core modules (``model``, ``motion``, ``geometry``,
``kinematics``, ``dynamics``).
"""

from __future__ import annotations

import math
import os
import re
import signal
import stat
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import prp3.cli.simulate as simulate_cli
import prp3.io.tables as prp3_tables
import prp3.staged_files as staged_files
from clitools import cli, listing
from prp3 import Motion, Robot
from prp3.analysis.equations_of_motion import platform_dynamics
from prp3.analysis.force_histories import ActuatorForces
from prp3.analysis.forward import MIN_RTOL, forward_dynamics
from prp3.analysis.forward_kinematics import forward_velocity
from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.analysis.reachability import jacobian_condition, reachable
from prp3.analysis.workspace import orientation_scan, workspace_slice
from prp3.apps.mjcf import mjcf_model
from prp3.cli import build_parser
from prp3.engines.compiled_robot import compile_robot
from prp3.engines.entries import paper_forces
from prp3.errors import (
    InputFileError,
    OutputFileError,
    ParameterError,
    Prp3Error,
    TrajectoryError,
)
from prp3.files import atomic_writer, check_output_directory
from prp3.io.trajectory import read_trajectory
from prp3.mechanics.geometry import forward_geometry, inverse_geometry
from prp3.model.motion import law_motion, paper_motion
from prp3.staged_files import staged_output

ROBOT = Robot()
ZERO = np.zeros(3)
SINGULAR_PHI = math.pi / 3.0  # sin(phi - pi/3) = 0: every leg singular (docs/model.md)


def program(argv: list[str]) -> str:
    """The prefix of prp3's messages for ``argv``: the command that was run."""
    return "prp3 " + ("export mjcf" if argv[0] == "export" else argv[0])


def error_line(status: int, err: str) -> str:
    """Assert exit 2 and exactly one error line (after any warnings); return it."""
    assert status == 2, err
    assert "Traceback" not in err
    lines = [line for line in err.strip().splitlines() if ": warning: " not in line]
    assert len(lines) == 1, err
    return lines[0]


def write_trajectory(path: Path, rows: list[list[float]], derivatives: bool = False) -> Path:
    header = "t,x,y,phi" + (",dx,dy,dphi,ddx,ddy,ddphi" if derivatives else "")
    path.write_text(header + "\n" + "".join(",".join(repr(v) for v in row) + "\n" for row in rows))
    return path


# ====================================================================== command line
def test_negative_numbers_in_scientific_notation_are_option_values(tmp_path, capsys):
    # argparse's own pattern (^-\d+$|^-\d*\.\d+$) took "-1e-3" for an option
    args = build_parser().parse_args(
        ["forward", "--forces", "f.csv", "--initial-pose", "-1e-3", "0", "-2E+1", "-o", "out"]
    )
    assert args.initial_pose == [-0.001, 0.0, -20.0]
    status, out, err = cli(
        capsys,
        "workspace",
        "--phi",
        "-1e-1",
        "--points",
        "3",
        "--orientations",
        "3",
        "-o",
        tmp_path / "ws",
    )
    assert status == 0, err
    assert "phi = -0.1 rad" in out
    # "-inf" reaches the value check and its message, not "expected one argument"
    status, _, err = cli(capsys, "workspace", "--phi", "-inf", "-o", tmp_path / "never")
    assert "argument --phi: expected a finite number, got '-inf'" in error_line(status, err)
    assert not (tmp_path / "never").exists()


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (
            ["simulate", "--motion", "vertical", "--samples", "99999999999999999999"],
            "--samples: expected an integer from 2 to 1000000000",
        ),
        (
            ["forward", "--forces", "f.csv", "--samples", "100000000000"],
            "--samples: expected an integer from 2 to 1000000000",
        ),
        (["workspace", "--points", "1000000"], "--points: expected an integer from 2 to 100000"),
        (["simulate", "--motion", "vertical", "--samples", "-5"], "--samples"),
        (  # was: scipy's UserWarning and a silently larger rtol, or "rtol must be ..."
            ["forward", "--forces", "f.csv", "--rtol", "1e-300"],
            f"--rtol: expected a number >= {MIN_RTOL:.3g}, got '1e-300'",
        ),
    ],
)
def test_absurd_option_values_are_usage_errors(tmp_path, capsys, monkeypatch, argv, fragment):
    # was: numpy's "Maximum allowed size exceeded" / MemoryError with a traceback
    monkeypatch.chdir(tmp_path)
    status, _, err = cli(capsys, *argv, "-o", "out")
    assert fragment in error_line(status, err)
    assert list(tmp_path.iterdir()) == []


def test_out_of_memory_is_one_line(tmp_path, capsys, monkeypatch):
    def no_memory(name: str, samples: int) -> Motion:
        raise MemoryError("Unable to allocate 7.28 TiB for an array")

    monkeypatch.setattr(simulate_cli, "paper_motion", no_memory)
    status, _, err = cli(capsys, "simulate", "--motion", "vertical", "-o", tmp_path / "out")
    assert "not enough memory (Unable to allocate 7.28 TiB" in error_line(status, err)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--motion", "vertical", "--output", ""],
        ["simulate", "--robot", "", "--motion", "vertical", "--output", "out"],
        ["export", "mjcf", "--output", ""],
    ],
)
def test_an_empty_path_is_refused_not_taken_for_the_current_directory(
    tmp_path, capsys, monkeypatch, argv
):
    monkeypatch.chdir(tmp_path)
    status, _, err = cli(capsys, *argv)
    assert "expected a path, got an empty string" in error_line(status, err)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--motion", "vertical", "--samples", "5", "-o"],
        ["workspace", "--points", "3", "--orientations", "3", "-o"],
        ["export", "mjcf", "-o"],
    ],
)
def test_a_name_too_long_for_the_file_system_is_one_line(tmp_path, capsys, argv):
    # was: OSError [Errno 36] with a traceback (Path.exists / Path.is_dir)
    name = tmp_path / ("x" * 300)
    status, _, err = cli(capsys, *argv, name)
    line = error_line(status, err)
    assert line.startswith(f"{program(argv)}: error: {name}") and "File name too long" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize(
    "argv", [["robot", "--template"], ["export", "mjcf"], ["simulate", "--motion", "vertical"]]
)
def test_standard_output_on_a_full_disk_is_one_line(tmp_path, argv):
    # was: OSError [Errno 28] with a traceback, exit status 1
    if argv[0] == "simulate":
        argv = [*argv, "--samples", "5", "-o", str(tmp_path / "out")]
    with open("/dev/full", "w") as full:
        run = subprocess.run(
            [sys.executable, "-m", "prp3", *argv], stdout=full, stderr=subprocess.PIPE, text=True
        )
    assert run.returncode == 2
    assert run.stderr == f"{program(argv)}: error: standard output: No space left on device\n"


def test_sigterm_while_writing_cleans_up_like_ctrl_c(tmp_path, capsys, monkeypatch, earlier_run):
    # was: killed outright, leaving DIR/.prp3-*.tmp/results.csv half written
    before = listing(earlier_run)
    written = prp3_tables.write_table_csv

    def write_then_terminate(path, table, **kwargs):
        written(path, table, **kwargs)
        os.kill(os.getpid(), signal.SIGTERM)  # the handler raises at the next bytecode

    class UnhandledSigtermError(Exception):
        pass

    def fallback(signum: int, frame: object) -> None:  # keeps pytest alive if main has none
        raise UnhandledSigtermError("prp3 did not handle SIGTERM")

    monkeypatch.setattr(simulate_cli, "write_table_csv", write_then_terminate)
    previous = signal.signal(signal.SIGTERM, fallback)
    try:
        for folder in (earlier_run, tmp_path / "new" / "out"):
            status, out, err = cli(
                capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", folder
            )
            assert (status, out, err) == (143, "", "prp3 simulate: terminated\n")
            assert signal.getsignal(signal.SIGTERM) is fallback  # main restores the handler
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert listing(earlier_run) == before  # no staging folder left, older files unchanged
    assert not (tmp_path / "new").exists()  # folders the run created are removed again


@pytest.mark.filterwarnings("always::RuntimeWarning")
def test_warnings_of_the_libraries_are_one_line(capsys, monkeypatch):
    # was: Python's two-line format with the source line, e.g. a numpy RuntimeWarning
    import prp3.cli.robot as robot_cli

    template = robot_cli.robot_template

    def noisy(*args: object, **kwargs: object) -> str:
        warnings.warn("overflow encountered in multiply", RuntimeWarning, stacklevel=1)
        return template()

    monkeypatch.setattr(robot_cli, "robot_template", noisy)
    status, out, err = cli(capsys, "robot", "--template")
    assert status == 0 and out == template()
    assert re.fullmatch(
        r"prp3 robot: warning: overflow encountered in multiply\n",  # no internal file.py:line
        err,
    )


def test_results_that_overflow_are_refused_and_nothing_is_written(tmp_path, capsys, earlier_run):
    # was: RuntimeWarnings on stderr, exit 0, and NaN in results.csv
    before = listing(earlier_run)
    # (the samples are independent states: their rates need not explain the steps)
    rows = [
        [k * 1e-210, k * 1e-10, k * 1e-10, k * 1e-10, 1e200, 1e200, 1e200, 0.0, 0.0, 0.0]
        for k in range(3)
    ]
    traj = write_trajectory(tmp_path / "fast.csv", rows, derivatives=True)
    status, _, err = cli(capsys, "simulate", "--trajectory", traj, "-o", earlier_run)
    line = error_line(status, err)
    # (1e200)^2 overflows already at the first sample, line 2 of the file
    assert line.startswith(
        f"prp3 simulate: error: {traj}:2: sample 0, t = 0 s: the results overflow"
    )
    (tmp_path / "heavy.toml").write_text("[platform]\nmass = 1e308\n")
    status, _, err = cli(
        capsys,
        "simulate",
        "--robot",
        tmp_path / "heavy.toml",
        "--motion",
        "vertical",
        "--samples",
        "5",
        "-o",
        earlier_run,
    )
    # a platform of 1e308 kg weighs more than float64 holds: refused with the robot file
    line = error_line(status, err)
    assert line.startswith(f"prp3 simulate: error: {tmp_path / 'heavy.toml'}: robot: l0 = 0.3 m ")
    assert "overflow float64" in line
    assert listing(earlier_run) == before


def test_derivatives_that_overflow_name_the_file_and_line(tmp_path):
    # was: "motion: velocity[0, 0] is not finite (nan)" (no file, a column the user never gave)
    rows = [[0.0, 0.0, 0.0, 0.0], [0.1, 1e308, 0.0, 0.0], [0.2, -1e308, 0.0, 0.0]]
    traj = write_trajectory(tmp_path / "huge.csv", rows)
    with pytest.raises(TrajectoryError) as info:
        read_trajectory(traj)
    message = str(info.value)
    assert message.startswith(f"{traj}:")
    assert "computed from the positions is not finite" in message
    assert "give the derivative columns" in message


@pytest.mark.parametrize(("cell", "shown"), [("1_0", "'1_0'"), ("\u0661", "'\u0661'")])
def test_csv_numbers_are_ascii_without_underscores(tmp_path, cell, shown):
    # Python's float() reads '1_0' as 10 and '١' (Arabic-Indic one) as 1
    path = tmp_path / "t.csv"
    path.write_text(f"t,x,y,phi\n0,0,0,0\n1,0,{cell},0\n", encoding="utf-8")
    with pytest.raises(InputFileError, match=rf"t\.csv:3: column 'y': not a number: {shown}"):
        read_trajectory(path)


def test_workspace_window_too_narrow_for_the_grid_names_the_options(tmp_path, capsys):
    # was: "x grid values must be strictly increasing" (no option, no value)
    status, _, err = cli(
        capsys,
        "workspace",
        "--extent",
        "0",
        "5e-324",
        "0",
        "5e-324",
        "--points",
        "3",
        "-o",
        tmp_path / "ws",
    )
    line = error_line(status, err)
    assert "--extent 0.0 5e-324 0.0 5e-324 is too narrow in x for --points 3" in line
    assert not (tmp_path / "ws").exists()


# ---------------------------------------------------------------- prp3 forward
@pytest.fixture
def force_table(tmp_path: Path) -> Path:
    path = tmp_path / "forces.csv"
    path.write_text("t,f10_A,f10_B,f10_C\n0,0,0,0\n1,0,0,0\n")
    return path


def test_forward_errors_name_where_the_initial_pose_comes_from(
    tmp_path, capsys, force_table, earlier_run
):
    # was: "pose: singular pose at sample 0 ..." without the option or the file
    before = listing(earlier_run)
    status, _, err = cli(
        capsys,
        "forward",
        "--forces",
        force_table,
        "--initial-pose",
        "0",
        "0",
        repr(SINGULAR_PHI),
        "-o",
        earlier_run,
    )
    line = error_line(status, err)
    assert line.startswith(
        f"prp3 forward: error: --initial-pose 0.0 0.0 {SINGULAR_PHI!r}: singular pose"
    )

    results = tmp_path / "results.csv"
    assert cli(capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", tmp_path)[0] == 0
    lines = results.read_text().splitlines()
    header = lines[0].split(",")
    first = lines[1].split(",")
    first[header.index("phi")] = repr(SINGULAR_PHI)
    bad = tmp_path / "bad_results.csv"
    bad.write_text("\n".join([lines[0], ",".join(first), *lines[2:]]) + "\n")
    status, _, err = cli(capsys, "forward", "--forces", bad, "-o", earlier_run)
    line = error_line(status, err)
    assert line.startswith(
        f"prp3 forward: error: {bad}: initial pose from the first row: singular pose"
    )

    (tmp_path / "weak.toml").write_text("[limits]\nmax_force = 10.0\n")
    status, _, err = cli(
        capsys,
        "forward",
        "--robot",
        tmp_path / "weak.toml",
        "--forces",
        results,
        "-o",
        earlier_run,
    )
    line = error_line(status, err)  # |f10_A| = 31.96 N at t = 0 (the static load, > 10 N)
    prefix = f"prp3 forward: error: {results}:2: forces: sample 0, t = 0 s, leg A: |f10_A| = "
    assert line.startswith(prefix), line  # the row's line and time
    assert "exceeds limits.max_force = 10.0 N" in line
    assert listing(earlier_run) == before


def test_forward_forces_too_large_to_interpolate(tmp_path, capsys, earlier_run):
    # was: scipy's ValueError "`dydx` must contain only finite values." with a traceback
    before = listing(earlier_run)
    huge = tmp_path / "huge.csv"
    huge.write_text("t,f10_A,f10_B,f10_C\n0,1e308,1e308,1e308\n1,-1e308,1e308,1e308\n")
    status, _, err = cli(capsys, "forward", "--forces", huge, "-o", earlier_run)
    line = error_line(status, err)
    assert line.startswith(
        f"prp3 forward: error: {huge}:2: forces: sample 0, t = 0 s: the force samples cannot "
        "be interpolated"
    )
    assert "between t[0] = 0.0 and t[1] = 1.0 s" in line
    assert listing(earlier_run) == before
    with pytest.raises(TrajectoryError, match="cannot be interpolated"):
        ActuatorForces(t=[0.0, 5e-324], f10=[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])


def test_a_run_never_replaces_its_own_input_file(tmp_path, capsys):
    # was: `prp3 forward --forces out/results.csv -o out` replaced the forces it read
    out = tmp_path / "out"
    assert cli(capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", out)[0] == 0
    before = listing(out)
    status, _, err = cli(capsys, "forward", "--forces", out / "results.csv", "-o", out)
    line = error_line(status, err)
    assert line == (
        f"prp3 forward: error: {out}/results.csv: the output would replace this input file; "
        "choose another output directory"
    )
    rows = [[t, 0.0, 0.01 * t, 0.0] for t in (0.0, 0.5, 1.0)]
    write_trajectory(out / "results.csv", rows)
    before = listing(out)
    status, _, err = cli(
        capsys, "simulate", "--trajectory", out / "results.csv", "-o", tmp_path / "." / "out"
    )
    assert "the output would replace this input file" in error_line(status, err)
    assert listing(out) == before


# ---------------------------------------------------------------- prp3 export
def test_export_refuses_to_replace_a_special_file(tmp_path, capsys):
    # was: the rename replaced the target, whatever it was (a FIFO, /dev/full as root)
    fifo = tmp_path / "model.xml"
    os.mkfifo(fifo)
    status, _, err = cli(capsys, "export", "mjcf", "-o", fifo)
    assert "model.xml: cannot write: it exists and is not a regular file" in error_line(status, err)
    assert stat.S_ISFIFO(fifo.lstat().st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.xml"]


def test_export_has_the_short_output_option(tmp_path, capsys):
    status, out, _ = cli(capsys, "export", "mjcf", "-o", tmp_path / "m.xml")
    assert status == 0 and out.endswith(f"files written:\n  {tmp_path / 'm.xml'}\n")
    assert (tmp_path / "m.xml").read_text().startswith('<mujoco model="prp3">')


@pytest.mark.parametrize(
    ("robot", "fragment"),
    [(None, "robot must be a prp3.Robot, got NoneType"), (Robot(l0=1e-9), "l0 = 1e-09 m")],
)
def test_mjcf_model_refuses_what_mujoco_cannot_load(robot, fragment):
    # was: AttributeError for None; XML that MuJoCo refuses ("fromto points too close")
    with pytest.raises(ParameterError, match=re.escape(fragment)):
        mjcf_model(robot)


# ====================================================================== output files
def test_atomic_writer_refuses_a_directory_or_a_pipe(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    for target, kind in ((tmp_path, "a directory"), (fifo, "not a regular file")):
        with pytest.raises(OutputFileError, match=f"it exists and is {kind}"):
            with atomic_writer(target) as stream:
                stream.write("x")
    assert stat.S_ISFIFO(fifo.lstat().st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe"]


def test_check_output_directory_name_too_long(tmp_path):
    with pytest.raises(OutputFileError, match="cannot create output directory"):
        check_output_directory(tmp_path / ("y" * 300) / "out")


def test_staged_output_checks_every_target_before_moving_any(tmp_path):
    # was: a.txt replaced, then IsADirectoryError on b.txt: half of the run in place
    (tmp_path / "a.txt").write_text("old a")
    (tmp_path / "b.txt").mkdir()
    with pytest.raises(OutputFileError, match=r"b\.txt: cannot write: it exists and is a dir"):
        with staged_output(tmp_path) as staged:
            staged.path("a.txt").write_text("new a")
            staged.path("b.txt").write_text("new b")
    assert (tmp_path / "a.txt").read_text() == "old a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt"]


@pytest.mark.parametrize("failure", [OSError(28, "No space left on device"), KeyboardInterrupt()])
def test_staged_output_puts_older_files_back_when_a_move_fails(tmp_path, monkeypatch, failure):
    (tmp_path / "a.txt").write_text("old a")
    (tmp_path / "c.txt").write_text("old c")
    replace = os.replace
    moves: list[str] = []

    def flaky_replace(source, target):
        moves.append(Path(target).name)
        if len(moves) == 3 and Path(target).parent == tmp_path:  # the third file moved in
            raise failure
        replace(source, target)

    monkeypatch.setattr(staged_files.os, "replace", flaky_replace)
    with pytest.raises(OutputFileError if isinstance(failure, OSError) else KeyboardInterrupt):
        with staged_output(tmp_path) as staged:
            for name in ("a.txt", "b.txt", "c.txt"):
                staged.path(name).write_text(f"new {name[0]}")
    monkeypatch.undo()
    # a.txt restored, b.txt (new, no predecessor) removed, c.txt never replaced, no staging left
    assert listing(tmp_path) == {"a.txt": b"old a", "c.txt": b"old c"}


# ====================================================================== Python API
@pytest.mark.parametrize(
    ("call", "error"),
    [
        (lambda: forward_geometry(ROBOT, np.array([0.0, 0.0, 0.01j])), TrajectoryError),
        (lambda: forward_velocity(ROBOT, ZERO, np.array([0.0, 1j, 0.0])), TrajectoryError),
        (lambda: platform_dynamics(ROBOT, ZERO + 0j, ZERO), TrajectoryError),
        (lambda: ActuatorForces(t=[0.0, 1.0], f10=np.zeros((2, 3)) + 1j), TrajectoryError),
        (lambda: forward_geometry(ROBOT, ["0", "0", "0.1"]), TrajectoryError),
        (lambda: reachable(ROBOT, np.array([0.0, 0.0, 1j])), TrajectoryError),
        (lambda: jacobian_condition(ROBOT, ["0", "0", "0"]), TrajectoryError),
        (lambda: workspace_slice(ROBOT, 0.1, np.array([0.0, 1j]), [0.0, 1.0]), ParameterError),
        (lambda: workspace_slice(ROBOT, 0.1, "ab", [0.0, 1.0]), ParameterError),
        (
            lambda: orientation_scan(ROBOT, [0.0, 1.0], [0.0, 1.0], np.array([0.0, 1j])),
            ParameterError,
        ),
        (lambda: paper_forces(compile_robot(ROBOT), ZERO + 1j, ZERO, ZERO), TrajectoryError),
    ],
)
def test_complex_numbers_and_text_are_refused_not_cast(call, error):
    # was: numpy's ComplexWarning and the imaginary part dropped, or text parsed as numbers
    with pytest.raises(error, match=r"real numbers|array of numbers"):
        call()


def test_inputs_of_any_real_dtype_and_layout_give_float64_results():
    # the central configuration: lambda10 = 0 <=> pose = 0 (docs/model.md), whatever the input type
    lam = np.zeros((6, 3))
    frozen = np.zeros((2, 3))
    frozen.flags.writeable = False
    for value in ([0, 0, 0], np.zeros(3, np.float32), np.zeros(3, np.int64), lam[::2], frozen):
        solution = forward_geometry(ROBOT, value)
        assert solution.pose.dtype == np.float64
        assert np.abs(solution.pose).max() < 1e-15
    # a float32 state gives the float64 result of the same (exactly representable) values
    pose32 = np.array([0.0, 0.0625, 0.125], np.float32)
    rates32 = np.array([0.5, -0.25, 0.125], np.float32)
    reference = forward_velocity(ROBOT, pose32.astype(np.float64), rates32.astype(np.float64))
    result = forward_velocity(ROBOT, pose32, rates32)
    assert result.dtype == np.float64 and np.array_equal(result, reference)
    forces = paper_forces(compile_robot(ROBOT), pose32, rates32, np.zeros(3, np.int32))
    assert forces.f10.dtype == np.float64 and forces.f10.shape == (3,)
    assert jacobian_condition(ROBOT, pose32).dtype == np.float64


def test_forward_dynamics_tolerances():
    free = Robot(gravity=(0.0, 0.0))
    still = ActuatorForces(t=[0.0, 1.0], f10=np.zeros((2, 3)))
    # a numpy float32 tolerance is a number: accepted (was refused)
    result = forward_dynamics(free, still, [0.0, 1.0], ZERO, ZERO, rtol=np.float32(1e-8))
    assert result.status == "completed"
    with pytest.raises(ParameterError, match="rtol must be a number, got True"):
        forward_dynamics(free, still, [0.0, 1.0], ZERO, ZERO, rtol=True)
    # was: scipy's UserWarning "rtol is too small", then a silently larger rtol
    with pytest.raises(ParameterError, match=f"rtol must be at least {MIN_RTOL:.3g}"):
        forward_dynamics(free, still, [0.0, 1.0], ZERO, ZERO, rtol=1e-300)


def test_forward_dynamics_force_function_that_turns_non_finite():
    # was: NaN accelerations, "divide by zero" RuntimeWarnings and a silent "failed" status
    def push(t: float) -> np.ndarray:
        return np.zeros(3) if t in (0.0, 1.0) else np.full(3, np.nan)

    with pytest.raises(ParameterError, match=r"forces: f10\(.*\) must be 3 finite forces"):
        forward_dynamics(Robot(gravity=(0.0, 0.0)), push, [0.0, 1.0], ZERO, ZERO)


def test_forward_dynamics_from_an_absurd_speed_warns_nothing():
    # was: overflow RuntimeWarnings from inside scipy's step-size selection
    # and with nothing integrated it is an error, not a one-sample result (issue 21)
    still = ActuatorForces(t=[0.0, 1.0], f10=np.zeros((2, 3)))
    with pytest.raises(TrajectoryError, match="fails at its first step"):
        forward_dynamics(ROBOT, still, [0.0, 1.0], ZERO, [1e300, 0.0, 0.0])


# ====================================================================== core modules


def test_core_huge_integer_parameter_is_a_parameter_error(tmp_path, capsys):
    with pytest.raises(ParameterError, match="l0"):
        Robot(l0=10**400)
    (tmp_path / "r.toml").write_text("l0 = 1" + "0" * 400 + "\n")
    status, _, err = cli(capsys, "robot", "--check", tmp_path / "r.toml")
    assert "r.toml:1: robot: l0" in error_line(status, err)


@pytest.mark.parametrize(
    "call",
    [
        lambda: inverse_geometry(ROBOT, np.array([0.0, 0.0, 0.1j])),  # a list is refused
        lambda: Motion(
            t=[0.0, 1.0],
            pose=np.zeros((2, 3)) + 1j,
            velocity=np.zeros((2, 3)),
            acceleration=np.zeros((2, 3)),
        ),
        lambda: Motion(
            t=np.array([0.0, 1.0]) + 1j,
            pose=np.zeros((2, 3)),
            velocity=np.zeros((2, 3)),
            acceleration=np.zeros((2, 3)),
        ),
    ],
)
def test_core_complex_inputs_are_refused(call):
    with pytest.raises(TrajectoryError):
        call()


@pytest.mark.parametrize(
    "call",
    [
        lambda: inverse_geometry(ROBOT, ["0", "0", "0.1"]),
        lambda: Motion(
            t=["0", "1"],
            pose=np.zeros((2, 3)),
            velocity=np.zeros((2, 3)),
            acceleration=np.zeros((2, 3)),
        ),
    ],
)
def test_core_text_inputs_are_refused(call):
    with pytest.raises(TrajectoryError):
        call()


@pytest.mark.parametrize(
    "call",
    [
        lambda: Motion(
            t=np.zeros(0),
            pose=np.zeros((0, 3)),
            velocity=np.zeros((0, 3)),
            acceleration=np.zeros((0, 3)),
        ),
        lambda: inverse_geometry(ROBOT, np.zeros((0, 3))),
    ],
)
def test_core_zero_samples_are_refused(call):
    with pytest.raises(TrajectoryError):
        call()


@pytest.mark.parametrize(("robot", "speed"), [(ROBOT, 1e200), (ROBOT, 1e160)])
def test_core_results_that_overflow_raise(robot, speed):
    motion = Motion(
        t=[0.0, 1.0],
        pose=np.zeros((2, 3)),
        velocity=np.full((2, 3), speed),
        acceleration=np.zeros((2, 3)),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the fix should not need them
        with pytest.raises(Prp3Error, match="sample 0"):
            inverse_dynamics(robot, motion)


@pytest.mark.parametrize(
    "call",
    [
        lambda: inverse_geometry(None, ZERO),  # type: ignore[arg-type]
        lambda: inverse_dynamics(ROBOT, np.zeros((5, 3))),  # type: ignore[arg-type]
        lambda: Robot(gravity={1.0, 2.0}),  # type: ignore[arg-type]
        lambda: paper_motion(["vertical"]),  # type: ignore[arg-type]
        lambda: law_motion([0.0, 0.01, 0.0], samples=10**20),
    ],
)
def test_core_wrong_argument_types_are_prp3_errors(call):
    with pytest.raises(Prp3Error):
        call()


def test_core_law_motion_duration_types():
    assert law_motion([0.0, 0.01, 0.0], 3, np.float32(3.0)).t[-1] == 3.0
    with pytest.raises(TrajectoryError, match="duration"):
        law_motion([0.0, 0.01, 0.0], 3, True)
