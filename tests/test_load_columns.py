"""The load columns ``fx, fy, mz`` of a trajectory: used by every command, or refused by name.

``simulate`` and ``forward`` use them (tests/test_forward_load_columns.py);
``sweep`` and ``optimize`` add them to the forces of every design, ``identify``
subtracts them as known forces, ``control`` refuses them (neither its
controller's model nor its plants apply a time-varying load).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from clitools import cli, one_line
from prp3 import Robot
from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.apps.control import control_times, hermite_reference
from prp3.apps.design import DesignEvaluator
from prp3.apps.design_evaluation import evaluate_designs
from prp3.apps.excitation import FourierSeries
from prp3.errors import TrajectoryError
from prp3.model.motion import Motion, paper_motion

LOAD = np.array([3.0, -2.0, 0.4])  # N, N, N·m


def loaded(motion: Motion, scale: float = 1.0) -> Motion:
    """``motion`` with a time-varying load ``LOAD·(1 + sin t)`` at every sample."""
    wave = 1.0 + np.sin(motion.t)[:, None]
    return Motion(t=motion.t, pose=motion.pose, velocity=motion.velocity,
                  acceleration=motion.acceleration, load=scale * LOAD * wave)  # fmt: skip


def write(path: Path, motion: Motion, f10: np.ndarray | None = None) -> Path:
    columns = {"t": motion.t, **dict(zip(("x", "y", "phi"), motion.pose.T, strict=True))}
    columns |= dict(zip(("dx", "dy", "dphi"), motion.velocity.T, strict=True))
    columns |= dict(zip(("ddx", "ddy", "ddphi"), motion.acceleration.T, strict=True))
    if motion.load is not None:
        columns |= dict(zip(("fx", "fy", "mz"), motion.load.T, strict=True))
    if f10 is not None:
        columns |= {f"f10_{leg}": f10[:, k] for k, leg in enumerate("ABC")}
    rows = np.column_stack(list(columns.values())).tolist()
    path.write_text(",".join(columns) + "\n" + "".join(",".join(map(repr, r)) + "\n" for r in rows))
    return path


# ------------------------------------------------------------------ sweep
def test_the_design_kernel_adds_the_trajectory_load() -> None:
    motion = loaded(paper_motion("vertical", 31))
    evaluator = DesignEvaluator(nominal={}, paths=("l0",), motions=(motion,), workspace=False)
    table = evaluate_designs(evaluator, np.array([[0.3], [0.25]]))
    for k, l0 in enumerate((0.3, 0.25)):
        robot = Robot.from_mapping({"l0": l0})
        dyn = inverse_dynamics(robot, motion, method="newton-euler")[1]  # independent
        got = [table[f"peak_f10_{leg}"][k] for leg in "ABC"]
        np.testing.assert_allclose(got, np.abs(dyn.f10).max(axis=0), rtol=1e-12)
    # and the load changes them: without it the peaks differ
    bare = inverse_dynamics(Robot(), paper_motion("vertical", 31))[1]
    got = np.array([table[f"peak_f10_{leg}"][0] for leg in "ABC"])
    assert np.abs(np.abs(bare.f10).max(axis=0) - got).max() > 0.1


@pytest.mark.slow  # a design sweep on a LocalCluster
def test_sweep_uses_the_load_columns(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    motion = loaded(paper_motion("vertical", 31))
    write(tmp_path / "loaded.csv", motion)
    spec = tmp_path / "spec.toml"
    spec.write_text(
        'designs = 2\nsampling = "grid"\n[parameters]\nl0 = [0.25, 0.3]\n'
        '[task]\nmotions = ["loaded.csv"]\n'
    )
    status, _out, err = cli(capsys, "sweep", "--spec", spec, "--output", tmp_path / "o")
    assert status == 0, err
    import pyarrow.parquet as pq

    table = pq.read_table(tmp_path / "o" / "designs.parquet").to_pydict()
    for k, l0 in enumerate(table["l0"]):
        robot = Robot.from_mapping({"l0": l0})
        expected = np.abs(inverse_dynamics(robot, motion, method="paper")[1].f10).max(axis=0)
        got = [table[f"peak_f10_{leg}"][k] for leg in "ABC"]
        np.testing.assert_allclose(got, expected, rtol=1e-12)


# ------------------------------------------------------------------ control
def test_control_refuses_the_load_columns_by_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    file = write(tmp_path / "loaded.csv", loaded(paper_motion("vertical", 31)))
    status, out, err = cli(
        capsys, "control", "--controller", "computed-torque", "--plant", "prp3",
        "--trajectory", file, "--output", tmp_path / "o",
    )  # fmt: skip
    line = one_line(err)
    assert status == 2 and out == ""
    assert (
        line.startswith(f"prp3 control: error: {file}: ")
        and "fx, fy, mz" in line
        and "prp3 control" in line
    )
    assert not (tmp_path / "o").exists()


def test_the_reference_does_not_drop_a_load() -> None:
    motion = loaded(paper_motion("vertical", 31))
    with pytest.raises(TrajectoryError, match="fx, fy, mz"):
        hermite_reference(motion, control_times(0.0, 3.0, 100.0))


# ------------------------------------------------------------------ identify
def test_identify_accepts_and_subtracts_the_load_columns(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    true = Robot.from_mapping(
        {"link": {"com": [0.02, 0.01], "inertia": 1e-3}, "platform": {"mass": 2.5}}
    )
    sine = np.array([[0.06, 0.03, 0.02], [0.05, -0.04, 0.02], [0.25, 0.1, -0.08]])
    sine[:2] *= true.l0
    series = FourierSeries(4.0, np.array([0.0, 0.0, 0.05]), sine, np.roll(sine, 1, axis=1) * 0.5)
    motion = loaded(series.motion(np.linspace(0.0, 4.0, 100)), scale=5.0)
    f10 = inverse_dynamics(true, motion, method="newton-euler")[1].f10  # with the load
    file = write(tmp_path / "m.csv", motion, f10)
    status, _out, err = cli(capsys, "identify", "--measurements", file, "--output", tmp_path / "o")
    assert status == 0, err
    found = Robot.from_mapping(tomllib.loads((tmp_path / "o" / "robot.toml").read_text()))
    bare = paper_motion("rotation", 31)  # another motion, no load: the robot's own forces
    expected = inverse_dynamics(true, bare, method="newton-euler")[1].f10
    got = inverse_dynamics(found, bare)[1].f10
    assert np.abs(got - expected).max() <= 1e-8 * np.abs(expected).max()
