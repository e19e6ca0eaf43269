"""The family's kernel generated for numba from the one Ops source (``prp3.family.compiled_kernel``).

The generated loop (the robot's numbers as inputs, one compiled function per
architecture × actuation) is held against the numpy engine
(:func:`prp3.family.mechanics.fast_dynamics`: angles, ``atan2``, batched 3×3
inverses, the path of §5 — another route than the kernel's rotation pairs and
branch rule) to 1e-12 relative to the largest value of each output and
sample, on every architecture and allowed actuation along the paper's motions
and on hypothesis-random designs, inertias, payloads, loads, gravities and
motions; one compiled function serves two robots of a structure; the codes
of the C (not finite, out of reach, singular, overflow) with NaN outputs;
the threads give the numbers of one thread; the generated module is cached
in ``NUMBA_CACHE_DIR`` when it is set.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

pytest.importorskip("numba")

from prp3.errors import SingularPoseError, UnreachablePoseError
from prp3.family import FamilyRobot
from prp3.family.codegen import python_sample
from prp3.family.compiled_kernel import (
    OUTPUTS,
    STATUS_NOT_FINITE,
    STATUS_OK,
    STATUS_OVERFLOW,
    STATUS_SINGULAR,
    STATUS_UNREACHABLE,
    kernel_batch,
    structure_module,
    structure_source,
)
from prp3.family.mechanics import family_kinematics, fast_dynamics
from prp3.model.motion import Motion, paper_motion
from strategies import FAMILY_ALLOWED, family_designs, family_motions, loaded_family_robot

CROSSING = {("3-PRR", 2, "rotation")}


def split(out: np.ndarray) -> dict[str, np.ndarray]:
    parts, at = {}, 0
    for name, size in OUTPUTS:
        parts[name] = out[:, at : at + size]
        at += size
    return parts


def reference(robot: FamilyRobot, motion: Motion) -> dict[str, np.ndarray]:
    """The numpy engine's outputs in the kernel's layout, ``(N, size)`` each."""
    kin = family_kinematics(robot, motion)
    sol = fast_dynamics(kin)
    n = motion.samples
    joint = np.concatenate([sol.force, sol.moment[..., None]], axis=-1)
    return {
        "mu_leg": kin.mu_leg.reshape(n, 3),
        "mu_par": kin.mu_par.reshape(n, 1),
        "tau": sol.tau.reshape(n, 3),
        "joint": joint.reshape(n, 27),
        "dq": sol.dq.reshape(n, 9),
        "ddq": sol.ddq.reshape(n, 9),
        "power": sol.power.reshape(n, 3),
        "jacobian": kin.jacobian.reshape(n, 27),
        "jacobian_inverse": kin.jacobian_inverse.reshape(n, 27),
    }


def worst(robot: FamilyRobot, motion: Motion) -> dict[str, float]:
    """The largest error of each output relative to its largest magnitude at the sample."""
    want = reference(robot, motion)
    status, out = kernel_batch(robot, motion.pose, motion.velocity, motion.acceleration)
    assert (status == STATUS_OK).all()
    got = split(out)
    errors = {}
    for name, w in want.items():
        scale = np.maximum(np.abs(w).max(axis=1, keepdims=True), 1e-300)
        errors[name] = float((np.abs(got[name] - w) / scale).max())
    return errors


@pytest.mark.parametrize(("arch", "act"), FAMILY_ALLOWED)
def test_every_actuation_matches_the_numpy_engine(arch: str, act: int) -> None:
    robot = loaded_family_robot(arch, act)
    for name in ("vertical", "rotation"):
        if (arch, act, name) in CROSSING:
            continue
        errors = worst(robot, paper_motion(name, 41))
        assert max(errors.values()) <= 1e-12, (name, errors)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_robots_and_motions_match_the_numpy_engine(data: st.DataObject) -> None:
    robot = data.draw(family_designs())
    motion = data.draw(family_motions(robot.home_poses.mean(axis=0), samples=9))
    try:
        reference(robot, motion)
    except (SingularPoseError, UnreachablePoseError):
        assume(False)
    errors = worst(robot, motion)
    assert max(errors.values()) <= 1e-12, errors


def test_one_compiled_function_serves_every_robot_of_a_structure() -> None:
    a = loaded_family_robot("3-RPR", 1)
    b = replace(FamilyRobot.default("3-RPR", 1), gravity=(0.0, 0.0))
    assert structure_module(a.types, a.actuated) is structure_module(b.types, b.actuated)
    motion = paper_motion("vertical", 11)
    for robot in (a, b):
        assert max(worst(robot, motion).values()) <= 1e-12
    assert structure_source("RPR", 1) != structure_source("RPR", 2)


def test_the_legs_and_tau_are_the_python_steps() -> None:
    """The same trace on Python floats (``python_sample``, the C's steps): the same numbers."""
    robot = loaded_family_robot("3-RRP", 3)
    motion = paper_motion("rotation", 7)
    status, out = kernel_batch(robot, motion.pose, motion.velocity, motion.acceleration)
    got = split(out)
    for k in range(motion.samples):
        code, values = python_sample(
            robot, motion.pose[k], motion.velocity[k], motion.acceleration[k]
        )
        assert code == status[k] == STATUS_OK
        want = np.array(values)
        have = np.concatenate([got["tau"][k], got["joint"][k]])
        assert np.abs(have - want).max() <= 1e-13 * np.abs(want).max()


def one(robot: FamilyRobot, pose, velocity=(0.0, 0.0, 0.0), acceleration=(0.0, 0.0, 0.0)):
    status, out = kernel_batch(
        robot, np.array([pose], float), np.array([velocity], float), np.array([acceleration], float)
    )
    return int(status[0]), out[0]


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("where", range(9))
def test_a_non_finite_input_is_refused_with_nan(where: int, bad: float) -> None:
    values = [0.0] * 9
    values[where] = bad
    code, out = one(FamilyRobot.default("3-RRR"), values[:3], values[3:6], values[6:])
    assert code == STATUS_NOT_FINITE
    assert np.isnan(out).all()


def test_the_refusals_are_the_pythons_steps() -> None:
    """Out of reach, singular, overflow: the codes of ``python_sample`` (the C's), NaN outputs."""
    robot = FamilyRobot.default("3-RRR")
    cases = [((5.0, 0.0, 0.0), (0.0,) * 3, (0.0,) * 3),  # far out of reach
             ((0.0, 0.0, 0.0), (1e300, 1e300, 0.0), (0.0,) * 3),  # overflow
             ((0.0, 0.0, 0.0), (0.0,) * 3, (1e308, -1e308, 1e308))]  # fmt: skip
    codes = set()
    for pose, velocity, acceleration in cases:
        code, out = one(robot, pose, velocity, acceleration)
        want, _ = python_sample(robot, pose, velocity, acceleration)
        assert code == want, (pose, velocity, acceleration)
        codes.add(code)
        if code != STATUS_OK:
            assert np.isnan(out).all()
    assert {STATUS_UNREACHABLE, STATUS_OVERFLOW} <= codes
    # a leg singularity: the 3-PRP's leg measure is sin(φ − π/3) up to sign (docs/family.md §6)
    prp = FamilyRobot.default("3-PRP")
    for phi in (math.pi / 3.0, math.pi / 3.0 - 5e-5, 2.0):
        code, out = one(prp, (0.0, 0.0, phi))
        assert code == STATUS_SINGULAR and np.isnan(out).all(), phi
    assert one(prp, (0.0, 0.0, math.pi / 3.0 - 2e-4))[0] == STATUS_OK
    # a parallel singularity: the 3-PRR actuated at joint 2 at φ = atan(1/2) (docs/family.md §3)
    prr = FamilyRobot.default("3-PRR", 2)
    code, out = one(prr, (0.0, 0.0, math.atan(0.5)))
    assert code == STATUS_SINGULAR and np.isnan(out).all()
    assert python_sample(prr, (0.0, 0.0, math.atan(0.5)), (0.0,) * 3, (0.0,) * 3)[0] == code
    assert one(prr, (0.0, 0.0, 0.2))[0] == STATUS_OK


def test_the_threads_give_the_numbers_of_one_thread() -> None:
    robot = loaded_family_robot("3-PRR", 1)
    motion = paper_motion("vertical", 5000)
    args = (robot, motion.pose, motion.velocity, motion.acceleration)
    s1, o1 = kernel_batch(*args, threads=False)
    s2, o2 = kernel_batch(*args, threads=True)
    assert (s1 == s2).all()
    assert np.array_equal(o1, o2)


def test_the_module_goes_to_numba_cache_dir(tmp_path: Path) -> None:
    script = (
        "from prp3.family.compiled_kernel import structure_module\n"
        "print(structure_module('PPR', 1).__file__)\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                          text=True, check=True)  # fmt: skip
    path = Path(done.stdout.strip())
    assert path.parent == tmp_path / "prp3_generated"
    assert path.read_text() == structure_source("PPR", 1)
