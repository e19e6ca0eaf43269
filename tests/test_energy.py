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

With every element (:mod:`prp3.model.elements`: a payload, a constant load, the
motion's wrench, smoothed friction of the three joints, the actuators' spring
with damper), the same two checks use the elements' own powers, potentials and
dissipations: ``Σ p10 + Σ_elements power = d(KE)/dt`` (kinetic energy written
here) in every method, and ``Σ p10 + P_external = d/dt(KE + Σ potentials) +
Σ dissipation`` by differences of the reference kinematics.

These checks see ``f10`` only; the workless reactions are checked by ``test_balances``.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import simpson

from prp3 import METHODS, Motion, Robot, inverse_dynamics
from prp3.model.element_base import State
from prp3.model.elements import SPRING, WRENCH
from prp3.model.motion import paper_motion
from prp3.model.parameters import Friction, JointFriction, Load, Payload, Spring, SpringParameters
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


# ------------------------------------------------ every element's power and potential
def kinetic(robot: Robot, bodies: BodyStates, payload_state: tuple[np.ndarray, ...]) -> np.ndarray:
    """Kinetic energy of the 7 bodies and the payload (J), written here."""
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    I2, I3 = robot.link.inertia, platform_inertia(robot)
    w = bodies.omega
    vp = payload_state[0]
    return (
        0.5 * m1 * dot(bodies.piston_velocity, bodies.piston_velocity).sum(-1)
        + 0.5 * m2 * dot(bodies.link_velocity, bodies.link_velocity).sum(-1)
        + 1.5 * I2 * w**2
        + 0.5 * m3 * dot(bodies.platform_velocity, bodies.platform_velocity)
        + 0.5 * I3 * w**2
        + 0.5 * robot.payload.mass * dot(vp, vp)
        + 0.5 * robot.payload.inertia * w**2
    )


def kinetic_rate(
    robot: Robot, bodies: BodyStates, payload_state: tuple[np.ndarray, ...]
) -> tuple[np.ndarray, np.ndarray]:
    """``d(KE)/dt = Σ m v·a + I ω ε`` (payload included) and the sum of its terms' magnitudes."""
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    I2, I3 = robot.link.inertia, platform_inertia(robot)
    w, e = bodies.omega, bodies.epsilon
    vp, ap = payload_state
    terms = [
        m1 * dot(bodies.piston_velocity, bodies.piston_acceleration).sum(-1),
        m2 * dot(bodies.link_velocity, bodies.link_acceleration).sum(-1),
        3.0 * I2 * w * e,
        m3 * dot(bodies.platform_velocity, bodies.platform_acceleration),
        I3 * w * e,
        robot.payload.mass * dot(vp, ap),
        robot.payload.inertia * w * e,
    ]
    return np.sum(terms, axis=0), np.sum(np.abs(terms), axis=0)


def payload_motion(robot: Robot, pose, velocity, acceleration) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    """Velocity and acceleration of the payload's mass centre ``G + Rot(φ)·c_p``."""
    phi, w, e = pose[..., 2], velocity[..., 2, None], acceleration[..., 2, None]
    cx, cy = robot.payload.com
    r = np.stack([np.cos(phi) * cx - np.sin(phi) * cy, np.sin(phi) * cx + np.cos(phi) * cy], -1)
    turned = np.stack([-r[..., 1], r[..., 0]], axis=-1)
    return velocity[..., :2] + w * turned, acceleration[..., :2] + e * turned - w * w * r


@st.composite
def loaded_scenarios(draw: st.DrawFn) -> tuple[Robot, AnalyticMotion, np.ndarray]:
    """A random robot with a payload, a load, smoothed friction and a spring on every joint."""
    robot, analytic = draw(scenarios())
    number = st.floats(0.0, 1.0)
    l0 = robot.l0

    def joint() -> JointFriction:
        return JointFriction(
            viscous=5.0 * draw(number), coulomb=2.0 * draw(number), smoothing=0.05 + draw(number)
        )

    robot = replace(
        robot,
        payload=Payload(
            mass=2.0 * draw(number), com=(0.3 * l0 * draw(number), -0.2 * l0 * draw(number)),
            inertia=0.01 * draw(number),
        ),
        load=Load(force=(10.0 * draw(number) - 5.0, 3.0), moment=draw(number) - 0.5),
        friction=Friction(joint(), joint(), joint()),
        spring=Spring(
            SpringParameters(
                stiffness=2e3 * draw(number), rest=0.1 * l0 * (draw(number) - 0.5),
                damping=20.0 * draw(number),
            ),
            # the torsion spring of each revolute joint (on phi) and the sleeves' (on lambda32)
            SpringParameters(
                stiffness=50.0 * draw(number) + 0.5, rest=0.5 * (draw(number) - 0.5),
                damping=2.0 * draw(number), kind="revolute",
            ),
            SpringParameters(
                stiffness=1e3 * draw(number) + 1.0, rest=0.5 * l0 * draw(number),
                damping=10.0 * draw(number), kind="sleeve",
            ),
        ),
    )  # fmt: skip
    wrench = np.array(draw(st.tuples(number, number, number))) * (4.0, -4.0, 0.5)
    return robot, analytic, wrench


