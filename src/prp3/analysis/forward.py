"""Forward dynamics: the platform motion integrated from the actuator forces.

The paper solves the inverse problems only (pose → actuators → forces).
:func:`forward_dynamics` solves the direct one: it integrates the equations of
motion ``q̈ = A(q)⁻¹·(f10(t) − b(q, q̇))``
(:func:`prp3.analysis.equations_of_motion.platform_dynamics`; with ``μ`` terms
the acceleration by chord iterations) with ``scipy.integrate.solve_ivp``,
from sampled forces or functions of time
(:mod:`prp3.analysis.force_histories`), and checks the motion by its inverse
dynamics (:mod:`prp3.analysis.inverse_dynamics`).  Friction that the
equations of motion cannot take is refused
(:func:`prp3.analysis.equations_of_motion.check_forward_friction`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.analysis.equations_of_motion import (
    LOST_MEANING,
    check_forward_friction,
    platform_accelerations,
    without_limits,
)
from prp3.analysis.force_histories import (
    ActuatorForces,
    ForceFunction,
    force_function,
    load_function,
)
from prp3.analysis.inverse_dynamics import kernel_method
from prp3.engines.compiled_robot import CompiledRobot, compile_robot
from prp3.errors import (
    ParameterError,
    Prp3Error,
    SingularPoseError,
    TrajectoryError,
)
from prp3.integration_bounds import BoundReachedError, IntegrationBounds
from prp3.mechanics.forces import InverseDynamics
from prp3.mechanics.geometry import inverse_geometry
from prp3.mechanics.kinematics import Kinematics, inverse_kinematics
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.pose_validation import SINGULARITY_THRESHOLD, check_poses, singularity_measure
from prp3.validation import (
    LEGS,
    MIN_RTOL,
    check_integer,
    check_per_leg,
    check_robot,
    check_scalar,
    check_times,
    check_tolerances,
)

__all__ = [
    "MAX_ACCELERATION",
    "MAX_EVALUATIONS",
    "MAX_SECONDS",
    "MIN_RTOL",
    "SINGULARITY_STOP",
    "ForwardDynamics",
    "forward_dynamics",
]

FloatArray = NDArray[np.float64]
Status = Literal["completed", "singular", "stroke", "failed"]


#: :func:`forward_dynamics` stops when ``|sin(φ − π/3)|`` falls to this value
#: (twice :data:`~prp3.pose_validation.SINGULARITY_THRESHOLD`, so that the stop pose
#: itself is still one prp3 computes with).
SINGULARITY_STOP: float = 2.0 * SINGULARITY_THRESHOLD


#: Default bound of :func:`forward_dynamics` on the evaluations of the equations of motion
#: (``max_evaluations``): a stiff motion (friction smoothed over ``1e-12`` m/s, huge forces)
#: that the explicit integrator would crawl through forever is stopped, and said so.  The
#: paper's 3 s motions take about 10⁴.
MAX_EVALUATIONS: int = 1_000_000

#: Default wall-time bound of :func:`forward_dynamics` (s, ``max_seconds``).
MAX_SECONDS: float = 600.0

#: The largest platform acceleration (m/s², rad/s², about 10⁵ g) that the forces and loads
#: may ask for at the initial state: beyond it (forces of 1e20 N) the explicit integrator
#: would crawl to :data:`MAX_SECONDS`, so the run is refused before it starts.
MAX_ACCELERATION: float = 1e6


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
    max_evaluations: int = MAX_EVALUATIONS,
    max_seconds: float = MAX_SECONDS,
) -> ForwardDynamics:
    """Integrate the platform motion driven by the actuator forces ``f10(t)``.

    The state ``(x, y, φ, ẋ, ẏ, φ̇)`` obeys ``q̈ = A(q)⁻¹·(f10(t) − b(q, q̇))``
    (:func:`~prp3.analysis.equations_of_motion.platform_dynamics`), integrated by
    ``scipy.integrate.solve_ivp`` with the explicit Runge–Kutta method
    ``DOP853``.  Terminal events stop the integration when ``|sin(φ − π/3)|``
    falls to :data:`SINGULARITY_STOP` or, with ``robot.limits.stroke``, when an
    actuator reaches an end of its stroke.  The result then holds the motion up
    to the stop and says why.

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
        (:attr:`~prp3.analysis.force_histories.ActuatorForces.load`, interpolated like the forces); giving
        both is refused.
    progress : callable, optional
        ``progress(samples_reached, N)``: the output times the integration
        has reached (the furthest time evaluated), reported when it grows.
    max_evaluations : int
        Bound on the evaluations of the equations of motion (default
        :data:`MAX_EVALUATIONS`, at least 1).
    max_seconds : float
        Wall-time bound of the integration (s; default :data:`MAX_SECONDS`).

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
        (:func:`check_forward_friction`); non-positive bounds.
    TrajectoryError
        A bound (``max_evaluations`` or ``max_seconds``) stopped the integration
        (the message names it and the time reached); the equations of motion
        lost their meaning on the way (the bias forces swamp the inertia, or the
        acceleration overflows: the message names the time, the state and the
        inputs there) and the integrator gave up.

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
    rtol, atol = check_tolerances(rtol, atol)
    bounds = (
        check_integer("max_evaluations", max_evaluations, 1, 10**12),
        check_scalar("max_seconds", max_seconds, positive=True),
    )
    q0, v0, aspect = _initial_state(robot, initial_pose, initial_velocity)
    force_of = force_function(robot, forces, times)
    load_of = load_function(forces, load, times)
    free = without_limits(robot)  # the stroke ends are events, not refusals
    stroke = robot.limits.stroke
    lost: list[tuple[float, FloatArray, str]] = []  # states where the equations lost meaning
    _check_accelerations(free, force_of, load_of, times, np.concatenate([q0, v0]))
    solution = _integrate(
        free, stroke, force_of, times, q0, v0, aspect, (rtol, atol), load_of, progress,
        bounds, lost,
    )  # fmt: skip
    if progress is not None:
        progress(times.size, times.size)
    stop = _stop(free, stroke, solution, times, q0, v0)
    if stop.status == "failed" and lost:
        raise TrajectoryError(
            _lost_meaning(robot, lost[-1], force_of, load_of), subject="forward dynamics"
        )
    if stop.status == "failed" and stop.t_stop <= float(times[0]):
        raise TrajectoryError(  # subject: the command line names the file of the cause
            _failed_start(robot, stop, force_of, q0, v0, load_of), subject="forward dynamics"
        )
    return _result(free, force_of, stop, int(solution.nfev), load_of)


