"""Forward dynamics of a spatial robot: the platform motion driven by given efforts (docs/spatial.md §18).

The inverse dynamics of §8 is affine in the platform's acceleration: with the
platform's free acceleration components ``a_f`` (all six ``(α, a)`` for the
hexapod; the components of ``robot.parasitic``'s complement for the 3-RPS and
the Delta, the parasitic ones following from the legs' constraints, §11),

``τ = A(x, ξ)·a_f + h(x, ξ)``,

so :func:`spatial_platform_dynamics` evaluates route (a) at ``a_f = 0`` (``h``)
and at the unit accelerations ``a_f = e_j`` (``h + A[:, j]``: exact, the map
being affine).  With the actuated rates ``dq_act = J_a·ξ_f`` (``J_a`` the
parallel Jacobian on the free twist), the task-space equations of motion are
``M·a_f + b = J_aᵀ·τ`` with ``M = J_aᵀ·A`` the platform's mass matrix (symmetric
positive definite: ``½ ξ_fᵀ·M·ξ_f`` is the kinetic energy of every body) and
``b = J_aᵀ·h``.  :func:`spatial_forward_dynamics` integrates
``a_f = A⁻¹·(τ(t) − h)`` with ``scipy.integrate.solve_ivp`` (``DOP853``) on the
state ``(p, quaternion, ω, v)``, the quaternion renormalised at every evaluation
and the pose and twist completed onto the legs' constraints (§11) for a robot of
fewer than 6 DOF; it refuses a singular ``M`` and a crossing of a singularity
(the measures of §6 falling to :data:`SINGULARITY_STOP`) naming the time, and
stops at its bounds on evaluations and wall time saying which.

>>> from prp3.spatial.model import hexapod
>>> robot = hexapod()
>>> home = PlatformMotion.at_rest(robot.home_position)
>>> dynamics = spatial_platform_dynamics(robot, home)
>>> dynamics.mass.shape, bool(np.allclose(dynamics.mass, np.swapaxes(dynamics.mass, 1, 2)))
((1, 6, 6), True)
>>> run = spatial_forward_dynamics(robot, hold_efforts(robot), duration=0.5, samples=3)
>>> float(np.abs(run.motion.position - robot.home_position).max()) < 1e-12
True
"""

from __future__ import annotations

import math
import time as time_module
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.analysis.forward import MAX_EVALUATIONS, MAX_SECONDS, MIN_RTOL
from prp3.errors import (
    ParameterError,
    Prp3Error,
    SingularPoseError,
    TrajectoryError,
    UnreachablePoseError,
)
from prp3.spatial.dynamics import body_wrenches, chunk_efforts, virtual_work_efforts
from prp3.spatial.geometry import (
    JointLimit,
    attachments,
    chain_frames,
    leg_coordinates,
    limit_margin,
)
from prp3.spatial.kinematics import (
    chunk_kinematics,
    complete_motion,
    home_signs,
    leg_jacobians,
)
from prp3.spatial.model import TWIST_COMPONENTS, SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.outputs import SpatialSolution, spatial_inverse_dynamics
from prp3.spatial.rotations import cross, matrix_quaternion, quaternion_matrix
from prp3.validation import (
    check_instance,
    check_integer,
    check_real,
    check_scalar,
    check_times,
    checked_spline,
)

__all__ = [
    "MAX_ACCELERATION",
    "SINGULARITY_STOP",
    "SpatialForward",
    "SpatialPlatformDynamics",
    "hold_efforts",
    "spatial_forward_dynamics",
    "spatial_platform_dynamics",
    "state_from_joints",
]

FloatArray = NDArray[np.float64]

#: The integration is refused when a singularity measure (§6, times its sign at home)
#: falls to this value on the way (ten times the threshold ``SINGULAR`` of the inverse
#: problems, so that the poses before it are ones prp3 computes with).
SINGULARITY_STOP: float = 1e-3

#: A mass matrix whose condition number reaches this is refused as singular.
MAX_CONDITION: float = 1e12

#: The largest platform acceleration (m/s² and rad/s², about 10⁵ g) the efforts may
#: ask for at the initial state (§18): efforts that ask for more (1e6 N·m on the Delta,
#: 1e20, 1e308) are refused before the integration, which would otherwise crawl to its
#: time bound.
MAX_ACCELERATION: float = 1e6

#: A right-hand side whose acceleration is not finite or reaches this (a million times
#: :data:`MAX_ACCELERATION`) stops the integration with an error naming the time.
MAX_DERIVATIVE: float = 1e12


