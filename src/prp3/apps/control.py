"""Closed-loop control: computed torque, PD and feed-forward against a simulated plant.

The paper's purpose is real-time control: its closed-form inverse dynamics
gives the actuator forces ``f10 = ID(q, q̇, q̈)`` of any platform motion
``q = (x, y, φ)`` in a few microseconds.  Open loop (feed-forward) those forces
cannot keep the platform on its path: the robot driven by forces alone is
unstable (a saddle with rates near ``6.2 s⁻¹``, see
:func:`prp3.analysis.forward.forward_dynamics`), so every error grows like
``e^{6.2 t}``.  A controller measures ``q`` and ``q̇`` at each control instant
and closes the loop.  With ``e = q_ref − q``, gains ``KP`` (1/s²) and ``KD``
(1/s), the same for ``x``, ``y`` and ``φ``, and ``ID_model`` the inverse
dynamics of the controller's model of the robot (:func:`control_force`):

* computed torque: ``f10 = ID_model(q, q̇, q̈_ref + KD·ė + KP·e)``.  With an
  exact model the closed loop is ``ë + KD·ė + KP·e = 0`` between the
  instants: critically damped for ``KD² = 4·KP`` (the defaults 400 and 40).
* PD: ``f10 = ID_model(q, 0, KD·ė + KP·e)``: a PD law through the model's mass
  matrix with gravity compensation, without feed-forward of the reference
  acceleration and without the velocity terms.
* feed-forward: ``f10 = ID_model(q_ref, q̇_ref, q̈_ref)`` (open loop).

The controller runs at the instants of the reference (:func:`control_times`,
default 1000 Hz) and the plant holds each force until the next instant (zero
order hold).  The plant is either prp3's own equations of motion
(``plant="prp3"``: ``q̈ = A(q)⁻¹·(f10 − b(q, q̇))`` of
:func:`prp3.analysis.equations_of_motion.platform_dynamics`, integrated over each step by
``scipy.integrate.solve_ivp`` (``RK45``, ``rtol = 1e-10``, ``atol = 1e-12``: the
:data:`prp3.apps.plants.PLANT_METHOD` and tolerances, restarted at every step),
or MuJoCo running the exported MJCF (``plant="mujoco"``,
:func:`prp3.apps.mjcf.mjcf_model`: its own RK4 integrator at ``1e-4 s`` and its
soft weld constraints), which is an independent simulation of the same robot.
The plant's robot may differ from the controller's model (a wrong mass, a
payload, unmodelled loads); their geometry ``l0`` must agree.

The control laws are :mod:`prp3.apps.control_law`, the plants
:mod:`prp3.apps.plants`; this module holds the reference (:func:`control_times`,
:func:`hermite_reference`) and the closed loop (:func:`track`).

>>> import prp3
>>> from prp3.model.motion import law_at
>>> reference = law_at([0.0, 0.0, 0.1], control_times(0.0, 0.05, 1000.0))
>>> run = track(prp3.Robot(), reference, controller="computed-torque")
>>> run.status, run.t.shape, bool(run.max_error.max() < 1e-6)
('completed', (51,), True)
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.apps.control_law import CONTROLLERS, Controller, Gains, control_force
from prp3.apps.plants import (
    PLANTS,
    MujocoPlant,
    Plant,
    PlantProtocol,
    Prp3Plant,
    Status,
    check_plant,
    without_limits,
)
from prp3.engines.compiled_robot import CompiledRobot, compile_robot
from prp3.engines.entries import paper_forces
from prp3.errors import (
    ParameterError,
    Prp3Error,
    SingularPoseError,
    TrajectoryError,
    UnreachablePoseError,
)
from prp3.family.forward import FamilyEffortModel, singularity_margin
from prp3.family.mechanics import family_kinematics
from prp3.family.model import FamilyRobot
from prp3.family.outputs import family_inverse_dynamics
from prp3.mechanics.geometry import inverse_geometry
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.path_validation import check_path
from prp3.pose_validation import SINGULARITY_THRESHOLD
from prp3.validation import check_instance, check_robot, check_scalar, check_times

__all__ = [
    "DEFAULT_RATE",
    "LOAD_REFUSAL",
    "MAX_STEPS",
    "Tracking",
    "check_model",
    "control_times",
    "hermite_reference",
    "track",
]

FloatArray = NDArray[np.float64]

#: Default control rate (Hz).
DEFAULT_RATE: float = 1000.0
#: Most control instants of one run (bounds time and memory).
MAX_STEPS: int = 1_000_000


# ------------------------------------------------------------------ reference
def control_times(start: float, stop: float, rate: float) -> FloatArray:
    """The control instants ``start, start + 1/rate, ...`` up to ``stop`` inclusive (s).

    When ``stop − start`` is not a whole number of periods, ``stop`` is added
    as the last instant (the last step is then shorter; an interval shorter
    than a period has its two ends).

    Raises
    ------
    ParameterError
        ``rate`` not a positive finite number (Hz), or more than
        :data:`MAX_STEPS` instants.

    >>> control_times(0.0, 0.01, 400.0).tolist()
    [0.0, 0.0025, 0.005, 0.0075, 0.01]
    >>> control_times(0.0, 0.01, 300.0).round(6).tolist()
    [0.0, 0.003333, 0.006667, 0.01]
    >>> control_times(0.0, 1e-300, 400.0).tolist()  # shorter than a period: its two ends
    [0.0, 1e-300]
    """
    rate = check_scalar("rate", rate, positive=True, unit="Hz")
    start = check_scalar("start", start, error=TrajectoryError)
    stop = check_scalar("stop", stop, error=TrajectoryError)
    if not (math.isfinite(start) and math.isfinite(stop) and stop > start):
        raise TrajectoryError(
            f"the control interval must be finite with stop > start, got [{start!r}, {stop!r}] s"
        )
    periods = (stop - start) * float(rate)
    if not periods < MAX_STEPS:
        raise ParameterError(
            f"rate {rate!r} Hz over {stop - start!r} s gives {periods:.3g} control steps, "
            f"more than {MAX_STEPS}"
        )
    count = math.floor(periods + 1e-9)
    times = start + np.arange(count + 1, dtype=np.float64) / float(rate)
    if stop - times[-1] > 1e-9 / float(rate) or times.size == 1:  # shorter than a period: both
        times = np.append(times, stop)
    times[-1] = stop
    return times


#: Why the control loop refuses a motion with a time-varying load ``fx, fy, mz``.
LOAD_REFUSAL: str = (
    "a time-varying load fx, fy, mz is not modelled by the control loop (neither the "
    "controller's model nor the plants apply it): give the wrench as a constant [load] of "
    "the robots, or leave the columns out"
)


def hermite_reference(motion: Motion, times: ArrayLike, *, crossing: bool = True) -> Motion:
    """The motion interpolated at ``times`` by quintic Hermite polynomials.

    Between two samples each of ``x, y, φ`` is the polynomial of degree 5 that
    matches the positions, velocities and accelerations of both samples
    (what ``scipy.interpolate.BPoly.from_derivatives`` builds); its
    derivatives give the reference velocity and acceleration.  At the samples
    the reference is the motion itself.  The polynomial is evaluated on the
    segment's own coordinate ``u = (t − t_k)/h`` in ``[0, 1]`` with the
    quintic Hermite basis, each term divided by the power of ``h`` it needs,
    so that a step ``h`` of ``1e-300`` s or a subnormal one overflows only
    where the reference itself does (positions that move by ``Δq`` in ``h``
    need an acceleration of order ``Δq/h²``).

    Parameters
    ----------
    motion : Motion
        ``N >= 2`` samples with velocities and accelerations.
    times : array_like, shape (M,)
        Strictly increasing times within ``[t[0], t[-1]]`` (s).
    crossing : bool
        Refuse a motion that crosses the 3-PRP's singularity ``φ = π/3 mod π``
        between two samples (the default); ``False`` for a family robot, whose
        singularities :func:`track` checks along the path.

    Raises
    ------
    TrajectoryError
        A single-sample motion, times outside the motion, a motion with a
        time-varying load (:data:`LOAD_REFUSAL`).
    SingularPoseError
        A motion that crosses the singularity (:func:`prp3.path_validation.check_path`).

    >>> from prp3.model.motion import law_at
    >>> m = law_at([0.01, 0.0, 0.0], np.linspace(0.0, 3.0, 31))
    >>> r = hermite_reference(m, [0.05, 1.55])
    >>> bool(np.abs(r.pose - law_at([0.01, 0.0, 0.0], [0.05, 1.55]).pose).max() < 1e-9)
    True
    """
    check_instance("motion", motion, Motion, "a prp3.Motion")
    if motion.t.ndim != 1 or motion.samples < 2:
        raise TrajectoryError("reference: the motion needs at least 2 samples")
    if motion.load is not None:
        raise TrajectoryError(LOAD_REFUSAL, subject="reference")
    if crossing:  # the 3-PRP's: an interpolant across φ = π/3 (a family robot's: by track)
        check_path(motion.t, motion.pose)
    at = check_times("times", times)
    first, last = float(motion.t[0]), float(motion.t[-1])
    if at.ndim != 1 or at.size == 0 or not (at.min() >= first and at.max() <= last):
        raise TrajectoryError(f"reference: times must lie within [{first!r}, {last!r}] s")
    t = motion.t
    k = np.clip(np.searchsorted(t, at, side="right") - 1, 0, t.size - 2)  # segment of each
    h = (t[k + 1] - t[k])[:, None]  # > 0, exact for subnormal steps
    u = ((at - t[k]) / h[:, 0])[:, None]
    q0, q1 = motion.pose[k], motion.pose[k + 1]
    v0, v1 = motion.velocity[k], motion.velocity[k + 1]
    a0, a1 = motion.acceleration[k], motion.acceleration[k + 1]
    basis = _hermite_basis(u)  # (3 orders, 5 functions, M, 1)
    b1, b2, b3, b4, b5 = basis[0]
    d1, _, d3, d4, d5 = basis[1]  # d2 = 1 − d1 − d3
    e1, _, e3, e4, e5 = basis[2]  # e2 = −e1 − e3
    with np.errstate(over="ignore", invalid="ignore"):  # a reference that overflows: refused
        step = q1 - q0
        slope = step / h  # the differences first: a straight line has no round-off/h
        pose = q0 + b1 * step + h * (b2 * v0 + b3 * v1) + h * (h * (b4 * a0 + b5 * a1))
        velocity = v0 + d1 * (slope - v0) + d3 * (v1 - v0) + h * (d4 * a0 + d5 * a1)
        acceleration = (e1 * (slope - v0) + e3 * (v1 - v0)) / h + e4 * a0 + e5 * a1
    knot = np.flatnonzero(np.isin(at, t))  # at the samples: the motion itself
    where = np.searchsorted(t, at[knot])
    pose[knot], velocity[knot] = motion.pose[where], motion.velocity[where]
    acceleration[knot] = motion.acceleration[where]
    return Motion(t=at, pose=pose, velocity=velocity, acceleration=acceleration)


def _hermite_basis(u: FloatArray) -> FloatArray:
    """The quintic Hermite basis on ``[0, 1]`` and its 1st and 2nd derivatives, ``(3, 5, ...)``.

    The functions multiply ``q1 − q0, h·q̇0, h·q̇1, h²·q̈0, h²·q̈1`` (``q0`` itself has
    the weight 1): ``10u³ − 15u⁴ + 6u⁵``, ``u − 6u³ + 8u⁴ − 3u⁵``,
    ``−4u³ + 7u⁴ − 3u⁵``, ``(u² − 3u³ + 3u⁴ − u⁵)/2``, ``(u³ − 2u⁴ + u⁵)/2``.

    >>> basis = _hermite_basis(np.array([0.0, 1.0]))
    >>> basis[0, :, 1].tolist(), basis[1, :, 0].tolist(), basis[2, :, 0].tolist()
    ([1.0, 0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0, 0.0])
    """
    u2, u3 = u * u, u * u * u
    u4, u5 = u3 * u, u3 * u2
    return np.array([
        [10*u3 - 15*u4 + 6*u5, u - 6*u3 + 8*u4 - 3*u5, -4*u3 + 7*u4 - 3*u5,
         (u2 - 3*u3 + 3*u4 - u5) / 2, (u3 - 2*u4 + u5) / 2],
        [30*u2 - 60*u3 + 30*u4, 1 - 18*u2 + 32*u3 - 15*u4, -12*u2 + 28*u3 - 15*u4,
         (2*u - 9*u2 + 12*u3 - 5*u4) / 2, (3*u2 - 8*u3 + 5*u4) / 2],
        [60*u - 180*u2 + 120*u3, -36*u + 96*u2 - 60*u3, -24*u + 84*u2 - 60*u3,
         (2 - 18*u + 36*u2 - 20*u3) / 2, (6*u - 24*u2 + 20*u3) / 2],
    ])  # fmt: skip


def check_model(robot: Robot | FamilyRobot, model: Robot | FamilyRobot) -> None:
    """Refuse a controller model whose geometry differs from the plant's robot.

    The controller computes the plant's kinematics from the measured pose
    with its model: ``l0`` must be the same (masses, inertias, centres of
    mass and gravity may differ: that is what a model error is).  A family
    robot's model is a family robot of the same architecture, actuated joint
    and ``[leg]`` (docs/family.md §2).

    >>> check_model(Robot(), Robot(l0=0.31))
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: model: l0 = 0.31 m differs from the plant robot's l0 = 0.3 m (the controller's kinematics must match the robot's)
    """
    if isinstance(robot, FamilyRobot) or isinstance(model, FamilyRobot):
        _check_family_model(robot, model)
        return
    check_robot(robot)
    check_robot(model, "model")
    if model.l0 != robot.l0:
        raise ParameterError(
            f"model: l0 = {model.l0!r} m differs from the plant robot's l0 = {robot.l0!r} m "
            "(the controller's kinematics must match the robot's)"
        )


def _check_family_model(robot: object, model: object) -> None:
    """:func:`check_model` of a family robot: the same architecture, actuation and legs."""
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    model = check_instance("model", model, FamilyRobot, "a prp3.family.FamilyRobot like the robot")
    for name in ("architecture", "actuated", "leg"):
        if getattr(model, name) != getattr(robot, name):
            raise ParameterError(
                f"model: its {name} differs from the plant robot's ({getattr(model, name)!r} "
                f"against {getattr(robot, name)!r}): the controller's kinematics must match "
                "the robot's",
                subject="model",
                key=name,
            )


# ------------------------------------------------------------------ closed loop
@dataclass(frozen=True)
class Tracking:
    """A closed-loop run: measured states, reference and forces at the control instants.

    Row ``k`` is the measured state at ``t[k]`` and the force held from
    ``t[k]`` to ``t[k+1]`` (the last row's force is the one the controller
    computed there).  A run stopped early holds the rows up to the last
    instant with a force.

    Attributes
    ----------
    t : ndarray (N,)
        Control instants (s).
    pose, velocity : ndarray (N, 3)
        Measured ``(x, y, φ)`` and ``(ẋ, ẏ, φ̇)`` (m, rad, m/s, rad/s).
    reference : Motion
        The reference at ``t``.
    f10 : ndarray (N, 3)
        Forces of actuators A, B, C (N).
    step_time : ndarray (N,)
        Wall time of each controller step (inverse dynamics + control law), s.
    controller, plant : str
    status : {"completed", "singular", "stroke", "failed"}
        ``completed``: reached the last instant; ``singular``: the plant came
        within ``|sin(φ − π/3)| < 1e-4`` of the singularity; ``stroke``: an
        actuator of the plant left ``limits.stroke``; ``failed``: the plant's
        simulation failed.
    message : str
        One line saying what happened.
    """

    t: FloatArray
    pose: FloatArray
    velocity: FloatArray
    reference: Motion
    f10: FloatArray
    step_time: FloatArray
    controller: Controller
    plant: Plant
    status: Status
    message: str

    @property
    def error(self) -> FloatArray:
        """Tracking error ``q_ref − q`` (N, 3) (m, m, rad)."""
        return np.asarray(self.reference.pose - self.pose, dtype=np.float64)

    @property
    def max_error(self) -> FloatArray:
        """Largest ``|q_ref − q|`` of ``x, y, φ`` (3,) (m, m, rad)."""
        return np.asarray(np.abs(self.error).max(axis=0), dtype=np.float64)

    @property
    def rms_error(self) -> FloatArray:
        """Root mean square of ``q_ref − q`` over the instants (3,) (m, m, rad)."""
        return np.asarray(np.sqrt(np.mean(self.error**2, axis=0)), dtype=np.float64)

    @property
    def step_time_median(self) -> float:
        """Median wall time of a controller step (s)."""
        return float(np.median(self.step_time))

    @property
    def step_time_p99(self) -> float:
        """99th percentile of the wall time of a controller step (s)."""
        return float(np.percentile(self.step_time, 99.0))


def _refusal(robot: Robot | FamilyRobot, pose: list[float]) -> tuple[Status, str] | None:
    """Why the plant's measured ``pose`` stops the run (singular, outside the stroke), if so."""
    if isinstance(robot, FamilyRobot):
        margin = singularity_margin(robot, pose)
        if margin < SINGULARITY_THRESHOLD:
            return "singular", (
                f"the smallest signed singularity measure is {margin:.3g} at (x = {pose[0]:.6g} "
                f"m, y = {pose[1]:.6g} m, phi = {pose[2]:.9g} rad), below "
                f"{SINGULARITY_THRESHOLD:g} (docs/family.md §6)"
            )
        return None
    try:
        inverse_geometry(robot, pose)
    except SingularPoseError as error:
        return "singular", str(error)
    except UnreachablePoseError as error:
        return "stroke", str(error)
    except TrajectoryError as error:
        return "failed", str(error)
    return None


