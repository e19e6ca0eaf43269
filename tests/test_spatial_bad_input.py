"""Bad input, round four, for the spatial robots (issue 33).

Absurd efforts in the spatial forward dynamics are refused up front from the equations
of motion (docs/spatial.md §18); hostile values on the spatial commands end in one line on
stderr, exit 2, and leave the output folder as it was.
"""

from __future__ import annotations

import math
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import prp3
from clitools import cli, listing, one_line
from prp3.apps.spatial_mjcf import MAX_MJCF_BYTES
from prp3.errors import InputFileError, ParameterError
from prp3.spatial.forward import MAX_ACCELERATION, hold_efforts, spatial_forward_dynamics
from prp3.spatial.model import delta, hexapod, three_rps
from read_only import NAMESPACES, run_read_only

ROBOTS = {"6-UPS": hexapod, "3-RPS": three_rps, "3-RUU": delta}


def _robot_file(folder: Path, architecture: str) -> Path:
    path = folder / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    return path


def _efforts_csv(path: Path, rows: list[list[float]], legs: int) -> Path:
    head = ",".join(["t"] + [f"tau_{i + 1}" for i in range(legs)])
    body = [",".join(repr(float(v)) for v in row) for row in rows]
    path.write_text("\n".join([head, *body]) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("architecture", sorted(ROBOTS))
@pytest.mark.parametrize("push", [1e6, 1e20, 1e308, -1e308])
def test_absurd_efforts_are_refused_before_the_integration(architecture, push):
    robot = ROBOTS[architecture]()
    began = time.monotonic()
    with pytest.raises(ParameterError, match="beyond the bound") as refused:
        spatial_forward_dynamics(robot, hold_efforts(robot) + push, duration=0.1, samples=3)
    assert time.monotonic() - began < 30.0
    assert "the effort of leg 1 is" in str(refused.value)
    assert refused.value.key == "efforts"


def test_the_bound_is_the_acceleration_of_the_equations_of_motion():
    """Efforts just below and above the bound (from ``a_f = A⁻¹(τ − h)`` by an independent
    finite difference of the inverse dynamics: the efforts are affine in ``a_f``)."""
    robot = hexapod()
    hold = hold_efforts(robot)
    # a uniform push of s N on every leg lifts the platform: the vertical acceleration is
    # s·6·(dτ/da_z)⁻¹-ish; measure it from a small push's integration instead of the code
    small = spatial_forward_dynamics(robot, hold + 1.0, duration=1e-4, samples=2)
    rate = float(
        np.abs(np.concatenate([small.motion.alpha[0], small.motion.acceleration[0]])).max()
    )
    below = 0.5 * MAX_ACCELERATION / rate
    spatial_forward_dynamics(robot, hold + below, duration=1e-6, samples=2)  # accepted
    with pytest.raises(ParameterError, match="beyond the bound"):
        spatial_forward_dynamics(robot, hold + 2.0 * MAX_ACCELERATION / rate, duration=1e-6)


@pytest.mark.parametrize("push", [1e6, 1e20, 1e308])
def test_prp3_forward_refuses_absurd_efforts_naming_the_file(capsys, tmp_path, push):
    robot_file = _robot_file(tmp_path, "3-RUU")
    hold = hold_efforts(delta())
    table = _efforts_csv(tmp_path / "push.csv", [[0.0, *(hold + push)], [0.1, *(hold + push)]], 3)
    out = tmp_path / "out"
    began = time.monotonic()
    status, _, err = cli(capsys, "forward", "--robot", robot_file, "--efforts", table,
                         "--output", out)  # fmt: skip
    assert time.monotonic() - began < 60.0
    assert status == 2
    line = one_line(err)
    assert "push.csv" in line and "beyond the bound" in line and repr(float(hold[0] + push)) in line
    assert not out.exists()


def test_a_callable_turning_absurd_stops_naming_the_time():
    robot = three_rps()
    hold = hold_efforts(robot)

    def efforts(t: float) -> np.ndarray:
        return hold + (1e300 if t > 1e-3 else 0.0)

    began = time.monotonic()
    with pytest.raises(Exception, match=r"at t = .* s, not below") as refused:
        spatial_forward_dynamics(robot, efforts, duration=0.01, samples=3)
    assert time.monotonic() - began < 60.0
    assert type(refused.value).__module__ == "prp3.errors"


READERS = {
    "read_spatial_robot": lambda p: prp3.read_spatial_robot(p),
    "read_spatial_trajectory": lambda p: prp3.read_spatial_trajectory(p),
    "read_spatial_efforts": lambda p: prp3.read_spatial_efforts(p, hexapod()),
    "read_spatial_sweep_spec": lambda p: prp3.read_spatial_sweep_spec(p),
    "read_spatial_mjcf": lambda p: prp3.read_spatial_mjcf(p),
    "read_spatial_urdf": lambda p: prp3.read_spatial_urdf(p),
}


@pytest.mark.parametrize("name", sorted(READERS))
@pytest.mark.parametrize("path", [None, 3, True, math.nan, b"robot.toml", ["a"], {"a": 1}])
def test_the_spatial_readers_refuse_a_path_of_the_wrong_type(name, path):
    with pytest.raises(ParameterError, match="path must be a file path"):
        READERS[name](path)


@pytest.mark.parametrize(
    "text",
    ["", "<mujoco><worldbody>", "\x00\x00", "<mujoco>" + "<a>" * 200_000,
     '<!DOCTYPE l [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;">]><mujoco>&b;</mujoco>'],
)  # fmt: skip
def test_read_spatial_mjcf_refuses_hostile_xml_in_one_line(tmp_path, text):
    path = tmp_path / "model.xml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputFileError) as refused:
        prp3.read_spatial_mjcf(path)
    assert "\n" not in str(refused.value) and "model.xml" in str(refused.value)


@pytest.mark.parametrize(
    ("text", "closures"),
    [("", None), ("<robot><link>", None), ("\x00\x00", None), ("<robot>" + "<a>" * 200_000, None),
     ('<!DOCTYPE l [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;">]><robot>&b;</robot>', None),
     (None, "a: &a [x, x, x]\nb: &b [*a, *a, *a]\nc: [*b, *b, *b]\n"), (None, "\x00"), (None, "[")],
)  # fmt: skip
def test_read_spatial_urdf_refuses_hostile_files_in_one_line(tmp_path, text, closures):
    pytest.importorskip("yaml")
    path = tmp_path / "robot.urdf"
    path.write_text(prp3.spatial_urdf_model(hexapod()) if text is None else text, encoding="utf-8")
    side = prp3.spatial_urdf_closures(hexapod()) if closures is None else closures
    (tmp_path / "robot.yaml").write_text(side, encoding="utf-8")
    with pytest.raises(InputFileError) as refused:
        prp3.read_spatial_urdf(path)
    assert "\n" not in str(refused.value) and "robot." in str(refused.value)


def test_read_spatial_mjcf_refuses_a_huge_file_before_reading_it(tmp_path):
    path = tmp_path / "huge.xml"
    with path.open("wb") as handle:  # sparse: no disk is written
        handle.seek(MAX_MJCF_BYTES + 1)
        handle.write(b" ")
    with pytest.raises(InputFileError, match=r"huge\.xml"):
        prp3.read_spatial_mjcf(path)


@pytest.mark.parametrize(
    "argv",
    [
        ["workspace", "--robot", "{robot}", "--points", "1000000000"],
        ["workspace", "--robot", "{robot}", "--extent", "-1e308", "1e308", "-1", "1"],
        ["simulate", "--robot", "{robot}", "--motion", "tilt", "--samples", "10000000000000"],
        ["simulate", "--robot", "{robot}", "--trajectory", "{huge}"],
        ["simulate", "--robot", "{robot}", "--trajectory", "{rates}"],
        ["export", "mjcf", "--robot", "{nan_robot}"],
    ],
)
def test_hostile_values_on_the_spatial_commands_keep_the_folder(capsys, tmp_path, argv):
    robot = _robot_file(tmp_path, "6-UPS")
    nan_robot = tmp_path / "nan.toml"
    nan_robot.write_text('architecture = "6-UPS"\n[platform]\nmass = nan\n', encoding="utf-8")
    head = "t,x,y,z,qw,qx,qy,qz,wx,wy,wz,vx,vy,vz,dwx,dwy,dwz,ax,ay,az"
    rows = {"huge": "{t},1e308,0,0.08,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0",
            "rates": "{t},0,0,0.08,1,0,0,0,1e200,0,0,1e200,0,0,0,0,0,0,0,0"}  # fmt: skip
    for name, row in rows.items():
        lines = [head] + [row.format(t=t) for t in (0.0, 0.1, 0.2)]
        (tmp_path / f"{name}.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    (out / "earlier.csv").write_text("kept\n", encoding="utf-8")
    before = listing(out)
    words = {"robot": robot, "nan_robot": nan_robot, "huge": tmp_path / "huge.csv",
             "rates": tmp_path / "rates.csv"}  # fmt: skip
    status, _, err = cli(capsys, *(a.format(**words) for a in argv), "--output", out)
    assert status == 2
    one_line(err)
    assert listing(out) == before


def _folder_state(folder: Path) -> dict[str, bytes]:
    return listing(folder) if folder.exists() else {}


@pytest.mark.slow
def test_a_killed_spatial_simulate_leaves_the_folder_as_before_or_whole(tmp_path):
    robot = _robot_file(tmp_path, "6-UPS")
    out = tmp_path / "out"
    argv = [sys.executable, "-m", "prp3", "simulate", "--robot", str(robot), "--motion",
            "tilt", "--samples", "20001", "--output", str(out)]  # fmt: skip
    env = {**os.environ, "PYTHONPATH": str(Path(prp3.__file__).parents[1])}
    whole = subprocess.run(argv, env=env, capture_output=True, text=True, timeout=300)
    assert whole.returncode == 0, whole.stderr
    complete = listing(out)
    (out / "results.csv").write_text("earlier\n", encoding="utf-8")
    earlier = listing(out)
    rng = random.Random(33)
    for _ in range(3):
        process = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL)  # fmt: skip
        time.sleep(rng.uniform(0.5, 4.0))
        process.send_signal(rng.choice([signal.SIGKILL, signal.SIGINT]))
        process.wait(timeout=60)
        state = {k: v for k, v in _folder_state(out).items() if not k.startswith(".")}
        assert state in ({k: v for k, v in earlier.items() if not k.startswith(".")},
                         {k: v for k, v in complete.items() if not k.startswith(".")}), sorted(state)  # fmt: skip
        if state != {k: v for k, v in earlier.items() if not k.startswith(".")}:
            (out / "results.csv").write_text("earlier\n", encoding="utf-8")
            earlier = listing(out)


@NAMESPACES
@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--robot", "{robot}", "--motion", "tilt", "--samples", "5"],
        ["workspace", "--robot", "{robot}", "--points", "5"],
        ["export", "mjcf", "--robot", "{robot}"],
    ],
)
def test_a_read_only_folder_ends_in_one_line(tmp_path, argv):
    robot = _robot_file(tmp_path, "6-UPS")
    locked = tmp_path / "locked"
    locked.mkdir()
    status, err = run_read_only(locked, *(a.format(robot=robot) for a in argv),
                                "--output", locked / "out")  # fmt: skip
    assert status == 2
    line = one_line(err)
    assert "locked" in line and ("not writable" in line or "Read-only file system" in line), line
    assert not (locked / "out").exists()


