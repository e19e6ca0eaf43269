"""Tests of prp3.io.tables, prp3.io.trajectory and prp3.files: CSV, atomic and staged files, TRAJ.csv.

Expected values are written out or derived beside each test (exact polynomials,
the paper's law of motion differentiated by hand), never taken from prp3.
"""

from __future__ import annotations

import math
import os
import stat
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import prp3.io.tables as prp3_tables
from prp3.errors import InputFileError, OutputFileError, TrajectoryError
from prp3.files import atomic_path, atomic_writer, check_output_directory
from prp3.io.results import result_columns
from prp3.io.tables import read_table_csv, write_table_csv
from prp3.io.trajectory import DERIVATIVE_COLUMNS, POSITION_COLUMNS, read_trajectory
from prp3.model.motion import differentiate_positions
from prp3.staged_files import MANIFEST_NAME, staged_output
from strategies import analytic_motions

finite = st.floats(allow_nan=False, allow_infinity=False)


def write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


def listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


# ---------------------------------------------------------------- writing
@given(st.lists(st.tuples(finite, finite), min_size=1, max_size=20))
def test_write_table_csv_round_trips_every_float_exactly(tmp_path_factory, rows):
    path = tmp_path_factory.mktemp("csv") / "table.csv"
    a = np.array([r[0] for r in rows])
    b = np.array([r[1] for r in rows])
    write_table_csv(path, {"t": a, "value": b})
    lines = path.read_text().splitlines()
    assert lines[0] == "t,value"
    back = np.array([[float(cell) for cell in line.split(",")] for line in lines[1:]])
    # bit-for-bit: repr is the shortest text that reads back to the same float
    assert back[:, 0].tobytes() == a.tobytes()
    assert back[:, 1].tobytes() == b.tobytes()


@pytest.mark.parametrize("arrow", [False, True], ids=["python", "pyarrow"])
def test_write_table_csv_streams_in_blocks_and_reports_progress(tmp_path, monkeypatch, arrow):
    if arrow:
        pytest.importorskip("pyarrow")
        block = prp3_tables.ARROW_ROWS_PER_BLOCK
    else:
        monkeypatch.setattr(prp3_tables, "_pyarrow", lambda: None)
        block = prp3_tables.ROWS_PER_BLOCK
    rows = 2 * block + 5_000  # more than two blocks
    t = np.arange(rows) * 0.5
    reports: list[tuple[int, int]] = []
    write_table_csv(tmp_path / "big.csv", {"t": t}, progress=lambda d, n: reports.append((d, n)))
    lines = (tmp_path / "big.csv").read_text().splitlines()
    assert len(lines) == rows + 1
    assert float(lines[1]) == 0.0 and float(lines[-1]) == (rows - 1) * 0.5
    if not arrow:  # Python's writer: repr itself
        assert lines[1] == "0.0" and lines[-1] == repr((rows - 1) * 0.5)
    assert reports == [(block, rows), (2 * block, rows), (rows, rows)]


