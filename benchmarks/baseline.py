#!/usr/bin/env python
"""Time an older prp3's fast path on given samples (the ``--baseline`` row of the benchmark).

``bench_inverse_dynamics.py --baseline COMMIT`` extracts ``src/`` of that
commit with ``git archive`` into a temporary folder and runs this script with
that folder first on ``PYTHONPATH``, so that ``import prp3`` is the old code::

    PYTHONPATH=/tmp/old/src python benchmarks/baseline.py samples.npz result.json

``samples.npz`` holds ``pose_K``, ``velocity_K``, ``acceleration_K`` for each
timed batch ``K`` (the same arrays the current code is timed on) and
``single_pose``, ``single_velocity``, ``single_acceleration`` (one sample).
Written to ``result.json``: for each batch, the median seconds of
``paper_forces(compiled, pose, velocity, acceleration).f10`` and its ``f10``
(for the agreement check); median microseconds of ``sample_forces`` with
ndarray and with tuple inputs.  The timing is the benchmark's own
(``median_seconds``, passed as ``--repeats`` and ``--budget``).  Only the
public API that commit had is used: ``compile_robot``, ``paper_forces``,
``sample_forces`` and ``Robot`` of the package, ``sample_forces_unchecked``
where the commit defines it.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import timeit
from collections.abc import Callable

import numpy as np


def median_seconds(call: Callable[[], object], repeats: int, budget: float) -> float:
    """As ``bench_inverse_dynamics.median_seconds`` (kept in step by hand: 10 lines)."""
    timer = timeit.Timer(call)
    number, total = timer.autorange()
    number = max(1, int(number * budget / max(total, 1e-9)))
    if total > 2.0:
        times = [total / number] + [timer.timeit(1) for _ in range(max(0, repeats - 1))]
        return statistics.median(times)
    return statistics.median(timer.repeat(repeat=repeats, number=number)) / number


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("samples")
    parser.add_argument("result")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--budget", type=float, default=0.2)
    args = parser.parse_args(argv)

    import prp3
    from prp3 import compile_robot, paper_forces, sample_forces

    try:  # where the commit keeps the unchecked call: today's module, else prp3.fast (older)
        from prp3.engines.sample_entries import sample_forces_unchecked
    except ImportError:
        from prp3.fast import sample_forces_unchecked  # type: ignore[no-redef]

    compiled = compile_robot(prp3.Robot())
    data = np.load(args.samples)
    keys = sorted({name.split("_", 1)[1] for name in data.files if name.startswith("pose_")})
    result: dict[str, object] = {"prp3_file": prp3.__file__, "batches": {}}
    for key in keys:
        arrays = tuple(data[f"{part}_{key}"] for part in ("pose", "velocity", "acceleration"))
        f10 = paper_forces(compiled, *arrays).f10
        seconds = median_seconds(
            lambda a=arrays: paper_forces(compiled, *a).f10, args.repeats, args.budget
        )
        result["batches"][key] = {"seconds": seconds, "f10": np.asarray(f10).tolist()}  # type: ignore[index]
        print(f"  baseline {key:<24} {len(arrays[0]) / seconds:10.4g} samples/s", file=sys.stderr)
    one = tuple(data[f"single_{part}"] for part in ("pose", "velocity", "acceleration"))
    tuples = tuple(tuple(a.tolist()) for a in one)
    flat = [v for a in tuples for v in a]
    calls: dict[str, Callable[[], object]] = {
        "sample_forces, ndarray (3,)": lambda: sample_forces(compiled, *one),
        "sample_forces, tuples": lambda: sample_forces(compiled, *tuples),
        "sample_forces_unchecked": lambda: sample_forces_unchecked(compiled, *flat),
    }
    result["single"] = {
        name: 1e6 * median_seconds(call, max(args.repeats, 7), args.budget)
        for name, call in calls.items()
    }
    with open(args.result, "w", encoding="utf-8") as handle:
        json.dump(result, handle)
    return 0


if __name__ == "__main__":
    sys.exit(main())
