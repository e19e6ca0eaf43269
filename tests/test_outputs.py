"""Output folders and result files: the manifest, CSV text byte for byte, Parquet.

* A run keeps a manifest of the files it wrote (``DIR/.prp3-manifest.json``),
  one record per command with the prp3 version, the command line and the
  SHA-256 of its input files; the next run of the same command into the
  folder removes those it does not write again (and says so on stderr), and
  nothing else: never a file of another command, nor one the user added,
  changed or replaced.
* The CSV text of every float is the shortest decimal that reads back to it,
  whichever writer makes it (Arrow's CSV writer, or Python's ``repr``): the
  same decimal number as ``repr``, held against ``repr`` cell by cell (and
  byte for byte for Python's writer).
* ``--format parquet`` writes the same columns as float64.
"""

from __future__ import annotations

import csv
import json
import math
import os
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import prp3
import prp3.cli.simulate as simulate_cli
import prp3.io.tables as prp3_tables
from clitools import cli
from prp3.errors import OutputFileError
from prp3.io.results import RESULT_COLUMNS
from prp3.io.tables import format_floats, write_table_csv
from prp3.staged_files import MANIFEST_NAME, staged_output

PAPER_FIGURES = ["fig3_p10.png", "fig4_f21y.png", "fig5_f21z.png", "f10.png", "lambda10.png"]


