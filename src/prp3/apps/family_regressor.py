"""The regressor of a family robot's actuator efforts: ``τ = Y·π + τ_known``, from the family kernel.

The actuator efforts of a :class:`~prp3.family.model.FamilyRobot` (docs/family.md §7)
are linear and homogeneous in the standard dynamic parameters ``π`` of its bodies, for
a fixed geometry, actuation and gravity:

- per link ``k = 1, 2`` of each leg, in the body's own frame ``F_k`` (docs/family.md
  §2: its origin ``O_k`` and its axes): ``m_k``, the first moment
  ``h_k = m_k·c_k`` (``c_k`` = the link's ``com``, m, in ``F_k``) and the inertia
  ``J_k = I_k + m_k·|c_k|²`` **about the frame's origin** ``O_k`` (``I_k``, the
  file's ``inertia``, is about the mass centre);
- the platform with its payload, in the platform frame about ``G``:
  ``m3 = m_platform + m_p``, ``h3 = m_p·c_p`` and
  ``J3 = I_platform + I_p + m_p·|c_p|²`` (as the 3-PRP's ``h3``, ``J3``);

(the family has no friction, docs/family.md §1: no friction columns).  The constant
``[load]`` adds a term that depends on no parameter (:func:`family_known_forces`).

The columns are the family's own kernel, not a second model: the kinematics of
the motion once (:func:`prp3.family.mechanics.family_kinematics`, the branch
followed from home), then the exact derivatives ``Y = ∂τ/∂π`` of the actuator
efforts of :func:`prp3.family.sample_mechanics.sample_dynamics` (the kernel the
numba route and the generated C run), recorded by forward differentiation of its
traced operations and emitted as numpy code once per architecture × actuated
joint (:mod:`prp3.family.regressor_kernel`: the chain rule from the file's
``m, c, I`` to ``π``); ``τ_known`` is the same kernel with every body massless.
The base parameters of a family robot are
:func:`prp3.apps.base_parameters.base_parameters` of it, the fit
:func:`prp3.apps.identification.identify` of it (docs/identification.md,
"Family robots").
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.errors import ParameterError
from prp3.family.mechanics import FamilyKinematics, family_kinematics, motion_batch
from prp3.family.model import FamilyRobot
from prp3.family.regressor_kernel import COLUMNS, regressor_batch
from prp3.model.motion import Motion
from prp3.validation import check_instance, check_integer, check_names, require_finite

__all__ = [
    "FAMILY_PARAMETERS",
    "FAMILY_PARAMETER_SYMBOLS",
    "FAMILY_PARAMETER_UNITS",
    "FamilyRegressor",
    "family_known_forces",
    "family_random_motion",
    "family_regressor",
    "family_standard_parameters",
    "unit_efforts",
]

FloatArray = NDArray[np.float64]

#: The standard parameters of a family robot, in the order of preference in which they
#: name a base parameter: the platform's, link 1's mass, then link 2's, then link 1's
#: (the order of the 3-PRP's :data:`prp3.apps.regressor.STANDARD_PARAMETERS`, link 1 in
#: the place of the piston).
FAMILY_PARAMETERS: tuple[str, ...] = (
    "platform_mass",
    "platform_moment_x",
    "platform_moment_y",
    "platform_inertia",
    "link1_mass",
    "link2_mass",
    "link2_moment_x",
    "link2_moment_y",
    "link2_inertia",
    "link1_moment_x",
    "link1_moment_y",
    "link1_inertia",
)

#: Short symbols (docs/identification.md, "Family robots").
FAMILY_PARAMETER_SYMBOLS: dict[str, str] = {
    "platform_mass": "m3",
    "platform_moment_x": "h3x",
    "platform_moment_y": "h3y",
    "platform_inertia": "J3",
    "link1_mass": "m1",
    "link1_moment_x": "h1x",
    "link1_moment_y": "h1y",
    "link1_inertia": "J1",
    "link2_mass": "m2",
    "link2_moment_x": "h2x",
    "link2_moment_y": "h2y",
    "link2_inertia": "J2",
}

#: SI units.
FAMILY_PARAMETER_UNITS: dict[str, str] = {
    name: {"mass": "kg", "moment_x": "kg m", "moment_y": "kg m", "inertia": "kg m^2"}[
        name.split("_", 1)[1]
    ]
    for name in FAMILY_PARAMETERS
}


def _check_names(parameters: Sequence[str], name: str = "parameters") -> tuple[str, ...]:
    return check_names(name, parameters, FAMILY_PARAMETERS, item="parameter")


def family_standard_parameters(
    robot: FamilyRobot, parameters: Sequence[str] = FAMILY_PARAMETERS
) -> FloatArray:
    """The standard parameters ``π`` of ``robot`` (module docstring: frames and points).

    >>> robot = FamilyRobot.default("3-RRR")
    >>> family_standard_parameters(robot, ("link1_moment_x", "link1_inertia")).round(12).tolist()
    [0.1, 0.013]
    """
    check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    values: dict[str, float] = {}
    for k, body in ((1, robot.link1), (2, robot.link2)):
        cx, cy = body.com
        values[f"link{k}_mass"] = body.mass
        values[f"link{k}_moment_x"] = body.mass * cx
        values[f"link{k}_moment_y"] = body.mass * cy
        values[f"link{k}_inertia"] = body.inertia + body.mass * (cx * cx + cy * cy)
    p = robot.payload
    px, py = p.com
    values["platform_mass"] = robot.platform.mass + p.mass
    values["platform_moment_x"] = p.mass * px
    values["platform_moment_y"] = p.mass * py
    values["platform_inertia"] = robot.platform.inertia + p.inertia + p.mass * (px * px + py * py)
    return np.array([values[name] for name in _check_names(parameters)])


@dataclass(frozen=True)
class FamilyRegressor:
    """The regressor of a family robot's motion: ``τ = Y·π + τ_known``.

    Attributes
    ----------
    parameters : tuple of str
        The standard parameters of the columns (:data:`FAMILY_PARAMETERS` names).
    tau : ndarray, shape (N, 3, P) or (3, P)
        ``Y`` of the actuator efforts of legs A, B, C (``Y @ π`` in N or N·m).
    q, dq : ndarray, shape (N, 3) or (3,)
        The actuated joint's value and rate of each leg (m or rad, per s).
    mu_leg : ndarray, shape (N, 3) or (3,)
        ``μ_leg`` of each leg (docs/family.md §6).
    mu_par : ndarray, shape (N,) or ()
        ``μ_par``.
    """

    parameters: tuple[str, ...]
    tau: FloatArray
    q: FloatArray
    dq: FloatArray
    mu_leg: FloatArray
    mu_par: FloatArray


def _kernel(kin: FamilyKinematics) -> tuple[FloatArray, FloatArray]:
    """``Y (N, 3, 12)`` (:data:`~prp3.family.regressor_kernel.COLUMNS`) and ``τ_known (N, 3)`` on ``kin``.

    Refused (:class:`~prp3.errors.TrajectoryError`, naming the sample) when a
    result is not finite, as the inverse dynamics refuses its efforts.
    """
    t, pose, velocity, acceleration = motion_batch(kin.motion)
    state = np.concatenate([pose, velocity, acceleration], axis=1)
    with np.errstate(all="ignore"):  # an overflow is refused below, named
        Y, known = regressor_batch(kin.robot, state, kin.q.reshape(-1, 9))
    require_finite({"tau": Y.reshape(-1, 36), "tau_known": known}, (t.size,), "motion", t)
    return Y, known


def unit_efforts(kin: FamilyKinematics, parameters: Sequence[str]) -> FloatArray:
    """The columns of the regressor on known kinematics ``kin``: shape ``(N, 3, P)``.

    ``kin`` is :func:`~prp3.family.mechanics.family_kinematics` of the motion
    for any robot of the same geometry, actuation and gravity (``kin.robot``'s);
    the columns are :func:`prp3.family.regressor_kernel.regressor_batch`'s.
    """
    names = _check_names(parameters)
    Y = _kernel(kin)[0]
    return Y[..., [COLUMNS.index(name) for name in names]]


def family_regressor(
    robot: FamilyRobot,
    motion: Motion,
    parameters: Sequence[str] = FAMILY_PARAMETERS,
    *,
    progress: Callable[[int, int], None] | None = None,
) -> FamilyRegressor:
    """The regressor ``Y`` of the actuator efforts of a family robot along ``motion``.

    ``Y @ family_standard_parameters(robot) + family_known_forces(robot, motion)``
    equals ``family_inverse_dynamics(robot, motion).tau`` to round-off.

    Parameters
    ----------
    robot : FamilyRobot
        Its geometry, actuation and gravity are used (its inertial parameters not).
    motion : Motion
        ``N`` samples or one (the outputs then lose the leading axis); no
        time-varying load (family robots take a ``[load]`` only).
    parameters : sequence of str
        The columns, from :data:`FAMILY_PARAMETERS` (default: all, in that order).
    progress : callable, optional
        ``progress(samples_done, N)`` when done.

    Raises
    ------
    ParameterError
        A bad ``robot``, ``parameters`` or ``progress``.
    TrajectoryError
        ``motion`` with a time-varying load.
    SingularPoseError, UnreachablePoseError
        As :func:`prp3.family.mechanics.family_kinematics`.

    Examples
    --------
    >>> from prp3.family.outputs import family_inverse_dynamics
    >>> from prp3.model.motion import paper_motion
    >>> robot, motion = FamilyRobot.default("3-RPR"), paper_motion("rotation", 31)
    >>> Y = family_regressor(robot, motion)
    >>> Y.tau.shape
    (31, 3, 12)
    >>> tau = family_inverse_dynamics(robot, motion).tau
    >>> bool(np.allclose(Y.tau @ family_standard_parameters(robot), tau, rtol=1e-12, atol=0))
    True
    """
    names = _check_names(parameters)
    if progress is not None and not callable(progress):
        raise ParameterError(
            f"progress must be a callable progress(done, total) or None, got {progress!r}",
            key="progress",
        )
    kin = family_kinematics(robot, motion)
    columns = unit_efforts(kin, names)
    samples = columns.shape[0]
    if progress is not None:
        progress(samples, samples)
    shape = motion.t.shape
    a = robot.actuated - 1
    return FamilyRegressor(
        parameters=names,
        tau=columns.reshape(*shape, 3, len(names)),
        q=kin.q[..., a],
        dq=kin.dq[..., a],
        mu_leg=kin.mu_leg,
        mu_par=kin.mu_par,
    )


def family_known_forces(robot: FamilyRobot, motion: Motion) -> FloatArray:
    """The actuator efforts that depend on no parameter: those of the robot's ``[load]``.

    The family kernel with every body massless and the robot's load; ``(N, 3)``
    (``(3,)`` for one sample).

    >>> from prp3.model.motion import paper_motion
    >>> family_known_forces(FamilyRobot.default("3-RRR"), paper_motion("vertical", 2)).tolist()
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """
    check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    return _kernel(family_kinematics(robot, motion))[1].reshape(*motion.t.shape, 3)


def family_random_motion(robot: FamilyRobot, samples: int, seed: int) -> Motion:
    """Random regular states about the robot's home pose (exciting every parameter).

    Poses within ``0.05·ℓ`` of the legs' mean home pose and ``0.15`` rad of its
    angle (``ℓ = leg.scale``), rates and accelerations of the robot's size; the
    amplitude is halved (up to 10 times) until the motion is reachable and
    regular.

    Raises
    ------
    ParameterError
        No such motion (the home pose is close to a singularity).
    """
    from prp3.errors import SingularPoseError, UnreachablePoseError

    check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    samples = check_integer("samples", samples, 1, 10**7)
    rng = np.random.default_rng(check_integer("seed", seed, 0, 2**63 - 1))
    length = robot.leg.scale
    centre = robot.home_poses.mean(axis=0)
    unit = rng.uniform(-1.0, 1.0, (samples, 3))
    scale = np.array([length, length, 1.0])
    velocity = rng.normal(size=(samples, 3)) * scale
    acceleration = rng.normal(size=(samples, 3)) * 3.0 * scale
    amplitude = np.array([0.05 * length, 0.05 * length, 0.15])
    for _ in range(10):
        motion = Motion(
            t=np.arange(samples, dtype=np.float64),
            pose=centre + unit * amplitude,
            velocity=velocity,
            acceleration=acceleration,
        )
        try:
            family_kinematics(robot, motion)
        except (SingularPoseError, UnreachablePoseError):
            amplitude = amplitude / 2.0
            continue
        return motion
    raise ParameterError(
        f"no regular random motion about the home pose {centre.tolist()} of the "
        f"{robot.architecture} (close to a singularity)"
    )
