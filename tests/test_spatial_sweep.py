"""``prp3 sweep`` / ``prp3 optimize`` of the spatial robots (docs/spatial.md §21).

The expected objective columns are rebuilt here from ``prp3.spatial_inverse_dynamics``
of the same design, built by ``prp3.spatial_robot_from_mapping`` from a mapping written
here (not by the sweep's key paths); the reachable fraction from the refusals of
``prp3.spatial_kinematics`` sample by sample.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("distributed")
pq = pytest.importorskip("pyarrow.parquet")

import prp3  # noqa: E402
import prp3.apps.cluster  # noqa: E402
import prp3.apps.sweep  # noqa: E402
from clitools import cli, one_line  # noqa: E402
from prp3.apps.spatial_design import (  # noqa: E402
    SPATIAL_DESIGN_COLUMNS,
    read_spatial_sweep_spec,
    spatial_sweep_spec,
)
from sweeptools import interrupted_sweep, write  # noqa: E402

#: The built-in motions each architecture can make.
MOTIONS = {"6-UPS": ("heave", "circle", "tilt"), "3-RPS": ("heave", "tilt"),
           "3-RUU": ("heave", "circle")}  # fmt: skip


def expected_row(mapping: dict, motion: str, samples: int) -> dict[str, float]:
    """The objective columns of the robot of ``mapping``, from its inverse dynamics."""
    robot = prp3.spatial_robot_from_mapping(mapping).robot
    home = prp3.PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    at_home = prp3.spatial_kinematics(robot, home)
    sign_leg, sign_par = np.sign(at_home.leg_measure[0]), np.sign(at_home.parallel_measure[0])
    given_motion = prp3.spatial_motion(robot, motion, samples, 3.0)
    solution = prp3.spatial_inverse_dynamics(robot, prp3.complete_motion(robot, given_motion))
    power = solution.power
    return {
        "peak_effort": float(np.abs(solution.tau).max()),
        "peak_power": float(np.abs(power).max()),
        "rms_power": float(np.sqrt(np.mean(power**2))),
        "energy": float(np.trapezoid(power.sum(axis=-1), solution.t)),
        "peak_joint_force": float(np.linalg.norm(solution.force, axis=-1).max()),
        "peak_joint_moment": float(np.linalg.norm(solution.moment, axis=-1).max()),
        "min_mu_leg": float((solution.kinematics.leg_measure * sign_leg).min()),
        "min_mu_par": float((solution.kinematics.parallel_measure * sign_par).min()),
        "reachable": 1.0,
    }


@settings(max_examples=6, deadline=None)
@given(
    architecture=st.sampled_from(sorted(MOTIONS)),
    scale=st.floats(0.9, 1.1),
    mass=st.floats(0.1, 3.0),
    motion_index=st.integers(0, 2),
    samples=st.integers(5, 15),
)
def test_objective_columns_are_those_of_the_designs_inverse_dynamics(
    architecture, scale, mass, motion_index, samples
):
    motions = MOTIONS[architecture]
    motion = motions[motion_index % len(motions)]
    radius = 0.1 * scale
    spec = spatial_sweep_spec(
        {
            "spatial": architecture,
            "sampling": "random",
            "designs": 1,
            "parameters": {"base_radius": [radius, radius * 1.0001], "platform.mass": [mass, mass + 0.5]},
            "task": {"motions": [motion], "samples": samples},
        }
    )  # fmt: skip
    values = spec.design_values()
    columns = spec.evaluator.evaluate(values)
    assert str(columns["status"][0]) == "ok"
    assert str(columns["architecture"][0]) == architecture
    r, m = float(values[0, 1]), float(values[0, 2])
    assert (columns["base_radius"][0], columns["platform.mass"][0]) == (r, m)
    mapping = {"architecture": architecture, "base_radius": r, "platform": {"mass": m}}
    expected = expected_row(mapping, motion, samples)
    assert {name: float(columns[name][0]) for name in SPATIAL_DESIGN_COLUMNS} == expected


def test_a_comparison_evaluates_every_robot_at_the_same_designs_and_a_file(tmp_path):
    write(tmp_path / "hexapod.toml", 'architecture = "6-UPS"\nhome_height = 0.09\n')
    spec = spatial_sweep_spec(
        {
            "spatial": ["hexapod.toml", "3-RPS", "3-RUU"],
            "designs": 2,
            "sampling": "grid",
            "parameters": {"platform.mass": [0.5, 1.5], "stroke.1": [0.125, 0.2]},
            "task": {"motions": ["heave"], "samples": 7},
        },
        base=tmp_path,
    )
    values = spec.design_values()
    assert spec.count == len(values) == 3 * 4  # row k of every robot: the same design
    columns = spec.evaluator.evaluate(values)
    assert [str(r) for r in columns["robot"]] == ["hexapod.toml"] * 4 + ["3-RPS"] * 4 + [
        "3-RUU"
    ] * 4
    assert np.isnan(columns["stroke.1"][8:]).all()  # the Delta has no stroke
    assert np.array_equal(columns["platform.mass"][:4], columns["platform.mass"][8:])
    assert spec.files == (tmp_path / "hexapod.toml",)
    for k in (0, 3, 5, 9):
        mapping = {"architecture": str(columns["architecture"][k]), "platform": {"mass": columns["platform.mass"][k]}}  # fmt: skip
        if k < 8:
            mapping["stroke"] = [0.085 if k < 4 else 0.06, float(columns["stroke.1"][k])]
        if k < 4:
            mapping["home_height"] = 0.09
        row = {name: float(columns[name][k]) for name in SPATIAL_DESIGN_COLUMNS}
        assert row == expected_row(mapping, "heave", 7), k


def test_an_unreachable_design_gives_its_status_and_the_fraction_of_samples_it_reaches():
    # a short stroke: the hexapod's heave leaves it at the top of the motion
    spec = spatial_sweep_spec(
        {
            "spatial": "6-UPS",
            "designs": 1,
            "sampling": "random",
            "parameters": {"stroke.1": [0.105, 0.10501]},
            "task": {"motions": ["heave"], "samples": 21},
        }
    )
    values = spec.design_values()
    columns = spec.evaluator.evaluate(values)
    assert str(columns["status"][0]) == "unreachable"
    assert all(math.isnan(columns[name][0]) for name in SPATIAL_DESIGN_COLUMNS[:-1])
    robot = prp3.spatial_robot_from_mapping(
        {"architecture": "6-UPS", "stroke": [0.085, float(values[0, 1])]}
    ).robot
    motion = prp3.spatial_motion(robot, "heave", 21, 3.0)
    reached = 0
    for k in range(len(motion)):
        try:
            prp3.spatial_kinematics(robot, motion.chunk(k, k + 1))
            reached += 1
        except (prp3.UnreachablePoseError, prp3.SingularPoseError):
            pass
    assert 0 < reached < 21
    assert columns["reachable"][0] == reached / 21


SPEC = """\
spatial = ["6-UPS", "3-RUU"]
designs = 7
chunk = 3
sampling = "lhs"
seed = 3
[parameters]
"platform.mass" = [0.5, 2.0]
base_radius = [0.09, 0.11]
[task]
motions = ["heave"]
samples = 9
[optimize]
maxiter = 2
popsize = 2
"""


def test_sweep_resumes_after_an_interruption_to_the_same_table(
    tmp_path, capsys, scheduler, monkeypatch
):
    spec = write(tmp_path / "spatial.toml", SPEC)
    args = ("sweep", "--spec", spec, "--scheduler", scheduler)
    status, out, err = cli(capsys, *args, "-o", tmp_path / "whole")
    assert status == 0, err
    assert "14 designs of 6-UPS, 3-RUU (lhs, 2 parameters) on heave: 14 ok" in out
    assert "5 of 5 chunks computed" in out
    whole = (tmp_path / "whole" / "designs.parquet").read_bytes()

    interrupted_sweep(capsys, monkeypatch, args, tmp_path / "cut")
    status, out, err = cli(capsys, *args, "-o", tmp_path / "cut")
    assert status == 0, err
    assert "3 of 5 chunks computed, 2 found done" in out
    assert (tmp_path / "cut" / "designs.parquet").read_bytes() == whole
    assert (tmp_path / "cut" / ".prp3-manifest.json").is_file()

    table = prp3.read_designs(tmp_path / "cut" / "designs.parquet")
    read = read_spatial_sweep_spec(spec)
    assert table.parameters == ("platform.mass", "base_radius")
    assert table.digest == read.digest()
    assert np.array_equal(
        np.column_stack([table.columns[p] for p in table.parameters]), read.design_values()[:, 1:]
    )
    again = read.evaluator.evaluate(read.design_values())
    for name in read.evaluator.columns:
        assert np.array_equal(np.asarray(table.columns[name]), np.asarray(again[name])), name


def test_optimize_finds_a_feasible_design_of_each_robot_and_writes_the_best(
    tmp_path, capsys, scheduler
):
    spec = write(tmp_path / "spatial.toml", SPEC)
    status, out, err = cli(
        capsys, "optimize", "--spec", spec, "-o", tmp_path / "best", "--scheduler", scheduler
    )
    assert status == 0, err
    assert "minimise peak_effort for 2 spatial robots" in out
    assert "compare like with like" in out  # N of the hexapod, N·m of the Delta
    best = prp3.read_spatial_robot(tmp_path / "best" / "ROBOT.toml")
    assert best.architecture == "3-RUU"
    history = (tmp_path / "best" / "history.csv").read_text().splitlines()
    assert history[0] == "robot,generation,platform.mass,base_radius,objective,violation"
    # the written robot's peak effort, from its own inverse dynamics, is the one reported
    quoted = float(out.split("best: 3-RUU (peak_effort = ")[1].split(")")[0])
    mapping = {"architecture": "3-RUU", "base_radius": best.parameters["base_radius"],
               "platform": {"mass": best.parameters["platform"].mass}}  # fmt: skip
    assert expected_row(mapping, "heave", 9)["peak_effort"] == pytest.approx(quoted, rel=1e-8)


def test_optimize_refuses_designs_that_cannot_do_the_task_and_says_why(tmp_path, capsys, scheduler):
    text = """\