def test_written_files_get_the_umask_permissions_not_mkstemps_0600(tmp_path):
    old = os.umask(0o022)
    try:
        write_table_csv(tmp_path / "a.csv", {"t": np.zeros(2)})
        with atomic_path(tmp_path / "b.bin") as temporary:
            temporary.write_bytes(b"x")
    finally:
        os.umask(old)
    for name in ("a.csv", "b.bin"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o644


def test_atomic_writer_and_atomic_path_leave_nothing_on_failure(tmp_path):
    target = write(tmp_path / "keep.txt", "old")
    with pytest.raises(RuntimeError), atomic_writer(target) as stream:
        stream.write("half")
        raise RuntimeError("boom")
    with pytest.raises(RuntimeError), atomic_path(target) as temporary:
        temporary.write_text("half")
        assert temporary.suffix == ".txt"  # writers that infer the format from it work
        raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert listing(tmp_path) == ["keep.txt"]


def test_atomic_path_in_a_missing_directory_is_a_one_line_error(tmp_path):
    with pytest.raises(OutputFileError, match=r"nowhere/x\.png: cannot write"):
        with atomic_path(tmp_path / "nowhere" / "x.png"):
            pass


# ---------------------------------------------------------------- strict reading
@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", r"empty table file"),
        ("t,x\n", r"no data rows"),
        ("t,x,z\n0,1,2\n", r"t\.csv:1: unknown column 'z'"),
        ("t\n0\n", r"t\.csv:1: missing column\(s\) x"),
        ("t,x,x\n0,1,2\n", r"t\.csv:1: duplicate column 'x'"),
        ("t,x\n0,1\n1\n", r"t\.csv:3: expected 2 values, got 1"),
        ("t,x\n0,1\n\n1,abc\n", r"t\.csv:4: column 'x': not a number: 'abc'"),
        ("t,x\n0,nan\n", r"t\.csv:2: column 'x': not a finite number: 'nan'"),
        ("t,x\n0,-inf\n", r"t\.csv:2: column 'x': not a finite number: '-inf'"),
    ],
)
def test_read_table_csv_names_file_line_and_column(tmp_path, text, message):
    path = write(tmp_path / "t.csv", text)
    with pytest.raises(InputFileError, match=message):
        read_table_csv(path, required=("t", "x"), optional=("y",))


def test_read_table_csv_any_column_order_and_blank_lines(tmp_path):
    path = write(tmp_path / "t.csv", "\n x , t\n\n2.5,0\n3.5,1\n")
    table = read_table_csv(path, required=("t", "x"))
    assert table["t"].tolist() == [0.0, 1.0]
    assert table["x"].tolist() == [2.5, 3.5]


def test_read_table_csv_missing_file(tmp_path):
    with pytest.raises(InputFileError, match=r"absent\.csv: cannot read table file"):
        read_table_csv(tmp_path / "absent.csv", required=("t",))


# ---------------------------------------------------------------- trajectories
W = math.pi / 3.0


def paper_law(t: np.ndarray, star: tuple[float, float, float]):
    """Eq. (4) and its derivatives by hand: q = q*(1 − cos wt), q̇ = q* w sin wt, q̈ = q* w² cos wt."""
    s = np.asarray(star)
    c, n = np.cos(W * t)[:, None], np.sin(W * t)[:, None]
    return s * (1.0 - c), s * W * n, s * W * W * c


def trajectory_text(columns: list[str], data: dict[str, np.ndarray]) -> str:
    rows = [",".join(repr(float(data[c][k])) for c in columns) for k in range(len(data["t"]))]
    return ",".join(columns) + "\n" + "\n".join(rows) + "\n"


def law_columns(t: np.ndarray, star=(0.01, 0.025, 0.2)) -> dict[str, np.ndarray]:
    pose, velocity, acceleration = paper_law(t, star)
    data = {"t": t}
    for j, name in enumerate(("x", "y", "phi")):
        data[name] = pose[:, j]
        data[DERIVATIVE_COLUMNS[j]] = velocity[:, j]
        data[DERIVATIVE_COLUMNS[3 + j]] = acceleration[:, j]
    return data


def test_trajectory_with_derivatives_is_read_as_given_in_any_column_order(tmp_path):
    t = np.linspace(0.0, 3.0, 7)
    data = law_columns(t)
    columns = ["ddphi", "phi", "t", "dx", "y", "ddx", "x", "dy", "ddy", "dphi"]
    trajectory = read_trajectory(write(tmp_path / "traj.csv", trajectory_text(columns, data)))
    pose, velocity, acceleration = paper_law(t, (0.01, 0.025, 0.2))
    assert trajectory.note is None
    assert trajectory.motion.t.tolist() == t.tolist()
    assert trajectory.motion.pose.tobytes() == pose.tobytes()
    # as given, but the round-off rates at rest (t = 3 s: sin(π)·q*·π/3) are zero
    assert abs(velocity[-1]).max() < 1e-16 and trajectory.motion.velocity[-1].tolist() == [0, 0, 0]
    assert trajectory.motion.velocity[:-1].tobytes() == velocity[:-1].tobytes()
    assert trajectory.motion.acceleration.tobytes() == acceleration.tobytes()
    assert trajectory.lines.tolist() == [2, 3, 4, 5, 6, 7, 8]


