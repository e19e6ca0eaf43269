"""Computed-torque control of a spatial robot (docs/spatial.md §23).

The law ``τ = A(x, ξ)·a_f + h(x, ξ)`` (the affine inverse dynamics of §18 at the
*actual* state) with the commanded free acceleration

``a = a_ref + Kd·ė + Kp·e``,  ``e = (log(R_ref·Rᵀ), p_ref − p)``,
``ė = (ω_ref − ω, v_ref − v)``

(``a_f`` its free components, §11; ``Kp``, ``Kd`` one gain for every component or
diagonal, one per component in the order of ``e``) makes the closed loop of the
exact model ``ë_c + Kd_c·ė_c + Kp_c·e_c = 0`` for each free position component ``c``.

>>> import numpy as np
>>> from prp3.spatial.model import hexapod
>>> robot = hexapod()
>>> still = lambda t: PlatformMotion.at_rest(robot.home_position)
>>> run = spatial_track(robot, still, 0.2, samples=3)
>>> float(np.abs(run.error).max()) < 1e-12
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.apps.spatial_mjcf import spatial_mjcf_joint_names, spatial_mjcf_model
from prp3.errors import ParameterError
from prp3.spatial.forward import spatial_forward_dynamics, spatial_platform_dynamics
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.outputs import spatial_inverse_dynamics
from prp3.spatial.rotations import log_rotation, matrix_quaternion, quaternion_matrix
from prp3.validation import check_finite, check_instance, check_integer, check_real, check_scalar

__all__ = ["SPATIAL_PLANTS", "SpatialTracking", "spatial_pose_error", "spatial_track"]

#: The plants of :func:`spatial_track`.
SPATIAL_PLANTS: tuple[str, ...] = ("prp3", "mujoco")

# The components of the pose error ``e = (log(R_ref·Rᵀ), p_ref − p)``, in order: the gains'.
_COMPONENTS: tuple[str, ...] = ("rx", "ry", "rz", "x", "y", "z")

# MuJoCo's largest constraint impedance (``mjMAXIMP``): the plant's ``solimp``.
_MUJOCO_MAX_IMPEDANCE = 0.9999

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
        ``max |τ_inverse − τ|`` of the plant's inverse dynamics (N or N·m); NaN for
        the MuJoCo plant.
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


def _gains(name: str, value: object, unit: str = "") -> FloatArray:
    """A gain of :func:`spatial_track` per pose component, shape ``(6,)``.

    ``value`` is one number for every component, or six, one per component of
    ``_COMPONENTS`` (rotation ``rx, ry, rz`` then translation ``x, y, z``);
    each finite and ``>= 0`` (``name`` and ``unit`` name it in a refusal).

    >>> _gains("kp", 400.0).tolist()
    [400.0, 400.0, 400.0, 400.0, 400.0, 400.0]
    >>> _gains("kd", [10, 10, 10, 20, 20, 40]).tolist()
    [10.0, 10.0, 10.0, 20.0, 20.0, 40.0]
    >>> _gains("kp", [1.0, 2.0])
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: kp must be a number or 6 numbers (rx, ry, rz, x, y, z), got shape (2,): [1.0, 2.0]
    """
    if not (isinstance(value, list | tuple) or (isinstance(value, np.ndarray) and value.ndim)):
        return np.full(6, check_scalar(name, value, non_negative=True, unit=unit))
    array = check_real(name, value, ParameterError)
    if array.shape != (6,):
        shown = repr(value) if len(repr(value)) <= 60 else repr(value)[:57] + "..."
        raise ParameterError(
            f"{name} must be a number or 6 numbers ({', '.join(_COMPONENTS)}), got shape "
            f"{array.shape}: {shown}",
            key=name,
        )
    check_finite(name, array, ParameterError, components=_COMPONENTS)
    negative = np.flatnonzero(~(array >= 0.0))
    if negative.size:
        k = int(negative[0])
        units = f" ({unit})" if unit else ""
        raise ParameterError(
            f"{_COMPONENTS[k]} of {name} must be non-negative{units}, got {float(array[k])!r}",
            key=name,
        )
    return array


def _reference_at(reference: Callable[[float], PlatformMotion], time: float) -> PlatformMotion:
    value = reference(time)
    if not isinstance(value, PlatformMotion) or len(value) != 1:
        raise ParameterError(
            f"reference must return a PlatformMotion of one sample, got {value!r}"[:300],
            key="reference",
        )
    return value


def _check_plant(plant: object) -> None:
    """Refuse an unknown plant."""
    if plant not in SPATIAL_PLANTS:
        raise ParameterError(
            f"plant must be one of {', '.join(SPATIAL_PLANTS)}, got {plant!r}", key="plant"
        )


def spatial_track(
    robot: SpatialRobot,
    reference: Callable[[float], PlatformMotion],
    duration: float,
    *,
    kp: float | ArrayLike = 400.0,
    kd: float | ArrayLike = 40.0,
    initial: PlatformMotion | None = None,
    samples: int = 101,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    plant: str = "prp3",
    timestep: float = 1e-3,
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
    kp, kd : float or (6,)
        Gains (1/s², 1/s, finite, ≥ 0): one for every component, or six, one per
        component of the error ``(rx, ry, rz, x, y, z)``; a
        parasitic component's gain (the 3-RPS's ``rz, x, y``) is not used.
    initial : PlatformMotion, optional
        The plant's initial state (default: the reference at 0, no error).
    samples, rtol, atol
        As :func:`~prp3.spatial.forward.spatial_forward_dynamics`.
    plant : {"prp3", "mujoco"}
        The plant: prp3's forward dynamics (§18), or MuJoCo running
        :func:`~prp3.apps.spatial_mjcf.spatial_mjcf_model` (§16) with its RK4
        integrator, the efforts held over each step (needs the ``mujoco`` package).
    timestep : float
        The MuJoCo plant's step (s, > 0), rounded so that ``duration`` is a whole
        number of steps; each output instant is the step nearest it.  The loop
        closures' equalities get MuJoCo's stiffest ``solref = (2·timestep, 1)`` and
        ``solimp`` (impedance 0.9999), a closing U's end body the platform's
        inverse weight (§23).
        ``rtol``, ``atol`` are the prp3 plant's.

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
    p_gain = _gains("kp", kp, "1/s²")
    d_gain = _gains("kd", kd, "1/s")
    _check_plant(plant)
    step = check_scalar("timestep", timestep, positive=True, unit="s")
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

    if plant == "mujoco":
        check_integer("samples", samples, 2, 10**7)
        return _mujoco_track(robot, reference, duration, start, law, samples, step)
    run = spatial_forward_dynamics(
        robot, np.zeros(len(robot.legs)), start, duration, samples=samples,
        rtol=rtol, atol=atol, feedback=law,
    )  # fmt: skip
    ref = _stacked([_reference_at(reference, float(s)) for s in run.motion.t])
    error = spatial_pose_error(ref, run.motion)
    return SpatialTracking(run.motion.t, ref, run.motion, error, run.efforts, run.effort_residual)


_FIELDS = ("position", "rotation", "omega", "velocity", "alpha", "acceleration")


def _mujoco_start(mujoco: Any, robot: SpatialRobot, start: PlatformMotion) -> tuple[Any, Any]:
    """MuJoCo's model of ``robot`` (RK4) and its data in the state ``start``."""
    model = mujoco.MjModel.from_xml_string(spatial_mjcf_model(robot))
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    data = mujoco.MjData(model)
    kinematics = spatial_inverse_dynamics(robot, start).kinematics
    names = set(spatial_mjcf_joint_names(robot))
    for i, leg in enumerate(robot.legs):
        for c, coordinate in enumerate(leg.coordinates):
            if f"leg{i + 1}_{coordinate}" in names:  # not a closing S's (the connect)
                joint = model.joint(f"leg{i + 1}_{coordinate}")
                data.qpos[joint.qposadr[0]] = kinematics.q[0, i, c]
                data.qvel[joint.dofadr[0]] = kinematics.dq[0, i, c]
    free = model.joint("platform")
    q0, v0 = int(free.qposadr[0]), int(free.dofadr[0])
    data.qpos[q0 : q0 + 3] = start.position[0]
    data.qpos[q0 + 3 : q0 + 7] = matrix_quaternion(start.rotation[0])
    data.qvel[v0 : v0 + 3] = start.velocity[0]
    data.qvel[v0 + 3 : v0 + 6] = start.rotation[0].T @ start.omega[0]
    mujoco.mj_forward(model, data)
    return model, data


