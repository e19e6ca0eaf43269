#!/usr/bin/env python
"""``prp3 simulate`` in a new process with each engine: where numba's start-up is repaid.

Run from the repository root::

    python benchmarks/bench_cli_engines.py            # 3-PRP and 3-RRR, N up to 3·10⁶
    python benchmarks/bench_cli_engines.py --quick    # fewer sizes

For each route (the 3-PRP kernel; the family's fast route on the default
3-RRR) and each N, the wall time of ``prp3 simulate --motion vertical
--samples N --engine E`` (results written as CSV) with ``E`` = numba and numpy,
the median of ``--repeats`` runs, each in a new process with a warm numba cache
(the cache is filled by one untimed run first).  Printed: the two times, their
difference, and the N from which numba is the faster in this run — what
:data:`prp3.cli._engine.NUMBA_FROM` (the rule of ``--engine auto``) is set from.
``PYTHONDONTWRITEBYTECODE`` is removed from the children's environment: a
user's Python writes its bytecode once, and compiling every module again in
each run would add the same time to both engines.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import timeit
from pathlib import Path

HERE = Path(__file__).resolve().parent
FAMILY_ROBOT = 'architecture = "3-RRR"\n'


def seconds(command: list[str], env: dict[str, str]) -> float:
    """Wall time of one command in a new process (s)."""
    start = timeit.default_timer()
    subprocess.run(command, check=True, env=env, capture_output=True)
    return timeit.default_timer() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 301, 10⁴, 10⁵, 10⁶")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    sizes = [301, 10**4, 10**5, 10**6] if args.quick else [301, 10**4, 5 * 10**4, 10**5, 3 * 10**5, 10**6, 3 * 10**6]  # fmt: skip
    env = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(HERE.parent / "src")
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"{os.cpu_count()} CPUs, load average at start {load}; median of {args.repeats} runs")
    with tempfile.TemporaryDirectory(prefix="prp3-engines-") as name:
        folder = Path(name)
        robot = folder / "ROBOT.toml"
        robot.write_text(FAMILY_ROBOT, encoding="utf-8")
        base = [sys.executable, "-m", "prp3", "simulate", "--motion", "vertical"]
        for route, extra in (("3-PRP", []), ("family (3-RRR)", ["--robot", str(robot)])):
            print(f"\n{route}: prp3 simulate --motion vertical --samples N, seconds")
            print("| N | numba | numpy | numpy − numba |")
            print("|---|---|---|---|")
            faster_from = None
            for n in sizes:
                times = {}
                for engine in ("numba", "numpy"):
                    command = [*base, *extra, "--samples", str(n), "--engine", engine]
                    command += ["--output", str(folder / f"out-{engine}")]
                    seconds(command, env)  # warm: the numba cache, the OS's file cache
                    times[engine] = statistics.median(
                        seconds(command, env) for _ in range(args.repeats)
                    )
                gain = times["numpy"] - times["numba"]
                if gain > 0 and faster_from is None:
                    faster_from = n
                elif gain <= 0:
                    faster_from = None
                print(f"| {n:,} | {times['numba']:.2f} | {times['numpy']:.2f} | {gain:+.2f} |")
            print(
                f"numba is the faster from N = {faster_from:,}"
                if faster_from
                else "numba is never the faster here"
            )


if __name__ == "__main__":
    main()
