"""The elements that act on the bodies: gravity, a payload, the constant load, the motion's wrench.

Each class is one effect of :mod:`prp3.model.elements` (the interface:
:class:`~prp3.model.element_base.Element`): the weight of the bodies
(:class:`GravityElement`), a rigid body fixed to the platform
(:class:`PayloadElement`), the constant wrench ``[load]`` on the platform
(:class:`LoadElement`) and the motion's time-varying wrench ``fx, fy, mz``
(:class:`WrenchElement`).  The module imports nothing of prp3 but the
element base.

>>> from prp3.model.parameters import Load
>>> from prp3.model.robot import Robot
>>> LoadElement().parameters(Robot(load=Load(force=(1.0, 2.0))))
{'load_x': 1.0, 'load_y': 2.0, 'load_moment': 0.0}
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from prp3.model.element_base import Element, FloatArray, State, number_text

__all__ = ["GravityElement", "LoadElement", "PayloadElement", "WrenchElement"]

_SQRT3 = math.sqrt(3.0)
#: ``α_i`` of legs A, B, C (eq. 1), rad.
_ALPHA = np.array([math.pi / 3.0, math.pi, -math.pi / 3.0])
_E = np.stack([np.cos(_ALPHA), np.sin(_ALPHA)], axis=-1)  # e_i (3, 2)
_N = np.stack([-np.sin(_ALPHA), np.cos(_ALPHA)], axis=-1)  # n_i


def _weight_terms(robot: Any, state: State) -> tuple[FloatArray, FloatArray]:
    """Mass-weighted positions and velocities of the legs' and platform's mass centres.

    Returns ``Σ m r`` and ``Σ m v`` (shape ``(N, 2)``): pistons at
    ``P_i + c1x·e_i + c1y·n_i``, ``P_i = B_i0 + (l0/√3 + λ10_i)·e_i``; links at
    ``P_i + c2x·d_i + c2y·d⊥_i``; the platform at ``G``.
    """
    l0 = robot.l0
    phi = state.pose[:, 2]
    base = l0 * np.stack([np.sin(_ALPHA - math.pi / 3.0), -np.cos(_ALPHA - math.pi / 3.0)], -1)
    P = base + (l0 / _SQRT3 + state.lambda10)[..., None] * _E  # (N, 3, 2)
    Pd = state.dlambda10[..., None] * _E
    angle = _ALPHA + phi[:, None] - math.pi / 3.0
    d = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    dp = np.stack([-d[..., 1], d[..., 0]], axis=-1)
    (c1x, c1y), (c2x, c2y) = robot.piston.com, robot.link.com
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    r1 = P + c1x * _E + c1y * _N
    o2 = c2x * d + c2y * dp
    r2 = P + o2
    w = state.velocity[:, 2, None, None]
    v2 = Pd + w * np.stack([-o2[..., 1], o2[..., 0]], axis=-1)
    G, Gd = state.pose[:, :2], state.velocity[:, :2]
    moment = m1 * r1.sum(axis=1) + m2 * r2.sum(axis=1) + m3 * G
    momentum = m1 * Pd.sum(axis=1) + m2 * v2.sum(axis=1) + m3 * Gd
    return moment, momentum


@dataclass(frozen=True)
class GravityElement(Element):
    """The weight of the bodies (``Robot.gravity``, the paper's eq. 19).

    It enters the kernel through the inertial stage: each body needs
    ``m·(a_C − g)`` (eq. 22), so the fields are those of the model
    (``gravity_x, gravity_y``) and adds no applied force.  Potential
    energy ``−g·Σ m·r_C``; power ``g·Σ m·v_C`` (the payload's weight is the
    payload's).
    """

    name: str = "gravity"
    generated_c: bool = True

    def present(self, robot: Any) -> bool:
        return tuple(robot.gravity) != (0.0, 0.0)

    def power(self, robot: Any, state: State) -> FloatArray:
        return np.asarray(_weight_terms(robot, state)[1] @ np.asarray(robot.gravity))

    def potential(self, robot: Any, state: State) -> FloatArray | None:
        return np.asarray(-(_weight_terms(robot, state)[0] @ np.asarray(robot.gravity)))


def _payload_offset(robot: Any, state: State) -> tuple[FloatArray, FloatArray]:
    """The payload's mass centre from ``G`` (``Rot(φ)·c_p``) and its rate, ``(N, 2)``."""
    phi = state.pose[:, 2]
    cx, cy = robot.payload.com
    r = np.stack([np.cos(phi) * cx - np.sin(phi) * cy, np.sin(phi) * cx + np.cos(phi) * cy], -1)
    rd = state.velocity[:, 2, None] * np.stack([-r[:, 1], r[:, 0]], axis=-1)
    return r, rd


@dataclass(frozen=True)
class PayloadElement(Element):
    """A rigid body fixed to the platform (``[payload]``).

    It enters the kernel through the platform's standard parameters (mass,
    first moment about ``G``, inertia about ``G``; :meth:`inertial`), so the
    generated C code, the MJCF model (a welded body) and the regressor carry
    it as they carry the platform.  Its weight: potential ``−m_p·g·r_p``,
    power ``m_p·g·v_p``.
    """

    name: str = "payload"
    generated_c: bool = True

    def present(self, robot: Any) -> bool:
        return bool(robot.payload.present)

    def changes_statics(self, robot: Any) -> bool:
        return self.present(robot)

    def inertial(self, robot: Any) -> tuple[float, float, float, float]:
        """The platform's ``(m3, h3x, h3y, J3)`` with the payload added (about ``G``)."""
        m3, j3 = robot.platform.mass, robot.platform_inertia
        payload = robot.payload
        if not payload.present:
            return m3, 0.0, 0.0, j3
        mp, (cpx, cpy) = payload.mass, payload.com
        return m3 + mp, mp * cpx, mp * cpy, j3 + payload.inertia + mp * (cpx * cpx + cpy * cpy)

    def power(self, robot: Any, state: State) -> FloatArray:
        _, rd = _payload_offset(robot, state)
        v = state.velocity[:, :2] + rd
        return np.asarray(robot.payload.mass * (v @ np.asarray(robot.gravity)))

    def potential(self, robot: Any, state: State) -> FloatArray | None:
        r, _ = _payload_offset(robot, state)
        return np.asarray(
            -robot.payload.mass * ((state.pose[:, :2] + r) @ np.asarray(robot.gravity))
        )


@dataclass(frozen=True)
class LoadElement(Element):
    """The constant wrench of the environment on the platform (``[load]``): force at ``G``, moment.

    Applied to the platform, with the motion's time-varying wrench
    (:data:`WRENCH`) in :func:`prp3.mechanics.wrenches.body_wrenches`.  Its forces are known, not estimated
    (identification subtracts them); MuJoCo has no constant external force
    (the model stores it as the numeric ``prp3_load``).  Power ``F·Ġ + M·φ̇``.
    """

    name: str = "load"
    fields: tuple[str, ...] = ("load_x", "load_y", "load_moment")
    broadcast: tuple[str, ...] = ("load_x", "load_y", "load_moment")

    def present(self, robot: Any) -> bool:
        return bool(robot.load.present)

    def changes_statics(self, robot: Any) -> bool:
        return self.present(robot)

    def parameters(self, robot: Any) -> dict[str, float]:
        load = robot.load
        if not load.present:
            return {}
        return {"load_x": load.force[0], "load_y": load.force[1], "load_moment": load.moment}

    def power(self, robot: Any, state: State) -> FloatArray:
        fx, fy = robot.load.force
        v = state.velocity
        return np.asarray(fx * v[:, 0] + fy * v[:, 1] + robot.load.moment * v[:, 2])

    def mjcf_omissions(self, robot: Any) -> list[str]:
        if not robot.load.present:
            return []
        (fx, fy), m = robot.load.force, robot.load.moment
        wrench = ", ".join(number_text(v) for v in (fx, fy, 0.0, 0.0, 0.0, m))
        return [
            f"the constant [load]: apply it as data.xfrc_applied[platform_A] = ({wrench}) "
            "(numeric prp3_load)"
        ]


@dataclass(frozen=True)
class WrenchElement(Element):
    """The motion's time-varying wrench ``fx, fy, mz`` on the platform at ``G`` (``TRAJ.csv``).

    Not a robot's parameter (no field): :func:`prp3.mechanics.wrenches.body_wrenches` adds it
    to the constant load.  The generated C code has no input for it.
    Power ``f·Ġ + m_z·φ̇``.
    """

    name: str = "wrench"

    def power(self, robot: Any, state: State) -> FloatArray:
        if state.wrench is None:
            return np.zeros(state.pose.shape[0])
        return np.asarray((state.wrench * state.velocity).sum(axis=-1))
