"""The spatial inverse dynamics compiled by numba, one sample at a time (docs/spatial.md §19).

:func:`compile_spatial` packs a :class:`~prp3.spatial.model.SpatialRobot` (joint
placements, bodies, limits, the signs of its measures at home) into one float64
vector and returns a :class:`CompiledSpatial`, whose ``solve`` (one state) and
``solve_batch`` (``N`` states) run one compiled loop (numba, ``cache=True``) of the
same steps as the numpy routes, on scalars:

1. each leg's closed-form inverse geometry on the branch of §5 (UPS, RPS, RUU), its
   chain of frames (§2) and the limits of §6;
2. the leg Jacobians at the legs' ends, ``x_i = J_i⁻ᵀ·e_a`` (``J_i(J_iᵀJ_i)⁻¹·e_a``
   and the constraint wrench ``w_i`` for a leg of 5 coordinates), the parallel
   Jacobian and the measures ``μ_leg``, ``μ_par`` refused below ``SINGULAR`` times
   their sign at home;
3. ``dq``, ``ddq`` from ``J_i·dq = (ω, v + ω × r_i)`` and the chain's recursion (§4, §8);
4. every body's inertial wrench, the leg bodies' balances from the platform inwards
   with ``W_n = 0``, the ``6 × 6`` system of the platform's balance for ``(τ, λ)`` and
   every joint's wrench (the structure of route (b),
   :func:`~prp3.spatial.newton_euler.recursive_newton_euler`).

The kernel never raises: it returns a status (:data:`SPATIAL_STATUS`, the codes of
the generated C of ``prp3 export c``), and the entries raise from it the error of
the numpy route (the numpy route is run on the refused sample, which raises it with
its message naming the sample, time and leg).  Inputs are checked by the entries
(shapes, finiteness, rotations orthonormal to ``1e-9``) before the kernel runs.

>>> from prp3.spatial.model import hexapod
>>> robot = hexapod()
>>> kernel = compile_spatial(robot)
>>> out = kernel.solve(robot.home_position, np.eye(3), np.zeros(3), np.zeros(3),
...                    np.zeros(3), np.zeros(3))
>>> round(float(out.tau[0]), 6), out.force.shape
(2.804864, (6, 3, 3))
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.errors import Prp3Error, TrajectoryError
from prp3.spatial.kinematics import COMPATIBILITY, SINGULAR, chunk_kinematics, home_signs
from prp3.spatial.model import ORTHONORMAL_TOLERANCE, SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.validation import check_instance

__all__ = [
    "SPATIAL_STATUS",
    "CompiledSpatial",
    "SpatialSample",
    "SpatialSamples",
    "compile_spatial",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The kernel's status codes (those of the generated C, ``prp3 export c``): name, value, meaning.
SPATIAL_STATUS: tuple[tuple[str, int, str], ...] = (
    ("PRP3_OK", 0, "every output computed and finite"),
    ("PRP3_NOT_FINITE", 1, "an input is NaN or infinite"),
    ("PRP3_SINGULAR", 2, "a measure mu_leg or mu_par, times its sign at home, is below 1e-4"),
    ("PRP3_OUTSIDE_STROKE", 3, "a P length is outside its stroke"),
    ("PRP3_UNREACHABLE", 4, "a leg cannot reach the pose (its closure has no real solution)"),
    (
        "PRP3_OVERFLOW",
        5,
        "the inputs are finite, an output is not: too large for double precision",
    ),
    ("PRP3_JOINT_LIMIT", 6, "an R or U angle, or an S rotation angle, is beyond its limit"),
    ("PRP3_NOT_ROTATION", 7, "the rotation is not orthonormal with determinant 1 (to 1e-9)"),
    (
        "PRP3_NOT_A_POSE",
        8,
        "a leg of 5 coordinates cannot close at the pose (not a pose of the robot's DOF)",
    ),
    (
        "PRP3_INCOMPATIBLE",
        9,
        "the twist or its derivative is not one the legs of 5 coordinates allow",
    ),
)
_OK, _NOT_FINITE, _SINGULAR, _STROKE, _UNREACHABLE, _OVERFLOW = 0, 1, 2, 3, 4, 5
_LIMIT, _NOT_ROTATION, _NOT_A_POSE, _INCOMPATIBLE = 6, 7, 8, 9

# ------------------------------------------------------------------ the packed robot
_L, _J = 6, 3  # at most 6 legs of 3 joints
JPOS = 0  # (legs, joints, 3) joint placements
JROT = JPOS + _L * _J * 3  # (legs, joints, 9)
APOS = JROT + _L * _J * 9  # (legs, 3)
AROT = APOS + _L * 3  # (legs, 9)
BMASS = AROT + _L * 9  # (legs, 2)
BCEN = BMASS + _L * 2  # (legs, 2, 3)
BINE = BCEN + _L * 2 * 3  # (legs, 2, 9)
PMASS = BINE + _L * 2 * 9
PCEN = PMASS + 1
PINE = PCEN + 3
GRAV = PINE + 9
SCALE = GRAV + 3
LIMITS = SCALE + 1  # (legs, joints, 3 coordinates, 2)
LEGSIGN = LIMITS + _L * _J * 3 * 2  # (legs,)
PARSIGN = LEGSIGN + _L
PLANE = PARSIGN + 1  # the closure tolerance PLANE_TOLERANCE·ℓ
SIZE = PLANE + 1
# the integers: pattern (0 UPS, 1 RPS, 2 RUU), legs, dof, actuated coordinate, joint kinds
# (0 R, 1 P, 2 U, 3 S), then 1 for legs of 6 coordinates closed by an S joint (the fast path)
#: The index in the packed integers of the flag of legs closed by an S joint (6-UPS, 3-RPS):
#: 1 takes the block solves of :func:`_s_closed` (6 coordinates) or :func:`_s_closed5` (5), 0 the
#: generic LU of ``J`` or ``JᵀJ`` and the ``5 × 5`` minors (the reference).
S_CLOSED: int = 4 + 3
#: The index of the flag of the chain's motion in one pass: 1 runs the chain once with
#: ``q̈ = 0`` (the bias) and adds the ``q̈`` terms by the Jacobian's columns (the
#: acceleration is linear in ``q̈``), 0 runs it a second time with ``q̈`` (the reference).
ONE_PASS: int = 4 + 4
#: The index of the flag of the U-P leg in closed form (6-UPS: U at the base, P along the U's
#: distal x axis, S at its end): 1 takes the U's cosines and sines straight from the leg's
#: direction (:func:`_u_frames`, no sine or cosine of the angles) and ``B⁻¹`` from the U's
#: frame (:func:`_u_closed`: ``l̇ = X·v``, no adjugate); 0 the chain of frames of
#: :func:`_chain` and the adjugate of :func:`_s_closed` (the reference).
U_CLOSED: int = 4 + 5
_PATTERNS = {"UPS": 0, "RPS": 1, "RUU": 2}
_KINDS = {"R": 0, "P": 1, "U": 2, "S": 3}
_DOF = (1, 1, 2, 3)

#: Samples of a batch computed by one thread at a time (the batch's blocks run in parallel).
BLOCK: int = 256
#: Batches of at least this many samples use every thread of numba's layer.
PARALLEL_MIN: int = 2048


def pack(robot: SpatialRobot) -> tuple[IntArray, FloatArray]:
    """The robot as the kernel's integers ``(4 + joints,)`` and floats ``(SIZE,)``."""
    legs = robot.legs
    if len(legs) > _L or len(legs[0].joints) != _J:  # pragma: no cover - the patterns have 3
        raise Prp3Error(f"the compiled kernel takes up to {_L} legs of {_J} joints")
    ints = np.zeros(7 + _J, dtype=np.int64)
    ints[0] = _PATTERNS[legs[0].pattern]
    ints[1] = len(legs)
    ints[2] = legs[0].dof
    ints[3] = legs[0].actuated_coordinate
    for k, joint in enumerate(legs[0].joints):
        ints[4 + k] = _KINDS[joint.kind]
    ints[S_CLOSED] = int(legs[0].dof >= 5 and legs[0].joints[-1].kind == "S")
    ints[ONE_PASS] = 1
    ints[U_CLOSED] = int(ints[S_CLOSED] == 1 and legs[0].pattern == "UPS" and u_p_leg(robot))
    par = np.zeros(SIZE)
    for i, leg in enumerate(legs):
        for k, joint in enumerate(leg.joints):
            par[JPOS + 3 * (_J * i + k) : JPOS + 3 * (_J * i + k) + 3] = joint.position
            par[JROT + 9 * (_J * i + k) : JROT + 9 * (_J * i + k) + 9] = np.ravel(joint.rotation)
            for c, (low, high) in enumerate(joint.limits):
                at = LIMITS + 2 * (3 * (_J * i + k) + c)
                par[at], par[at + 1] = low, high
        par[APOS + 3 * i : APOS + 3 * i + 3] = leg.attachment_position
        par[AROT + 9 * i : AROT + 9 * i + 9] = np.ravel(leg.attachment_rotation)
        for b, body in enumerate(leg.bodies):
            par[BMASS + 2 * i + b] = body.mass
            par[BCEN + 3 * (2 * i + b) : BCEN + 3 * (2 * i + b) + 3] = body.centre
            par[BINE + 9 * (2 * i + b) : BINE + 9 * (2 * i + b) + 9] = np.ravel(body.inertia)
    platform = robot.platform
    par[PMASS] = platform.mass
    par[PCEN : PCEN + 3] = platform.centre
    par[PINE : PINE + 9] = np.ravel(platform.inertia)
    par[GRAV : GRAV + 3] = robot.gravity
    par[SCALE] = robot.scale
    leg_sign, par_sign = home_signs(robot)
    par[LEGSIGN : LEGSIGN + len(legs)] = leg_sign
    par[PARSIGN] = par_sign
    from prp3.spatial.geometry import PLANE_TOLERANCE

    par[PLANE] = PLANE_TOLERANCE * robot.scale
    return ints, par


def u_p_leg(robot: SpatialRobot) -> bool:
    """Whether every leg's P and S joints sit on the distal x axis of the joint before, with
    the identity rotation (the U-P leg of :func:`_u_frames`: the leg's direction is the U's
    distal x axis and the P's axis)."""
    for leg in robot.legs:
        for joint in leg.joints[1:]:
            if joint.position[1] != 0.0 or joint.position[2] != 0.0:
                return False
            if not np.array_equal(np.asarray(joint.rotation), np.eye(3)):
                return False
    return True


