"""``prp3 sweep`` / ``prp3 optimize`` on Dask, results in Parquet.

The expected numbers come from ``prp3 simulate``'s ``results.csv`` read back
here (not from the sweep's code), from brute force, or from the robot file
the optimizer wrote.  One in-process Dask cluster serves the module; one
test starts a real cluster of 2 worker processes.
"""

from __future__ import annotations

import csv
import math
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

pytest.importorskip("distributed")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

import prp3  # noqa: E402
import prp3.apps.cluster  # noqa: E402
import prp3.apps.design_evaluation  # noqa: E402
import prp3.apps.design_objective  # noqa: E402
import prp3.apps.optimization  # noqa: E402
import prp3.apps.sweep  # noqa: E402
from clitools import cli  # noqa: E402
from prp3.apps.design import design_robot  # noqa: E402
from prp3.apps.design_evaluation import evaluate_designs  # noqa: E402
from prp3.apps.design_objective import pareto_front  # noqa: E402
from prp3.apps.sweep_spec import design_values, read_sweep_spec, sweep_spec  # noqa: E402
from prp3.mechanics.parameters import kernel_parameters  # noqa: E402
from sweeptools import interrupted_sweep, write  # noqa: E402

LEGS = "ABC"
GRID = """\
designs = 3
sampling = "grid"
[parameters]
"platform.mass" = [2.0, 4.0]
[task]
motions = ["vertical", "rotation"]
"""
#: 4 chunks, the last one partial; few samples, so that it is quick.
LHS = """\
designs = 67
chunk = 20
sampling = "lhs"
seed = 7
[parameters]
l0 = [0.25, 0.35]
platform.mass = [2.0, 4.0]
"limits.stroke.1" = [0.03, 0.09]
[limits]
stroke = [-0.06, 0.06]
[task]
motions = ["vertical", "rotation"]
samples = 21
"""


