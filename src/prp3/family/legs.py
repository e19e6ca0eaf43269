"""Inverse geometry of each leg architecture: one implementation of one interface per pattern.

Every leg pattern (``"PRP"``, ``"RPR"``, ...) is a :class:`LegGeometry`: given
the pose of the platform in the leg's own frame (the fixed frame turned by
``−σ_j``, so that every leg is leg A), :meth:`LegGeometry.candidates` returns
the closure solutions ``q`` in closed form — one for the three patterns with a
single R joint (its angle is ``φ − Γ``, the two slides then solve a 2×2 linear
system), two for the patterns with a quadratic (the two-branch RRR, PRR, RPR,
RRP).  The choice among them (docs/family.md §5) is made by
:func:`prp3.family.mechanics.inverse_geometry` from the sign of ``μ_leg``.

Notation (leg frame): ``c_k = (a_k, b_k)``, ``γ_k`` of ``joint{k}``; ``c_P``,
``γ_P`` of the attachment; ``Γ = γ_1 + γ_2 + γ_3 + γ_P``; the angle of the
attachment frame is ``φ``, so ``θ_{F3} = φ − γ_P``.

>>> import numpy as np
>>> from prp3.family.model import FamilyRobot
>>> robot = FamilyRobot.default("3-RRR")
>>> geometry = LEG_GEOMETRY["RRR"](robot.leg.placements)
>>> [np.round(q, 12).tolist() for q in geometry.candidates(np.zeros((1, 2)), np.zeros(1))]
[[[1.570796326795, -3.14159265359, 1.570796326795]], [[-0.0, 0.0, 0.0]]]
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np
from numpy.typing import NDArray

from prp3.family.chain import cross, leg_chain, perp, rotate, unit

__all__ = ["LEG_GEOMETRY", "LegGeometry"]

FloatArray = NDArray[np.float64]


class LegGeometry(ABC):
    """Closed-form closure solutions of one leg pattern (docs/family.md §2, §5).

    Parameters
    ----------
    placements : ndarray, shape (4, 3)
        ``joint1, joint2, joint3, attachment`` of the leg.
    """

    types: str = ""

    def __init__(self, placements: FloatArray) -> None:
        self.placements = np.asarray(placements, dtype=np.float64)
        self.c = self.placements[:, :2]
        self.gamma = self.placements[:, 2]
        self.total = float(self.gamma.sum())

    @abstractmethod
    def candidates(self, g: FloatArray, phi: FloatArray) -> list[FloatArray]:
        """Closure solutions ``q (n, 3)`` at poses ``g (n, 2)``, ``φ (n,)`` in the leg frame.

        R angles are returned modulo 2π; a pose out of reach gives NaN.
        """

    def wrist(self, g: FloatArray, phi: FloatArray) -> FloatArray:
        """``O_3 = G − Rot(φ − γ_P)·c_P``: the origin of ``F_3`` (for an R joint 3)."""
        return np.asarray(g - rotate(phi - self.gamma[3], self.c[3]))

    def linear(self, g: FloatArray, phi: FloatArray, q: FloatArray) -> FloatArray:
        """Fill the two P joints of a one-R pattern whose R angle ``q`` already holds.

        With the R angle known every frame angle is known; the chain end with the
        slides at zero is ``E_0``, and ``G − E_0 = q_a·u_a + q_b·u_b`` (Cramer's rule).
        """
        a, b = (k for k in range(3) if self.types[k] == "P")
        frames = leg_chain(self.types, self.placements, 0.0, q)
        rhs = g - frames.end_origin
        ua, ub = frames.axis[..., a, :], frames.axis[..., b, :]
        det = cross(ua, ub)
        with np.errstate(divide="ignore", invalid="ignore"):
            q[..., a] = cross(rhs, ub) / det
            q[..., b] = cross(ua, rhs) / det
        return q


def _roots(b: FloatArray, c: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The two roots ``−b ± √(b² − c)`` of ``s² + 2bs + c = 0`` (NaN when complex)."""
    with np.errstate(invalid="ignore"):
        root = np.sqrt(b * b - c)
    return -b + root, -b - root


def _angle(v: FloatArray) -> FloatArray:
    return np.asarray(np.arctan2(v[..., 1], v[..., 0]))


class OneRevolute(LegGeometry):
    """PRP, PPR, RPP: the R angle is ``φ − Γ``; the two slides are linear."""

    def candidates(self, g: FloatArray, phi: FloatArray) -> list[FloatArray]:
        q = np.zeros((*phi.shape, 3))
        q[..., self.types.index("R")] = phi - self.total
        return [self.linear(g, phi, q)]


class RRR(LegGeometry):
    """Base pivot ``O_1 = c_1``, elbow ``O_2`` on two circles: two branches."""

    types = "RRR"

    def candidates(self, g: FloatArray, phi: FloatArray) -> list[FloatArray]:
        o1 = self.c[0]
        o3 = self.wrist(g, phi)
        r2, r3 = math.hypot(*self.c[1]), math.hypot(*self.c[2])
        d = o3 - o1
        dist = np.hypot(d[..., 0], d[..., 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            along = (dist * dist + r2 * r2 - r3 * r3) / (2.0 * dist)
            height = np.sqrt(r2 * r2 - along * along)
            axis = d / dist[..., None]
        out = []
        for sign in (1.0, -1.0):
            o2 = o1 + along[..., None] * axis + (sign * height)[..., None] * perp(axis)
            t1 = _angle(o2 - o1) - _angle(self.c[1])
            t2 = _angle(o3 - o2) - _angle(self.c[2])
            q = np.stack(
                [
                    t1 - self.gamma[0],
                    t2 - t1 - self.gamma[1],
                    phi - self.gamma[3] - t2 - self.gamma[2],
                ],
                axis=-1,
            )
            out.append(q)
        return out


class RPR(LegGeometry):
    """``O_3 − c_1 = Rot(θ_F1)·(w_0 + q_2·v)``: a quadratic in the leg length ``q_2``."""

    types = "RPR"

    def candidates(self, g: FloatArray, phi: FloatArray) -> list[FloatArray]:
        d = self.wrist(g, phi) - self.c[0]
        v = unit(self.gamma[1])
        w0 = self.c[1] + rotate(self.gamma[1], self.c[2])
        b = float(w0 @ v)
        c = float(w0 @ w0) - np.sum(d * d, axis=-1)
        out = []
        for q2 in _roots(np.full(phi.shape, b), c):
            t1 = _angle(d) - _angle(w0 + q2[..., None] * v)
            q3 = phi - self.gamma[3] - t1 - self.gamma[1] - self.gamma[2]
            out.append(np.stack([t1 - self.gamma[0], q2, q3], axis=-1))
        return out


class PRR(LegGeometry):
    """``|D − q_1·u_1| = r_3``: a quadratic in the slide ``q_1``."""

    types = "PRR"

    def candidates(self, g: FloatArray, phi: FloatArray) -> list[FloatArray]:
        u1 = unit(self.gamma[0])
        d = self.wrist(g, phi) - self.c[0] - rotate(self.gamma[0], self.c[1])
        r3 = math.hypot(*self.c[2])
        b = -(d @ u1)
        c = np.sum(d * d, axis=-1) - r3 * r3
        out = []
        for q1 in _roots(b, c):
            t2 = _angle(d - q1[..., None] * u1) - _angle(self.c[2])
            q2 = t2 - self.gamma[0] - self.gamma[1]
            q3 = phi - self.gamma[3] - t2 - self.gamma[2]
            out.append(np.stack([q1, q2, q3], axis=-1))
        return out


class RRP(LegGeometry):
    """``K = Rot(θ_F1)·c_2 + q_3·u_3`` with ``θ_F2`` and ``u_3`` known: a quadratic in ``q_3``."""

    types = "RRP"

    def candidates(self, g: FloatArray, phi: FloatArray) -> list[FloatArray]:
        t3 = phi - self.gamma[3]
        t2 = t3 - self.gamma[2]
        u3 = unit(t3)
        k = g - self.c[0] - rotate(t2, self.c[2]) - rotate(t3, self.c[3])
        r2 = math.hypot(*self.c[1])
        b = -np.sum(k * u3, axis=-1)
        c = np.sum(k * k, axis=-1) - r2 * r2
        out = []
        for q3 in _roots(b, c):
            t1 = _angle(k - q3[..., None] * u3) - _angle(self.c[1])
            out.append(np.stack([t1 - self.gamma[0], t2 - t1 - self.gamma[1], q3], axis=-1))
        return out


class PRP(OneRevolute):
    types = "PRP"


class PPR(OneRevolute):
    types = "PPR"


class RPP(OneRevolute):
    types = "RPP"


#: The implementation of each leg pattern.
LEG_GEOMETRY: dict[str, type[LegGeometry]] = {
    kind.types: kind for kind in (PRP, RPR, RRR, PRR, PPR, RPP, RRP)
}