# ------------------------------------------------------------------ scalar pieces
_jit = numba.njit(cache=True, error_model="numpy")
#: The steps of one sample, which allocate nothing: without numba's reference counts (each
#: array an argument counted in and out, atomically, per call; ~25 % of the sample's time).
if TYPE_CHECKING:  # numba's stubs omit its option _nrt
    _step = _jit
else:
    _step = numba.njit(cache=True, error_model="numpy", _nrt=False)


@_step
def _lu(a: FloatArray, n: int, piv: IntArray) -> float:
    """LU with partial pivoting of ``a[:n, :n]`` in place; returns the determinant."""
    det = 1.0
    for k in range(n):
        p = k
        big = abs(a[k, k])
        for r in range(k + 1, n):
            if abs(a[r, k]) > big:
                big = abs(a[r, k])
                p = r
        piv[k] = p
        if p != k:
            det = -det
            for c in range(n):
                t = a[k, c]
                a[k, c] = a[p, c]
                a[p, c] = t
        d = a[k, k]
        det *= d
        if d == 0.0:  # the column is zero from row k down (LAPACK's getrf goes on alike)
            continue
        for r in range(k + 1, n):
            f = a[r, k] / d
            a[r, k] = f
            for c in range(k + 1, n):
                a[r, c] -= f * a[k, c]
    return det


@_step
def _lu_solve(a: FloatArray, n: int, piv: IntArray, b: FloatArray) -> None:
    """Solve ``A·x = b`` in place with the factors of :func:`_lu`."""
    for k in range(n):
        p = piv[k]
        if p != k:
            t = b[k]
            b[k] = b[p]
            b[p] = t
    for r in range(1, n):
        s = b[r]
        for c in range(r):
            s -= a[r, c] * b[c]
        b[r] = s
    for r in range(n - 1, -1, -1):
        s = b[r]
        for c in range(r + 1, n):
            s -= a[r, c] * b[c]
        b[r] = s / a[r, r]


@_step
def _log(r: FloatArray) -> tuple[float, float, float]:
    """The principal rotation vector of ``r`` through its quaternion (Shepperd), as log_rotation."""
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    d0, d1, d2, d3 = trace, r[0, 0], r[1, 1], r[2, 2]
    pick = 0
    best = d0
    if d1 > best:
        pick, best = 1, d1
    if d2 > best:
        pick, best = 2, d2
    if d3 > best:
        pick = 3
    if pick == 0:
        s = math.sqrt(max(1.0 + trace, 0.0)) * 2.0
        w, x, y, z = (
            s / 4.0,
            (r[2, 1] - r[1, 2]) / s,
            (r[0, 2] - r[2, 0]) / s,
            (r[1, 0] - r[0, 1]) / s,
        )
    elif pick == 1:
        s = math.sqrt(max(1.0 + r[0, 0] - r[1, 1] - r[2, 2], 0.0)) * 2.0
        w, x, y, z = (
            (r[2, 1] - r[1, 2]) / s,
            s / 4.0,
            (r[0, 1] + r[1, 0]) / s,
            (r[0, 2] + r[2, 0]) / s,
        )
    elif pick == 2:
        s = math.sqrt(max(1.0 - r[0, 0] + r[1, 1] - r[2, 2], 0.0)) * 2.0
        w, x, y, z = (
            (r[0, 2] - r[2, 0]) / s,
            (r[0, 1] + r[1, 0]) / s,
            s / 4.0,
            (r[1, 2] + r[2, 1]) / s,
        )
    else:
        s = math.sqrt(max(1.0 - r[0, 0] - r[1, 1] + r[2, 2], 0.0)) * 2.0
        w, x, y, z = (
            (r[1, 0] - r[0, 1]) / s,
            (r[0, 2] + r[2, 0]) / s,
            (r[1, 2] + r[2, 1]) / s,
            s / 4.0,
        )
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    if w < 0.0:
        norm = -norm
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    sv = math.sqrt(x * x + y * y + z * z)
    if sv < 1e-12:
        scale = 2.0 / (1.0 if w == 0.0 else w)
    else:
        scale = 2.0 * math.atan2(sv, w) / sv
    return scale * x, scale * y, scale * z


@_step
def _cross(a0: float, a1: float, a2: float, b0: float, b1: float, b2: float
           ) -> tuple[float, float, float]:  # fmt: skip
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@_step
def _chain(ints: IntArray, par: FloatArray, i: int, q: FloatArray, jo: FloatArray, jr: FloatArray,
           fo: FloatArray, fr: FloatArray, axes: FloatArray) -> None:  # fmt: skip
    """The frames of leg ``i`` for its joint values ``q[i]`` (geometry.chain_frames); the
    proximal frame of joint ``k`` is ``fr[i, k − 1]`` (the base's for ``k = 0``), indexed, no
    view of an array made (numba counts a view's references, atomically)."""
    col = 0
    for k in range(_J):
        kind = ints[4 + k]
        base = JPOS + 3 * (_J * i + k)
        pr = JROT + 9 * (_J * i + k)
        x, y, z = par[base], par[base + 1], par[base + 2]
        if k == 0:
            jo[i, k, 0], jo[i, k, 1], jo[i, k, 2] = x, y, z
            for r in range(3):
                for c in range(3):
                    jr[i, k, r, c] = par[pr + 3 * r + c]
        else:
            o0, o1, o2 = fo[i, k - 1, 0], fo[i, k - 1, 1], fo[i, k - 1, 2]
            for r in range(3):
                m0, m1, m2 = fr[i, k - 1, r, 0], fr[i, k - 1, r, 1], fr[i, k - 1, r, 2]
                jo[i, k, r] = (o0 if r == 0 else (o1 if r == 1 else o2)) + m0 * x + m1 * y + m2 * z
                for c in range(3):
                    jr[i, k, r, c] = m0 * par[pr + c] + m1 * par[pr + 3 + c] + m2 * par[pr + 6 + c]
        if kind == 0:  # R: fr = jr·Rot_z(q)
            cz, sz = math.cos(q[i, col]), math.sin(q[i, col])
            for r in range(3):
                u0, u1 = jr[i, k, r, 0], jr[i, k, r, 1]
                axes[i, col, r] = jr[i, k, r, 2]
                fr[i, k, r, 0] = u0 * cz + u1 * sz
                fr[i, k, r, 1] = -u0 * sz + u1 * cz
                fr[i, k, r, 2] = jr[i, k, r, 2]
                fo[i, k, r] = jo[i, k, r]
        elif kind == 1:  # P
            for r in range(3):
                axes[i, col, r] = jr[i, k, r, 0]
                fo[i, k, r] = jo[i, k, r] + q[i, col] * jr[i, k, r, 0]
                for c in range(3):
                    fr[i, k, r, c] = jr[i, k, r, c]
        elif kind == 2:  # U: the cross frame jr·Rot_z(a), then fr = (…)·Rot_y(b)
            cz, sz = math.cos(q[i, col]), math.sin(q[i, col])
            cy, sy = math.cos(q[i, col + 1]), math.sin(q[i, col + 1])
            for r in range(3):
                u0, u1, u2 = jr[i, k, r, 0], jr[i, k, r, 1], jr[i, k, r, 2]
                x0 = u0 * cz + u1 * sz
                x1 = -u0 * sz + u1 * cz
                axes[i, col, r] = u2
                axes[i, col + 1, r] = x1
                fo[i, k, r] = jo[i, k, r]
                fr[i, k, r, 0] = x0 * cy - u2 * sy
                fr[i, k, r, 1] = x1
                fr[i, k, r, 2] = x0 * sy + u2 * cy
        else:  # S, the last joint: world axes; its distal frame (the platform's) is not needed
            for a in range(3):
                for r in range(3):
                    axes[i, col + a, r] = 1.0 if a == r else 0.0
            for r in range(3):
                fo[i, k, r] = jo[i, k, r]
            return
        col += _DOF[kind]


@_step
def _u_frames(par: FloatArray, i: int, q: FloatArray, d0: float, d1: float, d2: float,
              rho: float, jo: FloatArray, jr: FloatArray, fo: FloatArray, fr: FloatArray,
              axes: FloatArray) -> None:  # fmt: skip
    """The frames of the U-P leg ``i`` (:data:`U_CLOSED`) as :func:`_chain` gives them, the U's
    ``cos a = d₀/h, sin a = d₁/h, cos b = h/ρ, sin b = −d₂/ρ`` (``h = √(d₀² + d₁²)``) straight
    from the leg's vector ``d`` in the U's frame (``a = atan2(d₁, d₀)``, ``b = atan2(−d₂, h)``
    of :func:`_geometry`); the P and the S on the distal x axes, unrotated (:func:`u_p_leg`)."""
    h = math.hypot(d0, d1)
    if h > 0.0:
        cz, sz = d0 / h, d1 / h
    else:  # along the U's first axis: a = atan2(±0, ±0)
        cz, sz = math.cos(q[i, 0]), math.sin(q[i, 0])
    cy, sy = h / rho, -d2 / rho
    base, pr = JPOS + 3 * _J * i, JROT + 9 * _J * i
    arm, fore, slide = par[base + 3], par[base + 6], q[i, 2]
    for r in range(3):
        u0, u1, u2 = par[pr + 3 * r], par[pr + 3 * r + 1], par[pr + 3 * r + 2]
        x0 = u0 * cz + u1 * sz
        x1 = -u0 * sz + u1 * cz
        o = par[base + r]
        ex = x0 * cy - u2 * sy
        jo[i, 0, r] = fo[i, 0, r] = o
        jr[i, 0, r, 0], jr[i, 0, r, 1], jr[i, 0, r, 2] = u0, u1, u2
        fr[i, 0, r, 0], fr[i, 0, r, 1], fr[i, 0, r, 2] = ex, x1, x0 * sy + u2 * cy
        axes[i, 0, r], axes[i, 1, r], axes[i, 2, r] = u2, x1, ex
        p1 = o + ex * arm
        jo[i, 1, r] = p1
        fo[i, 1, r] = p1 + slide * ex
        jo[i, 2, r] = fo[i, 2, r] = p1 + slide * ex + ex * fore
        for c in range(3):  # the P's and the S's frames: the U's distal frame
            jr[i, 1, r, c] = fr[i, 1, r, c] = jr[i, 2, r, c] = fr[i, 0, r, c]
        for a in range(3):
            axes[i, 3 + a, r] = 1.0 if a == r else 0.0


