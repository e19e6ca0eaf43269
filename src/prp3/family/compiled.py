"""The family's fast route compiled by numba: one loop over the samples (docs/family.md §5–§7).

The same mechanics as :mod:`prp3.family.mechanics` (the ``"numpy"`` engine),
written per sample in scalar code that numba compiles to machine code
(``cache=True``: compiled once per machine, then loaded from ``__pycache__``):

1. the path of §5 from each leg's home pose through the samples, in the
   sub-steps of :func:`prp3.family.mechanics.follow` (``|Δφ| ≤ MAX_TURN``,
   ``|ΔG| ≤ MAX_MOVE`` robot lengths); at every point the closed-form closure
   solutions of :mod:`prp3.family.legs`, the one whose ``μ_leg`` has its home
   sign, R angles unwrapped continuously from home (``numpy.unwrap``'s rule);
   ``μ_leg`` and ``μ_par`` checked at every point;
2. the chain frames at the samples, ``J``, ``K = J⁻¹``, ``q̇ = K·t``,
   ``q̈ = K·(ṫ − J̇·q̇)``;
3. the wrench each body needs, the actuator efforts by virtual work
   ``Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L`` and every joint force
   ``W_3 = K_Lᵀ·(τ_L·e_a − B_L)``, ``W_2 = N_2 + W_3``, ``W_1 = N_1 + W_2``.

The kernel never raises and never validates: it reports the first refusal
(pose out of range, unreachable, singular or crossed, results not finite) as
a status, and :func:`compiled_dynamics` raises from it exactly the error the
numpy engine raises (same class, message and fields).  The inputs are
checked once, at the public entry :func:`prp3.family.family_inverse_dynamics`.

>>> from prp3.model.motion import paper_motion
>>> from prp3.family.model import FamilyRobot
>>> from prp3.family.mechanics import family_kinematics, fast_dynamics
>>> robot, motion = FamilyRobot.default("3-RRR"), paper_motion("vertical", 5)
>>> compiled = compiled_dynamics(robot, motion)
>>> reference = fast_dynamics(family_kinematics(robot, motion))
>>> bool(np.allclose(compiled.tau, reference.tau, rtol=1e-12, atol=0))
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, TypeVar, cast

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.family.chain import SIGMA, SINGULAR, ChainFrames
from prp3.family.legs import LEG_GEOMETRY
from prp3.family.mechanics import (
    MAX_MOVE,
    MAX_TURN,
    FamilyKinematics,
    FamilySolution,
    pose_bound_error,
    robot_length,
    singular_error,
    unreachable_error,
)
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.validation import LEGS, MAX_ORIENTATION, POSE_BOUND, require_finite

numba: Any
try:
    import numba
except ImportError:  # pragma: no cover - the numba extra is not installed
    numba = None

__all__ = ["compiled_dynamics", "pack"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
F = TypeVar("F", bound=Callable[..., Any])


def _compile(function: F) -> F:
    """``numba.njit(cache=True, error_model="numpy")``, typed; the plain function without numba."""
    if numba is None:  # pragma: no cover
        return function
    return cast(F, numba.njit(cache=True, error_model="numpy")(function))


# ------------------------------------------------------------------ parameters
# Offsets into the float parameters ``par`` (see :func:`pack`).
_PLACE, _SCALE, _TOTAL, _LENGTH, _BOUND, _MAXPHI = 0, 12, 13, 14, 15, 16
_SIGN_LEG, _SIGN_PAR, _HOME, _OFFSET = 17, 20, 21, 24
_COS, _SIN, _COSN, _SINN = 27, 30, 33, 36
_LINK1, _LINK2, _PLATFORM, _PAYLOAD, _LOAD, _GRAVITY = 39, 43, 47, 49, 53, 56
_ANGLE_C1, _ANGLE_C2, _R2, _R3, _V, _W0, _B, _W0W0, _U1, _ROT = (
    58, 59, 60, 61, 62, 64, 66, 67, 68, 70,
)  # fmt: skip
_TURN, _MOVE, _SINGULAR, _HOME_POSES, _SIGMA, _CG, _SG = 72, 73, 74, 75, 84, 87, 91
_PARAMETERS = 95

# Integer parameters ``ints``: types (0 = R, 1 = P) of joints 1–3, the pattern,
# the actuated joint (0-based), the number of R joints and their indices, the P joints.
_ONE_R, _RRR, _RPR, _PRR, _RRP = 0, 1, 2, 3, 4
_PATTERN = {"PRP": _ONE_R, "PPR": _ONE_R, "RPP": _ONE_R, "RRR": _RRR, "RPR": _RPR,
            "PRR": _PRR, "RRP": _RRP}  # fmt: skip

# Status codes of the kernel (``status[0]``); ``status[1]`` the sample, ``status[2]`` the leg.
_OK, _OUT_OF_RANGE, _UNREACHABLE, _SINGULAR_LEG, _SINGULAR_PAR, _NOT_FINITE_KIN = 0, 1, 2, 3, 4, 5
_NOT_FINITE_DYN = 6


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
    ints[3] = _PATTERN[types]
    ints[4] = robot.actuated - 1
    ints[5] = len(revolute)
    ints[6 : 6 + len(revolute)] = revolute
    ints[9:11] = prismatic[:2]
    par = np.zeros(_PARAMETERS)
    par[_PLACE : _PLACE + 12] = placements.reshape(-1)
    par[_SCALE] = robot.leg.scale
    par[_TOTAL] = geometry.total
    length = robot_length(robot)
    par[_LENGTH] = length
    par[_BOUND] = POSE_BOUND * length
    par[_MAXPHI] = MAX_ORIENTATION
    par[_SIGN_LEG : _SIGN_LEG + 3] = [math.copysign(1.0, v) for v in home_leg]
    par[_SIGN_PAR] = math.copysign(1.0, home_par)
    par[_HOME : _HOME + 3] = home
    for j in range(3):  # the same expression as inverse_geometry's
        turns = home[revolute].sum() - (robot.home_poses[j, 2] - geometry.total)
        par[_OFFSET + j] = 2.0 * math.pi * round(turns / (2.0 * math.pi))
    par[_COS : _COS + 3] = np.cos(SIGMA)
    par[_SIN : _SIN + 3] = np.sin(SIGMA)
    par[_COSN : _COSN + 3] = np.cos(-SIGMA)
    par[_SINN : _SINN + 3] = np.sin(-SIGMA)
    for at, body in ((_LINK1, robot.link1), (_LINK2, robot.link2)):
        par[at : at + 4] = [body.mass, body.com[0], body.com[1], body.inertia]
    par[_PLATFORM : _PLATFORM + 2] = [robot.platform.mass, robot.platform.inertia]
    payload = robot.payload
    par[_PAYLOAD : _PAYLOAD + 4] = [payload.mass, payload.com[0], payload.com[1], payload.inertia]
    par[_LOAD : _LOAD + 3] = [robot.load.force[0], robot.load.force[1], robot.load.moment]
    par[_GRAVITY : _GRAVITY + 2] = robot.gravity
    c = placements[:, :2]
    par[_ANGLE_C1] = np.arctan2(c[1, 1], c[1, 0])
    par[_ANGLE_C2] = np.arctan2(c[2, 1], c[2, 0])
    par[_R2] = math.hypot(*c[1])
    par[_R3] = math.hypot(*c[2])
    gamma = placements[:, 2]
    v = np.array([np.cos(gamma[1]), np.sin(gamma[1])])
    w0 = c[1] + np.array(
        [np.cos(gamma[1]) * c[2, 0] - np.sin(gamma[1]) * c[2, 1],
         np.sin(gamma[1]) * c[2, 0] + np.cos(gamma[1]) * c[2, 1]]
    )  # fmt: skip
    par[_V : _V + 2] = v
    par[_W0 : _W0 + 2] = w0
    par[_B] = float(w0 @ v)
    par[_W0W0] = float(w0 @ w0)
    par[_U1 : _U1 + 2] = [np.cos(gamma[0]), np.sin(gamma[0])]
    par[_ROT : _ROT + 2] = [
        np.cos(gamma[0]) * c[1, 0] - np.sin(gamma[0]) * c[1, 1],
        np.sin(gamma[0]) * c[1, 0] + np.cos(gamma[0]) * c[1, 1],
    ]
    par[_TURN], par[_MOVE], par[_SINGULAR] = MAX_TURN, MAX_MOVE, SINGULAR
    par[_HOME_POSES : _HOME_POSES + 9] = robot.home_poses.reshape(-1)
    par[_SIGMA : _SIGMA + 3] = SIGMA
    par[_CG : _CG + 4] = np.cos(placements[:, 2])
    par[_SG : _SG + 4] = np.sin(placements[:, 2])
    ints.flags.writeable = False
    par.flags.writeable = False
    robot.__dict__["_compiled_parameters"] = (ints, par)
    return ints, par


# ------------------------------------------------------------------ scalar pieces
# A leg's frames in a flat buffer ``fr`` (33,): ``J_k`` origins [0:6] and angles [6:9],
# ``F_k`` origins [9:15] and angles [15:18], axes ``u_k`` [18:24], ``E`` [24:27]
# (x, y, angle), cos and sin of the ``F_k`` angles [27:33].
_JO, _JA, _FO, _FA, _AX, _END, _FCS = 0, 6, 9, 15, 18, 24, 27


@_compile
def _chain(ints: IntArray, par: FloatArray, c: float, s: float, theta: float,
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
        a = par[_PLACE + 3 * k]
        b = par[_PLACE + 3 * k + 1]
        jx = px + (c * a - s * b)
        jy = py + (s * a + c * b)
        cg = par[_CG + k]
        sg = par[_SG + k]
        cj = c * cg - s * sg
        sj = s * cg + c * sg
        tj = theta + par[_PLACE + 3 * k + 2]
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
        fr[_JO + 2 * k] = jx
        fr[_JO + 2 * k + 1] = jy
        fr[_JA + k] = tj
        fr[_FO + 2 * k] = px
        fr[_FO + 2 * k + 1] = py
        fr[_FA + k] = theta
        fr[_AX + 2 * k] = cj
        fr[_AX + 2 * k + 1] = sj
        fr[_FCS + 2 * k] = c
        fr[_FCS + 2 * k + 1] = s
    a = par[_PLACE + 9]
    b = par[_PLACE + 10]
    fr[_END] = px + (c * a - s * b)
    fr[_END + 1] = py + (s * a + c * b)
    fr[_END + 2] = theta + par[_PLACE + 11]


@_compile
def _jacobian(ints: IntArray, fr: FloatArray, gx: float, gy: float, scale: float,
              out: FloatArray) -> None:  # fmt: skip
    """:func:`~prp3.family.chain.leg_jacobian`: columns ``(perp(G − O_k)/ℓ, 1)`` or ``(u_k, 0)``."""
    for k in range(3):
        if ints[k] == 0:
            out[0, k] = -(gy - fr[_FO + 2 * k + 1]) / scale
            out[1, k] = (gx - fr[_FO + 2 * k]) / scale
            out[2, k] = 1.0
        else:
            out[0, k] = fr[_AX + 2 * k]
            out[1, k] = fr[_AX + 2 * k + 1]
            out[2, k] = 0.0


@_compile
def _column(out: FloatArray, k: int, revolute: bool, x: float, y: float, gx: float, gy: float,
            scale: float) -> None:  # fmt: skip
    """Column ``k`` of ``Ĵ``: ``(perp(G − O)/ℓ, 1)`` for ``O = (x, y)``, or ``(u, 0)`` for ``u = (x, y)``."""
    if revolute:
        out[0, k] = -(gy - y) / scale
        out[1, k] = (gx - x) / scale
        out[2, k] = 1.0
    else:
        out[0, k] = x
        out[1, k] = y
        out[2, k] = 0.0


@_compile
def _det3(m: FloatArray) -> float:
    """:func:`~prp3.family.chain.det3` (cofactors of row 0)."""
    return float(
        m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
        - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
        + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0])
    )


@_compile
def _inv3(m: FloatArray, out: FloatArray) -> None:
    """:func:`~prp3.family.chain.inv3`: the adjugate over the determinant."""
    a, b, c = m[0, 0], m[0, 1], m[0, 2]
    d, e, f = m[1, 0], m[1, 1], m[1, 2]
    g, h, i = m[2, 0], m[2, 1], m[2, 2]
    c0 = e * i - f * h
    c1 = f * g - d * i
    c2 = d * h - e * g
    det = a * c0 + b * c1 + c * c2
    out[0, 0], out[1, 0], out[2, 0] = c0 / det, c1 / det, c2 / det
    out[0, 1], out[1, 1], out[2, 1] = (
        (c * h - b * i) / det,
        (a * i - c * g) / det,
        (b * g - a * h) / det,
    )
    out[0, 2], out[1, 2], out[2, 2] = (
        (b * f - c * e) / det,
        (c * d - a * f) / det,
        (a * e - b * d) / det,
    )


@_compile
def _wrench(ints: IntArray, m: FloatArray, out: FloatArray) -> None:
    """:func:`~prp3.family.chain.transmitted_wrench`: ``Ĵ[:, p] × Ĵ[:, r]`` of the passive joints."""
    a = ints[4]
    p = 1 if a == 0 else 0
    r = 1 if a == 2 else 2
    out[0] = m[1, p] * m[2, r] - m[2, p] * m[1, r]
    out[1] = m[2, p] * m[0, r] - m[0, p] * m[2, r]
    out[2] = m[0, p] * m[1, r] - m[1, p] * m[0, r]


@_compile
def _parallel(w: FloatArray, rows: FloatArray) -> float:
    """:func:`~prp3.family.chain.parallel_measure` of the wrenches ``w (3 legs, 3)``."""
    for j in range(3):
        norm = math.sqrt(w[j, 0] * w[j, 0] + w[j, 1] * w[j, 1] + w[j, 2] * w[j, 2])
        for i in range(3):
            rows[j, i] = w[j, i] / norm if norm > 0.0 else 0.0
    return _det3(rows)


@_compile
def _roots(b: float, c: float) -> tuple[float, float]:
    """The two roots ``−b ± √(b² − c)`` of ``s² + 2bs + c = 0`` (NaN when complex)."""
    root = math.sqrt(b * b - c)
    return -b + root, -b - root


@_compile
def _branch(ints: IntArray, par: FloatArray, gx: float, gy: float, phi: float, sign: float,
            scale: float, q: FloatArray, hat: FloatArray, other: FloatArray,
            fr: FloatArray) -> None:  # fmt: skip
    """The closure solution of docs/family.md §5 at a leg-frame pose: ``q`` and its ``Ĵ``.

    The closed forms of :mod:`prp3.family.legs`; of two solutions, the one whose
    ``sign·det Ĵ`` is the larger finite value (the first on a tie), ``Ĵ`` built
    from the joint origins and axes the closed form gives (no chain).  ``q``
    holds NaN when no solution is real; R angles modulo 2π.
    """
    pattern = ints[3]
    g3 = par[_PLACE + 11]
    c0x, c0y = par[_PLACE], par[_PLACE + 1]
    if pattern == _ONE_R:
        r = 3 - ints[9] - ints[10]
        qr = phi - par[_TOTAL]
        _chain(ints, par, 1.0, 0.0, 0.0, qr if r == 0 else 0.0, qr if r == 1 else 0.0,
               qr if r == 2 else 0.0, fr)  # fmt: skip
        pa, pb = ints[9], ints[10]
        rx = gx - fr[_END]
        ry = gy - fr[_END + 1]
        uax, uay = fr[_AX + 2 * pa], fr[_AX + 2 * pa + 1]
        ubx, uby = fr[_AX + 2 * pb], fr[_AX + 2 * pb + 1]
        det = uax * uby - uay * ubx
        q[r] = qr
        q[pa] = (rx * uby - ry * ubx) / det
        q[pb] = (uax * ry - uay * rx) / det
        # O_r: the joint origin, moved by the slides before it
        ox, oy = fr[_FO + 2 * r], fr[_FO + 2 * r + 1]
        for k in range(r):
            ox += q[k] * fr[_AX + 2 * k]
            oy += q[k] * fr[_AX + 2 * k + 1]
        for k in range(3):
            if k == r:
                _column(hat, k, True, ox, oy, gx, gy, scale)
            else:
                _column(hat, k, False, fr[_AX + 2 * k], fr[_AX + 2 * k + 1], gx, gy, scale)
        if not (math.isfinite(q[pa]) and math.isfinite(q[pb])):
            q[0] = np.nan
        return
    if pattern == _RRP:
        t3 = phi - g3
        t2 = t3 - par[_PLACE + 8]
        u3x, u3y = math.cos(t3), math.sin(t3)
        c2, s2 = math.cos(t2), math.sin(t2)
        a2, b2 = par[_PLACE + 6], par[_PLACE + 7]
        a3, b3 = par[_PLACE + 9], par[_PLACE + 10]
        kx = gx - c0x - (c2 * a2 - s2 * b2) - (u3x * a3 - u3y * b3)
        ky = gy - c0y - (s2 * a2 + c2 * b2) - (u3y * a3 + u3x * b3)
        r2 = par[_R2]
        first, second = _roots(-(kx * u3x + ky * u3y), (kx * kx + ky * ky) - r2 * r2)
        for n in range(2):
            q3 = first if n == 0 else second
            mat = hat if n == 0 else other
            _column(mat, 0, True, c0x, c0y, gx, gy, scale)
            _column(mat, 1, True, c0x + (kx - q3 * u3x), c0y + (ky - q3 * u3y), gx, gy, scale)
            _column(mat, 2, False, u3x, u3y, gx, gy, scale)
        q3 = _pick(sign, hat, other, first, second)
        t1 = math.atan2(ky - q3 * u3y, kx - q3 * u3x) - par[_ANGLE_C1]
        q[0] = t1 - par[_PLACE + 2]
        q[1] = t2 - t1 - par[_PLACE + 5]
        q[2] = q3
        return
    # wrist O_3 = G − Rot(φ − γ_P)·c_P
    w = phi - g3
    cw, sw = math.cos(w), math.sin(w)
    a3, b3 = par[_PLACE + 9], par[_PLACE + 10]
    ox = gx - (cw * a3 - sw * b3)
    oy = gy - (sw * a3 + cw * b3)
    if pattern == _RRR:
        r2, r3 = par[_R2], par[_R3]
        dx = ox - c0x
        dy = oy - c0y
        dist = math.hypot(dx, dy)
        along = (dist * dist + r2 * r2 - r3 * r3) / (2.0 * dist)
        height = math.sqrt(r2 * r2 - along * along)
        axx = dx / dist
        axy = dy / dist
        for n in range(2):
            h = height if n == 0 else -height
            mat = hat if n == 0 else other
            _column(mat, 0, True, c0x, c0y, gx, gy, scale)
            _column(mat, 1, True, c0x + along * axx + h * -axy, c0y + along * axy + h * axx,
                    gx, gy, scale)  # fmt: skip
            _column(mat, 2, True, ox, oy, gx, gy, scale)
        h = _pick(sign, hat, other, height, -height)
        o2x = c0x + along * axx + h * -axy
        o2y = c0y + along * axy + h * axx
        t1 = math.atan2(o2y - c0y, o2x - c0x) - par[_ANGLE_C1]
        t2 = math.atan2(oy - o2y, ox - o2x) - par[_ANGLE_C2]
        q[0] = t1 - par[_PLACE + 2]
        q[1] = t2 - t1 - par[_PLACE + 5]
        q[2] = phi - g3 - t2 - par[_PLACE + 8]
        return
    if pattern == _RPR:
        dx = ox - c0x
        dy = oy - c0y
        vx, vy = par[_V], par[_V + 1]
        wx, wy = par[_W0], par[_W0 + 1]
        first, second = _roots(par[_B], par[_W0W0] - (dx * dx + dy * dy))
        for n in range(2):
            q2 = first if n == 0 else second
            mat = hat if n == 0 else other
            ex = wx + q2 * vx
            ey = wy + q2 * vy
            norm = (dx * dx + dy * dy) ** 0.5 * (ex * ex + ey * ey) ** 0.5
            ct = (dx * ex + dy * ey) / norm  # Rot(θ_F1) turns e onto d
            st = (ex * dy - ey * dx) / norm
            _column(mat, 0, True, c0x, c0y, gx, gy, scale)
            _column(mat, 1, False, ct * vx - st * vy, st * vx + ct * vy, gx, gy, scale)
            _column(mat, 2, True, ox, oy, gx, gy, scale)
        q2 = _pick(sign, hat, other, first, second)
        t1 = math.atan2(dy, dx) - math.atan2(wy + q2 * vy, wx + q2 * vx)
        q[0] = t1 - par[_PLACE + 2]
        q[1] = q2
        q[2] = phi - g3 - t1 - par[_PLACE + 5] - par[_PLACE + 8]
        return
    # PRR
    u1x, u1y = par[_U1], par[_U1 + 1]
    dx = ox - c0x - par[_ROT]
    dy = oy - c0y - par[_ROT + 1]
    r3 = par[_R3]
    first, second = _roots(-(dx * u1x + dy * u1y), (dx * dx + dy * dy) - r3 * r3)
    for n in range(2):
        q1 = first if n == 0 else second
        mat = hat if n == 0 else other
        _column(mat, 0, False, u1x, u1y, gx, gy, scale)
        _column(mat, 1, True, c0x + par[_ROT] + q1 * u1x, c0y + par[_ROT + 1] + q1 * u1y,
                gx, gy, scale)  # fmt: skip
        _column(mat, 2, True, ox, oy, gx, gy, scale)
    q1 = _pick(sign, hat, other, first, second)
    t2 = math.atan2(dy - q1 * u1y, dx - q1 * u1x) - par[_ANGLE_C2]
    q[0] = q1
    q[1] = t2 - par[_PLACE + 2] - par[_PLACE + 5]
    q[2] = phi - g3 - t2 - par[_PLACE + 8]


@_compile
def _pick(sign: float, hat: FloatArray, other: FloatArray, first: float, second: float) -> float:
    """Of two solutions (``Ĵ`` in ``hat`` and ``other``), the one of §5: ``hat`` ends up its ``Ĵ``.

    The larger finite ``sign·det Ĵ`` (the first on a tie); NaN (``hat`` NaN) when neither is finite.
    """
    one = sign * _det3(hat)
    two = sign * _det3(other)
    if math.isfinite(one) and (not math.isfinite(two) or one >= two):
        return first
    if math.isfinite(two):
        for i in range(3):
            for k in range(3):
                hat[i, k] = other[i, k]
        return second
    for i in range(3):
        for k in range(3):
            hat[i, k] = np.nan
    return np.nan


@_compile
def _mod_2pi(x: float) -> float:
    """``numpy.mod(x, 2π)`` (the result has the divisor's sign)."""
    period = 2.0 * math.pi
    m = np.fmod(x, period)
    if m != 0.0 and m < 0.0:
        m += period
    return float(m)


@_compile
def _unwrap_step(previous: float, value: float) -> float:
    """The correction ``numpy.unwrap`` adds for the step ``previous → value`` (multiple of 2π)."""
    dd = value - previous
    if abs(dd) < math.pi:
        return 0.0
    ddmod = _mod_2pi(dd + math.pi) - math.pi
    if ddmod == -math.pi and dd > 0.0:
        ddmod = math.pi
    return ddmod - dd


@_compile
def _steps(x0: float, y0: float, p0: float, x1: float, y1: float, p1: float,
           length: float, turn: float, move: float) -> int:  # fmt: skip
    """Sub-steps of a segment: ``max(1, ceil(max(|Δφ|/MAX_TURN, |ΔG|/(MAX_MOVE·length))))``."""
    dist = math.hypot(x1 - x0, y1 - y0) / (move * length)
    return max(1, math.ceil(max(abs(p1 - p0) / turn, dist)))


@_compile
def _omega(ints: IntArray, rates: FloatArray, upto: int) -> float:
    """``Σ_{i < upto, R} q̇_i``: the angular rate of the body before joint ``upto``."""
    out = 0.0
    for i in range(upto):
        if ints[i] == 0:
            out += rates[i]
    return out


@_compile
def _velocity(ints: IntArray, fr: FloatArray, dq: FloatArray, body: int,
              px: float, py: float) -> tuple[float, float]:  # fmt: skip
    """Velocity of the point ``p`` fixed in body ``body`` (1..3): ``Σ_i q̇_i·s_i``."""
    vx = 0.0
    vy = 0.0
    for i in range(body):
        if ints[i] == 0:
            vx += dq[i] * -(py - fr[_FO + 2 * i + 1])
            vy += dq[i] * (px - fr[_FO + 2 * i])
        else:
            vx += dq[i] * fr[_AX + 2 * i]
            vy += dq[i] * fr[_AX + 2 * i + 1]
    return vx, vy


@_compile
def _acceleration(ints: IntArray, fr: FloatArray, dq: FloatArray, ddq: FloatArray, body: int,
                  px: float, py: float) -> tuple[float, float]:  # fmt: skip
    """Acceleration of the point ``p`` fixed in body ``body``: ``Σ_i q̈_i·s_i + q̇_i·ṡ_i``."""
    vx, vy = _velocity(ints, fr, dq, body, px, py)
    ax = 0.0
    ay = 0.0
    for i in range(body):
        ux, uy = fr[_AX + 2 * i], fr[_AX + 2 * i + 1]
        if ints[i] == 0:
            o_x, o_y = fr[_FO + 2 * i], fr[_FO + 2 * i + 1]
            ovx, ovy = _velocity(ints, fr, dq, i + 1, o_x, o_y)
            ax += ddq[i] * -(py - o_y)
            ay += ddq[i] * (px - o_x)
            ax += dq[i] * -(vy - ovy)
            ay += dq[i] * (vx - ovx)
        else:
            w = dq[i] * _omega(ints, dq, i)
            ax = ax + ddq[i] * ux + w * -uy
            ay = ay + ddq[i] * uy + w * ux
    return ax, ay


#: The doubles of every output of one sample, in the order of the kernel's buffer.
_SIZES = (9, 9, 9, 3, 1, 18, 9, 18, 9, 18, 9, 27, 27, 3, 3, 18, 9)
_WIDTH = sum(_SIZES)
_BYTES = [8 * int(at) for at in np.concatenate([[0], np.cumsum(_SIZES)[:-1]])]
_F8 = np.dtype(np.float64)
_array = np.ndarray  # views of the buffer: np.ndarray(shape, dtype, buffer, offset)


@_compile
def _kernel(ints: IntArray, par: FloatArray, pose: FloatArray, velocity: FloatArray,
            acceleration: FloatArray, buffer: FloatArray) -> tuple[IntArray, FloatArray]:  # fmt: skip
    """Every output at the samples; ``buffer`` (``n·_WIDTH``, from numpy) holds them, array by array."""
    n = pose.shape[0]
    status = np.zeros(4, dtype=np.int64)
    info = np.zeros(4)
    at = 0
    q = buffer[at : at + 9 * n].reshape((n, 3, 3))
    at += 9 * n
    dq = buffer[at : at + 9 * n].reshape((n, 3, 3))
    at += 9 * n
    ddq = buffer[at : at + 9 * n].reshape((n, 3, 3))
    at += 9 * n
    mu_leg = buffer[at : at + 3 * n].reshape((n, 3))
    at += 3 * n
    mu_par = buffer[at : at + n]
    at += n
    jo = buffer[at : at + 18 * n].reshape((n, 3, 3, 2))
    at += 18 * n
    ja = buffer[at : at + 9 * n].reshape((n, 3, 3))
    at += 9 * n
    fo = buffer[at : at + 18 * n].reshape((n, 3, 3, 2))
    at += 18 * n
    fa = buffer[at : at + 9 * n].reshape((n, 3, 3))
    at += 9 * n
    ax = buffer[at : at + 18 * n].reshape((n, 3, 3, 2))
    at += 18 * n
    end = buffer[at : at + 9 * n].reshape((n, 3, 3))
    at += 9 * n
    jac = buffer[at : at + 27 * n].reshape((n, 3, 3, 3))
    at += 27 * n
    inv = buffer[at : at + 27 * n].reshape((n, 3, 3, 3))
    at += 27 * n
    tau = buffer[at : at + 3 * n].reshape((n, 3))
    at += 3 * n
    power = buffer[at : at + 3 * n].reshape((n, 3))
    at += 3 * n
    force = buffer[at : at + 18 * n].reshape((n, 3, 3, 2))
    at += 18 * n
    moment = buffer[at : at + 9 * n].reshape((n, 3, 3))
    out = (status, info)
    # 1. poses in range (mechanics.check_poses)
    for k in range(n):
        if (abs(pose[k, 0]) > par[_BOUND] or abs(pose[k, 1]) > par[_BOUND]
                or abs(pose[k, 2]) > par[_MAXPHI]):  # fmt: skip
            status[0], status[1] = _OUT_OF_RANGE, k
            return out
    # 2. the path of §5 (mechanics.follow), the legs side by side from sample 0 on
    scale, singular = par[_SCALE], par[_SINGULAR]
    length, turn, move = par[_LENGTH], par[_TURN], par[_MOVE]
    work = np.zeros(256)  # every small array of the kernel, in one allocation
    fr = work[0:33]
    hat = work[33:42].reshape((3, 3))
    other = work[42:51].reshape((3, 3))
    chosen = work[51:54]
    raw = work[54:63].reshape((3, 3))  # the previous point's raw R angles of each leg
    unwrapped = work[63:72].reshape((3, 3))
    correction = work[72:81].reshape((3, 3))
    wrench = work[81:90].reshape((3, 3))
    one = work[90:93]
    rows = work[93:102].reshape((3, 3))
    point = work[102:105]
    lost_pose = work[105:114].reshape((3, 3))
    bad_leg_mu = work[114:117]
    bad_leg_pose = work[117:126].reshape((3, 3))
    bad_par_pose = work[126:129]
    homes = par[_HOME_POSES : _HOME_POSES + 9].reshape((3, 3))
    flags = np.full(12, -1)
    lost_at = flags[0:3]
    lost_exact = flags[3:6]
    bad_leg = flags[6:9]
    steps_of = flags[9:12]
    steps_of[:] = 1
    bad_par = -1
    bad_par_mu = 0.0
    nrev = ints[5]
    for sample in range(-1, n):  # -1: each leg's home pose itself
        if sample == 0:  # each leg from its home pose
            for j in range(3):
                steps_of[j] = _steps(homes[j, 0], homes[j, 1], homes[j, 2], pose[0, 0],
                                     pose[0, 1], pose[0, 2], length, turn, move)  # fmt: skip
        elif sample > 0:  # the same segment for the three legs
            steps_of[0] = _steps(pose[sample - 1, 0], pose[sample - 1, 1], pose[sample - 1, 2],
                                 pose[sample, 0], pose[sample, 1], pose[sample, 2], length,
                                 turn, move)  # fmt: skip
            steps_of[1] = steps_of[0]
            steps_of[2] = steps_of[0]
        most = max(steps_of[0], max(steps_of[1], steps_of[2]))
        for step in range(1, most + 1):
            for j in range(3):
                steps = steps_of[j]
                if step > steps:
                    continue
                for i in range(3):  # follow's point: start + (step/steps)·(end − start)
                    if sample == -1:
                        point[i] = homes[j, i]
                    elif step == steps:
                        point[i] = pose[sample, i]
                    else:
                        start = homes[j, i] if sample == 0 else pose[sample - 1, i]
                        point[i] = start + (step / steps) * (pose[sample, i] - start)
                cn, sn = par[_COSN + j], par[_SINN + j]
                gx = cn * point[0] - sn * point[1]
                gy = sn * point[0] + cn * point[1]
                sign = par[_SIGN_LEG + j]
                _branch(ints, par, gx, gy, point[2], sign, scale, chosen, hat, other, fr)
                owner = max(sample, 0)
                finite = (math.isfinite(chosen[0]) and math.isfinite(chosen[1])
                          and math.isfinite(chosen[2]))  # fmt: skip
                if not finite and lost_at[j] < 0:
                    lost_at[j] = owner
                    lost_exact[j] = 1 if step == steps else 0
                    for i in range(3):
                        lost_pose[j, i] = point[i]
                mu = _det3(hat)
                if not (sign * mu >= singular) and bad_leg[j] < 0:
                    bad_leg[j] = owner
                    bad_leg_mu[j] = mu
                    for i in range(3):
                        bad_leg_pose[j, i] = point[i]
                # R angles continuous from home (numpy.unwrap along the path)
                for r in range(nrev - 1):
                    k = ints[6 + r]
                    previous = par[_HOME + k] if sample == -1 else raw[j, k]
                    correction[j, k] += _unwrap_step(previous, chosen[k])
                    raw[j, k] = chosen[k]
                    unwrapped[j, k] = chosen[k] + correction[j, k]
                if nrev > 0:
                    others = 0.0
                    for r in range(nrev - 1):
                        others += unwrapped[j, ints[6 + r]]
                    last = ints[6 + nrev - 1]
                    unwrapped[j, last] = point[2] - par[_TOTAL] + par[_OFFSET + j] - others
                if step == steps and sample >= 0:
                    for k in range(3):
                        q[sample, j, k] = unwrapped[j, k] if ints[k] == 0 else chosen[k]
                if sample >= 1 or (sample == 0 and step == steps):
                    _wrench(ints, hat, one)  # the shared path: turned by σ_j
                    cs, ss = par[_COS + j], par[_SIN + j]
                    wrench[j, 0] = cs * one[0] - ss * one[1]
                    wrench[j, 1] = ss * one[0] + cs * one[1]
                    wrench[j, 2] = one[2]
            if sample >= 1 or (sample == 0 and step == most):
                value = _parallel(wrench, rows)
                if not (par[_SIGN_PAR] * value >= singular) and bad_par < 0:
                    bad_par = sample
                    bad_par_mu = value
                    for i in range(3):
                        bad_par_pose[i] = point[i]
    for j in range(3):  # the numpy engine's order: a lost leg first, then the earliest measure
        if lost_at[j] >= 0:
            status[0], status[1], status[2], status[3] = _UNREACHABLE, lost_at[j], j, lost_exact[j]
            info[0], info[1], info[2] = lost_pose[j, 0], lost_pose[j, 1], lost_pose[j, 2]
            return out
    first = -1
    for j in range(3):
        if bad_leg[j] >= 0 and (first < 0 or bad_leg[j] < status[1]):
            first = j
            status[0], status[1], status[2] = _SINGULAR_LEG, bad_leg[j], j
            info[0], info[1], info[2], info[3] = (
                bad_leg_pose[j, 0], bad_leg_pose[j, 1], bad_leg_pose[j, 2], bad_leg_mu[j]
            )  # fmt: skip
    if bad_par >= 0 and (first < 0 or bad_par < status[1]):
        status[0], status[1], status[2] = _SINGULAR_PAR, bad_par, -1
        info[0], info[1], info[2], info[3] = (
            bad_par_pose[0], bad_par_pose[1], bad_par_pose[2], bad_par_mu
        )  # fmt: skip
    if status[0] != _OK:
        return out
    # 3. frames, measures, kinematics and dynamics at the samples
    a = ints[4]
    gvx, gvy = par[_GRAVITY], par[_GRAVITY + 1]
    links = work[129:147].reshape((3, 2, 3))
    b = work[147:156].reshape((3, 3))
    rhs = work[156:159]
    matrix = work[159:168].reshape((3, 3))
    minv = work[168:177].reshape((3, 3))
    bias = work[177:186].reshape((3, 3))
    jm = work[186:195].reshape((3, 3))
    km = work[195:222].reshape((3, 3, 3))
    v = work[222:225]
    acc = work[225:228]
    kin_ok = True
    dyn_ok = True
    for k in range(n):
        gx, gy, phi = pose[k, 0], pose[k, 1], pose[k, 2]
        vgx, vgy, omega = velocity[k, 0], velocity[k, 1], velocity[k, 2]
        agx, agy, alpha = acceleration[k, 0], acceleration[k, 1], acceleration[k, 2]
        for j in range(3):
            _chain(ints, par, par[_COS + j], par[_SIN + j], par[_SIGMA + j], q[k, j, 0],
                   q[k, j, 1], q[k, j, 2], fr)  # fmt: skip
            for c in range(3):
                jo[k, j, c, 0] = fr[_JO + 2 * c]
                jo[k, j, c, 1] = fr[_JO + 2 * c + 1]
                ja[k, j, c] = fr[_JA + c]
                fo[k, j, c, 0] = fr[_FO + 2 * c]
                fo[k, j, c, 1] = fr[_FO + 2 * c + 1]
                fa[k, j, c] = fr[_FA + c]
                ax[k, j, c, 0] = fr[_AX + 2 * c]
                ax[k, j, c, 1] = fr[_AX + 2 * c + 1]
                end[k, j, c] = fr[_END + c]
            _jacobian(ints, fr, gx, gy, scale, hat)
            mu_leg[k, j] = _det3(hat)
            _wrench(ints, hat, one)
            for i in range(3):
                wrench[j, i] = one[i]
            _jacobian(ints, fr, gx, gy, 1.0, jm)
            kk = km[j]
            _inv3(jm, kk)
            for i in range(3):
                v[i] = kk[i, 0] * vgx + kk[i, 1] * vgy + kk[i, 2] * omega
            # J̇: R columns perp(Ġ − Ȯ_c), P columns ω_{J_c}·perp(u_c)
            for c in range(3):
                if ints[c] == 0:
                    ovx, ovy = _velocity(ints, fr, v, c + 1, fr[_FO + 2 * c], fr[_FO + 2 * c + 1])
                    bias[0, c] = -(vgy - ovy)
                    bias[1, c] = vgx - ovx
                else:
                    w = _omega(ints, v, c)
                    bias[0, c] = w * -fr[_AX + 2 * c + 1]
                    bias[1, c] = w * fr[_AX + 2 * c]
            rhs[0] = agx - (bias[0, 0] * v[0] + bias[0, 1] * v[1] + bias[0, 2] * v[2])
            rhs[1] = agy - (bias[1, 0] * v[0] + bias[1, 1] * v[1] + bias[1, 2] * v[2])
            rhs[2] = alpha
            for i in range(3):
                acc[i] = kk[i, 0] * rhs[0] + kk[i, 1] * rhs[1] + kk[i, 2] * rhs[2]
            for i in range(3):
                dq[k, j, i] = v[i]
                ddq[k, j, i] = acc[i]
                if not (math.isfinite(v[i]) and math.isfinite(acc[i])):
                    kin_ok = False
                for c in range(3):
                    jac[k, j, i, c] = jm[i, c]
                    inv[k, j, i, c] = kk[i, c]
            # the wrench each link needs, about G
            for body in range(1, 3):
                at = _LINK1 if body == 1 else _LINK2
                mass, comx, comy, inertia = par[at], par[at + 1], par[at + 2], par[at + 3]
                ca, sa = fr[_FCS + 2 * (body - 1)], fr[_FCS + 2 * (body - 1) + 1]
                cx = fr[_FO + 2 * (body - 1)] + (ca * comx - sa * comy)
                cy = fr[_FO + 2 * (body - 1) + 1] + (sa * comx + ca * comy)
                lax, lay = _acceleration(ints, fr, v, acc, body, cx, cy)
                fx = mass * (lax - gvx)
                fy = mass * (lay - gvy)
                links[j, body - 1, 0] = fx
                links[j, body - 1, 1] = fy
                links[j, body - 1, 2] = (inertia * _omega(ints, acc, body)
                                         + ((cx - gx) * fy - (cy - gy) * fx))  # fmt: skip
            # B_L[c] = J[:, c]·Σ_{links i ≥ c} N_i
            for c in range(3):
                total = 0.0
                for i in range(3):
                    if c == 0:
                        distal = links[j, 0, i] + links[j, 1, i]
                    elif c == 1:
                        distal = links[j, 1, i]
                    else:
                        distal = 0.0
                    total += jm[i, c] * distal
                b[j, c] = total
        mu_par[k] = _parallel(wrench, rows)
        # the platform's need minus the load (with the payload)
        pm, pi_ = par[_PLATFORM], par[_PLATFORM + 1]
        lm, lcx, lcy, li = par[_PAYLOAD], par[_PAYLOAD + 1], par[_PAYLOAD + 2], par[_PAYLOAD + 3]
        cp, sp = math.cos(phi), math.sin(phi)
        rx = cp * lcx - sp * lcy
        ry = sp * lcx + cp * lcy
        plx = lm * (agx + alpha * -ry - (omega * omega) * rx - gvx)
        ply = lm * (agy + alpha * rx - (omega * omega) * ry - gvy)
        rhs[0] = pm * (agx - gvx) + plx - par[_LOAD]
        rhs[1] = pm * (agy - gvy) + ply - par[_LOAD + 1]
        rhs[2] = pi_ * alpha + li * alpha + (rx * ply - ry * plx) - par[_LOAD + 2]
        # virtual work: Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L
        for i in range(3):
            for j in range(3):
                kk = km[j]
                rhs[i] += kk[0, i] * b[j, 0] + kk[1, i] * b[j, 1] + kk[2, i] * b[j, 2]
                matrix[i, j] = kk[a, i]
        _inv3(matrix, minv)
        for j in range(3):
            t_j = minv[j, 0] * rhs[0] + minv[j, 1] * rhs[1] + minv[j, 2] * rhs[2]
            tau[k, j] = t_j
            power[k, j] = t_j * dq[k, j, a]
            if not math.isfinite(t_j):
                dyn_ok = False
            # every joint force: W_3 = K_Lᵀ·(τ_L·e_a − B_L), W_2 = N_2 + W_3, W_1 = N_1 + W_2
            kk = km[j]
            e0 = (t_j if a == 0 else 0.0) - b[j, 0]
            e1 = (t_j if a == 1 else 0.0) - b[j, 1]
            e2 = (t_j if a == 2 else 0.0) - b[j, 2]
            for i in range(3):
                one[i] = kk[0, i] * e0 + kk[1, i] * e1 + kk[2, i] * e2
            for c in range(3):
                for i in range(3):
                    if c == 0:
                        rows[c, i] = links[j, 0, i] + links[j, 1, i] + one[i]
                    elif c == 1:
                        rows[c, i] = links[j, 1, i] + one[i]
                    else:
                        rows[c, i] = one[i]
                m_c = rows[c, 2] + ((gx - fo[k, j, c, 0]) * rows[c, 1]
                                    - (gy - fo[k, j, c, 1]) * rows[c, 0])  # fmt: skip
                force[k, j, c, 0] = rows[c, 0]
                force[k, j, c, 1] = rows[c, 1]
                moment[k, j, c] = m_c
                if not (math.isfinite(rows[c, 0]) and math.isfinite(rows[c, 1])
                        and math.isfinite(m_c)):  # fmt: skip
                    dyn_ok = False
    if not kin_ok:
        status[0] = _NOT_FINITE_KIN
    elif not dyn_ok:
        status[0] = _NOT_FINITE_DYN
    return out


# ------------------------------------------------------------------ the engine
def compiled_dynamics(robot: FamilyRobot, motion: Motion) -> FamilySolution:
    """The fast route by the compiled kernel: the same :class:`FamilySolution` as the numpy engine.

    ``robot`` and ``motion`` are taken as checked (by the public entry).  A
    refusal reported by the kernel is raised as the numpy engine raises it:
    :class:`~prp3.errors.TrajectoryError` (pose out of range, results not
    finite), :class:`~prp3.errors.UnreachablePoseError`,
    :class:`~prp3.errors.SingularPoseError` (the same message and fields).
    """
    if numba is None:  # pragma: no cover
        raise Prp3Error(
            'engine="numba" needs numba, which is not installed: pip install "prp3[numba]" '
            'or use engine="numpy"'
        )
    ints, par = pack(robot)
    shape = motion.t.shape
    t = motion.t.reshape(-1)
    pose = motion.pose.reshape(-1, 3)
    n = t.size
    buffer = np.empty(_WIDTH * n)  # allocated by numpy: huge pages for a large N
    status, info = _kernel(
        ints, par, _c(pose), _c(motion.velocity.reshape(-1, 3)),
        _c(motion.acceleration.reshape(-1, 3)), buffer,
    )  # fmt: skip
    o = [at * n for at in _BYTES]  # the outputs' places in the buffer, array by array
    if status[0] != _OK:
        _refuse(robot, status, info, pose, t, _array((n, 3, 3), _F8, buffer, o[1]),
                _array((n, 3, 3), _F8, buffer, o[2]), _array((n, 3), _F8, buffer, o[13]),
                _array((n, 3, 3, 2), _F8, buffer, o[15]),
                _array((n, 3, 3), _F8, buffer, o[16]))  # fmt: skip
    end = _array((n, 3, 3), _F8, buffer, o[10])
    frames = ChainFrames(
        _array((n, 3, 3, 2), _F8, buffer, o[5]),
        _array((n, 3, 3), _F8, buffer, o[6]),
        _array((n, 3, 3, 2), _F8, buffer, o[7]),
        _array((n, 3, 3), _F8, buffer, o[8]),
        _array((n, 3, 3, 2), _F8, buffer, o[9]),
        end[..., :2],
        end[..., 2],
    )
    rank, legs, joints = (*shape, 3, 3), (*shape, 3), (*shape, 3, 3, 2)
    q = _array(rank, _F8, buffer, 0)
    dq = _array(rank, _F8, buffer, o[1])
    ddq = _array(rank, _F8, buffer, o[2])
    kin = FamilyKinematics(
        robot, motion, q, dq, ddq, _array(legs, _F8, buffer, o[3]),
        _array(shape, _F8, buffer, o[4]), frames, _array((n, 3, 3, 3), _F8, buffer, o[11]),
        _array((n, 3, 3, 3), _F8, buffer, o[12]),
    )  # fmt: skip
    return FamilySolution(
        kin, q, dq, ddq, _array(legs, _F8, buffer, o[13]), _array(legs, _F8, buffer, o[14]),
        _array(joints, _F8, buffer, o[15]), _array(rank, _F8, buffer, o[16]), "fast",
    )  # fmt: skip


def _c(values: FloatArray) -> FloatArray:
    """``values`` as the kernel's one compiled signature takes it: C-contiguous, read-only."""
    if values.flags.c_contiguous and not values.flags.writeable:
        return values
    out = np.ascontiguousarray(values, dtype=np.float64)
    if out is values:
        out = out.copy()
    out.flags.writeable = False
    return out


def _refuse(
    robot: FamilyRobot,
    status: IntArray,
    info: FloatArray,
    pose: FloatArray,
    t: FloatArray,
    dq: FloatArray,
    ddq: FloatArray,
    tau: FloatArray,
    force: FloatArray,
    moment: FloatArray,
) -> None:
    """Raise the numpy engine's error for the kernel's status (docs/family.md §5, §6)."""
    code, k, leg = int(status[0]), int(status[1]), int(status[2])
    if code == _OUT_OF_RANGE:
        raise pose_bound_error(robot, pose, t, k)
    if code == _UNREACHABLE:
        note = "" if status[3] else f" on the way to sample {k}"
        raise unreachable_error(robot, leg, info, note, k, t)
    if code in (_SINGULAR_LEG, _SINGULAR_PAR):
        home_leg, home_par = robot.home_measures
        name, at_home = (
            (f"mu_leg of leg {LEGS[leg]}", home_leg[leg]) if code == _SINGULAR_LEG
            else ("mu_par", home_par)
        )  # fmt: skip
        raise singular_error(
            name, float(info[3]), info, pose, t, k,
            LEGS[leg] if code == _SINGULAR_LEG else None, at_home,
        )  # fmt: skip
    require_finite({"dq": dq, "ddq": ddq}, (t.size,), "motion", t)
    require_finite({"tau": tau, "force": force, "moment": moment}, (t.size,), "motion", t)
