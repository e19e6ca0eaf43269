"""The near-lock warning of the implicit friction (``μ`` terms; docs/loads_and_friction.md).

The definition (``prp3.mechanics.implicit_friction.NEAR_LOCK_MU``): a sample is near a lock when the
solution reached continuously from ``μ = 0`` does not extend to ``1.2·μ``.

Independent checks:

* the samples flagged at ``μ`` are exactly those the Newton–Euler solver (its
  own iteration on the 21 balances and its own lock test) refuses at
  ``1.2·μ``;
* with ``μ`` only in the sleeves the implicit problem is piecewise linear in
  the three normal reactions ``n32``: with their signs ``σ`` fixed,
  ``n = n_e + R·diag(−μ·s(λ̇32))·(σ∘n)`` is a linear system (``n_e`` the
  reactions without the ``μ`` terms, ``R`` the reactions of unit sleeve
  friction forces), and every solution of the problem is the solution of
  one of the 8 sign patterns consistent with its own signs.  Enumerating them
  counts the solutions exactly; the samples with two are flagged.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from prp3 import Robot, inverse_dynamics
from prp3.cli import main
from prp3.errors import TrajectoryError
from prp3.io.tables import write_table_csv
from prp3.mechanics.implicit_friction import NEAR_LOCK_MU
from prp3.mechanics.joint_motion import kernel_geometry, kernel_kinematics
from prp3.mechanics.ops import NUMPY
from prp3.mechanics.parameters import kernel_parameters
from prp3.mechanics.virtual_work import joint_forces
from prp3.mechanics.wrenches import KernelFriction, body_wrenches
from prp3.model.motion import Motion, paper_motion
from prp3.model.parameters import Friction, JointFriction

SLEEVE_MU = 0.3  # the spec: the paper's rotation then locks at t ≈ 2.37 s (sample 237 of 301)


def sleeve_robot(mu: float) -> Robot:
    return Robot(friction=Friction(sleeve=JointFriction(mu=mu)))


def solution_counts(mu: float, motion: Motion) -> np.ndarray:
    """Number of solutions of each sample with sleeve friction ``μ``, sign pattern by pattern."""
    kin, ideal = inverse_dynamics(Robot(), motion, method="newton-euler")
    n_e = ideal.n32  # (N, 3): no friction at all
    params = kernel_parameters(Robot())
    pose, velocity, acceleration = motion.pose.T, motion.velocity.T, motion.acceleration.T
    geo = kernel_geometry(NUMPY, params, *pose)
    state = kernel_kinematics(params, geo, *velocity, *acceleration)
    response = np.empty((motion.samples, 3, 3))  # ∂n32_i/∂fric32_j (linear: unit forces)
    for j in range(3):
        unit = tuple(1.0 if leg == j else 0.0 for leg in range(3))
        friction = KernelFriction((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), unit)  # type: ignore[arg-type]
        wrenches = body_wrenches(params, state, 0.0, 0.0, 0.0, 0.0, friction=friction,
                                 inertia=False)  # fmt: skip
        _, _, _, rest = joint_forces(params, state, wrenches)
        assert rest is not None
        response[:, :, j] = np.stack(np.broadcast_arrays(*rest[2]), axis=-1)
    c = -mu * np.sign(kin.dlambda32)
    counts = np.zeros(motion.samples, dtype=int)
    for pattern in itertools.product((-1.0, 1.0), repeat=3):
        sigma = np.array(pattern)
        system = np.eye(3) - response * (c * sigma)[:, None, :]
        n = np.linalg.solve(system, n_e[..., None])[..., 0]
        counts += (np.sign(n) * sigma >= 0.0).all(axis=-1)
    return counts


def test_near_lock_is_the_lock_of_mu_twenty_percent_higher() -> None:
    motion = paper_motion("rotation")[176:237]  # up to the last sample solved at μ = 0.3
    _, dyn = inverse_dynamics(sleeve_robot(SLEEVE_MU), motion)
    assert dyn.near_lock is not None and dyn.near_lock.dtype == bool
    flagged = np.flatnonzero(dyn.near_lock)
    refused = []
    for k in range(motion.samples):  # Newton–Euler, sample by sample, at 1.2·μ
        try:
            inverse_dynamics(sleeve_robot(NEAR_LOCK_MU * SLEEVE_MU), motion[k : k + 1],
                             method="newton-euler")  # fmt: skip
        except TrajectoryError:
            refused.append(k)
    assert len(refused) > 10 and refused[0] > 0  # the constructed case: a run into the lock
    assert flagged.tolist() == refused


def test_samples_with_two_solutions_are_flagged() -> None:
    motion = paper_motion("rotation")[176:240]
    counts = solution_counts(SLEEVE_MU, motion)
    assert counts[0] == 1 and (counts == 2).any() and counts[-1] == 0  # one, two, none: a fold
    solved = int(np.argmax(counts == 0))  # the lock: the spec's t ≈ 2.37 s
    assert float(motion.t[solved]) == pytest.approx(2.37, abs=0.005)
    _, dyn = inverse_dynamics(sleeve_robot(SLEEVE_MU), motion[:solved])
    assert dyn.near_lock is not None
    assert dyn.near_lock[counts[:solved] == 2].all()
    assert not dyn.near_lock[0]


@pytest.mark.parametrize("name", ["vertical", "rotation"])
def test_mild_friction_on_the_papers_motions_is_not_near_a_lock(name: str) -> None:
    mild = JointFriction(viscous=2.0, coulomb=1.0, mu=0.1)
    robot = Robot(
        friction=Friction(
            actuator=mild,
            revolute=JointFriction(coulomb=0.01, mu=0.1, pin_radius=0.01),
            sleeve=mild,
        )
    )
    _, dyn = inverse_dynamics(robot, paper_motion(name))
    assert dyn.near_lock is not None and not dyn.near_lock.any()
    assert dyn.iterations is not None and (dyn.iterations > 0).any()  # the μ terms act
    _, plain = inverse_dynamics(Robot(friction=Friction(sleeve=JointFriction(coulomb=1.0))),
                                paper_motion(name, 11))  # fmt: skip
    assert plain.near_lock is None  # nothing implicit: no such flag


def trajectory_file(path: Path, motion: Motion) -> Path:
    columns = {"t": motion.t}
    for k, name in enumerate(("x", "y", "phi")):
        columns[name] = motion.pose[:, k]
        columns[f"d{name}"] = motion.velocity[:, k]
        columns[f"dd{name}"] = motion.acceleration[:, k]
    write_table_csv(path, columns)
    return path


@pytest.mark.parametrize("method", ["fast", "newton-euler"])
def test_simulate_warns_naming_the_samples_near_a_lock(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], method: str
) -> None:
    (tmp_path / "robot.toml").write_text(f"[friction.sleeve]\nmu = {SLEEVE_MU}\n")
    rotation = paper_motion("rotation")
    traj = trajectory_file(tmp_path / "traj.csv", rotation[150:237])
    _, dyn = inverse_dynamics(sleeve_robot(SLEEVE_MU), rotation[150:237])
    assert dyn.near_lock is not None
    flagged = np.flatnonzero(dyn.near_lock)
    status = main(["simulate", "--robot", str(tmp_path / "robot.toml"), "--trajectory",
                   str(traj), "--method", method, "--output", str(tmp_path / "out")])  # fmt: skip
    captured = capsys.readouterr()
    assert status == 0, captured.err
    warnings = [line for line in captured.err.splitlines() if "near a lock" in line]
    assert len(warnings) == 1, captured.err
    first = int(flagged[0])  # data row k is file line k + 2 (the header is line 1)
    t_first = float(rotation.t[150 + first])
    assert warnings[0].startswith(f"prp3 simulate: warning: {flagged.size} samples near a lock")
    assert f"line {first + 2} (t = {t_first:.6g} s)" in warnings[0]
    assert f"line {int(flagged[-1]) + 2} (t =" in warnings[0]
    assert (tmp_path / "out" / "results.csv").is_file()


def test_simulate_with_mild_friction_does_not_warn(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "robot.toml").write_text("[friction.sleeve]\nmu = 0.1\ncoulomb = 0.5\n")
    status = main(["simulate", "--robot", str(tmp_path / "robot.toml"), "--motion", "rotation",
                   "--output", str(tmp_path / "out")])  # fmt: skip
    captured = capsys.readouterr()
    assert status == 0 and "near a lock" not in captured.err