def read_results(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return {name: values[:, j] for j, name in enumerate(rows[0])}


def test_grid_row_of_the_paper_robot_equals_simulate_on_both_motions(tmp_path, capsys, scheduler):
    spec = write(tmp_path / "sweep.toml", GRID)
    status, out, err = cli(
        capsys, "sweep", "--spec", spec, "--output", tmp_path / "s", "--scheduler", scheduler
    )
    assert (status, err) == (0, ""), err  # not a terminal: no progress bar
    assert "3 ok" in out
    table = pq.read_table(tmp_path / "s" / "designs.parquet").to_pydict()
    assert table["platform.mass"] == [2.0, 3.0, 4.0]
    assert table["status"] == ["ok"] * 3
    row = 1
    expected: dict[str, float] = {}
    energy = 0.0
    for motion in ("vertical", "rotation"):
        assert cli(capsys, "simulate", "--motion", motion, "--output", tmp_path / motion)[0] == 0
        results = read_results(tmp_path / motion / "results.csv")
        for leg in LEGS:
            peaks = {
                "f10": np.abs(results[f"f10_{leg}"]).max(),
                "p10": np.abs(results[f"p10_{leg}"]).max(),
                "f21": np.sqrt(results[f"f21y_{leg}"] ** 2 + results[f"f21z_{leg}"] ** 2).max(),
                "n32": np.abs(results[f"n32_{leg}"]).max(),
            }
            for name, value in peaks.items():
                key = f"peak_{name}_{leg}"
                expected[key] = max(expected.get(key, -math.inf), float(value))
        power = sum(results[f"p10_{leg}"] for leg in LEGS)
        energy += float(np.trapezoid(power, results["t"]))
    for key, value in expected.items():
        assert table[key][row] == pytest.approx(value, rel=1e-12, abs=0.0), key
    assert table["energy"][row] == pytest.approx(energy, rel=1e-12)


def _digest_bytes(path: Path) -> bytes:
    return (path / "designs.parquet").read_bytes()


def test_one_or_two_workers_and_an_interrupted_run_give_the_same_file(
    tmp_path, capsys, scheduler, monkeypatch
):
    spec = write(tmp_path / "sweep.toml", LHS)
    assert (
        cli(capsys, "sweep", "--spec", spec, "-o", tmp_path / "one", "--scheduler", scheduler)[0]
        == 0
    )
    status, out, err = cli(capsys, "sweep", "--spec", spec, "-o", tmp_path / "two", "--workers", 2)
    assert status == 0, err
    assert _digest_bytes(tmp_path / "one") == _digest_bytes(tmp_path / "two")

    # interrupted after two chunks: the staging folder keeps them, no designs.parquet
    interrupted_sweep(capsys, monkeypatch, ("sweep", "--spec", spec, "--scheduler", scheduler),
                      tmp_path / "cut")  # fmt: skip
    args = ("sweep", "--spec", spec, "-o", tmp_path / "cut", "--scheduler", scheduler)
    status, out, err = cli(capsys, *args)
    assert status == 0, err
    assert "2 of 4 chunks computed, 2 found done" in out
    assert _digest_bytes(tmp_path / "cut") == _digest_bytes(tmp_path / "one")
    assert not list((tmp_path / "cut").glob(".prp3-sweep-*"))
    # once complete, the same command computes nothing and keeps the file
    status, out, err = cli(capsys, *args)
    assert status == 0 and "0 of 4 chunks computed" in out
    assert _digest_bytes(tmp_path / "cut") == _digest_bytes(tmp_path / "one")

    # rows in generation order, each one the design's own evaluation
    table = pq.read_table(tmp_path / "two" / "designs.parquet").to_pydict()
    values = design_values(read_sweep_spec(spec))
    assert np.array_equal(
        np.column_stack([table[p] for p in ("l0", "platform.mass", "limits.stroke.1")]), values
    )
    statuses = set(table["status"])
    assert statuses == {"ok", "stroke"}  # short strokes cannot do the vertical motion (0.05 m)
    for k in (0, len(values) - 1):
        robot = design_robot(
            {"limits": {"stroke": [-0.06, 0.06]}},
            ["l0", "platform.mass", "limits.stroke.1"],
            values[k],
        )
        motions = [prp3.paper_motion(m, 21) for m in ("vertical", "rotation")]
        try:
            f10 = max(float(np.abs(prp3.inverse_dynamics(robot, m)[1].f10).max()) for m in motions)
        except prp3.UnreachablePoseError:
            assert table["status"][k] == "stroke" and math.isnan(table["peak_f10_A"][k])
            continue
        assert table["status"][k] == "ok"
        assert max(table[f"peak_f10_{leg}"][k] for leg in LEGS) == pytest.approx(f10, rel=1e-12)


def test_workspace_area_and_condition_columns(tmp_path):
    spec = sweep_spec(
        {
            "designs": 2,
            "sampling": "grid",
            "parameters": {"limits": {"stroke": {"1": [0.05, 0.1]}}, "l0": [0.2, 0.4]},
            "limits": {"stroke": [-0.05, 0.05]},
            "task": {"motions": ["rotation"], "samples": 11},
        }
    )
    columns = evaluate_designs(spec.evaluator, design_values(spec))
    # symmetric stroke ±s at φ = 0: a regular hexagon of circumradius s (workspace docs)
    hexagon = 1.5 * math.sqrt(3.0) * 0.05**2
    assert columns["workspace_area"][0] == pytest.approx(hexagon, rel=1e-12)
    assert columns["workspace_area"][2] > hexagon  # a longer upper stroke
    poses = prp3.paper_motion("rotation", 11).pose
    for k, l0 in enumerate(design_values(spec)[:, 1]):
        robot = prp3.Robot(l0=float(l0))
        assert columns["max_condition"][k] == float(prp3.jacobian_condition(robot, poses).max())


def test_failing_designs_are_rows_with_their_status(tmp_path):
    t = np.linspace(0.0, 1.0, 5)
    phi = np.array([0.0, 0.5, math.pi / 3.0, 0.5, 0.0])
    lines = ["t,x,y,phi"] + [
        f"{float(a)!r},0.0,0.0,{float(b)!r}" for a, b in zip(t, phi, strict=True)
    ]
    write(tmp_path / "singular.csv", "\n".join(lines) + "\n")
    singular = sweep_spec(
        {"designs": 3, "parameters": {"l0": [0.2, 0.4]}, "task": {"motions": ["singular.csv"]}},
        base=tmp_path,
    )
    columns = evaluate_designs(singular.evaluator, design_values(singular))
    assert columns["status"].tolist() == ["singular"] * 3
    assert np.isnan(columns["peak_f10_A"]).all() and np.isnan(columns["energy"]).all()
    stroke = sweep_spec(
        {
            "designs": 2,
            "sampling": "grid",
            "parameters": {"limits.stroke.1": [0.01, 0.1]},
            "limits": {"stroke": [-0.1, 0.1]},
            "task": {"motions": ["vertical"], "samples": 11},
        }
    )
    columns = evaluate_designs(stroke.evaluator, design_values(stroke))
    assert columns["status"].tolist() == ["stroke", "ok"]
    assert math.isnan(columns["peak_p10_B"][0]) and columns["peak_p10_B"][1] > 0.0
    huge = sweep_spec(  # a valid robot whose forces overflow double precision
        {
            "designs": 2,
            "sampling": "grid",
            "parameters": {"platform.mass": [1.0, 5e307]},
            "task": {"motions": ["rotation"], "samples": 11},
        }
    )
    columns = evaluate_designs(huge.evaluator, design_values(huge))
    assert columns["status"].tolist() == ["ok", "unreachable"]
    assert np.isnan(columns["energy"][1]) and np.isfinite(columns["energy"][0])


def test_key_paths_are_generic_and_the_platform_inertia_follows_mass_and_l0():
    nominal = {"l0": 0.3, "link": {"com": [0.0, 0.0]}}
    robot = design_robot(nominal, ["link.com.1", "platform.mass", "l0"], [0.01, 2.0, 0.4])
    assert robot.link.com == (0.0, 0.01) and robot.platform.mass == 2.0
    assert robot.platform_inertia == pytest.approx(2.0 * (0.4 * math.sqrt(3.0)) ** 2 / 12.0)
    given = design_robot({"platform": {"inertia": 0.05}}, ["platform.mass"], [2.0])
    assert given.platform_inertia == 0.05
    assert nominal == {"l0": 0.3, "link": {"com": [0.0, 0.0]}}  # not changed
    with pytest.raises(prp3.ParameterError, match="unknown key 'gripper'"):
        design_robot({}, ["gripper.mass"], [1.0])  # a table the robot does not know
    assert design_robot({}, ["payload.mass"], [1.0]).payload.mass == 1.0  # not in nominal
    assert design_robot({}, ["friction.sleeve.mu"], [0.1]).friction.sleeve.mu == 0.1


@given(
    st.lists(
        st.tuples(st.integers(0, 6).map(float), st.integers(0, 6).map(float)),
        min_size=1,
        max_size=30,
    ),
    st.booleans(),
)
def test_pareto_front_is_the_set_of_non_dominated_points(points, maximize_x):
    x, y = (np.array(v) for v in zip(*points, strict=True))
    front = set(pareto_front(x, y, maximize_x=maximize_x).tolist())
    sx = -x if maximize_x else x
    for i in range(len(x)):
        dominated = any(
            sx[j] <= sx[i] and y[j] <= y[i] and (sx[j] < sx[i] or y[j] < y[i])
            for j in range(len(x))
        )
        duplicate_before = any(sx[j] == sx[i] and y[j] == y[i] for j in range(i))
        assert (i in front) == (not dominated and not duplicate_before)


BAD_INPUTS = [
    ('[parameters]\n"platfrom.mass" = [2.0, 4.0]\n', "unknown key 'platfrom'"),
    ('[parameters]\n"platform.mass" = [4.0, 2.0]\n', "low > high"),
    ('[parameters]\n"platform.mass" = []\n', "empty range"),
    ('[parameters]\n"platform.mass" = [2.0, 2.0]\n', "empty range"),
    ('sampling = "sobol"\n[parameters]\nl0 = [0.2, 0.4]\n', "unknown sampling 'sobol'"),
    (
        '[parameters]\nl0 = [0.2, 0.4]\n[task]\nmotions = ["vertical", "missing.csv"]\n',
        "missing.csv",
    ),
    ('[parameters]\n"platform.mass" = [-1.0, 2.0]\n', "platform.mass"),
    ("designs = 0\n[parameters]\nl0 = [0.2, 0.4]\n", "designs"),
    ('[parameters]\nl0 = [0.2, 0.4]\n[optimize]\nobjective = "peak_f99"\n', "peak_f99"),
    ("[parameters\n", "invalid TOML"),
]


@pytest.mark.parametrize(("text", "fragment"), BAD_INPUTS)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, text, fragment):
    spec = write(tmp_path / "sweep.toml", text)
    for command in ("sweep", "optimize"):
        status, out, err = cli(capsys, command, "--spec", spec, "--output", tmp_path / "out")
        assert status == 2 and out == ""
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1
        assert err.startswith(f"prp3 {command}: error: ") and fragment in err, err
        assert str(spec) in err or (fragment == "low > high" and "sweep.toml" in err)
        assert not (tmp_path / "out").exists()


