"""The equations of motion in platform coordinates, ``f10 = A(q)·q̈ + b(q, q̇)``.

The actuator forces are affine in the platform acceleration: ``b`` is ``f10``
of the inverse dynamics (eq. 23) at ``q̈ = 0`` and the columns of ``A`` are
``f10(q̈ = unit) − b``.  ``M = Jᵀ·A`` is the (symmetric, positive definite)
mass matrix in platform coordinates, because ``Σ f10·λ̇10 = q̇ᵀ·(M·q̈ + h)``
with ``h = Jᵀ·b`` (``J = ∂λ10/∂(x, y, φ)``,
:func:`prp3.mechanics.kinematics.jacobian`, from eq. 14).
:func:`prp3.analysis.forward.forward_dynamics` integrates ``q̈ = A⁻¹·(f10(t) − b)``.

Loads and friction.  The payload adds to the platform's inertial parameters
and the constant ``[load]`` and the friction forces to the body wrenches, all
in the kernel (:func:`prp3.mechanics.wrenches.body_wrenches`), so ``A`` and ``b`` carry
them.  Viscous and Coulomb friction depend on the velocities only: at a given
``(q, q̇)`` they are part of ``b`` and ``f10`` stays exactly affine in ``q̈``.
The load-dependent ``μ`` terms make ``f10`` non-linear in ``q̈`` (the
reaction magnitudes depend on ``q̈``): the acceleration is then solved by chord
iterations on the kernel's ``f10`` (:func:`platform_accelerations`), and near a
self-locking pose, where ``f10(q, q̇, q̈) = f_applied`` has several or no
solutions, the step is rejected rather than a branch chosen.  Refused
(:func:`check_forward_friction`): Coulomb or ``μ`` friction with the exact
sign (``smoothing = 0``): ``s(v)`` jumps where a joint rate passes zero, the
motion is then not an ordinary differential equation (sticking needs a
complementarity problem).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.engines.compiled_robot import CompiledRobot, compile_robot
from prp3.engines.entries import actuator_forces, solve_batch
from prp3.errors import ParameterError, TrajectoryError
from prp3.mechanics.geometry import inverse_geometry
from prp3.mechanics.kinematics import jacobian
from prp3.model.motion import Motion
from prp3.model.parameters import Limits, Load
from prp3.model.robot import Robot
from prp3.pose_validation import check_poses
from prp3.validation import check_choice, check_per_leg, check_robot, check_same_shape

__all__ = [
    "SPACES",
    "PlatformDynamics",
    "bias_forces",
    "check_forward_friction",
    "gravity_forces",
    "mass_matrix",
    "open_loop_growth_rate",
    "platform_dynamics",
]

FloatArray = NDArray[np.float64]


def without_limits(robot: Robot) -> Robot:
    """The same robot with no stroke or force limit (the dynamics do not use them)."""
    if robot.limits == Limits():
        return robot
    return replace(robot, limits=Limits())


@dataclass(frozen=True)
class PlatformDynamics:
    """Equations of motion in platform coordinates ``q = (x, y, φ)``.

    ``f10 = force_matrix·q̈ + force_bias`` and, multiplied by ``Jᵀ``,
    ``Jᵀ·f10 = mass_matrix·q̈ + bias`` (virtual work of the actuators).

    Attributes
    ----------
    force_matrix : ndarray (..., 3, 3)
        ``A = ∂f10/∂q̈`` (N per m/s², N per rad/s²); depends on ``q`` only.
    force_bias : ndarray (..., 3)
        ``b = f10`` at ``q̈ = 0`` (N): gravity and velocity terms (eq. 23).
    mass_matrix : ndarray (..., 3, 3)
        ``M = Jᵀ·A``, symmetric positive definite (kg, kg·m, kg·m²).
    bias : ndarray (..., 3)
        ``h = Jᵀ·b`` (N, N, N·m).
    jacobian : ndarray (..., 3, 3)
        ``J = ∂λ10/∂q``.
    """

    force_matrix: FloatArray
    force_bias: FloatArray
    mass_matrix: FloatArray
    bias: FloatArray
    jacobian: FloatArray


def platform_dynamics(
    robot: Robot, pose: ArrayLike, velocity: ArrayLike, *, load: ArrayLike | None = None
) -> PlatformDynamics:
    """Build ``f10 = A(q)·q̈ + b(q, q̇)`` from the inverse dynamics (eq. 23).

    The actuator forces are affine in the platform acceleration, so four
    evaluations of :func:`~prp3.analysis.inverse_dynamics.kernel_method` per state — at
    ``q̈ = 0`` and at the three unit accelerations, one batch of ``4·N``
    samples — give ``b`` and the columns of ``A``.  The payload enters ``A``
    and ``b``, the constant load and the viscous and (smoothed) Coulomb
    friction enter ``b`` only (they do not depend on ``q̈``).

    Raises
    ------
    ParameterError
        Friction :func:`check_forward_friction` refuses.

    Parameters
    ----------
    robot : Robot
    pose, velocity : array_like, shape (3,) or (N, 3)
        Platform states.
    load : array_like, shape of ``pose``, optional
        A time-varying wrench ``(f_x, f_y, m_z)`` on the platform (added to the
        constant ``[load]``); it enters ``b`` only.

    Returns
    -------
    PlatformDynamics

    Examples
    --------
    >>> eq = platform_dynamics(Robot(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    >>> bool(np.allclose(eq.mass_matrix, eq.mass_matrix.T, atol=1e-12))
    True
    >>> eq.force_bias.round(4).tolist()   # the static forces of the central configuration
    [31.8589, -8.4957, -23.3632]
    """
    check_robot(robot)
    check_forward_friction(robot)
    compiled = compile_robot(robot)
    _check_affine(compiled)
    return _platform_dynamics(compiled, pose, velocity, load)


def _platform_dynamics(
    compiled: CompiledRobot, pose: ArrayLike, velocity: ArrayLike, load: ArrayLike | None = None
) -> PlatformDynamics:
    """:func:`platform_dynamics` of a robot compiled once (the integrator calls it per step)."""
    robot = compiled.robot
    q = check_poses(pose, robot)
    qdot = check_per_leg("velocity", velocity)
    check_same_shape("velocity", qdot, q, "pose")
    wrench = None
    if load is not None:
        given = check_per_leg("load", load)
        check_same_shape("load", given, q, "pose")
        wrench = np.repeat(given.reshape(-1, 1, 3), 4, axis=1).reshape(-1, 3)  # enters b only
    batch = q.shape[:-1]
    flat_q = np.repeat(q.reshape(-1, 1, 3), 4, axis=1)  # (n, 4, 3)
    flat_v = np.repeat(qdot.reshape(-1, 1, 3), 4, axis=1)
    unit = np.zeros((4, 3))
    unit[1:] = np.eye(3)  # q̈ = 0, e_x, e_y, e_φ
    flat_a = np.broadcast_to(unit, flat_q.shape)
    count = flat_q.shape[0] * 4
    motion = Motion(
        t=np.arange(float(count)),
        pose=flat_q.reshape(count, 3),
        velocity=flat_v.reshape(count, 3),
        acceleration=flat_a.reshape(count, 3),
    )
    if wrench is None:  # f10 alone: a few states by the traced single-sample code
        forces = actuator_forces(compiled, motion.pose, motion.velocity, motion.acceleration)
    else:
        forces = solve_batch(
            compiled, motion.pose, motion.velocity, motion.acceleration, load=wrench
        )["f10"]
    if not np.isfinite(forces).all():
        raise TrajectoryError(
            "platform_dynamics: the actuator forces overflow at this state", subject=LOST_MEANING
        )
    f10 = forces.reshape(-1, 4, 3)  # eq. (23)
    b = f10[:, 0, :]
    A = np.swapaxes(f10[:, 1:, :] - b[:, None, :], -1, -2)  # column k = f10(e_k) − b
    _check_resolved(A, f10, robot.l0)
    J = jacobian(inverse_geometry(robot, q.reshape(-1, 3)))
    Jt = np.swapaxes(J, -1, -2)
    return PlatformDynamics(
        force_matrix=A.reshape(*batch, 3, 3),
        force_bias=b.reshape(*batch, 3),
        mass_matrix=(Jt @ A).reshape(*batch, 3, 3),
        bias=(Jt @ b[..., None])[..., 0].reshape(*batch, 3),
        jacobian=J.reshape(*batch, 3, 3),
    )


#: ``A = f10(unit q̈) − b`` must keep this relative precision (its round-off
#: ``ε·|f10|`` against its smallest singular value): beyond, the bias forces swamp the
#: inertia and ``q̈ = A⁻¹·(f − b)`` has lost its meaning (a load of ``1e12 N`` on the
#: paper's robot).
MATRIX_PRECISION: float = 1e-4

#: The subject of the error :func:`_check_resolved` raises (forward dynamics tells it).
LOST_MEANING: str = "equations of motion"


def _check_resolved(A: FloatArray, f10: FloatArray, l0: float) -> None:
    """Refuse states whose ``A`` is round-off of the bias forces (``MATRIX_PRECISION``)."""
    scale = np.array([1.0, 1.0, 1.0 / l0])  # the rotation's column in N per (m/s²)
    noise = 16.0 * np.finfo(np.float64).eps * np.abs(f10).max(axis=(-1, -2))
    with np.errstate(all="ignore"):
        smallest = np.linalg.svd(A * scale, compute_uv=False)[..., -1]
    lost = ~(noise <= MATRIX_PRECISION * smallest)
    if lost.any():
        k = int(np.argmax(lost))
        raise TrajectoryError(
            f"the actuator forces |f10| = {float(np.abs(f10[k]).max()):.3g} N swamp the inertia "
            f"of the equations of motion (smallest singular value of A "
            f"{float(smallest[k]):.3g} kg): float64 keeps fewer than "
            f"{-math.log10(MATRIX_PRECISION):.0f} digits of A, q̈ = A⁻¹·(f10 − b) has no meaning",
            subject=LOST_MEANING,
        )


#: The spaces of :func:`mass_matrix`, :func:`bias_forces`, :func:`gravity_forces`.
SPACES: tuple[str, ...] = ("actuator", "platform")


def _at_rest(robot: Robot, pose: ArrayLike) -> FloatArray:
    """Poses validated, and the zero velocities of their shape."""
    check_robot(robot)
    return np.zeros_like(check_poses(pose, robot))


def mass_matrix(robot: Robot, pose: ArrayLike, *, space: str = "actuator") -> FloatArray:
    """The inertia of the equations of motion at ``pose``, shape ``(3, 3)`` or ``(N, 3, 3)``.

    ``space="actuator"`` (default): ``A(q) = ∂f10/∂q̈``, the actuator forces
    per unit platform acceleration, so that the inverse dynamics is
    ``f10 = A(q)·q̈ + b(q, q̇)`` (:func:`bias_forces`; eq. 23, as
    :func:`platform_dynamics` builds it).  ``space="platform"``: the mass
    matrix ``M(q) = Jᵀ·A`` of the platform coordinates ``(x, y, φ)``,
    symmetric positive definite, as ``pinocchio.crba`` gives it for a serial
    robot (``Jᵀ·f10 = M·q̈ + Jᵀ·b``).  The payload is included.

    Raises
    ------
    SingularPoseError, UnreachablePoseError, TrajectoryError, ParameterError
        A singular pose, one outside ``robot.limits.stroke``, a bad shape or
        value; friction :func:`check_forward_friction` refuses; ``space``
        not one of ``"actuator"``, ``"platform"``.

    >>> A = mass_matrix(Robot(), [0.0, 0.0, 0.0])
    >>> A.shape, mass_matrix(Robot(), [[0.0, 0.0, 0.0]] * 2).shape
    ((3, 3), (2, 3, 3))
    >>> M = mass_matrix(Robot(), [0.0, 0.0, 0.0], space="platform")
    >>> bool(np.allclose(M, M.T, rtol=0.0, atol=1e-12)), bool((np.linalg.eigvalsh(M) > 0).all())
    (True, True)
    """
    check_choice("space", space, SPACES)
    eq = platform_dynamics(robot, pose, _at_rest(robot, pose))
    return eq.force_matrix if space == "actuator" else eq.mass_matrix


def bias_forces(
    robot: Robot, pose: ArrayLike, velocity: ArrayLike, *, space: str = "actuator"
) -> FloatArray:
    """The forces of the equations of motion at zero acceleration, shape ``(3,)`` or ``(N, 3)``.

    ``space="actuator"`` (default): ``b(q, q̇) = f10`` at ``q̈ = 0`` (N):
    gravity, the velocity terms, the constant ``[load]`` and the viscous and
    smoothed Coulomb friction, so that ``f10 = A(q)·q̈ + b(q, q̇)``
    (:func:`mass_matrix`).  ``space="platform"``: ``Jᵀ·b`` (N, N, N·m), the
    platform-space bias, as ``pinocchio.nonLinearEffects`` gives it for a
    serial robot.

    Raises
    ------
    As :func:`mass_matrix`; ``velocity`` of another shape than ``pose``.

    >>> bias_forces(Robot(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]).round(4).tolist()
    [31.8589, -8.4957, -23.3632]
    """
    check_choice("space", space, SPACES)
    eq = platform_dynamics(robot, pose, velocity)
    return eq.force_bias if space == "actuator" else eq.bias


def gravity_forces(robot: Robot, pose: ArrayLike, *, space: str = "actuator") -> FloatArray:
    """The actuator forces that hold the robot still against gravity, shape ``(3,)`` or ``(N, 3)``.

    ``space="actuator"`` (default): ``g(q) = f10`` at rest (``q̇ = q̈ = 0``)
    of the robot without its external ``[load]`` and friction: the weight
    of the bodies and of the payload alone (N).  ``space="platform"``:
    ``Jᵀ·g`` (N, N, N·m), as ``pinocchio.computeGeneralizedGravity`` gives it
    for a serial robot.  Without a load, ``g = b(q, 0)`` (:func:`bias_forces`).

    Raises
    ------
    As :func:`mass_matrix` (without the friction refusals: friction is left out).

    >>> gravity_forces(Robot(), [0.0, 0.0, 0.0]).round(4).tolist()
    [31.8589, -8.4957, -23.3632]
    >>> gravity_forces(Robot(gravity=(0.0, 0.0)), [0.01, 0.02, 0.1]).tolist()
    [0.0, 0.0, 0.0]
    """
    check_choice("space", space, SPACES)
    check_robot(robot)
    weight_only = replace(robot, load=Load(), friction=None)
    eq = platform_dynamics(weight_only, pose, _at_rest(weight_only, pose))
    return eq.force_bias if space == "actuator" else eq.bias


#: Step of the central differences of :func:`open_loop_growth_rate`, as a fraction of ``l0``
#: (m) and in rad.
_GROWTH_STEP: float = 1e-5


def open_loop_growth_rate(robot: Robot, pose: ArrayLike) -> float:
    """Rate (1/s) at which errors grow when constant forces hold the platform still at ``pose``.

    Open-loop force control: the actuators apply the forces that hold the
    platform at rest at ``pose``, ``f = b(q, 0)``.  Linearised there,
    ``δq̈ = K·δq`` with ``K = −A⁻¹·∂b/∂q`` (:func:`platform_dynamics`; at rest
    the velocity terms of ``b`` are quadratic, and ``f − b = 0`` removes the
    change of ``A``), so the motion has the rates ``±√μ`` for the eigenvalues
    ``μ`` of ``K``.  The result is the largest real part: errors of the
    initial state, of the forces or of the integration grow like
    ``e^{rate·t}``; ``0`` means no exponential growth (e.g. without gravity).
    ``∂b/∂q`` is taken by central differences (steps ``1e-5·l0`` m and
    ``1e-5`` rad; relative error about 1e-9).

    Parameters
    ----------
    robot : Robot
    pose : array_like, shape (3,)
        ``(x, y, φ)``, not singular.

    Returns
    -------
    float
        The growth rate (1/s), ``>= 0``.

    Examples
    --------
    >>> round(open_loop_growth_rate(Robot(), [0.0, 0.0, 0.0]), 2)   # gravity on: a saddle
    6.18
    >>> open_loop_growth_rate(Robot(gravity=(0.0, 0.0)), [0.0, 0.0, 0.0])
    0.0
    """
    check_robot(robot)
    q = check_poses(pose, robot)
    if q.shape != (3,):
        raise TrajectoryError(f"pose must have shape (3,), got {q.shape}")
    # at rest every friction force of the model vanishes (s(0) = 0, no viscous force), so
    # A and b(q, 0) are those of the robot without friction, whatever its friction law
    free = replace(without_limits(robot), friction=None)
    steps = np.array([_GROWTH_STEP * robot.l0, _GROWTH_STEP * robot.l0, _GROWTH_STEP])
    shifts = np.concatenate([np.diag(steps), -np.diag(steps)])  # (6, 3): +h e_k, then −h e_k
    poses = np.concatenate([q[None, :], q + shifts])
    eq = platform_dynamics(free, poses, np.zeros_like(poses))
    gradient = (eq.force_bias[1:4] - eq.force_bias[4:7]).T / (2.0 * steps)  # ∂b/∂q, (3, 3)
    stiffness = -np.linalg.solve(eq.force_matrix[0], gradient)
    mu = np.linalg.eigvals(stiffness).astype(np.complex128)
    rate = float(np.sqrt(mu).real.max())
    # round-off of the differences (|μ| ~ 1e-9·|K| when K = 0) is no growth
    floor = math.sqrt(1e-8 * max(float(np.abs(stiffness).max()), 1e-300))
    return rate if rate > floor else 0.0


def check_forward_friction(robot: Robot) -> None:
    """Refuse the elements forward dynamics cannot integrate (module notes).

    Each of the robot's elements checks itself
    (:meth:`prp3.model.element_base.Element.check_forward`); today only friction refuses
    anything.  The sign of a Coulomb or ``μ`` term must be smoothed: with the exact sign
    the joint force jumps where the joint velocity changes sign, and the
    equations of motion have no unique acceleration there.

    Raises
    ------
    ParameterError
        A Coulomb or ``μ`` term with the exact sign (``coulomb > 0`` or
        ``mu > 0`` with ``smoothing = 0``); the message names the table and key.

    >>> from prp3.model.parameters import Friction, JointFriction
    >>> check_forward_friction(Robot(friction=Friction(actuator=JointFriction(coulomb=1.0))))
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: friction.actuator.coulomb = 1.0 N with smoothing = 0 (the exact sign): forward dynamics needs friction.actuator.smoothing > 0
    """
    for element in robot.elements:  # each element says what forward dynamics cannot take
        element.check_forward(robot)


def _check_affine(compiled: CompiledRobot) -> None:
    """Refuse ``μ`` terms where the affine form ``f10 = A·q̈ + b`` is asked for."""
    if compiled.parameters.has_mu:
        raise ParameterError(
            "friction mu terms make f10 non-affine in the acceleration, so it has no "
            "A(q)·q̈ + b(q, q̇) form; forward_dynamics solves them iteratively",
            subject="robot",
        )


#: Largest number of chord iterations of :func:`platform_accelerations` (``μ`` terms).
MU_CHORD_ITERATIONS: int = 60


def platform_accelerations(
    compiled: CompiledRobot,
    q: FloatArray,
    qdot: FloatArray,
    applied: FloatArray,
    load: FloatArray | None = None,
) -> FloatArray:
    """The platform acceleration ``q̈`` at which the actuator forces are ``applied``.

    Without ``μ`` terms ``f10`` is affine in ``q̈`` and one solve of
    ``A·q̈ = f − b`` (:func:`_platform_dynamics`) is exact.  The ``μ`` terms
    (friction proportional to the joint reactions, which depend on ``q̈``)
    make ``f10(q̈)`` non-linear: from that first solve, chord iterations
    ``q̈ ← q̈ + A⁻¹·(f − f10(q̈))`` with the kernel's ``f10`` (its own Newton
    solve of the ``μ`` terms) run until the residual is round-off
    (``1e-12`` of the force scale), at most :data:`MU_CHORD_ITERATIONS`.

    Raises
    ------
    TrajectoryError
        The iterations do not converge, or the friction locks (no motion has
        these forces: the friction cone swallows the drive).
    """
    eq = _platform_dynamics(compiled, q, qdot, load)
    try:
        qddot = np.linalg.solve(eq.force_matrix, (applied - eq.force_bias)[..., None])[..., 0]
    except np.linalg.LinAlgError:  # _check_resolved keeps this from happening
        raise TrajectoryError(
            "the matrix A of the equations of motion is singular", subject=LOST_MEANING
        ) from None
    if not np.isfinite(qddot).all():
        raise TrajectoryError(
            "the platform acceleration q̈ = A⁻¹·(f10 − b) overflows", subject=LOST_MEANING
        )
    if not compiled.parameters.has_mu:
        return np.asarray(qddot, dtype=np.float64)
    scale = 1.0 + np.maximum(np.abs(applied).max(axis=-1), np.abs(eq.force_bias).max(axis=-1))
    for _ in range(MU_CHORD_ITERATIONS):
        if load is None:
            f10 = actuator_forces(compiled, q, qdot, qddot)
        else:
            f10 = solve_batch(compiled, q, qdot, qddot, load=load)["f10"]
        residual = applied - f10
        if (np.abs(residual).max(axis=-1) <= 1e-12 * scale).all():
            return np.asarray(qddot, dtype=np.float64)
        qddot = qddot + np.linalg.solve(eq.force_matrix, residual[..., None])[..., 0]
    raise TrajectoryError(
        f"the acceleration under the friction's mu terms did not converge in "
        f"{MU_CHORD_ITERATIONS} iterations (near a self-locking joint)",
        subject="forward dynamics",
    )
