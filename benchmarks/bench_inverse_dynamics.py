#!/usr/bin/env python
"""Actuator forces ``f10`` of the paper's motions by prp3, MuJoCo and Pinocchio: speed and memory.

Run from the repository root (``pip install -e ".[bench]"`` for the engines)::

    python benchmarks/bench_inverse_dynamics.py            # full run, about 20 minutes
    python benchmarks/bench_inverse_dynamics.py --quick    # smaller sizes, ~30 s

Methods, all on the same samples of the paper's ``vertical`` and ``rotation``
motions (eq. 4) resampled to N samples:

* ``prp3 fast`` — :func:`prp3.fast.paper_forces`, the one kernel traced into
  numpy ufunc calls (chunked); ``prp3 fast f10 alone`` —
  :func:`prp3.fast.actuator_forces`; the ``numba`` rows — the same with
  ``backend="numba"`` (when numba is installed); single sample:
  :func:`prp3.fast.sample_forces` (tuples, ndarrays, a load).
* ``prp3 2731610 (hand-fused)`` — ``--baseline``: that commit's fast path on
  the same samples (``benchmarks/baseline.py`` run on ``git archive`` of its
  ``src``; ``--no-baseline`` to skip).
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
step alone, and operation counts); the speed targets.
"""

from __future__ import annotations