def _checked_options(
    robot: Robot | FamilyRobot,
    model: Robot | FamilyRobot | None,
    gains: Gains | None,
    controller: str,
    plant: str,
) -> tuple[Robot | FamilyRobot, Gains]:
    """The robot and the options of :func:`track` checked; the model and the gains."""
    if not isinstance(robot, FamilyRobot):
        check_robot(robot)
    model = robot if model is None else model
    check_model(robot, model)
    gains = Gains() if gains is None else gains
    if not isinstance(gains, Gains):
        raise ParameterError(
            f"gains must be prp3.apps.control_law.Gains, got {type(gains).__name__}"
        )
    if controller not in CONTROLLERS:
        raise ParameterError(
            f"controller must be one of {', '.join(CONTROLLERS)}, got {controller!r}"
        )
    if plant not in PLANTS:
        raise ParameterError(f"plant must be one of {', '.join(PLANTS)}, got {plant!r}")
    return model, gains


def _checked_reference(
    robot: Robot | FamilyRobot, model: Robot | FamilyRobot, reference: Motion
) -> CompiledRobot | FamilyEffortModel:
    """The reference of :func:`track` checked (the plant and the model can follow it, naming
    the sample) and the model the controller evaluates."""
    family = isinstance(robot, FamilyRobot)
    if not isinstance(reference, Motion) or reference.t.ndim != 1 or reference.samples < 2:
        raise TrajectoryError("reference must be a Motion of at least 2 samples")
    if reference.load is not None:
        raise TrajectoryError(LOAD_REFUSAL, subject="reference")
    if not family:
        check_path(reference.t, reference.pose, subject="reference")  # no singularity between
    if reference.samples > MAX_STEPS + 1:
        raise ParameterError(
            f"reference: {reference.samples} control instants, more than {MAX_STEPS + 1}"
        )
    compiled: CompiledRobot | FamilyEffortModel
    try:
        if isinstance(robot, FamilyRobot) and isinstance(model, FamilyRobot):
            compiled = FamilyEffortModel(model)
            # both follow the reference from home, every step in between checked (§5, §6)
            family_kinematics(robot, reference)
            family_inverse_dynamics(model, reference, engine="numpy")
        elif isinstance(robot, Robot) and isinstance(model, Robot):
            compiled = compile_robot(without_limits(model))
            inverse_geometry(robot, reference.pose)  # the plant must be able to follow it
            # the model's inverse dynamics of the reference itself: validates it for the model
            paper_forces(compiled, reference.pose, reference.velocity, reference.acceleration)
    except (SingularPoseError, UnreachablePoseError, TrajectoryError) as error:
        index = error.sample
        when = None if index is None else float(reference.t[index])
        raise error.located(origin="reference", time=when) from None
    return compiled


