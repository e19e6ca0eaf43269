"""The hexapod's inverse dynamics with every joint reaction: how fast, beside MuJoCo and Pinocchio.

From the repository root::

    PYTHONPATH=src python benchmarks/bench_spatial_speed.py [--samples N]

Measures in one run, for the default 6-UPS (docs/spatial.md §7) on the tilt motion:

* prp3's routes for ``N`` samples: the one linear system of every unknown (route (b) as
  written, the reference), the recursive numpy route (``recursive_newton_euler``) and
  the compiled kernel's batch (``compile_spatial(robot).solve_batch``, numba's threads),
  also with its fast path of the legs closed by an S joint switched off (``S_CLOSED``) and
  with the chain's motion in two passes per leg instead of one (``ONE_PASS``);
* one validated call of the compiled kernel (``CompiledSpatial.solve``, one state), and
  the steps of the former single call (the inputs as a batch of one through ``raw``, the
  outputs indexed: its kernel work, without its checks);
* MuJoCo's ``mj_inverse`` on the hexapod as an open tree (a free platform, each leg two
  hinges, a slide and a ball, the ball's body welded to the platform by a ``connect``
  equality) and Pinocchio's ``rnea`` on the same tree without the closures (their fastest
  routes: MuJoCo's gives the generalised forces of its soft constraint model, Pinocchio's
  the tree's joint torques, neither the joint reactions of §9), one Python call each;

and prints the samples per second, the time per call and the ratios; then, per
architecture in one thread, the kernel as compiled, with the chain's motion in two passes
and generic (both flags at 0), timed in turn.  Never run as a
test (the tests assert no timings); the table of docs/spatial.md §19 is its output.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import prp3
from prp3.spatial.compiled import ONE_PASS, S_CLOSED, U_CLOSED
from prp3.spatial.newton_euler import newton_euler_dynamics, recursive_newton_euler


def _best(function, repeat: int = 5) -> float:  # type: ignore[no-untyped-def]
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return float(best)


def _mjcf(robot: prp3.SpatialRobot) -> str:
    """The hexapod as an open tree closed by ``connect`` equalities (MuJoCo)."""
    bodies = []
    equalities = []
    for i, leg in enumerate(robot.legs):
        u = leg.joints[0]
        rot = np.array(u.rotation)
        z, y = rot[:, 2], rot[:, 1]
        cyl, rod = leg.bodies
        pos = " ".join(f"{v:.9g}" for v in u.position)
        xaxis = " ".join(f"{v:.9g}" for v in rot[:, 0])
        yaxis = " ".join(f"{v:.9g}" for v in rot[:, 1])
        del z, y
        bodies.append(
            f"""<body name="cyl{i}" pos="{pos}" xyaxes="{xaxis} {yaxis}">
  <joint name="ua{i}" type="hinge" axis="0 0 1"/><joint name="ub{i}" type="hinge" axis="0 1 0"/>
  <inertial pos="{cyl.centre[0]} 0 0" mass="{cyl.mass}" diaginertia="{cyl.inertia[0][0]} {cyl.inertia[1][1]} {cyl.inertia[2][2]}"/>
  <body name="rod{i}" pos="0 0 0">
    <joint name="p{i}" type="slide" axis="1 0 0"/>
    <inertial pos="0.072 0 0" mass="{rod.mass}" diaginertia="{rod.inertia[0][0]} {rod.inertia[1][1]} {rod.inertia[2][2]}"/>
    <body name="ball{i}" pos="0.10284 0 0"><joint name="s{i}" type="ball"/>
      <inertial pos="0 0 0" mass="1e-6" diaginertia="1e-9 1e-9 1e-9"/></body>
  </body>
</body>"""
        )
        a = " ".join(f"{v:.9g}" for v in leg.attachment_position)
        equalities.append(f'<connect body1="ball{i}" body2="platform" anchor="0 0 0"/>'
                          f'<!-- platform point {a} -->')  # fmt: skip
    p = robot.platform
    home = " ".join(f"{v:.9g}" for v in robot.home_position)
    return f"""<mujoco model="hexapod"><option gravity="0 0 -9.81"/><worldbody>
