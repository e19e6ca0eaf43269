"""The regressor of the joint forces: ``f = Y·π``, column by column from the kernel.

The joint forces of the kernel (:mod:`prp3.mechanics.kernel`, eqs. 19–25) are linear and
homogeneous in the standard inertial parameters ``π`` of
:class:`~prp3.mechanics.parameters.KernelParameters` (for a fixed ``l0`` and gravity):
gravity multiplies the masses and first moments only, every inertia wrench
(eq. 22) is a parameter times a kinematic quantity, and the virtual work
(eqs. 23–25) is linear in the wrenches.  So, for any motion,

``f10 = Y(q, q̇, q̈)·π``  (and likewise ``f21y``, ``f21z``),

and column ``k`` of the regressor ``Y`` is exactly the kernel evaluated with
``π_k = 1`` and every other inertial parameter 0.  :func:`regressor` builds it
that way, from the one source: the geometry and kinematics of a chunk of
samples once (eqs. 10, 14, 17), then :func:`~prp3.mechanics.wrenches.body_wrenches` and
:func:`~prp3.mechanics.virtual_work.joint_forces` once per parameter.  (The symbolic route —
``sympy`` derivatives of :func:`~prp3.mechanics.kernel.symbolic_solution` — gives the
same columns, but expressions of thousands of operations per column; the
numeric one is exact to round-off because the forces are linear, and runs on
the batch path.)  :func:`known_forces` is the part of the forces that is not
estimated (fixed parameters, loads); the parameters' names, symbols and units
are here too.  The base parameters are :mod:`prp3.apps.base_parameters`, the
fit :mod:`prp3.apps.identification`; ``docs/identification.md`` works through
all of it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from prp3.engines.entries import DEFAULT_CHUNK, MAX_CHUNK
from prp3.errors import ParameterError, TrajectoryError
from prp3.mechanics.geometry import inverse_geometry
from prp3.mechanics.joint_motion import (
    KernelKinematics,
    kernel_geometry,
    kernel_kinematics,
    rate_floor,
    rest_kinematics,
)
from prp3.mechanics.ops import NUMPY, Legs
from prp3.mechanics.parameters import EFFECT_FIELDS, KernelParameters, kernel_parameters
from prp3.mechanics.virtual_work import joint_forces
from prp3.mechanics.wrenches import body_wrenches, friction_forces
from prp3.model.elements import ELEMENTS, FRICTIONS, LOAD
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.validation import check_instance, check_integer, check_names, check_robot

__all__ = [
    "ELEMENT_PARAMETERS",
    "FORCES",
    "FRICTION_PARAMETERS",
    "PARAMETERS",
    "PARAMETER_SYMBOLS",
    "PARAMETER_UNITS",
    "STANDARD_PARAMETERS",
    "Regressor",
    "known_forces",
    "regressor",
    "standard_parameters",
]

FloatArray = NDArray[np.float64]

#: The standard inertial parameters (fields of :class:`~prp3.mechanics.parameters.KernelParameters`),
#: in the order of preference in which they name a base parameter: the platform's
#: first, then the legs'.
STANDARD_PARAMETERS: tuple[str, ...] = (
    "platform_mass",
    "platform_moment_x",
    "platform_moment_y",
    "platform_inertia",
    "piston_mass",
    "link_mass",
    "link_moment_x",
    "link_moment_y",
    "link_inertia",
    "piston_moment_x",
    "piston_moment_y",
)

#: Friction coefficients that enter the forces linearly (``docs/loads_and_friction.md``):
#: viscous ``b`` and Coulomb ``c`` of the guides, the revolute joints and the sleeves, the
#: regressor fields of the friction elements.  (The load-dependent ``μ`` terms multiply
#: reaction magnitudes that depend on every parameter: they are not linear in anything and
#: have no column.)
FRICTION_PARAMETERS: tuple[str, ...] = tuple(n for e in FRICTIONS for n in e.regressor)

#: The regressor fields of every element (:attr:`prp3.model.element_base.Element.regressor`):
#: the friction coefficients, the spring's stiffness and damping.
ELEMENT_PARAMETERS: tuple[str, ...] = tuple(n for e in ELEMENTS for n in e.regressor)

#: Every parameter a regressor column can stand for.
PARAMETERS: tuple[str, ...] = STANDARD_PARAMETERS + ELEMENT_PARAMETERS

#: Short symbols of the standard parameters (docs/identification.md).
PARAMETER_SYMBOLS: dict[str, str] = {
    "platform_mass": "m3",
    "platform_moment_x": "h3x",
    "platform_moment_y": "h3y",
    "platform_inertia": "J3",
    "piston_mass": "m1",
    "link_mass": "m2",
    "link_moment_x": "h2x",
    "link_moment_y": "h2y",
    "link_inertia": "J2",
    "piston_moment_x": "h1x",
    "piston_moment_y": "h1y",
    **{name: symbol for e in ELEMENTS for name, symbol in e.symbols},
}

#: SI units of the standard parameters.
PARAMETER_UNITS: dict[str, str] = {
    "platform_mass": "kg",
    "platform_moment_x": "kg m",
    "platform_moment_y": "kg m",
    "platform_inertia": "kg m^2",
    "piston_mass": "kg",
    "link_mass": "kg",
    "link_moment_x": "kg m",
    "link_moment_y": "kg m",
    "link_inertia": "kg m^2",
    "piston_moment_x": "kg m",
    "piston_moment_y": "kg m",
    **{name: unit for e in ELEMENTS for name, unit in e.units},
}

#: Force outputs a regressor can be built for.
FORCES: tuple[str, ...] = ("f10", "f21y", "f21z")


def standard_parameters(
    robot: Robot, parameters: Sequence[str] = STANDARD_PARAMETERS
) -> FloatArray:
    """The standard parameters ``π`` of ``robot`` (:func:`prp3.mechanics.parameters.kernel_parameters`).

    >>> standard_parameters(Robot(), ("piston_mass", "link_inertia")).tolist()
    [1.0, 0.000625]
    """
    k = kernel_parameters(check_robot(robot))
    return np.array([float(getattr(k, name)) for name in check_parameter_names(parameters)])


def check_parameter_names(parameters: Sequence[str], name: str = "parameters") -> tuple[str, ...]:
    return check_names(name, parameters, PARAMETERS, item="parameter")


@dataclass(frozen=True)
class Regressor:
    """The regressor of a motion: ``f = Y·π`` for each force.

    Attributes
    ----------
    parameters : tuple of str
        The standard parameters of the columns (:data:`STANDARD_PARAMETERS` names).
    f10, f21y, f21z : ndarray, shape (N, 3, P) or (3, P)
        ``Y`` of the actuator forces and of the joint forces (legs A, B, C on
        the middle axis, one column per parameter; N, m, m/s²·... so that
        ``Y @ π`` is in newtons).
    lambda10, dlambda10 : ndarray, shape (N, 3) or (3,)
        The actuator displacements and velocities of the motion (m, m/s).
    """

    parameters: tuple[str, ...]
    f10: FloatArray
    f21y: FloatArray
    f21z: FloatArray
    lambda10: FloatArray
    dlambda10: FloatArray


def _zero_parameters(robot: Robot, keep: Sequence[str] = ()) -> KernelParameters:
    """``robot``'s kernel parameters with every inertial field and element field 0.

    Kept: ``l0``, gravity, the fields each element keeps for the shape of its
    columns (:attr:`prp3.model.element_base.Element.kept`: the friction smoothings, a
    Coulomb column is ``s(v)`` with the robot's smoothing; the spring's rest
    length) and the fields named in ``keep``.
    """
    k = kernel_parameters(robot)
    shape = {name for element in ELEMENTS for name in element.kept}
    cleared = [
        name
        for name in (*STANDARD_PARAMETERS, *EFFECT_FIELDS)
        if name not in shape and name not in keep
    ]
    return replace(k, **dict.fromkeys(cleared, 0.0))


def unit_parameters(robot: Robot, names: Sequence[str]) -> list[KernelParameters]:
    """One :class:`KernelParameters` per name: that parameter 1, every other one 0."""
    zero = _zero_parameters(robot)
    return [replace(zero, **{name: 1.0}) for name in names]


def _forces(
    k: KernelParameters,
    kin: KernelKinematics,
    rows: FloatArray,
    load: FloatArray | None = None,
) -> tuple[Legs, Legs, Legs]:
    """``f10, f21y, f21z`` of the kernel for ``k`` (no ``μ`` terms), wrenches to virtual work."""
    ddx, ddy, dphi, ddphi = rows[6], rows[7], rows[5], rows[8]
    floor = rate_floor(NUMPY, k, kin.geometry, rows[0], rows[1], rows[3], rows[4], dphi)
    friction = friction_forces(NUMPY, k, rest_kinematics(kin, floor), dphi)
    loads = None if load is None else (load[0], load[1], load[2])
    wrenches = body_wrenches(k, kin, ddx, ddy, dphi, ddphi, load=loads, friction=friction)
    f10, f21y, f21z, _ = joint_forces(k, kin, wrenches, reactions=False)
    return f10, f21y, f21z


def regressor_rows(
    units: Sequence[KernelParameters], rows: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Regressor of the states ``rows`` (9, n): ``(3 forces, n, 3, P)``, ``λ10``, ``λ̇10``."""
    kin = _kinematics(units[0], rows)  # l0 is the same in every unit parameter set
    out = np.empty((3, rows.shape[1], 3, len(units)))
    for column, unit in enumerate(units):
        for f, legs in enumerate(_forces(unit, kin, rows)):
            for leg in range(3):
                out[f, :, leg, column] = legs[leg]
    return out, np.stack(kin.geometry.lambda10, axis=-1), np.stack(kin.dlambda10, axis=-1)


