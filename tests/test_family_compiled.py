"""The compiled engine of the family's fast route against the numpy engine and Newton–Euler.

``engine="numba"`` (:mod:`prp3.family.compiled`, one compiled loop over the
samples) and ``engine="numpy"`` (:mod:`prp3.family.mechanics`, arrays) compute
the same mechanics in different code: every output, every kinematic quantity
and every refusal must be the same — results to 1e-12 relative, errors with the
same class, message and fields.  Newton–Euler (the 21×21 balance of
docs/family.md §7) is the independent check; the balances rebuilt from the
columns are checked for the default engine by ``test_family_dynamics.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.typing import NDArray

from prp3 import Motion, paper_motion
from prp3.errors import Prp3Error
from prp3.family import (
    FAMILY_COLUMNS,
    FamilyRobot,
    FamilySolution,
    family_inverse_dynamics,
    family_results_table,
)
from prp3.family.outputs import DEFAULT_ENGINE
from test_family_dynamics import ALLOWED, check_sample, designs, motions

FloatArray = NDArray[np.float64]
RTOL = 1e-12

KINEMATIC = ("mu_leg", "mu_par", "jacobian", "jacobian_inverse")
FRAMES = ("joint_origin", "joint_angle", "origin", "angle", "axis", "end_origin", "end_angle")


def run(robot: FamilyRobot, motion: Motion, **kw: str) -> FamilySolution | Prp3Error:
    try:
        return family_inverse_dynamics(robot, motion, **kw)  # type: ignore[arg-type]
    except Prp3Error as error:
        return error


def same_error(a: Prp3Error, b: Prp3Error) -> None:
    assert type(a) is type(b), (a, b)
    assert str(a) == str(b)
    assert vars(a) == vars(b)


def close(a: FloatArray, b: FloatArray, what: str) -> None:
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, what
    scale = 1.0 + float(np.abs(b).max(initial=0.0))
    np.testing.assert_allclose(a, b, rtol=0, atol=RTOL * scale, err_msg=what)


def same_solution(a: FamilySolution, b: FamilySolution) -> None:
    """Every column and every kinematic quantity (frames, Jacobians, measures) agree."""
    ta, tb = family_results_table(a), family_results_table(b)
    for name in FAMILY_COLUMNS:
        close(ta[name], tb[name], name)
    for name in ("q", "dq", "ddq", "tau", "power", "force", "moment"):
        close(getattr(a, name), getattr(b, name), name)
    for name in KINEMATIC:
        close(getattr(a.kinematics, name), getattr(b.kinematics, name), name)
    for name in FRAMES:
        close(getattr(a.kinematics.frames, name), getattr(b.kinematics.frames, name), name)


def compare(robot: FamilyRobot, motion: Motion) -> FamilySolution | None:
    """Both engines: the same solution, or the same error; Newton–Euler equal when solved."""
    compiled = run(robot, motion, engine="numba")
    arrays = run(robot, motion, engine="numpy")
    if isinstance(arrays, Prp3Error):
        assert isinstance(compiled, Prp3Error), f"numpy refused ({arrays}), numba did not"
        same_error(compiled, arrays)
        return None
    assert isinstance(compiled, FamilySolution), f"numba refused ({compiled}), numpy did not"
    assert compiled.method == arrays.method == "fast"
    same_solution(compiled, arrays)
    reference = family_inverse_dynamics(robot, motion, "newton-euler")
    ta, tr = family_results_table(compiled), family_results_table(reference)
    scale = 1.0 + max(float(np.abs(v).max()) for v in tr.values())
    for name in FAMILY_COLUMNS:
        np.testing.assert_allclose(ta[name], tr[name], rtol=0, atol=RTOL * scale, err_msg=name)
    return compiled


def test_default_engine_is_numba() -> None:
    assert DEFAULT_ENGINE == "numba"  # numba is in the test extra


@given(data=st.data())
def test_engines_agree_on_random_robots_and_motions(data: st.DataObject) -> None:
    """Random designs, actuations, inertias, payloads, loads, gravity and motions."""
    robot = data.draw(designs())
    centre = robot.home_poses.mean(axis=0)
    samples = data.draw(st.integers(1, 9))
    solution = compare(robot, data.draw(motions(centre, samples)))
    if solution is not None:  # the independent balances of the reported columns
        table = family_results_table(solution)
        motion = solution.kinematics.motion
        for k in range(motion.samples):
            row = {name: float(table[name][k]) for name in FAMILY_COLUMNS}
            assert abs(check_sample(solution.kinematics.robot, row, motion, k)) < 1e-10


@given(data=st.data())
def test_engines_agree_far_from_home(data: st.DataObject) -> None:
    """Coarse motions over the whole workspace and beyond: sub-steps, crossings, refusals."""
    robot = data.draw(designs())
    n = data.draw(st.integers(1, 4))
    box = st.floats(-0.4, 0.4, allow_nan=False)
    turn = st.floats(-2.5, 2.5, allow_nan=False)
    pose = np.array([[data.draw(box), data.draw(box), data.draw(turn)] for _ in range(n)])
    rates = np.array([[data.draw(st.floats(-2, 2, allow_nan=False)) for _ in range(3)]])
    motion = Motion(
        t=np.arange(n, dtype=float),
        pose=pose,
        velocity=np.repeat(rates, n, axis=0),
        acceleration=np.repeat(-rates, n, axis=0),
    )
    compare(robot, motion)


@pytest.mark.parametrize(("arch", "act"), ALLOWED)
@pytest.mark.parametrize("name", ["vertical", "rotation"])
def test_engines_agree_on_the_paper_motions(arch: str, act: int, name: str) -> None:
    """Every allowed actuation of every default design (the 3-PRR 2's rotation is refused)."""
    compare(FamilyRobot.default(arch, act), paper_motion(name, 201))


@pytest.mark.parametrize(
    ("arch", "act", "poses"),
    [
        ("3-RRR", 1, [[0.0, 0.0, 0.0], [0.6, 0.0, 0.0]]),  # unreachable on the way
        ("3-RRR", 1, [[0.6, 0.0, 0.0]]),  # unreachable at the sample
        ("3-PRR", 2, [[0.0, 0.0, 0.0], [0.0, 0.0, 0.3], [0.0, 0.0, 0.7]]),  # mu_par crossed
        ("3-PRP", 1, [[0.0, 0.0, 0.0], [0.0, 0.0, 1.3]]),  # mu_leg crossed on the way
        ("3-PRP", 1, [[0.0, 0.0, np.pi / 3]]),  # mu_leg = 0 at the sample
        ("3-RRR", 1, [[0.0, 0.0, 0.0], [1e300, 0.0, 0.0]]),  # out of range
        ("3-RRR", 1, [[0.0, 0.0, 0.0], [0.0, 0.0, 1e10]]),
    ],
)
def test_refusals_are_identical(arch: str, act: int, poses: list[list[float]]) -> None:
    motion = Motion.at_rest(poses, t=np.arange(len(poses), dtype=float))
    robot = FamilyRobot.default(arch, act)
    compiled = run(robot, motion, engine="numba")
    arrays = run(robot, motion, engine="numpy")
    assert isinstance(arrays, Prp3Error) and isinstance(compiled, Prp3Error)
    same_error(compiled, arrays)


def test_results_that_overflow_are_refused_alike() -> None:
    motion = Motion.at_rest([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0]], t=[0.0, 1.0])
    huge = Motion(t=motion.t, pose=motion.pose, velocity=np.full((2, 3), 1e200),
                  acceleration=np.zeros((2, 3)))  # fmt: skip
    robot = FamilyRobot.default("3-RPR")
    with np.errstate(over="ignore", invalid="ignore"):
        arrays = run(robot, huge, engine="numpy")
    compiled = run(robot, huge, engine="numba")
    assert isinstance(arrays, Prp3Error) and isinstance(compiled, Prp3Error)
    same_error(compiled, arrays)
    assert compiled.sample == 0 and "overflow" in str(compiled)