def _inputs(
    robot: Robot,
    time: float,
    force_of: Callable[[float], FloatArray],
    load_of: Callable[[float], FloatArray] | None,
) -> str:
    """The inputs of the equations of motion at ``time``: forces, load, the robot's effects."""
    parts = [f"forces f10 = {np.asarray(force_of(time), dtype=np.float64).tolist()!r} N"]
    if load_of is not None:
        parts.append(f"load (fx, fy, mz) = {np.asarray(load_of(time)).tolist()!r}")
    if robot.load.present:
        parts.append(
            f"the robot's [load] force = {list(robot.load.force)!r} N, "
            f"moment = {robot.load.moment!r} N·m"
        )
    if robot.payload.present:
        parts.append(
            f"its [payload] mass = {robot.payload.mass!r} kg, com = "
            f"{list(robot.payload.com)!r} m, inertia = {robot.payload.inertia!r} kg·m²"
        )
    if robot.friction is not None:
        for kind in ("actuator", "revolute", "sleeve"):
            joint = getattr(robot.friction, kind)
            if joint.coulomb or joint.mu:
                parts.append(
                    f"[friction.{kind}] coulomb = {joint.coulomb!r}, mu = {joint.mu!r}, "
                    f"smoothing = {joint.smoothing!r}"
                )
    return ", ".join(parts)


def _check_accelerations(
    robot: Robot,
    force_of: Callable[[float], FloatArray],
    load_of: Callable[[float], FloatArray] | None,
    times: FloatArray,
    state: FloatArray,
) -> None:
    """Refuse forces whose accelerations at the initial state exceed :data:`MAX_ACCELERATION`.

    ``q̈ = A⁻¹·(f10 − b)`` at the initial state under the forces of up to 257 of the
    sample times (an overflow is left to the integration, which names it at once).
    """
    compiled = compile_robot(robot)
    picks = np.unique(np.linspace(0, times.size - 1, min(times.size, 257)).astype(int))
    for k in picks.tolist():
        time = float(times[k])
        with np.errstate(all="ignore"):
            size = float(
                np.abs(state_derivative(compiled, force_of, time, state, load_of)[3:]).max()
            )
        if math.isfinite(size) and size >= MAX_ACCELERATION:
            raise ParameterError(
                f"the inputs at t = {time!r} s ask for a platform acceleration of {size:.3g} "
                f"(m/s², rad/s²) at the initial state, beyond the bound {MAX_ACCELERATION:g} "
                f"(q̈ = A⁻¹·(f10 − b)); the inputs there: "
                f"{_inputs(robot, time, force_of, load_of)}; give forces and loads of the "
                "robot's size",
                subject="forward dynamics",
                key="forces",
                time=time,
            )


