"""The fused paths of ``prp3.engines.entries`` against the reference solvers and against physics.

Expected numbers come from :func:`prp3.references.newton_euler.newton_euler` (the fast
paths share no code with it: it solves each leg's closure numerically and the
balances of the 7 bodies), from the test's own reference model
(``strategies``) for the whole-robot balance, or are worked by hand beside the
test.  Tolerance: 1e-12 of a per-sample force scale (the largest reported
force plus the total weight), as in ``test_dynamics``.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from prp3 import (
    Limits,
    Motion,
    Prp3Error,
    Robot,
    SingularPoseError,
    TrajectoryError,
    UnreachablePoseError,
    inverse_dynamics,
    inverse_kinematics,
    newton_euler,
)
from prp3.engines.compiled_robot import CompiledRobot, compile_robot
from prp3.engines.entries import FastForces, actuator_forces, paper_forces, solve_batch
from prp3.engines.sample_entries import (
    sample_actuator_forces,
    sample_forces,
    sample_forces_unchecked,
)
from prp3.engines.select import ENGINES
from prp3.model.motion import paper_motion
from prp3.model.parameters import Friction, JointFriction
from strategies import (
    REF_E,
    REF_N,
    AnalyticMotion,
    body_states,
    cross,
    platform_inertia,
    ref_geometry,
    ref_rates,
    scenarios,
    total_mass,
)

FORCES = ("f10", "f21y", "f21z", "n10", "n32")
MOMENTS = ("m10", "m32")
QUANTITIES = ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32")
OUTPUTS = ("f10", "p10", "f21y", "f21z")  # without reactions


def scales(robot: Robot, motion: Motion, reference: object) -> dict[str, np.ndarray]:
    """Per-sample scale of each quantity, shape ``(..., 1)``."""
    largest = np.max([np.abs(getattr(reference, name)).max(axis=-1) for name in FORCES], axis=0)
    force = largest + total_mass(robot) * math.hypot(*robot.gravity)
    kin = inverse_kinematics(robot, motion)
    lever = robot.l0 + np.abs(kin.geometry.lever).max(axis=(-1, -2))
    power = force * np.abs(kin.dlambda10).max(axis=-1)
    scale = {name: force for name in FORCES}
    scale.update({name: force * lever for name in MOMENTS}, p10=power)
    return {name: np.asarray(value)[..., None] for name, value in scale.items()}


def assert_agree(
    got: object, expected: object, scale: dict[str, np.ndarray], names: tuple[str, ...]
) -> None:
    for name in names:
        difference = np.abs(np.asarray(getattr(got, name)) - getattr(expected, name))
        assert np.all(difference <= 1e-12 * scale[name]), (
            name,
            float((difference / scale[name]).max()),
        )


# ------------------------------------------------------------ batch vs references
@given(
    scenario=scenarios(),
    chunk=st.sampled_from([1, 5, 64, 4096]),
    engine=st.sampled_from(ENGINES),
)
def test_batch_agrees_with_newton_euler_and_newton_euler(
    scenario: tuple[Robot, AnalyticMotion], chunk: int, engine: str
) -> None:
    # Random l0, masses, inertias, centres of mass of pistons and links, any gravity,
    # smooth motions with |sin(φ − π/3)| ≥ 0.27 (strategies); chunks that split the batch
    # (numpy engine), and a part of the batch on its own.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 40))
    args = (motion.pose, motion.velocity, motion.acceleration)
    fast = paper_forces(robot, *args, reactions=True, chunk_size=chunk, engine=engine)  # type: ignore[arg-type]
    plain = paper_forces(robot, *args, chunk_size=chunk, engine=engine)  # type: ignore[arg-type]
    few = motion[3:19]
    looped = paper_forces(robot, few.pose, few.velocity, few.acceleration, engine=engine)  # type: ignore[arg-type]
    kin = inverse_kinematics(robot, motion)
    for reference in (newton_euler(robot, kin),):
        scale = scales(robot, motion, reference)
        assert_agree(fast, reference, scale, QUANTITIES)
        assert_agree(plain, reference, scale, OUTPUTS)
        short = {name: getattr(reference, name)[3:19] for name in OUTPUTS}
        assert_agree(
            looped, SimpleNamespace(**short), {k: v[3:19] for k, v in scale.items()}, OUTPUTS
        )


@given(scenario=scenarios(), engine=st.sampled_from(ENGINES))
def test_single_sample_agrees_with_newton_euler_and_newton_euler(
    scenario: tuple[Robot, AnalyticMotion], engine: str
) -> None:
    robot, analytic = scenario
    compiled = compile_robot(robot)
    for t in np.linspace(0.0, analytic.duration, 4):
        motion = analytic.motion(t)  # a single sample: arrays (3,)
        forces = sample_forces(
            compiled,
            motion.pose,
            motion.velocity,
            motion.acceleration,
            engine=engine,  # type: ignore[arg-type]
        )
        unchecked = compiled.sample_function(engine)(  # type: ignore[arg-type]
            *motion.pose.tolist(), *motion.velocity.tolist(), *motion.acceleration.tolist()
        )
        assert forces == (unchecked[0:3], unchecked[3:6], unchecked[6:9], unchecked[9:12])
        unchecked = sample_forces_unchecked(
            compiled,
            *motion.pose.tolist(),
            *motion.velocity.tolist(),
            *motion.acceleration.tolist(),
        )
        assert forces == (unchecked[0:3], unchecked[3:6], unchecked[6:9], unchecked[9:12])
        assert all(type(value) is float for value in unchecked)
        for method in ("paper", "newton-euler"):
            _, reference = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
            assert_agree(forces, reference, scales(robot, motion, reference), OUTPUTS)


@given(scenario=scenarios(), engine=st.sampled_from(ENGINES))
def test_single_sample_path_equals_batch_path(
    scenario: tuple[Robot, AnalyticMotion], engine: str
) -> None:
    # The single-sample and batch paths run the same kernel: agreement to round-off.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 8))
    batch = paper_forces(robot, motion.pose, motion.velocity, motion.acceleration, engine="numpy")
    compiled = compile_robot(robot)
    for k in range(motion.samples):
        one = sample_forces(
            compiled,
            motion.pose[k],
            motion.velocity[k],
            motion.acceleration[k],
            engine=engine,  # type: ignore[arg-type]
        )
        for name in OUTPUTS:
            expected = getattr(batch, name)[k]
            scale = np.abs(expected).max() + total_mass(robot) * math.hypot(*robot.gravity)
            np.testing.assert_allclose(getattr(one, name), expected, rtol=0, atol=1e-13 * scale)


@settings(max_examples=15)
@given(scenario=scenarios())
def test_whole_robot_balance(scenario: tuple[Robot, AnalyticMotion]) -> None:
    # Only the base acts on the robot from outside: on piston i the actuator force f10·e_i
    # and the guide's n10·n_i (both through P_i) and moment m10.  So, with the test's own
    # kinematics (strategies) for every body's centre of mass:
    #   Σ_bodies m·(a − g) = Σ_i (f10_i·e_i + n10_i·n_i)
    #   Σ_bodies [r × m·(a − g) + I·ε] = Σ_i [P_i × (f10_i·e_i + n10_i·n_i) + m10_i]  (about O)
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 16))
    fast = paper_forces(robot, motion.pose, motion.velocity, motion.acceleration, reactions=True)
    assert fast.n10 is not None and fast.m10 is not None
    geo = ref_geometry(robot.l0, motion.pose)
    rates = ref_rates(robot.l0, motion.pose, motion.velocity, motion.acceleration)
    b = body_states(
        robot, geo.lambda10, rates.dlambda10, rates.ddlambda10,
        motion.pose, motion.velocity, motion.acceleration,
    )  # fmt: skip
    g = np.asarray(robot.gravity)
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    need_1 = m1 * (b.piston_acceleration - g)
    need_2 = m2 * (b.link_acceleration - g)
    need_3 = m3 * (b.platform_acceleration - g)
    force = need_1.sum(-2) + need_2.sum(-2) + need_3
    moment = (
        cross(b.piston, need_1).sum(-1)
        + cross(b.link, need_2).sum(-1)
        + 3.0 * robot.link.inertia * b.epsilon
        + cross(b.platform, need_3)
        + platform_inertia(robot) * b.epsilon
    )
    base = fast.f10[..., None] * REF_E + fast.n10[..., None] * REF_N
    scale = np.abs(base).max() + total_mass(robot) * (math.hypot(*robot.gravity) + 1.0)
    np.testing.assert_allclose(base.sum(-2), force, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(
        (cross(b.joint, base) + fast.m10).sum(-1), moment, rtol=0, atol=1e-11 * scale * robot.l0
    )


def test_static_central_configuration_by_hand() -> None:
    # Default robot at rest at the centre (derivation in test_dynamics: the base carries
    # the platform's weight 29.43 N as n32 = (2/3, −1/3, −1/3)·m3·g, then link and piston):
    # f10_A = (m1 + m2 + 2/3·m3)·g·√3/2 = 36.7875·√3/2, f10_B = −(m3/3)·g·√3/2 ... (N).
    s, g = math.sqrt(3.0), 9.81
    expected_f10 = [36.7875 * s / 2, -g * s / 2, -g * s / 4 - 22.0725 * s / 2]
    expected_f21y = [26.9775 / 2, -12.2625, -g * 3 / 4 + 12.2625 / 2]
    forces = paper_forces(Robot(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    np.testing.assert_allclose(forces.f10, expected_f10, rtol=0, atol=1e-12)
    np.testing.assert_allclose(forces.f21y, expected_f21y, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(forces.p10, 0.0)
    one = sample_forces(compile_robot(Robot()), (0, 0, 0), (0, 0, 0), (0, 0, 0))
    np.testing.assert_allclose(one.f10, expected_f10, rtol=0, atol=1e-12)
    np.testing.assert_allclose(one.f21y, expected_f21y, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ["vertical", "rotation"])
def test_paper_motions(name: str) -> None:
    robot = Robot()
    motion = paper_motion(name, samples=301)
    _, reference = inverse_dynamics(robot, motion)
    fast = paper_forces(robot, motion.pose, motion.velocity, motion.acceleration, reactions=True)
    assert_agree(fast, reference, scales(robot, motion, reference), QUANTITIES)


# ------------------------------------------------------------------ shapes, out=
def test_output_rank_follows_input_rank() -> None:
    robot = compile_robot(Robot())
    motion = paper_motion("rotation", samples=5)
    batch = paper_forces(robot, motion.pose, motion.velocity, motion.acceleration, reactions=True)
    assert all(getattr(batch, name).shape == (5, 3) for name in QUANTITIES)
    one = paper_forces(robot, motion.pose[2], motion.velocity[2], motion.acceleration[2])
    assert one.f10.shape == one.p10.shape == one.f21y.shape == one.f21z.shape == (3,)
    assert one.n10 is None and one.m10 is None and one.n32 is None and one.m32 is None
    np.testing.assert_allclose(one.f10, batch.f10[2], rtol=1e-14)
    row = paper_forces(robot, motion.pose[2:3], motion.velocity[2:3], motion.acceleration[2:3])
    assert row.f10.shape == (1, 3)
    empty = paper_forces(robot, np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)))
    assert empty.f10.shape == (0, 3)
    lists = paper_forces(
        robot, motion.pose.tolist(), motion.velocity.tolist(), motion.acceleration.tolist()
    )
    np.testing.assert_allclose(lists.f10, batch.f10, rtol=1e-13)


def test_out_arrays_are_filled_and_returned() -> None:
    robot = Robot()
    motion = paper_motion("vertical", samples=7)
    expected = paper_forces(
        robot, motion.pose, motion.velocity, motion.acceleration, reactions=True
    )
    out = FastForces(*(np.full((7, 3), np.nan) for _ in QUANTITIES))
    got = paper_forces(
        robot,
        motion.pose,
        motion.velocity,
        motion.acceleration,
        reactions=True,
        out=out,
        chunk_size=3,
    )
    for name in QUANTITIES:
        assert getattr(got, name) is getattr(out, name)
        np.testing.assert_allclose(
            getattr(got, name), getattr(expected, name), rtol=1e-14, atol=1e-14
        )


@pytest.mark.parametrize(
    ("out", "message"),
    [
        ("nope", "out must be a FastForces"),
        (FastForces(*(np.zeros((4, 3)) for _ in range(4))), r"out\.f10 must be .* shape \(7, 3\)"),
        (FastForces(*(np.zeros((7, 3), dtype=np.float32) for _ in range(4))), "out.f10 must be"),
        (FastForces(*(np.zeros((3, 7)).T for _ in range(4))), "out.f10 must be .*C-contiguous"),
        (FastForces(*(np.zeros((7, 3)) for _ in range(4))), "out.n10 must be .* got None"),
    ],
)
def test_bad_out_is_refused(out: object, message: str) -> None:
    motion = paper_motion("vertical", samples=7)
    with pytest.raises(Prp3Error, match=message):
        paper_forces(
            Robot(),
            motion.pose,
            motion.velocity,
            motion.acceleration,
            reactions=True,
            out=out,  # type: ignore[arg-type]
        )


def test_compiled_robot_is_reused_and_read_only() -> None:
    robot = Robot(link=Robot().link.__class__(com=(0.01, -0.02)))
    compiled = compile_robot(robot)
    assert isinstance(compiled, CompiledRobot) and compiled.robot is robot
    motion = paper_motion("rotation", samples=9)
    np.testing.assert_array_equal(
        paper_forces(compiled, motion.pose, motion.velocity, motion.acceleration).f10,
        paper_forces(robot, motion.pose, motion.velocity, motion.acceleration).f10,
    )
    with pytest.raises(AttributeError):
        compiled.parameters = compiled.parameters  # type: ignore[misc]
    with pytest.raises(Prp3Error, match=r"robot must be a prp3\.Robot"):
        compile_robot("robot.toml")  # type: ignore[arg-type]


# ------------------------------------------------------------------------ errors
def singular_motion(samples: int, index: int) -> Motion:
    motion = paper_motion("rotation", samples=samples)
    pose = motion.pose.copy()
    pose[index, 2] = math.pi / 3.0 + 2e-5  # |sin(φ − π/3)| = 2e-5 < 1e-4
    return Motion(motion.t, pose, motion.velocity, motion.acceleration)


# (chunk, reactions): the chunked numpy path, and (None, False) the loop over single samples
PATHS = [(1, True), (4, True), (4096, True), (4096, False)]


@pytest.mark.parametrize(("chunk", "reactions"), PATHS)
def test_singular_pose_is_refused_with_the_reference_message(chunk: int, reactions: bool) -> None:
    motion = singular_motion(10, index=6)
    with pytest.raises(SingularPoseError) as reference:
        inverse_dynamics(Robot(), motion)
    with pytest.raises(SingularPoseError) as fast:
        paper_forces(
            Robot(), motion.pose, motion.velocity, motion.acceleration,
            chunk_size=chunk, reactions=reactions,
        )  # fmt: skip
    assert str(fast.value) == str(reference.value)
    assert "sample 6" in str(fast.value)
    with pytest.raises(SingularPoseError) as one:
        sample_forces(
            compile_robot(Robot()), motion.pose[6], motion.velocity[6], motion.acceleration[6]
        )
    assert "singular pose (x=0.0, y=0.0, phi=" in str(one.value)


@pytest.mark.parametrize(("chunk", "reactions"), PATHS)
def test_pose_outside_the_stroke_is_refused_with_the_reference_message(
    chunk: int, reactions: bool
) -> None:
    # Vertical motion (φ = 0, x = 0): eq. (10) with d_A = (1, 0), D = sin(−π/3) = −√3/2 and
    # G × d_A = −y gives λ10_A = 2y/√3, beyond a stroke of ±1 cm once y > 8.7 mm (y ends at 5 cm).
    robot = Robot(limits=Limits(stroke=(-0.01, 0.01)))
    motion = paper_motion("vertical", samples=10)
    with pytest.raises(UnreachablePoseError) as reference:
        inverse_dynamics(robot, motion)
    with pytest.raises(UnreachablePoseError) as fast:
        paper_forces(
            robot, motion.pose, motion.velocity, motion.acceleration,
            chunk_size=chunk, reactions=reactions,
        )  # fmt: skip
    assert str(fast.value) == str(reference.value)
    index = fast.value.sample  # a field of the error, not parsed from its message
    assert index is not None and index > 0  # the motion starts at the centre, inside the stroke
    with pytest.raises(UnreachablePoseError):
        sample_forces(
            compile_robot(robot), motion.pose[-1], motion.velocity[-1], motion.acceleration[-1]
        )
    inside = sample_forces(
        compile_robot(robot), motion.pose[0], motion.velocity[0], motion.acceleration[0]
    )
    np.testing.assert_allclose(
        inside.f10,
        paper_forces(Robot(), motion.pose[0], motion.velocity[0], motion.acceleration[0]).f10,
    )


@pytest.mark.parametrize("name", ["pose", "velocity", "acceleration"])
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("reactions", [True, False])
def test_non_finite_input_is_refused(name: str, bad: float, reactions: bool) -> None:
    motion = paper_motion("rotation", samples=6)
    arrays = {n: getattr(motion, n).copy() for n in ("pose", "velocity", "acceleration")}
    arrays[name][4, 1] = bad
    component = {"pose": "y", "velocity": "dy", "acceleration": "ddy"}[name]
    with pytest.raises(TrajectoryError, match=rf"^sample 4: {component} of {name} is not finite"):
        paper_forces(Robot(), **arrays, chunk_size=2, reactions=reactions)
    single = {n: a[4] for n, a in arrays.items()}
    with pytest.raises(TrajectoryError, match=rf"{component} of {name} is not finite"):
        sample_forces(compile_robot(Robot()), **single)


@pytest.mark.parametrize("singular", [False, True])
@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_rates_are_refused_by_the_batch_path(
    bad: float, engine: str, singular: bool
) -> None:
    # checked before any engine runs (40 samples, chunks of 16), named before a singular pose
    compiled = compile_robot(Robot())
    motion = paper_motion("rotation", samples=40)
    for name in ("velocity", "acceleration"):
        for k, component in enumerate(("x", "y", "phi")):
            arrays = {n: getattr(motion, n).copy() for n in ("pose", "velocity", "acceleration")}
            arrays[name][25, k] = bad
            if singular:  # a singular pose earlier: the non-finite rate is still named first
                arrays["pose"][3, 2] = math.pi / 3
            prefix = {"velocity": "d", "acceleration": "dd"}[name]
            message = rf"^sample 25: {prefix}{component} of {name} is not finite"
            with pytest.raises(TrajectoryError, match=message):
                actuator_forces(compiled, **arrays, chunk_size=16, engine=engine)  # type: ignore[arg-type]
            with pytest.raises(TrajectoryError, match=message):
                paper_forces(compiled, **arrays, chunk_size=16, engine=engine)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("pose", "velocity", "message"),
    [
        (np.zeros((4, 3)), np.zeros((5, 3)), "must have the same shape"),
        (np.zeros((4, 2)), np.zeros((4, 2)), r"pose must have shape \(3,\) or \(N, 3\)"),
        (np.zeros((2, 4, 3)), np.zeros((2, 4, 3)), r"pose must have shape"),
        ("abc", np.zeros(3), "pose must be an array of real numbers, got text"),
    ],
)
def test_bad_shapes_are_refused(pose: object, velocity: object, message: str) -> None:
    with pytest.raises(TrajectoryError, match=message):
        paper_forces(Robot(), pose, velocity, velocity)  # type: ignore[arg-type]


@pytest.mark.parametrize("chunk", [0, -3, 2.5, True, 10**400, 10**6 + 1])
def test_bad_chunk_size_is_refused(chunk: object) -> None:
    # also for one sample (the few-samples path uses no chunks: refused all the same)
    for pose in ([0, 0, 0], [[0, 0, 0]] * 20):
        with pytest.raises(Prp3Error, match=r"chunk_size must be an integer from 1 to 1e\+06"):
            paper_forces(Robot(), pose, pose, pose, chunk_size=chunk)  # type: ignore[arg-type]
    with pytest.raises(Prp3Error, match="engine must be one of 'numba', 'numpy', got 'cuda'"):
        actuator_forces(Robot(), [0, 0, 0], [0, 0, 0], [0, 0, 0], engine="cuda")  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("pose", "message"),
    [
        ([0.0, 0.0], r"pose must have shape \(3,\) or \(N, 3\)"),
        ([[0.0, 0.0, 0.0]], r"pose must be 3 numbers \(shape \(3,\)\), got shape \(1, 3\)"),
        (None, "pose must be an array of real numbers, got None"),
        (["a", "b", "c"], "pose must be an array of real numbers, got text"),
    ],
)
def test_single_sample_bad_input_is_refused(pose: object, message: str) -> None:
    with pytest.raises(TrajectoryError, match=message):
        sample_forces(compile_robot(Robot()), pose, [0, 0, 0], [0, 0, 0])  # type: ignore[arg-type]


def test_single_sample_needs_a_compiled_robot() -> None:
    with pytest.raises(
        Prp3Error, match=r"compiled must come from compile_robot\(robot\), got Robot"
    ):
        sample_forces(Robot(), [0, 0, 0], [0, 0, 0], [0, 0, 0])  # type: ignore[arg-type]


# -------------------------------------------------- single sample: inputs, checks, a load
def test_single_sample_takes_arrays_tuples_lists_and_integers_alike() -> None:
    compiled = compile_robot(Robot())
    motion = paper_motion("rotation", samples=31)[12]
    pose, velocity, acceleration = motion.pose, motion.velocity, motion.acceleration
    expected = sample_forces(compiled, pose, velocity, acceleration)
    as_tuples = [tuple(a.tolist()) for a in (pose, velocity, acceleration)]
    as_lists = [a.tolist() for a in (pose, velocity, acceleration)]
    assert sample_forces(compiled, *as_tuples) == expected
    assert sample_forces(compiled, *as_lists) == expected
    # np.float64 scalars and integers: the batch path's conversion, the same numbers
    scalars = [tuple(np.float64(v) for v in a) for a in (pose, velocity, acceleration)]
    batch = paper_forces(compiled, pose[None], velocity[None], acceleration[None])
    for got in (
        sample_forces(compiled, *scalars),
        sample_forces(compiled, pose, [0, 0, 0], [1, 2, 3]),
    ):
        assert all(type(v) is float for legs in got for v in legs)
    one = sample_forces(compiled, *scalars)
    for name in OUTPUTS:
        np.testing.assert_allclose(
            getattr(one, name), getattr(batch, name)[0], rtol=1e-15, atol=1e-13
        )
    ints = sample_forces(compiled, (0, 0, 0), (0, 0, 0), (0, 0, 0))
    assert ints == sample_forces(compiled, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    for inputs in (as_tuples, as_lists, scalars, (pose, velocity, acceleration)):
        f10 = sample_actuator_forces(compiled, *inputs)
        assert type(f10) is tuple and f10 == expected.f10


@pytest.mark.parametrize(
    ("pose", "velocity", "error"),
    [
        ([0.0, 0.0, math.pi / 3], [0.0, 0.0, 0.0], SingularPoseError),
        ([0.0, 31.0, 0.0], [0.0, 0.0, 0.0], TrajectoryError),  # beyond 100·l0
        ([0.0, 0.0, 0.0], [0.0, 1e308, 1e308], TrajectoryError),  # a sum that overflows
        ([0.0, 0.0, 0.0], [math.nan, 0.0, 0.0], TrajectoryError),
        ((True, 0.0, 0.0), [0.0, 0.0, 0.0], None),  # whatever the batch path does
        ({0.0, 1.0, 2.0}, [0.0, 0.0, 0.0], None),
    ],
)
def test_single_sample_refuses_what_the_batch_path_refuses(
    pose: object, velocity: list[float], error: type[Exception] | None
) -> None:
    compiled, zero = compile_robot(Robot()), [0.0, 0.0, 0.0]
    try:
        expected = paper_forces(compiled, pose, velocity, zero)  # type: ignore[arg-type]
    except Prp3Error as refused:
        assert error is None or type(refused) is error
        for single_sample in (sample_forces, sample_actuator_forces):
            with pytest.raises(type(refused)) as single:
                single_sample(compiled, pose, velocity, zero)  # type: ignore[arg-type]
            assert str(single.value) == str(refused)
    else:
        assert error is None
        one = sample_forces(compiled, pose, velocity, zero)  # type: ignore[arg-type]
        np.testing.assert_allclose(one.f10, expected.f10, rtol=1e-15, atol=1e-13)
        assert sample_actuator_forces(compiled, pose, velocity, zero) == one.f10  # type: ignore[arg-type]


@pytest.mark.parametrize("engine", ENGINES)
def test_finite_results_whose_sum_overflows_are_returned(engine: str) -> None:
    # two actuator forces of about -3e307 and more: each finite, their sum -inf (the one-sample
    # entries' quick test); was an AssertionError, now the numbers of the batch path
    compiled = compile_robot(Robot())
    velocity, acceleration = [0.0, 3.0, 0.0], [-1e307, -1e307, 1.0]
    batch = paper_forces(compiled, [0.0, 0.0, 0.0], velocity, acceleration, engine=engine)
    one = sample_forces(compiled, [0.0, 0.0, 0.0], velocity, acceleration, engine=engine)
    values = [v for name in OUTPUTS for v in getattr(one, name)]
    assert all(math.isfinite(v) for v in values) and not math.isfinite(sum(values))
    for name in OUTPUTS:
        np.testing.assert_allclose(getattr(one, name), getattr(batch, name), rtol=1e-14)
    f10 = sample_actuator_forces(compiled, [0.0, 0.0, 0.0], velocity, acceleration, engine=engine)
    np.testing.assert_allclose(f10, batch.f10, rtol=1e-14)


def _with_effects(robot: Robot, friction: bool, mu: float) -> Robot:
    from prp3.model.parameters import Load

    joint = JointFriction(viscous=0.7, coulomb=0.4, mu=mu, smoothing=0.05)
    return Robot(
        l0=robot.l0, gravity=robot.gravity, piston=robot.piston, link=robot.link,
        platform=robot.platform, load=Load(force=(1.5, -2.0), moment=0.3),
        friction=Friction(joint, joint, joint) if friction else None,
    )  # fmt: skip


@pytest.mark.parametrize(("friction", "mu"), [(False, 0.0), (True, 0.0), (True, 0.02)])
def test_the_unchecked_f10_alone_is_the_unchecked_call_s_f10(friction: bool, mu: float) -> None:
    # a constant load, viscous and smoothed Coulomb friction traced, mu terms by the
    # kernel's Newton solve: f10 alone is the first three values of sample_function
    compiled = compile_robot(_with_effects(Robot(), friction, mu))
    state = (0.01, -0.02, 0.3, 0.1, -0.2, 0.5, 1.0, -2.0, 3.0)
    for engine in ENGINES:
        f10 = compiled.actuator_sample_function(engine)(*state)  # type: ignore[arg-type]
        assert len(f10) == 3 and f10 == compiled.sample_function(engine)(*state)[:3]  # type: ignore[arg-type]
        assert f10 == sample_forces(compiled, state[:3], state[3:6], state[6:], engine=engine).f10  # type: ignore[arg-type]


@settings(max_examples=10, deadline=None)
@given(
    scenario=scenarios(),
    effects=st.sampled_from([(False, 0.0), (True, 0.0), (True, 0.02)]),
    seed=st.integers(0, 2**32 - 1),
)
def test_single_sample_with_a_load_agrees_with_the_batch_path(
    scenario: tuple[Robot, AnalyticMotion], effects: tuple[bool, float], seed: int
) -> None:
    # The time-varying load (f_x, f_y, m_z) as three more traced inputs: the single-sample
    # path agrees with solve_batch(load=...) (the kernel on numpy arrays) to round-off,
    # with the robot's constant load and friction (viscous and smoothed Coulomb traced,
    # the mu terms by the kernel's Newton solve).
    robot, analytic = scenario
    robot = _with_effects(robot, *effects)
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 6))
    load = np.random.default_rng(seed).normal(size=(6, 3)) * [20.0, 20.0, 2.0]
    batch = solve_batch(robot, motion.pose, motion.velocity, motion.acceleration, load=load)
    unloaded = solve_batch(robot, motion.pose, motion.velocity, motion.acceleration)
    compiled = compile_robot(robot)
    for k in range(6):
        state = (motion.pose[k], motion.velocity[k], motion.acceleration[k])
        one = sample_forces(compiled, *state, load=load[k])
        assert sample_forces(compiled, *state, load=tuple(load[k].tolist())) == one
        # f10 alone: the kernel traced for f10 only, the same operations (bit for bit)
        assert sample_actuator_forces(compiled, *state, load=load[k]) == one.f10
        assert sample_actuator_forces(compiled, *state) == sample_forces(compiled, *state).f10
        for name in OUTPUTS:
            expected = batch[name][k]
            scale = np.abs(expected).max() + 1.0
            assert np.abs(np.array(getattr(one, name)) - expected).max() <= 1e-15 * scale, name
        # and the load matters: without it the forces differ
        assert not np.allclose(sample_forces(compiled, *state).f10, one.f10, rtol=0, atol=1e-9)
        np.testing.assert_allclose(
            sample_forces(compiled, *state).f10, unloaded["f10"][k], rtol=1e-14, atol=1e-12
        )


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("friction", [False, True])
def test_single_sample_load_is_the_kernel_on_floats(engine: str, friction: bool) -> None:
    from prp3.mechanics import kernel
    from prp3.mechanics.ops import MATH

    robot = _with_effects(Robot(), friction, 0.0)
    compiled = compile_robot(robot)
    state = (0.01, -0.02, 0.3, 0.1, -0.2, 0.5, 1.0, -2.0, 3.0)
    load = (4.0, -5.0, 0.25)
    one = sample_forces(compiled, state[:3], state[3:6], state[6:], load, engine=engine)  # type: ignore[arg-type]
    expected = kernel.solve(MATH, compiled.parameters, *state, reactions=False, load=load)
    for got, legs in zip(
        one, (expected.f10, expected.p10, expected.f21y, expected.f21z), strict=True
    ):
        np.testing.assert_allclose(got, legs, rtol=1e-15, atol=1e-15 * (np.abs(legs).max() + 1))


@pytest.mark.parametrize(
    ("load", "message"),
    [
        ([math.nan, 0.0, 0.0], r"fx of load is not finite \(nan\)"),
        ([0.0, 0.0, math.inf], r"mz of load is not finite \(inf\)"),
        ([0.0, 1.0], r"load must have shape \(3,\) or \(N, 3\)"),
        ("abc", "load must be an array of real numbers, got text"),
        ([[0.0, 0.0, 0.0]], r"load must have the shape of pose \(3,\)"),
    ],
)
def test_single_sample_bad_load_is_refused_as_the_batch_path(load: object, message: str) -> None:
    zero = [0.0, 0.0, 0.0]
    with pytest.raises(TrajectoryError, match=message):
        sample_forces(compile_robot(Robot()), zero, zero, zero, load=load)  # type: ignore[arg-type]


def test_batch_non_finite_load_is_refused_naming_the_sample() -> None:
    load = np.zeros((4, 3))
    load[2, 1] = math.nan
    zeros = np.zeros((4, 3))
    with pytest.raises(TrajectoryError, match=r"^sample 2: fy of load is not finite \(nan\)"):
        solve_batch(Robot(), zeros, zeros, zeros, load=load)


# ------------------------------------------------------------- f10 alone
@settings(max_examples=10, deadline=None)
@given(scenario=scenarios(), samples=st.sampled_from([1, 7, 40]), chunk=st.sampled_from([3, 4096]))
def test_actuator_forces_are_paper_forces_f10(
    scenario: tuple[Robot, AnalyticMotion], samples: int, chunk: int
) -> None:
    # The kernel traced for f10 alone: the same operations for f10, so the same numbers.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, samples))
    compiled = compile_robot(robot)
    args = (motion.pose, motion.velocity, motion.acceleration)
    expected = paper_forces(compiled, *args, chunk_size=chunk).f10
    np.testing.assert_array_equal(actuator_forces(compiled, *args, chunk_size=chunk), expected)
    out = np.empty_like(expected)
    assert actuator_forces(robot, *args, out=out) is out
    np.testing.assert_array_equal(out, expected)
    one = actuator_forces(compiled, motion.pose[0], motion.velocity[0], motion.acceleration[0])
    assert one.shape == (3,)
    np.testing.assert_array_equal(one, expected[0])


def test_actuator_forces_refuse_as_paper_forces() -> None:
    motion = singular_motion(10, index=6)
    args = (motion.pose, motion.velocity, motion.acceleration)
    with pytest.raises(SingularPoseError) as batch:
        paper_forces(Robot(), *args)
    with pytest.raises(SingularPoseError) as alone:
        actuator_forces(Robot(), *args)
    assert str(alone.value) == str(batch.value)
    zero = np.zeros((4, 3))
    with pytest.raises(Prp3Error, match=r"^out must be a writeable C-contiguous float64 array"):
        actuator_forces(Robot(), zero, zero, zero, out=np.zeros((4, 3)).T.copy().T)
    with pytest.raises(TrajectoryError, match="pose must be an array of real numbers, got text"):
        actuator_forces(Robot(), "abc", zero, zero)  # type: ignore[arg-type]
