"""Complete inverse dynamics: paper method vs Newton–Euler, hand calculations, closed forms.

Expected numbers are worked by hand from docs/model.md (derivations beside each
test).  Conventions used in every derivation (docs/model.md):

* piston i:  f10·e + n10·n − F21 + m1·g = m1·a1,   F21 = f21y·n + f21z·e (piston on link 2);
* link 2:    F21 − n32·d⊥ + m2·g = m2·a2,           −m32 + r2 × m2(g − a2) = I2·φ̈ (about P);
* platform:  Σ n32·d⊥ + m3·g = m3·G̈,               Σ [m32 + (P − G) × n32·d⊥] = I3·φ̈ (about G).

With centres of mass at the joints (c1 = c2 = 0) these give, per leg,
``f21z = n32·(d⊥·e) + m2(λ̈10 − g·e)``, ``f21y = n32·(d⊥·n) − m2·g·n``,
``f10 = f21z + m1(λ̈10 − g·e)``, ``n10 = f21y − m1·g·n``, ``m10 = 0``,
``m32 = −I2·φ̈``, where ``d⊥·e = cos(φ + π/6)`` and ``d⊥·n = cos(φ − π/3)``
(angles: e at α, n at α + π/2, d⊥ at α + φ + π/6).  The lever of n32 about G
is ``(P − G) × d⊥ = −λ32 − Rot(α+φ)c × d⊥ = l0/(2√3) − λ32`` (the cross
product is rotation invariant: ``c × Rot(−π/3)(0, 1) = −l0/(2√3)``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from prp3 import (
    METHODS,
    InverseDynamics,
    LinkParameters,
    Motion,
    PistonParameters,
    Prp3Error,
    Robot,
    SingularPoseError,
    inverse_dynamics,
    inverse_kinematics,
    kernel_method,
    newton_euler,
)
from prp3.io.results import RESULT_COLUMNS, results_table
from prp3.model.motion import law_motion, paper_motion
from prp3.references.paper import paper_inverse_dynamics, paper_method
from strategies import (
    REF_E,
    REF_N,
    SQRT3,
    AnalyticMotion,
    gravities,
    poses,
    robots,
    scenarios,
    total_mass,
)

FORCES = ("f10", "f21y", "f21z", "n10", "n32")
MOMENTS = ("m10", "m32")
QUANTITIES = ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32")


def force_scale(robot: Robot, dyn: InverseDynamics) -> np.ndarray:
    """Per-sample force scale (N): the largest reported force plus the total weight."""
    largest = np.max([np.abs(getattr(dyn, name)).max(axis=-1) for name in FORCES], axis=0)
    return np.asarray(largest + total_mass(robot) * math.hypot(*robot.gravity))


# ------------------------------------------------------------- paper vs Newton–Euler
@given(scenario=scenarios())
def test_kernel_method_agrees_with_newton_euler(scenario: tuple[Robot, AnalyticMotion]) -> None:
    # Random l0, masses, inertias, centre-of-mass offsets of pistons and links, any
    # gravity (zero included) and smooth motions with |sin(φ − π/3)| ≥ 0.27.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 12))
    kin = inverse_kinematics(robot, motion)
    paper, reference = kernel_method(robot, kin), newton_euler(robot, kin)
    assert (paper.method, reference.method) == ("fast", "newton-euler")
    forces = force_scale(robot, reference)[:, None]
    lever = robot.l0 + np.abs(kin.geometry.lever).max(axis=(-1, -2))[:, None]
    power = forces * np.abs(kin.dlambda10).max(axis=-1, keepdims=True)
    for name in QUANTITIES:
        scale = forces * lever if name in MOMENTS else power if name == "p10" else forces
        difference = np.abs(getattr(paper, name) - getattr(reference, name))
        # The issue asks for 1e-9; measured ≤ 1e-15 over 300 random cases, so 1e-12 is asserted.
        assert np.all(difference <= 1e-12 * scale + 1e-300), (
            name,
            float((difference / scale).max()),
        )


@given(scenario=scenarios())
def test_inverse_dynamics_dispatches_to_both_methods(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 3))
    kin = inverse_kinematics(robot, motion)
    paper_kin, _ = paper_method(robot, motion)  # the paper's own kinematics (eqs. 10–18)
    for method, solver in (
        ("fast", kernel_method),
        ("paper", lambda r, k: paper_inverse_dynamics(r, k.motion)),
        ("newton-euler", newton_euler),
    ):
        kin_out, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
        expected = solver(robot, kin)
        assert dyn.method == method
        own = paper_kin if method == "paper" else kin
        np.testing.assert_array_equal(kin_out.dlambda10, own.dlambda10)
        np.testing.assert_array_equal(kin_out.geometry.lambda10, own.geometry.lambda10)
        for name in QUANTITIES:
            np.testing.assert_array_equal(getattr(dyn, name), getattr(expected, name))
    assert METHODS == ("fast", "paper", "newton-euler")


# ------------------------------------------------------------- hand calculations
@pytest.mark.parametrize("method", METHODS)
def test_static_central_configuration_by_hand(method: str) -> None:
    # Default robot at rest at x = y = φ = 0 (λ32 = 0, c2 = 0 ⇒ m32 = −I2·φ̈ = 0).
    # Platform moments about G: (P_i − G) × d⊥_i = l0/(2√3) for every leg ⇒ Σ n32 = 0.
    # Platform forces, d⊥ = (0, 1), (−√3/2, −1/2), (√3/2, −1/2), m3·g = 29.43 N up:
    #   n32 = (2/3, −1/3, −1/3)·m3·g = (19.62, −9.81, −9.81) N.
    # Link: F21 = n32·d⊥ + (0, m2·g), m2·g = 7.3575 N:
    #   A: (0, 26.9775)    B: (8.49571, 12.2625)    C: (−8.49571, 12.2625)
    #   f21y = F21·n, f21z = F21·e with n = (−√3/2, 1/2), (0, −1), (√3/2, 1/2),
    #   e = (1/2, √3/2), (−1, 0), (1/2, −√3/2).
    # Piston: f10·e + n10·n = F21 + (0, m1·g), m1·g = 9.81 N:
    #   A: (0, 36.7875) ⇒ f10 = 36.7875·√3/2 = 31.8589,  n10 = 18.39375
    #   B: (8.49571, 22.0725) ⇒ f10 = −8.49571,           n10 = −22.0725
    #   C: (−8.49571, 22.0725) ⇒ f10 = −4.24785 − 19.11535 = −23.3632, n10 = 3.67875
    #   (and f21z = F21·e: A 23.3632, B −8.49571, C −4.24785 − 10.61966 = −14.8675)
    g, s = 9.81, SQRT3
    kin, dyn = inverse_dynamics(Robot(), Motion.at_rest([0.0, 0.0, 0.0]), method=method)  # type: ignore[arg-type]
    n32 = np.array([19.62, -9.81, -9.81])
    F21 = np.array([[0.0, 26.9775], [9.81 * s / 2, 12.2625], [-9.81 * s / 2, 12.2625]])
    expected = {
        "n32": n32,
        "m32": np.zeros(3),
        "f21y": np.array([26.9775 / 2, -12.2625, -9.81 * 3 / 4 + 12.2625 / 2]),
        "f21z": np.array([26.9775 * s / 2, -9.81 * s / 2, -9.81 * s / 4 - 12.2625 * s / 2]),
        "f10": np.array([36.7875 * s / 2, -9.81 * s / 2, -9.81 * s / 4 - 22.0725 * s / 2]),
        "n10": np.array([18.39375, -22.0725, -9.81 * 3 / 4 + 22.0725 / 2]),
        "m10": np.zeros(3),
        "p10": np.zeros(3),
    }
    for name, value in expected.items():
        np.testing.assert_allclose(getattr(dyn, name), value, rtol=0, atol=1e-12, err_msg=name)
    np.testing.assert_allclose(
        dyn.f21y[:, None] * REF_N + dyn.f21z[:, None] * REF_E, F21, atol=1e-12
    )
    # literal values (rounded) as printed in the derivation
    np.testing.assert_allclose(dyn.f10, [31.8589, -8.4957, -23.3632], atol=5e-5)
    np.testing.assert_allclose(dyn.f21z, [23.3632, -8.4957, -14.8675], atol=5e-5)
    assert kin.dlambda10.shape == (3,)
    # the base carries the whole weight: Σ (f10·e + n10·n) = (0, 8.25·9.81)
    support = (dyn.f10[:, None] * REF_E + dyn.n10[:, None] * REF_N).sum(axis=0)
    np.testing.assert_allclose(support, [0.0, 8.25 * g], rtol=0, atol=1e-12)


@given(robot=robots(gravity=st.just((0.0, 0.0))), pose=poses())
def test_at_rest_without_gravity_no_force_is_needed(robot: Robot, pose: np.ndarray) -> None:
    pose = pose * np.array([robot.l0 / 0.3, robot.l0 / 0.3, 1.0])
    for method in METHODS:
        _, dyn = inverse_dynamics(robot, Motion.at_rest(pose), method=method)  # type: ignore[arg-type]
        for name in QUANTITIES:
            np.testing.assert_allclose(getattr(dyn, name), 0.0, rtol=0, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("method", METHODS)
def test_accelerating_from_rest_at_the_centre_by_hand(method: str) -> None:
    # g = 0, default masses (m1, m2, m3) = (1, 0.75, 3), at rest at x = y = φ = 0 with
    # G̈ = (0, 2) m/s², φ̈ = 0: a translation.  Joint accelerations (test_geometry's
    # linear map): λ̈10 = (2, −1, −1)·2/√3, λ̈32 = (−1, 2, −1)·2/√3.
    # Platform: Σ n32 = 0 (equal levers) and Σ n32·d⊥ = m3·G̈ ⇒ n32 = (2/3)·m3·G̈·d⊥
    #   = (4, −2, −2) N  (Σ d⊥d⊥ᵀ = (3/2)·1, Σ d⊥ = 0).
    # Link (translates with P): f21z = (√3/2)·n32 + m2·λ̈10, f21y = n32/2:
    #   A: f21z = 2√3 + 0.75·4/√3 = 3√3,  f21y = 2
    #   B, C: f21z = −√3 − 0.75·2/√3 = −3√3/2,  f21y = −1
    # Piston: f10 = f21z + m1·λ̈10, n10 = f21y:
    #   A: 3√3 + 4/√3 = 13/√3;  B, C: −3√3/2 − 2/√3 = −13/(2√3).
    robot = Robot(gravity=(0.0, 0.0))
    motion = Motion(
        t=np.array(0.0),
        pose=np.zeros(3),
        velocity=np.zeros(3),
        acceleration=np.array([0.0, 2.0, 0.0]),
    )
    kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
    s = SQRT3
    np.testing.assert_allclose(kin.ddlambda10, [4 / s, -2 / s, -2 / s], atol=1e-15)
    np.testing.assert_allclose(kin.ddlambda32, [-2 / s, 4 / s, -2 / s], atol=1e-15)
    np.testing.assert_allclose(dyn.n32, [4.0, -2.0, -2.0], atol=1e-13)
    np.testing.assert_allclose(dyn.f21z, [3 * s, -1.5 * s, -1.5 * s], atol=1e-13)
    np.testing.assert_allclose(dyn.f21y, [2.0, -1.0, -1.0], atol=1e-13)
    np.testing.assert_allclose(dyn.f10, [13 / s, -6.5 / s, -6.5 / s], atol=1e-13)
    np.testing.assert_allclose(dyn.n10, [2.0, -1.0, -1.0], atol=1e-13)
    np.testing.assert_allclose(np.c_[dyn.m10, dyn.m32, dyn.p10], 0.0, atol=1e-13)


@pytest.mark.parametrize("method", METHODS)
def test_accelerating_sideways_from_rest_at_the_centre_by_hand(method: str) -> None:
    # Same with G̈ = (2, 0): λ̈10 = (0, −2, 2) (test_geometry: λ10 = (0, −x, x) at y = 0),
    # n32 = (2/3)·3·2·d⊥_x = (0, −2√3, 2√3) N;
    # f21z = (√3/2)·n32 + 0.75·λ̈10 = (0, −4.5, 4.5), f21y = n32/2 = (0, −√3, √3),
    # f10 = f21z + λ̈10 = (0, −6.5, 6.5), n10 = f21y.
    robot = Robot(gravity=(0.0, 0.0))
    motion = Motion(
        t=np.array(0.0),
        pose=np.zeros(3),
        velocity=np.zeros(3),
        acceleration=np.array([2.0, 0.0, 0.0]),
    )
    kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
    s = SQRT3
    np.testing.assert_allclose(kin.ddlambda10, [0.0, -2.0, 2.0], atol=1e-15)
    np.testing.assert_allclose(dyn.n32, [0.0, -2 * s, 2 * s], atol=1e-13)
    np.testing.assert_allclose(dyn.f21z, [0.0, -4.5, 4.5], atol=1e-13)
    np.testing.assert_allclose(dyn.f21y, [0.0, -s, s], atol=1e-13)
    np.testing.assert_allclose(dyn.f10, [0.0, -6.5, 6.5], atol=1e-13)
    np.testing.assert_allclose(dyn.n10, [0.0, -s, s], atol=1e-13)


def _legs_closed_form(
    robot: Robot, phi: np.ndarray, n32: np.ndarray, ddlambda10: np.ndarray
) -> dict[str, np.ndarray]:
    """Per-leg forces with c1 = c2 = 0 given n32 (module docstring)."""
    g = np.asarray(robot.gravity)
    m1, m2 = robot.piston.mass, robot.link.mass
    g_e, g_n = REF_E @ g, REF_N @ g  # (3,)
    f21z = n32 * np.cos(phi + math.pi / 6)[:, None] + m2 * (ddlambda10 - g_e)
    f21y = n32 * np.cos(phi - math.pi / 3)[:, None] - m2 * g_n
    return {
        "f21z": f21z,
        "f21y": f21y,
        "f10": f21z + m1 * (ddlambda10 - g_e),
        "n10": f21y - m1 * g_n,
        "m10": np.zeros_like(n32),
    }


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("gravity", [(0.0, -9.81), (0.0, 0.0), (0.0, 1.62)])
def test_vertical_paper_motion_closed_form(method: str, gravity: tuple[float, float]) -> None:
    # x = φ = 0, y(t) = 0.025(1 − cos(πt/3)), g = (0, g_y); default masses, c1 = c2 = 0.
    # Kinematics (test_kinematics): λ10 = (2, −1, −1)y/√3, λ32 = (−1, 2, −1)y/√3, rates alike.
    # Platform with Δ = ÿ − g_y, levers L_i = l0/(2√3) − λ32_i:
    #   x: (√3/2)(n32_C − n32_B) = 0 ⇒ n32_B = n32_C =: ν;  y: n32_A − ν = m3·Δ;
    #   moments (φ̈ = 0, m32 = 0): n32_A·L_A + ν(L_B + L_C) = 0, L_A = (l0 + 2y)/(2√3),
    #   L_B + L_C = (2l0 − 2y)/(2√3)  ⇒  ν = −m3·Δ·(l0 + 2y)/(3l0),  n32_A = m3·Δ·(2l0 − 2y)/(3l0).
    # Legs: the closed forms of the module docstring at φ = 0.
    robot = Robot(gravity=gravity)
    motion = paper_motion("vertical", samples=301)
    kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
    l0, m3, w = robot.l0, robot.platform.mass, math.pi / 3
    t = motion.t
    y = 0.025 * (1 - np.cos(w * t))
    yd = 0.025 * w * np.sin(w * t)
    ydd = 0.025 * w * w * np.cos(w * t)
    delta = ydd - gravity[1]
    nu = -m3 * delta * (l0 + 2 * y) / (3 * l0)
    n32 = np.stack([m3 * delta * (2 * l0 - 2 * y) / (3 * l0), nu, nu], axis=-1)
    ddlambda10 = ydd[:, None] * np.array([2.0, -1.0, -1.0]) / SQRT3
    dlambda10 = yd[:, None] * np.array([2.0, -1.0, -1.0]) / SQRT3
    expected = _legs_closed_form(robot, motion.pose[:, 2], n32, ddlambda10)
    expected |= {"n32": n32, "m32": np.zeros_like(n32), "p10": expected["f10"] * dlambda10}
    for name, value in expected.items():
        np.testing.assert_allclose(getattr(dyn, name), value, rtol=0, atol=1e-12, err_msg=name)
    assert kin.dlambda10.shape == (301, 3)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("gravity", [(0.0, -9.81), (0.0, 0.0), (3.0, -4.0)])
def test_rotation_paper_motion_closed_form(method: str, gravity: tuple[float, float]) -> None:
    # G = O, φ(t) = (π/12)(1 − cos(πt/3)); c1 = c2 = 0 so m32 = −I2·φ̈.
    # λ32 is the same for the three legs (test_geometry), so are the levers
    # L = l0/(2√3) − λ32.  Platform: Σ n32·d⊥ = −m3·g (G̈ = 0) and
    # Σ (m32 + n32·L) = I3·φ̈ ⇒ Σ n32 = (I3 + 3·I2)·φ̈/L, hence (Σ d⊥ = 0, Σ d⊥d⊥ᵀ = (3/2)·1)
    #   n32_i = (I3 + 3·I2)·φ̈/(3L) − (2/3)·m3·g·d⊥_i.
    # λ̈10 = (l0/4)·sec²(u/2)·(φ̈ + tan(u/2)·φ̇²), u = φ − π/3 (test_kinematics).
    robot = Robot(gravity=gravity)
    motion = paper_motion("rotation", samples=301)
    kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
    l0, m3, w, star = robot.l0, robot.platform.mass, math.pi / 3, math.pi / 12
    I2, I3 = 6.25e-4, 3.0 * (SQRT3 * l0) ** 2 / 12  # docs/model.md defaults (0.0675 kg·m²)
    t = motion.t
    phi = star * (1 - np.cos(w * t))
    phid = star * w * np.sin(w * t)
    phidd = star * w * w * np.cos(w * t)
    half = (phi - math.pi / 3) / 2
    lambda32 = 0.5 * l0 * (np.tan(half) + 1 / SQRT3)
    dlambda10 = 0.25 * l0 * phid / np.cos(half) ** 2
    ddlambda10 = 0.25 * l0 * (phidd + np.tan(half) * phid**2) / np.cos(half) ** 2
    lever = l0 / (2 * SQRT3) - lambda32
    d_perp = np.stack(  # d⊥_i at angle α_i + φ + π/6
        [
            np.cos(phi[:, None] + np.array([math.pi / 3, math.pi, -math.pi / 3]) + math.pi / 6),
            np.sin(phi[:, None] + np.array([math.pi / 3, math.pi, -math.pi / 3]) + math.pi / 6),
        ],
        axis=-1,
    )
    n32 = ((I3 + 3 * I2) * phidd / (3 * lever))[:, None] - (2 / 3) * m3 * (
        d_perp @ np.array(gravity)
    )
    per_leg = np.ones(3)
    expected = _legs_closed_form(robot, phi, n32, ddlambda10[:, None] * per_leg)
    expected |= {
        "n32": n32,
        "m32": -I2 * phidd[:, None] * per_leg,
        "p10": expected["f10"] * dlambda10[:, None],
    }
    for name, value in expected.items():
        np.testing.assert_allclose(getattr(dyn, name), value, rtol=0, atol=1e-12, err_msg=name)
    assert robot.platform_inertia == pytest.approx(0.0675, rel=1e-15)
    assert kin.geometry.lambda32.shape == (301, 3)


# ------------------------------------------------------------- statements of docs/model.md
@given(scenario=scenarios(offsets=False))
def test_reaction_moments_with_centres_of_mass_at_the_joints(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    # docs/model.md: m10 = 0 when c1 = (0, 0); m32 = −I2·φ̈ when c2 = (0, 0); p10 = f10·λ̇10.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 6))
    for method in METHODS:
        kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
        scale = force_scale(robot, dyn)[:, None] * (robot.l0 + np.abs(kin.geometry.lever).max())
        np.testing.assert_allclose(dyn.m10, 0.0, rtol=0, atol=1e-12 * scale.max())
        expected = -robot.link.inertia * motion.acceleration[:, 2:3] * np.ones(3)
        np.testing.assert_allclose(dyn.m32, expected, rtol=1e-12, atol=1e-12 * scale.max())
        # each method's own λ̇10 (Newton–Euler solves the closure numerically)
        power = force_scale(robot, dyn)[:, None] * np.abs(kin.dlambda10).max()
        assert np.all(np.abs(dyn.p10 - dyn.f10 * kin.dlambda10) <= 1e-13 * power + 1e-300)


@given(robot=robots(gravity=gravities(allow_zero=False)))
def test_static_support_carries_the_weight(robot: Robot) -> None:
    # At rest, the base (actuators and guides) carries the weight of the 7 bodies:
    # Σ (f10·e + n10·n) = −M·g.  Moments about O: Σ [m10 + P × (f10·e + n10·n)]
    # = −Σ_k C_k × m_k·g (f10 acts through P, the guide reaction is n10 at P plus m10).
    pose = np.array([0.02, -0.03, 0.25]) * np.array([robot.l0 / 0.3, robot.l0 / 0.3, 1.0])
    g = np.asarray(robot.gravity)
    for method in METHODS:
        kin, dyn = inverse_dynamics(robot, Motion.at_rest(pose), method=method)  # type: ignore[arg-type]
        support = dyn.f10[:, None] * REF_E + dyn.n10[:, None] * REF_N
        np.testing.assert_allclose(
            support.sum(axis=0),
            -total_mass(robot) * g,
            rtol=1e-12,
            atol=1e-12 * total_mass(robot) * np.abs(g).max(),
        )
        P = kin.geometry.joint
        moment = (dyn.m10 + P[:, 0] * support[:, 1] - P[:, 1] * support[:, 0]).sum()
        weights = (
            robot.piston.mass * kin.piston_com.sum(axis=0)
            + robot.link.mass * kin.link_com.sum(axis=0)
            + robot.platform.mass * pose[:2]
        )
        expected = -(weights[0] * g[1] - weights[1] * g[0])
        scale = total_mass(robot) * np.abs(g).max() * (robot.l0 + np.abs(P).max())
        assert float(moment) == pytest.approx(expected, abs=1e-12 * scale)


# ------------------------------------------------------------- rank and refusals
@pytest.mark.parametrize("method", METHODS)
def test_output_rank_follows_input_rank(method: str) -> None:
    robot = Robot(piston=PistonParameters(com=(0.01, 0.02)), link=LinkParameters(com=(0.02, -0.01)))
    batch = law_motion([0.01, 0.02, 0.3], samples=5, duration=1.5)
    _, many = inverse_dynamics(robot, batch, method=method)  # type: ignore[arg-type]
    _, single = inverse_dynamics(robot, batch[3], method=method)  # type: ignore[arg-type]
    _, one = inverse_dynamics(robot, batch[3:4], method=method)  # type: ignore[arg-type]
    for name in QUANTITIES:
        assert getattr(single, name).shape == (3,), name
        assert getattr(one, name).shape == (1, 3), name
        assert getattr(many, name).shape == (5, 3), name
        np.testing.assert_allclose(
            getattr(single, name), getattr(many, name)[3], rtol=1e-14, atol=1e-14, err_msg=name
        )
        np.testing.assert_allclose(
            getattr(one, name)[0], getattr(many, name)[3], rtol=1e-14, atol=1e-14, err_msg=name
        )


def test_results_table_follows_the_data_contract() -> None:
    # docs/model.md: t, x, y, phi, then for each leg A, B, C (all of A's first) 14 columns.
    per_leg = (
        "lambda10 dlambda10 ddlambda10 lambda32 dlambda32 ddlambda32 "
        "f10 p10 f21y f21z n10 m10 n32 m32"
    ).split()
    columns = ["t", "x", "y", "phi"] + [f"{q}_{leg}" for leg in "ABC" for q in per_leg]
    assert list(RESULT_COLUMNS) == columns
    motion = paper_motion("rotation", samples=7)
    kin, dyn = inverse_dynamics(Robot(), motion)
    table = results_table(kin, dyn)
    assert list(table) == columns
    assert all(table[name].shape == (7,) for name in columns)
    np.testing.assert_array_equal(table["phi"], motion.pose[:, 2])
    np.testing.assert_array_equal(table["t"], motion.t)
    np.testing.assert_array_equal(table["f10_C"], dyn.f10[:, 2])
    np.testing.assert_array_equal(table["ddlambda32_B"], kin.ddlambda32[:, 1])
    np.testing.assert_array_equal(table["m32_A"], dyn.m32[:, 0])
    single = results_table(*inverse_dynamics(Robot(), motion[2]))
    assert all(single[name].shape == () for name in columns)
    assert float(single["n32_B"]) == float(table["n32_B"][2])


@pytest.mark.parametrize("method", ["Paper", "newton_euler", "", "lagrange"])
def test_unknown_method_is_refused(method: str) -> None:
    with pytest.raises(Prp3Error) as info:
        inverse_dynamics(Robot(), paper_motion("vertical", samples=3), method=method)  # type: ignore[arg-type]
    assert repr(method) in str(info.value)
    assert all(repr(name) in str(info.value) for name in METHODS)


@pytest.mark.parametrize("method", METHODS)
def test_singular_motion_is_refused(method: str) -> None:
    motion = law_motion([0.0, 0.0, math.pi / 6], samples=3, duration=3.0)  # ends at φ = π/3
    with pytest.raises(SingularPoseError, match=r"sample 2: singular pose .*phi=1\.04719"):
        inverse_dynamics(Robot(), motion, method=method)  # type: ignore[arg-type]


@pytest.mark.parametrize("chunk", [1, 7, 64])
def test_newton_euler_in_chunks_equals_the_kernel_method(
    chunk: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The solver bounds its memory by solving in chunks; the chunk edges change nothing."""
    import prp3.references.newton_euler

    monkeypatch.setattr(prp3.references.newton_euler, "NEWTON_EULER_CHUNK", chunk)
    robot = Robot(piston=PistonParameters(com=(0.02, -0.01)), link=LinkParameters(com=(0.03, 0.01)))
    kin = inverse_kinematics(robot, law_motion([0.01, 0.02, 0.2], samples=20))
    expected, got = kernel_method(robot, kin), newton_euler(robot, kin)
    for name in ("f10", "f21y", "f21z", "n10", "m10", "n32", "m32"):
        scale = np.abs(getattr(expected, name)).max() + 1.0
        assert np.abs(getattr(got, name) - getattr(expected, name)).max() < 1e-12 * scale, name
