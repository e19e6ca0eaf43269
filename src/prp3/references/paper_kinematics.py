"""The paper's frames, geometry and kinematics, as printed (Staicu & Chablat, eqs. 1–18).

The first half of :mod:`prp3.references.paper`: 3-D vectors and 3×3 matrices in the
local frames ``T0 … T3`` of each leg, one function per stage of the paper,
each citing its equations:

* :func:`orientation_condition` — eqs. (5)–(7): the rotation condition
  ``q30°ᵀ·q30 = R`` solved for ``a21``, from which ``φ21 = φ`` follows;
* :func:`paper_geometry` — eqs. (2)–(3), (8)–(10): the frames, the joint
  displacements ``λ10, λ32`` (eq. 10 as printed) and the loop closure;
* :func:`paper_velocities` — eqs. (11)–(14): the conditions of connectivity
  and the recursion of the angular velocities and the joint velocities;
* :func:`paper_accelerations` — eqs. (17)–(18): the same for accelerations;
* :func:`virtual_velocities` — eqs. (15)–(16): the virtual motions behind
  the forces of eqs. (23)–(25);
* :func:`fixed_frame_kinematics` — the joints and centres of mass of pistons
  and links in the fixed frame (``T0``), the Jacobian of eq. (14): what a
  :class:`prp3.mechanics.kinematics.Kinematics` holds, from the quantities above.

It shares nothing with :mod:`prp3.mechanics.geometry`'s inverse geometry,
:mod:`prp3.mechanics.kinematics` or :mod:`prp3.mechanics.kernel` but the leg angles ``α_i``
(eq. 1), so that it checks them.

Arrays: ``n`` samples first, then legs ``A, B, C``, then bodies ``k = 1, 2,
3``, then the components in frame ``T_k``; a vector is ``(n, 3, 3, 3)``, a
matrix ``(n, 3, 3, 3, 3)``.

>>> phi = np.array([0.4, -1.2])
>>> a21, phi21 = orientation_condition(phi)
>>> phi21.shape, bool(np.allclose(phi21, phi[:, None], rtol=0, atol=1e-15))
((2, 3), True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.mechanics.geometry import ALPHA

__all__ = [
    "A10",
    "A30_CIRCLE",
    "A32",
    "R00",
    "THETA_1",
    "THETA_2",
    "U1",
    "U2",
    "U3",
    "U3_TILDE",
    "VIRTUAL_SETS",
    "FixedFrameKinematics",
    "PaperAccelerations",
    "PaperGeometry",
    "PaperVelocities",
    "VirtualVelocities",
    "fixed_frame_kinematics",
    "orientation_condition",
    "paper_accelerations",
    "paper_geometry",
    "paper_velocities",
    "platform_centre",
    "rot",
    "skew",
    "theta_alpha",
    "vee",
    "virtual_velocities",
]

FloatArray = NDArray[np.float64]

SQRT3 = math.sqrt(3.0)

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

#: The sets of unit virtual velocities of eq. (16), shape (3 forces, 3 legs l, 3 legs i,
#: 3 joint rates): entry ``[s, l, i]`` is ``(v10^iv, v21^iyv, v21^izv)`` of the virtual
#: motion that gives force ``s`` (``f10, f21y, f21z``) of leg ``l``.
VIRTUAL_SETS: FloatArray = np.einsum("sr,li->slir", np.eye(3), np.eye(3))


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


def mv(matrix: FloatArray, vector: FloatArray) -> FloatArray:
    """``matrix·vector`` over the last axes (broadcast)."""
    return np.asarray((matrix @ vector[..., None])[..., 0])


def tr(matrix: FloatArray) -> FloatArray:
    """``matrixᵀ`` over the last two axes."""
    return np.swapaxes(matrix, -1, -2)


def solve(matrix: FloatArray, rhs: FloatArray) -> FloatArray:
    """``numpy.linalg.solve`` for the validated (non-singular) poses; NaN where values overflowed."""
    try:
        return np.asarray(np.linalg.solve(matrix, rhs))
    except np.linalg.LinAlgError:  # only when values overflowed to inf or nan
        shape = np.broadcast_shapes(matrix.shape[:-2], rhs.shape[:-2]) + rhs.shape[-2:]
        return np.full(shape, np.nan)


#: ``a10 = θ1·θα^i`` (eq. 2) of the legs, shape (3, 3, 3); constant.
A10: FloatArray = THETA_1 @ theta_alpha(ALPHA)
#: ``a32 = θ1·θ2`` (eq. 2), shape (3, 3); the same for every leg, constant.
A32: FloatArray = THETA_1 @ THETA_2
#: ``q30° = θ1·θ2·θα^i`` (eq. 6) of the legs, shape (3, 3, 3): ``a30`` at ``φ = 0``.
A30_CIRCLE: FloatArray = THETA_1 @ THETA_2 @ theta_alpha(ALPHA)
#: ``r00^i`` of eq. (9) per unit ``l0``: the base vertices ``A0, B0, C0`` in ``T0``, (3, 3).
R00: FloatArray = np.array([[0.0, -1.0, 0.0], [0.5 * SQRT3, 0.5, 0.0], [-0.5 * SQRT3, 0.5, 0.0]])

for _constant in (U1, U2, U3, U3_TILDE, THETA_1, THETA_2, VIRTUAL_SETS, A10, A32, A30_CIRCLE, R00):
    _constant.flags.writeable = False


def platform_centre(l0: float) -> FloatArray:
    """``r3^G = 0.5·l0·(0, 1, −1/√3)`` of eq. (9): ``G`` from ``A3``, in ``T3``, shape (3,).

    >>> platform_centre(0.3).round(6).tolist()
    [0.0, 0.15, -0.086603]
    """
    return 0.5 * l0 * np.array([0.0, 1.0, -1.0 / SQRT3])


# ---------------------------------------------------------------- eqs. (5)–(7)
def orientation_condition(phi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Eq. (5) solved for the link's rotation: ``a21`` and ``φ21`` of each leg, for ``φ (n,)``.

    The platform's orientation fixes the last frame: ``q30°ᵀ·q30 = R = rot(φ)``
    (eq. 5) with ``q30 = q32·q21·q10`` and ``q30° = θ1·θ2·θα^i`` (eq. 6), so
    ``q21 = q32ᵀ·q30°·R·q10ᵀ``.  By eq. (2) ``q21 = rot(φ21)·θ1ᵀ``, so
    ``rot(φ21) = q21·θ1``, whose first row is ``(cos φ21, sin φ21, 0)``: the
    angle is read from it, on the branch nearest ``φ`` (the platform turns
    continuously, eq. 4).  This is eq. (7), ``φ21^A = φ21^B = φ21^C = φ``.

    Returns
    -------
    a21 : ndarray (n, 3, 3, 3)
        ``q21`` of legs A, B, C from eq. (5).
    phi21 : ndarray (n, 3)
        ``φ21`` of legs A, B, C (rad), ``φ`` to round-off.
    """
    R = rot(phi)[:, None]  # (n, 1, 3, 3)
    a21 = tr(A32) @ A30_CIRCLE @ R @ tr(A10)  # eq. (5): q21 = q32ᵀ q30° R q10ᵀ
    turn = a21 @ THETA_1  # eq. (2): rot(φ21)
    angle = np.arctan2(turn[..., 0, 1], turn[..., 0, 0])
    offset = angle - phi[:, None]
    phi21 = phi[:, None] + (offset - 2.0 * math.pi * np.round(offset / (2.0 * math.pi)))
    return a21, phi21