def _closed_loop(
    simulator: PlantProtocol,
    robot: Robot | FamilyRobot,
    compiled: CompiledRobot | FamilyEffortModel,
    controller: Controller,
    gains: Gains,
    reference: Motion,
    progress: Callable[[int, int], None] | None,
) -> tuple[FloatArray, FloatArray, FloatArray, int, Status, str]:
    """The loop of :func:`track`: the measured states ``(N, 6)``, the forces ``(N, 3)``, the
    controller's step times (s), the instants done, the status and its message."""
    times = reference.t.tolist()
    rows = np.concatenate([reference.pose, reference.velocity, reference.acceleration], axis=1)
    targets = rows.tolist()
    count = len(times)
    measured = np.empty((count, 6))
    forces = np.empty((count, 3))
    elapsed = np.empty(count)
    clock = time.perf_counter_ns
    status: Status = "completed"
    message = f"completed: tracked to t = {times[-1]!r} s"
    done = 0
    for k in range(count):
        state = simulator.measure()
        if not all(math.isfinite(value) for value in state):
            status, message = "failed", f"stopped at t = {times[k]!r} s: non-finite plant state"
            break
        refused = _refusal(robot, state[:3])  # the exact checks, before the timed step
        if refused is None:
            start = clock()
            try:
                f10 = control_force(controller, compiled, gains, targets[k], state)
            except Prp3Error as error:  # the model's own refusal of the measured state
                refused = ("singular", str(error))
            stop = clock()
        if refused is not None:
            status, why = refused
            message = f"stopped at t = {times[k]!r} s: the plant's pose is refused: {why}"
            break
        measured[k] = state
        forces[k] = f10
        elapsed[k] = (stop - start) * 1e-9
        done = k + 1
        if progress is not None:
            progress(done, count)
        if not math.isfinite(f10[0] + f10[1] + f10[2]):
            status, message = "failed", f"stopped at t = {times[k]!r} s: non-finite forces"
            break
        if k + 1 < count:
            stopped = simulator.advance(times[k], times[k + 1], f10)
            if stopped is not None:
                status, message = stopped
                break
    return measured, forces, elapsed, done, status, message


