"""Bad input, round six (issue 33, the last siblings).

* An efforts, forces or measurements file whose sample is refused names the file's
  line and the sample's time, for the 3-PRP, a family robot and the 6-UPS.
* ``prp3 identify`` refuses a measured value of ``±1e308`` in one line naming the
  column, the value and the line (exit 2, nothing written), for the three kinds.
* A file over the read bound is refused at once, before it is read.
* The overflow checks of the robot's parameters refuse what float64 cannot hold
  and nothing else: the edge both sides, against exact rational arithmetic, and
  the efforts just inside it checked against their linear extrapolation.
* The spatial inverse dynamics refuses results that overflow (it returned NaN).
"""

from __future__ import annotations

import os
import sys
import threading
import time
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import prp3
import prp3.files
from clitools import cli, one_line
from prp3.errors import InputFileError, ParameterError, Prp3Error, TrajectoryError
from prp3.family.model import FamilyRobot
from prp3.model.parameters import Load, Payload
from prp3.spatial.model import Body
from prp3.validation import OVERFLOW_REASON

HERE = Path(__file__).parent
EXAMPLES = HERE.parent / "examples"
BIGGEST = Fraction(sys.float_info.max)
SETTINGS = settings(
    max_examples=12,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


def _write(path: Path, header: list[str], rows: list[list[float]]) -> None:
    text = ",".join(header) + "\n" + "".join(",".join(repr(v) for v in row) + "\n" for row in rows)
    path.write_text(text, encoding="utf-8")


# ------------------------------------------- 1. a refused sample names its file line
EFFORTS = {  # robot file text, the option, the effort columns
    "3-PRP": (None, "--forces", ["f10_A", "f10_B", "f10_C"]),
    "3-RRR": ('architecture = "3-RRR"\nactuated = 1\n', "--forces", ["tau_A", "tau_B", "tau_C"]),
    "6-UPS": ('architecture = "6-UPS"\n', "--efforts", [f"tau_{i}" for i in range(1, 7)]),
}


@pytest.mark.parametrize("kind", list(EFFORTS))
@SETTINGS
@given(
    row=st.integers(0, 10),
    column=st.integers(0, 5),
    value=st.sampled_from([1e308, -1e308, 1e200, -1e30]),
    blank=st.integers(0, 3),
)
def test_a_refused_effort_sample_names_its_line_and_time(
    capsys, tmp_path, kind, row, column, value, blank
):
    text, option, names = EFFORTS[kind]
    column %= len(names)
    if text is None:  # the example robot: limits.max_force = 60 N
        robot = EXAMPLES / "robot.toml"
    else:
        robot = tmp_path / "r.toml"
        robot.write_text(text, encoding="utf-8")
    t = [0.1 * k for k in range(11)]
    rows = [[v] + [1.0] * len(names) for v in t]
    rows[row][1 + column] = value
    # blank lines before the header shift every line: the line is the file's, not the row's
    path = tmp_path / f"{row}-{column}-{blank}.csv"
    _write(path, ["t", *names], rows)
    path.write_text("\n" * blank + path.read_text(encoding="utf-8"), encoding="utf-8")
    status, _, err = cli(capsys, "forward", "--robot", robot, option, path,
                         "--output", tmp_path / "out")  # fmt: skip
    message = one_line(err)
    assert status == 2, message
    # ±1e308: the slope into (or, for the first row, out of) the row overflows, named at
    # the interval's first sample; other values: the row itself (a force limit, or the
    # acceleration it asks for at the initial state)
    sample = max(row - 1, 0) if abs(value) == 1e308 else row
    line = blank + 2 + sample
    assert f"{path}:{line}: " in message, message
    assert f"sample {sample}, " in message and f"t = {t[sample]:.9g} s" in message, message
    assert repr(abs(value)).lstrip("-") in message, message
    assert not (tmp_path / "out").exists()


def test_the_spatial_efforts_reader_keeps_the_line_of_each_row(tmp_path):
    names = [f"tau_{i}" for i in range(1, 7)]
    path = tmp_path / "e.csv"
    path.write_text("\n" + ",".join(["t", *names]) + "\n0,1,1,1,1,1,1\n\n0.5,2,2,2,2,2,2\n")
    efforts = prp3.read_spatial_efforts(path, prp3.hexapod())
    assert efforts.lines.tolist() == [3, 5]


def test_read_forces_keeps_the_line_of_each_row(tmp_path):
    path = tmp_path / "f.csv"
    path.write_text("t,f10_A,f10_B,f10_C\n\n0,1,2,3\n1,1,2,3\n", encoding="utf-8")
    assert prp3.read_forces(path).lines.tolist() == [3, 4]
    with pytest.raises(TrajectoryError) as caught:  # the library's error names the sample
        prp3.read_forces(_spoiled_forces(tmp_path))
    # 1 to 1e308 in 1 s: the slope is finite, the spline's are not; the largest sample named
    assert (caught.value.line, caught.value.sample, caught.value.key) == (4, 2, "f10_A")
    assert "f10_A = 1e+308" in str(caught.value)


def _spoiled_forces(tmp_path: Path) -> Path:
    path = tmp_path / "g.csv"
    path.write_text("t,f10_A,f10_B,f10_C\n0,1,2,3\n1,1,2,3\n2,1e308,2,3\n", encoding="utf-8")
    return path


# ------------------------------------------- 2. identify: a measured 1e308, by column and line
@pytest.fixture(scope="module")
def measurements(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Path, Path]]:
    """(robot file, measurement file) of the 3-PRP, the 3-RRR and the 6-UPS that identify
    accepts: an exciting trajectory of ``prp3 excite`` and its efforts of ``prp3 simulate``."""
    import contextlib
    import csv
    import io

    from prp3.cli import main

    folder = tmp_path_factory.mktemp("measured")
    made: dict[str, tuple[Path, Path]] = {}
    for kind, text, samples, efforts in (
        ("3-PRP", None, "101", ["f10_A", "f10_B", "f10_C"]),
        ("3-RRR", 'architecture = "3-RRR"\nactuated = 1\n', "101", ["tau_A", "tau_B", "tau_C"]),
        ("6-UPS", 'architecture = "6-UPS"\n', "201", [f"tau_{i}" for i in range(1, 7)]),
    ):
        robot = folder / f"{kind}.toml"
        if text is None:
            robot.write_text((EXAMPLES / "robot.toml").read_text(encoding="utf-8"))
        else:
            robot.write_text(text, encoding="utf-8")
        ex, sim = folder / f"ex-{kind}", folder / f"sim-{kind}"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            assert main(["excite", "--robot", str(robot), "--samples", samples,
                         "--iterations", "2", "--output", str(ex)]) == 0  # fmt: skip
            assert main(["simulate", "--robot", str(robot), "--trajectory",
                         str(ex / "trajectory.csv"), "--output", str(sim)]) == 0  # fmt: skip
        with (ex / "trajectory.csv").open(newline="") as handle:
            motion = list(csv.DictReader(handle))
        with (sim / "results.csv").open(newline="") as handle:
            results = list(csv.DictReader(handle))
        pose = [name for name in motion[0] if kind == "6-UPS" or name in ("t", "x", "y", "phi")]
        if kind == "3-PRP":  # the 3-PRP's results name its forces f10_A ..
            assert all(name in results[0] for name in efforts)
        rows = [[float(a[n]) for n in pose] + [float(b[n]) for n in efforts]
                for a, b in zip(motion, results, strict=True)]  # fmt: skip
        _write(folder / f"{kind}.csv", pose + efforts, rows)
        made[kind] = (robot, folder / f"{kind}.csv")
    return made