def test_an_unreachable_scheduler_is_reported_within_10_s(tmp_path, capsys, monkeypatch):
    assert prp3.apps.cluster.CONNECT_TIMEOUT <= 5.0  # the default leaves time to start and report
    monkeypatch.setattr(prp3.apps.cluster, "CONNECT_TIMEOUT", 1.0)  # the same path, sooner
    spec = write(tmp_path / "sweep.toml", GRID)
    start = time.monotonic()
    status, _out, err = cli(
        capsys, "sweep", "--spec", spec, "-o", tmp_path / "out", "--scheduler", "tcp://127.0.0.1:9"
    )
    assert time.monotonic() - start < 10.0
    assert status == 2 and len(err.strip().splitlines()) == 1
    assert "tcp://127.0.0.1:9" in err and "cannot reach the Dask scheduler" in err
    assert not (tmp_path / "out").exists()  # no staging folder, no empty output folder
    (tmp_path / "kept").mkdir()
    (tmp_path / "kept" / "notes.txt").write_text("mine")
    status, _out, err = cli(
        capsys, "sweep", "--spec", spec, "-o", tmp_path / "kept", "--scheduler", "tcp://127.0.0.1:9"
    )
    assert status == 2
    assert [p.name for p in (tmp_path / "kept").iterdir()] == ["notes.txt"]


