"""Identification of the dynamic parameters: regressor, base parameters, least squares.

The joint forces of the kernel (:mod:`prp3.mechanics.kernel`, eqs. 19–25) are linear and
homogeneous in the standard inertial parameters ``π`` of
:class:`~prp3.mechanics.kernel.KernelParameters` (for a fixed ``l0`` and gravity):
gravity multiplies the masses and first moments only, every inertia wrench
(eq. 22) is a parameter times a kinematic quantity, and the virtual work
(eqs. 23–25) is linear in the wrenches.  So, for any motion,

``f10 = Y(q, q̇, q̈)·π``  (and likewise ``f21y``, ``f21z``),

and column ``k`` of the regressor ``Y`` is exactly the kernel evaluated with
``π_k = 1`` and every other inertial parameter 0.  :func:`regressor` builds it
that way, from the one source: the geometry and kinematics of a chunk of
samples once (eqs. 10, 14, 17), then :func:`~prp3.mechanics.kernel.body_wrenches` and
:func:`~prp3.mechanics.kernel.joint_forces` once per parameter.  (The symbolic route —
``sympy`` derivatives of :func:`~prp3.mechanics.kernel.symbolic_solution` — gives the
same columns, but expressions of thousands of operations per column; the
numeric one is exact to round-off because the forces are linear, and runs on
the batch path.)

:func:`base_parameters` finds the identifiable combinations numerically: the
regressor of random exciting samples, its columns scaled to unit norm, taken
in a fixed order of preference; a column that adds nothing to the rank (its
residual after projection on the kept columns is below ``1e-8``) is
dependent, and least squares on the kept columns gives the combination it
enters.  A column that is zero on every sample is unidentifiable.

With ``f10`` alone (the actuator forces, what a user measures), 7 base
parameters of the 11 standard ones are identifiable for the robot of any size:

>>> from prp3.model.robot import Robot
>>> base = base_parameters(Robot())
>>> base.labels
('m3', 'h3x', 'h3y', 'J3 + 3·J2', 'm1 + m2', 'h2x', 'h2y')
>>> base.unidentifiable
('piston_moment_x', 'piston_moment_y')
>>> base_parameters(Robot(), forces=("f10", "f21y", "f21z")).labels
('m3', 'h3x', 'h3y', 'J3 + 3·J2', 'm1', 'm2', 'h2x', 'h2y')

:func:`identify` fits the base parameters to measured actuator forces by
weighted least squares (each actuator weighted by the standard deviation of
its residual in a first, unweighted pass) and :func:`identified_robot` turns
the estimate into a :class:`~prp3.model.robot.Robot`.  :func:`exciting_trajectory`
designs a motion (a finite Fourier series) that makes the regressor well
conditioned.  ``docs/identification.md`` works through all of it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.engines.entries import DEFAULT_CHUNK
from prp3.errors import ParameterError, TrajectoryError
from prp3.mechanics import kernel
from prp3.mechanics.geometry import inverse_geometry
from prp3.model.elements import ELEMENTS, FRICTIONS, LOAD
from prp3.model.motion import Motion
from prp3.model.robot import (
    Limits,
    LinkParameters,
    PistonParameters,
    PlatformParameters,
    Robot,
)
from prp3.validation import (
    check_instance,
    check_integer,
    check_names,
    check_per_leg,
    check_robot,
    check_scalar,
)

__all__ = [
    "ELEMENT_PARAMETERS",
    "FORCES",
    "FRICTION_MODELS",
    "FRICTION_PARAMETERS",
    "MIN_SAMPLES_PER_PARAMETER",
    "PARAMETERS",
    "PARAMETER_SYMBOLS",
    "PARAMETER_UNITS",
    "STANDARD_PARAMETERS",
    "BaseParameters",
    "ExcitingTrajectory",
    "FourierSeries",
    "Identification",
    "IdentifiedRobot",
    "Regressor",
    "base_parameters",
    "exciting_trajectory",
    "identified_robot",
    "identify",
    "known_forces",
    "regressor",
    "robot_from_standard",
    "standard_parameters",
    "weighted_least_squares",
]

FloatArray = NDArray[np.float64]

#: The standard inertial parameters (fields of :class:`~prp3.mechanics.kernel.KernelParameters`),
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

#: The regressor fields of every element (:attr:`prp3.model.elements.Element.regressor`):
#: the friction coefficients, the spring's stiffness and damping.
ELEMENT_PARAMETERS: tuple[str, ...] = tuple(n for e in ELEMENTS for n in e.regressor)

#: Every parameter a regressor column can stand for.
PARAMETERS: tuple[str, ...] = STANDARD_PARAMETERS + ELEMENT_PARAMETERS

#: The friction coefficients of each ``prp3 identify --friction`` choice.
FRICTION_MODELS: dict[str, tuple[str, ...]] = {
    "none": (),
    "viscous": tuple(e.regressor[0] for e in FRICTIONS),
    "coulomb": tuple(e.regressor[1] for e in FRICTIONS),
    "both": FRICTION_PARAMETERS,
}

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

#: Why a standard parameter cannot be identified on its own (structural reasons).
_REASONS: dict[str, str] = {
    "piston_moment_x": "the piston only translates along e_i: its first moment loads only "
    "the guide (n10, m10), never f10, f21y or f21z",
    "piston_moment_y": "the piston only translates along e_i: its first moment loads only "
    "the guide (n10, m10), never f10, f21y or f21z",
    "link_mass": "link 2's reference point P_i moves with the piston along e_i, so f10 sees "
    "only m1 + m2; the joint force f21z = f10 - m1 (lambda10'' - g.e_i) separates them",
    "link_inertia": "each link 2 turns with the platform (phi21 = phi, eq. 7) and its inertia "
    "about P_i enters only the sum of moments M2 (eq. 21) with the platform's; only the "
    "reaction moment m32 = -M20 would separate them",
}

#: Force outputs a regressor can be built for.
FORCES: tuple[str, ...] = ("f10", "f21y", "f21z")

#: Fewest samples (rows of a measurement file) per base parameter :func:`identify` accepts.
MIN_SAMPLES_PER_PARAMETER: int = 5

#: Relative residual below which a scaled regressor column adds nothing to the rank.
_RANK_TOLERANCE: float = 1e-8

#: Same, for a measured motion: below it a base parameter is not excited.
_EXCITATION_TOLERANCE: float = 1e-6


# ------------------------------------------------------------------ regressor
def standard_parameters(
    robot: Robot, parameters: Sequence[str] = STANDARD_PARAMETERS
) -> FloatArray:
    """The standard parameters ``π`` of ``robot`` (:func:`prp3.mechanics.kernel.kernel_parameters`).

    >>> standard_parameters(Robot(), ("piston_mass", "link_inertia")).tolist()
    [1.0, 0.000625]
    """
    k = kernel.kernel_parameters(check_robot(robot))
    return np.array([float(getattr(k, name)) for name in _check_names(parameters)])


def _check_names(parameters: Sequence[str], name: str = "parameters") -> tuple[str, ...]:
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


def _zero_parameters(robot: Robot, keep: Sequence[str] = ()) -> kernel.KernelParameters:
    """``robot``'s kernel parameters with every inertial field and element field 0.

    Kept: ``l0``, gravity, the fields each element keeps for the shape of its
    columns (:attr:`prp3.model.elements.Element.kept`: the friction smoothings, a
    Coulomb column is ``s(v)`` with the robot's smoothing; the spring's rest
    length) and the fields named in ``keep``.
    """
    k = kernel.kernel_parameters(robot)
    shape = {name for element in ELEMENTS for name in element.kept}
    cleared = [
        name
        for name in (*STANDARD_PARAMETERS, *kernel.EFFECT_FIELDS)
        if name not in shape and name not in keep
    ]
    return replace(k, **dict.fromkeys(cleared, 0.0))


def _unit_parameters(robot: Robot, names: Sequence[str]) -> list[kernel.KernelParameters]:
    """One :class:`KernelParameters` per name: that parameter 1, every other one 0."""
    zero = _zero_parameters(robot)
    return [replace(zero, **{name: 1.0}) for name in names]


def _forces(
    k: kernel.KernelParameters,
    kin: kernel.KernelKinematics,
    rows: FloatArray,
    load: FloatArray | None = None,
) -> tuple[kernel.Legs, kernel.Legs, kernel.Legs]:
    """``f10, f21y, f21z`` of the kernel for ``k`` (no ``μ`` terms), wrenches to virtual work."""
    ddx, ddy, dphi, ddphi = rows[6], rows[7], rows[5], rows[8]
    friction = kernel.friction_forces(kernel.NUMPY, k, kin, dphi)
    loads = None if load is None else (load[0], load[1], load[2])
    wrenches = kernel.body_wrenches(k, kin, ddx, ddy, dphi, ddphi, load=loads, friction=friction)
    f10, f21y, f21z, _ = kernel.joint_forces(k, kin, wrenches, reactions=False)
    return f10, f21y, f21z


def _regressor_rows(
    units: Sequence[kernel.KernelParameters], rows: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Regressor of the states ``rows`` (9, n): ``(3 forces, n, 3, P)``, ``λ10``, ``λ̇10``."""
    kin = _kinematics(units[0], rows)  # l0 is the same in every unit parameter set
    out = np.empty((3, rows.shape[1], 3, len(units)))
    for column, unit in enumerate(units):
        for f, legs in enumerate(_forces(unit, kin, rows)):
            for leg in range(3):
                out[f, :, leg, column] = legs[leg]
    return out, np.stack(kin.geometry.lambda10, axis=-1), np.stack(kin.dlambda10, axis=-1)