@pytest.mark.parametrize("kind", ["3-PRP", "3-RRR", "6-UPS"])
@pytest.mark.parametrize("value", [1e308, -1e308, 1e200])
def test_identify_refuses_a_huge_measured_value_naming_column_value_and_line(
    capsys, tmp_path, measurements, kind, value
):
    robot, good = measurements[kind]
    lines = good.read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    column = header[-2]  # an effort column, the last but one
    row = 7
    cells = lines[1 + row].split(",")
    cells[header.index(column)] = repr(value)
    lines[1 + row] = ",".join(cells)
    spoiled = tmp_path / "m.csv"
    spoiled.write_text("\n".join(lines) + "\n", encoding="utf-8")
    status, out, err = cli(capsys, "identify", "--robot", robot, "--measurements", spoiled,
                           "--output", tmp_path / "out")  # fmt: skip
    message = one_line(err)
    assert status == 2 and out == "", message
    assert f"{spoiled}:{row + 2}: sample {row}, t = " in message, message
    assert f"{column} = {value!r}" in message and "overflow" in message, message
    assert message.count(str(spoiled)) == 1, message  # the file named once
    assert not (tmp_path / "out").exists()


def test_identify_still_identifies_the_good_measurements(capsys, tmp_path, measurements):
    robot, good = measurements["6-UPS"]
    status, _, err = cli(capsys, "identify", "--robot", robot, "--measurements", good,
                           "--output", tmp_path / "out")  # fmt: skip
    assert status == 0, err
    assert (tmp_path / "out" / "parameters.csv").is_file()


