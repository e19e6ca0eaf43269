r"""Identification of the spatial robots (docs/identification.md, "Spatial robots").

The actuator efforts ``τ (N, legs)`` of a :class:`~prp3.spatial.model.SpatialRobot`
(docs/spatial.md §8) are linear and homogeneous in the standard inertial
parameters of its moving bodies, for a fixed geometry and gravity.  Of each
body, **in its own frame and about its frame's origin** (a leg body ``k``: the
distal frame of joint ``k``, origin at that joint's centre; the platform: the
platform frame ``(p, R)``, origin ``p``), ten parameters:

- ``mass`` ``m`` (kg);
- ``moment_x, moment_y, moment_z``: the first moment ``h = m·c`` (kg·m;
  ``c`` = the body's ``centre``, in its frame);
- ``inertia_xx, inertia_xy, inertia_xz, inertia_yy, inertia_yz, inertia_zz``: the
  entries of the inertia tensor about the frame's origin,
  ``J = I + m·(|c|²·1 − c·cᵀ)`` (kg·m²; ``I`` = the body's ``inertia`` about its
  mass centre; the products are the tensor's entries, ``J_xy = I_xy − m·c_x·c_y``).

With ``ω, α`` the body's angular velocity and acceleration, ``a`` its frame
origin's acceleration, ``g`` gravity and ``R`` its rotation (world frame), its
inertial wrench about its origin is linear in them:

``F = m·(a − g) + α × Rh + ω × (ω × Rh)``,
``M_o = RJRᵀ·α + ω × (RJRᵀ·ω) + Rh × (a − g)``,

and route (a) of the inverse dynamics (:func:`prp3.spatial.dynamics.chunk_efforts`:
virtual work on the chain's matrices, the solve of ``J_pᵀ``) is linear in the
bodies' wrenches: the regressor's column of a parameter is route (a) run on the
kinematics of the motion with that parameter's unit wrench on its body alone
(every other body's zero) — prp3's own inverse dynamics, not a second model.

The legs are alike (the spatial robot files of docs/spatial.md §13 give one
table per leg body for every leg): the default ``per_leg=False`` takes each leg
body's parameters as *shared* by every leg (``rod_mass``: the mass of every
leg's rod; its column the sum of the legs' columns), ``10·(bodies per leg + 1)``
parameters; ``per_leg=True`` gives every leg its own (``leg3_rod_mass``),
``10·(legs·bodies + 1)``.  The base parameters are those of
:func:`prp3.apps.base_parameters.base_parameters_of` on random regular states
(:func:`spatial_random_motion`); the estimate is
:func:`prp3.apps.identification.weighted_least_squares` of the base regressor.

>>> from prp3.spatial.model import three_rps
>>> from prp3.spatial.outputs import spatial_inverse_dynamics
>>> robot = three_rps()
>>> motion = spatial_random_motion(robot, 20, seed=1)
>>> Y = spatial_regressor(robot, motion)
>>> Y.tau.shape, Y.parameters[:2]
((20, 3, 30), ('platform_mass', 'platform_moment_x'))
>>> tau = spatial_inverse_dynamics(robot, motion).tau
>>> bool(np.allclose(Y.tau @ spatial_standard_parameters(robot), tau, rtol=0, atol=1e-12))
True
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.apps.base_parameters import BaseParameters, base_parameters_of
from prp3.apps.identification import (
    Identification,
    check_samples,
    excitation_refusal,
    fit_base_parameters,
)
from prp3.errors import ParameterError, Prp3Error, TrajectoryError
from prp3.io.spatial_robot import SpatialRobotFile, spatial_robot_from_mapping, spatial_robot_text
from prp3.spatial.dynamics import BodyWrenches, chunk_efforts, virtual_work_efforts
from prp3.spatial.geometry import CHUNK
from prp3.spatial.kinematics import chunk_kinematics, complete_motion, spatial_kinematics
from prp3.spatial.model import TWIST_COMPONENTS, Body, SpatialRobot
from prp3.spatial.motion import PlatformMotion, rpy_rates
from prp3.spatial.rotations import cross, rpy_matrix
from prp3.validation import check_instance, check_integer, check_real, check_scalar

__all__ = [
    "BODY_PARAMETERS",
    "SPATIAL_FORCES",
    "SpatialExcitation",
    "SpatialRegressor",
    "body_parameters",
    "spatial_base_parameters",
    "spatial_body_names",
    "spatial_exciting_trajectory",
    "spatial_identified_robot",
    "spatial_identify",
    "spatial_parameter_names",
    "spatial_parameter_unit",
    "spatial_random_motion",
    "spatial_regressor",
    "spatial_standard_parameters",
]

FloatArray = NDArray[np.float64]

#: The ten standard parameters of one body, in order (module docstring: frame and point).
BODY_PARAMETERS: tuple[str, ...] = (
    "mass",
    "moment_x",
    "moment_y",
    "moment_z",
    "inertia_xx",
    "inertia_xy",
    "inertia_xz",
    "inertia_yy",
    "inertia_yz",
    "inertia_zz",
)

#: The efforts the spatial base parameters are of: the actuator efforts.
SPATIAL_FORCES: tuple[str, ...] = ("tau",)

_INERTIA_INDEX: dict[str, tuple[int, int]] = {
    "xx": (0, 0), "xy": (0, 1), "xz": (0, 2), "yy": (1, 1), "yz": (1, 2), "zz": (2, 2),
}  # fmt: skip

_IDENTIFIER = re.compile(r"[a-z][a-z0-9]*\Z")


def _check_robot(robot: object) -> SpatialRobot:
    check_instance("robot", robot, SpatialRobot, "a prp3 SpatialRobot")
    assert isinstance(robot, SpatialRobot)
    return robot


def _check_flag(per_leg: object) -> bool:
    if not isinstance(per_leg, bool):
        raise ParameterError(f"per_leg must be True or False, got {per_leg!r}"[:200], key="per_leg")
    return per_leg


def spatial_body_names(robot: SpatialRobot) -> tuple[str, ...]:
    """The names of a leg's bodies in the parameter names: their ``Body.name`` (``cylinder``,
    ``rod``; ``arm``, ``forearm``), or ``body1, body2, ...`` when those are not distinct
    lower-case identifiers other than ``platform``.

    >>> from prp3.spatial.model import delta
    >>> spatial_body_names(delta())
    ('arm', 'forearm')
    """
    robot = _check_robot(robot)
    names = tuple(body.name for body in robot.legs[0].bodies)
    if (
        len(set(names)) == len(names)
        and all(_IDENTIFIER.match(name) for name in names)
        and "platform" not in names
        and not any(name.startswith("leg") for name in names)
    ):
        return names
    return tuple(f"body{k + 1}" for k in range(len(names)))


def _bodies(robot: SpatialRobot, per_leg: bool) -> list[tuple[str, int | None, int | None]]:
    """``(prefix, leg, body)`` of every parameterised body, in order of preference: the platform,
    then the leg bodies from the platform inward (per leg: leg by leg)."""
    names = spatial_body_names(robot)
    order = list(range(len(names)))[::-1]
    out: list[tuple[str, int | None, int | None]] = [("platform", None, None)]
    if per_leg:
        for i in range(len(robot.legs)):
            out += [(f"leg{i + 1}_{names[k]}", i, k) for k in order]
    else:
        out += [(names[k], None, k) for k in order]
    return out


def spatial_parameter_names(robot: SpatialRobot, *, per_leg: bool = False) -> tuple[str, ...]:
    """The standard parameters of ``robot``: ``<body>_<kind>`` (kinds :data:`BODY_PARAMETERS`).

    >>> from prp3.spatial.model import hexapod
    >>> names = spatial_parameter_names(hexapod())
    >>> len(names), names[10], len(spatial_parameter_names(hexapod(), per_leg=True))
    (30, 'rod_mass', 130)
    """
    robot = _check_robot(robot)
    per_leg = _check_flag(per_leg)
    return tuple(
        f"{prefix}_{kind}" for prefix, _, _ in _bodies(robot, per_leg) for kind in BODY_PARAMETERS
    )


def spatial_parameter_unit(name: str) -> str:
    """The SI unit of a standard parameter's kind: ``kg``, ``kg m`` or ``kg m^2``.

    >>> spatial_parameter_unit("rod_moment_x"), spatial_parameter_unit("platform_inertia_xy")
    ('kg m', 'kg m^2')
    """
    if not isinstance(name, str) or not any(name.endswith("_" + k) for k in BODY_PARAMETERS):
        raise ParameterError(
            f"{name!r} is not a spatial standard parameter (<body>_<kind>, kinds: "
            f"{', '.join(BODY_PARAMETERS)})"[:300],
            key="name",
        )
    if "_moment_" in name:
        return "kg m"
    return "kg m^2" if "_inertia_" in name else "kg"


def body_parameters(body: Body) -> FloatArray:
    """The ten standard parameters of ``body`` (:data:`BODY_PARAMETERS`), about its frame's origin.

    >>> from prp3.spatial.model import hexapod
    >>> body_parameters(hexapod().legs[0].bodies[1]).round(9).tolist()[:5]  # the rod
    [0.05, -0.0015, 0.0, 0.0, 6.25e-07]
    """
    check_instance("body", body, Body, "a prp3 spatial Body")
    m = body.mass
    c = np.array(body.centre)
    J = np.array(body.inertia) + m * (float(c @ c) * np.eye(3) - np.outer(c, c))
    return np.array([m, *(m * c), *(J[i, j] for i, j in _INERTIA_INDEX.values())], dtype=np.float64)


def spatial_standard_parameters(robot: SpatialRobot, *, per_leg: bool = False) -> FloatArray:
    """The standard parameters ``π`` of ``robot``, in the order of :func:`spatial_parameter_names`.

    With ``per_leg=False`` every leg must have the same bodies (the shared parameters).

    >>> from prp3.spatial.model import hexapod
    >>> spatial_standard_parameters(hexapod())[10:14].round(12).tolist()  # the rod: m, m·c
    [0.05, -0.0015, 0.0, 0.0]
    """
    robot = _check_robot(robot)
    per_leg = _check_flag(per_leg)
    if not per_leg:
        first = robot.legs[0].bodies
        for i, leg in enumerate(robot.legs):
            for k, body in enumerate(leg.bodies):
                same = (body.mass, body.centre, body.inertia)
                if same != (first[k].mass, first[k].centre, first[k].inertia):
                    raise ParameterError(
                        f"leg {i + 1}'s body {k + 1} ({body.name}) differs from leg 1's: the "
                        "shared parameters need alike legs; use per_leg=True",
                        key="robot",
                    )
    values = []
    for _, which, index in _bodies(robot, per_leg):
        body = (
            robot.platform
            if index is None
            else robot.legs[0 if which is None else which].bodies[index]
        )
        values.append(body_parameters(body))
    return np.concatenate(values)


@dataclass(frozen=True)
class SpatialRegressor:
    """The regressor of a spatial robot's motion: ``τ = Y·π``.

    Attributes
    ----------
    parameters : tuple of str
        The standard parameters of the columns (:func:`spatial_parameter_names`).
    tau : ndarray, shape (N, legs, P)
        ``Y``: ``Y @ π`` is the actuator efforts (N for a P joint, N·m for an R joint).
    """

    parameters: tuple[str, ...]
    tau: FloatArray


def _unit_wrenches(
    rotation: FloatArray, acceleration: FloatArray, omega: FloatArray, alpha: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The inertial wrench ``(F, M_o)`` of each of the ten unit parameters: ``(..., 10, 3)``.

    ``acceleration`` is the frame origin's minus gravity."""
    forces, moments = [], []
    zero = np.zeros_like(acceleration)
    forces.append(acceleration)
    moments.append(zero)
    for j in range(3):
        u = rotation[..., :, j]
        forces.append(cross(alpha, u) + cross(omega, cross(omega, u)))
        moments.append(cross(u, acceleration))
    for i, j in _INERTIA_INDEX.values():
        ui, uj = rotation[..., :, i], rotation[..., :, j]
        a_i = np.einsum("...k,...k->...", ui, alpha)[..., None]
        a_j = np.einsum("...k,...k->...", uj, alpha)[..., None]
        w_i = np.einsum("...k,...k->...", ui, omega)[..., None]
        w_j = np.einsum("...k,...k->...", uj, omega)[..., None]
        if i == j:  # J = u uᵀ
            ja, jw = ui * a_i, ui * w_i
        else:  # J = ui ujᵀ + uj uiᵀ
            ja, jw = ui * a_j + uj * a_i, ui * w_j + uj * w_i
        forces.append(zero)
        moments.append(ja + cross(omega, jw))
    return np.stack(forces, axis=-2), np.stack(moments, axis=-2)