@_step
def _u_closed(jac: FloatArray, kinds: IntArray, scale: float, normal: FloatArray, i: int,
              fo: FloatArray, fr: FloatArray) -> float:  # fmt: skip
    """:func:`_s_closed` for the U-P leg (:data:`U_CLOSED`): ``B = [a × ρX, Y × ρX, X] =
    [ρ a × X, −ρZ, X]`` (``X, Y, Z`` the U's distal frame, ``a`` its first axis, ``ρX`` the leg
    from the U's centre to the S's), so ``det B = −ρ² a·Z`` and the rows of ``B⁻¹`` are
    ``Y/(ρ a·Z)``, ``−Z/ρ``, ``X``: ``ȧ = Y·t_v/(ρ a·Z)``, ``ḃ = −Z·t_v/ρ``, ``l̇ = X·t_v``.
    Keeps ``A`` and ``B⁻¹`` in ``normal[i]`` as :func:`_s_closed`; returns the leg measure."""
    x0, x1, x2 = fr[i, 0, 0, 0], fr[i, 0, 1, 0], fr[i, 0, 2, 0]
    rho = (x0 * (fo[i, 2, 0] - fo[i, 0, 0]) + x1 * (fo[i, 2, 1] - fo[i, 0, 1])
           + x2 * (fo[i, 2, 2] - fo[i, 0, 2]))  # fmt: skip
    cz = jac[0, 0] * fr[i, 0, 0, 2] + jac[1, 0] * fr[i, 0, 1, 2] + jac[2, 0] * fr[i, 0, 2, 2]
    f = 1.0 / (rho * cz)
    for c in range(3):
        normal[i, 3, c] = fr[i, 0, c, 1] * f
        normal[i, 4, c] = -fr[i, 0, c, 2] / rho
        normal[i, 5, c] = fr[i, 0, c, 0]
    factor = -1.0 / (scale * scale * scale)
    for c in range(3):
        if kinds[c] == 1:
            factor *= scale
        for r in range(3):
            normal[i, r, c] = jac[r, c]
    return float(-rho * rho * cz * factor)


@_step
def _angles(x: float, y: float, z: float) -> tuple[float, float]:
    """The U angles ``(a, b)`` of the direction ``(x, y, z)`` (``cos b > 0``)."""
    return math.atan2(y, x), math.atan2(-z, math.hypot(x, y))


@_step
def _geometry(ints: IntArray, par: FloatArray, p: FloatArray, rm: FloatArray, q: FloatArray,
              jo: FloatArray, jr: FloatArray, fo: FloatArray, fr: FloatArray, axes: FloatArray,
              work: tuple, ce: FloatArray, f: FloatArray) -> int:  # type: ignore[type-arg]  # fmt: skip
    """Every leg's closed-form inverse geometry (geometry.leg_coordinates), limits checked."""
    legs, pattern = ints[1], ints[0]
    status = _OK
    for i in range(legs):
        ap, ar = APOS + 3 * i, AROT + 9 * i
        re_ = work[0]
        for r in range(3):
            ce[r] = p[r] + rm[r, 0] * par[ap] + rm[r, 1] * par[ap + 1] + rm[r, 2] * par[ap + 2]
            for c in range(3):
                re_[r, c] = (
                    rm[r, 0] * par[ar + c] + rm[r, 1] * par[ar + 3 + c] + rm[r, 2] * par[ar + 6 + c]
                )
        b0, r0 = JPOS + 3 * _J * i, JROT + 9 * _J * i
        e0, e1, e2 = ce[0] - par[b0], ce[1] - par[b0 + 1], ce[2] - par[b0 + 2]
        d0 = par[r0] * e0 + par[r0 + 3] * e1 + par[r0 + 6] * e2
        d1 = par[r0 + 1] * e0 + par[r0 + 4] * e1 + par[r0 + 7] * e2
        d2 = par[r0 + 2] * e0 + par[r0 + 5] * e1 + par[r0 + 8] * e2
        for c in range(ints[2]):
            q[i, c] = 0.0
        arm = par[JPOS + 3 * (_J * i + 1)]
        fore = par[JPOS + 3 * (_J * i + 2)]
        if pattern == 2:  # RUU
            kk = (d0 * d0 + d1 * d1 + d2 * d2 + arm * arm - fore * fore) / (2.0 * arm)
            rho = math.hypot(d0, d1)
            if not abs(kk) <= rho:
                return _UNREACHABLE
            q[i, 0] = math.atan2(d1, d0) - math.acos(kk / rho)
            _chain(ints, par, i, q, jo, jr, fo, fr, axes)
            for r in range(3):
                f[r] = ((ce[0] - jo[i, 1, 0]) * jr[i, 1, 0, r] + (ce[1] - jo[i, 1, 1]) * jr[i, 1, 1, r]
                        + (ce[2] - jo[i, 1, 2]) * jr[i, 1, 2, r])  # fmt: skip
            q[i, 1], q[i, 2] = _angles(f[0], f[1], f[2])
            _chain(ints, par, i, q, jo, jr, fo, fr, axes)
            m = work[1]
            for r in range(3):
                for c in range(3):
                    m[r, c] = (
                        jr[i, 2, 0, r] * re_[0, c]
                        + jr[i, 2, 1, r] * re_[1, c]
                        + jr[i, 2, 2, r] * re_[2, c]
                    )
            q[i, 3], q[i, 4] = _angles(m[0, 0], m[1, 0], m[2, 0])
            off = par[SCALE] * m[2, 1]
        else:
            if pattern == 0:
                rho = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                if not rho > 0.0:
                    return _UNREACHABLE
                q[i, 0] = math.atan2(d1, d0)
                q[i, 1] = math.atan2(-d2, math.hypot(d0, d1))
                slide = 2
                off = 0.0
            else:
                rho = math.hypot(d0, d1)
                if not rho > 0.0:
                    return _UNREACHABLE
                q[i, 0] = math.atan2(d1, d0)
                slide = 1
                off = d2
            q[i, slide] = rho - arm - fore
            if pattern == 0 and ints[U_CLOSED] == 1:
                _u_frames(par, i, q, d0, d1, d2, rho, jo, jr, fo, fr, axes)
            else:
                _chain(ints, par, i, q, jo, jr, fo, fr, axes)
            m = work[1]
            for r in range(3):
                for c in range(3):
                    m[r, c] = (
                        jr[i, 2, 0, r] * re_[0, c]
                        + jr[i, 2, 1, r] * re_[1, c]
                        + jr[i, 2, 2, r] * re_[2, c]
                    )
            q[i, slide + 1], q[i, slide + 2], q[i, slide + 3] = _log(m)
        if pattern == 2:  # the second U's cross axis (the S joint's frames need no q_S)
            _chain(ints, par, i, q, jo, jr, fo, fr, axes)
        # limits (check_reach) and the closure (plane_offsets)
        col = 0
        for k in range(_J):
            kind = ints[4 + k]
            lim = LIMITS + 2 * 3 * (_J * i + k)
            if kind == 3:
                s0, s1, s2 = q[i, col], q[i, col + 1], q[i, col + 2]
                angle = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
                if angle < par[lim] or angle > par[lim + 1]:
                    status = _LIMIT if status == _OK else status
            else:
                for c in range(_DOF[kind]):
                    v = q[i, col + c]
                    if v < par[lim + 2 * c] or v > par[lim + 2 * c + 1]:
                        code = _STROKE if kind == 1 else _LIMIT
                        status = code if status == _OK else status
            col += _DOF[kind]
        if abs(off) > par[PLANE]:
            return _NOT_A_POSE
    return status


