"""The leg chain of docs/family.md §2: planar frames, placements, joint motions, measures.

A planar frame is an origin ``p`` (shape ``(..., 2)``) and an angle ``θ``
(shape ``(...)``).  Leg ``j`` starts in ``S_j = (O, σ_j)``, ``σ_j = 2πj/3``;
each joint ``k`` is the placement ``joint{k} = (a_k, b_k, γ_k)`` in the
preceding frame, moved by ``q_k`` (a turn for R, a slide along the joint
frame's ``x`` axis for P); the attachment frame ``E`` is the placement
``attachment`` in ``F_3``.

Everything here is plain numpy on arrays whose leading axes are the batch
(time, legs); it does not validate (the public entries of :mod:`prp3.family`
do).

>>> import numpy as np
>>> frames = leg_chain("RRR", np.array([[0, -0.3, 0], [0.2, 0, np.pi / 2],
...                    [0.2, 0, -np.pi / 2], [-0.2, 0.1, 0]]), 0.0, np.zeros(3))
>>> np.round(frames.end_origin, 12).tolist(), float(frames.end_angle)
([0.0, 0.0], 0.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "SIGMA",
    "SINGULAR",
    "ChainFrames",
    "cross",
    "det3",
    "inv3",
    "leg_chain",
    "leg_jacobian",
    "leg_measure",
    "parallel_measure",
    "perp",
    "rotate",
    "transmitted_wrench",
    "unit",
    "wrap",
]

FloatArray = NDArray[np.float64]

#: ``σ_j = 2πj/3`` of legs A, B, C (rad).
SIGMA: FloatArray = np.asarray(2.0 * math.pi * np.arange(3) / 3.0, dtype=np.float64)

#: Threshold of the signed singularity measures (docs/family.md §6).
SINGULAR: float = 1e-4


def unit(angle: ArrayLike) -> FloatArray:
    """``(cos θ, sin θ)``, shape ``(..., 2)``."""
    a = np.asarray(angle, dtype=np.float64)
    return np.stack([np.cos(a), np.sin(a)], axis=-1)


def perp(v: ArrayLike) -> FloatArray:
    """``Rot(π/2)·v = (−v_y, v_x)`` over the last axis."""
    w = np.asarray(v, dtype=np.float64)
    return np.stack([-w[..., 1], w[..., 0]], axis=-1)


def rotate(angle: ArrayLike, v: ArrayLike) -> FloatArray:
    """``Rot(θ)·v`` for broadcastable ``θ (...)`` and ``v (..., 2)``."""
    a = np.asarray(angle, dtype=np.float64)
    w = np.asarray(v, dtype=np.float64)
    c, s = np.cos(a), np.sin(a)
    return np.stack([c * w[..., 0] - s * w[..., 1], s * w[..., 0] + c * w[..., 1]], axis=-1)


def cross(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """``a × b = a_x b_y − a_y b_x`` over the last axis."""
    u = np.asarray(a, dtype=np.float64)
    v = np.asarray(b, dtype=np.float64)
    return np.asarray(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])


def wrap(angle: ArrayLike) -> FloatArray:
    """Angles wrapped into ``(−π, π]``."""
    a = np.asarray(angle, dtype=np.float64)
    return np.asarray(math.pi - np.mod(math.pi - a, 2.0 * math.pi))


@dataclass(frozen=True)
class ChainFrames:
    """The frames of a leg chain for joint values ``q`` (docs/family.md §2).

    Attributes
    ----------
    joint_origin, joint_angle : ndarray, shapes ``(..., 3, 2)``, ``(..., 3)``
        The joint-k frames ``J_k`` (before the joint moves).
    origin, angle : ndarray, shapes ``(..., 3, 2)``, ``(..., 3)``
        The body frames ``F_k``; ``origin[..., k, :]`` is the joint origin ``O_k``.
    axis : ndarray, shape ``(..., 3, 2)``
        ``u_k = (cos, sin)(angle of J_k)``, the slide axis of a P joint.
    end_origin, end_angle : ndarray, shapes ``(..., 2)``, ``(...)``
        The attachment frame ``E``.
    """

    joint_origin: FloatArray
    joint_angle: FloatArray
    origin: FloatArray
    angle: FloatArray
    axis: FloatArray
    end_origin: FloatArray
    end_angle: FloatArray


def leg_chain(types: str, placements: FloatArray, sigma: ArrayLike, q: ArrayLike) -> ChainFrames:
    """Frames of a leg with joint types ``types`` (``"RRR"`` ...) at joint values ``q``.

    Parameters
    ----------
    types : str
        Three letters R or P, base to platform.
    placements : ndarray, shape (4, 3)
        ``joint1, joint2, joint3, attachment`` as ``[a, b, γ]`` (m, m, rad).
    sigma : array_like, broadcastable with ``q[..., 0]``
        Angle of the start frame (rad): ``σ_j`` of the leg.
    q : array_like, shape ``(..., 3)``
        Joint values (m for P, rad for R).
    """
    qs = np.asarray(q, dtype=np.float64)
    batch = qs.shape[:-1]
    theta = np.broadcast_to(np.asarray(sigma, dtype=np.float64), batch).astype(np.float64)
    p = np.zeros((*batch, 2))
    j_origin, j_angle, f_origin, f_angle, axes = [], [], [], [], []
    for k in range(3):
        a, b, gamma = placements[k]
        pj = p + rotate(theta, np.array([a, b]))
        tj = theta + gamma
        u = unit(tj)
        if types[k] == "R":
            p, theta = pj, tj + qs[..., k]
        else:
            p, theta = pj + qs[..., k, None] * u, tj
        j_origin.append(pj)
        j_angle.append(tj)
        f_origin.append(p)
        f_angle.append(theta)
        axes.append(u)
    a, b, gamma = placements[3]
    return ChainFrames(
        joint_origin=np.stack(j_origin, axis=-2),
        joint_angle=np.stack(j_angle, axis=-1),
        origin=np.stack(f_origin, axis=-2),
        angle=np.stack(f_angle, axis=-1),
        axis=np.stack(axes, axis=-2),
        end_origin=p + rotate(theta, np.array([a, b])),
        end_angle=theta + gamma,
    )


def leg_jacobian(types: str, frames: ChainFrames, g: ArrayLike, scale: float = 1.0) -> FloatArray:
    """The leg's joint twists at the platform centre ``G`` as columns, shape ``(..., 3, 3)``.

    Column ``k`` is ``(perp(G − O_k)/ℓ, 1)`` for an R joint and ``(u_k, 0)``
    for a P joint (docs/family.md §6); with ``scale = ℓ = 1`` it maps the joint
    rates to the platform twist ``(ẋ, ẏ, φ̇) = J·q̇``.
    """
    centre = np.asarray(g, dtype=np.float64)
    columns = []
    for k in range(3):
        if types[k] == "R":
            v = perp(centre - frames.origin[..., k, :]) / scale
            one = np.ones(v.shape[:-1])
        else:
            v = frames.axis[..., k, :]
            one = np.zeros(v.shape[:-1])
        columns.append(np.concatenate([v, one[..., None]], axis=-1))
    return np.stack(columns, axis=-1)


def det3(m: FloatArray) -> FloatArray:
    """Determinants of stacked 3×3 matrices ``(..., 3, 3)`` in closed form (cofactors of row 0)."""
    return np.asarray(
        m[..., 0, 0] * (m[..., 1, 1] * m[..., 2, 2] - m[..., 1, 2] * m[..., 2, 1])
        - m[..., 0, 1] * (m[..., 1, 0] * m[..., 2, 2] - m[..., 1, 2] * m[..., 2, 0])
        + m[..., 0, 2] * (m[..., 1, 0] * m[..., 2, 1] - m[..., 1, 1] * m[..., 2, 0])
    )


def inv3(m: FloatArray) -> FloatArray:
    """Inverses of stacked 3×3 matrices ``(..., 3, 3)``: the adjugate over the determinant.

    >>> a = np.array([[2.0, 1.0, 0.0], [0.0, 1.0, 3.0], [1.0, 0.0, 1.0]])
    >>> bool(np.allclose(inv3(a) @ a, np.eye(3)))
    True
    """
    a, b, c = m[..., 0, 0], m[..., 0, 1], m[..., 0, 2]
    d, e, f = m[..., 1, 0], m[..., 1, 1], m[..., 1, 2]
    g, h, i = m[..., 2, 0], m[..., 2, 1], m[..., 2, 2]
    co = [e * i - f * h, f * g - d * i, d * h - e * g]
    det = a * co[0] + b * co[1] + c * co[2]
    adj = np.empty(m.shape)
    adj[..., 0, 0], adj[..., 1, 0], adj[..., 2, 0] = co
    adj[..., 0, 1], adj[..., 1, 1], adj[..., 2, 1] = c * h - b * i, a * i - c * g, b * g - a * h
    adj[..., 0, 2], adj[..., 1, 2], adj[..., 2, 2] = b * f - c * e, c * d - a * f, a * e - b * d
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(adj / det[..., None, None])


def leg_measure(jacobian_hat: FloatArray) -> FloatArray:
    """``μ_leg = det Ĵ`` (signed, dimensionless), docs/family.md §6."""
    return det3(jacobian_hat)


def transmitted_wrench(jacobian_hat: FloatArray, actuated: int) -> FloatArray:
    """``w_L = Ĵ[:, p] × Ĵ[:, r]`` of the two passive joints ``p < r``, shape ``(..., 3)``.

    ``actuated`` is the driven joint, 1 to 3.
    """
    p, r = (k for k in range(3) if k != actuated - 1)
    return np.asarray(np.cross(jacobian_hat[..., :, p], jacobian_hat[..., :, r]))


def parallel_measure(wrenches: FloatArray) -> FloatArray:
    """``μ_par = det[ŵ_A; ŵ_B; ŵ_C]`` of the legs' wrenches ``(..., 3 legs, 3)``.

    A leg that transmits no wrench (``|w| = 0``) gives ``μ_par = 0``.
    """
    norm = np.linalg.norm(wrenches, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        rows = np.where(norm > 0.0, wrenches / np.where(norm > 0.0, norm, 1.0), 0.0)
    return det3(rows)
