"""The numba engine's batches on every thread: the numbers of one thread, from any thread.

From ``PARALLEL_MIN_SAMPLES`` samples a batch of the numba engine runs its
parallel loops (``prange`` on a thread-safe threading layer), below it the
loops on one thread.  The same samples give the same numbers either way (each
sample is computed alone, by the same machine code), also when several Python
threads call at once; without a thread-safe layer, and in a forked child of a
process whose threads ran, the batches run on one thread.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
import pytest

from prp3 import Robot
from prp3.engines.compiled_robot import CompiledRobot, compile_robot
from prp3.engines.entries import actuator_forces, paper_forces, solve_batch
from prp3.engines.select import EngineWarning
from prp3.model.parameters import Load, Spring, SpringParameters

numba_engine = pytest.importorskip("prp3.engines.numba")
numba = pytest.importorskip("numba")

#: More samples than the threshold, not a multiple of the threads: uneven shares.
SAMPLES = numba_engine.PARALLEL_MIN_SAMPLES + 1001
#: A piece below the threshold: the batch cut into these runs on one thread.
PIECE = numba_engine.PARALLEL_MIN_SAMPLES - 1

ROBOT = Robot(
    load=Load(force=(1.5, -2.0), moment=0.3),
    spring=Spring(SpringParameters(stiffness=40.0, rest=0.01, damping=2.0)),
)

Batch = Callable[[CompiledRobot, tuple[np.ndarray, ...], np.ndarray], dict[str, np.ndarray]]


def _states(samples: int, seed: int) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Random poses away from the singularity, velocities, accelerations, a load."""
    rng = np.random.default_rng(seed)
    pose = rng.uniform([-0.04, -0.04, -0.6], [0.04, 0.04, 0.6], size=(samples, 3))
    velocity = rng.normal(size=(samples, 3)) * [0.2, 0.2, 1.0]
    acceleration = rng.normal(size=(samples, 3)) * [2.0, 2.0, 10.0]
    load = rng.normal(size=(samples, 3)) * [20.0, 20.0, 2.0]
    return (pose, velocity, acceleration), load


def _f10(compiled: CompiledRobot, arrays: tuple[np.ndarray, ...], _: np.ndarray) -> dict[str, Any]:
    return {"f10": actuator_forces(compiled, *arrays)}


def _forces(
    compiled: CompiledRobot, arrays: tuple[np.ndarray, ...], _: np.ndarray
) -> dict[str, Any]:
    found = paper_forces(compiled, *arrays)
    return {name: getattr(found, name) for name in ("f10", "p10", "f21y", "f21z")}


def _reactions(
    compiled: CompiledRobot, arrays: tuple[np.ndarray, ...], _: np.ndarray
) -> dict[str, Any]:
    found = paper_forces(compiled, *arrays, reactions=True)
    return {name: getattr(found, name) for name in ("f10", "p10", "f21y", "f21z", "n10", "m32")}


def _solve(
    compiled: CompiledRobot, arrays: tuple[np.ndarray, ...], _: np.ndarray
) -> dict[str, Any]:
    return dict(solve_batch(compiled, *arrays))


def _solve_loaded(
    compiled: CompiledRobot, arrays: tuple[np.ndarray, ...], load: np.ndarray
) -> dict[str, Any]:
    return dict(solve_batch(compiled, *arrays, load=load))


BATCHES: dict[str, Batch] = {
    "f10 alone": _f10,
    "forces": _forces,
    "reactions": _reactions,
    "solve_batch": _solve,
    "solve_batch, load": _solve_loaded,
}


def _in_pieces(batch: Batch, compiled: CompiledRobot, arrays: tuple[np.ndarray, ...],
               load: np.ndarray) -> dict[str, np.ndarray]:  # fmt: skip
    """``batch`` of the samples in pieces below the threshold: on one thread."""
    pieces = [
        batch(
            compiled, tuple(a[start : start + PIECE] for a in arrays), load[start : start + PIECE]
        )
        for start in range(0, arrays[0].shape[0], PIECE)
    ]
    return {name: np.concatenate([p[name] for p in pieces]) for name in pieces[0]}


def _assert_same(got: dict[str, np.ndarray], expected: dict[str, np.ndarray]) -> None:
    assert got.keys() == expected.keys()
    for name, values in expected.items():
        scale = np.abs(values).max() + 1e-300
        error = float(np.abs(got[name] - values).max() / scale)
        assert error <= 1e-13, (name, error)  # bit for bit where the machine code is one


@pytest.fixture(scope="module")
def threads() -> str:
    layer = numba_engine.parallel_layer()
    if layer is None:
        pytest.skip("no thread-safe threading layer of numba here")
    return str(layer)