def _chunk_columns(
    robot: SpatialRobot, motion: PlatformMotion, offset: int, per_leg: bool
) -> FloatArray:
    """The regressor of one chunk: ``(n, legs, P)``."""
    kin = chunk_kinematics(robot, motion, offset)
    gravity = np.array(robot.gravity)
    count = len(robot.legs[0].bodies)
    n, legs = len(motion), len(robot.legs)
    bodies, frames = kin.bodies, kin.frames
    origin = bodies.origin[:, :, :count]
    leg_f, leg_m = _unit_wrenches(
        frames.rotation[:, :, :count],
        bodies.acceleration[:, :, :count] - gravity,
        bodies.omega[:, :, :count],
        bodies.alpha[:, :, :count],
    )  # (n, legs, count, 10, 3)
    plat_f, plat_m = _unit_wrenches(
        motion.rotation, motion.acceleration - gravity, motion.omega, motion.alpha
    )  # (n, 10, 3)
    zeros_leg = np.zeros((n, legs, count, 3))
    zeros_platform = np.zeros((n, 3))

    def efforts(
        force: FloatArray, moment: FloatArray, pf: FloatArray, pm: FloatArray
    ) -> FloatArray:
        wrenches = BodyWrenches(
            origin, zeros_leg, zeros_leg, zeros_leg, force, moment,
            motion.position, zeros_platform, pf, pm,
        )  # fmt: skip
        return chunk_efforts(robot, kin, motion, wrenches)

    columns = []
    for _, i, k in _bodies(robot, per_leg):
        for p in range(len(BODY_PARAMETERS)):
            if k is None:
                columns.append(efforts(zeros_leg, zeros_leg, plat_f[:, p], plat_m[:, p]))
                continue
            force, moment = zeros_leg.copy(), zeros_leg.copy()
            legs_of = slice(None) if i is None else slice(i, i + 1)
            force[:, legs_of, k] = leg_f[:, legs_of, k, p]
            moment[:, legs_of, k] = leg_m[:, legs_of, k, p]
            columns.append(efforts(force, moment, zeros_platform, zeros_platform))
    return np.stack(columns, axis=-1)


