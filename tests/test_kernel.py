"""The one kernel serves every engine: floats, numpy arrays, numba, sympy.

The physics of the kernel is tested against Newton–Euler and the paper's
matrices elsewhere (``test_dynamics``, ``test_fast``, ``test_balances``); here
each engine is held against the reference — the kernel on numpy arrays and
Newton–Euler — to 1e-13 of a per-sample scale on random robots and motions,
and the traced numpy code of the design sweeps (:mod:`prp3.engines.trace`) against
the kernel bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from prp3 import Motion, Prp3Error, Robot, SingularPoseError, newton_euler
from prp3.engines import select as engines
from prp3.engines.compiled_robot import compile_robot
from prp3.engines.entries import actuator_forces, paper_forces, solve_batch
from prp3.engines.sample_entries import sample_forces_unchecked
from prp3.engines.select import ENGINES
from prp3.engines.trace import array_function, broadcast_function
from prp3.mechanics import kernel
from prp3.mechanics.geometry import inverse_geometry
from prp3.mechanics.kernel import STATE_SYMBOLS, KernelSolution, solve, symbolic_solution
from prp3.mechanics.ops import MATH, NUMPY
from prp3.mechanics.parameters import (
    INERTIAL_FIELDS,
    KernelParameters,
    kernel_parameters,
    symbolic_parameters,
)
from strategies import robots, scenarios

FIELDS = KernelSolution._fields[:14]  # the per-leg joint motion and forces


def states(robot: Robot, rng: np.random.Generator, n: int) -> np.ndarray:
    """``(n, 9)`` random regular states of the size of ``robot``."""
    pose = np.column_stack([rng.uniform(-0.1, 0.1, (n, 2)) * robot.l0, rng.uniform(-0.8, 0.8, n)])
    return np.column_stack([pose, rng.normal(size=(n, 3)), rng.normal(size=(n, 3)) * 3])


@settings(max_examples=20, deadline=None)
@given(robot=robots(), seed=st.integers(0, 2**32 - 1))
def test_floats_and_arrays_are_the_same_operations(robot: Robot, seed: int) -> None:
    k = kernel_parameters(robot)
    rows = states(robot, np.random.default_rng(seed), 5)
    batch = solve(NUMPY, k, *rows.T)
    for n, row in enumerate(rows.tolist()):
        one = solve(MATH, k, *row)
        for name in FIELDS:
            got, expected = np.array(getattr(one, name)), np.stack(getattr(batch, name))[:, n]
            scale = np.abs(expected).max() + 1.0
            # only cos and sin may differ (in their last bit) between math and numpy
            assert np.abs(got - expected).max() <= 1e-15 * scale * 16, name


@settings(max_examples=10, deadline=None)
@given(scenario=scenarios(), seed=st.integers(0, 2**32 - 1))
def test_single_sample_and_batch_paths_agree(scenario, seed) -> None:  # type: ignore[no-untyped-def]
    robot, _ = scenario
    rows = states(robot, np.random.default_rng(seed), 40)
    compiled = compile_robot(robot)
    batch = paper_forces(compiled, rows[:, :3], rows[:, 3:6], rows[:, 6:], engine="numpy")
    for n, row in enumerate(rows.tolist()):
        one = sample_forces_unchecked(compiled, *row)
        # f10 alone (the control loop's model): the same operations for f10, bit for bit
        assert compiled.actuator_sample_function()(*row) == one[:3]
        for j, name in enumerate(("f10", "p10", "f21y", "f21z")):
            expected = getattr(batch, name)[n]
            scale = np.abs(expected).max() + 1.0
            assert np.abs(np.array(one[3 * j : 3 * j + 3]) - expected).max() <= 1e-14 * scale


CHECKED = ("lambda10", "ddlambda32", "f10", "f21y", "f21z", "n32", "m32")


@pytest.fixture(scope="module")
def symbolic():  # type: ignore[no-untyped-def]
    """The kernel on sympy symbols, turned into an mpmath function (30 digits)."""
    sympy = pytest.importorskip("sympy")
    pytest.importorskip("mpmath")
    parameters = symbolic_parameters()
    state, sol = symbolic_solution(parameters)
    symbols = [getattr(parameters, f) for f in INERTIAL_FIELDS] + list(state)
    expressions = [e for name in CHECKED for e in getattr(sol, name)]
    return sympy.lambdify(symbols, expressions, modules="mpmath")


@settings(max_examples=10, deadline=None)
@given(robot=robots(), seed=st.integers(0, 2**32 - 1))
def test_symbolic_evaluation_equals_the_numeric_one(symbolic, robot, seed) -> None:  # type: ignore[no-untyped-def]
    import mpmath

    numbers = kernel_parameters(robot)
    row = states(robot, np.random.default_rng(seed), 1)[0].tolist()
    with mpmath.workdps(30):
        values = [getattr(numbers, f) for f in INERTIAL_FIELDS] + row
        got = np.array([float(v) for v in symbolic(*values)]).reshape(len(CHECKED), 3)
    expected = solve(MATH, numbers, *row)
    for name, values_of_name in zip(CHECKED, got, strict=True):
        want = np.array(getattr(expected, name))
        scale = np.abs(want).max() + 1.0
        assert np.abs(values_of_name - want).max() <= 1e-12 * scale, name


def test_numba_engine_runs_the_same_operations() -> None:
    pytest.importorskip("numba")
    robot = Robot.from_mapping({"link": {"com": [0.01, 0.02]}, "limits": {"stroke": [-0.2, 0.2]}})
    compiled = compile_robot(robot)
    rows = states(robot, np.random.default_rng(7), 50)
    args = (rows[:, :3], rows[:, 3:6], rows[:, 6:])
    fast = paper_forces(compiled, *args, reactions=True, engine="numba")
    plain = paper_forces(compiled, *args, reactions=True, engine="numpy")
    for name in ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32"):
        expected = getattr(plain, name)
        scale = np.abs(expected).max() + 1.0
        assert np.abs(getattr(fast, name) - expected).max() <= 1e-15 * scale, name
    # non-contiguous inputs, f10 alone, the forces alone: the same numbers
    chunked = paper_forces(compiled, *(np.asfortranarray(a) for a in args), engine="numba")
    np.testing.assert_array_equal(chunked.f10, fast.f10)
    np.testing.assert_array_equal(actuator_forces(compiled, *args, engine="numba"), fast.f10)
    np.testing.assert_array_equal(paper_forces(compiled, *args, engine="numba").f21z, fast.f21z)
    # the unchecked single-sample functions (their machine code): the 12 forces and, with a
    # stroke, λ10 of eq. (10) after them, as the numpy engine and the inverse geometry give
    lambda10 = inverse_geometry(robot, rows[:, :3]).lambda10
    for n, row in enumerate(rows[:5].tolist()):
        one = sample_forces_unchecked(compiled, *row)
        assert one == compiled.sample_function("numba")(*row)
        assert compiled.actuator_sample_function("numba")(*row) == one[:3]
        plain_one = compiled.sample_function("numpy")(*row)
        assert len(one) == len(plain_one) == 15
        np.testing.assert_allclose(one, plain_one, rtol=1e-14, atol=1e-12)
        np.testing.assert_allclose(one[12:], lambda10[n], rtol=1e-14, atol=1e-15)
    singular = rows[:, :3].copy()
    singular[30, 2] = math.pi / 3 + 1e-6
    with pytest.raises(SingularPoseError, match="sample 30"):
        paper_forces(compiled, singular, rows[:, 3:6], rows[:, 6:], engine="numba")
    with pytest.raises(Prp3Error, match="engine must be"):
        paper_forces(compiled, *args, engine="cuda")  # type: ignore[arg-type]


def test_solve_batch_returns_every_kernel_output_with_the_input_rank() -> None:
    one = solve_batch(Robot(), [0.01, 0.0, 0.1], [0, 0, 0], [0, 0, 0])
    many = solve_batch(Robot(), [[0.01, 0.0, 0.1]] * 2, [[0, 0, 0]] * 2, [[0, 0, 0]] * 2)
    assert set(one) == set(FIELDS) and all(a.shape == (3,) for a in one.values())
    assert all(a.shape == (2, 3) for a in many.values())
    # λ10 by hand: at rest at (x, 0, φ = 0.1) with x = 0.01 the sum of the actuator
    # displacements depends on φ only: Σλ10 = (3 l0/2)·tan(ψ/2) + √3 l0/2, ψ = φ − π/3
    psi = 0.1 - math.pi / 3
    assert one["lambda10"].sum() == pytest.approx(
        1.5 * 0.3 * math.tan(psi / 2) + math.sqrt(3) * 0.3 / 2, rel=1e-13
    )


@settings(max_examples=15, deadline=None)
@given(
    h=st.tuples(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5)),
    mass=st.floats(0.5, 5.0),
    inertia=st.floats(0.0, 0.2),
    seed=st.integers(0, 2**32 - 1),
)
def test_platform_first_moment_by_its_energy(h, mass, inertia, seed) -> None:  # type: ignore[no-untyped-def]
    # Only the platform has mass, its centre at G + Rot(φ)·h/m (a payload): the
    # power of the actuators is the rate of its energy, written here from scratch:
    # E = ½m|v_C|² + ½(J − m|r|²)·φ̇² − m·g·C with C = G + Rot(φ)·r, r = h/m.
    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.02, 0.02, 3)
    w = rng.uniform(0.5, 2.0, 3)
    g = (0.7, -9.81)

    def pose(t: float) -> np.ndarray:
        return np.array(
            [a[0] * math.sin(w[0] * t), a[1] * math.sin(w[1] * t), 0.3 * math.sin(w[2] * t)]
        )

    def energy(t: float, dt: float = 1e-5) -> float:
        q, qd = pose(t), (pose(t + dt) - pose(t - dt)) / (2 * dt)
        r = np.array(h) / mass
        c, s = math.cos(q[2]), math.sin(q[2])
        rr = np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])
        v = qd[:2] + qd[2] * np.array([-rr[1], rr[0]])
        com = q[:2] + rr
        return (
            0.5 * mass * v @ v
            + 0.5 * (inertia + mass * r @ r - mass * r @ r) * qd[2] ** 2
            - mass * (g[0] * com[0] + g[1] * com[1])
        )

    zeros = dict.fromkeys(
        ("piston_mass", "piston_moment_x", "piston_moment_y", "link_mass", "link_moment_x",
         "link_moment_y", "link_inertia"), 0.0,
    )  # fmt: skip
    k = KernelParameters(
        l0=0.3, gravity_x=g[0], gravity_y=g[1], platform_mass=mass, platform_moment_x=h[0],
        platform_moment_y=h[1], platform_inertia=inertia + (h[0] ** 2 + h[1] ** 2) / mass, **zeros,
    )  # fmt: skip
    t, dt = 0.7, 1e-3
    q = pose(t)
    qd = np.array([a[0] * w[0] * math.cos(w[0] * t), a[1] * w[1] * math.cos(w[1] * t),
                   0.3 * w[2] * math.cos(w[2] * t)])  # fmt: skip
    qdd = -np.array([a[0] * w[0] ** 2, a[1] * w[1] ** 2, 0.3 * w[2] ** 2]) * np.sin(w * t)
    power = sum(solve(MATH, k, *q, *qd, *qdd).p10)
    rate = (energy(t + dt) - energy(t - dt)) / (2 * dt)  # O(dt²) ≈ 1e-6 relative
    assert abs(power - rate) <= 1e-5 * (abs(power) + mass * 10 * 0.1)


def test_argument_names_of_the_generated_code_s_own_are_refused() -> None:
    # the generated code names its rows w0, w1, ..., its outputs o0, ... and constants k0, ...
    def f(ops, a, b):  # type: ignore[no-untyped-def]
        return (a * b,)

    for names in (("w1", "b"), ("a", "o0"), ("k3", "b"), ("w1_2", "b")):
        with pytest.raises(ValueError, match="the generated code's own"):
            array_function(f, names)
        with pytest.raises(ValueError, match="the generated code's own"):
            broadcast_function(f, names, (0, 1))
    assert array_function(f, ("w", "o1x")).rows == 0  # not of that form: accepted


def test_a_constant_is_not_taken_for_the_line_of_its_value() -> None:
    # lines are numbered 0, 1, 2...: x + 1.0 (a constant) is not x + line 1
    def f(ops, x):  # type: ignore[no-untyped-def]
        c, s = ops.cos(x), ops.sin(x)
        return (c, x + s, x + 1.0, x * 2.0 + c * 2.0)

    out = np.empty((4, 1))
    array_function(f, ("x",))(np.zeros(1), out)
    assert out[:, 0].tolist() == [1.0, 0.0, 1.0, 2.0]


@settings(max_examples=10, deadline=None)
@given(robot=robots(), seed=st.integers(0, 2**32 - 1))
def test_broadcast_code_is_the_kernel_on_a_block_of_robots(robot: Robot, seed: int) -> None:
    # The inertial parameters of 4 robots as a column (B, 1), the states as a row (1, n):
    # the kernel traced at the shapes of what each operation depends on gives the same
    # numbers as the kernel on those arrays, and as the kernel of each robot alone.
    rng = np.random.default_rng(seed)
    base = kernel_parameters(robot)
    varied = ("l0", "link_mass", "platform_inertia", "piston_moment_x")
    column = {
        n: getattr(base, n) * rng.uniform(0.5, 1.5, (4, 1)) + (0.01 if "moment" in n else 0.0)
        for n in varied
    }
    fixed = {n: getattr(base, n) for n in INERTIAL_FIELDS if n not in varied}
    effects = {n: getattr(base, n) for n in KernelParameters.__dataclass_fields__ if n not in
               INERTIAL_FIELDS}  # fmt: skip
    if KernelParameters(**fixed, **effects, **{n: 1.0 for n in varied}).has_mu:
        return  # implicit friction: the kernel solves it sample by sample
    rows = states(robot, rng, 7).T[:, None, :]  # nine (1, 7) rows

    def outputs(ops, *values):  # type: ignore[no-untyped-def]
        k = KernelParameters(**fixed, **effects, **dict(zip(varied, values[:4], strict=True)))
        sol = solve(ops, k, *values[4:])
        return tuple(v for name in FIELDS for v in getattr(sol, name))

    function = broadcast_function(outputs, (*varied, *STATE_SYMBOLS), (0,) * 4 + (1,) * 9)
    shapes = {1: (4, 1), 2: (1, 7), 3: (4, 7)}
    work = [np.empty((rows_, *shapes[mask])) for mask, rows_ in function.blocks]
    out = np.empty((3 * len(FIELDS), 4, 7))
    function(*(column[n] for n in varied), *rows, out=out, work=work)
    on_arrays = outputs(NUMPY, *(column[n] for n in varied), *rows)
    for j, value in enumerate(on_arrays):
        np.testing.assert_array_equal(out[j], np.broadcast_to(value, (4, 7)))
    alone = outputs(NUMPY, *(column[n][2:3] for n in varied), *rows)
    for j, value in enumerate(alone):
        np.testing.assert_array_equal(out[j, 2], np.broadcast_to(value, (1, 7))[0])


# ------------------------------------------------------------- each engine, held against the reference
#: Outputs of solve_batch compared, by kind of scale.
_FORCE_OUTPUTS = ("f10", "f21y", "f21z", "n10", "n32")
_MOMENT_OUTPUTS = ("m10", "m32")
_MOTION_OUTPUTS = ("lambda10", "dlambda10", "ddlambda10", "lambda32", "dlambda32", "ddlambda32")


def _scales(robot: Robot, values: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Per-sample scale ``(N, 1)`` of each output of the reference ``values``."""
    weight = (
        robot.piston.mass * 3 + robot.link.mass * 3 + robot.platform.mass + robot.payload.mass
    ) * math.hypot(*robot.gravity)
    force = np.max([np.abs(values[n]).max(axis=-1) for n in _FORCE_OUTPUTS], axis=0) + weight
    force = force + 1e-100  # at rest without gravity every force is zero
    scale = dict.fromkeys(_FORCE_OUTPUTS, force)
    scale.update(dict.fromkeys(_MOMENT_OUTPUTS, force * robot.l0 * 10))
    scale["p10"] = force * (np.abs(values["dlambda10"]).max(axis=-1) + 1e-100)
    for name in _MOTION_OUTPUTS:
        scale[name] = np.abs(values[name]).max(axis=-1) + robot.l0
    return {name: s[:, None] for name, s in scale.items()}