def _kinematics(k: kernel.KernelParameters, rows: FloatArray) -> kernel.KernelKinematics:
    """Joint displacements and rates of the states ``rows`` (eqs. 10, 14, 17)."""
    x, y, phi, dx, dy, dphi, ddx, ddy, ddphi = rows
    geo = kernel.kernel_geometry(kernel.NUMPY, k, x, y, phi)
    return kernel.kernel_kinematics(k, geo, dx, dy, dphi, ddx, ddy, ddphi)


def _state_rows(motion: Motion) -> FloatArray:
    """The states of a motion as rows ``(9, N)``: x, y, φ, their rates, their accelerations."""
    return np.concatenate(
        [
            motion.pose.reshape(-1, 3).T,
            motion.velocity.reshape(-1, 3).T,
            motion.acceleration.reshape(-1, 3).T,
        ]
    )


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
        Samples per chunk (memory bounded for any ``N``).
    progress : callable, optional
        ``progress(samples_done, N)`` after every chunk.

    Raises
    ------
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
    names = _check_names(parameters)
    if not isinstance(motion, Motion):
        raise TrajectoryError(f"motion must be a prp3.Motion, got {type(motion).__name__}")
    inverse_geometry(robot, motion.pose)  # refuses singular and unreachable poses
    units = _unit_parameters(robot, names)
    rows = _state_rows(motion)
    samples = rows.shape[1]
    width = max(1, min(int(chunk_size), samples))
    forces = np.empty((3, samples, 3, len(names)))
    lambda10 = np.empty((samples, 3))
    dlambda10 = np.empty((samples, 3))
    for start in range(0, samples, width):
        stop = min(start + width, samples)
        block, lam, dlam = _regressor_rows(units, rows[:, start:stop])
        forces[:, start:stop] = block
        lambda10[start:stop] = lam
        dlambda10[start:stop] = dlam
        if progress is not None:
            progress(stop, samples)
    shape = motion.pose.shape[:-1]
    return Regressor(
        parameters=names,
        f10=forces[0].reshape(*shape, 3, len(names)),
        f21y=forces[1].reshape(*shape, 3, len(names)),
        f21z=forces[2].reshape(*shape, 3, len(names)),
        lambda10=lambda10.reshape(*shape, 3),
        dlambda10=dlambda10.reshape(*shape, 3),
    )


