#!/usr/bin/env python
"""Actuator forces ``f10`` of the paper's motions by prp3, MuJoCo and Pinocchio: speed and memory.

Run from the repository root (``pip install -e ".[bench]"`` for the engines)::

    python benchmarks/bench_inverse_dynamics.py            # full run, about 20 minutes
    python benchmarks/bench_inverse_dynamics.py --quick    # smaller sizes, ~30 s

Methods, all on the same samples of the paper's ``vertical`` and ``rotation``
motions (eq. 4) resampled to N samples:

* ``prp3 fast`` — :func:`prp3.paper_forces` with the default engine
  (``numba``: the kernel's own functions compiled by numba, :mod:`prp3.engines.select`);
  ``prp3 fast f10 alone`` — :func:`prp3.actuator_forces`; from
  :data:`prp3.engines.numba.PARALLEL_MIN_SAMPLES` samples on every thread of
  numba's threading layer, and the ``1 thread`` rows the same with
  ``numba.set_num_threads(1)`` (in the same run, on the same samples); the ``numpy``
  rows — the same with ``engine="numpy"`` (the kernel on numpy arrays,
  chunked); single sample: :func:`prp3.sample_forces` (tuples of floats,
  tuples of numpy scalars, ``(3,)`` ndarrays, a load) on both engines.
* ``prp3 <commit>`` — ``--baseline``: that commit's fast path on the same
  samples (``benchmarks/baseline.py`` run on ``git archive`` of its ``src``;
  ``--no-baseline`` to skip); its ``prp3 simulate`` too (``--cli``).
* ``prp3 paper`` — ``prp3.inverse_dynamics(robot, motion, "paper")``: the
  reference implementation (inverse kinematics + :func:`prp3.kernel_method`).
* ``prp3 newton-euler`` — ``inverse_dynamics(..., "newton-euler")``: 21×21
  solve per sample, in chunks of 8192 samples (N ≤ ``--ne-max``: 10⁶ samples
  take about 10 s per motion).
* ``mujoco``, ``pinocchio`` — ``benchmarks/peers.py``: closed-chain inverse
  dynamics per sample in a Python loop (mass matrix/RNEA, bias forces,
  constraint Jacobian, 9×9 solve); the tree coordinates are prepared
  vectorized and untimed (N ≤ ``--peers-max``).  Skipped when ``peers.py`` or
  an engine is missing.

Printed: samples per second for each N (median of repeats, both motions) and
the speed-up of prp3 fast over each method; microseconds per single-sample
call (median); the peak memory of one call for each N (a subprocess per
method and N: ``tracemalloc`` peak of the call and peak RSS of the process);
the agreement of every method with prp3 fast (max |Δf10| / max |f10| ≤ 1e-8,
exit status 1 otherwise); the paper's method against Newton–Euler (dynamics
step alone); ``prp3 simulate --motion vertical`` cold (a fresh numba cache,
``NUMBA_CACHE_DIR``) and warm (``--cli``); the speed targets.
"""

from __future__ import annotations

import argparse
import gc
import importlib.util
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import timeit
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import prp3
from prp3 import actuator_forces, compile_robot, paper_forces
from prp3.engines.sample_entries import (
    sample_actuator_forces,
    sample_forces,
    sample_forces_unchecked,
)

HERE = Path(__file__).resolve().parent
MOTIONS = ("vertical", "rotation")
AGREEMENT = 1e-8
#: The last commit with the hand-fused fast path, before the one kernel (``--baseline``).
BASELINE = "2731610"


# ------------------------------------------------------------------ methods
@dataclass
class Method:
    """One way of computing ``f10``: ``prepare`` is untimed, ``run`` is timed."""

    name: str
    prepare: Callable[[prp3.Motion], Any]
    run: Callable[[Any], np.ndarray]
    max_samples: int | None = None


