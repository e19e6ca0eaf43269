"""The spatial inverse dynamics (docs/spatial.md §8–§10) on random 6-UPS hexapods.

* routes (a) virtual work and (b) Newton–Euler agree to 1e-10 of the largest effort;
* the energy balance ``∫ Σ τ·dq_P dt = Δ(kinetic + potential)``, the kinetic energy
  rebuilt from body velocities taken by finite differences of the bodies' frames,
  which are written out here from the joint values (scipy's rotations);
* every body's force and moment balance, with the bodies' motions written out here
  for the UPS leg from ``q, dq, ddq`` (not the library's chain recursion), and the
  joints' free directions (``M_S = 0``, ``M_U·axes = 0``, ``F_P·u = τ``).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from prp3.errors import ParameterError, UnreachablePoseError
from prp3.spatial import newton_euler
from prp3.spatial.dynamics import virtual_work_efforts
from prp3.spatial.geometry import inverse_geometry
from prp3.spatial.kinematics import spatial_kinematics
from prp3.spatial.model import SpatialRobot, hexapod
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.newton_euler import newton_euler_dynamics
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table
from spatial_strategies import Wave, derivative, hexapods, waves

#: docs/spatial.md §10: the routes agree to this fraction of the largest effort.
AGREEMENT = 1e-10


@st.composite
def states(draw: st.DrawFn, robot: SpatialRobot, n: int = 4) -> PlatformMotion:
    """``n`` independent random states near home: pose, twist and its derivative."""

    def block(scale: float) -> np.ndarray:
        return np.array([[draw(st.floats(-scale, scale)) for _ in range(3)] for _ in range(n)])

    position = np.array(robot.home_position) + block(0.006)
    rotation = Rotation.from_euler("xyz", block(0.1)).as_matrix()
    return PlatformMotion.of(
        np.arange(n, dtype=np.float64), position, rotation,
        block(2.0), block(0.05), block(50.0), block(3.0),
    )  # fmt: skip


def _agreement(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(np.abs(a).max(), 1e-300))


@given(hexapods(), st.data())
def test_the_two_routes_agree(robot: SpatialRobot, data: st.DataObject) -> None:
    motion = data.draw(states(robot))
    tau_a = virtual_work_efforts(robot, motion)
    tau_b = newton_euler_dynamics(robot, motion).tau
    assert _agreement(tau_a, tau_b) < AGREEMENT


@given(hexapods(), st.data())
def test_the_two_routes_agree_along_a_smooth_motion(
    robot: SpatialRobot, data: st.DataObject
) -> None:
    motion = data.draw(waves(robot)).motion(np.linspace(0.0, 2.0, 11))
    assert (
        _agreement(virtual_work_efforts(robot, motion), newton_euler_dynamics(robot, motion).tau)
        < AGREEMENT
    )


# ---------------------------------------------------------------- energy


def _leg_rotation(robot: SpatialRobot, q: np.ndarray) -> np.ndarray:
    """Every leg's cylinder (and rod) rotation ``R_U·Rot_z(a)·Rot_y(b)`` ``(N, legs, 3, 3)``."""
    out = np.empty(q.shape[:2] + (3, 3))
    for i, leg in enumerate(robot.legs):
        a = Rotation.from_euler("z", q[:, i, 0, None]).as_matrix()
        b = Rotation.from_euler("y", q[:, i, 1, None]).as_matrix()
        out[:, i] = np.array(leg.joints[0].rotation) @ a @ b
    return out


def _bodies(
    robot: SpatialRobot, motion: PlatformMotion
) -> list[tuple[float, np.ndarray, np.ndarray, np.ndarray]]:
    """``(mass, inertia in its frame, centre (N, 3), rotation (N, 3, 3))`` of every moving body."""
    q = inverse_geometry(robot, motion)
    rotation = _leg_rotation(robot, q)
    out = []
    for i, leg in enumerate(robot.legs):
        cylinder, rod = leg.bodies
        base = np.array(leg.joints[0].position)
        r = rotation[:, i]
        out.append(
            (cylinder.mass, np.array(cylinder.inertia), base + r @ np.array(cylinder.centre), r)
        )
        origin = base + q[:, i, 2, None] * r[:, :, 0]
        out.append((rod.mass, np.array(rod.inertia), origin + r @ np.array(rod.centre), r))
    p = robot.platform
    centre = motion.position + motion.rotation @ np.array(p.centre)
    out.append((p.mass, np.array(p.inertia), centre, motion.rotation))
    return out


def _energy(robot: SpatialRobot, wave: Wave, t: float, h: float = 1e-4) -> float:
    """Kinetic + potential energy at ``t``, velocities by five-point differences of the frames."""
    times = t + h * np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    bodies = _bodies(robot, wave.motion(times))
    g = np.array(robot.gravity)
    energy = 0.0
    for mass, inertia, centre, rotation in bodies:
        v = derivative(centre, h)
        dr = derivative(rotation, h)
        w = dr @ rotation[2].T
        omega = np.array([w[2, 1], w[0, 2], w[1, 0]])
        world = rotation[2] @ inertia @ rotation[2].T
        energy += 0.5 * mass * v @ v + 0.5 * omega @ world @ omega - mass * g @ centre[2]
    return float(energy)


