"""The paper's recursive matrix method as printed (prp3.references.paper) against independent routes.

* Forces: the Newton–Euler solver of the 7 bodies (shares nothing with prp3.references.paper
  but the inputs) and the other methods of prp3, to 1e-12 of the force scale, on
  random robots (centre-of-mass offsets, any gravity) and motions.
* Intermediate quantities, each against something it could disagree with: the
  frames against the axes of docs/model.md and eq. (5); the closure (eq. 8) against the
  pose and the reference geometry of tests/strategies.py; ω̃ skew-symmetric with the
  platform's rate; ω̃² + ε̃ of the matrix recursion against ω̃ and ε of the vector
  ones; v_k0, γ_k0 and ω̃_k0 against finite differences of the positions and the
  frames; the virtual velocities against the real ones (eq. 14 is eq. 15 with the
  real rates) and against the sleeve constraints written in the plane; the body
  wrenches against m(a − g) of the reference body states.
* Eq. (5), the orientation condition, solved for q21 (whence φ21 = φ, eq. 7) for
  any φ in ±100 rad and at random poses, against the matrices written out here.
* ``--method paper`` whole (``paper_method``): its kinematics against the reference
  geometry, rates and body states of tests/strategies.py and the kernel's, and
  against finite differences of its own positions; results.csv of ``--method
  paper`` from the paper's recursion alone (the kernel's kinematics disabled).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import prp3
from prp3 import (
    Limits,
    Motion,
    Robot,
    SingularPoseError,
    TrajectoryError,
    UnreachablePoseError,
    inverse_dynamics,
)
from prp3.model.motion import paper_motion
from prp3.references.paper import (
    FORCE_SETS,
    MAX_RECORDED_SAMPLES,
    RecursiveMatrixResult,
    paper_inverse_dynamics,
    paper_method,
    recursive_matrix_method,
)
from prp3.references.paper_kinematics import orientation_condition
from strategies import (
    REF_ALPHA,
    REF_E,
    REF_N,
    SQRT3,
    AnalyticMotion,
    body_states,
    cross,
    differentiate,
    poses,
    ref_geometry,
    ref_rates,
    scenarios,
    stencil_times,
    total_mass,
    turn,
)

QUANTITIES = ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32")
MOMENTS = ("m10", "m32")

# The paper's matrices (eq. 2), written out again here from the print.
THETA_1 = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
THETA_2 = 0.5 * np.array([[1.0, -SQRT3, 0.0], [SQRT3, 1.0, 0.0], [0.0, 0.0, 2.0]])


def rot_z(angle: np.ndarray) -> np.ndarray:
    """rot(φ) of eq. (3): rows (cos, sin, 0), (−sin, cos, 0), (0, 0, 1)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((*np.shape(angle), 3, 3))
    out[..., 0, 0], out[..., 0, 1], out[..., 1, 0], out[..., 1, 1] = c, s, -s, c
    out[..., 2, 2] = 1.0
    return out


def plane(vectors: np.ndarray) -> np.ndarray:
    """3-D vectors (..., 3) with a zero z component → plane vectors (..., 2)."""
    return vectors[..., :2]


def in_fixed_frame(result: RecursiveMatrixResult, vectors: np.ndarray) -> np.ndarray:
    """Vectors (..., 3 legs, 3 bodies, 3) in T_k → T0: q_k0ᵀ·v."""
    return np.einsum("...ji,...j->...i", result.a0, vectors)


def force_scale(robot: Robot, dyn: prp3.InverseDynamics) -> np.ndarray:
    """Per-sample force scale (N): the largest reported force plus the total weight."""
    largest = np.max(
        [np.abs(getattr(dyn, name)).max(axis=-1) for name in ("f10", "f21y", "f21z", "n10", "n32")],
        axis=0,
    )
    return np.asarray(largest + total_mass(robot) * math.hypot(*robot.gravity))


def assert_forces_agree(
    robot: Robot, motion: Motion, dyn: prp3.InverseDynamics, reference: prp3.InverseDynamics
) -> None:
    kin = prp3.inverse_kinematics(robot, motion)
    forces = force_scale(robot, reference)[..., None]
    lever = robot.l0 + np.abs(kin.geometry.lever).max(axis=(-1, -2))[..., None]
    power = forces * np.abs(kin.dlambda10).max(axis=-1, keepdims=True)
    for name in QUANTITIES:
        scale = forces * lever if name in MOMENTS else power if name == "p10" else forces
        difference = np.abs(getattr(dyn, name) - getattr(reference, name))
        assert np.all(difference <= 1e-12 * scale + 1e-300), (
            name,
            reference.method,
            float((difference / scale).max()),
        )