@pytest.mark.parametrize("push", [1e7, 1e20, 1e300])
def test_prp3_forward_of_the_planar_robot_refuses_absurd_forces_at_once(capsys, tmp_path, push):
    table = tmp_path / "huge.csv"
    rows = "".join(f"{t},{push!r},{push!r},{push!r}\n" for t in (0.0, 0.05, 0.1))
    table.write_text("t,f10_A,f10_B,f10_C\n" + rows, encoding="utf-8")
    began = time.monotonic()
    status, _, err = cli(capsys, "forward", "--forces", table, "--output", tmp_path / "o")
    assert time.monotonic() - began < 60.0
    line = one_line(err)
    assert status == 2 and "huge.csv" in line and "beyond the bound" in line
    assert not (tmp_path / "o").exists()


# ------------------------------------------- hostile sweep specs, explore, identify (round 4)
SPEC_HEAD = 'spatial = "6-UPS"\ndesigns = 2\n[task]\nsamples = 5\n'


@pytest.mark.parametrize(
    ("tail", "words"),
    [
        ("[parameters]\nbase_radius = [nan, 0.5]\n", "low must be a finite number, got nan"),
        ("[parameters]\nbase_radius = [0.1, inf]\n", "high must be a finite number, got inf"),
        ("[parameters]\nbase_radius = [0.1, 1e308]\n", "base_radius must be at most"),
        ('[parameters]\n"platform.mass" = [-1.0, 2.0]\n', "platform.mass must be a non-negative"),
        ("[parameters]\nbase_radius = [true, false]\n", "low must be a finite number, got True"),
        ('[parameters]\nbase_radius = [0.1, 0.5]\n"base_radius" = [0.2, 0.4]\n', "set twice"),
        ("bogus = 1\n", "unknown key task.'bogus'"),
    ],
)
@pytest.mark.parametrize("command", ["sweep", "optimize"])
def test_hostile_spatial_sweep_specs_end_in_one_line_and_keep_the_folder(
    capsys, tmp_path, command, tail, words
):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC_HEAD + tail, encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("kept\n", encoding="utf-8")
    before = listing(out)
    status, _, err = cli(capsys, command, "--spec", spec, "--output", out, "--workers", 1)
    line = one_line(err)
    assert status == 2 and "spec.toml" in line and words in line
    assert listing(out) == before


