"""Direct problems: forward geometry, forward kinematics and forward dynamics.

The paper solves the inverse problems only (pose → actuators → forces).  This
module solves the direct ones, each by a route that the tests hold against the
inverse problems of :mod:`prp3.mechanics.geometry`, :mod:`prp3.mechanics.kinematics` and
:mod:`prp3.analysis.inverse_dynamics`.

The forward geometry (closed form, eqs. (i)–(iii)) is in :mod:`prp3.mechanics.geometry`,
next to the inverse one; its names are importable from here too.

Forward kinematics and dynamics
-------------------------------
With the Jacobian ``J = ∂λ10/∂(x, y, φ)`` (:func:`prp3.mechanics.kinematics.jacobian`,
from eq. 14), ``q̇ = J⁻¹·λ̇10`` and ``q̈ = J⁻¹·(λ̈10 − J̇·q̇)``, where ``J̇·q̇`` is
the ``λ̈10`` of eq. (17) at zero platform acceleration.  The actuator forces
are affine in the platform acceleration, ``f10 = A(q)·q̈ + b(q, q̇)``: ``b``
is ``f10`` of the inverse dynamics (eq. 23) at ``q̈ = 0`` and the columns of
``A`` are ``f10(q̈ = unit) − b``.  ``M = Jᵀ·A`` is the (symmetric, positive
definite) mass matrix in platform coordinates, because
``Σ f10·λ̇10 = q̇ᵀ·(M·q̈ + h)`` with ``h = Jᵀ·b``.  :func:`forward_dynamics`
integrates ``q̈ = A⁻¹·(f10(t) − b)`` with ``scipy.integrate.solve_ivp``.

Loads and friction.  The payload adds to the platform's inertial parameters
and the constant ``[load]`` and the friction forces to the body wrenches, all
in the kernel (:func:`prp3.mechanics.kernel.body_wrenches`), so ``A`` and ``b`` carry
them.  Viscous and Coulomb friction depend on the velocities only: at a given
``(q, q̇)`` they are part of ``b`` and ``f10`` stays exactly affine in ``q̈``.
The load-dependent ``μ`` terms make ``f10`` non-linear in ``q̈`` (the
reaction magnitudes depend on ``q̈``): the acceleration is then solved by chord
iterations on the kernel's ``f10`` (:func:`_accelerations`), and near a
self-locking pose, where ``f10(q, q̇, q̈) = f_applied`` has several or no
solutions, the step is rejected rather than a branch chosen.  Refused
(:func:`check_forward_friction`): Coulomb or ``μ`` friction with the exact
sign (``smoothing = 0``): ``s(v)`` jumps where a joint rate passes zero, the
motion is then not an ordinary differential equation (sticking needs a
complementarity problem).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.analysis.inverse_dynamics import InverseDynamics, kernel_method
from prp3.engines.entries import CompiledRobot, actuator_forces, compile_robot, solve_batch
from prp3.errors import (
    ParameterError,
    Prp3Error,
    SingularPoseError,
    TrajectoryError,
)
from prp3.mechanics.geometry import (
    DEGENERATE_ASSEMBLY,
    LEGS,
    SINGULARITY_THRESHOLD,
    ForwardGeometry,
    forward_geometry,
    inverse_geometry,
    orientation_from_sum,
    singularity_measure,
    sum_from_orientation,
)
from prp3.mechanics.kinematics import Kinematics, inverse_kinematics, jacobian
from prp3.model.motion import Motion
from prp3.model.robot import Limits, Load, Robot
from prp3.validation import (
    check_choice,
    check_finite,
    check_per_leg,
    check_poses,
    check_real,
    check_robot,
    check_same_shape,
    check_scalar,
    check_times,
)

__all__ = [
    "DEGENERATE_ASSEMBLY",
    "MIN_RTOL",
    "SINGULARITY_STOP",
    "SPACES",
    "ActuatorForces",
    "ForwardDynamics",
    "ForwardGeometry",
    "PlatformDynamics",
    "bias_forces",
    "check_forward_friction",
    "forward_acceleration",
    "forward_dynamics",
    "forward_geometry",
    "forward_kinematics",
    "forward_velocity",
    "gravity_forces",
    "mass_matrix",
    "open_loop_growth_rate",
    "orientation_from_sum",
    "platform_dynamics",
    "sum_from_orientation",
]

FloatArray = NDArray[np.float64]
ForceFunction = Callable[[float], ArrayLike]
Status = Literal["completed", "singular", "stroke", "failed"]

#: Smallest relative tolerance of :func:`forward_dynamics` (scipy raises smaller ones to it).
MIN_RTOL: float = 100.0 * float(np.finfo(np.float64).eps)

#: :func:`forward_dynamics` stops when ``|sin(φ − π/3)|`` falls to this value
#: (twice :data:`~prp3.mechanics.geometry.SINGULARITY_THRESHOLD`, so that the stop pose
#: itself is still one prp3 computes with).
SINGULARITY_STOP: float = 2.0 * SINGULARITY_THRESHOLD

_SQRT3 = math.sqrt(3.0)


# --------------------------------------------------------------------- helpers
def _float_array(name: str, value: ArrayLike) -> FloatArray:
    """``value`` as a new float64 array (:func:`prp3.validation.check_real`)."""
    return check_real(name, value, TrajectoryError)


def _without_limits(robot: Robot) -> Robot:
    """The same robot with no stroke or force limit (the dynamics do not use them)."""
    if robot.limits == Limits():
        return robot
    return replace(robot, limits=Limits())


def _dummy_times(batch: tuple[int, ...]) -> FloatArray:
    """Strictly increasing placeholder times for a Motion used as a batch of states."""
    if batch == ():
        return np.asarray(0.0)
    return np.arange(float(batch[0]))


# ---------------------------------------------------------- forward kinematics
def forward_velocity(robot: Robot, pose: ArrayLike, dlambda10: ArrayLike) -> FloatArray:
    """Platform velocity ``(ẋ, ẏ, φ̇) = J⁻¹·λ̇10`` (eq. 14 solved for the platform).

    Parameters
    ----------
    robot : Robot
    pose : array_like, shape (3,) or (N, 3)
        Platform poses (m, m, rad).
    dlambda10 : array_like, same shape as ``pose``
        Actuator velocities (m/s).

    Returns
    -------
    ndarray, same shape as ``pose``
        ``(ẋ, ẏ, φ̇)`` (m/s, m/s, rad/s).

    Equal actuator speeds turn the platform about ``G`` (``Σλ̇10 = l0·φ̇`` at ``φ = 0``):

    >>> (forward_velocity(Robot(), [0.0, 0.0, 0.0], [0.01, 0.01, 0.01]).round(12) + 0.0).tolist()
    [0.0, 0.0, 0.1]
    """
    geo = inverse_geometry(robot, pose)
    rates = check_per_leg("dlambda10", dlambda10)
    check_same_shape("dlambda10", rates, geo.pose, "pose")
    return np.asarray(np.linalg.solve(jacobian(geo), rates[..., None])[..., 0])


def forward_acceleration(
    robot: Robot, pose: ArrayLike, velocity: ArrayLike, ddlambda10: ArrayLike
) -> FloatArray:
    """Platform acceleration ``q̈ = J⁻¹·(λ̈10 − J̇·q̇)`` (eq. 17 solved for the platform).

    ``J̇·q̇`` is the actuator acceleration of eq. (17) at zero platform
    acceleration (:func:`~prp3.mechanics.kinematics.inverse_kinematics` with ``q̈ = 0``).

    Parameters
    ----------
    robot : Robot
    pose, velocity : array_like, shape (3,) or (N, 3)
        Platform poses and velocities ``(ẋ, ẏ, φ̇)``.
    ddlambda10 : array_like, same shape
        Actuator accelerations (m/s²).

    Returns
    -------
    ndarray, same shape as ``pose``
        ``(ẍ, ÿ, φ̈)`` (m/s², m/s², rad/s²).
    """
    check_robot(robot)
    pose_array = check_poses(pose, robot)
    accelerations = check_per_leg("ddlambda10", ddlambda10)
    speed = check_per_leg("velocity", velocity)
    check_same_shape("velocity", speed, pose_array, "pose")
    check_same_shape("ddlambda10", accelerations, pose_array, "pose")
    still = Motion(
        t=_dummy_times(pose_array.shape[:-1]),
        pose=pose_array,
        velocity=speed,
        acceleration=np.zeros_like(pose_array),
    )
    kin = inverse_kinematics(robot, still)
    bias = kin.ddlambda10  # J̇·q̇, eq. (17) with q̈ = 0
    return np.asarray(np.linalg.solve(kin.jacobian, (accelerations - bias)[..., None])[..., 0])


def forward_kinematics(
    robot: Robot,
    t: ArrayLike,
    lambda10: ArrayLike,
    dlambda10: ArrayLike,
    ddlambda10: ArrayLike,
) -> Motion:
    """Platform motion from the actuator displacements, velocities and accelerations.

    Chains :func:`forward_geometry`, :func:`forward_velocity` and
    :func:`forward_acceleration`; the inverse of
    :func:`~prp3.mechanics.kinematics.inverse_kinematics` (their round trip is tested).

    Parameters
    ----------
    robot : Robot
    t : array_like, shape (N,) or ()
        Sample times (s), strictly increasing.
    lambda10, dlambda10, ddlambda10 : array_like, shape (N, 3) or (3,)
        Actuator displacements (m), velocities (m/s), accelerations (m/s²).

    Returns
    -------
    Motion

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> robot = Robot()
    >>> kin = inverse_kinematics(robot, paper_motion("rotation", samples=5))
    >>> motion = forward_kinematics(robot, kin.motion.t, kin.geometry.lambda10,
    ...                             kin.dlambda10, kin.ddlambda10)
    >>> bool(np.allclose(motion.acceleration, kin.motion.acceleration, atol=1e-12))
    True
    """
    solution = forward_geometry(robot, lambda10)
    velocity = forward_velocity(robot, solution.pose, dlambda10)
    acceleration = forward_acceleration(robot, solution.pose, velocity, ddlambda10)
    return Motion(
        t=_float_array("t", t), pose=solution.pose, velocity=velocity, acceleration=acceleration
    )


# ------------------------------------------------------------- forward dynamics
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
        raise TrajectoryError("platform_dynamics: the actuator forces overflow at this state")
    f10 = forces.reshape(-1, 4, 3)  # eq. (23)
    b = f10[:, 0, :]
    A = np.swapaxes(f10[:, 1:, :] - b[:, None, :], -1, -2)  # column k = f10(e_k) − b
    J = jacobian(inverse_geometry(robot, q.reshape(-1, 3)))
    Jt = np.swapaxes(J, -1, -2)
    return PlatformDynamics(
        force_matrix=A.reshape(*batch, 3, 3),
        force_bias=b.reshape(*batch, 3),
        mass_matrix=(Jt @ A).reshape(*batch, 3, 3),
        bias=(Jt @ b[..., None])[..., 0].reshape(*batch, 3),
        jacobian=J.reshape(*batch, 3, 3),
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
    free = replace(_without_limits(robot), friction=None)
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
    (:meth:`prp3.model.elements.Element.check_forward`); today only friction refuses
    anything.  The sign of a Coulomb or ``μ`` term must be smoothed: with the exact sign
    the joint force jumps where the joint velocity changes sign, and the
    equations of motion have no unique acceleration there.

    Raises
    ------
    ParameterError
        A Coulomb or ``μ`` term with the exact sign (``coulomb > 0`` or
        ``mu > 0`` with ``smoothing = 0``); the message names the table and key.

    >>> from prp3.model.robot import Friction, JointFriction
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


#: Largest number of chord iterations of :func:`_accelerations` (``μ`` terms).
MU_CHORD_ITERATIONS: int = 60


def _accelerations(
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
    qddot = np.linalg.solve(eq.force_matrix, (applied - eq.force_bias)[..., None])[..., 0]
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


@dataclass(frozen=True)
class ActuatorForces:
    """Sampled actuator force histories ``f10(t)``, interpolated by a cubic spline.

    Between the samples the forces follow the not-a-knot cubic spline through
    them (``scipy.interpolate.CubicSpline``; a straight line for 2 samples):
    smooth, and exact at the samples.

    Attributes
    ----------
    t : ndarray (N,)
        Sample times (s), strictly increasing, ``N >= 2``.
    f10 : ndarray (N, 3)
        Forces of actuators A, B, C on their pistons along ``+e_i`` (N).
    load : ndarray (N, 3) or None
        A time-varying wrench of the environment on the platform at the same
        times, ``(f_x, f_y, m_z)`` (N at ``G``, fixed frame; N·m), added to the
        robot's constant ``[load]`` (the ``fx, fy, mz`` columns of a force
        file); interpolated like the forces (:meth:`load_at`).

    Examples
    --------
    >>> forces = ActuatorForces(t=[0.0, 1.0, 2.0], f10=[[0, 0, 0], [1, 2, 3], [2, 4, 6]])
    >>> forces(0.5).tolist()
    [0.5, 1.0, 1.5]
    """

    t: FloatArray
    f10: FloatArray
    load: FloatArray | None = None
    _spline: Any = field(init=False, repr=False, compare=False)
    _load_spline: Any = field(init=False, repr=False, compare=False, default=None)

    def __post_init__(self) -> None:
        t = check_times("t", self.t, minimum=2, subject="forces")
        f10 = check_real("f10", self.f10, subject="forces")
        if f10.shape != (t.size, 3):
            raise TrajectoryError(
                f"f10 must have shape ({t.size}, 3), got {f10.shape}", subject="forces"
            )
        check_finite("f10", f10, subject="forces")
        from scipy.interpolate import CubicSpline

        t.flags.writeable = False
        f10.flags.writeable = False
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "f10", f10)
        try:
            with np.errstate(all="ignore"):
                spline = CubicSpline(t, f10, axis=0)
        except ValueError:  # the slopes overflow: huge forces or tiny time steps
            with np.errstate(all="ignore"):
                slopes = np.diff(f10, axis=0) / np.diff(t)[:, None]
            index = int(np.argmax(~np.isfinite(slopes).all(axis=1)))
            raise _not_interpolable(t, index, "their rate of change") from None
        bad = ~np.isfinite(spline.c).all(axis=(0, 2))  # (4, N - 1, 3) coefficients per interval
        if bad.any():  # steps so small (1e-300 s) that the cubic terms overflow
            raise _not_interpolable(t, int(np.argmax(bad)), "the spline's coefficients")
        object.__setattr__(self, "_spline", spline)
        if self.load is not None:
            load = check_real("load", self.load, subject="forces")
            if load.shape != (t.size, 3):
                raise TrajectoryError(
                    f"load must have shape ({t.size}, 3) (fx, fy, mz), got {load.shape}",
                    subject="forces",
                )
            check_finite("load", load, subject="forces")
            load.flags.writeable = False
            object.__setattr__(self, "load", load)
            with np.errstate(all="ignore"):
                load_spline = CubicSpline(t, load, axis=0)
            bad = ~np.isfinite(load_spline.c).all(axis=(0, 2))
            if bad.any():
                raise _not_interpolable(t, int(np.argmax(bad)), "the load spline's coefficients")
            object.__setattr__(self, "_load_spline", load_spline)

    def __call__(self, time: float) -> FloatArray:
        """Forces ``(3,)`` at ``time`` (s), within ``[t[0], t[-1]]``."""
        return np.asarray(self._spline(time), dtype=np.float64)

    def load_at(self, time: float) -> FloatArray | None:
        """The load ``(f_x, f_y, m_z)`` at ``time`` (s) by its cubic spline, or ``None``.

        >>> forces = ActuatorForces(t=[0.0, 1.0], f10=np.zeros((2, 3)),
        ...                         load=[[0.0, -2.0, 0.0], [1.0, -2.0, 0.5]])
        >>> forces.load_at(0.5).tolist()
        [0.5, -2.0, 0.25]
        """
        if self._load_spline is None:
            return None
        return np.asarray(self._load_spline(time), dtype=np.float64)


def _not_interpolable(t: FloatArray, index: int, what: str) -> TrajectoryError:
    return TrajectoryError(
        f"the force samples cannot be interpolated: {what} overflow between t[{index}] = "
        f"{float(t[index])!r} and t[{index + 1}] = {float(t[index + 1])!r} s (forces too "
        "large or time steps too small)",
        subject="forces",
    )


@dataclass(frozen=True)
class ForwardDynamics:
    """Platform motion integrated from actuator forces.

    Attributes
    ----------
    motion : Motion
        Samples at the requested times up to the stop; when the integration
        stopped early, the stop instant is the last sample.  The acceleration
        is the model's ``A⁻¹·(f10 − b)`` at each sample.
    kinematics : Kinematics
        Inverse kinematics of :attr:`motion` (stroke limits not applied).
    dynamics : InverseDynamics
        Inverse dynamics of :attr:`motion` (paper's method); its ``f10``
        reproduces the input forces (see :attr:`force_residual`).
    status : {"completed", "singular", "stroke", "failed"}
        ``"completed"``: reached the last requested time.  ``"singular"``:
        ``|sin(φ − π/3)|`` fell to :data:`SINGULARITY_STOP`.  ``"stroke"``: an
        actuator reached an end of ``limits.stroke``.  ``"failed"``: the
        integrator gave up (its message is in :attr:`message`).
    message : str
        One line saying what happened.
    t_stop : float
        Last time reached (s).
    evaluations : int
        Evaluations of the equations of motion by the integrator.
    force_residual : float
        ``max |f10(inverse dynamics of motion) − f10(input)|`` over the samples (N).
    """

    motion: Motion
    kinematics: Kinematics
    dynamics: InverseDynamics
    status: Status
    message: str
    t_stop: float
    evaluations: int
    force_residual: float


def forward_dynamics(
    robot: Robot,
    forces: ActuatorForces | ForceFunction,
    t: ArrayLike,
    initial_pose: ArrayLike,
    initial_velocity: ArrayLike,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    load: ForceFunction | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> ForwardDynamics:
    """Integrate the platform motion driven by the actuator forces ``f10(t)``.

    The state ``(x, y, φ, ẋ, ẏ, φ̇)`` obeys ``q̈ = A(q)⁻¹·(f10(t) − b(q, q̇))``
    (:func:`platform_dynamics`), integrated by ``scipy.integrate.solve_ivp``
    with the explicit Runge–Kutta method ``DOP853``.  Terminal events stop the
    integration when ``|sin(φ − π/3)|`` falls to :data:`SINGULARITY_STOP` or,
    with ``robot.limits.stroke``, when an actuator reaches an end of its
    stroke.  The result then holds the motion up to the stop and says why.

    Parameters
    ----------
    robot : Robot
    forces : ActuatorForces or callable
        Sampled forces (cubic spline between samples) or a function
        ``f10(t) -> (3,)`` (N).
    t : array_like, shape (N,)
        Output times (s), strictly increasing, ``N >= 2``; the integration runs
        from ``t[0]`` to ``t[-1]``, within the samples of ``forces``.
    initial_pose, initial_velocity : array_like, shape (3,)
        State at ``t[0]``: ``(x, y, φ)`` and ``(ẋ, ẏ, φ̇)``; the pose must be
        within the strokes and farther than :data:`SINGULARITY_STOP` from the
        singularity.
    rtol, atol : float
        Tolerances of ``solve_ivp`` (relative; absolute in m, rad, m/s, rad/s).
    load : callable, optional
        A time-varying wrench of the environment on the platform,
        ``load(t) -> (f_x, f_y, m_z)`` (N at ``G``, fixed frame; N·m), added to
        the robot's constant ``[load]``.  Sampled forces carry theirs
        (:attr:`ActuatorForces.load`, interpolated like the forces); giving
        both is refused.
    progress : callable, optional
        ``progress(samples_reached, N)``: the output times the integration
        has reached (the furthest time evaluated), reported when it grows.

    Returns
    -------
    ForwardDynamics

    Raises
    ------
    TrajectoryError
        Bad times or initial state.
    SingularPoseError, UnreachablePoseError
        Initial pose singular (closer than ``SINGULARITY_STOP``) or outside the strokes.
    ParameterError
        Times outside the force samples; a sampled force beyond
        ``limits.max_force``; a force function that returns anything but 3
        finite numbers; non-positive tolerances or ``rtol < MIN_RTOL``;
        Coulomb friction with ``smoothing = 0`` or ``μ`` terms
        (:func:`check_forward_friction`).

    Notes
    -----
    The motion under open-loop forces is unstable: holding the platform still
    at the central configuration with constant forces (gravity on) is a
    saddle whose linearisation has the rates ``±6.18`` and ``±6.18i`` (1/s).
    Errors of the integration or of the force samples grow like ``e^{6.2 t}``
    (see ``docs/forward_and_workspace.md`` for measured round trips).

    Trial states that the integrator probes beyond the singular stop, where
    prp3 refuses to compute (``|sin(φ − π/3)| < 1e-4``), get a NaN derivative:
    the Runge–Kutta step is then rejected and retried with a smaller step
    (scipy's step control shrinks the step by its minimum factor when the
    error estimate is not a number).  A test drives the robot into the
    singularity to keep this honest.

    Examples
    --------
    >>> robot = Robot(gravity=(0.0, 0.0))
    >>> still = forward_dynamics(robot, lambda t: np.zeros(3), [0.0, 1.0],
    ...                          [0.0, 0.0, 0.0], [0.01, 0.0, 0.0])
    >>> still.status, still.motion.pose[-1].round(9).tolist()   # drifts at constant speed
    ('completed', [0.01, 0.0, 0.0])
    """
    check_robot(robot)
    check_forward_friction(robot)
    times = check_times("t", t, minimum=2)
    rtol, atol = _tolerances(rtol, atol)
    q0, v0, aspect = _initial_state(robot, initial_pose, initial_velocity)
    force_of = _force_function(robot, forces, times)
    load_of = _load_function(forces, load, times)
    free = _without_limits(robot)  # the stroke ends are events, not refusals
    stroke = robot.limits.stroke
    solution = _integrate(
        free, stroke, force_of, times, q0, v0, aspect, (rtol, atol), load_of, progress
    )
    if progress is not None:
        progress(times.size, times.size)
    stop = _stop(free, stroke, solution, times, q0, v0)
    if stop.status == "failed" and stop.t_stop <= float(times[0]):
        raise TrajectoryError(_failed_start(stop, force_of, q0, v0, load_of))
    return _result(free, force_of, stop, int(solution.nfev), load_of)


def _failed_start(
    stop: _Stop,
    force_of: Callable[[float], FloatArray],
    q0: FloatArray,
    v0: FloatArray,
    load_of: Callable[[float], FloatArray] | None,
) -> str:
    """The refusal of an integration that failed at its first step: nothing was integrated."""
    t0 = float(stop.t[0])
    forces = np.asarray(force_of(t0), dtype=np.float64).tolist()
    loads = "" if load_of is None else f", load {np.asarray(load_of(t0)).tolist()!r}"
    return (
        f"the integration fails at its first step (t = {t0!r} s): "
        f"{stop.message.split(': ', 1)[-1].rstrip('.')}; nothing was integrated: with the forces f10(t0) = {forces!r} N{loads}, the initial pose "
        f"{q0.tolist()!r} and the initial velocity {v0.tolist()!r} the equations of motion "
        "leave double precision (or the step size vanishes); give forces and velocities of the "
        "robot's size"
    )


# ------------------------------------------------------- steps of forward_dynamics
def _tolerances(rtol: object, atol: object) -> tuple[float, float]:
    """Step 1: the tolerances, finite and positive, ``rtol`` not below scipy's floor."""
    relative = check_scalar("rtol", rtol, positive=True)
    absolute = check_scalar("atol", atol, positive=True)
    if relative < MIN_RTOL:
        raise ParameterError(
            f"rtol must be at least {MIN_RTOL:.3g} (100 machine epsilons, scipy's floor), "
            f"got {relative!r}"
        )
    return relative, absolute


def _initial_state(
    robot: Robot, initial_pose: ArrayLike, initial_velocity: ArrayLike
) -> tuple[FloatArray, FloatArray, float]:
    """Step 2: the initial pose and velocity, and the aspect ``sign(sin(φ0 − π/3))``.

    The pose must be one prp3 computes with, inside the strokes, and farther
    than :data:`SINGULARITY_STOP` from the singularity.
    """
    q0 = check_poses(initial_pose, robot, "initial_pose")
    v0 = check_per_leg("initial_velocity", initial_velocity)
    if q0.shape != (3,) or v0.shape != (3,):
        raise TrajectoryError(
            "initial_pose and initial_velocity must be 3 numbers each, "
            f"got shapes {q0.shape} and {v0.shape}",
            subject="initial_pose",
        )
    try:
        inverse_geometry(robot, q0)  # refuses an out-of-stroke initial pose
    except Prp3Error as error:
        raise error.located(subject="initial_pose") from None
    D0 = float(singularity_measure(q0[2]))
    if abs(D0) <= SINGULARITY_STOP:
        x, y, phi = q0.tolist()
        raise SingularPoseError(
            f"singular pose (x={x!r}, y={y!r}, phi={phi!r}): too near the singularity, "
            f"|sin(phi - pi/3)| = {abs(D0):.3g} <= {SINGULARITY_STOP:g}",
            subject="initial_pose",
            pose=(x, y, phi),
        )
    return q0, v0, math.copysign(1.0, D0)


def _integrate(
    robot: Robot,
    stroke: tuple[float, float] | None,
    force_of: Callable[[float], FloatArray],
    times: FloatArray,
    q0: FloatArray,
    v0: FloatArray,
    aspect: float,
    tolerances: tuple[float, float],
    load_of: Callable[[float], FloatArray] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Any:
    """Step 3: ``solve_ivp`` (DOP853) of the state ``(q, q̇)``, with the terminal events."""
    from scipy.integrate import solve_ivp

    compiled = compile_robot(robot)
    reached = [0]

    def rhs(time: float, state: FloatArray) -> FloatArray:
        if progress is not None:
            done = int(np.searchsorted(times, time, side="right"))
            if done > reached[0]:
                reached[0] = done
                progress(min(done, times.size), times.size)
        return _state_derivative(compiled, force_of, time, state, load_of)

    def singular(_time: float, state: FloatArray) -> float:
        return aspect * math.sin(state[2] - math.pi / 3.0) - SINGULARITY_STOP

    events: list[Callable[[float, FloatArray], float]] = [singular]
    if stroke is not None:
        events += _stroke_events(robot, stroke)
    for event in events:
        event.terminal = True  # type: ignore[attr-defined]
        event.direction = -1.0  # type: ignore[attr-defined]
    with np.errstate(all="ignore"):  # trial states may overflow: NaN rejects the step
        return solve_ivp(
            rhs,
            (float(times[0]), float(times[-1])),
            np.concatenate([q0, v0]),
            method="DOP853",
            t_eval=times,
            events=events,
            rtol=tolerances[0],
            atol=tolerances[1],
        )


@dataclass(frozen=True)
class _Stop:
    """What the integration reached: the sample times and states, and why it ended."""

    t: FloatArray
    states: FloatArray
    status: Status
    message: str
    t_stop: float


def _stop(
    robot: Robot,
    stroke: tuple[float, float] | None,
    solution: Any,
    times: FloatArray,
    q0: FloatArray,
    v0: FloatArray,
) -> _Stop:
    """Step 4: the samples reached and the reason the integration ended."""
    sample_t = np.asarray(solution.t, dtype=np.float64)
    states = np.asarray(solution.y, dtype=np.float64).T
    status: Status
    if solution.status == 1:  # a terminal event: the singularity or a stroke end
        hit = next(k for k, found in enumerate(solution.t_events) if len(found))
        t_stop = float(solution.t_events[hit][0])
        stop_state = np.asarray(solution.y_events[hit][0], dtype=np.float64)
        if sample_t.size == 0 or t_stop > sample_t[-1]:
            sample_t = np.append(sample_t, t_stop)
            states = np.vstack([states, stop_state])
        status = "singular" if hit == 0 else "stroke"
        message = _stop_message(robot, hit, t_stop, stop_state, stroke)
    elif solution.status == 0:
        t_stop = float(times[-1])
        status, message = "completed", f"completed: integrated to t = {t_stop!r} s"
    else:
        t_stop = float(sample_t[-1]) if sample_t.size else float(times[0])
        status = "failed"
        message = f"integration failed after t = {t_stop!r} s: {solution.message}"
    if sample_t.size == 0:  # failed before the first sample: keep the initial state
        sample_t = times[:1]
        states = np.concatenate([q0, v0])[None, :]
    return _Stop(sample_t, states, status, message, t_stop)


def _result(
    robot: Robot,
    force_of: Callable[[float], FloatArray],
    stop: _Stop,
    evaluations: int,
    load_of: Callable[[float], FloatArray] | None = None,
) -> ForwardDynamics:
    """Step 5: the motion with the model's accelerations, its inverse problems and residual."""
    loads = None if load_of is None else np.stack([load_of(float(time)) for time in stop.t])
    applied = np.stack([np.asarray(force_of(float(time)), dtype=np.float64) for time in stop.t])
    compiled = compile_robot(robot)
    qddot = _accelerations(compiled, stop.states[:, :3], stop.states[:, 3:], applied, loads)
    motion = Motion(
        t=stop.t,
        pose=stop.states[:, :3],
        velocity=stop.states[:, 3:],
        acceleration=qddot,
        load=loads,
    )
    kin = inverse_kinematics(robot, motion)
    dyn = kernel_method(robot, kin)
    return ForwardDynamics(
        motion=motion,
        kinematics=kin,
        dynamics=dyn,
        status=stop.status,
        message=stop.message,
        t_stop=stop.t_stop,
        evaluations=evaluations,
        force_residual=float(np.abs(dyn.f10 - applied).max()),
    )


def _state_derivative(
    compiled: CompiledRobot,
    force_of: Callable[[float], FloatArray],
    time: float,
    state: FloatArray,
    load_of: Callable[[float], FloatArray] | None = None,
) -> FloatArray:
    """``(q̇, q̈)`` of the state ``(q, q̇)`` at ``time``; NaN in the refused zone.

    States with ``|sin(φ − π/3)| < SINGULARITY_THRESHOLD`` (only ever probed by
    a trial stage beyond the singular stop) and non-finite states get NaN,
    which makes the Runge–Kutta step's error estimate NaN: scipy rejects the
    step and retries it with a step shrunk by its minimum factor.
    """
    q, qdot = state[:3], state[3:]
    if not np.isfinite(state).all() or abs(math.sin(q[2] - math.pi / 3.0)) < (
        SINGULARITY_THRESHOLD
    ):
        return np.full(6, np.nan)
    applied, load = force_of(time), None if load_of is None else load_of(time)
    try:
        qddot = _accelerations(compiled, q, qdot, applied, load)
    except Prp3Error:  # a trial state beyond the bounds of prp3 (or a lock): reject the step
        return np.full(6, np.nan)
    return np.concatenate([qdot, qddot])


def _force_function(
    robot: Robot, forces: ActuatorForces | ForceFunction, times: FloatArray
) -> Callable[[float], FloatArray]:
    """Validate the forces against the time span and ``max_force``; return ``f10(t)``."""
    if isinstance(forces, ActuatorForces):
        first, last = float(forces.t[0]), float(forces.t[-1])
        if times[0] < first or times[-1] > last:
            raise ParameterError(
                f"t: the times [{float(times[0])!r}, {float(times[-1])!r}] s must lie within "
                f"the force samples [{first!r}, {last!r}] s"
            )
        sampled_t, sampled = forces.t, forces.f10
    elif callable(forces):
        sampled_t = times
        sampled = np.stack([np.asarray(forces(float(time)), dtype=np.float64) for time in times])
        if sampled.shape != (times.size, 3) or not np.isfinite(sampled).all():
            raise ParameterError("the function must return 3 finite forces (N)", subject="forces")
    else:
        raise ParameterError(
            f"forces must be ActuatorForces or a function of t, got {type(forces).__name__}"
        )
    limit = robot.limits.max_force
    if limit is not None:
        over = np.abs(sampled) > limit
        if over.any():
            index, leg = np.argwhere(over)[0].tolist()
            raise ParameterError(
                f"|f10_{LEGS[leg]}| = {abs(float(sampled[index, leg]))!r} N at "
                f"t = {float(sampled_t[index])!r} s exceeds limits.max_force = {limit!r} N",
                subject="forces",
                key="limits.max_force",
                leg=LEGS[leg],
            )
    function = forces

    def force_of(time: float) -> FloatArray:
        value = np.asarray(function(time), dtype=np.float64)
        if value.shape != (3,) or not np.isfinite(value).all():
            raise ParameterError(
                f"f10({time!r}) must be 3 finite forces (N), got {value.tolist()!r}",
                subject="forces",
            )
        return value

    return force_of


def _load_function(
    forces: ActuatorForces | ForceFunction, load: ForceFunction | None, times: FloatArray
) -> Callable[[float], FloatArray] | None:
    """The time-varying load ``(f_x, f_y, m_z)(t)``: the forces' own or ``load``; validated."""
    sampled = isinstance(forces, ActuatorForces) and forces.load is not None
    if load is None:
        if not sampled:
            return None
        assert isinstance(forces, ActuatorForces)
        spline = forces

        def of_samples(time: float) -> FloatArray:
            value = spline.load_at(time)
            assert value is not None
            return value

        return of_samples
    if sampled:
        raise ParameterError(
            "load: the sampled forces carry a load already (their fx, fy, mz); give one of the two",
            subject="forces",
        )
    if not callable(load):
        raise ParameterError(f"load must be a function of t, got {type(load).__name__}")
    function = load

    def load_of(time: float) -> FloatArray:
        value = np.asarray(function(time), dtype=np.float64)
        if value.shape != (3,) or not np.isfinite(value).all():
            raise ParameterError(
                f"load({time!r}) must be 3 finite numbers (fx, fy in N, mz in N·m), "
                f"got {value.tolist()!r}",
                subject="load",
            )
        return value

    for time in (float(times[0]), float(times[-1])):
        load_of(time)  # refused before the integration starts
    return load_of


def _lambda10_or_nan(robot: Robot, pose: FloatArray) -> FloatArray:
    try:
        return inverse_geometry(robot, pose).lambda10
    except Prp3Error:  # a refused pose: no stroke crossing reported there
        return np.full(3, np.nan)


def _stroke_events(
    robot: Robot, stroke: tuple[float, float]
) -> list[Callable[[float, FloatArray], float]]:
    lower, upper = stroke
    events: list[Callable[[float, FloatArray], float]] = []
    for leg in range(3):

        def below(_time: float, state: FloatArray, leg: int = leg) -> float:
            return float(_lambda10_or_nan(robot, state[:3])[leg]) - lower

        def above(_time: float, state: FloatArray, leg: int = leg) -> float:
            return upper - float(_lambda10_or_nan(robot, state[:3])[leg])

        events += [below, above]
    return events


def _stop_message(
    robot: Robot,
    hit: int,
    t_stop: float,
    state: FloatArray,
    stroke: tuple[float, float] | None,
) -> str:
    x, y, phi = state[:3].tolist()
    where = f"at t = {t_stop:.9g} s (x = {x:.6g} m, y = {y:.6g} m, phi = {phi:.9g} rad)"
    if hit == 0:
        return (
            f"stopped {where}: the platform reached the singularity, |sin(phi - pi/3)| = "
            f"{SINGULARITY_STOP:g} (singular at phi = pi/3 mod pi)"
        )
    assert stroke is not None
    leg, end = divmod(hit - 1, 2)
    value = float(inverse_geometry(robot, state[:3]).lambda10[leg])
    bound = ("lower", stroke[0]) if end == 0 else ("upper", stroke[1])
    return (
        f"stopped {where}: actuator {LEGS[leg]} reached its {bound[0]} stroke limit "
        f"{bound[1]!r} m (lambda10_{LEGS[leg]} = {value:.9g} m)"
    )