def element_state(robot, motion, kin, dyn) -> State:  # type: ignore[no-untyped-def]
    friction = (dyn.fric10, dyn.fric21, dyn.fric32) if robot.friction is not None else None
    return State(
        motion.pose, motion.velocity, kin.geometry.lambda10, kin.dlambda10, kin.dlambda32,
        wrench=motion.load, friction=friction, lambda32=kin.geometry.lambda32,
    )  # fmt: skip


@given(scenario=loaded_scenarios())
def test_power_of_the_elements_balances_the_kinetic_energy(
    scenario: tuple[Robot, AnalyticMotion, np.ndarray],
) -> None:
    # Σ p10 + Σ_elements (power of its forces) = d(KE)/dt, every method: gravity, payload,
    # constant load, time-varying wrench, friction of the three joints, the spring and damper
    robot, analytic, wrench = scenario
    plain = analytic.motion(np.linspace(0.0, analytic.duration, 10))
    motion = Motion(plain.t, plain.pose, plain.velocity, plain.acceleration,
                    load=np.broadcast_to(wrench, (10, 3)).copy())  # fmt: skip
    assert {e.name for e in robot.elements} >= {
        "spring.actuator", "spring.revolute", "spring.sleeve", "friction.sleeve", "load"
    }  # fmt: skip
    for method in METHODS:
        kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
        bodies = body_states(
            robot, kin.geometry.lambda10, kin.dlambda10, kin.ddlambda10,
            motion.pose, motion.velocity, motion.acceleration,
        )  # fmt: skip
        payload_state = payload_motion(robot, motion.pose, motion.velocity, motion.acceleration)
        rate, scale = kinetic_rate(robot, bodies, payload_state)
        state = element_state(robot, motion, kin, dyn)
        powers = [element.power(robot, state) for element in (*robot.elements, WRENCH)]
        total = dyn.p10.sum(axis=-1) + np.sum(powers, axis=0)
        scale = scale + np.abs(dyn.p10).sum(axis=-1) + np.abs(powers).sum(axis=0) + 1e-300
        assert np.all(np.abs(total - rate) <= 1e-12 * scale), (method, np.abs(total - rate) / scale)


@settings(max_examples=30)
@given(scenario=loaded_scenarios())
def test_input_power_is_the_derivative_of_the_energy_with_every_element(
    scenario: tuple[Robot, AnalyticMotion, np.ndarray],
) -> None:
    # Σ p10 + P_external − P_dissipated = d/dt(KE + Σ potentials): the potentials (gravity,
    # the payload's weight, ½k(λ10 − rest)²) from the elements on the independent reference
    # kinematics at shifted times, differentiated at 6th order (h = 2 ms, as above); the
    # powers of the elements without a potential at the sample times
    robot, analytic, wrench = scenario
    T = analytic.duration
    t = np.linspace(0.1 * T, 0.9 * T, 5)
    h = 2e-3
    shifted = stencil_times(t, h)
    pose, velocity, acceleration = analytic.evaluate(shifted)
    geo = ref_geometry(robot.l0, pose)
    rates = ref_rates(robot.l0, pose, velocity, acceleration)
    bodies = body_states(
        robot, geo.lambda10, rates.dlambda10, rates.ddlambda10, pose, velocity, acceleration
    )
    state = State(
        pose, velocity, geo.lambda10, rates.dlambda10, rates.dlambda32, lambda32=geo.lambda32
    )
    potentials = [element.potential(robot, state) for element in robot.elements]
    assert SPRING.potential(robot, state) is not None
    payload_state = payload_motion(robot, pose, velocity, acceleration)
    terms = [kinetic(robot, bodies, payload_state), *(p for p in potentials if p is not None)]
    rate_fd, _ = differentiate(np.sum(terms, axis=0), h, len(t))
    plain = analytic.motion(t)
    motion = Motion(plain.t, plain.pose, plain.velocity, plain.acceleration,
                    load=np.broadcast_to(wrench, (len(t), 3)).copy())  # fmt: skip
    kin, dyn = inverse_dynamics(robot, motion)
    at_t = element_state(robot, motion, kin, dyn)
    # external power (no potential, nothing dissipated: load, wrench), minus what is dissipated
    others = [
        e.power(robot, at_t) if e.potential(robot, at_t) is None else -e.dissipation(robot, at_t)
        for e in (*robot.elements, WRENCH)
    ]
    dissipated = [e.dissipation(robot, at_t) for e in robot.elements]
    assert np.all(np.sum(dissipated, axis=0) >= 0.0)
    total = dyn.p10.sum(axis=-1) + np.sum(others, axis=0)
    energy_scale = np.abs(terms).sum(axis=0).reshape(len(t), 7).max(axis=-1)
    power_scale = np.abs(dyn.p10).sum(axis=-1) + np.abs(others).sum(axis=0) + np.abs(rate_fd)
    tolerance = 1e-9 * power_scale + 100 * np.finfo(float).eps * energy_scale / h + 1e-300
    assert np.all(np.abs(total - rate_fd) <= tolerance), np.abs(total - rate_fd) / tolerance
