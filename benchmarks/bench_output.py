#!/usr/bin/env python
"""Writing the results of a big run: CSV text (two writers) and Parquet, and whole runs.

Run from the repository root (``pip install -e ".[parquet]"`` for pyarrow)::

    python benchmarks/bench_output.py                 # N = 10^6 samples, a few minutes
    python benchmarks/bench_output.py --samples 100000

Measured on the 46 columns of ``results.csv`` for the paper's rotation motion
resampled to N samples (computed once, untimed):

* ``csv, repr``: the CSV writer without pyarrow (``repr`` of every float, row
  by row: prp3's writer before Arrow made the text);
* ``csv, arrow``: :func:`prp3.write_table_csv` with pyarrow (Arrow's CSV
  writer on the float64 columns: its shortest round-trip texts) — both files
  read back (:func:`prp3.read_table_csv`) to the same doubles bit for bit
  (exit status 1 if they do not); the reading is timed too (``read csv``);
* ``parquet``: :func:`prp3.write_table_parquet`;

then the whole command ``prp3 simulate --motion rotation --samples N`` in a
subprocess (start-up, computing, writing), with ``--format parquet`` and with
CSV.  Each writer runs ``--repeats`` times (default 1 at N = 10^6); the best
time is printed, with the ratio to ``csv, repr`` measured in the same run
(the machine may be shared: ratios are what to compare).
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import prp3
from prp3 import simulate_table
from prp3.io import tables as prp3_tables


def best_of(repeats: int, action: Callable[[], None]) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--no-runs", action="store_true", help="skip the whole-command runs")
    args = parser.parse_args()
    samples = args.samples
    arrow = prp3_tables.parquet_available()
    print(
        f"prp3 {prp3.__version__}, Python {platform.python_version()}, numpy {np.__version__}, "
        f"pyarrow {'missing' if not arrow else __import__('pyarrow').__version__}, "
        f"{platform.machine()}, {os.cpu_count()} CPUs"
    )
    start = time.perf_counter()
    table = simulate_table(prp3.Robot(), prp3.paper_motion("rotation", samples))
    print(f"N = {samples}: 46 columns computed in {time.perf_counter() - start:.2f} s (untimed)")
    names = list(table)
    columns = [np.asarray(table[name], dtype=np.float64) for name in names]
    failures = 0
    with tempfile.TemporaryDirectory() as folder:
        plain, fast, parquet = (Path(folder) / n for n in ("a.csv", "b.csv", "c.parquet"))
        timings = {
            "csv, repr": best_of(
                args.repeats, lambda: prp3_tables._write_csv_python(plain, names, columns, None)
            )
        }
        if arrow:
            timings["csv, arrow"] = best_of(
                args.repeats, lambda: prp3_tables.write_table_csv(fast, table)
            )
            timings["parquet"] = best_of(
                args.repeats, lambda: prp3_tables.write_table_parquet(parquet, table)
            )
            start = time.perf_counter()
            back = prp3_tables.read_table_csv(fast, required=names)
            read_seconds = time.perf_counter() - start
            again = prp3_tables.read_table_csv(plain, required=names)
            same = all(
                back[name].tobytes() == again[name].tobytes() == column.tobytes()
                for name, column in zip(names, columns, strict=True)
            )
            if not same:
                print("FAILED: the two CSV files do not read back to the same doubles")
                failures += 1
            else:
                print(f"both CSV files read back bit for bit (read csv: {read_seconds:.2f} s)")
        sizes = {"csv, repr": plain, "csv, arrow": fast, "parquet": parquet}
        reference = timings["csv, repr"]
        print(f"{'writer':<12} {'time (s)':>9} {'ratio':>7} {'MB':>8}")
        for name, seconds in timings.items():
            size = sizes[name].stat().st_size / 1e6
            print(f"{name:<12} {seconds:9.2f} {reference / seconds:6.2f}x {size:8.1f}")
        if not args.no_runs:
            print(f"whole runs: prp3 simulate --motion rotation --samples {samples}")
            for extra in (["--format", "parquet"] if arrow else [], []):
                command = [sys.executable, "-m", "prp3", "simulate", "--motion", "rotation",
                           "--samples", str(samples), "-o", str(Path(folder) / "run"), *extra]  # fmt: skip
                start = time.perf_counter()
                done = subprocess.run(command, capture_output=True, text=True)
                seconds = time.perf_counter() - start
                label = " ".join(extra) or "--format csv"
                if done.returncode != 0:
                    print(f"FAILED: {label}: {done.stderr.strip()}")
                    failures += 1
                else:
                    print(f"  {label:<18} {seconds:7.2f} s (target for parquet: <= 3 s)")
                if not extra:
                    break
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
