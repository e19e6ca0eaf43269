"""The spatial hexapod (docs/spatial.md): how closely the checks of §10 hold, and how long it takes.

From the repository root::

    PYTHONPATH=src python benchmarks/bench_spatial.py            # 200 random designs, N up to 10⁶
    PYTHONPATH=src python benchmarks/bench_spatial.py --quick    # 20 designs, N up to 10⁴

Prints, over random hexapods (radii, angles, height, bodies with off-axis mass
centres and full inertia tensors, tilted gravity) and random independent
states near home:

* the largest relative difference of the efforts of routes (a) and (b);
* the largest relative gap of the energy balance over a smooth motion
  (``∫ Σ power dt`` by 48-point Gauss–Legendre against ``Δ(kinetic + potential)``
  from the library's body motions at the two ends);
* the largest residual of the bodies' balances rebuilt from the reported
  wrenches (route (b)), relative to the largest joint force;
* the time of the kinematics and of each route for N samples.

Never run as a test (the tests assert no timings).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from prp3.spatial.dynamics import body_wrenches, virtual_work_efforts
from prp3.spatial.kinematics import chunk_kinematics, complete_motion, spatial_kinematics
from prp3.spatial.model import Body, SpatialRobot, delta, hexapod, three_rps
from prp3.spatial.motion import PlatformMotion, rpy_motion
from prp3.spatial.newton_euler import newton_euler_dynamics
from prp3.spatial.rotations import rpy_matrix


def _inertia(rng: np.random.Generator, scale: float) -> np.ndarray:
    a, b = rng.uniform(0.3, 1.0, 2)
    c = rng.uniform(abs(a - b) + 0.02, a + b - 0.02)
    r = rpy_matrix(rng.uniform(-math.pi, math.pi, 3))
    return scale * (r @ np.diag([a, b, c]) @ r.T)


def _body(rng: np.random.Generator, x: float, mass: float, scale: float, name: str) -> Body:
    centre = (x * rng.uniform(0.2, 1.5), *rng.uniform(-0.01, 0.01, 2))
    inertia = _inertia(rng, scale)
    return Body(mass * rng.uniform(0.2, 3.0), centre, 0.5 * (inertia + inertia.T), name)


def random_hexapod(rng: np.random.Generator) -> SpatialRobot:
    """A random design of docs/spatial.md §7 with wide limits."""
    return hexapod(
        base_radius=rng.uniform(0.08, 0.14),
        platform_radius=rng.uniform(0.05, 0.08),
        base_half_angle=math.radians(rng.uniform(5, 20)),
        platform_half_angle=math.radians(rng.uniform(35, 55)),
        home_height=rng.uniform(0.07, 0.1),
        stroke=(0.03, 0.3),
        u_limit=1.4,
        s_limit=1.4,
        cylinder=_body(rng, 0.025, 0.12, 4e-5, "cylinder"),
        rod=_body(rng, -0.03, 0.05, 1.5e-5, "rod"),
        platform=_body(rng, 0.0, 1.0, 2e-3, "platform"),
        gravity=(*rng.uniform(-3, 3, 2), -rng.uniform(5, 12)),
    )


def random_rps(rng: np.random.Generator) -> SpatialRobot:
    """A random 3-RPS (docs/spatial.md §11) with wide limits."""
    return three_rps(
        base_radius=rng.uniform(0.08, 0.14),
        platform_radius=rng.uniform(0.04, 0.08),
        home_height=rng.uniform(0.08, 0.12),
        stroke=(0.03, 0.3),
        r_limit=1.5,
        s_limit=1.4,
        cylinder=_body(rng, 0.025, 0.12, 4e-5, "cylinder"),
        rod=_body(rng, -0.03, 0.05, 1.5e-5, "rod"),
        platform=_body(rng, 0.0, 1.0, 2e-3, "platform"),
        gravity=(*rng.uniform(-3, 3, 2), -rng.uniform(5, 12)),
    )


def random_delta(rng: np.random.Generator) -> SpatialRobot:
    """A random Delta as a 3-RUU (docs/spatial.md §12), the arm about horizontal at home."""
    arm, base, platform = rng.uniform(0.08, 0.14), rng.uniform(0.08, 0.14), rng.uniform(0.02, 0.05)
    forearm = (base + arm - platform) * rng.uniform(1.3, 1.8)
    level = math.sqrt(forearm**2 - (base + arm - platform) ** 2)
    return delta(
        base_radius=base,
        arm=arm,
        forearm=forearm,
        platform_radius=platform,
        home_height=level * rng.uniform(0.95, 1.05),
        r_limit=1.5,
        u_limit=1.5,
        arm_body=_body(rng, arm / 2, 0.1, 8e-5, "arm"),
        forearm_body=_body(rng, forearm / 2, 0.06, 3e-4, "forearm"),
        platform=_body(rng, 0.0, 0.2, 6e-5, "platform"),
        gravity=(*rng.uniform(-3, 3, 2), -rng.uniform(5, 12)),
    )


def random_states(
    rng: np.random.Generator, robot: SpatialRobot, n: int, reach: float = 0.006
) -> PlatformMotion:
    """``n`` independent random states near home (completed for robots of fewer than 6 DOF)."""
    position = np.array(robot.home_position) + rng.uniform(-reach, reach, (n, 3))
    motion = PlatformMotion.of(
        np.arange(n, dtype=np.float64),
        position,
        rpy_matrix(rng.uniform(-0.1, 0.1, (n, 3))),
        rng.uniform(-2, 2, (n, 3)),
        rng.uniform(-0.05, 0.05, (n, 3)),
        rng.uniform(-50, 50, (n, 3)),
        rng.uniform(-3, 3, (n, 3)),
    )
    return complete_motion(robot, motion)


def wave(rng: np.random.Generator, robot: SpatialRobot, t: np.ndarray) -> PlatformMotion:
    """A smooth motion near home: sines of time in position and roll–pitch–yaw."""
    a, w, c = rng.uniform(-0.008, 0.008, 3), rng.uniform(0.5, 6, 3), rng.uniform(-3, 3, 3)
    b, u, d = rng.uniform(-0.12, 0.12, 3), rng.uniform(0.5, 6, 3), rng.uniform(-3, 3, 3)
    p0 = np.array(robot.home_position)
    x, y = w * t[:, None] + c, u * t[:, None] + d
    return rpy_motion(
        t, p0 + a * np.sin(x), b * np.sin(y),
        a * w * np.cos(x), b * u * np.cos(y), -a * w * w * np.sin(x), -b * u * u * np.sin(y),
    )  # fmt: skip


def energy(robot: SpatialRobot, motion: PlatformMotion) -> np.ndarray:
    """Kinetic + potential energy per sample from the library's body motions."""
    kin = chunk_kinematics(robot, motion)
    wr = body_wrenches(robot, kin, motion)
    g = np.array(robot.gravity)
    total = np.zeros(len(motion))
    for i, leg in enumerate(robot.legs):
        for k, body in enumerate(leg.bodies):
            r = kin.frames.rotation[:, i, k]
            world = r @ np.array(body.inertia) @ np.swapaxes(r, -1, -2)
            w, v = wr.omega[:, i, k], wr.centre_velocity[:, i, k]
            total += 0.5 * body.mass * np.einsum("ni,ni->n", v, v)
            total += 0.5 * np.einsum("ni,nij,nj->n", w, world, w)
            total -= body.mass * wr.centre[:, i, k] @ g
    p = robot.platform
    world = motion.rotation @ np.array(p.inertia) @ np.swapaxes(motion.rotation, -1, -2)
    v = wr.platform_velocity
    total += 0.5 * p.mass * np.einsum("ni,ni->n", v, v)
    total += 0.5 * np.einsum("ni,nij,nj->n", motion.omega, world, motion.omega)
    total -= p.mass * wr.platform_centre @ g
    return total


