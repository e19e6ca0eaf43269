"""The paper's recursive matrix method, as printed (Staicu & Chablat, eqs. 1–25).

A reference implementation that follows the paper's own formulation line by
line: 3-D vectors and 3×3 matrices in the local frames ``T0 … T3`` of each leg
(the plane motion embedded in 3-D), the recursive relations of the kinematics
and the compact virtual-work relations of the dynamics.  It shares nothing with
:mod:`prp3.mechanics.geometry`'s inverse geometry, :mod:`prp3.mechanics.kinematics`,
:mod:`prp3.mechanics.kernel`, :mod:`prp3.engines.entries` or Newton–Euler but the leg angles
``α_i`` (eq. 1) and the input checks, so that it checks them.

The stages of the paper are functions of :mod:`prp3.references.paper_kinematics` (the
frames and the kinematics, eqs. 2–18) and :mod:`prp3.references.paper_wrenches` (the
dynamics, eqs. 19–25); :mod:`prp3.references.paper_evaluation` chains them for
a chunk of samples with the effects beyond the paper (the load, the joint
friction, the spring, and the ``μ`` terms' fixed point), and this module runs
them over a motion in chunks: :func:`recursive_matrix_method`
keeps every quantity, :func:`paper_inverse_dynamics` the forces, and
:func:`paper_method` the kinematics and the forces that ``--method paper``
writes, all of them by the paper's recursion.

Frames of leg ``i`` (``q = a, b, c`` for ``i = A, B, C``), eqs. (2)–(3)::

    a10 = θ1·θα^i,   a21 = a21^φ·θ1ᵀ,   a32 = θ1·θ2,   a_k0 = a_k,k-1 ··· a10

``a_k,k-1`` maps the components of a vector in frame ``T_{k-1}`` to its
components in ``T_k``.  With them ``z1 = a10ᵀu3`` is the actuator axis
``e_i``, ``y1 = a10ᵀu2`` its normal ``n_i``, ``z2 = z0`` the axis of the
revolute joint ``A2 = P_i`` and ``z3 = a30ᵀu3`` the platform edge ``d_i``;
``x1 = x3 = −z0``.  Bodies ``k = 1, 2, 3`` are piston 1, link 2 and the
platform; ``A_k`` is the origin of ``T_k`` (``A1 = A2 = P_i``, ``A3`` on the
platform edge at ``λ32`` from ``A2``).

Readings of the print (``docs/conventions.md``):

* eq. (17): ``a20`` stands for ``a20ᵀ``;
* eqs. (24)–(25): ``ω21^Bv, ω21^Cv`` stand for ``ω21a^Bv, ω21a^Cv``, the
  virtual velocities of the set of eq. (16) that belongs to the force computed;
* eq. (19): the weight is ``m_k·q_k0·g`` with the gravity vector ``g`` of the
  robot (the paper's ``9.81·u2`` is ``g`` with its ``y0`` axis pointing down);
* eq. (20): ``Ĵ_k`` inside the braces ``m_k{…}`` is the inertia tensor about
  ``A_k`` per unit mass (else the units do not match); it holds the body's
  ``I_zz`` about its centre of mass, moved to ``A_k`` by the parallel axes;
* eq. (21): the platform belongs to chain A (the paper's "first and more
  complicated open tree system"): ``F_3 = M_3 = 0`` in chains B and C.

Arrays: time on the leading axis (none for a single sample), then legs
``A, B, C``, then bodies ``k = 1, 2, 3``, then the components in frame
``T_k``; a vector is ``(..., 3, 3, 3)``, a matrix ``(..., 3, 3, 3, 3)``.

>>> from prp3.model.motion import paper_motion
>>> result = recursive_matrix_method(Robot(), paper_motion("vertical", samples=31))
>>> result.f10.shape, result.a.shape, result.omega_tilde.shape
((31, 3), (31, 3, 3, 3, 3), (31, 3, 3, 3, 3))
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray

from prp3.errors import TrajectoryError
from prp3.mechanics.forces import InverseDynamics
from prp3.mechanics.geometry import InverseGeometry, check_stroke
from prp3.mechanics.kinematics import Kinematics
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.pose_validation import check_poses
from prp3.references.paper_evaluation import evaluate_loaded
from prp3.references.paper_kinematics import FixedFrameKinematics
from prp3.validation import OVERFLOW_REASON, check_robot, first_non_finite

__all__ = [
    "FORCE_SETS",
    "MAX_RECORDED_SAMPLES",
    "PAPER_CHUNK",
    "RecursiveMatrixResult",
    "paper_inverse_dynamics",
    "paper_method",
    "recursive_matrix_method",
]

FloatArray = NDArray[np.float64]

#: Samples evaluated at once (bounds the temporaries to a few tens of MiB).
PAPER_CHUNK: int = 1024

#: Largest motion :func:`recursive_matrix_method` records (its result holds
#: about 7 kB per sample); :func:`paper_inverse_dynamics` takes any length.
MAX_RECORDED_SAMPLES: int = 20_000

#: The forces of eqs. (23)–(25), in the order of the sets of eq. (16).
FORCE_SETS: tuple[str, str, str] = ("f10", "f21y", "f21z")


@dataclass(frozen=True)
class RecursiveMatrixResult:
    """The paper's quantities per sample, leg and body, in the paper's frames.

    ``...`` is the batch shape of the motion (``(N,)`` or ``()``).  Axes after
    it: leg ``i = A, B, C``; body ``k = 1, 2, 3`` (piston, link 2, platform);
    components in frame ``T_k`` of leg ``i`` unless said otherwise.  SI units.

    Attributes
    ----------
    motion : Motion
        The platform motion (eq. 4 for the paper's examples).
    lambda10, lambda32, phi21 : ndarray (..., 3)
        ``λ10^i, λ32^i`` (m) from eq. (10) as printed, ``φ21^i = φ`` (rad) eq. (7).
    a : ndarray (..., 3, 3, 3, 3)
        ``a_k,k-1`` (eqs. 2–3): ``a[..., i, 0] = a10``, ``a21``, ``a32``.
    a0 : ndarray (..., 3, 3, 3, 3)
        ``a_k0 = a_k,k-1 ··· a10`` (eq. 3).
    r : ndarray (..., 3, 3, 3)
        ``r_k,k-1`` (eqs. 8–9): ``r10`` (the position of ``A1``) in ``T0``,
        ``r21 = 0`` in ``T1``, ``r32 = λ32·a32ᵀu3`` in ``T2``.
    position : ndarray (..., 3, 3, 3)
        Position of the joint ``A_k`` in ``T0``: the partial sums of eq. (8).
    centre : ndarray (..., 3, 3)
        ``r0^G`` rebuilt from every leg by eq. (8), in ``T0`` (the pose's ``G``).
    v10, v32, omega21 : ndarray (..., 3)
        Relative velocities ``v10^i, v32^i`` (m/s) of eq. (14) and ``ω21^i = φ̇`` (rad/s).
    gamma10, gamma32, epsilon21 : ndarray (..., 3)
        Relative accelerations ``γ10^i, γ32^i`` (m/s²) of eq. (17) and ``ε21^i = φ̈``.
    omega_tilde : ndarray (..., 3, 3, 3, 3)
        ``ω̃_k0`` of eq. (11) (rad/s).
    omega : ndarray (..., 3, 3, 3)
        ``ω_k0``, the vectors associated to ``ω̃_k0`` (eq. 12).
    v : ndarray (..., 3, 3, 3)
        ``v_k0`` of eq. (13): absolute velocity of ``A_k`` (m/s).
    epsilon : ndarray (..., 3, 3, 3)
        ``ε_k0`` of eq. (18) (rad/s²).
    omega2_epsilon : ndarray (..., 3, 3, 3, 3)
        ``ω̃_k0·ω̃_k0 + ε̃_k0`` by the matrix recursion of eq. (18) (1/s²).
    gamma : ndarray (..., 3, 3, 3)
        ``γ_k0`` of eq. (18): absolute acceleration of ``A_k`` (m/s²).
    r_C : ndarray (3, 3, 3)
        ``r_k^C``: centre of mass of body ``k`` from ``A_k`` (m); ``r_3^C = r3^G`` (eq. 8).
    J : ndarray (3, 3, 3, 3)
        ``Ĵ_k`` of eq. (20): inertia about ``A_k`` per unit mass (m²).
    F_star, M_star : ndarray (..., 3, 3, 3)
        ``F_k*``, ``M_k*`` of eq. (19): weight and its moment about ``A_k`` (N, N·m).
    F_in, M_in : ndarray (..., 3, 3, 3)
        ``F_k^in``, ``M_k^in`` of eq. (20): inertia force and its moment about ``A_k``.
    F0, M0 : ndarray (..., 3, 3, 3)
        ``F_k0``, ``M_k0`` of eq. (22).  For ``k = 3`` every leg holds the
        platform's wrench about its own ``A3``.
    F, M : ndarray (..., 3, 3, 3)
        ``F_k``, ``M_k`` of eq. (21); ``F_3 = M_3 = 0`` in chains B and C.
    omega21_virtual : ndarray (..., 3, 3, 3)
        ``ω21^iv`` of eq. (15) for the virtual motions of eq. (16): entry
        ``[..., s, l, i]`` for force ``FORCE_SETS[s]`` of leg ``l`` (rad/s per unit).
    v32_virtual : ndarray (..., 3, 3, 3)
        ``v32^iv`` of eq. (15), indexed like ``omega21_virtual``.
    vG_virtual : ndarray (..., 3, 3, 3)
        ``v0^Gv`` of eq. (15) in ``T0``, entry ``[..., s, l, :]``.
    f10, f21y, f21z : ndarray (..., 3)
        Eqs. (23), (24), (25) (N).
    n10, m10, n32, m32 : ndarray (..., 3)
        The other reactions from the balances of piston 1 and link 2 (N, N·m).
    p10 : ndarray (..., 3)
        Input power ``f10·v10`` (W).
    fric10, fric21, fric32 : ndarray (..., 3) or None
        With a robot's ``[friction]``: the joint friction forces
        (``docs/loads_and_friction.md``), included in ``F_k*, M_k*``.
    iterations : ndarray (...) or None
        With ``μ`` terms: the fixed-point iterations of each sample.
    """

    motion: Motion
    lambda10: FloatArray
    lambda32: FloatArray
    phi21: FloatArray
    a: FloatArray
    a0: FloatArray
    r: FloatArray
    position: FloatArray
    centre: FloatArray
    v10: FloatArray
    v32: FloatArray
    omega21: FloatArray
    gamma10: FloatArray
    gamma32: FloatArray
    epsilon21: FloatArray
    omega_tilde: FloatArray
    omega: FloatArray
    v: FloatArray
    epsilon: FloatArray
    omega2_epsilon: FloatArray
    gamma: FloatArray
    r_C: FloatArray  # noqa: N815 - the paper's r_k^C
    J: FloatArray
    F_star: FloatArray
    M_star: FloatArray
    F_in: FloatArray
    M_in: FloatArray
    F0: FloatArray
    M0: FloatArray
    F: FloatArray
    M: FloatArray
    omega21_virtual: FloatArray
    v32_virtual: FloatArray
    vG_virtual: FloatArray  # noqa: N815 - the paper's v0^Gv
    f10: FloatArray
    f21y: FloatArray
    f21z: FloatArray
    n10: FloatArray
    m10: FloatArray
    n32: FloatArray
    m32: FloatArray
    p10: FloatArray
    fric10: FloatArray | None = None
    fric21: FloatArray | None = None
    fric32: FloatArray | None = None
    iterations: FloatArray | None = None

    def inverse_dynamics(self) -> InverseDynamics:
        """The forces as a :class:`prp3.mechanics.forces.InverseDynamics` (``method="paper"``).

        The signs are those of ``docs/model.md``: ``f10`` along ``+e_i`` on the
        piston, ``f21y, f21z`` of piston on link 2 along ``n_i, e_i``,
        ``n10, m10`` of the guide on the piston, ``n32, m32`` of link 2 on the
        platform (moments about ``P_i = A2``).
        """
        names = _FORCES + (_FRICTION if self.fric10 is not None else ())
        forces = {name: getattr(self, name) for name in names}
        if self.iterations is not None:
            forces["iterations"] = self.iterations
        return _to_inverse_dynamics(forces)


#: The per-leg results of eqs. (23)–(25) and the balances, and the power.
_FORCES: tuple[str, ...] = ("f10", "p10", "f21y", "f21z", "n10", "m10", "n32", "m32")

#: The friction forces (with a robot's ``[friction]``).
_FRICTION: tuple[str, ...] = ("fric10", "fric21", "fric32")

#: Quantities checked finite (the inputs are finite: a non-finite value is an overflow).
_CHECKED: tuple[str, ...] = ("lambda10", "lambda32", "v10", "v32", "gamma10", "gamma32", *_FORCES)

#: The fields of the fixed frame's kinematics (computed for :func:`paper_method` only).
_FIXED_FRAME: frozenset[str] = frozenset(f.name for f in fields(FixedFrameKinematics))

#: The kinematics :func:`paper_method` returns: the joint rates and the fixed frame's fields.
_KINEMATICS: tuple[str, ...] = (
    "lambda10", "lambda32", "phi21", "determinant", "v10", "v32", "omega21",
    "gamma10", "gamma32", "epsilon21", *sorted(_FIXED_FRAME),
)  # fmt: skip

#: Quantities that do not depend on the sample.
_CONSTANT = ("r_C", "J")


def _to_inverse_dynamics(forces: dict[str, FloatArray]) -> InverseDynamics:
    return InverseDynamics(**forces, method="paper")


def _checked_motion(robot: Robot, motion: Motion) -> tuple[FloatArray, FloatArray, FloatArray]:
    check_robot(robot)
    if not isinstance(motion, Motion):
        raise TrajectoryError(f"motion must be a prp3.Motion, got {motion!r}"[:200])
    pose = check_poses(motion.pose, robot).reshape(-1, 3)
    return pose, motion.velocity.reshape(-1, 3), motion.acceleration.reshape(-1, 3)


def _require_finite(chunk: dict[str, FloatArray], first: int, motion: Motion) -> None:
    """Raise :class:`TrajectoryError` naming the first sample (from ``first``) that overflowed."""
    found = first_non_finite({name: chunk[name] for name in _CHECKED}, chunk["f10"].shape[:1])
    if found is None:
        return
    index, name = found[0] + first, found[1]
    raise TrajectoryError(
        f"{OVERFLOW_REASON}: {name} is not finite; "
        "the motion or the robot's parameters are too large for double precision",
        subject="motion",
        sample=index,
        time=float(motion.t.reshape(-1)[index]),
    )


def _run(robot: Robot, motion: Motion, names: tuple[str, ...]) -> dict[str, FloatArray]:
    """The quantities ``names`` for every sample, evaluated ``PAPER_CHUNK`` samples at a time."""
    pose, velocity, acceleration = _checked_motion(robot, motion)
    load = None if motion.load is None else motion.load.reshape(-1, 3)
    if robot.friction is not None:
        names = names + _FRICTION + (("iterations",) if robot.friction.has_mu else ())
    fixed_frame = not _FIXED_FRAME.isdisjoint(names)
    total = pose.shape[0]
    out: dict[str, FloatArray] = {}
    lambda10 = np.empty((total, 3))
    for first in range(0, total, PAPER_CHUNK):
        rows = slice(first, first + PAPER_CHUNK)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            chunk = evaluate_loaded(
                robot, pose[rows], velocity[rows], acceleration[rows],
                None if load is None else load[rows], first, motion, fixed_frame,
            )  # fmt: skip
        _require_finite(chunk, first, motion)
        lambda10[rows] = chunk["lambda10"]
        for name in names:
            value = chunk[name]
            if name in _CONSTANT:
                out[name] = value
                continue
            if name not in out:
                out[name] = np.empty((total, *value.shape[1:]))
            out[name][rows] = value
    check_stroke(robot, lambda10, pose)
    if motion.t.ndim == 0:
        out = {name: value if name in _CONSTANT else value[0] for name, value in out.items()}
    return out


def recursive_matrix_method(robot: Robot, motion: Motion) -> RecursiveMatrixResult:
    """The paper's recursive matrix method with every intermediate quantity (eqs. 1–25).

    Parameters
    ----------
    robot : Robot
        Robot parameters (centres of mass, inertias, gravity, stroke limits).
    motion : Motion
        Platform motion, ``N <= MAX_RECORDED_SAMPLES`` samples or a single one.

    Returns
    -------
    RecursiveMatrixResult
        Per sample, leg and body, the paper's quantities in the paper's frames.

    Raises
    ------
    TrajectoryError
        ``motion`` is not a Motion, is longer than ``MAX_RECORDED_SAMPLES`` (use
        :func:`paper_inverse_dynamics`), or the results overflow.
    SingularPoseError, UnreachablePoseError
        A pose at ``φ ≡ π/3 (mod π)`` or outside the actuator strokes.

    Examples
    --------
    The static central configuration of the paper's robot: the actuator forces
    and, in ``T1`` of leg A, the wrench ``F1 = F10 + a21ᵀF2`` of eq. (21) of
    chain A (piston, link and platform), which carries their whole weight
    ``(1 + 0.75 + 3)·9.81 = 46.5975 N`` along ``y0``, ``a10·u2 = (0, 1/2, √3/2)``:

    >>> result = recursive_matrix_method(Robot(), Motion.at_rest([0.0, 0.0, 0.0]))
    >>> result.f10.round(4).tolist()
    [31.8589, -8.4957, -23.3632]
    >>> result.F[0, 0].round(4).tolist()
    [0.0, 23.2988, 40.3546]
    >>> (46.5975 * np.array([0.0, 0.5, np.sqrt(3) / 2])).round(4).tolist()
    [0.0, 23.2988, 40.3546]
    """
    if isinstance(motion, Motion) and motion.samples > MAX_RECORDED_SAMPLES:
        raise TrajectoryError(
            f"motion: {motion.samples} samples is more than the {MAX_RECORDED_SAMPLES} that "
            "recursive_matrix_method records; use paper_inverse_dynamics for the forces alone"
        )
    optional = _FRICTION + ("iterations",)
    names = tuple(
        f.name for f in fields(RecursiveMatrixResult) if f.name not in ("motion", *optional)
    )
    values = _run(robot, motion, names)
    for value in values.values():
        value.flags.writeable = False
    return RecursiveMatrixResult(motion=motion, **values)


def paper_inverse_dynamics(robot: Robot, motion: Motion) -> InverseDynamics:
    """Inverse dynamics by the paper's recursive matrix method, forces only (eqs. 1–25).

    The same computation as :func:`recursive_matrix_method`, evaluated
    ``PAPER_CHUNK`` samples at a time and keeping only the forces: memory
    proportional to the output for any ``N``.

    Returns
    -------
    InverseDynamics
        ``f10, p10, f21y, f21z, n10, m10, n32, m32`` with ``method="paper"``.

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> dyn = paper_inverse_dynamics(Robot(), paper_motion("vertical"))
    >>> dyn.f10.shape, dyn.method
    ((301, 3), 'paper')
    """
    return _to_inverse_dynamics(_run(robot, motion, _FORCES))  # with friction and iterations


def paper_method(robot: Robot, motion: Motion) -> tuple[Kinematics, InverseDynamics]:
    """Kinematics and inverse dynamics, every number by the paper's recursion (eqs. 1–25).

    What ``--method paper`` writes: the joint displacements of eq. (10), the
    rates of eqs. (14), (17), the joints and centres of mass in ``T0`` from the
    recursions of eqs. (11)–(13), (18) and the Jacobian of eq. (14)
    (:func:`prp3.references.paper_kinematics.fixed_frame_kinematics`), and the forces of
    :func:`paper_inverse_dynamics`; nothing from :mod:`prp3.mechanics.kinematics` or the
    kernel.  Any number of samples, ``PAPER_CHUNK`` at a time.

    Returns
    -------
    (Kinematics, InverseDynamics)
        As :func:`prp3.analysis.inverse_dynamics.inverse_dynamics` returns them (``method="paper"``).

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> kin, dyn = paper_method(Robot(), paper_motion("vertical", samples=7))
    >>> kin.dlambda10.shape, kin.geometry.joint.shape, kin.jacobian.shape, dyn.method
    ((7, 3), (7, 3, 2), (7, 3, 3), 'paper')
    """
    values = _run(robot, motion, _FORCES + _KINEMATICS)
    geometry = InverseGeometry(
        pose=np.asarray(motion.pose, dtype=np.float64),
        lambda10=values["lambda10"],
        lambda32=values["lambda32"],
        phi21=values["phi21"],
        joint=values["joint"],
        slide=values["slide"],
        slide_normal=values["slide_normal"],
        lever=values["lever"],
        determinant=values["determinant"],
    )
    kinematics = Kinematics(
        motion=motion,
        geometry=geometry,
        dlambda10=values["v10"],
        ddlambda10=values["gamma10"],
        dlambda32=values["v32"],
        ddlambda32=values["gamma32"],
        dphi21=values["omega21"],
        ddphi21=values["epsilon21"],
        **{name: values[name] for name in sorted(_FIXED_FRAME) if name not in _GEOMETRY},
    )
    forces = {name: value for name, value in values.items() if name not in _KINEMATICS}
    return kinematics, _to_inverse_dynamics(forces)


#: The fixed frame's fields that belong to :class:`~prp3.mechanics.geometry.InverseGeometry`.
_GEOMETRY: frozenset[str] = frozenset(("joint", "slide", "slide_normal", "lever"))
