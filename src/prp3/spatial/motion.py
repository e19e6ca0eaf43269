"""The platform's motion on a batch of samples (docs/spatial.md §3, §4).

A :class:`PlatformMotion` is ``N`` independent samples (time on the leading
axis) of the pose ``(p, R)``, the twist ``(ω, v)`` (angular velocity in the
world frame, velocity of the platform origin) and its derivative ``(α, a)``.
It is validated when built (the project's :class:`~prp3.errors.TrajectoryError`,
naming the sample and the component).  :func:`rpy_motion` builds one from
roll–pitch–yaw angles and their derivatives, :func:`quaternion_motion` from
quaternions ``[w, x, y, z]`` and a twist.

>>> import numpy as np
>>> motion = PlatformMotion.at_rest([0.0, 0.0, 0.08])
>>> motion.position.shape, motion.rotation.shape, motion.omega.tolist()
((1, 3), (1, 3, 3), [[0.0, 0.0, 0.0]])
>>> PlatformMotion.at_rest([0.0, 0.0, float("nan")])
Traceback (most recent call last):
...
prp3.errors.TrajectoryError: motion: sample 0: z of position is not finite (nan)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import TrajectoryError
from prp3.spatial.model import ORTHONORMAL_TOLERANCE
from prp3.spatial.rotations import axis_rotation, cross, quaternion_matrix, rpy_matrix
from prp3.validation import check_finite, check_real, check_times

__all__ = ["PlatformMotion", "quaternion_motion", "rpy_motion", "rpy_rates"]

FloatArray = NDArray[np.float64]

_XYZ = ("x", "y", "z")


def _vectors(name: str, value: ArrayLike, n: int | None, components: tuple[str, ...]) -> FloatArray:
    array = check_real(name, value, TrajectoryError, "motion")
    if array.ndim == 1:
        array = array[None, :]
    k = len(components)
    if array.ndim != 2 or array.shape[1] != k or (n is not None and array.shape[0] != n):
        want = f"({'N' if n is None else n}, {k})"
        raise TrajectoryError(
            f"{name} must have shape {want}, got {array.shape}", subject="motion", key=name
        )
    return check_finite(name, array, components=components, subject="motion")


def _rotations(value: ArrayLike, n: int) -> FloatArray:
    array = check_real("rotation", value, TrajectoryError, "motion")
    if array.ndim == 2:
        array = array[None]
    if array.shape != (n, 3, 3):
        raise TrajectoryError(
            f"rotation must have shape ({n}, 3, 3), got {array.shape}",
            subject="motion",
            key="rotation",
        )
    check_finite("rotation", array.reshape(n, 9), subject="motion")
    error = np.abs(np.swapaxes(array, -1, -2) @ array - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(array)
    bad = (error > ORTHONORMAL_TOLERANCE) | (np.abs(det - 1.0) > ORTHONORMAL_TOLERANCE)
    if bad.any():
        k = int(np.argmax(bad))
        raise TrajectoryError(
            f"rotation is not a rotation matrix (|R^T R - I| = {error[k]:.3g}, "
            f"det = {det[k]:.12g})",
            subject="motion",
            sample=k,
            key="rotation",
        )
    return array


@dataclass(frozen=True)
class PlatformMotion:
    """``N`` samples of the platform's pose, twist and its derivative (docs/spatial.md §4).

    Attributes
    ----------
    t : (N,) s, strictly increasing
    position : (N, 3) m, the platform origin ``p``
    rotation : (N, 3, 3), ``R`` (world ← platform)
    omega : (N, 3) rad/s, angular velocity in the world frame
    velocity : (N, 3) m/s, velocity of ``p``
    alpha : (N, 3) rad/s², ``dω/dt``
    acceleration : (N, 3) m/s², ``dv/dt``
    """

    t: FloatArray
    position: FloatArray
    rotation: FloatArray
    omega: FloatArray
    velocity: FloatArray
    alpha: FloatArray
    acceleration: FloatArray

    @classmethod
    def of(
        cls,
        t: ArrayLike,
        position: ArrayLike,
        rotation: ArrayLike,
        omega: ArrayLike | None = None,
        velocity: ArrayLike | None = None,
        alpha: ArrayLike | None = None,
        acceleration: ArrayLike | None = None,
    ) -> PlatformMotion:
        """A validated motion; rates and accelerations left out are zero.

        Shapes as in the attributes; one sample may be given without its leading axis.
        """
        times = check_real("t", t, TrajectoryError, "motion")
        times = check_times("t", times.reshape(-1), subject="motion")
        n = times.shape[0]
        p = _vectors("position", position, n, _XYZ)
        r = _rotations(rotation, n)
        rates = [
            np.zeros((n, 3)) if value is None else _vectors(name, value, n, _XYZ)
            for name, value in (
                ("omega", omega),
                ("velocity", velocity),
                ("alpha", alpha),
                ("acceleration", acceleration),
            )
        ]
        return cls(times, p, r, *rates)

    @classmethod
    def at_rest(cls, position: ArrayLike, rotation: ArrayLike | None = None) -> PlatformMotion:
        """Poses at rest: ``position (3,)`` or ``(N, 3)``, ``rotation`` (identity by default)."""
        p = _vectors("position", position, None, _XYZ)
        n = p.shape[0]
        r = np.broadcast_to(np.eye(3), (n, 3, 3)) if rotation is None else rotation
        return cls.of(np.arange(n, dtype=np.float64), p, r)

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def chunk(self, start: int, stop: int) -> PlatformMotion:
        """Samples ``start:stop`` (views, not validated again)."""
        s = slice(start, stop)
        return PlatformMotion(
            self.t[s], self.position[s], self.rotation[s], self.omega[s],
            self.velocity[s], self.alpha[s], self.acceleration[s],
        )  # fmt: skip


def rpy_rates(
    rpy: FloatArray, rpy_rate: FloatArray, rpy_acceleration: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """``(ω, α)`` in the world frame of ``R = Rot_z(yaw)·Rot_y(pitch)·Rot_x(roll)`` and its rates.

    ``ω = ẏ·e_z + ṗ·Rz·e_y + ṙ·Rz·Ry·e_x``; ``α`` its derivative.  Shapes ``(N, 3)``.
    """
    rz = axis_rotation(2, rpy[..., 2])
    ry = axis_rotation(1, rpy[..., 1])
    e_z = np.broadcast_to(np.array([0.0, 0.0, 1.0]), rpy.shape)
    e_y = rz[..., :, 1]
    e_x = (rz @ ry)[..., :, 0]
    dr, dp, dy = (rpy_rate[..., i, None] for i in range(3))
    ddr, ddp, ddy = (rpy_acceleration[..., i, None] for i in range(3))
    w_z = dy * e_z
    w_zy = w_z + dp * e_y
    omega = w_zy + dr * e_x
    alpha = ddy * e_z + ddp * e_y + dp * cross(w_z, e_y) + ddr * e_x + dr * cross(w_zy, e_x)
    return omega, alpha


def rpy_motion(
    t: ArrayLike,
    position: ArrayLike,
    rpy: ArrayLike,
    velocity: ArrayLike | None = None,
    rpy_rate: ArrayLike | None = None,
    acceleration: ArrayLike | None = None,
    rpy_acceleration: ArrayLike | None = None,
) -> PlatformMotion:
    """A motion from roll–pitch–yaw (docs/spatial.md §3) and their time derivatives (rad, /s, /s²).

    ``position, rpy`` and their rates have shape ``(N, 3)``; rates left out are zero.
    """
    times = check_real("t", t, TrajectoryError, "motion").reshape(-1)
    n = times.shape[0]
    angles = _vectors("rpy", rpy, n, ("roll", "pitch", "yaw"))
    zero = np.zeros((n, 3))
    rate = zero if rpy_rate is None else _vectors("rpy_rate", rpy_rate, n, ("roll", "pitch", "yaw"))
    acc = (
        zero
        if rpy_acceleration is None
        else _vectors("rpy_acceleration", rpy_acceleration, n, ("roll", "pitch", "yaw"))
    )
    omega, alpha = rpy_rates(angles, rate, acc)
    return PlatformMotion.of(
        times, position, rpy_matrix(angles), omega, velocity, alpha, acceleration
    )


def quaternion_motion(
    t: ArrayLike,
    position: ArrayLike,
    quaternion: ArrayLike,
    omega: ArrayLike | None = None,
    velocity: ArrayLike | None = None,
    alpha: ArrayLike | None = None,
    acceleration: ArrayLike | None = None,
) -> PlatformMotion:
    """A motion from unit quaternions ``[w, x, y, z]`` ``(N, 4)`` (norm within ``1e-6`` of 1)."""
    times = check_real("t", t, TrajectoryError, "motion").reshape(-1)
    q = _vectors("quaternion", quaternion, times.shape[0], ("w", "x", "y", "z"))
    norm = np.sqrt(np.einsum("ij,ij->i", q, q))
    bad = np.abs(norm - 1.0) > 1e-6
    if bad.any():
        k = int(np.argmax(bad))
        raise TrajectoryError(
            f"quaternion is not a unit quaternion (norm {norm[k]:.12g})",
            subject="motion",
            sample=k,
            key="quaternion",
        )
    return PlatformMotion.of(
        times, position, quaternion_matrix(q), omega, velocity, alpha, acceleration
    )
