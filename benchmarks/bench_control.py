#!/usr/bin/env python
"""The controller step in Python and the generated C inverse dynamics: time per call.

Run from the repository root::

    python benchmarks/bench_control.py            # ~1 minute
    python benchmarks/bench_control.py --quick    # fewer repeats

Measured, in the same run (ratios are what travel between machines):

* the controller step of ``prp3 control`` (inverse dynamics of the model +
  control law, :func:`prp3.control_force`): median and 99th
  percentile inside a closed-loop run (``track``, rotation motion, 1 s at
  1 kHz: the caches are cold after each plant step, as in a real loop) for
  the prp3 and the MuJoCo plant, and in a tight loop (warm caches);
* the C function of ``prp3 export c`` for the paper's robot, compiled with
  the system's compiler (``-O2``) together with a small C harness that times
  ``--batches`` batches of 1000 calls over 1000 different samples with
  ``clock_gettime``: the median batch, in ns per call; and the same function
  called through ctypes from Python;
* the Python single-sample calls ``prp3.sample_forces`` (validated) and
  ``sample_forces_unchecked`` on the same samples.

Exit status 1 if the C results differ from ``sample_forces`` by more than
1e-12 relative.
"""

from __future__ import annotations

import argparse
import ctypes
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import prp3
from prp3 import PAPER_MOTIONS, Gains, compile_robot, control_force, control_times, law_at, track
from prp3.apps.codegen import HEADER_NAME, SOURCE_NAME, c_inverse_dynamics
from prp3.engines.sample_entries import sample_forces, sample_forces_unchecked

HARNESS = r"""
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "prp3_inverse_dynamics.h"

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* argv: batches, input file (1000 samples of 9 doubles). Prints the median over
   the batches of the time per call of one batch of 1000 calls (ns): robust to
   the preemptions of a shared machine. */
int main(int argc, char **argv)
{
    long batches = argc > 1 ? atol(argv[1]) : 1000, b;
    int k;
    static double in[1000][9];
    double f10[3], f21y[3], f21z[3], sink = 0.0, *per_call;
    struct timespec start, stop;
    FILE *file = fopen(argv[2], "rb");
    if (file == NULL || fread(in, sizeof(double), 9000, file) != 9000) return 2;
    fclose(file);
    per_call = malloc(sizeof(double) * (size_t)batches);
    if (per_call == NULL) return 2;
    for (b = 0; b < batches; ++b) {
        clock_gettime(CLOCK_MONOTONIC, &start);
        for (k = 0; k < 1000; ++k) {
            if (prp3_inverse_dynamics(in[k], in[k] + 3, in[k] + 6, f10, f21y, f21z) != 0)
                return 3;
            sink += f10[0] + f21y[1] + f21z[2];
        }
        clock_gettime(CLOCK_MONOTONIC, &stop);
        per_call[b] = ((stop.tv_sec - start.tv_sec) * 1e9 + (stop.tv_nsec - start.tv_nsec)) / 1000.0;
    }
    qsort(per_call, (size_t)batches, sizeof(double), by_value);
    printf("%.3f %g\n", per_call[batches / 2], sink);
    free(per_call);
    return 0;
}
"""


def _samples(count: int) -> np.ndarray:
    rng = np.random.default_rng(3)
    pose = np.column_stack(
        [
            rng.uniform(-0.05, 0.05, count),
            rng.uniform(-0.05, 0.05, count),
            rng.uniform(-1, 0.5, count),
        ]
    )
    return np.column_stack([pose, rng.uniform(-1, 1, (count, 3)), rng.uniform(-10, 10, (count, 3))])