@dataclass(frozen=True)
class SpatialPlatformDynamics:
    """The equations of motion of ``N`` states in the platform's free coordinates (§18).

    ``L`` = the robot's degrees of freedom (legs); the free components are
    :attr:`free` (of ``wx, wy, wz, vx, vy, vz``).

    Attributes
    ----------
    free : tuple of str
        The free twist components, ``L`` of them.
    effort_matrix : (N, legs, L)
        ``A = ∂τ/∂a_f`` (N or N·m per rad/s² or m/s²).
    effort_bias : (N, legs)
        ``h``: the efforts at ``a_f = 0`` (gravity, velocity terms).
    rates : (N, legs, L)
        ``J_a``: the actuated rates per unit free twist, ``dq_act = J_a·ξ_f``.
    mass : (N, L, L)
        ``M = J_aᵀ·A`` (kg, kg·m, kg·m²), symmetric positive definite.
    bias : (N, L)
        ``b = J_aᵀ·h`` (N, N·m): ``M·a_f + b = J_aᵀ·τ``.
    """

    free: tuple[str, ...]
    effort_matrix: FloatArray
    effort_bias: FloatArray
    rates: FloatArray
    mass: FloatArray
    bias: FloatArray


def _free_index(robot: SpatialRobot) -> list[int]:
    return [c for c in range(6) if c not in robot.parasitic_index]


def _batch(
    position: FloatArray, rotation: FloatArray, twist: FloatArray, acc: FloatArray
) -> PlatformMotion:
    """An unvalidated motion of ``len(position)`` states (times 0, 1, …)."""
    n = position.shape[0]
    return PlatformMotion(
        np.arange(n, dtype=np.float64), position, rotation,
        twist[:, :3], twist[:, 3:], acc[:, :3], acc[:, 3:],
    )  # fmt: skip


@dataclass(frozen=True)
class _Evaluation:
    dynamics: SpatialPlatformDynamics
    accelerations: FloatArray  # (N, L + 1, 6): the full (α, a) at a_f = 0, e_1, …, e_L
    margin: FloatArray  # (N,): min of the measures of §6 times their signs at home


def _evaluate(robot: SpatialRobot, motion: PlatformMotion) -> _Evaluation:
    """:func:`spatial_platform_dynamics` without validation.

    ``motion`` closes every leg and its accelerations are those of ``a_f = 0`` (the
    parasitic ones completed, §11).  The parasitic acceleration is affine in ``a_f``
    with the slope of the parasitic twist in ``ξ_f`` (``−C_par⁻¹·C_free``), so that
    the unit accelerations need no completion of their own.
    """
    free = _free_index(robot)
    n, size = len(motion), len(free)
    rep = size + 1
    twist = np.concatenate([motion.omega, motion.velocity], axis=1)
    base = np.concatenate([motion.alpha, motion.acceleration], axis=1)
    basis = np.zeros((n, 6, size))  # the full twist (or acceleration) per unit free one
    for j, c in enumerate(free):
        basis[:, c, j] = 1.0
    if robot.parasitic:
        kin0 = chunk_kinematics(robot, motion)
        if kin0.constraint is not None:
            index = list(robot.parasitic_index)
            constraint = kin0.constraint
            basis[:, index, :] = -np.linalg.solve(constraint[..., index], constraint[..., free])
    acc = np.concatenate([base[:, None, :], base[:, None, :] + np.swapaxes(basis, 1, 2)], axis=1)
    batch = _batch(
        np.repeat(motion.position, rep, axis=0),
        np.repeat(motion.rotation, rep, axis=0),
        np.repeat(twist, rep, axis=0),
        acc.reshape(-1, 6),
    )
    kin = chunk_kinematics(robot, batch)
    tau = chunk_efforts(robot, kin, batch, body_wrenches(robot, kin, batch)).reshape(n, rep, -1)
    h = tau[:, 0]
    a = np.swapaxes(tau[:, 1:] - h[:, None, :], 1, 2)
    rates = kin.parallel[::rep] @ basis
    jt = np.swapaxes(rates, 1, 2)
    dynamics = SpatialPlatformDynamics(
        tuple(TWIST_COMPONENTS[c] for c in free), a, h, rates, jt @ a, (jt @ h[..., None])[..., 0]
    )
    leg_sign, par_sign = home_signs(robot)
    margin = np.minimum(
        (kin.leg_measure[::rep] * leg_sign).min(axis=-1), kin.parallel_measure[::rep] * par_sign
    )
    return _Evaluation(dynamics, acc, margin)


def _at_zero(robot: SpatialRobot, motion: PlatformMotion) -> PlatformMotion:
    """``motion`` completed (§11) with its free accelerations zero: the state of :func:`_evaluate`."""
    zero = np.zeros((len(motion), 3))
    rest = PlatformMotion(
        motion.t, motion.position, motion.rotation, motion.omega, motion.velocity, zero, zero
    )
    return complete_motion(robot, rest)


