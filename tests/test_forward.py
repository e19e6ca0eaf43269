"""Forward geometry, forward kinematics and forward dynamics (``prp3.analysis.forward``).

Every expected value comes from a route other than the code under test: the
core inverse geometry/kinematics/dynamics, a bracketing search, energy
quadratures, finite differences.  The derivations are written beside them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

import prp3.analysis.forward as fw
from prp3 import (
    Limits,
    LinkParameters,
    Motion,
    ParameterError,
    PistonParameters,
    PlatformParameters,
    Robot,
    SingularPoseError,
    TrajectoryError,
    UnreachablePoseError,
    inverse_dynamics,
    inverse_geometry,
    inverse_kinematics,
    paper_motion,
)
from prp3.analysis.equations_of_motion import platform_dynamics
from prp3.analysis.force_histories import ActuatorForces
from prp3.analysis.forward import SINGULARITY_STOP, forward_dynamics
from prp3.analysis.forward_kinematics import (
    forward_acceleration,
    forward_kinematics,
    forward_velocity,
)
from prp3.engines.compiled_robot import compile_robot
from prp3.engines.sample_entries import sample_actuator_forces
from prp3.mechanics.geometry import (
    DEGENERATE_ASSEMBLY,
    LEG_AXIS,
    base_vertices,
    forward_geometry,
    orientation_from_sum,
    platform_vertices,
    sum_from_orientation,
)
from prp3.model.motion import PAPER_MOTIONS

ROBOT = Robot()
L0 = ROBOT.l0


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angle difference wrapped to (−π, π]."""
    return np.asarray((np.asarray(angle) + math.pi) % (2.0 * math.pi) - math.pi)


def regular(phi: float, margin: float = 1e-3) -> bool:
    return abs(math.sin(phi - math.pi / 3.0)) > margin


poses = st.tuples(
    st.floats(-0.2, 0.2),
    st.floats(-0.2, 0.2),
    st.floats(-math.pi, math.pi),
).filter(lambda p: regular(p[2]))

#: Poses away from the singular orientation: the forward problem is well conditioned there.
well_conditioned_poses = st.tuples(
    st.floats(-0.3, 0.3),
    st.floats(-0.3, 0.3),
    st.floats(-math.pi, math.pi),
).filter(lambda p: regular(p[2], 0.05))


# ------------------------------------------------------------ forward geometry
@settings(max_examples=200, deadline=None)
@given(pose=well_conditioned_poses)
def test_round_trip_with_inverse_geometry_recovers_the_pose(
    pose: tuple[float, float, float],
) -> None:
    lam = inverse_geometry(ROBOT, pose).lambda10
    solution = forward_geometry(ROBOT, lam)
    assert solution.pose.shape == (3,)
    np.testing.assert_allclose(solution.pose[:2], pose[:2], rtol=0, atol=1e-12)
    assert abs(float(wrap(solution.pose[2] - pose[2]))) <= 1e-12
    # the solution really assembles: its inverse geometry gives back the displacements
    np.testing.assert_allclose(solution.geometry.lambda10, lam, rtol=1e-13, atol=1e-13)


def test_round_trip_batch_of_random_poses() -> None:
    rng = np.random.default_rng(7)
    n = 20000
    pose = np.column_stack(
        [rng.uniform(-0.3, 0.3, n), rng.uniform(-0.3, 0.3, n), rng.uniform(-math.pi, math.pi, n)]
    )
    D = np.sin(pose[:, 2] - math.pi / 3.0)
    pose, D = pose[np.abs(D) > 1e-4], D[np.abs(D) > 1e-4]  # every pose the core accepts
    lam = inverse_geometry(ROBOT, pose).lambda10
    solution = forward_geometry(ROBOT, lam)
    assert solution.pose.shape == pose.shape
    error = np.abs(solution.pose - pose)
    error[:, 2] = np.abs(wrap(solution.pose[:, 2] - pose[:, 2]))
    error = error.max(axis=1)
    # away from the singularity: 1e-12
    assert error[np.abs(D) > 0.05].max() <= 1e-12
    # near it the problem itself is ill conditioned: λ10 carries round-off ε·|λ10|
    # (|λ10| ~ |G|/|D|) and ∂φ/∂Σλ10 is finite but ∂G/∂φ ~ |λ10|, so the error is
    # O(ε·|λ10|/|D|); the constant measured on 1.2 million poses is below 15.
    eps = np.finfo(float).eps
    bound = 50.0 * eps * (np.abs(lam).max(axis=1) + L0) / np.abs(D)
    assert (error <= np.maximum(bound, 1e-12)).all()
    # aspect: the sign of sin(φ − π/3), computed here from the true poses
    np.testing.assert_array_equal(solution.aspect, np.sign(D))