@_step
def _sample(ints: IntArray, par: FloatArray, p: FloatArray, rm: FloatArray, w: FloatArray,
            v: FloatArray, al: FloatArray, a: FloatArray, q: FloatArray, dq: FloatArray,
            ddq: FloatArray, tau: FloatArray, force: FloatArray, moment: FloatArray,
            measures: FloatArray, work: tuple, frames: tuple, scr: tuple) -> int:  # type: ignore[type-arg]  # fmt: skip
    """One state: ``q, dq, ddq (legs, dof)``, ``tau (legs,)``, ``force, moment (legs, 3, 3)``,
    ``measures (legs + 1,)`` (``μ_leg``, then ``μ_par``); returns the status."""
    legs, dof, act = ints[1], ints[2], ints[3]
    fast = ints[S_CLOSED] == 1
    one = ints[ONE_PASS] == 1
    for r in range(3):
        if not (math.isfinite(p[r]) and math.isfinite(w[r]) and math.isfinite(v[r])
                and math.isfinite(al[r]) and math.isfinite(a[r])):  # fmt: skip
            return _NOT_FINITE
        for c in range(3):
            if not math.isfinite(rm[r, c]):
                return _NOT_FINITE
    err = 0.0
    for r in range(3):
        for c in range(3):
            s = rm[0, r] * rm[0, c] + rm[1, r] * rm[1, c] + rm[2, r] * rm[2, c]
            err = max(err, abs(s - (1.0 if r == c else 0.0)))
    det = (rm[0, 0] * (rm[1, 1] * rm[2, 2] - rm[1, 2] * rm[2, 1])
           - rm[0, 1] * (rm[1, 0] * rm[2, 2] - rm[1, 2] * rm[2, 0])
           + rm[0, 2] * (rm[1, 0] * rm[2, 1] - rm[1, 1] * rm[2, 0]))  # fmt: skip
    if err > ORTHONORMAL_TOLERANCE or abs(det - 1.0) > ORTHONORMAL_TOLERANCE:
        return _NOT_ROTATION
    jo, fo, jr, fr, axes = frames
    (
        kinds,
        owner,
        jac,
        fac,
        piv,
        b,
        xw,
        nw,
        kmat,
        ends,
        big,
        normal,
        jacs,
        pivs,
        st,
        _bias_w,
        _bias_a,
        bw,
        ba,
        bo,
        rhs,
        z,
        y0,
        fk,
        mk,
        ce,
        f,
        ref,
        wn,
        y6,
    ) = scr
    status = _geometry(ints, par, p, rm, q, jo, jr, fo, fr, axes, work, ce, f)
    if status != _OK:
        return status
    scale = par[SCALE]
    # per coordinate: kinds 0 rotation about a body axis, 1 slide, 2 S; owner its joint
    col = 0
    for k in range(_J):
        kind = ints[4 + k]
        for _c in range(_DOF[kind]):
            kinds[col] = 1 if kind == 1 else (2 if kind == 3 else 0)
            owner[col] = k
            col += 1
    # xw: x_i = J⁻ᵀ e_a as (M, F); nw: the constraint wrench w_i (legs of 5 coordinates);
    # kmat: the rows J_p, then C; normal: the factors of J (dof 6) or JᵀJ (dof 5)
    for r in range(6):
        for c in range(6):
            kmat[r, c] = 0.0
        for i in range(_L):
            nw[i, r] = 0.0
    for i in range(legs):
        e0, e1, e2 = fo[i, _J - 1, 0], fo[i, _J - 1, 1], fo[i, _J - 1, 2]
        ends[i, 0], ends[i, 1], ends[i, 2] = e0, e1, e2
        for c in range(dof):
            ax0, ax1, ax2 = axes[i, c, 0], axes[i, c, 1], axes[i, c, 2]
            if kinds[c] == 1:
                jac[0, c] = jac[1, c] = jac[2, c] = 0.0
                jac[3, c], jac[4, c], jac[5, c] = ax0, ax1, ax2
            else:
                o = owner[c]
                jac[0, c], jac[1, c], jac[2, c] = ax0, ax1, ax2
                jac[3, c], jac[4, c], jac[5, c] = _cross(ax0, ax1, ax2, e0 - fo[i, o, 0], e1 - fo[i, o, 1],
                                                         e2 - fo[i, o, 2])  # fmt: skip
            for r in range(6):
                jacs[i, r, c] = jac[r, c]
        r0, r1, r2 = e0 - p[0], e1 - p[1], e2 - p[2]
        # the scaled Jacobian and the leg measure
        for r in range(6):
            for c in range(dof):
                value = jac[r, c]
                if r >= 3:
                    value /= scale
                if kinds[c] == 1:
                    value *= scale
                fac[r, c] = value
        if fast:  # J = [[A, 1], [B, 0]]: A and B⁻¹ (or B(BᵀB)⁻¹) kept, x_i by blocks
            if ints[U_CLOSED] == 1:
                measures[i] = _u_closed(jac, kinds, scale, normal, i, fo, fr)
            elif dof == 6:
                measures[i] = _s_closed(jac, kinds, scale, normal, i)
            else:
                measures[i] = _s_closed5(jac, kinds, scale, normal, nw, i)
            for r in range(6):
                y6[r] = 0.0
            y6[act] = 1.0
            xw[i, 0], xw[i, 1], xw[i, 2], xw[i, 3], xw[i, 4], xw[i, 5] = (
                _s_transpose(normal, i, y6) if dof == 6 else _s_transpose5(normal, i, y6)
            )
        elif dof == 6:
            for r in range(6):
                for c in range(6):
                    big[r, c] = fac[r, c]
            measures[i] = _lu(big, 6, piv)
        else:
            # generalised cross product of the 5 scaled columns: w̃_j = (−1)^j det(rows ≠ j)
            total = 0.0
            for j in range(6):
                rr = 0
                for r in range(6):
                    if r == j:
                        continue
                    for c in range(5):
                        big[rr, c] = fac[r, c]
                    rr += 1
                minor = _lu(big, 5, piv)
                value = minor if j % 2 == 0 else -minor
                nw[i, j] = value if j < 3 else value / scale
                total += value * value
            measures[i] = math.sqrt(total)
        # factors: J (dof 6) for J·dq = t and Jᵀ·x = e; JᵀJ (dof 5)
        if fast:
            pass
        elif dof == 6:
            for r in range(6):
                for c in range(6):
                    normal[i, r, c] = jac[r, c]
        else:
            for r in range(dof):
                for c in range(dof):
                    s = 0.0
                    for k in range(6):
                        s += jac[k, r] * jac[k, c]
                    normal[i, r, c] = s
        if not fast:
            _lu(normal[i], dof, pivs[i])
            # x_i: Jᵀ x = e_a (dof 6: solve with the transposed factors), J (JᵀJ)⁻¹ e_a (dof 5)
            _transpose_solve(normal[i], jacs[i], pivs[i], dof, act, b, xw[i], y6)
        kmat[i, 0] = xw[i, 0] + r1 * xw[i, 5] - r2 * xw[i, 4]
        kmat[i, 1] = xw[i, 1] + r2 * xw[i, 3] - r0 * xw[i, 5]
        kmat[i, 2] = xw[i, 2] + r0 * xw[i, 4] - r1 * xw[i, 3]
        kmat[i, 3], kmat[i, 4], kmat[i, 5] = xw[i, 3], xw[i, 4], xw[i, 5]
        if dof == 5:
            row = legs + i
            kmat[row, 0] = nw[i, 0] + r1 * nw[i, 5] - r2 * nw[i, 4]
            kmat[row, 1] = nw[i, 1] + r2 * nw[i, 3] - r0 * nw[i, 5]
            kmat[row, 2] = nw[i, 2] + r0 * nw[i, 4] - r1 * nw[i, 3]
            kmat[row, 3], kmat[row, 4], kmat[row, 5] = nw[i, 3], nw[i, 4], nw[i, 5]
    # the parallel measure in units of ℓ
    for r in range(6):
        for c in range(6):
            value = kmat[r, c]
            if r < legs:
                if kinds[act] == 1:
                    if c < 3:
                        value /= scale
                elif c >= 3:
                    value *= scale
            elif c >= 3:
                value *= scale
            big[r, c] = value
    measures[legs] = _lu(big, 6, piv)
    for i in range(legs):
        if not measures[i] * par[LEGSIGN + i] >= SINGULAR:
            return _SINGULAR
    if not measures[legs] * par[PARSIGN] >= SINGULAR:
        return _SINGULAR
    # rates: J·dq = (ω, v + ω × r)
    # bw, ba: each body's angular velocity and acceleration; bo: its origin's acceleration
    for i in range(legs):
        r0, r1, r2 = ends[i, 0] - p[0], ends[i, 1] - p[1], ends[i, 2] - p[2]
        c0, c1, c2 = _cross(w[0], w[1], w[2], r0, r1, r2)
        st[0], st[1], st[2] = w[0], w[1], w[2]
        st[3], st[4], st[5] = v[0] + c0, v[1] + c1, v[2] + c2
        if dof == 5 and not _compatible(nw[i], st, st, scale):
            return _INCOMPATIBLE
        if fast:
            _s_rates(normal, i, st, b) if dof == 6 else _s_rates5(normal, i, st, b)
        else:
            _solve_rates(normal[i], jacs[i], pivs[i], dof, st, b)
        for c in range(dof):
            dq[i, c] = b[c]
            ddq[i, c] = 0.0
        _chain_motion(ints, i, jo, fo, axes, dq, ddq, bw, ba, bo)  # the bias, q̈ = 0
        d0, d1, d2 = _cross(w[0], w[1], w[2], c0, c1, c2)
        g0, g1, g2 = _cross(al[0], al[1], al[2], r0, r1, r2)
        for r in range(3):
            ref[r] = ba[i, _J - 1, r]
            ref[3 + r] = bo[i, _J - 1, r]
        st[0], st[1], st[2] = al[0] - ref[0], al[1] - ref[1], al[2] - ref[2]
        st[3] = a[0] + g0 + d0 - ref[3]
        st[4] = a[1] + g1 + d1 - ref[4]
        st[5] = a[2] + g2 + d2 - ref[5]
        if dof == 5 and not _compatible(nw[i], st, ref, scale):
            return _INCOMPATIBLE
        if fast:
            _s_rates(normal, i, st, b) if dof == 6 else _s_rates5(normal, i, st, b)
        else:
            _solve_rates(normal[i], jacs[i], pivs[i], dof, st, b)
        for c in range(dof):
            ddq[i, c] = b[c]
        if one:  # the q̈ terms onto the bias
            _add_accelerations(i, dof, kinds, owner, fo, axes, ddq, ba, bo)
        else:  # the chain again with q̈ (the reference)
            _chain_motion(ints, i, jo, fo, axes, dq, ddq, bw, ba, bo)
    # inertial wrenches and the particular wrenches (W_n = 0) from the platform inwards
    g = (par[GRAV], par[GRAV + 1], par[GRAV + 2])
    for r in range(6):
        rhs[r] = 0.0
    for i in range(legs):
        for r in range(3):
            fk[_J - 1, r] = 0.0
            mk[_J - 1, r] = 0.0
        for k in range(_J - 2, -1, -1):
            bc = BCEN + 3 * (2 * i + k)
            bi = BINE + 9 * (2 * i + k)
            mass = par[BMASS + 2 * i + k]
            rot = (fr[i, k, 0, 0], fr[i, k, 0, 1], fr[i, k, 0, 2], fr[i, k, 1, 0], fr[i, k, 1, 1],
                   fr[i, k, 1, 2], fr[i, k, 2, 0], fr[i, k, 2, 1], fr[i, k, 2, 2])  # fmt: skip
            rc0 = rot[0] * par[bc] + rot[1] * par[bc + 1] + rot[2] * par[bc + 2]
            rc1 = rot[3] * par[bc] + rot[4] * par[bc + 1] + rot[5] * par[bc + 2]
            rc2 = rot[6] * par[bc] + rot[7] * par[bc + 1] + rot[8] * par[bc + 2]
            gx, gy, gz = fo[i, k, 0] + rc0, fo[i, k, 1] + rc1, fo[i, k, 2] + rc2
            fx, fy, fz, mx, my, mz = _inertial(
                par, bi, mass, rot, (bw[i, k, 0], bw[i, k, 1], bw[i, k, 2]),
                (ba[i, k, 0], ba[i, k, 1], ba[i, k, 2]), (bo[i, k, 0], bo[i, k, 1], bo[i, k, 2]),
                rc0, rc1, rc2, g)  # fmt: skip
            # F_k = F_{k+1} + force; M_k = M_{k+1} + (o_{k+1} − G) × F_{k+1} − (o_k − G) × F_k + moment
            n0, n1, n2 = fk[k + 1, 0], fk[k + 1, 1], fk[k + 1, 2]
            fk[k, 0], fk[k, 1], fk[k, 2] = n0 + fx, n1 + fy, n2 + fz
            u0, u1, u2 = _cross(fo[i, k + 1, 0] - gx, fo[i, k + 1, 1] - gy, fo[i, k + 1, 2] - gz,
                                n0, n1, n2)  # fmt: skip
            t0, t1, t2 = _cross(fo[i, k, 0] - gx, fo[i, k, 1] - gy, fo[i, k, 2] - gz,
                                fk[k, 0], fk[k, 1], fk[k, 2])  # fmt: skip
            mk[k, 0] = mk[k + 1, 0] + u0 - t0 + mx
            mk[k, 1] = mk[k + 1, 1] + u1 - t1 + my
            mk[k, 2] = mk[k + 1, 2] + u2 - t2 + mz
        for c in range(dof):
            o = owner[c]
            if kinds[c] == 1:
                y0[c] = (
                    axes[i, c, 0] * fk[o, 0] + axes[i, c, 1] * fk[o, 1] + axes[i, c, 2] * fk[o, 2]
                )
            else:
                y0[c] = (
                    axes[i, c, 0] * mk[o, 0] + axes[i, c, 1] * mk[o, 1] + axes[i, c, 2] * mk[o, 2]
                )
        if fast:
            z[0], z[1], z[2], z[3], z[4], z[5] = (
                _s_transpose(normal, i, y0) if dof == 6 else _s_transpose5(normal, i, y0)
            )
        else:
            _transpose_solve_vector(normal[i], jacs[i], pivs[i], dof, y0, b, z)
        r0, r1, r2 = ends[i, 0] - p[0], ends[i, 1] - p[1], ends[i, 2] - p[2]
        c0, c1, c2 = _cross(r0, r1, r2, z[3], z[4], z[5])
        rhs[0] += z[0] + c0
        rhs[1] += z[1] + c1
        rhs[2] += z[2] + c2
        rhs[3] += z[3]
        rhs[4] += z[4]
        rhs[5] += z[5]
        for k in range(_J):
            for r in range(3):
                force[i, k, r] = fk[k, r]
                moment[i, k, r] = mk[k, r]
        # keep z for the wrenches of the legs' ends
        for r in range(6):
            fac[i, r] = z[r]
    # the platform
    rp0 = rm[0, 0] * par[PCEN] + rm[0, 1] * par[PCEN + 1] + rm[0, 2] * par[PCEN + 2]
    rp1 = rm[1, 0] * par[PCEN] + rm[1, 1] * par[PCEN + 1] + rm[1, 2] * par[PCEN + 2]
    rp2 = rm[2, 0] * par[PCEN] + rm[2, 1] * par[PCEN + 1] + rm[2, 2] * par[PCEN + 2]
    fx, fy, fz, mx, my, mz = _inertial(
        par, PINE, par[PMASS], (rm[0, 0], rm[0, 1], rm[0, 2], rm[1, 0], rm[1, 1], rm[1, 2],
                                rm[2, 0], rm[2, 1], rm[2, 2]),
        (w[0], w[1], w[2]), (al[0], al[1], al[2]), (a[0], a[1], a[2]), rp0, rp1, rp2, g)  # fmt: skip
    c0, c1, c2 = _cross(rp0, rp1, rp2, fx, fy, fz)
    rhs[0] += mx + c0
    rhs[1] += my + c1
    rhs[2] += mz + c2
    rhs[3] += fx
    rhs[4] += fy
    rhs[5] += fz
    # Kᵀ·(τ, λ) = rhs
    for r in range(6):
        for c in range(6):
            big[r, c] = kmat[c, r]
    _lu(big, 6, piv)
    _lu_solve(big, 6, piv, rhs)
    for i in range(legs):
        t = rhs[i]
        tau[i] = t
        lam = rhs[legs + i] if dof == 5 else 0.0
        for r in range(6):
            wn[r] = t * xw[i, r] - fac[i, r] + lam * nw[i, r]
        for k in range(_J):
            l0, l1, l2 = (
                ends[i, 0] - fo[i, k, 0],
                ends[i, 1] - fo[i, k, 1],
                ends[i, 2] - fo[i, k, 2],
            )
            c0, c1, c2 = _cross(l0, l1, l2, wn[3], wn[4], wn[5])
            force[i, k, 0] += wn[3]
            force[i, k, 1] += wn[4]
            force[i, k, 2] += wn[5]
            moment[i, k, 0] += wn[0] + c0
            moment[i, k, 1] += wn[1] + c1
            moment[i, k, 2] += wn[2] + c2
    for i in range(legs):
        if not math.isfinite(tau[i]):
            return _OVERFLOW
        for c in range(dof):
            if not (math.isfinite(dq[i, c]) and math.isfinite(ddq[i, c])):
                return _OVERFLOW
        for k in range(_J):
            for r in range(3):
                if not (math.isfinite(force[i, k, r]) and math.isfinite(moment[i, k, r])):
                    return _OVERFLOW
    return _OK


