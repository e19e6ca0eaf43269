"""Newton–Euler balance of all 7 bodies rebuilt from the reported columns alone.

Only the ``results_table`` columns (``t, x, y, phi, lambda10_L … m32_L``), the
robot parameters and the platform's ``φ̇, φ̈`` (which the table does not
carry) are used; positions come from the test's own geometry
(``strategies``), never from the core.  The 21 equations, derived from
docs/model.md's sign conventions (forces on each body; moments about ``z0``):

* piston i (translates along e_i; f10 acts through P_i; the guide gives n10·n
  at P_i and the moment m10; link 2 pushes back with −F21 at P_i; weight at C1):
  ``f10·e + n10·n − F21 + m1·g = m1·a1``  and, about P_i,
  ``m10 + r1 × m1·g = r1 × m1·a1``  (r1 = C1 − P, ω = 0);
* link 2 of leg i (F21 = f21y·n + f21z·e from the piston at P_i; the platform
  pushes back with −n32·d⊥ and −m32 about P_i):
  ``F21 − n32·d⊥ + m2·g = m2·a2``  and, about P_i,
  ``−m32 + r2 × m2·(g − a2) = I2·φ̈``  (r2 = C2 − P);
* platform (n32·d⊥ with moment m32 about P_i from each link; about G the
  moment is m32 + (P_i − G) × n32·d⊥):
  ``Σ n32·d⊥ + m3·g = m3·G̈``  and  ``Σ [m32 + (P_i − G) × n32·d⊥] = I3·φ̈``.

The reactions that do no work (n10, m10, n32's moment) escape the power
balance of ``test_energy``; these equations catch them
(``test_every_reported_column_is_checked``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pytest
from hypothesis import given
from numpy.typing import NDArray

from prp3 import METHODS, LinkParameters, Motion, PistonParameters, Robot, inverse_dynamics
from prp3.io.results import PER_LEG_COLUMNS, results_table
from prp3.model.motion import law_motion, paper_motion
from strategies import (
    REF_E,
    REF_N,
    AnalyticMotion,
    body_states,
    cross,
    platform_inertia,
    ref_platform_offset,
    ref_slide,
    scenarios,
    total_mass,
    turn,
)

LEGS = "ABC"
Table = Mapping[str, NDArray[np.float64]]


def columns(table: Table, quantity: str) -> np.ndarray:
    """The three legs' columns of ``quantity`` stacked on the last axis, ``(N, 3)``."""
    return np.stack([np.asarray(table[f"{quantity}_{leg}"]) for leg in LEGS], axis=-1)


def balance_residuals(robot: Robot, table: Table, phi_rates: np.ndarray) -> np.ndarray:
    """Relative residuals of the 21 balance equations and of ``p10 = f10·λ̇10``.

    ``phi_rates`` is ``(N, 2)``: ``φ̇, φ̈``.  Returns ``(N, 36)`` residuals, each
    divided by its scale (forces: largest reported force plus ``M·(|g| + |a|max)``;
    moments: that times the largest lever; powers: force scale times |λ̇10|max):
    18 piston and link equations, 3 platform equations, 3 powers ``p10 − f10·λ̇10``,
    6 closures (eq. 10) and 6 differences between the legs' rebuilt ``G̈``.
    """
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    I2, I3 = robot.link.inertia, platform_inertia(robot)
    g = np.asarray(robot.gravity)
    phi = np.asarray(table["phi"])
    G = np.stack([table["x"], table["y"]], axis=-1)
    phid, phidd = phi_rates[:, 0], phi_rates[:, 1]
    lam10, dlam10, ddlam10 = (columns(table, q) for q in ("lambda10", "dlambda10", "ddlambda10"))
    lam32, dlam32, ddlam32 = (columns(table, q) for q in ("lambda32", "dlambda32", "ddlambda32"))
    f10, p10, f21y, f21z = (columns(table, q) for q in ("f10", "p10", "f21y", "f21z"))
    n10, m10, n32, m32 = (columns(table, q) for q in ("n10", "m10", "n32", "m32"))

    # platform acceleration rebuilt from each leg's columns (closure differentiated twice),
    # G̈ = λ̈10·e + λ̈32·d + 2λ̇32·φ̇·Jd + φ̈·Jρ − φ̇²·ρ, ρ = λ32·d + Rot(α+φ)c; legs averaged.
    d = ref_slide(phi)
    d_perp = turn(d)
    rho = lam32[..., None] * d + ref_platform_offset(robot.l0, phi)
    w, a = phid[:, None, None], phidd[:, None, None]
    G_acc_legs = (
        ddlam10[..., None] * REF_E
        + ddlam32[..., None] * d
        + 2.0 * dlam32[..., None] * w * turn(d)
        + a * turn(rho)
        - w**2 * rho
    )
    G_acc = G_acc_legs.mean(axis=1)
    pose = np.column_stack([G, phi])
    rates = np.column_stack([np.zeros_like(G), phid])
    accelerations = np.column_stack([G_acc, phidd])
    bodies = body_states(robot, lam10, dlam10, ddlam10, pose, rates, accelerations)
    P, a1, a2 = bodies.joint, bodies.piston_acceleration, bodies.link_acceleration
    r1, r2 = bodies.piston_offset, bodies.link_offset

    F21 = f21y[..., None] * REF_N + f21z[..., None] * REF_E
    residuals = [
        # piston i: force (2) and moment about P_i (1)
        f10[..., None] * REF_E + n10[..., None] * REF_N - F21 + m1 * g - m1 * a1,
        (m10 + cross(r1, m1 * (g - a1)))[..., None],
        # link 2 of leg i: force (2) and moment about P_i (1)
        F21 - n32[..., None] * d_perp + m2 * g - m2 * a2,
        (-m32 + cross(r2, m2 * (g - a2)) - I2 * phidd[:, None])[..., None],
    ]
    per_leg = np.concatenate(residuals, axis=-1)  # (N, 3, 6)
    push = n32[..., None] * d_perp
    platform_force = push.sum(axis=1) + m3 * g - m3 * G_acc
    platform_moment = (m32 + cross(P - G[:, None, :], push)).sum(axis=1) - I3 * phidd

    largest = np.max(np.abs(np.concatenate([f10, f21y, f21z, n10, n32], axis=1)), axis=1)
    accel = max(float(np.abs(a1).max()), float(np.abs(a2).max()), float(np.abs(G_acc).max()))
    forces = largest + total_mass(robot) * (math.hypot(*g) + accel) + 1e-300
    lever = robot.l0 + np.abs(P - G[:, None, :]).max(axis=(1, 2)) + np.abs(r2).max()
    lever = lever + np.abs(r1).max()
    scale_leg = (
        np.array([1.0, 1.0, 0.0, 1.0, 1.0, 0.0])[None, :]
        + np.array([0.0, 0.0, 1.0, 0.0, 0.0, 1.0])[None, :] * lever[:, None]
    )  # moments × lever
    relative_leg = per_leg / (forces[:, None, None] * scale_leg[:, None, :])
    power = p10 - f10 * dlam10
    power_scale = np.maximum(forces[:, None] * np.abs(dlam10).max(axis=1, keepdims=True), 1e-300)
    # closure: G rebuilt from every leg's λ10, λ32 (eq. 10)
    closure = (P + rho - G[:, None, :]).reshape(len(phi), 6) / lever[:, None]
    return np.concatenate(
        [
            relative_leg.reshape(len(phi), 18),
            platform_force / forces[:, None],
            (platform_moment / (forces * lever))[:, None],
            power / power_scale,
            closure,
            ((G_acc_legs - G_acc[:, None, :]).reshape(len(phi), 6) / (accel + 1e-300)),
        ],
        axis=1,
    )


