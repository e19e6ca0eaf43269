"""Symmetries of the model: 3-fold rotation, the paper's motions, time reversal, scaling.

Expected relations are derived here from docs/model.md; each test compares the core
with itself on transformed inputs (metamorphic tests), so they hold whatever
the numbers are and catch leg mix-ups, sign slips and missing terms.

Why the 120° rotation about O permutes the legs A → B → C → A at the same φ:
``α_B = α_A + 2π/3``, ``α_C = α_B + 2π/3``, ``α_A = α_C + 2π/3 − 2π``, and the
base vertices follow (``B0 = R·A0``, ``C0 = R·B0`` with ``R = Rot(2π/3)``).  So
``e``, ``n``, ``d(φ)``, ``d⊥(φ)`` and ``Rot(α + φ)·c`` of leg i+1 are those of
leg i turned by R *at the same φ* (``d_i`` depends on ``α_i + φ``); the closure
of leg i+1 at ``R·G`` is R times the closure of leg i at ``G``.  The platform,
an equilateral plate, turned by 120° about O is the same plate at ``R·G``
with the same φ (a 120° turn maps the triangle onto itself) and the same
``I3``.  Turning the motion (``G, Ġ, G̈`` by R, φ unchanged) and gravity by R
therefore turns every body's equations by R: every scalar of the results
(displacements, components along the leg's own axes, moments about z0) moves
from leg i to leg i+1 unchanged.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from prp3 import METHODS, Motion, PistonParameters, Robot, inverse_dynamics
from prp3.io.results import PER_LEG_COLUMNS, results_table
from prp3.model.motion import paper_motion
from strategies import (
    REF_E,
    REF_N,
    AnalyticMotion,
    analytic_motions,
    robots,
    rotate,
    scenarios,
)

LEGS = "ABC"
KINEMATIC = ("lambda10", "dlambda10", "ddlambda10", "lambda32", "dlambda32", "ddlambda32")
DYNAMIC = ("f10", "f21y", "f21z", "n10", "m10", "n32", "m32")


def table_of(robot: Robot, motion: Motion, method: str = "fast") -> dict[str, np.ndarray]:
    kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
    return dict(results_table(kin, dyn))


def scales(table: dict[str, np.ndarray], l0: float) -> dict[str, float]:
    """Comparison scale of each per-leg quantity: its largest value over the legs
    (displacements: plus ``l0``; forces: the largest force; moments: plus force·l0)."""
    out = {}
    for quantity in PER_LEG_COLUMNS:
        values = np.concatenate([np.ravel(table[f"{quantity}_{leg}"]) for leg in LEGS])
        out[quantity] = float(np.abs(values).max())
    out["lambda10"] += l0
    out["lambda32"] += l0
    force = max(out[q] for q in ("f10", "f21y", "f21z", "n10", "n32"))
    for q in ("f10", "f21y", "f21z", "n10", "n32"):
        out[q] = force
    for q in ("m10", "m32"):
        out[q] = max(out[q], force * l0)
    return out


def rotated(motion: Motion, angle: float) -> Motion:
    """The motion turned by ``angle`` about O: G, Ġ, G̈ rotated, φ and its rates unchanged."""

    def turn(array: np.ndarray) -> np.ndarray:
        return np.concatenate([rotate(angle, array[..., :2]), array[..., 2:]], axis=-1)

    return Motion(
        t=motion.t,
        pose=turn(motion.pose),
        velocity=turn(motion.velocity),
        acceleration=turn(motion.acceleration),
    )


@pytest.mark.parametrize("turns", [1, 2])
@given(scenario=scenarios())
def test_rotation_by_120_degrees_permutes_the_legs(
    turns: int, scenario: tuple[Robot, AnalyticMotion]
) -> None:
    robot, analytic = scenario
    angle = turns * 2 * math.pi / 3
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 8))
    gravity = rotate(angle, np.array(robot.gravity))
    turned_robot = dataclasses.replace(robot, gravity=(float(gravity[0]), float(gravity[1])))
    for method in METHODS:
        before = table_of(robot, motion, method)
        after = table_of(turned_robot, rotated(motion, angle), method)
        np.testing.assert_array_equal(after["phi"], before["phi"])
        np.testing.assert_array_equal(after["t"], before["t"])
        tolerance = scales(before, robot.l0)
        for leg in range(3):
            moved = LEGS[(leg + turns) % 3]
            for quantity in PER_LEG_COLUMNS:
                scale = tolerance[quantity]
                if quantity == "p10":
                    scale = tolerance["f10"] * tolerance["dlambda10"]
                np.testing.assert_allclose(
                    after[f"{quantity}_{moved}"],
                    before[f"{quantity}_{LEGS[leg]}"],
                    rtol=0,
                    atol=1e-12 * scale + 1e-300,
                    err_msg=f"{method}: {quantity}_{LEGS[leg]} -> {moved}",
                )


@given(robot=robots(gravity=st.just((0.0, 0.0))), data=st.data())
def test_rotation_about_the_centre_without_gravity_is_the_same_for_every_leg(
    robot: Robot, data: st.DataObject
) -> None:
    # G = O is fixed by the 120° turn and g = 0: the three legs are interchangeable.
    analytic = data.draw(analytic_motions(robot.l0, translation=False))
    analytic = dataclasses.replace(analytic, centre=np.array([0.0, 0.0, analytic.centre[2]]))
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 8))
    table = table_of(robot, motion)
    tolerance = scales(table, robot.l0)
    tolerance["p10"] = tolerance["f10"] * tolerance["dlambda10"]
    for quantity in PER_LEG_COLUMNS:
        for leg in "BC":
            np.testing.assert_allclose(
                table[f"{quantity}_{leg}"],
                table[f"{quantity}_A"],
                rtol=0,
                atol=1e-12 * tolerance[quantity] + 1e-300,
                err_msg=quantity,
            )


@pytest.mark.parametrize("method", METHODS)
def test_rotation_paper_motion_without_gravity_is_the_same_for_every_leg(method: str) -> None:
    table = table_of(Robot(gravity=(0.0, 0.0)), paper_motion("rotation"), method)
    for quantity in PER_LEG_COLUMNS:
        for leg in "BC":
            np.testing.assert_allclose(
                table[f"{quantity}_{leg}"], table[f"{quantity}_A"], rtol=1e-12, atol=1e-15
            )
    assert np.abs(table["f10_A"]).max() > 1e-3  # a genuine, non-trivial motion


# ------------------------------------------------------------------ vertical motions
def _vertical(analytic: AnalyticMotion) -> AnalyticMotion:
    """The same y(t), with x ≡ 0 and φ ≡ 0."""
    return dataclasses.replace(
        analytic,
        centre=np.array([0.0, analytic.centre[1], 0.0]),
        span=np.array([0.0, analytic.span[1], 0.0]),
    )


@given(robot=robots(gravity=st.just((0.0, 0.0))), data=st.data())
def test_vertical_translation_without_gravity_legs_b_and_c_agree(
    robot: Robot, data: st.DataObject
) -> None:
    # x = φ = 0, g = 0 (any masses, inertias and centre-of-mass offsets).
    # Kinematics (test_geometry): λ10 = (2, −1, −1)·y/√3 ⇒ legs B and C move alike.
    # Platform x-balance: (√3/2)(n32_C − n32_B) = m3·(ẍ − g_x) = 0 ⇒ n32_B = n32_C.
    # At φ = 0 every leg has d⊥·e = √3/2, d⊥·n = 1/2, and e × d, e × d⊥ (hence the
    # moments of r1, r2 about P) are the same for all legs; with equal λ̈10 and n32
    # the balances of links and pistons B and C are identical: every column agrees.
    # (This is not a mirror symmetry: the robot is chiral, P_i sits one third of the
    # way along edge i; λ32_B ≠ λ32_C and the legs differ under gravity, below.)
    analytic = _vertical(data.draw(analytic_motions(robot.l0)))
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 8))
    for method in METHODS:
        table = table_of(robot, motion, method)
        tolerance = scales(table, robot.l0)
        tolerance["p10"] = tolerance["f10"] * tolerance["dlambda10"]
        for quantity in PER_LEG_COLUMNS:
            if quantity.endswith("lambda32"):
                continue  # λ32_B = 2y/√3, λ32_C = −y/√3
            np.testing.assert_allclose(
                table[f"{quantity}_C"],
                table[f"{quantity}_B"],
                rtol=0,
                atol=1e-12 * tolerance[quantity] + 1e-300,
                err_msg=f"{method}: {quantity}",
            )
        for prefix in ("", "d", "dd"):
            np.testing.assert_allclose(
                table[f"{prefix}lambda32_C"], table[f"{prefix}lambda32_A"], rtol=0, atol=1e-15
            )


@pytest.mark.parametrize("method", METHODS)
def test_vertical_paper_motion_legs_b_and_c_differ_by_gravity_only(method: str) -> None:
    # With g = (0, −9.81) the same balances give B − C differences due to the weights
    # of piston and link resolved on different axes (c1 = c2 = 0, n32_B = n32_C):
    #   f21z_B − f21z_C = −m2·g·(e_B − e_C),   f10_B − f10_C = −(m1 + m2)·g·(e_B − e_C),
    #   f21y_B − f21y_C = −m2·g·(n_B − n_C),   n10_B − n10_C = −(m1 + m2)·g·(n_B − n_C).
    # g·(e_B − e_C) = −9.81·(0 + √3/2), g·(n_B − n_C) = −9.81·(−1 − 1/2):
    #   f10_B − f10_C = 1.75·9.81·√3/2 = 14.8675 N,  n10_B − n10_C = −1.75·9.81·1.5 = −25.75 N.
    robot = Robot()
    table = table_of(robot, paper_motion("vertical"), method)
    g = np.array(robot.gravity)
    m1, m2 = robot.piston.mass, robot.link.mass
    de, dn = (REF_E[1] - REF_E[2]) @ g, (REF_N[1] - REF_N[2]) @ g
    expected = {
        "n32": 0.0,
        "f21z": -m2 * de,
        "f10": -(m1 + m2) * de,
        "f21y": -m2 * dn,
        "n10": -(m1 + m2) * dn,
        "m10": 0.0,
        "m32": 0.0,
    }
    for quantity, difference in expected.items():
        np.testing.assert_allclose(
            table[f"{quantity}_B"] - table[f"{quantity}_C"], difference, rtol=0, atol=1e-12
        )
    assert float(-(m1 + m2) * de) == pytest.approx(1.75 * 9.81 * math.sqrt(3) / 2, rel=1e-14)
    assert float(-(m1 + m2) * dn) == pytest.approx(-1.75 * 9.81 * 1.5, rel=1e-14)
    np.testing.assert_allclose(table["lambda10_B"], table["lambda10_C"], rtol=0, atol=1e-15)


# ------------------------------------------------------------------ other invariances
@given(scenario=scenarios())
def test_time_reversal(scenario: tuple[Robot, AnalyticMotion]) -> None:
    # Running the motion backwards, q(t) → q(−t): velocities change sign, accelerations
    # do not; the velocity terms of the dynamics (φ̇², λ̇32·φ̇) are quadratic, so every
    # force and moment is unchanged, every rate and input power changes sign.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 7))
    backwards = Motion(
        t=-motion.t[::-1],
        pose=motion.pose[::-1],
        velocity=-motion.velocity[::-1],
        acceleration=motion.acceleration[::-1],
    )
    forward, reverse = table_of(robot, motion), table_of(robot, backwards)
    tolerance = scales(forward, robot.l0)
    for leg in LEGS:
        for quantity in PER_LEG_COLUMNS:
            sign = -1.0 if quantity in ("dlambda10", "dlambda32", "p10") else 1.0
            scale = tolerance["f10"] * tolerance["dlambda10"] if quantity == "p10" else None
            np.testing.assert_allclose(
                sign * reverse[f"{quantity}_{leg}"][::-1],
                forward[f"{quantity}_{leg}"],
                rtol=0,
                atol=1e-12 * (scale if scale is not None else tolerance[quantity]) + 1e-300,
                err_msg=quantity,
            )


@given(scenario=scenarios(), factor=st.floats(0.1, 10.0))
def test_forces_scale_with_the_masses(
    scenario: tuple[Robot, AnalyticMotion], factor: float
) -> None:
    # Every equation is linear and homogeneous in (masses, inertias, reactions).
    robot, analytic = scenario
    heavier = dataclasses.replace(
        robot,
        piston=dataclasses.replace(
            robot.piston, mass=factor * robot.piston.mass, inertia=factor * robot.piston.inertia
        ),
        link=dataclasses.replace(
            robot.link, mass=factor * robot.link.mass, inertia=factor * robot.link.inertia
        ),
        platform=dataclasses.replace(
            robot.platform,
            mass=factor * robot.platform.mass,
            inertia=None if robot.platform.inertia is None else factor * robot.platform.inertia,
        ),
    )
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 6))
    light, heavy = table_of(robot, motion), table_of(heavier, motion)
    tolerance = scales(light, robot.l0)
    for leg in LEGS:
        for quantity in KINEMATIC:
            np.testing.assert_array_equal(heavy[f"{quantity}_{leg}"], light[f"{quantity}_{leg}"])
        for quantity in DYNAMIC:
            np.testing.assert_allclose(
                heavy[f"{quantity}_{leg}"],
                factor * light[f"{quantity}_{leg}"],
                rtol=0,
                atol=1e-12 * factor * tolerance[quantity] + 1e-300,
                err_msg=quantity,
            )


@given(
    scenario=scenarios(gravity=st.just((0.0, 0.0))),
    g1=st.tuples(st.floats(-20, 20), st.floats(-20, 20)),
    g2=st.tuples(st.floats(-20, 20), st.floats(-20, 20)),
)
def test_reactions_are_affine_in_gravity(
    scenario: tuple[Robot, AnalyticMotion],
    g1: tuple[float, float],
    g2: tuple[float, float],
) -> None:
    # Gravity enters every balance linearly: F(g1 + g2) = F(g1) + F(g2) − F(0).
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 6))
    both = (g1[0] + g2[0], g1[1] + g2[1])
    tables = [
        table_of(dataclasses.replace(robot, gravity=g), motion) for g in (g1, g2, both, (0.0, 0.0))
    ]
    tolerance = scales(tables[2], robot.l0)
    for other in tables[:2]:
        for quantity, value in scales(other, robot.l0).items():
            tolerance[quantity] = max(tolerance[quantity], value)
    for leg in LEGS:
        for quantity in DYNAMIC:
            first, second, total, none = (table[f"{quantity}_{leg}"] for table in tables)
            np.testing.assert_allclose(
                total,
                first + second - none,
                rtol=0,
                atol=1e-12 * tolerance[quantity] + 1e-300,
                err_msg=quantity,
            )


def test_offset_centres_of_mass_break_no_symmetry_of_the_equations() -> None:
    # Sanity of the 3-fold test with offsets: with c1 ≠ 0 the guide moment m10 is
    # not zero and still moves from leg to leg under the 120° turn.
    robot = Robot(piston=PistonParameters(com=(0.02, 0.03)), gravity=(0.0, 0.0))
    motion = paper_motion("vertical", samples=21)
    before = table_of(robot, motion)
    after = table_of(robot, rotated(motion, 2 * math.pi / 3))
    assert np.abs(before["m10_A"]).max() > 1e-4
    for quantity in ("m10", "f10", "n10"):
        np.testing.assert_allclose(after[f"{quantity}_B"], before[f"{quantity}_A"], atol=1e-13)
