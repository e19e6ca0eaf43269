"""The control laws: actuator forces of one control step from the reference and the measured state.

With ``e = q_ref − q``, gains ``KP`` (1/s²) and ``KD`` (1/s), the same for
``x``, ``y`` and ``φ`` or one per axis (:class:`Gains`), and ``ID_model`` the
inverse dynamics of the controller's model of the robot (:func:`control_force`):

* computed torque: ``f10 = ID_model(q, q̇, q̈_ref + KD·ė + KP·e)``.  With an
  exact model the closed loop is ``ë + KD·ė + KP·e = 0`` between the
  instants: critically damped for ``KD² = 4·KP`` (the defaults 400 and 40).
* PD: ``f10 = ID_model(q, 0, KD·ė + KP·e)``: a PD law through the model's mass
  matrix with gravity compensation, without feed-forward of the reference
  acceleration and without the velocity terms.
* feed-forward: ``f10 = ID_model(q_ref, q̇_ref, q̈_ref)`` (open loop).

The closed loop that calls them is :func:`prp3.apps.control.track`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from prp3.engines.compiled_robot import CompiledRobot
from prp3.errors import ParameterError
from prp3.family.forward import FamilyEffortModel
from prp3.validation import check_scalar

__all__ = [
    "CONTROLLERS",
    "DEFAULT_KD",
    "DEFAULT_KP",
    "AxisGains",
    "Controller",
    "Gains",
    "control_force",
]

Controller = Literal["computed-torque", "pd", "feedforward"]

#: The control laws of :func:`control_force`.
CONTROLLERS: tuple[Controller, ...] = ("computed-torque", "pd", "feedforward")
#: Default position gain ``KP`` (1/s²) and velocity gain ``KD`` (1/s): critically damped.
DEFAULT_KP: float = 400.0
DEFAULT_KD: float = 40.0


def _gain(name: str, value: Any, unit: str) -> float:
    try:
        return check_scalar(name, value, non_negative=True)
    except ParameterError:
        shown = repr(value) if len(repr(value)) <= 40 else repr(value)[:37] + "..."
        raise ParameterError(
            f"{name} must be a non-negative finite number ({unit}), got {shown}",
            subject="gains",
            key=name,
        ) from None


AxisGains = float | tuple[float, float, float]


def _gains(name: str, value: Any, unit: str) -> AxisGains:
    """One gain for every axis (a number) or one per axis ``(x, y, φ)`` (3 numbers)."""
    if (
        isinstance(value, (str, bytes))
        or not isinstance(value, (Sequence, np.ndarray))
        or (isinstance(value, np.ndarray) and value.ndim != 1)
    ):
        return _gain(name, value, unit)
    if len(value) != 3:
        shown = repr(value) if len(repr(value)) <= 40 else repr(value)[:37] + "..."
        raise ParameterError(
            f"{name} must be a number or 3 numbers (x, y, phi), got {len(value)} numbers: {shown}",
            subject="gains",
            key=name,
        )
    x, y, phi = (_gain(f"{name}[{k}]", v, unit) for k, v in enumerate(value))
    return (x, y, phi)


def _per_axis(value: AxisGains) -> tuple[float, float, float]:
    return value if isinstance(value, tuple) else (value, value, value)


@dataclass(frozen=True)
class Gains:
    """Gains of the control laws: the same for ``x``, ``y`` and ``φ``, or one per axis.

    Attributes
    ----------
    kp : float or tuple of 3 floats
        ``KP`` (1/s²), >= 0: one for every axis, or ``(KP_x, KP_y, KP_φ)``.
    kd : float or tuple of 3 floats
        ``KD`` (1/s), >= 0: one for every axis, or ``(KD_x, KD_y, KD_φ)``.
    kp_axes, kd_axes : tuple of 3 floats
        The gains of ``x``, ``y``, ``φ`` (derived).

    >>> Gains(kd=-1.0)
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: gains: kd must be a non-negative finite number (1/s), got -1.0
    >>> Gains(kp=(400.0, 400.0, 900.0)).kp_axes, Gains(kd=60).kd_axes
    ((400.0, 400.0, 900.0), (60.0, 60.0, 60.0))
    """

    kp: AxisGains = DEFAULT_KP
    kd: AxisGains = DEFAULT_KD
    kp_axes: tuple[float, float, float] = field(init=False, repr=False, compare=False)
    kd_axes: tuple[float, float, float] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        kp, kd = _gains("kp", self.kp, "1/s²"), _gains("kd", self.kd, "1/s")
        object.__setattr__(self, "kp", kp)
        object.__setattr__(self, "kd", kd)
        object.__setattr__(self, "kp_axes", _per_axis(kp))
        object.__setattr__(self, "kd_axes", _per_axis(kd))


def control_force(
    controller: Controller,
    model: CompiledRobot | FamilyEffortModel,
    gains: Gains,
    reference: Sequence[float],
    measured: Sequence[float],
) -> tuple[float, float, float]:
    """Actuator forces ``f10`` (N) of one control step (see the module notes).

    Pure Python floats on prp3's single-sample inverse dynamics
    (:meth:`prp3.engines.compiled_robot.CompiledRobot.actuator_sample_function`, ``f10`` alone):
    it does not validate, the caller guarantees finite numbers and poses away
    from the singularity.

    Parameters
    ----------
    controller : {"computed-torque", "pd", "feedforward"}
    model : CompiledRobot or FamilyEffortModel
        The controller's model of the robot (:func:`prp3.engines.compiled_robot.compile_robot`
        of a 3-PRP, :class:`prp3.family.forward.FamilyEffortModel` of any architecture:
        the same laws on its actuator efforts ``tau``, N or N·m).
    gains : Gains
    reference : sequence of 9 floats
        ``(x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈)`` of the reference at this instant.
    measured : sequence of 6 floats
        Measured ``(x, y, φ, ẋ, ẏ, φ̇)``.

    Returns
    -------
    tuple of 3 floats
        ``f10`` of legs A, B, C (N), held until the next instant.

    Examples
    --------
    >>> from prp3 import Robot
    >>> from prp3.engines.compiled_robot import compile_robot
    >>> still = (0.0,) * 9
    >>> f = control_force("pd", compile_robot(Robot()), Gains(), still, (0.0,) * 6)
    >>> [round(v, 4) for v in f]          # gravity compensation at the centre
    [31.8589, -8.4957, -23.3632]
    """
    rx, ry, rp, rvx, rvy, rvp, rax, ray, rap = reference
    x, y, p, vx, vy, vp = measured
    kpx, kpy, kpp = gains.kp_axes
    kdx, kdy, kdp = gains.kd_axes
    inverse = model.actuator_sample_function()  # f10 alone, unchecked
    if controller == "computed-torque":
        f = inverse(
            x, y, p, vx, vy, vp,
            rax + kdx * (rvx - vx) + kpx * (rx - x),
            ray + kdy * (rvy - vy) + kpy * (ry - y),
            rap + kdp * (rvp - vp) + kpp * (rp - p),
        )  # fmt: skip
    elif controller == "pd":
        f = inverse(
            x, y, p, 0.0, 0.0, 0.0,
            kdx * (rvx - vx) + kpx * (rx - x),
            kdy * (rvy - vy) + kpy * (ry - y),
            kdp * (rvp - vp) + kpp * (rp - p),
        )  # fmt: skip
    elif controller == "feedforward":
        f = inverse(rx, ry, rp, rvx, rvy, rvp, rax, ray, rap)
    else:
        raise ParameterError(
            f"controller must be one of {', '.join(CONTROLLERS)}, got {controller!r}"
        )
    return (f[0], f[1], f[2])