def platform_acceleration_from_leg_a(
    robot: Robot, table: Table, phi_rates: np.ndarray
) -> np.ndarray:
    """G̈ rebuilt from leg A's columns alone (for the check against the motion)."""
    phi = np.asarray(table["phi"])
    d = ref_slide(phi)[:, 0]
    rho = np.asarray(table["lambda32_A"])[:, None] * d + ref_platform_offset(robot.l0, phi)[:, 0]
    w, a = phi_rates[:, :1], phi_rates[:, 1:]
    return np.asarray(
        np.asarray(table["ddlambda10_A"])[:, None] * REF_E[0]
        + np.asarray(table["ddlambda32_A"])[:, None] * d
        + 2.0 * np.asarray(table["dlambda32_A"])[:, None] * w * turn(d)
        + a * turn(rho)
        - w**2 * rho
    )


def check(robot: Robot, motion: Motion, method: str) -> float:
    """Largest relative residual of the balances for ``motion`` solved by ``method``."""
    kin, dyn = inverse_dynamics(robot, motion, method=method)  # type: ignore[arg-type]
    table = results_table(kin, dyn)
    rates = np.column_stack([motion.velocity[:, 2], motion.acceleration[:, 2]])
    residuals = balance_residuals(robot, table, rates)
    # the platform acceleration rebuilt from the columns is the motion's
    G_acc_error = np.abs(
        platform_acceleration_from_leg_a(robot, table, rates) - motion.acceleration[:, :2]
    ).max()
    assert G_acc_error <= 1e-12 * (np.abs(motion.acceleration).max() + robot.l0)
    return float(np.abs(residuals).max())


@given(scenario=scenarios())
def test_every_body_is_in_equilibrium(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 10))
    for method in METHODS:
        assert check(robot, motion, method) < 1e-12, method


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name", ["vertical", "rotation"])
def test_paper_motions_are_in_equilibrium(name: str, method: str) -> None:
    assert check(Robot(), paper_motion(name, samples=301), method) < 1e-13


@pytest.mark.parametrize("column", [*PER_LEG_COLUMNS, "x", "y", "phi"])
@pytest.mark.parametrize("leg", list(LEGS))
def test_every_reported_column_is_checked(column: str, leg: str) -> None:
    # The check must fail when any reported column is off by 1e-6 of its scale —
    # including the workless reactions n10, m10 that the power balance cannot see.
    robot = Robot(
        gravity=(1.0, -9.81),
        piston=PistonParameters(com=(0.01, 0.02)),
        link=LinkParameters(com=(0.02, -0.01), inertia=1e-3),
    )
    motion = law_motion([0.01, -0.02, 0.2], samples=11)
    kin, dyn = inverse_dynamics(robot, motion)
    table = dict(results_table(kin, dyn))
    rates = np.column_stack([motion.velocity[:, 2], motion.acceleration[:, 2]])
    assert float(np.abs(balance_residuals(robot, table, rates)).max()) < 1e-13
    key = column if column in ("x", "y", "phi") else f"{column}_{leg}"
    table[key] = table[key] + 1e-6 * (np.abs(table[key]).max() + 1.0)
    assert float(np.abs(balance_residuals(robot, table, rates)).max()) > 1e-8