def _all_orientations_by_bracketing(lam: np.ndarray) -> list[float]:
    """Every regular φ that assembles with ``lam``, found without the closed form.

    At a fixed φ the core's λ10(G, φ) is affine in G with the 3×2 matrix of
    rows −d⊥_i/D, whose left null vector is (1, 1, 1) (Σ d⊥_i = 0).  So the
    pose assembles iff Σλ10(G, φ) = Σλ_target, and Σλ10 does not depend on G:
    h(φ) = Σλ10((0, 0, φ)) − Σλ_target.  Scan φ on a fine grid (the core
    refuses the singular orientations), bracket the sign changes between
    neighbours of the same aspect (a sign flip across a singular orientation
    is a pole, not a root), polish with brentq.
    """
    target = float(lam.sum())

    def h(phi: float) -> float:
        return float(inverse_geometry(ROBOT, [0.0, 0.0, phi]).lambda10.sum()) - target

    grid = np.linspace(-math.pi, math.pi, 20001)
    grid = grid[np.abs(np.sin(grid - math.pi / 3.0)) > 2e-4]
    values = inverse_geometry(ROBOT, np.column_stack([0 * grid, 0 * grid, grid])).lambda10.sum(-1)
    values -= target
    aspect = np.sign(np.sin(grid - math.pi / 3.0))
    positive = values > 0.0  # a value that is exactly 0 brackets once, not twice
    change = (positive[:-1] != positive[1:]) & (aspect[:-1] == aspect[1:])
    return [brentq(h, grid[k], grid[k + 1], xtol=1e-15, rtol=1e-15) for k in np.nonzero(change)[0]]


def _position_by_least_squares(lam: np.ndarray, phi: float) -> np.ndarray:
    """G at a given φ from the core's affine map λ10(G) (two unit steps of G)."""
    base = inverse_geometry(ROBOT, [0.0, 0.0, phi]).lambda10
    columns = [inverse_geometry(ROBOT, [1.0, 0.0, phi]).lambda10 - base]
    columns.append(inverse_geometry(ROBOT, [0.0, 1.0, phi]).lambda10 - base)
    G, *_ = np.linalg.lstsq(np.column_stack(columns), lam - base, rcond=None)
    return np.asarray(G)


@settings(max_examples=15, deadline=None)
@given(lam=st.lists(st.floats(-0.15, 0.15), min_size=3, max_size=3))
def test_bracketing_finds_the_same_single_regular_assembly(lam: list[float]) -> None:
    lam_array = np.array(lam)
    if abs(lam_array.sum() - math.sqrt(3.0) * L0 / 2.0) < 1e-3:
        return  # too close to the singular sum
    roots = _all_orientations_by_bracketing(lam_array)
    solution = forward_geometry(ROBOT, lam_array)
    assert len(roots) == 1  # one regular assembly per 2π
    assert abs(float(wrap(roots[0] - solution.pose[2]))) < 1e-12
    np.testing.assert_allclose(
        solution.pose[:2], _position_by_least_squares(lam_array, roots[0]), atol=1e-12
    )


@settings(max_examples=30, deadline=None)
@given(lam=st.lists(st.floats(-0.5, 0.5), min_size=3, max_size=3))
def test_degenerate_assembly_fits_every_actuator_displacement(lam: list[float]) -> None:
    # At (0, 0, π/3) each joint P_i = B_i0 + (l0/√3 + λ10_i)·e_i must lie on the line
    # of platform edge i (the edge through P_i along d_i); the edge of leg i joins
    # the platform vertices i+1 and i+2 (see platform_vertices' layout).
    P = base_vertices(ROBOT) + (L0 / math.sqrt(3.0) + np.array(lam))[:, None] * LEG_AXIS
    vertices = platform_vertices(ROBOT, DEGENERATE_ASSEMBLY)
    for i in range(3):
        a, b = vertices[(i + 1) % 3], vertices[(i + 2) % 3]
        edge, offset = b - a, P[i] - a
        assert abs(edge[0] * offset[1] - edge[1] * offset[0]) < 1e-12


