#!/usr/bin/env python
"""The family's three routes (docs/family.md §7): samples per second, per architecture.

Run from the repository root::

    python benchmarks/bench_family.py            # N = 10^3, 10^4, 10^5 (about a minute)
    python benchmarks/bench_family.py --quick    # N = 10^3, 10^4

For each architecture's default design, on the paper's ``rotation`` motion
resampled to N samples: ``fast`` (:func:`prp3.family.family_inverse_dynamics`,
kinematics included), ``paper`` and ``newton-euler`` (N ≤ 10^4), and one
single-sample call (µs, median); beside them, in the same run, the 3-PRP of
model form by :func:`prp3.fast.paper_forces` with every reaction (the peer the
ratios are taken against) and by ``prp3.inverse_dynamics(..., "paper")``.
"""

from __future__ import annotations

import argparse
import statistics
import timeit

from prp3 import Motion, Robot, inverse_dynamics, paper_motion
from prp3.family import ARCHITECTURES, FamilyRobot, family_inverse_dynamics
from prp3.fast import paper_forces


def rate(call: object, samples: int, repeat: int = 3) -> float:
    """Samples per second of ``call()`` (the best of ``repeat`` runs)."""
    timer = timeit.Timer(call)  # type: ignore[arg-type]
    best = min(timer.repeat(repeat=repeat, number=1))
    return samples / best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 10^3, 10^4 only")
    args = parser.parse_args()
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


if __name__ == "__main__":
    main()