@settings(max_examples=30, deadline=None)
@given(
    scenario=scenarios(),
    engine=st.sampled_from(ENGINES),
    samples=st.sampled_from([1, 3, 40]),
    loaded=st.booleans(),
    seed=st.integers(0, 2**32 - 1),
)
def test_each_engine_is_the_kernel_on_arrays_and_newton_euler(  # type: ignore[no-untyped-def]
    scenario, engine, samples, loaded, seed
) -> None:
    # Random robots (l0, masses, inertias, centres of mass, gravity) and smooth motions,
    # with or without a time-varying load: every output of solve_batch by each engine
    # against kernel.solve on numpy arrays and the reactions against Newton–Euler (the
    # balances of the 7 bodies, which share nothing with the kernel), to 1e-13 of a scale.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, samples))
    load = np.random.default_rng(seed).normal(size=(samples, 3)) * [20.0, 20.0, 2.0]
    wrench = load if loaded else None
    args = (motion.pose, motion.velocity, motion.acceleration)
    got = solve_batch(robot, *args, load=wrench, engine=engine)
    sol = solve(
        NUMPY, kernel_parameters(robot), *(a[:, j] for a in args for j in range(3)),
        load=None if wrench is None else tuple(wrench.T),
    )  # fmt: skip
    reference = {name: np.stack(getattr(sol, name), axis=-1) for name in FIELDS}
    scale = _scales(robot, reference)
    for name in FIELDS:
        error = np.abs(got[name] - reference[name]) / scale[name]
        assert error.max() <= 1e-13, (name, float(error.max()))
    ne = newton_euler(robot, Motion(motion.t, *args, load=wrench))
    for name in ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32"):
        error = np.abs(got[name] - getattr(ne, name)) / scale[name]
        assert error.max() <= 1e-13, (name, float(error.max()))


