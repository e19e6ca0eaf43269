"""The scalar pieces of the compiled engine: one leg's chain, closure and Jacobian per sample.

The kernels of :mod:`prp3.family.compiled_path` and :mod:`prp3.family.compiled`
call these per leg and per point (numba, ``cache=True``); they are the scalar
forms of :mod:`prp3.family.chain` (the chain frames, ``Ĵ``, ``det``, ``inv``, the
transmitted wrench, ``μ_par``) and :mod:`prp3.family.legs` (the closed-form
closure solutions of docs/family.md §5 and the branch of the working mode),
with the robot's constants read from the flat parameters of :func:`pack`.

>>> from prp3.family.model import FamilyRobot
>>> ints, par = pack(FamilyRobot.default("3-RRR"))
>>> ints.shape, par.shape, bool(par[PAR_SCALE] > 0)
((12,), (95,), True)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, TypeVar, cast

import numpy as np
from numpy.typing import NDArray

from prp3.family.chain import SIGMA, SINGULAR
from prp3.family.legs import LEG_GEOMETRY
from prp3.family.mechanics import MAX_MOVE, MAX_TURN, robot_length
from prp3.family.model import FamilyRobot
from prp3.pose_validation import MAX_ORIENTATION, POSE_BOUND

numba: Any
try:
    import numba
except ImportError:  # pragma: no cover - the numba extra is not installed
    numba = None

__all__ = ["pack"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
F = TypeVar("F", bound=Callable[..., Any])


def njit_compiled(function: F) -> F:
    """``numba.njit(cache=True, error_model="numpy")``, typed; the plain function without numba."""
    if numba is None:  # pragma: no cover
        return function
    return cast(F, numba.njit(cache=True, error_model="numpy")(function))


def njit_inlined(function: F) -> F:
    """:func:`njit_compiled` with ``inline="always"``: inlined by numba into the loops that call it.

    For the pieces that take arrays: a call numba does not inline counts the
    arrays' references (atomic increments and decrements, a third of the
    kernel's time when these pieces were plain calls).
    """
    if numba is None:  # pragma: no cover
        return function
    return cast(F, numba.njit(cache=True, error_model="numpy", inline="always")(function))


# ------------------------------------------------------------------ parameters
# Offsets into the float parameters ``par`` (see :func:`pack`).
PAR_PLACE, PAR_SCALE, PAR_TOTAL, PAR_LENGTH, PAR_BOUND, PAR_MAXPHI = 0, 12, 13, 14, 15, 16
PAR_SIGN_LEG, PAR_SIGN_PAR, PAR_HOME, PAR_OFFSET = 17, 20, 21, 24
PAR_COS, PAR_SIN, PAR_COSN, PAR_SINN = 27, 30, 33, 36
PAR_LINK1, PAR_LINK2, PAR_PLATFORM, PAR_PAYLOAD, PAR_LOAD, PAR_GRAVITY = 39, 43, 47, 49, 53, 56
PAR_ANGLE_C1, PAR_ANGLE_C2, PAR_R2, PAR_R3, PAR_V, PAR_W0, PAR_B, PAR_W0W0, PAR_U1, PAR_ROT = (
    58, 59, 60, 61, 62, 64, 66, 67, 68, 70,
)  # fmt: skip
PAR_TURN, PAR_MOVE, PAR_SINGULAR, PAR_HOME_POSES, PAR_SIGMA, PAR_CG, PAR_SG = (
    72,
    73,
    74,
    75,
    84,
    87,
    91,
)
PAR_PARAMETERS = 95

# Integer parameters ``ints``: types (0 = R, 1 = P) of joints 1–3, the pattern,
# the actuated joint (0-based), the number of R joints and their indices, the P joints.
PATTERN_ONE_R, PATTERN_RRR, PATTERN_RPR, PATTERN_PRR, PATTERN_RRP = 0, 1, 2, 3, 4
PATTERNS = {"PRP": PATTERN_ONE_R, "PPR": PATTERN_ONE_R, "RPP": PATTERN_ONE_R, "RRR": PATTERN_RRR, "RPR": PATTERN_RPR,
            "PRR": PATTERN_PRR, "RRP": PATTERN_RRP}  # fmt: skip

# Status codes of the kernel (``status[0]``); ``status[1]`` the sample, ``status[2]`` the leg.
(
    STATUS_OK,
    STATUS_OUT_OF_RANGE,
    STATUS_UNREACHABLE,
    STATUS_SINGULAR_LEG,
    STATUS_SINGULAR_PAR,
    STATUS_NOT_FINITE_KIN,
) = 0, 1, 2, 3, 4, 5
STATUS_NOT_FINITE_DYN = 6


def pack(robot: FamilyRobot) -> tuple[IntArray, FloatArray]:
    """The robot's parameters as the kernel reads them: ``(ints (12,), par (84,))``.

    Every constant the numpy engine computes once per call (the closed forms'
    lengths and angles of :mod:`prp3.family.legs`, the home signs, the turn
    offsets of the R angles, ``cos σ_j``...) is computed here by the same
    numpy expressions, and kept on the robot (it is immutable).
    """
    cached = robot.__dict__.get("_compiled_parameters")
    if cached is not None:
        return cast(tuple[IntArray, FloatArray], cached)
    types = robot.types
    placements = robot.leg.placements
    geometry = LEG_GEOMETRY[types](placements)
    home_leg, home_par = robot.home_measures
    home = np.asarray(robot.leg.home)
    revolute = [k for k in range(3) if types[k] == "R"]
    prismatic = [k for k in range(3) if types[k] == "P"] + [0, 0]
    ints = np.zeros(12, dtype=np.int64)
    ints[:3] = [0 if kind == "R" else 1 for kind in types]
    ints[3] = PATTERNS[types]
    ints[4] = robot.actuated - 1
    ints[5] = len(revolute)
    ints[6 : 6 + len(revolute)] = revolute
    ints[9:11] = prismatic[:2]
    par = np.zeros(PAR_PARAMETERS)
    par[PAR_PLACE : PAR_PLACE + 12] = placements.reshape(-1)
    par[PAR_SCALE] = robot.leg.scale
    par[PAR_TOTAL] = geometry.total
    length = robot_length(robot)
    par[PAR_LENGTH] = length
    par[PAR_BOUND] = POSE_BOUND * length
    par[PAR_MAXPHI] = MAX_ORIENTATION
    par[PAR_SIGN_LEG : PAR_SIGN_LEG + 3] = [math.copysign(1.0, v) for v in home_leg]
    par[PAR_SIGN_PAR] = math.copysign(1.0, home_par)
    par[PAR_HOME : PAR_HOME + 3] = home
    for j in range(3):  # the same expression as inverse_geometry's
        turns = home[revolute].sum() - (robot.home_poses[j, 2] - geometry.total)
        par[PAR_OFFSET + j] = 2.0 * math.pi * round(turns / (2.0 * math.pi))
    par[PAR_COS : PAR_COS + 3] = np.cos(SIGMA)
    par[PAR_SIN : PAR_SIN + 3] = np.sin(SIGMA)
    par[PAR_COSN : PAR_COSN + 3] = np.cos(-SIGMA)
    par[PAR_SINN : PAR_SINN + 3] = np.sin(-SIGMA)
    for at, body in ((PAR_LINK1, robot.link1), (PAR_LINK2, robot.link2)):
        par[at : at + 4] = [body.mass, body.com[0], body.com[1], body.inertia]
    par[PAR_PLATFORM : PAR_PLATFORM + 2] = [robot.platform.mass, robot.platform.inertia]
    payload = robot.payload
    par[PAR_PAYLOAD : PAR_PAYLOAD + 4] = [
        payload.mass,
        payload.com[0],
        payload.com[1],
        payload.inertia,
    ]
    par[PAR_LOAD : PAR_LOAD + 3] = [robot.load.force[0], robot.load.force[1], robot.load.moment]
    par[PAR_GRAVITY : PAR_GRAVITY + 2] = robot.gravity
    c = placements[:, :2]
    par[PAR_ANGLE_C1] = np.arctan2(c[1, 1], c[1, 0])
    par[PAR_ANGLE_C2] = np.arctan2(c[2, 1], c[2, 0])
    par[PAR_R2] = math.hypot(*c[1])
    par[PAR_R3] = math.hypot(*c[2])
    gamma = placements[:, 2]
    v = np.array([np.cos(gamma[1]), np.sin(gamma[1])])
    w0 = c[1] + np.array(
        [np.cos(gamma[1]) * c[2, 0] - np.sin(gamma[1]) * c[2, 1],
         np.sin(gamma[1]) * c[2, 0] + np.cos(gamma[1]) * c[2, 1]]
    )  # fmt: skip
    par[PAR_V : PAR_V + 2] = v
    par[PAR_W0 : PAR_W0 + 2] = w0
    par[PAR_B] = float(w0 @ v)
    par[PAR_W0W0] = float(w0 @ w0)
    par[PAR_U1 : PAR_U1 + 2] = [np.cos(gamma[0]), np.sin(gamma[0])]
    par[PAR_ROT : PAR_ROT + 2] = [
        np.cos(gamma[0]) * c[1, 0] - np.sin(gamma[0]) * c[1, 1],
        np.sin(gamma[0]) * c[1, 0] + np.cos(gamma[0]) * c[1, 1],
    ]
    par[PAR_TURN], par[PAR_MOVE], par[PAR_SINGULAR] = MAX_TURN, MAX_MOVE, SINGULAR
    par[PAR_HOME_POSES : PAR_HOME_POSES + 9] = robot.home_poses.reshape(-1)
    par[PAR_SIGMA : PAR_SIGMA + 3] = SIGMA
    par[PAR_CG : PAR_CG + 4] = np.cos(placements[:, 2])
    par[PAR_SG : PAR_SG + 4] = np.sin(placements[:, 2])
    ints.flags.writeable = False
    par.flags.writeable = False
    robot.__dict__["_compiled_parameters"] = (ints, par)
    return ints, par


# ------------------------------------------------------------------ scalar pieces
# A leg's frames in a flat buffer ``fr`` (33,): ``J_k`` origins [0:6] and angles [6:9],
# ``F_k`` origins [9:15] and angles [15:18], axes ``u_k`` [18:24], ``E`` [24:27]
# (x, y, angle), cos and sin of the ``F_k`` angles [27:33].
FRAME_JO, FRAME_JA, FRAME_FO, FRAME_FA, FRAME_AX, FRAME_END, FRAME_FCS = 0, 6, 9, 15, 18, 24, 27


@njit_inlined
def scalar_leg_chain(ints: IntArray, par: FloatArray, c: float, s: float, theta: float,
           q0: float, q1: float, q2: float, fr: FloatArray) -> None:  # fmt: skip
    """:func:`~prp3.family.chain.leg_chain` of one leg from the start frame ``(0, θ)``.

    ``c, s = cos θ, sin θ``; the frame angles are the same sums as the numpy
    engine's, their cosines and sines are composed (``cos(θ + γ) = c·cos γ − s·sin γ``),
    so each R joint costs one sine and one cosine of its ``q_k``.
    """
    px = 0.0
    py = 0.0
    for k in range(3):
        qk = q0 if k == 0 else (q1 if k == 1 else q2)
        a = par[PAR_PLACE + 3 * k]
        b = par[PAR_PLACE + 3 * k + 1]
        jx = px + (c * a - s * b)
        jy = py + (s * a + c * b)
        cg = par[PAR_CG + k]
        sg = par[PAR_SG + k]
        cj = c * cg - s * sg
        sj = s * cg + c * sg
        tj = theta + par[PAR_PLACE + 3 * k + 2]
        if ints[k] == 0:
            cq = math.cos(qk)
            sq = math.sin(qk)
            c = cj * cq - sj * sq
            s = sj * cq + cj * sq
            px = jx
            py = jy
            theta = tj + qk
        else:
            c = cj
            s = sj
            px = jx + qk * cj
            py = jy + qk * sj
            theta = tj
        fr[FRAME_JO + 2 * k] = jx
        fr[FRAME_JO + 2 * k + 1] = jy
        fr[FRAME_JA + k] = tj
        fr[FRAME_FO + 2 * k] = px
        fr[FRAME_FO + 2 * k + 1] = py
        fr[FRAME_FA + k] = theta
        fr[FRAME_AX + 2 * k] = cj
        fr[FRAME_AX + 2 * k + 1] = sj
        fr[FRAME_FCS + 2 * k] = c
        fr[FRAME_FCS + 2 * k + 1] = s
    a = par[PAR_PLACE + 9]
    b = par[PAR_PLACE + 10]
    fr[FRAME_END] = px + (c * a - s * b)
    fr[FRAME_END + 1] = py + (s * a + c * b)
    fr[FRAME_END + 2] = theta + par[PAR_PLACE + 11]


@njit_inlined
def scalar_leg_jacobian(ints: IntArray, fr: FloatArray, gx: float, gy: float, scale: float,
              out: FloatArray) -> None:  # fmt: skip
    """:func:`~prp3.family.chain.leg_jacobian`: columns ``(perp(G − O_k)/ℓ, 1)`` or ``(u_k, 0)``."""
    for k in range(3):
        if ints[k] == 0:
            out[0, k] = -(gy - fr[FRAME_FO + 2 * k + 1]) / scale
            out[1, k] = (gx - fr[FRAME_FO + 2 * k]) / scale
            out[2, k] = 1.0
        else:
            out[0, k] = fr[FRAME_AX + 2 * k]
            out[1, k] = fr[FRAME_AX + 2 * k + 1]
            out[2, k] = 0.0


@njit_inlined
def _column(out: FloatArray, n: int, k: int, revolute: bool, x: float, y: float, gx: float, gy: float,
            scale: float) -> None:  # fmt: skip
    """Column ``k`` of ``Ĵ`` ``out[n]``: ``(perp(G − O)/ℓ, 1)`` for ``O = (x, y)``, or ``(u, 0)`` for ``u = (x, y)``."""
    if revolute:
        out[n, 0, k] = -(gy - y) / scale
        out[n, 1, k] = (gx - x) / scale
        out[n, 2, k] = 1.0
    else:
        out[n, 0, k] = x
        out[n, 1, k] = y
        out[n, 2, k] = 0.0


@njit_inlined
def det3(m: FloatArray) -> float:
    """:func:`~prp3.family.chain.det3` (cofactors of row 0)."""
    return float(
        m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
        - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
        + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0])
    )


@njit_inlined
def _det3n(m: FloatArray, n: int) -> float:
    """:func:`det3` of ``m[n]`` (no view of ``m``, no reference counted)."""
    return float(
        m[n, 0, 0] * (m[n, 1, 1] * m[n, 2, 2] - m[n, 1, 2] * m[n, 2, 1])
        - m[n, 0, 1] * (m[n, 1, 0] * m[n, 2, 2] - m[n, 1, 2] * m[n, 2, 0])
        + m[n, 0, 2] * (m[n, 1, 0] * m[n, 2, 1] - m[n, 1, 1] * m[n, 2, 0])
    )


@njit_inlined
def _inverse3(m: FloatArray) -> tuple[float, ...]:
    """:func:`~prp3.family.chain.inv3`: the adjugate over the determinant, row by row."""
    a, b, c = m[0, 0], m[0, 1], m[0, 2]
    d, e, f = m[1, 0], m[1, 1], m[1, 2]
    g, h, i = m[2, 0], m[2, 1], m[2, 2]
    c0 = e * i - f * h
    c1 = f * g - d * i
    c2 = d * h - e * g
    det = a * c0 + b * c1 + c * c2
    return (
        c0 / det,
        (c * h - b * i) / det,
        (b * f - c * e) / det,
        c1 / det,
        (a * i - c * g) / det,
        (c * d - a * f) / det,
        c2 / det,
        (b * g - a * h) / det,
        (a * e - b * d) / det,
    )


@njit_inlined
def inv3(m: FloatArray, out: FloatArray) -> None:
    """The inverse of the 3×3 ``m`` into ``out`` (:func:`_inverse3`)."""
    (
        out[0, 0], out[0, 1], out[0, 2],
        out[1, 0], out[1, 1], out[1, 2],
        out[2, 0], out[2, 1], out[2, 2],
    ) = _inverse3(m)  # fmt: skip


@njit_inlined
def inv3j(m: FloatArray, out: FloatArray, j: int) -> None:
    """:func:`inv3` into ``out[j]`` (no view of ``out``, no reference counted)."""
    (
        out[j, 0, 0], out[j, 0, 1], out[j, 0, 2],
        out[j, 1, 0], out[j, 1, 1], out[j, 1, 2],
        out[j, 2, 0], out[j, 2, 1], out[j, 2, 2],
    ) = _inverse3(m)  # fmt: skip


@njit_inlined
def scalar_transmitted_wrench(ints: IntArray, m: FloatArray, out: FloatArray) -> None:
    """:func:`~prp3.family.chain.transmitted_wrench`: ``Ĵ[:, p] × Ĵ[:, r]`` of the passive joints."""
    a = ints[4]
    p = 1 if a == 0 else 0
    r = 1 if a == 2 else 2
    out[0] = m[1, p] * m[2, r] - m[2, p] * m[1, r]
    out[1] = m[2, p] * m[0, r] - m[0, p] * m[2, r]
    out[2] = m[0, p] * m[1, r] - m[1, p] * m[0, r]


@njit_inlined
def parallel(w: FloatArray, rows: FloatArray) -> float:
    """:func:`~prp3.family.chain.parallel_measure` of the wrenches ``w (3 legs, 3)``."""
    for j in range(3):
        norm = math.sqrt(w[j, 0] * w[j, 0] + w[j, 1] * w[j, 1] + w[j, 2] * w[j, 2])
        for i in range(3):
            rows[j, i] = w[j, i] / norm if norm > 0.0 else 0.0
    return det3(rows)


@njit_compiled
def _roots(b: float, c: float) -> tuple[float, float]:
    """The two roots ``−b ± √(b² − c)`` of ``s² + 2bs + c = 0`` (NaN when complex)."""
    root = math.sqrt(b * b - c)
    return -b + root, -b - root


@njit_inlined
def closure_branch(ints: IntArray, par: FloatArray, gx: float, gy: float, phi: float, sign: float,
            scale: float, q: FloatArray, cand: FloatArray,
            fr: FloatArray) -> None:  # fmt: skip
    """The closure solution of docs/family.md §5 at a leg-frame pose: ``q`` and its ``Ĵ`` (``cand[0]``).

    The closed forms of :mod:`prp3.family.legs`; of two solutions, the one whose
    ``sign·det Ĵ`` is the larger finite value (the first on a tie), ``Ĵ`` built
    from the joint origins and axes the closed form gives (no chain).  ``q``
    holds NaN when no solution is real; R angles modulo 2π.
    """
    pattern = ints[3]
    g3 = par[PAR_PLACE + 11]
    c0x, c0y = par[PAR_PLACE], par[PAR_PLACE + 1]
    if pattern == PATTERN_ONE_R:
        r = 3 - ints[9] - ints[10]
        qr = phi - par[PAR_TOTAL]
        scalar_leg_chain(ints, par, 1.0, 0.0, 0.0, qr if r == 0 else 0.0, qr if r == 1 else 0.0,
               qr if r == 2 else 0.0, fr)  # fmt: skip
        pa, pb = ints[9], ints[10]
        rx = gx - fr[FRAME_END]
        ry = gy - fr[FRAME_END + 1]
        uax, uay = fr[FRAME_AX + 2 * pa], fr[FRAME_AX + 2 * pa + 1]
        ubx, uby = fr[FRAME_AX + 2 * pb], fr[FRAME_AX + 2 * pb + 1]
        det = uax * uby - uay * ubx
        q[r] = qr
        q[pa] = (rx * uby - ry * ubx) / det
        q[pb] = (uax * ry - uay * rx) / det
        # O_r: the joint origin, moved by the slides before it
        ox, oy = fr[FRAME_FO + 2 * r], fr[FRAME_FO + 2 * r + 1]
        for k in range(r):
            ox += q[k] * fr[FRAME_AX + 2 * k]
            oy += q[k] * fr[FRAME_AX + 2 * k + 1]
        for k in range(3):
            if k == r:
                _column(cand, 0, k, True, ox, oy, gx, gy, scale)
            else:
                _column(
                    cand, 0, k, False, fr[FRAME_AX + 2 * k], fr[FRAME_AX + 2 * k + 1], gx, gy, scale
                )
        if not (math.isfinite(q[pa]) and math.isfinite(q[pb])):
            q[0] = np.nan
        return
    if pattern == PATTERN_RRP:
        t3 = phi - g3
        t2 = t3 - par[PAR_PLACE + 8]
        u3x, u3y = math.cos(t3), math.sin(t3)
        c2, s2 = math.cos(t2), math.sin(t2)
        a2, b2 = par[PAR_PLACE + 6], par[PAR_PLACE + 7]
        a3, b3 = par[PAR_PLACE + 9], par[PAR_PLACE + 10]
        kx = gx - c0x - (c2 * a2 - s2 * b2) - (u3x * a3 - u3y * b3)
        ky = gy - c0y - (s2 * a2 + c2 * b2) - (u3y * a3 + u3x * b3)
        r2 = par[PAR_R2]
        first, second = _roots(-(kx * u3x + ky * u3y), (kx * kx + ky * ky) - r2 * r2)
        for n in range(2):
            q3 = first if n == 0 else second
            _column(cand, n, 0, True, c0x, c0y, gx, gy, scale)
            _column(cand, n, 1, True, c0x + (kx - q3 * u3x), c0y + (ky - q3 * u3y), gx, gy, scale)
            _column(cand, n, 2, False, u3x, u3y, gx, gy, scale)
        q3 = _pick(sign, cand, first, second)
        t1 = math.atan2(ky - q3 * u3y, kx - q3 * u3x) - par[PAR_ANGLE_C1]
        q[0] = t1 - par[PAR_PLACE + 2]
        q[1] = t2 - t1 - par[PAR_PLACE + 5]
        q[2] = q3
        return
    # wrist O_3 = G − Rot(φ − γ_P)·c_P
    w = phi - g3
    cw, sw = math.cos(w), math.sin(w)
    a3, b3 = par[PAR_PLACE + 9], par[PAR_PLACE + 10]
    ox = gx - (cw * a3 - sw * b3)
    oy = gy - (sw * a3 + cw * b3)
    if pattern == PATTERN_RRR:
        r2, r3 = par[PAR_R2], par[PAR_R3]
        dx = ox - c0x
        dy = oy - c0y
        dist = math.hypot(dx, dy)
        along = (dist * dist + r2 * r2 - r3 * r3) / (2.0 * dist)
        height = math.sqrt(r2 * r2 - along * along)
        axx = dx / dist
        axy = dy / dist
        for n in range(2):
            h = height if n == 0 else -height
            _column(cand, n, 0, True, c0x, c0y, gx, gy, scale)
            _column(cand, n, 1, True, c0x + along * axx + h * -axy, c0y + along * axy + h * axx,
                    gx, gy, scale)  # fmt: skip
            _column(cand, n, 2, True, ox, oy, gx, gy, scale)
        h = _pick(sign, cand, height, -height)
        o2x = c0x + along * axx + h * -axy
        o2y = c0y + along * axy + h * axx
        t1 = math.atan2(o2y - c0y, o2x - c0x) - par[PAR_ANGLE_C1]
        t2 = math.atan2(oy - o2y, ox - o2x) - par[PAR_ANGLE_C2]
        q[0] = t1 - par[PAR_PLACE + 2]
        q[1] = t2 - t1 - par[PAR_PLACE + 5]
        q[2] = phi - g3 - t2 - par[PAR_PLACE + 8]
        return
    if pattern == PATTERN_RPR:
        dx = ox - c0x
        dy = oy - c0y
        vx, vy = par[PAR_V], par[PAR_V + 1]
        wx, wy = par[PAR_W0], par[PAR_W0 + 1]
        first, second = _roots(par[PAR_B], par[PAR_W0W0] - (dx * dx + dy * dy))
        for n in range(2):
            q2 = first if n == 0 else second
            ex = wx + q2 * vx
            ey = wy + q2 * vy
            norm = (dx * dx + dy * dy) ** 0.5 * (ex * ex + ey * ey) ** 0.5
            ct = (dx * ex + dy * ey) / norm  # Rot(θ_F1) turns e onto d
            st = (ex * dy - ey * dx) / norm
            _column(cand, n, 0, True, c0x, c0y, gx, gy, scale)
            _column(cand, n, 1, False, ct * vx - st * vy, st * vx + ct * vy, gx, gy, scale)
            _column(cand, n, 2, True, ox, oy, gx, gy, scale)
        q2 = _pick(sign, cand, first, second)
        t1 = math.atan2(dy, dx) - math.atan2(wy + q2 * vy, wx + q2 * vx)
        q[0] = t1 - par[PAR_PLACE + 2]
        q[1] = q2
        q[2] = phi - g3 - t1 - par[PAR_PLACE + 5] - par[PAR_PLACE + 8]
        return
    # PRR
    u1x, u1y = par[PAR_U1], par[PAR_U1 + 1]
    dx = ox - c0x - par[PAR_ROT]
    dy = oy - c0y - par[PAR_ROT + 1]
    r3 = par[PAR_R3]
    first, second = _roots(-(dx * u1x + dy * u1y), (dx * dx + dy * dy) - r3 * r3)
    for n in range(2):
        q1 = first if n == 0 else second
        _column(cand, n, 0, False, u1x, u1y, gx, gy, scale)
        _column(cand, n, 1, True, c0x + par[PAR_ROT] + q1 * u1x, c0y + par[PAR_ROT + 1] + q1 * u1y,
                gx, gy, scale)  # fmt: skip
        _column(cand, n, 2, True, ox, oy, gx, gy, scale)
    q1 = _pick(sign, cand, first, second)
    t2 = math.atan2(dy - q1 * u1y, dx - q1 * u1x) - par[PAR_ANGLE_C2]
    q[0] = q1
    q[1] = t2 - par[PAR_PLACE + 2] - par[PAR_PLACE + 5]
    q[2] = phi - g3 - t2 - par[PAR_PLACE + 8]


@njit_inlined
def _pick(sign: float, cand: FloatArray, first: float, second: float) -> float:
    """Of two solutions (their ``Ĵ`` in ``cand[0]``, ``cand[1]``), the one of §5; ``cand[0]`` ends up its ``Ĵ``.

    The larger finite ``sign·det Ĵ`` (the first on a tie); NaN (``cand[0]`` NaN) when neither is finite.
    """
    one = sign * _det3n(cand, 0)
    two = sign * _det3n(cand, 1)
    if math.isfinite(one) and (not math.isfinite(two) or one >= two):
        return first
    if math.isfinite(two):
        for i in range(3):
            for k in range(3):
                cand[0, i, k] = cand[1, i, k]
        return second
    for i in range(3):
        for k in range(3):
            cand[0, i, k] = np.nan
    return np.nan


@njit_compiled
def _mod_2pi(x: float) -> float:
    """``numpy.mod(x, 2π)`` (the result has the divisor's sign)."""
    period = 2.0 * math.pi
    m = np.fmod(x, period)
    if m != 0.0 and m < 0.0:
        m += period
    return float(m)


@njit_compiled
def unwrap_step(previous: float, value: float) -> float:
    """The correction ``numpy.unwrap`` adds for the step ``previous → value`` (multiple of 2π)."""
    dd = value - previous
    if abs(dd) < math.pi:
        return 0.0
    ddmod = _mod_2pi(dd + math.pi) - math.pi
    if ddmod == -math.pi and dd > 0.0:
        ddmod = math.pi
    return ddmod - dd


@njit_compiled
def segment_steps(x0: float, y0: float, p0: float, x1: float, y1: float, p1: float,
           length: float, turn: float, move: float) -> int:  # fmt: skip
    """Sub-steps of a segment: ``max(1, ceil(max(|Δφ|/MAX_TURN, |ΔG|/(MAX_MOVE·length))))``."""
    dist = math.hypot(x1 - x0, y1 - y0) / (move * length)
    return max(1, math.ceil(max(abs(p1 - p0) / turn, dist)))


@njit_inlined
def body_rate(ints: IntArray, rates: FloatArray, upto: int) -> float:
    """``Σ_{i < upto, R} q̇_i``: the angular rate of the body before joint ``upto``."""
    out = 0.0
    for i in range(upto):
        if ints[i] == 0:
            out += rates[i]
    return out


@njit_inlined
def point_velocity(ints: IntArray, fr: FloatArray, dq: FloatArray, body: int,
              px: float, py: float) -> tuple[float, float]:  # fmt: skip
    """Velocity of the point ``p`` fixed in body ``body`` (1..3): ``Σ_i q̇_i·s_i``."""
    vx = 0.0
    vy = 0.0
    for i in range(body):
        if ints[i] == 0:
            vx += dq[i] * -(py - fr[FRAME_FO + 2 * i + 1])
            vy += dq[i] * (px - fr[FRAME_FO + 2 * i])
        else:
            vx += dq[i] * fr[FRAME_AX + 2 * i]
            vy += dq[i] * fr[FRAME_AX + 2 * i + 1]
    return vx, vy


@njit_inlined
def point_acceleration(ints: IntArray, fr: FloatArray, dq: FloatArray, ddq: FloatArray, body: int,
                  px: float, py: float) -> tuple[float, float]:  # fmt: skip
    """Acceleration of the point ``p`` fixed in body ``body``: ``Σ_i q̈_i·s_i + q̇_i·ṡ_i``."""
    vx, vy = point_velocity(ints, fr, dq, body, px, py)
    ax = 0.0
    ay = 0.0
    for i in range(body):
        ux, uy = fr[FRAME_AX + 2 * i], fr[FRAME_AX + 2 * i + 1]
        if ints[i] == 0:
            o_x, o_y = fr[FRAME_FO + 2 * i], fr[FRAME_FO + 2 * i + 1]
            ovx, ovy = point_velocity(ints, fr, dq, i + 1, o_x, o_y)
            ax += ddq[i] * -(py - o_y)
            ay += ddq[i] * (px - o_x)
            ax += dq[i] * -(vy - ovy)
            ay += dq[i] * (vx - ovx)
        else:
            w = dq[i] * body_rate(ints, dq, i)
            ax = ax + ddq[i] * ux + w * -uy
            ay = ay + ddq[i] * uy + w * ux
    return ax, ay
