"""An exciting motion for identification: a Fourier series that conditions the base regressor.

:func:`exciting_trajectory` designs a motion (a finite Fourier series,
:class:`FourierSeries`) that makes the base regressor of ``f10``
(:mod:`prp3.apps.regressor`, :mod:`prp3.apps.base_parameters`) well
conditioned within the robot's limits; ``prp3 excite`` writes it as a
trajectory file.  ``docs/identification.md`` works through it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.apps.base_parameters import base_parameters
from prp3.apps.identification import excitation_refusal
from prp3.apps.regressor import _regressor_rows, _state_rows, _unit_parameters, standard_parameters
from prp3.errors import ParameterError
from prp3.model.motion import Motion
from prp3.model.parameters import Limits
from prp3.model.robot import Robot
from prp3.validation import check_integer, check_robot, check_scalar

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

    def motion(self, t: FloatArray) -> Motion:
        """Pose, velocity and acceleration at times ``t`` (analytic derivatives)."""
        time = np.asarray(t, dtype=np.float64)
        harmonics = np.arange(1, self.sine.shape[1] + 1)
        w = 2.0 * math.pi / self.period * harmonics  # (L,)
        arg = time[:, None] * w  # (N, L)
        s, c = np.sin(arg), np.cos(arg)
        pose = self.offset + s @ self.sine.T + c @ self.cosine.T
        velocity = (c * w) @ self.sine.T - (s * w) @ self.cosine.T
        acceleration = -(s * w**2) @ self.sine.T - (c * w**2) @ self.cosine.T
        return Motion(t=time, pose=pose, velocity=velocity, acceleration=acceleration)


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
        Largest ``|λ10|`` (m), ``|λ̇10|`` (m/s) and ``|f10|`` (N) of the nominal robot.
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


def exciting_trajectory(
    robot: Robot,
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

    Raises
    ------
    ParameterError
        Bad options, no feasible motion found (names the violated limit), or
        limits within which no motion found excites every base parameter (names
        the limit that binds and the condition number).
    """
    from scipy.optimize import minimize

    check_robot(robot)
    period, reach, rotation, max_velocity = (
        check_scalar(name, value, positive=True)
        for name, value in (("period", period), ("reach", reach), ("rotation", rotation),
                            ("max_velocity", max_velocity))
    )  # fmt: skip
    if not 0.0 < rotation < 1.0:
        raise ParameterError(f"rotation must be in (0, 1) rad (singular at pi/3), got {rotation!r}")
    harmonics = check_integer("harmonics", harmonics, 1, 20)
    samples = check_integer("samples", samples, 2, 10**7)
    seed = check_integer("seed", seed, 0, 2**63 - 1)
    max_iterations = check_integer("max_iterations", max_iterations, 1, 10**6)
    if max_force is not None:
        max_force = check_scalar("max_force", max_force, positive=True)
    force_limit = max_force if max_force is not None else robot.limits.max_force
    base = base_parameters(robot)
    free = replace(robot, limits=Limits())
    units = _unit_parameters(free, base.names)
    nominal = base.values(standard_parameters(robot))
    coarse = t = np.linspace(0.0, period, samples, endpoint=False)
    L = harmonics
    bounds = np.array([reach * robot.l0, reach * robot.l0, rotation])
    stroke = robot.limits.stroke

    def unpack(z: FloatArray) -> FourierSeries:
        return FourierSeries(
            period=period,
            offset=z[:3] * bounds,
            sine=z[3 : 3 + 3 * L].reshape(3, L) * bounds[:, None],
            cosine=z[3 + 3 * L :].reshape(3, L) * bounds[:, None],
        )

    def evaluate(z: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        motion = unpack(z).motion(t)
        with np.errstate(all="ignore"):
            forces, lam, dlam = _regressor_rows(units, _state_rows(motion))
        return forces[0].reshape(-1, base.count), motion.pose, lam, dlam

    def objective(z: FloatArray) -> float:
        W = evaluate(z)[0]
        singular = np.linalg.svd(W, compute_uv=False)
        if not np.isfinite(singular).all() or singular[-1] <= 0.0:
            return 1e3
        return float(np.log(singular[0] / singular[-1]))

    def margins(z: FloatArray) -> list[tuple[str, FloatArray]]:
        """Margins to each limit (>= 0 inside, relative), with the limit's name."""
        W, pose, lam, dlam = evaluate(z)
        parts = [
            (f"reach = {reach!r} l0 (--reach)", 1.0 - np.abs(pose[:, :2] / bounds[:2])),
            (f"rotation = {rotation!r} rad (--rotation)", 1.0 - np.abs(pose[:, 2] / bounds[2])),
            (
                f"max_velocity = {max_velocity!r} m/s (--max-velocity)",
                1.0 - np.abs(dlam) / max_velocity,
            ),
        ]
        if stroke is not None:
            lower, upper = stroke
            margin = np.minimum((upper - lam) / upper, (lam - lower) / -lower)
            parts.append((f"the robot's [limits] stroke = {list(stroke)!r} m", margin))
        if force_limit is not None:
            parts.append(
                (
                    f"max_force = {force_limit!r} N (--max-force or [limits] max_force)",
                    1.0 - np.abs(W @ nominal) / force_limit,
                )
            )
        return parts

    def constraints(z: FloatArray) -> FloatArray:
        """Margins to the limits (>= 0 inside), 1 % kept for the instants between samples."""
        return np.concatenate([part.reshape(-1) for _, part in margins(z)]) - _LIMIT_MARGIN

    rng = np.random.default_rng(seed)
    z0 = np.concatenate([np.zeros(3), rng.uniform(-1.0, 1.0, 6 * L) * 0.3 / L])
    for _ in range(30):  # shrink the guess into the limits
        if constraints(z0).min() >= 0.0:
            break
        z0[3:] *= 0.5
    else:
        raise ParameterError("no motion within the limits found (limits too tight)")
    initial = math.exp(objective(z0))
    solution: Any = minimize(
        objective,
        z0,
        method="SLSQP",
        constraints=[{"type": "ineq", "fun": constraints}],
        bounds=[(-1.0, 1.0)] * 3 + [(-1.0, 1.0)] * (6 * L),
        options={"maxiter": max_iterations, "ftol": 1e-6},
        callback=None if progress is None else _counter(progress, max_iterations),
    )
    if progress is not None:
        progress(max_iterations, max_iterations)
    z = np.asarray(solution.x, dtype=np.float64)
    if constraints(z).min() < -1e-6 or objective(z) > objective(z0):
        z = z0  # the optimiser left the limits: keep the feasible guess
    t = np.linspace(0.0, period, _FINE_SAMPLES)  # the limits between the samples too
    for _ in range(40):
        worst = float(constraints(z).min())
        if worst >= 0.0:
            break
        z[3:] *= 1.0 - max(0.01, 2.0 * -worst)  # a smaller oscillation about the offset
    else:  # pragma: no cover - the offset alone satisfies the limits
        z = z0
    # on the fine instants: the limit that binds, and identification's criterion
    binding = min(margins(z), key=lambda part: float(part[1].min()))[0]
    W, _, lam, dlam = evaluate(z)
    t = coarse
    refused = excitation_refusal(base, W)
    if refused is not None:
        raise ParameterError(
            f"no motion found within the limits excites every base parameter: the limit that "
            f"binds is {binding}, and {refused}; widen it"
        )
    return ExcitingTrajectory(
        series=unpack(z),
        condition=math.exp(objective(z)),
        initial_condition=initial,
        peak_lambda10=float(np.abs(lam).max()),
        peak_dlambda10=float(np.abs(dlam).max()),
        peak_f10=float(np.abs(W @ nominal).max()),
        iterations=int(getattr(solution, "nit", 0)),
    )