def test_the_numpy_engine_runs_the_kernel_itself(monkeypatch: pytest.MonkeyPatch) -> None:
    # engine="numpy" calls body_wrenches (through kernel.dynamics) on the arrays (a
    # breakpoint there stops): no generated code stands between the caller and the kernel
    calls: list[int] = []
    original = kernel.body_wrenches

    def spy(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls.append(np.size(args[2]))
        return original(*args, **kwargs)

    monkeypatch.setattr(kernel, "body_wrenches", spy)
    zeros = np.zeros((20, 3))
    paper_forces(Robot(), zeros, zeros, zeros, engine="numpy", chunk_size=8)
    assert calls == [8, 8, 4]  # one call per chunk, on arrays
    calls.clear()
    prp3_sample = __import__(
        "prp3.engines.sample_entries", fromlist=["sample_forces"]
    ).sample_forces
    prp3_sample(compile_robot(Robot()), (0, 0, 0), (0, 0, 0), (0, 0, 0), engine="numpy")
    assert calls == [1]  # one sample, on floats


@pytest.mark.parametrize("samples", [0, 1, 2, 20, 5000])
def test_engine_numba_without_numba_is_refused_at_every_size(
    samples: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(engines, "_numba", None)  # as if numba did not import
    zeros = np.zeros((samples, 3))
    compiled = compile_robot(Robot())
    message = r'engine="numba" needs numba, which is not installed'
    for call in (paper_forces, actuator_forces, solve_batch):
        with pytest.raises(Prp3Error, match=message):
            call(compiled, zeros, zeros, zeros, engine="numba")  # type: ignore[operator]
    with pytest.raises(Prp3Error, match=message):
        prp3_fast = __import__("prp3.engines.sample_entries", fromlist=["sample_forces"])
        prp3_fast.sample_forces(compiled, (0, 0, 0), (0, 0, 0), (0, 0, 0), engine="numba")


def test_without_numba_the_default_is_numpy_and_says_so_once(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(engines, "_numba", None)
    monkeypatch.setattr(engines, "_warned", False)
    zeros = np.zeros((3, 3))
    with pytest.warns(engines.EngineWarning, match="numba is not installed"):
        first = paper_forces(Robot(), zeros, zeros, zeros)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said once: no second warning
        again = paper_forces(Robot(), zeros, zeros, zeros)
    np.testing.assert_array_equal(first.f10, again.f10)
    assert engines.default_engine() == "numpy"


def test_the_numba_cache_is_keyed_on_the_kernel_sources_too() -> None:
    # the engine's loops inline the kernel's stages: their cached machine code must be
    # stale when any module whose functions it compiles changes, not only numba.py
    numba_engine = pytest.importorskip("prp3.engines.numba")
    import os

    from numba.core import caching

    from prp3.mechanics import joint_motion, parameters, virtual_work, wrenches
    from prp3.model import joint_elements

    sources = {os.path.abspath(path) for path in numba_engine.KERNEL_SOURCES}
    for module in (joint_motion, wrenches, virtual_work, parameters, joint_elements):
        assert os.path.abspath(str(module.__file__)) in sources
    # every file a function compiled from the kernel comes from (its bytecode's) is keyed
    compiled = {
        os.path.abspath(value.py_func.__code__.co_filename)
        for name, value in vars(numba_engine._kernel).items()
        if hasattr(value, "py_func") and name != "_zero"
    }
    # the three mechanics stages and the spring's force law (model.joint_elements)
    assert len(compiled) == 4
    assert compiled <= sources
    for loop in (numba_engine.f10_loop, numba_engine.solve_loop, numba_engine.sample_f10):
        locator = loop._cache._impl.locator  # the dispatcher's own cache
        assert isinstance(locator, numba_engine._KernelStamp)
        own, *of_sources = locator.get_source_stamp()
        assert len(of_sources) == len(numba_engine.KERNEL_SOURCES)
        for path, stamp in zip(numba_engine.KERNEL_SOURCES, of_sources, strict=True):
            stat = os.stat(path)
            assert stamp == caching._hash_source_file(path, stat.st_mtime, stat.st_size)
            assert own != stamp
