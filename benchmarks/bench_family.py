#!/usr/bin/env python
"""The family's three routes (docs/family.md §7): samples per second, per architecture.

Run from the repository root::

    python benchmarks/bench_family.py            # N = 10^3, 10^4, 10^5 (a few minutes)
    python benchmarks/bench_family.py --quick    # N = 10^3, 10^4
    python benchmarks/bench_family.py --engines  # the engines' table only (N = 10^5, single call)

For each architecture's default design, on the paper's ``rotation`` motion
resampled to N samples: ``fast`` (:func:`prp3.family_inverse_dynamics`,
kinematics included), ``paper`` and ``newton-euler`` (N ≤ 10^4), and one
single-sample call (µs, median); beside them, in the same run, the 3-PRP of
model form by :func:`prp3.paper_forces` with every reaction (the peer the
ratios are taken against) and by ``prp3.inverse_dynamics(..., "paper")``.

Then the engines of the fast route side by side (the targets of issue 20:
≥ 10^6 samples/s at N = 10^5, ≤ 20 µs per validated single call):
``engine="numba"`` (:mod:`prp3.family.compiled`) and ``engine="numpy"``
(:mod:`prp3.family.mechanics`), batch samples/s at N = 10^5 and the single
validated call in µs (median), with MuJoCo's inverse dynamics of the same
robot beside (:func:`mujoco_rate`, the model of ``prp3 export mjcf``; "-"
without MuJoCo) and the ratios to it.  The first call of the numba engine compiles it (once
per machine, cached); it is made before the clock starts.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import time
import timeit
import warnings

from prp3 import (
    ARCHITECTURES,
    FamilyRobot,
    Motion,
    Robot,
    family_inverse_dynamics,
    inverse_dynamics,
    paper_forces,
    paper_motion,
)


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


def cpu_single_call(call: object, number: int = 200) -> float:
    """Median CPU µs of one ``call()`` (7 repeats of ``number`` calls): without other load."""
    times = []
    for _ in range(7):
        start = time.process_time()
        for _ in range(number):
            call()  # type: ignore[operator]
        times.append(time.process_time() - start)
    return statistics.median(times) / number * 1e6


def mujoco_rate(robot: FamilyRobot, motion: Motion) -> tuple[float, float] | None:
    """MuJoCo's inverse dynamics of the same robot: ``(samples/s, single-call µs)``, or None.

    The model of ``prp3 export mjcf`` (:func:`prp3.family_mjcf_model`:
    the three legs as a tree, the platform's thirds welded), solved per sample in
    a Python loop as ``benchmarks/peers.py`` solves the 3-PRP: the family's
    ``q, q̇, q̈`` (untimed, from the fast route) set MuJoCo's state, then
    ``mj_kinematics``, ``mj_comPos``, ``mj_comVel``, ``mj_rne`` with the
    acceleration (``M·q̈ + c``, gravity included) and ``mj_jac`` of the three
    thirds at ``G``; the 9×9 system ``M·q̈ + c = S·τ + J_cᵀ·λ`` gives ``τ``
    (``J_c``: the planar rows of the thirds B and C relative to A).  The efforts
    are checked against the fast route's (relative 1e-8).  Samples/s over the
    first 10^4 samples of ``motion`` (a Python loop: the rate does not depend on
    N); None without MuJoCo (``pip install .[bench]``).
    """
    if importlib.util.find_spec("mujoco") is None:
        return None
    import mujoco
    import numpy as np

    from prp3 import family_mjcf_model, joint_names

    with warnings.catch_warnings():  # the MjcfWarning of a [load]: the defaults have none
        warnings.simplefilter("ignore")
        model = mujoco.MjModel.from_xml_string(family_mjcf_model(robot))
    data = mujoco.MjData(model)
    names = joint_names(robot)
    dof = np.array([model.jnt_dofadr[model.joint(name).id] for name in names])
    thirds = [int(model.body(f"platform_{leg}").id) for leg in "ABC"]
    m = min(motion.t.size, 10_000)
    part = Motion(motion.t[:m], motion.pose[:m], motion.velocity[:m], motion.acceleration[:m])
    solution = family_inverse_dynamics(robot, part)
    q, dq, ddq = (np.zeros((m, model.nv)) for _ in range(3))
    for state, value in ((q, solution.q), (dq, solution.dq), (ddq, solution.ddq)):
        state[:, dof] = value.reshape(m, 9)
    tau = np.zeros(model.nv)
    jac = np.zeros((3, 6, model.nv))
    difference = np.zeros((6, 18))  # (v_x, v_y, ω_z) of third B minus A, then C minus A
    for r, row in enumerate((0, 1, 5)):
        for k in (1, 2):
            difference[3 * (k - 1) + r, 6 * k + row] = 1.0
            difference[3 * (k - 1) + r, row] = -1.0
    system = np.zeros((model.nv, 9))
    for a in range(model.nu):
        system[model.jnt_dofadr[model.actuator_trnid[a, 0]], a] = model.actuator_gear[a, 0]

    def single(k: int) -> object:
        data.qpos[:] = q[k]
        data.qvel[:] = dq[k]
        data.qacc[:] = ddq[k]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        mujoco.mj_comVel(model, data)
        mujoco.mj_rne(model, data, 1, tau)
        point = data.xipos[thirds[0]]  # G: the inertial frame of platform_A
        for i, body in enumerate(thirds):
            mujoco.mj_jac(model, data, jac[i, :3], jac[i, 3:], point, body)
        system[:, 3:] = (difference @ jac.reshape(18, -1)).T
        return np.linalg.solve(system, tau)[:3]

    def loop() -> object:
        return [single(k) for k in range(m)]

    got = np.array(loop())
    want = solution.tau.reshape(m, 3)
    error = float(np.abs(got - want).max() / np.abs(want).max())
    if not error < 1e-8:
        raise AssertionError(f"MuJoCo's efforts differ from the fast route's by {error:.2g}")
    return rate(loop, m, 1), single_call(lambda: single(0), number=200)


def engines_table(n: int = 100_000) -> None:
    """Batch samples/s at N = ``n`` and single validated call µs, numba and numpy engines."""
    motion = paper_motion("rotation", n)
    single = Motion.at_rest([0.01, 0.0, 0.05])
    head = ("architecture", f"numba N={n}", "numba (CPU time)", f"numpy N={n}", "ratio",
            "numba single", "numba single (CPU time)",
            "numpy single", "MuJoCo", "MuJoCo single", "numba/MuJoCo", "single vs MuJoCo")  # fmt: skip
    print("| " + " | ".join(head) + " |")
    print("|---" + "|---:" * (len(head) - 1) + "|")
    for arch in ARCHITECTURES:
        robot = FamilyRobot.default(arch)
        family_inverse_dynamics(robot, single, engine="numba")  # compiled (or loaded) first
        fast = rate(lambda r=robot: family_inverse_dynamics(r, motion, engine="numba"), n, 5)
        cpu = cpu_rate(lambda r=robot: family_inverse_dynamics(r, motion, engine="numba"), n)
        slow = rate(lambda r=robot: family_inverse_dynamics(r, motion, engine="numpy"), n, 1)
        one = single_call(lambda r=robot: family_inverse_dynamics(r, single, engine="numba"))
        one_cpu = cpu_single_call(
            lambda r=robot: family_inverse_dynamics(r, single, engine="numba")
        )
        ref = single_call(
            lambda r=robot: family_inverse_dynamics(r, single, engine="numpy"), number=20
        )
        peer = mujoco_rate(robot, motion)
        mj = (
            ("-",) * 4 if peer is None
            else (f"{peer[0]:.3g}", f"{peer[1]:.1f} µs", f"{fast / peer[0]:.0f}x",
                  f"{peer[1] / one:.1f}x")
        )  # fmt: skip
        cells = (arch, f"{fast:.3g}", f"{cpu:.3g}", f"{slow:.3g}", f"{fast / slow:.0f}x", f"{one:.1f} µs", f"{one_cpu:.1f} µs",
                 f"{ref:.0f} µs", *mj)  # fmt: skip
        print("| " + " | ".join(cells) + " |")
    print("samples/s of wall time (best of 5 runs for numba, 1 for numpy), and of this process's")
    print("CPU time (the machine's other load left out); single call: median µs, validated;")
    print("MuJoCo: samples/s of its per-sample loop (first 10^4 samples) and its single call")


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
