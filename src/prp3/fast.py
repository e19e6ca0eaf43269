"""The paper's method, fused for speed: a batch path and a single-sample path.

Same algorithm as :func:`prp3.kinematics.inverse_kinematics` followed by
:func:`prp3.dynamics.paper_method` — inverse geometry (eq. 10), conditions of
connectivity (eqs. 14, 17), body wrenches (eqs. 19, 20, 22), the recursion of
chain A (eq. 21), the virtual velocities (eqs. 15, 16) and eqs. (23)–(25) —
with every planar dot and cross product between fixed vectors worked out once.
Only ``f10``, ``f21y``, ``f21z`` (and ``p10``; ``n10, m10, n32, m32`` on
request) are produced: none of the intermediate ``(N, 3, 2)`` stacks exist.

* :func:`paper_forces` — ``(N, 3)`` arrays in, ``(N, 3)`` arrays out, pure
  numpy in chunks of preallocated 1-D work rows (memory bounded for any N).
* :func:`sample_forces` — one sample with the :mod:`math` module (no numpy in
  the hot path), on the constants of a :class:`CompiledRobot` built once by
  :func:`compile_robot`; :func:`sample_forces_unchecked` is its inner function
  for a control loop that has validated its input already.

Closed forms used (``J`` is the +90° rotation, ``c = (l0/2)(1/√3, 1)``,
``d_i = Rot(φ)·a_i`` with ``a_i = Rot(α_i − π/3)·(1, 0)``):

* ``e_i × d_i = D = sin(φ − π/3)`` and ``e_i·d_i = C = cos(φ − π/3)`` for the
  three legs; ``B_i0 × d_i = l0·cos φ``; ``e_i × Rot(α_i+φ)·c = q`` and
  ``e_i·Rot(α_i+φ)·c = p`` with ``(p, q) = Rot(φ)·c``; ``Rot(α_i+φ)·c·d_i =
  −l0/(2√3)`` and ``Rot(α_i+φ)·c × d_i = −l0/2``.  Hence eq. (10) gives
  ``λ32_i = (n_i·G + l0/2 − q)/D`` and ``ρ_i·d_i = λ32_i − l0/(2√3)``;
  eq. (14) gives ``λ̇32_i = (n_i·Ġ − φ̇·(C·λ32_i + p))/D`` and
  ``λ̇10_i = (Ġ × d_i + φ̇·ρ_i·d_i)/D``; eq. (17) gives
  ``λ̈10_i = (G̈ × d_i + φ̈·ρ_i·d_i − (l0/2)·φ̇² + 2·φ̇·λ̇32_i)/D``.
* ``d⊥_j·e_j = −D``, ``d⊥_j·n_j = C`` and ``d_A·d⊥_j = −sin(α_j − α_A)``, so
  the virtual velocities of eqs. (15)–(16) are ``ω^v·e_j = D/S``,
  ``ω^v·n_j = −C/S`` with ``S = Σ ρ_i·d_i``, ``S·D = 3l0/2 − 3q − (√3/2)·l0·D``,
  and ``v32^Av·e_j = D·κ_j − δ_jA·C``, ``v32^Av·n_j = −C·κ_j − δ_jA·D`` with
  ``κ_j = ((2/3)·d_A·Σ d⊥_i(ρ_i·d_i) + l0/2)/S + (2/3)·sin(α_j − α_A)``.
* Then eqs. (23)–(25) read, with ``T = d_A·F3``, ``M2 = Σ_i M2^i`` (eq. 21)
  and ``W_j = M2/S + κ_j·T``:
  ``f21z_j = F2^j·e_j + D·W_j − δ_jA·C·T``,
  ``f21y_j = F2^j·n_j − C·W_j − δ_jA·D·T`` and
  ``f10_j = f21z_j + m1·(λ̈10_j − g·e_j)``.

Every per-leg quantity before the forces is a combination
``u_x·n_ix + u_y·n_iy + u_1`` of the leg normal (the three legs are turned by
120°): the batch path carries the three coefficient rows ``u_x, u_y, u_1`` of
``λ32, λ̇32, λ̈10`` (one row each instead of one per leg) and turns the rows
into the forces of the three legs by one small matrix product per output,
whose coefficients :func:`compile_robot` computes once.  Results agree with
:func:`~prp3.dynamics.paper_method` to about 1e-14 relative (round-off).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import Prp3Error, TrajectoryError
from .geometry import ALPHA, LEG_AXIS, LEG_NORMAL, SINGULARITY_THRESHOLD, check_poses
from .geometry import inverse_geometry as _inverse_geometry
from .model import Robot

__all__ = [
    "DEFAULT_CHUNK",
    "CompiledRobot",
    "FastForces",
    "SampleForces",
    "compile_robot",
    "paper_forces",
    "sample_forces",
    "sample_forces_unchecked",
]

FloatArray = NDArray[np.float64]

_H = math.sqrt(3.0) / 2.0  # sin(π/3)

#: Samples per chunk of :func:`paper_forces` (work rows stay in the CPU caches).
DEFAULT_CHUNK = 4096

#: ``a_i = d_i`` at ``φ = 0``: unit vectors at ``α_i − π/3``, shape (3, 2).
_SLIDE_AT_ZERO: FloatArray = np.stack(
    [np.cos(ALPHA - math.pi / 3.0), np.sin(ALPHA - math.pi / 3.0)], -1
)
#: Rows ``n_x, n_y, 1`` of the three legs: ``coefficients (n, 3) @ _LEGS → legs (n, 3)``.
_LEGS: FloatArray = np.stack([LEG_NORMAL[:, 0], LEG_NORMAL[:, 1], np.ones(3)])
_LEGS.flags.writeable = False
#: ``sin(α_j − α_A)·2/3``: leg term of ``κ_j`` (0, 1/√3, −1/√3).
_KAPPA_LEG: FloatArray = (2.0 / 3.0) * np.sin(ALPHA - ALPHA[0])
#: ``δ_jA``: the platform hangs on chain A (eq. 21).
_CHAIN_A: FloatArray = np.array([1.0, 0.0, 0.0])

# Rows of the matrix product of compile_robot's trig matrix with (cos φ, sin φ, 1):
_D, _C, _P, _LAMBDA_FREE, _SD, _RA_X, _RA_Y, _KA, _KB, _GT_X, _GT_Y = range(11)
_FORCE_TRIG_ROWS = 9  # rows up to _KB; the rotated gravity only for the reactions

# Rows of the basis the forces are linear in (``basis.T @ matrix → legs``), ordered
# so that each force reads a contiguous block: f21z rows 0–10, f21y rows 6–13, and
# f10 − f21z = m1·(λ̈10 − g·e) rows 3–6.
(
    _DZ,  # D·Z with Z = D·(M2 + (...)·T)/(S·D)
    _EPS_KA, _W2_KB,  # φ̈·ka, φ̇²·kb
    _GAM_X, _GAM_Y, _GAM_1,  # coefficient rows of λ̈10
    _ONE,
    _F3_X, _F3_Y,  # F3 = m3·(G̈ − g), eq. (22)
    _DT, _CT,  # D·T, C·T with T = d_A·F3
    _CZ,  # C·Z
    _EPS_KB, _W2_KA,  # φ̈·kb, φ̇²·ka
    # reactions only:
    _KA_GAM_X, _KA_GAM_Y, _KA_GAM_1,
    _D_GAM_X, _D_GAM_Y, _D_GAM_1,
    _EPS, _W2, _GT_X_B, _GT_Y_B,
) = range(24)  # fmt: skip
_F21Z_ROWS = slice(_DZ, _CT + 1)
_F21Y_ROWS = slice(_ONE, _W2_KA + 1)
_PISTON_ROWS = slice(_GAM_X, _ONE + 1)
_FORCE_BASIS_ROWS = 14
_ALL_BASIS_ROWS = 24

#: Up to this many samples (without reactions) :func:`paper_forces` loops over
#: :func:`sample_forces_unchecked`: below it numpy's per-call overhead dominates.
_FEW_SAMPLES = 16

# Screening margins of the batch checks; the exact reference checks decide.
_SINGULAR_SCREEN = SINGULARITY_THRESHOLD * (1.0 + 1e-9)
_STROKE_SCREEN = 1e-9  # m


@dataclass(frozen=True, eq=False, slots=True)
class CompiledRobot:
    """Constants of a robot for the fast paths, computed once by :func:`compile_robot`.

    A pure function of :attr:`robot`; read-only.  The floats are the ones the
    single-sample path needs; the matrices serve the batch path.

    Attributes
    ----------
    robot : Robot
        The robot the constants were computed from.
    l0, cx, cy : float
        ``l0`` and the platform vector ``c = (cx, cy) = (l0/2)(1/√3, 1)`` (m), eq. (8).
    gravity_x, gravity_y : float
        Gravity (m/s²).
    piston_mass, link_mass, platform_mass : float
        ``m1, m2, m3`` (kg).
    rotary_inertia : float
        ``3·(I2 + m2·|c2|²) + I3`` (kg·m²): the ``φ̈`` term of ``Σ M2`` (eq. 21).
    link_com_x, link_com_y : float
        ``c2`` (m).
    link_gravity_axial, link_gravity_normal : tuple of float
        ``m2·g·e_i`` and ``m2·g·n_i`` (N) of legs A, B, C.
    piston_gravity_axial : tuple of float
        ``m1·g·e_i`` (N).
    stroke : tuple of float or None
        ``robot.limits.stroke``.
    trig_matrix : ndarray (11, 3)
        Rows of the functions of ``φ`` alone as combinations of ``(cos φ, sin φ, 1)``.
    f21z_matrix, f21y_matrix : ndarray (11, 3), (8, 3)
        ``f21z`` and ``f21y`` of the three legs from their blocks of basis rows.
    piston_matrix : ndarray (4, 3)
        ``f10 − f21z = m1·(λ̈10 − g·e)`` of the three legs from its block of basis rows.
    n10_matrix, m10_matrix, n32_matrix, m32_matrix : ndarray (24, 3)
        Reactions (``n32`` without its ``C·f21y − D·f21z`` part) from 24 basis rows.
    """

    robot: Robot
    l0: float
    cx: float
    cy: float
    gravity_x: float
    gravity_y: float
    piston_mass: float
    link_mass: float
    platform_mass: float
    rotary_inertia: float
    link_com_x: float
    link_com_y: float
    link_gravity_axial: tuple[float, float, float]
    link_gravity_normal: tuple[float, float, float]
    piston_gravity_axial: tuple[float, float, float]
    stroke: tuple[float, float] | None
    trig_matrix: FloatArray
    f21z_matrix: FloatArray
    f21y_matrix: FloatArray
    piston_matrix: FloatArray
    n10_matrix: FloatArray
    m10_matrix: FloatArray
    n32_matrix: FloatArray
    m32_matrix: FloatArray


def _frozen(array: FloatArray) -> FloatArray:
    array.flags.writeable = False
    return array


def compile_robot(robot: Robot) -> CompiledRobot:
    """Precompute the constants of ``robot`` for :func:`paper_forces` and :func:`sample_forces`.

    Raises
    ------
    Prp3Error
        If ``robot`` is not a :class:`~prp3.model.Robot`.

    Examples
    --------
    >>> compiled = compile_robot(Robot())
    >>> round(compiled.rotary_inertia, 6)    # 3·6.25e-4 + 0.0675
    0.069375
    """
    if not isinstance(robot, Robot):
        raise Prp3Error(f"robot must be a prp3.Robot, got {type(robot).__name__}")
    l0 = robot.l0
    cx, cy = 0.5 * l0 / math.sqrt(3.0), 0.5 * l0
    gx, gy = robot.gravity
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    I2, I3 = robot.link.inertia, robot.platform_inertia
    c1x, c1y = robot.piston.com
    c2x, c2y = robot.link.com
    g = np.array([gx, gy])
    g_axial = LEG_AXIS @ g  # g·e_i
    g_normal = LEG_NORMAL @ g  # g·n_i
    nx, ny, one = _LEGS  # per-leg constants of the coefficient rows

    # functions of φ alone as rows over (cos φ, sin φ, 1)
    cos_, sin_, const = np.eye(3)
    D = 0.5 * sin_ - _H * cos_  # sin(φ − π/3)
    C = 0.5 * cos_ + _H * sin_  # cos(φ − π/3)
    p = cx * cos_ - cy * sin_  # (p, q) = Rot(φ)·c
    q = cx * sin_ + cy * cos_
    trig = np.stack(
        [
            D,
            C,
            p,
            cy * const - q,  # D·λ32_i − n_i·G, eq. (10)
            1.5 * l0 * const - 3.0 * q - _H * l0 * D,  # S·D, S = Σ ρ_i·d_i
            0.5 * p - _H * q,  # Rot(α_A + φ)·c = G − A3, eq. (8)
            _H * p + 0.5 * q,
            c2x * D + c2y * C,  # ka = −c2 × e_i (link centre of mass)
            c2x * C - c2y * D,  # kb = c2·e_i in the frame (d_i, d⊥_i)
            gx * cos_ + gy * sin_,  # Rot(−φ)·g
            gy * cos_ - gx * sin_,
        ]
    )

    def matrix(rows: dict[int, ArrayLike], block: slice = slice(0, _ALL_BASIS_ROWS)) -> FloatArray:
        out = np.zeros((_ALL_BASIS_ROWS, 3))
        for row, legs in rows.items():
            out[row] = legs
        assert not out[: block.start].any() and not out[block.stop :].any(), block
        return _frozen(out[block].copy())

    # f21z_j = m2·(λ̈10_j − g·e_j) + ce + D·W_j + δ_jA·(F3·e_A − C·T), eq. (25)
    f21z = {
        _GAM_X: m2 * nx, _GAM_Y: m2 * ny, _GAM_1: m2 * one,
        _F3_X: LEG_AXIS[0, 0] * _CHAIN_A, _F3_Y: LEG_AXIS[0, 1] * _CHAIN_A,
        _DT: _KAPPA_LEG, _CT: -_CHAIN_A, _DZ: one,
        _EPS_KA: -m2 * one, _W2_KB: -m2 * one,  # ce = −m2·(φ̈·ka + φ̇²·kb)
        _ONE: -m2 * g_axial,
    }  # fmt: skip
    # f21y_j = −m2·g·n_j + cn − C·W_j + δ_jA·(F3·n_A − D·T), eq. (24)
    f21y = {
        _F3_X: LEG_NORMAL[0, 0] * _CHAIN_A, _F3_Y: LEG_NORMAL[0, 1] * _CHAIN_A,
        _DT: -_CHAIN_A, _CT: -_KAPPA_LEG, _CZ: -one,
        _EPS_KB: m2 * one, _W2_KA: -m2 * one,  # cn = m2·(φ̈·kb − φ̇²·ka)
        _ONE: -m2 * g_normal,
    }  # fmt: skip
    # f10_j = f21z_j + m1·(λ̈10_j − g·e_j), eq. (23)
    piston = {_GAM_X: m1 * nx, _GAM_Y: m1 * ny, _GAM_1: m1 * one, _ONE: -m1 * g_axial}
    # reactions: balance of piston (n10, m10) and link 2 (n32, m32) of each leg
    a = _SLIDE_AT_ZERO
    cross_o1_g = c1x * (LEG_AXIS[:, 0] * gy - LEG_AXIS[:, 1] * gx) + c1y * (
        LEG_NORMAL[:, 0] * gy - LEG_NORMAL[:, 1] * gx
    )
    n10 = dict(f21y)
    n10[_ONE] = -(m1 + m2) * g_normal  # n10 = f21y − m1·g·n
    m10 = {  # m10 = c1 × F10 = −m1·(c1y·λ̈10 + c1 × g)
        _GAM_X: -m1 * c1y * nx, _GAM_Y: -m1 * c1y * ny, _GAM_1: -m1 * c1y * one,
        _ONE: -m1 * cross_o1_g,
    }  # fmt: skip
    # n32 − (C·f21y − D·f21z) = m2·(D·λ̈10 − φ̈·c2x + φ̇²·c2y + d × g)
    n32 = {
        _D_GAM_X: m2 * nx, _D_GAM_Y: m2 * ny, _D_GAM_1: m2 * one,
        _EPS: -m2 * c2x * one, _W2: m2 * c2y * one,
        _GT_X_B: -m2 * a[:, 1], _GT_Y_B: m2 * a[:, 0],
    }  # fmt: skip
    # m32 = −M20 = −(I2 + m2|c2|²)·φ̈ + m2·ka·λ̈10 + m2·(c2x·d × g − c2y·d·g)
    m32 = {
        _KA_GAM_X: m2 * nx, _KA_GAM_Y: m2 * ny, _KA_GAM_1: m2 * one,
        _EPS: -(I2 + m2 * (c2x * c2x + c2y * c2y)) * one,
        _GT_X_B: -m2 * (c2x * a[:, 1] + c2y * a[:, 0]),
        _GT_Y_B: m2 * (c2x * a[:, 0] - c2y * a[:, 1]),
    }  # fmt: skip
    return CompiledRobot(
        robot=robot,
        l0=l0,
        cx=cx,
        cy=cy,
        gravity_x=gx,
        gravity_y=gy,
        piston_mass=m1,
        link_mass=m2,
        platform_mass=m3,
        rotary_inertia=3.0 * (I2 + m2 * (c2x * c2x + c2y * c2y)) + I3,
        link_com_x=c2x,
        link_com_y=c2y,
        link_gravity_axial=_three(m2 * g_axial),
        link_gravity_normal=_three(m2 * g_normal),
        piston_gravity_axial=_three(m1 * g_axial),
        stroke=robot.limits.stroke,
        trig_matrix=_frozen(trig.copy()),
        f21z_matrix=matrix(f21z, _F21Z_ROWS),
        f21y_matrix=matrix(f21y, _F21Y_ROWS),
        piston_matrix=matrix(piston, _PISTON_ROWS),
        n10_matrix=matrix(n10),
        m10_matrix=matrix(m10),
        n32_matrix=matrix(n32),
        m32_matrix=matrix(m32),
    )


def _three(values: FloatArray) -> tuple[float, float, float]:
    a, b, c = values.tolist()
    return (a, b, c)


# ---------------------------------------------------------------------- batch
@dataclass(frozen=True)
class FastForces:
    """Actuator forces, input powers and joint forces from :func:`paper_forces`.

    Every array has the batch shape of the input and legs A, B, C last:
    ``(N, 3)``, or ``(3,)`` for a single sample.  Signs and units as in
    :class:`prp3.dynamics.InverseDynamics`.

    Attributes
    ----------
    f10 : ndarray
        Force of actuator i on its piston along ``+e_i`` (N), eq. (23).
    p10 : ndarray
        Input power ``f10·λ̇10`` (W).
    f21y, f21z : ndarray
        Force of piston i on link 2 along ``n_i`` and ``e_i`` (N), eqs. (24), (25).
    n10, m10, n32, m32 : ndarray or None
        The other reactions (N, N·m), or ``None`` unless ``reactions=True``.
    """

    f10: FloatArray
    p10: FloatArray
    f21y: FloatArray
    f21z: FloatArray
    n10: FloatArray | None = None
    m10: FloatArray | None = None
    n32: FloatArray | None = None
    m32: FloatArray | None = None


_OUTPUTS = ("f10", "p10", "f21y", "f21z")
_REACTIONS = ("n10", "m10", "n32", "m32")


def paper_forces(
    robot: Robot | CompiledRobot,
    pose: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    *,
    reactions: bool = False,
    out: FastForces | None = None,
    chunk_size: int = DEFAULT_CHUNK,
) -> FastForces:
    """Forces of the paper's method (eqs. 10, 14, 17, 19–25) for a batch of samples.

    The same numbers as ``paper_method(robot, inverse_kinematics(robot, motion))``
    to round-off, computed in chunks of ``chunk_size`` samples with a few
    preallocated work rows: memory beyond inputs and outputs stays bounded.
    Up to 16 samples without ``reactions`` are computed one by one by
    :func:`sample_forces_unchecked` (numpy's per-call overhead would dominate).

    Parameters
    ----------
    robot : Robot or CompiledRobot
        The robot (compiled on the fly when a :class:`Robot` is given).
    pose, velocity, acceleration : array_like, shape (N, 3) or (3,)
        ``(x, y, φ)``, ``(ẋ, ẏ, φ̇)``, ``(ẍ, ÿ, φ̈)`` of the platform (SI units, rad).
    reactions : bool
        Also compute ``n10, m10, n32, m32``.
    out : FastForces, optional
        Arrays to write into (C-contiguous float64 of the output shape; with
        ``reactions=True`` the reaction arrays too).  They are returned.  If
        an error is raised, their content is unspecified.  Without ``out``
        the returned arrays are views of one new block (huge pages for big N).
    chunk_size : int
        Samples per chunk, >= 1.

    Returns
    -------
    FastForces
        Arrays ``(N, 3)``, or ``(3,)`` for a single sample.

    Raises
    ------
    TrajectoryError
        Shapes differ or are not ``(N, 3)``/``(3,)``, or a value is not finite.
    SingularPoseError, UnreachablePoseError
        As :func:`prp3.geometry.inverse_geometry` (same messages and sample index).
    Prp3Error
        Bad ``out`` or ``chunk_size``.

    Examples
    --------
    >>> forces = paper_forces(Robot(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    >>> forces.f10.round(4).tolist()     # static central configuration (see paper_method)
    [31.8589, -8.4957, -23.3632]
    """
    compiled = robot if isinstance(robot, CompiledRobot) else compile_robot(robot)
    arrays = [_as_samples(name, value) for name, value in _named(pose, velocity, acceleration)]
    if not arrays[0].shape == arrays[1].shape == arrays[2].shape:
        shapes = ", ".join(f"{name} {a.shape}" for name, a in zip(_INPUTS, arrays, strict=True))
        raise TrajectoryError(
            f"pose, velocity and acceleration must have the same shape, got {shapes}"
        )
    shape = arrays[0].shape
    if (
        isinstance(chunk_size, bool)
        or not isinstance(chunk_size, int | np.integer)
        or chunk_size < 1
    ):
        raise Prp3Error(f"chunk_size must be an integer >= 1, got {chunk_size!r}")
    names = _OUTPUTS + (_REACTIONS if reactions else ())
    result = _outputs(out, names, shape)
    flat = [a.reshape(-1, 3) for a in arrays]
    samples = flat[0].shape[0]
    if samples and not reactions and samples <= _FEW_SAMPLES:
        table = _sample_table(compiled, flat)
        for name, values in zip(_OUTPUTS, table, strict=True):
            result[name][...] = values.reshape(shape)
    elif samples:
        targets = {name: array.reshape(-1, 3) for name, array in result.items()}
        _compute(compiled, flat, targets, reactions, int(chunk_size))
    return FastForces(**result)


_INPUTS = ("pose", "velocity", "acceleration")


def _named(*values: ArrayLike) -> zip[tuple[str, ArrayLike]]:
    return zip(_INPUTS, values, strict=True)


def _as_samples(name: str, value: ArrayLike) -> FloatArray:
    try:
        if np.asarray(value).dtype.kind in "cSUV":  # would drop an imaginary part, parse text
            raise TypeError(name)
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise TrajectoryError(f"{name} must be an array of numbers, got {value!r}") from None
    if array.ndim not in (1, 2) or array.shape[-1] != 3:
        raise TrajectoryError(f"{name} must have shape (3,) or (N, 3), got {array.shape}")
    return array


def _outputs(
    out: FastForces | None, names: tuple[str, ...], shape: tuple[int, ...]
) -> dict[str, FloatArray]:
    if out is None:
        # one block: large enough for numpy to ask for huge pages (fewer page faults)
        block = np.empty((len(names), *shape))
        return dict(zip(names, block, strict=True))
    if not isinstance(out, FastForces):
        raise Prp3Error(f"out must be a FastForces, got {type(out).__name__}")
    result: dict[str, FloatArray] = {}
    for name in names:
        array = getattr(out, name)
        if (
            not isinstance(array, np.ndarray)
            or array.dtype != np.float64
            or array.shape != shape
            or not array.flags.c_contiguous
            or not array.flags.writeable
        ):
            described = (
                "None" if array is None else f"{type(array).__name__} {getattr(array, 'shape', '')}"
            )
            raise Prp3Error(
                f"out.{name} must be a writeable C-contiguous float64 array of shape {shape}, "
                f"got {described}"
            )
        result[name] = array
    return result


def _compute(
    compiled: CompiledRobot,
    inputs: list[FloatArray],
    targets: dict[str, FloatArray],
    reactions: bool,
    chunk_size: int,
) -> None:
    samples = inputs[0].shape[0]
    width = min(chunk_size, samples)
    rows = _ALL_BASIS_ROWS if reactions else _FORCE_BASIS_ROWS
    state = np.empty((9, width))  # x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈
    trig_in = np.empty((3, width))  # cos φ, sin φ, 1
    trig_in[2] = 1.0
    trig = np.empty((11 if reactions else _FORCE_TRIG_ROWS, width))
    basis = np.empty((rows, width))
    basis[_ONE] = 1.0
    rate = np.empty((3, width))  # coefficient rows of λ̇10
    work = np.empty((16, width))
    for start in range(0, samples, width):
        stop = min(start + width, samples)
        n = stop - start
        for k, array in enumerate(inputs):
            np.copyto(state[3 * k : 3 * k + 3, :n], array[start:stop].T)
        chunk_targets = {name: array[start:stop] for name, array in targets.items()}
        buffers = (
            state[:, :n],
            trig_in[:, :n],
            trig[:, :n],
            basis[:, :n],
            rate[:, :n],
            work[:, :n],
        )
        if _chunk(compiled, *buffers, chunk_targets, reactions, validate=True):
            _raise_input_error(compiled, inputs, stop)  # raises unless a borderline stroke case
            _chunk(compiled, *buffers, chunk_targets, reactions, validate=False)


def _chunk(
    cr: CompiledRobot,
    state: FloatArray,
    trig_in: FloatArray,
    trig: FloatArray,
    basis: FloatArray,
    rate: FloatArray,
    work: FloatArray,
    out: dict[str, FloatArray],
    reactions: bool,
    validate: bool,
) -> bool:
    """Forces of one chunk into ``out``; True (nothing computed) if it needs the error path.

    The cheap checks err on the side of caution (a sum that overflowed, a
    margin at the thresholds); :func:`_raise_input_error` decides exactly.
    """
    mul, add, sub = np.multiply, np.add, np.subtract
    if validate and not -math.inf < float(state.min()) <= float(state.max()) < math.inf:
        return True  # a NaN or an infinity (NaN propagates through min and max)
    x, y, phi, dx, dy, dphi, ddx, ddy, ddphi = state
    np.cos(phi, out=trig_in[0])
    np.sin(phi, out=trig_in[1])
    cos_phi, sin_phi = trig_in[0], trig_in[1]
    rows = trig.shape[0]
    np.matmul(cr.trig_matrix[:rows], trig_in, out=trig)
    D, C, p, lambda_free, SD, RA_x, RA_y, ka, kb = trig[:_FORCE_TRIG_ROWS]
    inv, lx, ly, l1, u, vx, vy, v1, tx, ty, t1, t2, w2, dphi2, M2, Z = work

    if validate:
        np.abs(D, out=t1)
        if float(t1.min()) < _SINGULAR_SCREEN:
            return True
    np.divide(1.0, D, out=inv)
    # eq. (10): λ32_i = (n_i·G + l0/2 − q)/D → rows (x, y, l0/2 − q)/D
    mul(x, inv, out=lx)
    mul(y, inv, out=ly)
    mul(lambda_free, inv, out=l1)
    if validate and cr.stroke is not None:
        if _outside_stroke(cr, x, y, cos_phi, D, C, inv, t1, t2, out["f10"]):
            return True
    # eq. (14): λ̇32_i = (n_i·Ġ − φ̇·(C·λ32_i + p))/D
    mul(dphi, C, out=u)
    mul(u, lx, out=vx)
    sub(dx, vx, out=vx)
    mul(vx, inv, out=vx)
    mul(u, ly, out=vy)
    sub(dy, vy, out=vy)
    mul(vy, inv, out=vy)
    mul(u, l1, out=v1)
    mul(dphi, p, out=t1)
    add(v1, t1, out=v1)
    mul(v1, inv, out=v1)
    np.negative(v1, out=v1)
    # eq. (14): λ̇10_i = (Ġ × d_i + φ̇·ρ_i·d_i)/D, Ġ × d_i = (Rot(5π/6 − φ)·Ġ) × n_i
    mul(D, dx, out=tx)
    mul(C, dy, out=t1)
    sub(tx, t1, out=tx)
    mul(C, dx, out=ty)
    mul(D, dy, out=t1)
    add(ty, t1, out=ty)
    rate_x, rate_y, rate_1 = rate
    mul(dphi, lx, out=rate_x)
    sub(rate_x, ty, out=rate_x)
    mul(rate_x, inv, out=rate_x)
    mul(dphi, ly, out=rate_y)
    add(rate_y, tx, out=rate_y)
    mul(rate_y, inv, out=rate_y)
    sub(l1, cr.cx, out=t2)  # ρ·d = λ32 − l0/(2√3): its "1" row
    mul(dphi, t2, out=rate_1)
    mul(rate_1, inv, out=rate_1)
    # eq. (17): λ̈10_i = (G̈ × d_i + φ̈·ρ_i·d_i − (l0/2)·φ̇² + 2·φ̇·λ̇32_i)/D
    mul(D, ddx, out=tx)
    mul(C, ddy, out=t1)
    sub(tx, t1, out=tx)
    mul(C, ddx, out=ty)
    mul(D, ddy, out=t1)
    add(ty, t1, out=ty)
    mul(dphi, 2.0, out=dphi2)
    mul(dphi, dphi, out=w2)
    gam_x, gam_y, gam_1 = basis[_GAM_X], basis[_GAM_Y], basis[_GAM_1]
    mul(ddphi, lx, out=gam_x)
    mul(dphi2, vx, out=t1)
    add(gam_x, t1, out=gam_x)
    sub(gam_x, ty, out=gam_x)
    mul(gam_x, inv, out=gam_x)
    mul(ddphi, ly, out=gam_y)
    mul(dphi2, vy, out=t1)
    add(gam_y, t1, out=gam_y)
    add(gam_y, tx, out=gam_y)
    mul(gam_y, inv, out=gam_y)
    mul(ddphi, t2, out=gam_1)
    mul(dphi2, v1, out=t1)
    add(gam_1, t1, out=gam_1)
    mul(w2, cr.cy, out=t1)
    sub(gam_1, t1, out=gam_1)
    mul(gam_1, inv, out=gam_1)
    # eq. (22): platform wrench F3 = m3·(G̈ − g); T = d_A·F3 with d_A = (cos φ, sin φ)
    F3_x, F3_y = basis[_F3_X], basis[_F3_Y]
    sub(ddx, cr.gravity_x, out=F3_x)
    mul(F3_x, cr.platform_mass, out=F3_x)
    sub(ddy, cr.gravity_y, out=F3_y)
    mul(F3_y, cr.platform_mass, out=F3_y)
    T = t2
    mul(cos_phi, F3_x, out=T)
    mul(sin_phi, F3_y, out=t1)
    add(T, t1, out=T)
    # eq. (21): M2 = Σ_i M20_i + M30 + ρ_A × F3 (the platform carried to P_A in chain A)
    #   = (3(I2 + m2|c2|²) + I3)·φ̈ − 3·m2·ka·γ_1 + λ32_A·(d_A × F3) + (G − A3) × F3
    mul(cos_phi, F3_y, out=M2)
    mul(sin_phi, F3_x, out=t1)
    sub(M2, t1, out=M2)
    mul(lx, LEG_NORMAL[0, 0], out=t1)  # λ32_A = n_A·(lx, ly) + l1
    add(t1, l1, out=t1)
    mul(ly, LEG_NORMAL[0, 1], out=tx)
    add(t1, tx, out=t1)
    mul(M2, t1, out=M2)
    mul(RA_x, F3_y, out=t1)
    add(M2, t1, out=M2)
    mul(RA_y, F3_x, out=t1)
    sub(M2, t1, out=M2)
    mul(ka, gam_1, out=t1)
    mul(t1, 3.0 * cr.link_mass, out=t1)
    sub(M2, t1, out=M2)
    mul(ddphi, cr.rotary_inertia, out=t1)
    add(M2, t1, out=M2)
    # eqs. (15)-(16): Z = D·(M2 + ((2/3)·d_A·Σ d⊥_i(ρ_i·d_i) + l0/2)·T)/(S·D), where
    #   d_A·Σ d⊥_i(ρ_i·d_i) = (√3/2)·(λ32_C − λ32_B) = (√3/2)·((√3/2)·lx + (3/2)·ly)
    mul(lx, 0.5, out=Z)
    mul(ly, _H, out=t1)
    add(Z, t1, out=Z)
    add(Z, cr.cy, out=Z)
    mul(Z, T, out=Z)
    add(Z, M2, out=Z)
    np.divide(D, SD, out=t1)
    mul(Z, t1, out=Z)
    mul(D, T, out=basis[_DT])
    mul(C, T, out=basis[_CT])
    mul(D, Z, out=basis[_DZ])
    mul(C, Z, out=basis[_CZ])
    mul(ddphi, ka, out=basis[_EPS_KA])
    mul(w2, kb, out=basis[_W2_KB])
    mul(ddphi, kb, out=basis[_EPS_KB])
    mul(w2, ka, out=basis[_W2_KA])
    # eqs. (23)-(25) for the three legs at once
    f10, f21z = out["f10"], out["f21z"]
    np.matmul(basis[_F21Z_ROWS].T, cr.f21z_matrix, out=f21z)
    np.matmul(basis[_F21Y_ROWS].T, cr.f21y_matrix, out=out["f21y"])
    np.matmul(basis[_PISTON_ROWS].T, cr.piston_matrix, out=f10)
    add(f10, f21z, out=f10)
    p10 = out["p10"]
    np.matmul(rate.T, _LEGS, out=p10)  # λ̇10 of the three legs
    mul(p10, f10, out=p10)
    if reactions:
        _reactions(cr, basis, trig, ka, D, C, ddphi, w2, out)
    return False


def _reactions(
    cr: CompiledRobot,
    basis: FloatArray,
    trig: FloatArray,
    ka: FloatArray,
    D: FloatArray,
    C: FloatArray,
    ddphi: FloatArray,
    w2: FloatArray,
    out: dict[str, FloatArray],
) -> None:
    """n10, m10 (piston balance) and n32, m32 (link 2 balance) of one chunk."""
    for k, row in enumerate((_GAM_X, _GAM_Y, _GAM_1)):
        np.multiply(ka, basis[row], out=basis[_KA_GAM_X + k])
        np.multiply(D, basis[row], out=basis[_D_GAM_X + k])
    np.copyto(basis[_EPS], ddphi)
    np.copyto(basis[_W2], w2)
    np.copyto(basis[_GT_X_B], trig[_GT_X])
    np.copyto(basis[_GT_Y_B], trig[_GT_Y])
    all_basis = basis.T
    np.matmul(all_basis, cr.n10_matrix, out=out["n10"])
    np.matmul(all_basis, cr.m10_matrix, out=out["m10"])
    np.matmul(all_basis, cr.m32_matrix, out=out["m32"])
    n32 = out["n32"]
    np.matmul(all_basis, cr.n32_matrix, out=n32)
    # link 2 along d⊥_i: F21·d⊥_i = C·f21y − D·f21z
    n32 += C[:, None] * out["f21y"]
    n32 -= D[:, None] * out["f21z"]


def _outside_stroke(
    cr: CompiledRobot,
    x: FloatArray,
    y: FloatArray,
    cos_phi: FloatArray,
    D: FloatArray,
    C: FloatArray,
    inv: FloatArray,
    t1: FloatArray,
    t2: FloatArray,
    scratch: FloatArray,
) -> bool:
    """Whether some λ10 of the chunk may be outside the stroke (eq. 10), within a margin.

    ``λ10_i = (G × d_i − l0·cos φ + l0/2)/D − l0/√3`` with
    ``G × d_i = (Rot(5π/6 − φ)·G) × n_i``.
    """
    assert cr.stroke is not None
    lower, upper = cr.stroke
    coefficients = np.empty((3, x.shape[0]))
    row_x, row_y, row_1 = coefficients
    np.multiply(C, x, out=t1)  # −(Rot·G)_y = −(C·x + D·y)
    np.multiply(D, y, out=t2)
    np.add(t1, t2, out=row_x)
    np.multiply(row_x, inv, out=row_x)
    np.negative(row_x, out=row_x)
    np.multiply(D, x, out=t1)  # (Rot·G)_x = D·x − C·y
    np.multiply(C, y, out=t2)
    np.subtract(t1, t2, out=row_y)
    np.multiply(row_y, inv, out=row_y)
    np.multiply(cos_phi, -cr.l0, out=row_1)
    np.add(row_1, cr.cy, out=row_1)
    np.multiply(row_1, inv, out=row_1)
    np.subtract(row_1, 2.0 * cr.cx, out=row_1)
    np.matmul(coefficients.T, _LEGS, out=scratch)
    return bool(scratch.min() < lower + _STROKE_SCREEN or scratch.max() > upper - _STROKE_SCREEN)


def _raise_input_error(compiled: CompiledRobot, inputs: list[FloatArray], stop: int) -> None:
    """Raise the error the reference path raises for these inputs (chunks up to ``stop``).

    In the reference's order: non-finite values, singular poses (anywhere),
    then actuator strokes.  Returns if there is no error after all.
    """
    for name, array in zip(_INPUTS, inputs, strict=True):
        bad = ~np.isfinite(array)
        if bad.any():
            index, column = np.argwhere(bad)[0].tolist()
            raise TrajectoryError(
                f"{name}[{index}, {column}] is not finite ({float(array[index, column])!r})"
            )
    check_poses(inputs[0])  # SingularPoseError, as the reference
    _inverse_geometry(compiled.robot, inputs[0][:stop])  # UnreachablePoseError, as the reference


# -------------------------------------------------------------- single sample
#: One pose, velocity or acceleration: three numbers.
SampleInput = Sequence[float] | FloatArray


class SampleForces(NamedTuple):
    """Forces of one sample, each ``(A, B, C)``: eqs. (23), (24), (25) (N) and ``p10`` (W)."""

    f10: tuple[float, float, float]
    p10: tuple[float, float, float]
    f21y: tuple[float, float, float]
    f21z: tuple[float, float, float]


def sample_forces(
    compiled: CompiledRobot,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
) -> SampleForces:
    """Forces of one sample by the paper's method, with the :mod:`math` module.

    Validates its input (finite numbers, not singular, inside the stroke) and
    calls :func:`sample_forces_unchecked`.

    Parameters
    ----------
    compiled : CompiledRobot
        From :func:`compile_robot` (compile once, call many times).
    pose, velocity, acceleration : sequence of 3 floats
        ``(x, y, φ)``, ``(ẋ, ẏ, φ̇)``, ``(ẍ, ÿ, φ̈)`` (SI units, rad).

    Returns
    -------
    SampleForces
        ``f10``, ``p10``, ``f21y``, ``f21z`` of legs A, B, C (N, W).

    Raises
    ------
    TrajectoryError, SingularPoseError, UnreachablePoseError
        As :func:`paper_forces`.

    Examples
    --------
    >>> compiled = compile_robot(Robot())
    >>> forces = sample_forces(compiled, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    >>> [round(f, 4) for f in forces.f10]
    [31.8589, -8.4957, -23.3632]
    """
    if type(compiled) is not CompiledRobot:
        raise Prp3Error(
            f"compiled must come from compile_robot(robot), got {type(compiled).__name__}"
        )
    values: tuple[float, ...]
    try:
        x, y, phi = pose
        dx, dy, dphi = velocity
        ddx, ddy, ddphi = acceleration
        values = (
            float(x), float(y), float(phi),
            float(dx), float(dy), float(dphi),
            float(ddx), float(ddy), float(ddphi),
        )  # fmt: skip
    except (TypeError, ValueError):
        values = _sample_error(compiled, pose, velocity, acceleration)
    if not _plausible(compiled, values):
        _sample_error(compiled, pose, velocity, acceleration)
    f = sample_forces_unchecked(compiled, *values)
    return SampleForces(
        (f[0], f[1], f[2]), (f[3], f[4], f[5]), (f[6], f[7], f[8]), (f[9], f[10], f[11])
    )


def _plausible(compiled: CompiledRobot, values: tuple[float, ...]) -> bool:
    """Cheap screen of one sample: False if it may be non-finite, singular or out of stroke."""
    if not math.isfinite(sum(values)):  # NaN, ±inf (or a sum that overflowed)
        return False
    x, y, phi = values[0], values[1], values[2]
    if abs(math.sin(phi - math.pi / 3.0)) < SINGULARITY_THRESHOLD:  # as check_poses
        return False
    if compiled.stroke is None:
        return True
    lower, upper = compiled.stroke
    c, s = math.cos(phi), math.sin(phi)
    D = 0.5 * s - _H * c
    C = 0.5 * c + _H * s
    gx, gy = D * x - C * y, C * x + D * y  # Rot(5π/6 − φ)·G, see _outside_stroke
    base = (compiled.cy - compiled.l0 * c) / D - 2.0 * compiled.cx
    for nx, ny in _LEG_NORMALS:
        lambda10 = (gx * ny - gy * nx) / D + base
        if not lower + _STROKE_SCREEN <= lambda10 <= upper - _STROKE_SCREEN:
            return False
    return True


_LEG_NORMALS: tuple[tuple[float, float], ...] = tuple((nx, ny) for nx, ny in LEG_NORMAL.tolist())


def _sample_error(compiled: CompiledRobot, *values: SampleInput) -> tuple[float, ...]:
    """Raise what :func:`paper_forces` raises for one sample; its floats if nothing is wrong."""
    arrays = [_as_samples(name, value) for name, value in _named(*values)]
    for name, array in zip(_INPUTS, arrays, strict=True):
        if array.shape != (3,):
            raise TrajectoryError(f"{name} must be 3 numbers (shape (3,)), got shape {array.shape}")
    _raise_input_error(compiled, [array[None, :] for array in arrays], 1)
    return tuple(np.concatenate(arrays).tolist())


def _sample_table(compiled: CompiledRobot, inputs: list[FloatArray]) -> FloatArray:
    """Few samples: :func:`sample_forces_unchecked` in a loop (numpy's call overhead dominates).

    Returns ``f10, p10, f21y, f21z`` stacked, shape ``(4, N, 3)``.
    """
    rows = []
    for pose, velocity, acceleration in zip(*(array.tolist() for array in inputs), strict=True):
        values = (*pose, *velocity, *acceleration)
        if not _plausible(compiled, values):
            _raise_input_error(compiled, inputs, inputs[0].shape[0])
        rows.append(sample_forces_unchecked(compiled, *values))
    return np.array(rows).reshape(-1, 4, 3).transpose(1, 0, 2)


def sample_forces_unchecked(
    compiled: CompiledRobot,
    x: float,
    y: float,
    phi: float,
    dx: float,
    dy: float,
    dphi: float,
    ddx: float,
    ddy: float,
    ddphi: float,
) -> tuple[float, ...]:
    """Inner function of :func:`sample_forces`: NO validation, for a control loop.

    The caller guarantees finite floats and ``|sin(φ − π/3)| >= 1e-4``; a
    singular pose gives huge or infinite numbers or ZeroDivisionError, a pose
    outside the stroke is not noticed.

    Returns
    -------
    tuple of 12 floats
        ``f10_A, f10_B, f10_C`` (N), ``p10_A, p10_B, p10_C`` (W),
        ``f21y_A, f21y_B, f21y_C``, ``f21z_A, f21z_B, f21z_C`` (N).

    Examples
    --------
    >>> f = sample_forces_unchecked(compile_robot(Robot()), 0.0, 0.0, 0.0, 0, 0, 0, 0, 0, 0)
    >>> round(f[0], 4)
    31.8589
    """
    cr = compiled
    cx, cy, m1, m2 = cr.cx, cr.cy, cr.piston_mass, cr.link_mass
    c = math.cos(phi)
    s = math.sin(phi)
    D = 0.5 * s - 0.8660254037844386 * c  # sin(φ − π/3)
    C = 0.5 * c + 0.8660254037844386 * s  # cos(φ − π/3)
    inv = 1.0 / D
    q = cx * s + cy * c  # (p, q) = Rot(φ)·c
    p = cx * c - cy * s
    # eq. (10): λ32_i = lx·n_ix + ly·n_iy + l1
    lx = x * inv
    ly = y * inv
    l1 = (cy - q) * inv
    # eq. (14): λ̇32_i, same rows
    u = dphi * C
    vx = (dx - u * lx) * inv
    vy = (dy - u * ly) * inv
    v1 = -(u * l1 + dphi * p) * inv
    # eq. (14): λ̇10_i, same rows; Ġ × d_i = (Rot(5π/6 − φ)·Ġ) × n_i
    rx = (dphi * lx - C * dx - D * dy) * inv
    ry = (dphi * ly + D * dx - C * dy) * inv
    r1 = dphi * (l1 - cx) * inv
    hrx = 0.8660254037844386 * rx
    half_ry_1 = 0.5 * ry + r1
    # eq. (17): λ̈10_i, same rows; G̈ × d_i = (Rot(5π/6 − φ)·G̈) × n_i
    tx = D * ddx - C * ddy
    ty = C * ddx + D * ddy
    dphi2 = dphi + dphi
    w2 = dphi * dphi
    gx = (ddphi * lx + dphi2 * vx - ty) * inv
    gy = (ddphi * ly + dphi2 * vy + tx) * inv
    g1 = (ddphi * (l1 - cx) + dphi2 * v1 - cy * w2) * inv
    # legs: n_A = (−√3/2, 1/2), n_B = (0, −1), n_C = (√3/2, 1/2)
    hx = 0.8660254037844386 * gx
    half_gy_1 = 0.5 * gy + g1
    gam_A = half_gy_1 - hx
    gam_B = g1 - gy
    gam_C = half_gy_1 + hx
    # eq. (22): link-2 and platform wrenches
    ka = cr.link_com_x * D + cr.link_com_y * C
    kb = cr.link_com_x * C - cr.link_com_y * D
    F3x = cr.platform_mass * (ddx - cr.gravity_x)
    F3y = cr.platform_mass * (ddy - cr.gravity_y)
    T = c * F3x + s * F3y  # d_A·F3
    # eq. (21): Σ M2 with the platform carried to P_A along chain A
    lam_A = l1 + 0.5 * ly - 0.8660254037844386 * lx
    M2 = (
        cr.rotary_inertia * ddphi
        - 3.0 * m2 * ka * g1
        + lam_A * (c * F3y - s * F3x)
        + (0.5 * p - 0.8660254037844386 * q) * F3y
        - (0.8660254037844386 * p + 0.5 * q) * F3x
    )
    # eqs. (15)-(16): W_j = Z + κ_j·T, Z = D·(M2 + (...)·T)/(S·D)
    SD = 1.5 * cr.l0 - 3.0 * q - 0.8660254037844386 * cr.l0 * D
    Z = (M2 + (0.5 * lx + 0.8660254037844386 * ly + cy) * T) * D / SD
    DT = D * T
    CT = C * T
    DT3 = DT * 0.5773502691896258  # D·T/√3
    CT3 = CT * 0.5773502691896258
    ze = D * Z - m2 * (ddphi * ka + w2 * kb)
    yn = m2 * (ddphi * kb - w2 * ka) - C * Z
    ga, gb, gc = cr.link_gravity_axial
    na, nb, nc = cr.link_gravity_normal
    pa, pb, pc = cr.piston_gravity_axial
    # eq. (25)
    zA = m2 * gam_A - ga + ze + 0.5 * F3x + 0.8660254037844386 * F3y - CT
    zB = m2 * gam_B - gb + ze + DT3
    zC = m2 * gam_C - gc + ze - DT3
    # eq. (24)
    yA = yn - na + 0.5 * F3y - 0.8660254037844386 * F3x - DT
    yB = yn - nb - CT3
    yC = yn - nc + CT3
    # eq. (23)
    fA = zA + m1 * gam_A - pa
    fB = zB + m1 * gam_B - pb
    fC = zC + m1 * gam_C - pc
    return (
        fA,
        fB,
        fC,
        fA * (half_ry_1 - hrx),  # p10 = f10·λ̇10
        fB * (r1 - ry),
        fC * (half_ry_1 + hrx),
        yA,
        yB,
        yC,
        zA,
        zB,
        zC,
    )
