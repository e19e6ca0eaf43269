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

from prp3.errors import Prp3Error, TrajectoryError
from prp3.path_validation import rest_rates
from prp3.validation import (
    OVERFLOW_REASON,
    check_finite,
    check_integer,
    check_real,
    check_scalar,
    check_times,
    first_not_increasing,
    require_finite,
)

__all__ = [
    "MAX_SAMPLES",
    "PAPER_DURATION",
    "PAPER_MOTIONS",
    "Motion",
    "differentiate_positions",
    "law_at",
    "law_motion",
    "name_overflow_input",
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
    return check_real(name, value, TrajectoryError, "motion")


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
        ``(ẋ, ẏ, φ̇)`` (m/s, m/s, rad/s).  Rates of round-off size (at most
        :data:`~prp3.path_validation.RATE_TOLERANCE` times the motion's largest of
        their kind, :func:`~prp3.path_validation.rest_rates`) are stored as zero:
        the platform is at rest there, and the sign of a Coulomb friction is 0.
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
    prp3.errors.TrajectoryError: motion: sample 1: time must be strictly increasing; t[1] = 0.0 follows t[0] = 0.0
    """

    t: FloatArray
    pose: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    load: FloatArray | None = None

    def __post_init__(self) -> None:
        t = _float_array("t", self.t)
        if t.ndim > 1:
            raise TrajectoryError(f"t must have shape (N,) or (), got {t.shape}", subject="motion")
        if t.shape == (0,):
            raise TrajectoryError("needs at least 1 sample, got t of shape (0,)", subject="motion")
        if t.ndim == 1:
            t = check_times("t", t, subject="motion")
        else:
            check_finite("t", t, subject="motion")
        expected = (*t.shape, 3)
        quantities = [
            ("pose", ("x", "y", "phi")),
            ("velocity", ("dx", "dy", "dphi")),
            ("acceleration", ("ddx", "ddy", "ddphi")),
        ]
        if self.load is not None:
            quantities.append(("load", ("fx", "fy", "mz")))
        for name, components in quantities:
            array = _float_array(name, getattr(self, name))
            if array.shape != expected:
                raise TrajectoryError(
                    f"{name} must have shape {expected} to match t, got {array.shape}",
                    subject="motion",
                )
            check_finite(name, array, components=components, subject="motion")
            if name == "velocity":  # rates of round-off size at rest are zero
                array = rest_rates(array)
            array.flags.writeable = False
            object.__setattr__(self, name, array)
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


#: The inputs of a sample of a motion, as the columns of ``TRAJ.csv`` name them.
INPUT_COLUMNS: tuple[str, ...] = (
    "x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi", "fx", "fy", "mz",
)  # fmt: skip


#: Below this magnitude no input of a sample makes results overflow with a robot of
#: ordinary size (the dynamics forms at most the square of a rate times a mass and an
#: arm): an overflow of results is then the robot's, not the sample's.
MODERATE_INPUT = 1e100


def name_overflow_input(error: Prp3Error, motion: Motion) -> Prp3Error:
    """``error`` naming the largest input of its sample when it is an overflow of results.

    The inputs are validated finite, so results that overflow
    (:func:`prp3.validation.require_finite`) come from values too large for
    float64: a rate of ``1e200`` m/s gives ``p10 = f10·λ̇10`` or ``λ̈10``
    (``φ̇²`` terms) beyond it.  The sample's input of largest magnitude among
    :data:`INPUT_COLUMNS` (pose, rates, accelerations, load) is named in the
    reason and in the ``key`` field (the ``TRAJ.csv`` column); when even that input
    is below :data:`MODERATE_INPUT`, the reason says the robot's values caused it
    and no column is named.  Other errors, and errors that name one already, are
    returned as they are.

    >>> from prp3.validation import require_finite
    >>> motion = Motion(t=[0.0, 1.0], pose=np.zeros((2, 3)),
    ...                 velocity=[[0.0, 0.0, 0.0], [0.0, 0.0, 1e200]], acceleration=np.zeros((2, 3)))
    >>> try:
    ...     require_finite({"p10": np.array([[0.0], [np.inf]])}, (2,), "motion")
    ... except TrajectoryError as error:
    ...     named = name_overflow_input(error, motion)
    >>> named.key, named.reason.split("; ")[-1]
    ('dphi', 'the largest input of the sample is dphi = 1e+200 (column dphi)')
    >>> calm = Motion(t=[0.0, 1.0], pose=np.zeros((2, 3)), velocity=np.zeros((2, 3)),
    ...               acceleration=[[0.0, 0.0, 0.0], [0.0, 0.0, 0.25]])
    >>> try:
    ...     require_finite({"f10": np.array([[0.0], [np.inf]])}, (2,), "motion")
    ... except TrajectoryError as error:
    ...     named = name_overflow_input(error, calm)
    >>> named.key is None, named.reason.split("; ")[-1]
    (True, "the sample's inputs are moderate (the largest is ddphi = 0.25): the robot's masses, inertias or loads are too large for float64")
    """
    overflow = isinstance(error, TrajectoryError) and error.reason.startswith(OVERFLOW_REASON)
    single = motion.t.ndim == 0
    if not overflow or error.key is not None or (error.sample is None and not single):
        return error
    k = 0 if single or error.sample is None else error.sample
    if k >= motion.samples:
        return error
    parts = [motion.pose, motion.velocity, motion.acceleration]
    if motion.load is not None:
        parts.append(motion.load)
    values = np.concatenate([np.reshape(part, (-1, 3))[k] for part in parts])
    index = int(np.argmax(np.abs(values)))
    column = INPUT_COLUMNS[index]
    named = error.located()
    if abs(float(values[index])) < MODERATE_INPUT:  # no input can be the cause: the robot is
        named.reason = (
            f"{error.reason}; the sample's inputs are moderate (the largest is {column} = "
            f"{float(values[index]):.6g}): the robot's masses, inertias or loads are too "
            "large for float64"
        )
        named.args = (str(named),)
        return named
    named.reason = (
        f"{error.reason}; the largest input of the sample is {column} = "
        f"{float(values[index]):.6g} (column {column})"
    )
    named.key = column
    named.args = (str(named),)
    return named


def _amplitude(amplitude: ArrayLike) -> FloatArray:
    star = _float_array("amplitude", amplitude)
    if star.shape != (3,):
        raise TrajectoryError(f"amplitude must have shape (3,), got {star.shape}", subject="motion")
    return check_finite("amplitude", star, components=("x*", "y*", "phi*"), subject="motion")


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
    star = _amplitude(amplitude)
    samples = check_integer("samples", samples, 2, MAX_SAMPLES, TrajectoryError, "motion")
    duration = check_scalar(
        "duration", duration, error=TrajectoryError, positive=True, unit="s", subject="motion"
    )
    return law_at(star, np.linspace(0.0, duration, samples))


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
    star = _amplitude(amplitude)
    times = check_times("t", t, subject="motion")
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
    prp3.errors.TrajectoryError: motion: unknown motion 'spiral' (name must be 'vertical' or 'rotation')
    """
    if not isinstance(name, str) or name not in PAPER_MOTIONS:
        raise TrajectoryError(
            f"unknown motion {name!r} (name must be 'vertical' or 'rotation')"[:200],
            subject="motion",
        )
    return law_motion(PAPER_MOTIONS[name], samples=samples)


def differentiate_positions(t: FloatArray, pose: FloatArray) -> tuple[FloatArray, FloatArray, int]:
    """Velocities and accelerations of sampled poses by an interpolating spline.

    Each of ``x, y, φ`` is interpolated by a spline of degree 5 (quintic) with
    the not-a-knot end conditions through all the samples
    (``scipy.interpolate.make_interp_spline(t, q, k=5)``); the velocity and
    acceleration are its first and second derivatives at the sample times.
    With fewer than 6 samples the degree drops to 3 (4 or 5 samples) or 1
    (2 or 3 samples; zero acceleration).  For a smooth motion sampled every
    millisecond the derivatives are accurate to about 1e-9 relative away from
    the ends; within a few samples of the ends the error is larger.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Strictly increasing times (s), ``N >= 2``.
    pose : ndarray, shape (N, 3)
        ``(x, y, φ)`` (m, m, rad).

    Returns
    -------
    velocity, acceleration : ndarray, shape (N, 3)
        ``(ẋ, ẏ, φ̇)`` (m/s, rad/s) and ``(ẍ, ÿ, φ̈)`` (m/s², rad/s²).
    degree : int
        The spline degree used.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> pose = np.stack([t**2, 3.0 * t, np.zeros_like(t)], axis=-1)
    >>> velocity, acceleration, degree = differentiate_positions(t, pose)
    >>> degree, velocity[5].round(12).tolist(), acceleration[5].round(9).tolist()
    (5, [1.0, 3.0, 0.0], [2.0, 0.0, 0.0])
    """
    times = check_times("t", t, minimum=2)
    poses = check_real("pose", pose)
    if poses.shape != (times.size, 3):
        raise TrajectoryError(
            f"pose must have shape (N, 3) with N = {times.size} (the samples of t), "
            f"got {poses.shape}"
        )
    check_finite("pose", poses, components=("x", "y", "phi"))
    with np.errstate(all="ignore"):  # an overflow is refused below, naming the sample
        velocity, acceleration, degree = spline_derivatives(times, poses)
    require_finite(
        {"velocity": velocity, "acceleration": acceleration}, (times.size,), "pose", times
    )
    return velocity, acceleration, degree


def spline_derivatives(t: FloatArray, pose: FloatArray) -> tuple[FloatArray, FloatArray, int]:
    """:func:`differentiate_positions` on arrays already checked; may return non-finite values."""
    from scipy.interpolate import make_interp_spline

    samples = t.size
    degree = 5 if samples >= 6 else 3 if samples >= 4 else 1
    # on s = (t − t0)/T in [0, 1] and the moves from the first pose: a time step of
    # 1e-300 s or a subnormal one, and a constant coordinate, lose no digit (q(t) =
    # q(t0 + T·s) is the same spline; dq/dt = (dq/ds)/T, d²q/dt² = (d²q/ds²)/T/T)
    duration = float(t[-1]) - float(t[0])  # Python floats: inf, no warning, on overflow
    if math.isfinite(duration):
        s = (t - t[0]) / duration
    else:  # times of either sign near the float64 limit: halves do not overflow
        half = float(t[-1] / 2.0 - t[0] / 2.0)
        s, duration = (t / 2.0 - t[0] / 2.0) / half, math.inf
    s[-1] = 1.0
    k = first_not_increasing(s)
    if k is not None:  # steps lost against the span (t of 1e-3 s beside one of -1e308)
        raise TrajectoryError(
            f"time steps too small against the time span {float(t[-1]) - float(t[0])!r} s: "
            f"samples {k - 1} and {k} (t = {float(t[k - 1])!r}, {float(t[k])!r}) cannot be "
            "told apart on it in float64",
            sample=k,
        )
    spline = make_interp_spline(s, pose - pose[0], k=degree, axis=0)
    if math.isinf(duration):
        velocity = np.asarray(spline(s, 1), dtype=np.float64) / half / 2.0
        acceleration = np.asarray(spline(s, 2), dtype=np.float64) / half / half / 4.0
    else:
        velocity = np.asarray(spline(s, 1), dtype=np.float64) / duration
        acceleration = np.asarray(spline(s, 2), dtype=np.float64) / duration / duration
    return velocity, acceleration, degree