# ------------------------------------------- 3. the read bound: refused before a byte is read
READERS = {
    "read_measurements": ("t,x,y,phi,f10_A,f10_B,f10_C\n0,0,0,0,1,2,3\n", prp3.read_measurements),
    "read_spatial_measurements": (
        "t,x,y,z,qw,qx,qy,qz,tau_1\n0,0,0,0.08,1,0,0,0,1\n",
        lambda path: prp3.read_spatial_measurements(path, 1),
    ),
    "read_spatial_efforts": (
        "t,tau_1,tau_2,tau_3,tau_4,tau_5,tau_6\n0,1,1,1,1,1,1\n",
        lambda path: prp3.read_spatial_efforts(path, prp3.hexapod()),
    ),
    "read_forces": ("t,f10_A,f10_B,f10_C\n0,1,2,3\n", prp3.read_forces),
}


@pytest.mark.parametrize("name", list(READERS))
def test_a_file_over_the_read_bound_is_refused_before_it_is_read(tmp_path, name):
    text, read = READERS[name]
    path = tmp_path / "big.csv"
    path.write_text(text, encoding="utf-8")
    os.truncate(path, prp3.files.MAX_INPUT_BYTES + 1)  # sparse: no disk, no time
    started = time.monotonic()
    with pytest.raises(InputFileError) as caught:
        read(path)
    assert time.monotonic() - started < 2.0
    assert caught.value.file == str(path) and caught.value.line is None
    assert f"larger than {prp3.files.MAX_INPUT_BYTES} bytes" in str(caught.value)
    assert f"{prp3.files.MAX_INPUT_BYTES + 1} bytes" in str(caught.value)


@pytest.mark.parametrize("name", list(READERS))
def test_the_read_bound_is_the_limit_both_sides(tmp_path, monkeypatch, name):
    text, read = READERS[name]
    path = tmp_path / "m.csv"
    rows = text.splitlines()
    path.write_text("\n".join([rows[0], rows[1], rows[1].replace("0,", "1,", 1)]) + "\n")
    size = path.stat().st_size
    monkeypatch.setattr(prp3.files, "MAX_INPUT_BYTES", size)
    try:
        read(path)
    except Prp3Error as error:  # refused for what it holds (too few samples), not its size
        assert "larger than" not in str(error)
    monkeypatch.setattr(prp3.files, "MAX_INPUT_BYTES", size - 1)
    with pytest.raises(InputFileError, match=f"larger than {size - 1} bytes"):
        read(path)


def test_a_pipe_over_the_read_bound_is_refused_as_it_is_read(tmp_path, monkeypatch):
    """A pipe has no size to look at: the bound counts the bytes read."""
    monkeypatch.setattr(prp3.files, "MAX_INPUT_BYTES", 10_000)
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)

    def feed() -> None:
        with open(fifo, "w", encoding="utf-8") as stream:
            stream.write("t,f10_A,f10_B,f10_C\n")
            try:
                for k in range(100_000):
                    stream.write(f"{k},1,2,3\n")
            except BrokenPipeError:
                pass

    writer = threading.Thread(target=feed, daemon=True)
    writer.start()
    with pytest.raises(InputFileError, match="larger than 10000 bytes") as caught:
        prp3.read_forces(fifo)
    assert caught.value.line is not None
    writer.join(timeout=10)