# ---------------------------------------------------------------- eqs. (2)–(3), (8)–(10)
@dataclass(frozen=True)
class PaperGeometry:
    """The frames and the inverse geometry of ``n`` poses (eqs. 2–3, 5–10).

    ``lambda10, lambda32, phi21 (n, 3)``; ``a, a0 (n, 3, 3, 3, 3)``: ``a_k,k-1``
    and ``a_k0``; ``r (n, 3, 3, 3)``: ``r10`` (in ``T0``), ``r21``, ``r32``;
    ``position (n, 3, 3, 3)``: ``A_k`` in ``T0``; ``centre (n, 3, 3)``: ``r0^G``
    of each leg's loop (eq. 8); ``r3G (3,)``; ``determinant (n,)``: of the
    system of eq. (10) (leg A's; the same, ``sin(φ − π/3)``, for every leg).
    """

    lambda10: FloatArray
    lambda32: FloatArray
    phi21: FloatArray
    a: FloatArray
    a0: FloatArray
    r: FloatArray
    position: FloatArray
    centre: FloatArray
    r3G: FloatArray  # noqa: N815 - the paper's r3^G
    determinant: FloatArray


def paper_geometry(l0: float, pose: FloatArray) -> PaperGeometry:
    """The frames (eqs. 2–3, 5–7) and the inverse geometry (eqs. 8–10) for poses ``(n, 3)``.

    Eq. (10) as printed, per leg a 2×2 system in ``l0/√3 + λ10^i`` and ``λ32^i``::

        [cos α_i, cos(φ − π/3 + α_i); sin α_i, sin(φ − π/3 + α_i)]·[l0/√3 + λ10; λ32]
            = [x − x00 − l0/(2√3)·cos(φ + α) + l0/2·sin(φ + α);
               y − y00 − l0/(2√3)·sin(φ + α) − l0/2·cos(φ + α)]

    then the frames ``a10 = θ1·θα^i``, ``a21`` of eq. (5), ``a32 = θ1·θ2``
    and their products (eq. 3), and the vectors of eq. (8).
    """
    n = pose.shape[0]
    x, y, phi = pose[:, 0, None], pose[:, 1, None], pose[:, 2, None]  # (n, 1)
    r00 = l0 * R00  # eq. (9)
    r3G = platform_centre(l0)
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
    solution = solve(system, rhs[..., None])[..., 0]  # eq. (10)
    lambda10 = solution[..., 0] - l0 / SQRT3
    lambda32 = solution[..., 1]
    determinant = system[:, 0, 0, 0] * system[:, 0, 1, 1] - system[:, 0, 0, 1] * system[:, 0, 1, 0]

    # eqs. (2)–(3), (5): a10 = θ1θα^i, a21 from the orientation condition, a32 = θ1θ2
    _, phi21 = orientation_condition(pose[:, 2])
    a10 = np.broadcast_to(A10, (n, 3, 3, 3))
    a21 = rot(phi21) @ THETA_1.T  # eq. (2) with φ21 of eq. (7)
    a32 = np.broadcast_to(A32, (n, 3, 3, 3))
    a = np.stack([a10, a21, a32], axis=2)  # (n, 3 legs, 3 bodies, 3, 3)
    a20 = a21 @ a10
    a30 = a32 @ a20
    a0 = np.stack([a10, a20, a30], axis=2)

    # eqs. (8)–(9): r10 = r00 + (l0/√3 + λ10)·a10ᵀu3, r21 = 0, r32 = λ32·a32ᵀu3
    r10 = r00 + (l0 / SQRT3 + lambda10)[..., None] * mv(tr(a10), U3)
    r21 = np.zeros_like(r10)
    r32 = lambda32[..., None] * mv(tr(a32), U3)
    r = np.stack([r10, r21, r32], axis=2)
    position_A2 = r10 + mv(tr(a10), r21)  # eq. (8), partial sums
    position_A3 = position_A2 + mv(tr(a20), r32)
    position = np.stack([r10, position_A2, position_A3], axis=2)
    centre = position_A3 + mv(tr(a30), r3G)  # eq. (8): r0^G
    return PaperGeometry(
        lambda10=lambda10,
        lambda32=lambda32,
        phi21=phi21,
        a=a,
        a0=a0,
        r=r,
        position=position,
        centre=centre,
        r3G=r3G,
        determinant=determinant,
    )