def test_positions_only_derivatives_match_the_analytic_law_to_1e_5(tmp_path):
    t = np.arange(3001) * 1e-3  # every millisecond over the paper's 3 s
    data = law_columns(t)
    text = trajectory_text(list(POSITION_COLUMNS), data)
    trajectory = read_trajectory(write(tmp_path / "traj.csv", text))
    assert trajectory.note is not None and "degree-5 interpolating spline" in trajectory.note
    _, velocity, acceleration = paper_law(t, (0.01, 0.025, 0.2))
    inner = slice(30, -30)  # away from the ends (30 ms)
    for got, want in (
        (trajectory.motion.velocity, velocity),
        (trajectory.motion.acceleration, acceleration),
    ):
        scale = np.abs(want).max(axis=0)
        error = np.abs(got[inner] - want[inner]).max(axis=0) / scale
        assert (error <= 1e-5).all(), error
        # a quintic spline does much better than the requirement (docs/model.md: ~1e-9)
        assert (error <= 1e-7).all(), error


@given(analytic_motions(l0=0.3))
def test_spline_derivatives_of_random_smooth_motions_within_1e_5(motion):
    t = np.arange(0.0, motion.duration, 1e-3)
    pose, velocity, acceleration = motion.evaluate(t)
    got_v, got_a, degree = differentiate_positions(t, pose)
    assert degree == 5
    inner = slice(20, -20)
    for got, want in ((got_v, velocity), (got_a, acceleration)):
        # relative to the largest derivative; below 1e-3 (m/s, rad/s²…) an absolute 1e-8,
        # the round-off of differentiating 1e-3-spaced samples twice
        scale = np.maximum(np.abs(want).max(axis=0), 1e-3)
        assert (np.abs(got[inner] - want[inner]).max(axis=0) <= 1e-5 * scale).all()


def test_spline_is_exact_for_polynomials_of_its_degree():
    # degree 5 with 9 samples: q = t^5 − 2t^3 + t, q̇ = 5t^4 − 6t^2 + 1, q̈ = 20t^3 − 12t
    t = np.linspace(-1.0, 2.0, 9)
    q = t**5 - 2 * t**3 + t
    pose = np.stack([q, 2 * q, np.zeros_like(t)], axis=-1)
    velocity, acceleration, degree = differentiate_positions(t, pose)
    assert degree == 5
    np.testing.assert_allclose(velocity[:, 0], 5 * t**4 - 6 * t**2 + 1, atol=1e-9)
    np.testing.assert_allclose(acceleration[:, 1], 2 * (20 * t**3 - 12 * t), atol=1e-8)
    # 4 samples: cubic, exact for q = t^3 (q̇ = 3t², q̈ = 6t)
    t4 = np.array([0.0, 0.5, 1.5, 2.0])
    pose4 = np.stack([t4**3, t4, t4], axis=-1)
    v4, a4, degree4 = differentiate_positions(t4, pose4)
    assert degree4 == 3
    np.testing.assert_allclose(v4[:, 0], 3 * t4**2, atol=1e-12)
    np.testing.assert_allclose(a4[:, 0], 6 * t4, atol=1e-12)
    # 2 samples: a straight line, zero acceleration
    v2, a2, degree2 = differentiate_positions(
        np.array([0.0, 2.0]), np.array([[0, 1, 2], [4, 1, 0]], float)
    )
    assert degree2 == 1
    assert v2.tolist() == [[2.0, 0.0, -1.0]] * 2
    assert a2.tolist() == [[0.0, 0.0, 0.0]] * 2