@pytest.mark.parametrize(
    ("command", "text"),
    [
        ("identify", READERS["read_measurements"][0]),
        ("forward", READERS["read_forces"][0]),
    ],
)
def test_a_command_refuses_a_file_over_the_bound_in_one_line(capsys, tmp_path, command, text):
    path = tmp_path / "big.csv"
    path.write_text(text, encoding="utf-8")
    os.truncate(path, prp3.files.MAX_INPUT_BYTES + 1)
    option = "--measurements" if command == "identify" else "--forces"
    started = time.monotonic()
    status, _, err = cli(capsys, command, option, path, "--output", tmp_path / "out")
    assert time.monotonic() - started < 5.0
    message = one_line(err)
    assert status == 2 and f"{path}: " in message and "larger than" in message, message
    assert not (tmp_path / "out").exists()


# ------------------------------------------- 5. the overflow checks: the edge, both sides
G = 9.81


def _robot(kind: str, mass: float) -> object:
    """The robot of ``kind`` whose heaviest body (payload or platform) has ``mass`` kg."""
    if kind == "3-PRP":
        return prp3.Robot(payload=Payload(mass=mass))
    if kind == "3-RRR":
        return replace(FamilyRobot.default("3-RRR"), payload=Payload(mass=mass))
    robot = prp3.hexapod() if kind == "6-UPS" else prp3.three_rps()
    return replace(robot, platform=Body(mass, (0.0, 0.0, 0.0), robot.platform.inertia, "platform"))


def _efforts(kind: str, robot: object) -> np.ndarray:
    if kind == "3-PRP":
        return prp3.inverse_dynamics(robot, prp3.paper_motion("vertical", 5))[1].f10
    if kind == "3-RRR":
        return prp3.family_inverse_dynamics(robot, prp3.paper_motion("vertical", 5)).tau
    return prp3.spatial_inverse_dynamics(robot, prp3.spatial_motion(robot, "heave", 5)).tau


def _others(kind: str) -> Fraction:
    """The weight of every body but the heaviest, exactly (N): it adds to the total."""
    if kind == "3-PRP":
        return Fraction(0)  # the 3-PRP's checks are of its payload alone
    if kind == "3-RRR":
        base = FamilyRobot.default("3-RRR")
        masses = [base.link1.mass] * 3 + [base.link2.mass] * 3 + [base.platform.mass]
    else:
        robot = prp3.hexapod() if kind == "6-UPS" else prp3.three_rps()
        masses = [body.mass for body in robot.bodies if body.name != "platform"]
    return sum((Fraction(m) for m in masses), Fraction(0)) * Fraction(G)


@pytest.mark.parametrize("kind", ["3-PRP", "3-RRR", "6-UPS", "3-RPS"])
@SETTINGS
@given(fraction=st.one_of(st.floats(0.5, 1.0 - 1e-9), st.floats(1.0 + 1e-9, 8.0)))
def test_a_heavy_body_is_accepted_exactly_while_its_weight_is_finite(kind, fraction):
    mass = float(Fraction(sys.float_info.max) / Fraction(G) * Fraction(fraction))
    total = Fraction(mass) * Fraction(G) + _others(kind)  # exact: no rounding to hide behind
    if total > BIGGEST:
        with pytest.raises(ParameterError) as caught:
            _robot(kind, mass)
        key = "payload.mass" if kind in ("3-PRP", "3-RRR") else "platform.mass"
        assert caught.value.key == key and "overflow" in caught.value.reason
        assert repr(mass) in str(caught.value).replace("e+", "e+")
        return
    robot = _robot(kind, mass)  # accepted: its efforts finite and linear in the mass,
    light, lighter = _robot(kind, 2.0), _robot(kind, 1.0)  # or refused, naming the overflow
    try:
        tau = _efforts(kind, robot)
    except TrajectoryError as error:
        assert error.reason.startswith(OVERFLOW_REASON) and error.sample is not None, error
        return
    slope = _efforts(kind, light) - _efforts(kind, lighter)
    expected = _efforts(kind, lighter) + (mass - 1.0) * slope
    assert np.isfinite(tau).all()
    np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize(
    ("kind", "mass"), [("3-RRR", 1.8e307), ("6-UPS", 1.8e307), ("3-PRP", 1.8e307)]
)
def test_the_numbers_the_docs_quote_are_the_edge(capsys, tmp_path, kind, mass):
    """docs/family.md and docs/spatial.md: 1.8e307 kg accepted, 1.84e307 kg refused."""
    robot = _robot(kind, mass)
    assert np.isfinite(_efforts(kind, robot)).all()
    assert float(Fraction(mass) * Fraction(G)) == pytest.approx(1.7658e308)
    with pytest.raises(ParameterError, match="weight m·g overflows"):
        _robot(kind, 1.84e307)