def _stiffen_closures(model: Any, robot: SpatialRobot) -> None:
    """The loop closures as stiff as MuJoCo allows (docs/spatial.md §23, the Delta).

    ``solref = (2·timestep, 1)`` and ``solimp`` of impedance ``0.9999`` (``mjMAXIMP``).
    A closing U's body ``leg{i}_end`` (mass ``END_MASS_FRACTION`` of the platform's,
    §16) is welded to the platform, so its inverse weight, which scales the weld's
    regularisation ``R = (1 − d)/d · (w_end + w_platform)``, is set to the platform's:
    with its own (about ``1e12`` times larger) the weld is so soft that the Delta's
    platform turns by 0.2 rad.
    """
    model.eq_solref[:] = (2.0 * model.opt.timestep, 1.0)
    model.eq_solimp[:, :2] = _MUJOCO_MAX_IMPEDANCE
    platform = model.body("platform").id
    for i, leg in enumerate(robot.legs, 1):
        if leg.joints[-1].kind != "S":
            model.body_invweight0[model.body(f"leg{i}_end").id] = model.body_invweight0[platform]


def _mujoco_state(model: Any, data: Any, time: float) -> PlatformMotion:
    """The platform's pose and twist in MuJoCo's state (accelerations zero: unused)."""
    free = model.joint("platform")
    q0, v0 = int(free.qposadr[0]), int(free.dofadr[0])
    rotation = quaternion_matrix(data.qpos[q0 + 3 : q0 + 7])
    return PlatformMotion.of(
        [time], [data.qpos[q0 : q0 + 3]], rotation[None], [rotation @ data.qvel[v0 + 3 : v0 + 6]],
        [data.qvel[v0 : v0 + 3]],
    )  # fmt: skip