def test_optimize_writes_the_best_design_and_its_history(tmp_path, capsys, scheduler):
    spec = write(
        tmp_path / "synthesis.toml",
        """\
seed = 3
[parameters]
"link.mass" = [0.3, 1.0]
"limits.stroke.1" = [0.03, 0.12]
[limits]
stroke = [-0.08, 0.08]
[task]
motions = ["vertical"]
samples = 31
[optimize]
objective = "peak_f10"
maxiter = 8
popsize = 5
[optimize.constraints]
workspace_area = { min = 0.02 }
""",
    )
    status, out, err = cli(
        capsys, "optimize", "--spec", spec, "-o", tmp_path / "best", "--scheduler", scheduler
    )
    assert status == 0, err
    robot = prp3.Robot.from_toml(tmp_path / "best" / "ROBOT.toml")
    history = read_results(tmp_path / "best" / "history.csv")
    feasible = np.isfinite(history["objective"])
    assert feasible.any() and (history["violation"][~feasible] > 0).all()
    # the written robot: its own peak force (inverse dynamics) is the best of the history
    motion = prp3.paper_motion("vertical", 31)
    best = float(np.abs(prp3.inverse_dynamics(robot, motion)[1].f10).max())
    assert best == pytest.approx(history["objective"][feasible].min(), rel=1e-12)
    assert f"best peak_f10 = {best:.9g}" in out
    area = prp3.workspace_slice(robot, 0.0, [-1.0, 1.0], [-1.0, 1.0]).area
    assert area >= 0.02
    assert robot.platform.mass == 3.0 and robot.limits.stroke[0] == -0.08
    # the same seed, the same search
    status, _, err = cli(
        capsys, "optimize", "--spec", spec, "-o", tmp_path / "again", "--scheduler", scheduler
    )
    assert status == 0, err
    for name in ("ROBOT.toml", "history.csv"):
        assert (tmp_path / "again" / name).read_bytes() == (tmp_path / "best" / name).read_bytes()


class _FullStream:
    """A standard output on a full disk."""

    def write(self, text: str) -> int:
        raise OSError(28, "No space left on device")

    def flush(self) -> None:
        raise OSError(28, "No space left on device")


def test_optimize_prints_its_summary_before_the_files_move_in(
    tmp_path, capsys, monkeypatch, scheduler
):
    # was: ROBOT.toml and history.csv moved in first, then the summary failed (exit 2)
    spec = write(
        tmp_path / "synthesis.toml",
        "seed = 1\n[parameters]\nl0 = [0.25, 0.35]\n[task]\nsamples = 7\n"
        "[optimize]\nmaxiter = 1\npopsize = 2\n",
    )
    earlier = tmp_path / "best"
    earlier.mkdir()
    (earlier / "ROBOT.toml").write_text("l0 = 0.3\n")
    monkeypatch.setattr(sys, "stdout", _FullStream())
    status, _, err = cli(
        capsys, "optimize", "--spec", spec, "-o", earlier, "--scheduler", scheduler
    )
    assert status == 2
    assert err == "prp3 optimize: error: standard output: No space left on device\n"
    assert sorted(p.name for p in earlier.iterdir()) == ["ROBOT.toml"]
    assert (earlier / "ROBOT.toml").read_text() == "l0 = 0.3\n"


def test_plots_from_the_designs_file(tmp_path, capsys, scheduler):
    spec = write(tmp_path / "sweep.toml", LHS)
    status, _out, err = cli(
        capsys, "sweep", "--spec", spec, "-o", tmp_path / "s", "--scheduler", scheduler,
        "--plots", "--pareto", "workspace_area,peak_f21:min",
    )  # fmt: skip
    assert status == 0, err
    from PIL import Image

    for name in ("pareto.png", "sensitivity.png"):
        with Image.open(tmp_path / "s" / name) as image:
            assert image.size[0] > 400
    status, _out, err = cli(
        capsys, "sweep", "--spec", spec, "-o", tmp_path / "s", "--plots", "--pareto", "energy,bogus"
    )
    assert status == 2 and "unknown column 'bogus'" in err


def test_without_the_design_extra_the_commands_say_what_to_install(tmp_path, capsys, monkeypatch):
    import importlib.util

    import prp3.cli.design

    real = importlib.util.find_spec
    monkeypatch.setattr(
        prp3.cli.design.importlib.util,
        "find_spec",
        lambda name, *a: None if name == "distributed" else real(name, *a),
    )
    spec = write(tmp_path / "sweep.toml", GRID)
    for command in ("sweep", "optimize"):
        status, out, err = cli(capsys, command, "--spec", spec, "-o", tmp_path / "out")
        assert (status, out) == (2, "")
        assert err == (
            f"prp3 {command}: error: design studies need distributed: pip install 'prp3[design]'\n"
        )


def test_workers_and_scheduler_are_exclusive_and_bounded(tmp_path, capsys):
    spec = write(tmp_path / "sweep.toml", GRID)
    for extra in (("--workers", 2, "--scheduler", "tcp://h:1"), ("--workers", 0)):
        status, _out, err = cli(capsys, "sweep", "--spec", spec, "-o", tmp_path / "o", *extra)
        assert status == 2 and len(err.splitlines()) == 1 and "--workers" in err


def test_a_positions_only_trajectory_is_a_warning(tmp_path, capsys):
    t = np.linspace(0.0, 1.0, 21)
    lines = ["t,x,y,phi"] + [f"{float(a)!r},0.0,{0.01 * float(a)!r},0.0" for a in t]
    write(tmp_path / "lift.csv", "\n".join(lines) + "\n")
    spec = sweep_spec(
        {"designs": 2, "parameters": {"l0": [0.2, 0.4]}, "task": {"motions": ["lift.csv"]}},
        base=tmp_path,
    )
    assert len(spec.notes) == 1 and "positions only" in spec.notes[0]
    assert spec.evaluator.motions[0].samples == 21