def spatial_regressor(
    robot: SpatialRobot, motion: PlatformMotion, *, per_leg: bool = False
) -> SpatialRegressor:
    """The regressor ``Y (N, legs, P)`` of the actuator efforts of ``robot`` along ``motion``.

    ``Y @ spatial_standard_parameters(robot)`` equals
    ``spatial_inverse_dynamics(robot, motion).tau`` to round-off (module docstring).

    Parameters
    ----------
    robot : SpatialRobot
        Its geometry and gravity are used (its inertial parameters not).
    motion : PlatformMotion
        ``N`` samples, complete (a robot of fewer than 6 DOF:
        :func:`~prp3.spatial.kinematics.complete_motion` first).
    per_leg : bool
        Every leg's bodies their own parameters (default: shared by the legs).

    Raises
    ------
    ParameterError
        A bad ``robot`` or ``per_leg``.
    UnreachablePoseError, SingularPoseError
        As :func:`~prp3.spatial.kinematics.spatial_kinematics`.
    """
    robot = _check_robot(robot)
    check_instance("motion", motion, PlatformMotion, "a prp3 PlatformMotion")
    names = spatial_parameter_names(robot, per_leg=per_leg)
    n = len(motion)
    tau = np.empty((n, len(robot.legs), len(names)))
    for start in range(0, n, CHUNK):
        stop = min(start + CHUNK, n)
        tau[start:stop] = _chunk_columns(robot, motion.chunk(start, stop), start, per_leg)
    return SpatialRegressor(names, tau)


