"""The checks between the samples of a motion, and the rates of a motion at rest (layer 0).

:func:`check_path` refuses a motion that crosses a singular orientation
between two of its samples, whatever its sampling; :func:`rest_rates` and
:func:`rest_joint_rates` set the round-off rates of a motion at rest to zero
(:data:`RATE_TOLERANCE`), so that every method reads the same sign of
friction.

Each sample of a motion is a state of its own (its pose and rates at its
time): nothing asks that the rates integrate to the steps between samples,
so a static grid of poses with zero rates, or measured data, is a motion too.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import SingularPoseError
from prp3.pose_validation import SINGULARITY_THRESHOLD, singularity_measure

__all__ = [
    "RATE_TOLERANCE",
    "check_path",
    "joint_rate_floor",
    "rest_joint_rates",
    "rest_rates",
]

FloatArray = NDArray[np.float64]

#: Platform rates at most this fraction of the motion's largest rate of their
#: kind are round-off and count as zero (:func:`rest_rates`): the translation
#: ``(ẋ, ẏ)`` against the largest ``|(ẋ, ẏ)|`` over the motion, ``φ̇`` against
#: the largest ``|φ̇|``.
RATE_TOLERANCE: float = 1e-12

#: The value ``STEP_TOLERANCE`` had while :func:`check_path` compared the steps
#: with the rates (deprecated: read through the module, with a warning).
_OLD_STEP_TOLERANCE: float = 0.25


def __getattr__(name: str) -> Any:
    """``STEP_TOLERANCE``, deprecated: the steps are no longer checked against the rates."""
    if name == "STEP_TOLERANCE":
        warnings.warn(
            "prp3.path_validation.STEP_TOLERANCE is deprecated and unused: the samples of a "
            "motion are independent states, their steps are no longer checked against their "
            "rates; it will be removed in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return _OLD_STEP_TOLERANCE
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _crossing(t: FloatArray, phi: FloatArray) -> int | None:
    """The first sample ``k`` such that a singular orientation lies between ``k − 1`` and ``k``."""
    band = np.floor((phi - math.pi / 3.0) / math.pi)  # singular orientations below φ
    regular = np.abs(singularity_measure(phi)) >= SINGULARITY_THRESHOLD
    crossed = (band[1:] != band[:-1]) & regular[1:] & regular[:-1]  # else check_poses says
    return int(np.argmax(crossed)) + 1 if crossed.any() else None


def check_path(
    t: ArrayLike,
    pose: ArrayLike,
    velocity: ArrayLike | None = None,
    acceleration: ArrayLike | None = None,
    *,
    lines: ArrayLike | None = None,
    subject: str | None = "motion",
) -> None:
    """Refuse a motion that crosses the singularity between two samples.

    The pose check (:func:`~prp3.pose_validation.check_poses`) sees the samples
    only; this one sees the straight path between two consecutive samples
    (the poses ``(1 − s)·q_{k−1} + s·q_k``, ``0 <= s <= 1``), so that it holds
    whatever the sampling: the orientation ``φ`` may not pass a singular
    orientation ``φ = π/3 mod π`` on it (where ``sin(φ − π/3)``, the
    determinant of eq. 10, vanishes: the actuator forces are infinite there,
    and the inverse geometry's joint coordinates jump from one side to the
    other).  ``φ`` is linear in ``s`` on that path, so it passes a singular
    orientation exactly when the two samples lie on either side of one.
    The judgement reads the poses only, never the rates: each sample is a
    state of its own, and its rates need not integrate to the steps (a static
    grid of poses with zero rates is a motion too).  Between the singular
    orientations ``λ10, λ32`` are smooth single-valued functions of the pose
    (eq. 10), so the 3-PRP has no branch to follow from sample to sample.

    Parameters
    ----------
    t : array_like, shape (N,)
        Strictly increasing times (s); a single sample (shape ``()``) has no step.
    pose : array_like, shape (N, 3)
        ``(x, y, φ)`` (validated finite by the caller).
    velocity, acceleration : None
        Deprecated and ignored (a :class:`DeprecationWarning` when given): the
        steps were once checked against the rates.
    lines : array_like of int, shape (N,), optional
        The file line of each sample, to name the earlier sample by its line.
    subject : str or None
        The ``subject`` field of the error.

    Raises
    ------
    SingularPoseError
        Naming both samples and their times (``sample`` and ``time`` fields:
        the later one).  A sample that is singular itself is left to
        :func:`~prp3.pose_validation.check_poses`, which names it.

    Examples
    --------
    >>> t = np.array([0.4, 0.6])
    >>> pose = np.array([[0.01, 0.0, 0.8], [0.01, 0.0, 1.2]])
    >>> check_path(t, pose)
    Traceback (most recent call last):
    ...
    prp3.errors.SingularPoseError: motion: sample 1, t = 0.6 s: the motion crosses the singular orientation phi = 1.0472 rad (pi/3 mod pi) between sample 0 (t = 0.4 s, phi = 0.8) and sample 1 (t = 0.6 s, phi = 1.2): sin(phi - pi/3) changes sign (-0.245 to 0.152); the actuator forces are infinite there

    Two poses of a static grid (zero rates) are two independent states:

    >>> check_path(t, np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.5]]))
    """
    if velocity is not None or acceleration is not None:
        warnings.warn(
            "check_path's velocity and acceleration are deprecated and ignored: the samples "
            "of a motion are independent states, their steps are no longer checked against "
            "their rates; leave them out (they will be removed in the next release)",
            DeprecationWarning,
            stacklevel=2,
        )
    times = np.asarray(t, dtype=np.float64)
    if times.ndim != 1 or times.size < 2:
        return
    q = np.asarray(pose, dtype=np.float64).reshape(times.size, 3)
    k = _crossing(times, q[:, 2])
    if k is None:
        return
    raise _crossing_error(times, q, k, lines, subject)


def _crossing_error(
    times: FloatArray, q: FloatArray, k: int, lines: ArrayLike | None, subject: str | None
) -> SingularPoseError:
    """The refusal of the step from sample ``k − 1`` to ``k`` of the poses ``q`` (N, 3),
    which crosses a singular orientation: both samples named (by file line when ``lines``)."""
    where = None if lines is None else np.asarray(lines).reshape(-1)

    def sample(k: int) -> str:
        label = f"line {int(where[k])}" if where is not None else f"sample {k}"
        return f"{label} (t = {float(times[k]):.6g} s"

    phi0, phi1 = float(q[k - 1, 2]), float(q[k, 2])
    band = math.floor((phi0 - math.pi / 3.0) / math.pi)
    singular = math.pi / 3.0 + math.pi * (band + 1 if phi1 > phi0 else band)
    d0, d1 = (float(v) for v in singularity_measure(np.array([phi0, phi1])))
    change = f"changes sign ({d0:.3g} to {d1:.3g})" if d0 * d1 < 0 else "passes zero"
    return SingularPoseError(
        f"the motion crosses the singular orientation phi = {singular:.6g} rad (pi/3 mod pi) "
        f"between {sample(k - 1)}, phi = {phi0:.6g}) and {sample(k)}, phi = {phi1:.6g}): "
        f"sin(phi - pi/3) {change}; the actuator forces are infinite there",
        subject=subject,
        sample=k,
        time=float(times[k]),
    )


def rest_joint_rates(
    rate: FloatArray, pose: FloatArray, velocity: FloatArray, l0: float
) -> FloatArray:
    """Joint rates ``(N, 3)`` of the legs with the round-off ones set to zero, for ``s(v)``.

    A joint rate can vanish by cancellation while the platform moves (at
    ``φ = 0`` and ``ẏ = φ̇ = 0``, leg B's ``λ̇32 = n_B·Ġ/D`` is zero), and each
    method computes that zero with its own round-off (``sin π ≈ 1.2e-16``):
    an exact-sign friction law would read a random sign.  So, in every method,
    a joint rate of magnitude at most :data:`RATE_TOLERANCE` times its
    sample's scale ``(|Ġ| + |φ̇|·(l0 + |G|)) / |sin(φ − π/3)|`` (the size of the
    terms of eq. 14) counts as zero for the sign.

    >>> rest_joint_rates(np.array([[0.5, 3e-17, -0.2]]), np.zeros((1, 3)),
    ...                  np.array([[0.25, 0.0, 0.0]]), 0.3).tolist()
    [[0.5, 0.0, -0.2]]
    """
    speed = np.hypot(velocity[:, 0], velocity[:, 1])
    reach = l0 + np.hypot(pose[:, 0], pose[:, 1])
    floor = joint_rate_floor(speed, velocity[:, 2], reach, singularity_measure(pose[:, 2]))
    return np.where(np.abs(rate) <= floor[:, None], 0.0, rate)


def joint_rate_floor(speed: Any, turn_rate: Any, reach: Any, measure: Any) -> Any:
    """``RATE_TOLERANCE·(|Ġ| + |φ̇|·(l0 + |G|)) / |sin(φ − π/3)|``: a joint rate at most this is zero.

    The floor of :func:`rest_joint_rates` (floats or arrays: ``speed = |Ġ|``,
    ``reach = l0 + |G|``, ``measure = sin(φ − π/3)``), also read by the kernel.

    >>> float(joint_rate_floor(0.25, 0.0, 0.3, 0.5))
    5e-13
    """
    return RATE_TOLERANCE * (speed + np.abs(turn_rate) * reach) / np.abs(measure)


def rest_rates(velocity: FloatArray) -> FloatArray:
    """Platform rates ``(N, 3)`` with the round-off ones set to zero (:data:`RATE_TOLERANCE`).

    A sampled motion that comes to rest gives rates of round-off size there
    (``sin(π)·q*·π/3 ≈ 3e-18 m/s`` at the end of the paper's motions), and an
    exact-sign law of friction ``s(v)`` would read their random sign as
    motion: a full Coulomb force of either sign at a sample at rest.  So a
    translation rate ``(ẋ, ẏ)`` of magnitude at most ``RATE_TOLERANCE`` times
    the largest one over the motion is zero, and so is ``φ̇`` at most
    ``RATE_TOLERANCE`` times the largest ``|φ̇|``: every joint rate computed
    from them (eq. 14) is then exactly zero, and ``s(0) = 0`` in every
    method.  Applying the rule again to some of the samples changes nothing
    (their largest rates are at most the motion's), so a motion computed in
    chunks gives the same numbers.  A single sample (shape ``(3,)``) is its
    own scale: nothing is zeroed but zeros.

    >>> rest_rates(np.array([[0.0, 0.026, 0.0], [0.0, 3.2e-18, 0.0]])).tolist()
    [[0.0, 0.026, 0.0], [0.0, 0.0, 0.0]]
    """
    if velocity.ndim != 2 or velocity.shape[0] < 2:
        return velocity
    speed = np.hypot(velocity[:, 0], velocity[:, 1])
    spin = np.abs(velocity[:, 2])
    still = speed <= RATE_TOLERANCE * speed.max()
    fixed = spin <= RATE_TOLERANCE * spin.max()
    if not (still & (speed > 0.0)).any() and not (fixed & (spin > 0.0)).any():
        return velocity
    cleaned = velocity.copy()
    cleaned[still, :2] = 0.0
    cleaned[fixed, 2] = 0.0
    return cleaned
