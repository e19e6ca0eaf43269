#!/usr/bin/env python
"""Line profiles of prp3's reference path and of the fused kernel of ``prp3.engines.entries``.

Needs ``line_profiler`` (``pip install line_profiler``)::

    python benchmarks/profile_paths.py              # N = 10⁵ samples of the rotation motion
    python benchmarks/profile_paths.py --samples 1000000 --top 15

Prints, for ``inverse_dynamics(robot, motion, "paper")`` (inverse geometry,
inverse kinematics, body wrenches, paper method) and for
:func:`prp3.paper_forces`, the share of time of each function and the
lines that take the most time.
"""

from __future__ import annotations

import argparse
import linecache
import sys

import prp3
import prp3.analysis.inverse_dynamics
import prp3.engines.compiled_robot
import prp3.engines.entries
import prp3.engines.select
import prp3.mechanics.geometry
import prp3.mechanics.kinematics
import prp3.mechanics.virtual_work


def profile(call: object, functions: list[object], top: int) -> None:
    try:
        from line_profiler import LineProfiler
    except ImportError:
        sys.exit("line_profiler is not installed: pip install line_profiler")
    profiler = LineProfiler(*functions)
    profiler.runcall(call)  # type: ignore[arg-type]
    stats = profiler.get_stats()
    rows = []
    totals = {}
    for (filename, _, name), timings in stats.timings.items():
        seconds = sum(t for _, _, t in timings) * stats.unit
        totals[name] = seconds
        for line, hits, time in timings:
            text = linecache.getline(filename, line).strip()
            rows.append((time * stats.unit, name, line, hits, text))
    outer = max(totals.values())
    for name, seconds in sorted(totals.items(), key=lambda item: -item[1]):
        print(
            f"  {name:<22} {seconds * 1e3:9.2f} ms  ({100 * seconds / outer:5.1f} % of the outermost)"
        )
    print(f"  top {top} lines:")
    for seconds, name, line, hits, text in sorted(rows, reverse=True)[:top]:
        print(
            f"    {seconds * 1e3:8.2f} ms {100 * seconds / outer:5.1f} %  {name}:{line} ×{hits}  {text[:90]}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=10**5)
    parser.add_argument("--top", type=int, default=12)
    args = parser.parse_args()
    robot = prp3.Robot()
    motion = prp3.paper_motion("rotation", samples=args.samples)
    print(f"Reference path: inverse_dynamics(robot, motion, 'paper'), N = {args.samples}")
    profile(
        lambda: prp3.inverse_dynamics(robot, motion),
        [
            prp3.analysis.inverse_dynamics.inverse_dynamics,
            prp3.mechanics.geometry.inverse_geometry,
            prp3.mechanics.kinematics.inverse_kinematics,
            prp3.mechanics.kinematics.jacobian,
            prp3.analysis.inverse_dynamics.kernel_method,
        ],
        args.top,
    )
    compiled = prp3.compile_robot(robot)
    print(f"\nFused path, numpy engine: prp3.engines.entries.paper_forces, N = {args.samples}")
    profile(
        lambda: prp3.paper_forces(
            compiled, motion.pose, motion.velocity, motion.acceleration, engine="numpy"
        ),
        [
            prp3.engines.entries.paper_forces,
            prp3.engines.select.run_numpy,
            prp3.mechanics.virtual_work.joint_forces,
        ],
        args.top,
    )


if __name__ == "__main__":
    main()