@given(hexapods(), st.data())
def test_the_actuators_power_is_the_change_of_energy(
    robot: SpatialRobot, data: st.DataObject
) -> None:
    wave = data.draw(waves(robot))
    t0 = data.draw(st.floats(0.0, 1.0))
    span = data.draw(st.floats(0.2, 0.6))
    nodes, weights = np.polynomial.legendre.leggauss(48)
    t = t0 + 0.5 * span * (nodes + 1.0)
    solution = spatial_inverse_dynamics(robot, wave.motion(t), method="virtual-work")
    power = solution.power.sum(axis=1)
    work = 0.5 * span * float(weights @ power)
    change = _energy(robot, wave, t0 + span) - _energy(robot, wave, t0)
    scale = 0.5 * span * float(weights @ np.abs(power)) + 1e-12
    assert abs(work - change) < 1e-7 * scale


# ---------------------------------------------------------------- body balances


def _ups_motion(robot: SpatialRobot, motion: PlatformMotion):  # type: ignore[no-untyped-def]
    """Each leg body's (centre, ω, α, a_G) written out for the UPS leg from ``q, dq, ddq``."""
    kin = spatial_kinematics(robot, motion)
    q, dq, ddq = kin.q, kin.dq, kin.ddq
    rotation = _leg_rotation(robot, q)
    result = []
    for i, leg in enumerate(robot.legs):
        r_u = np.array(leg.joints[0].rotation)
        z = r_u[:, 2]
        y = (r_u @ Rotation.from_euler("z", q[:, i, 0, None]).as_matrix())[:, :, 1]
        r = rotation[:, i]
        u = r[:, :, 0]
        omega = dq[:, i, 0, None] * z + dq[:, i, 1, None] * y
        alpha = (
            ddq[:, i, 0, None] * z
            + ddq[:, i, 1, None] * y
            + dq[:, i, 1, None] * np.cross(dq[:, i, 0, None] * z, y)
        )
        base = np.array(leg.joints[0].position)
        bodies = []
        for body, slide in zip(leg.bodies, (False, True), strict=True):
            length = q[:, i, 2, None] if slide else 0.0
            offset = length * u + r @ np.array(body.centre)
            acc = np.cross(alpha, offset) + np.cross(omega, np.cross(omega, offset))
            if slide:
                acc = acc + ddq[:, i, 2, None] * u + 2.0 * dq[:, i, 2, None] * np.cross(omega, u)
            bodies.append((body, base + offset, omega, alpha, acc, r))
        result.append(bodies)
        # the S's relative rate: ω_platform − ω_rod
        assert np.allclose(motion.omega - omega, dq[:, i, 3:], atol=1e-12 * (1 + np.abs(dq).max()))
    return kin, result


def _residual(body, centre, omega, alpha, acc, rotation, wrenches, gravity):  # type: ignore[no-untyped-def]
    """The force and moment balance of a body under ``wrenches`` [(sign, point, F, M)]."""
    world = rotation @ np.array(body.inertia) @ np.swapaxes(rotation, -1, -2)
    force = body.mass * (acc - gravity)
    moment = np.einsum("nij,nj->ni", world, alpha) + np.cross(
        omega, np.einsum("nij,nj->ni", world, omega)
    )
    for sign, point, f, m in wrenches:
        force = force - sign * f
        moment = moment - sign * (m + np.cross(point - centre, f))
    return force, moment