spatial = "6-UPS"
[parameters]
"stroke.1" = [0.104, 0.106]
[task]
motions = ["heave"]
samples = 9
[optimize]
maxiter = 1
popsize = 2
"""
    spec = write(tmp_path / "short.toml", text)
    status, out, err = cli(
        capsys, "optimize", "--spec", spec, "-o", tmp_path / "best", "--scheduler", scheduler
    )
    assert status == 1, err
    assert "no design satisfies the constraints and the task" in out
    assert "status unreachable" in out
    counted = re.search(r"(\d+) designs \([^)]*\); (\d+) refused", out)
    assert counted is not None and counted[1] == counted[2], out  # every one of them


@pytest.mark.parametrize(
    ("text", "named"),
    [
        ('spatial = "6-UPS"\nbogus = 1\n', "unknown key 'bogus'"),
        ('spatial = "6-UPX"\n', "spatial '6-UPX'"),
        ('spatial = "6-UPS"\n[parameters]\nbase_radiu = [0.1, 0.2]\n', "'base_radiu': not a key path"),
        ('spatial = "6-UPS"\n[parameters]\nbase_radius = [0.2, 0.1]\n', "'base_radius': low must be below high"),
        ('spatial = "6-UPS"\n[parameters]\n"platform.mass" = [-1.0, 1.0]\n', "'platform.mass' = -1.0"),
        ('spatial = "3-RUU"\n[task]\nmotions = ["tilt"]\n', "task.motions 'tilt' for 3-RUU"),
        ('spatial = "6-UPS"\n[task]\nmotion = "heave"\n', "unknown key task.'motion'"),
        ('spatial = "6-UPS"\n[optimize]\nobjective = "peak_f10"\n', "unknown quantity 'peak_f10'"),
        ('spatial = "6-UPS"\n[task]\nmotions = ["missing.csv"]\n', "task.motions 'missing.csv'"),
    ],
)  # fmt: skip
def test_a_bad_spec_is_one_line_naming_the_key(tmp_path, capsys, text, named):
    spec = write(tmp_path / "bad.toml", text)
    for command in ("sweep", "optimize"):
        status, _, err = cli(capsys, command, "--spec", spec, "-o", tmp_path / "out")
        assert status == 2, (command, err)
        line = one_line(err)
        assert named in line and "bad.toml" in line, line
        assert not (tmp_path / "out").exists()