@_step
def _s_closed(jac: FloatArray, kinds: IntArray, scale: float, normal: FloatArray, i: int) -> float:
    """A leg of 6 coordinates closed by an S joint: its Jacobian is ``[[A, 1], [B, 0]]``
    (the S's columns are the identity in ω and zero in v, the S's centre being the leg's
    end), so ``det J = −det B`` and ``J⁻¹`` needs ``B⁻¹`` only.  Keeps ``A`` in
    ``normal[i, :3, :3]`` and ``B⁻¹`` (adjugate over determinant) in ``normal[i, 3:, :3]``;
    returns the leg measure, the determinant of the scaled ``J`` (rows of ``v`` over ℓ,
    slide columns times ℓ) as the generic path's LU gives it."""
    b00, b01, b02 = jac[3, 0], jac[3, 1], jac[3, 2]
    b10, b11, b12 = jac[4, 0], jac[4, 1], jac[4, 2]
    b20, b21, b22 = jac[5, 0], jac[5, 1], jac[5, 2]
    c00, c01, c02 = b11 * b22 - b12 * b21, b12 * b20 - b10 * b22, b10 * b21 - b11 * b20
    det = b00 * c00 + b01 * c01 + b02 * c02
    inv = 1.0 / det
    normal[i, 3, 0], normal[i, 4, 0], normal[i, 5, 0] = c00 * inv, c01 * inv, c02 * inv
    normal[i, 3, 1] = (b02 * b21 - b01 * b22) * inv
    normal[i, 4, 1] = (b00 * b22 - b02 * b20) * inv
    normal[i, 5, 1] = (b01 * b20 - b00 * b21) * inv
    normal[i, 3, 2] = (b01 * b12 - b02 * b11) * inv
    normal[i, 4, 2] = (b02 * b10 - b00 * b12) * inv
    normal[i, 5, 2] = (b00 * b11 - b01 * b10) * inv
    factor = -1.0 / (scale * scale * scale)
    for c in range(3):
        if kinds[c] == 1:
            factor *= scale
        for r in range(3):
            normal[i, r, c] = jac[r, c]
    return float(det * factor)


@_step
def _s_rates(normal: FloatArray, i: int, t: FloatArray, out: FloatArray) -> None:
    """``J⁻¹·t`` for a leg closed by S (:func:`_s_closed`): ``B⁻¹·t_v``, then ``t_ω − A·(…)``."""
    for r in range(3):
        out[r] = (
            normal[i, 3 + r, 0] * t[3] + normal[i, 3 + r, 1] * t[4] + normal[i, 3 + r, 2] * t[5]
        )
    for r in range(3):
        out[3 + r] = t[r] - (normal[i, r, 0] * out[0] + normal[i, r, 1] * out[1]
                             + normal[i, r, 2] * out[2])  # fmt: skip


@_step
def _s_transpose(normal: FloatArray, i: int, y: FloatArray
                 ) -> tuple[float, float, float, float, float, float]:  # fmt: skip
    """``J⁻ᵀ·y`` for a leg closed by S as ``(M, F)``: ``M = y_S``, ``F = B⁻ᵀ(y_a − Aᵀ·y_S)``."""
    u0 = y[0] - (normal[i, 0, 0] * y[3] + normal[i, 1, 0] * y[4] + normal[i, 2, 0] * y[5])
    u1 = y[1] - (normal[i, 0, 1] * y[3] + normal[i, 1, 1] * y[4] + normal[i, 2, 1] * y[5])
    u2 = y[2] - (normal[i, 0, 2] * y[3] + normal[i, 1, 2] * y[4] + normal[i, 2, 2] * y[5])
    return (y[3], y[4], y[5],
            normal[i, 3, 0] * u0 + normal[i, 4, 0] * u1 + normal[i, 5, 0] * u2,
            normal[i, 3, 1] * u0 + normal[i, 4, 1] * u1 + normal[i, 5, 1] * u2,
            normal[i, 3, 2] * u0 + normal[i, 4, 2] * u1 + normal[i, 5, 2] * u2)  # fmt: skip


