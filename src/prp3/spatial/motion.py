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

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import ParameterError, TrajectoryError
from prp3.spatial.model import ORTHONORMAL_TOLERANCE, SpatialRobot
from prp3.spatial.rotations import axis_rotation, cross, quaternion_matrix, rpy_matrix
from prp3.validation import (
    check_choice,
    check_finite,
    check_instance,
    check_integer,
    check_real,
    check_scalar,
    check_times,
)

__all__ = [
    "MAX_ANGLE",
    "SPATIAL_MOTIONS",
    "PlatformMotion",
    "check_rpy",
    "quaternion_motion",
    "rpy_motion",
    "rpy_rates",
    "spatial_motion",
]

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


#: The largest roll, pitch or yaw taken (rad): beyond it float64 holds an angle to worse
#: than ``1e-10`` rad, and the rotation it names has lost its meaning.
MAX_ANGLE: float = 1e6


def check_rpy(rpy: FloatArray) -> FloatArray:
    """``rpy`` ``(N, 3)`` (rad) if every angle is within ``±MAX_ANGLE``, else refused naming it.

    >>> check_rpy(np.array([[0.0, 0.0, 1e300]]))
    Traceback (most recent call last):
    ...
    prp3.errors.TrajectoryError: motion: sample 0: yaw = 1e+300 rad is beyond +-1e+06 rad, where float64 no longer holds the angle to 1e-10 rad: give it modulo 2 pi
    """
    beyond = ~(np.abs(rpy) <= MAX_ANGLE)
    if beyond.any():
        k, i = (int(v) for v in np.argwhere(beyond)[0])
        name = ("roll", "pitch", "yaw")[i]
        raise TrajectoryError(
            f"{name} = {float(rpy[k, i])!r} rad is beyond +-{MAX_ANGLE:g} rad, where float64 "
            "no longer holds the angle to 1e-10 rad: give it modulo 2 pi",
            subject="motion",
            key=name,
            sample=k,
        )
    return rpy


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
    angles = check_rpy(_vectors("rpy", rpy, n, ("roll", "pitch", "yaw")))
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


#: The built-in motions of a spatial robot (``prp3 simulate --motion``, docs/spatial.md §15):
#: what each does, over ``t = 0 .. T`` with ``θ = 2π·t/T`` and ``ℓ`` the robot's scale.
SPATIAL_MOTIONS: dict[str, str] = {
    "heave": "p = home + (0, 0, 0.1·ℓ·sin θ)",
    "circle": "p = home + 0.1·ℓ·(cos θ − 1, sin θ, 0): a horizontal circle through home",
    "tilt": "roll = 0.1·sin θ, pitch = 0.1·(1 − cos θ) rad about home",
}

#: The twist components each built-in motion drives (refused where they are parasitic).
_DRIVES: dict[str, tuple[str, ...]] = {
    "heave": ("vz",),
    "circle": ("vx", "vy"),
    "tilt": ("wx", "wy"),
}


def spatial_motion(
    robot: SpatialRobot,
    name: str,
    samples: int = 301,
    duration: float = 3.0,
    *,
    times: ArrayLike | None = None,
) -> PlatformMotion:
    """A built-in motion of :data:`SPATIAL_MOTIONS` about ``robot``'s home, its exact rates.

    ``samples`` equally spaced times over ``0 .. duration`` (s), or the given ``times``
    (s, finite; ``samples`` then unused): the closed form at any instant, e.g. one
    sample at a time as the reference of :func:`~prp3.apps.spatial_control.spatial_track`
    (docs/spatial.md §23).  A motion that drives a
    component ``robot`` determines (``robot.parasitic``: the 3-RPS's circle, the Delta's
    tilt) is refused; the other parasitic components are left at home's (zero), for
    :func:`~prp3.spatial.kinematics.complete_motion` to solve.

    >>> from prp3.spatial.model import hexapod, delta
    >>> motion = spatial_motion(hexapod(), "heave", 5)
    >>> motion.position[:, 2].round(6).tolist(), motion.velocity[0].round(6).tolist()
    ([0.08, 0.09, 0.08, 0.07, 0.08], [0.0, 0.0, 0.020944])
    >>> spatial_motion(delta(), "tilt")
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: motion: the tilt motion drives wx, wy, which the 3-RUU determines itself (its parasitic components wx, wy, wz); choose one of heave, circle
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_choice("motion", name, tuple(SPATIAL_MOTIONS))
    n = check_integer("samples", samples, 2, 10**9)
    period = check_scalar("duration", duration, positive=True, unit="s")
    driven = [c for c in _DRIVES[name] if c in robot.parasitic]
    if driven:
        allowed = [m for m, drives in _DRIVES.items() if not set(drives) & set(robot.parasitic)]
        raise ParameterError(
            f"the {name} motion drives {', '.join(_DRIVES[name])}, which the {robot.name} "
            f"determines itself (its parasitic components {', '.join(robot.parasitic)}); "
            f"choose one of {', '.join(allowed)}",
            subject="motion",
            key="motion",
        )
    if times is None:
        t = np.linspace(0.0, period, n)
    else:
        t = check_times("times", times)
        n = t.size
    w = 2.0 * np.pi / period
    if not math.isfinite(w * w * max(0.1 * robot.scale, 0.1)):
        raise ParameterError(
            f"duration = {period!r} s is too short: the motion's accelerations overflow float64",
            key="duration",
        )
    return _closed_form(robot, name, t, w)


def _closed_form(robot: SpatialRobot, name: str, t: FloatArray, w: float) -> PlatformMotion:
    """The built-in motion ``name`` at the times ``t`` (s), ``w = 2π/T`` (rad/s)."""
    n = t.size
    theta = w * t
    sin, cos, zero = np.sin(theta), np.cos(theta), np.zeros(n)
    home = np.broadcast_to(np.asarray(robot.home_position), (n, 3))
    r = 0.1 * robot.scale
    rpy = np.zeros((n, 3))
    rpy_rate, rpy_acc = np.zeros((n, 3)), np.zeros((n, 3))
    velocity, acceleration = np.zeros((n, 3)), np.zeros((n, 3))
    offset = np.zeros((n, 3))
    if name == "heave":
        offset = np.stack([zero, zero, r * sin], axis=-1)
        velocity = np.stack([zero, zero, r * w * cos], axis=-1)
        acceleration = np.stack([zero, zero, -r * w * w * sin], axis=-1)
    elif name == "circle":
        offset = r * np.stack([cos - 1.0, sin, zero], axis=-1)
        velocity = r * w * np.stack([-sin, cos, zero], axis=-1)
        acceleration = -r * w * w * np.stack([cos, sin, zero], axis=-1)
    else:
        a = 0.1
        rpy = a * np.stack([sin, 1.0 - cos, zero], axis=-1)
        rpy_rate = a * w * np.stack([cos, sin, zero], axis=-1)
        rpy_acc = a * w * w * np.stack([-sin, cos, zero], axis=-1)
    omega, alpha = rpy_rates(rpy, rpy_rate, rpy_acc)
    rotation = np.asarray(robot.home_rotation) @ rpy_matrix(rpy)
    omega = omega @ np.asarray(robot.home_rotation).T
    alpha = alpha @ np.asarray(robot.home_rotation).T
    return PlatformMotion.of(t, home + offset, rotation, omega, velocity, alpha, acceleration)
