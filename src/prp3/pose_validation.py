"""The validation of platform poses and of one sample's state (layer 0, foundation).

Poses must be finite, lie within :data:`POSE_BOUND` robot sizes of the
centre and :data:`MAX_ORIENTATION` rad of zero, and keep away from the
singularity (:data:`SINGULARITY_THRESHOLD`): :func:`check_poses` for arrays,
:func:`check_state_sample` and :func:`check_pose_sample` for one sample of
Python numbers.  The refusals are those of :mod:`prp3.validation`, with the
pose in the ``pose`` field.

>>> check_poses([[0.0, 0.0, 0.0], [0.0, 0.0, float("nan")]])
Traceback (most recent call last):
...
prp3.errors.TrajectoryError: sample 1: phi of pose is not finite (nan)
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import Prp3Error, SingularPoseError, TrajectoryError
from prp3.validation import check_finite, check_real

if TYPE_CHECKING:
    from prp3.model.robot import Robot

__all__ = [
    "MAX_ORIENTATION",
    "POSE_BOUND",
    "POSE_COMPONENTS",
    "SINGULARITY_THRESHOLD",
    "check_pose_array",
    "check_pose_sample",
    "check_poses",
    "check_sample",
    "check_state_sample",
    "singularity_measure",
]

FloatArray = NDArray[np.float64]

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

#: The orientations between the singular ones nearest zero, ``−2π/3`` and ``π/3``, less
#: twice the threshold: a pose's ``|sin(φ − π/3)|`` there exceeds the threshold, no sine needed.
_BAND_LOW: float = -2.0 * math.pi / 3.0 + 2.0 * SINGULARITY_THRESHOLD
_BAND_HIGH: float = math.pi / 3.0 - 2.0 * SINGULARITY_THRESHOLD

#: The names of a pose's three components, in messages.
POSE_COMPONENTS: tuple[str, str, str] = ("x", "y", "phi")


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
    """:func:`check_poses` of a float64 array ``(3,)`` or ``(N, 3)``, as ``check_real`` gives it.

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
        check_finite(name, array, error, components=POSE_COMPONENTS)
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
        if _BAND_LOW < float(phi.min()) and float(phi.max()) < _BAND_HIGH:
            return array
        psi = phi - math.pi / 3.0
        near = np.abs(psi - np.pi * np.rint(psi * (1.0 / np.pi)))
        if float(near.min()) >= 2.0 * SINGULARITY_THRESHOLD:
            return array
    elif inside:
        return array
    _refuse_poses(flat, robot, name, singular=singular, error=error, batch=batch)
    return array


def _refuse_poses(
    flat: FloatArray,
    robot: Robot | None,
    name: str,
    *,
    singular: bool,
    error: type[Prp3Error],
    batch: bool,
) -> None:
    """The slow path of :func:`check_pose_array`: raise for the first pose ``(N, 3)`` too far
    from the centre, turned too far, or (``singular``) near the singularity, in that order."""
    reach = math.inf if robot is None else POSE_BOUND * robot.l0
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


#: The types of a number of one sample that :func:`check_sample` converts at once.
_NUMBERS = frozenset((float, int, np.float64))


def check_sample(
    name: str, value: object, components: tuple[str, str, str] = POSE_COMPONENTS
) -> tuple[float, float, float]:
    """Three finite real numbers of one sample (a pose, a velocity, ...), as Python floats.

    A tuple or list of three numbers (Python floats or ints, numpy scalars)
    or a ``(3,)`` array: the same cost for each.  Refused as
    :func:`~prp3.validation.check_real` and
    :func:`~prp3.validation.check_finite` refuse (booleans, text,
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
    elif (
        isinstance(value, np.ndarray)
        and kind is np.ndarray
        and value.ndim == 1
        and value.dtype == np.float64
    ):
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


#: What :func:`check_state_sample` unpacks at once (arrays: as their ``tolist()``).
_UNPACKED = frozenset((tuple, list))
_RATE_COMPONENTS = (("dx", "dy", "dphi"), ("ddx", "ddy", "ddphi"))
_UNBOUNDED = math.inf
_PI_3 = math.pi / 3.0


def check_state_sample(
    pose: object, velocity: object, acceleration: object, robot: Robot | None = None
) -> tuple[float, float, float, float, float, float, float, float, float]:
    """One sample's pose, velocity and acceleration as nine Python floats, validated.

    Each a tuple or list of three numbers (Python floats or ints, numpy
    scalars) or a ``(3,)`` array, all at about the same cost; checked in the
    order of the batch checks — each as :func:`check_sample` (pose, velocity,
    acceleration), then the pose as :func:`check_poses` — with their messages.

    The common case takes one pass: nine numbers of the accepted types
    (Python floats as they are; ints and numpy float64 scalars converted),
    finite (their sum times zero is zero), the pose within the bounds and its
    orientation in the band of no singular orientation (else its sine
    tested).  Anything else, and a sum that overflows, takes the exact
    checks, which name what is wrong; the fast pass accepts only what they
    accept.

    >>> check_state_sample((0, 0, 0.1), [0.0, 0.0, 0.0], np.zeros(3))
    (0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    """
    # arrays as their Python numbers, at once; the exact checks see the values as given
    three: Any = (
        pose.tolist() if type(pose) is np.ndarray else pose,
        velocity.tolist() if type(velocity) is np.ndarray else velocity,
        acceleration.tolist() if type(acceleration) is np.ndarray else acceleration,
    )
    if type(three[0]) in _UNPACKED and type(three[1]) in _UNPACKED and type(three[2]) in _UNPACKED:
        try:
            (x, y, phi), (dx, dy, dphi), (ddx, ddy, ddphi) = three
        except (TypeError, ValueError):
            return exact_state(pose, velocity, acceleration, robot)  # not three values each
        if not (
            type(x) is float and type(y) is float and type(phi) is float
            and type(dx) is float and type(dy) is float and type(dphi) is float
            and type(ddx) is float and type(ddy) is float and type(ddphi) is float
        ):  # fmt: skip
            numbers = _NUMBERS
            if not (
                type(x) in numbers and type(y) in numbers and type(phi) in numbers
                and type(dx) in numbers and type(dy) in numbers and type(dphi) in numbers
                and type(ddx) in numbers and type(ddy) in numbers and type(ddphi) in numbers
            ):  # fmt: skip
                return exact_state(pose, velocity, acceleration, robot)
            try:
                x, y, phi = float(x), float(y), float(phi)
                dx, dy, dphi = float(dx), float(dy), float(dphi)
                ddx, ddy, ddphi = float(ddx), float(ddy), float(ddphi)
            except OverflowError:  # an integer too large for float64
                return exact_state(pose, velocity, acceleration, robot)
        reach = _UNBOUNDED if robot is None else POSE_BOUND * robot.l0
        if (
            0.0 * (x + y + dx + dy + dphi + ddx + ddy + ddphi) == 0.0
            and -reach <= x <= reach
            and -reach <= y <= reach
            and (
                _BAND_LOW < phi < _BAND_HIGH
                or (
                    -MAX_ORIENTATION <= phi <= MAX_ORIENTATION
                    and abs(math.sin(phi - _PI_3)) >= SINGULARITY_THRESHOLD
                )
            )
        ):
            return x, y, phi, dx, dy, dphi, ddx, ddy, ddphi
    return exact_state(pose, velocity, acceleration, robot)


def exact_state(
    pose: object, velocity: object, acceleration: object, robot: Robot | None
) -> tuple[float, float, float, float, float, float, float, float, float]:
    """:func:`check_state_sample` by the exact checks, in their order, with their messages."""
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