def test_a_parquet_file_of_something_else_is_refused(tmp_path):
    pq.write_table(pa.table({"x": [1.0]}), tmp_path / "other.parquet")
    with pytest.raises(prp3.InputFileError, match="not a designs file of prp3 sweep"):
        prp3.apps.sweep.read_designs(tmp_path / "other.parquet")
    (tmp_path / "text.parquet").write_text("not parquet")
    with pytest.raises(prp3.InputFileError, match="cannot read a Parquet file"):
        prp3.apps.sweep.read_designs(tmp_path / "text.parquet")


def test_rows_are_the_batch_kernel_of_each_design_bit_for_bit():
    # evaluate_designs runs prp3.mechanics.kernel.solve on a block of designs; paper_forces one robot
    spec = sweep_spec(
        {
            "designs": 7,
            "seed": 5,
            "parameters": {
                "l0": [0.2, 0.4],
                "link.com.0": [-0.02, 0.02],
                "piston.com.1": [-0.01, 0.01],
                "gravity.0": [-1.0, 1.0],
            },
            "task": {"motions": ["vertical", "rotation"], "samples": 31},
        }
    )
    values = design_values(spec)
    columns = evaluate_designs(spec.evaluator, values)
    motions = [prp3.paper_motion(m, 31) for m in ("vertical", "rotation")]
    for k in range(len(values)):
        robot = design_robot(spec.evaluator.nominal, spec.paths, values[k].tolist())
        forces = [
            prp3.paper_forces(robot, m.pose, m.velocity, m.acceleration, reactions=True)
            for m in motions
        ]
        for leg, j in zip(LEGS, range(3), strict=True):
            f10 = max(np.abs(f.f10[:, j]).max() for f in forces)
            f21 = max(np.sqrt(f.f21y[:, j] ** 2 + f.f21z[:, j] ** 2).max() for f in forces)
            n32 = max(np.abs(f.n32[:, j]).max() for f in forces)
            assert columns[f"peak_f10_{leg}"][k] == f10
            assert columns[f"peak_f21_{leg}"][k] == f21
            assert columns[f"peak_n32_{leg}"][k] == n32


@pytest.mark.parametrize(
    ("parameters", "robot"),
    [
        ({"payload.mass": [0.0, 1.0], "load.moment": [-1.0, 1.0]}, ""),
        (
            {"l0": [0.25, 0.35]},
            "[friction.sleeve]\nviscous = 2.0\ncoulomb = 0.5\nsmoothing = 0.01\n",
        ),
        ({"friction.sleeve.mu": [0.2, 0.5]}, "[friction.sleeve]\ncoulomb = 0.5\n"),
        ({"friction.actuator.viscous": [0.0, 2.0], "l0": [0.25, 0.35]}, ""),  # no [friction]
        (  # the spring's element: its fields broadcast over the designs of one kernel call
            {"spring.actuator.stiffness": [0.0, 800.0], "spring.actuator.rest": [-0.02, 0.02]},
            "[spring.actuator]\ndamping = 3.0\n",
        ),
        ({"spring.actuator.damping": [0.0, 5.0]}, ""),  # no [spring]
    ],
)
def test_loads_and_friction_are_parameters_too(tmp_path, parameters, robot):
    # a design whose friction locks is 'unreachable', where paper_forces refuses the motion
    write(tmp_path / "robot.toml", robot)
    data = {"robot": "robot.toml", "designs": 5, "seed": 2, "parameters": parameters}
    spec = sweep_spec(
        data | {"task": {"motions": ["vertical", "rotation"], "samples": 41}}, base=tmp_path
    )
    values = design_values(spec)
    columns = evaluate_designs(spec.evaluator, values)
    motions = [prp3.paper_motion(m, 41) for m in ("vertical", "rotation")]
    for k in range(len(values)):
        robot_k = design_robot(spec.evaluator.nominal, spec.paths, values[k].tolist())
        try:
            forces = [
                prp3.paper_forces(robot_k, m.pose, m.velocity, m.acceleration, reactions=True)
                for m in motions
            ]
        except prp3.TrajectoryError as error:
            assert "locks" in str(error)
            assert columns["status"][k] == "unreachable" and math.isnan(columns["energy"][k])
            continue
        assert columns["status"][k] == "ok"
        for j, leg in enumerate(LEGS):
            assert columns[f"peak_f10_{leg}"][k] == max(np.abs(f.f10[:, j]).max() for f in forces)
            assert columns[f"peak_n32_{leg}"][k] == max(np.abs(f.n32[:, j]).max() for f in forces)
    if "friction.sleeve.mu" in parameters:
        assert set(columns["status"]) == {"ok", "unreachable"}