def spatial_platform_dynamics(
    robot: SpatialRobot, motion: PlatformMotion
) -> SpatialPlatformDynamics:
    """``τ = A·a_f + h`` and ``M·a_f + b = J_aᵀ·τ`` at the states of ``motion`` (§18).

    Parameters
    ----------
    robot : SpatialRobot
    motion : PlatformMotion
        ``N`` states (pose and twist; the accelerations are not used).  For a robot of
        fewer than 6 DOF they are completed first (:func:`~prp3.spatial.kinematics.complete_motion`).

    Returns
    -------
    SpatialPlatformDynamics

    Raises
    ------
    UnreachablePoseError, SingularPoseError
        As :func:`~prp3.spatial.kinematics.spatial_kinematics`.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    with np.errstate(all="ignore"):
        result = _evaluate(robot, _at_zero(robot, motion)).dynamics
    if not all(np.isfinite(x).all() for x in (result.mass, result.bias, result.effort_bias)):
        raise TrajectoryError(
            "the equations of motion overflow float64: the motion's rates or the robot's "
            "parameters are out of range",
            subject="motion",
        )
    return result


def hold_efforts(robot: SpatialRobot) -> FloatArray:
    """The efforts ``(legs,)`` (N or N·m) that hold ``robot`` at rest at its home pose.

    >>> from prp3.spatial.model import hexapod
    >>> round(float(hold_efforts(hexapod())[0]), 6)
    2.804864
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    home = PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    return np.asarray(virtual_work_efforts(robot, home)[0], dtype=np.float64)


