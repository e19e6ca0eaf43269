"""A time-varying load in the forward dynamics (``fx, fy, mz`` of a force file).

Round trips: the inverse dynamics of a motion under a time-varying load gives
the actuator forces; the forward dynamics driven by those forces and the same
load must give the motion back, to the integration tolerance with the exact
functions of time and to the spline's accuracy with samples (a results.csv of
``prp3 simulate`` of a trajectory with load columns).  Without the load the
same forces drive the platform elsewhere: the load is not ignored.
"""

from __future__ import annotations

import contextlib
import io
import math
from pathlib import Path

import numpy as np
import pytest

from prp3 import Motion, Robot, inverse_dynamics, paper_motion
from prp3.analysis.equations_of_motion import platform_dynamics
from prp3.analysis.force_histories import ActuatorForces
from prp3.analysis.forward import forward_dynamics
from prp3.cli import main
from prp3.engines.compiled_robot import compile_robot
from prp3.engines.entries import solve_batch
from prp3.errors import ParameterError
from prp3.io.forces import read_forces
from prp3.io.tables import write_table_csv
from prp3.model.motion import PAPER_MOTIONS
from prp3.model.parameters import Load, Payload

ROBOT = Robot(payload=Payload(0.5, (0.02, 0.0), 1e-3), load=Load((1.0, -2.0), 0.05))
W = math.pi / 3.0


def wrench(t: float | np.ndarray) -> np.ndarray:
    """The environment's push on the platform (N, N, N·m): smooth, several newtons."""
    t = np.asarray(t, dtype=np.float64)
    return np.stack([3.0 * np.sin(2.0 * t), -4.0 + np.cos(3.0 * t), 0.2 * t], axis=-1)


