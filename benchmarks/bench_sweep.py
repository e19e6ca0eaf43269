#!/usr/bin/env python
"""``prp3 sweep`` on Dask: designs per second with 1 and 2 workers, against the kernel's own rate.

Run from the repository root (``pip install -e ".[bench]"``)::

    python benchmarks/bench_sweep.py              # 2000 designs, 301 samples per motion
    python benchmarks/bench_sweep.py --samples 3001 --designs 500
    python benchmarks/bench_sweep.py --quick      # 400 designs, ~20 s

Measured in the same run, on the same task (the paper's two motions, the
designs of a Latin hypercube over ``l0``, ``link.mass``, ``platform.mass``):

* ``kernel`` — :func:`prp3.paper_forces` with the reactions on one core
  (``numba.set_num_threads(1)``: a batch this large runs on every thread otherwise),
  the task repeated to ~10⁵ samples per call (its best rate: no per-call cost);
* ``paper_forces, 1 call`` — one ``paper_forces`` call over the task (its
  per-call checks included), the robot compiled already;
* ``paper_forces per new robot`` — :func:`~prp3.engines.compiled_robot.compile_robot` + one
  call for a robot it has not seen (what a sweep would pay per design through
  ``paper_forces``: the batch path prepares its code per robot);
* ``evaluate_designs`` — :func:`prp3.evaluate_designs` on one chunk in
  this process: the kernel traced for blocks of designs × samples (the
  designs' parameters traced from their values), peaks and energy, no Dask;
* ``sweep, 1 worker`` / ``2 workers`` — :func:`prp3.run_sweep` on a
  LocalCluster of 1 or 2 worker processes (one thread each), Parquet files
  included; the cluster start is timed apart (it is paid once per command).

Printed: designs/s and samples/s (designs × samples of the task per second)
of each, the ratio of each to the kernel's rate, and the scaling efficiency
``rate(2 workers) / (2 · rate(1 worker))``.  Timings are the median of
``--repeats`` runs.  On a machine whose cores are shared the wall-clock
numbers move from run to run; the CPU time per sample of the kernel, of
``evaluate_designs`` in this process and of the same chunk inside a Dask
worker process is printed too (what other users' load does not inflate),
with the load average.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import platform
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

import prp3
import prp3.apps.cluster
import prp3.apps.sweep
from prp3 import compile_robot, design_values, evaluate_designs, paper_forces, sweep_spec


def _median_time(function: Callable[[], Any], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def _cpu_time(function: Callable[..., Any], *args: Any) -> float:
    """CPU seconds of the calling thread for one call (what a shared machine does not inflate)."""
    start = time.thread_time()
    function(*args)
    return time.thread_time() - start


@contextlib.contextmanager
def _one_thread() -> Iterator[None]:
    """The numba engine's batches on one thread (``numba.set_num_threads(1)``), if numba runs."""
    try:
        import numba
    except ImportError:
        yield
        return
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        yield
    finally:
        numba.set_num_threads(threads)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--designs", type=int, default=2000)
    parser.add_argument("--samples", type=int, default=301, help="samples per paper motion")
    parser.add_argument("--chunk", type=int, default=250, help="designs per Dask task")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="400 designs, 1 repeat")
    args = parser.parse_args()
    load_start = os.getloadavg()[0]
    if args.quick:
        args.designs, args.repeats = 400, 1

    from dask.distributed import Client, LocalCluster

    spec = sweep_spec(
        {
            "designs": args.designs,
            "sampling": "lhs",
            "seed": 1,
            "chunk": args.chunk,
            "parameters": {
                "l0": [0.25, 0.35],
                "link.mass": [0.5, 1.0],
                "platform.mass": [2.0, 4.0],
            },
            "task": {"motions": ["vertical", "rotation"], "samples": args.samples},
        }
    )
    values = design_values(spec)
    task = 2 * args.samples
    motions = [prp3.paper_motion(m, args.samples) for m in ("vertical", "rotation")]
    pose, velocity, acceleration = (
        np.concatenate([getattr(m, name) for m in motions])
        for name in ("pose", "velocity", "acceleration")
    )
    robot = prp3.Robot()
    compiled = compile_robot(robot)

    # the kernel alone, big batches (its best single-core rate)
    repeat = max(1, 100_000 // task)
    big = [np.tile(a, (repeat, 1)) for a in (pose, velocity, acceleration)]
    with _one_thread():
        paper_forces(compiled, *big, reactions=True)
        t_kernel = _median_time(
            lambda: paper_forces(compiled, *big, reactions=True), max(3, args.repeats)
        )
        cpu_kernel = statistics.median(
            _cpu_time(lambda: paper_forces(compiled, *big, reactions=True)) for _ in range(3)
        ) / (repeat * task)
    kernel_rate = repeat * task / t_kernel

    # one call over the task, the robot compiled already
    t_call = (
        _median_time(
            lambda: [
                paper_forces(compiled, pose, velocity, acceleration, reactions=True)
                for _ in range(200)
            ],
            args.repeats,
        )
        / 200
    )

    # what a design costs the kernel: compile + one call over the task
    robots = [prp3.Robot(l0=0.25 + 0.1 * k / 20) for k in range(20)]

    def per_design() -> None:
        for r in robots:
            paper_forces(compile_robot(r), pose, velocity, acceleration, reactions=True)

    per_design()
    t_design = _median_time(per_design, args.repeats) / len(robots)

    # evaluate_designs in this process (no Dask)
    part = values[: args.chunk]
    evaluate_designs(spec.evaluator, part)
    t_eval = _median_time(lambda: evaluate_designs(spec.evaluator, part), args.repeats) / len(part)
    cpu_eval = statistics.median(
        _cpu_time(evaluate_designs, spec.evaluator, part) for _ in range(args.repeats)
    ) / len(part)
    cpu_worker = math.nan

    rows: list[tuple[str, float]] = [
        ("kernel: paper_forces, 1e5 samples/call", kernel_rate / task),
        (f"paper_forces, 1 call of {task} samples", 1.0 / t_call),
        ("paper_forces per new robot (compile + call)", 1.0 / t_design),
        ("evaluate_designs (traced kernel, blocks)", 1.0 / t_eval),
    ]
    starts: dict[int, float] = {}
    for workers in (1, 2):
        begin = time.perf_counter()
        with (
            LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                scheduler_kwargs=prp3.apps.cluster.QUIET_SCHEDULER,
            ) as cluster,
            Client(cluster) as client,
        ):
            client.wait_for_workers(workers)
            starts[workers] = time.perf_counter() - begin

            @contextlib.contextmanager
            def existing(c: Client = client) -> Iterator[Client]:
                yield c

            def sweep() -> None:
                folder = Path(tempfile.mkdtemp(prefix="prp3-bench-sweep-"))
                try:
                    prp3.run_sweep(spec, folder, existing)
                finally:
                    shutil.rmtree(folder, ignore_errors=True)

            sweep()  # warm: workers import prp3, first chunks
            t_sweep = _median_time(sweep, args.repeats)
            if workers == 1:  # the same chunk's CPU time inside a worker process
                shared = client.scatter(spec.evaluator, broadcast=True)
                cpu_worker = statistics.median(
                    client.submit(_cpu_time, evaluate_designs, shared, part, pure=False).result()
                    for _ in range(args.repeats)
                ) / len(part)
        rows.append(
            (f"sweep, {workers} worker{'s' if workers > 1 else ''}", args.designs / t_sweep)
        )

    print(
        f"prp3 sweep benchmark: {args.designs} designs x {task} samples "
        f"(vertical + rotation, {args.samples} each), chunks of {args.chunk}; "
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {sys.version.split()[0]}, numpy {np.__version__}"
    )
    print(f"{'':<42}{'designs/s':>12}{'samples/s':>14}{'/ kernel':>10}")
    for name, rate in rows:
        print(f"{name:<42}{rate:>12.1f}{rate * task:>14.3g}{rate / rows[0][1]:>10.2f}")
    one, two = rows[-2][1], rows[-1][1]
    print(f"scaling efficiency 2 workers: {two / (2 * one):.2f}  (speed-up {two / one:.2f})")
    print(
        f"cluster start (untimed above): {starts[1]:.2f} s with 1 worker, {starts[2]:.2f} s with 2"
    )
    half = rows[-2][1] >= 0.5 * rows[0][1]
    print(
        f"sweep with 1 worker at >= half the kernel's rate (wall clock): {'yes' if half else 'no'}"
    )
    print(
        f"CPU time per sample: kernel {cpu_kernel * 1e9:.0f} ns, evaluate_designs "
        f"{cpu_eval / task * 1e9:.0f} ns in this process, {cpu_worker / task * 1e9:.0f} ns in a "
        f"Dask worker: the sweep's CPU rate is {cpu_kernel * task / cpu_worker:.2f} of the kernel's"
    )
    print(
        f"load average (1 min) at the start and the end: {load_start:.1f}, {os.getloadavg()[0]:.1f}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
