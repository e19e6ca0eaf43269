"""The fast path of legs closed by an S joint (docs/spatial.md §19, §24).

For the 6-UPS hexapod the compiled kernel solves each leg's Jacobian
``J = [[A, 1], [B, 0]]`` by its blocks (``B⁻¹``, ``det J = −det B``) instead of the
generic ``6 × 6`` LU; for the 3-RPS (``A, B`` of 3 × 2) by ``B(BᵀB)⁻¹`` and the constraint
wrench ``(0, −b̃₀ × b̃₁/ℓ)`` instead of the ``5 × 5`` minors and the LU of ``JᵀJ``.  Held here against the generic path of the same kernel (the flag
``S_CLOSED`` of the packed integers set to 0) to 1e-12 relative in every output and
status, on random designs and states (hypothesis), also far from home where the poses
are refused (the 3-RPS: also off its poses, with rates it does not allow); and against the
numpy kinematics for ``det J``'s sign and size.  Likewise the chain's
motion in one pass (the flag ``ONE_PASS``: the bias with ``q̈ = 0``, then the ``q̈`` terms
by the Jacobian's columns) against its two passes, on every architecture.  The 3-RUU keeps the generic path.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import prp3
from prp3.errors import Prp3Error
from prp3.spatial.compiled import ONE_PASS, S_CLOSED, U_CLOSED
from prp3.spatial.model import SpatialRobot
from spatial_strategies import deltas, hexapods, rps_robots
from test_spatial_compiled import states

TOLERANCE = 1e-12
NAMES = ("q", "dq", "ddq", "tau", "power", "force", "moment", "leg_measure", "parallel_measure")


def _both(robot: SpatialRobot, arrays: list[np.ndarray], flags: tuple[int, ...] = (S_CLOSED,
          ONE_PASS, U_CLOSED)) -> tuple[prp3.SpatialSamples, ...]:  # fmt: skip
    """The kernel as compiled, and with the ``flags`` set to 0 (the reference paths)."""
    fast = prp3.compile_spatial(robot)
    generic = prp3.compile_spatial(robot)
    generic.ints = generic.ints.copy()
    for flag in flags:
        generic.ints[flag] = 0
    with np.errstate(all="ignore"):  # raw's power of a refused sample's unset outputs
        return fast.raw(*arrays, threads=False), generic.raw(*arrays, threads=False)


#: Far from home the accepted states come close to singular ones (efforts of 1e4 from rates of
#: 1), where the two paths' round-off is amplified by the Jacobians' condition: there the paths
#: agree to the routes' tolerance of docs/spatial.md §10 (a CI run found 1.07e-12 at seed 74).
FAR_TOLERANCE = 1e-10


def _agree(fast: prp3.SpatialSamples, generic: prp3.SpatialSamples,
           tolerance: float = TOLERANCE) -> None:  # fmt: skip
    assert np.array_equal(fast.status, generic.status)
    ok = generic.status == 0
    for name in NAMES:
        a, b = getattr(fast, name)[ok], getattr(generic, name)[ok]
        if not b.size:
            continue
        scale = max(float(np.abs(b).max()), 1e-300)
        assert float(np.abs(a - b).max()) <= tolerance * scale, name


def _arrays(motion: prp3.PlatformMotion) -> list[np.ndarray]:
    return [np.ascontiguousarray(x) for x in (motion.position, motion.rotation, motion.omega,
            motion.velocity, motion.alpha, motion.acceleration)]  # fmt: skip


def test_the_flag_is_set_for_the_hexapod_and_the_3rps_only() -> None:
    for make in (prp3.hexapod, prp3.three_rps):
        assert prp3.compile_spatial(make()).ints[S_CLOSED] == 1
        assert "#define PRP3_S_CLOSED 1" in prp3.spatial_c_inverse_dynamics(make()).source
    assert prp3.compile_spatial(prp3.delta()).ints[S_CLOSED] == 0
    assert "#define PRP3_S_CLOSED 0" in prp3.spatial_c_inverse_dynamics(prp3.delta()).source


@settings(max_examples=40, deadline=None)
@given(st.sampled_from((hexapods, rps_robots)), st.data())
def test_the_fast_path_equals_the_generic_kernel(make: object, data: st.DataObject) -> None:
    robot = data.draw(make())  # type: ignore[operator]
    motion = data.draw(states(robot, 8))
    fast, generic = _both(robot, _arrays(motion))
    _agree(fast, generic)
    kin = prp3.spatial_kinematics(robot, motion) if not generic.status.any() else None
    if kin is not None:  # the measure's sign and size: the numpy route's det J
        assert np.allclose(fast.leg_measure, kin.leg_measure, rtol=1e-10, atol=0.0)


@settings(max_examples=20, deadline=None)
@given(st.sampled_from((hexapods, rps_robots)), st.data(), st.integers(0, 2**32 - 1))
def test_refusals_far_from_home_are_the_generic_kernels(make: object, data: st.DataObject,
                                                        seed: int) -> None:  # fmt: skip
    robot = data.draw(make())  # type: ignore[operator]
    rng = np.random.default_rng(seed)
    n = 400
    position = np.array(robot.home_position) + rng.normal(0.0, 0.15 * robot.scale, (n, 3))
    rotation = Rotation.from_rotvec(rng.normal(0.0, 0.25, (n, 3))).as_matrix()
    rates = [rng.normal(0.0, 1.0, (n, 3)) for _ in range(4)]
    fast, generic = _both(robot, [np.ascontiguousarray(x) for x in (position, rotation, *rates)])
    _agree(fast, generic, FAR_TOLERANCE)


def test_the_generic_path_still_runs_for_the_3ruu_and_the_fast_for_the_3rps() -> None:
    for make, name in ((prp3.delta, "circle"), (prp3.three_rps, "tilt")):
        robot = make()
        motion = prp3.complete_motion(robot, prp3.spatial_motion(robot, name, 21))
        out = prp3.compile_spatial(robot).solve_batch(motion)
        kin = prp3.spatial_kinematics(robot, motion)
        assert not out.status.any()
        assert np.allclose(out.dq, kin.dq, rtol=1e-10, atol=1e-12 * np.abs(kin.dq).max())


@settings(max_examples=20, deadline=None)
@given(st.sampled_from((hexapods, rps_robots, deltas)), st.data())
def test_one_pass_of_the_chain_equals_two(make: object, data: st.DataObject) -> None:
    robot = data.draw(make())  # type: ignore[operator]
    motion = data.draw(states(robot, 8))
    one, two = _both(robot, _arrays(motion), (ONE_PASS,))
    _agree(one, two)
    assert prp3.compile_spatial(robot).ints[ONE_PASS] == 1


@settings(max_examples=20, deadline=None)
@given(st.sampled_from((hexapods, rps_robots, deltas)), st.data())
def test_the_single_call_equals_the_batch(make: object, data: st.DataObject) -> None:
    """``solve`` (one state through one short kernel call) gives the batch's every output,
    bit for bit (the same sample's steps), and raises what the batch of one raises."""
    robot = data.draw(make())  # type: ignore[operator]
    motion = data.draw(states(robot, 3))
    kernel = prp3.compile_spatial(robot)
    arrays = _arrays(motion)
    for k in range(len(motion)):
        one = [a[k : k + 1] for a in arrays]
        try:
            batch = kernel.solve_batch(*one)
        except Prp3Error as error:
            with pytest.raises(type(error)) as caught:
                kernel.solve(*(a[0] for a in one))
            assert str(caught.value) == str(error)
            continue
        single = kernel.solve(*(a[0] for a in one))
        for name in NAMES:
            assert np.array_equal(getattr(single, name), getattr(batch, name)[0]), name


def test_the_single_calls_refusals_are_the_batchs() -> None:
    robot = prp3.hexapod()
    kernel = prp3.compile_spatial(robot)
    zero = np.zeros(3)
    home = np.array(robot.home_position)
    tilted = Rotation.from_rotvec([0.0, 1.2, 0.0]).as_matrix()
    for state in ((home + [0.0, 0.0, 0.2], np.eye(3)), (home + [0.0, 0.0, np.nan], np.eye(3)),
                  (home, 2.0 * np.eye(3)), (home, np.diag([1.0, 1.0, -1.0])), (home, tilted),
                  (home * [1.0, 1.0, 0.5], np.eye(3))):  # fmt: skip
        with pytest.raises(Prp3Error) as batch:
            kernel.solve_batch(state[0][None], state[1][None], *(zero[None],) * 4)
        with pytest.raises(type(batch.value)) as single:
            kernel.solve(state[0], state[1], zero, zero, zero, zero)
        assert str(single.value) == str(batch.value)


def test_the_u_p_leg_in_closed_form_is_the_hexapods_only() -> None:
    assert prp3.compile_spatial(prp3.hexapod()).ints[U_CLOSED] == 1
    for make in (prp3.three_rps, prp3.delta):
        assert prp3.compile_spatial(make()).ints[U_CLOSED] == 0


@settings(max_examples=30, deadline=None)
@given(hexapods(), st.data(), st.integers(0, 2**32 - 1))
def test_the_u_p_leg_in_closed_form_equals_the_chain(robot: SpatialRobot, data: st.DataObject,
                                                     seed: int) -> None:  # fmt: skip
    """The U's cosines and sines from the leg's vector and ``B⁻¹`` from the U's frame
    (``U_CLOSED``) against the chain of frames and the adjugate (the flag at 0, the S-closed
    block path kept): every output and status, near home (1e-12) and far from it (1e-10)."""
    motion = data.draw(states(robot, 8))
    closed, chain = _both(robot, _arrays(motion), (U_CLOSED,))
    _agree(closed, chain)
    rng = np.random.default_rng(seed)
    n = 200
    position = np.array(robot.home_position) + rng.normal(0.0, 0.15 * robot.scale, (n, 3))
    rotation = Rotation.from_rotvec(rng.normal(0.0, 0.25, (n, 3))).as_matrix()
    rates = [rng.normal(0.0, 1.0, (n, 3)) for _ in range(4)]
    closed, chain = _both(robot, [np.ascontiguousarray(x) for x in (position, rotation, *rates)],
                          (U_CLOSED,))  # fmt: skip
    _agree(closed, chain, FAR_TOLERANCE)