# ------------------------------------------------------------ base parameters
def _independent_columns(matrix: FloatArray, tolerance: float) -> tuple[list[int], list[int]]:
    """Columns that raise the rank, in order (greedy Gram–Schmidt), and the zero columns.

    The columns are scaled to unit norm first; a column whose residual after
    projection on the kept ones is below ``tolerance`` is dependent.
    """
    norms = np.linalg.norm(matrix, axis=0)
    top = float(norms.max()) if norms.size else 0.0
    zero = [j for j in range(matrix.shape[1]) if not norms[j] > 1e-13 * top]
    basis: list[FloatArray] = []
    kept: list[int] = []
    for j in range(matrix.shape[1]):
        if j in zero:
            continue
        v = matrix[:, j] / norms[j]
        for _ in range(2):  # twice is enough (Kahan–Parlett)
            for b in basis:
                v = v - (b @ v) * b
        residual = float(np.linalg.norm(v))
        if residual > tolerance:
            basis.append(v / residual)
            kept.append(j)
    return kept, zero


def _snap(value: float) -> float:
    """A coefficient as the nearest simple fraction (denominator ≤ 12) when within 1e-9."""
    fraction = Fraction(value).limit_denominator(12)
    if abs(float(fraction) - value) <= 1e-9 * max(1.0, abs(value)):
        return float(fraction)
    return value


@dataclass(frozen=True)
class BaseParameters:
    """The identifiable combinations of the standard parameters.

    Attributes
    ----------
    parameters : tuple of str
        The standard parameters considered (columns), in order of preference.
    forces : tuple of str
        The forces whose regressor was used (``("f10",)``: the actuator forces).
    independent : tuple of int
        For each base parameter, the index of the standard parameter that names it.
    combination : ndarray, shape (B, P)
        ``base = combination @ standard``; row ``b`` has 1 at ``independent[b]``.
    unidentifiable : tuple of str
        Standard parameters that enter none of the forces.
    """

    parameters: tuple[str, ...]
    forces: tuple[str, ...]
    independent: tuple[int, ...]
    combination: FloatArray
    unidentifiable: tuple[str, ...]

    @property
    def count(self) -> int:
        """Number of base parameters ``B``."""
        return len(self.independent)

    @property
    def names(self) -> tuple[str, ...]:
        """The standard parameter that names each base parameter."""
        return tuple(self.parameters[j] for j in self.independent)

    @property
    def labels(self) -> tuple[str, ...]:
        """Each combination written out, e.g. ``'J3 + 3·J2'``."""
        return tuple(self.label(b) for b in range(self.count))

    def label(self, b: int) -> str:
        """Base parameter ``b`` as a readable combination of the standard parameters."""
        row = self.combination[b]
        order = [self.independent[b]] + [
            j for j in range(len(self.parameters)) if j != self.independent[b] and row[j] != 0.0
        ]
        text = ""
        for j in order:
            symbol = PARAMETER_SYMBOLS[self.parameters[j]]
            value = float(row[j])
            magnitude = abs(value)
            term = symbol if magnitude == 1.0 else f"{_coefficient(magnitude)}·{symbol}"
            if not text:
                text = term if value > 0 else f"-{term}"
            else:
                text += f" {'+' if value > 0 else '-'} {term}"
        return text

    def members(self, b: int) -> tuple[int, ...]:
        """Indices of the standard parameters in base parameter ``b``."""
        return tuple(int(j) for j in np.flatnonzero(self.combination[b]))

    def dependent(self) -> tuple[str, ...]:
        """Standard parameters identifiable only inside a combination with others."""
        named = set(self.independent)
        return tuple(
            name
            for j, name in enumerate(self.parameters)
            if j not in named and name not in self.unidentifiable
        )

    def reason(self, name: str) -> str:
        """Why the standard parameter ``name`` is not identifiable on its own."""
        if name in _REASONS:
            return _REASONS[name]
        j = self.parameters.index(name)
        within = [self.label(b) for b in range(self.count) if self.combination[b, j] != 0.0]
        if within:
            return f"appears only in {', '.join(within)}"
        return f"enters none of {', '.join(self.forces)}"

    def values(self, standard: FloatArray) -> FloatArray:
        """The base parameters of a vector of standard parameters ``(P,)`` → ``(B,)``."""
        return np.asarray(self.combination @ np.asarray(standard, dtype=np.float64))


def _coefficient(value: float) -> str:
    fraction = Fraction(value).limit_denominator(12)
    if float(fraction) == value:
        return str(fraction)
    return f"{value:.6g}"


def _random_motion(robot: Robot, samples: int, seed: int) -> Motion:
    """Random regular states of the size of ``robot`` (exciting every parameter)."""
    rng = np.random.default_rng(seed)
    l0 = robot.l0
    pose = np.column_stack(
        [rng.uniform(-0.1, 0.1, (samples, 2)) * l0, rng.uniform(-0.5, 0.5, samples)]
    )
    scale = np.array([l0, l0, 1.0])
    return Motion(
        t=np.arange(samples, dtype=np.float64),
        pose=pose,
        velocity=rng.normal(size=(samples, 3)) * scale,
        acceleration=rng.normal(size=(samples, 3)) * 3.0 * scale,
    )


