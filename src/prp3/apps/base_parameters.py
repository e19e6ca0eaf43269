"""The base parameters: the identifiable combinations of the standard parameters.

:func:`base_parameters` finds the identifiable combinations numerically: the
regressor (:func:`prp3.apps.regressor.regressor`) of random exciting samples,
its columns scaled to unit norm, taken in a fixed order of preference; a
column that adds nothing to the rank (its residual after projection on the
kept columns is below ``1e-8``) is dependent, and least squares on the kept
columns gives the combination it enters.  A column that is zero on every
sample is unidentifiable.

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

A family robot (:class:`~prp3.family.model.FamilyRobot`, docs/family.md) has the
standard parameters :data:`prp3.apps.family_regressor.FAMILY_PARAMETERS` and
its actuator efforts ``tau`` only (:mod:`prp3.apps.family_regressor`):

>>> from prp3.family import FamilyRobot
>>> base = base_parameters(FamilyRobot.default("3-RPR"))
>>> base.labels
('m3 + 3·m2', 'h3x', 'h3y', 'J3 + 0.15·m2', 'h2x', 'h2y', 'J2 + J1', 'h1x', 'h1y')
>>> base.forces, base.unidentifiable
(('tau',), ('link1_mass',))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

from prp3.apps.family_regressor import (
    FAMILY_PARAMETER_SYMBOLS,
    FAMILY_PARAMETERS,
    family_random_motion,
    family_regressor,
)
from prp3.apps.regressor import (
    FORCES,
    PARAMETER_SYMBOLS,
    STANDARD_PARAMETERS,
    check_parameter_names,
    regressor,
)
from prp3.errors import ParameterError
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.model.parameters import Limits
from prp3.model.robot import Robot
from prp3.validation import check_names, check_real, check_robot

#: The symbol of every standard parameter, of the 3-PRP and of a family robot (the
#: platform's are the same; the links' names differ).
_SYMBOLS: dict[str, str] = {**PARAMETER_SYMBOLS, **FAMILY_PARAMETER_SYMBOLS}

#: The effort a family robot's base parameters are of: its actuator efforts.
FAMILY_FORCES: tuple[str, ...] = ("tau",)

__all__ = [
    "FAMILY_FORCES",
    "BaseParameters",
    "base_parameters",
    "base_parameters_of",
]

FloatArray = NDArray[np.float64]

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

#: Relative residual below which a scaled regressor column adds nothing to the rank.
_RANK_TOLERANCE: float = 1e-8


def independent_columns(matrix: FloatArray, tolerance: float) -> tuple[list[int], list[int]]:
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
    plain : bool
        The labels spell the parameters' names (the spatial robots') rather than
        their symbols (``m3``, ``J2``).
    """

    parameters: tuple[str, ...]
    forces: tuple[str, ...]
    independent: tuple[int, ...]
    combination: FloatArray
    unidentifiable: tuple[str, ...]
    plain: bool = False

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
            name = self.parameters[j]
            symbol = name if self.plain else _SYMBOLS.get(name, name)
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
    robot: Robot | FamilyRobot,
    forces: Sequence[str] = ("f10",),
    parameters: Sequence[str] | None = None,
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
    robot : Robot or FamilyRobot
        Its ``l0`` and gravity (the stroke is ignored here); of a family robot
        (docs/family.md) its geometry, actuation and gravity, the regressor
        :func:`prp3.apps.family_regressor.family_regressor` on
        :func:`~prp3.apps.family_regressor.family_random_motion` (random
        states about its home pose).
    forces : sequence of str
        Which measured forces: ``("f10",)`` or any of :data:`FORCES`; of a
        family robot its actuator efforts, ``("tau",)`` (:data:`FAMILY_FORCES`;
        the default ``("f10",)`` means them too).
    parameters : sequence of str, optional
        The standard parameters to consider, in order of preference (default
        :data:`~prp3.apps.regressor.STANDARD_PARAMETERS`, of a family robot
        :data:`~prp3.apps.family_regressor.FAMILY_PARAMETERS`).
    samples, seed : int
        The random states.

    Examples
    --------
    >>> from prp3.apps.regressor import standard_parameters
    >>> base = base_parameters(Robot())
    >>> base.count, base.dependent()
    (7, ('link_mass', 'link_inertia'))
    >>> round(float(base.values(standard_parameters(Robot()))[3]), 12)  # J3 + 3·J2
    0.069375
    """
    if isinstance(robot, FamilyRobot):
        names = check_names(
            "parameters", FAMILY_PARAMETERS if parameters is None else parameters,
            FAMILY_PARAMETERS, item="parameter",
        )  # fmt: skip
        if tuple(forces) not in (("f10",), FAMILY_FORCES):
            raise ParameterError(
                f"forces must be {FAMILY_FORCES} for the {robot.architecture} of a family "
                f"robot (its actuator efforts; no joint forces), got {forces!r}",
                key="forces",
            )
        chosen: tuple[str, ...] = FAMILY_FORCES
        motion = family_random_motion(robot, samples, seed)
        W = family_regressor(robot, motion, names).tau.reshape(-1, len(names))
    else:
        check_robot(robot)
        names = check_parameter_names(STANDARD_PARAMETERS if parameters is None else parameters)
        chosen = check_names("forces", forces, FORCES, item="force")
        if not chosen or any(f not in FORCES for f in chosen) or len(set(chosen)) != len(chosen):
            raise ParameterError(f"forces must be distinct names from {FORCES}, got {chosen!r}")
        free = replace(robot, limits=Limits())
        Y = regressor(free, _random_motion(free, samples, seed), names)
        W = np.concatenate([getattr(Y, f).reshape(-1, len(names)) for f in chosen])
    return base_parameters_of(W, names, chosen)


def base_parameters_of(
    stacked: FloatArray, parameters: Sequence[str], forces: Sequence[str], *, plain: bool = False
) -> BaseParameters:
    """The base parameters of a stacked regressor ``stacked`` (rows: samples × efforts).

    The step of :func:`base_parameters` after the regressor is built, for any
    robot (the spatial robots' :func:`prp3.apps.spatial_identification.spatial_base_parameters`):
    the columns scaled to unit norm and taken in order, a column independent when it
    raises the rank (relative residual > 1e-8), the least-squares coefficients of a
    dependent one snapped to a simple fraction within 1e-9.

    Parameters
    ----------
    stacked : ndarray, shape (R, P)
        The regressor of ``P`` standard parameters, every row one effort of one sample.
    parameters : sequence of str
        The ``P`` names, in order of preference.
    forces : sequence of str
        The efforts the rows are of (named in :meth:`BaseParameters.reason`).
    plain : bool
        Labels of the parameters' names, not their symbols (:attr:`BaseParameters.plain`).

    >>> W = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 0.0, 0.0], [1.0, 2.0, 0.0]])
    >>> base = base_parameters_of(np.c_[W[:, :2], [0, 1, 0, 0]], ("a", "b", "c"), ("tau",))
    >>> base.labels, base.unidentifiable
    (('a + 2·b', 'c'), ())
    """
    W = check_real("stacked", stacked, ParameterError)
    if isinstance(parameters, str) or not all(isinstance(p, str) for p in parameters):
        raise ParameterError(
            f"parameters must be a sequence of names, got {parameters!r}"[:200], key="parameters"
        )
    names = tuple(parameters)
    if W.ndim != 2 or W.shape[1] != len(names) or not np.isfinite(W).all():
        raise ParameterError(
            f"stacked must be a finite (rows, {len(names)}) regressor of the {len(names)} "
            f"parameters, got shape {W.shape}",
            key="stacked",
        )
    kept, zero = independent_columns(W, _RANK_TOLERANCE)
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
        forces=tuple(forces),
        independent=tuple(kept),
        combination=combination,
        unidentifiable=tuple(names[j] for j in zero),
        plain=bool(plain),
    )