# ------------------------------------------------------------------ forces
@given(scenario=scenarios())
def test_forces_agree_with_newton_euler_and_the_other_methods(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 9))
    recorded = recursive_matrix_method(robot, motion)
    dyn = paper_inverse_dynamics(robot, motion)
    assert dyn.method == "paper"
    for name in QUANTITIES:  # one computation, two ways to get it
        np.testing.assert_array_equal(
            getattr(recorded.inverse_dynamics(), name), getattr(dyn, name)
        )
    references = [inverse_dynamics(robot, motion, method="newton-euler")[1]]
    if "fast" in prp3.METHODS:  # the fused kernel, once it exists
        references.append(inverse_dynamics(robot, motion, method="fast")[1])  # type: ignore[arg-type]
    for reference in references:
        assert_forces_agree(robot, motion, dyn, reference)


def test_static_central_configuration_by_hand() -> None:
    # Worked in tests/test_dynamics.py from the body balances of docs/model.md.
    s = SQRT3
    result = recursive_matrix_method(Robot(), Motion.at_rest([0.0, 0.0, 0.0]))
    np.testing.assert_allclose(
        result.f10, [36.7875 * s / 2, -9.81 * s / 2, -9.81 * s / 4 - 22.0725 * s / 2], atol=1e-12
    )
    np.testing.assert_allclose(result.n32, [19.62, -9.81, -9.81], atol=1e-12)
    # eq. (21): F1 of chain A carries the weight of piston, link and platform along y0,
    # in T1 (x1 = −z0, y1 = n_i, z1 = e_i); F1 of B and C: piston and link only.
    weight = 9.81 * np.array([1.0 + 0.75 + 3.0, 1.75, 1.75])[:, None]
    y0_in_T1 = np.stack([np.zeros(3), REF_N[:, 1], REF_E[:, 1]], axis=-1)  # (u1·, n_i·y0, e_i·y0)
    np.testing.assert_allclose(result.F[:, 0], weight * y0_in_T1, atol=1e-12)
    np.testing.assert_allclose(y0_in_T1[0], [0.0, 0.5, s / 2], atol=1e-15)


def test_single_sample_and_batch_agree() -> None:
    motion = paper_motion("rotation", samples=7)
    robot = Robot(gravity=(1.0, -9.0))
    batch = recursive_matrix_method(robot, motion)
    for index in (0, 3, 6):
        one = recursive_matrix_method(robot, motion[index])
        assert one.f10.shape == (3,) and one.a.shape == (3, 3, 3, 3)
        for name in ("a", "omega_tilde", "gamma", "F", "M", "v32_virtual", *QUANTITIES):
            np.testing.assert_allclose(
                getattr(one, name), getattr(batch, name)[index], rtol=1e-15, atol=1e-15
            )
    assert recursive_matrix_method(robot, motion[2:3]).f10.shape == (1, 3)
    assert paper_inverse_dynamics(robot, motion[2]).n32.shape == (3,)


def test_chunks_do_not_change_the_result(monkeypatch: pytest.MonkeyPatch) -> None:
    robot = Robot(gravity=(2.0, -9.81))
    motion = paper_motion("rotation", samples=50)
    whole = paper_inverse_dynamics(robot, motion)
    monkeypatch.setattr(prp3.references.paper, "PAPER_CHUNK", 7)
    chunked = paper_inverse_dynamics(robot, motion)
    for name in QUANTITIES:
        np.testing.assert_allclose(getattr(chunked, name), getattr(whole, name), rtol=1e-15, atol=0)


def test_results_are_read_only() -> None:
    result = recursive_matrix_method(Robot(), paper_motion("vertical", samples=3))
    with pytest.raises(ValueError, match="read-only"):
        result.F[0, 0, 0, 0] = 1.0