def test_the_loops_are_a_function_of_the_batch_size(threads: str) -> None:
    small = numba_engine.batch_loops(numba_engine.PARALLEL_MIN_SAMPLES - 1)
    large = numba_engine.batch_loops(numba_engine.PARALLEL_MIN_SAMPLES)
    assert small == (numba_engine.f10_loop, numba_engine.forces_loop,
                     numba_engine.reactions_loop, numba_engine.solve_loop)  # fmt: skip
    assert large == (numba_engine.f10_loop_parallel, numba_engine.forces_loop_parallel,
                     numba_engine.reactions_loop_parallel, numba_engine.solve_loop_parallel)  # fmt: skip
    assert numba_engine.batch_loops(10**7) == large  # again: no state of earlier calls
    assert numba_engine.batch_loops(0) == small
    assert threads in numba_engine.THREAD_SAFE_LAYERS


@pytest.mark.parametrize("name", list(BATCHES))
def test_a_batch_on_every_thread_is_the_batch_on_one(name: str, threads: str) -> None:
    compiled = compile_robot(ROBOT)
    arrays, load = _states(SAMPLES, seed=len(name))
    batch = BATCHES[name]
    _assert_same(batch(compiled, arrays, load), _in_pieces(batch, compiled, arrays, load))


def test_concurrent_calls_from_python_threads(threads: str) -> None:
    # the explorer's server, dask's threads or a user's call the engine at once: every
    # call gets its own samples' numbers (workqueue would abort the process here)
    compiled = compile_robot(ROBOT)
    jobs = []
    for k, name in enumerate(["forces", "f10 alone", "solve_batch, load", "reactions"] * 2):
        arrays, load = _states(SAMPLES + 17 * k, seed=100 + k)
        jobs.append((BATCHES[name], arrays, load))
    expected = [_in_pieces(batch, compiled, arrays, load) for batch, arrays, load in jobs]
    with ThreadPoolExecutor(max_workers=4) as pool:
        futures = [pool.submit(batch, compiled, arrays, load) for batch, arrays, load in jobs]
        for future, reference in zip(futures, expected, strict=True):
            _assert_same(future.result(), reference)


def _fresh(monkeypatch: pytest.MonkeyPatch) -> None:
    """The engine as if its threading layer was never asked for (restored after the test)."""
    monkeypatch.setattr(numba_engine, "_layer", numba_engine._UNSET)


def test_without_a_thread_safe_layer_batches_run_on_one_thread(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    _fresh(monkeypatch)
    monkeypatch.setattr(numba, "threading_layer", lambda: "workqueue")  # started before
    with pytest.warns(EngineWarning, match="'workqueue' is not thread-safe"):
        assert numba_engine.parallel_layer() is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said once
        assert numba_engine.parallel_layer() is None
        assert numba_engine.batch_loops(10**6).f10 is numba_engine.f10_loop
        zeros = np.zeros((numba_engine.PARALLEL_MIN_SAMPLES, 3))
        assert np.isfinite(actuator_forces(Robot(), zeros, zeros, zeros)).all()


def test_no_layer_at_all_leaves_numba_s_choice_to_the_user(monkeypatch: pytest.MonkeyPatch) -> None:
    _fresh(monkeypatch)
    asked: list[str] = []

    def not_started() -> str:
        raise ValueError("Threading layer is not initialized.")

    def no_layer() -> int:
        asked.append(numba.config.THREADING_LAYER)
        raise ValueError("No threading layer could be loaded.")

    monkeypatch.setattr(numba, "threading_layer", not_started)
    monkeypatch.setattr(numba, "get_num_threads", no_layer)
    monkeypatch.setattr(numba.config, "THREADING_LAYER", "default")
    with pytest.warns(EngineWarning, match="'tbb or omp' is not thread-safe or not available"):
        assert numba_engine.parallel_layer() is None
    assert asked == ["threadsafe"]  # a thread-safe layer asked for, only while starting
    assert numba.config.THREADING_LAYER == "default"


@pytest.mark.skipif(not hasattr(os, "fork"), reason="no fork")
def test_a_forked_child_runs_its_batches_on_one_thread(threads: str) -> None:
    compiled = compile_robot(ROBOT)
    arrays, load = _states(SAMPLES, seed=7)
    expected = _f10(compiled, arrays, load)["f10"]
    assert np.array_equal(_f10(compiled, arrays, load)["f10"], expected)  # the threads ran
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # fork of a threaded process
        pid = os.fork()
    if pid == 0:  # pragma: no cover  (the child)
        code = 3
        try:
            serial = numba_engine.batch_loops(SAMPLES).f10 is numba_engine.f10_loop
            same = np.array_equal(_f10(compiled, arrays, load)["f10"], expected)
            code = 0 if serial and same else 1
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status
