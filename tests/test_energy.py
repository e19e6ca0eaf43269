"""Power balance ``Σ_i p10_i = d/dt (kinetic + potential energy)`` of the 7 bodies.

The joints are ideal (no friction) and the guides' reactions do no work
(``n10·n ⊥ Ṗ``, the piston does not turn), so the actuators' input power is the
rate of change of the total mechanical energy

    E = Σ_i [½ m1 |v1|² + ½ m2 |v2|² + ½ I2 φ̇² − m1 g·C1 − m2 g·C2] + ½ m3 |Ġ|² + ½ I3 φ̇² − m3 g·G

(the piston's inertia does not enter: ω10 = 0).  Two independent evaluations of
``dE/dt``:

* analytic, ``Σ m v·a + I ω ε − m g·v``, with body velocities and accelerations
  rebuilt from the reported ``λ̇10, λ̈10`` columns (``strategies.body_states``,
  verified against finite differences in ``test_kinematics``);
* 6th-order central differences of ``E(t)`` where ``E`` is computed from the
  independent reference kinematics (``strategies.ref_rates``) at shifted times —
  no output of the core enters it.

These checks see ``f10`` only; the workless reactions are checked by ``test_balances``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from scipy.integrate import simpson

from prp3 import METHODS, Robot, inverse_dynamics
from prp3.motion import paper_motion
from strategies import (
    SQRT3,
    AnalyticMotion,
    BodyStates,
    body_states,
    differentiate,
    dot,
    platform_inertia,
    ref_geometry,
    ref_rates,
    scenarios,
    stencil_times,
)


def energy(robot: Robot, bodies: BodyStates) -> tuple[np.ndarray, np.ndarray]:
    """Total mechanical energy ``E`` and the sum of the magnitudes of its terms (J)."""
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    I2, I3 = robot.link.inertia, platform_inertia(robot)
    g = np.asarray(robot.gravity)
    w = bodies.omega
    terms = [
        0.5 * m1 * dot(bodies.piston_velocity, bodies.piston_velocity).sum(-1),
        0.5 * m2 * dot(bodies.link_velocity, bodies.link_velocity).sum(-1),
        1.5 * I2 * w**2,
        -m1 * (bodies.piston @ g).sum(-1),
        -m2 * (bodies.link @ g).sum(-1),
        0.5 * m3 * dot(bodies.platform_velocity, bodies.platform_velocity),
        0.5 * I3 * w**2,
        -m3 * (bodies.platform @ g),
    ]
    return np.sum(terms, axis=0), np.sum(np.abs(terms), axis=0)


def energy_rate(robot: Robot, bodies: BodyStates) -> tuple[np.ndarray, np.ndarray]:
    """``dE/dt = Σ m v·a + I ω ε − m g·v`` and the sum of the magnitudes of its terms (W)."""
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    I2, I3 = robot.link.inertia, platform_inertia(robot)
    g = np.asarray(robot.gravity)
    w, e = bodies.omega, bodies.epsilon
    terms = [
        m1 * dot(bodies.piston_velocity, bodies.piston_acceleration).sum(-1),
        m2 * dot(bodies.link_velocity, bodies.link_acceleration).sum(-1),
        3.0 * I2 * w * e,
        -m1 * (bodies.piston_velocity @ g).sum(-1),
        -m2 * (bodies.link_velocity @ g).sum(-1),
        m3 * dot(bodies.platform_velocity, bodies.platform_acceleration),
        I3 * w * e,
        -m3 * (bodies.platform_velocity @ g),
    ]
    return np.sum(terms, axis=0), np.sum(np.abs(terms), axis=0)


def reference_energy(robot: Robot, analytic: AnalyticMotion, t: np.ndarray) -> np.ndarray:
    """``E(t)`` from the independent reference kinematics only."""
    pose, velocity, acceleration = analytic.evaluate(t)
    geo = ref_geometry(robot.l0, pose)
    rates = ref_rates(robot.l0, pose, velocity, acceleration)
    bodies = body_states(
        robot, geo.lambda10, rates.dlambda10, rates.ddlambda10, pose, velocity, acceleration
    )
    return energy(robot, bodies)[0]


@given(scenario=scenarios())
def test_input_power_is_the_analytic_energy_rate(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 10))
    for method in METHODS:
        kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
        bodies = body_states(
            robot,
            kin.geometry.lambda10,
            kin.dlambda10,
            kin.ddlambda10,
            motion.pose,
            motion.velocity,
            motion.acceleration,
        )
        rate, scale = energy_rate(robot, bodies)
        power = dyn.p10.sum(axis=-1)
        scale = scale + np.abs(dyn.p10).sum(axis=-1) + 1e-300
        assert np.all(np.abs(power - rate) <= 1e-12 * scale), (method, np.abs(power - rate) / scale)


@given(scenario=scenarios())
def test_input_power_is_the_derivative_of_the_energy(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    # 6th-order differences of E with h = 2 ms.  Error model: truncation O(h⁶ E⁽⁷⁾),
    # bounded by 1e-9 of the power scale, plus round-off ≈ 100·ε·|E terms|/h (the
    # reference positions carry ~10 ε of noise, amplified by the weights / h).
    # Over 400 random cases the error stayed below 4 % of this tolerance.
    robot, analytic = scenario
    T = analytic.duration
    t = np.linspace(0.1 * T, 0.9 * T, 5)
    h = 2e-3
    energy_values = reference_energy(robot, analytic, stencil_times(t, h))
    rate_fd, _ = differentiate(energy_values, h, len(t))
    motion = analytic.motion(t)
    _, dyn = inverse_dynamics(robot, motion)
    power = dyn.p10.sum(axis=-1)
    pose, velocity, acceleration = analytic.evaluate(t)
    geo = ref_geometry(robot.l0, pose)
    rates = ref_rates(robot.l0, pose, velocity, acceleration)
    bodies = body_states(
        robot, geo.lambda10, rates.dlambda10, rates.ddlambda10, pose, velocity, acceleration
    )
    _, power_scale = energy_rate(robot, bodies)
    _, energy_scale = energy(robot, bodies)
    power_scale = power_scale + np.abs(dyn.p10).sum(axis=-1)
    tolerance = 1e-9 * power_scale + 100 * np.finfo(float).eps * energy_scale / h + 1e-300
    assert np.all(np.abs(power - rate_fd) <= tolerance), np.abs(power - rate_fd) / tolerance


@pytest.mark.parametrize("method", METHODS)
def test_work_of_the_actuators_in_the_vertical_paper_motion(method: str) -> None:
    # From rest at y = 0 to rest at y = 0.05 m (x = φ = 0): the work is the rise in
    # potential energy.  Platform: 0.05 m; pistons and links (centres at P_i) move
    # by λ10·e with λ10 = (2, −1, −1)·0.05/√3:
    #   Δy_A = (0.1/√3)(√3/2) = 0.05,  Δy_B = 0 (e_B horizontal),  Δy_C = (−0.05/√3)(−√3/2) = 0.025
    #   W = 9.81·[3·0.05 + (1 + 0.75)(0.05 + 0 + 0.025)] = 9.81·0.28125 = 2.7590625 J.
    motion = paper_motion("vertical", samples=3001)
    _, dyn = inverse_dynamics(Robot(), motion, method=method)  # type: ignore[arg-type]
    work = simpson(dyn.p10.sum(axis=-1), x=motion.t)
    assert work == pytest.approx(9.81 * 0.28125, rel=1e-10)
    assert 0.1 / SQRT3 * (SQRT3 / 2) == pytest.approx(0.05, rel=1e-15)


@pytest.mark.parametrize("method", METHODS)
def test_work_of_the_actuators_in_the_rotation_paper_motion(method: str) -> None:
    # G = O fixed, rest to rest; every leg's λ10 is the same (3-fold symmetry) and
    # Σ e_i = 0, so the centres of mass of the pistons and links (at P_i) move
    # without changing the potential energy: Σ_i λ10·g·e_i = 0 ⇒ the total work is 0,
    # although each actuator works (|∫p10_i dt| > 0).
    motion = paper_motion("rotation", samples=3001)
    _, dyn = inverse_dynamics(Robot(), motion, method=method)  # type: ignore[arg-type]
    per_leg = simpson(dyn.p10, x=motion.t, axis=0)
    scale = simpson(np.abs(dyn.p10).sum(axis=-1), x=motion.t)
    assert abs(per_leg.sum()) <= 1e-10 * scale
    assert np.all(np.abs(per_leg) > 1e-3 * scale)
    assert math.isfinite(scale) and scale > 0