def balance_residual(robot: SpatialRobot, motion: PlatformMotion) -> float:
    """The largest force/moment residual of any body under route (b)'s wrenches (relative)."""
    kin = chunk_kinematics(robot, motion)
    wr = body_wrenches(robot, kin, motion)
    sol = newton_euler_dynamics(robot, motion)
    f, m, o = sol.force, sol.moment, kin.frames.origin
    scale = float(np.abs(f).max())
    worst = 0.0
    for k in range(len(robot.legs[0].bodies)):
        c = wr.centre[:, :, k]
        force = f[:, :, k] - f[:, :, k + 1] - wr.force[:, :, k]
        moment = (m[:, :, k] + np.cross(o[:, :, k] - c, f[:, :, k]) - m[:, :, k + 1]
                  - np.cross(o[:, :, k + 1] - c, f[:, :, k + 1]) - wr.moment[:, :, k])  # fmt: skip
        worst = max(worst, float(np.abs(force).max()), float(np.abs(moment).max()) / robot.scale)
    c = wr.platform_centre[:, None]
    force = f[:, :, -1].sum(axis=1) - wr.platform_force
    moment = (m[:, :, -1] + np.cross(o[:, :, -1] - c, f[:, :, -1])).sum(axis=1) - wr.platform_moment
    worst = max(worst, float(np.abs(force).max()), float(np.abs(moment).max()) / robot.scale)
    return worst / scale


