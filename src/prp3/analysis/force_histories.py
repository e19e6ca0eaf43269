"""The actuator force histories ``f10(t)`` and loads that drive forward dynamics.

Sampled forces (:class:`ActuatorForces`, a cubic spline between the samples)
or functions of time, validated against the integration's time span and
``[limits] max_force`` before :func:`prp3.analysis.forward.forward_dynamics`
integrates them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError, TrajectoryError
from prp3.model.robot import Robot
from prp3.validation import LEGS, check_finite, check_real, check_times

__all__ = [
    "ActuatorForces",
]

FloatArray = NDArray[np.float64]
ForceFunction = Callable[[float], ArrayLike]


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
        t.flags.writeable = False
        f10.flags.writeable = False
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "f10", f10)
        spline = _spline(t, f10, tuple(f"f10_{leg}" for leg in LEGS), "force")
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
            load_spline = _spline(t, load, LOAD_NAMES, "load")
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


#: The names of the load's components (the columns of a force file).
LOAD_NAMES: tuple[str, str, str] = ("fx", "fy", "mz")


def _spline(t: FloatArray, values: FloatArray, names: tuple[str, ...], what: str) -> Any:
    """The not-a-knot cubic spline through ``values (N, 3)``, refused where it overflows.

    Its slopes or its coefficients overflow float64 when the samples are huge
    (``±1e308``) or the time steps tiny (``1e-300 s``): the refusal names the
    component (``names``, the columns of a force file) and the interval.
    """
    from scipy.interpolate import CubicSpline

    with np.errstate(all="ignore"):
        slopes = np.diff(values, axis=0) / np.diff(t)[:, None]
    bad_slopes = ~np.isfinite(slopes)
    if bad_slopes.any():
        index, column = np.argwhere(bad_slopes)[0].tolist()
        ends = f"{float(values[index, column])!r} to {float(values[index + 1, column])!r}"
        raise _not_interpolable(
            t, index, f"the rate of change of {names[column]} overflows (from {ends})", what,
            names[column],
        )  # fmt: skip
    try:
        with np.errstate(all="ignore"):
            spline = CubicSpline(t, values, axis=0)
    except ValueError:  # the spline's own slopes overflow (scipy's check): the largest sample
        index, column = (int(v) for v in np.unravel_index(np.argmax(np.abs(values)), values.shape))
        raise TrajectoryError(
            f"the {what} samples cannot be interpolated: the slopes of the {what} spline "
            f"overflow float64; the largest sample is {names[column]} = "
            f"{float(values[index, column])!r} ({what} too large for its time steps)",
            subject="forces",
            key=names[column],
            sample=index,
        ) from None
    bad = ~np.isfinite(spline.c).all(axis=0)  # (4, N - 1, 3) coefficients per interval
    if bad.any():  # steps so small (1e-300 s) that the cubic terms overflow
        index, column = np.argwhere(bad)[0].tolist()
        raise _not_interpolable(
            t, index, f"the spline coefficients of {names[column]} overflow", what, names[column]
        )
    return spline


def _not_interpolable(
    t: FloatArray, index: int, what: str, kind: str, column: str | None
) -> TrajectoryError:
    return TrajectoryError(
        f"the {kind} samples cannot be interpolated: {what} between t[{index}] = "
        f"{float(t[index])!r} and t[{index + 1}] = {float(t[index + 1])!r} s ({kind} too "
        "large or time steps too small)",
        subject="forces",
        key=column,
        sample=index,
    )


def force_function(
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
        sampled_t, sampled, table = forces.t, forces.f10, True
    elif callable(forces):
        sampled_t, table = times, False
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
                sample=index if table else None,  # a sample of the table (a file's row)
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


def load_function(
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
