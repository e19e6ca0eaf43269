"""Forward dynamics of a family robot: the platform motion driven by given actuator efforts.

The equations of motion in platform coordinates ``x = (x, y, φ)`` come from the
same mechanics as the inverse dynamics (:mod:`prp3.family.mechanics`, docs/family.md
§7): the actuator efforts are affine in the platform acceleration,

    ``τ = A(x)·ẍ + b(x, ẋ)``,

so ``b`` is the inverse dynamics at ``ẍ = 0`` and column ``i`` of ``A`` is the
inverse dynamics at ``ẍ = e_i`` minus ``b`` ("M by unit accelerations":
``A = Kᵀ``-weighted mass matrix, ``A = J_aᵀ⁻¹·M`` with ``J_a`` the actuated
rows).  The state ``(x, ẋ)`` then obeys ``ẍ = A⁻¹·(τ(t) − b)``, integrated by
``scipy.integrate.solve_ivp`` (``DOP853``) as :func:`prp3.analysis.forward.forward_dynamics`
does for the 3-PRP.  ``τ(t)`` is the not-a-knot cubic spline through the
given samples.  A terminal event stops the motion when a singularity
measure on the working mode's side (§6) falls to :data:`SINGULARITY_STOP`;
the result then holds the motion up to the stop.

:func:`family_energy` gives the kinetic and potential energy of the seven
bodies (with the payload), for the energy balance
``Σ_L p_L + P_ext = d/dt(T + V)`` (§10).

>>> from prp3.family.model import FamilyRobot
>>> robot = FamilyRobot.default("3-RRR")
>>> a, b = platform_dynamics(robot, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
>>> a.shape, [round(float(v), 6) for v in b]
((3, 3), [7.11225, -3.556125, -3.556125])
"""

from __future__ import annotations

import math
import time as time_module
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.analysis.forward import MAX_EVALUATIONS, MAX_SECONDS
from prp3.errors import ParameterError, Prp3Error, TrajectoryError
from prp3.family.chain import (
    SIGMA,
    SINGULAR,
    inv3,
    leg_chain,
    leg_jacobian,
    parallel_measure,
    rotate,
)
from prp3.family.mechanics import (
    FamilyKinematics,
    FamilySolution,
    body_rates_before,
    family_kinematics,
    fast_dynamics,
    jacobian_rate,
    point_velocity,
)
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.validation import (
    check_finite,
    check_instance,
    check_integer,
    check_real,
    check_scalar,
    check_times,
    check_tolerances,
    checked_spline,
)

__all__ = [
    "MAX_ACCELERATION",
    "MAX_DERIVATIVE",
    "SINGULARITY_STOP",
    "FamilyEffortModel",
    "FamilyForward",
    "family_energy",
    "family_forward_dynamics",
    "platform_dynamics",
    "singularity_margin",
]

FloatArray = NDArray[np.float64]

#: The integration stops when ``s·μ`` of a measure falls to this (above §6's 1e-4).
SINGULARITY_STOP: float = 1e-3

#: The largest platform acceleration (m/s², rad/s², about 10⁵ g) that the efforts and the
#: load may ask for at the initial state: beyond it (efforts of 1e6 N·m on the default
#: 3-RRR, 1e20) the explicit integrator would crawl for ever, so the run is refused before
#: it starts (``ẍ = A⁻¹·(τ − b)`` at the initial state, §7).
MAX_ACCELERATION: float = 1e6

#: A right-hand side whose acceleration reaches this (a million times
#: :data:`MAX_ACCELERATION`) at a finite state stops the integration with an error naming
#: the time (efforts given as a function that turn absurd during the motion).
MAX_DERIVATIVE: float = 1e12


class _AbsurdDerivativeError(Exception):
    """Raised inside the right-hand side when the acceleration reaches :data:`MAX_DERIVATIVE`."""


def _vector(name: str, value: ArrayLike) -> FloatArray:
    v = check_real(name, value, TrajectoryError)
    if v.shape != (3,):
        raise TrajectoryError(f"{name} must have 3 components, got shape {v.shape}")
    return check_finite(name, v, TrajectoryError, components=("x", "y", "phi"))