#: The pose coordinate each twist component drives (x, y, z of p; roll, pitch, yaw).
_COORDINATE = {"vx": 0, "vy": 1, "vz": 2, "wx": 3, "wy": 4, "wz": 5}


def _driven(robot: SpatialRobot) -> list[int]:
    """The pose coordinates (x, y, z, roll, pitch, yaw) a motion of ``robot`` may drive."""
    return sorted(_COORDINATE[c] for c in TWIST_COMPONENTS if c not in robot.parasitic)


def _pose_motion(
    robot: SpatialRobot, t: FloatArray, q: FloatArray, dq: FloatArray, ddq: FloatArray
) -> PlatformMotion:
    """The completed motion of offsets ``q (N, 6)`` (x, y, z, roll, pitch, yaw) from home."""
    home = np.asarray(robot.home_rotation)
    omega, alpha = rpy_rates(q[:, 3:], dq[:, 3:], ddq[:, 3:])
    motion = PlatformMotion.of(
        t,
        np.asarray(robot.home_position) + q[:, :3],
        home @ rpy_matrix(q[:, 3:]),
        omega @ home.T,
        dq[:, :3],
        alpha @ home.T,
        ddq[:, :3],
    )
    return complete_motion(robot, motion)


def spatial_random_motion(robot: SpatialRobot, samples: int, seed: int) -> PlatformMotion:
    """Random regular states about ``robot``'s home pose (exciting every parameter), completed.

    Offsets within ``0.05·scale`` of the home position and ``0.1`` rad of its
    orientation in the components the robot drives, rates of ``scale`` per s and
    1 rad/s, accelerations three times larger; the amplitude halved (up to 10
    times) until every state is reachable and regular.

    Raises
    ------
    ParameterError
        No such motion (home is close to a singularity or to a limit).
    """
    robot = _check_robot(robot)
    samples = check_integer("samples", samples, 1, 10**7)
    rng = np.random.default_rng(check_integer("seed", seed, 0, 2**63 - 1))
    mask = np.zeros(6)
    mask[_driven(robot)] = 1.0
    size = np.array([robot.scale] * 3 + [1.0] * 3) * mask
    unit = rng.uniform(-1.0, 1.0, (samples, 6))
    rate = rng.normal(size=(samples, 6)) * size
    second = rng.normal(size=(samples, 6)) * 3.0 * size
    amplitude = np.array([0.05 * robot.scale] * 3 + [0.1] * 3) * mask
    t = np.arange(samples, dtype=np.float64)
    for _ in range(10):
        try:
            motion = _pose_motion(robot, t, unit * amplitude, rate, second)
            spatial_kinematics(robot, motion)
        except Prp3Error:
            amplitude = amplitude / 2.0
            continue
        return motion
    raise ParameterError(
        f"no regular random motion about the home pose {list(robot.home_position)} of the "
        f"{robot.name} (close to a singularity or a limit)"
    )


