"""An exciting motion for identification: a Fourier series that conditions the base regressor.

:func:`exciting_trajectory` designs a motion (a finite Fourier series,
:class:`FourierSeries`) that makes the base regressor of ``f10``
(:mod:`prp3.apps.regressor`, :mod:`prp3.apps.base_parameters`) well
conditioned within the robot's limits; ``prp3 excite`` writes it as a
trajectory file.  A family robot (:class:`~prp3.family.model.FamilyRobot`,
docs/family.md) gets the same, about its home pose, for the base regressor of
its actuator efforts (:mod:`prp3.apps.family_regressor`).  ``docs/identification.md`` works through it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.apps.base_parameters import BaseParameters, base_parameters
from prp3.apps.family_regressor import family_standard_parameters, unit_efforts
from prp3.apps.identification import excitation_refusal
from prp3.apps.regressor import regressor_rows, standard_parameters, state_rows, unit_parameters
from prp3.errors import ParameterError, SingularPoseError, UnreachablePoseError
from prp3.family.mechanics import family_kinematics, fast_dynamics
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.model.parameters import Limits
from prp3.model.robot import Robot
from prp3.validation import (
    check_integer,
    check_real,
    check_robot,
    check_scalar,
    check_times,
    require_finite,
)

__all__ = [
    "ExcitingTrajectory",
    "FourierSeries",
    "exciting_trajectory",
]

FloatArray = NDArray[np.float64]

#: Fraction of each limit kept free by the optimiser (the limits hold between its samples).
_LIMIT_MARGIN: float = 0.01

#: Instants per period at which the optimised motion is checked against the limits.
_FINE_SAMPLES: int = 2000


@dataclass(frozen=True)
class FourierSeries:
    """A finite Fourier series of the platform pose (a periodic exciting motion).

    ``q_k(t) = q0_k + Σ_l (a_kl·sin(l·ω·t) + b_kl·cos(l·ω·t))``,
    ``ω = 2π/period``, ``l = 1..L``, for ``k = x, y, φ``.

    Attributes
    ----------
    period : float
        ``2π/ω`` (s).
    offset : ndarray, shape (3,)
        ``q0`` (m, m, rad).
    sine, cosine : ndarray, shape (3, L)
        ``a`` and ``b`` (m, m, rad).
    """

    period: float
    offset: FloatArray
    sine: FloatArray
    cosine: FloatArray

    def __post_init__(self) -> None:
        """Refuse a bad field (:class:`~prp3.errors.ParameterError` naming it); store float64 copies.

        >>> FourierSeries(0.0, np.zeros(3), np.zeros((3, 1)), np.zeros((3, 1)))
        Traceback (most recent call last):
        ...
        prp3.errors.ParameterError: period must be a positive finite number (s), got 0.0
        """
        period = check_scalar("period", self.period, positive=True, unit="s")
        offset = _field("offset", self.offset)
        if offset.shape != (3,):
            raise ParameterError(
                f"offset must have shape (3,) (x, y, phi), got {offset.shape}", key="offset"
            )
        sine = _field("sine", self.sine)
        if sine.ndim != 2 or sine.shape[0] != 3 or sine.shape[1] < 1:
            raise ParameterError(
                f"sine must have shape (3, L) with L >= 1 harmonics, got {sine.shape}", key="sine"
            )
        cosine = _field("cosine", self.cosine)
        if cosine.shape != sine.shape:
            raise ParameterError(
                f"cosine must have the shape of sine {sine.shape}, got {cosine.shape}",
                key="cosine",
            )
        for name, value in (
            ("period", period),
            ("offset", offset),
            ("sine", sine),
            ("cosine", cosine),
        ):
            object.__setattr__(self, name, value)

    def motion(self, t: FloatArray) -> Motion:
        """Pose, velocity and acceleration at times ``t`` (s, shape ``(N,)``; analytic derivatives).

        Raises
        ------
        TrajectoryError
            ``t`` not finite, strictly increasing times of shape ``(N,)``, or a
            motion too large for double precision.
        """
        time = check_times("t", t)
        harmonics = np.arange(1, self.sine.shape[1] + 1)
        w = 2.0 * math.pi / self.period * harmonics  # (L,)
        with np.errstate(all="ignore"):  # an overflow is refused below, naming the sample
            arg = time[:, None] * w  # (N, L)
            s, c = np.sin(arg), np.cos(arg)
            pose = self.offset + s @ self.sine.T + c @ self.cosine.T
            velocity = (c * w) @ self.sine.T - (s * w) @ self.cosine.T
            acceleration = -(s * w**2) @ self.sine.T - (c * w**2) @ self.cosine.T
        require_finite(
            {"pose": pose, "velocity": velocity, "acceleration": acceleration},
            time.shape,
            "FourierSeries.motion",
            time,
        )
        return Motion(t=time, pose=pose, velocity=velocity, acceleration=acceleration)


def _field(name: str, value: object) -> FloatArray:
    """A finite float64 array of the field ``name`` of a :class:`FourierSeries`."""
    array = check_real(name, value, ParameterError)  # type: ignore[arg-type]
    bad = np.argwhere(~np.isfinite(array))
    if bad.size:
        index = tuple(bad[0].tolist())
        where = ", ".join(str(i) for i in index)
        raise ParameterError(f"{name}[{where}] is not finite ({float(array[index])!r})", key=name)
    return array


@dataclass(frozen=True)
class ExcitingTrajectory:
    """An optimised exciting motion from :func:`exciting_trajectory`.

    Attributes
    ----------
    series : FourierSeries
        The motion.
    condition : float
        Condition number of the stacked base regressor of ``f10`` on the
        optimisation samples (SI units).
    initial_condition : float
        The same for the starting guess.
    peak_lambda10, peak_dlambda10, peak_f10 : float
        Largest ``|λ10|`` (m), ``|λ̇10|`` (m/s) and ``|f10|`` (N) of the nominal robot;
        of a family robot, of its actuated joints' ``q`` (m or rad, about 0),
        ``q̇`` and efforts ``τ`` (N or N·m, with its ``[load]``).
    iterations : int
        Optimiser iterations.
    """

    series: FourierSeries
    condition: float
    initial_condition: float
    peak_lambda10: float
    peak_dlambda10: float
    peak_f10: float
    iterations: int


def _counter(progress: Callable[[int, int], None], total: int) -> Callable[..., None]:
    """A ``minimize`` callback that reports the iterations done of ``total``."""
    done = [0]

    def step(*_: object) -> None:
        done[0] += 1
        progress(min(done[0], total), total)

    return step


#: The singularity measures of a family robot's exciting motion stay above this fraction of
#: their home values.
_MEASURE_FRACTION: float = 0.25


def exciting_trajectory(
    robot: Robot | FamilyRobot,
    *,
    period: float = 5.0,
    harmonics: int = 4,
    reach: float = 0.2,
    rotation: float = 0.5,
    max_velocity: float = 0.5,
    max_force: float | None = None,
    samples: int = 120,
    seed: int = 0,
    max_iterations: int = 150,
    progress: Callable[[int, int], None] | None = None,
) -> ExcitingTrajectory:
    """A Fourier-series motion that minimises the condition number of the base regressor.

    Minimises ``log cond(W)`` of the stacked base regressor of ``f10``
    (:func:`base_parameters`) on ``samples`` instants of one period, by SLSQP
    (``scipy.optimize.minimize``) over the offsets and coefficients, under
    constraints at those instants: ``|x|, |y| ≤ reach·l0``,
    ``|φ| ≤ rotation`` (rad, away from the singularity ``φ = π/3``),
    ``λ10`` inside ``robot.limits.stroke`` (when set), ``|λ̇10| ≤ max_velocity``
    and ``|f10| ≤ max_force`` (default ``robot.limits.max_force``; none if
    neither) of the nominal robot.  ``progress(iterations_done,
    max_iterations)`` is called after every SLSQP iteration (and with
    ``max_iterations`` at the end: the optimiser may stop earlier).

    The motion found must excite every base parameter by the criterion of
    :func:`prp3.apps.identification.identify`
    (:func:`~prp3.apps.identification.excitation_refusal`, on the optimisation
    samples): limits so tight that it does not (a stroke of ±0.1 mm) are
    refused, naming the limit that binds, rather than a motion returned that
    identification would refuse.

    A family robot (docs/family.md): the same about its home pose ``(x0, y0,
    φ0)`` (``robot.home_poses``): ``|x − x0|, |y − y0| ≤ reach·ℓ`` (``ℓ =
    robot.leg.scale``), ``|φ − φ0| ≤ rotation`` (``< π``), ``|q̇| ≤ max_velocity``
    of the actuated joints (m/s or rad/s), ``|τ| ≤ max_force`` (N or N·m, none by
    default) and the singularity measures ``|μ_leg|``, ``|μ_par|`` (docs/family.md
    §6) above a quarter of their home values; the base regressor of its efforts
    ``τ`` (:func:`prp3.apps.family_regressor.family_regressor`).

    Raises
    ------
    ParameterError
        Bad options, no feasible motion found (names the violated limit), or
        limits within which no motion found excites every base parameter (names
        the limit that binds and the condition number).
    """
    family = isinstance(robot, FamilyRobot)
    period, limits = _checked_limits(robot, period, reach, rotation, max_velocity, max_force)
    harmonics = check_integer("harmonics", harmonics, 1, 20)
    samples = check_integer("samples", samples, 2, 10**7)
    seed = check_integer("seed", seed, 0, 2**63 - 1)
    max_iterations = check_integer("max_iterations", max_iterations, 1, 10**6)
    if max_force is not None:
        limits = (*limits[:3], check_scalar("max_force", max_force, positive=True))
    coarse = np.linspace(0.0, period, samples, endpoint=False)
    problem = _Problem(robot, base_parameters(robot), period, harmonics, limits, coarse)
    z0 = _initial_guess(problem, seed)
    initial = math.exp(problem.objective(z0))
    solution = _slsqp(problem, z0, max_iterations, progress)
    z = np.asarray(solution.x, dtype=np.float64)
    # (a family robot's: within 5 % of its limits, the smaller oscillation below repairs it)
    worst = problem.constraints(z).min()
    if worst < (-0.05 if family else -1e-6) or problem.objective(z) > problem.objective(z0):
        z = z0  # the optimiser left the limits: keep the feasible guess
    z, lam, dlam, effort = _checked_on_fine_instants(problem, z, z0)
    return ExcitingTrajectory(
        series=problem.unpack(z),
        condition=math.exp(problem.objective(z)),
        initial_condition=initial,
        peak_lambda10=float(np.abs(lam).max()),
        peak_dlambda10=float(np.abs(dlam).max()),
        peak_f10=float(np.abs(effort).max()),
        iterations=int(getattr(solution, "nit", 0)),
    )


def _checked_limits(
    robot: Robot | FamilyRobot,
    period: float,
    reach: float,
    rotation: float,
    max_velocity: float,
    max_force: float | None,
) -> tuple[float, tuple[float, float, float, float | None]]:
    """The robot, ``period`` and the limits of :func:`exciting_trajectory` checked (but
    ``max_force``, checked after the counts)."""
    family = isinstance(robot, FamilyRobot)
    if not family:
        check_robot(robot)
    period, reach, rotation, max_velocity = (
        check_scalar(name, value, positive=True)
        for name, value in (("period", period), ("reach", reach), ("rotation", rotation),
                            ("max_velocity", max_velocity))
    )  # fmt: skip
    if family and not rotation < math.pi:
        raise ParameterError(f"rotation must be in (0, pi) rad, got {rotation!r}")
    if not family and not 0.0 < rotation < 1.0:
        raise ParameterError(f"rotation must be in (0, 1) rad (singular at pi/3), got {rotation!r}")
    return period, (reach, rotation, max_velocity, max_force)


def _slsqp(
    problem: _Problem,
    z0: FloatArray,
    max_iterations: int,
    progress: Callable[[int, int], None] | None,
) -> Any:
    """SLSQP's minimum of ``problem.objective`` from ``z0`` within the limits."""
    from scipy.optimize import minimize

    solution = minimize(
        problem.objective,
        z0,
        method="SLSQP",
        constraints=[{"type": "ineq", "fun": problem.constraints}],
        bounds=[(-1.0, 1.0)] * (3 + 6 * problem.L),
        options={"maxiter": max_iterations, "ftol": 1e-6},
        callback=None if progress is None else _counter(progress, max_iterations),
    )
    if progress is not None:
        progress(max_iterations, max_iterations)
    return solution


