"""Rotations in 3-D on batches (docs/spatial.md §2, §3): matrices, quaternions, roll–pitch–yaw.

Every function takes arrays whose leading axes are the batch and acts on the
last one (vectors ``(..., 3)``, quaternions ``(..., 4)`` scalar first) or two
(matrices ``(..., 3, 3)``).  Plain numpy; no validation (the public entries of
:mod:`prp3.spatial` validate).

>>> import numpy as np
>>> R = rpy_matrix(np.array([0.1, -0.2, 0.3]))
>>> np.allclose(quaternion_matrix(matrix_quaternion(R)), R)
True
>>> np.round(matrix_rpy(R), 12).tolist()
[0.1, -0.2, 0.3]
>>> np.round(log_rotation(exp_rotation(np.array([0.0, 0.0, 0.5]))), 12).tolist()
[0.0, 0.0, 0.5]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "axis_rotation",
    "cross",
    "exp_rotation",
    "log_rotation",
    "matrix_quaternion",
    "matrix_rpy",
    "quaternion_matrix",
    "rpy_matrix",
    "skew",
]

FloatArray = NDArray[np.float64]


def cross(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """``a × b`` over the last axis (broadcast), written out (faster than ``np.cross`` on small axes)."""
    u = np.asarray(a, dtype=np.float64)
    v = np.asarray(b, dtype=np.float64)
    return np.stack(
        [
            u[..., 1] * v[..., 2] - u[..., 2] * v[..., 1],
            u[..., 2] * v[..., 0] - u[..., 0] * v[..., 2],
            u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0],
        ],
        axis=-1,
    )


def skew(v: ArrayLike) -> FloatArray:
    """The matrix ``[v]×`` with ``[v]×·w = v × w``, shape ``(..., 3, 3)``."""
    w = np.asarray(v, dtype=np.float64)
    zero = np.zeros_like(w[..., 0])
    x, y, z = w[..., 0], w[..., 1], w[..., 2]
    rows = [np.stack(r, axis=-1) for r in ((zero, -z, y), (z, zero, -x), (-y, x, zero))]
    return np.stack(rows, axis=-2)


def axis_rotation(axis: int, angle: ArrayLike) -> FloatArray:
    """``Rot_x``, ``Rot_y`` or ``Rot_z`` (``axis`` 0, 1, 2) of ``angle (...)`` rad, ``(..., 3, 3)``."""
    a = np.asarray(angle, dtype=np.float64)
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((*a.shape, 3, 3))
    i, j = (axis + 1) % 3, (axis + 2) % 3  # cyclic: Rot_y turns z towards x
    out[..., axis, axis] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., j, i] = s
    out[..., i, j] = -s
    return out


def exp_rotation(phi: ArrayLike) -> FloatArray:
    """``exp([φ]×)``: the rotation by ``|φ|`` about ``φ/|φ|`` (Rodrigues), ``(..., 3, 3)``."""
    p = np.asarray(phi, dtype=np.float64)
    theta2 = np.einsum("...i,...i->...", p, p)
    theta = np.sqrt(theta2)
    small = theta2 < 1e-12
    safe = np.where(small, 1.0, theta)
    a = np.where(small, 1.0 - theta2 / 6.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - theta2 / 24.0, (1.0 - np.cos(safe)) / np.where(small, 1.0, theta2))
    k = skew(p)
    return np.eye(3) + a[..., None, None] * k + b[..., None, None] * (k @ k)


def log_rotation(rotation: ArrayLike) -> FloatArray:
    """The principal rotation vector ``φ`` (``|φ| ≤ π``) with ``exp([φ]×) = R``, ``(..., 3)``.

    Through the quaternion (accurate near 0 and near ``π``).
    """
    q = matrix_quaternion(rotation)
    w = q[..., 0]
    v = q[..., 1:]
    s = np.sqrt(np.einsum("...i,...i->...", v, v))
    angle = 2.0 * np.arctan2(s, w)
    small = s < 1e-12
    scale = np.where(small, 2.0 / np.where(w == 0.0, 1.0, w), angle / np.where(small, 1.0, s))
    return np.asarray(scale[..., None] * v)


def quaternion_matrix(quaternion: ArrayLike) -> FloatArray:
    """The rotation of unit quaternions ``[w, x, y, z]`` ``(..., 4)`` (normalised here), ``(..., 3, 3)``."""
    q = np.asarray(quaternion, dtype=np.float64)
    q = q / np.sqrt(np.einsum("...i,...i->...", q, q))[..., None]
    w, v = q[..., 0], q[..., 1:]
    k = skew(v)
    return np.asarray(np.eye(3) + 2.0 * w[..., None, None] * k + 2.0 * (k @ k))


def matrix_quaternion(rotation: ArrayLike) -> FloatArray:
    """The unit quaternion ``[w, x, y, z]`` with ``w ≥ 0`` of rotations ``(..., 3, 3)``, ``(..., 4)``.

    Shepperd's method: the largest of ``w, x, y, z`` is taken from the diagonal.
    """
    r = np.asarray(rotation, dtype=np.float64)
    trace = r[..., 0, 0] + r[..., 1, 1] + r[..., 2, 2]
    d = np.stack([trace, r[..., 0, 0], r[..., 1, 1], r[..., 2, 2]], axis=-1)
    pick = np.argmax(d, axis=-1)
    out = np.empty((*r.shape[:-2], 4))
    s_w = np.sqrt(np.maximum(1.0 + trace, 0.0)) * 2.0  # 4w
    cases = [
        (
            s_w,
            (
                s_w / 4.0,
                (r[..., 2, 1] - r[..., 1, 2]),
                (r[..., 0, 2] - r[..., 2, 0]),
                (r[..., 1, 0] - r[..., 0, 1]),
            ),
            0,
        )
    ]
    s_x = np.sqrt(np.maximum(1.0 + r[..., 0, 0] - r[..., 1, 1] - r[..., 2, 2], 0.0)) * 2.0
    cases.append(
        (
            s_x,
            (
                (r[..., 2, 1] - r[..., 1, 2]),
                s_x / 4.0,
                (r[..., 0, 1] + r[..., 1, 0]),
                (r[..., 0, 2] + r[..., 2, 0]),
            ),
            1,
        )
    )
    s_y = np.sqrt(np.maximum(1.0 - r[..., 0, 0] + r[..., 1, 1] - r[..., 2, 2], 0.0)) * 2.0
    cases.append(
        (
            s_y,
            (
                (r[..., 0, 2] - r[..., 2, 0]),
                (r[..., 0, 1] + r[..., 1, 0]),
                s_y / 4.0,
                (r[..., 1, 2] + r[..., 2, 1]),
            ),
            2,
        )
    )
    s_z = np.sqrt(np.maximum(1.0 - r[..., 0, 0] - r[..., 1, 1] + r[..., 2, 2], 0.0)) * 2.0
    cases.append(
        (
            s_z,
            (
                (r[..., 1, 0] - r[..., 0, 1]),
                (r[..., 0, 2] + r[..., 2, 0]),
                (r[..., 1, 2] + r[..., 2, 1]),
                s_z / 4.0,
            ),
            3,
        )
    )
    for s, parts, index in cases:
        chosen = pick == index
        if not chosen.any():
            continue
        safe = np.where(s == 0.0, 1.0, s)
        for component, part in enumerate(parts):
            value = part if component == index else part / safe
            out[..., component] = np.where(chosen, value, out[..., component])
    out = out / np.sqrt(np.einsum("...i,...i->...", out, out))[..., None]
    return np.asarray(np.where(out[..., :1] < 0.0, -out, out))


def rpy_matrix(rpy: ArrayLike) -> FloatArray:
    """``Rot_z(yaw)·Rot_y(pitch)·Rot_x(roll)`` of ``(roll, pitch, yaw)`` ``(..., 3)`` rad."""
    a = np.asarray(rpy, dtype=np.float64)
    return axis_rotation(2, a[..., 2]) @ axis_rotation(1, a[..., 1]) @ axis_rotation(0, a[..., 0])


def matrix_rpy(rotation: ArrayLike) -> FloatArray:
    """``(roll, pitch, yaw)`` of rotations ``(..., 3, 3)``: pitch in ``[−π/2, π/2]``, roll 0 at ``|pitch| = π/2``."""
    r = np.asarray(rotation, dtype=np.float64)
    pitch = np.arcsin(np.clip(-r[..., 2, 0], -1.0, 1.0))
    lock = np.hypot(r[..., 2, 1], r[..., 2, 2]) < 1e-12
    roll = np.where(lock, 0.0, np.arctan2(r[..., 2, 1], r[..., 2, 2]))
    yaw = np.where(
        lock, np.arctan2(-r[..., 0, 1], r[..., 1, 1]), np.arctan2(r[..., 1, 0], r[..., 0, 0])
    )
    return np.stack([roll, pitch, yaw], axis=-1)