def _connectivity(geo: PaperGeometry) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The matrix of eqs. (14), (17) (rows ``j = 1, 2``; columns ``a10ᵀu3, a30ᵀu3``),
    ``a20ᵀũ3`` and the lever ``{r32 + a32ᵀ r3^G}`` (in ``T2``) of each leg."""
    a10, a20, a30 = geo.a0[:, :, 0], geo.a0[:, :, 1], geo.a0[:, :, 2]
    lever = geo.r[:, :, 2] + mv(A32.T, geo.r3G)
    matrix = np.stack([mv(tr(a10), U3), mv(tr(a30), U3)], axis=-1)[..., :2, :]
    return matrix, tr(a20) @ U3_TILDE, lever


# ---------------------------------------------------------------- eqs. (11)–(14)
@dataclass(frozen=True)
class PaperVelocities:
    """Velocities of ``n`` samples (eqs. 11–14).

    ``v10, v32, omega21 (n, 3)``: the relative rates of eq. (14) and ``ω21 = φ̇``;
    ``omega_tilde (n, 3, 3, 3, 3)``: ``ω̃_k0`` (eq. 11); ``omega (n, 3, 3, 3)``:
    ``ω_k0`` (eq. 12); ``v (n, 3, 3, 3)``: ``v_k0`` (eq. 13), in ``T_k``.
    """

    v10: FloatArray
    v32: FloatArray
    omega21: FloatArray
    omega_tilde: FloatArray
    omega: FloatArray
    v: FloatArray


def paper_velocities(geo: PaperGeometry, velocity: FloatArray) -> PaperVelocities:
    """The conditions of connectivity (eq. 14) and the recursions (eqs. 11–13), ``velocity (n, 3)``.

    ``v10·u_jᵀa10ᵀu3 + v32·u_jᵀa30ᵀu3 = u_jᵀṙ0^G − φ̇·u_jᵀa20ᵀũ3{r32 + a32ᵀr3^G}``
    (``j = 1, 2``); ``ω̃_k0 = a_k,k-1·ω̃_k-1,0·a_k,k-1ᵀ + ω_k,k-1·ũ3`` (eq. 11) and
    ``v_k0 = a_k,k-1·v_k-1,0 + a_k,k-1·ω̃_k-1,0·r_k,k-1 + v_k,k-1·u3`` (eq. 13).
    """
    n = velocity.shape[0]
    matrix, a20T_u3t, lever = _connectivity(geo)
    phid = velocity[:, 2, None]
    Gdot = np.concatenate([velocity[:, :2], np.zeros((n, 1))], axis=-1)[:, None, :]  # ṙ0^G
    rhs = Gdot - phid[..., None] * mv(a20T_u3t, lever)  # eq. (14)
    rates = solve(matrix, rhs[..., :2, None])[..., 0]
    v10, v32 = rates[..., 0], rates[..., 1]
    omega21 = np.asarray(np.broadcast_to(phid, v10.shape))  # eq. (12): ω21 = φ̇
    zero = np.zeros_like(v10)
    omega_rel = (zero, omega21, zero)  # eq. (12): ω10 = 0, ω21 = φ̇, ω32 = 0
    v_rel = (v10, zero, v32)  # eq. (13): v10 = λ̇10, v21 = 0, v32 = λ̇32
    omega_prev, v_prev = np.zeros((n, 3, 3, 3)), np.zeros((n, 3, 3))
    omegas, vs = [], []
    for k in range(3):
        ak, rk = geo.a[:, :, k], geo.r[:, :, k]
        omega_t = ak @ omega_prev @ tr(ak) + omega_rel[k][..., None, None] * U3_TILDE  # eq. (11)
        v_new = mv(ak, v_prev) + mv(ak @ omega_prev, rk) + v_rel[k][..., None] * U3  # eq. (13)
        omegas.append(omega_t)
        vs.append(v_new)
        omega_prev, v_prev = omega_t, v_new
    omega_tilde = np.stack(omegas, axis=2)
    return PaperVelocities(
        v10=v10,
        v32=v32,
        omega21=omega21,
        omega_tilde=omega_tilde,
        omega=vee(omega_tilde),  # eq. (12): the associated vectors
        v=np.stack(vs, axis=2),
    )


# ---------------------------------------------------------------- eqs. (17)–(18)
@dataclass(frozen=True)
class PaperAccelerations:
    """Accelerations of ``n`` samples (eqs. 17–18).

    ``gamma10, gamma32, epsilon21 (n, 3)``: the relative accelerations of eq. (17)
    and ``ε21 = φ̈``; ``epsilon (n, 3, 3, 3)``: ``ε_k0``; ``omega2_epsilon (n, 3,
    3, 3, 3)``: ``ω̃_k0² + ε̃_k0`` by the matrix recursion; ``gamma (n, 3, 3, 3)``:
    ``γ_k0``, in ``T_k`` (eq. 18).
    """

    gamma10: FloatArray
    gamma32: FloatArray
    epsilon21: FloatArray
    epsilon: FloatArray
    omega2_epsilon: FloatArray
    gamma: FloatArray


def paper_accelerations(
    geo: PaperGeometry, vel: PaperVelocities, velocity: FloatArray, acceleration: FloatArray
) -> PaperAccelerations:
    """The derivative of the conditions of connectivity (eq. 17) and the recursions of eq. (18).

    Eq. (17) with ``a20ᵀ`` for the printed ``a20`` (``docs/conventions.md``)::

        γ10·u_jᵀa10ᵀu3 + γ32·u_jᵀa30ᵀu3 = u_jᵀr̈0^G − φ̇²·u_jᵀa20ᵀũ3ũ3{…}
                                        − φ̈·u_jᵀa20ᵀũ3{…} − 2·v32·φ̇·u_jᵀa20ᵀũ3a32ᵀu3
    """
    n = velocity.shape[0]
    matrix, a20T_u3t, lever = _connectivity(geo)
    phid, phidd = velocity[:, 2, None], acceleration[:, 2, None]
    Gddot = np.concatenate([acceleration[:, :2], np.zeros((n, 1))], axis=-1)[:, None, :]
    rhs = (  # eq. (17), a20 read as a20ᵀ
        Gddot
        - (phid**2)[..., None] * mv(a20T_u3t @ U3_TILDE, lever)
        - phidd[..., None] * mv(a20T_u3t, lever)
        - 2.0 * (vel.v32 * phid)[..., None] * mv(a20T_u3t @ A32.T, U3)
    )
    accelerations = solve(matrix, rhs[..., :2, None])[..., 0]
    gamma10, gamma32 = accelerations[..., 0], accelerations[..., 1]
    epsilon21 = np.asarray(np.broadcast_to(phidd, gamma10.shape))  # eq. (18): ε21 = φ̈
    zero = np.zeros_like(gamma10)
    omega_rel = (zero, vel.omega21, zero)
    v_rel = (vel.v10, zero, vel.v32)
    epsilon_rel = (zero, epsilon21, zero)  # eq. (18)
    gamma_rel = (gamma10, zero, gamma32)  # eq. (18)
    omega_prev = np.zeros((n, 3, 3, 3))
    omega2_eps_prev = np.zeros((n, 3, 3, 3))
    eps_prev, gamma_prev = np.zeros((n, 3, 3)), np.zeros((n, 3, 3))
    epsilons, omega2_epsilons, gammas = [], [], []
    for k in range(3):
        ak, rk = geo.a[:, :, k], geo.r[:, :, k]
        w_k, v_k = omega_rel[k][..., None, None], v_rel[k][..., None]
        e_k, g_k = epsilon_rel[k][..., None, None], gamma_rel[k][..., None]
        carried = ak @ omega_prev @ tr(ak)  # a_k,k-1 ω̃_k-1,0 a_k,k-1ᵀ
        eps = mv(ak, eps_prev) + e_k[..., 0] * U3 + w_k[..., 0] * mv(carried, U3)  # eq. (18)
        omega2_eps = (  # eq. (18), the matrix relation
            ak @ omega2_eps_prev @ tr(ak)
            + w_k * w_k * (U3_TILDE @ U3_TILDE)
            + e_k * U3_TILDE
            + 2.0 * w_k * carried @ U3_TILDE
        )
        gamma_new = (  # eq. (18)
            mv(ak, gamma_prev)
            + mv(ak @ omega2_eps_prev, rk)
            + 2.0 * v_k * mv(carried, U3)
            + g_k * U3
        )
        epsilons.append(eps)
        omega2_epsilons.append(omega2_eps)
        gammas.append(gamma_new)
        omega_prev = vel.omega_tilde[:, :, k]
        eps_prev, omega2_eps_prev, gamma_prev = eps, omega2_eps, gamma_new
    return PaperAccelerations(
        gamma10=gamma10,
        gamma32=gamma32,
        epsilon21=epsilon21,
        epsilon=np.stack(epsilons, axis=2),
        omega2_epsilon=np.stack(omega2_epsilons, axis=2),
        gamma=np.stack(gammas, axis=2),
    )


# ---------------------------------------------------------------- eqs. (15)–(16)
@dataclass(frozen=True)
class VirtualVelocities:
    """The virtual motions of eq. (16) solved by eq. (15), entry ``[n, s, l, ...]``.

    ``omega21_virtual (n, 3, 3, 3)``: ``ω21^iv`` for force ``s`` of leg ``l``, legs
    ``i``; ``v32_virtual`` alike; ``vG_virtual (n, 3, 3, 3)``: ``v0^Gv`` in ``T0``.
    """

    omega21_virtual: FloatArray
    v32_virtual: FloatArray
    vG_virtual: FloatArray  # noqa: N815 - the paper's v0^Gv


def virtual_velocities(geo: PaperGeometry) -> VirtualVelocities:
    """Eq. (15) for the three legs and every set of eq. (16).

    ``v10^iv·u_jᵀa10ᵀu3 + v21^iyv·u_jᵀa10ᵀu2 + v21^izv·u_jᵀa10ᵀu3
    + ω21^iv·u_jᵀa20ᵀũ3{r32 + a32ᵀr3^G} + v32^iv·u_jᵀa30ᵀu3 = u_jᵀv0^Gv``:
    six equations (``j = 1, 2``, three legs) in ``(v0^Gv_x, v0^Gv_y, ω21^v,
    v32^Av, v32^Bv, v32^Cv)``; ``ω21^iv`` is the platform's virtual angular
    velocity for every leg (eq. 7).  One right-hand side per set of eq. (16).
    """
    n = geo.a.shape[0]
    _, a20T_u3t, lever = _connectivity(geo)
    a30 = geo.a0[:, :, 2]
    matrix = np.zeros((n, 3, 2, 6))
    matrix[..., 0:2] = -np.eye(2)  # − u_jᵀ v0^Gv
    matrix[..., 2] = mv(a20T_u3t, lever)[..., :2]  # u_jᵀ a20ᵀ ũ3 {r32 + a32ᵀ r3^G}
    for i in range(3):
        matrix[:, i, :, 3 + i] = mv(tr(a30[:, i]), U3)[..., :2]  # u_jᵀ a30ᵀ u3
    joint_axes = np.stack(  # u_jᵀ a10ᵀ u3, u_jᵀ a10ᵀ u2, u_jᵀ a10ᵀ u3 of (v10, v21y, v21z)
        [mv(tr(A10), U3), mv(tr(A10), U2), mv(tr(A10), U3)], axis=-1
    )[:, :2, :]  # (3 legs i, 2, 3 rates)
    virtual_rhs = -np.einsum("slir,ijr->slij", VIRTUAL_SETS, joint_axes).reshape(9, 6).T
    unknowns = solve(matrix.reshape(n, 6, 6), np.broadcast_to(virtual_rhs, (n, 6, 9)))
    unknowns = unknowns.reshape(n, 6, 3, 3)  # (n, unknown, set s, leg l)
    vG_virtual = np.concatenate(
        [np.moveaxis(unknowns[:, 0:2], 1, -1), np.zeros((n, 3, 3, 1))], axis=-1
    )
    return VirtualVelocities(
        omega21_virtual=np.asarray(np.broadcast_to(unknowns[:, 2, :, :, None], (n, 3, 3, 3))),
        v32_virtual=np.moveaxis(unknowns[:, 3:6], 1, -1),  # (n, s, l, i)
        vG_virtual=vG_virtual,
    )


# ---------------------------------------------------------------- the fixed frame
@dataclass(frozen=True)
class FixedFrameKinematics:
    """What :class:`prp3.mechanics.kinematics.Kinematics` holds beyond the joint rates, in ``T0``.

    Plane vectors ``(n, 3, 2)`` of legs A, B, C: ``joint`` (``P_i = A2``),
    ``slide`` (``d_i = z3``), ``slide_normal`` (``d⊥_i = y3``), ``lever``
    (``ρ_i = G − P_i``), ``joint_velocity``, ``joint_acceleration``, the centres of
    mass of pistons and links and their velocities and accelerations;
    ``jacobian (n, 3, 3)``: ``∂λ10/∂(x, y, φ)`` from eq. (14).
    """

    joint: FloatArray
    slide: FloatArray
    slide_normal: FloatArray
    lever: FloatArray
    joint_velocity: FloatArray
    joint_acceleration: FloatArray
    piston_com: FloatArray
    piston_velocity: FloatArray
    piston_acceleration: FloatArray
    link_com: FloatArray
    link_velocity: FloatArray
    link_acceleration: FloatArray
    jacobian: FloatArray


def fixed_frame_kinematics(
    geo: PaperGeometry,
    vel: PaperVelocities,
    acc: PaperAccelerations,
    r1C: FloatArray,
    r2C: FloatArray,
) -> FixedFrameKinematics:
    """Joints and centres of mass of pistons and links in ``T0``, from the paper's recursion.

    A point ``r_k^C`` of body ``k`` (in ``T_k``, from ``A_k``) is at
    ``A_k + a_k0ᵀ·r_k^C``, moves with ``a_k0ᵀ(v_k0 + ω̃_k0·r_k^C)`` and accelerates
    with ``a_k0ᵀ(γ_k0 + (ω̃²_k0 + ε̃_k0)·r_k^C)`` (eqs. 13, 18, 20).  The Jacobian:
    ``v10`` of eq. (14) for ``ṙ0^G = u1``, ``u2`` and ``φ̇ = 1``.
    """
    a0T = tr(geo.a0)  # (n, 3, 3, 3, 3): T_k → T0

    def point(k: int, offset: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        where = geo.position[:, :, k] + mv(a0T[:, :, k], offset)
        moving = mv(a0T[:, :, k], vel.v[:, :, k] + mv(vel.omega_tilde[:, :, k], offset))
        turning = mv(a0T[:, :, k], acc.gamma[:, :, k] + mv(acc.omega2_epsilon[:, :, k], offset))
        return where[..., :2], moving[..., :2], turning[..., :2]

    zero = np.zeros(3)
    joint, joint_velocity, joint_acceleration = point(1, zero)
    piston = point(0, r1C)
    link = point(1, r2C)
    n = geo.a.shape[0]
    matrix, a20T_u3t, lever = _connectivity(geo)
    columns = np.zeros((n, 3, 3, 3))  # (n, leg, component, column x, y, φ): eq. (14)'s rhs
    columns[..., 0, 0] = 1.0
    columns[..., 1, 1] = 1.0
    columns[..., 2] = -mv(a20T_u3t, lever)
    jacobian = solve(matrix, columns[..., :2, :])[..., 0, :]  # the v10 row of each leg
    return FixedFrameKinematics(
        joint=joint,
        slide=mv(a0T[:, :, 2], U3)[..., :2],
        slide_normal=mv(a0T[:, :, 2], U2)[..., :2],
        lever=geo.centre[..., :2] - joint,
        joint_velocity=joint_velocity,
        joint_acceleration=joint_acceleration,
        piston_com=piston[0],
        piston_velocity=piston[1],
        piston_acceleration=piston[2],
        link_com=link[0],
        link_velocity=link[1],
        link_acceleration=link[2],
        jacobian=jacobian,
    )