def _timed(function, *args):  # type: ignore[no-untyped-def]
    start = time.perf_counter()
    function(*args)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--seed", type=int, default=0)
    options = parser.parse_args()
    designs = 20 if options.quick else 200
    rng = np.random.default_rng(options.seed)
    agreement = energy_gap = residual = 0.0
    nodes, weights = np.polynomial.legendre.leggauss(48)
    for _ in range(designs):
        robot = random_hexapod(rng)
        states = random_states(rng, robot, 16)
        tau_a = virtual_work_efforts(robot, states)
        tau_b = newton_euler_dynamics(robot, states).tau
        agreement = max(agreement, float(np.abs(tau_a - tau_b).max() / np.abs(tau_a).max()))
        residual = max(residual, balance_residual(robot, states))
        span = rng.uniform(0.2, 0.6)
        t = 0.5 * span * (nodes + 1.0)
        seed = rng.integers(2**32)
        inner = wave(np.random.default_rng(seed), robot, t)
        ends_motion = wave(np.random.default_rng(seed), robot, np.array([0.0, span]))
        tau = virtual_work_efforts(robot, inner)
        power = (tau * spatial_kinematics(robot, inner).dq[..., 2]).sum(axis=1)
        ends = energy(robot, ends_motion)
        gap = abs(0.5 * span * float(weights @ power) - (ends[1] - ends[0]))
        energy_gap = max(energy_gap, gap / (0.5 * span * float(weights @ np.abs(power))))
    print(f"designs: {designs} random hexapods, 16 random states each (seed {options.seed})")
    print(f"routes (a) and (b), max |tau_a - tau_b| / max |tau|:  {agreement:.2e}")
    print(f"energy balance, max |work - change| / int |power| dt: {energy_gap:.2e}")
    print(f"body balances, max residual / max |F|:              {residual:.2e}")
    for name, build, reach in (("3-RPS", random_rps, 0.008), ("3-RUU", random_delta, 0.015)):
        agreement = residual = 0.0
        for _ in range(designs):
            robot = build(rng)
            states = random_states(rng, robot, 16, reach)
            tau_a = virtual_work_efforts(robot, states)
            tau_b = newton_euler_dynamics(robot, states).tau
            agreement = max(agreement, float(np.abs(tau_a - tau_b).max() / np.abs(tau_a).max()))
            residual = max(residual, balance_residual(robot, states))
        print(f"{name}: routes (a) and (b) {agreement:.2e}, body balances {residual:.2e}")
    robot = hexapod()
    sizes = (1, 10**4) if options.quick else (1, 10**4, 10**6)
    for n in sizes:
        motion = wave(np.random.default_rng(1), robot, np.linspace(0.0, 10.0, n))
        kin = _timed(spatial_kinematics, robot, motion)
        route_a = _timed(virtual_work_efforts, robot, motion)
        route_b = _timed(newton_euler_dynamics, robot, motion) if n <= 10**4 else math.nan
        print(f"N = {n:>7}: kinematics {kin:8.3f} s, route (a) {route_a:8.3f} s, "
              f"route (b) {route_b:8.3f} s")  # fmt: skip


if __name__ == "__main__":
    main()
