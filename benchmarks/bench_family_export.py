#!/usr/bin/env python
"""The family's speed table beside MuJoCo's model of the same robot, and the C per architecture.

Run from the repository root (about a minute; ``--quick`` for fewer samples)::

    python benchmarks/bench_family_export.py
    python benchmarks/bench_family_export.py --quick

For each architecture's default design, on the paper's ``rotation`` motion
resampled to N samples (the design's own joint values, rates and
accelerations from prp3, prepared untimed for MuJoCo):

* ``prp3 batch``: :func:`prp3.family_inverse_dynamics` (the default
  fast route, validation and kinematics included, every joint force) at
  ``N = 10⁵`` — samples/s, the best of 3;
* ``prp3 single``: the same with a one-sample motion (validated), median µs;
* ``numba batch`` / ``single``: :func:`prp3.family_inverse_dynamics` with ``engine="numba"``
  (validated; tau, joint wrenches, measures), the same samples, compiled
  before timing (``numba compile``: its first call, s);
* ``mujoco batch`` / ``single``: the model of ``prp3 export mjcf``
  (:func:`prp3.family_mjcf_model`), per sample in a Python loop:
  ``mj_kinematics``, ``mj_comPos``, ``mj_comVel``, ``mj_rne`` (``M·q̈ + c``),
  ``mj_jac`` of the three platform thirds at ``G`` and the 9×9 solve
  ``S·tau + J_cᵀ·λ = M·q̈ + c`` (exact, no soft constraint); the actuator
  efforts only.  Checked against prp3 to 1e-8 relative (exit status 1 otherwise);
* ``C``: the code of ``prp3 export c`` (:func:`prp3.family_c_inverse_dynamics`),
  compiled with ``-std=c99 -pedantic-errors -Wall -Werror -O2`` together with a C
  harness: the median over batches of 1000 calls on 1000 different samples,
  ns per call (tau and all 27 joint-wrench components).

Issue targets: batch ≥ 10⁶ samples/s, single call ≤ 20 µs, C ≤ 500 ns/call.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
import timeit
from pathlib import Path

import numpy as np

from prp3 import (
    ARCHITECTURES,
    FamilyRobot,
    Motion,
    family_c_inverse_dynamics,
    family_inverse_dynamics,
    family_mjcf_model,
    joint_names,
    paper_motion,
)
from prp3.apps.codegen import HEADER_NAME, SOURCE_NAME

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

/* argv: batches, input file (1000 samples of 9 doubles). Prints the median over the
   batches of the time per call of a batch of 1000 calls (ns). */
int main(int argc, char **argv)
{
    long batches = argc > 1 ? atol(argv[1]) : 1000, b;
    int k;
    static double in[1000][9];
    double tau[3], joint[27], sink = 0.0, *per_call;
    struct timespec start, stop;
    FILE *file = fopen(argv[2], "rb");
    if (file == NULL || fread(in, sizeof(double), 9000, file) != 9000) return 2;
    fclose(file);
    per_call = malloc(sizeof(double) * (size_t)batches);
    if (per_call == NULL) return 2;
    for (b = 0; b < batches; ++b) {
        clock_gettime(CLOCK_MONOTONIC, &start);
        for (k = 0; k < 1000; ++k) {
            if (prp3_inverse_dynamics(in[k], in[k] + 3, in[k] + 6, tau, joint) != 0) return 3;
            sink += tau[0] + joint[26];
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


class MujocoFamily:
    """Closed-chain inverse dynamics of a family robot with MuJoCo (actuator efforts)."""

    def __init__(self, robot: FamilyRobot) -> None:
        import mujoco

        self.mj = mujoco
        self.model = mujoco.MjModel.from_xml_string(family_mjcf_model(robot))
        self.data = mujoco.MjData(self.model)
        m = self.model
        names = joint_names(robot)
        self.order = np.array([int(m.jnt_dofadr[m.joint(n).id]) for n in names])
        self.thirds = [int(m.body(f"platform_{leg}").id) for leg in "ABC"]
        self.tau = np.zeros(m.nv)
        self.jac = np.zeros((3, 6, m.nv))
        self.difference = np.zeros((6, 18))
        for r, row in enumerate((0, 1, 5)):
            for k in (1, 2):
                self.difference[3 * (k - 1) + r, 6 * k + row] = 1.0
                self.difference[3 * (k - 1) + r, row] = -1.0
        self.system = np.zeros((m.nv, 9))
        for i, leg in enumerate("ABC"):
            self.system[m.jnt_dofadr[m.joint(f"q{robot.actuated}_{leg}").id], i] = 1.0

    def prepare(self, robot: FamilyRobot, motion: Motion) -> tuple[np.ndarray, ...]:
        """The family's ``q, q̇, q̈`` in MuJoCo's dof order, ``(N, 9)`` each (untimed)."""
        solution = family_inverse_dynamics(robot, motion)
        out = []
        for values in (solution.q, solution.dq, solution.ddq):
            flat = values.reshape(-1, 9)
            tree = np.empty_like(flat)
            tree[:, self.order] = flat
            out.append(tree)
        return tuple(out)

    def single(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        mj, m, d = self.mj, self.model, self.data
        d.qpos[:] = q
        d.qvel[:] = qd
        d.qacc[:] = qdd
        mj.mj_kinematics(m, d)
        mj.mj_comPos(m, d)
        mj.mj_comVel(m, d)
        mj.mj_rne(m, d, 1, self.tau)
        centre = d.xipos[self.thirds[0]]
        for k, body in enumerate(self.thirds):
            mj.mj_jac(m, d, self.jac[k, :3], self.jac[k, 3:], centre, body)
        self.system[:, 3:] = (self.difference @ self.jac.reshape(18, -1)).T
        return np.linalg.solve(self.system, self.tau)[:3]

    def batch(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        out = np.empty((q.shape[0], 3))
        for k in range(q.shape[0]):
            out[k] = self.single(q[k], qd[k], qdd[k])
        return out


def best_rate(call: object, samples: int, repeat: int = 3) -> float:
    return samples / min(timeit.Timer(call).repeat(repeat=repeat, number=1))  # type: ignore[arg-type]


def median_us(call: object, number: int = 50, repeat: int = 9) -> float:
    return statistics.median(timeit.Timer(call).repeat(repeat=repeat, number=number)) / number * 1e6  # type: ignore[arg-type]


def c_ns(robot: FamilyRobot, motion: Motion, batches: int) -> float | None:
    compiler = shutil.which("gcc") or shutil.which("cc") or shutil.which("clang")
    if compiler is None:
        return None
    rows = np.concatenate([motion.pose, motion.velocity, motion.acceleration], axis=1)[:1000]
    with tempfile.TemporaryDirectory() as folder:
        where = Path(folder)
        code = family_c_inverse_dynamics(robot)
        (where / HEADER_NAME).write_text(code.header)
        (where / SOURCE_NAME).write_text(code.source)
        (where / "harness.c").write_text(HARNESS)
        (where / "inputs.bin").write_bytes(np.ascontiguousarray(rows).tobytes())
        flags = ["-std=c99", "-pedantic-errors", "-Wall", "-Werror", "-O2"]
        subprocess.run(
            [compiler, *flags, "-o", str(where / "harness"), str(where / "harness.c"),
             str(where / SOURCE_NAME), "-lm"],
            check=True,
        )  # fmt: skip
        runs = []
        for _ in range(3):
            done = subprocess.run(
                [str(where / "harness"), str(batches), str(where / "inputs.bin")],
                capture_output=True, text=True, check=True,
            )  # fmt: skip
            runs.append(float(done.stdout.split()[0]))
        return statistics.median(runs)


def numba_cells(robot: FamilyRobot, motion: Motion, single: Motion) -> list[str]:
    """The compiled engine's batch samples/s, single call µs and compile time (s)."""
    start = timeit.default_timer()
    family_inverse_dynamics(robot, single, engine="numba")
    compile_s = timeit.default_timer() - start
    rate = best_rate(lambda: family_inverse_dynamics(robot, motion, engine="numba"), motion.samples)
    one = median_us(lambda: family_inverse_dynamics(robot, single, engine="numba"), number=200)
    return [f"{rate:>15.3g}", f"{one:>9.1f}", f"{compile_s:>9.1f}"]