def base_parameters(
    robot: Robot,
    forces: Sequence[str] = ("f10",),
    parameters: Sequence[str] = STANDARD_PARAMETERS,
    *,
    samples: int = 200,
    seed: int = 0,
) -> BaseParameters:
    """The base parameters of ``robot``'s geometry, found numerically.

    The regressor of ``forces`` over ``samples`` random states (poses within
    ``0.1·l0`` of the centre, ``|φ| ≤ 0.5``, random rates), stacked, columns
    scaled to unit norm and taken in the order of ``parameters``: a column is
    independent when it raises the rank (relative residual > 1e-8), dependent
    otherwise; the least-squares combination of the independent columns that
    reproduces a dependent column gives its coefficient in the base parameters
    (snapped to a simple fraction within 1e-9).

    Parameters
    ----------
    robot : Robot
        Its ``l0`` and gravity (the stroke is ignored here).
    forces : sequence of str
        Which measured forces: ``("f10",)`` or any of :data:`FORCES`.
    parameters : sequence of str
        The standard parameters to consider, in order of preference.
    samples, seed : int
        The random states.

    Examples
    --------
    >>> base = base_parameters(Robot())
    >>> base.count, base.dependent()
    (7, ('link_mass', 'link_inertia'))
    >>> round(float(base.values(standard_parameters(Robot()))[3]), 12)  # J3 + 3·J2
    0.069375
    """
    check_robot(robot)
    names = _check_names(parameters)
    chosen = check_names("forces", forces, FORCES, item="force")
    if not chosen or any(f not in FORCES for f in chosen) or len(set(chosen)) != len(chosen):
        raise ParameterError(f"forces must be distinct names from {FORCES}, got {chosen!r}")
    free = replace(robot, limits=Limits())
    Y = regressor(free, _random_motion(free, samples, seed), names)
    W = np.concatenate([getattr(Y, f).reshape(-1, len(names)) for f in chosen])
    kept, zero = _independent_columns(W, _RANK_TOLERANCE)
    combination = np.zeros((len(kept), len(names)))
    for b, j in enumerate(kept):
        combination[b, j] = 1.0
    dependent = [j for j in range(len(names)) if j not in kept and j not in zero]
    if dependent:
        beta = np.linalg.lstsq(W[:, kept], W[:, dependent], rcond=None)[0]  # (B, D)
        scale = np.abs(beta).max(axis=0, keepdims=True)
        beta = np.where(np.abs(beta) <= 1e-9 * scale, 0.0, beta)
        for d, j in enumerate(dependent):
            combination[:, j] = [_snap(float(v)) for v in beta[:, d]]
    return BaseParameters(
        parameters=names,
        forces=chosen,
        independent=tuple(kept),
        combination=combination,
        unidentifiable=tuple(names[j] for j in zero),
    )


# ----------------------------------------------------------- identification
@dataclass(frozen=True)
class Identification:
    """The result of :func:`identify`.

    Attributes
    ----------
    base : BaseParameters
        The combinations estimated.
    estimate, std : ndarray, shape (B,)
        The base parameters and their standard deviations (SI units).
    condition : float
        2-norm condition number of the stacked base regressor ``(3N, B)`` (SI units).
    sigma : ndarray, shape (3,)
        Residual standard deviation of each actuator after the first
        (unweighted) pass: the weights of the second (N).
    residual_rms : ndarray, shape (3,)
        RMS of ``measured − fitted`` per actuator after the weighted fit (N).
    t : ndarray, shape (N,)
        Sample times (s).
    measured, fitted : ndarray, shape (N, 3)
        The measured actuator forces and those of the estimate (N).
    fixed : tuple of str
        Standard parameters not estimated but kept at the nominal robot's
        values (their forces are subtracted from the measurements).
    """

    base: BaseParameters
    estimate: FloatArray
    std: FloatArray
    condition: float
    sigma: FloatArray
    residual_rms: FloatArray
    t: FloatArray
    measured: FloatArray
    fitted: FloatArray
    fixed: tuple[str, ...]


def identify(
    robot: Robot,
    motion: Motion,
    f10: FloatArray,
    parameters: Sequence[str] = STANDARD_PARAMETERS,
    *,
    where: str = "measurements",
    progress: Callable[[int, int], None] | None = None,
) -> Identification:
    """Base parameters from measured actuator forces by weighted least squares.

    1. The base regressor ``W`` of ``f10`` on the motion: the columns of the
       standard parameters that name the base parameters
       (``Y·π = W·β`` for any ``π``, because every other column is a
       combination of these on any motion).  Standard parameters not in
       ``parameters`` are fixed at ``robot``'s values and their forces
       subtracted from the measurements.
    2. Refusals: fewer than :data:`MIN_SAMPLES_PER_PARAMETER` samples per base
       parameter; a motion that does not excite a base parameter (its scaled
       column of ``W`` lies in the span of the others to 1e-6: names it).
    3. Ordinary least squares; the residual standard deviation of each
       actuator ``σ_j = ‖r_j‖ / √(N − B/3)``.
    4. Weighted least squares: the rows of actuator ``j`` divided by ``σ_j``;
       covariance ``s²·(AᵀA)⁻¹`` with ``s² = ‖r_w‖² / (3N − B)``.

    Parameters
    ----------
    robot : Robot
        The nominal robot: geometry, gravity and the fixed parameters.
    motion : Motion
        ``N`` samples of the platform motion.
    f10 : ndarray, shape (N, 3)
        Measured actuator forces (N).
    parameters : sequence of str
        The standard parameters to estimate.
    where : str
        Names the data in messages (the file).
    progress : callable, optional
        ``progress(samples_done, N)`` while the regressor is built (the long part).

    Raises
    ------
    TrajectoryError
        Too few samples, wrong shapes, or a motion that does not excite the
        base parameters.

    Examples
    --------
    >>> from prp3.model.motion import law_motion
    >>> from prp3.analysis.inverse_dynamics import inverse_dynamics
    >>> robot = Robot()
    >>> motion = law_motion((0.01, 0.02, 0.2), samples=101)
    >>> result = identify(robot, motion, inverse_dynamics(robot, motion)[1].f10)
    >>> bool(np.allclose(result.estimate, result.base.values(standard_parameters(robot))))
    True
    """
    check_robot(robot)
    names = _check_names(parameters)
    if not isinstance(motion, Motion) or motion.t.ndim != 1:
        raise TrajectoryError(f"{where}: the motion must be a batch prp3.Motion")
    _refuse_mu(robot)
    measured = check_per_leg("f10", f10)
    samples = motion.samples
    if measured.shape != (samples, 3):
        raise TrajectoryError(
            f"{where}: f10 must have shape ({samples}, 3) to match the motion, got {measured.shape}"
        )
    base = base_parameters(robot, ("f10",), names)
    needed = MIN_SAMPLES_PER_PARAMETER * base.count
    if samples < needed:
        raise TrajectoryError(
            f"{where}: {samples} samples are too few to identify {base.count} base parameters "
            f"(at least {MIN_SAMPLES_PER_PARAMETER} per parameter: {needed})"
        )
    fixed = tuple(name for name in PARAMETERS if name not in names)
    Y = regressor(robot, motion, names, progress=progress)
    known = known_forces(robot, motion, fixed)
    target = measured - known
    W = Y.f10[..., list(base.independent)]  # (N, 3, B)
    stacked = W.reshape(-1, base.count)
    kept = _independent_columns(stacked, _EXCITATION_TOLERANCE)[0]
    if len(kept) < base.count:
        missing = [b for b in range(base.count) if b not in kept]
        raise TrajectoryError(
            f"{where}: the motion does not excite the base parameter(s) "
            f"{', '.join(repr(base.label(b)) for b in missing)} (regressor rank {len(kept)} < "
            f"{base.count}); move every coordinate, e.g. along a trajectory of prp3 excite"
        )
    estimate, std, sigma = weighted_least_squares(W, target)
    fitted = W @ estimate + known
    return Identification(
        base=base,
        estimate=estimate,
        std=std,
        condition=float(np.linalg.cond(stacked)),
        sigma=sigma,
        residual_rms=np.sqrt(((measured - fitted) ** 2).mean(axis=0)),
        t=np.asarray(motion.t, dtype=np.float64),
        measured=measured,
        fitted=fitted,
        fixed=fixed,
    )