# ------------------------------------------------------------------ frames, eqs. (2)–(10)
@given(scenario=scenarios())
def test_frames_closure_and_geometry(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 6))
    result = recursive_matrix_method(robot, motion)
    eye = np.eye(3)
    for matrices in (result.a, result.a0):  # orthogonal, proper
        np.testing.assert_allclose(
            matrices @ np.swapaxes(matrices, -1, -2),
            np.broadcast_to(eye, matrices.shape),
            atol=1e-15,
        )
        np.testing.assert_allclose(np.linalg.det(matrices), 1.0, atol=1e-14)
    # eq. (3): a_k0 = a_k,k-1 ··· a10
    a = result.a
    np.testing.assert_allclose(
        result.a0[..., 1, :, :], a[..., 1, :, :] @ a[..., 0, :, :], atol=1e-15
    )
    np.testing.assert_allclose(
        result.a0[..., 2, :, :], a[..., 2, :, :] @ result.a0[..., 1, :, :], atol=1e-15
    )
    # eq. (2) from the print, and the axes of docs/model.md: z1 = e, y1 = n, z2 = z0, z3 = d, y3 = d⊥
    phi = motion.pose[:, 2]
    theta_alpha = rot_z(REF_ALPHA)
    np.testing.assert_allclose(
        a[:, :, 0], np.broadcast_to(THETA_1 @ theta_alpha, (6, 3, 3, 3)), atol=1e-15
    )
    np.testing.assert_allclose(
        a[:, :, 1], rot_z(np.broadcast_to(phi[:, None], (6, 3))) @ THETA_1.T, atol=1e-15
    )
    np.testing.assert_allclose(
        a[:, :, 2], np.broadcast_to(THETA_1 @ THETA_2, (6, 3, 3, 3)), atol=1e-15
    )
    d = np.stack(
        [
            np.cos(phi[:, None] + REF_ALPHA - math.pi / 3),
            np.sin(phi[:, None] + REF_ALPHA - math.pi / 3),
        ],
        -1,
    )
    axes = np.swapaxes(result.a0, -1, -2)  # columns: x_k, y_k, z_k in T0
    np.testing.assert_allclose(
        plane(axes[:, :, 0, :, 2]), np.broadcast_to(REF_E, (6, 3, 2)), atol=1e-15
    )
    np.testing.assert_allclose(
        plane(axes[:, :, 0, :, 1]), np.broadcast_to(REF_N, (6, 3, 2)), atol=1e-15
    )
    np.testing.assert_allclose(
        axes[:, :, 1, :, 2], np.broadcast_to([0.0, 0.0, 1.0], (6, 3, 3)), atol=1e-15
    )
    np.testing.assert_allclose(plane(axes[:, :, 2, :, 2]), d, atol=1e-15)
    np.testing.assert_allclose(plane(axes[:, :, 2, :, 1]), turn(d), atol=1e-15)
    # eq. (5)–(6): q30°ᵀ q30 = R = rot(φ) with q30° = θ1 θ2 θα^i
    q30_circle = THETA_1 @ THETA_2 @ theta_alpha
    np.testing.assert_allclose(
        np.swapaxes(q30_circle, -1, -2) @ result.a0[:, :, 2],
        rot_z(np.broadcast_to(phi[:, None], (6, 3))),
        atol=1e-15,
    )
    # eq. (8): every leg's loop closes on G; eq. (10) agrees with the reference geometry
    l0 = robot.l0
    np.testing.assert_allclose(
        plane(result.centre),
        np.broadcast_to(motion.pose[:, None, :2], (6, 3, 2)),
        rtol=0,
        atol=1e-14 * l0,
    )
    np.testing.assert_allclose(result.centre[..., 2], 0.0, atol=1e-15 * l0)
    ref = ref_geometry(l0, motion.pose)
    np.testing.assert_allclose(result.lambda10, ref.lambda10, rtol=0, atol=1e-14 * l0)
    np.testing.assert_allclose(result.lambda32, ref.lambda32, rtol=0, atol=1e-14 * l0)
    np.testing.assert_allclose(plane(result.position[:, :, 1]), ref.joint, rtol=0, atol=1e-14 * l0)
    # eq. (7) from eq. (5): φ21 = φ to round-off of φ
    np.testing.assert_allclose(
        result.phi21,
        np.broadcast_to(phi[:, None], (6, 3)),
        rtol=0,
        atol=4e-16 * (1 + np.abs(phi).max()),
    )


