"""The one validation layer: the generic ``check_*`` functions used by every public function.

Every public function of prp3 passes its arguments through these checks
before it computes anything, so that a bad value gets the same refusal
wherever it is given (in the style of pytransform3d's ``check_*``):

* booleans, text, bytes, ``None``, objects and complex numbers are refused,
  never cast (numpy would read ``True`` as 1 and drop an imaginary part);
* masked arrays are refused (numpy would silently use the hidden values);
* integers too large for float64 (``10**400``) are refused;
* shapes are checked, and non-finite values are refused naming the sample,
  the leg or component, and the value.

The checks of poses and of one sample's state are
:mod:`prp3.pose_validation`; those between the samples of a motion are
:mod:`prp3.path_validation`.  Every refusal is a
:class:`~prp3.errors.Prp3Error` whose fields (``subject``, ``sample``,
``leg``, ``pose``, ``key``) say where it happened.

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
import os
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError, Prp3Error, TrajectoryError
from prp3.moved_paths import moved_attribute

if TYPE_CHECKING:
    from prp3.model.robot import Robot

__all__ = [
    "LEGS",
    "MIN_RTOL",
    "OVERFLOW_REASON",
    "check_choice",
    "check_file_path",
    "check_finite",
    "check_instance",
    "check_integer",
    "check_names",
    "check_per_leg",
    "check_real",
    "check_robot",
    "check_same_shape",
    "check_scalar",
    "check_times",
    "check_tolerances",
    "checked_spline",
    "first_non_finite",
    "first_not_increasing",
    "require_finite",
]

FloatArray = NDArray[np.float64]
T = TypeVar("T")
#: Leg names, in the order of the last axis of every per-leg array.
LEGS: tuple[str, str, str] = ("A", "B", "C")

#: How the reason of an error of results that overflowed begins (:func:`require_finite`).
OVERFLOW_REASON: str = "the results overflow"

_KINDS = {"b": "booleans", "c": "complex numbers", "U": "text", "S": "bytes", "V": "records"}


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


def first_not_increasing(t: FloatArray) -> int | None:
    """The index of the first time of ``t`` (shape ``(N,)``) not after the one before, or ``None``.

    >>> first_not_increasing(np.array([0.0, 0.1, 0.1, 0.3])), first_not_increasing(np.array([0.0, 1.0]))
    (2, None)
    """
    late = np.diff(t) <= 0.0
    return int(np.argmax(late)) + 1 if late.any() else None


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
    k = first_not_increasing(t)
    if k is not None:
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


def check_file_path(name: str, value: object) -> Path:
    """Return ``value`` as a :class:`~pathlib.Path` if it is a text path, else refuse it.

    >>> check_file_path("path", None)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: path must be a file path (str or pathlib.Path), got None
    """
    if isinstance(value, (str, os.PathLike)):
        try:
            path = Path(value)
        except TypeError:  # a PathLike returning bytes
            pass
        else:
            if "\0" not in str(path):  # the operating system refuses a NUL in a path
                return path
    raise ParameterError(
        f"{name} must be a file path (str or pathlib.Path), got {_describe(value)}", key=name
    )


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
        f"{OVERFLOW_REASON}: {name} is not finite; "
        "the motion or the robot's parameters are too large for double precision",
        subject=what,
        sample=index if batch else None,
        time=time if batch else None,
    )


def __getattr__(name: str) -> object:
    """The names this module had in prp3 0.1, now elsewhere (a DeprecationWarning names where)."""
    return moved_attribute(__name__, name)


#: The smallest relative tolerance of the forward integrations (100 machine epsilons:
#: scipy's ``solve_ivp`` raises smaller ones to this with a warning).
MIN_RTOL: float = 100.0 * float(np.finfo(np.float64).eps)


def check_tolerances(rtol: object, atol: object) -> tuple[float, float]:
    """The tolerances of a forward integration: finite, positive, ``rtol >= MIN_RTOL``.

    >>> check_tolerances(1e-10, 1e-12)
    (1e-10, 1e-12)
    >>> check_tolerances(1e-20, 1e-12)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: rtol must be at least 2.22e-14 (100 machine epsilons, scipy's floor), got 1e-20
    """
    relative = check_scalar("rtol", rtol, positive=True)
    absolute = check_scalar("atol", atol, positive=True)
    if relative < MIN_RTOL:
        raise ParameterError(
            f"rtol must be at least {MIN_RTOL:.3g} (100 machine epsilons, scipy's floor), "
            f"got {relative!r}",
            key="rtol",
        )
    return relative, absolute


def checked_spline(name: str, t: FloatArray, values: FloatArray) -> Any:
    """The not-a-knot ``scipy.interpolate.CubicSpline`` of the samples ``values`` at ``t``
    (axis 0), or a ParameterError naming ``name``, the sample and why float64 cannot hold it.

    ``t`` increasing and ``values`` finite (checked before); refused: samples whose slope
    ``Δv/Δt`` overflows (values of ``±1e308``), and a spline whose coefficients are not
    finite or that scipy cannot form (steps so small that its ``1/Δt²`` terms overflow:
    subnormal steps), naming the smallest step.

    >>> checked_spline("efforts", np.array([0.0, 0.5, 1.0]), np.array([0.0, 1e308, -1e308]))
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: sample 0: efforts change by 1e+308 from t = 0.0 s to t = 0.5 s: the slope overflows float64 (values out of range)
    """
    from scipy.interpolate import CubicSpline

    failure = ""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # scipy's LinAlgWarning: refused below
        step = np.diff(t)
        change = np.diff(values, axis=0).reshape(step.size, -1)
        bad = ~np.isfinite(change / step[:, None]).all(axis=1)
        if not bad.any():
            try:
                spline = CubicSpline(t, values, axis=0, bc_type="not-a-knot")
                if np.isfinite(spline.c).all():
                    return spline
                failure = "its coefficients are not finite"
            except ValueError as error:  # a system the steps make singular
                failure = str(error).rstrip(".")
    if bad.any():
        k = int(np.argmax(bad))
        largest = float(change[k][int(np.argmax(np.abs(change[k])))])
        raise ParameterError(
            f"{name} change by {largest!r} from t = {float(t[k])!r} s to "
            f"t = {float(t[k + 1])!r} s: the slope overflows float64 (values out of range)",
            key=name,
            sample=k,
        )
    k = int(np.argmin(step))
    if float(step[k]) ** 2 > 0.0:  # normal steps: the values are too large
        j = int(np.argmax(np.abs(values.reshape(t.size, -1)).max(axis=1)))
        shown = float(np.abs(values.reshape(t.size, -1)[j]).max())
        raise ParameterError(
            f"the cubic spline of the {name} does not fit in float64 ({failure}): the "
            f"samples' values are too large (|{name}| = {shown!r} at t = {float(t[j])!r} s)",
            key=name,
            sample=j,
        )
    raise ParameterError(
        f"the cubic spline of the {name} does not fit in float64 ({failure}): its smallest "
        f"time step, t = {float(t[k])!r} s to t = {float(t[k + 1])!r} s ({float(step[k])!r} s), "
        "is too small for the samples' values",
        key=name,
        sample=k,
    )