<body name="platform" pos="{home}"><freejoint/>
  <inertial pos="0 0 0" mass="{p.mass}" diaginertia="{p.inertia[0][0]} {p.inertia[1][1]} {p.inertia[2][2]}"/></body>
{"".join(bodies)}
</worldbody><equality>{"".join(equalities)}</equality></mujoco>"""


def _mujoco(robot: prp3.SpatialRobot, calls: int) -> float | None:
    try:
        import mujoco
    except ImportError:
        return None
    model = mujoco.MjModel.from_xml_string(_mjcf(robot))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(1)
    data.qvel[:] = rng.normal(0, 0.1, model.nv)
    data.qacc[:] = rng.normal(0, 1.0, model.nv)
    mujoco.mj_inverse(model, data)

    def run() -> None:
        for _ in range(calls):
            mujoco.mj_inverse(model, data)

    return _best(run) / calls


def _pinocchio(robot: prp3.SpatialRobot, calls: int) -> float | None:
    try:
        import pinocchio as pin
    except ImportError:
        return None
    model = pin.Model()
    p = robot.platform
    free = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "platform")
    model.appendBodyToJoint(free, pin.Inertia(p.mass, np.zeros(3), np.array(p.inertia)),
                            pin.SE3.Identity())  # fmt: skip
    for i, leg in enumerate(robot.legs):
        u = leg.joints[0]
        placement = pin.SE3(np.array(u.rotation), np.array(u.position))
        a = model.addJoint(0, pin.JointModelRZ(), placement, f"ua{i}")
        b = model.addJoint(a, pin.JointModelRY(), pin.SE3.Identity(), f"ub{i}")
        cyl, rod = leg.bodies
        model.appendBodyToJoint(b, pin.Inertia(cyl.mass, np.array(cyl.centre), np.array(cyl.inertia)),
                                pin.SE3.Identity())  # fmt: skip
        s = model.addJoint(b, pin.JointModelPX(), pin.SE3.Identity(), f"p{i}")
        model.appendBodyToJoint(s, pin.Inertia(rod.mass, np.array([0.072, 0.0, 0.0]),
                                               np.array(rod.inertia)), pin.SE3.Identity())  # fmt: skip
        model.addJoint(s, pin.JointModelSpherical(), pin.SE3(np.eye(3), np.array([0.10284, 0, 0])),
                       f"s{i}")  # fmt: skip
    data = model.createData()
    q = pin.neutral(model)
    rng = np.random.default_rng(1)
    v, a = rng.normal(0, 0.1, model.nv), rng.normal(0, 1.0, model.nv)
    pin.rnea(model, data, q, v, a)

    def run() -> None:
        for _ in range(calls):
            pin.rnea(model, data, q, v, a)

    return _best(run) / calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=200_000)
    args = parser.parse_args()
    robot = prp3.hexapod()
    kernel = prp3.compile_spatial(robot)
    motion = prp3.spatial_motion(robot, "tilt", args.samples)
    small = motion.chunk(0, 2000)
    kernel.solve_batch(small)  # compiled or loaded from the cache before timing
    system = _best(lambda: newton_euler_dynamics(robot, small), 1) / len(small)
    recursive = _best(lambda: recursive_newton_euler(robot, motion), 2) / len(motion)
    batch = _best(lambda: kernel.solve_batch(motion), 3) / len(motion)
    generic = prp3.compile_spatial(robot)  # the legs closed by S through the 6 x 6 LU
    generic.ints = generic.ints.copy()
    generic.ints[S_CLOSED] = 0
    generic.solve_batch(small)
    batch_generic = _best(lambda: generic.solve_batch(motion), 3) / len(motion)
    two = prp3.compile_spatial(robot)  # the chain's motion in two passes per leg
    two.ints = two.ints.copy()
    two.ints[ONE_PASS] = 0
    two.solve_batch(small)
    batch_two = _best(lambda: two.solve_batch(motion), 3) / len(motion)
    state = (motion.position[7], motion.rotation[7], motion.omega[7], motion.velocity[7],
             motion.alpha[7], motion.acceleration[7])  # fmt: skip
    calls = 20_000
    kernel.solve(*state)

    def singles() -> None:
        for _ in range(calls):
            kernel.solve(*state)

    single = _best(singles) / calls

    def former() -> None:  # the single call before _one: a batch of one through raw
        for _ in range(calls):
            arrays = [np.ascontiguousarray(np.asarray(x, dtype=np.float64))[None] for x in state]
            out = kernel.raw(*arrays, threads=False)
            prp3.SpatialSample(out.q[0], out.dq[0], out.ddq[0], out.tau[0], out.power[0],
                               out.force[0], out.moment[0], out.leg_measure[0],
                               float(out.parallel_measure[0]))  # fmt: skip

    single_former = _best(former) / calls
    mj = _mujoco(robot, calls)
    pn = _pinocchio(robot, calls)
    print(f"6-UPS, tilt motion, {len(motion)} samples; {numba_threads()} threads")
    print(f"{'route':52s} {'per sample':>12s} {'samples/s':>12s}")
    rows = [
        ("prp3 route (b), one 114 x 114 system (reference)", system),
        ("prp3 recursive_newton_euler (numpy)", recursive),
        ("prp3 compile_spatial .solve_batch (numba)", batch),
        ("  the same, the chain's motion twice (ONE_PASS = 0)", batch_two),
        ("  the same, generic path (S_CLOSED = 0)", batch_generic),
        ("prp3 compile_spatial .solve, one validated call", single),
        ("  the former call's steps (raw, a batch of one)", single_former),
    ]
    if mj is not None:
        rows.append(("MuJoCo mj_inverse, open tree + 6 connect (Python)", mj))
    if pn is not None:
        rows.append(("Pinocchio rnea, open tree, no closure (Python)", pn))
    for name, seconds in rows:
        print(f"{name:52s} {seconds * 1e6:9.2f} us {1.0 / seconds:12.3g}")
    print(
        f"batch vs recursive numpy: {recursive / batch:.1f}x; vs the system: {system / batch:.0f}x"
    )
    if mj is not None:
        print(f"validated single call / mj_inverse: {single / mj:.1f}")
    if pn is not None:
        print(f"validated single call / rnea: {single / pn:.1f}")
    print(f"validated single call / the former call's steps: {single / single_former:.2f}")
    _variants()


def _variants(samples: int = 5000, rounds: int = 15) -> None:
    """Each architecture's kernel in one thread on random regular states, as compiled, with
    the U-P leg through the chain of frames (``U_CLOSED = 0``, the 6-UPS only), with the chain's
    motion in two passes too (``ONE_PASS = 0``) and generic (``S_CLOSED = 0`` too),
    timed in turn ``rounds`` times (the best of each: the load of a shared machine hits the
    three alike)."""
    print(f"one thread, {samples} random regular states, the variants timed in turn "
          f"{rounds} times (best), per sample:")  # fmt: skip
    for make in (prp3.hexapod, prp3.three_rps, prp3.delta):
        robot = make()
        motion = prp3.spatial_random_motion(robot, samples, 1)
        arrays = [np.ascontiguousarray(x) for x in (motion.position, motion.rotation,
                  motion.omega, motion.velocity, motion.alpha, motion.acceleration)]  # fmt: skip
        kernels = []
        for flags in ((), (U_CLOSED,), (U_CLOSED, ONE_PASS), (U_CLOSED, ONE_PASS, S_CLOSED)):
            kernel = prp3.compile_spatial(robot)
            kernel.ints = kernel.ints.copy()
            kernel.ints[list(flags)] = 0
            kernel.raw(*arrays, threads=False)
            kernels.append(kernel)
        best = [np.inf] * 4
        for _ in range(rounds):
            for k, kernel in enumerate(kernels):
                start = time.perf_counter()
                kernel.raw(*arrays, threads=False)
                best[k] = min(best[k], time.perf_counter() - start)
        one, chain, two, generic = (b / samples * 1e6 for b in best)
        print(f"  {robot.name:6s} as compiled {one:6.2f} us, U-P by the chain {chain:6.2f} us, "
              f"two passes {two:6.2f} us, generic {generic:6.2f} us")  # fmt: skip


def numba_threads() -> int:
    import numba

    return int(numba.get_num_threads())


if __name__ == "__main__":
    main()