def names(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


# ---------------------------------------------------------------- the manifest
def test_a_new_run_removes_its_own_stale_files_and_nothing_else(tmp_path, capsys):
    # was: the vertical run's Figs. 3-5 stayed beside a later rotation run's results
    out = tmp_path / "out"
    status, _, _ = cli(capsys, "simulate", "--motion", "vertical", "--samples", "7",
                       "-o", out, "--plots")  # fmt: skip
    assert status == 0
    assert names(out) == sorted([MANIFEST_NAME, "results.csv", *PAPER_FIGURES])
    (out / "notes.txt").write_text("mine")  # the user's own file
    (out / "f10.png").write_bytes(b"edited by the user")  # changed since prp3 wrote it
    status, report, err = cli(
        capsys, "simulate", "--motion", "rotation", "--samples", "7", "-o", out
    )
    assert status == 0
    assert err == (
        "prp3 simulate: note: removed 4 files that the last `prp3 simulate` wrote into "
        f"{out} and this run did not write again (fig3_p10.png, fig4_f21y.png, fig5_f21z.png, "
        "lambda10.png); files of other commands are kept\n"
    )
    assert names(out) == [MANIFEST_NAME, "f10.png", "notes.txt", "results.csv"]
    assert (out / "notes.txt").read_text() == "mine"
    assert (out / "f10.png").read_bytes() == b"edited by the user"
    removed = report.split("files removed", 1)[1].split("files kept", 1)[0].splitlines()[1:]
    assert sorted(removed) == sorted(
        f"  {out / name}" for name in PAPER_FIGURES if name != "f10.png"
    )
    assert (
        "files kept (the last run of this command wrote them, but they have changed since):"
        f"\n  {out / 'f10.png'}" in report
    )
    manifest = json.loads((out / MANIFEST_NAME).read_text())
    (record,) = manifest["commands"].values()
    assert list(record["files"]) == ["results.csv"]
    assert record["files"]["results.csv"]["size"] == (out / "results.csv").stat().st_size


def test_a_file_of_the_same_name_rewritten_is_not_removed_twice(tmp_path, capsys):
    out = tmp_path / "out"
    for samples in (5, 9):
        assert (
            cli(capsys, "simulate", "--motion", "vertical", "--samples", samples, "-o", out)[0] == 0
        )
    status, report, _ = cli(capsys, "simulate", "--motion", "vertical", "-o", out)
    assert status == 0 and "files removed" not in report
    assert names(out) == [MANIFEST_NAME, "results.csv"]


def test_parquet_after_csv_removes_the_csv(tmp_path, capsys):
    pytest.importorskip("pyarrow")
    out = tmp_path / "out"
    assert cli(capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", out)[0] == 0
    status, report, _ = cli(capsys, "simulate", "--motion", "vertical", "--samples", "5",
                            "-o", out, "--format", "parquet")  # fmt: skip
    assert status == 0
    assert names(out) == [MANIFEST_NAME, "results.parquet"]
    assert (
        f"files removed (the last run of this command wrote them, {MANIFEST_NAME}; not written "
        f"again):\n  {out / 'results.csv'}" in report
    )


def test_a_failed_run_removes_nothing(tmp_path, capsys):
    out = tmp_path / "out"
    assert (
        cli(capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", out, "--plots")[0]
        == 0
    )
    before = {name: (out / name).read_bytes() for name in names(out)}
    traj = tmp_path / "singular.csv"
    traj.write_text("t,x,y,phi\n0,0,0,0\n0.1,0,0,0.5\n0.2,0,0,1.0471975511965976\n")
    status, _, _ = cli(capsys, "simulate", "--trajectory", traj, "-o", out)
    assert status == 2
    assert {name: (out / name).read_bytes() for name in names(out)} == before


def test_a_manifest_never_removes_anything_outside_its_folder_or_not_a_regular_file(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    outside = tmp_path / "precious.txt"
    outside.write_text("keep")
    (out / "sub").mkdir()
    (out / "sub" / "inner.txt").write_text("keep")
    (out / "link.txt").symlink_to(outside)
    stamp = {"size": 4, "mtime_ns": outside.stat().st_mtime_ns}
    forged: dict[str, object] = {
        "files": {
            "../precious.txt": stamp,
            str(outside): stamp,
            "sub/inner.txt": {
                "size": 4,
                "mtime_ns": (out / "sub" / "inner.txt").stat().st_mtime_ns,
            },
            "sub": {"size": 0, "mtime_ns": 0},
            "link.txt": stamp,
            "..": stamp,
            MANIFEST_NAME: stamp,
        }
    }
    forged = {"commands": {"library": forged}}  # the runs of staged_output without a command
    (out / MANIFEST_NAME).write_text(json.dumps(forged))
    with staged_output(out) as staged:
        staged.path("new.txt").write_text("new")
    assert staged.removed == []
    assert outside.read_text() == "keep" and (out / "sub" / "inner.txt").read_text() == "keep"
    assert (out / "link.txt").is_symlink()
    assert names(out) == [MANIFEST_NAME, "link.txt", "new.txt", "sub"]


@pytest.mark.parametrize(
    "text", ["", "not json", "[1, 2]", '{"files": [1]}', '{"files": {"a.txt": {"size": "4"}}}',
             '{"files": {"a.txt": {"size": true, "mtime_ns": 1}}}', "[" * 100_000,
             '{"commands": [1]}', '{"commands": {"library": {"files": {"a.txt": 1}}}}',
             '{"commands": {"library": {"files": {"a.txt": {"size": true, "mtime_ns": 1}}}}}',
             '{"files": {"a.txt": {"size": 4, "mtime_ns": %d}}}']  # a manifest of older prp3
)  # fmt: skip
def test_a_malformed_manifest_counts_as_nothing_written(tmp_path, text):
    (tmp_path / "a.txt").write_text("user")
    if "%d" in text:
        text = text % (tmp_path / "a.txt").stat().st_mtime_ns
    (tmp_path / MANIFEST_NAME).write_text(text)
    with staged_output(tmp_path) as staged:
        staged.path("b.txt").write_text("b")
    assert staged.removed == [] and (tmp_path / "a.txt").read_text() == "user"
    manifest = json.loads((tmp_path / MANIFEST_NAME).read_text())
    assert manifest["commands"]["library"]["files"].keys() == {"b.txt"}


def _sha256(path: Path) -> str:
    import hashlib

    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.slow  # six commands into one folder
def test_commands_sharing_a_folder_keep_each_others_files(tmp_path, capsys):
    # was: simulate, then workspace, then export c into one folder: each run deleted the
    # files of the one before (one manifest for the folder, whatever the command)
    out = tmp_path / "out"
    simulate = ("simulate", "--motion", "vertical", "--samples", "5", "-o", out, "--plots")
    assert cli(capsys, *simulate)[0] == 0
    assert cli(capsys, "workspace", "--points", "11", "--orientations", "5", "-o", out)[0] == 0
    status, report, err = cli(capsys, "export", "c", "-o", out)
    assert (status, err) == (0, "") and "files removed" not in report
    expected = sorted([MANIFEST_NAME, "results.csv", *PAPER_FIGURES,
                       "workspace.csv", "orientations.csv", "workspace.png",
                       "prp3_inverse_dynamics.c", "prp3_inverse_dynamics.h"])  # fmt: skip
    assert names(out) == expected
    records = json.loads((out / MANIFEST_NAME).read_text())["commands"]
    assert sorted(records) == ["export c", "simulate", "workspace"]
    assert sorted(records["workspace"]["files"]) == ["orientations.csv", "workspace.csv",
                                                     "workspace.png"]  # fmt: skip
    # simulate again, without --plots: only its own figures go, and stderr says so
    status, _, err = cli(capsys, *simulate[:-1])
    assert status == 0 and err.startswith("prp3 simulate: note: removed 5 files that the last "
                                          "`prp3 simulate` wrote")  # fmt: skip
    assert names(out) == sorted(set(expected) - set(PAPER_FIGURES))
    # a file of the same name written by another command leaves the first one's record
    (tmp_path / "forces.csv").write_bytes((out / "results.csv").read_bytes())
    # (5 samples of forces: the platform drifts to the singularity, exit 1, files written)
    assert cli(capsys, "forward", "--forces", tmp_path / "forces.csv", "-o", out)[0] in (0, 1)
    records = json.loads((out / MANIFEST_NAME).read_text())["commands"]
    assert "simulate" not in records  # its one file, results.csv, is forward's now
    assert "results.csv" in records["forward"]["files"]


def test_the_manifest_says_how_the_folder_was_made(tmp_path, capsys, monkeypatch):
    robot = tmp_path / "robot.toml"
    robot.write_text("[platform]\nmass = 3.5\n")
    traj = tmp_path / "traj.csv"
    traj.write_text("t,x,y,phi\n0,0,0,0\n0.5,0.01,0,0.1\n1,0.02,0,0.2\n1.5,0.03,0,0.3\n")
    out = tmp_path / "out"
    monkeypatch.chdir(tmp_path)
    argv = ["simulate", "--robot", "robot.toml", "--trajectory", str(traj), "-o", "out"]
    assert cli(capsys, *argv)[0] == 0
    record = json.loads((out / MANIFEST_NAME).read_text())["commands"]["simulate"]
    assert record["prp3"] == prp3.__version__
    assert record["command_line"] == ["prp3", *argv]
    assert record["working_directory"] == str(tmp_path)
    assert record["inputs"] == [
        {"path": "robot.toml", "size": robot.stat().st_size, "sha256": _sha256(robot)},
        {"path": str(traj), "size": traj.stat().st_size, "sha256": _sha256(traj)},
    ]
    assert record["finished"].endswith("Z") and record["finished"][:2] == "20"


# ---------------------------------------------------------------- CSV text
SPECIAL = [
    0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 2.225073858507201e-308,
    1.7976931348623157e308, 1e300, 1e-300, 1e16, 9999999999999998.0, 1e15, 1.5e15,
    123456789012345.6, 1e-4, 9.999999999999999e-05, 1e-5, -1e-5, 1.2e-5, 1e-7, 1.5e-8,
    1e-9, 9.99999999999e-10, 1e-10, 3.0, -7.0, 2.0**53, 2.0**60, 1e22, 0.1, 1 / 3,
    math.nan, math.inf, -math.inf, 1234.5, 100.0, 1e-6, 0.5e-4,
]  # fmt: skip


def assert_shortest_round_trip(texts: list[str], values: np.ndarray) -> None:
    """Each text reads back to its float bit for bit and is the decimal number repr gives
    (the shortest digits that read back, the closest to the float among them)."""
    assert len(texts) == len(values)
    back = np.array([float(text) for text in texts])
    assert back.tobytes() == values.tobytes() or np.array_equal(back, values, equal_nan=True)
    numbers = ~np.isnan(values)  # (a NaN's text carries no sign: repr(-nan) is 'nan')
    assert np.array_equal(np.signbit(back[numbers]), np.signbit(values[numbers]))
    for text, value in zip(texts, values.tolist(), strict=True):
        if math.isfinite(value):
            assert Decimal(text) == Decimal(repr(value)), (text, repr(value))
        else:
            assert text == repr(value)


@pytest.mark.parametrize("arrow", [False, True], ids=["python", "pyarrow"])
def test_format_floats_is_the_shortest_round_trip_for_special_and_random_doubles(
    monkeypatch, arrow
):
    if arrow:
        pytest.importorskip("pyarrow")
    else:
        monkeypatch.setattr(prp3_tables, "_pyarrow", lambda: None)
    rng = np.random.default_rng(20261201)
    bits = rng.integers(0, 2**64, 200_000, dtype=np.uint64).view(np.float64)  # every exponent
    scaled = rng.standard_normal(200_000) * 10.0 ** rng.integers(-12, 20, 200_000)
    for values in (np.array(SPECIAL), bits, scaled, np.zeros(3), -np.zeros(3), np.arange(5.0)):
        texts = format_floats(values)
        assert_shortest_round_trip(texts, values)
        if not arrow:  # without pyarrow the texts are repr itself
            assert texts == [repr(v) for v in values.tolist()]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True),
        min_size=1,
        max_size=200,
    )
)
def test_format_floats_is_the_shortest_round_trip_for_any_floats(values):
    assert_shortest_round_trip(format_floats(np.array(values)), np.array(values, dtype=np.float64))


def _random_table(rows: int) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(7)
    table = {
        "t": np.arange(rows) * 1e-3,
        "small": rng.standard_normal(rows) * 1e-6,
        "big": rng.standard_normal(rows) * 1e17,
        "bits": rng.integers(0, 2**64, rows, dtype=np.uint64).view(np.float64),
        "zero": np.zeros(rows),
    }
    table["bits"][~np.isfinite(table["bits"])] = 1.5  # the tables prp3 writes are finite
    table["zero"][1::3] = -0.0
    return table


@pytest.mark.parametrize("arrow", [False, True], ids=["python", "pyarrow"])
def test_write_table_csv_writes_the_shortest_round_trip_texts(tmp_path, monkeypatch, arrow):
    if arrow:
        pytest.importorskip("pyarrow")
    else:
        monkeypatch.setattr(prp3_tables, "_pyarrow", lambda: None)
    monkeypatch.setattr(prp3_tables, "ARROW_ROWS_PER_BLOCK", 1000)  # three blocks, the last short
    table = _random_table(2017)
    write_table_csv(tmp_path / "a.csv", table)
    text = (tmp_path / "a.csv").read_bytes().decode("ascii")
    lines = text.split("\n")
    assert lines[0] == ",".join(table) and lines[-1] == "" and len(lines) == 2017 + 2
    rows = [line.split(",") for line in lines[1:-1]]  # no quotes, one cell per column
    for c, column in enumerate(table.values()):
        assert_shortest_round_trip([row[c] for row in rows], column)
    if not arrow:  # Python's writer: repr of every float, byte for byte
        columns = list(table.values())
        expected = "".join(
            ",".join(repr(float(column[k])) for column in columns) + "\n" for k in range(2017)
        )
        assert text == lines[0] + "\n" + expected


# ---------------------------------------------------------------- Parquet
def test_simulate_parquet_has_the_csv_columns_as_float64(tmp_path, capsys):
    pq = pytest.importorskip("pyarrow.parquet")
    assert (
        cli(capsys, "simulate", "--motion", "rotation", "--samples", "31", "-o", tmp_path / "c")[0]
        == 0
    )
    status, report, _ = cli(capsys, "simulate", "--motion", "rotation", "--samples", "31",
                            "-o", tmp_path / "p", "--format", "parquet")  # fmt: skip
    assert status == 0 and f"  {tmp_path / 'p' / 'results.parquet'}" in report
    data = pq.read_table(tmp_path / "p" / "results.parquet")
    assert data.column_names == list(RESULT_COLUMNS)
    assert all(str(field.type) == "double" for field in data.schema)
    with open(tmp_path / "c" / "results.csv", newline="") as stream:
        rows = list(csv.reader(stream))
    from_csv = np.array(rows[1:], dtype=np.float64)
    from_parquet = np.column_stack([data.column(name).to_numpy() for name in RESULT_COLUMNS])
    assert from_parquet.tobytes() == from_csv.tobytes()  # the same doubles, bit for bit


def test_parquet_without_pyarrow_is_refused_before_anything_runs(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(simulate_cli, "parquet_available", lambda: False)
    status, out, err = cli(capsys, "simulate", "--motion", "vertical", "-o", tmp_path / "o",
                           "--format", "parquet")  # fmt: skip
    assert (status, out) == (2, "")
    assert err == (
        "prp3 simulate: error: --format parquet needs pyarrow, which is not installed: "
        "pip install 'prp3[parquet]' (or pyarrow), or leave --format out for CSV\n"
    )
    assert not (tmp_path / "o").exists()
    monkeypatch.setattr(prp3_tables, "_pyarrow", lambda: None)
    with pytest.raises(OutputFileError, match="writing Parquet needs pyarrow"):
        prp3_tables.write_table_parquet(tmp_path / "x.parquet", {"t": np.zeros(2)})
    assert not os.path.exists(tmp_path / "x.parquet")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_an_input_that_is_not_a_regular_file_is_recorded_without_a_hash(tmp_path):
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)  # hashing it would wait for a writer
    with staged_output(tmp_path / "out", command="c", inputs=[pipe, None]) as staged:
        staged.path("a.txt").write_text("a")
    record = json.loads((tmp_path / "out" / MANIFEST_NAME).read_text())["commands"]["c"]
    assert record["inputs"] == [
        {"path": str(pipe), "sha256": None, "unreadable": "not a regular file"}
    ]
