"""The family regressor's build time per sample, before (one fast-route run per unit robot) and after.

Before: the columns by :func:`prp3.family.mechanics.fast_dynamics` on the unit robots (the
``h`` columns by difference), what ``family_regressor`` ran until the generated kernel;
after: ``unit_efforts`` (:mod:`prp3.family.regressor_kernel`).  Both on the same
kinematics (computed once, not timed); CPU µs per sample, best of 5, N = 2000.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from prp3.apps.family_regressor import FAMILY_PARAMETERS, family_random_motion, unit_efforts
from prp3.family.mechanics import family_kinematics, fast_dynamics
from prp3.family.model import ARCHITECTURES, Body, FamilyRobot, PlatformBody
from prp3.model.parameters import Load, Payload


def _before(kin):  # type: ignore[no-untyped-def]
    zero = replace(kin.robot, link1=Body(0.0, (0.0, 0.0), 0.0, name="link1"),
                   link2=Body(0.0, (0.0, 0.0), 0.0, name="link2"), platform=PlatformBody(0.0, 0.0),
                   payload=Payload(), load=Load())  # fmt: skip

    def run(name, mass, com, inertia):  # type: ignore[no-untyped-def]
        if name == "platform":
            unit = (replace(zero, platform=PlatformBody(mass, inertia)) if com == (0.0, 0.0)
                    else replace(zero, payload=Payload(mass, com, inertia)))  # fmt: skip
        else:
            unit = replace(zero, **{name: Body(mass, com, inertia, name=name)})
        return fast_dynamics(replace(kin, robot=unit)).tau

    cache = {}
    columns = []
    for parameter in FAMILY_PARAMETERS:
        part, kind = parameter.split("_", 1)
        keys = {"mass": [(1.0, (0.0, 0.0), 0.0)], "inertia": [(0.0, (0.0, 0.0), 1.0)]}.get(
            kind, [(1.0, (1.0, 0.0) if kind == "moment_x" else (0.0, 1.0), 0.0),
                   (1.0, (0.0, 0.0), 0.0), (0.0, (0.0, 0.0), 1.0)])  # fmt: skip
        values = []
        for key in keys:
            if (part, key) not in cache:
                cache[part, key] = run(part, *key)
            values.append(cache[part, key])
        columns.append(values[0] if len(values) == 1 else values[0] - values[1] - values[2])
    return np.stack(columns, axis=-1)


def _best(function, argument) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(5):
        start = time.process_time()
        function(argument)
        times.append(time.process_time() - start)
    return min(times)


def main() -> None:
    samples = 2000
    print("| architecture | before (µs/sample) | after (µs/sample) | ratio |")
    print("|---|---:|---:|---:|")
    for arch in ARCHITECTURES:
        robot = FamilyRobot.default(arch)
        kin = family_kinematics(robot, family_random_motion(robot, samples, 1))
        unit_efforts(kin, FAMILY_PARAMETERS)  # the generated function built once
        before = _best(_before, kin) / samples * 1e6
        after = _best(lambda k: unit_efforts(k, FAMILY_PARAMETERS), kin) / samples * 1e6
        print(f"| {arch} | {before:.2f} | {after:.2f} | {before / after:.0f}x |")


if __name__ == "__main__":
    main()
