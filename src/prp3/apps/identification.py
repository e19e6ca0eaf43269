"""Identification of the dynamic parameters: weighted least squares and the robot of the estimate.

:func:`identify` fits the base parameters (:mod:`prp3.apps.base_parameters`)
to measured actuator forces by weighted least squares on the base regressor
(:mod:`prp3.apps.regressor`; each actuator weighted by the standard deviation
of its residual in a first, unweighted pass) and :func:`identified_robot`
turns the estimate into a :class:`~prp3.model.robot.Robot`.  A family robot
(:class:`~prp3.family.model.FamilyRobot`, docs/family.md) is identified the
same way from its actuator efforts ``tau``, on the regressor of
:mod:`prp3.apps.family_regressor`.  An exciting motion for the measurements is
:mod:`prp3.apps.excitation`.
``docs/identification.md`` works through all of it.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from prp3.apps.base_parameters import (
    FAMILY_FORCES,
    BaseParameters,
    base_parameters,
    independent_columns,
)
from prp3.apps.family_regressor import (
    FAMILY_PARAMETERS,
    family_known_forces,
    family_regressor,
    family_standard_parameters,
)
from prp3.apps.regressor import (
    ELEMENT_PARAMETERS,
    FRICTION_PARAMETERS,
    PARAMETER_SYMBOLS,
    PARAMETERS,
    STANDARD_PARAMETERS,
    check_parameter_names,
    known_forces,
    refuse_mu,
    regressor,
    standard_parameters,
)
from prp3.errors import ParameterError, TrajectoryError
from prp3.family.model import Body, FamilyRobot, PlatformBody
from prp3.model.elements import ELEMENTS, FRICTIONS
from prp3.model.motion import Motion
from prp3.model.parameters import LinkParameters, Payload, PistonParameters, PlatformParameters
from prp3.model.robot import Robot
from prp3.validation import (
    LEGS,
    check_instance,
    check_names,
    check_per_leg,
    check_real,
    check_robot,
    check_scalar,
)

__all__ = [
    "FRICTION_MODELS",
    "MIN_SAMPLES_PER_PARAMETER",
    "Identification",
    "IdentifiedRobot",
    "excitation_refusal",
    "identified_robot",
    "identify",
    "robot_from_standard",
    "samples_refusal",
    "weighted_least_squares",
]

FloatArray = NDArray[np.float64]

#: The friction coefficients of each ``prp3 identify --friction`` choice.
FRICTION_MODELS: dict[str, tuple[str, ...]] = {
    "none": (),
    "viscous": tuple(e.regressor[0] for e in FRICTIONS),
    "coulomb": tuple(e.regressor[1] for e in FRICTIONS),
    "both": FRICTION_PARAMETERS,
}

#: Fewest samples (rows of a measurement file) per base parameter :func:`identify` accepts.
MIN_SAMPLES_PER_PARAMETER: int = 5

#: Same, for a measured motion: below it a base parameter is not excited.
_EXCITATION_TOLERANCE: float = 1e-6

#: Singular values of the column-scaled regressor below this (relative) make it rank deficient
#: in :func:`weighted_least_squares`.
_RANK_TOLERANCE: float = 1e-9


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
    robot: Robot | FamilyRobot,
    motion: Motion,
    f10: FloatArray,
    parameters: Sequence[str] | None = None,
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

    A family robot (docs/family.md) is identified the same way from its
    actuator efforts ``tau`` (N or N·m) on the regressor of
    :func:`prp3.apps.family_regressor.family_regressor`; its constant
    ``[load]`` and the parameters not estimated are known efforts.

    Parameters
    ----------
    robot : Robot or FamilyRobot
        The nominal robot: geometry, gravity and the fixed parameters.
    motion : Motion
        ``N`` samples of the platform motion.
    f10 : ndarray, shape (N, 3)
        Measured actuator forces (N); of a family robot its actuator efforts
        ``tau`` (N for a P joint, N·m for an R joint).
    parameters : sequence of str, optional
        The standard parameters to estimate (default
        :data:`~prp3.apps.regressor.STANDARD_PARAMETERS`, of a family robot
        :data:`~prp3.apps.family_regressor.FAMILY_PARAMETERS`).
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
    every, names, measured = _checked_inputs(robot, motion, f10, parameters, where)
    fixed = tuple(name for name in every if name not in names)
    base, W, known = _base_columns(robot, motion, every, names, fixed, where, progress)
    try:
        return fit_base_parameters(base, W, measured, motion.t, where, known=known, fixed=fixed)
    except ParameterError as error:
        raise _named_overflow(error, robot, measured) from None


def _named_overflow(
    error: ParameterError, robot: Robot | FamilyRobot, measured: FloatArray
) -> ParameterError:
    """``error`` itself, or, when the measured efforts overflow the least squares, the
    error naming the largest measured value by its column and sample."""
    with np.errstate(over="ignore"):
        squares = float(np.sum(measured**2))
    if error.key != "measured" or np.isfinite(squares):  # W too large: as it is
        return error
    effort = "f10" if isinstance(robot, Robot) else "tau"
    k, j = (int(v) for v in np.unravel_index(np.argmax(np.abs(measured)), measured.shape))
    return ParameterError(
        f"the least squares overflow double precision: {effort}_{LEGS[j]} = "
        f"{float(measured[k, j])!r} is far beyond the efforts of the robot",
        key="measured",
        sample=k,
    )


def _checked_inputs(
    robot: Robot | FamilyRobot,
    motion: Motion,
    f10: FloatArray,
    parameters: Sequence[str] | None,
    where: str,
) -> tuple[tuple[str, ...], tuple[str, ...], FloatArray]:
    """:func:`identify`'s arguments checked: every standard parameter of ``robot``, those
    estimated, and the measured efforts ``(N, 3)``."""
    family = isinstance(robot, FamilyRobot)
    if family:
        every = FAMILY_PARAMETERS
        names = check_names(
            "parameters", every if parameters is None else parameters, every, item="parameter"
        )
    else:
        check_robot(robot)
        every = PARAMETERS
        names = check_parameter_names(STANDARD_PARAMETERS if parameters is None else parameters)
    if not isinstance(motion, Motion) or motion.t.ndim != 1:
        raise TrajectoryError(f"{where}: the motion must be a batch prp3.Motion")
    effort = "tau" if family else "f10"
    measured = check_per_leg(effort, f10)
    if measured.shape != (motion.samples, 3):
        raise TrajectoryError(
            f"{where}: {effort} must have shape ({motion.samples}, 3) to match the motion, got "
            f"{measured.shape}"
        )
    return tuple(every), tuple(names), measured


def _base_columns(
    robot: Robot | FamilyRobot,
    motion: Motion,
    every: Sequence[str],
    names: Sequence[str],
    fixed: tuple[str, ...],
    where: str,
    progress: Callable[[int, int], None] | None,
) -> tuple[BaseParameters, FloatArray, FloatArray]:
    """The base parameters, the base regressor ``W (N, 3, B)`` of the efforts and the known
    efforts: of the 3-PRP its ``f10`` and its elements' and fixed parameters' forces; of a
    family robot its ``tau``, its ``[load]``'s and the fixed parameters' efforts."""
    if not isinstance(robot, FamilyRobot):
        refuse_mu(robot)
        base = base_parameters(robot, ("f10",), names)
        check_samples(base, motion.samples, where)
        known = known_forces(robot, motion, fixed)
        W = regressor(robot, motion, names, progress=progress).f10[..., list(base.independent)]
        return base, W, known
    base = base_parameters(robot, FAMILY_FORCES, names)
    check_samples(base, motion.samples, where)
    Y = family_regressor(robot, motion, every, progress=progress).tau
    columns = [every.index(name) for name in fixed]
    known = family_known_forces(robot, motion)
    if fixed:
        known = known + Y[..., columns] @ family_standard_parameters(robot, fixed)
    return base, Y[..., [every.index(names[j]) for j in base.independent]], known


def check_samples(base: BaseParameters, samples: int, where: str) -> None:
    """Raise the :class:`~prp3.errors.TrajectoryError` of :func:`samples_refusal` (naming
    ``where``) when ``samples`` samples are too few for ``base``."""
    too_few = samples_refusal(base, samples)
    if too_few is not None:
        raise TrajectoryError(f"{where}: {too_few}")


def fit_base_parameters(
    base: BaseParameters,
    W: FloatArray,
    measured: FloatArray,
    t: FloatArray,
    where: str,
    *,
    known: FloatArray | float = 0.0,
    fixed: tuple[str, ...] = (),
) -> Identification:
    """Steps 2–4 of :func:`identify`, shared by every robot: the excitation refusal, the
    two-pass weighted least squares of ``measured − known`` on the base regressor
    ``W (N, legs, B)``, and the :class:`Identification` (``t``: the sample times, s).

    Raises
    ------
    TrajectoryError
        ``W`` does not excite a base parameter (naming ``where``).
    ParameterError
        Key ``measured``: values so large that the least squares overflow.
    """
    target = measured - known
    stacked = W.reshape(-1, base.count)
    refused = excitation_refusal(base, stacked)
    if refused is not None:
        raise TrajectoryError(
            f"{where}: {refused}; move every coordinate, e.g. along a trajectory of prp3 excite"
        )
    estimate, std, sigma = weighted_least_squares(W, target, names=base.labels)
    fitted = W @ estimate + known
    return Identification(
        base=base,
        estimate=estimate,
        std=std,
        condition=float(np.linalg.cond(stacked)),
        sigma=sigma,
        residual_rms=np.sqrt(((measured - fitted) ** 2).mean(axis=0)),
        t=np.asarray(t, dtype=np.float64),
        measured=measured,
        fitted=fitted,
        fixed=fixed,
    )


def samples_refusal(base: BaseParameters, samples: int) -> str | None:
    """Why :func:`identify` refuses ``samples`` samples for ``base``: too few; ``None`` if not.

    At least :data:`MIN_SAMPLES_PER_PARAMETER` samples per base parameter.
    ``prp3 excite`` asks the same of the trajectory it writes.

    >>> from prp3.apps.base_parameters import base_parameters
    >>> samples_refusal(base_parameters(Robot()), 20)
    '20 samples are too few to identify 7 base parameters (at least 5 per parameter: 35)'
    """
    needed = MIN_SAMPLES_PER_PARAMETER * base.count
    if samples >= needed:
        return None
    return (
        f"{samples} samples are too few to identify {base.count} base parameters "
        f"(at least {MIN_SAMPLES_PER_PARAMETER} per parameter: {needed})"
    )


def excitation_refusal(base: BaseParameters, stacked: FloatArray) -> str | None:
    """Why :func:`identify` refuses a motion as not exciting; ``None`` if it excites ``base``.

    The one criterion of identification, which ``prp3 excite``
    (:func:`prp3.apps.excitation.exciting_trajectory`) applies to the motion
    it designs: every base parameter is excited when the column of ``stacked``
    that multiplies it, scaled to unit norm, is farther than 1e-6 from the
    span of the columns before it (greedy Gram–Schmidt).

    Parameters
    ----------
    base : BaseParameters
        The base parameters, one column of ``stacked`` each, in their order.
    stacked : ndarray, shape (3N, B)
        The base regressor of ``f10`` of the ``N`` samples, stacked (SI units).

    Returns
    -------
    str or None
        ``"the motion does not excite the base parameter(s) ... (regressor rank
        r < B: ... condition number c ...)"``, or ``None``.
    """
    kept = independent_columns(stacked, _EXCITATION_TOLERANCE)[0]
    if len(kept) >= base.count:
        return None
    missing = [b for b in range(base.count) if b not in kept]
    norms = np.linalg.norm(stacked, axis=0)
    condition = float(np.linalg.cond(stacked / np.where(norms > 0.0, norms, 1.0)))
    return (
        f"the motion does not excite the base parameter(s) "
        f"{', '.join(repr(base.label(b)) for b in missing)} (regressor rank {len(kept)} < "
        f"{base.count}: its unit columns have condition number {condition:.3g}; identification "
        f"needs each one farther than 1e-6 from the span of the others)"
    )


def weighted_least_squares(
    W: FloatArray, measured: FloatArray, *, names: Sequence[str] | None = None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Two-pass weighted least squares of ``measured ≈ W·β``, for one or many data sets.

    First pass: ordinary least squares; ``σ_j = ‖r_j‖ / √(N − B/A)`` is the
    residual standard deviation of actuator ``j`` (``A`` actuators).  Second
    pass: the rows of actuator ``j`` divided by ``σ_j``; the covariance of the
    estimate is ``s²·(AᵀA)⁻¹`` with ``s² = ‖r_w‖² / (A·N − B)`` (solved by SVD).

    Parameters
    ----------
    W : ndarray, shape (N, A, B)
        The base regressor of ``A`` actuators (3 of the planar robots, one per leg
        of a spatial robot).
    measured : ndarray, shape (..., N, A)
        One data set, or a stack of them (vectorised: e.g. many noise draws).
    names : sequence of str, optional
        The parameters of the ``B`` columns, to name them in messages
        (default: ``column 0``, ``column 1``, ...).

    Raises
    ------
    ParameterError
        ``W`` or ``measured`` not finite real arrays of these shapes, fewer
        rows than parameters (``A·N <= B``), a rank-deficient ``W`` (names the
        columns not identifiable: zero, or a combination of the others to
        ``1e-9`` after scaling each to unit norm), or results too large for
        double precision.

    Returns
    -------
    estimate, std : ndarray, shape (..., B)
        The estimate and its standard deviations.
    sigma : ndarray, shape (..., A)
        The weights: first-pass residual standard deviation per actuator.

    Examples
    --------
    >>> W = np.stack([np.ones((20, 3)), np.linspace(0, 1, 60).reshape(20, 3)], axis=-1)
    >>> estimate, std, sigma = weighted_least_squares(W, W @ np.array([2.0, -1.0]))
    >>> np.round(estimate, 12).tolist()
    [2.0, -1.0]
    >>> weighted_least_squares(W[..., [0, 0]], W @ np.array([2.0, -1.0]), names=("a", "b"))
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: W: the parameters 'a', 'b' are not identifiable (rank 1 < 2: their columns are zero or combinations of each other)
    """
    W, target, _ = _check_least_squares(W, measured, names)
    samples, _, count = W.shape
    stacked = W.reshape(-1, count)
    with np.errstate(all="ignore"):  # an overflow is refused below
        try:
            estimate, std, sigma = _two_passes(W, target, stacked, samples, count)
        except np.linalg.LinAlgError:  # the SVD of overflowed weights does not converge
            estimate = std = sigma = np.full(count, np.nan)
    if not (np.isfinite(estimate).all() and np.isfinite(std).all() and np.isfinite(sigma).all()):
        sets = np.abs(target).reshape(-1, samples, target.shape[-1])
        k, j = (int(v) for v in np.unravel_index(int(np.argmax(sets.max(axis=0))), sets.shape[1:]))
        raise ParameterError(
            "measured or W is too large for double precision: the least squares overflow; "
            f"the largest measured value is {float(sets[:, k, j].max())!r} (actuator {j}), the "
            f"largest of W {float(np.abs(W).max())!r}",
            key="measured",
            sample=k,
        )
    return estimate, std, sigma


