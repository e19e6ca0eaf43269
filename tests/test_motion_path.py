"""Motions checked between their samples, and rates at rest (issue 21, silent wrong answers).

* A motion whose orientation passes a singular orientation ``φ = π/3 mod π``
  between two samples is refused, naming both samples (the samples alone are
  all regular).  The rates are never compared with the steps: each sample is
  a state of its own (tests/test_independent_samples.py).
* Rates of round-off size at a sample at rest are zero for the sign of the
  Coulomb friction, in every method.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clitools import cli, listing, one_line
from prp3 import Robot
from prp3.analysis.inverse_dynamics import METHODS, inverse_dynamics
from prp3.apps.runs import simulate_table
from prp3.errors import SingularPoseError
from prp3.model.motion import Motion, law_motion, paper_motion
from prp3.model.parameters import Friction, JointFriction
from prp3.path_validation import RATE_TOLERANCE, check_path, rest_rates
from strategies import analytic_motions, robots

# x = 0.01 m, φ = 2t rad, every 0.2 s: φ passes π/3 between t = 0.4 and 0.6 s
CROSSING_T = np.round(np.arange(0.0, 1.01, 0.2), 12)


def _write(path: Path, header: str, rows: list[list[float]]) -> Path:
    path.write_text(header + "\n" + "".join(",".join(repr(v) for v in row) + "\n" for row in rows))
    return path


def crossing_file(folder: Path, derivatives: bool = True) -> Path:
    rows = []
    for t in CROSSING_T.tolist():
        row = [t, 0.01, 0.0, 2.0 * t]
        rows.append(row + [0.0, 0.0, 2.0, 0.0, 0.0, 0.0] if derivatives else row)
    header = "t,x,y,phi" + (",dx,dy,dphi,ddx,ddy,ddphi" if derivatives else "")
    return _write(folder / "cross.csv", header, rows)


def jump_file(folder: Path) -> Path:
    # the positions move 0.05 m in 0.01 s at sample 3, the velocities say rest
    rows = [[0.01 * k, 0.05 if k >= 3 else 0.0] + [0.0, 0.0] + [0.0] * 6 for k in range(6)]
    rows = [[r[0], r[1], 0.0, 0.0, *r[4:]] for r in rows]
    return _write(folder / "jump.csv", "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi", rows)


# ------------------------------------------------------------------ the check itself
def test_a_crossing_between_two_regular_samples_is_refused() -> None:
    pose = np.stack([np.full(CROSSING_T.size, 0.01), np.zeros(CROSSING_T.size), 2 * CROSSING_T], 1)
    D = np.sin(pose[:, 2] - math.pi / 3)
    assert np.abs(D).min() > 0.1  # every sample is far from the singularity
    with pytest.raises(SingularPoseError) as caught:
        check_path(CROSSING_T, pose)
    error = caught.value
    assert error.sample == 3 and error.time == pytest.approx(0.6)
    text = str(error)
    assert "sample 2 (t = 0.4 s, phi = 0.8)" in text and "sample 3 (t = 0.6 s, phi = 1.2)" in text
    assert "phi = 1.0472 rad" in text


def test_a_crossing_of_two_singular_orientations_is_refused_too() -> None:
    # φ from 0.5 to 0.5 + 2π: sin(φ − π/3) has the same sign at both samples
    pose = np.array([[0.0, 0.0, 0.5], [0.0, 0.0, 0.5 + 2.0 * math.pi]])
    with pytest.raises(SingularPoseError, match="passes zero"):
        check_path([0.0, 1.0], pose)


@settings(max_examples=30, deadline=None)
@given(data=st.data(), samples=st.integers(8, 60))
def test_smooth_motions_pass_whatever_their_sampling(data: st.DataObject, samples: int) -> None:
    robot = data.draw(robots())
    analytic = data.draw(analytic_motions(robot.l0))
    t = np.sort(data.draw(st.lists(st.floats(0.0, analytic.duration), min_size=samples,
                                   max_size=samples, unique=True)))  # fmt: skip
    motion = analytic.motion(np.asarray(t))
    check_path(motion.t, motion.pose)


@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_a_jump_the_rates_do_not_explain_is_accepted(data: st.DataObject) -> None:
    # samples are independent states: a step of the position that the rates do not
    # give is no refusal (a translation: the orientation, so the crossing, is unchanged)
    robot = data.draw(robots())
    analytic = data.draw(analytic_motions(robot.l0))
    t = np.linspace(0.0, analytic.duration, 41)
    motion = analytic.motion(t)
    k = data.draw(st.integers(1, 40))
    axis = data.draw(st.integers(0, 1))
    pose = motion.pose.copy()
    pose[k:, axis] += robot.l0 * data.draw(st.floats(0.05, 0.2))
    check_path(t, pose)
    with pytest.warns(DeprecationWarning, match="velocity and acceleration are deprecated"):
        check_path(t, pose, motion.velocity, motion.acceleration)  # ignored, as it says


# ------------------------------------------------------------------ the library entries
def crossing_motion() -> Motion:
    n = CROSSING_T.size
    return Motion(
        t=CROSSING_T,
        pose=np.stack([np.full(n, 0.01), np.zeros(n), 2.0 * CROSSING_T], axis=-1),
        velocity=np.tile([0.0, 0.0, 2.0], (n, 1)),
        acceleration=np.zeros((n, 3)),
    )


@pytest.mark.parametrize("method", METHODS)
def test_inverse_dynamics_refuses_a_crossing(method: str) -> None:
    with pytest.raises(SingularPoseError, match="crosses the singular orientation") as caught:
        inverse_dynamics(Robot(), crossing_motion(), method)  # type: ignore[arg-type]
    assert caught.value.sample == 3


def test_simulate_table_refuses_a_crossing_split_over_chunks() -> None:
    with pytest.raises(SingularPoseError) as caught:
        simulate_table(Robot(), crossing_motion(), chunk=3)  # the crossing is between chunks
    assert caught.value.sample == 3


# ------------------------------------------------------------------ the commands
SIMPLE_ROBOT_COMMANDS = ("simulate", "control")
EXTRA = {"simulate": (), "control": ("--controller", "computed-torque", "--plant", "prp3")}


@pytest.mark.parametrize("derivatives", [True, False])
@pytest.mark.parametrize("command", SIMPLE_ROBOT_COMMANDS)
def test_commands_refuse_a_crossing_trajectory(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: str, derivatives: bool
) -> None:
    file = crossing_file(tmp_path, derivatives)
    status, out, err = cli(
        capsys, command, *EXTRA[command], "--trajectory", file, "--output", tmp_path / "out"
    )
    line = one_line(err)
    assert status == 2 and out == ""
    assert f"{file}:5:" in line  # the file line of sample 3
    assert "crosses the singular orientation" in line
    assert "line 4 (t = 0.4 s" in line and "line 5 (t = 0.6 s" in line
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("command", SIMPLE_ROBOT_COMMANDS)
def test_commands_accept_a_jump_the_velocities_do_not_explain(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    # each row is the state at its time: positions that jump where the rates say rest
    file = jump_file(tmp_path)
    status, _out, err = cli(
        capsys, command, *EXTRA[command], "--trajectory", file, "--output", tmp_path / "out"
    )
    assert status == 0, err
    assert "jumps" not in err and "consistent derivatives" not in err
    assert (tmp_path / "out").is_dir()


def test_identify_refuses_a_crossing_measurement(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rows = [[t, 0.01, 0.0, 2.0 * t, 1.0, 2.0, 3.0] for t in CROSSING_T.tolist()]
    file = _write(tmp_path / "m.csv", "t,x,y,phi,f10_A,f10_B,f10_C", rows)
    status, _, err = cli(capsys, "identify", "--measurements", file, "--output", tmp_path / "o")
    line = one_line(err)
    assert status == 2 and f"{file}:5:" in line and "crosses the singular orientation" in line


def test_sweep_refuses_a_crossing_trajectory(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    crossing_file(tmp_path)
    spec = tmp_path / "spec.toml"
    spec.write_text(
        'designs = 2\nsampling = "random"\n[parameters]\nl0 = [0.25, 0.3]\n'
        '[task]\nmotions = ["cross.csv"]\n'
    )
    status, _, err = cli(capsys, "sweep", "--spec", spec, "--output", tmp_path / "o")
    line = one_line(err)
    assert status == 2 and "crosses the singular orientation" in line
    assert listing(tmp_path).keys() == {"cross.csv", "spec.toml"}


# ------------------------------------------------------------------ friction at rest
COULOMB = Robot(
    friction=Friction(
        actuator=JointFriction(viscous=20.0, coulomb=2.0, mu=0.05),
        revolute=JointFriction(coulomb=0.01),
        sleeve=JointFriction(coulomb=1.0),
    )
)


@pytest.mark.parametrize("name", ["vertical", "rotation"])
@pytest.mark.parametrize("method", METHODS)
def test_coulomb_friction_is_zero_at_rest_in_every_method(name: str, method: str) -> None:
    motion = paper_motion(name, 301)  # at t = 3 s the rates are sin(π)·q*·π/3: round-off
    _, dyn = inverse_dynamics(COULOMB, motion, method)  # type: ignore[arg-type]
    assert dyn.fric10 is not None and dyn.fric21 is not None and dyn.fric32 is not None
    for force in (dyn.fric10, dyn.fric21, dyn.fric32):
        assert np.all(force[-1] == 0.0) and np.all(force[0] == 0.0)  # at rest: s(0) = 0
    # the same as the motion with the last velocity exactly zero (independent of the rule)
    at_rest = Motion(t=motion.t[-1], pose=motion.pose[-1], velocity=np.zeros(3),
                     acceleration=motion.acceleration[-1])  # fmt: skip
    _, still = inverse_dynamics(COULOMB, at_rest, method)  # type: ignore[arg-type]
    np.testing.assert_allclose(dyn.f10[-1], still.f10, rtol=1e-13, atol=1e-12)


def test_the_rule_is_the_documented_one() -> None:
    v = np.array([[0.0, 0.0, 1.0], [3e-3, 4e-3, 0.0], [3e-15, 4e-15, 1e-12], [6e-15, 8e-15, 2e-12]])
    # translation scale |(ẋ, ẏ)| = 5e-3: 5e-15 is round-off, 1e-14 is not; φ̇ scale 1
    cleaned = rest_rates(v)
    assert RATE_TOLERANCE == 1e-12
    assert cleaned[2].tolist() == [0.0, 0.0, 0.0]
    assert cleaned[3].tolist() == v[3].tolist()
    # applied again to some of the samples: nothing changes (chunks give the same numbers)
    assert rest_rates(cleaned[1:3]).tolist() == cleaned[1:3].tolist()


def test_a_slow_motion_keeps_its_friction() -> None:
    # a whole motion 1e-9 times slower: its rates are its own scale, none is round-off
    motion = law_motion([0.0, 0.025e-9, 0.0], samples=11)
    _, dyn = inverse_dynamics(COULOMB, motion)
    assert dyn.fric10 is not None
    assert np.all(np.abs(dyn.fric10[1:-1]) >= 2.0)  # the full Coulomb level while moving
    assert np.all(dyn.fric10[-1] == 0.0)


def test_step_tolerance_is_deprecated() -> None:
    import prp3.path_validation

    with pytest.warns(DeprecationWarning, match="STEP_TOLERANCE is deprecated"):
        assert prp3.path_validation.STEP_TOLERANCE == 0.25  # its old value, for a release
    with pytest.raises(AttributeError):
        _ = prp3.path_validation.NO_SUCH_NAME  # type: ignore[attr-defined]


def test_track_refuses_a_reference_across_the_singularity() -> None:
    from prp3.apps.control import track

    with pytest.raises(SingularPoseError, match="crosses the singular orientation"):
        track(Robot(), crossing_motion(), controller="pd")