def test_designs_in_a_box_of_valid_robots_are_not_built_one_by_one(monkeypatch):
    # the kernel's parameters of the designs come from kernel_parameters traced over their
    # values, the kernel from one trace per process: no robot and no solve per design
    spec = sweep_spec(
        {
            "designs": 40,
            "seed": 3,
            "parameters": {"l0": [0.25, 0.35], "link.mass": [0.5, 1.0], "payload.mass": [0, 1]},
            "task": {"motions": ["vertical", "rotation"], "samples": 31},
        }
    )
    values = design_values(spec)
    expected = evaluate_designs(spec.evaluator, values)  # traces what it needs
    built, solved = [], []
    real_from_mapping, real_solve = (
        prp3.Robot.from_mapping.__func__,
        prp3.apps.design_evaluation.solve,
    )
    monkeypatch.setattr(
        prp3.Robot, "from_mapping", classmethod(lambda cls, m: built.append(m) or
                                               real_from_mapping(cls, m))
    )  # fmt: skip
    monkeypatch.setattr(
        prp3.apps.design_evaluation,
        "solve",
        lambda *a, **k: solved.append(1) or real_solve(*a, **k),
    )
    columns = evaluate_designs(spec.evaluator, values)
    assert (built, solved) == ([], [])
    for name, column in expected.items():
        assert np.array_equal(column, columns[name]), name
    # a design outside the box is built and checked, and refused by name
    outside = values[:2].copy()
    outside[1, 1] = -1.0
    with pytest.raises(prp3.ParameterError, match=r"design l0 = .*link.mass = -1.0.*link.mass"):
        evaluate_designs(spec.evaluator, outside)
    assert len(built) == 2


@pytest.mark.parametrize(
    "paths",
    [
        {"l0": [0.2, 0.4], "platform.mass": [2.0, 4.0], "link.com.0": [-0.02, 0.02]},
        {"platform.inertia": [0.05, 0.1], "piston.com.1": [-0.01, 0.01], "gravity.0": [-1, 1]},
        {"payload.mass": [0.0, 1.0], "payload.com.1": [0.0, 0.02], "load.force.0": [-5, 5]},
        {"friction.actuator.viscous": [0.0, 2.0], "link.inertia": [1e-4, 1e-3]},
        {"spring.actuator.stiffness": [0.0, 800.0], "spring.actuator.damping": [0.0, 5.0]},
    ],
)
def test_traced_parameters_of_designs_are_kernel_parameters_of_their_robots(tmp_path, paths):
    # a nominal robot with friction and a payload, so that every table can be swept
    write(
        tmp_path / "robot.toml",
        "[friction.actuator]\ncoulomb = 0.5\n[payload]\nmass = 0.5\n[load]\nforce = [1.0, 0.0]\n"
        "[spring.actuator]\nrest = 0.01\n",
    )
    spec = sweep_spec(
        {"robot": "robot.toml", "designs": 9, "seed": 1, "parameters": paths,
         "task": {"motions": ["rotation"]}},
        base=tmp_path,
    )  # fmt: skip
    evaluator, values = spec.evaluator, design_values(spec)
    fixed, columns, lower, upper = prp3.apps.design_evaluation.design_parameter_columns(
        evaluator, values, None
    )
    assert set(columns) and np.isneginf(lower).all() and np.isposinf(upper).all()
    for k, row in enumerate(values.tolist()):
        expected = kernel_parameters(design_robot(evaluator.nominal, spec.paths, row))
        for name in prp3.apps.design_evaluation.PARAMETER_FIELDS:
            got = fixed[name] if name in fixed else columns[name][k]
            assert got == getattr(expected, name), (name, k)


def test_optimize_sends_its_objective_to_the_workers_once(scheduler, monkeypatch):
    from dask.distributed import Client, Future

    spec = sweep_spec(
        {
            "seed": 4,
            "parameters": {"link.mass": [0.3, 1.0], "platform.mass": [2.0, 4.0]},
            "task": {"motions": ["vertical"], "samples": 21},
            "optimize": {"objective": "peak_f10", "maxiter": 3, "popsize": 3},
        }
    )
    with Client(scheduler, set_as_default=False) as client:
        scattered, submitted = [], []
        real_scatter, real_submit = client.scatter, client.submit

        def scatter(data, **options):
            scattered.append(data)
            return real_scatter(data, **options)

        def submit(function, *args, **options):
            submitted.append(args)
            return real_submit(function, *args, **options)

        monkeypatch.setattr(client, "scatter", scatter)
        monkeypatch.setattr(client, "submit", submit)
        outcome = prp3.apps.optimization.optimize_design(spec, client)
    assert len(scattered) == 1 and isinstance(
        scattered[0], prp3.apps.design_objective.DesignObjective
    )
    assert outcome.generations >= 2 and len(submitted) > outcome.generations
    assert all(isinstance(args[0], Future) for args in submitted)
    assert len({args[0].key for args in submitted}) == 1  # every generation: the same copy
    # evaluated together, each member has the value it has alone
    objective = scattered[0]
    xs = design_values(spec)[:6]
    assert objective.many(xs).tolist() == [objective(x) for x in xs]