def _check_least_squares(
    W: object, measured: object, names: object
) -> tuple[FloatArray, FloatArray, tuple[str, ...]]:
    """The validated arguments of :func:`weighted_least_squares` and the columns' labels."""
    matrix = check_real("W", W, ParameterError)  # type: ignore[arg-type]
    if matrix.ndim != 3 or 0 in matrix.shape:
        raise ParameterError(
            f"W must have shape (N, A, B) with N, A, B >= 1 (A actuators), got {matrix.shape}",
            key="W",
        )
    samples, actuators, count = matrix.shape
    if actuators * samples <= count:
        raise ParameterError(
            f"W has {actuators * samples} rows for {count} parameters: least squares needs more rows "
            "than parameters",
            key="W",
        )
    _refuse_non_finite("W", matrix)
    target = check_real("measured", measured, ParameterError)  # type: ignore[arg-type]
    if target.ndim < 2 or target.shape[-2:] != (samples, actuators):
        raise ParameterError(
            f"measured must have shape (..., {samples}, {actuators}) to match W, got {target.shape}",
            key="measured",
        )
    _refuse_non_finite("measured", target)
    if names is None:
        labels = tuple(str(j) for j in range(count))
    else:
        if isinstance(names, str) or not isinstance(names, Sequence):
            raise ParameterError(
                f"names must be a sequence of {count} strings or None, got {names!r}", key="names"
            )
        labels = tuple(names)
        if len(labels) != count or not all(isinstance(label, str) for label in labels):
            raise ParameterError(
                f"names must be {count} strings (one per column of W), got {names!r}",
                key="names",
            )
        labels = tuple(repr(label) for label in labels)
    stacked = matrix.reshape(-1, count)
    with np.errstate(all="ignore"):
        norms = np.linalg.norm(stacked, axis=0)
    if not np.isfinite(norms).all():
        raise ParameterError(
            "W is too large for double precision: the norms of its columns overflow", key="W"
        )
    zero = ~(norms > 0.0)
    unit = stacked / np.where(zero, 1.0, norms)
    _, singular, vt = np.linalg.svd(unit, full_matrices=False)
    null = vt[singular <= _RANK_TOLERANCE * max(float(singular[0]), 1.0)]
    involved = zero | (np.abs(null) > 1e-6).any(axis=0)
    if involved.any():
        rank = count - len(null)
        bad = [labels[j] for j in range(count) if involved[j]]
        what = "the parameters" if names is not None else "columns"
        raise ParameterError(
            f"W: {what} {', '.join(bad)} are not identifiable (rank {rank} < {count}: "
            "their columns are zero or combinations of each other)",
            key="W",
        )
    return matrix, target, labels