@pytest.mark.parametrize(
    ("text", "error", "message"),
    [
        ("t,x,y\n0,0,0\n1,0,0\n", InputFileError, r"traj\.csv:1: missing column\(s\) phi"),
        ("t,x,y,phy\n0,0,0,0\n", InputFileError, r"traj\.csv:1: unknown column 'phy'"),
        ("t,x,y,phi,z\n0,0,0,0,0\n", InputFileError, r"traj\.csv:1: unknown column 'z'"),
        (
            "t,x,y,phi,dx,dy,dphi\n0,0,0,0,0,0,0\n1,0,0,0,0,0,0\n",
            InputFileError,
            r"traj\.csv:1: give all of the derivative columns .* missing ddx, ddy, ddphi",
        ),
        (
            "t,x,y,phi\n0,0,0,0\n0.1,0,zero,0\n",
            InputFileError,
            r"traj\.csv:3: column 'y': not a number: 'zero'",
        ),
        (
            "t,x,y,phi\n0,0,0,0\n0.1,NaN,0,0\n",
            InputFileError,
            r"traj\.csv:3: column 'x': not a finite number",
        ),
        (
            "t,x,y,phi\n0,0,0,0\n",
            TrajectoryError,
            r"traj\.csv:2: a trajectory needs at least 2 samples, got 1",
        ),
        (
            "t,x,y,phi\n0,0,0,0\n0.2,0,0,0\n\n0.2,0,0,0\n",
            TrajectoryError,
            r"traj\.csv:5: time must increase: t = 0\.2 follows t = 0\.2 on line 3",
        ),
        ("t,x,y,phi\n1,0,0,0\n0.5,0,0,0\n", TrajectoryError, r"traj\.csv:3: time must increase"),
    ],
)
def test_bad_trajectory_files_are_refused_with_file_and_line(tmp_path, text, error, message):
    with pytest.raises(error, match=message):
        read_trajectory(write(tmp_path / "traj.csv", text))


# ---------------------------------------------------------------- output folders
def test_staged_output_moves_every_file_in_together(tmp_path):
    out = tmp_path / "a" / "b"
    with staged_output(out) as staged:
        staged.path("one.txt").write_text("1")
        staged.path("two.txt").write_text("2")
        assert listing(out) != ["one.txt", "two.txt"]  # not there before the end
    assert listing(out) == [MANIFEST_NAME, "one.txt", "two.txt"]
    assert staged.written == [out / "one.txt", out / "two.txt"]


def test_staged_output_failure_leaves_no_file_and_removes_created_folders(tmp_path):
    out = tmp_path / "new" / "run"
    with pytest.raises(RuntimeError), staged_output(out) as staged:
        staged.path("results.csv").write_text("complete")
        raise RuntimeError("figure failed")
    assert listing(tmp_path) == []


def test_staged_output_failure_keeps_older_files_unchanged(tmp_path):
    write(tmp_path / "results.csv", "old run")
    with pytest.raises(RuntimeError), staged_output(tmp_path) as staged:
        staged.path("results.csv").write_text("new run")
        raise RuntimeError("boom")
    assert listing(tmp_path) == ["results.csv"]
    assert (tmp_path / "results.csv").read_text() == "old run"


def test_staged_output_refuses_repeated_or_nested_names(tmp_path):
    with staged_output(tmp_path) as staged:
        staged.path("a.txt")
        with pytest.raises(ValueError, match="repeated"):
            staged.path("a.txt")
        with pytest.raises(ValueError, match="plain name"):
            staged.path("sub/b.txt")


def test_output_directory_under_a_file_is_refused(tmp_path):
    blocker = write(tmp_path / "file.txt", "")
    with pytest.raises(OutputFileError, match=r"file\.txt/out: cannot create output directory"):
        check_output_directory(blocker / "out")
    with pytest.raises(OutputFileError, match=r"file\.txt/out: cannot write output directory"):
        with staged_output(blocker / "out"):
            pass
    check_output_directory(tmp_path / "missing" / "deeper")  # creatable: no error