def spatial_base_parameters(
    robot: SpatialRobot, *, per_leg: bool = False, samples: int = 60, seed: int = 0
) -> BaseParameters:
    """The base parameters of ``robot``'s geometry: :func:`~prp3.apps.base_parameters.base_parameters_of`
    the regressor on :func:`spatial_random_motion` (``samples`` states, ``seed``).

    >>> from prp3.spatial.model import hexapod
    >>> base = spatial_base_parameters(hexapod())
    >>> base.count, base.unidentifiable
    (22, ('cylinder_mass',))
    """
    robot = _check_robot(robot)
    Y = spatial_regressor(robot, spatial_random_motion(robot, samples, seed), per_leg=per_leg)
    return base_parameters_of(
        Y.tau.reshape(-1, len(Y.parameters)), Y.parameters, SPATIAL_FORCES, plain=True
    )


def spatial_identify(
    robot: SpatialRobot,
    motion: PlatformMotion,
    tau: FloatArray,
    *,
    per_leg: bool = False,
    where: str = "measurements",
) -> Identification:
    """The base parameters of ``robot`` from measured actuator efforts ``tau (N, legs)``.

    As :func:`prp3.apps.identification.identify` (the same refusals: too few
    samples, a motion that does not excite a base parameter; the same two-pass
    weighted least squares): the base regressor is the columns of
    :func:`spatial_regressor` that name the base parameters of
    :func:`spatial_base_parameters`.  ``fixed`` is empty (every inertial
    parameter enters; the spatial robots have no friction or load).

    Raises
    ------
    TrajectoryError
        ``tau`` not of shape ``(N, legs)`` or not finite, too few samples, or a motion
        that does not excite the base parameters (naming ``where``).
    UnreachablePoseError, SingularPoseError
        As :func:`spatial_regressor`.

    Examples
    --------
    >>> from prp3.spatial.model import three_rps
    >>> from prp3.spatial.outputs import spatial_inverse_dynamics
    >>> robot = three_rps()
    >>> motion = spatial_random_motion(robot, 200, seed=3)
    >>> result = spatial_identify(robot, motion, spatial_inverse_dynamics(robot, motion).tau)
    >>> true = result.base.values(spatial_standard_parameters(robot))
    >>> bool(np.allclose(result.estimate, true, rtol=1e-8, atol=1e-12))
    True
    """
    robot = _check_robot(robot)
    check_instance("motion", motion, PlatformMotion, "a prp3 PlatformMotion")
    legs = len(robot.legs)
    measured = check_real("tau", tau, TrajectoryError)
    if measured.shape != (len(motion), legs):
        raise TrajectoryError(
            f"{where}: tau must be an array of shape ({len(motion)}, {legs}) to match the "
            f"motion and the legs, got {measured.shape}"
        )
    if not np.isfinite(measured).all():
        k, i = (int(v) for v in np.argwhere(~np.isfinite(measured))[0])
        raise TrajectoryError(
            f"{where}: tau_{i + 1} is not finite ({float(measured[k, i])!r})",
            sample=k,
            key=f"tau_{i + 1}",
        )
    if not isinstance(where, str):
        raise ParameterError(f"where must be a string, got {where!r}"[:200], key="where")
    per_leg = _check_flag(per_leg)
    base = spatial_base_parameters(robot, per_leg=per_leg)
    check_samples(base, len(motion), where)
    W = spatial_regressor(robot, motion, per_leg=per_leg).tau[..., list(base.independent)]
    try:
        return fit_base_parameters(base, W, measured, motion.t, where)
    except ParameterError as error:
        if error.key != "measured":
            raise
        k, i = (int(v) for v in np.unravel_index(np.argmax(np.abs(measured)), measured.shape))
        raise TrajectoryError(
            f"{where}: the least squares overflow double precision: tau_{i + 1} = "
            f"{float(measured[k, i])!r} is far beyond the efforts of the robot",
            sample=k,
            key=f"tau_{i + 1}",
        ) from None