def track(
    robot: Robot | FamilyRobot,
    reference: Motion,
    *,
    controller: Controller = "computed-torque",
    plant: Plant = "prp3",
    model: Robot | FamilyRobot | None = None,
    gains: Gains | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Tracking:
    """Simulate the closed loop: the controller at the instants ``reference.t``, the plant between.

    The plant starts in the reference's first state; at each instant the
    controller measures the plant's state, computes :func:`control_force`
    with ``model`` (default: ``robot`` itself) and the plant holds the force
    until the next instant.

    Parameters
    ----------
    robot : Robot or FamilyRobot
        The plant's robot (the "real" one); its ``limits.stroke`` stops the run.
        A family robot of any architecture (docs/family.md) runs the same laws
        on its actuator efforts ``tau`` (:attr:`Tracking.f10` holds them, N or
        N·m), on the ``"prp3"`` plant (its ``τ = A·ẍ + b``,
        :func:`prp3.family.forward.platform_dynamics`).
    reference : Motion
        ``N >= 2`` samples at the control instants (:func:`control_times`
        with :func:`prp3.model.motion.law_at` or :func:`hermite_reference`).
    controller : {"computed-torque", "pd", "feedforward"}
    plant : {"prp3", "mujoco"}
    model : Robot or FamilyRobot, optional
        The controller's model; same ``l0`` as ``robot`` (:func:`check_model`).
    gains : Gains, optional
        Default ``KP = 400 1/s²``, ``KD = 40 1/s`` on every axis.
    progress : callable, optional
        ``progress(instants_done, N)`` after every control instant.

    Returns
    -------
    Tracking

    Raises
    ------
    ParameterError
        Unknown controller or plant, bad gains, a model of another geometry.
    Prp3Error
        ``plant="mujoco"`` without MuJoCo installed.
    TrajectoryError, SingularPoseError, UnreachablePoseError
        A reference the robot or the model cannot follow (names the sample).
    """
    model, gains = _checked_options(robot, model, gains, controller, plant)
    compiled = _checked_reference(robot, model, reference)
    check_plant(robot, plant)
    simulator: PlantProtocol = (
        Prp3Plant(robot, reference) if plant == "prp3" else MujocoPlant(robot, reference)
    )
    measured, forces, elapsed, done, status, message = _closed_loop(
        simulator, robot, compiled, controller, gains, reference, progress
    )
    if done == 0:
        raise TrajectoryError(f"the plant could not start: {message}")
    return Tracking(
        t=reference.t[:done].copy(),
        pose=measured[:done, :3].copy(),
        velocity=measured[:done, 3:].copy(),
        reference=reference[:done],
        f10=forces[:done].copy(),
        step_time=elapsed[:done].copy(),
        controller=controller,
        plant=plant,
        status=status,
        message=message,
    )