# ------------------------------------------------------------------ kinematics, eqs. (11)–(18)
@given(scenario=scenarios())
def test_angular_velocities_and_accelerations(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 6))
    result = recursive_matrix_method(robot, motion)
    w = result.omega_tilde
    rate = np.abs(motion.velocity[:, 2]).max() + 1.0
    np.testing.assert_allclose(w + np.swapaxes(w, -1, -2), 0.0, atol=1e-15 * rate)  # skew
    # in T0: ω10 = 0, ω20 = ω30 = φ̇·z0 (eq. 12); ε alike with φ̈ (eq. 18)
    phid, phidd = motion.velocity[:, 2], motion.acceleration[:, 2]
    expected = np.zeros((6, 3, 3, 3))
    expected[:, :, 1:, 2] = phid[:, None, None]
    np.testing.assert_allclose(in_fixed_frame(result, result.omega), expected, atol=1e-15 * rate)
    expected[:, :, 1:, 2] = phidd[:, None, None]
    accel = np.abs(phidd).max() + rate**2
    np.testing.assert_allclose(in_fixed_frame(result, result.epsilon), expected, atol=1e-14 * accel)
    # the matrix relation of eq. (18) against the vector relations of eqs. (11), (18)
    eps_tilde = result.omega2_epsilon - w @ w
    np.testing.assert_allclose(eps_tilde + np.swapaxes(eps_tilde, -1, -2), 0.0, atol=1e-14 * accel)
    np.testing.assert_allclose(eps_tilde[..., 2, 1], result.epsilon[..., 0], atol=1e-14 * accel)
    np.testing.assert_allclose(eps_tilde[..., 0, 2], result.epsilon[..., 1], atol=1e-14 * accel)
    np.testing.assert_allclose(eps_tilde[..., 1, 0], result.epsilon[..., 2], atol=1e-14 * accel)
    # the relative rates of eqs. (14), (17) against the reference kinematics
    ref = ref_rates(robot.l0, motion.pose, motion.velocity, motion.acceleration)
    for mine, theirs in (
        (result.v10, ref.dlambda10),
        (result.v32, ref.dlambda32),
        (result.gamma10, ref.ddlambda10),
        (result.gamma32, ref.ddlambda32),
    ):
        np.testing.assert_allclose(
            mine, theirs, rtol=1e-12, atol=1e-12 * (np.abs(theirs).max() + 1e-300)
        )


@given(scenario=scenarios())
def test_velocities_and_accelerations_are_derivatives(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    # 6th-order central differences of the positions of A_k (eq. 8) and of the frames
    # q_k0ᵀ: v_k0 (eq. 13) and γ_k0 (eq. 18) are the derivatives of the positions,
    # d(q_k0ᵀ)/dt = q_k0ᵀ ω̃_k0 (eq. 11).  Error: truncation O(h⁶) plus round-off
    # ≈ ε·|x|/h (first) and ε·|x|/h² (second derivative).
    robot, analytic = scenario
    T = analytic.duration
    t = np.linspace(0.1 * T, 0.9 * T, 4)
    h = 1e-3
    stencil = recursive_matrix_method(robot, analytic.motion(stencil_times(t, h)))
    result = recursive_matrix_method(robot, analytic.motion(t))
    velocity, acceleration = differentiate(stencil.position, h, len(t))
    size = robot.l0 + np.abs(stencil.position).max()
    speed = np.abs(velocity).max() + size
    np.testing.assert_allclose(
        in_fixed_frame(result, result.v), velocity, rtol=0, atol=1e-8 * speed
    )
    np.testing.assert_allclose(
        in_fixed_frame(result, result.gamma),
        acceleration,
        rtol=0,
        atol=2e-5 * (np.abs(acceleration).max() + size),
    )
    frames_rate, _ = differentiate(np.swapaxes(stencil.a0, -1, -2), h, len(t))
    rate = np.abs(result.omega).max() + 1.0
    np.testing.assert_allclose(
        np.swapaxes(result.a0, -1, -2) @ result.omega_tilde, frames_rate, rtol=0, atol=1e-9 * rate
    )


# ------------------------------------------------------------------ virtual velocities, eqs. (15)–(16)
@given(scenario=scenarios())
def test_virtual_velocities(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 5))
    result = recursive_matrix_method(robot, motion)
    s10, s21y, s21z = (FORCE_SETS.index(name) for name in ("f10", "f21y", "f21z"))
    # eq. (14) is eq. (15) with the real rates: the real motion is Σ_l v10^l·(set a of leg l)
    v10 = result.v10[:, :, None]
    np.testing.assert_allclose(
        (v10 * result.vG_virtual[:, s10]).sum(axis=1)[:, :2],
        motion.velocity[:, :2],
        rtol=1e-12,
        atol=1e-12 * (np.abs(motion.velocity).max() + 1e-300),
    )
    np.testing.assert_allclose(
        (result.v10 * result.omega21_virtual[:, s10, :, 0]).sum(axis=1),
        motion.velocity[:, 2],
        rtol=1e-12,
        atol=1e-12 * (np.abs(motion.velocity).max() + 1e-300),
    )
    np.testing.assert_allclose(
        (v10 * result.v32_virtual[:, s10]).sum(axis=1),
        result.v32,
        rtol=1e-12,
        atol=1e-12 * (np.abs(result.v32).max() + 1e-300),
    )
    # the rigid platform turns with the same ω21^v for every leg (eq. 7); no motion out of plane
    np.testing.assert_array_equal(
        result.omega21_virtual,
        np.broadcast_to(result.omega21_virtual[..., :1], result.omega21_virtual.shape),
    )
    np.testing.assert_array_equal(result.vG_virtual[..., 2], 0.0)
    # sets a and c of eq. (16) move A2 alike (both along z1): the same virtual velocities
    np.testing.assert_allclose(
        result.v32_virtual[:, s21z], result.v32_virtual[:, s10], rtol=1e-15, atol=0
    )
    # in the plane: A2 of leg l moves by u (e_l or n_l), the others stay; the platform's
    # point at A2^i then slides along d_i relative to A2^i by v32^iv and never across it
    ref = ref_geometry(robot.l0, motion.pose)
    d = ref.slide
    for s, u in ((s10, REF_E), (s21y, REF_N)):
        for leg in range(3):
            joint_velocity = np.zeros((5, 3, 2))
            joint_velocity[:, leg] = u[leg]
            vG = plane(result.vG_virtual[:, s, leg])[:, None, :]
            omega = result.omega21_virtual[:, s, leg, :, None]
            relative = vG + omega * turn(ref.joint - motion.pose[:, None, :2]) - joint_velocity
            np.testing.assert_allclose(
                (relative * turn(d)).sum(-1), 0.0, atol=1e-12 * (1.0 + np.abs(relative).max())
            )
            np.testing.assert_allclose(
                (relative * d).sum(-1),
                result.v32_virtual[:, s, leg],
                atol=1e-12 * (1.0 + np.abs(relative).max()),
            )