def _lost_meaning(
    robot: Robot,
    lost: tuple[float, FloatArray, str],
    force_of: Callable[[float], FloatArray],
    load_of: Callable[[float], FloatArray] | None,
) -> str:
    """The refusal of a run whose state left what the equations of motion resolve."""
    time, state, reason = lost
    return (
        f"the integration gave up at t = {time!r} s, where the state (pose "
        f"{state[:3].tolist()!r}, velocity {state[3:].tolist()!r}) has lost its meaning: "
        f"{reason}; the inputs there: {_inputs(robot, time, force_of, load_of)}; give forces "
        "and loads of the robot's size"
    )


def _bound_detail(
    time: float,
    robot: Robot,
    force_of: Callable[[float], FloatArray],
    load_of: Callable[[float], FloatArray] | None,
) -> str:
    """What follows the bound's message: why the run is stiff, and the inputs at ``time``."""
    return (
        ": the motion is too stiff for the explicit integrator "
        "(friction smoothed over a tiny velocity, forces or springs far beyond the robot's "
        f"size); the inputs there: {_inputs(robot, time, force_of, load_of)}"
    )


def _failed_start(
    robot: Robot,
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
        f"robot's size; the inputs there: {_inputs(robot, t0, force_of, load_of)}"
    )


# ------------------------------------------------------- steps of forward_dynamics
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
    bounds: tuple[int, float] = (MAX_EVALUATIONS, MAX_SECONDS),
    lost: list[tuple[float, FloatArray, str]] | None = None,
) -> Any:
    """Step 3: ``solve_ivp`` (DOP853) of the state ``(q, q̇)``, with the terminal events.

    Stopped by :class:`~prp3.integration_bounds.BoundReachedError` (a ``TrajectoryError`` naming the bound) when
    ``bounds = (max_evaluations, max_seconds)`` is reached; the states where the
    equations of motion lost their meaning are appended to ``lost``.
    """
    from scipy.integrate import solve_ivp

    compiled = compile_robot(robot)
    reached = [0]
    limit = IntegrationBounds(bounds[0], bounds[1], float(times[0]))

    def rhs(time: float, state: FloatArray) -> FloatArray:
        if progress is not None:
            done = int(np.searchsorted(times, time, side="right"))
            if done > reached[0]:
                reached[0] = done
                progress(min(done, times.size), times.size)
        return state_derivative(compiled, force_of, time, state, load_of, lost)

    def singular(_time: float, state: FloatArray) -> float:
        return aspect * math.sin(state[2] - math.pi / 3.0) - SINGULARITY_STOP

    events: list[Callable[[float, FloatArray], float]] = [singular]
    if stroke is not None:
        events += _stroke_events(robot, stroke)
    for event in events:
        event.terminal = True  # type: ignore[attr-defined]
        event.direction = -1.0  # type: ignore[attr-defined]
    try:
        with np.errstate(all="ignore"):  # trial states may overflow: NaN rejects the step
            return solve_ivp(
                limit.bounded(rhs),
                (float(times[0]), float(times[-1])),
                np.concatenate([q0, v0]),
                method="DOP853",
                t_eval=times,
                events=events,
                rtol=tolerances[0],
                atol=tolerances[1],
            )
    except BoundReachedError as stop:
        detail = _bound_detail(limit.furthest, compiled.robot, force_of, load_of)
        raise limit.refusal(stop, (float(times[0]), float(times[-1])), detail) from None


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
    states = np.asarray(solution.y, dtype=np.float64).reshape(q0.size + v0.size, -1).T
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
    qddot = platform_accelerations(compiled, stop.states[:, :3], stop.states[:, 3:], applied, loads)
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


def state_derivative(
    compiled: CompiledRobot,
    force_of: Callable[[float], FloatArray],
    time: float,
    state: FloatArray,
    load_of: Callable[[float], FloatArray] | None = None,
    lost: list[tuple[float, FloatArray, str]] | None = None,
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
        qddot = platform_accelerations(compiled, q, qdot, applied, load)
    except Prp3Error as error:  # a trial state beyond the bounds of prp3 (or a lock): rejected
        if lost is not None and error.subject == LOST_MEANING:
            lost[:] = [(float(time), np.array(state, dtype=np.float64), error.reason)]
        return np.full(6, np.nan)
    return np.concatenate([qdot, qddot])


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