def _mujoco_track(
    robot: SpatialRobot,
    reference: Callable[[float], PlatformMotion],
    duration: float,
    start: PlatformMotion,
    law: Callable[[float, PlatformMotion], FloatArray],
    samples: int,
    timestep: float,
) -> SpatialTracking:
    """:func:`spatial_track` on the MuJoCo plant: ``law`` evaluated and held each step."""
    try:
        import mujoco
    except ImportError:
        raise ParameterError(
            "plant='mujoco' needs the mujoco package: pip install mujoco", key="plant"
        ) from None
    model, data = _mujoco_start(mujoco, robot, start)
    steps = max(1, round(duration / timestep))
    model.opt.timestep = duration / steps
    _stiffen_closures(model, robot)
    marks = np.rint(np.linspace(0.0, steps, samples)).astype(int)
    states, efforts = [], []
    for k in range(steps + 1):
        state = _mujoco_state(model, data, k * model.opt.timestep)
        tau = law(k * model.opt.timestep, state)
        for _ in range(int(np.count_nonzero(marks == k))):
            states.append(state)
            efforts.append(tau)
        if k < steps:
            data.ctrl[:] = tau / model.actuator_gear[:, 0]
            mujoco.mj_step(model, data)
    t = marks * model.opt.timestep
    actual = _stacked(states)
    ref = _stacked([_reference_at(reference, float(s)) for s in t])
    return SpatialTracking(
        actual.t, ref, actual, spatial_pose_error(ref, actual), np.array(efforts), math.nan
    )


def _stacked(samples: list[PlatformMotion]) -> PlatformMotion:
    """One motion of the one-sample motions ``samples``, in order."""
    return PlatformMotion(
        np.concatenate([m.t for m in samples]),
        *(np.concatenate([getattr(m, f) for m in samples]) for f in _FIELDS),
    )