def load_peers(robot: prp3.Robot) -> tuple[list[Any], str]:
    """The peers of ``benchmarks/peers.py`` whose engine imports, and a note."""
    path = HERE / "peers.py"
    if not path.exists():
        return [], "benchmarks/peers.py not found: peers skipped"
    spec = importlib.util.spec_from_file_location("prp3_bench_peers", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    try:
        spec.loader.exec_module(module)
    except ImportError as error:
        return [], f"peers.py does not import ({error}): peers skipped"
    found = module.available_peers(robot)
    missing = {"mujoco", "pinocchio"} - {peer.name for peer in found}
    return found, (
        f"engines not installed, skipped: {', '.join(sorted(missing))}" if missing else ""
    )


def methods(
    robot: prp3.Robot, peers: list[Any], args: argparse.Namespace, numba: bool | None = None
) -> list[Method]:
    """The methods timed; ``numba``: with the numpy engine rows too (default: yes)."""
    compiled = compile_robot(robot)

    def fused_prepare(motion: prp3.Motion) -> tuple[np.ndarray, ...]:
        return motion.pose, motion.velocity, motion.acceleration

    def fused(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return paper_forces(compiled, *arrays).f10

    def fused_numpy(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return paper_forces(compiled, *arrays, engine="numpy").f10

    def alone(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return actuator_forces(compiled, *arrays)

    def alone_numpy(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return actuator_forces(compiled, *arrays, engine="numpy")

    def one_thread(run: Callable[[Any], np.ndarray]) -> Callable[[Any], np.ndarray]:
        """``run`` with ``numba.set_num_threads(1)``: the batch on one thread."""

        def call(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
            threads = numba_threads.get_num_threads()
            numba_threads.set_num_threads(1)
            try:
                return run(arrays)
            finally:
                numba_threads.set_num_threads(threads)

        return call

    try:
        import numba as numba_threads
    except ImportError:
        threaded: list[Method] = []
    else:
        threaded = [
            Method("prp3 fast, 1 thread", fused_prepare, one_thread(fused)),
            Method("prp3 fast f10 alone, 1 thread", fused_prepare, one_thread(alone)),
        ]

    def paper(motion: prp3.Motion) -> np.ndarray:
        return prp3.inverse_dynamics(robot, motion, "paper")[1].f10

    def newton_euler(motion: prp3.Motion) -> np.ndarray:
        return prp3.inverse_dynamics(robot, motion, "newton-euler")[1].f10

    def identity(motion: prp3.Motion) -> prp3.Motion:
        return motion

    found = [
        Method("prp3 fast", fused_prepare, fused),
        Method("prp3 fast f10 alone", fused_prepare, alone),
        *threaded,
        *(
            [
                Method("prp3 fast numpy", fused_prepare, fused_numpy),
                Method("prp3 fast f10 alone numpy", fused_prepare, alone_numpy),
            ]
            if (True if numba is None else numba)
            else []
        ),
        Method("prp3 paper", identity, paper),
        Method("prp3 newton-euler", identity, newton_euler, args.ne_max),
    ]
    for peer in peers:
        found.append(Method(peer.name, peer.prepare, peer.forces, args.peers_max))
    return found


def motion_of(name: str, samples: int) -> prp3.Motion:
    """The paper's motion resampled to ``samples`` (one sample: t = 1 s of 301)."""
    if samples == 1:
        return prp3.paper_motion(name, samples=301)[100]
    return prp3.paper_motion(name, samples=samples)


def batch(motion: prp3.Motion) -> prp3.Motion:
    """A single-sample motion as a batch of one (every method then returns ``(1, 3)``)."""
    if motion.t.ndim:
        return motion
    return prp3.Motion(
        motion.t[None], motion.pose[None], motion.velocity[None], motion.acceleration[None]
    )


# ------------------------------------------------------------------- timing
def median_seconds(call: Callable[[], object], repeats: int, budget: float) -> float:
    """Median time of one call: ``repeats`` timings of enough calls to last ``budget`` s."""
    timer = timeit.Timer(call)
    number, total = timer.autorange()  # total ≥ 0.2 s
    number = max(1, int(number * budget / max(total, 1e-9)))
    if total > 2.0:  # a slow call: time single calls, at most ``repeats``
        times = [total / number] + [timer.timeit(1) for _ in range(max(0, repeats - 1))]
        return statistics.median(times)
    return statistics.median(timer.repeat(repeat=repeats, number=number)) / number


def run_throughput(
    all_methods: list[Method],
    sizes: list[int],
    args: argparse.Namespace,
    kept: dict[str, np.ndarray] | None = None,
) -> tuple[dict[tuple[str, int], float], dict[str, float]]:
    """Samples per second for every method and N, and the agreement of f10 with prp3 fast.

    ``kept`` receives the samples and prp3 fast's ``f10`` of every batch (for
    the baseline).
    """
    rates: dict[tuple[str, int], float] = {}
    agreement: dict[str, float] = {}
    for samples in sizes:
        for name in MOTIONS:
            motion = batch(motion_of(name, samples))
            if kept is not None:
                key = f"{samples}_{name}"
                kept[f"pose_{key}"] = motion.pose
                kept[f"velocity_{key}"] = motion.velocity
                kept[f"acceleration_{key}"] = motion.acceleration
            reference: np.ndarray | None = None
            for method in all_methods:
                if method.max_samples is not None and samples > method.max_samples:
                    continue
                state = method.prepare(motion)
                f10 = np.asarray(method.run(state))
                if reference is None:
                    reference = f10
                    if kept is not None:
                        kept[f"f10_{samples}_{name}"] = f10
                deviation = float(np.abs(f10 - reference).max() / np.abs(reference).max())
                agreement[method.name] = max(agreement.get(method.name, 0.0), deviation)
                gc.collect()
                seconds = median_seconds(
                    lambda m=method, s=state: m.run(s), args.repeats, args.budget
                )
                rates.setdefault((method.name, samples), 0.0)
                rates[(method.name, samples)] += samples / seconds / len(MOTIONS)
                print(
                    f"  N={samples:>8} {name:<8} {method.name:<18} {samples / seconds:10.4g} samples/s",
                    file=sys.stderr,
                    flush=True,
                )
                del state, f10
    return rates, agreement


def run_single(robot: prp3.Robot, peers: list[Any], args: argparse.Namespace) -> dict[str, float]:
    """Median microseconds of one single-sample call (the rotation motion at t = 1 s)."""
    compiled = compile_robot(robot)
    motion = motion_of("rotation", 1)
    arrays = (motion.pose, motion.velocity, motion.acceleration)  # ndarrays (3,)
    pose, velocity, acceleration = (tuple(a.tolist()) for a in arrays)
    scalars = tuple(tuple(a) for a in arrays)  # what tuple(array[k]) gives: numpy scalars
    flat = (*pose, *velocity, *acceleration)
    load = (1.5, -2.0, 0.25)
    calls: dict[str, Callable[[], object]] = {
        "prp3 fast sample_forces, tuples": lambda: sample_forces(
            compiled, pose, velocity, acceleration
        ),
        "prp3 fast sample_forces, numpy scalars": lambda: sample_forces(compiled, *scalars),
        "prp3 fast sample_forces, ndarray (3,)": lambda: sample_forces(compiled, *arrays),
        "prp3 fast sample_forces, tuples, engine=numpy": lambda: sample_forces(
            compiled, pose, velocity, acceleration, engine="numpy"
        ),
        "prp3 fast sample_forces, tuples, load=": lambda: sample_forces(
            compiled, pose, velocity, acceleration, load=load
        ),
        "prp3 fast sample_actuator_forces (f10 alone), tuples": lambda: sample_actuator_forces(
            compiled, pose, velocity, acceleration
        ),
        "prp3 fast sample_actuator_forces (f10 alone), numpy scalars": lambda: (
            sample_actuator_forces(compiled, *scalars)
        ),
        "prp3 fast sample_actuator_forces (f10 alone), ndarray (3,)": lambda: (
            sample_actuator_forces(compiled, *arrays)
        ),
        "prp3 fast sample_forces_unchecked": lambda: sample_forces_unchecked(compiled, *flat),
        "prp3 fast paper_forces, (3,) arrays": lambda: paper_forces(compiled, *arrays),
        "prp3 paper inverse_dynamics": lambda: prp3.inverse_dynamics(robot, motion, "paper"),
        "prp3 newton-euler inverse_dynamics": lambda: prp3.inverse_dynamics(
            robot, motion, "newton-euler"
        ),
    }
    expected = np.asarray(sample_forces(compiled, pose, velocity, acceleration).f10)
    assert sample_actuator_forces(compiled, pose, velocity, acceleration) == tuple(expected)
    for peer in peers:
        prepared = peer.prepare(batch(motion))
        q, qd, qdd = peer.single_state(prepared, 0)
        got = np.asarray(peer.single(q, qd, qdd))
        assert np.abs(got - expected).max() <= AGREEMENT * np.abs(expected).max(), peer.name
        calls[f"{peer.name} single"] = lambda p=peer, a=(q, qd, qdd): p.single(*a)
    return {
        name: 1e6 * median_seconds(call, max(args.repeats, 7), args.budget)
        for name, call in calls.items()
    }


# ----------------------------------------------------------------- baseline
def run_baseline(
    commit: str, kept: dict[str, np.ndarray], args: argparse.Namespace
) -> tuple[dict[tuple[str, int], float], dict[str, float], float, str]:
    """An older commit's fast path timed on the same samples (``benchmarks/baseline.py``).

    Returns its samples per second for each N (as ``rates``), its single-call
    µs, its agreement with prp3 fast's ``f10``, and the row name.
    """
    name = f"prp3 {commit}" + (" (hand-fused)" if commit == BASELINE else "")
    motion = motion_of("rotation", 1)
    with tempfile.TemporaryDirectory(prefix="prp3-baseline-") as folder:
        root = Path(folder)
        archive = subprocess.run(
            ["git", "-C", str(HERE.parent), "archive", "--format=tar", commit, "src"],
            capture_output=True, check=True,
        )  # fmt: skip
        subprocess.run(["tar", "-x", "-C", str(root)], input=archive.stdout, check=True)
        samples = root / "samples.npz"
        arrays = {k: v for k, v in kept.items() if not k.startswith("f10_")}
        np.savez(samples, **arrays, single_pose=motion.pose,
                 single_velocity=motion.velocity, single_acceleration=motion.acceleration)  # fmt: skip
        command = [sys.executable, str(HERE / "baseline.py"), str(samples), str(root / "out.json")]
        command += ["--repeats", str(args.repeats), "--budget", str(args.budget)]
        env = {**os.environ, "PYTHONPATH": str(root / "src")}
        subprocess.run(command, check=True, env=env)
        found = json.loads((root / "out.json").read_text())
    if not found["prp3_file"].startswith(folder):
        raise RuntimeError(f"the baseline imported {found['prp3_file']}, not the old source")
    rates: dict[tuple[str, int], float] = {}
    deviation = 0.0
    for key, value in found["batches"].items():
        samples_n = int(key.split("_", 1)[0])
        rates.setdefault((name, samples_n), 0.0)
        rates[(name, samples_n)] += samples_n / value["seconds"] / len(MOTIONS)
        reference = kept[f"f10_{key}"]
        difference = np.abs(np.asarray(value["f10"]) - reference).max()
        deviation = max(deviation, float(difference / np.abs(reference).max()))
    single = {f"{name} {call}": micro for call, micro in found["single"].items()}
    return rates, single, deviation, name


# ------------------------------------------------------------------- memory
def _status_mib(field: str) -> float | None:
    """``field`` (``VmHWM``, ``VmRSS``) of ``/proc/self/status`` in MiB; ``None`` off Linux."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(f"{field}:"):
                return int(line.split()[1]) / 2**10  # kB
    except OSError:
        pass
    return None


def peak_rss_mib() -> float:
    """Peak resident memory of this process (MiB).

    ``VmHWM`` of ``/proc/self/status`` on Linux: ``ru_maxrss`` would carry the
    peak of the parent across ``fork`` + ``exec``.
    """
    peak = _status_mib("VmHWM")
    if peak is not None:
        return peak
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10  # KiB on Linux


def reset_peak_rss() -> bool:
    """Set the peak resident memory to the current one (Linux ≥ 4.0); whether it could."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        return False
    return True


def child_memory(method_name: str, samples: int, args: argparse.Namespace) -> None:
    """In a subprocess: peak memory of one call (printed as JSON).

    ``rss`` is the process's peak resident memory during the call: the peak is
    reset after the motion is made (its making, with the copies a
    :class:`prp3.Motion` keeps, peaks above what it holds), so ``rss`` counts
    the imports, the motion held and what the call adds; ``rss_before`` is the
    resident memory just before the call.  Where the peak cannot be reset,
    ``rss`` is the whole process's peak and ``reset`` is false.
    """
    robot = prp3.Robot()
    prp3_only = method_name.startswith("prp3 ")
    peers = [] if prp3_only else load_peers(robot)[0]
    found = methods(robot, peers, args, numba="numpy" in method_name)
    method = next(m for m in found if m.name == method_name)
    motion = batch(motion_of("rotation", samples))
    state = method.prepare(motion)
    gc.collect()
    reset = reset_peak_rss()
    before = _status_mib("VmRSS") or peak_rss_mib()
    tracemalloc.start()
    method.run(state)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(
        json.dumps(
            {"call": peak / 2**20, "rss": peak_rss_mib(), "rss_before": before, "reset": reset}
        )
    )


def run_memory(
    all_methods: list[Method], sizes: list[int], args: argparse.Namespace
) -> dict[tuple[str, int], dict[str, float]]:
    found: dict[tuple[str, int], dict[str, float]] = {}
    for samples in sizes:
        for method in all_methods:
            if method.max_samples is not None and samples > method.max_samples:
                continue
            command = [sys.executable, __file__, "--child-memory", method.name, str(samples)]
            command += ["--ne-max", str(args.ne_max), "--peers-max", str(args.peers_max)]
            done = subprocess.run(command, capture_output=True, text=True, check=False)
            if done.returncode != 0:
                print(
                    f"  memory {method.name} N={samples}: failed: {done.stderr.strip()[-300:]}",
                    file=sys.stderr,
                )
                continue
            found[(method.name, samples)] = json.loads(done.stdout.strip().splitlines()[-1])
            print(
                f"  memory N={samples:>8} {method.name:<18} {found[(method.name, samples)]}",
                file=sys.stderr,
                flush=True,
            )
    return found


# ------------------------------------------------------- paper vs Newton–Euler
def run_paper_vs_newton_euler(args: argparse.Namespace) -> dict[str, Any]:
    """Dynamics step alone (kinematics given) of the reference paper method and Newton–Euler."""
    robot = prp3.Robot()
    result: dict[str, Any] = {"seconds_per_sample": {}}
    for samples in (10**3, 10**5) if not args.quick else (10**3, 10**4):
        motion = prp3.paper_motion("rotation", samples=samples)
        kin = prp3.inverse_kinematics(robot, motion)
        for name, solver in (
            ("kernel_method", prp3.kernel_method),
            ("newton_euler", prp3.newton_euler),
        ):
            seconds = median_seconds(lambda s=solver, k=kin: s(robot, k), args.repeats, args.budget)
            result["seconds_per_sample"][(name, samples)] = seconds / samples
        kin_seconds = median_seconds(
            lambda m=motion: prp3.inverse_kinematics(robot, m), args.repeats, args.budget
        )
        result["seconds_per_sample"][("inverse_kinematics", samples)] = kin_seconds / samples
    n = 21
    result["newton_euler_lu_flops"] = round(2 * n**3 / 3 + 2 * n**2)
    return result


# ------------------------------------------------------------- the command line
def _simulate_seconds(env: dict[str, str], folder: Path, *extra: str) -> float:
    """Wall time of one ``prp3 simulate --motion vertical`` in a fresh process (s)."""
    command = [sys.executable, "-m", "prp3", "simulate", "--motion", "vertical", *extra]
    command += ["--output", str(folder / "out")]
    start = timeit.default_timer()
    subprocess.run(command, check=True, env=env, capture_output=True)
    return timeit.default_timer() - start


def run_cli(commit: str | None, repeats: int) -> dict[str, float]:
    """``prp3 simulate --motion vertical`` cold (a fresh numba cache) and warm (median), s.

    As it runs by default (``--engine auto``: the numpy engine for this run,
    docs/cli.md) and with ``--engine numba`` (numba's start-up, and its
    compilation when cold).  With ``commit``: the same warm, by that commit's
    source (``git archive``).  ``PYTHONDONTWRITEBYTECODE`` is removed from the
    children's environment: a user's Python writes its bytecode once.
    """
    found: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="prp3-cli-") as name:
        folder = Path(name)
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        env["PYTHONPATH"] = str(HERE.parent / "src")
        env["NUMBA_CACHE_DIR"] = str(folder / "numba-cache")  # empty: cold
        for label, extra in (("", ()), (" --engine numba", ("--engine", "numba"))):
            cold = _simulate_seconds(env, folder, *extra)
            found[f"prp3 simulate{label}, cold (fresh numba cache)"] = cold
            warm = [_simulate_seconds(env, folder, *extra) for _ in range(repeats)]
            found[f"prp3 simulate{label}, warm"] = statistics.median(warm)
            shutil.rmtree(folder / "numba-cache", ignore_errors=True)
        if commit is not None:
            archive = subprocess.run(
                ["git", "-C", str(HERE.parent), "archive", "--format=tar", commit, "src"],
                capture_output=True, check=True,
            )  # fmt: skip
            (folder / "old").mkdir()
            subprocess.run(["tar", "-x", "-C", str(folder / "old")], input=archive.stdout,
                           check=True)  # fmt: skip
            old = {**env, "PYTHONPATH": str(folder / "old" / "src")}
            _simulate_seconds(old, folder)
            times = [_simulate_seconds(old, folder) for _ in range(repeats)]
            found[f"prp3 {commit} simulate, warm"] = statistics.median(times)
    return found


# ------------------------------------------------------------------- report
def fmt_rate(value: float) -> str:
    return f"{value:.3g}"


def machine() -> list[str]:
    model = "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    versions = [f"numpy {np.__version__}"]
    for module in ("mujoco", "pinocchio"):
        try:
            versions.append(f"{module} {__import__(module).__version__}")
        except ImportError:
            versions.append(f"{module} not installed")
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    return [
        f"Machine: {model}, {os.cpu_count()} CPUs, {platform.system()} {platform.release()}; load average at start {load}",
        f"Python {platform.python_version()}, {', '.join(versions)}, prp3 {prp3.__version__}",
    ]


def report(
    sizes: list[int],
    all_methods: list[Method],
    rates: dict[tuple[str, int], float],
    agreement: dict[str, float],
    single: dict[str, float],
    memory: dict[tuple[str, int], dict[str, float]],
    comparison: dict[str, Any],
    notes: list[str],
    extra_rows: list[str],
    cli: dict[str, float],
) -> list[str]:
    out = [*notes, ""]
    out.append(
        "Samples per second (median of repeats, mean over the vertical and rotation motions);"
    )
    out.append("in brackets: how many times faster prp3 fast is.")
    out.append("")
    out.append("| method | " + " | ".join(f"N = {n:,}" for n in sizes) + " |")
    out.append("|---|" + "---|" * len(sizes))
    for row in [method.name for method in all_methods] + extra_rows:
        cells = []
        for n in sizes:
            rate = rates.get((row, n))
            base = rates.get(("prp3 fast", n))
            if rate is None:
                cells.append("—")
            elif row == "prp3 fast":
                cells.append(fmt_rate(rate))
            else:
                cells.append(f"{fmt_rate(rate)} [{base / rate:.3g}×]" if base else fmt_rate(rate))
        out.append(f"| {row} | " + " | ".join(cells) + " |")
    out.append("")
    fastest = single.get(CHECKED_CALL, float("nan"))
    out.append(
        "Single-sample call (one pose, velocity, acceleration → f10), median µs; ratio to prp3's checked call."
    )
    out.append("")
    out.append("| call | µs | ratio |")
    out.append("|---|---|---|")
    for name, micro in single.items():
        out.append(f"| {name} | {micro:.3g} | {micro / fastest:.3g} |")
    out.append("")
    if memory:
        out.append(
            "Peak memory of one call on the rotation motion: tracemalloc peak of the call / peak RSS of the"
        )
        out.append(
            "whole process (imports and the input motion included), MiB; ratio of the call peak to prp3 fast."
        )
        out.append("")
        out.append("| method | " + " | ".join(f"N = {n:,}" for n in sizes) + " |")
        out.append("|---|" + "---|" * len(sizes))
        for method in all_methods:
            cells = []
            for n in sizes:
                found = memory.get((method.name, n))
                base = memory.get(("prp3 fast", n))
                if found is None:
                    cells.append("—")
                    continue
                ratio = (
                    f" [{found['call'] / base['call']:.3g}×]"
                    if base and method.name != "prp3 fast" and base["call"] > 0
                    else ""
                )
                cells.append(f"{found['call']:.3g} / {found['rss']:.0f}{ratio}")
            out.append(f"| {method.name} | " + " | ".join(cells) + " |")
        out.append("")
    out.append(
        f"Agreement of f10 with prp3 fast (max |Δf10| / max |f10| over each motion, required ≤ {AGREEMENT:g}):"
    )
    out.append("  " + ", ".join(f"{name} {value:.2g}" for name, value in agreement.items()))
    out.append("")
    per = comparison["seconds_per_sample"]
    out.append(
        "The paper's claim (fewer operations, less time) — prp3's paper method against its Newton–Euler solver:"
    )
    for (name, n), seconds in sorted(per.items(), key=lambda item: (item[0][1], item[0][0])):
        out.append(f"  N = {n:>7,}: {name:<20} {seconds * 1e6:8.3f} µs per sample")
    for n in sorted({n for _, n in per}):
        ratio = per[("newton_euler", n)] / per[("kernel_method", n)]
        out.append(f"  N = {n:>7,}: dynamics step, Newton–Euler / paper method = {ratio:.2f}")
    out.append(
        f"  The Newton–Euler solver's dense 21×21 LU solve alone is about "
        f"{comparison['newton_euler_lu_flops']:,} flops (2n³/3 + 2n²), before assembling the system."
    )
    out.append("")
    if cli:
        out.append("The command line, wall time of one process (s):")
        out.extend(f"  {name}: {seconds:.2f} s" for name, seconds in cli.items())
        out.append("")
    out.extend(targets(rates, single, memory, extra_rows, cli))
    return out


#: The validated single-sample call the targets are about.
CHECKED_CALL = "prp3 fast sample_forces, tuples"


def targets(
    rates: dict[tuple[str, int], float],
    single: dict[str, float],
    memory: dict[tuple[str, int], dict[str, float]],
    extra_rows: list[str],
    cli: dict[str, float],
) -> list[str]:
    def verdict(ok: bool) -> str:
        return "met" if ok else "NOT met"

    out = ["Speed targets (the default install: the numba engine):"]
    n = 10**5
    # the peers at N = 10⁵, or at their largest N timed (--peers-max): a Python loop per sample
    timed = [size for (name, size) in rates if name in ("mujoco", "pinocchio") and size <= n]
    peer_n = max(timed, default=n)
    peers = {
        name: rate
        for (name, size), rate in rates.items()
        if size == peer_n and name in ("mujoco", "pinocchio")
    }
    best = max(peers, key=lambda k: peers[k]) if peers else None
    at = "" if peer_n == n else f" at N = {peer_n:,}"
    for row, what, target, ratio_target in (
        ("prp3 fast f10 alone", "f10", 2e7, 300.0),
        ("prp3 fast f10 alone, 1 thread", "f10", None, None),
        ("prp3 fast", "f10, p10, f21y, f21z", 1.5e7, None),
        ("prp3 fast, 1 thread", "f10, p10, f21y, f21z", None, None),
    ):
        rate = rates.get((row, n))
        if rate is None:
            continue
        line = f"  batch {what} N = 10⁵, {row}: {rate:.3g} samples/s"
        if target is not None:
            line += f" (target ≥ {target:.2g}: {verdict(rate >= target)})"
        if best is not None:
            ratio = rate / peers[best]
            line += f"; {ratio:.3g}× the faster peer ({best}{at} {peers[best]:.3g}/s)"
            if ratio_target is not None:
                line += f" (target ≥ {ratio_target:.0f}: {verdict(ratio >= ratio_target)})"
        out.append(line)
    for call in (  # the target is f10's (the issue's "validated single call (f10)")
        "prp3 fast sample_actuator_forces (f10 alone), tuples",
        "prp3 fast sample_actuator_forces (f10 alone), numpy scalars",
        "prp3 fast sample_actuator_forces (f10 alone), ndarray (3,)",
        CHECKED_CALL,
        "prp3 fast sample_forces, numpy scalars",
        "prp3 fast sample_forces, ndarray (3,)",
    ):
        checked = single.get(call)
        if checked is not None:
            target = f" (target ≤ 2 µs: {verdict(checked <= 2)})" if "f10 alone" in call else ""
            out.append(f"  single sample, {call}: {checked:.3g} µs{target}")
    # the memory target is the batch f10's (the targets are f10's but for the four
    # forces' speed); the four forces' row holds three more (N, 3) outputs, 3 × 24 MB at 10⁶
    for row, what in (("prp3 fast f10 alone", "f10"), ("prp3 fast", "f10, p10, f21y, f21z")):
        big = memory.get((row, 10**6))
        if big is not None:
            peak = "peak RSS during the call" if big.get("reset") else "peak RSS of the process"
            target = f"; target ≤ 300 MiB: {verdict(big['rss'] <= 300)}" if what == "f10" else ""
            out.append(
                f"  memory N = 10⁶, {what}, {row}: {peak} {big['rss']:.0f} MiB "
                f"({big['rss_before']:.0f} MiB before it{target})"
            )
    for row in extra_rows:  # no speed lost: the same machine, the same run, the same samples
        for size in (10**3, n):
            old, new = rates.get((row, size)), rates.get(("prp3 fast", size))
            if old and new:
                out.append(
                    f"  against {row}: batch N = {size:,} {new:.3g} against {old:.3g} samples/s "
                    f"({new / old:.3g}×: {verdict(new >= old)})"
                )
        for call in ("tuples", "ndarray (3,)"):
            before = single.get(f"{row} sample_forces, {call}")
            now = single.get(f"prp3 fast sample_forces, {call}")
            if before and now:
                out.append(
                    f"  against {row}: sample_forces, {call}, {now:.3g} against "
                    f"{before:.3g} µs ({before / now:.3g}× faster: {verdict(now <= before)})"
                )
    warm = cli.get("prp3 simulate, warm")
    for name, seconds in cli.items():
        if name.endswith("simulate, warm") and name != "prp3 simulate, warm" and warm:
            out.append(
                f"  prp3 simulate warm {warm:.2f} s against {name} {seconds:.2f} s: {verdict(warm <= seconds * 1.05)}"
            )
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--quick", action="store_true", help="N = 1, 10³, 10⁴ and short timings (~30 s)"
    )
    parser.add_argument(
        "--sizes", type=int, nargs="+", help="sample counts N (default 1 10³ 10⁵ 10⁶)"
    )
    parser.add_argument("--repeats", type=int, default=5, help="timings per method and N (median)")
    parser.add_argument(
        "--budget", type=float, default=0.2, help="seconds per timing of fast calls"
    )
    parser.add_argument(
        "--peers-max", type=int, default=10**5, help="largest N for the engines' Python loops"
    )
    parser.add_argument(
        "--ne-max", type=int, default=10**5, help="largest N for prp3's Newton–Euler solver"
    )
    parser.add_argument("--no-peers", action="store_true", help="prp3 only")
    parser.add_argument(
        "--baseline",
        default=BASELINE,
        help=f"an older commit whose fast path is timed on the same samples (default {BASELINE}, "
        "the hand-fused code before the one kernel; needs git)",
    )
    parser.add_argument("--no-baseline", action="store_true", help="skip the baseline row")
    parser.add_argument(
        "--no-memory", action="store_true", help="skip the peak-memory subprocesses"
    )
    parser.add_argument(
        "--cli", action="store_true", help="time prp3 simulate --motion vertical, cold and warm"
    )
    parser.add_argument("--child-memory", nargs=2, metavar=("METHOD", "N"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.quick:
        args.repeats, args.budget = 3, 0.05
    if args.child_memory:
        child_memory(args.child_memory[0], int(args.child_memory[1]), args)
        return 0
    sizes = args.sizes or ([1, 10**3, 10**4] if args.quick else [1, 10**3, 10**5, 10**6])
    robot = prp3.Robot()
    notes = machine()
    peers, note = ([], "peers skipped (--no-peers)") if args.no_peers else load_peers(robot)
    if note:
        notes.append(note)
    notes.append(
        f"Command: python benchmarks/bench_inverse_dynamics.py {' '.join(argv if argv is not None else sys.argv[1:])}".rstrip()
    )
    all_methods = methods(robot, peers, args)
    print("timing batches ...", file=sys.stderr)
    kept: dict[str, np.ndarray] | None = None if args.no_baseline else {}
    rates, agreement = run_throughput(all_methods, sizes, args, kept)
    print("timing single samples ...", file=sys.stderr)
    single = run_single(robot, peers, args)
    extra_rows: list[str] = []
    if kept is not None:
        print(f"timing the baseline {args.baseline} on the same samples ...", file=sys.stderr)
        try:
            old_rates, old_single, deviation, row = run_baseline(args.baseline, kept, args)
        except (OSError, subprocess.CalledProcessError, RuntimeError) as error:
            notes.append(f"baseline {args.baseline} skipped: {error}")
        else:
            rates.update(old_rates)
            single.update(old_single)
            agreement[row] = deviation
            extra_rows.append(row)
        del kept
    memory = {}
    if not args.no_memory:
        print("measuring peak memory ...", file=sys.stderr)
        memory = run_memory(all_methods, sizes, args)
    print("paper method vs Newton–Euler ...", file=sys.stderr)
    comparison = run_paper_vs_newton_euler(args)
    cli: dict[str, float] = {}
    if args.cli:
        print("prp3 simulate, cold and warm ...", file=sys.stderr)
        cli = run_cli(None if args.no_baseline else args.baseline, max(3, args.repeats))
    print(
        "\n".join(
            report(
                sizes,
                all_methods,
                rates,
                agreement,
                single,
                memory,
                comparison,
                notes,
                extra_rows,
                cli,
            )
        )
    )
    bad = {name: value for name, value in agreement.items() if not value <= AGREEMENT}
    if bad:
        print(f"DISAGREEMENT beyond {AGREEMENT:g}: {bad}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