@_step
def _s_closed5(jac: FloatArray, kinds: IntArray, scale: float, normal: FloatArray,
               nw: FloatArray, i: int) -> float:  # fmt: skip
    """A leg of 5 coordinates closed by an S joint (3-RPS): ``J = [[A, 1], [B, 0]]`` with
    ``A, B`` of 3 × 2.  The generalised cross product of the scaled columns is ``(0,
    −b̃₀ × b̃₁)`` (the 5 × 5 minors without a row of ``ω`` vanish, those without a row of
    ``v`` are ``B``'s 2 × 2 minors); so the constraint wrench ``w_i`` is ``(0, −b̃₀ × b̃₁/ℓ)``
    and ``μ_leg = |b̃₀ × b̃₁|``.  Keeps ``A`` in ``normal[i, :3, :2]`` and ``B(BᵀB)⁻¹`` in
    ``normal[i, 3:, :2]`` (``det BᵀB = |b₀ × b₁|²``); returns ``μ_leg``."""
    s0 = 1.0 if kinds[0] == 1 else 1.0 / scale  # the scaled columns: v over ℓ, slides times ℓ
    s1 = 1.0 if kinds[1] == 1 else 1.0 / scale
    x0, x1, x2 = jac[3, 0], jac[4, 0], jac[5, 0]
    y0, y1, y2 = jac[3, 1], jac[4, 1], jac[5, 1]
    c0, c1, c2 = _cross(x0, x1, x2, y0, y1, y2)
    f = s0 * s1
    nw[i, 0] = nw[i, 1] = nw[i, 2] = 0.0
    nw[i, 3], nw[i, 4], nw[i, 5] = -c0 * f / scale, -c1 * f / scale, -c2 * f / scale
    g00 = x0 * x0 + x1 * x1 + x2 * x2
    g11 = y0 * y0 + y1 * y1 + y2 * y2
    g01 = x0 * y0 + x1 * y1 + x2 * y2
    inv = 1.0 / (c0 * c0 + c1 * c1 + c2 * c2)
    for r in range(3):
        bx, by = jac[3 + r, 0], jac[3 + r, 1]
        normal[i, 3 + r, 0] = (bx * g11 - by * g01) * inv
        normal[i, 3 + r, 1] = (by * g00 - bx * g01) * inv
        normal[i, r, 0] = jac[r, 0]
        normal[i, r, 1] = jac[r, 1]
    return math.sqrt(c0 * c0 + c1 * c1 + c2 * c2) * abs(f)


@_step
def _s_rates5(normal: FloatArray, i: int, t: FloatArray, out: FloatArray) -> None:
    """``(JᵀJ)⁻¹Jᵀ·t`` for a leg of 5 closed by S (:func:`_s_closed5`): ``(BᵀB)⁻¹Bᵀ·t_v``,
    then ``t_ω − A·(…)`` (the least-squares solution: ``x_S`` zeroes the ``ω`` rows)."""
    for c in range(2):
        out[c] = normal[i, 3, c] * t[3] + normal[i, 4, c] * t[4] + normal[i, 5, c] * t[5]
    for r in range(3):
        out[2 + r] = t[r] - (normal[i, r, 0] * out[0] + normal[i, r, 1] * out[1])


@_step
def _s_transpose5(normal: FloatArray, i: int, y: FloatArray
                  ) -> tuple[float, float, float, float, float, float]:  # fmt: skip
    """``J(JᵀJ)⁻¹·y`` for a leg of 5 closed by S as ``(M, F)``, the least-norm solution of
    ``Jᵀ·x = y``: ``M = y_S``, ``F = B(BᵀB)⁻¹(y_a − Aᵀ·y_S)``."""
    u0 = y[0] - (normal[i, 0, 0] * y[2] + normal[i, 1, 0] * y[3] + normal[i, 2, 0] * y[4])
    u1 = y[1] - (normal[i, 0, 1] * y[2] + normal[i, 1, 1] * y[3] + normal[i, 2, 1] * y[4])
    return (y[2], y[3], y[4],
            normal[i, 3, 0] * u0 + normal[i, 3, 1] * u1,
            normal[i, 4, 0] * u0 + normal[i, 4, 1] * u1,
            normal[i, 5, 0] * u0 + normal[i, 5, 1] * u1)  # fmt: skip


@_step
def _inertial(par: FloatArray, at: int, mass: float, rot: tuple, om: tuple, alpha: tuple,  # type: ignore[type-arg]
              acc: tuple, rc0: float, rc1: float, rc2: float, g: tuple  # type: ignore[type-arg]
              ) -> tuple[float, float, float, float, float, float]:  # fmt: skip
    """``(m(a_G − g), I·α + ω × I·ω)`` of a body whose origin accelerates by ``acc``, mass
    centre ``rc`` from it (world), ``I = R·I_body·Rᵀ``; ``rot`` the 9 entries of ``R`` row by
    row, ``om, alpha, acc, g`` 3 each (scalars: no view of an array)."""
    w0, w1, w2 = om
    k0, k1, k2 = _cross(w0, w1, w2, rc0, rc1, rc2)
    h0, h1, h2 = _cross(w0, w1, w2, k0, k1, k2)
    s0, s1, s2 = _cross(alpha[0], alpha[1], alpha[2], rc0, rc1, rc2)
    fx = mass * (acc[0] + s0 + h0 - g[0])
    fy = mass * (acc[1] + s1 + h1 - g[1])
    fz = mass * (acc[2] + s2 + h2 - g[2])
    # I·u = R·(I_b·(Rᵀ·u))
    iw = _apply(par, at, rot, w0, w1, w2)
    ia = _apply(par, at, rot, alpha[0], alpha[1], alpha[2])
    c0, c1, c2 = _cross(w0, w1, w2, iw[0], iw[1], iw[2])
    return fx, fy, fz, ia[0] + c0, ia[1] + c1, ia[2] + c2


@_step
def _apply(par: FloatArray, at: int, rot: tuple, u0: float, u1: float, u2: float  # type: ignore[type-arg]
           ) -> tuple[float, float, float]:  # fmt: skip
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rot
    l0 = r00 * u0 + r10 * u1 + r20 * u2
    l1 = r01 * u0 + r11 * u1 + r21 * u2
    l2 = r02 * u0 + r12 * u1 + r22 * u2
    b0 = par[at] * l0 + par[at + 1] * l1 + par[at + 2] * l2
    b1 = par[at + 3] * l0 + par[at + 4] * l1 + par[at + 5] * l2
    b2 = par[at + 6] * l0 + par[at + 7] * l1 + par[at + 8] * l2
    return (r00 * b0 + r01 * b1 + r02 * b2,
            r10 * b0 + r11 * b1 + r12 * b2,
            r20 * b0 + r21 * b1 + r22 * b2)  # fmt: skip


@_step
def _compatible(nw: FloatArray, target: FloatArray, reference: FloatArray, scale: float) -> bool:
    """kinematics._check_compatible for one leg: ``|w̃·t̃| ≤ 1e-8·6·max|w̃|·max(|t̃|, |r̃|)``."""
    off = 0.0
    wmax = 0.0
    tmax = 0.0
    for r in range(6):
        wt = nw[r] if r < 3 else nw[r] * scale
        tt = target[r] if r < 3 else target[r] / scale
        rr = reference[r] if r < 3 else reference[r] / scale
        off += wt * tt
        wmax = max(wmax, abs(wt))
        tmax = max(tmax, abs(tt), abs(rr))
    size = 6.0 * wmax * tmax
    return abs(off) <= COMPATIBILITY * max(size, 2.2250738585072014e-308)


@_step
def _solve_rates(fac: FloatArray, jac: FloatArray, piv: IntArray, dof: int, t: FloatArray,
                 out: FloatArray) -> None:  # fmt: skip
    """``J⁻¹·t`` (dof 6) or ``(JᵀJ)⁻¹Jᵀ·t`` (dof 5) with the leg's factors."""
    if dof == 6:
        for r in range(6):
            out[r] = t[r]
    else:
        for c in range(dof):
            s = 0.0
            for r in range(6):
                s += jac[r, c] * t[r]
            out[c] = s
    _lu_solve(fac, dof, piv, out)


@_step
def _lu_solve_transposed(a: FloatArray, n: int, piv: IntArray, b: FloatArray) -> None:
    """Solve ``Aᵀ·x = b`` in place with the factors ``P·A = L·U`` of :func:`_lu`."""
    # Aᵀ = Uᵀ·Lᵀ·P: Uᵀ y = b, Lᵀ z = y, x = Pᵀ z
    for r in range(n):
        s = b[r]
        for c in range(r):
            s -= a[c, r] * b[c]
        b[r] = s / a[r, r]
    for r in range(n - 1, -1, -1):
        s = b[r]
        for c in range(r + 1, n):
            s -= a[c, r] * b[c]
        b[r] = s
    for k in range(n - 1, -1, -1):
        p = piv[k]
        if p != k:
            t = b[k]
            b[k] = b[p]
            b[p] = t


@_step
def _transpose_solve_vector(fac: FloatArray, jac: FloatArray, piv: IntArray, dof: int,
                            y: FloatArray, work: FloatArray, out: FloatArray) -> None:  # fmt: skip
    """``J⁻ᵀ·y`` (dof 6) or ``J(JᵀJ)⁻¹·y`` (dof 5), ``(6,)`` as ``(M, F)``."""
    for c in range(dof):
        work[c] = y[c]
    if dof == 6:
        _lu_solve_transposed(fac, 6, piv, work)
        for r in range(6):
            out[r] = work[r]
    else:
        _lu_solve(fac, dof, piv, work)
        for r in range(6):
            s = 0.0
            for c in range(dof):
                s += jac[r, c] * work[c]
            out[r] = s


@_step
def _transpose_solve(fac: FloatArray, jac: FloatArray, piv: IntArray, dof: int, act: int,
                     work: FloatArray, out: FloatArray, y: FloatArray) -> None:  # fmt: skip
    """``x = J⁻ᵀ·e_act`` (or ``J(JᵀJ)⁻¹·e_act``)."""
    for r in range(6):
        y[r] = 0.0
    y[act] = 1.0
    _transpose_solve_vector(fac, jac, piv, dof, y, work, out)