import argparse
import ast
import gc
import importlib.util
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import textwrap
import timeit
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import prp3
from prp3.fast import (
    actuator_forces,
    compile_robot,
    paper_forces,
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
    """The methods timed; ``numba``: with the numba backend rows (default: if it imports)."""
    compiled = compile_robot(robot)

    def fused_prepare(motion: prp3.Motion) -> tuple[np.ndarray, ...]:
        return motion.pose, motion.velocity, motion.acceleration

    def fused(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return paper_forces(compiled, *arrays).f10

    def fused_numba(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return paper_forces(compiled, *arrays, backend="numba").f10

    def alone(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return actuator_forces(compiled, *arrays)

    def alone_numba(arrays: tuple[np.ndarray, ...]) -> np.ndarray:
        return actuator_forces(compiled, *arrays, backend="numba")

    def paper(motion: prp3.Motion) -> np.ndarray:
        return prp3.inverse_dynamics(robot, motion, "paper")[1].f10

    def newton_euler(motion: prp3.Motion) -> np.ndarray:
        return prp3.inverse_dynamics(robot, motion, "newton-euler")[1].f10

    def identity(motion: prp3.Motion) -> prp3.Motion:
        return motion

    found = [
        Method("prp3 fast", fused_prepare, fused),
        Method("prp3 fast f10 alone", fused_prepare, alone),
        *(
            [
                Method("prp3 fast numba", fused_prepare, fused_numba),
                Method("prp3 fast f10 alone numba", fused_prepare, alone_numba),
            ]
            if (_has_numba() if numba is None else numba)
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
    flat = (*pose, *velocity, *acceleration)
    load = (1.5, -2.0, 0.25)
    calls: dict[str, Callable[[], object]] = {
        "prp3 fast sample_forces, tuples": lambda: sample_forces(
            compiled, pose, velocity, acceleration
        ),
        "prp3 fast sample_forces, ndarray (3,)": lambda: sample_forces(compiled, *arrays),
        "prp3 fast sample_forces, tuples, load=": lambda: sample_forces(
            compiled, pose, velocity, acceleration, load=load
        ),
        "prp3 fast sample_actuator_forces (f10 alone), tuples": lambda: sample_actuator_forces(
            compiled, pose, velocity, acceleration
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
def peak_rss_mib() -> float:
    """Peak resident memory of this process (MiB).

    ``VmHWM`` of ``/proc/self/status`` on Linux: ``ru_maxrss`` would carry the
    peak of the parent across ``fork`` + ``exec``.
    """
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 2**10  # kB
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10  # KiB on Linux


def child_memory(method_name: str, samples: int, args: argparse.Namespace) -> None:
    """In a subprocess: peak memory of one call (printed as JSON)."""
    robot = prp3.Robot()
    prp3_only = method_name.startswith("prp3 ")
    peers = [] if prp3_only else load_peers(robot)[0]
    # numba imported only for its rows (its import alone adds about 60 MiB of RSS)
    found = methods(robot, peers, args, numba="numba" in method_name)
    method = next(m for m in found if m.name == method_name)
    motion = batch(motion_of("rotation", samples))
    state = method.prepare(motion)
    gc.collect()
    before = peak_rss_mib()
    tracemalloc.start()
    method.run(state)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(json.dumps({"call": peak / 2**20, "rss": peak_rss_mib(), "rss_before": before}))


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
def count_operations(source: str) -> dict[str, int]:
    """Arithmetic operations written in a scalar function's source (one sample)."""
    tree = ast.parse(textwrap.dedent(source))
    counts = {"add/sub": 0, "mul": 0, "div": 0, "neg": 0, "cos/sin": 0}
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp):
            key = {ast.Add: "add/sub", ast.Sub: "add/sub", ast.Mult: "mul", ast.Div: "div"}.get(
                type(node.op)
            )
            if key:
                counts[key] += 1
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            counts["neg"] += 1
        elif isinstance(node, ast.Call) and getattr(node.func, "id", None) in ("cos", "sin"):
            counts["cos/sin"] += 1
    return counts


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
    # the traced kernel of sample_forces_unchecked (its source is its __doc__)
    result["fused_counts"] = count_operations(compile_robot(robot).sample_function.__doc__ or "")
    return result


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
    counts = comparison["fused_counts"]
    total = sum(v for k, v in counts.items() if k != "cos/sin")
    out.append(
        f"  Operations per sample, fused paper method incl. kinematics (source count of the traced kernel of sample_forces_unchecked): "
        f"{total} ({', '.join(f'{k} {v}' for k, v in counts.items())}); the Newton–Euler solver's dense 21×21 LU "
        f"solve alone is about {comparison['newton_euler_lu_flops']:,} flops (2n³/3 + 2n²), before assembling the system."
    )
    out.append("")
    out.extend(targets(rates, single, memory, extra_rows))
    return out


def _has_numba() -> bool:
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


#: The validated single-sample call the targets are about.
CHECKED_CALL = "prp3 fast sample_forces, tuples"


def targets(
    rates: dict[tuple[str, int], float],
    single: dict[str, float],
    memory: dict[tuple[str, int], dict[str, float]],
    extra_rows: list[str],
) -> list[str]:
    out = ["Speed targets (the default install, numpy backend):"]
    n = 10**5
    peers = {
        name: rate
        for (name, size), rate in rates.items()
        if size == n and name in ("mujoco", "pinocchio")
    }
    for row in ("prp3 fast", "prp3 fast f10 alone"):
        fused = rates.get((row, n))
        if fused is None:
            continue
        line = f"  batch N = 10⁵: {row} {fused:.3g} samples/s (target ≥ 1e7: {'met' if fused >= 1e7 else 'NOT met'})"
        if peers:
            best_name = max(peers, key=lambda k: peers[k])
            ratio = fused / peers[best_name]
            line += f"; faster peer {best_name} {peers[best_name]:.3g}/s, ratio {ratio:.3g} (target ≥ 150: {'met' if ratio >= 150 else 'NOT met'})"
        out.append(line)
    peer_single = {k: v for k, v in single.items() if k.endswith(" single")}
    for call in (
        CHECKED_CALL,
        "prp3 fast sample_forces, ndarray (3,)",
        "prp3 fast sample_actuator_forces (f10 alone), tuples",
        "prp3 fast sample_actuator_forces (f10 alone), ndarray (3,)",
    ):
        checked = single.get(call)
        if checked is None:
            continue
        out.append(
            f"  single sample, {call}: {checked:.3g} µs (target ≤ 3 µs: {'met' if checked <= 3 else 'NOT met'}"
            + (
                f"; below every peer's {', '.join(f'{v:.3g}' for v in peer_single.values())} µs: "
                f"{'met' if all(checked < v for v in peer_single.values()) else 'NOT met'}"
                if peer_single
                else ""
            )
            + ")"
        )
    big = memory.get(("prp3 fast", 10**6))
    if big is not None:
        out.append(
            f"  memory N = 10⁶: prp3 fast peak RSS {big['rss']:.0f} MiB (target ≤ 300 MiB: {'met' if big['rss'] <= 300 else 'NOT met'})"
        )
    for row in extra_rows:  # no speed lost: the same machine, the same run, the same samples
        old, new = rates.get((row, n)), rates.get(("prp3 fast", n))
        if old and new:
            out.append(
                f"  no speed lost against {row}: batch N = 10⁵ {new:.3g} against {old:.3g} samples/s "
                f"({new / old:.3g}×: {'met' if new >= old else 'NOT met'})"
            )
        for call in ("tuples", "ndarray (3,)"):
            before = single.get(f"{row} sample_forces, {call}")
            now = single.get(f"prp3 fast sample_forces, {call}")
            if before and now:
                out.append(
                    f"  no speed lost against {row}: sample_forces, {call}, {now:.3g} against "
                    f"{before:.3g} µs ({before / now:.3g}× faster: {'met' if now <= before else 'NOT met'})"
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
    print(
        "\n".join(
            report(
                sizes, all_methods, rates, agreement, single, memory, comparison, notes, extra_rows
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