def _refuse_non_finite(name: str, array: FloatArray) -> None:
    """Refuse the first non-finite value of ``array``, naming its index."""
    bad = np.argwhere(~np.isfinite(array))
    if bad.size:
        index = tuple(bad[0].tolist())
        where = ", ".join(str(i) for i in index)
        raise ParameterError(f"{name}[{where}] is not finite ({float(array[index])!r})", key=name)


def _two_passes(
    W: FloatArray, target: FloatArray, stacked: FloatArray, samples: int, count: int
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The ordinary then the weighted pass of :func:`weighted_least_squares`."""
    first = np.einsum(
        "bk,...k->...b", np.linalg.pinv(stacked), target.reshape(*target.shape[:-2], -1)
    )
    residual = target - np.einsum("nlb,...b->...nl", W, first)
    actuators = W.shape[1]
    sigma = np.sqrt((residual**2).sum(axis=-2) / (samples - count / actuators))
    floor = 1e-12 * np.sqrt((target**2).mean(axis=-2)).max(axis=-1, keepdims=True) + 1e-300
    sigma = np.maximum(sigma, floor)
    A = (W / sigma[..., None, :, None]).reshape(*sigma.shape[:-1], -1, count)
    b = (target / sigma[..., None, :]).reshape(*sigma.shape[:-1], -1)
    U, S, Vt = np.linalg.svd(A, full_matrices=False)
    coordinates = np.einsum("...nb,...n->...b", U, b) / S
    estimate = np.einsum("...bk,...b->...k", Vt, coordinates)
    weighted = b - np.einsum("...nk,...k->...n", A, estimate)
    s2 = (weighted**2).sum(axis=-1) / (actuators * samples - count)
    variance = np.einsum("...bk,...b->...k", Vt**2, 1.0 / S**2) * s2[..., None]
    return estimate, np.sqrt(variance), sigma


# ------------------------------------------------------ physical parameters
def _all_standard(nominal: Robot | FamilyRobot) -> dict[str, float]:
    """Every standard parameter of ``nominal`` (and its element fields), by name."""
    if isinstance(nominal, FamilyRobot):
        values = family_standard_parameters(nominal).tolist()
        return dict(zip(FAMILY_PARAMETERS, values, strict=True))
    return dict(zip(PARAMETERS, standard_parameters(nominal, PARAMETERS).tolist(), strict=True))


def _platform_from_standard(
    values: Mapping[str, float], payload: Payload, round_off: float
) -> tuple[float, float, Payload]:
    """The platform's mass and inertia about ``G`` and the payload of ``(m3, h3, J3)``."""
    mass, inertia = values["platform_mass"], values["platform_inertia"]
    h3 = (values["platform_moment_x"], values["platform_moment_y"])
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
    elif not mass > 0.0:
        raise ParameterError(f"m3 = {mass!r} kg: a mass must be positive")
    if -round_off * mass <= inertia < 0.0:
        inertia = 0.0
    if not inertia >= 0.0:
        raise ParameterError(
            f"J3 = {values['platform_inertia']!r} kg m^2: the platform inertia about G would "
            "be negative"
        )
    return mass, inertia, payload


def _family_from_standard(nominal: FamilyRobot, values: Mapping[str, float]) -> FamilyRobot:
    """:func:`robot_from_standard` of a family robot: its links and platform."""
    round_off = 1e-12 * nominal.leg.scale**2  # kg·m² per kg: an inertia of round-off size
    links = []
    for k, body in ((1, nominal.link1), (2, nominal.link2)):
        m = values[f"link{k}_mass"]
        hx, hy = values[f"link{k}_moment_x"], values[f"link{k}_moment_y"]
        J = values[f"link{k}_inertia"]
        if not m >= 0.0:
            raise ParameterError(f"m{k} = {m!r} kg: link {k}'s mass would be negative")
        if m > 0.0:
            com = (hx / m, hy / m)
        elif abs(hx) + abs(hy) <= 1e-12 * nominal.leg.scale:
            com = body.com
        else:
            raise ParameterError(
                f"h{k} = ({hx!r}, {hy!r}) kg m with m{k} = 0: a first moment needs a mass"
            )
        inertia = J - m * (com[0] ** 2 + com[1] ** 2)
        if -round_off * max(m, 1.0) <= inertia < 0.0:
            inertia = 0.0
        if not inertia >= 0.0:
            raise ParameterError(
                f"J{k} = {J!r} kg m^2 is less than m{k}·|c{k}|^2 = "
                f"{m * (com[0] ** 2 + com[1] ** 2)!r}: link {k}'s inertia about its centre of "
                "mass would be negative"
            )
        links.append(Body(m, com, inertia, name=f"link{k}"))
    mass, inertia, payload = _platform_from_standard(values, nominal.payload, round_off)
    return replace(
        nominal,
        link1=links[0],
        link2=links[1],
        platform=PlatformBody(mass, inertia),
        payload=payload,
    )


def robot_from_standard(
    nominal: Robot | FamilyRobot, standard: dict[str, float]
) -> Robot | FamilyRobot:
    """The robot with the parameters ``standard`` (the others from ``nominal``).

    The inverse of :func:`prp3.mechanics.parameters.kernel_parameters`: ``c = h/m``,
    ``I2 = J2 − m2·|c2|²`` about the centre of mass.  The platform side
    ``(m3, h3, J3)`` is the platform and its payload together: with a payload
    in ``nominal``, its mass and own inertia are kept and the platform mass,
    the payload's centre of mass ``h3/m_p`` and the platform inertia
    ``J3 − I_p − |h3|²/m_p`` are solved; without one, ``h3`` must be zero.
    Friction coefficients replace ``nominal``'s (its ``μ``, smoothing and pin
    radius are kept).  The piston inertia (it never enters the dynamics),
    geometry, gravity, limits and load are ``nominal``'s.  Of a family robot
    (names :data:`~prp3.apps.family_regressor.FAMILY_PARAMETERS`), links 1 and
    2 likewise (``c_k = h_k/m_k``, ``I_k = J_k − m_k·|c_k|²``; a link of mass 0
    keeps its nominal ``com``) and the platform as above.

    Raises
    ------
    ParameterError
        ``nominal`` not a robot, ``standard`` not a mapping of known parameter
        names to finite numbers, a non-positive mass, a negative inertia about
        a centre of mass or a negative friction coefficient (names the
        parameter and its value).

    Examples
    --------
    >>> robot = robot_from_standard(Robot(), {"link_moment_x": 0.015, "link_inertia": 1e-3})
    >>> robot.link.com, round(robot.link.inertia, 12)
    ((0.02, 0.0), 0.0007)
    """
    if not isinstance(nominal, FamilyRobot):
        check_robot(nominal, "nominal")
    if not isinstance(standard, Mapping):
        raise ParameterError(
            f"standard must be a mapping of parameter names to numbers, got {standard!r}",
            key="standard",
        )
    values = _all_standard(nominal)
    for name, value in standard.items():
        check_names("standard", [name], tuple(values), item="parameter")
        values[name] = check_scalar(f"standard[{name!r}]", value)
    if isinstance(nominal, FamilyRobot):
        return _family_from_standard(nominal, values)
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
    mass, inertia, payload = _platform_from_standard(values, nominal.payload, round_off)
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
    robot : Robot or FamilyRobot
        Geometry, gravity and limits of the nominal robot (a family robot's
        for a family nominal robot).
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

    robot: Robot | FamilyRobot
    solved: tuple[str, ...]
    kept: tuple[str, ...]
    clamped: tuple[str, ...] = ()


#: Most choices of solved parameters :func:`identified_robot` tries.
_MAX_CHOICES: int = 4096


def _family_kept_values(nominal: FamilyRobot, values: dict[str, float]) -> dict[str, float]:
    """:func:`_kept_values` of a family robot: its links' centres of mass and inertias."""
    kept = _all_standard(nominal)
    for k, body in ((1, nominal.link1), (2, nominal.link2)):
        m = values[f"link{k}_mass"]
        hx, hy = values[f"link{k}_moment_x"], values[f"link{k}_moment_y"]
        kept[f"link{k}_moment_x"] = m * body.com[0]
        kept[f"link{k}_moment_y"] = m * body.com[1]
        kept[f"link{k}_inertia"] = body.inertia + ((hx * hx + hy * hy) / m if m > 0 else 0.0)
    payload = nominal.payload
    if payload.mass > 0.0:
        h3x, h3y = values["platform_moment_x"], values["platform_moment_y"]
        kept["platform_inertia"] = (
            nominal.platform.inertia + payload.inertia + (h3x * h3x + h3y * h3y) / payload.mass
        )
    return kept


def _kept_values(nominal: Robot | FamilyRobot, values: dict[str, float]) -> dict[str, float]:
    """The parameters of ``nominal``'s physical ones, with the current masses and moments.

    A kept first moment keeps the nominal centre of mass (``h = m·c``), a kept
    inertia the nominal inertia about the centre of mass (``J2 = I2 + |h2|²/m2``,
    ``J3 = I3 + I_p + |h3|²/m_p`` with a payload), whatever the masses and
    moments solved; friction coefficients are kept as they are.
    """
    if isinstance(nominal, FamilyRobot):
        return _family_kept_values(nominal, values)
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
    nominal: Robot | FamilyRobot, base: BaseParameters, estimate: FloatArray, solved: list[int]
) -> dict[str, float]:
    """Standard parameters: ``solved`` from the base parameters, the others kept (physically)."""
    names = base.parameters
    C = base.combination
    others = [j for j in range(len(names)) if j not in solved]
    values = _all_standard(nominal)
    for _ in range(4):  # masses, then moments, then inertias: a fixed point in 3 passes
        kept = _kept_values(nominal, values)
        fixed = np.array([kept[names[j]] for j in others])
        rhs = estimate - C[:, others] @ fixed
        for j, v in zip(others, fixed.tolist(), strict=True):
            values[names[j]] = v
        for j, v in zip(solved, np.linalg.solve(C[:, solved], rhs).tolist(), strict=True):
            values[names[j]] = v
    return values