@given(scenario=scenarios())
def test_forces_are_the_virtual_power_of_the_body_wrenches(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    # The principle of virtual work behind eqs. (21)–(25), body by body in T0: for the
    # virtual motion of set s, leg l (eq. 16), the force is the virtual power of the
    # wrenches F_k0, M_k0 (about A_k) of every body that moves: pistons with A1 (v10^v·e),
    # links with A2 (A1 plus v21y^v·n + v21z^v·e) and ω21^v, the platform with its point
    # A3^A, v0^Gv + ω21^v·J(A3^A − G), and ω21^v.  No accumulation (eq. 21) involved.
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 4))
    result = recursive_matrix_method(robot, motion)
    F0 = plane(in_fixed_frame(result, result.F0))  # (4, 3 legs, 3 bodies, 2)
    M0 = in_fixed_frame(result, result.M0)[..., 2]  # about z0
    A3 = plane(result.position[:, 0, 2])
    lever_A3 = A3 - motion.pose[:, :2]
    forces = {"f10": result.f10, "f21y": result.f21y, "f21z": result.f21z}
    scale = np.abs(F0).max() + np.abs(M0).max() / robot.l0 + 1e-300
    for s, name in enumerate(FORCE_SETS):
        for leg in range(3):
            piston = np.zeros((4, 3, 2))
            link = np.zeros((4, 3, 2))
            if name == "f10":
                piston[:, leg] = link[:, leg] = REF_E[leg]
            else:
                link[:, leg] = REF_N[leg] if name == "f21y" else REF_E[leg]
            omega = result.omega21_virtual[:, s, leg, 0]
            vG = plane(result.vG_virtual[:, s, leg])
            platform = vG + omega[:, None] * turn(lever_A3)
            power = (
                (F0[:, :, 0] * piston).sum(axis=(-1, -2))
                + (F0[:, :, 1] * link).sum(axis=(-1, -2))
                + omega * M0[:, :, 1].sum(axis=-1)
                + (F0[:, 0, 2] * platform).sum(axis=-1)
                + omega * M0[:, 0, 2]
            )
            virtual = 1.0 + np.abs(result.omega21_virtual).max() * robot.l0
            np.testing.assert_allclose(
                forces[name][:, leg], power, rtol=0, atol=1e-12 * scale * virtual
            )