def test_a_coarse_single_sample_follows_the_path() -> None:
    """One sample far from home (many sub-steps): the R angles of the fine path, as numpy."""
    robot = FamilyRobot.default("3-RRR")
    coarse = family_inverse_dynamics(robot, Motion.at_rest([0.02, -0.01, 0.5]), engine="numba")
    t = np.linspace(0.0, 1.0, 301)
    fine = Motion.at_rest(np.array([0.02, -0.01, 0.5]) * t[:, None], t=t)
    np.testing.assert_allclose(coarse.q, family_inverse_dynamics(robot, fine).q[-1], atol=1e-12)
    assert coarse.q.shape == (3, 3) and coarse.tau.shape == (3,)


def test_single_sample_rank_as_numpy() -> None:
    robot = FamilyRobot.default("3-PRR")
    single = Motion(t=0.0, pose=[0.01, 0.02, 0.1], velocity=[0.1, 0.0, 0.3],
                    acceleration=[0.0, 1.0, -2.0])  # fmt: skip
    compiled = family_inverse_dynamics(robot, single, engine="numba")
    same_solution(compiled, family_inverse_dynamics(robot, single, engine="numpy"))
    assert compiled.force.shape == (3, 3, 2) and compiled.kinematics.mu_par.shape == ()


def test_engine_is_refused_by_name() -> None:
    with pytest.raises(Prp3Error, match="engine must be one of 'numba', 'numpy', got 'fortran'"):
        family_inverse_dynamics(
            FamilyRobot.default("3-RRR"),
            Motion.at_rest([0.0, 0.0, 0.0]),
            engine="fortran",  # type: ignore[arg-type]
        )