@_step
def _chain_motion(ints: IntArray, i: int, jo: FloatArray, fo: FloatArray, axes: FloatArray,
                  dq: FloatArray, ddq: FloatArray, ow: FloatArray, oa: FloatArray,
                  oacc: FloatArray) -> None:  # fmt: skip
    """kinematics.chain_motion for leg ``i``: each body's ``ω, α`` and its origin's acceleration
    (the velocities as locals)."""
    w0 = w1 = w2 = 0.0
    a0 = a1 = a2 = 0.0
    o0 = o1 = o2 = 0.0
    v0 = v1 = v2 = 0.0
    c0 = c1 = c2 = 0.0
    col = 0
    for k in range(_J):
        kind = ints[4 + k]
        # the joint origin's velocity and acceleration on the proximal body
        x0, x1, x2 = jo[i, k, 0] - o0, jo[i, k, 1] - o1, jo[i, k, 2] - o2
        t0, t1, t2 = _cross(w0, w1, w2, x0, x1, x2)
        vj0, vj1, vj2 = v0 + t0, v1 + t1, v2 + t2
        s0, s1, s2 = _cross(a0, a1, a2, x0, x1, x2)
        u0, u1, u2 = _cross(w0, w1, w2, t0, t1, t2)
        aj0, aj1, aj2 = c0 + s0 + u0, c1 + s1 + u1, c2 + s2 + u2
        vf0, vf1, vf2 = vj0, vj1, vj2
        af0, af1, af2 = aj0, aj1, aj2
        for _n in range(_DOF[kind]):
            e0, e1, e2 = axes[i, col, 0], axes[i, col, 1], axes[i, col, 2]
            rate, acc = dq[i, col], ddq[i, col]
            if kind == 1:  # P: the frame origin on the proximal body, then the slide
                y0, y1, y2 = (
                    fo[i, k, 0] - jo[i, k, 0],
                    fo[i, k, 1] - jo[i, k, 1],
                    fo[i, k, 2] - jo[i, k, 2],
                )
                t0, t1, t2 = _cross(w0, w1, w2, y0, y1, y2)
                s0, s1, s2 = _cross(a0, a1, a2, y0, y1, y2)
                u0, u1, u2 = _cross(w0, w1, w2, t0, t1, t2)
                h0, h1, h2 = _cross(w0, w1, w2, e0, e1, e2)
                vf0, vf1, vf2 = vj0 + t0 + e0 * rate, vj1 + t1 + e1 * rate, vj2 + t2 + e2 * rate
                af0 = aj0 + s0 + u0 + e0 * acc + 2.0 * h0 * rate
                af1 = aj1 + s1 + u1 + e1 * acc + 2.0 * h1 * rate
                af2 = aj2 + s2 + u2 + e2 * acc + 2.0 * h2 * rate
            elif kind == 3:  # S: world axes
                a0, a1, a2 = a0 + e0 * acc, a1 + e1 * acc, a2 + e2 * acc
                w0, w1, w2 = w0 + e0 * rate, w1 + e1 * rate, w2 + e2 * rate
            else:  # R, U: an axis fixed in the proximal body
                h0, h1, h2 = _cross(w0, w1, w2, e0, e1, e2)
                a0, a1, a2 = (
                    a0 + e0 * acc + h0 * rate,
                    a1 + e1 * acc + h1 * rate,
                    a2 + e2 * acc + h2 * rate,
                )
                w0, w1, w2 = w0 + e0 * rate, w1 + e1 * rate, w2 + e2 * rate
            col += 1
        o0, o1, o2 = fo[i, k, 0], fo[i, k, 1], fo[i, k, 2]
        v0, v1, v2 = vf0, vf1, vf2
        c0, c1, c2 = af0, af1, af2
        ow[i, k, 0], ow[i, k, 1], ow[i, k, 2] = w0, w1, w2
        oa[i, k, 0], oa[i, k, 1], oa[i, k, 2] = a0, a1, a2
        oacc[i, k, 0], oacc[i, k, 1], oacc[i, k, 2] = c0, c1, c2


@_step
def _add_accelerations(i: int, dof: int, kinds: IntArray, owner: IntArray, fo: FloatArray,
                       axes: FloatArray, ddq: FloatArray, oa: FloatArray, oacc: FloatArray
                       ) -> None:  # fmt: skip
    """The ``q̈`` terms of leg ``i``'s bodies ``0 … J−2`` onto the bias of
    :func:`_chain_motion` (``q̈ = 0``): coordinate ``c`` of joint ``o ≤ k`` adds ``e_c·q̈_c``
    to ``α_k`` and ``e_c × (o_k − o_o)·q̈_c`` to the acceleration of body ``k``'s origin (a
    rotation), or ``e_c·q̈_c`` to the latter (a slide): the columns of the body's Jacobian."""
    for k in range(_J - 1):
        x0, x1, x2 = fo[i, k, 0], fo[i, k, 1], fo[i, k, 2]
        for c in range(dof):
            o = owner[c]
            if o > k:
                break
            acc = ddq[i, c]
            e0, e1, e2 = axes[i, c, 0] * acc, axes[i, c, 1] * acc, axes[i, c, 2] * acc
            if kinds[c] == 1:
                oacc[i, k, 0] += e0
                oacc[i, k, 1] += e1
                oacc[i, k, 2] += e2
            else:
                oa[i, k, 0] += e0
                oa[i, k, 1] += e1
                oa[i, k, 2] += e2
                if o < k:
                    h0, h1, h2 = _cross(e0, e1, e2, x0 - fo[i, o, 0], x1 - fo[i, o, 1],
                                        x2 - fo[i, o, 2])  # fmt: skip
                    oacc[i, k, 0] += h0
                    oacc[i, k, 1] += h1
                    oacc[i, k, 2] += h2


@_jit
def _scratch() -> tuple:  # type: ignore[type-arg]
    """The work arrays of :func:`_sample`: ``work``, ``frames`` and its scratch tuple."""
    work = (np.zeros((3, 3)), np.zeros((3, 3)))  # R·R_a of the leg's end, jr_Sᵀ·(…)
    frames = (
        np.zeros((_L, _J, 3)),
        np.zeros((_L, _J, 3)),
        np.zeros((_L, _J, 3, 3)),
        np.zeros((_L, _J, 3, 3)),
        np.zeros((_L, 6, 3)),
    )  # jo, fo, jr, fr, axes
    m6, v6, l6, lj3 = (6, 6), 6, (_L, 6), (_L, _J, 3)
    scr = (np.zeros(6, dtype=np.int64), np.zeros(6, dtype=np.int64), np.zeros(m6), np.zeros(m6),
           np.zeros(6, dtype=np.int64), np.zeros(v6), np.zeros(l6), np.zeros(l6), np.zeros(m6),
           np.zeros((_L, 3)), np.zeros(m6), np.zeros((_L, 6, 6)), np.zeros((_L, 6, 6)),
           np.zeros(l6, dtype=np.int64), np.zeros(v6), np.zeros(lj3), np.zeros(lj3),
           np.zeros(lj3), np.zeros(lj3), np.zeros(lj3), np.zeros(v6), np.zeros(v6), np.zeros(v6),
           np.zeros((_J, 3)), np.zeros((_J, 3)), np.zeros(3), np.zeros(3), np.zeros(v6),
           np.zeros(v6), np.zeros(v6))  # fmt: skip
    return work, frames, scr


@_jit
def _loop(ints: IntArray, par: FloatArray, p: FloatArray, rm: FloatArray, w: FloatArray,
          v: FloatArray, al: FloatArray, a: FloatArray, q: FloatArray, dq: FloatArray,
          ddq: FloatArray, tau: FloatArray, force: FloatArray, moment: FloatArray,
          measures: FloatArray, status: IntArray, start: int, stop: int) -> None:  # fmt: skip
    work, frames, scr = _scratch()
    # one sample's inputs and outputs staged in arrays of the loop (no view of the batch's
    # arrays per sample: each would count references, atomically)
    xp, xr, xw, xv, xal, xa = (np.zeros(3), np.zeros((3, 3)), np.zeros(3), np.zeros(3),
                               np.zeros(3), np.zeros(3))  # fmt: skip
    legs, dof = ints[1], ints[2]
    yq, ydq, yddq = np.zeros((legs, dof)), np.zeros((legs, dof)), np.zeros((legs, dof))
    ytau, ymeas = np.zeros(legs), np.zeros(legs + 1)
    yf, ym = np.zeros((legs, _J, 3)), np.zeros((legs, _J, 3))
    for n in range(start, stop):
        for r in range(3):
            xp[r], xw[r], xv[r], xal[r], xa[r] = p[n, r], w[n, r], v[n, r], al[n, r], a[n, r]
            for c in range(3):
                xr[r, c] = rm[n, r, c]
        status[n] = _sample(ints, par, xp, xr, xw, xv, xal, xa, yq, ydq, yddq, ytau, yf, ym,
                            ymeas, work, frames, scr)  # fmt: skip
        for i in range(legs):
            tau[n, i] = ytau[i]
            measures[n, i] = ymeas[i]
            for c in range(dof):
                q[n, i, c], dq[n, i, c], ddq[n, i, c] = yq[i, c], ydq[i, c], yddq[i, c]
            for k in range(_J):
                for r in range(3):
                    force[n, i, k, r], moment[n, i, k, r] = yf[i, k, r], ym[i, k, r]
        measures[n, legs] = ymeas[legs]


@_jit
def _one(ints: IntArray, par: FloatArray, p: FloatArray, rm: FloatArray, w: FloatArray,
         v: FloatArray, al: FloatArray, a: FloatArray, out: FloatArray) -> int:  # fmt: skip
    """One state (``(3,)``, ``(3, 3)``, four ``(3,)``) into ``out``: the blocks ``q, dq, ddq,
    tau, power, force, moment, measures`` flat, in that order, as :func:`_layout`; returns
    the status of :func:`_sample`.  One short call: the validated single call."""
    legs, dof, act = ints[1], ints[2], ints[3]
    nq, nw = legs * dof, legs * _J * 3
    work, frames, scr = _scratch()
    at = 3 * nq + 2 * legs
    q = out[0:nq].reshape((legs, dof))
    dq = out[nq : 2 * nq].reshape((legs, dof))
    tau = out[3 * nq : 3 * nq + legs]
    status = _sample(ints, par, p, rm, w, v, al, a, q, dq,
                     out[2 * nq : 3 * nq].reshape((legs, dof)), tau,
                     out[at : at + nw].reshape((legs, _J, 3)),
                     out[at + nw : at + 2 * nw].reshape((legs, _J, 3)),
                     out[at + 2 * nw : at + 2 * nw + legs + 1], work, frames, scr)  # fmt: skip
    for i in range(legs):
        out[3 * nq + legs + i] = tau[i] * dq[i, act]
    return status


def _layout(legs: int, dof: int, joints: int) -> tuple[int, list[tuple[int, int, tuple[int, ...]]]]:
    """The size of :func:`_one`'s ``out`` and its blocks ``(start, stop, shape)``: ``q, dq,
    ddq (legs, dof)``, ``tau, power (legs,)``, ``force, moment (legs, joints, 3)``, ``μ_leg
    (legs,)``, then ``μ_par`` alone."""
    blocks: list[tuple[int, int, tuple[int, ...]]] = []
    at = 0
    for shape in ((legs, dof),) * 3 + ((legs,),) * 2 + ((legs, joints, 3),) * 2 + ((legs,),):
        size = int(np.prod(shape))
        blocks.append((at, at + size, shape))
        at += size
    return at + 1, blocks