def test_aspect_changes_at_the_singular_sum() -> None:
    singular_sum = math.sqrt(3.0) * L0 / 2.0  # Σλ10 at φ = π/3, from sum_from_orientation's formula
    below = forward_geometry(ROBOT, np.full(3, singular_sum / 3.0 - 0.01))
    above = forward_geometry(ROBOT, np.full(3, singular_sum / 3.0 + 0.01))
    assert int(below.aspect) == -1 and int(above.aspect) == 1
    assert below.pose[2] < math.pi / 3.0 < above.pose[2]
    with pytest.raises(SingularPoseError, match="sqrt"):
        forward_geometry(ROBOT, np.full(3, singular_sum / 3.0))


def test_orientation_and_sum_are_inverse_functions() -> None:
    phi = np.linspace(-2.0, 2.0, 41)
    np.testing.assert_allclose(
        orientation_from_sum(L0, sum_from_orientation(L0, phi)), phi, atol=1e-14
    )
    # the central configuration: λ10 = 0 ⇒ φ = 0
    assert abs(float(orientation_from_sum(L0, 0.0))) < 1e-15


def test_forward_geometry_refuses_bad_input() -> None:
    limited = Robot(limits=Limits(stroke=(-0.05, 0.05)))
    with pytest.raises(UnreachablePoseError, match=r"lambda10_B = 0\.06"):
        forward_geometry(limited, [0.0, 0.06, 0.0])
    with pytest.raises(TrajectoryError, match=r"shape \(3,\) or \(N, 3\)"):
        forward_geometry(ROBOT, [0.0, 0.0])
    with pytest.raises(TrajectoryError, match="not finite"):
        forward_geometry(ROBOT, [[0.0, 0.0, 0.0], [0.0, math.nan, 0.0]])


def test_output_rank_follows_input_rank() -> None:
    assert forward_geometry(ROBOT, [0.0, 0.0, 0.0]).pose.shape == (3,)
    assert forward_geometry(ROBOT, [[0.0, 0.0, 0.0]]).pose.shape == (1, 3)
    assert forward_geometry(ROBOT, [0.0, 0.0, 0.0]).aspect.shape == ()


# --------------------------------------------------------- forward kinematics
samples = st.tuples(
    poses,
    st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3),
    st.lists(st.floats(-5.0, 5.0), min_size=3, max_size=3),
)


