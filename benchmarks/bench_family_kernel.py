#!/usr/bin/env python
"""The family's numba engine before and after a change, in one run: samples/s, single call, compile.

Run from the repository root::

    python benchmarks/bench_family_kernel.py --before /path/to/other/src
    python benchmarks/bench_family_kernel.py --before /path/to/other/src --quick

For each architecture's default design, in a fresh process per source tree
(``PYTHONPATH`` = that tree's ``src``, the trees measured in turn, twice,
the best kept): the validated batch ``prp3.family_inverse_dynamics(robot,
motion, engine="numba")`` on the paper's ``rotation`` motion at N = 10^5
(samples per CPU second of the process, best of 5: every output of
``FamilySolution``), the validated single call (``Motion.at_rest([0.01, 0,
0.05])``, median CPU µs), and the ratios after/before.  Then, for this tree,
the first compile of the seven default designs in a fresh ``NUMBA_CACHE_DIR``
(wall seconds of the first call of each, the process's start left out), and
the generated sample kernel alone (``prp3.family.compiled_kernel.kernel_batch``:
the closures, branch rule and dynamics of every sample, no path).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parents[1] / "src"

_MEASURE = r"""
import json, statistics, sys, time
from prp3 import ARCHITECTURES, FamilyRobot, Motion, family_inverse_dynamics, paper_motion
n = int(sys.argv[1])
motion = paper_motion("rotation", n)
single = Motion.at_rest([0.01, 0.0, 0.05])
out = {}
for arch in ARCHITECTURES:
    robot = FamilyRobot.default(arch)
    family_inverse_dynamics(robot, motion, engine="numba")  # compiled (or loaded) first
    best = float("inf")
    for _ in range(5):
        start = time.process_time()
        family_inverse_dynamics(robot, motion, engine="numba")
        best = min(best, time.process_time() - start)
    times = []
    for _ in range(7):
        start = time.process_time()
        for _ in range(300):
            family_inverse_dynamics(robot, single, engine="numba")
        times.append((time.process_time() - start) / 300)
    out[arch] = (n / best, statistics.median(times) * 1e6)
print(json.dumps(out))
"""

_COMPILE = r"""
import json, time
import numpy as np
from prp3 import ARCHITECTURES, FamilyRobot, Motion, family_inverse_dynamics, paper_motion
from prp3.family.compiled_kernel import kernel_batch
single = Motion.at_rest([0.01, 0.0, 0.05])
out = {}
for arch in ARCHITECTURES:
    robot = FamilyRobot.default(arch)
    start = time.perf_counter()
    family_inverse_dynamics(robot, single, engine="numba")
    out[arch] = [time.perf_counter() - start]
motion = paper_motion("rotation", 100000)
for arch in ARCHITECTURES:
    robot = FamilyRobot.default(arch)
    start = time.perf_counter()
    kernel_batch(robot, motion.pose[:1], motion.velocity[:1], motion.acceleration[:1], False)
    out[arch].append(time.perf_counter() - start)
    best = float("inf")
    for _ in range(5):
        start = time.process_time()
        kernel_batch(robot, motion.pose, motion.velocity, motion.acceleration)
        best = min(best, time.process_time() - start)
    out[arch].append(motion.t.size / best)
print(json.dumps(out))
"""


def run(script: str, src: Path, *args: str, cache: str | None = None) -> dict[str, list[float]]:
    env = {**os.environ, "PYTHONPATH": str(src)}
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = cache
    done = subprocess.run(
        [sys.executable, "-c", script, *args], env=env, capture_output=True, text=True, check=True
    )
    result: dict[str, list[float]] = json.loads(done.stdout.strip().splitlines()[-1])
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True, help="the other tree's src")
    parser.add_argument("--quick", action="store_true", help="N = 10^4, one round")
    args = parser.parse_args()
    n = "10000" if args.quick else "100000"
    best: dict[str, dict[str, list[float]]] = {}
    for _ in range(1 if args.quick else 2):
        for name, src in (("before", args.before), ("after", HERE)):
            got = run(_MEASURE, src, n)
            old = best.setdefault(name, got)
            for arch, (rate, micro) in got.items():
                old[arch] = [max(old[arch][0], rate), min(old[arch][1], micro)]
    print(f"| architecture | before N={n} | after | ratio | before single | after single | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for arch, (rate, micro) in best["after"].items():
        rate0, micro0 = best["before"][arch]
        print(f"| {arch} | {rate0:.3g} | {rate:.3g} | {rate / rate0:.2f}x | {micro0:.1f} µs "
              f"| {micro:.1f} µs | {micro0 / micro:.2f}x |")  # fmt: skip
    print("samples per CPU second (best of 5), validated, every output; single: median CPU µs")
    with tempfile.TemporaryDirectory() as cache:
        compile_times = run(_COMPILE, HERE, cache=cache)
    print()
    print("| architecture | first compile, route (s) | first compile, sample kernel (s) "
          "| sample kernel N=10^5 (samples/CPU s) |")  # fmt: skip
    print("|---|---:|---:|---:|")
    for arch, (route, kernel, rate) in compile_times.items():
        print(f"| {arch} | {route:.1f} | {kernel:.1f} | {rate:.3g} |")
    total = sum(v[0] for v in compile_times.values())
    print(f"first compile of the route, all seven, fresh NUMBA_CACHE_DIR: {total:.0f} s")


if __name__ == "__main__":
    main()