# ------------------------------------------------------------------ wrenches, eqs. (19)–(22)
@given(scenario=scenarios())
def test_body_wrenches(scenario: tuple[Robot, AnalyticMotion]) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 5))
    result = recursive_matrix_method(robot, motion)
    ref = ref_geometry(robot.l0, motion.pose)
    rates = ref_rates(robot.l0, motion.pose, motion.velocity, motion.acceleration)
    bodies = body_states(
        robot,
        ref.lambda10,
        rates.dlambda10,
        rates.ddlambda10,
        motion.pose,
        motion.velocity,
        motion.acceleration,
    )
    g = np.asarray(robot.gravity)
    need = [
        robot.piston.mass * (bodies.piston_acceleration - g),
        robot.link.mass * (bodies.link_acceleration - g),
        np.broadcast_to(
            robot.platform.mass * (bodies.platform_acceleration - g)[:, None], (5, 3, 2)
        ),
    ]
    F0 = in_fixed_frame(result, result.F0)
    M0 = in_fixed_frame(result, result.M0)
    scale = (
        total_mass(robot)
        * (
            np.abs(
                np.c_[bodies.link_acceleration.reshape(5, -1), bodies.platform_acceleration]
            ).max()
            + np.hypot(*g)
        )
        + 1e-300
    )
    inertia = (
        robot.platform.inertia
        if robot.platform.inertia is not None
        else robot.platform.mass * 3 * robot.l0**2 / 12
    )
    moment_about_A3 = inertia * motion.acceleration[:, 2, None] + cross(
        motion.pose[:, None, :2] - plane(result.position[:, :, 2]), need[2]
    )
    moments = [
        cross(bodies.piston_offset, need[0]),
        robot.link.inertia * motion.acceleration[:, 2, None] + cross(bodies.link_offset, need[1]),
        moment_about_A3,
    ]
    lever = robot.l0 + np.abs(result.position).max()
    for k in range(3):
        np.testing.assert_allclose(plane(F0[:, :, k]), need[k], rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(M0[:, :, k, 2], moments[k], rtol=0, atol=1e-12 * scale * lever)
    # the plane motion embedded in 3-D: no force out of the plane, no moment in it
    for forces in (result.F_star, result.F_in, result.F):
        np.testing.assert_allclose(in_fixed_frame(result, forces)[..., 2], 0.0, atol=1e-12 * scale)
    for moments_3d in (result.M_star, result.M_in, result.M):
        np.testing.assert_allclose(
            plane(in_fixed_frame(result, moments_3d)), 0.0, atol=1e-12 * scale * lever
        )
    # eq. (21): the platform in chain A only
    np.testing.assert_array_equal(result.F[:, 1:, 2], 0.0)
    np.testing.assert_array_equal(result.M[:, 1:, 2], 0.0)


# ------------------------------------------------------------------ bad input
def test_bad_input_is_refused() -> None:
    robot = Robot()
    with pytest.raises(TrajectoryError, match=r"motion must be a prp3\.Motion"):
        recursive_matrix_method(robot, "vertical")  # type: ignore[arg-type]
    with pytest.raises(prp3.ParameterError, match=r"robot must be a prp3\.Robot"):
        paper_inverse_dynamics(None, paper_motion("vertical"))  # type: ignore[arg-type]
    with pytest.raises(SingularPoseError, match=r"^pose: singular pose"):
        paper_inverse_dynamics(robot, Motion.at_rest([0.0, 0.0, math.pi / 3]))
    with pytest.raises(TrajectoryError, match=f"more than the {MAX_RECORDED_SAMPLES}"):
        recursive_matrix_method(robot, paper_motion("vertical", samples=MAX_RECORDED_SAMPLES + 1))


def test_errors_name_the_sample_across_chunks(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(prp3.references.paper, "PAPER_CHUNK", 4)
    motion = paper_motion("vertical", samples=11)
    limited = Robot(limits=Limits(stroke=(-0.1, 0.02)))  # λ10_A = 2y/√3 > 0.02 once y > 0.0173
    first = int(np.argmax(2 * motion.pose[:, 1] / SQRT3 > 0.02))
    with pytest.raises(
        UnreachablePoseError, match=f"sample {first}, leg A: unreachable pose .*lambda10_A"
    ):
        paper_inverse_dynamics(limited, motion)
    acceleration = np.zeros((11, 3))
    acceleration[9, 1] = 1e308  # finite input, forces overflow
    huge = Motion(t=motion.t, pose=motion.pose, velocity=motion.velocity, acceleration=acceleration)
    with pytest.raises(TrajectoryError, match=r"sample 9, t = 2\.7 s: the results overflow"):
        paper_inverse_dynamics(Robot(), huge)


# ------------------------------------------------------------------ eq. (5), the orientation
@settings(max_examples=60)
@given(phi=st.lists(st.floats(-100.0, 100.0), min_size=1, max_size=8))
def test_the_orientation_condition_gives_phi21_equal_phi(phi: list[float]) -> None:
    # eq. (5) q30°ᵀ q30 = R = rot(φ), with q30 = q32 q21 q10 and q30° = θ1 θ2 θα^i
    # (eq. 6), written out again here from the print; φ anywhere in ±100 rad.
    angles = np.array(phi)
    a21, phi21 = orientation_condition(angles)
    theta_alpha = rot_z(REF_ALPHA)
    q10, q32 = THETA_1 @ theta_alpha, THETA_1 @ THETA_2
    q30 = q32 @ a21 @ q10
    q30_circle = THETA_1 @ THETA_2 @ theta_alpha
    R = rot_z(np.broadcast_to(angles[:, None], (len(phi), 3)))
    np.testing.assert_allclose(np.swapaxes(q30_circle, -1, -2) @ q30, R, rtol=0, atol=2e-15)
    # eq. (2): q21 = rot(φ21)·θ1ᵀ, and eq. (7): φ21 = φ for every leg
    # (φ21 is φ to the round-off of φ: its sine and cosine to that too)
    turn_by = 4e-16 * (1.0 + np.abs(angles).max())
    np.testing.assert_allclose(a21, rot_z(phi21) @ THETA_1.T, rtol=0, atol=2e-15 + turn_by)
    np.testing.assert_allclose(
        phi21, np.broadcast_to(angles[:, None], phi21.shape), rtol=0,
        atol=4e-16 * (1.0 + np.abs(angles).max()),
    )  # fmt: skip


@given(pose=poses())
def test_the_frames_satisfy_eq_5_at_any_pose(pose: np.ndarray) -> None:
    # the platform frame T3 of every leg is the fixed one turned by φ: a30 = q30°·rot(φ)
    result = recursive_matrix_method(Robot(), Motion.at_rest(pose))
    q30_circle = THETA_1 @ THETA_2 @ rot_z(REF_ALPHA)
    np.testing.assert_allclose(
        np.swapaxes(q30_circle, -1, -2) @ result.a0[:, 2],
        np.broadcast_to(rot_z(pose[2]), (3, 3, 3)),
        rtol=0,
        atol=2e-15,
    )
    np.testing.assert_allclose(result.phi21, pose[2], rtol=0, atol=4e-16 * (1 + abs(pose[2])))


# ------------------------------------------------------------------ --method paper, whole
KINEMATICS_FIELDS = (
    "dlambda10", "ddlambda10", "dlambda32", "ddlambda32", "dphi21", "ddphi21",
    "joint_velocity", "joint_acceleration", "piston_com", "piston_velocity",
    "piston_acceleration", "link_com", "link_velocity", "link_acceleration", "jacobian",
)  # fmt: skip
GEOMETRY_FIELDS = ("lambda10", "lambda32", "phi21", "joint", "slide", "slide_normal", "lever")


@given(scenario=scenarios())
def test_paper_kinematics_agree_with_the_references(
    scenario: tuple[Robot, AnalyticMotion],
) -> None:
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 7))
    kin, dyn = paper_method(robot, motion)
    l0 = robot.l0
    # the independent geometry, rates and body states of tests/strategies.py
    ref = ref_geometry(l0, motion.pose)
    rates = ref_rates(l0, motion.pose, motion.velocity, motion.acceleration)
    bodies = body_states(
        robot, ref.lambda10, rates.dlambda10, rates.ddlambda10,
        motion.pose, motion.velocity, motion.acceleration,
    )  # fmt: skip
    speed = np.abs(motion.velocity).max() * (1.0 + l0) + 1e-300
    accel = (np.abs(motion.acceleration).max() + np.abs(motion.velocity).max() ** 2) * (1 + l0)
    pairs = [
        (kin.geometry.lambda10, ref.lambda10, l0),
        (kin.geometry.lambda32, ref.lambda32, l0),
        (kin.geometry.joint, ref.joint, l0),
        (kin.geometry.slide, ref.slide, 1.0),
        (kin.geometry.lever, ref.lever, l0),
        (kin.geometry.slide_normal, turn(ref.slide), 1.0),
        (kin.dlambda10, rates.dlambda10, speed),
        (kin.dlambda32, rates.dlambda32, speed),
        (kin.ddlambda10, rates.ddlambda10, accel),
        (kin.ddlambda32, rates.ddlambda32, accel),
        (kin.piston_com, bodies.piston, l0),
        (kin.piston_velocity, bodies.piston_velocity, speed),
        (kin.piston_acceleration, bodies.piston_acceleration, accel),
        (kin.link_com, bodies.link, l0),
        (kin.link_velocity, bodies.link_velocity, speed),
        (kin.link_acceleration, bodies.link_acceleration, accel),
        (kin.joint_velocity, bodies.piston_velocity, speed),
    ]
    for mine, theirs, scale in pairs:
        np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(
        kin.geometry.determinant, np.sin(motion.pose[:, 2] - math.pi / 3), rtol=0, atol=1e-15
    )
    # the Jacobian of eq. (14) maps the platform's rates to the actuators'
    np.testing.assert_allclose(
        np.einsum("nij,nj->ni", kin.jacobian, motion.velocity), rates.dlambda10,
        rtol=0, atol=1e-12 * speed,
    )  # fmt: skip
    # and the kernel's kinematics, field by field
    kernel = prp3.inverse_kinematics(robot, motion)
    for name in KINEMATICS_FIELDS:
        theirs = getattr(kernel, name)
        scale = np.abs(theirs).max() + 1e-300
        np.testing.assert_allclose(getattr(kin, name), theirs, rtol=0, atol=1e-12 * scale)
    for name in GEOMETRY_FIELDS:
        theirs = getattr(kernel.geometry, name)
        np.testing.assert_allclose(getattr(kin.geometry, name), theirs, rtol=0, atol=1e-13)
    # the forces are those of paper_inverse_dynamics, bit for bit
    alone = paper_inverse_dynamics(robot, motion)
    for name in QUANTITIES:
        np.testing.assert_array_equal(getattr(dyn, name), getattr(alone, name))


