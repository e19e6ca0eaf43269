"""Computed-torque control of a spatial robot (docs/spatial.md §23).

The law ``τ = A(x, ξ)·a_f + h(x, ξ)`` (the affine inverse dynamics of §18 at the
*actual* state) with the commanded free acceleration

``a = a_ref + Kd·ė + Kp·e``,  ``e = (log(R_ref·Rᵀ), p_ref − p)``,
``ė = (ω_ref − ω, v_ref − v)``

(``a_f`` its free components, §11) makes the closed loop of the exact model
``ë_p + Kd·ė_p + Kp·e_p = 0`` for the free position components.

>>> import numpy as np
>>> from prp3.spatial.model import hexapod
>>> robot = hexapod()
>>> still = lambda t: PlatformMotion.at_rest(robot.home_position)
>>> run = spatial_track(robot, still, 0.2, samples=3)
>>> float(np.abs(run.error).max()) < 1e-12
True
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.errors import ParameterError
from prp3.spatial.forward import spatial_forward_dynamics, spatial_platform_dynamics
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import log_rotation
from prp3.validation import check_instance, check_scalar

__all__ = ["SpatialTracking", "spatial_pose_error", "spatial_track"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class SpatialTracking:
    """Result of :func:`spatial_track`.

    Attributes
    ----------
    t : (N,) s
    reference : PlatformMotion
        The reference at the output times.
    actual : PlatformMotion
        The integrated motion of the plant.
    error : (N, 6)
        ``(log(R_ref·Rᵀ), p_ref − p)`` (rad, m).
    efforts : (N, legs)
        The law's efforts (N or N·m).
    effort_residual : float
        ``max |τ_inverse − τ|`` of the plant's inverse dynamics (N or N·m).
    """

    t: FloatArray
    reference: PlatformMotion
    actual: PlatformMotion
    error: FloatArray
    efforts: FloatArray
    effort_residual: float


def spatial_pose_error(reference: PlatformMotion, actual: PlatformMotion) -> FloatArray:
    """The pose error ``(log(R_ref·Rᵀ), p_ref − p)``, shape ``(N, 6)`` (rad, m).

    >>> import numpy as np
    >>> a = PlatformMotion.at_rest([0.0, 0.0, 0.1])
    >>> spatial_pose_error(a, PlatformMotion.at_rest([0.0, 0.0, 0.0])).tolist()
    [[0.0, 0.0, 0.0, 0.0, 0.0, 0.1]]
    """
    check_instance("reference", reference, PlatformMotion, "a PlatformMotion")
    check_instance("actual", actual, PlatformMotion, "a PlatformMotion")
    if len(reference) != len(actual):
        raise ParameterError(
            f"reference and actual must have as many samples, got {len(reference)} and "
            f"{len(actual)}",
            key="actual",
        )
    rotation = reference.rotation @ np.swapaxes(actual.rotation, -1, -2)
    return np.concatenate([log_rotation(rotation), reference.position - actual.position], axis=1)


def _reference_at(reference: Callable[[float], PlatformMotion], time: float) -> PlatformMotion:
    value = reference(time)
    if not isinstance(value, PlatformMotion) or len(value) != 1:
        raise ParameterError(
            f"reference must return a PlatformMotion of one sample, got {value!r}"[:300],
            key="reference",
        )
    return value


def spatial_track(
    robot: SpatialRobot,
    reference: Callable[[float], PlatformMotion],
    duration: float,
    *,
    kp: float = 400.0,
    kd: float = 40.0,
    initial: PlatformMotion | None = None,
    samples: int = 101,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    plant: str = "prp3",
) -> SpatialTracking:
    """Track ``reference`` with the computed-torque law on the prp3 plant (§23).

    Parameters
    ----------
    robot : SpatialRobot
        Both the plant and the controller's model.
    reference : callable
        ``reference(t) -> PlatformMotion`` of one sample (pose, twist, accelerations).
    duration : float
        ``T`` (s, > 0) from ``t0 = 0``.
    kp, kd : float
        Gains (1/s², 1/s, ≥ 0), the same for every component.
    initial : PlatformMotion, optional
        The plant's initial state (default: the reference at 0, no error).
    samples, rtol, atol
        As :func:`~prp3.spatial.forward.spatial_forward_dynamics`.
    plant : {"prp3"}
        The plant (the MuJoCo plant is not built yet).

    Returns
    -------
    SpatialTracking
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    if not callable(reference):
        raise ParameterError(
            f"reference must be a function t -> PlatformMotion, got {reference!r}"[:300],
            key="reference",
        )
    p_gain = check_scalar("kp", kp, non_negative=True, unit="1/s²")
    d_gain = check_scalar("kd", kd, non_negative=True, unit="1/s")
    if plant != "prp3":
        raise ParameterError(f"plant must be 'prp3', got {plant!r}", key="plant")
    start = initial if initial is not None else _reference_at(reference, 0.0)
    free = [c for c in range(6) if c not in robot.parasitic_index]

    def law(time: float, state: PlatformMotion) -> FloatArray:
        ref = _reference_at(reference, time)
        e = spatial_pose_error(ref, state)[0]
        de = np.concatenate([ref.omega - state.omega, ref.velocity - state.velocity], axis=1)[0]
        a_ref = np.concatenate([ref.alpha, ref.acceleration], axis=1)[0]
        command = a_ref + d_gain * de + p_gain * e
        dyn = spatial_platform_dynamics(robot, state)
        return np.asarray(dyn.effort_matrix[0] @ command[free] + dyn.effort_bias[0])

    run = spatial_forward_dynamics(
        robot, np.zeros(len(robot.legs)), start, duration, samples=samples,
        rtol=rtol, atol=atol, feedback=law,
    )  # fmt: skip
    refs = [_reference_at(reference, float(s)) for s in run.motion.t]
    ref = PlatformMotion(
        run.motion.t.copy(),
        *(np.concatenate([getattr(r, f) for r in refs]) for f in _FIELDS),
    )
    error = spatial_pose_error(ref, run.motion)
    return SpatialTracking(run.motion.t, ref, run.motion, error, run.efforts, run.effort_residual)


_FIELDS = ("position", "rotation", "omega", "velocity", "alpha", "acceleration")
