"""The one validation layer: ``check_*`` functions used by every public function.

Every public function of prp3 passes its arguments through these checks
before it computes anything, so that a bad value gets the same refusal
wherever it is given (in the style of pytransform3d's ``check_*``):

* booleans, text, bytes, ``None``, objects and complex numbers are refused,
  never cast (numpy would read ``True`` as 1 and drop an imaginary part);
* masked arrays are refused (numpy would silently use the hidden values);
* integers too large for float64 (``10**400``) are refused;
* shapes are checked, and non-finite values are refused naming the sample,
  the leg or component, and the value;
* poses must lie within :data:`POSE_BOUND` robot sizes of the centre and
  :data:`MAX_ORIENTATION` rad of zero, and away from the singularity
  (:data:`SINGULARITY_THRESHOLD`).

Every refusal is a :class:`~prp3.errors.Prp3Error` whose fields
(``subject``, ``sample``, ``leg``, ``pose``, ``key``) say where it happened.

>>> check_real("pose", [0, 1.5, 2]).dtype
dtype('float64')
>>> check_real("pose", ["0", "1"])
Traceback (most recent call last):
...
prp3.errors.TrajectoryError: pose must be an array of real numbers, got text (dtype <U1)
>>> check_per_leg("lambda10", [[0.0, 0.0, 0.0], [0.0, float("nan"), 0.0]])
Traceback (most recent call last):
...
prp3.errors.TrajectoryError: sample 1, leg B: lambda10 is not finite (nan)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError, Prp3Error, SingularPoseError, TrajectoryError

if TYPE_CHECKING:
    from prp3.model.robot import Robot

__all__ = [
    "LEGS",
    "MAX_ORIENTATION",
    "POSE_BOUND",
    "RATE_TOLERANCE",
    "SINGULARITY_THRESHOLD",
    "STEP_TOLERANCE",
    "check_choice",
    "check_finite",
    "check_instance",
    "check_integer",
    "check_names",
    "check_path",
    "check_per_leg",
    "check_pose_array",
    "check_pose_sample",
    "check_poses",
    "check_real",
    "check_robot",
    "check_same_shape",
    "check_sample",
    "check_scalar",
    "check_state_sample",
    "check_times",
    "first_non_finite",
    "require_finite",
    "rest_joint_rates",
    "rest_rates",
    "singularity_measure",
]

FloatArray = NDArray[np.float64]
T = TypeVar("T")

#: Leg names, in the order of the last axis of every per-leg array.
LEGS: tuple[str, str, str] = ("A", "B", "C")

#: Poses with ``|sin(φ − π/3)|`` below this value are refused as singular.
#: At the threshold the actuator velocities are 10⁴ times the platform's.
SINGULARITY_THRESHOLD: float = 1e-4

#: Largest ``|x|``, ``|y|`` of a pose, and ``|λ10|``, in units of the robot's
#: size ``l0``.  Farther away the three methods of the inverse dynamics lose
#: agreement (their relative difference grows like ``|G|/l0 · 1e-16``) and
#: the forces become round-off noise; at 100·l0 they still agree to ~1e-13.
POSE_BOUND: float = 100.0

#: Largest ``|φ|`` of a pose (rad): the mechanism cannot turn through its
#: singular orientations, so larger angles only add round-off to ``sin φ``.
MAX_ORIENTATION: float = 100.0

#: Largest relative misfit of a step between two samples of a motion and the
#: step its rates give (:func:`check_path`): a step of a coordinate ``q`` from
#: sample ``k − 1`` to ``k`` (time step ``h``) must satisfy
#: ``|E| <= STEP_TOLERANCE·S + 1e-6·Q`` with the misfit of the corrected
#: trapezoid ``E = Δq − h·(q̇₀ + q̇₁)/2 + h²·(q̈₁ − q̈₀)/12`` (exact for any
#: polynomial of degree 4 in t), its size ``S = |Δq| + h·(|q̇₀| + |q̇₁|)/2 +
#: h²·(|q̈₀| + |q̈₁|)/12`` (so ``|E| <= S`` always) and ``Q`` the coordinate's
#: largest magnitude over the motion (digits lost in a file's text).
STEP_TOLERANCE: float = 0.25

#: Platform rates at most this fraction of the motion's largest rate of their
#: kind are round-off and count as zero (:func:`rest_rates`): the translation
#: ``(ẋ, ẏ)`` against the largest ``|(ẋ, ẏ)|`` over the motion, ``φ̇`` against
#: the largest ``|φ̇|``.
RATE_TOLERANCE: float = 1e-12

_KINDS = {"b": "booleans", "c": "complex numbers", "U": "text", "S": "bytes", "V": "records"}
_COMPONENTS = ("x", "y", "phi")


def _describe(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def check_real(
    name: str,
    value: ArrayLike,
    error: type[Prp3Error] = TrajectoryError,
    subject: str | None = None,
) -> FloatArray:
    """A new float64 array of ``value``, refusing anything that is not real numbers.

    Refused: booleans, text, bytes, ``None``, other objects, complex numbers,
    masked arrays and integers beyond the range of float64.  Shapes and
    finiteness are not checked here (see :func:`check_finite`).

    >>> check_real("t", 10**400)
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: t must be an array of real numbers, got an integer too large for float64
    >>> check_real("t", np.ma.masked_array([0.0, 1.0], mask=[0, 1]))
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: t is a masked array: not accepted (numpy would use the masked values); fill or remove them first
    """
    refusal = f"{name} must be an array of real numbers, got"
    if isinstance(value, np.ma.MaskedArray):
        raise error(
            f"{name} is a masked array: not accepted (numpy would use the masked values); "
            "fill or remove them first",
            subject=subject,
        )
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError, OverflowError):
        raise error(f"{refusal} {_describe(value)}", subject=subject) from None
    kind = raw.dtype.kind
    if kind in "iuf":
        return raw.astype(np.float64)
    if kind == "O":
        items = raw.reshape(-1).tolist()
        if items and all(type(item) is int for item in items):  # beyond int64: exact ints
            try:
                return np.array(items, dtype=np.float64).reshape(raw.shape)
            except OverflowError:
                raise error(
                    f"{refusal} an integer too large for float64", subject=subject
                ) from None
        if any(item is None for item in items):
            raise error(f"{refusal} None", subject=subject)
        raise error(f"{refusal} {_describe(value)}", subject=subject)
    what = _KINDS.get(kind, "values")
    raise error(f"{refusal} {what} (dtype {raw.dtype})", subject=subject)


def _all_finite(array: FloatArray) -> bool:
    """Whether every value of ``array`` is finite: one pass (a finite sum says so) when large."""
    if array.size > 512:
        with np.errstate(over="ignore", invalid="ignore"):
            if math.isfinite(float(np.add.reduce(array, axis=None))):
                return True
    return bool(np.isfinite(array).all())


def check_finite(
    name: str,
    array: FloatArray,
    error: type[Prp3Error] = TrajectoryError,
    *,
    components: tuple[str, ...] | None = None,
    subject: str | None = None,
) -> FloatArray:
    """Refuse a non-finite value of ``array`` ``(..., k)``, naming its sample and component.

    ``components`` names the last axis (legs ``A, B, C`` by default for 3
    columns); a batch ``(N, k)`` names the sample's index.
    """
    if _all_finite(array):
        return array
    if array.ndim == 0:
        raise error(f"{name} is not finite ({float(array)!r})", subject=subject)
    flat = array.reshape(-1, array.shape[-1])
    index, column = np.argwhere(~np.isfinite(flat))[0].tolist()
    value = float(flat[index, column])
    sample = index if array.ndim >= 2 else None
    if components is None and array.shape[-1] == 3:
        raise error(
            f"{name} is not finite ({value!r})", subject=subject, sample=sample, leg=LEGS[column]
        )
    if components is None:
        raise error(f"{name}[{column}] is not finite ({value!r})", subject=subject, sample=sample)
    label = components[column]
    what = name if label == name else f"{label} of {name}"
    raise error(f"{what} is not finite ({value!r})", subject=subject, sample=sample)


def check_per_leg(
    name: str,
    value: ArrayLike,
    error: type[Prp3Error] = TrajectoryError,
    subject: str | None = None,
) -> FloatArray:
    """Finite values of the three legs, shape ``(3,)`` or ``(N, 3)`` with ``N >= 1``.

    >>> check_per_leg("f10", [1, 2]).shape
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: f10 must have shape (3,) or (N, 3) with N >= 1, got (2,)
    """
    array = check_real(name, value, error, subject)
    if array.ndim not in (1, 2) or array.shape[-1] != 3 or array.size == 0:
        raise error(
            f"{name} must have shape (3,) or (N, 3) with N >= 1, got {array.shape}",
            subject=subject,
        )
    return check_finite(name, array, error, subject=subject)


def singularity_measure(phi: ArrayLike) -> FloatArray:
    """Determinant ``D = e_i × d_i = sin(φ − π/3)`` of every leg's system (eq. 10).

    >>> round(float(singularity_measure(0.0)), 6)
    -0.866025
    """
    return np.asarray(np.sin(np.asarray(phi, dtype=np.float64) - math.pi / 3.0))


def check_poses(
    pose: ArrayLike,
    robot: Robot | None = None,
    name: str = "pose",
    *,
    singular: bool = True,
    error: type[Prp3Error] = TrajectoryError,
) -> FloatArray:
    """Validate platform poses ``(3,)`` or ``(N, 3)`` = ``(x, y, φ)``; return them as float64.

    Finite; with ``robot``, ``|x|, |y| <= POSE_BOUND·l0``; ``|φ| <=
    MAX_ORIENTATION``; with ``singular``, ``|sin(φ − π/3)| >=
    SINGULARITY_THRESHOLD``.

    Raises
    ------
    TrajectoryError
        Wrong type or shape, a non-finite value, a pose beyond the bounds
        (the fields name the sample and the pose).
    SingularPoseError
        A singular pose (names the sample and the pose).

    Examples
    --------
    >>> check_poses([[0, 0, 0], [0, 0.1, 0.2]]).dtype
    dtype('float64')
    >>> check_poses([[0.0, 0.0, 0.0], [0.0, 0.0, float("nan")]])
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: sample 1: phi of pose is not finite (nan)
    >>> from prp3.model.robot import Robot
    >>> check_poses([1e3, 0.0, 0.0], Robot())
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: pose: pose too far from the centre (x=1000.0, y=0.0, phi=0.0): |x| and |y| must be at most 100*l0 = 30 m (l0 = 0.3 m)
    """
    array = check_real(name, pose, error)
    if array.ndim not in (1, 2) or array.shape[-1] != 3 or array.size == 0:
        raise error(f"{name} must have shape (3,) or (N, 3) with N >= 1, got {array.shape}")
    return check_pose_array(array, robot, name, singular=singular, error=error)


def check_pose_array(
    array: FloatArray,
    robot: Robot | None = None,
    name: str = "pose",
    *,
    singular: bool = True,
    error: type[Prp3Error] = TrajectoryError,
    finite: bool = False,
) -> FloatArray:
    """:func:`check_poses` of a float64 array ``(3,)`` or ``(N, 3)`` (from :func:`check_real`).

    The same checks and messages, without a copy: ``array`` itself is returned
    (``finite=True``: its finiteness checked by the caller already).
    The common case (every pose well inside the bounds, far from the
    singularity) takes a few passes over the poses and no sine.

    >>> check_pose_array(np.array([0.0, 0.0, math.pi / 3.0]))
    Traceback (most recent call last):
    ...
    prp3.errors.SingularPoseError: pose: singular pose (x=0.0, y=0.0, phi=1.0471975511965976): |sin(phi - pi/3)| = 0 < 0.0001 (phi = pi/3 mod pi is singular)
    """
    if not finite:  # finite=True: the caller has checked it (check_finite)
        check_finite(name, array, error, components=_COMPONENTS)
    flat = array.reshape(-1, 3)
    batch = array.ndim == 2
    reach = math.inf if robot is None else POSE_BOUND * robot.l0
    # the common case in two contiguous passes: every coordinate within the smaller bound
    inside = max(-float(flat.min()), float(flat.max())) <= min(reach, MAX_ORIENTATION) or (
        float(np.abs(flat[:, :2]).max()) <= reach
        and float(np.abs(flat[:, 2]).max()) <= MAX_ORIENTATION
    )
    if singular and inside:
        # the singular orientations nearest zero are π/3 and −2π/3: a range of φ between them
        # (by twice the threshold) has none, else the distance of φ − π/3 to the nearest
        # multiple of π bounds |sin(φ − π/3)| from below: only poses within twice the
        # threshold need the sine
        phi = flat[:, 2]
        margin = 2.0 * SINGULARITY_THRESHOLD
        if -2.0 * math.pi / 3.0 + margin < float(phi.min()) and float(phi.max()) < (
            math.pi / 3.0 - margin
        ):
            return array
        psi = phi - math.pi / 3.0
        near = np.abs(psi - np.pi * np.rint(psi * (1.0 / np.pi)))
        if float(near.min()) >= 2.0 * SINGULARITY_THRESHOLD:
            return array
    elif inside:
        return array
    if robot is not None:
        far = (np.abs(flat[:, :2]) > reach).any(axis=1)
        if far.any():
            raise _pose_error(
                error,
                name,
                flat,
                int(np.argmax(far)),
                batch,
                "pose too far from the centre",
                f"|x| and |y| must be at most {POSE_BOUND:g}*l0 = {reach:g} m "
                f"(l0 = {robot.l0:g} m)",
            )
    turned = np.abs(flat[:, 2]) > MAX_ORIENTATION
    if turned.any():
        raise _pose_error(
            error,
            name,
            flat,
            int(np.argmax(turned)),
            batch,
            "orientation too large",
            f"|phi| must be at most {MAX_ORIENTATION:g} rad (give the angle modulo 2*pi)",
        )
    if singular:
        D = np.abs(singularity_measure(flat[:, 2]))
        near = D < SINGULARITY_THRESHOLD
        if near.any():
            index = int(np.argmax(near))
            raise _pose_error(
                SingularPoseError,
                name,
                flat,
                index,
                batch,
                "singular pose",
                f"|sin(phi - pi/3)| = {float(D[index]):.3g} < {SINGULARITY_THRESHOLD:g} "
                "(phi = pi/3 mod pi is singular)",
            )
    return array


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
    """Refuse a motion that crosses the singularity or jumps between two samples.

    The pose check (:func:`check_poses`) sees the samples only; this one sees
    the steps between them, so that it holds whatever the sampling:

    * the orientation ``φ`` of a motion may not pass a singular orientation
      ``φ = π/3 mod π`` between two consecutive samples (where
      ``sin(φ − π/3)``, the determinant of eq. 10, vanishes: the actuator
      forces are infinite there, and the inverse geometry's joint
      coordinates jump from one side to the other) — refused as a
      :class:`~prp3.errors.SingularPoseError`;
    * with ``velocity`` (and ``acceleration``, else zero), every coordinate
      ``x, y, φ`` must move from one sample to the next as its rates say:
      the corrected trapezoid of :data:`STEP_TOLERANCE`.  The joint
      coordinates ``λ10, λ32`` are smooth single-valued functions of the pose
      between the singular orientations (eq. 10), so with no crossing and
      steps that agree with their rates they cannot jump either.

    Parameters
    ----------
    t : array_like, shape (N,)
        Strictly increasing times (s); a single sample (shape ``()``) has no step.
    pose, velocity, acceleration : array_like, shape (N, 3)
        ``(x, y, φ)`` and its rates (validated finite by the caller).
    lines : array_like of int, shape (N,), optional
        The file line of each sample, to name the earlier sample by its line.
    subject : str or None
        The ``subject`` field of the error.

    Raises
    ------
    SingularPoseError, TrajectoryError
        Naming both samples and their times (``sample`` and ``time`` fields:
        the later one).  A sample that is singular itself is left to
        :func:`check_poses`, which names it.

    Examples
    --------
    >>> t = np.array([0.4, 0.6])
    >>> pose = np.array([[0.01, 0.0, 0.8], [0.01, 0.0, 1.2]])
    >>> check_path(t, pose)
    Traceback (most recent call last):
    ...
    prp3.errors.SingularPoseError: motion: sample 1, t = 0.6 s: the motion crosses the singular orientation phi = 1.0472 rad (pi/3 mod pi) between sample 0 (t = 0.4 s, phi = 0.8) and sample 1 (t = 0.6 s, phi = 1.2): sin(phi - pi/3) changes sign (-0.245 to 0.152); the actuator forces are infinite there
    >>> check_path(t, np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]]), np.zeros((2, 3)))
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: motion: sample 1, t = 0.6 s: x jumps by 0.1 from sample 0 (t = 0.4 s) to sample 1 (t = 0.6 s), but its rates give a step of 0 (corrected trapezoid of dx, ddx): the velocities do not explain the step; give consistent derivatives (or none)
    """
    times = np.asarray(t, dtype=np.float64)
    if times.ndim != 1 or times.size < 2:
        return
    q = np.asarray(pose, dtype=np.float64).reshape(times.size, 3)
    where = None if lines is None else np.asarray(lines).reshape(-1)

    def sample(k: int) -> str:
        label = f"line {int(where[k])}" if where is not None else f"sample {k}"
        return f"{label} (t = {float(times[k]):.6g} s"

    k = _crossing(times, q[:, 2])
    if k is not None:
        phi0, phi1 = float(q[k - 1, 2]), float(q[k, 2])
        band = math.floor((phi0 - math.pi / 3.0) / math.pi)
        singular = math.pi / 3.0 + math.pi * (band + 1 if phi1 > phi0 else band)
        d0, d1 = (float(v) for v in singularity_measure(np.array([phi0, phi1])))
        change = f"changes sign ({d0:.3g} to {d1:.3g})" if d0 * d1 < 0 else "passes zero"
        raise SingularPoseError(
            f"the motion crosses the singular orientation phi = {singular:.6g} rad (pi/3 mod pi) "
            f"between {sample(k - 1)}, phi = {phi0:.6g}) and {sample(k)}, phi = {phi1:.6g}): "
            f"sin(phi - pi/3) {change}; the actuator forces are infinite there",
            subject=subject,
            sample=k,
            time=float(times[k]),
        )
    if velocity is None:
        return
    qd = np.asarray(velocity, dtype=np.float64).reshape(q.shape)
    qdd = (
        np.zeros_like(q)
        if acceleration is None
        else np.asarray(acceleration, dtype=np.float64).reshape(q.shape)
    )
    floor = 1e-6 * np.abs(q).max(axis=0)  # digits lost in a file's text
    for first in range(0, times.size - 1, _STEP_BLOCK):  # bounded memory
        last = min(first + _STEP_BLOCK, times.size - 1) + 1
        _check_steps(times[first:last], q[first:last], qd[first:last], qdd[first:last],
                     floor, first, sample, subject)  # fmt: skip


#: Steps of a motion checked at a time by :func:`check_path` (bounds its memory).
_STEP_BLOCK: int = 65_536


def _check_steps(
    t: FloatArray, q: FloatArray, qd: FloatArray, qdd: FloatArray, floor: FloatArray,
    offset: int, sample: Callable[[int], str], subject: str | None,
) -> None:  # fmt: skip
    """The step test of :func:`check_path` on samples ``offset, offset + 1, ...``."""
    h = np.diff(t)[:, None]
    with np.errstate(over="ignore", invalid="ignore"):
        trapezoid = h * (qd[1:] + qd[:-1]) / 2.0 - h * h * (qdd[1:] - qdd[:-1]) / 12.0
        step = np.diff(q, axis=0)
        size = (
            np.abs(step)
            + h * (np.abs(qd[1:]) + np.abs(qd[:-1])) / 2.0
            + h * h * (np.abs(qdd[1:]) + np.abs(qdd[:-1])) / 12.0
        )
        bad = np.abs(step - trapezoid) > STEP_TOLERANCE * size + floor
    if not bad.any():
        return
    index, axis = np.argwhere(bad)[0].tolist()
    k = offset + index + 1
    name = _COMPONENTS[axis]
    raise TrajectoryError(
        f"{name} jumps by {float(step[index, axis]):.6g} from {sample(k - 1)}) to {sample(k)}), "
        f"but its rates give a step of {float(trapezoid[index, axis]):.6g} (corrected trapezoid "
        f"of d{name}, dd{name}): the velocities do not explain the step; give consistent "
        "derivatives (or none)",
        subject=subject,
        sample=k,
        time=float(t[index + 1]),
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
    scale = (speed + np.abs(velocity[:, 2]) * reach) / np.abs(singularity_measure(pose[:, 2]))
    floor = (RATE_TOLERANCE * scale)[:, None]
    return np.where(np.abs(rate) <= floor, 0.0, rate)


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


#: The types of a number of one sample that :func:`check_sample` converts at once.
_NUMBERS = (float, int, np.float64)


def check_sample(
    name: str, value: object, components: tuple[str, str, str] = _COMPONENTS
) -> tuple[float, float, float]:
    """Three finite real numbers of one sample (a pose, a velocity, ...), as Python floats.

    A tuple or list of three numbers (Python floats or ints, numpy scalars)
    or a ``(3,)`` array: the same cost for each.  Refused as
    :func:`check_real` and :func:`check_finite` refuse (booleans, text,
    ``None``, huge integers, masked values, NaN, infinity), or a shape other
    than ``(3,)``; ``components`` name the three values in messages.

    >>> check_sample("pose", (0, np.float64(0.5), 1.0))
    (0.0, 0.5, 1.0)
    >>> check_sample("velocity", [0.0, float("nan"), 0.0], ("dx", "dy", "dphi"))
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: dy of velocity is not finite (nan)
    """
    kind = type(value)
    items: Any
    if kind is tuple or kind is list:
        items = value
    elif isinstance(value, np.ndarray) and kind is np.ndarray and value.dtype == np.float64:
        items = value.tolist()
    else:
        items = None
    if items is not None and len(items) == 3:
        a, b, c = items
        if type(a) in _NUMBERS and type(b) in _NUMBERS and type(c) in _NUMBERS:
            try:
                x, y, z = float(a), float(b), float(c)
            except OverflowError:
                pass  # an integer too large: check_real says so
            else:
                if math.isfinite(x) and math.isfinite(y) and math.isfinite(z):
                    return x, y, z
    array = check_real(name, value)  # type: ignore[arg-type]
    if array.ndim not in (1, 2) or array.shape[-1] != 3:
        raise TrajectoryError(f"{name} must have shape (3,) or (N, 3), got {array.shape}")
    if array.shape != (3,):
        raise TrajectoryError(f"{name} must be 3 numbers (shape (3,)), got shape {array.shape}")
    check_finite(name, array, components=components)
    x, y, z = array.tolist()
    return x, y, z


_SEQUENCES = (tuple, list, np.ndarray)
_STATE_NAMES = ("pose", "velocity", "acceleration")
_RATE_COMPONENTS = (("dx", "dy", "dphi"), ("ddx", "ddy", "ddphi"))


def check_state_sample(
    pose: object, velocity: object, acceleration: object, robot: Robot | None = None
) -> tuple[float, float, float, float, float, float, float, float, float]:
    """One sample's pose, velocity and acceleration as nine Python floats, validated.

    Each a tuple or list of three numbers (Python floats or ints, numpy
    scalars) or a ``(3,)`` array, all at the same cost; checked in the order
    of the batch checks — each as :func:`check_sample` (pose, velocity,
    acceleration), then the pose as :func:`check_poses` — with their messages.

    >>> check_state_sample((0, 0, 0.1), [0.0, 0.0, 0.0], np.zeros(3))
    (0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    """
    if (
        type(pose) in _SEQUENCES
        and type(velocity) in _SEQUENCES
        and type(acceleration) in _SEQUENCES
    ):
        if type(pose) is np.ndarray:
            pose = pose.tolist()  # Python numbers (3,), at once
        if type(velocity) is np.ndarray:
            velocity = velocity.tolist()
        if type(acceleration) is np.ndarray:
            acceleration = acceleration.tolist()
        three: Any = (pose, velocity, acceleration)
        try:
            (x, y, phi), (dx, dy, dphi), (ddx, ddy, ddphi) = three
        except (TypeError, ValueError):
            pass  # not three values each: the exact checks say which
        else:
            numbers = _NUMBERS
            if (
                type(x) in numbers and type(y) in numbers and type(phi) in numbers
                and type(dx) in numbers and type(dy) in numbers and type(dphi) in numbers
                and type(ddx) in numbers and type(ddy) in numbers and type(ddphi) in numbers
            ):  # fmt: skip
                try:
                    values = (
                        float(x), float(y), float(phi), float(dx), float(dy), float(dphi),
                        float(ddx), float(ddy), float(ddphi),
                    )  # fmt: skip
                except OverflowError:
                    pass  # an integer too large for float64
                else:
                    reach = math.inf if robot is None else POSE_BOUND * robot.l0
                    fx, fy, fphi = values[0], values[1], values[2]
                    if (
                        0.0 * sum(values) == 0.0  # finite (a sum that overflows: exactly below)
                        and -reach <= fx <= reach
                        and -reach <= fy <= reach
                        and -MAX_ORIENTATION <= fphi <= MAX_ORIENTATION
                        and abs(math.sin(fphi - math.pi / 3.0)) >= SINGULARITY_THRESHOLD
                    ):
                        return values
    state = (
        check_sample("pose", pose),
        check_sample("velocity", velocity, _RATE_COMPONENTS[0]),
        check_sample("acceleration", acceleration, _RATE_COMPONENTS[1]),
    )
    check_pose_array(np.array(state[0]), robot)
    return (*state[0], *state[1], *state[2])


def check_pose_sample(
    value: object, robot: Robot | None = None, name: str = "pose"
) -> tuple[float, float, float]:
    """One pose ``(x, y, φ)`` as :func:`check_sample` takes it, checked as :func:`check_poses`.

    >>> from prp3.model.robot import Robot
    >>> check_pose_sample((0.0, 0, np.float64(0.1)), Robot())
    (0.0, 0.0, 0.1)
    """
    x, y, phi = check_sample(name, value)
    reach = math.inf if robot is None else POSE_BOUND * robot.l0
    if (
        -reach <= x <= reach
        and -reach <= y <= reach
        and -MAX_ORIENTATION <= phi <= MAX_ORIENTATION
        and abs(math.sin(phi - math.pi / 3.0)) >= SINGULARITY_THRESHOLD
    ):
        return x, y, phi
    check_pose_array(np.array([x, y, phi]), robot, name)  # the message of check_poses
    return x, y, phi


def _pose_error(
    error: type[Prp3Error],
    name: str,
    flat: FloatArray,
    index: int,
    batch: bool,
    what: str,
    reason: str,
) -> Prp3Error:
    x, y, phi = flat[index].tolist()
    return error(
        f"{what} (x={x!r}, y={y!r}, phi={phi!r}): {reason}",
        subject=name,
        sample=index if batch else None,
        pose=(x, y, phi),
    )


def check_times(
    name: str, value: ArrayLike, *, minimum: int = 1, subject: str | None = None
) -> FloatArray:
    """Finite, strictly increasing times ``(N,)`` with ``N >= minimum`` (s).

    >>> check_times("t", [0.0, 0.0])
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: sample 1: time must be strictly increasing; t[1] = 0.0 follows t[0] = 0.0
    """
    t = check_real(name, value, subject=subject)
    if t.ndim != 1 or t.size < minimum:
        raise TrajectoryError(
            f"{name} must have shape (N,) with N >= {minimum}, got {t.shape}", subject=subject
        )
    check_finite(name, t[:, None], components=(name,), subject=subject)
    steps = np.diff(t)
    if (steps <= 0).any():
        k = int(np.argmax(steps <= 0)) + 1
        raise TrajectoryError(
            f"time must be strictly increasing; {name}[{k}] = {float(t[k])!r} follows "
            f"{name}[{k - 1}] = {float(t[k - 1])!r}",
            subject=subject,
            sample=k,
        )
    return t


def check_same_shape(name: str, array: FloatArray, reference: FloatArray, other: str) -> None:
    """Refuse ``array`` unless it has the shape of ``reference`` (named ``other``)."""
    if array.shape != reference.shape:
        raise TrajectoryError(
            f"{name} must have the shape of {other} {reference.shape}, got {array.shape}"
        )


def check_scalar(
    name: str,
    value: Any,
    *,
    error: type[Prp3Error] = ParameterError,
    positive: bool = False,
    non_negative: bool = False,
    unit: str = "",
    subject: str | None = None,
) -> float:
    """A finite real number (not a boolean, not text), optionally > 0 or >= 0.

    >>> check_scalar("rtol", 1e-8, positive=True)
    1e-08
    >>> check_scalar("rtol", True)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: rtol must be a number, got True (bool)
    """
    if isinstance(value, bool | np.bool_) or not isinstance(
        value, int | float | np.floating | np.integer
    ):
        raise error(
            f"{name} must be a number, got {_describe(value)} ({type(value).__name__})",
            subject=subject,
            key=name,
        )
    try:
        number = float(value)
    except OverflowError:
        raise error(
            f"{name} is too large for float64, got {_describe(value)}", subject=subject, key=name
        ) from None
    units = f" ({unit})" if unit else ""
    if not math.isfinite(number):
        raise error(f"{name} must be a finite number, got {value!r}", subject=subject, key=name)
    if positive and not number > 0.0:
        raise error(
            f"{name} must be a positive finite number{units}, got {value!r}",
            subject=subject,
            key=name,
        )
    if non_negative and not number >= 0.0:
        raise error(
            f"{name} must be a non-negative finite number{units}, got {value!r}",
            subject=subject,
            key=name,
        )
    return number


def check_integer(
    name: str,
    value: Any,
    minimum: int,
    maximum: int,
    error: type[Prp3Error] = ParameterError,
    subject: str | None = None,
) -> int:
    """An integer (not a boolean) from ``minimum`` to ``maximum``.

    >>> check_integer("samples", 2.0, 2, 10)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: samples must be an integer from 2 to 10, got 2.0
    """
    if (
        isinstance(value, bool | np.bool_)
        or not isinstance(value, int | np.integer)
        or not minimum <= value <= maximum
    ):
        raise error(
            f"{name} must be an integer from {minimum} to {_bound(maximum)}, got "
            f"{_describe(value)}",
            key=name,
            subject=subject,
        )
    return int(value)


def _bound(value: int) -> str:
    return f"{value:.0e}" if value >= 10**6 else str(value)


def check_robot(robot: object, name: str = "robot") -> Robot:
    """Return ``robot`` if it is a :class:`~prp3.model.robot.Robot`, else raise :class:`ParameterError`.

    >>> check_robot(None)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot must be a prp3.Robot, got None
    >>> check_robot("robot.toml", "model")
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: model must be a prp3.Robot, got 'robot.toml'
    """
    from prp3.model.robot import Robot

    if not isinstance(robot, Robot):
        raise ParameterError(f"{name} must be a prp3.Robot, got {_describe(robot)}", key=name)
    return robot


def check_instance(name: str, value: object, kind: type[T], what: str) -> T:
    """Return ``value`` if it is a ``kind`` (called ``what`` in the message), else refuse it.

    >>> from prp3.model.motion import Motion
    >>> check_instance("motion", [0.0, 0.0, 0.0], Motion, "a prp3.Motion")
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: motion must be a prp3.Motion, got [0.0, 0.0, 0.0]
    """
    if not isinstance(value, kind):
        raise ParameterError(f"{name} must be {what}, got {_describe(value)}", key=name)
    return value


def check_choice(name: str, value: object, choices: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of the strings ``choices``, else refuse it.

    >>> check_choice("method", "euler", ("fast", "paper"))
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: method must be one of 'fast', 'paper', got 'euler'
    """
    if not isinstance(value, str) or value not in choices:
        expected = ", ".join(repr(choice) for choice in choices)
        raise ParameterError(f"{name} must be one of {expected}, got {_describe(value)}", key=name)
    return value


def check_names(
    name: str, value: object, known: tuple[str, ...], *, item: str = "name", empty: bool = False
) -> tuple[str, ...]:
    """Distinct names out of ``known`` (a sequence of strings, not one string).

    >>> check_names("parameters", "platform_mass", ("platform_mass",))
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: parameters must be a sequence of names, got 'platform_mass' (a single string)
    """
    if isinstance(value, str) or not isinstance(value, tuple | list):
        if isinstance(value, str):
            raise ParameterError(
                f"{name} must be a sequence of names, got {_describe(value)} (a single string)",
                key=name,
            )
        raise ParameterError(
            f"{name} must be a sequence of names, got {_describe(value)}", key=name
        )
    names = tuple(value)
    for entry in names:
        if not isinstance(entry, str) or entry not in known:
            raise ParameterError(
                f"{name}: unknown {item} {_describe(entry)} (expected one of: {', '.join(known)})",
                key=name,
            )
    if len(set(names)) != len(names) or (not names and not empty):
        required = "distinct" if empty else "distinct and at least one"
        raise ParameterError(f"{name} must be {required}, got {names!r}", key=name)
    return names


def first_non_finite(
    arrays: Mapping[str, FloatArray], batch: tuple[int, ...]
) -> tuple[int, str] | None:
    """``(sample, name)`` of the first non-finite value of per-sample ``arrays``, or None."""
    samples = int(np.prod(batch)) if batch else 1
    first: tuple[int, str] | None = None
    for name, array in arrays.items():
        flat = np.asarray(array).reshape(samples, -1)
        bad = ~np.isfinite(flat).all(axis=1)
        if bad.any():
            index = int(np.argmax(bad))
            if first is None or index < first[0]:
                first = (index, name)
    return first


def require_finite(
    arrays: Mapping[str, FloatArray],
    batch: tuple[int, ...],
    what: str,
    times: FloatArray | None = None,
) -> None:
    """Raise :class:`TrajectoryError` naming the first sample whose results overflowed.

    The inputs are validated finite, so a non-finite result means that the
    motion or the parameters are too large for float64: such numbers have
    lost their meaning and are refused, never returned.
    """
    if all(_all_finite(np.asarray(array)) for array in arrays.values()):
        return
    found = first_non_finite(arrays, batch)
    if found is None:
        return
    index, name = found
    time = float(np.asarray(times).reshape(-1)[index]) if times is not None else None
    raise TrajectoryError(
        f"the results overflow: {name} is not finite; "
        "the motion or the robot's parameters are too large for double precision",
        subject=what,
        sample=index if batch else None,
        time=time if batch else None,
    )