@settings(max_examples=100, deadline=None)
@given(sample=samples)
def test_forward_kinematics_inverts_inverse_kinematics(sample) -> None:  # type: ignore[no-untyped-def]
    pose, velocity, acceleration = (np.array(v, dtype=float) for v in sample)
    motion = Motion(t=0.0, pose=pose, velocity=velocity, acceleration=acceleration)
    kin = inverse_kinematics(ROBOT, motion)
    back = forward_kinematics(ROBOT, 0.0, kin.geometry.lambda10, kin.dlambda10, kin.ddlambda10)
    assert back.pose.shape == (3,)
    np.testing.assert_allclose(back.pose[:2], pose[:2], atol=1e-12)
    np.testing.assert_allclose(back.velocity, velocity, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(back.acceleration, acceleration, rtol=1e-8, atol=1e-8)


def test_forward_velocity_matches_finite_differences_of_forward_geometry() -> None:
    # q̇ = ∂q/∂λ10 · λ̇10, the derivative taken by central differences of the closed form
    lam = np.array([0.02, -0.03, 0.01])
    rate = np.array([0.3, -0.1, 0.2])
    h = 1e-6
    plus = forward_geometry(ROBOT, lam + h * rate).pose
    minus = forward_geometry(ROBOT, lam - h * rate).pose
    expected = (plus - minus) / (2.0 * h)
    pose = forward_geometry(ROBOT, lam).pose
    np.testing.assert_allclose(forward_velocity(ROBOT, pose, rate), expected, rtol=1e-7, atol=1e-9)


def test_forward_acceleration_matches_second_differences() -> None:
    # λ10(t) = λ0 + v·t + a·t²/2 → pose(t) by the closed form; q̈ by second differences
    lam0, v, a = (
        np.array([0.01, 0.0, -0.02]),
        np.array([0.2, -0.1, 0.05]),
        np.array([1.0, 2.0, -1.5]),
    )
    h = 1e-4

    def q(t: float) -> np.ndarray:
        return forward_geometry(ROBOT, lam0 + v * t + 0.5 * a * t * t).pose

    expected = (q(h) - 2.0 * q(0.0) + q(-h)) / (h * h)
    qdot = (q(h) - q(-h)) / (2.0 * h)
    got = forward_acceleration(ROBOT, q(0.0), forward_velocity(ROBOT, q(0.0), v), a)
    np.testing.assert_allclose(got, expected, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(forward_velocity(ROBOT, q(0.0), v), qdot, rtol=1e-7)


def test_forward_kinematics_batch_of_the_paper_motion() -> None:
    motion = paper_motion("rotation", samples=31)
    kin = inverse_kinematics(ROBOT, motion)
    back = forward_kinematics(ROBOT, motion.t, kin.geometry.lambda10, kin.dlambda10, kin.ddlambda10)
    assert back.pose.shape == (31, 3)
    np.testing.assert_allclose(back.pose, motion.pose, atol=1e-12)
    np.testing.assert_allclose(back.velocity, motion.velocity, atol=1e-12)
    np.testing.assert_allclose(back.acceleration, motion.acceleration, atol=1e-12)


# ---------------------------------------------------------- platform dynamics
robots = st.builds(
    lambda m1, m2, m3, i2, c1, c2: Robot(
        piston=PistonParameters(mass=m1, com=c1),
        link=LinkParameters(mass=m2, inertia=i2, com=c2),
        platform=PlatformParameters(mass=m3),
    ),
    st.floats(0.1, 5.0),
    st.floats(0.1, 5.0),
    st.floats(0.1, 5.0),
    st.floats(0.0, 0.01),
    st.tuples(st.floats(-0.05, 0.05), st.floats(-0.05, 0.05)),
    st.tuples(st.floats(-0.05, 0.05), st.floats(-0.05, 0.05)),
)


def _kinetic_energy(robot: Robot, pose: np.ndarray, velocity: np.ndarray) -> float:
    """T = Σ ½m|v|² + ½I ω² of the 7 bodies from the core's inverse kinematics."""
    kin = inverse_kinematics(
        robot, Motion(t=0.0, pose=pose, velocity=velocity, acceleration=np.zeros(3))
    )
    omega = velocity[2]
    T = 0.5 * robot.piston.mass * float((kin.piston_velocity**2).sum())
    T += 0.5 * robot.link.mass * float((kin.link_velocity**2).sum())
    T += 0.5 * 3 * robot.link.inertia * omega**2
    T += 0.5 * robot.platform.mass * float(velocity[0] ** 2 + velocity[1] ** 2)
    T += 0.5 * robot.platform_inertia * omega**2
    return T


def _potential_energy(robot: Robot, pose: np.ndarray) -> float:
    """V = −Σ m g·r_C of the 7 bodies (centres of mass from the core's kinematics)."""
    kin = inverse_kinematics(robot, Motion.at_rest(pose))
    g = np.array(robot.gravity)
    V = -robot.piston.mass * float((kin.piston_com @ g).sum())
    V -= robot.link.mass * float((kin.link_com @ g).sum())
    return V - robot.platform.mass * float(pose[:2] @ g)


@settings(max_examples=40, deadline=None)
@given(robot=robots, pose=poses, velocity=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3))
def test_mass_matrix_is_the_kinetic_energy(robot: Robot, pose, velocity) -> None:  # type: ignore[no-untyped-def]
    pose, velocity = np.array(pose), np.array(velocity)
    eq = platform_dynamics(robot, pose, velocity)
    M = eq.mass_matrix
    scale = np.abs(M).max()
    np.testing.assert_allclose(M, M.T, atol=1e-9 * scale)
    assert np.linalg.eigvalsh(0.5 * (M + M.T)).min() > 0.0
    T = _kinetic_energy(robot, pose, velocity)
    assert abs(0.5 * velocity @ M @ velocity - T) <= 1e-9 * max(T, 1e-12) + 1e-12


@settings(max_examples=25, deadline=None)
@given(robot=robots, pose=poses)
def test_bias_at_rest_is_the_gradient_of_the_potential(robot: Robot, pose) -> None:  # type: ignore[no-untyped-def]
    pose = np.array(pose)
    if not regular(pose[2], 0.05):
        return
    h = 1e-6
    gradient = np.array(
        [
            (_potential_energy(robot, pose + h * e) - _potential_energy(robot, pose - h * e))
            / (2 * h)
            for e in np.eye(3)
        ]
    )
    eq = platform_dynamics(robot, pose, np.zeros(3))
    np.testing.assert_allclose(eq.bias, gradient, rtol=1e-6, atol=1e-6)


def test_platform_dynamics_batch_matches_single_samples() -> None:
    motion = paper_motion("vertical", samples=5)
    batch = platform_dynamics(ROBOT, motion.pose, motion.velocity)
    assert batch.force_matrix.shape == (5, 3, 3) and batch.force_bias.shape == (5, 3)
    for k in range(5):
        one = platform_dynamics(ROBOT, motion.pose[k], motion.velocity[k])
        np.testing.assert_allclose(one.force_matrix, batch.force_matrix[k], rtol=1e-14, atol=1e-12)
    # f10 = A·q̈ + b reproduces the inverse dynamics
    _, dyn = inverse_dynamics(ROBOT, motion)
    f10 = (batch.force_matrix @ motion.acceleration[..., None])[..., 0] + batch.force_bias
    np.testing.assert_allclose(f10, dyn.f10, atol=1e-12)


# ----------------------------------------------------------- forward dynamics
def _exact_forces(name: str):  # type: ignore[no-untyped-def]
    """f10(t) of the paper's motion (eq. 4) by the core's kernel at any t (one sample)."""
    star = np.array(PAPER_MOTIONS[name])
    w = math.pi / 3.0
    compiled = compile_robot(ROBOT)

    def f10(t: float) -> tuple[float, float, float]:
        return sample_actuator_forces(
            compiled,
            star * (1.0 - math.cos(w * t)),
            star * w * math.sin(w * t),
            star * w * w * math.cos(w * t),
        )

    return f10


@pytest.mark.parametrize("name", ["vertical", "rotation"])
def test_forward_dynamics_reproduces_the_paper_motions(name: str) -> None:
    reference = paper_motion(name)
    result = forward_dynamics(
        ROBOT,
        _exact_forces(name),
        reference.t,
        reference.pose[0],
        reference.velocity[0],
        rtol=1e-11,  # the open loop grows errors like e^(6.18 t): at rtol 1e-10 they reach 1e-6
        atol=1e-14,
    )
    assert result.status == "completed"
    assert result.motion.pose.shape == (301, 3)
    error = max(
        np.abs(result.motion.pose - reference.pose).max(),
        np.abs(result.motion.velocity - reference.velocity).max(),
    )
    assert error <= 1e-6
    assert result.force_residual <= 1e-9


def test_forward_dynamics_from_sampled_forces() -> None:
    # The spline through 301 samples differs from the exact forces by ~1e-9 N; the
    # open-loop motion is unstable (~e^{6.2 t}), so compare over the first 2 s.
    reference = paper_motion("vertical")
    _, dyn = inverse_dynamics(ROBOT, reference)
    result = forward_dynamics(
        ROBOT,
        ActuatorForces(reference.t, dyn.f10),
        reference.t,
        reference.pose[0],
        reference.velocity[0],
    )
    assert result.status == "completed"
    early = reference.t <= 2.0
    assert np.abs(result.motion.pose[early] - reference.pose[early]).max() <= 1e-5
    np.testing.assert_allclose(result.dynamics.f10, dyn.f10, atol=1e-9)  # exact at the samples


def _time_to_reach(lam_end: float, force: float, robot: Robot) -> float:
    """Time for equal forces F on the three actuators (g = 0, from rest at φ = 0) to reach λ.

    By symmetry λ10_i = λ for all legs and G stays at 0 (eq. iii with Σ d⊥_i = 0);
    φ follows from 3λ = (3·l0/2)(tan(ψ/2) + 1/√3), ψ = φ − π/3, so
    dφ/dλ = 4/(l0·sec²(ψ/2)).  With c1 = c2 = 0 the kinetic energy is
    ½·m(λ)·λ̇², m(λ) = 3(m1 + m2) + (3·I2 + I3)·(dφ/dλ)², and the work of the
    forces is 3·F·λ, so λ̇ = √(6Fλ/m(λ)).  With λ = u²,
    t = ∫₀^√λ 2·√(m(u²)/(6F)) du.
    """
    l0 = robot.l0
    inertia = 3 * robot.link.inertia + robot.platform_inertia

    def mass(lam: float) -> float:
        psi = 2.0 * math.atan(2.0 * lam / l0 - 1.0 / math.sqrt(3.0))
        dphi = 4.0 / (l0 / math.cos(psi / 2.0) ** 2)
        return 3 * (robot.piston.mass + robot.link.mass) + inertia * dphi**2

    value, _ = quad(
        lambda u: 2.0 * math.sqrt(mass(u * u) / (6.0 * force)),
        0.0,
        math.sqrt(lam_end),
        epsabs=1e-14,
        epsrel=1e-12,
    )
    return float(value)


def test_forward_dynamics_stops_at_the_singularity() -> None:
    robot = Robot(gravity=(0.0, 0.0))
    force = 100.0
    result = forward_dynamics(
        robot, lambda t: np.full(3, force), np.linspace(0.0, 1.0, 11), [0, 0, 0], [0, 0, 0]
    )
    assert result.status == "singular"
    assert "singularity" in result.message and "\n" not in result.message
    # stop where sin(φ − π/3) = −SINGULARITY_STOP, i.e. ψ = −asin(2e-4)
    psi_stop = -math.asin(SINGULARITY_STOP)
    lam_stop = L0 / 2.0 * (math.tan(psi_stop / 2.0) + 1.0 / math.sqrt(3.0))
    assert result.t_stop == pytest.approx(_time_to_reach(lam_stop, force, robot), rel=1e-7)
    assert result.motion.t[-1] == result.t_stop
    assert result.motion.pose[-1, 2] == pytest.approx(math.pi / 3.0 + psi_stop, abs=1e-9)
    # a trial stage in the refused zone gets NaN (scipy rejects the step), not an error
    refused = np.array([0.0, 0.0, math.pi / 3.0 + 0.25 * psi_stop, 0.0, 0.0, 0.0])
    assert np.isnan(fw.state_derivative(robot, lambda t: np.zeros(3), 0.0, refused)).all()


def test_forward_dynamics_stops_at_the_stroke() -> None:
    robot = Robot(gravity=(0.0, 0.0), limits=Limits(stroke=(-0.05, 0.05)))
    result = forward_dynamics(
        robot, lambda t: np.full(3, 10.0), np.linspace(0.0, 1.0, 11), [0, 0, 0], [0, 0, 0]
    )
    assert result.status == "stroke"
    assert "upper stroke limit 0.05 m" in result.message
    assert result.t_stop == pytest.approx(_time_to_reach(0.05, 10.0, robot), rel=1e-7)
    assert result.kinematics.geometry.lambda10[-1] == pytest.approx(np.full(3, 0.05), abs=1e-9)
    assert result.motion.samples == int(np.sum(np.linspace(0.0, 1.0, 11) < result.t_stop)) + 1


def test_forward_dynamics_refuses_bad_input() -> None:
    still = [0.0, 0.0, 0.0]
    with pytest.raises(SingularPoseError, match="too near the singularity"):
        forward_dynamics(ROBOT, lambda t: np.zeros(3), [0, 1], [0, 0, math.pi / 3 + 1.5e-4], still)
    with pytest.raises(UnreachablePoseError):
        forward_dynamics(
            Robot(limits=Limits(stroke=(-0.01, 0.01))),
            lambda t: np.zeros(3),
            [0, 1],
            [0.0, 0.1, 0.0],
            still,
        )
    with pytest.raises(ParameterError, match=r"exceeds limits\.max_force = 10\.0 N"):
        forward_dynamics(
            Robot(limits=Limits(max_force=10.0)), lambda t: np.full(3, 20.0), [0, 1], still, still
        )
    forces = ActuatorForces(t=[0.0, 1.0], f10=np.zeros((2, 3)))
    with pytest.raises(ParameterError, match="within the force samples"):
        forward_dynamics(ROBOT, forces, [0.0, 2.0], still, still)
    with pytest.raises(TrajectoryError, match="strictly increasing"):
        ActuatorForces(t=[0.0, 0.0], f10=np.zeros((2, 3)))
    with pytest.raises(ParameterError, match="rtol"):
        forward_dynamics(ROBOT, forces, [0.0, 1.0], still, still, rtol=0.0)