def _body_of(name: str, values: FloatArray, default: Body) -> Body:
    """The body of ten standard parameters (mass, first moment, inertia about the origin)."""
    m = float(values[0])
    h = values[1:4]
    J = np.zeros((3, 3))
    for (i, j), v in zip(_INERTIA_INDEX.values(), values[4:], strict=True):
        J[i, j] = J[j, i] = v
    if not m > 0.0:
        if m == 0.0 and not h.any():
            return Body(0.0, (0.0, 0.0, 0.0), (tuple(J[0]), tuple(J[1]), tuple(J[2])), default.name)
        raise ParameterError(
            f"the identified {name} mass {m:.6g} kg is not positive: no body has these parameters",
            key=name,
        )
    c = h / m
    inertia = J - m * (float(c @ c) * np.eye(3) - np.outer(c, c))
    inertia = 0.5 * (inertia + inertia.T)
    moments, axes = np.linalg.eigh(inertia)
    scale = max(float(np.abs(moments).max()), 1e-300)
    a, b, top = (float(v) for v in moments)
    if -1e-9 * scale <= a < 0.0 or 0.0 < top - a - b <= 1e-9 * scale:  # round-off of a limit
        moments = np.array([max(a, 0.0), b, min(top, max(a, 0.0) + b)])
        inertia = axes @ np.diag(moments) @ axes.T
        inertia = 0.5 * (inertia + inertia.T)
    try:
        return Body(
            m, tuple(c), (tuple(inertia[0]), tuple(inertia[1]), tuple(inertia[2])), default.name
        )
    except ParameterError as error:
        raise ParameterError(
            f"the identified {name} parameters are not those of a body ({error.reason})",
            key=name,
        ) from None


def spatial_identified_robot(design: SpatialRobotFile, result: Identification) -> SpatialRobotFile:
    """The robot file of ``design`` with bodies that reproduce ``result``'s base parameters.

    The standard parameter naming each base parameter is solved from it, every
    other standard parameter kept at ``design``'s value (shared parameters:
    ``result`` of ``per_leg=False``); each body is rebuilt from its ten
    parameters (``c = h/m``, ``I = J − m·(|c|²·1 − c·cᵀ)``; principal moments
    within ``1e-9`` (relative) of a body's bounds — a flat plate's ``I_z = I_x + I_y``
    identified with round-off — are moved onto them).

    Raises
    ------
    ParameterError
        ``result`` not of this robot's shared parameters, or a body whose identified
        parameters are not physical (a mass ≤ 0, an inertia not of a body): names it.
    """
    check_instance("design", design, SpatialRobotFile, "a prp3 SpatialRobotFile")
    check_instance("result", result, Identification, "a prp3 Identification")
    robot = design.robot
    names = spatial_parameter_names(robot)
    if result.base.parameters != names:
        raise ParameterError(
            f"result is not of the {robot.name}'s shared standard parameters "
            f"({len(result.base.parameters)} parameters, expected {len(names)})",
            key="result",
        )
    nominal = spatial_standard_parameters(robot)
    combination = result.base.combination
    solved = nominal.copy()
    for b, j in enumerate(result.base.independent):
        others = combination[b] @ nominal - nominal[j]
        solved[j] = float(result.estimate[b]) - others
    data: dict[str, Any] = tomllib.loads(spatial_robot_text(design, comments=False))
    tables = [key for key, value in data.items() if isinstance(value, dict)]  # leg bodies, platform
    size = len(BODY_PARAMETERS)
    prefixes = (*spatial_body_names(robot), "platform")
    defaults = (*robot.legs[0].bodies, robot.platform)
    for table, prefix, default in zip(tables, prefixes, defaults, strict=True):
        start = names.index(f"{prefix}_mass")
        body = _body_of(prefix, solved[start : start + size], default)
        data[table] = {
            "mass": body.mass,
            "centre": list(body.centre),
            "inertia": [list(row) for row in body.inertia],
        }
    return spatial_robot_from_mapping(data)