def mujoco_row(robot: FamilyRobot, motion: Motion) -> tuple[float, float, float]:
    """MuJoCo's batch samples/s, single call µs and largest relative error against prp3."""
    peer = MujocoFamily(robot)
    q, qd, qdd = peer.prepare(robot, motion)
    rate = best_rate(lambda: peer.batch(q, qd, qdd), motion.samples, repeat=1)
    one = median_us(lambda: peer.single(q[7], qd[7], qdd[7]), number=200)
    want = family_inverse_dynamics(robot, motion).tau
    error = float(np.abs(peer.batch(q, qd, qdd) - want).max() / np.abs(want).max())
    return rate, one, error


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 10^4, MuJoCo 2000 samples")
    parser.add_argument("--mujoco-samples", type=int, default=20_000, help="MuJoCo loop samples")
    args = parser.parse_args()
    n = 10_000 if args.quick else 100_000
    n_mj = 2000 if args.quick else args.mujoco_samples
    batches = 200 if args.quick else 1000
    motion = paper_motion("rotation", n)
    small = paper_motion("rotation", n_mj)
    c_motion = paper_motion("rotation", 1000)
    single = Motion(
        t=np.zeros(1),
        pose=np.array([[0.01, -0.005, 0.05]]),
        velocity=np.array([[0.1, 0.05, 0.2]]),
        acceleration=np.array([[0.5, -0.3, 1.0]]),
    )
    try:
        import mujoco  # noqa: F401

        have_mujoco = True
    except ImportError:
        have_mujoco = False
    header = (
        f"{'architecture':<14}{f'prp3 N={n:.0e}':>14}{'single':>9}"
        f"{f'numba N={n:.0e}':>15}{'single':>9}{'compile':>9}"
        f"{f'mujoco N={n_mj:.0e}':>16}{'single':>9}{'C':>9}{'mujoco err':>12}"
    )
    print(header)
    print(
        f"{'':<14}{'samples/s':>14}{'µs':>9}{'samples/s':>15}{'µs':>9}{'s':>9}"
        f"{'samples/s':>16}{'µs':>9}{'ns/call':>9}{'rel.':>12}"
    )
    status = 0
    for arch in ARCHITECTURES:
        robot = FamilyRobot.default(arch)
        batch = best_rate(lambda robot=robot: family_inverse_dynamics(robot, motion), n)
        one = median_us(lambda robot=robot: family_inverse_dynamics(robot, single))
        cells = [f"{batch:>14.3g}", f"{one:>9.1f}"]
        cells += numba_cells(robot, motion, single)
        if have_mujoco:
            mj_rate, mj_one, error = mujoco_row(robot, small)
            if not error <= 1e-8:
                status = 1
            cells += [f"{mj_rate:>16.3g}", f"{mj_one:>9.1f}"]
        else:
            error = float("nan")
            cells += [f"{'-':>16}", f"{'-':>9}"]
        ns = c_ns(robot, c_motion, batches)
        cells += [f"{ns:>9.0f}" if ns is not None else f"{'-':>9}", f"{error:>12.1e}"]
        print(f"{arch:<14}" + "".join(cells), flush=True)
    print("targets: batch >= 1e6 samples/s, single <= 20 µs, C <= 500 ns/call")
    return status


if __name__ == "__main__":
    sys.exit(main())