def _refuse_mu(robot: Robot) -> None:
    """The load-dependent ``μ`` friction terms are not linear: refuse a robot with them."""
    if kernel.kernel_parameters(robot).has_mu:
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
    _refuse_mu(robot)
    names = check_names("fixed", fixed, PARAMETERS, item="parameter", empty=True)
    inverse_geometry(robot, motion.pose)
    k = _zero_parameters(robot, keep=(*names, *LOAD.fields))
    rows = _state_rows(motion)
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


def weighted_least_squares(
    W: FloatArray, measured: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Two-pass weighted least squares of ``measured ≈ W·β``, for one or many data sets.

    First pass: ordinary least squares; ``σ_j = ‖r_j‖ / √(N − B/3)`` is the
    residual standard deviation of actuator ``j``.  Second pass: the rows of
    actuator ``j`` divided by ``σ_j``; the covariance of the estimate is
    ``s²·(AᵀA)⁻¹`` with ``s² = ‖r_w‖² / (3N − B)`` (solved by SVD).

    Parameters
    ----------
    W : ndarray, shape (N, 3, B)
        The base regressor.
    measured : ndarray, shape (..., N, 3)
        One data set, or a stack of them (vectorised: e.g. many noise draws).

    Returns
    -------
    estimate, std : ndarray, shape (..., B)
        The estimate and its standard deviations.
    sigma : ndarray, shape (..., 3)
        The weights: first-pass residual standard deviation per actuator.

    Examples
    --------
    >>> W = np.stack([np.ones((20, 3)), np.linspace(0, 1, 60).reshape(20, 3)], axis=-1)
    >>> estimate, std, sigma = weighted_least_squares(W, W @ np.array([2.0, -1.0]))
    >>> np.round(estimate, 12).tolist()
    [2.0, -1.0]
    """
    samples, _, count = W.shape
    target = np.asarray(measured, dtype=np.float64)
    stacked = W.reshape(-1, count)
    first = np.einsum(
        "bk,...k->...b", np.linalg.pinv(stacked), target.reshape(*target.shape[:-2], -1)
    )
    residual = target - np.einsum("nlb,...b->...nl", W, first)
    sigma = np.sqrt((residual**2).sum(axis=-2) / (samples - count / 3.0))
    floor = 1e-12 * np.sqrt((target**2).mean(axis=-2)).max(axis=-1, keepdims=True) + 1e-300
    sigma = np.maximum(sigma, floor)
    A = (W / sigma[..., None, :, None]).reshape(*sigma.shape[:-1], -1, count)
    b = (target / sigma[..., None, :]).reshape(*sigma.shape[:-1], -1)
    U, S, Vt = np.linalg.svd(A, full_matrices=False)
    coordinates = np.einsum("...nb,...n->...b", U, b) / S
    estimate = np.einsum("...bk,...b->...k", Vt, coordinates)
    weighted = b - np.einsum("...nk,...k->...n", A, estimate)
    s2 = (weighted**2).sum(axis=-1) / (3 * samples - count)
    variance = np.einsum("...bk,...b->...k", Vt**2, 1.0 / S**2) * s2[..., None]
    return estimate, np.sqrt(variance), sigma


# ------------------------------------------------------ physical parameters
def robot_from_standard(nominal: Robot, standard: dict[str, float]) -> Robot:
    """The robot with the parameters ``standard`` (the others from ``nominal``).

    The inverse of :func:`prp3.mechanics.kernel.kernel_parameters`: ``c = h/m``,
    ``I2 = J2 − m2·|c2|²`` about the centre of mass.  The platform side
    ``(m3, h3, J3)`` is the platform and its payload together: with a payload
    in ``nominal``, its mass and own inertia are kept and the platform mass,
    the payload's centre of mass ``h3/m_p`` and the platform inertia
    ``J3 − I_p − |h3|²/m_p`` are solved; without one, ``h3`` must be zero.
    Friction coefficients replace ``nominal``'s (its ``μ``, smoothing and pin
    radius are kept).  The piston inertia (it never enters the dynamics),
    geometry, gravity, limits and load are ``nominal``'s.

    Raises
    ------
    ParameterError
        A non-positive mass, a negative inertia about a centre of mass or a
        negative friction coefficient (names the parameter and its value).

    Examples
    --------
    >>> robot = robot_from_standard(Robot(), {"link_moment_x": 0.015, "link_inertia": 1e-3})
    >>> robot.link.com, round(robot.link.inertia, 12)
    ((0.02, 0.0), 0.0007)
    """
    values = dict(zip(PARAMETERS, standard_parameters(nominal, PARAMETERS).tolist(), strict=True))
    for name, value in standard.items():
        _check_names([name])
        values[name] = float(value)
    for name in ("piston_mass", "link_mass", "platform_mass"):
        if not values[name] > 0.0:
            raise ParameterError(
                f"{PARAMETER_SYMBOLS[name]} = {values[name]!r} kg: a mass must be positive"
            )
    m1, m2 = values["piston_mass"], values["link_mass"]
    c1 = (values["piston_moment_x"] / m1, values["piston_moment_y"] / m1)
    c2 = (values["link_moment_x"] / m2, values["link_moment_y"] / m2)
    round_off = 1e-12 * nominal.l0**2  # kg·m² per kg: an inertia of round-off size
    link_inertia = values["link_inertia"] - m2 * (c2[0] ** 2 + c2[1] ** 2)
    if -round_off * m2 <= link_inertia < 0.0:
        link_inertia = 0.0
    if not link_inertia >= 0.0:
        raise ParameterError(
            f"J2 = {values['link_inertia']!r} kg m^2 is less than m2·|c2|^2 = "
            f"{m2 * (c2[0] ** 2 + c2[1] ** 2)!r}: link 2's inertia about its centre of mass "
            "would be negative"
        )
    mass, inertia = values["platform_mass"], values["platform_inertia"]
    h3 = (values["platform_moment_x"], values["platform_moment_y"])
    payload = nominal.payload
    if payload.mass > 0.0:
        mp = payload.mass
        cp = (h3[0] / mp, h3[1] / mp)
        mass = mass - mp
        inertia = inertia - payload.inertia - (h3[0] ** 2 + h3[1] ** 2) / mp
        payload = replace(payload, com=cp)
        if not mass > 0.0:
            raise ParameterError(
                f"m3 = {values['platform_mass']!r} kg is not more than the payload's "
                f"{mp!r} kg: the platform mass would not be positive"
            )
    elif h3 != (0.0, 0.0):
        raise ParameterError(
            f"h3 = ({h3[0]!r}, {h3[1]!r}) kg m: a first moment of the platform about G "
            "needs a payload; give the nominal robot a [payload] with its mass"
        )
    if -round_off * mass <= inertia < 0.0:
        inertia = 0.0
    if not inertia >= 0.0:
        raise ParameterError(
            f"J3 = {values['platform_inertia']!r} kg m^2: the platform inertia about G would "
            "be negative"
        )
    robot = replace(
        nominal,
        piston=PistonParameters(mass=m1, inertia=nominal.piston.inertia, com=c1),
        link=LinkParameters(mass=m2, inertia=link_inertia, com=c2),
        platform=PlatformParameters(mass=mass, inertia=inertia),
        payload=payload,
    )
    for element in ELEMENTS:  # the friction coefficients, the spring's stiffness and damping
        if element.regressor:
            robot = element.identified(robot, values)
    return robot


@dataclass(frozen=True)
class IdentifiedRobot:
    """A robot whose physical parameters reproduce identified base parameters.

    Attributes
    ----------
    robot : Robot
        Geometry, gravity and limits of the nominal robot.
    solved : tuple of str
        For each base parameter, the standard parameter solved from it.
    kept : tuple of str
        Standard parameters kept at the nominal robot's values.
    clamped : tuple of str
        Friction coefficients estimated below zero but within 3 standard
        deviations of it (or round-off), and, for a nominal robot without a
        payload, the platform's first moments ``h3x``, ``h3y`` estimated within
        3 standard deviations of zero (or ``1e-9·m3·l0``): written as 0.
    """

    robot: Robot
    solved: tuple[str, ...]
    kept: tuple[str, ...]
    clamped: tuple[str, ...] = ()


#: Most choices of solved parameters :func:`identified_robot` tries.
_MAX_CHOICES: int = 4096


def _kept_values(nominal: Robot, values: dict[str, float]) -> dict[str, float]:
    """The parameters of ``nominal``'s physical ones, with the current masses and moments.

    A kept first moment keeps the nominal centre of mass (``h = m·c``), a kept
    inertia the nominal inertia about the centre of mass (``J2 = I2 + |h2|²/m2``,
    ``J3 = I3 + I_p + |h3|²/m_p`` with a payload), whatever the masses and
    moments solved; friction coefficients are kept as they are.
    """
    m1, m2 = values["piston_mass"], values["link_mass"]
    h2x, h2y = values["link_moment_x"], values["link_moment_y"]
    h3x, h3y = values["platform_moment_x"], values["platform_moment_y"]
    payload = nominal.payload
    mp = payload.mass
    kept = dict(zip(PARAMETERS, standard_parameters(nominal, PARAMETERS).tolist(), strict=True))
    kept.update(
        piston_moment_x=m1 * nominal.piston.com[0],
        piston_moment_y=m1 * nominal.piston.com[1],
        link_moment_x=m2 * nominal.link.com[0],
        link_moment_y=m2 * nominal.link.com[1],
        link_inertia=nominal.link.inertia + (h2x * h2x + h2y * h2y) / m2 if m2 > 0 else 0.0,
    )
    if mp > 0.0:
        kept["platform_inertia"] = (
            nominal.platform_inertia + payload.inertia + (h3x * h3x + h3y * h3y) / mp
        )
    return kept


def _solve_choice(
    nominal: Robot, base: BaseParameters, estimate: FloatArray, solved: list[int]
) -> dict[str, float]:
    """Standard parameters: ``solved`` from the base parameters, the others kept (physically)."""
    names = base.parameters
    C = base.combination
    others = [j for j in range(len(names)) if j not in solved]
    values = dict(zip(PARAMETERS, standard_parameters(nominal, PARAMETERS).tolist(), strict=True))
    for _ in range(4):  # masses, then moments, then inertias: a fixed point in 3 passes
        kept = _kept_values(nominal, values)
        fixed = np.array([kept[names[j]] for j in others])
        rhs = estimate - C[:, others] @ fixed
        for j, v in zip(others, fixed.tolist(), strict=True):
            values[names[j]] = v
        for j, v in zip(solved, np.linalg.solve(C[:, solved], rhs).tolist(), strict=True):
            values[names[j]] = v
    return values


def identified_robot(nominal: Robot, result: Identification) -> IdentifiedRobot:
    """The robot of an identification: in each combination, solve the dominant parameter.

    Within each base parameter the member with the largest nominal
    contribution ``|coefficient × nominal value|`` is solved (the platform
    inertia, not a link's small inertia), the others keep ``nominal``'s
    physical values: its masses, centres of mass and inertias about the
    centres of mass (so a kept ``J2`` follows the identified ``h2``).
    If that robot is not physically valid (a mass ≤ 0, an inertia < 0 about a
    centre of mass), the other choices are tried in order of dominance.  A
    friction coefficient estimated below 0 but within 3 standard deviations
    of it is written as 0 (and listed in :attr:`IdentifiedRobot.clamped`);
    further below, the robot is invalid.  Likewise, without a payload in
    ``nominal`` the platform's centre of mass is ``G`` (``h3 = 0``, the
    robot cannot say otherwise): the first moments ``h3x``, ``h3y`` estimated
    within 3 standard deviations of zero (noise), or within ``1e-9·m3·l0``
    (round-off on exact forces), are written as 0; farther from it, the robot is invalid (give
    ``nominal`` a ``[payload]``).

    Examples
    --------
    >>> from prp3.model.motion import law_motion
    >>> from prp3.analysis.inverse_dynamics import inverse_dynamics
    >>> robot, motion = Robot(), law_motion((0.01, 0.02, 0.2), samples=101)
    >>> result = identify(robot, motion, inverse_dynamics(robot, motion)[1].f10)
    >>> identified = identified_robot(robot, result)
    >>> round(identified.robot.platform.mass, 9), identified.clamped
    (3.0, ('platform_moment_x', 'platform_moment_y'))

    Raises
    ------
    ParameterError
        No choice gives a physically valid robot (names the first failure).
    """
    base = result.base
    estimate = result.estimate.copy()
    clamped = []
    without_payload = not nominal.payload.mass > 0.0
    moment_floor = 1e-9 * nominal.platform.mass * nominal.l0  # kg m: round-off of h3
    roundoff = 1e-12 * float(np.abs(result.measured).max())  # of the forces: N (N s/m at 1 m/s)
    for b, name in enumerate(base.names):  # a friction coefficient of 0 estimated below 0
        if base.members(b) != (base.independent[b],):
            continue
        floor = max(3.0 * result.std[b], roundoff)
        if name in ELEMENT_PARAMETERS and -floor <= estimate[b] < 0.0:
            estimate[b] = 0.0
            clamped.append(name)
        elif (  # no payload: the centre of mass of the platform is G
            without_payload
            and name in ("platform_moment_x", "platform_moment_y")
            and estimate[b] != 0.0
            and abs(estimate[b]) <= max(3.0 * result.std[b], moment_floor)
        ):
            estimate[b] = 0.0
            clamped.append(name)
    nominal_values = standard_parameters(nominal, base.parameters)
    candidates = []
    for b in range(base.count):
        members = base.members(b)
        weight = [abs(base.combination[b, j] * nominal_values[j]) for j in members]
        order = sorted(range(len(members)), key=lambda i: (-weight[i], members[i]))
        candidates.append([members[i] for i in order])
    first_error: ParameterError | None = None
    for choice in itertools.islice(itertools.product(*candidates), _MAX_CHOICES):
        if (
            len(set(choice)) != len(choice)
            or abs(np.linalg.det(base.combination[:, choice])) < 1e-12
        ):
            continue
        values = _solve_choice(nominal, base, estimate, list(choice))
        for name in ELEMENT_PARAMETERS:  # a zero coefficient solved to round-off below zero
            if name in values and -roundoff <= values[name] < 0.0:
                values[name] = 0.0
        try:
            robot = robot_from_standard(nominal, values)
        except ParameterError as error:
            first_error = first_error or error
            continue
        solved_names = tuple(base.parameters[j] for j in choice)
        kept = tuple(name for name in PARAMETERS if name not in solved_names)
        return IdentifiedRobot(robot=robot, solved=solved_names, kept=kept, clamped=tuple(clamped))
    raise ParameterError(
        f"the identified base parameters give no physically valid robot ({first_error})"
    )


# ---------------------------------------------------------- exciting motion
#: Fraction of each limit kept free by the optimiser (the limits hold between its samples).
_LIMIT_MARGIN: float = 0.01

#: Instants per period at which the optimised motion is checked against the limits.
_FINE_SAMPLES: int = 2000


@dataclass(frozen=True)
class FourierSeries:
    """A finite Fourier series of the platform pose (a periodic exciting motion).

    ``q_k(t) = q0_k + Σ_l (a_kl·sin(l·ω·t) + b_kl·cos(l·ω·t))``,
    ``ω = 2π/period``, ``l = 1..L``, for ``k = x, y, φ``.

    Attributes
    ----------
    period : float
        ``2π/ω`` (s).
    offset : ndarray, shape (3,)
        ``q0`` (m, m, rad).
    sine, cosine : ndarray, shape (3, L)
        ``a`` and ``b`` (m, m, rad).
    """

    period: float
    offset: FloatArray
    sine: FloatArray
    cosine: FloatArray

    def motion(self, t: FloatArray) -> Motion:
        """Pose, velocity and acceleration at times ``t`` (analytic derivatives)."""
        time = np.asarray(t, dtype=np.float64)
        harmonics = np.arange(1, self.sine.shape[1] + 1)
        w = 2.0 * math.pi / self.period * harmonics  # (L,)
        arg = time[:, None] * w  # (N, L)
        s, c = np.sin(arg), np.cos(arg)
        pose = self.offset + s @ self.sine.T + c @ self.cosine.T
        velocity = (c * w) @ self.sine.T - (s * w) @ self.cosine.T
        acceleration = -(s * w**2) @ self.sine.T - (c * w**2) @ self.cosine.T
        return Motion(t=time, pose=pose, velocity=velocity, acceleration=acceleration)


@dataclass(frozen=True)
class ExcitingTrajectory:
    """An optimised exciting motion from :func:`exciting_trajectory`.

    Attributes
    ----------
    series : FourierSeries
        The motion.
    condition : float
        Condition number of the stacked base regressor of ``f10`` on the
        optimisation samples (SI units).
    initial_condition : float
        The same for the starting guess.
    peak_lambda10, peak_dlambda10, peak_f10 : float
        Largest ``|λ10|`` (m), ``|λ̇10|`` (m/s) and ``|f10|`` (N) of the nominal robot.
    iterations : int
        Optimiser iterations.
    """

    series: FourierSeries
    condition: float
    initial_condition: float
    peak_lambda10: float
    peak_dlambda10: float
    peak_f10: float
    iterations: int


def _counter(progress: Callable[[int, int], None], total: int) -> Callable[..., None]:
    """A ``minimize`` callback that reports the iterations done of ``total``."""
    done = [0]

    def step(*_: object) -> None:
        done[0] += 1
        progress(min(done[0], total), total)

    return step


def exciting_trajectory(
    robot: Robot,
    *,
    period: float = 5.0,
    harmonics: int = 4,
    reach: float = 0.2,
    rotation: float = 0.5,
    max_velocity: float = 0.5,
    max_force: float | None = None,
    samples: int = 120,
    seed: int = 0,
    max_iterations: int = 150,
    progress: Callable[[int, int], None] | None = None,
) -> ExcitingTrajectory:
    """A Fourier-series motion that minimises the condition number of the base regressor.

    Minimises ``log cond(W)`` of the stacked base regressor of ``f10``
    (:func:`base_parameters`) on ``samples`` instants of one period, by SLSQP
    (``scipy.optimize.minimize``) over the offsets and coefficients, under
    constraints at those instants: ``|x|, |y| ≤ reach·l0``,
    ``|φ| ≤ rotation`` (rad, away from the singularity ``φ = π/3``),
    ``λ10`` inside ``robot.limits.stroke`` (when set), ``|λ̇10| ≤ max_velocity``
    and ``|f10| ≤ max_force`` (default ``robot.limits.max_force``; none if
    neither) of the nominal robot.  ``progress(iterations_done,
    max_iterations)`` is called after every SLSQP iteration (and with
    ``max_iterations`` at the end: the optimiser may stop earlier).

    Raises
    ------
    ParameterError
        Bad options, or no feasible motion found (names the violated limit).
    """
    from scipy.optimize import minimize

    check_robot(robot)
    period, reach, rotation, max_velocity = (
        check_scalar(name, value, positive=True)
        for name, value in (("period", period), ("reach", reach), ("rotation", rotation),
                            ("max_velocity", max_velocity))
    )  # fmt: skip
    if not 0.0 < rotation < 1.0:
        raise ParameterError(f"rotation must be in (0, 1) rad (singular at pi/3), got {rotation!r}")
    harmonics = check_integer("harmonics", harmonics, 1, 20)
    samples = check_integer("samples", samples, 2, 10**7)
    seed = check_integer("seed", seed, 0, 2**63 - 1)
    max_iterations = check_integer("max_iterations", max_iterations, 1, 10**6)
    if max_force is not None:
        max_force = check_scalar("max_force", max_force, positive=True)
    force_limit = max_force if max_force is not None else robot.limits.max_force
    base = base_parameters(robot)
    free = replace(robot, limits=Limits())
    units = _unit_parameters(free, base.names)
    nominal = base.values(standard_parameters(robot))
    coarse = t = np.linspace(0.0, period, samples, endpoint=False)
    L = harmonics
    bounds = np.array([reach * robot.l0, reach * robot.l0, rotation])
    stroke = robot.limits.stroke

    def unpack(z: FloatArray) -> FourierSeries:
        return FourierSeries(
            period=period,
            offset=z[:3] * bounds,
            sine=z[3 : 3 + 3 * L].reshape(3, L) * bounds[:, None],
            cosine=z[3 + 3 * L :].reshape(3, L) * bounds[:, None],
        )

    def evaluate(z: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        motion = unpack(z).motion(t)
        with np.errstate(all="ignore"):
            forces, lam, dlam = _regressor_rows(units, _state_rows(motion))
        return forces[0].reshape(-1, base.count), motion.pose, lam, dlam

    def objective(z: FloatArray) -> float:
        W = evaluate(z)[0]
        singular = np.linalg.svd(W, compute_uv=False)
        if not np.isfinite(singular).all() or singular[-1] <= 0.0:
            return 1e3
        return float(np.log(singular[0] / singular[-1]))

    def constraints(z: FloatArray) -> FloatArray:
        """Margins to the limits (>= 0 inside), 1 % kept for the instants between samples."""
        W, pose, lam, dlam = evaluate(z)
        parts = [1.0 - np.abs(pose / bounds).reshape(-1)]
        parts.append(1.0 - np.abs(dlam).reshape(-1) / max_velocity)
        if stroke is not None:
            lower, upper = stroke
            parts += [(upper - lam).reshape(-1) / upper, (lam - lower).reshape(-1) / -lower]
        if force_limit is not None:
            parts.append(1.0 - np.abs(W @ nominal) / force_limit)
        return np.concatenate(parts) - _LIMIT_MARGIN

    rng = np.random.default_rng(seed)
    z0 = np.concatenate([np.zeros(3), rng.uniform(-1.0, 1.0, 6 * L) * 0.3 / L])
    for _ in range(30):  # shrink the guess into the limits
        if constraints(z0).min() >= 0.0:
            break
        z0[3:] *= 0.5
    else:
        raise ParameterError("no motion within the limits found (limits too tight)")
    initial = math.exp(objective(z0))
    solution: Any = minimize(
        objective,
        z0,
        method="SLSQP",
        constraints=[{"type": "ineq", "fun": constraints}],
        bounds=[(-1.0, 1.0)] * 3 + [(-1.0, 1.0)] * (6 * L),
        options={"maxiter": max_iterations, "ftol": 1e-6},
        callback=None if progress is None else _counter(progress, max_iterations),
    )
    if progress is not None:
        progress(max_iterations, max_iterations)
    z = np.asarray(solution.x, dtype=np.float64)
    if constraints(z).min() < -1e-6 or objective(z) > objective(z0):
        z = z0  # the optimiser left the limits: keep the feasible guess
    t = np.linspace(0.0, period, _FINE_SAMPLES)  # the limits between the samples too
    for _ in range(40):
        worst = float(constraints(z).min())
        if worst >= 0.0:
            break
        z[3:] *= 1.0 - max(0.01, 2.0 * -worst)  # a smaller oscillation about the offset
    else:  # pragma: no cover - the offset alone satisfies the limits
        z = z0
    W, _, lam, dlam = evaluate(z)
    t = coarse
    return ExcitingTrajectory(
        series=unpack(z),
        condition=math.exp(objective(z)),
        initial_condition=initial,
        peak_lambda10=float(np.abs(lam).max()),
        peak_dlambda10=float(np.abs(dlam).max()),
        peak_f10=float(np.abs(W @ nominal).max()),
        iterations=int(getattr(solution, "nit", 0)),
    )