@dataclass(frozen=True)
class SpatialExcitation:
    """The result of :func:`spatial_exciting_trajectory`.

    Attributes
    ----------
    motion : PlatformMotion
        The completed motion at the ``samples`` times over one period.
    condition : float
        Condition number of the base regressor's unit columns on it.
    candidates : int
        The random series tried; ``seed`` the seed of the one kept.
    peak_q, peak_dq, peak_tau : float
        Peaks of the actuated joints' value, rate and effort (nominal robot).
    """

    motion: PlatformMotion
    condition: float
    candidates: int
    seed: int
    peak_q: float
    peak_dq: float
    peak_tau: float


def _fourier(
    coefficients: tuple[FloatArray, FloatArray], period: float, t: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The finite Fourier series ``q_j(t) = Σ_l a_jl sin(lωt) + b_jl (1 − cos(lωt))`` (``q = 0``
    at ``t = 0``, periodic) and its first two derivatives, ``(N, 6)`` each."""
    a, b = coefficients
    l = np.arange(1, a.shape[1] + 1) * (2.0 * math.pi / period)  # noqa: E741
    s, c = np.sin(np.outer(t, l)), np.cos(np.outer(t, l))
    return (
        s @ a.T + (1.0 - c) @ b.T,
        (c * l) @ a.T + (s * l) @ b.T,
        (-s * l * l) @ a.T + (c * l * l) @ b.T,
    )


def spatial_exciting_trajectory(
    robot: SpatialRobot,
    *,
    period: float = 5.0,
    harmonics: int = 4,
    samples: int = 1001,
    reach: float = 0.2,
    rotation: float = 0.2,
    max_velocity: float | None = None,
    max_force: float | None = None,
    candidates: int = 10,
    seed: int = 0,
) -> SpatialExcitation:
    """An exciting periodic platform motion for the identification of ``robot``.

    ``candidates`` random finite Fourier series (:func:`numpy.random.default_rng`
    of ``[seed, k]``) of ``harmonics`` harmonics and period ``period`` (s) of
    the pose coordinates the robot drives (offsets from home: ``x, y, z``
    peaking at ``reach·scale``, roll, pitch, yaw at ``rotation`` rad; the
    parasitic ones completed, :func:`~prp3.spatial.kinematics.complete_motion`).
    A series that leaves the reach or the joints' limits, nears a singularity,
    or exceeds ``max_velocity`` (the actuated joints' ``|dq|``, m/s or rad/s)
    or ``max_force`` (``|τ|`` of the nominal robot) is shrunk (×0.7, up to 12
    times); of those that pass (checked on 201 of the times), the one kept has
    the lowest condition number of the base regressor's unit columns, is
    checked again on all ``samples`` times (shrunk further if it must) and
    passes :func:`prp3.apps.identification.excitation_refusal`, the criterion
    of :func:`spatial_identify`.

    Raises
    ------
    ParameterError
        Bad arguments, or no series within the limits excites every base parameter.
    """
    robot = _check_robot(robot)
    period = check_scalar("period", period, positive=True, unit="s")
    harmonics = check_integer("harmonics", harmonics, 1, 20)
    samples = check_integer("samples", samples, 2, 10**7)
    reach = check_scalar("reach", reach, positive=True)
    rotation = check_scalar("rotation", rotation, positive=True, unit="rad")
    if max_velocity is not None:
        max_velocity = check_scalar("max_velocity", max_velocity, positive=True)
    if max_force is not None:
        max_force = check_scalar("max_force", max_force, positive=True)
    candidates = check_integer("candidates", candidates, 1, 10_000)
    seed = check_integer("seed", seed, 0, 2**63 - 1)
    check = _SeriesCheck(robot, spatial_base_parameters(robot), period, max_velocity, max_force)
    mask = np.zeros(6)
    mask[_driven(robot)] = 1.0
    amplitude = np.array([reach * robot.scale] * 3 + [rotation] * 3) * mask
    why = "every series left the reach or the limits"
    coarse = np.linspace(0.0, period, min(samples, 201))
    best: tuple[float, int, tuple[FloatArray, FloatArray]] | None = None
    for k in range(candidates):
        found, coefficients = _first_passing(
            check, _random_series(seed, k, harmonics, amplitude, period), coarse
        )
        if isinstance(found, str):
            why = found
        elif best is None or found[1] < best[0]:
            best = (found[1], k, coefficients)
    if best is not None:
        _, k, coefficients = best
        final, _ = _first_passing(check, coefficients, np.linspace(0.0, period, samples))
        if not isinstance(final, str):
            motion, condition, peak_q, peak_dq, peak_tau = final
            return SpatialExcitation(motion, condition, candidates, k, peak_q, peak_dq, peak_tau)
        why = final
    raise ParameterError(
        f"no exciting motion of the {robot.name} within the limits in {candidates} random "
        f"series: {why}"[:400]
    )


_Series = tuple[FloatArray, FloatArray]
_Passed = tuple[PlatformMotion, float, float, float, float]


@dataclass(frozen=True)
class _SeriesCheck:
    """Whether a Fourier series of :func:`spatial_exciting_trajectory` passes its limits."""

    robot: SpatialRobot
    base: BaseParameters
    period: float
    max_velocity: float | None
    max_force: float | None

    def __call__(self, coefficients: _Series, t: FloatArray) -> _Passed | str:
        """The motion, its condition number and peaks; or why it is refused."""
        robot, base, a = self.robot, self.base, self.robot.legs[0].actuated_coordinate
        try:
            with np.errstate(all="ignore"):
                motion = _pose_motion(robot, t, *_fourier(coefficients, self.period, t))
                kin = spatial_kinematics(robot, motion)
                tau = virtual_work_efforts(robot, motion)
        except Prp3Error as error:
            return error.reason
        peak_dq, peak_tau = float(np.abs(kin.dq[..., a]).max()), float(np.abs(tau).max())
        if self.max_velocity is not None and peak_dq > self.max_velocity:
            return f"the actuated joints' |dq| {peak_dq:.4g} > max_velocity {self.max_velocity:g}"
        if self.max_force is not None and peak_tau > self.max_force:
            return f"|tau| {peak_tau:.4g} > max_force {self.max_force:g}"
        columns = list(base.independent)
        stacked = spatial_regressor(robot, motion).tau[..., columns].reshape(-1, base.count)
        refused = excitation_refusal(base, stacked)
        if refused is not None:
            return refused
        condition = float(np.linalg.cond(stacked / np.linalg.norm(stacked, axis=0)))
        return motion, condition, float(np.abs(kin.q[..., a]).max()), peak_dq, peak_tau


def _random_series(
    seed: int, k: int, harmonics: int, amplitude: FloatArray, period: float
) -> _Series:
    """Random series ``k`` (:func:`numpy.random.default_rng` of ``[seed, k]``), scaled to peak
    at ``amplitude`` in each coordinate."""
    rng = np.random.default_rng([seed, k])
    weights = 1.0 / np.arange(1, harmonics + 1)
    a = rng.normal(size=(6, harmonics)) * weights
    b = rng.normal(size=(6, harmonics)) * weights
    peak = np.abs(_fourier((a, b), period, np.linspace(0.0, period, 401))[0]).max(axis=0)
    factor = (amplitude / np.where(peak > 0.0, peak, 1.0))[:, None]
    return a * factor, b * factor


def _first_passing(
    check: _SeriesCheck, coefficients: _Series, t: FloatArray
) -> tuple[_Passed | str, _Series]:
    """The series shrunk (×0.7, up to 12 times) until it passes ``check`` on ``t``: what
    passes and its coefficients, or the last refusal."""
    for _ in range(12):
        found = check(coefficients, t)
        if not isinstance(found, str):
            return found, coefficients
        coefficients = (0.7 * coefficients[0], 0.7 * coefficients[1])
    return found, coefficients
