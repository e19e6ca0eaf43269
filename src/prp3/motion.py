"""Motion of the platform: pose, velocity and acceleration of ``G`` and ``φ``.

A :class:`Motion` holds ``N`` samples (or a single one) of the platform's
pose ``(x, y, φ)``, velocity ``(ẋ, ẏ, φ̇)`` and acceleration ``(ẍ, ÿ, φ̈)``,
time on the leading axis.  :func:`paper_motion` builds the paper's law
(eq. 4) and its two named examples.

>>> m = paper_motion("vertical", samples=301)
>>> m.pose.shape, float(m.t[-1]), round(float(m.pose[-1, 1]), 12)
((301, 3), 3.0, 0.05)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._checks import real_array
from .errors import TrajectoryError

__all__ = [
    "MAX_SAMPLES",
    "PAPER_DURATION",
    "PAPER_MOTIONS",
    "Motion",
    "law_at",
    "law_motion",
    "paper_motion",
]

FloatArray = NDArray[np.float64]

#: Duration of the paper's simulations (s), section 3.
PAPER_DURATION: float = 3.0

#: Largest number of samples :func:`law_motion` makes.
MAX_SAMPLES: int = 10**9

#: Amplitudes ``(x*, y*, φ*)`` of the paper's two examples (section 3; docs/model.md).
PAPER_MOTIONS: dict[str, tuple[float, float, float]] = {
    "vertical": (0.0, 0.025, 0.0),  # Figs. 3–5
    "rotation": (0.0, 0.0, math.pi / 12.0),  # Figs. 6–8
}


def _float_array(name: str, value: ArrayLike) -> FloatArray:
    return real_array(f"motion: {name}", value, TrajectoryError)


@dataclass(frozen=True)
class Motion:
    """Platform motion sampled at times ``t``.

    Attributes
    ----------
    t : ndarray, shape (N,) or ()
        Sample times (s), strictly increasing.
    pose : ndarray, shape (N, 3) or (3,)
        ``(x, y, φ)``: mass centre ``G`` (m) and orientation (rad).
    velocity : ndarray, same shape as ``pose``
        ``(ẋ, ẏ, φ̇)`` (m/s, m/s, rad/s).
    acceleration : ndarray, same shape as ``pose``
        ``(ẍ, ÿ, φ̈)`` (m/s², m/s², rad/s²).
    load : ndarray, same shape as ``pose``, or None
        ``(f_x, f_y, m_z)``: a time-varying wrench of the environment on the
        platform, force at ``G`` in the fixed frame (N) and moment about ``z0``
        (N·m), added to the robot's constant ``[load]``; ``None``: no such wrench.

    A single sample (``t`` of shape ``()``, arrays ``(3,)``) gives results of
    rank one less than a batch: the output rank follows the input rank.

    Examples
    --------
    >>> Motion(t=[0.0, 1.0], pose=np.zeros((2, 3)), velocity=np.zeros((2, 3)),
    ...        acceleration=np.zeros((2, 3))).samples
    2
    >>> Motion(t=[0.0, 0.0], pose=np.zeros((2, 3)), velocity=np.zeros((2, 3)),
    ...        acceleration=np.zeros((2, 3)))
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: motion: time must be strictly increasing; t[1] = 0.0 follows t[0] = 0.0
    """

    t: FloatArray
    pose: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    load: FloatArray | None = None

    def __post_init__(self) -> None:
        t = _float_array("t", self.t)
        if t.ndim > 1:
            raise TrajectoryError(f"motion: t must have shape (N,) or (), got {t.shape}")
        if t.shape == (0,):
            raise TrajectoryError("motion: needs at least 1 sample, got t of shape (0,)")
        expected = (*t.shape, 3)
        names = ("pose", "velocity", "acceleration") + (("load",) if self.load is not None else ())
        for name in names:
            array = _float_array(name, getattr(self, name))
            if array.shape != expected:
                raise TrajectoryError(
                    f"motion: {name} must have shape {expected} to match t, got {array.shape}"
                )
            flat = array.reshape(-1, 3)
            bad = ~np.isfinite(flat)
            if bad.any():
                index, column = np.argwhere(bad)[0].tolist()
                raise TrajectoryError(
                    f"motion: {name}[{index}, {column}] is not finite ({float(flat[index, column])!r})"
                )
            array.flags.writeable = False
            object.__setattr__(self, name, array)
        flat_t = t.reshape(-1)
        if not np.isfinite(flat_t).all():
            index = int(np.argmax(~np.isfinite(flat_t)))
            raise TrajectoryError(f"motion: t[{index}] is not finite ({float(flat_t[index])!r})")
        steps = np.diff(flat_t)
        if (steps <= 0).any():
            index = int(np.argmax(steps <= 0)) + 1
            raise TrajectoryError(
                "motion: time must be strictly increasing; "
                f"t[{index}] = {float(flat_t[index])!r} follows t[{index - 1}] = {float(flat_t[index - 1])!r}"
            )
        t.flags.writeable = False
        object.__setattr__(self, "t", t)

    @property
    def samples(self) -> int:
        """Number of samples ``N`` (1 for a single sample)."""
        return int(self.t.size)

    @classmethod
    def at_rest(cls, pose: ArrayLike, t: ArrayLike = 0.0) -> Motion:
        """The platform held still at ``pose`` (zero velocity and acceleration).

        >>> Motion.at_rest([0.0, 0.0, 0.0]).pose.shape
        (3,)
        """
        array = _float_array("pose", pose)
        zeros = np.zeros_like(array)
        return cls(t=_float_array("t", t), pose=array, velocity=zeros, acceleration=zeros)

    def __getitem__(self, index: int | slice) -> Motion:
        """Samples ``index`` of a batch motion (an int gives a single sample)."""
        if self.t.ndim == 0:
            raise TrajectoryError("motion: a single-sample motion cannot be indexed")
        return Motion(
            t=self.t[index],
            pose=self.pose[index],
            velocity=self.velocity[index],
            acceleration=self.acceleration[index],
            load=None if self.load is None else self.load[index],
        )


def law_motion(
    amplitude: ArrayLike,
    samples: int = 301,
    duration: float = PAPER_DURATION,
) -> Motion:
    """The paper's law of motion (eq. 4): ``q = q*·(1 − cos(πt/3))``.

    Parameters
    ----------
    amplitude : array_like, shape (3,)
        ``(x*, y*, φ*)`` (m, m, rad); the motion ends at ``2·q*`` when
        ``duration = 3 s``.
    samples : int
        Number of samples ``N >= 2``, evenly spaced over ``[0, duration]``.
    duration : float
        Final time (s), > 0.

    Returns
    -------
    Motion
        With the analytic derivatives ``q*·(π/3)·sin(πt/3)`` and
        ``q*·(π/3)²·cos(πt/3)``.

    Examples
    --------
    >>> m = law_motion([0.01, 0.0, 0.0], samples=3)   # x goes 0 → 0.02 m
    >>> m.t.tolist(), m.pose[:, 0].round(12).tolist(), m.velocity[:, 0].round(6).tolist()
    ([0.0, 1.5, 3.0], [0.0, 0.01, 0.02], [0.0, 0.010472, 0.0])
    """
    star = _float_array("amplitude", amplitude)
    if star.shape != (3,) or not np.isfinite(star).all():
        raise TrajectoryError(f"motion: amplitude must be 3 finite numbers, got {amplitude!r}")
    if (
        isinstance(samples, bool)
        or not isinstance(samples, int | np.integer)
        or not 2 <= samples <= MAX_SAMPLES
    ):
        raise TrajectoryError(
            f"motion: samples must be an integer from 2 to {MAX_SAMPLES:.0e}, got {samples!r}"
        )
    if (
        isinstance(duration, bool | np.bool_)
        or not isinstance(duration, int | float | np.integer | np.floating)
        or not (math.isfinite(duration) and duration > 0)
    ):
        raise TrajectoryError(f"motion: duration must be a positive number (s), got {duration!r}")
    return law_at(star, np.linspace(0.0, float(duration), int(samples)))


def law_at(amplitude: ArrayLike, t: ArrayLike) -> Motion:
    """The law of eq. (4), ``q = q*·(1 − cos(πt/3))``, at given times.

    Parameters
    ----------
    amplitude : array_like, shape (3,)
        ``(x*, y*, φ*)`` (m, m, rad).
    t : array_like, shape (N,)
        Strictly increasing times (s), e.g. the instants of a controller.

    Returns
    -------
    Motion
        Pose, velocity ``q*·(π/3)·sin(πt/3)`` and acceleration
        ``q*·(π/3)²·cos(πt/3)`` at ``t``.

    Examples
    --------
    >>> law_at([0.0, 0.025, 0.0], [0.0, 3.0]).pose[:, 1].round(12).tolist()
    [0.0, 0.05]
    """
    star = _float_array("amplitude", amplitude)
    if star.shape != (3,) or not np.isfinite(star).all():
        raise TrajectoryError(f"motion: amplitude must be 3 finite numbers, got {amplitude!r}")
    times = _float_array("t", t)
    if times.ndim != 1:
        raise TrajectoryError(f"motion: t must have shape (N,), got {times.shape}")
    w = math.pi / 3.0
    cos_wt, sin_wt = np.cos(w * times)[:, None], np.sin(w * times)[:, None]
    return Motion(
        t=times,
        pose=star * (1.0 - cos_wt),  # eq. (4)
        velocity=star * w * sin_wt,
        acceleration=star * w * w * cos_wt,
    )


def paper_motion(name: str, samples: int = 301) -> Motion:
    """One of the paper's two examples, ``"vertical"`` or ``"rotation"`` (eq. 4).

    >>> bool(paper_motion("rotation").pose[-1, 2] == 2 * math.pi / 12)
    True
    >>> paper_motion("spiral")
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: motion: unknown motion 'spiral' (expected 'vertical' or 'rotation')
    """
    if not isinstance(name, str) or name not in PAPER_MOTIONS:
        raise TrajectoryError(
            f"motion: unknown motion {name!r} (expected 'vertical' or 'rotation')"
        )
    return law_motion(PAPER_MOTIONS[name], samples=samples)