def test_an_unknown_top_level_key_of_a_spatial_spec_is_named(capsys, tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text('bogus = 1\nspatial = "6-UPS"\n', encoding="utf-8")
    status, _, err = cli(capsys, "sweep", "--spec", spec, "--output", tmp_path / "out")
    assert status == 2 and "unknown key 'bogus'" in one_line(err)
    assert not (tmp_path / "out").exists()


def test_an_unreachable_scheduler_leaves_no_staging_folder(capsys, tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC_HEAD, encoding="utf-8")
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("kept\n", encoding="utf-8")
    before = listing(out)
    status, _, err = cli(capsys, "sweep", "--spec", spec, "--output", out,
                         "--scheduler", "tcp://127.0.0.1:1")  # fmt: skip
    assert status == 2 and "cannot reach the Dask scheduler" in one_line(err)
    assert listing(out) == before and sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_a_truncated_spatial_designs_file_is_named_truncated(capsys, tmp_path):
    pytest.importorskip("pyarrow")
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC_HEAD, encoding="utf-8")
    out = tmp_path / "out"
    status, _, err = cli(capsys, "sweep", "--spec", spec, "--output", out, "--workers", 1)
    assert status == 0, err
    designs = out / "designs.parquet"
    designs.write_bytes(designs.read_bytes()[: designs.stat().st_size // 2])
    before = listing(out)
    status, _, err = cli(capsys, "sweep", "--spec", spec, "--output", out, "--workers", 1)
    line = one_line(err)
    assert status == 2 and "designs.parquet: truncated: a Parquet file cut short" in line
    assert "not a designs file" not in line
    assert listing(out) == before


@pytest.fixture
def hexapod_run(capsys, tmp_path):
    robot_file = _robot_file(tmp_path, "6-UPS")
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "tilt",
                         "--samples", 7, "--output", tmp_path / "run")  # fmt: skip
    assert status == 0, err
    return robot_file, tmp_path / "run"


def _broken_runs(run: Path, folder: Path) -> dict[str, Path]:
    rows = (run / "results.csv").read_text(encoding="utf-8").splitlines()
    runs = {}
    for name in ("truncated", "nan", "huge"):
        (folder / name).mkdir()
        runs[name] = folder / name
    text = "\n".join(rows) + "\n"
    (runs["truncated"] / "results.csv").write_text(text[: len(text) // 2], encoding="utf-8")
    for name, value in (("nan", "nan"), ("huge", "1e308")):
        changed = list(rows)
        cells = changed[3].split(",")
        cells[3] = value
        changed[3] = ",".join(cells)
        (runs[name] / "results.csv").write_text("\n".join(changed) + "\n", encoding="utf-8")
    return runs


@pytest.mark.parametrize("kind", ["truncated", "nan", "huge", "missing", "other"])
def test_explore_export_of_a_broken_spatial_run_writes_no_html(capsys, tmp_path, hexapod_run, kind):
    robot_file, run = hexapod_run
    runs = _broken_runs(run, tmp_path)
    runs["missing"] = tmp_path / "nowhere"
    runs["other"] = run
    if kind == "other":
        robot_file = _robot_file(tmp_path, "3-RPS")
    export = tmp_path / "page.html"
    status, out, err = cli(capsys, "explore", "--robot", robot_file, "--results", runs[kind],
                           "--export", export)  # fmt: skip
    assert status == 2 and out == ""
    one_line(err)
    assert not export.exists()


def test_explore_names_a_truncated_parquet_run(capsys, tmp_path):
    pytest.importorskip("pyarrow")
    robot_file = _robot_file(tmp_path, "6-UPS")
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "tilt",
                         "--samples", 7, "--output", tmp_path / "pq", "--format", "parquet")  # fmt: skip
    assert status == 0, err
    parquet = tmp_path / "pq" / "results.parquet"
    parquet.write_bytes(parquet.read_bytes()[: parquet.stat().st_size // 2])
    export = tmp_path / "page.html"
    status, _, err = cli(capsys, "explore", "--robot", robot_file, "--results", tmp_path / "pq",
                         "--export", export)  # fmt: skip
    assert status == 2 and "results.parquet: truncated: a Parquet file cut short" in one_line(err)
    assert not export.exists()


def _measurements(folder: Path, capsys) -> tuple[Path, list[list[str]]]:
    """A 3-RPS robot file and the rows of its measurements (trajectory columns and efforts)."""
    import csv

    robot_file = _robot_file(folder, "3-RPS")
    status, _, err = cli(capsys, "excite", "--robot", robot_file, "--output", folder / "ex",
                         "--samples", 101, "--iterations", 1, "--rotation", 0.3)  # fmt: skip
    assert status == 0, err
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--trajectory",
                         folder / "ex" / "trajectory.csv", "--output", folder / "sim")  # fmt: skip
    assert status == 0, err
    poses = list(csv.reader((folder / "ex" / "trajectory.csv").read_text().splitlines()))
    sim = list(csv.reader((folder / "sim" / "results.csv").read_text().splitlines()))
    columns = [sim[0].index(f"tau_{i}") for i in (1, 2, 3)]
    return robot_file, [p + [s[c] for c in columns] for p, s in zip(poses, sim, strict=True)]


@pytest.mark.parametrize(
    ("column", "value", "words"),
    [
        ("tau_3", "nan", "not a finite number: 'nan'"),
        ("tau_3", "1e308", "the least squares overflow double precision: tau_3 = 1e+308"),
        ("x", "1e308", "cannot be completed for the legs"),
        ("wx", "1e308", "of alpha is not finite"),
    ],
)
def test_identify_of_a_spatial_robot_refuses_absurd_measurements(
    capsys, tmp_path, column, value, words
):
    robot_file, rows = _measurements(tmp_path, capsys)
    rows[5][rows[0].index(column)] = value
    measured = tmp_path / "m.csv"
    measured.write_text("\n".join(",".join(r) for r in rows) + "\n", encoding="utf-8")
    status, _, err = cli(capsys, "identify", "--robot", robot_file, "--measurements", measured,
                           "--output", tmp_path / "id")  # fmt: skip
    line = one_line(err)
    assert status == 2 and "m.csv:6" in line and words in line
    assert not (tmp_path / "id").exists()