def test_a_finished_sweep_leaves_no_staging_folder_of_its_own_or_of_other_specs(
    tmp_path, capsys, scheduler, monkeypatch
):
    old = write(tmp_path / "old.toml", LHS)
    new = write(tmp_path / "new.toml", LHS.replace("seed = 7", "seed = 8"))
    out = tmp_path / "study"
    mine = out / ".prp3-sweep-notes"  # not a staging folder: never touched
    mine.mkdir(parents=True)
    # the sweep of old.toml interrupted after two of its four chunks
    interrupted_sweep(capsys, monkeypatch, ("sweep", "--spec", old, "--scheduler", scheduler), out)
    (stale,) = [p for p in out.glob(".prp3-sweep-*") if p != mine]
    # its spec changed: a new sweep into the same folder says what it will remove, then does
    status, text, err = cli(capsys, "sweep", "--spec", new, "-o", out, "--scheduler", scheduler)
    assert status == 0, err
    described = f"{stale} (2 of 4 chunks of {old})"
    assert err == (
        f"prp3 sweep: warning: {described}: an unfinished sweep of another spec; it is "
        "removed when this sweep finishes (resume it first to keep it)\n"
    )
    assert f"  removed {described}: superseded by this sweep" in text
    assert sorted(out.iterdir()) == [out / ".prp3-manifest.json", mine, out / "designs.parquet"]
    # a finished sweep whose own staging folder was left (stopped before removing it)
    staging = prp3.apps.sweep.staging_folder(out, read_sweep_spec(new))
    staging.mkdir()
    status, text, err = cli(capsys, "sweep", "--spec", new, "-o", out, "--scheduler", scheduler)
    assert (status, err) == (0, "") and "0 of 4 chunks computed" in text
    assert sorted(out.iterdir()) == [out / ".prp3-manifest.json", mine, out / "designs.parquet"]


# ---------------------------------------------------------------- the output folder
def test_a_folder_of_another_spec_is_refused_unless_forced_and_stale_figures_go(
    tmp_path, capsys, scheduler
):
    # was: designs.parquet of another spec replaced silently, pareto.png and
    # sensitivity.png of the old sweep left beside it, and no manifest
    import hashlib
    import json

    old = write(tmp_path / "old.toml", GRID)
    new = write(tmp_path / "new.toml", GRID.replace("[2.0, 4.0]", "[2.0, 5.0]"))
    out = tmp_path / "study"
    run = ("-o", out, "--scheduler", scheduler)
    assert cli(capsys, "sweep", "--spec", old, *run, "--plots")[0] == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == [".prp3-manifest.json", "designs.parquet", "pareto.png", "sensitivity.png"]
    record = json.loads((out / ".prp3-manifest.json").read_text())["commands"]["sweep"]
    assert sorted(record["files"]) == ["designs.parquet", "pareto.png", "sensitivity.png"]
    assert record["inputs"] == [
        {"path": str(old), "size": old.stat().st_size,
         "sha256": hashlib.sha256(old.read_bytes()).hexdigest()}
    ]  # fmt: skip
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    status, text, err = cli(capsys, "sweep", "--spec", new, *run)
    assert (status, text) == (2, "")
    assert err == (
        f"prp3 sweep: error: {out / 'designs.parquet'}: holds the designs of another sweep "
        f"({old}); choose another output directory, or replace it (--force, force=True)\n"
    )
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    # the same spec again, without --plots: its own figures of the last run go
    status, text, err = cli(capsys, "sweep", "--spec", old, *run)
    assert status == 0 and "0 of 1 chunks computed" in text
    assert err.startswith("prp3 sweep: note: removed 2 files that the last `prp3 sweep` wrote")
    assert sorted(p.name for p in out.iterdir()) == [".prp3-manifest.json", "designs.parquet"]
    # forced: replaced, and the manifest says by which spec
    status, text, err = cli(capsys, "sweep", "--spec", new, *run, "--force")
    assert (status, err) == (0, ""), err
    assert prp3.apps.sweep.read_designs(out / "designs.parquet").columns["platform.mass"].tolist() == [
        2.0, 3.5, 5.0
    ]  # fmt: skip
    record = json.loads((out / ".prp3-manifest.json").read_text())["commands"]["sweep"]
    assert record["inputs"][0]["path"] == str(new) and "--force" in record["command_line"]
    # a designs.parquet prp3 did not write is not replaced either
    other = tmp_path / "other"
    other.mkdir()
    (other / "designs.parquet").write_bytes(b"mine")
    status, _, err = cli(capsys, "sweep", "--spec", old, "-o", other, "--scheduler", scheduler)
    assert status == 2 and "is not a designs file of prp3 sweep" in err
    assert (other / "designs.parquet").read_bytes() == b"mine"