def _per_call(function, rows: list, repeats: int) -> float:
    """Median over ``repeats`` passes over ``rows`` of the time of one call (s).

    Each call is timed on its own (``perf_counter_ns``, about 50 ns of its own
    included, as in the control loop): the median ignores the preemptions of a
    shared machine.
    """
    clock = time.perf_counter_ns
    times = []
    for _ in range(repeats):
        for row in rows:
            start = clock()
            function(row)
            times.append(clock() - start)
    return statistics.median(times) * 1e-9


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--batches", type=int, default=5000, help="C batches of 1000 calls")
    args = parser.parse_args()
    repeats = 3 if args.quick else 9
    robot = prp3.Robot()
    compiled = compile_robot(robot)
    print(f"machine: {platform.machine()}, {platform.processor() or platform.platform()}, "
          f"Python {platform.python_version()}, numpy {np.__version__}")  # fmt: skip

    # ---- controller step in the loop
    print("\ncontroller step (inverse dynamics + control law), rotation motion 1 s at 1 kHz:")
    reference = law_at(PAPER_MOTIONS["rotation"], control_times(0.0, 1.0, 1000.0))
    plants = ["prp3"] + (["mujoco"] if _has("mujoco") else [])
    for plant in plants:
        for controller in ("computed-torque", "pd", "feedforward"):
            runs = [
                track(robot, reference, controller=controller, plant=plant)  # type: ignore[arg-type]
                for _ in range(1 if args.quick else 3)
            ]  # the median run of three: the load of a shared machine varies
            run = sorted(runs, key=lambda r: r.step_time_median)[len(runs) // 2]
            print(
                f"  in the loop, {plant:>6} plant, {controller:<15}: median "
                f"{run.step_time_median * 1e6:6.2f} us, p99 {run.step_time_p99 * 1e6:6.2f} us"
            )
    rows9 = _samples(1000)
    targets = rows9.tolist()
    measured = rows9[:, :6].tolist()
    gains = Gains()
    pairs = list(zip(targets, measured, strict=True))
    warm = _per_call(
        lambda pair: control_force("computed-torque", compiled, gains, pair[0], pair[1]),
        pairs,  # type: ignore[arg-type]
        repeats,
    )
    print(f"  tight loop (warm caches), computed-torque: {warm * 1e6:.2f} us per step")

    # ---- Python single sample
    rows = rows9.tolist()
    checked = _per_call(lambda r: sample_forces(compiled, r[:3], r[3:6], r[6:]), rows, repeats)
    unchecked = _per_call(lambda r: sample_forces_unchecked(compiled, *r), rows, repeats)

    # ---- C
    compiler = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if compiler is None:
        print("\nno C compiler: C timings skipped")
        print(f"\nPython: sample_forces {checked * 1e9:.0f} ns, unchecked {unchecked * 1e9:.0f} ns")
        return 0
    status = 0
    with tempfile.TemporaryDirectory() as folder:
        where = Path(folder)
        code = c_inverse_dynamics(robot)
        (where / HEADER_NAME).write_text(code.header)
        (where / SOURCE_NAME).write_text(code.source)
        (where / "harness.c").write_text(HARNESS)
        (where / "inputs.bin").write_bytes(np.ascontiguousarray(rows9).tobytes())
        flags = ["-std=c99", "-pedantic-errors", "-Wall", "-Werror", "-O2"]
        subprocess.run(
            [compiler, *flags, "-o", str(where / "harness"), str(where / "harness.c"),
             str(where / SOURCE_NAME), "-lm"],
            check=True,
        )  # fmt: skip
        subprocess.run(
            [compiler, *flags, "-shared", "-fPIC", "-o", str(where / "lib.so"),
             str(where / SOURCE_NAME), "-lm"],
            check=True,
        )  # fmt: skip
        per_call = []
        for _ in range(repeats):
            done = subprocess.run(
                [str(where / "harness"), str(args.batches), str(where / "inputs.bin")],
                capture_output=True, text=True, check=True,
            )  # fmt: skip
            per_call.append(float(done.stdout.split()[0]))
        c_ns = statistics.median(per_call)
        library = ctypes.CDLL(str(where / "lib.so"))
        function = library.prp3_inverse_dynamics
        pointer = ctypes.POINTER(ctypes.c_double)
        function.argtypes = [pointer] * 6
        function.restype = ctypes.c_int
        outputs = [np.zeros(3) for _ in range(3)]
        output_pointers = [array.ctypes.data_as(pointer) for array in outputs]
        arrays = [(row[:3].copy(), row[3:6].copy(), row[6:].copy()) for row in rows9]
        inputs = [tuple(a.ctypes.data_as(pointer) for a in triple) for triple in arrays]
        worst = 0.0
        for (pose, velocity, acceleration), row in zip(inputs, rows, strict=True):
            assert function(pose, velocity, acceleration, *output_pointers) == 0
            expected = sample_forces(compiled, row[:3], row[3:6], row[6:])
            want = np.array([expected.f10, expected.f21y, expected.f21z])
            worst = max(worst, float(np.abs(np.stack(outputs) - want).max() / np.abs(want).max()))
        ctypes_s = _per_call(lambda i: function(*i, *output_pointers), inputs, repeats)  # type: ignore[arg-type]
    if worst > 1e-12:
        status = 1
    print("\none sample (pose, velocity, acceleration -> f10, f21y, f21z), median:")
    print(f"  C, {compiler} -O2, timed in C     : {c_ns:8.1f} ns per call   (target <= 200 ns)")
    print(f"  C through ctypes from Python     : {ctypes_s * 1e9:8.0f} ns per call")
    print(
        f"  Python sample_forces_unchecked   : {unchecked * 1e9:8.0f} ns per call "
        f"[{unchecked * 1e9 / c_ns:.0f}x the C]"
    )
    print(
        f"  Python sample_forces (validated) : {checked * 1e9:8.0f} ns per call "
        f"[{checked * 1e9 / c_ns:.0f}x the C]"
    )
    print(f"  C against sample_forces: max relative difference {worst:.2e} (<= 1e-12)")
    return status


def _has(module: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(module) is not None


if __name__ == "__main__":
    sys.exit(main())