def state(name: str, t: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The paper's motion (eq. 4) at ``t``: pose, velocity, acceleration."""
    star = np.array(PAPER_MOTIONS[name])
    c, s = np.cos(W * np.asarray(t))[..., None], np.sin(W * np.asarray(t))[..., None]
    return star * (1.0 - c), star * W * s, star * W * W * c


def test_exact_forces_under_a_time_varying_load_drive_the_motion_back() -> None:
    compiled = compile_robot(ROBOT)

    def f10(t: float) -> np.ndarray:
        return solve_batch(compiled, *state("rotation", t), load=wrench(t))["f10"]

    t = np.linspace(0.0, 0.5, 6)
    pose, velocity, acceleration = state("rotation", t)
    result = forward_dynamics(
        ROBOT, f10, t, pose[0], velocity[0], rtol=1e-10, atol=1e-13, load=wrench
    )
    assert result.status == "completed", result.message
    assert np.abs(result.motion.pose - pose).max() <= 1e-8
    assert np.abs(result.motion.velocity - velocity).max() <= 1e-8
    assert np.abs(result.motion.acceleration - acceleration).max() <= 1e-6
    assert result.force_residual <= 1e-9
    assert result.motion.load is not None
    np.testing.assert_array_equal(result.motion.load, wrench(t))
    # the same forces without the load would accelerate the platform elsewhere
    eq = platform_dynamics(ROBOT, pose[0], velocity[0])
    unloaded = np.linalg.solve(eq.force_matrix, f10(0.0) - eq.force_bias)
    assert np.abs(unloaded - acceleration[0]).max() > 0.1


def test_the_load_enters_the_bias_only_by_statics() -> None:
    # virtual work at rest: Jᵀ·Δf10 + (f_x, f_y, m_z) = 0, A unchanged
    pose, velocity, push = [0.01, -0.02, 0.15], [0.02, 0.01, -0.1], np.array([2.0, -3.0, 0.3])
    bare = platform_dynamics(ROBOT, pose, velocity)
    pushed = platform_dynamics(ROBOT, pose, velocity, load=push)
    np.testing.assert_allclose(pushed.force_matrix, bare.force_matrix, atol=1e-13)
    np.testing.assert_allclose(
        pushed.force_bias - bare.force_bias,
        -np.linalg.solve(np.swapaxes(bare.jacobian, -1, -2), push),
        atol=1e-12,
    )


def test_sampled_forces_carry_their_load() -> None:
    reference = paper_motion("vertical", samples=61)[:21]  # t = 0 .. 1 s
    loaded = Motion(reference.t, reference.pose, reference.velocity, reference.acceleration,
                    load=wrench(reference.t))  # fmt: skip
    _, dyn = inverse_dynamics(ROBOT, loaded, "newton-euler")  # independent of the kernel
    forces = ActuatorForces(reference.t, dyn.f10, load=loaded.load)
    early = reference.t <= 0.5
    result = forward_dynamics(
        ROBOT, forces, reference.t[early], reference.pose[0], reference.velocity[0]
    )
    assert np.abs(result.motion.pose - reference.pose[early]).max() <= 1e-5
    np.testing.assert_allclose(result.dynamics.f10, dyn.f10[early], atol=1e-9)
    with pytest.raises(ParameterError, match="carry a load already"):
        forward_dynamics(ROBOT, forces, reference.t[:3], reference.pose[0],
                         reference.velocity[0], load=wrench)  # fmt: skip


def _cli(*args: object) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main([str(a) for a in args])
    return status, out.getvalue(), err.getvalue()


def test_a_results_csv_with_a_time_varying_load_drives_the_motion_back(tmp_path: Path) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text("[payload]\nmass = 0.5\ncom = [0.02, 0.0]\ninertia = 1e-3\n"
                     "[load]\nforce = [1.0, -2.0]\nmoment = 0.05\n")  # fmt: skip
    t = np.linspace(0.0, 1.0, 201)
    pose, velocity, acceleration = state("rotation", t)
    push = wrench(t)
    columns = {"t": t}
    for k, name in enumerate(("x", "y", "phi")):
        columns |= {name: pose[:, k], f"d{name}": velocity[:, k], f"dd{name}": acceleration[:, k]}
    columns |= {"fx": push[:, 0], "fy": push[:, 1], "mz": push[:, 2]}
    write_table_csv(tmp_path / "traj.csv", columns)
    status, _, err = _cli("simulate", "--robot", robot, "--trajectory", tmp_path / "traj.csv",
                          "--output", tmp_path / "inv")  # fmt: skip
    assert status == 0, err
    results = tmp_path / "inv" / "results.csv"
    header = results.read_text().splitlines()[0].split(",")
    assert header[-3:] == ["fx", "fy", "mz"] and len(header) == 49
    given = read_forces(results)
    assert given.forces.load is not None
    np.testing.assert_array_equal(given.forces.load, push)  # written at full precision
    status, out, err = _cli("forward", "--robot", robot, "--forces", results,
                            "--output", tmp_path / "fwd")  # fmt: skip
    assert status == 0, err
    assert "with the load fx, fy, mz" in out
    back = np.genfromtxt(tmp_path / "fwd" / "results.csv", delimiter=",", names=True)
    assert np.abs(back["phi"] - pose[:, 2]).max() <= 1e-7
    assert np.abs(np.hypot(back["x"] - pose[:, 0], back["y"] - pose[:, 1])).max() <= 1e-7
    np.testing.assert_allclose(back["fy"], push[:, 1], rtol=0, atol=1e-15)


def test_a_force_file_with_some_load_columns_is_one_line_and_exit_2(tmp_path: Path) -> None:
    forces = tmp_path / "forces.csv"
    forces.write_text("t,f10_A,f10_B,f10_C,fx,fy\n0,0,0,0,0,0\n1,0,0,0,0,0\n")
    status, out, err = _cli("forward", "--forces", forces, "--output", tmp_path / "o")
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "missing mz" in err and str(forces) in err
    forces.write_text("t,f10_A,f10_B,f10_C,fx,fy,mz\n0,0,0,0,0,0,0\n1,0,0,0,nan,0,0\n")
    status, out, err = _cli("forward", "--forces", forces, "--output", tmp_path / "o")
    assert status == 2 and err.count("\n") == 1 and "fx" in err, err
    assert not (tmp_path / "o").exists()
