"""The paper's recursive matrix method, as printed (Staicu & Chablat, eqs. 1–25).

A reference implementation that follows the paper's own formulation line by
line: 3-D vectors and 3×3 matrices in the local frames ``T0 … T3`` of each leg
(the plane motion embedded in 3-D), the recursive relations of the kinematics
and the compact virtual-work relations of the dynamics.  It shares nothing with
:mod:`prp3.geometry`'s inverse geometry, :mod:`prp3.kinematics`,
:mod:`prp3.kernel`, :mod:`prp3.fast` or Newton–Euler but the leg angles
``α_i`` (eq. 1) and the input checks, so that it checks them.

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

>>> from prp3.motion import paper_motion
>>> result = recursive_matrix_method(Robot(), paper_motion("vertical", samples=31))
>>> result.f10.shape, result.a.shape, result.omega_tilde.shape
((31, 3), (31, 3, 3, 3, 3), (31, 3, 3, 3, 3))
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray

from .errors import TrajectoryError
from .forces import InverseDynamics
from .geometry import ALPHA, check_poses, check_stroke
from .model import Robot
from .motion import Motion
from .validation import check_robot, first_non_finite

__all__ = [
    "FORCE_SETS",
    "MAX_RECORDED_SAMPLES",
    "PAPER_CHUNK",
    "THETA_1",
    "THETA_2",
    "U1",
    "U2",
    "U3",
    "U3_TILDE",
    "VIRTUAL_SETS",
    "RecursiveMatrixResult",
    "paper_inverse_dynamics",
    "recursive_matrix_method",
    "rot",
    "skew",
    "theta_alpha",
    "vee",
]

FloatArray = NDArray[np.float64]

SQRT3 = math.sqrt(3.0)

#: Samples evaluated at once (bounds the temporaries to a few tens of MiB).
PAPER_CHUNK: int = 1024

#: Largest motion :func:`recursive_matrix_method` records (its result holds
#: about 7 kB per sample); :func:`paper_inverse_dynamics` takes any length.
MAX_RECORDED_SAMPLES: int = 20_000

#: The unit vectors ``u1, u2, u3`` of eq. (9).
U1: FloatArray = np.array([1.0, 0.0, 0.0])
U2: FloatArray = np.array([0.0, 1.0, 0.0])
U3: FloatArray = np.array([0.0, 0.0, 1.0])

#: ``ũ3`` of eq. (9), the skew-symmetric matrix of ``u3``.
U3_TILDE: FloatArray = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])

#: ``θ1`` of eq. (2).
THETA_1: FloatArray = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])

#: ``θ2`` of eq. (2).
THETA_2: FloatArray = 0.5 * np.array([[1.0, -SQRT3, 0.0], [SQRT3, 1.0, 0.0], [0.0, 0.0, 2.0]])

#: The forces of eqs. (23)–(25), in the order of the sets of eq. (16).
FORCE_SETS: tuple[str, str, str] = ("f10", "f21y", "f21z")

#: The sets of unit virtual velocities of eq. (16), shape (3 forces, 3 legs l, 3 legs i,
#: 3 joint rates): entry ``[s, l, i]`` is ``(v10^iv, v21^iyv, v21^izv)`` of the virtual
#: motion that gives force ``FORCE_SETS[s]`` of leg ``l``.
VIRTUAL_SETS: FloatArray = np.einsum("sr,li->slir", np.eye(3), np.eye(3))

for _constant in (U1, U2, U3, U3_TILDE, THETA_1, THETA_2, VIRTUAL_SETS):
    _constant.flags.writeable = False


def rot(angle: FloatArray | float) -> FloatArray:
    """``rot(φ)`` of eq. (3) (and ``θα`` of eq. 2) for angles ``(...)``, shape ``(..., 3, 3)``.

    The matrix maps the components of a vector in a frame to its components in
    the frame turned by ``angle`` about the common ``z`` axis.

    >>> rot(math.pi / 2).round(12).tolist()
    [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    angle = np.asarray(angle, dtype=np.float64)
    c, s = np.cos(angle), np.sin(angle)
    zero, one = np.zeros_like(angle), np.ones_like(angle)
    rows = [
        np.stack([c, s, zero], -1),
        np.stack([-s, c, zero], -1),
        np.stack([zero, zero, one], -1),
    ]
    return np.stack(rows, axis=-2)


def theta_alpha(alpha: FloatArray | float) -> FloatArray:
    """``θα^i`` of eq. (2) for the angles ``α_i`` of eq. (1), shape ``(..., 3, 3)``.

    >>> theta_alpha(math.pi).round(12).tolist()
    [[-1.0, 0.0, 0.0], [-0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    return rot(alpha)


def skew(vector: FloatArray) -> FloatArray:
    """The skew-symmetric matrix ``ṽ`` of vectors ``(..., 3)``: ``ṽ·w = v × w``.

    >>> bool((skew(U3) == U3_TILDE).all())
    True
    """
    x, y, z = vector[..., 0], vector[..., 1], vector[..., 2]
    zero = np.zeros_like(x)
    rows = [np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)]
    return np.stack(rows, axis=-2)


def vee(matrix: FloatArray) -> FloatArray:
    """The vector ``v`` *associated* (eq. 12) to skew-symmetric matrices ``ṽ (..., 3, 3)``.

    >>> vee(skew(np.array([1.0, 2.0, 3.0]))).tolist()
    [1.0, 2.0, 3.0]
    """
    return np.stack([matrix[..., 2, 1], matrix[..., 0, 2], matrix[..., 1, 0]], axis=-1)


def _mv(matrix: FloatArray, vector: FloatArray) -> FloatArray:
    """``matrix·vector`` over the last axes."""
    return np.asarray((matrix @ vector[..., None])[..., 0])


def _T(matrix: FloatArray) -> FloatArray:
    """``matrixᵀ`` over the last two axes."""
    return np.swapaxes(matrix, -1, -2)


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    """``aᵀ·b`` over the last axis."""
    return np.asarray(np.sum(a * b, axis=-1))


#: ``a10 = θ1·θα^i`` (eq. 2) of the legs, shape (3, 3, 3); constant.
A10: FloatArray = THETA_1 @ theta_alpha(ALPHA)
#: ``a32 = θ1·θ2`` (eq. 2), shape (3, 3); the same for every leg, constant.
A32: FloatArray = THETA_1 @ THETA_2
A10.flags.writeable = False
A32.flags.writeable = False

#: The platform belongs to chain A (eq. 21): 1 for leg A, 0 for legs B and C.
_CHAIN_A: FloatArray = np.array([1.0, 0.0, 0.0])


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
        """The forces as a :class:`prp3.forces.InverseDynamics` (``method="paper"``).

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

#: Fixed-point iterations allowed for the ``μ`` terms of friction.
MU_MAX_ITERATIONS: int = 500

#: Quantities checked finite (the inputs are finite: a non-finite value is an overflow).
_CHECKED: tuple[str, ...] = ("lambda10", "lambda32", "v10", "v32", "gamma10", "gamma32", *_FORCES)

#: Quantities that do not depend on the sample.
_CONSTANT = ("r_C", "J")


def _to_inverse_dynamics(forces: dict[str, FloatArray]) -> InverseDynamics:
    return InverseDynamics(**forces, method="paper")


def _evaluate_loaded(
    robot: Robot,
    pose: FloatArray,
    velocity: FloatArray,
    acceleration: FloatArray,
    load: FloatArray | None,
    first: int,
    motion: Motion,
) -> dict[str, FloatArray]:
    """:func:`_evaluate` with the load and the joint friction.

    Friction ``fric = −(b·v + (c + μ·N)·s(v))`` with the rates ``v10, ω21 = φ̇,
    v32`` of eq. (14); the ``μ`` terms by fixed-point iteration on the
    reactions ``N = |n10|, |F21|, |n32|`` (from the frictionless ones): the
    paper's method evaluated again with the friction of the last reactions
    until the friction changes by less than round-off.
    """
    chunk = _evaluate(robot, pose, velocity, acceleration, load)
    friction = robot.friction
    if friction is None:
        return chunk
    act, rev, slv = friction.actuator, friction.revolute, friction.sleeve

    def s(rate: FloatArray, smoothing: float) -> FloatArray:
        return np.sign(rate) if smoothing == 0.0 else np.tanh(rate / smoothing)

    v10, v32 = chunk["v10"], chunk["v32"]
    w = np.broadcast_to(velocity[:, 2, None], v10.shape)
    s10, s21, s32 = s(v10, act.smoothing), s(w, rev.smoothing), s(v32, slv.smoothing)
    e10 = -(act.viscous * v10 + act.coulomb * s10)
    e21 = -(rev.viscous * w + rev.coulomb * s21)
    e32 = -(slv.viscous * v32 + slv.coulomb * s32)
    k10, k21, k32 = act.mu * s10, rev.mu * rev.pin_radius * s21, slv.mu * s32
    fric = (e10, e21, e32)
    iterations = np.zeros(v10.shape[0])
    settled = np.ones(v10.shape[0], dtype=bool)
    for _ in range(MU_MAX_ITERATIONS if friction.has_mu else 1):
        chunk = _evaluate(robot, pose, velocity, acceleration, load, fric)
        if not friction.has_mu:
            break
        new = (
            e10 - k10 * np.abs(chunk["n10"]),
            e21 - k21 * np.hypot(chunk["f21y"], chunk["f21z"]),
            e32 - k32 * np.abs(chunk["n32"]),
        )
        change = np.max([np.abs(a - b).max(axis=-1) for a, b in zip(new, fric, strict=True)], 0)
        size = np.max([np.abs(a).max(axis=-1) for a in new], 0) + 1.0
        settled = change <= 1e-15 * size
        iterations[~settled] += 1
        if settled.all():
            break
        fric = new
    if not settled.all():
        k = first + int(np.flatnonzero(~settled)[0])
        raise TrajectoryError(
            "the joint friction locks: the fixed-point iteration of the mu terms does not "
            f"settle in {MU_MAX_ITERATIONS} steps (self-locking)",
            subject="motion",
            sample=k,
            time=float(motion.t.reshape(-1)[k]),
        )
    chunk["fric10"], chunk["fric21"], chunk["fric32"] = fric
    chunk["iterations"] = iterations
    return chunk


def _body_constants(robot: Robot) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Masses ``m_k``, ``r_k^C``, ``Ĵ_k`` (legs, bodies) and ``r3^G`` (frames ``T_k``).

    A payload makes body 3 the platform with the payload: their mass, mass
    centre and inertia about ``A3``.
    """
    l0 = robot.l0
    r3G = 0.5 * l0 * np.array([0.0, 1.0, -1.0 / SQRT3])  # eq. (9), A3 → G in T3
    c1, c2 = robot.piston.com, robot.link.com
    r1C = c1[0] * U3 + c1[1] * U2  # along z1 = e_i and y1 = n_i
    r2C = c2[0] * (A32.T @ U3) + c2[1] * (A32.T @ U2)  # along d_i = z3 and d⊥_i = y3, in T2
    r_C = np.stack([r1C, r2C, r3G])  # (3 bodies, 3)
    mass = np.array([robot.piston.mass, robot.link.mass, robot.platform.mass])
    inertia = np.array([robot.piston.inertia, robot.link.inertia, robot.platform_inertia])
    # the plane normal z0 in T_k: a10·u3 = a30·u3 = −u1, a20·u3 = u3 for every leg and pose
    normal = np.stack([A10[0] @ U3, U3, A32 @ U3])

    def parallel_axes(m: FloatArray, r: FloatArray) -> FloatArray:  # m(|r|²·1 − r rᵀ)
        return np.asarray(
            m[..., None, None]
            * (np.einsum("...i,...i->...", r, r)[..., None, None] * np.eye(3)
               - np.einsum("...i,...j->...ij", r, r))
        )  # fmt: skip

    # Ĵ_k (eq. 20): I_zz about the centre of mass, moved to A_k, per unit mass
    about_joint = np.einsum("k,ki,kj->kij", inertia, normal, normal) + parallel_axes(mass, r_C)
    legs = (3, 3, 3)
    r_C = np.broadcast_to(r_C, legs).copy()
    about = np.broadcast_to(about_joint, (*legs, 3)).copy()
    masses = np.broadcast_to(mass, (3, 3)).copy()  # (legs, bodies)
    payload = robot.payload
    if payload.present:  # a body fixed to the platform: body 3 is the platform and it
        # its centre from A3 in T3 of each leg: r3^G + (a30 at φ = 0)·(c_p, 0)
        a30_still = A32 @ THETA_1.T @ A10  # (3 legs, 3, 3)
        r_p = r3G + a30_still @ np.array([payload.com[0], payload.com[1], 0.0])
        total = robot.platform.mass + payload.mass
        about[:, 2] += payload.inertia * np.outer(normal[2], normal[2]) + parallel_axes(
            np.full(3, payload.mass), r_p
        )
        r_C[:, 2] = (robot.platform.mass * r3G + payload.mass * r_p) / total
        masses[:, 2] = total
    J = about / masses[..., None, None]
    return masses, r_C, J, r3G


def _applied(
    robot: Robot,
    F_star: FloatArray,
    M_star: FloatArray,
    a0: FloatArray,
    position: FloatArray,
    r3G: FloatArray,
    load: FloatArray | None,
    friction: tuple[FloatArray, FloatArray, FloatArray] | None,
) -> tuple[FloatArray, FloatArray]:
    """``F_k*, M_k*`` with the load on the platform and the joint friction added (about ``A_k``).

    The environment's wrench ``(F, M)`` at ``G``: ``a30·F`` and ``r3^G × a30·F + M·a30·u3``
    on body 3.  Friction (``docs/loads_and_friction.md``): ``fric10·u3`` and
    ``−fric21·a10·u3`` on body 1 (at ``A1``); ``−fric32·a32ᵀu3`` and ``fric21·u3``
    on body 2 (at ``A2``); ``fric32_j·d_j`` at ``A2`` of leg ``j`` on body 3.
    """
    a10, a30 = a0[:, :, 0], a0[:, :, 2]
    F_star, M_star = F_star.copy(), M_star.copy()
    external = np.zeros((F_star.shape[0], 3))
    external[:, :2] = robot.load.force
    moment = np.full(F_star.shape[0], robot.load.moment)
    if load is not None:
        external[:, :2] += load[:, :2]
        moment = moment + load[:, 2]
    if robot.load.present or load is not None:
        F_ext = _mv(a30, external[:, None, :])  # in T3 of each leg
        F_star[:, :, 2] += F_ext
        M_star[:, :, 2] += np.cross(r3G, F_ext) + moment[:, None, None] * _mv(a30, U3)
    if friction is not None:
        fric10, fric21, fric32 = friction
        z0_in_1 = _mv(a10, U3)
        F_star[:, :, 0] += fric10[..., None] * U3
        M_star[:, :, 0] -= fric21[..., None] * z0_in_1
        F_star[:, :, 1] -= fric32[..., None] * _mv(A32.T, U3)
        M_star[:, :, 1] += fric21[..., None] * U3
        d0 = _mv(_T(a30), U3)  # d_j in T0, (n, legs, 3)
        for j in range(3):
            force0 = fric32[:, j, None] * d0[:, j]  # on the platform at A2 of leg j, in T0
            lever0 = position[:, j, 1][:, None, :] - position[:, :, 2]  # from A3 of each leg
            F_star[:, :, 2] += _mv(a30, force0[:, None, :])
            M_star[:, :, 2] += _mv(a30, np.cross(lever0, force0[:, None, :]))
    return F_star, M_star


def _spring(robot: Robot, F_star: FloatArray, lambda10: FloatArray, v10: FloatArray) -> FloatArray:
    """``F_1*`` with the spring with damper of the actuator added (``[spring.actuator]``).

    The force ``(−k·(λ10 − λ_rest) − c·v10)·u3`` on body 1 along its axis
    ``z1 = e_i`` (``T1``), through ``A1`` (no moment), like ``fric10``.
    """
    if robot.spring is None:
        return F_star
    spring = robot.spring.actuator
    force = -spring.stiffness * (lambda10 - spring.rest) - spring.damping * v10
    F_star = F_star.copy()
    F_star[:, :, 0] += force[..., None] * U3
    return F_star


def _evaluate(
    robot: Robot,
    pose: FloatArray,
    velocity: FloatArray,
    acceleration: FloatArray,
    load: FloatArray | None = None,
    friction: tuple[FloatArray, FloatArray, FloatArray] | None = None,
) -> dict[str, FloatArray]:
    """Every quantity of the paper for ``n`` samples (arrays ``(n, 3)``)."""
    l0 = robot.l0
    n = pose.shape[0]
    x, y, phi = pose[:, 0, None], pose[:, 1, None], pose[:, 2, None]  # (n, 1)
    phid, phidd = velocity[:, 2, None], acceleration[:, 2, None]
    Gdot = np.concatenate([velocity[:, :2], np.zeros((n, 1))], axis=-1)[:, None, :]  # ṙ0^G
    Gddot = np.concatenate([acceleration[:, :2], np.zeros((n, 1))], axis=-1)[:, None, :]
    mass, r_C, J, r3G = _body_constants(robot)

    # eq. (9): r00^i, the base vertices
    r00 = l0 * np.array([[0.0, -1.0, 0.0], [0.5 * SQRT3, 0.5, 0.0], [-0.5 * SQRT3, 0.5, 0.0]])

    # eq. (10) as printed: [cos α, cos(φ − π/3 + α); sin α, sin(φ − π/3 + α)]·[l0/√3 + λ10, λ32]
    alpha = ALPHA  # eq. (1)
    theta = phi + alpha  # φ + α_i, (n, 3)
    beta = phi - math.pi / 3.0 + alpha
    system = np.stack(
        [
            np.stack([np.broadcast_to(np.cos(alpha), beta.shape), np.cos(beta)], -1),
            np.stack([np.broadcast_to(np.sin(alpha), beta.shape), np.sin(beta)], -1),
        ],
        axis=-2,
    )  # (n, 3, 2, 2)
    rhs = np.stack(
        [
            x - r00[:, 0] - l0 / (2.0 * SQRT3) * np.cos(theta) + 0.5 * l0 * np.sin(theta),
            y - r00[:, 1] - l0 / (2.0 * SQRT3) * np.sin(theta) - 0.5 * l0 * np.cos(theta),
        ],
        axis=-1,
    )
    solution = _solve(system, rhs[..., None])[..., 0]
    lambda10 = solution[..., 0] - l0 / SQRT3
    lambda32 = solution[..., 1]
    phi21 = np.broadcast_to(phi, lambda10.shape)  # eq. (7)

    # eqs. (2)–(3): a10 = θ1θα^i, a21 = a21^φ θ1ᵀ, a32 = θ1θ2; a_k0 = Π a
    a10 = np.broadcast_to(A10, (n, 3, 3, 3))
    a21 = rot(phi21) @ THETA_1.T
    a32 = np.broadcast_to(A32, (n, 3, 3, 3))
    a = np.stack([a10, a21, a32], axis=2)  # (n, 3 legs, 3 bodies, 3, 3)
    a20 = a21 @ a10
    a30 = a32 @ a20
    a0 = np.stack([a10, a20, a30], axis=2)

    # eqs. (8)–(9): r10 = r00 + (l0/√3 + λ10)·a10ᵀu3, r21 = 0, r32 = λ32·a32ᵀu3
    r10 = r00 + (l0 / SQRT3 + lambda10)[..., None] * _mv(_T(a10), U3)
    r21 = np.zeros_like(r10)
    r32 = lambda32[..., None] * _mv(_T(a32), U3)
    r = np.stack([r10, r21, r32], axis=2)
    position_A2 = r10 + _mv(_T(a10), r21)  # eq. (8), partial sums
    position_A3 = position_A2 + _mv(_T(a20), r32)
    position = np.stack([r10, position_A2, position_A3], axis=2)
    centre = position_A3 + _mv(_T(a30), r3G)  # eq. (8): r0^G

    # eqs. (14) and (17): the conditions of connectivity, j = 1, 2 (rows x0, y0)
    lever = r32 + _mv(_T(a32), r3G)  # {r32 + a32ᵀ r3^G}, in T2
    a20T_u3t = _T(a20) @ U3_TILDE  # a20ᵀ ũ3
    connectivity = np.stack([_mv(_T(a10), U3), _mv(_T(a30), U3)], axis=-1)[..., :2, :]
    rhs14 = Gdot - phid[..., None] * _mv(a20T_u3t, lever)  # eq. (14)
    rates = _solve(connectivity, rhs14[..., :2, None])[..., 0]
    v10, v32 = rates[..., 0], rates[..., 1]
    omega21 = np.broadcast_to(phid, v10.shape)  # eq. (12): ω21 = φ̇
    rhs17 = (  # eq. (17), a20 read as a20ᵀ
        Gddot
        - (phid**2)[..., None] * _mv(a20T_u3t @ U3_TILDE, lever)
        - phidd[..., None] * _mv(a20T_u3t, lever)
        - 2.0 * (v32 * phid)[..., None] * _mv(a20T_u3t @ _T(a32), U3)
    )
    accelerations = _solve(connectivity, rhs17[..., :2, None])[..., 0]
    gamma10, gamma32 = accelerations[..., 0], accelerations[..., 1]
    epsilon21 = np.broadcast_to(phidd, v10.shape)  # eq. (18): ε21 = φ̈

    # eqs. (11), (13), (18): the recursive relations, k = 1, 2, 3
    zero = np.zeros_like(v10)
    omega_rel = [zero, omega21, zero]  # eq. (12): ω10 = 0, ω21 = φ̇, ω32 = 0
    v_rel = [v10, zero, v32]  # eq. (13): v10 = λ̇10, v21 = 0, v32 = λ̇32
    epsilon_rel = [zero, epsilon21, zero]  # eq. (18)
    gamma_rel = [gamma10, zero, gamma32]  # eq. (18)
    omega_t_prev = np.zeros((n, 3, 3, 3))
    omega2_eps_prev = np.zeros((n, 3, 3, 3))
    v_prev = np.zeros((n, 3, 3))
    eps_prev = np.zeros((n, 3, 3))
    gamma_prev = np.zeros((n, 3, 3))
    records: dict[str, list[FloatArray]] = {
        "omega_tilde": [],
        "v": [],
        "epsilon": [],
        "omega2_epsilon": [],
        "gamma": [],
    }
    for k in range(3):
        ak, rk = a[:, :, k], r[:, :, k]
        w_k, v_k = omega_rel[k][..., None, None], v_rel[k][..., None]
        e_k, g_k = epsilon_rel[k][..., None, None], gamma_rel[k][..., None]
        carried = ak @ omega_t_prev @ _T(ak)  # a_k,k-1 ω̃_k-1,0 a_k,k-1ᵀ
        omega_t = carried + w_k * U3_TILDE  # eq. (11)
        v_new = _mv(ak, v_prev) + _mv(ak @ omega_t_prev, rk) + v_k * U3  # eq. (13)
        eps = _mv(ak, eps_prev) + e_k[..., 0] * U3 + w_k[..., 0] * _mv(carried, U3)  # eq. (18)
        omega2_eps = (  # eq. (18), the matrix relation
            ak @ omega2_eps_prev @ _T(ak)
            + w_k * w_k * (U3_TILDE @ U3_TILDE)
            + e_k * U3_TILDE
            + 2.0 * w_k * carried @ U3_TILDE
        )
        gamma_new = (  # eq. (18)
            _mv(ak, gamma_prev)
            + _mv(ak @ omega2_eps_prev, rk)
            + 2.0 * v_k * _mv(carried, U3)
            + g_k * U3
        )
        for name, value in (
            ("omega_tilde", omega_t),
            ("v", v_new),
            ("epsilon", eps),
            ("omega2_epsilon", omega2_eps),
            ("gamma", gamma_new),
        ):
            records[name].append(value)
        omega_t_prev, v_prev, eps_prev = omega_t, v_new, eps
        omega2_eps_prev, gamma_prev = omega2_eps, gamma_new
    omega_tilde = np.stack(records["omega_tilde"], axis=2)
    v = np.stack(records["v"], axis=2)
    epsilon = np.stack(records["epsilon"], axis=2)
    omega2_epsilon = np.stack(records["omega2_epsilon"], axis=2)
    gamma = np.stack(records["gamma"], axis=2)
    omega = vee(omega_tilde)  # eq. (12): the associated vectors

    # eq. (19): the weight m_k·g and its moment about A_k, in T_k
    g0 = np.array([robot.gravity[0], robot.gravity[1], 0.0])
    m = mass[..., None]  # (3 legs, 3 bodies, 1)
    F_star = m * _mv(a0, g0)
    M_star = np.cross(r_C, F_star)  # r̃_k^C F_k*
    # beyond the paper: the applied forces enter F_k*, M_k* as the weight does
    F_star, M_star = _applied(robot, F_star, M_star, a0, position, r3G, load, friction)
    F_star = _spring(robot, F_star, lambda10, v10)
    # eq. (20): inertia force and moment of inertia forces about A_k
    F_in = -m * (gamma + _mv(omega2_epsilon, r_C))
    M_in = -m * (np.cross(r_C, gamma) + _mv(J, epsilon) + _mv(omega_tilde, _mv(J, omega)))
    # eq. (22)
    F0 = -F_in - F_star
    M0 = -M_in - M_star

    # eq. (21), the platform in chain A: F3 = F30, M3 = M30 for leg A, 0 for B and C
    F3 = _CHAIN_A[:, None] * F0[:, :, 2]
    M3 = _CHAIN_A[:, None] * M0[:, :, 2]
    F2 = F0[:, :, 1] + _mv(_T(a32), F3)
    M2 = M0[:, :, 1] + _mv(_T(a32), M3) + np.cross(r32, _mv(_T(a32), F3))
    F1 = F0[:, :, 0] + _mv(_T(a21), F2)
    M1 = M0[:, :, 0] + _mv(_T(a21), M2) + np.cross(r21, _mv(_T(a21), F2))
    F = np.stack([F1, F2, F3], axis=2)
    M = np.stack([M1, M2, M3], axis=2)

    # eq. (15) for the three legs, j = 1, 2: six equations in the unknowns
    # (v0^Gv_x, v0^Gv_y, ω21^v, v32^Av, v32^Bv, v32^Cv); ω21^iv is the platform's
    # virtual angular velocity for every leg (eq. 7).  One right-hand side per set of eq. (16).
    matrix = np.zeros((n, 3, 2, 6))
    matrix[..., 0:2] = -np.eye(2)  # − u_jᵀ v0^Gv
    matrix[..., 2] = _mv(a20T_u3t, lever)[..., :2]  # u_jᵀ a20ᵀ ũ3 {r32 + a32ᵀ r3^G}
    for i in range(3):
        matrix[:, i, :, 3 + i] = _mv(_T(a30[:, i]), U3)[..., :2]  # u_jᵀ a30ᵀ u3
    joint_axes = np.stack(  # u_jᵀ a10ᵀ u3, u_jᵀ a10ᵀ u2, u_jᵀ a10ᵀ u3 of (v10, v21y, v21z)
        [_mv(_T(A10), U3), _mv(_T(A10), U2), _mv(_T(A10), U3)], axis=-1
    )[:, :2, :]  # (3 legs i, 2, 3 rates)
    virtual_rhs = -np.einsum("slir,ijr->slij", VIRTUAL_SETS, joint_axes).reshape(9, 6).T
    unknowns = _solve(matrix.reshape(n, 6, 6), np.broadcast_to(virtual_rhs, (n, 6, 9)))
    unknowns = unknowns.reshape(n, 6, 3, 3)  # (n, unknown, set s, leg l)
    vG_virtual = np.concatenate(
        [np.moveaxis(unknowns[:, 0:2], 1, -1), np.zeros((n, 3, 3, 1))], axis=-1
    )
    omega21_virtual = np.broadcast_to(unknowns[:, 2, :, :, None], (n, 3, 3, 3))
    v32_virtual = np.moveaxis(unknowns[:, 3:6], 1, -1)  # (n, s, l, i)

    # eqs. (23)–(25), for every leg l; the braces sum over the chains i = A, B, C
    braces = np.einsum("nsli,ni->nsl", omega21_virtual, M2[..., 2]) + np.einsum(
        "nsli,ni->nsl", v32_virtual, F3[..., 2]
    )  # u3ᵀ{ω21^Av M2^A + v32^Av F3^A + ω21^Bv M2^B + ω21^Cv M2^C}
    a21T_F2 = _mv(_T(a21), F2)
    f10 = F1[..., 2] + braces[:, 0]  # eq. (23): u3ᵀF1 + {…}
    f21y = a21T_F2[..., 1] + braces[:, 1]  # eq. (24): u2ᵀ a21ᵀ F2 + {…}
    f21z = a21T_F2[..., 2] + braces[:, 2]  # eq. (25): u3ᵀ a21ᵀ F2 + {…}

    # the other reactions.  Piston 1 in T1: F10 = f10·u3 + n10·u2 − (f21y·u2 + f21z·u3),
    # every force through A1, the guide's moment m10 about z0 = a10·u3.
    n10 = F0[:, :, 0, 1] + f21y
    m10 = _dot(_mv(_T(a10), M0[:, :, 0]), U3)  # u3ᵀ a10ᵀ M10
    # Link 2 in T2: F20 = a21·F21 − n32·a32ᵀu2, M20 = −m32·u3 (z2 = z0), about A2.
    F21 = f21y[..., None] * U2 + f21z[..., None] * U3  # in T1
    n32 = _dot(_mv(_T(a32), U2), _mv(a21, F21) - F0[:, :, 1])
    m32 = -M0[:, :, 1, 2]
    return {
        "lambda10": lambda10,
        "lambda32": lambda32,
        "phi21": np.asarray(phi21),
        "a": a,
        "a0": a0,
        "r": r,
        "position": position,
        "centre": centre,
        "v10": v10,
        "v32": v32,
        "omega21": np.asarray(omega21),
        "gamma10": gamma10,
        "gamma32": gamma32,
        "epsilon21": np.asarray(epsilon21),
        "omega_tilde": omega_tilde,
        "omega": omega,
        "v": v,
        "epsilon": epsilon,
        "omega2_epsilon": omega2_epsilon,
        "gamma": gamma,
        "r_C": r_C,
        "J": J,
        "F_star": F_star,
        "M_star": M_star,
        "F_in": F_in,
        "M_in": M_in,
        "F0": F0,
        "M0": M0,
        "F": F,
        "M": M,
        "omega21_virtual": np.asarray(omega21_virtual),
        "v32_virtual": v32_virtual,
        "vG_virtual": vG_virtual,
        "f10": f10,
        "f21y": f21y,
        "f21z": f21z,
        "n10": n10,
        "m10": m10,
        "n32": n32,
        "m32": m32,
        "p10": f10 * v10,
    }


def _solve(matrix: FloatArray, rhs: FloatArray) -> FloatArray:
    """``numpy.linalg.solve`` for the validated (non-singular) poses."""
    try:
        return np.asarray(np.linalg.solve(matrix, rhs))
    except np.linalg.LinAlgError:  # only when values overflowed to inf or nan
        shape = np.broadcast_shapes(matrix.shape[:-2], rhs.shape[:-2]) + rhs.shape[-2:]
        return np.full(shape, np.nan)


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
        f"the results overflow: {name} is not finite; "
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
    total = pose.shape[0]
    out: dict[str, FloatArray] = {}
    lambda10 = np.empty((total, 3))
    for first in range(0, total, PAPER_CHUNK):
        rows = slice(first, first + PAPER_CHUNK)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            chunk = _evaluate_loaded(
                robot, pose[rows], velocity[rows], acceleration[rows],
                None if load is None else load[rows], first, motion,
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
    >>> (46.5975 * np.array([0.0, 0.5, math.sqrt(3) / 2])).round(4).tolist()
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
    >>> from prp3.motion import paper_motion
    >>> dyn = paper_inverse_dynamics(Robot(), paper_motion("vertical"))
    >>> dyn.f10.shape, dyn.method
    ((301, 3), 'paper')
    """
    return _to_inverse_dynamics(_run(robot, motion, _FORCES))  # with friction and iterations