@given(scenario=scenarios(offsets=True))
def test_paper_kinematics_are_derivatives(scenario: tuple[Robot, AnalyticMotion]) -> None:
    # 6th-order central differences (h = 1e-3) of the paper's positions against its rates:
    # truncation O(h⁶) plus round-off ≈ ε·|x|/h and ε·|x|/h².
    robot, analytic = scenario
    T = analytic.duration
    t = np.linspace(0.1 * T, 0.9 * T, 4)
    h = 1e-3
    stencil, _ = paper_method(robot, analytic.motion(stencil_times(t, h)))
    kin, _ = paper_method(robot, analytic.motion(t))
    size = robot.l0 + np.abs(stencil.geometry.joint).max()
    for position, velocity, acceleration in (
        (stencil.geometry.lambda10, kin.dlambda10, kin.ddlambda10),
        (stencil.geometry.lambda32, kin.dlambda32, kin.ddlambda32),
        (stencil.geometry.joint, kin.joint_velocity, kin.joint_acceleration),
        (stencil.piston_com, kin.piston_velocity, kin.piston_acceleration),
        (stencil.link_com, kin.link_velocity, kin.link_acceleration),
        (stencil.geometry.phi21, kin.dphi21, kin.ddphi21),
    ):
        first, second = differentiate(position, h, len(t))
        np.testing.assert_allclose(
            velocity, first, rtol=0, atol=1e-8 * (np.abs(first).max() + size)
        )
        np.testing.assert_allclose(
            acceleration, second, rtol=0, atol=2e-5 * (np.abs(second).max() + size)
        )