def state_from_joints(
    robot: SpatialRobot, t: ArrayLike, q: ArrayLike, dq: ArrayLike
) -> PlatformMotion:
    """The platform's poses and twists of the joint values and rates of every leg (§2, §4).

    The chain of each leg from the base (:func:`~prp3.spatial.geometry.chain_frames`)
    gives its end frame, which is the platform frame placed by the attachment:
    ``R = R_end·R_Aᵀ``, ``p = c_end − R·c_A``; the leg Jacobian gives the end's twist
    ``(ω, v_end) = J_i·dq_i`` and ``v = v_end − ω × (c_end − p)``.  The legs' answers are
    averaged (they agree on a motion of the robot: the rows of a ``results.csv``), the
    rotation taken back to the nearest rotation matrix.  Accelerations are zero.

    Parameters
    ----------
    t : (N,) s, strictly increasing
    q, dq : (N, legs, dof)
        Joint values and rates (docs/spatial.md §9).

    >>> from prp3.spatial.model import hexapod
    >>> from prp3.spatial.kinematics import spatial_kinematics
    >>> robot = hexapod()
    >>> kin = spatial_kinematics(robot, PlatformMotion.at_rest(robot.home_position))
    >>> state = state_from_joints(robot, [0.0], kin.q, kin.dq)
    >>> (np.round(state.position, 12) + 0.0).tolist()
    [[0.0, 0.0, 0.08]]
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    times = check_times("t", t, subject="joints")
    shape = (times.size, len(robot.legs), robot.legs[0].dof)
    values = []
    for name, value in (("q", q), ("dq", dq)):
        array = check_real(name, value, TrajectoryError, "joints")
        if array.shape != shape:
            raise TrajectoryError(
                f"{name} must have shape {shape}, got {array.shape}", subject="joints", key=name
            )
        if not np.isfinite(array).all():
            k = int(np.argwhere(~np.isfinite(array))[0, 0])
            raise TrajectoryError(f"{name} is not finite", subject="joints", sample=k, key=name)
        values.append(array)
    with np.errstate(all="ignore"):
        frames = chain_frames(robot, values[0])
        end, end_rotation = frames.origin[:, :, -1], frames.rotation[:, :, -1]
        c_a, r_a = attachments(robot)
        rotations = (end_rotation @ np.swapaxes(r_a, -1, -2)).mean(axis=1)
        bad = ~np.isfinite(rotations).all(axis=(1, 2))
        if bad.any():
            raise TrajectoryError(
                "the joint values give no platform pose (its rotation is not finite)",
                subject="joints",
                sample=int(np.argmax(bad)),
                key="q",
            )
        u, _, vt = np.linalg.svd(rotations)
        rotation = u @ vt
        position = (end - np.einsum("nij,lj->nli", rotation, c_a)).mean(axis=1)
        twist = np.einsum("nlij,nlj->nli", leg_jacobians(robot, frames, end), values[1])
        omega = twist[..., :3].mean(axis=1)
        velocity = (twist[..., 3:] - cross(omega[:, None, :], end - position[:, None, :])).mean(1)
    return PlatformMotion.of(times, position, rotation, omega, velocity)


@dataclass(frozen=True)
class SpatialForward:
    """Result of :func:`spatial_forward_dynamics`.

    Attributes
    ----------
    motion : PlatformMotion
        The integrated motion at the output times: pose, twist and the acceleration
        of the equations of motion (completed onto the legs' constraints, §11).
    solution : SpatialSolution
        Its inverse dynamics by the Newton–Euler route (every joint's wrench, §9); its
        ``tau`` gives the efforts back (:attr:`effort_residual`).
    efforts : (N, legs)
        The given efforts at the output times.
    effort_residual : float
        ``max |solution.tau − efforts|`` (N or N·m).
    evaluations : int
        Evaluations of the equations of motion.
    message : str
    """

    motion: PlatformMotion
    solution: SpatialSolution
    efforts: FloatArray
    effort_residual: float
    evaluations: int
    message: str


class _BoundReachedError(Exception):
    """Raised inside the right-hand side when a bound of the run is reached."""


class _AbsurdDerivativeError(Exception):
    """Raised inside the right-hand side when the acceleration is not finite or absurd."""

    def __init__(self, time: float, acceleration: float, tau: FloatArray) -> None:
        super().__init__(time)
        self.time, self.acceleration, self.tau = time, acceleration, tau


def _effort_samples(
    effort_of: Callable[[float], FloatArray], efforts: object, t0: float
) -> tuple[FloatArray, bool]:
    """The effort rows to check up front (every sample of a table) and whether sampled."""
    if callable(efforts):
        return effort_of(t0)[None], False
    tau = np.asarray(efforts, dtype=np.float64)
    return (tau[None] if tau.ndim == 1 else tau), tau.ndim == 2


def _check_accelerations(
    robot: SpatialRobot, dynamics: SpatialPlatformDynamics, rows: FloatArray, sampled: bool
) -> None:
    """Refuse efforts whose free accelerations at the initial state are absurd (§18).

    ``a_f = A⁻¹·(τ − h)`` at the initial state for each row of ``rows`` (legs,); the
    largest ``|a_f|`` must be finite and below :data:`MAX_ACCELERATION`.
    """
    with np.errstate(all="ignore"):
        solved = np.linalg.solve(dynamics.effort_matrix[0], (rows - dynamics.effort_bias[0]).T).T
        size = np.abs(solved).max(axis=1)
    size = np.where(np.isfinite(size), size, math.inf)
    k = int(np.argmax(size))
    if size[k] < MAX_ACCELERATION:
        return
    leg = int(np.argmax(np.abs(rows[k])))
    raise ParameterError(  # the sample, when sampled, is the error's field
        f"the efforts ask for a platform acceleration of {size[k]:.3g} (m/s², rad/s²) at the "
        f"initial state of the {robot.name}, beyond the bound {MAX_ACCELERATION:g} "
        f"(docs/spatial.md §18: a_f = A⁻¹·(τ − h)); the effort of leg {leg + 1} is "
        f"{float(rows[k, leg])!r}",
        key="efforts",
        sample=k if sampled else None,
    )


def _effort_function(
    robot: SpatialRobot, efforts: object, t_efforts: ArrayLike | None
) -> tuple[Callable[[float], FloatArray], tuple[float, float] | None]:
    """``τ(t)`` and the span it is defined on (``None``: every time)."""
    legs = len(robot.legs)
    if callable(efforts):
        function = efforts

        def checked(time: float) -> FloatArray:
            value = np.asarray(function(time), dtype=np.float64)
            if value.shape != (legs,) or not np.isfinite(value).all():
                raise ParameterError(
                    f"efforts: the function must return {legs} finite numbers, got {value!r}"[:300],
                    key="efforts",
                )
            return value

        return checked, None
    tau = check_real("efforts", efforts, ParameterError)  # type: ignore[arg-type]
    if t_efforts is None:
        if tau.shape != (legs,):
            raise ParameterError(
                f"efforts must have shape ({legs},) (constant efforts), or ({legs},) per "
                f"sample with t_efforts; got shape {tau.shape}",
                key="efforts",
            )
        if not np.isfinite(tau).all():
            raise ParameterError(f"efforts must be finite, got {tau.tolist()!r}", key="efforts")
        constant = tau.copy()
        return (lambda _time: constant), None
    te = check_times("t_efforts", t_efforts, minimum=2)
    if tau.shape != (te.size, legs):
        raise ParameterError(
            f"efforts must have shape ({te.size}, {legs}) (one row per t_efforts), got {tau.shape}",
            key="efforts",
        )
    if not np.isfinite(tau).all():
        k = int(np.argwhere(~np.isfinite(tau))[0, 0])
        raise ParameterError(f"efforts of sample {k} are not finite", key="efforts", sample=k)
    if te.size == 2:
        slope = (tau[1] - tau[0]) / (te[1] - te[0])
        return (lambda time: tau[0] + slope * (time - te[0])), (float(te[0]), float(te[-1]))
    spline = checked_spline("efforts", te, tau)
    return (lambda time: np.asarray(spline(time), dtype=np.float64)), (float(te[0]), float(te[-1]))


def _closed(
    robot: SpatialRobot,
    feedback: Callable[[float, PlatformMotion], ArrayLike] | None,
    time: float,
    state: PlatformMotion,
) -> FloatArray | float:
    """The feedback efforts at ``(time, state)`` (0 without feedback), checked."""
    if feedback is None:
        return 0.0
    value = np.asarray(feedback(time, state), dtype=np.float64)
    if value.shape != (len(robot.legs),) or not np.isfinite(value).all():
        raise ParameterError(
            f"feedback must return {len(robot.legs)} finite numbers, got {value!r}"[:300],
            key="feedback",
        )
    return value


def _row(motion: PlatformMotion, k: int) -> PlatformMotion:
    """Sample ``k`` of ``motion`` as a motion of one sample."""
    return PlatformMotion(
        motion.t[k : k + 1], motion.position[k : k + 1], motion.rotation[k : k + 1],
        motion.omega[k : k + 1], motion.velocity[k : k + 1], motion.alpha[k : k + 1],
        motion.acceleration[k : k + 1],
    )  # fmt: skip


def _without_limits(robot: SpatialRobot) -> SpatialRobot:
    """``robot`` with every joint unbounded: the equations of motion a little beyond a limit.

    The integrator's trial states may overshoot a limit; their equations of motion stay
    defined there (the limits are the user's, not the geometry's), so that the terminal
    event of the limit margin finds the crossing instead of the step shrinking onto it.
    """
    legs = tuple(
        replace(leg, joints=tuple(replace(joint, limits=()) for joint in leg.joints))
        for leg in robot.legs
    )
    return replace(robot, legs=legs)


def _limit_reached(robot: SpatialRobot, time: float, state: PlatformMotion) -> UnreachablePoseError:
    """The refusal of a motion that reaches a joint limit at ``time`` (the closest limit named)."""
    q = leg_coordinates(robot, state.position, state.rotation).q
    _, bounded = limit_margin(robot, q)

    def distance(limit: JointLimit) -> float:
        unit = robot.scale if limit.unit == "m" else 1.0
        value = float(limit.values[0])
        low = -math.inf if limit.kind == "S" else limit.low
        return min(value - low, limit.high - value) / unit

    distances = [distance(limit) for limit in bounded]
    nearest = min(distances)  # legs at a limit together (a symmetric push): the first named
    closest = next(lim for lim, d in zip(bounded, distances, strict=True) if d <= nearest + 1e-9)
    value = float(closest.values[0])
    bound = closest.high if abs(closest.high - value) <= abs(value - closest.low) else closest.low
    p = ", ".join(f"{v:.6g}" for v in state.position[0])
    return UnreachablePoseError(
        f"the motion reaches a joint limit at t = {time!r} s: {closest.name} of leg "
        f"{closest.leg + 1} = {value:.6g} {closest.unit} reaches its limit {bound:.6g} "
        f"{closest.unit} (limits [{closest.low:.6g}, {closest.high:.6g}]) at the pose "
        f"p = ({p}) m; the efforts drive the platform there",
        subject="forward dynamics",
        time=time,
        leg=str(closest.leg + 1),
    )


def _initial(robot: SpatialRobot, initial: PlatformMotion | None, t0: float) -> PlatformMotion:
    if initial is None:
        return PlatformMotion.of([t0], robot.home_position, robot.home_rotation)
    check_instance("initial", initial, PlatformMotion, "a PlatformMotion of one sample or None")
    if len(initial) != 1:
        raise ParameterError(
            f"initial must be one state (a PlatformMotion of 1 sample), got {len(initial)} samples",
            key="initial",
        )
    return initial


def spatial_forward_dynamics(
    robot: SpatialRobot,
    efforts: ArrayLike | Callable[[float], ArrayLike],
    initial: PlatformMotion | None = None,
    duration: float = 1.0,
    *,
    t_efforts: ArrayLike | None = None,
    samples: int = 101,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_evaluations: int = MAX_EVALUATIONS,
    max_seconds: float = MAX_SECONDS,
    progress: Callable[[int, int], None] | None = None,
    feedback: Callable[[float, PlatformMotion], ArrayLike] | None = None,
) -> SpatialForward:
    """Integrate the platform motion of ``robot`` driven by the actuator efforts ``τ(t)`` (§18).

    The state ``(p, q, ω, v)`` (``q`` the orientation's unit quaternion ``[w, x, y, z]``)
    obeys ``ṗ = v``, ``q̇ = ½ (0, ω) ⊗ q``, and ``(α, a)`` from ``a_f = A⁻¹·(τ(t) − h)``
    (:func:`spatial_platform_dynamics`; the parasitic components of a robot of fewer than
    6 DOF from the legs' constraints), integrated by ``scipy.integrate.solve_ivp``
    (``DOP853``).

    Parameters
    ----------
    robot : SpatialRobot
    efforts : array_like or callable
        The actuator efforts (N for a P actuator, N·m for an R one): ``(legs,)``
        constant; ``(M, legs)`` at the times ``t_efforts`` (the not-a-knot cubic
        spline between them; linear for 2); or a function ``τ(t) -> (legs,)``.
    initial : PlatformMotion, optional
        The state at the start: one sample, its time ``t0`` (s), pose and twist (its
        accelerations are not used).  Default: at rest at the home pose, at
        ``t_efforts[0]`` (or 0).
    duration : float
        ``T`` (s, > 0): the motion over ``t0 .. t0 + T`` (within ``t_efforts``).
    t_efforts : array_like, shape (M,), optional
        The times of sampled efforts (s), strictly increasing, ``M ≥ 2``.
    samples : int
        Output times, evenly over ``t0 .. t0 + T`` (≥ 2).
    rtol, atol : float
        Tolerances of ``solve_ivp`` (relative ≥ ``MIN_RTOL``; absolute in m, 1, rad/s, m/s).
    max_evaluations, max_seconds : int, float
        Bounds on the evaluations of the equations of motion and on the wall time (s)
        (defaults :data:`~prp3.analysis.forward.MAX_EVALUATIONS`,
        :data:`~prp3.analysis.forward.MAX_SECONDS`).
    progress : callable, optional
        ``progress(samples_reached, N)``, reported as the integration advances.
    feedback : callable, optional
        ``feedback(t, state) -> (legs,)``: efforts of the time and of the state (one
        sample, completed onto the legs' constraints, accelerations zero), added to
        ``efforts`` (a closed loop, :func:`~prp3.apps.spatial_control.spatial_track`).

    Returns
    -------
    SpatialForward

    Raises
    ------
    ParameterError
        Bad efforts, times, tolerances or bounds; output times outside ``t_efforts``; a
        singular mass matrix at the start (condition number ≥ ``1e12``).
    UnreachablePoseError, SingularPoseError, TrajectoryError
        The initial state is out of reach, singular or not one the legs allow (§6, §11).
    SingularPoseError
        The motion reaches a singularity: a measure of §6 falls to
        :data:`SINGULARITY_STOP` (the message names the time and the measure).
    UnreachablePoseError
        The motion reaches a stroke or joint limit (a terminal event on the limit margin
        of :func:`~prp3.spatial.geometry.limit_margin`: names the time, the joint and the
        limit), or leaves the poses a leg can close (names the time).
    TrajectoryError
        A bound (``max_evaluations`` or ``max_seconds``) stopped the integration (the
        message names it and the time reached), or the integrator failed.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    effort_of, span = _effort_function(robot, efforts, t_efforts)
    if feedback is not None and not callable(feedback):
        raise ParameterError(
            f"feedback must be a function (t, state) -> efforts or None, got {feedback!r}"[:300],
            key="feedback",
        )
    period = check_scalar("duration", duration, positive=True, unit="s")
    count = check_integer("samples", samples, 2, 10**7)
    relative = check_scalar("rtol", rtol, positive=True)
    absolute = check_scalar("atol", atol, positive=True)
    if relative < MIN_RTOL:
        raise ParameterError(
            f"rtol must be at least {MIN_RTOL:.3g} (100 machine epsilons, scipy's floor), "
            f"got {relative!r}",
            key="rtol",
        )
    bound_evaluations = check_integer("max_evaluations", max_evaluations, 1, 10**12)
    bound_seconds = check_scalar("max_seconds", max_seconds, positive=True, unit="s")
    start = _initial(robot, initial, span[0] if span is not None else 0.0)
    t0 = float(start.t[0])
    times = np.linspace(t0, t0 + period, count)
    if not (np.isfinite(times).all() and (np.diff(times) > 0).all()):
        raise ParameterError(
            f"duration = {period!r} s from t0 = {t0!r} s gives no {count} increasing times",
            key="duration",
        )
    if span is not None and (times[0] < span[0] or times[-1] > span[1] * (1 + 1e-15) + 1e-300):
        raise ParameterError(
            f"the motion's times {times[0]!r} .. {times[-1]!r} s lie outside the efforts' "
            f"{span[0]!r} .. {span[1]!r} s",
            key="duration",
        )
    times[-1] = min(times[-1], span[1]) if span is not None else times[-1]
    try:
        first = _at_zero(robot, start)
        with np.errstate(all="ignore"):
            dyn0 = _evaluate(robot, first).dynamics
    except Prp3Error as error:
        raise error.located(subject="initial state", sample=None, time=t0) from None
    mass = dyn0.mass[0]
    if not np.isfinite(mass).all():
        raise ParameterError(
            f"the mass matrix of the {robot.name} overflows float64 at the initial state: its "
            f"bodies' masses and inertias are too large (the largest mass "
            f"{max(body.mass for body in robot.bodies)!r} kg)",
            subject="robot",
        )
    scale = float(np.abs(mass).max())  # the condition number of M/scale is M's, without overflow
    condition = float(np.linalg.cond(mass / scale)) if scale > 0.0 else math.inf
    if not condition < MAX_CONDITION:
        raise ParameterError(
            f"the mass matrix of the {robot.name} is singular or ill-conditioned at the initial "
            f"state (condition number {condition:.3g} >= {MAX_CONDITION:g}): its masses and "
            "inertias leave a motion without inertia, or differ too much in scale (the "
            f"largest mass {max(body.mass for body in robot.bodies)!r} kg)",
            subject="robot",
        )
    effort_of(t0)  # a function of the wrong kind is refused before the integration
    _check_accelerations(robot, dyn0, *_effort_samples(effort_of, efforts, t0))
    y0 = np.concatenate(
        [
            first.position[0],
            matrix_quaternion(first.rotation[0]),
            first.omega[0],
            first.velocity[0],
        ]
    )
    evaluations = [0]
    furthest = [t0]
    clock = time_module.monotonic()
    failures: list[tuple[float, Prp3Error]] = []
    cache: dict[bytes, tuple[PlatformMotion, FloatArray, float, float]] = {}
    unlimited = _without_limits(robot)

    def evaluate(time: float, y: FloatArray) -> tuple[PlatformMotion, FloatArray, float, float]:
        """The completed state, its full ``(α, a)`` (6,), its singularity and limit margins."""
        key = y.tobytes() + np.float64(time).tobytes()
        if key in cache:
            return cache[key]
        quaternion = y[3:7] / math.sqrt(float(y[3:7] @ y[3:7]))
        zero = np.zeros((1, 3))
        motion = PlatformMotion(
            np.array([time]), y[None, :3].copy(), quaternion_matrix(quaternion)[None],
            y[None, 7:10].copy(), y[None, 10:13].copy(), zero, zero,
        )  # fmt: skip
        if robot.parasitic:
            motion = complete_motion(unlimited, motion)
        done = _evaluate(unlimited, motion)
        reach = limit_margin(robot, leg_coordinates(robot, motion.position, motion.rotation).q)
        dyn = done.dynamics
        tau = effort_of(time) + _closed(robot, feedback, time, motion)
        a_free = np.linalg.solve(dyn.effort_matrix[0], tau - dyn.effort_bias[0])
        base = done.accelerations[0, 0]
        full = base + a_free @ (done.accelerations[0, 1:] - base)  # affine in a_f (§11)
        moved = PlatformMotion(
            motion.t, motion.position, motion.rotation, motion.omega, motion.velocity,
            full[None, :3], full[None, 3:],
        )  # fmt: skip
        result = (moved, full, float(done.margin[0]), float(reach[0][0]))
        if len(cache) > 64:
            cache.clear()
        cache[key] = result
        return result

    def rhs(time: float, y: FloatArray) -> FloatArray:
        time = float(time)
        evaluations[0] += 1
        if evaluations[0] > bound_evaluations:
            raise _BoundReachedError(f"max_evaluations = {bound_evaluations}")
        if time_module.monotonic() - clock > bound_seconds:
            raise _BoundReachedError(f"max_seconds = {bound_seconds!r} s")
        try:
            with np.errstate(all="ignore"):
                moved, acc, _, _ = evaluate(time, y)
        except Prp3Error as error:  # a trial state out of reach: NaN rejects the step
            if np.isfinite(y).all():
                failures.append((time, error))
            return np.full(13, np.nan)
        except np.linalg.LinAlgError:
            return np.full(13, np.nan)
        size = float(np.abs(acc).max())
        if np.isfinite(y).all() and not size < MAX_DERIVATIVE:
            raise _AbsurdDerivativeError(time, size, effort_of(time))
        if time > furthest[0]:
            furthest[0] = float(time)
            if progress is not None:
                progress(int(np.searchsorted(times, time, side="right")), times.size)
        q = y[3:7]
        w = moved.omega[0]
        dq = 0.5 * np.array(
            [
                -w @ q[1:],
                q[0] * w[0] + w[1] * q[3] - w[2] * q[2],
                q[0] * w[1] + w[2] * q[1] - w[0] * q[3],
                q[0] * w[2] + w[0] * q[2] - w[1] * q[1],
            ]
        )
        return np.concatenate([moved.velocity[0], dq, acc])

    def singular(time: float, y: FloatArray) -> float:
        try:
            with np.errstate(all="ignore"):
                return evaluate(time, y)[2] - SINGULARITY_STOP
        except (Prp3Error, np.linalg.LinAlgError):
            return 1.0  # out of reach: said by the right-hand side

    def beyond(time: float, y: FloatArray) -> float:
        try:
            with np.errstate(all="ignore"):
                return evaluate(time, y)[3]
        except (Prp3Error, np.linalg.LinAlgError):
            return 1.0  # out of reach: said by the right-hand side

    for event in (singular, beyond):
        event.terminal = True  # type: ignore[attr-defined]
        event.direction = -1.0  # type: ignore[attr-defined]
    from scipy.integrate import solve_ivp

    try:
        with np.errstate(all="ignore"):
            solution = solve_ivp(
                rhs, (float(times[0]), float(times[-1])), y0, method="DOP853", t_eval=times,
                events=[singular, beyond], rtol=relative, atol=absolute,
            )  # fmt: skip
    except _BoundReachedError as bound:
        raise TrajectoryError(
            f"the integration was stopped by its bound {bound} after {evaluations[0] - 1} "
            f"evaluations of the equations of motion, at t = {furthest[0]!r} s of "
            f"[{float(times[0])!r}, {float(times[-1])!r}] s",
            subject="forward dynamics",
            time=furthest[0],
        ) from None
    except _AbsurdDerivativeError as absurd:
        tau_text = ", ".join(f"{v:.6g}" for v in absurd.tau)
        raise TrajectoryError(
            f"the equations of motion give a platform acceleration of {absurd.acceleration:.3g} "
            f"(m/s², rad/s²) at t = {absurd.time!r} s, not below {MAX_DERIVATIVE:g}, under the "
            f"efforts ({tau_text}): the efforts are absurd for the {robot.name}",
            subject="forward dynamics",
            time=absurd.time,
        ) from None
    if (
        solution.status == 1
        and solution.t_events[1].size
        and not (solution.t_events[0].size and solution.t_events[0][0] <= solution.t_events[1][0])
    ):
        t_limit = float(solution.t_events[1][0])
        state = evaluate(t_limit, np.asarray(solution.y_events[1][0], dtype=np.float64))[0]
        raise _limit_reached(robot, t_limit, state)
    if solution.status == 1:
        t_stop = float(solution.t_events[0][0])
        y_stop = np.asarray(solution.y_events[0][0], dtype=np.float64)
        p = ", ".join(f"{v:.6g}" for v in y_stop[:3])
        raise SingularPoseError(
            f"the motion reaches a singularity at t = {t_stop!r} s: a measure of docs/spatial.md "
            f"§6 (times its sign at home) falls to {SINGULARITY_STOP:g} at the pose p = ({p}) m; "
            "the efforts drive the platform there",
            subject="forward dynamics",
            time=t_stop,
        )
    if solution.status != 0:
        reached = float(solution.t[-1]) if solution.t.size else t0
        if failures:  # the latest state the integrator tried and prp3 refused
            latest_time, refused = max(failures, key=lambda failure: failure[0])
            latest = float(latest_time)
            raise type(refused)(
                f"the motion leaves the poses prp3 computes with near t = {latest!r} s: "
                f"{refused.reason}",
                subject="forward dynamics",
                time=latest,
                leg=refused.leg,
            ) from None
        raise TrajectoryError(
            f"the integration failed at t = {reached!r} s after {evaluations[0]} evaluations: "
            f"{solution.message}",
            subject="forward dynamics",
            time=reached,
        )
    if progress is not None:
        progress(times.size, times.size)
    states = np.asarray(solution.y, dtype=np.float64).T
    motions = [evaluate(float(s), y)[0] for s, y in zip(solution.t, states, strict=True)]
    motion = PlatformMotion.of(
        np.asarray(solution.t, dtype=np.float64),
        np.concatenate([m.position for m in motions]),
        np.concatenate([m.rotation for m in motions]),
        np.concatenate([m.omega for m in motions]),
        np.concatenate([m.velocity for m in motions]),
        np.concatenate([m.alpha for m in motions]),
        np.concatenate([m.acceleration for m in motions]),
    )
    # the parasitic accelerations solved afresh from the free ones (§11), not by the
    # affine combination of the right-hand side (round-off relative to a small acceleration)
    motion = complete_motion(robot, motion)
    given = np.array(
        [
            effort_of(float(s)) + _closed(robot, feedback, float(s), _row(motion, k))
            for k, s in enumerate(motion.t)
        ]
    )
    inverse = spatial_inverse_dynamics(robot, motion, "newton-euler")
    residual = float(np.abs(inverse.tau - given).max())
    message = (
        f"completed t = {float(times[0]):.6g} .. {float(times[-1]):.6g} s in "
        f"{evaluations[0]} evaluations of the equations of motion"
    )
    return SpatialForward(motion, inverse, given, residual, evaluations[0], message)