def _checked_on_fine_instants(
    problem: _Problem, z: FloatArray, z0: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """``z`` within the limits between the samples too (:func:`_within_limits`), and its
    actuated joints' values, rates and efforts there; refused when it does not excite every
    base parameter (naming the limit that binds).  ``problem.t`` is left as it was."""
    coarse = problem.t
    problem.t = np.linspace(0.0, problem.period, _FINE_SAMPLES)
    z = _within_limits(problem, z, z0)
    # on the fine instants: the limit that binds, and identification's criterion
    binding = min(problem.margins(z), key=lambda part: float(part[1].min()))[0]
    W, _, lam, dlam, effort, _ = problem.evaluate(z)
    problem.t = coarse
    refused = excitation_refusal(problem.base, W)
    if refused is not None:
        raise ParameterError(
            f"no motion found within the limits excites every base parameter: the limit that "
            f"binds is {binding}, and {refused}; widen it"
        )
    return z, lam, dlam, effort


_Evaluation = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]


class _Problem:
    """The optimisation of :func:`exciting_trajectory`: the series of a vector ``z`` (the
    offsets and coefficients relative to the bounds), its objective and its margins to the
    limits at the instants ``t`` (an attribute: the coarse or the fine ones)."""

    def __init__(
        self,
        robot: Robot | FamilyRobot,
        base: BaseParameters,
        period: float,
        harmonics: int,
        limits: tuple[float, float, float, float | None],
        t: FloatArray,
    ) -> None:
        self.robot, self.base, self.period, self.L, self.t = robot, base, period, harmonics, t
        self.reach, self.rotation, self.max_velocity, max_force = limits
        self.family = isinstance(robot, FamilyRobot)
        self.last: dict[bytes, _Evaluation] = {}
        self.stroke: tuple[float, float] | None = None
        self.force_limit = max_force
        if isinstance(robot, FamilyRobot):
            length = robot.leg.scale
            self.centre = robot.home_poses.mean(axis=0)
            self.nominal = base.values(family_standard_parameters(robot, base.parameters))
            home_leg, home_par = robot.home_measures
            self.floors = _MEASURE_FRACTION * np.abs(np.array([*home_leg, home_par]))
        else:
            self.force_limit = max_force if max_force is not None else robot.limits.max_force
            length = robot.l0
            self.centre = np.zeros(3)
            self.stroke = robot.limits.stroke
            self.units = unit_parameters(replace(robot, limits=Limits()), base.names)
            self.nominal = base.values(standard_parameters(robot))
        self.bounds = np.array([self.reach * length, self.reach * length, self.rotation])

    def unpack(self, z: FloatArray) -> FourierSeries:
        """The series of ``z``."""
        L, bounds = self.L, self.bounds
        return FourierSeries(
            period=self.period,
            offset=self.centre + z[:3] * bounds,
            sine=z[3 : 3 + 3 * L].reshape(3, L) * bounds[:, None],
            cosine=z[3 + 3 * L :].reshape(3, L) * bounds[:, None],
        )

    def evaluate(self, z: FloatArray) -> _Evaluation:
        """``W`` (3N, B), poses, actuated joints' values and rates, the nominal efforts and
        the margins to a family robot's singularities ``|μ|/floor − 1`` (N, 4; none for the
        3-PRP); the last one kept (SLSQP asks the objective and the constraints at each point).
        """
        key = z.tobytes() + self.t.tobytes()
        if key in self.last:
            return self.last[key]
        motion = self.unpack(z).motion(self.t)
        count = self.base.count
        robot = self.robot
        if not isinstance(robot, FamilyRobot):
            with np.errstate(all="ignore"):
                forces, lam, dlam = regressor_rows(self.units, state_rows(motion))
            W = forces[0].reshape(-1, count)
            result = (W, motion.pose, lam, dlam, W @ self.nominal, np.zeros((0,)))
        else:
            with np.errstate(all="ignore"):
                kin = family_kinematics(robot, motion)
                W = unit_efforts(kin, self.base.names).reshape(-1, count)
                tau = fast_dynamics(kin).tau
            mu = np.concatenate([kin.mu_leg, kin.mu_par[:, None]], axis=-1)
            margin = np.asarray(np.abs(mu) / self.floors - 1.0)
            a = robot.actuated - 1
            result = (W, motion.pose, kin.q[..., a], kin.dq[..., a], tau, margin)
        self.last.clear()
        self.last[key] = result
        return result

    def objective(self, z: FloatArray) -> float:
        """``log cond(W)`` (1e3 where it cannot be computed)."""
        try:
            W = self.evaluate(z)[0]
        except (SingularPoseError, UnreachablePoseError):
            return 1e3
        singular = np.linalg.svd(W, compute_uv=False)
        if not np.isfinite(singular).all() or singular[-1] <= 0.0:
            return 1e3
        return float(np.log(singular[0] / singular[-1]))

    def margins(self, z: FloatArray) -> list[tuple[str, FloatArray]]:
        """Margins to each limit (>= 0 inside, relative), with the limit's name."""
        _, pose, lam, dlam, effort, singular = self.evaluate(z)
        family, bounds, offset = self.family, self.bounds, pose - self.centre
        parts = [
            (
                f"reach = {self.reach!r} {'leg.scale' if family else 'l0'} (--reach)",
                1.0 - np.abs(offset[:, :2] / bounds[:2]),
            ),
            (
                f"rotation = {self.rotation!r} rad (--rotation)",
                1.0 - np.abs(offset[:, 2] / bounds[2]),
            ),
            (
                f"max_velocity = {self.max_velocity!r} {'(m or rad)/s' if family else 'm/s'} "
                "(--max-velocity)",
                1.0 - np.abs(dlam) / self.max_velocity,
            ),
        ]
        if family:
            parts.append(
                (
                    f"the singularity measures (above {_MEASURE_FRACTION:g} of their home values)",
                    singular,
                )
            )
        if self.stroke is not None:
            lower, upper = self.stroke
            margin = np.minimum((upper - lam) / upper, (lam - lower) / -lower)
            parts.append((f"the robot's [limits] stroke = {list(self.stroke)!r} m", margin))
        if self.force_limit is not None:
            parts.append(
                (
                    f"max_force = {self.force_limit!r} {'N or N m' if family else 'N'} "
                    "(--max-force" + (")" if family else " or [limits] max_force)"),
                    1.0 - np.abs(effort) / self.force_limit,
                )
            )
        return parts

    def constraints(self, z: FloatArray) -> FloatArray:
        """Margins to the limits (>= 0 inside), 1 % kept for the instants between samples.

        A motion through a family robot's singularity or out of its reach: every margin -1.
        """
        try:
            parts = self.margins(z)
        except (SingularPoseError, UnreachablePoseError):
            return np.full(self.width(), -1.0)
        return np.concatenate([part.reshape(-1) for _, part in parts]) - _LIMIT_MARGIN

    def width(self) -> int:
        """The number of constraints at the current instants (the offset alone is regular)."""
        return sum(part.size for _, part in self.margins(np.zeros(3 + 6 * self.L)))


def _initial_guess(problem: _Problem, seed: int) -> FloatArray:
    """A random series (``seed``) of small coefficients, halved until within the limits."""
    L = problem.L
    rng = np.random.default_rng(seed)
    z0 = np.concatenate([np.zeros(3), rng.uniform(-1.0, 1.0, 6 * L) * 0.3 / L])
    for _ in range(30):  # shrink the guess into the limits
        if problem.constraints(z0).min() >= 0.0:
            return z0
        z0[3:] *= 0.5
    raise ParameterError("no motion within the limits found (limits too tight)")


def _within_limits(problem: _Problem, z: FloatArray, z0: FloatArray) -> FloatArray:
    """``z`` with a smaller oscillation about its offset until within the limits at
    ``problem.t`` (else the guess ``z0``)."""
    for _ in range(40):
        worst = float(problem.constraints(z).min())
        if worst >= 0.0:
            return z
        z[3:] *= 1.0 - max(0.01, 2.0 * -worst)  # a smaller oscillation about the offset
    return z0  # pragma: no cover - the offset alone satisfies the limits