@given(hexapods(), st.data())
def test_every_body_balances_under_the_reported_wrenches(
    robot: SpatialRobot, data: st.DataObject
) -> None:
    motion = data.draw(states(robot))
    kin, legs = _ups_motion(robot, motion)
    solution = spatial_inverse_dynamics(robot, motion)
    table = spatial_results_table(solution)
    g = np.array(robot.gravity)

    def wrench(i: int, label: str):  # type: ignore[no-untyped-def]
        f = np.stack([table[f"F{c}_{i + 1}_{label}"] for c in "xyz"], axis=1)
        m = np.stack([table[f"M{c}_{i + 1}_{label}"] for c in "xyz"], axis=1)
        return f, m

    scale = np.abs(solution.force).max()
    platform_force = np.zeros((len(motion), 3))
    platform_moment = np.zeros((len(motion), 3))
    p = robot.platform
    pc = motion.position + np.einsum("nij,j->ni", motion.rotation, np.array(p.centre))
    for i, leg in enumerate(robot.legs):
        base = np.array(leg.joints[0].position)
        f_u, m_u = wrench(i, "U1")
        f_p, m_p = wrench(i, "P2")
        f_s, m_s = wrench(i, "S3")
        (cyl, c1, w, al, a1, r), (rod, c2, _, _, a2, _) = legs[i]
        u = r[:, :, 0]
        rod_origin = base + table[f"q_{i + 1}_P2"][:, None] * u
        sphere = motion.position + np.einsum(
            "nij,j->ni", motion.rotation, np.array(leg.attachment_position)
        )
        assert np.allclose(rod_origin, sphere, atol=1e-15)
        for body, centre, acc, acting in (
            (cyl, c1, a1, [(1.0, base, f_u, m_u), (-1.0, rod_origin, f_p, m_p)]),
            (rod, c2, a2, [(1.0, rod_origin, f_p, m_p), (-1.0, sphere, f_s, m_s)]),
        ):
            force, moment = _residual(body, centre, w, al, acc, r, acting, g)
            assert np.abs(force).max() < 1e-12 * scale
            assert np.abs(moment).max() < 1e-12 * scale * robot.scale
        platform_force += f_s
        platform_moment += m_s + np.cross(sphere - pc, f_s)
        # the free directions: no moment through S, none about the U's axes, τ along P
        assert np.abs(m_s).max() < 1e-12 * scale * robot.scale
        z = np.array(leg.joints[0].rotation)[:, 2]
        y = (
            np.array(leg.joints[0].rotation)
            @ Rotation.from_euler("z", kin.q[:, i, 0, None]).as_matrix()
        )[:, :, 1]
        assert np.abs(m_u @ z).max() < 1e-12 * scale * robot.scale
        assert np.abs(np.einsum("ni,ni->n", m_u, y)).max() < 1e-12 * scale * robot.scale
        assert np.allclose(
            np.einsum("ni,ni->n", f_p, u), table[f"tau_{i + 1}"], rtol=0, atol=1e-12 * scale
        )
    world = motion.rotation @ np.array(p.inertia) @ np.swapaxes(motion.rotation, -1, -2)
    rp = pc - motion.position
    acc = (
        motion.acceleration
        + np.cross(motion.alpha, rp)
        + np.cross(motion.omega, np.cross(motion.omega, rp))
    )
    expected_moment = np.einsum("nij,nj->ni", world, motion.alpha) + np.cross(
        motion.omega, np.einsum("nij,nj->ni", world, motion.omega)
    )
    assert np.allclose(platform_force, p.mass * (acc - g), rtol=0, atol=1e-12 * scale)
    assert np.allclose(platform_moment, expected_moment, rtol=0, atol=1e-12 * scale * robot.scale)


def test_at_rest_each_leg_carries_a_sixth_of_the_platform() -> None:
    """The symmetric hexapod at home, no leg masses: each S pushes up ``m·g/6``, the efforts
    are ``m·g/(6·u_z)`` (the legs are two-force members)."""
    from prp3.spatial.model import Body

    light = Body(0.0, (0.0, 0.0, 0.0), name="leg")
    robot = hexapod(cylinder=light, rod=light)
    solution = spatial_inverse_dynamics(robot, PlatformMotion.at_rest(robot.home_position))
    leg = np.array(robot.legs[0].attachment_position) + np.array(robot.home_position)
    u = leg - np.array(robot.legs[0].joints[0].position)
    u_z = u[2] / np.linalg.norm(u)
    assert np.allclose(solution.tau, 9.81 / (6 * u_z), rtol=1e-13)
    assert solution.force is not None
    assert np.allclose(solution.force[0, :, 2, 2], 9.81 / 6, rtol=1e-13)


def test_one_sample_and_a_batch_by_the_same_code(monkeypatch: pytest.MonkeyPatch) -> None:
    robot = hexapod()
    wave = Wave(np.array([0.0, 0.0, 0.08]), np.full(3, 0.004), np.array([1.0, 2.0, 3.0]),
                np.zeros(3), np.full(3, 0.05), np.array([2.0, 1.0, 3.0]), np.ones(3))  # fmt: skip
    motion = wave.motion(np.linspace(0.0, 3.0, 13))
    monkeypatch.setattr(newton_euler, "NE_CHUNK", 4)
    batch = newton_euler_dynamics(robot, motion)
    for k in (0, 3, 4, 12):
        single = newton_euler_dynamics(robot, motion.chunk(k, k + 1))
        assert np.array_equal(batch.force[k], single.force[0])
        assert np.array_equal(batch.tau[k], single.tau[0])


def test_refusals_pass_through_the_dynamics(monkeypatch: pytest.MonkeyPatch) -> None:
    robot = hexapod()
    monkeypatch.setattr(newton_euler, "NE_CHUNK", 2)
    z = np.full(5, 0.08)
    z[3] = 0.05
    motion = PlatformMotion.at_rest(np.stack([np.zeros(5), np.zeros(5), z], axis=1))
    for method in ("newton-euler", "virtual-work"):
        with pytest.raises(UnreachablePoseError, match=r"^sample 3, t = 3 s, leg 1: P2 = "):
            spatial_inverse_dynamics(robot, motion, method)
    with pytest.raises(
        ParameterError, match="method must be one of 'newton-euler', 'virtual-work'"
    ):
        spatial_inverse_dynamics(robot, motion, "paper")
