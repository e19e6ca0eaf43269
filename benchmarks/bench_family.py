#!/usr/bin/env python
"""The family's three routes (docs/family.md §7): samples per second, per architecture.

Run from the repository root::

    python benchmarks/bench_family.py            # N = 10^3, 10^4, 10^5 (a few minutes)
    python benchmarks/bench_family.py --quick    # N = 10^3, 10^4
    python benchmarks/bench_family.py --engines  # the engines' table only (N = 10^5, single call)

For each architecture's default design, on the paper's ``rotation`` motion
resampled to N samples: ``fast`` (:func:`prp3.family.family_inverse_dynamics`,
kinematics included), ``paper`` and ``newton-euler`` (N ≤ 10^4), and one
single-sample call (µs, median); beside them, in the same run, the 3-PRP of
model form by :func:`prp3.engines.entries.paper_forces` with every reaction (the peer the
ratios are taken against) and by ``prp3.inverse_dynamics(..., "paper")``.

Then the engines of the fast route side by side (the targets of issue 20:
≥ 10^6 samples/s at N = 10^5, ≤ 20 µs per validated single call):
``engine="numba"`` (:mod:`prp3.family.compiled`) and ``engine="numpy"``
(:mod:`prp3.family.mechanics`), batch samples/s at N = 10^5 and the single
validated call in µs (median), with MuJoCo's inverse dynamics of the same
robot beside when :mod:`prp3.family.mjcf` is there (:func:`mujoco_rate`, the
hook; "-" otherwise).  The first call of the numba engine compiles it (once
per machine, cached); it is made before the clock starts.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import time
import timeit

from prp3 import Motion, Robot, inverse_dynamics, paper_motion
from prp3.engines.entries import paper_forces
from prp3.family import ARCHITECTURES, FamilyRobot, family_inverse_dynamics


def rate(call: object, samples: int, repeat: int = 3) -> float:
    """Samples per second of ``call()`` (the best of ``repeat`` runs)."""
    timer = timeit.Timer(call)  # type: ignore[arg-type]
    best = min(timer.repeat(repeat=repeat, number=1))
    return samples / best


def cpu_rate(call: object, samples: int, repeat: int = 5) -> float:
    """Samples per CPU second of ``call()`` (best of ``repeat``): the rate without other load."""
    best = float("inf")
    for _ in range(repeat):
        start = time.process_time()
        call()  # type: ignore[operator]
        best = min(best, time.process_time() - start)
    return samples / best


def single_call(call: object, number: int = 200) -> float:
    """Median µs of one ``call()`` (7 repeats of ``number`` calls)."""
    times = timeit.Timer(call).repeat(7, number)  # type: ignore[arg-type]
    return statistics.median(times) / number * 1e6


def mujoco_rate(robot: FamilyRobot, motion: Motion) -> tuple[float, float] | None:
    """MuJoCo's inverse dynamics of the same robot: ``(samples/s, single-call µs)``, or None.

    The hook for ``prp3.family.mjcf`` (``prp3 export mjcf`` of a family robot,
    written on another branch): None while that module is not in this tree.
    When it is, plug its per-sample loop in here (``family_mjcf_model(robot)``,
    ``mj_inverse`` on the closed chain, the weld forces solved as in
    ``benchmarks/peers.py`` for the 3-PRP).
    """
    if importlib.util.find_spec("prp3.family.mjcf") is None:
        return None
    return None  # pragma: no cover - to be filled with the module's loop


def engines_table(n: int = 100_000) -> None:
    """Batch samples/s at N = ``n`` and single validated call µs, numba and numpy engines."""
    motion = paper_motion("rotation", n)
    single = Motion.at_rest([0.01, 0.0, 0.05])
    head = ("architecture", f"numba N={n}", "numba (CPU time)", f"numpy N={n}", "ratio",
            "numba single",
            "numpy single", "MuJoCo N", "MuJoCo single")  # fmt: skip
    print("| " + " | ".join(head) + " |")
    print("|---" + "|---:" * (len(head) - 1) + "|")
    for arch in ARCHITECTURES:
        robot = FamilyRobot.default(arch)
        family_inverse_dynamics(robot, single, engine="numba")  # compiled (or loaded) first
        fast = rate(lambda r=robot: family_inverse_dynamics(r, motion, engine="numba"), n, 5)
        cpu = cpu_rate(lambda r=robot: family_inverse_dynamics(r, motion, engine="numba"), n)
        slow = rate(lambda r=robot: family_inverse_dynamics(r, motion, engine="numpy"), n, 1)
        one = single_call(lambda r=robot: family_inverse_dynamics(r, single, engine="numba"))
        ref = single_call(
            lambda r=robot: family_inverse_dynamics(r, single, engine="numpy"), number=20
        )
        peer = mujoco_rate(robot, motion)
        mj = ("-", "-") if peer is None else (f"{peer[0]:.3g}", f"{peer[1]:.1f}")
        cells = (arch, f"{fast:.3g}", f"{cpu:.3g}", f"{slow:.3g}", f"{fast / slow:.0f}x", f"{one:.1f} µs",
                 f"{ref:.0f} µs", *mj)  # fmt: skip
        print("| " + " | ".join(cells) + " |")
    print("samples/s of wall time (best of 5 runs for numba, 1 for numpy), and of this process's")
    print("CPU time (the machine's other load left out); single call: median µs, validated")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 10^3, 10^4 only")
    parser.add_argument("--engines", action="store_true", help="the engines' table only")
    args = parser.parse_args()
    if args.engines:
        engines_table()
        return
    sizes = [1000, 10_000] if args.quick else [1000, 10_000, 100_000]
    print(f"{'robot':<22}{'method':<14}" + "".join(f"{f'N={n}':>14}" for n in sizes))
    model = Robot()
    motions = {n: paper_motion("rotation", n) for n in sizes}
    peer: dict[int, float] = {}
    row = []
    for n in sizes:
        m = motions[n]
        peer[n] = rate(
            lambda m=m: paper_forces(model, m.pose, m.velocity, m.acceleration, reactions=True), n
        )
        row.append(f"{peer[n]:>14.3g}")
    print(f"{'3-PRP (model form)':<22}{'fast':<14}" + "".join(row))
    row = [
        f"{rate(lambda m=motions[n]: inverse_dynamics(model, m, 'paper'), n):>14.3g}" for n in sizes
    ]
    print(f"{'3-PRP (model form)':<22}{'paper':<14}" + "".join(row))
    single = Motion.at_rest([0.01, 0.0, 0.05])
    for arch in ARCHITECTURES:
        robot = FamilyRobot.default(arch)
        for method in ("fast", "paper", "newton-euler"):
            cells = []
            for n in sizes:
                if method != "fast" and n > 10_000:
                    cells.append(f"{'-':>14}")
                    continue
                value = rate(
                    lambda m=motions[n], method=method, robot=robot: family_inverse_dynamics(
                        robot, m, method
                    ),
                    n,
                )
                ratio = f" ({value / peer[n]:.2f}x)" if method == "fast" else ""
                cells.append(f"{f'{value:.3g}{ratio}':>14}")
            print(f"{arch:<22}{method:<14}" + "".join(cells))
        times = timeit.Timer(lambda robot=robot: family_inverse_dynamics(robot, single)).repeat(
            7, 20
        )
        micro = statistics.median(times) / 20 * 1e6
        print(f"{arch:<22}{'single call':<14}{f'{micro:.0f} µs':>14}")
    print("samples/s; (x): the fast route against the 3-PRP kernel of model form, same N")
    print()
    engines_table(sizes[-1])


if __name__ == "__main__":
    main()