def _kinematics(k: KernelParameters, rows: FloatArray) -> KernelKinematics:
    """Joint displacements and rates of the states ``rows`` (eqs. 10, 14, 17)."""
    x, y, phi, dx, dy, dphi, ddx, ddy, ddphi = rows
    geo = kernel_geometry(NUMPY, k, x, y, phi)
    return kernel_kinematics(k, geo, dx, dy, dphi, ddx, ddy, ddphi)


def state_rows(motion: Motion) -> FloatArray:
    """The states of a motion as rows ``(9, N)``: x, y, φ, their rates, their accelerations."""
    return np.concatenate(
        [
            motion.pose.reshape(-1, 3).T,
            motion.velocity.reshape(-1, 3).T,
            motion.acceleration.reshape(-1, 3).T,
        ]
    )


def _chunked_rows(
    units: Sequence[KernelParameters],
    rows: FloatArray,
    width: int,
    progress: Callable[[int, int], None] | None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """:func:`regressor_rows` of the states ``rows`` (9, N) in chunks of ``width`` samples
    (``progress`` after each): ``(3 forces, N, 3, P)``, ``λ10`` and ``λ̇10`` ``(N, 3)``."""
    samples = rows.shape[1]
    width = max(1, min(width, samples))
    forces = np.empty((3, samples, 3, len(units)))
    lambda10 = np.empty((samples, 3))
    dlambda10 = np.empty((samples, 3))
    for start in range(0, samples, width):
        stop = min(start + width, samples)
        block, lam, dlam = regressor_rows(units, rows[:, start:stop])
        forces[:, start:stop] = block
        lambda10[start:stop] = lam
        dlambda10[start:stop] = dlam
        if progress is not None:
            progress(stop, samples)
    return forces, lambda10, dlambda10


def regressor(
    robot: Robot,
    motion: Motion,
    parameters: Sequence[str] = STANDARD_PARAMETERS,
    *,
    chunk_size: int = DEFAULT_CHUNK,
    progress: Callable[[int, int], None] | None = None,
) -> Regressor:
    """The regressor ``Y`` of ``f10``, ``f21y``, ``f21z`` for a motion (batch or one sample).

    Column ``k`` is the kernel (eqs. 10, 14, 17, 19–25) evaluated with the
    parameter ``parameters[k]`` set to 1 and every other inertial and
    element parameter 0 (``l0``, gravity and the fields the elements keep —
    the friction smoothings, the spring's rest length — from ``robot``): the
    forces are linear and homogeneous in the inertial parameters and in the
    regressor fields of the elements (viscous and Coulomb friction
    coefficients, the spring's stiffness and damping), so
    ``Y @ standard_parameters(robot, PARAMETERS)`` equals the forces of
    :func:`prp3.analysis.inverse_dynamics.inverse_dynamics` to round-off for a robot without
    load and ``μ`` terms (a load adds a known term, :func:`known_forces`).

    Parameters
    ----------
    robot : Robot
        Only ``l0``, gravity and ``limits.stroke`` (checked) are used.
    motion : Motion
        ``N`` samples, or a single one (then the outputs lose the leading axis).
    parameters : sequence of str
        The columns, from :data:`PARAMETERS` (default: the inertial ones,
        :data:`STANDARD_PARAMETERS`, in that order).
    chunk_size : int
        Samples per chunk (memory bounded for any ``N``), an integer from 1 to
        :data:`~prp3.engines.entries.MAX_CHUNK`.
    progress : callable, optional
        ``progress(samples_done, N)`` after every chunk.

    Raises
    ------
    ParameterError
        A bad ``robot``, ``parameters``, ``chunk_size`` or ``progress``.
    SingularPoseError, UnreachablePoseError
        A pose at a singularity or outside ``robot.limits.stroke``.

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> from prp3.analysis.inverse_dynamics import inverse_dynamics
    >>> robot, motion = Robot(), paper_motion("rotation", samples=31)
    >>> Y = regressor(robot, motion)
    >>> Y.f10.shape
    (31, 3, 11)
    >>> forces = inverse_dynamics(robot, motion)[1].f10
    >>> bool(np.allclose(Y.f10 @ standard_parameters(robot), forces, rtol=1e-13, atol=0))
    True
    """
    check_robot(robot)
    names = check_parameter_names(parameters)
    if not isinstance(motion, Motion):
        raise TrajectoryError(f"motion must be a prp3.Motion, got {type(motion).__name__}")
    width = check_integer("chunk_size", chunk_size, 1, MAX_CHUNK)
    if progress is not None and not callable(progress):
        raise ParameterError(
            f"progress must be a callable progress(done, total) or None, got {progress!r}",
            key="progress",
        )
    inverse_geometry(robot, motion.pose)  # refuses singular and unreachable poses
    units = unit_parameters(robot, names)
    forces, lambda10, dlambda10 = _chunked_rows(units, state_rows(motion), width, progress)
    shape = motion.pose.shape[:-1]
    return Regressor(
        parameters=names,
        f10=forces[0].reshape(*shape, 3, len(names)),
        f21y=forces[1].reshape(*shape, 3, len(names)),
        f21z=forces[2].reshape(*shape, 3, len(names)),
        lambda10=lambda10.reshape(*shape, 3),
        dlambda10=dlambda10.reshape(*shape, 3),
    )


def refuse_mu(robot: Robot) -> None:
    """The load-dependent ``μ`` friction terms are not linear: refuse a robot with them."""
    if kernel_parameters(robot).has_mu:
        raise ParameterError(
            "the robot has load-dependent friction (a friction mu > 0): its forces are not "
            "linear in the parameters, so it cannot be identified by least squares; set the "
            "mu terms of the nominal robot to 0"
        )


def known_forces(robot: Robot, motion: Motion, fixed: Sequence[str]) -> FloatArray:
    """The actuator forces of what is not estimated: the parameters ``fixed`` and the loads.

    The kernel with the ``fixed`` parameters at ``robot``'s values, every
    other inertial and friction parameter 0, and the robot's constant
    ``[load]`` plus the motion's time-varying load: the part of ``f10`` that
    least squares subtracts from the measurements.  Shape ``(N, 3)``.

    >>> from prp3.model.motion import paper_motion
    >>> known_forces(Robot(), paper_motion("vertical", samples=3), ()).tolist()
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """
    check_robot(robot)
    check_instance("motion", motion, Motion, "a prp3.Motion")
    refuse_mu(robot)
    names = check_names("fixed", fixed, PARAMETERS, item="parameter", empty=True)
    inverse_geometry(robot, motion.pose)
    k = _zero_parameters(robot, keep=(*names, *LOAD.fields))
    rows = state_rows(motion)
    load = None if motion.load is None else motion.load.reshape(-1, 3).T
    out = np.empty((rows.shape[1], 3))
    width = DEFAULT_CHUNK
    for start in range(0, rows.shape[1], width):
        stop = min(start + width, rows.shape[1])
        chunk = rows[:, start:stop]
        part = None if load is None else load[:, start:stop]
        f10 = _forces(k, _kinematics(k, chunk), chunk, part)[0]
        for leg in range(3):
            out[start:stop, leg] = f10[leg]
    return out.reshape(*motion.pose.shape[:-1], 3)