def test_method_paper_writes_only_the_papers_numbers(monkeypatch: pytest.MonkeyPatch) -> None:
    # --method paper: every column of results.csv from prp3.references.paper's recursion; with the
    # kernel's kinematics and prp3.mechanics.kinematics disabled, the same table, bit for bit.
    from prp3.apps.runs import simulate_table
    from prp3.io.results import results_table

    robot = Robot(gravity=(1.5, -9.81))
    motion = paper_motion("rotation", samples=13)
    recorded = recursive_matrix_method(robot, motion)
    expected = results_table(*inverse_dynamics(robot, motion, "paper"))
    for j, leg in enumerate("ABC"):
        for column, value in (
            ("lambda10", recorded.lambda10), ("dlambda10", recorded.v10),
            ("ddlambda10", recorded.gamma10), ("lambda32", recorded.lambda32),
            ("dlambda32", recorded.v32), ("ddlambda32", recorded.gamma32),
            ("f10", recorded.f10), ("n32", recorded.n32),
        ):  # fmt: skip
            np.testing.assert_array_equal(expected[f"{column}_{leg}"], value[:, j])

    def refused(*args: object, **kwargs: object) -> None:
        raise AssertionError("--method paper used the kernel")

    for module, name in (
        (prp3.analysis.inverse_dynamics, "inverse_kinematics"),
        (prp3.mechanics.kinematics, "kernel_kinematics"),
        (prp3.mechanics.kinematics, "kernel_geometry"),
        (prp3.mechanics.geometry, "kernel_geometry"),
    ):
        monkeypatch.setattr(module, name, refused)
    table = simulate_table(robot, motion, "paper", chunk=5)
    assert list(table) == list(expected)
    for name, column in expected.items():
        np.testing.assert_array_equal(table[name], column)