def test_any_memory_layout_of_the_motion() -> None:
    """Fortran-ordered or strided motion arrays give the same results (one compiled signature)."""
    from prp3.family.compiled_kernel import structure_module

    base = paper_motion("vertical", 12)
    strided = Motion(
        t=base.t,
        pose=np.asfortranarray(base.pose),
        velocity=np.repeat(base.velocity, 2, axis=0)[::2],
        acceleration=np.asfortranarray(base.acceleration),
    )
    robot = FamilyRobot.default("3-RPR")
    module = structure_module(robot.types, robot.actuated)
    family_inverse_dynamics(robot, base)
    signatures = len(module.path.signatures), len(module.samples.signatures)
    same_solution(family_inverse_dynamics(robot, strided), family_inverse_dynamics(robot, base))
    assert (len(module.path.signatures), len(module.samples.signatures)) == signatures == (1, 1)


@pytest.mark.parametrize("arch", sorted({arch for arch, _ in ALLOWED}))
def test_a_batch_on_every_thread_gives_the_one_thread_numbers(
    arch: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """From ``PARALLEL_MIN_SAMPLES`` samples steps 2 and 3 run block by block on every thread.

    Each sample is computed alone by the same machine code, so every output equals
    the same batch on the calling thread bit for bit (an uneven last block included).
    """
    from prp3.engines.numba import BLOCK, PARALLEL_MIN_SAMPLES
    from prp3.family import compiled

    samples = PARALLEL_MIN_SAMPLES + BLOCK // 2 + 3
    assert compiled.uses_threads(samples) and not compiled.uses_threads(PARALLEL_MIN_SAMPLES - 1)
    robot, motion = FamilyRobot.default(arch), paper_motion("rotation", samples)
    threaded = compiled.compiled_dynamics(robot, motion)
    monkeypatch.setattr(compiled, "uses_threads", lambda samples: False)
    alone = compiled.compiled_dynamics(robot, motion)
    for name in ("q", "dq", "ddq", "tau", "power", "force", "moment"):
        np.testing.assert_array_equal(getattr(threaded, name), getattr(alone, name), err_msg=name)
    for name in ("jacobian", "jacobian_inverse"):
        np.testing.assert_array_equal(
            getattr(threaded.kinematics, name), getattr(alone.kinematics, name), err_msg=name
        )
