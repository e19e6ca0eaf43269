"""Hypothesis strategies and independent references for the spatial robots (docs/spatial.md).

Random hexapods (radii, angles, height, bodies with off-axis mass centres and
full inertia tensors, tilted gravity) and smooth motions near home whose
derivatives are written out here (sines of time); the reference formulas
(the hexapod's parallel Jacobian in closed form, finite differences) do not
call the code under test beyond the public constructors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, is_dataclass
from typing import Any

import numpy as np
from hypothesis import strategies as st
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import Body, SpatialRobot, delta, hexapod, three_rps
from prp3.spatial.motion import PlatformMotion, rpy_motion

FloatArray = NDArray[np.float64]


def _inertia(draw: st.DrawFn, scale: float) -> tuple[tuple[float, ...], ...]:
    """A random inertia tensor: random principal moments (triangle inequality) and axes."""
    a = draw(st.floats(0.2, 1.0))
    b = draw(st.floats(0.2, 1.0))
    c = draw(st.floats(abs(a - b) + 0.05, a + b - 0.01)) if a + b - 0.01 > abs(a - b) + 0.05 else a
    angles = [draw(st.floats(-math.pi, math.pi)) for _ in range(3)]
    rz, ry, rx = (np.eye(3) for _ in range(3))
    cz, sz = math.cos(angles[0]), math.sin(angles[0])
    rz[:2, :2] = [[cz, -sz], [sz, cz]]
    cy, sy = math.cos(angles[1]), math.sin(angles[1])
    ry[0, 0], ry[0, 2], ry[2, 0], ry[2, 2] = cy, sy, -sy, cy
    cx, sx = math.cos(angles[2]), math.sin(angles[2])
    rx[1:, 1:] = [[cx, -sx], [sx, cx]]
    r = rz @ ry @ rx
    tensor = scale * (r @ np.diag([a, b, c]) @ r.T)
    tensor = 0.5 * (tensor + tensor.T)
    return tuple(tuple(float(v) for v in row) for row in tensor)


@st.composite
def bodies(draw: st.DrawFn, name: str, centre_x: float, mass: float, scale: float) -> Body:
    """A body of random mass, mass centre near ``(centre_x, 0, 0)`` and inertia."""
    m = draw(st.floats(0.2 * mass, 3.0 * mass))
    centre = (
        centre_x * draw(st.floats(0.2, 1.5)),
        draw(st.floats(-0.01, 0.01)),
        draw(st.floats(-0.01, 0.01)),
    )
    return Body(m, centre, _inertia(draw, scale), name)


def _gravity(draw: st.DrawFn) -> tuple[float, float, float]:
    """A random gravity, tilted up to 3 m/s² from the vertical, 5 to 12 m/s² down."""
    return (draw(st.floats(-3.0, 3.0)), draw(st.floats(-3.0, 3.0)), -draw(st.floats(5.0, 12.0)))


@st.composite
def free_states(
    draw: st.DrawFn,
    robot: SpatialRobot,
    scales: tuple[float, float, float, float, float, float],
    n: int = 4,
) -> PlatformMotion:
    """``n`` random states near home, each component uniform within its scale (position
    offset m, rotation vector rad, ω, v, α, a): the parasitic components left to
    :func:`~prp3.spatial.kinematics.complete_motion`."""
    position, angle, omega, velocity, alpha, acceleration = scales

    def block(scale: float) -> FloatArray:
        return np.array([[draw(st.floats(-scale, scale)) for _ in range(3)] for _ in range(n)])

    return PlatformMotion.of(
        np.arange(n, dtype=np.float64),
        np.array(robot.home_position) + block(position),
        Rotation.from_euler("xyz", block(angle)).as_matrix(),
        block(omega), block(velocity), block(alpha), block(acceleration),
    )  # fmt: skip


@st.composite
def hexapods(draw: st.DrawFn) -> SpatialRobot:
    """A random 6-UPS hexapod (docs/spatial.md §7 with random parameters), wide limits."""
    gravity = _gravity(draw)
    return hexapod(
        base_radius=draw(st.floats(0.08, 0.14)),
        platform_radius=draw(st.floats(0.05, 0.08)),
        base_half_angle=math.radians(draw(st.floats(5.0, 20.0))),
        platform_half_angle=math.radians(draw(st.floats(35.0, 55.0))),
        home_height=draw(st.floats(0.07, 0.1)),
        stroke=(0.03, 0.3),
        u_limit=1.4,
        s_limit=1.4,
        cylinder=draw(bodies("cylinder", 0.025, 0.12, 4e-5)),
        rod=draw(bodies("rod", -0.03, 0.05, 1.5e-5)),
        platform=draw(bodies("platform", 0.0, 1.0, 2e-3)),
        gravity=gravity,
    )


@st.composite
def rps_robots(draw: st.DrawFn) -> SpatialRobot:
    """A random 3-RPS (docs/spatial.md §11 with random parameters), wide limits."""
    gravity = _gravity(draw)
    return three_rps(
        base_radius=draw(st.floats(0.08, 0.14)),
        platform_radius=draw(st.floats(0.04, 0.08)),
        home_height=draw(st.floats(0.08, 0.12)),
        stroke=(0.03, 0.3),
        r_limit=1.5,
        s_limit=1.4,
        cylinder=draw(bodies("cylinder", 0.025, 0.12, 4e-5)),
        rod=draw(bodies("rod", -0.03, 0.05, 1.5e-5)),
        platform=draw(bodies("platform", 0.0, 1.0, 2e-3)),
        gravity=gravity,
    )


@st.composite
def deltas(draw: st.DrawFn) -> SpatialRobot:
    """A random Delta as a 3-RUU (docs/spatial.md §12 with random parameters), wide limits."""
    gravity = _gravity(draw)
    arm = draw(st.floats(0.08, 0.14))
    base = draw(st.floats(0.08, 0.14))
    platform = draw(st.floats(0.02, 0.05))
    forearm = (base + arm - platform) * draw(st.floats(1.3, 1.8))
    level = math.sqrt(forearm**2 - (base + arm - platform) ** 2)  # the arm horizontal at home
    return delta(
        base_radius=base,
        arm=arm,
        forearm=forearm,
        platform_radius=platform,
        home_height=level * draw(st.floats(0.95, 1.05)),
        r_limit=1.5,
        u_limit=1.5,
        arm_body=draw(bodies("arm", arm / 2, 0.1, 8e-5)),
        forearm_body=draw(bodies("forearm", forearm / 2, 0.06, 3e-4)),
        platform=draw(bodies("platform", 0.0, 0.2, 6e-5)),
        gravity=gravity,
    )


@dataclass(frozen=True)
class Wave:
    """A smooth motion: ``p = p0 + A·sin(w t + c)``, ``rpy = B·sin(u t + d)`` (with derivatives)."""

    p0: FloatArray
    amplitude: FloatArray
    frequency: FloatArray
    phase: FloatArray
    angles: FloatArray
    angular_frequency: FloatArray
    angular_phase: FloatArray

    def pose(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``p, ṗ, p̈`` ``(N, 3)``."""
        arg = self.frequency * t[:, None] + self.phase
        a, w = self.amplitude, self.frequency
        return self.p0 + a * np.sin(arg), a * w * np.cos(arg), -a * w * w * np.sin(arg)

    def rpy(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """roll–pitch–yaw and their derivatives ``(N, 3)``."""
        arg = self.angular_frequency * t[:, None] + self.angular_phase
        b, u = self.angles, self.angular_frequency
        return b * np.sin(arg), b * u * np.cos(arg), -b * u * u * np.sin(arg)

    def motion(self, t: ArrayLike) -> PlatformMotion:
        times = np.atleast_1d(np.asarray(t, dtype=np.float64))
        p, v, a = self.pose(times)
        r, dr, ddr = self.rpy(times)
        return rpy_motion(times, p, r, v, dr, a, ddr)


@st.composite
def waves(draw: st.DrawFn, robot: SpatialRobot, size: float = 1.0) -> Wave:
    """A smooth motion around ``robot``'s home (``size`` scales the amplitudes)."""

    def triple(low: float, high: float) -> FloatArray:
        return np.array([draw(st.floats(low, high)) for _ in range(3)])

    return Wave(
        np.array(robot.home_position) + size * triple(-0.005, 0.005),
        size * triple(-0.008, 0.008),
        triple(0.5, 6.0),
        triple(-math.pi, math.pi),
        size * triple(-0.12, 0.12),
        triple(0.5, 6.0),
        triple(-math.pi, math.pi),
    )


#: The spatial architectures and their random designs.
ARCHITECTURES = {"6-UPS": hexapods, "3-RPS": rps_robots, "3-RUU": deltas}
#: The times of the exchange tests' motions (s).
EXCHANGE_TIMES = np.array([0.1, 0.45, 0.8])


def _leaves(value: Any) -> list[Any]:
    """Every leaf of a robot (its dataclasses and tuples) in order."""
    if is_dataclass(value) and not isinstance(value, type):
        return [leaf for f in fields(value) for leaf in _leaves(getattr(value, f.name))]
    if isinstance(value, tuple):
        return [leaf for item in value for leaf in _leaves(item)]
    return [value]


def assert_same_robot(a: SpatialRobot, b: SpatialRobot, tol: float) -> None:
    """``a`` and ``b`` leaf by leaf: equal, floats within ``tol`` relative (of 1 at least)."""
    left, right = _leaves(a), _leaves(b)
    assert len(left) == len(right)
    for x, y in zip(left, right, strict=True):
        if isinstance(x, float) and isinstance(y, float):
            assert x == y or abs(x - y) <= tol * max(1.0, abs(y)), (x, y)
        else:
            assert x == y


@st.composite
def robots_and_motions(draw: st.DrawFn, architecture: str) -> tuple[SpatialRobot, Any]:
    """A random design of ``architecture`` and a smooth motion of it at EXCHANGE_TIMES."""
    robot = draw(ARCHITECTURES[architecture]())
    motion = draw(waves(robot)).motion(EXCHANGE_TIMES)
    if robot.parasitic:
        motion = complete_motion(robot, motion)
    return robot, motion


def hexapod_parallel_jacobian(robot: SpatialRobot, motion: PlatformMotion) -> FloatArray:
    """The hexapod's closed form ``dq_P,i = u_i·v + (r_i × u_i)·ω``: rows ``(r_i × u_i, u_i)``."""
    base = np.array([leg.joints[0].position for leg in robot.legs])
    attach = np.array([leg.attachment_position for leg in robot.legs])
    r = np.einsum("nij,lj->nli", motion.rotation, attach)
    d = motion.position[:, None, :] + r - base[None]
    u = d / np.linalg.norm(d, axis=-1, keepdims=True)
    return np.concatenate([np.cross(r, u), u], axis=-1)


def angular_velocity(rotations: FloatArray, h: float) -> FloatArray:
    """``ω`` from five rotations at ``t − 2h … t + 2h`` ``(5, ..., 3, 3)``: ``Ṙ·Rᵀ = [ω]×``."""
    dr = (rotations[0] - 8 * rotations[1] + 8 * rotations[3] - rotations[4]) / (12 * h)
    w = dr @ np.swapaxes(rotations[2], -1, -2)
    return np.stack([w[..., 2, 1], w[..., 0, 2], w[..., 1, 0]], axis=-1)


def derivative(values: FloatArray, h: float) -> FloatArray:
    """The five-point central difference of ``values (5, ...)`` sampled at ``t − 2h … t + 2h``."""
    return (values[0] - 8 * values[1] + 8 * values[3] - values[4]) / (12 * h)