@numba.njit(cache=True, error_model="numpy", parallel=True)
def _loop_parallel(ints: IntArray, par: FloatArray, p: FloatArray, rm: FloatArray, w: FloatArray,
                   v: FloatArray, al: FloatArray, a: FloatArray, q: FloatArray, dq: FloatArray,
                   ddq: FloatArray, tau: FloatArray, force: FloatArray, moment: FloatArray,
                   measures: FloatArray, status: IntArray) -> None:  # fmt: skip
    n = p.shape[0]
    blocks = (n + BLOCK - 1) // BLOCK
    for k in numba.prange(blocks):
        _loop(ints, par, p, rm, w, v, al, a, q, dq, ddq, tau, force, moment, measures, status,
              k * BLOCK, min(n, (k + 1) * BLOCK))  # fmt: skip


# ------------------------------------------------------------------ the entries
@dataclass(frozen=True)
class SpatialSample:
    """One state's inverse dynamics (docs/spatial.md §9 without the batch axis).

    Attributes
    ----------
    q, dq, ddq : (legs, dof)
    tau, power : (legs,)
    force, moment : (legs, joints, 3), N and N·m, world frame, at the joint points
    leg_measure : (legs,); parallel_measure : float
    """

    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    tau: FloatArray
    power: FloatArray
    force: FloatArray
    moment: FloatArray
    leg_measure: FloatArray
    parallel_measure: float


@dataclass(frozen=True)
class SpatialSamples:
    """``N`` states' inverse dynamics: the arrays of :class:`SpatialSample` with a leading
    ``N``, ``parallel_measure (N,)`` and the kernel's ``status (N,)`` (all 0 when returned by
    :meth:`CompiledSpatial.solve_batch`)."""

    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    tau: FloatArray
    power: FloatArray
    force: FloatArray
    moment: FloatArray
    leg_measure: FloatArray
    parallel_measure: FloatArray
    status: IntArray


def _vector(name: str, value: ArrayLike | None, shape: tuple[int, ...]) -> FloatArray:
    """``value`` as a C-contiguous float64 array of ``shape`` (itself when it is one)."""
    if (type(value) is np.ndarray and value.dtype == np.float64 and value.shape == shape
            and value.flags.c_contiguous):  # fmt: skip
        return value
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise TrajectoryError(f"{name} must be real numbers: {error}"[:200], subject="motion",
                              key=name) from None  # fmt: skip
    if array.shape != shape:
        raise TrajectoryError(
            f"{name} must have shape {shape}, got {array.shape}", subject="motion", key=name
        )
    return np.ascontiguousarray(array)


class CompiledSpatial:
    """The compiled inverse dynamics of one robot (:func:`compile_spatial`).

    ``solve(position, rotation, omega, velocity, alpha, acceleration)`` takes one state
    (``(3,)``, ``(3, 3)``, four ``(3,)``: §4's pose, twist and its derivative) and returns
    a :class:`SpatialSample`; ``solve_batch`` takes ``N`` states (``(N, 3)``,
    ``(N, 3, 3)``, …) or a :class:`~prp3.spatial.motion.PlatformMotion` and returns a
    :class:`SpatialSamples`.  A refused state raises the error the numpy route raises on it
    (:class:`~prp3.errors.UnreachablePoseError`, :class:`~prp3.errors.SingularPoseError`,
    :class:`~prp3.errors.TrajectoryError`).
    """

    def __init__(self, robot: SpatialRobot) -> None:
        self.robot = robot
        self.ints, self.par = pack(robot)
        legs, dof = len(robot.legs), robot.legs[0].dof
        self._shapes = (legs, dof, len(robot.legs[0].joints))
        self._size, self._blocks = _layout(*self._shapes)

    def _arrays(self, n: int) -> tuple[FloatArray, ...]:
        legs, dof, joints = self._shapes
        return (np.empty((n, legs, dof)), np.empty((n, legs, dof)), np.empty((n, legs, dof)),
                np.empty((n, legs)), np.empty((n, legs, joints, 3)),
                np.empty((n, legs, joints, 3)), np.empty((n, legs + 1)))  # fmt: skip

    def raw(
        self,
        position: FloatArray,
        rotation: FloatArray,
        omega: FloatArray,
        velocity: FloatArray,
        alpha: FloatArray,
        acceleration: FloatArray,
        threads: bool = True,
    ) -> SpatialSamples:
        """The kernel on contiguous float64 arrays ``(N, 3)``, ``(N, 3, 3)``, … unchecked: every
        sample's status, nothing raised (for benchmarks and the C's tests)."""
        n = position.shape[0]
        q, dq, ddq, tau, force, moment, measures = self._arrays(n)
        status = np.empty(n, dtype=np.int64)
        loop = _loop_parallel if threads and n >= PARALLEL_MIN else None
        if loop is not None:
            loop(self.ints, self.par, position, rotation, omega, velocity, alpha, acceleration,
                 q, dq, ddq, tau, force, moment, measures, status)  # fmt: skip
        else:
            _loop(self.ints, self.par, position, rotation, omega, velocity, alpha, acceleration,
                  q, dq, ddq, tau, force, moment, measures, status, 0, n)  # fmt: skip
        act = self.robot.legs[0].actuated_coordinate
        legs = self._shapes[0]
        return SpatialSamples(q, dq, ddq, tau, tau * dq[..., act], force, moment,
                              measures[:, :legs], measures[:, legs], status)  # fmt: skip

    def _refuse(self, status: IntArray, motion: PlatformMotion) -> None:
        """Raise the numpy route's error for the first refused sample of ``motion``."""
        bad = np.flatnonzero(status)
        if not bad.size:
            return
        k = int(bad[0])
        code = int(status[k])
        one = motion.chunk(k, k + 1)
        chunk_kinematics(self.robot, one, k)  # raises the refusal, naming sample k
        if code == _OVERFLOW:
            raise TrajectoryError(
                "the inverse dynamics overflows float64 (an output is not finite)",
                subject="motion",
                sample=k,
                time=float(motion.t[k]),
            )
        raise TrajectoryError(  # pragma: no cover - the kernel's tolerance edge
            f"refused by the compiled kernel: {SPATIAL_STATUS[code][2]}",
            subject="motion",
            sample=k,
            time=float(motion.t[k]),
        )

    def solve(
        self,
        position: ArrayLike,
        rotation: ArrayLike,
        omega: ArrayLike,
        velocity: ArrayLike,
        alpha: ArrayLike,
        acceleration: ArrayLike,
    ) -> SpatialSample:
        """One state's joint motion, efforts, powers and every joint's wrench (docs/spatial.md §9).

        Raises
        ------
        TrajectoryError
            A wrong shape, a value that is not finite, a rotation that is not one.
        UnreachablePoseError, SingularPoseError
            As :func:`~prp3.spatial.outputs.spatial_inverse_dynamics`.
        """
        p = _vector("position", position, (3,))
        r = _vector("rotation", rotation, (3, 3))
        rates = [_vector(name, value, (3,)) for name, value in (
            ("omega", omega), ("velocity", velocity), ("alpha", alpha),
            ("acceleration", acceleration))]  # fmt: skip
        out = np.empty(self._size)
        status = _one(self.ints, self.par, p, r, rates[0], rates[1], rates[2], rates[3], out)
        if status:  # the motion's validation names a bad input, the route a refusal
            self._refuse(np.array([status]), PlatformMotion.of([0.0], p, r, *rates))
        q, dq, ddq, tau, power, force, moment, leg = [
            out[a:b] if len(shape) == 1 else out[a:b].reshape(shape) for a, b, shape in self._blocks
        ]
        return SpatialSample(q, dq, ddq, tau, power, force, moment, leg, float(out[-1]))

    def solve_batch(
        self,
        position: ArrayLike | PlatformMotion,
        rotation: ArrayLike | None = None,
        omega: ArrayLike | None = None,
        velocity: ArrayLike | None = None,
        alpha: ArrayLike | None = None,
        acceleration: ArrayLike | None = None,
    ) -> SpatialSamples:
        """``N`` states at once (every thread of numba's layer from ``PARALLEL_MIN`` states).

        ``position`` may be a :class:`~prp3.spatial.motion.PlatformMotion` (the other
        arguments left out), already validated; else the arrays are checked as
        :meth:`solve`'s, with the sample named.

        Raises
        ------
        TrajectoryError, UnreachablePoseError, SingularPoseError
            The first refused sample, as the numpy route names it.
        """
        if isinstance(position, PlatformMotion):
            motion = position
            arrays = [np.ascontiguousarray(x) for x in (
                motion.position, motion.rotation, motion.omega, motion.velocity, motion.alpha,
                motion.acceleration)]  # fmt: skip
        else:
            p = np.asarray(position, dtype=np.float64)
            n = p.shape[0] if p.ndim == 2 else -1
            if n < 1:
                raise TrajectoryError(f"position must have shape (N, 3), got {p.shape}",
                                      subject="motion", key="position")  # fmt: skip
            arrays = [_vector("position", p, (n, 3)), _vector("rotation", rotation, (n, 3, 3))]
            arrays += [_vector(name, value, (n, 3)) for name, value in (
                ("omega", omega), ("velocity", velocity), ("alpha", alpha),
                ("acceleration", acceleration))]  # fmt: skip
            motion = None
        out = self.raw(arrays[0], arrays[1], arrays[2], arrays[3], arrays[4], arrays[5])
        if out.status.any():
            if motion is None:  # its validation names a bad input and its sample
                motion = PlatformMotion.of(np.arange(len(arrays[0]), dtype=np.float64), *arrays)
            self._refuse(out.status, motion)
        return out


def compile_spatial(robot: SpatialRobot) -> CompiledSpatial:
    """The compiled inverse dynamics of ``robot`` (docs/spatial.md §19): ``.solve`` and ``.solve_batch``.

    The machine code is compiled once per installation (numba's cache) and serves every
    robot: the robot is data (:func:`pack`).

    Raises
    ------
    ParameterError
        ``robot`` is not a :class:`~prp3.spatial.model.SpatialRobot`.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    return CompiledSpatial(robot)