def _clamped_estimate(
    nominal: Robot | FamilyRobot, result: Identification
) -> tuple[FloatArray, list[str]]:
    """The base estimate with what is zero within its noise written as 0: a friction
    coefficient estimated just below 0, and (no payload) the platform's first moments; with
    the names of those clamped."""
    estimate = result.estimate.copy()
    clamped = []
    without_payload = not nominal.payload.mass > 0.0
    length = nominal.leg.scale if isinstance(nominal, FamilyRobot) else nominal.l0
    moment_floor = 1e-9 * nominal.platform.mass * length  # kg m: round-off of h3
    roundoff = 1e-12 * float(np.abs(result.measured).max())  # of the forces: N (N s/m at 1 m/s)
    base = result.base
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
    return estimate, clamped


def identified_robot(nominal: Robot | FamilyRobot, result: Identification) -> IdentifiedRobot:
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
    ``nominal`` a ``[payload]``).  A family nominal robot (docs/family.md) gives
    a family robot the same way (``l0`` there is its ``leg.scale``).

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
        ``nominal`` not a robot, ``result`` not an :class:`Identification`, or
        no choice gives a physically valid robot (names the first failure).
    """
    if not isinstance(nominal, FamilyRobot):
        check_robot(nominal, "nominal")
    check_instance("result", result, Identification, "a prp3 Identification (from identify)")
    base = result.base
    family = isinstance(nominal, FamilyRobot)
    if family != (base.forces == FAMILY_FORCES):
        raise ParameterError(
            f"nominal is a {'family robot' if family else '3-PRP'} but result identifies a "
            f"{'family robot' if base.forces == FAMILY_FORCES else '3-PRP'}: give "
            "identified_robot the nominal robot given to identify",
            key="result",
        )
    estimate, clamped = _clamped_estimate(nominal, result)
    roundoff = 1e-12 * float(np.abs(result.measured).max())  # of the forces: N (N s/m at 1 m/s)
    every = _all_standard(nominal)
    nominal_values = np.array([every[name] for name in base.parameters])
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
        kept = tuple(name for name in every if name not in solved_names)
        return IdentifiedRobot(robot=robot, solved=solved_names, kept=kept, clamped=tuple(clamped))
    raise ParameterError(
        f"the identified base parameters give no physically valid robot ({first_error})"
    )