# ---------------------------------------------------------------- line ends, numpy's reader
@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"], ids=["lf", "crlf", "cr"])
def test_every_line_end_is_read_with_its_line_numbers(tmp_path, end):
    # was: a file with CR-only line ends (old Mac) was refused as one long line
    rows = ["t,x,y,phi", "0,0,0,0", "", "0.5,0.001,0.002,0.01", "1,0.002,0.004,0.02"]
    path = tmp_path / "traj.csv"
    path.write_bytes(end.join(rows).encode() + end.encode())
    trajectory = read_trajectory(path)
    assert trajectory.motion.t.tolist() == [0.0, 0.5, 1.0]
    assert trajectory.motion.pose[:, 1].tolist() == [0.0, 0.002, 0.004]
    assert trajectory.lines.tolist() == [2, 4, 5]
    bad = tmp_path / "bad.csv"
    bad.write_bytes(end.join([*rows, "1.5,zero,0,0"]).encode())
    with pytest.raises(InputFileError, match=r"bad\.csv:6: column 'x': not a number: 'zero'"):
        read_trajectory(bad)


def test_mixed_line_ends_and_a_cr_only_file_on_the_command_line(tmp_path, capsys):
    from clitools import cli

    path = tmp_path / "mac.csv"
    rows = "".join(f"{k / 10!r},0,{k / 1000!r},0\r" for k in range(7))
    path.write_bytes(("t,x,y,phi\r" + rows).encode())
    status, out, err = cli(capsys, "simulate", "--trajectory", path, "-o", tmp_path / "o")
    assert status == 0 and "files written:" in out, err
    table = read_table_csv(
        tmp_path / "o" / "results.csv", required=("t", "y"), optional=result_columns(False)
    )
    assert table["y"].tolist() == [k / 1000 for k in range(7)]
    mixed = write(tmp_path / "mixed.csv", "t,x\r\n0,1\r2,3\n4,5\r\n")
    assert read_table_csv(mixed, required=("t", "x"))["x"].tolist() == [1.0, 3.0, 5.0]


@pytest.mark.parametrize(
    ("cell", "message"),
    [
        ("1_0", "not a number: '1_0'"),  # float() takes it, numpy.loadtxt does not
        ("0x10", "not a number: '0x10'"),
        ("\u0661", "not a number: '\u0661'"),  # an Arabic-Indic digit
        ("1,5", "expected 2 values, got 3"),
        ("", "not a number: ''"),
        ("1e400", "not a finite number: '1e400'"),
        ("inf", "not a finite number: 'inf'"),
    ],
)
def test_cells_numpy_refuses_are_named_with_line_and_column(tmp_path, monkeypatch, cell, message):
    # the bad cell deep in a later block: the bisection finds its line
    monkeypatch.setattr(prp3_tables, "_READ_BLOCK", 16)
    rows = [f"{k},{k / 7!r}" for k in range(40)]
    rows[37] = f"37,{cell}"
    path = write(tmp_path / "t.csv", "t,x\n" + "\n".join(rows) + "\n")
    with pytest.raises(InputFileError, match=rf"t\.csv:39: (column 'x': )?{message}$"):
        read_table_csv(path, required=("t", "x"))


def test_quoted_numbers_spaces_and_empty_rows_are_read(tmp_path):
    path = write(tmp_path / "t.csv", '"t","x"\n"0", 1.5 \n,\n\n 2 ,"-0.25"\n,,\n')
    table = read_table_csv(path, required=("t", "x"))
    assert list(table) == ["t", "x"]
    assert table["t"].tolist() == [0.0, 2.0] and table["x"].tolist() == [1.5, -0.25]


@pytest.mark.parametrize("arrow", [False, True], ids=["python", "pyarrow"])
@given(rows=st.lists(st.tuples(finite, finite), min_size=1, max_size=40))
def test_written_tables_read_back_bit_for_bit(tmp_path_factory, arrow, rows):
    path = tmp_path_factory.mktemp("csv") / "table.csv"
    a = np.array([r[0] for r in rows])
    b = np.array([r[1] for r in rows])
    with pytest.MonkeyPatch.context() as patch:
        if not arrow:
            patch.setattr(prp3_tables, "_pyarrow", lambda: None)
        write_table_csv(path, {"t": a, "x": b})
    table = read_table_csv(path, required=("t", "x"))
    assert table["t"].tobytes() == a.tobytes() and table["x"].tobytes() == b.tobytes()