def platform_dynamics(
    robot: FamilyRobot, pose: ArrayLike, velocity: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """``A(x)`` ``(3, 3)`` and ``b(x, ẋ)`` ``(3,)`` of ``τ = A·ẍ + b`` (legs A, B, C).

    Four inverse-dynamics samples at the same state: ``ẍ = 0`` gives ``b``,
    ``ẍ = e_i`` gives ``A[:, i] + b``.

    Raises
    ------
    SingularPoseError, UnreachablePoseError
        The pose is singular or out of reach (§6).
    """
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    x, v = _vector("pose", pose), _vector("velocity", velocity)
    return _dynamics(robot, x, v)


def _state_kinematics(robot: FamilyRobot, x: FloatArray, v: FloatArray) -> FamilyKinematics:
    """The kinematics of four samples at the state ``(x, ẋ)``, ``ẍ = 0, e_1, e_2, e_3``.

    The home-branch closure solution at the pose (§5: the solution whose
    ``μ_leg`` has its home sign; the integration stops before a measure
    changes sign), then ``q̇ = J⁻¹·ẋ``, ``q̈ = J⁻¹·(ẍ − J̇·q̇)`` as
    :func:`prp3.family.mechanics.family_kinematics` computes them.
    """
    from prp3.errors import SingularPoseError, UnreachablePoseError
    from prp3.family.workspace import home_branch

    q, mu_leg, wrenches = home_branch(robot, x[None, :2], x[2:3])
    if not np.isfinite(q).all():
        raise UnreachablePoseError(f"a leg cannot reach the pose {tuple(x.tolist())}")
    mu_par = parallel_measure(wrenches)
    home_leg, home_par = robot.home_measures
    signs = np.sign(np.asarray(home_leg))
    if not (
        (signs * mu_leg >= SINGULAR).all() and math.copysign(1.0, home_par) * mu_par[0] >= SINGULAR
    ):
        raise SingularPoseError(f"the pose {tuple(x.tolist())} is singular (docs/family.md §6)")
    acceleration = np.vstack([np.zeros(3), np.eye(3)])
    motion = Motion(
        t=np.arange(4.0), pose=np.tile(x, (4, 1)), velocity=np.tile(v, (4, 1)),
        acceleration=acceleration,
    )  # fmt: skip
    q4 = np.broadcast_to(q, (4, 3, 3))
    frames = leg_chain(robot.types, robot.leg.placements, SIGMA, q4)
    jac = leg_jacobian(robot.types, frames, motion.pose[:, None, :2])
    inverse = inv3(jac)
    twist = np.broadcast_to(motion.velocity[:, None, :], (4, 3, 3))
    dq = np.einsum("nlij,nlj->nli", inverse, twist)
    bias = jacobian_rate(robot.types, frames, jac, dq, motion.velocity)
    rhs = motion.acceleration[:, None, :] - np.einsum("nlij,nlj->nli", bias, dq)
    ddq = np.einsum("nlij,nlj->nli", inverse, rhs)
    return FamilyKinematics(
        robot=robot, motion=motion, q=np.array(q4), dq=dq, ddq=ddq,
        mu_leg=np.tile(mu_leg, (4, 1)), mu_par=np.repeat(mu_par, 4), frames=frames,
        jacobian=jac, jacobian_inverse=inverse,
    )  # fmt: skip


def _dynamics(robot: FamilyRobot, x: FloatArray, v: FloatArray) -> tuple[FloatArray, FloatArray]:
    tau = fast_dynamics(_state_kinematics(robot, x, v)).tau
    b = tau[0]
    return np.asarray((tau[1:] - b).T), np.asarray(b)


def _margin(robot: FamilyRobot, x: FloatArray) -> float:
    """``min(s_L·μ_leg,L, s_par·μ_par)`` at the pose (home branch); −1 out of reach."""
    from prp3.family.workspace import family_measures_at

    mu_leg, mu_par, reach = family_measures_at(robot, x[None, :2], float(x[2]))
    if not reach[0]:
        return -1.0
    home_leg, home_par = robot.home_measures
    values = [math.copysign(1.0, h) * float(m) for h, m in zip(home_leg, mu_leg[0], strict=True)]
    values.append(math.copysign(1.0, home_par) * float(mu_par[0]))
    return min(values)


def singularity_margin(robot: FamilyRobot, pose: ArrayLike) -> float:
    """``min_L(s_L·μ_leg,L, s_par·μ_par)`` at ``pose`` on the home branch (§6), −1 out of reach.

    Positive on the working mode's side; a pose is regular when it is at least
    ``1e-4``.

    >>> round(singularity_margin(FamilyRobot.default("3-RPR"), [0.0, 0.0, 0.0]), 3)
    0.943
    """
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    return _margin(robot, _vector("pose", pose))


@dataclass(frozen=True)
class FamilyEffortModel:
    """A family robot as the control loop's model: the efforts of one state, unchecked floats.

    :meth:`actuator_sample_function` gives ``τ(x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈) =
    A(x)·ẍ + b(x, ẋ)`` (:func:`platform_dynamics`), the interface of
    :meth:`prp3.engines.compiled_robot.CompiledRobot.actuator_sample_function`;
    ``A`` and ``b`` of the last state are kept, so that the four calls of a
    plant step at one state cost one evaluation.  A singular or unreachable
    state raises :class:`~prp3.errors.SingularPoseError` or
    :class:`~prp3.errors.UnreachablePoseError`.
    """

    robot: FamilyRobot

    def __post_init__(self) -> None:
        check_instance("robot", self.robot, FamilyRobot, "a prp3.family.FamilyRobot")

    def actuator_sample_function(self) -> Callable[..., tuple[float, float, float]]:
        """The function ``τ`` of one state (9 floats) as a tuple of 3 floats (N or N·m)."""
        robot = self.robot
        cache: dict[str, tuple[float, ...] | tuple[FloatArray, FloatArray]] = {}

        def effort(
            x: float, y: float, p: float, vx: float, vy: float, vp: float,
            ax: float, ay: float, ap: float,
        ) -> tuple[float, float, float]:  # fmt: skip
            state = (x, y, p, vx, vy, vp)
            if cache.get("state") != state:
                cache["dynamics"] = _dynamics(robot, np.array(state[:3]), np.array(state[3:]))
                cache["state"] = state
            a, b = cache["dynamics"]
            tau = np.asarray(a) @ np.array([ax, ay, ap]) + np.asarray(b)
            return (float(tau[0]), float(tau[1]), float(tau[2]))

        return effort


def family_energy(kin: FamilyKinematics) -> tuple[FloatArray, FloatArray]:
    """Kinetic and potential energy ``(T, V)`` of the seven bodies and the payload, shapes ``(N,)``.

    ``T = Σ ½ m |v_C|² + ½ I ω²`` with ``v_C`` the velocity of each mass centre
    from the joint rates (``Σ_i q̇_i·s_i(C)``, ``s_i`` the twist of joint ``i``),
    ``V = −Σ m g·C``.
    """
    robot = kin.robot
    types, frames = robot.types, kin.frames
    pose = kin.motion.pose.reshape(-1, 3)
    velocity = kin.motion.velocity.reshape(-1, 3)
    dq = kin.dq.reshape(-1, 3, 3)
    g = np.asarray(robot.gravity)
    kinetic = np.zeros(pose.shape[0])
    potential = np.zeros(pose.shape[0])
    for body in (1, 2):
        params = robot.link1 if body == 1 else robot.link2
        c = frames.origin[..., body - 1, :] + rotate(frames.angle[..., body - 1], params.com)
        v = point_velocity(types, frames, dq, body, c)
        w = body_rates_before(types, dq, body)
        kinetic += (0.5 * params.mass * (v * v).sum(-1) + 0.5 * params.inertia * w * w).sum(-1)
        potential -= params.mass * (c @ g).sum(-1)
    omega = velocity[:, 2]
    vg = velocity[:, :2]
    kinetic += 0.5 * robot.platform.mass * (vg * vg).sum(-1)
    kinetic += 0.5 * (robot.platform.inertia + robot.payload.inertia) * omega * omega
    potential -= robot.platform.mass * (pose[:, :2] @ g)
    payload = robot.payload
    r = rotate(pose[:, 2], payload.com)
    vp = vg + omega[:, None] * np.stack([-r[:, 1], r[:, 0]], axis=-1)
    kinetic += 0.5 * payload.mass * (vp * vp).sum(-1)
    potential -= payload.mass * ((pose[:, :2] + r) @ g)
    return kinetic, potential


@dataclass(frozen=True)
class FamilyForward:
    """Result of :func:`family_forward_dynamics`.

    Attributes
    ----------
    motion : Motion
        The integrated motion at the output times up to the stop: pose,
        velocity and the acceleration of the equations of motion.
    solution : FamilySolution or None
        The inverse dynamics of that motion (every joint force; its ``tau``
        reproduces the given efforts); ``None`` when fewer than one sample.
    status : str
        ``"completed"``, ``"singular"`` (stopped at a singularity measure) or ``"failed"``.
    message : str
    evaluations : int
        Evaluations of the equations of motion.
    """

    motion: Motion
    solution: FamilySolution | None
    status: str
    message: str
    evaluations: int


def _effort_function(t: FloatArray, tau: FloatArray) -> Callable[[float], FloatArray]:
    if t.size == 2:
        slope = (tau[1] - tau[0]) / (t[1] - t[0])
        return lambda time: np.asarray(tau[0] + slope * (time - t[0]))
    spline = checked_spline("efforts", t, tau)
    return lambda time: np.asarray(spline(time))


def _checked(function: Callable[[float], ArrayLike]) -> Callable[[float], FloatArray]:
    def effort(time: float) -> FloatArray:
        value = np.asarray(function(time), dtype=np.float64)
        if value.shape != (3,) or not np.isfinite(value).all():
            raise ParameterError(
                f"the efforts function must return 3 finite numbers, got {value!r}"
            )
        return value

    return effort


def _effort_of(
    t_efforts: ArrayLike | None,
    efforts: ArrayLike | Callable[[float], ArrayLike],
    times: FloatArray,
) -> tuple[Callable[[float], FloatArray], tuple[FloatArray, FloatArray] | None]:
    """The efforts ``τ(t)`` and, for a table, its samples ``(t_efforts, efforts)``."""
    if callable(efforts):
        return _checked(efforts), None
    if t_efforts is None:
        raise ParameterError("t_efforts: the times of the effort samples are missing")
    te = check_times("t_efforts", t_efforts, minimum=2)
    tau = check_real("efforts", efforts, ParameterError)
    if tau.shape != (te.size, 3):
        raise ParameterError(f"efforts must have shape ({te.size}, 3), got {tau.shape}")
    if times[0] < te[0] or times[-1] > te[-1]:
        raise ParameterError(
            f"the output times {times[0]!r} .. {times[-1]!r} s lie outside the efforts' "
            f"{te[0]!r} .. {te[-1]!r} s"
        )
    with np.errstate(all="ignore"):  # ±1e308: inf slopes, refused by _check_accelerations
        return _effort_function(te, tau), (te, tau)


def _inertia_extremes(robot: FamilyRobot) -> str:
    """The robot's largest and smallest nonzero mass and inertia, named by key (for a refusal).

    >>> for part in _inertia_extremes(FamilyRobot.default("3-RRR")).split("; "):
    ...     print(part)
    the largest: platform.mass = 3.0 kg, platform.inertia = 0.0675 kg·m²
    the smallest: link2.mass = 0.75 kg, link2.inertia = 0.0025 kg·m²
    """
    bodies = {"link1": robot.link1, "link2": robot.link2, "platform": robot.platform,
              "payload": robot.payload}  # fmt: skip
    named = {
        unit: [
            (float(getattr(body, key)), f"{name}.{key}")
            for name, body in bodies.items()
            if float(getattr(body, key)) > 0.0
        ]
        for key, unit in (("mass", "kg"), ("inertia", "kg·m²"))
    }

    def pick(choose: Callable[..., tuple[float, str]]) -> str:
        return ", ".join(
            f"{key} = {value!r} {unit}"
            for unit, values in named.items()
            if values
            for value, key in [choose(values)]
        )

    return f"the largest: {pick(max)}; the smallest: {pick(min)}"


def _check_load(robot: FamilyRobot, x0: FloatArray, v0: FloatArray, b0: FloatArray) -> None:
    """Refuse a robot file's ``[load]`` that alone (zero efforts) asks for an absurd ``|ẍ|``.

    ``ẍ = −A⁻¹·b`` at the initial state (§7) with and without the load; the load is to
    blame (named by its key, ``load.force`` or ``load.moment``) when the first is not
    below :data:`MAX_ACCELERATION` and the second is.
    """
    from dataclasses import replace

    from prp3.model.parameters import Load

    load = robot.load
    if not any((*load.force, load.moment)):
        return
    with np.errstate(all="ignore"):
        a_free, b_free = _dynamics(replace(robot, load=Load()), x0, v0)
        try:
            sizes = [float(np.abs(np.linalg.solve(a_free, -b)).max()) for b in (b0, b_free)]
        except np.linalg.LinAlgError:  # a massless platform: the caller's refusal
            return
    if sizes[0] < MAX_ACCELERATION or not sizes[1] < MAX_ACCELERATION:
        return
    key = "load.moment" if abs(load.moment) > max(map(abs, load.force)) else "load.force"
    value = load.moment if key == "load.moment" else list(load.force)
    raise ParameterError(
        f"{key} = {value!r} alone asks for a platform acceleration of "
        f"{sizes[0]:.3g} (m/s², rad/s²) at the initial state of the {robot.architecture}, "
        f"beyond the bound {MAX_ACCELERATION:g} (docs/family.md §7: ẍ = A⁻¹·(τ − b)); "
        "give a load of the robot's size",
        key=key,
    )


def _check_accelerations(
    robot: FamilyRobot,
    a0: FloatArray,
    b0: FloatArray,
    effort: Callable[[float], FloatArray],
    times: FloatArray,
    samples: tuple[FloatArray, FloatArray] | None,
) -> None:
    """Refuse efforts whose platform accelerations at the initial state are absurd.

    ``ẍ = A⁻¹·(τ − b)`` at the initial state (§7) for every effort sample of a table
    and for ``τ`` at up to 257 of the output times; the largest ``|ẍ|`` must be
    finite and below :data:`MAX_ACCELERATION`.  A sample of the table is named by
    its index (from 0) and time, with the column and value of its largest effort.
    """
    picks = np.unique(np.linspace(0, times.size - 1, min(times.size, 257)).astype(int))
    at = times[picks]
    with np.errstate(all="ignore"):
        rows = np.array([effort(float(time)) for time in at]).reshape(-1, 3)
    sampled = 0
    if samples is not None:
        at, rows, sampled = np.concatenate([samples[0], at]), np.vstack([samples[1], rows]), 1
    with np.errstate(all="ignore"):
        size = np.abs(np.linalg.solve(a0, (rows - b0).T).T).max(axis=1)
    size = np.where(np.isfinite(size), size, math.inf)
    k = int(np.argmax(size))
    if size[k] < MAX_ACCELERATION:
        return
    leg = int(np.argmax(np.abs(rows[k])))
    table = bool(sampled) and samples is not None and k < samples[0].size
    load = robot.load
    asking = "the efforts and the [load]" if any((*load.force, load.moment)) else "the efforts"
    raise ParameterError(
        f"{asking} ask for a platform acceleration of {size[k]:.3g} "
        f"(m/s², rad/s²) at the initial state of the {robot.architecture}, beyond the bound "
        f"{MAX_ACCELERATION:g} (docs/family.md §7: ẍ = A⁻¹·(τ − b)); tau_{'ABC'[leg]} = "
        f"{float(rows[k, leg])!r}, [load] force = {list(load.force)!r} N, moment = "
        f"{load.moment!r} N·m; give efforts and loads of the robot's size",
        key="efforts",
        sample=k if table else None,
        time=float(at[k]),
    )


class _BoundReachedError(Exception):
    """Raised inside the right-hand side when a bound of the run is reached."""


def _absurd_refusal(
    robot: FamilyRobot, effort: Callable[[float], FloatArray], time: float, size: float
) -> TrajectoryError:
    """The refusal of a run whose right-hand side reached :data:`MAX_DERIVATIVE`."""
    with np.errstate(all="ignore"):
        tau = ", ".join(f"{v:.6g}" for v in effort(time).tolist())
    return TrajectoryError(
        f"the equations of motion give a platform acceleration of {size:.3g} (m/s², rad/s²) at "
        f"t = {time!r} s, not below {MAX_DERIVATIVE:g}, under the efforts ({tau}): the "
        f"efforts are absurd for the {robot.architecture}",
        subject="forward dynamics",
        time=time,
    )


def family_forward_dynamics(
    robot: FamilyRobot,
    t_efforts: ArrayLike | None,
    efforts: ArrayLike | Callable[[float], ArrayLike],
    t: ArrayLike,
    initial_pose: ArrayLike,
    initial_velocity: ArrayLike,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_evaluations: int = MAX_EVALUATIONS,
    max_seconds: float = MAX_SECONDS,
) -> FamilyForward:
    """Integrate the platform motion driven by the actuator efforts ``τ_L(t)``.

    Parameters
    ----------
    robot : FamilyRobot
    t_efforts : array_like, shape (M,), or None
        Times of the effort samples (s), strictly increasing, ``M >= 2``
        (ignored when ``efforts`` is a function).
    efforts : array_like, shape (M, 3), or callable
        ``tau_A, tau_B, tau_C`` (N for a P actuator, N·m for an R one) at
        ``t_efforts`` (cubic spline between them), or a function ``τ(t) -> (3,)``.
    t : array_like, shape (N,)
        Output times (s), strictly increasing, within ``t_efforts``.
    initial_pose, initial_velocity : array_like, shape (3,)
        ``(x, y, φ)`` and ``(ẋ, ẏ, φ̇)`` at ``t[0]``.
    rtol, atol : float
        Tolerances of ``solve_ivp``.
    max_evaluations, max_seconds : int, float
        Bounds on the evaluations of the equations of motion and on the wall time (s)
        (defaults :data:`~prp3.analysis.forward.MAX_EVALUATIONS`,
        :data:`~prp3.analysis.forward.MAX_SECONDS`): a stiff motion the explicit
        integrator would crawl through (a platform 1e12 times heavier than its legs)
        is stopped, and said so.

    Raises
    ------
    TrajectoryError, ParameterError
        Bad times, efforts or initial state (named); a bound stopped the integration
        (the message names the bound and the time reached).
    SingularPoseError, UnreachablePoseError
        The initial pose is singular or out of reach.
    """
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    times = check_times("t", t, minimum=2)
    effort, samples = _effort_of(t_efforts, efforts, times)
    rtol, atol = check_tolerances(rtol, atol)
    bounds = (
        check_integer("max_evaluations", max_evaluations, 1, 10**12),
        check_scalar("max_seconds", max_seconds, positive=True, unit="s"),
    )
    x0, v0 = _vector("initial_pose", initial_pose), _vector("initial_velocity", initial_velocity)
    try:  # refuses a singular or unreachable initial pose
        with np.errstate(all="ignore"):  # an overflow: the results' own refusal, located
            a0, b0 = _dynamics(robot, x0, v0)
    except Prp3Error as error:  # its samples are the probes of _dynamics, not the user's
        raise error.located(subject="initial pose", sample=None, time=None) from None
    _check_load(robot, x0, v0, b0)
    scale = float(np.abs(a0).max())  # cond(A/scale) is cond(A), without overflow
    condition = float(np.linalg.cond(a0 / scale)) if scale > 0.0 else math.inf
    if not condition < 1e12:
        raise ParameterError(
            f"the equations of motion of this {robot.architecture} are singular or "
            f"ill-conditioned at the initial pose (condition number of A: {condition:.3g}, the "
            "bound 1e12): its masses "
            "and inertias leave a motion without inertia (a massless platform?), or differ "
            f"too much in scale ({_inertia_extremes(robot)})",
            subject="robot",
        )
    _check_accelerations(robot, a0, b0, effort, times, samples)
    count, furthest, clock = [0], [float(times[0])], time_module.monotonic()

    def bounded(time: float, state: FloatArray) -> FloatArray:
        """``rhs`` as the integrator calls it: stopped by ``max_evaluations``, ``max_seconds``."""
        if count[0] >= bounds[0]:
            raise _BoundReachedError(f"max_evaluations = {bounds[0]}")
        if count[0] % 64 == 63 and time_module.monotonic() - clock > bounds[1]:
            raise _BoundReachedError(f"max_seconds = {bounds[1]!r} s (wall time)")
        furthest[0] = max(furthest[0], float(time))
        return rhs(time, state)

    def rhs(time: float, state: FloatArray) -> FloatArray:
        count[0] += 1
        try:
            a, b = _dynamics(robot, state[:3], state[3:])
            acceleration = np.linalg.solve(a, effort(time) - b)
        except (Prp3Error, np.linalg.LinAlgError):  # a trial state beyond the stop: NaN
            return np.full(6, np.nan)  # rejects the step
        if np.isfinite(state).all() and not np.abs(acceleration).max() < MAX_DERIVATIVE:
            raise _AbsurdDerivativeError(time, float(np.abs(acceleration).max()))
        return np.concatenate([state[3:], acceleration])

    def singular(_time: float, state: FloatArray) -> float:
        return _margin(robot, state[:3]) - SINGULARITY_STOP

    singular.terminal = True  # type: ignore[attr-defined]
    singular.direction = -1.0  # type: ignore[attr-defined]
    from scipy.integrate import solve_ivp

    try:
        with np.errstate(all="ignore"):
            solution = solve_ivp(
                bounded,
                (float(times[0]), float(times[-1])),
                np.concatenate([x0, v0]),
                method="DOP853",
                t_eval=times,
                events=[singular],
                rtol=rtol,
                atol=atol,
            )
    except _BoundReachedError as bound:
        raise TrajectoryError(
            f"the integration was stopped by its bound {bound} after {count[0]} "
            f"evaluations of the equations of motion, at t = {furthest[0]!r} s of "
            f"[{float(times[0])!r}, {float(times[-1])!r}] s (a stiff motion: masses or "
            "inertias far apart in scale?)",
            subject="forward dynamics",
            time=furthest[0],
        ) from None
    except _AbsurdDerivativeError as absurd:
        raise _absurd_refusal(robot, effort, *absurd.args) from None
    states = np.asarray(solution.y, dtype=np.float64).reshape(x0.size + v0.size, -1).T
    reached = np.asarray(solution.t, dtype=np.float64)
    if solution.status == 1:
        status, message = (
            "singular",
            (
                f"stopped at t = {float(solution.t_events[0][0]):.9g} s: a singularity measure fell to "
                f"{SINGULARITY_STOP:g} (docs/family.md §6)"
            ),
        )
    elif solution.status == 0:
        status, message = "completed", "completed"
    else:
        status, message = "failed", f"the integration failed: {solution.message}"
    finite = np.isfinite(states).all(axis=1)
    states, reached = states[finite], reached[finite]
    accelerations = np.array([rhs(float(s), y)[3:] for s, y in zip(reached, states, strict=True)])
    accelerations = accelerations.reshape(-1, 3)
    if reached.size == 0:
        reached, states = times[:1], np.concatenate([x0, v0])[None, :]
        accelerations = rhs(float(times[0]), states[0])[None, 3:]
    motion = Motion(
        t=reached, pose=states[:, :3], velocity=states[:, 3:], acceleration=accelerations
    )
    inverse = fast_dynamics(family_kinematics(robot, motion))
    return FamilyForward(
        motion=motion,
        solution=inverse,
        status=status,
        message=message,
        evaluations=count[0],
    )