@pytest.mark.parametrize("kind", ["3-RRR", "6-UPS", "3-RPS"])
@SETTINGS
@given(fraction=st.one_of(st.floats(0.5, 1.0 - 1e-9), st.floats(1.0 + 1e-9, 8.0)))
def test_gravity_is_accepted_while_the_total_weight_is_finite_and_named_when_not(kind, fraction):
    if kind == "3-RRR":
        base: object = FamilyRobot.default("3-RRR")
        masses = [base.link1.mass] * 3 + [base.link2.mass] * 3 + [base.platform.mass]  # type: ignore[attr-defined]
    else:
        base = prp3.hexapod() if kind == "6-UPS" else prp3.three_rps()
        masses = [body.mass for body in base.bodies]  # type: ignore[attr-defined]
    total_mass = sum((Fraction(m) for m in masses), Fraction(0))
    g = float(min(BIGGEST / total_mass * Fraction(fraction), BIGGEST))
    gravity = (0.0, -g) if kind == "3-RRR" else (0.0, 0.0, -g)
    if Fraction(g) * total_mass > BIGGEST:
        with pytest.raises(ParameterError) as caught:
            replace(base, gravity=gravity)  # type: ignore[type-var]
        assert caught.value.key == "gravity" and "overflow" in caught.value.reason
    else:
        assert replace(base, gravity=gravity).gravity == gravity  # type: ignore[type-var, attr-defined]


@SETTINGS
@given(force=st.floats(1e300, sys.float_info.max), share=st.floats(0.0, 1.0))
def test_a_load_is_accepted_while_its_force_and_moment_are_finite(force, share):
    """|F_x| + |F_y| and (|F_x| + |F_y|)·r + |M| finite (r = 0.92 m, the 3-RRR's reach < 1)."""
    load = Load(force=(force, share * force), moment=0.0)
    base = FamilyRobot.default("3-RRR")
    if Fraction(force) * (1 + Fraction(share * force) / Fraction(force)) > BIGGEST:
        with pytest.raises(ParameterError) as caught:
            replace(base, load=load)
        assert caught.value.key == "load.force"
    else:
        assert replace(base, load=load).load == load


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"com": (1e155, 0.0)}, "payload.com"),  # r² overflows, whatever the mass
        ({"mass": 1e-300, "com": (1e155, 0.0)}, "payload.com"),
        ({"mass": 1.0, "com": (1e150, 0.0)}, None),  # r² = 1e300, m·r² finite: accepted
        ({"mass": 1e10, "com": (1e150, 0.0)}, "payload.inertia"),  # m·r² = 1e310
        ({"inertia": 1.7e308}, None),  # finite, and so is the total
    ],
)
def test_a_payload_far_away_or_of_a_huge_inertia(change, key):
    base = FamilyRobot.default("3-RRR")
    payload = Payload(**{"mass": 1.0, **change})
    if key is None:
        assert replace(base, payload=payload).payload == payload
        return
    with pytest.raises(ParameterError) as caught:
        replace(base, payload=payload)
    assert caught.value.key == key and "overflow" in caught.value.reason


# ------------------------------------------- 6. the spatial inverse dynamics never returns NaN
@pytest.mark.parametrize("method", ["newton-euler", "virtual-work"])
def test_spatial_inverse_dynamics_refuses_results_that_overflow(method):
    robot = _robot("6-UPS", 1.8e307)
    home = prp3.PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    fast = replace(home, acceleration=home.acceleration + np.array([[0.0, 0.0, 10.0]]))
    with pytest.raises(TrajectoryError) as caught:
        prp3.spatial_inverse_dynamics(robot, fast, method)
    assert caught.value.reason.startswith(OVERFLOW_REASON) and caught.value.sample == 0
    assert caught.value.time == 0.0
    assert np.isfinite(prp3.spatial_inverse_dynamics(robot, home, method).tau).all()


