"""The bounds of a forward-dynamics integration: evaluations and wall time of its right-hand side.

:class:`IntegrationBounds` wraps the right-hand side that ``scipy.integrate.solve_ivp``
calls: it counts the evaluations, checks the wall time every :data:`CLOCK_EVERY`
evaluations, keeps the furthest time evaluated, and raises :class:`BoundReachedError`
when ``max_evaluations`` or ``max_seconds`` is reached; :meth:`IntegrationBounds.refusal`
turns that stop into the :class:`~prp3.errors.TrajectoryError` naming the bound, the
evaluations and the time reached.  Shared by the forward dynamics of the 3-PRP, of the
family and of the spatial robots.

>>> bounds = IntegrationBounds(2, 600.0, 0.0)
>>> rhs = bounds.bounded(lambda time, state: state)
>>> rhs(0.5, 1.0), rhs(0.75, 2.0)
(1.0, 2.0)
>>> try:
...     rhs(1.0, 3.0)
... except BoundReachedError as stop:
...     print(bounds.refusal(stop, (0.0, 1.0)))
forward dynamics: the integration was stopped by its bound max_evaluations = 2 after 2 evaluations of the equations of motion, at t = 0.75 s of [0.0, 1.0] s
"""

from __future__ import annotations

import time as time_module
from collections.abc import Callable
from typing import Any

from prp3.errors import TrajectoryError

__all__ = ["CLOCK_EVERY", "BoundReachedError", "IntegrationBounds"]

#: The wall time is read before every this many evaluations (the 64th, 128th, ...).
CLOCK_EVERY: int = 64


class BoundReachedError(Exception):
    """Raised inside the integrator's right-hand side when a bound of the run is reached.

    Its one argument names the bound (``"max_evaluations = 500"``).
    """


class IntegrationBounds:
    """The evaluation count, the wall clock and the furthest time of one integration.

    Parameters
    ----------
    max_evaluations : int
        At most this many evaluations of the right-hand side.
    max_seconds : float
        Wall-time bound (s).
    t0 : float
        The first time of the integration (s): the time reached before any evaluation.
    """

    def __init__(self, max_evaluations: int, max_seconds: float, t0: float) -> None:
        self.max_evaluations = max_evaluations
        self.max_seconds = max_seconds
        self.evaluations = 0
        self.furthest = float(t0)
        self.start = time_module.monotonic()

    def check(self, time: float) -> None:
        """Count one evaluation at ``time``, or raise :class:`BoundReachedError` at a bound."""
        if self.evaluations >= self.max_evaluations:
            raise BoundReachedError(f"max_evaluations = {self.max_evaluations}")
        if (self.evaluations + 1) % CLOCK_EVERY == 0 and (
            time_module.monotonic() - self.start > self.max_seconds
        ):
            raise BoundReachedError(f"max_seconds = {self.max_seconds!r} s (wall time)")
        self.evaluations += 1
        self.furthest = max(self.furthest, float(time))

    def bounded(self, rhs: Callable[[float, Any], Any]) -> Callable[[float, Any], Any]:
        """``rhs`` as the integrator calls it: counted, and stopped at a bound."""

        def call(time: float, state: Any) -> Any:
            self.check(time)
            return rhs(time, state)

        return call

    def refusal(
        self, stop: BoundReachedError, span: tuple[float, float], detail: str = ""
    ) -> TrajectoryError:
        """The error of a run stopped by a bound: the bound, evaluations, time reached, ``detail``."""
        return TrajectoryError(
            f"the integration was stopped by its bound {stop.args[0]} after {self.evaluations} "
            f"evaluations of the equations of motion, at t = {self.furthest!r} s of "
            f"[{float(span[0])!r}, {float(span[1])!r}] s{detail}",
            subject="forward dynamics",
            time=self.furthest,
        )