def test_a_truncated_designs_file_is_named_truncated(tmp_path, capsys, scheduler):
    # was: "is not a designs file of prp3 sweep" for the designs of the same spec cut short
    spec = write(tmp_path / "grid.toml", GRID)
    out = tmp_path / "study"
    run = ("sweep", "--spec", spec, "-o", out, "--scheduler", scheduler)
    assert cli(capsys, *run)[0] == 0
    target = out / "designs.parquet"
    whole = target.read_bytes()
    rows = prp3.apps.sweep.read_designs(target).columns
    for size in (0, 3, 4, 100, len(whole) // 2, len(whole) - 1):
        target.write_bytes(whole[:size])
        with pytest.raises(prp3.InputFileError) as info:
            prp3.apps.sweep.read_designs(target)
        message = str(info.value)
        assert message.startswith(f"{target}: truncated: a Parquet file cut short ({size} bytes")
        assert "\n" not in message
    status, out_text, err = cli(capsys, *run)
    assert (status, out_text) == (2, "")
    assert err.startswith(
        f"prp3 sweep: error: {target}: truncated: a Parquet file cut short ({len(whole) - 1} bytes"
    )
    assert "cannot be told" in err and "--force" in err and err.count("\n") == 1
    assert target.read_bytes() == whole[:-1]  # left as it was
    # recomputed when forced: the same designs
    assert cli(capsys, *run, "--force")[0] == 0
    again = prp3.apps.sweep.read_designs(target).columns
    assert again.keys() == rows.keys()
    for name in rows:
        assert np.array_equal(again[name], rows[name]), name
    # a file that is not Parquet at all is still called so
    target.write_bytes(b"mine, not a Parquet file")
    status, _, err = cli(capsys, *run)
    assert status == 2 and "is not a designs file of prp3 sweep" in err


def test_a_parameter_given_twice_in_the_spec_is_refused(tmp_path, capsys):
    # the same key quoted and bare: tomllib refuses it, named by prp3 with the key and its table
    twice = write(
        tmp_path / "quoted.toml",
        'designs = 3\n[parameters]\n"l0" = [0.25, 0.35]\nl0 = [0.2, 0.3]\n',
    )
    status, _, err = cli(capsys, "sweep", "--spec", twice, "-o", tmp_path / "a", "--workers", "1")
    assert status == 2 and err.count("\n") == 1
    assert f"{twice}:4:" in err and "the key 'l0' of [parameters] is set twice" in err
    # a quoted key with a dot and a dotted key (or a table): two TOML keys, one parameter
    for text in (
        '"platform.mass" = [2.0, 4.0]\nplatform.mass = [2.0, 5.0]\n',
        'platform.mass = [2.0, 4.0]\n"platform.mass" = [2.0, 5.0]\n',
        '"platform.mass" = [2.0, 4.0]\n[parameters.platform]\nmass = [2.0, 5.0]\n',
    ):
        spec = write(tmp_path / "dotted.toml", f"designs = 3\n[parameters]\n{text}")
        status, _, err = cli(
            capsys, "sweep", "--spec", spec, "-o", tmp_path / "b", "--workers", "1"
        )
        assert status == 2 and err.count("\n") == 1, text
        assert f"{spec}: [parameters] 'platform.mass' is given twice" in err, err
        assert not (tmp_path / "b").exists()
        with pytest.raises(prp3.ParameterError, match=r"'platform\.mass' is given twice"):
            read_sweep_spec(spec)


def test_run_sweep_and_optimize_take_a_client_or_a_factory(tmp_path, scheduler):
    from dask.distributed import Client

    spec = sweep_spec(
        {
            "designs": 3,
            "sampling": "grid",
            "parameters": {"platform.mass": [2.0, 4.0]},
            "task": {"motions": ["vertical"], "samples": 21},
            "optimize": {"objective": "peak_f10", "maxiter": 2, "popsize": 3},
        }
    )
    files = []
    with Client(scheduler, set_as_default=False) as client:
        for k, given_ in enumerate((client, lambda: Client(scheduler, set_as_default=False))):
            run = prp3.apps.sweep.run_sweep(spec, tmp_path / f"s{k}", given_)
            files.append(run.path.read_bytes())
        assert client.status == "running"  # a client given is left open
        outcomes = []
        for given_ in (client, lambda: prp3.apps.cluster.dask_client(scheduler=scheduler)):
            reports: list[tuple[int, int]] = []
            outcome = prp3.apps.optimization.optimize_design(
                spec, given_, progress=lambda done, total, seen=reports: seen.append((done, total))
            )
            outcomes.append(outcome)
            # one report per generation (the initial population is the first), then the end
            assert reports[-1] == (3, 3) and len(reports) == outcome.generations + 2
            assert [done for done, _ in reports[:-1]] == list(range(1, outcome.generations + 2))
        assert client.status == "running"
    assert files[0] == files[1]
    assert outcomes[0].x.tolist() == outcomes[1].x.tolist()
    for bad in (42, lambda: 42):
        with pytest.raises(prp3.errors.ParameterError, match="client"):
            prp3.apps.optimization.optimize_design(spec, bad)


def test_sweep_and_optimize_draw_a_bar_on_a_terminal(tmp_path, monkeypatch, scheduler):
    import io

    import prp3.cli._progress
    from prp3.cli import main

    class FakeTerminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    monkeypatch.setattr(prp3.cli._progress, "DELAY", 0.0)
    spec = write(
        tmp_path / "synthesis.toml",
        GRID.replace("[task]", '[optimize]\nobjective = "peak_f10"\nmaxiter = 2\npopsize = 3\n'
                     '[task]').replace('motions = ["vertical", "rotation"]',
                                       'motions = ["vertical"]\nsamples = 21'),
    )  # fmt: skip
    for command, stage in (("sweep", "designs"), ("optimize", "generations")):
        stream = FakeTerminal()
        monkeypatch.setattr(sys, "stderr", stream)
        status = main([command, "--spec", str(spec), "-o", str(tmp_path / command),
                       "--scheduler", scheduler])  # fmt: skip
        monkeypatch.setattr(sys, "stderr", sys.__stderr__)
        assert status in (0, 1), stream.getvalue()
        text = stream.getvalue()
        assert f"\r{stage}: 100%|" in text, text