# ------------------------------------------- the planar readers fed a spoiled file
PLANAR = {
    "read_measurements": (
        "t,x,y,phi,f10_A,f10_B,f10_C\n"
        + "".join(f"{k / 10!r},0,{k / 100!r},0,1,2,3\n" for k in range(8)),
        prp3.read_measurements,
    ),
    "read_forces": (
        "t,f10_A,f10_B,f10_C\n" + "".join(f"{k / 10!r},1,2,3\n" for k in range(8)),
        prp3.read_forces,
    ),
}
HOSTILE = ["nan", "inf", "-inf", "1e308", "-1e308", "1e999", "1e-320", "", "x", '"1"', "0x1"]


@pytest.mark.parametrize("name", list(PLANAR))
@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.data())
def test_a_planar_reader_fed_a_spoiled_file_names_a_line_it_has(tmp_path, name, data):
    text, read = PLANAR[name]
    lines = text.splitlines()
    how = data.draw(st.sampled_from(["cell", "truncate", "drop", "junk"]))
    if how == "cell":
        k = data.draw(st.integers(1, len(lines) - 1))
        cells = lines[k].split(",")
        cells[data.draw(st.integers(0, len(cells) - 1))] = data.draw(st.sampled_from(HOSTILE))
        lines[k] = ",".join(cells)
        spoiled = "\n".join(lines) + "\n"
    elif how == "truncate":
        spoiled = text[: data.draw(st.integers(0, len(text) - 1))]
    elif how == "drop":
        k = data.draw(st.integers(0, len(lines) - 1))
        spoiled = "\n".join(lines[:k] + lines[k + 1 :]) + "\n"
    else:
        spoiled = data.draw(st.text(max_size=40))
    path = tmp_path / f"{data.draw(st.integers(0, 10**9))}.csv"
    path.write_text(spoiled, encoding="utf-8", errors="surrogateescape")
    try:
        result = read(path)
    except Prp3Error as error:
        assert "\n" not in str(error), str(error)
        if error.line is not None:  # a line of the file, 1-based
            assert 1 <= error.line <= max(len(spoiled.splitlines()), 1), (error.line, spoiled)
        return
    finally:
        path.unlink(missing_ok=True)
    values = result.f10 if name == "read_measurements" else result.forces.f10
    assert np.isfinite(values).all() and values.shape[1] == 3


# ------------------------------------------- forward dynamics of a heavy robot: named, not "singular"
@pytest.mark.parametrize(
    ("mass", "words"),
    [
        (1e3, None),
        (1e12, "ill-conditioned at the initial state (condition number "),
        (1.8e307, "the mass matrix of the 6-UPS overflows float64 at the initial state"),
    ],
)
def test_spatial_forward_of_a_heavy_platform_names_why(mass, words):
    robot = _robot("6-UPS", mass)
    if words is None:
        result = prp3.spatial_forward_dynamics(robot, prp3.hold_efforts(robot), None, 0.01)
        assert np.isfinite(result.motion.position).all()
        return
    with pytest.raises(ParameterError) as caught:
        prp3.spatial_forward_dynamics(robot, prp3.hold_efforts(robot), None, 0.01)
    assert words in str(caught.value) and repr(mass) in str(caught.value), str(caught.value)
    assert "condition number inf" not in str(caught.value)  # 1e12 kg: about 5e14, computed


def _forward_at_rest(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, robot_text: str, efforts: str
) -> tuple[int, str, Path, Path]:
    """``prp3 forward`` of the robot file ``robot_text`` under zero efforts (header
    ``t,<efforts>``) over 0.1 s: (exit status, its one error line, robot file, efforts file)."""
    robot = tmp_path / "heavy.toml"
    robot.write_text(robot_text, encoding="utf-8")
    forces = tmp_path / "zero.csv"
    forces.write_text(f"t,{efforts}\n0,0,0,0\n0.1,0,0,0\n", encoding="utf-8")
    status, _, err = cli(capsys, "forward", "--robot", robot, "--forces", forces,
                         "--output", tmp_path / "out")  # fmt: skip
    return status, one_line(err), robot, forces


