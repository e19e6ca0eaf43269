"""The generated C of the spatial robots (``prp3 export c``), per call, beside the numba kernel.

From the repository root::

    PYTHONPATH=src python benchmarks/bench_spatial_c.py [--samples N] [--calls M]

For each architecture (6-UPS, 3-RPS, 3-RUU: docs/spatial.md §7, §11, §12) on ``N`` random
regular states (``prp3.spatial_random_motion``), in one run:

* the generated C (``prp3.spatial_c_inverse_dynamics``) compiled with the system's ``cc
  -O2`` into a small driver program that reads the states and calls
  ``prp3_inverse_dynamics`` ``M`` times in a loop over them (no Python in the loop; the
  best of five loops), its outputs checked against the numba kernel's to 1e-12;
* the same C with the chain's motion in two passes per leg (``#define PRP3_ONE_PASS 0``:
  the bias with ``q̈ = 0``, then the chain again with ``q̈``) instead of one;
* the same C with neither that nor its fast path of the legs closed by an S joint
  (``PRP3_S_CLOSED 0`` too, the generic LU; the 6-UPS and the 3-RPS differ);
* the numba kernel (``prp3.compile_spatial(robot).raw``) on the same states, one thread,
  per sample (a batch: the loop is numba's), and one state per Python call.

Never run as a test (the tests assert no timings); the table of docs/spatial.md §24 is
its output.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import prp3
from prp3.apps.codegen import HEADER_NAME, SOURCE_NAME

_DRIVER = r"""#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "prp3_inverse_dynamics.h"
#define OUT_Q (PRP3_LEGS * PRP3_DOF)
#define OUT_W (PRP3_LEGS * PRP3_JOINTS * 3)
int main(int argc, char **argv)
{
    long n = atol(argv[2]), calls = atol(argv[3]), k, c;
    int repeat, bad = 0;
    double *s = malloc(sizeof(double) * 24 * n), best = 1e300, sum = 0.0;
    double q[OUT_Q], dq[OUT_Q], ddq[OUT_Q], tau[PRP3_LEGS], force[OUT_W], moment[OUT_W];
    FILE *in = fopen(argv[1], "rb"), *out = fopen(argv[4], "wb");
    if (fread(s, sizeof(double), 24 * n, in) != (size_t)(24 * n)) return 3;
    for (k = 0; k < n; ++k) { /* the outputs of every state, for the check */
        const double *x = s + 24 * k;
        bad |= prp3_inverse_dynamics(x, x + 3, x + 12, x + 15, x + 18, x + 21, q, dq, ddq, tau,
                                     force, moment);
        fwrite(tau, sizeof(double), PRP3_LEGS, out);
        fwrite(force, sizeof(double), OUT_W, out);
        fwrite(moment, sizeof(double), OUT_W, out);
    }
    for (repeat = 0; repeat < 5; ++repeat) {
        struct timespec t0, t1;
        double seconds;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        for (c = 0; c < calls; ++c) {
            const double *x = s + 24 * (c % n);
            bad |= prp3_inverse_dynamics(x, x + 3, x + 12, x + 15, x + 18, x + 21, q, dq, ddq,
                                         tau, force, moment);
            sum += tau[0];
        }
        clock_gettime(CLOCK_MONOTONIC, &t1);
        seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        if (seconds < best) best = seconds;
    }
    printf("%.6e %d %g\n", best / (double)calls, bad, sum);
    fclose(out);
    return 0;
}
"""


def _c_time(robot: prp3.SpatialRobot, states: np.ndarray, calls: int, folder: Path,
            off: tuple[str, ...] = ()) -> tuple[float, np.ndarray]:  # fmt: skip
    """The C's time per call and outputs, with the ``#define``'s named in ``off`` set to 0."""
    code = prp3.spatial_c_inverse_dynamics(robot)
    source = code.source
    for name in off:
        source = source.replace(f"#define {name} 1", f"#define {name} 0")
    (folder / HEADER_NAME).write_text(code.header)
    (folder / SOURCE_NAME).write_text(source)
    (folder / "driver.c").write_text(_DRIVER)
    compiler = shutil.which("cc") or shutil.which("gcc") or "clang"
    program = folder / "bench"
    subprocess.run([compiler, "-std=c99", "-O2", "-o", str(program), str(folder / "driver.c"),
                    str(folder / SOURCE_NAME), "-lm"], check=True)  # fmt: skip
    states.astype(np.float64).tofile(folder / "states.bin")
    done = subprocess.run(
        [str(program), str(folder / "states.bin"), str(len(states)), str(calls),
         str(folder / "out.bin")], check=True, capture_output=True, text=True)  # fmt: skip
    per_call, bad, _ = done.stdout.split()
    if int(bad):
        raise SystemExit(f"{robot.name}: the C refused a regular state (code {bad})")
    return float(per_call), np.fromfile(folder / "out.bin")


def _kernel(
    robot: prp3.SpatialRobot, motion: prp3.PlatformMotion
) -> tuple[float, float, np.ndarray]:
    kernel = prp3.compile_spatial(robot)
    arrays = [np.ascontiguousarray(a) for a in (motion.position, motion.rotation, motion.omega,
              motion.velocity, motion.alpha, motion.acceleration)]  # fmt: skip
    kernel.raw(*arrays, threads=False)  # compiled (or loaded from the cache) before timing
    best = np.inf
    for _ in range(5):
        start = time.perf_counter()
        out = kernel.raw(*arrays, threads=False)
        best = min(best, time.perf_counter() - start)
    ones = [[a[k : k + 1] for a in arrays] for k in range(min(len(motion), 2000))]
    single = np.inf
    for _ in range(3):
        start = time.perf_counter()
        for one in ones:
            kernel.raw(*one, threads=False)
        single = min(single, (time.perf_counter() - start) / len(ones))
    n = len(motion)
    values = np.concatenate([out.tau.reshape(n, -1), out.force.reshape(n, -1),
                             out.moment.reshape(n, -1)], axis=1)  # fmt: skip
    return float(best / n), float(single), values.ravel()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--calls", type=int, default=200000)
    args = parser.parse_args()
    print(f"random regular states: {args.samples}; C calls per loop: {args.calls}; one thread")
    print(f"{'robot':<8}{'generated C':>16}{'C, 2 passes':>16}{'C, generic':>16}"
          f"{'numba batch':>16}{'numba 1 call':>16}  C vs batch")  # fmt: skip
    for make in (prp3.hexapod, prp3.three_rps, prp3.delta):
        robot = make()
        motion = prp3.spatial_random_motion(robot, args.samples, 1)
        states = np.concatenate([motion.position, motion.rotation.reshape(-1, 9), motion.omega,
                                 motion.velocity, motion.alpha, motion.acceleration], axis=1)  # fmt: skip
        with tempfile.TemporaryDirectory() as folder:
            c_call, c_values = _c_time(robot, states, args.calls, Path(folder))
        with tempfile.TemporaryDirectory() as folder:  # the legs closed by S through the LU
            c_generic, _ = _c_time(robot, states, args.calls, Path(folder),
                                   ("PRP3_S_CLOSED", "PRP3_ONE_PASS"))  # fmt: skip
        with tempfile.TemporaryDirectory() as folder:  # the chain's motion twice per leg
            c_two, _ = _c_time(robot, states, args.calls, Path(folder), ("PRP3_ONE_PASS",))
        batch, single, k_values = _kernel(robot, motion)
        scale = float(np.max(np.abs(k_values)))
        error = float(np.max(np.abs(c_values - k_values)))
        if error > 1e-12 * scale:
            raise SystemExit(f"{robot.name}: C and kernel differ by {error:.3g} (of {scale:.3g})")
        print(f"{robot.name:<8}{c_call * 1e6:>13.3f} us{c_two * 1e6:>13.3f} us"
              f"{c_generic * 1e6:>13.3f} us{batch * 1e6:>13.3f} us"
              f"{single * 1e6:>13.3f} us  {batch / c_call:8.1f}x")  # fmt: skip


if __name__ == "__main__":
    main()