def test_family_forward_of_a_heavy_payload_names_the_robot_file(capsys, tmp_path):
    status, message, robot, efforts = _forward_at_rest(
        capsys,
        tmp_path,
        'architecture = "3-RRR"\nactuated = 1\n[payload]\nmass = 1.8e307\n',
        "tau_A,tau_B,tau_C",
    )
    assert status == 2 and f"{robot}: robot at the initial pose: the results overflow" in message
    assert "sample" not in message and str(efforts) not in message, message
    assert not (tmp_path / "out").exists()


def test_prp3_forward_of_a_heavy_payload_names_the_robot_file_and_the_payload(capsys, tmp_path):
    status, message, robot, _ = _forward_at_rest(
        capsys, tmp_path, "[payload]\nmass = 1.8e307\n", "f10_A,f10_B,f10_C"
    )
    assert status == 2 and message.startswith(f"prp3 forward: error: {robot}: "), message
    assert "[payload] mass = 1.8e+307 kg" in message, message
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("method", ["fast", "paper", "newton-euler"])
def test_results_that_overflow_with_moderate_inputs_blame_the_robot_not_a_column(method):
    # A payload of 1.83e307 kg is accepted (its weight 1.795e308 N is finite, the checks
    # above), but with the rest of the robot's weight f10 overflows at home on the vertical
    # motion, whose inputs are all below 1 in SI units: no input can be the cause.
    motion = prp3.paper_motion("vertical", samples=11)
    with pytest.raises(TrajectoryError) as caught:
        prp3.inverse_dynamics(_robot("3-PRP", 1.83e307), motion, method=method)
    assert caught.value.key is None, caught.value
    assert "the sample's inputs are moderate" in str(caught.value)
    assert "the robot's masses, inertias or loads are too large" in str(caught.value)
    assert "the largest input of the sample is" not in str(caught.value)


@pytest.mark.parametrize(
    ("architecture", "mass"), [("3-RRR", 1e12), ("3-RRR", 1e300), ("3-RPR", 1e300)]
)
def test_family_forward_of_an_ill_scaled_robot_names_the_file_and_the_bodies(
    capsys, tmp_path, architecture, mass
):
    # a platform of `mass` kg beside an inertia of 0.1 kg·m²: the equations of motion
    # mix kg and kg·m², so A's condition number is about mass / 0.1 ≥ 1e13 > 1e12
    text = f'architecture = "{architecture}"\nactuated = 1\n[platform]\nmass = {mass!r}\n'
    status, message, robot, _ = _forward_at_rest(
        capsys, tmp_path, text + "inertia = 0.1\n", "tau_A,tau_B,tau_C"
    )
    assert status == 2 and message.startswith(f"prp3 forward: error: {robot}: robot: "), message
    assert "ill-conditioned" in message and "the bound 1e12" in message, message
    assert f"the largest: platform.mass = {mass!r} kg" in message, message
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    ("bound", "words"),
    [({"max_evaluations": 300}, "max_evaluations = 300"),
     ({"max_seconds": 0.2}, "max_seconds = 0.2 s (wall time)")],
)  # fmt: skip
def test_family_forward_of_a_stiff_robot_is_stopped_by_its_bound(bound, words):
    # a 3-RPR platform of 3e11 kg on legs of about 1 kg passes the start's condition
    # check (cond(A) ≈ 5e11 < 1e12) but is stiff: DOP853 crawls (a heavier platform, still
    # accepted, ran for more than 300 s before the bound), so both bounds are reached
    robot = replace(FamilyRobot.default("3-RPR"), platform=replace(
        FamilyRobot.default("3-RPR").platform, mass=3e11))  # fmt: skip
    t = np.linspace(0.0, 1.0, 3)
    with pytest.raises(TrajectoryError) as caught:
        prp3.family_forward_dynamics(robot, t, np.zeros((3, 3)), t, np.zeros(3), np.zeros(3),
                                     **bound)  # fmt: skip
    message = str(caught.value)
    assert f"stopped by its bound {words}" in message and "at t = " in message, message
    assert caught.value.time is not None and 0.0 <= caught.value.time < 1.0, message
