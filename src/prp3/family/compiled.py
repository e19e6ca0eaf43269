"""The family's fast route compiled by numba: one loop over the samples (docs/family.md §5–§7).

The same mechanics as :mod:`prp3.family.mechanics` (the ``"numpy"`` engine),
written per sample in scalar code that numba compiles to machine code
(``cache=True``: compiled once per machine, then loaded from ``__pycache__``);
the scalar pieces per leg are :mod:`prp3.family.compiled_legs`:

1. the path of §5 from each leg's home pose through the samples
   (:mod:`prp3.family.compiled_path`): the joint values ``q`` and the
   measures ``μ_leg``, ``μ_par`` at the samples, checked at every point;
2. here, at the samples: the chain frames, ``J``, ``K = J⁻¹``, ``q̇ = K·t``,
   ``q̈ = K·(ṫ − J̇·q̇)``;
3. the wrench each body needs, the actuator efforts by virtual work
   ``Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L`` and every joint force
   ``W_3 = K_Lᵀ·(τ_L·e_a − B_L)``, ``W_2 = N_2 + W_3``, ``W_1 = N_1 + W_2``.

The kernel never raises and never validates: it reports the first refusal
(pose out of range, unreachable, singular or crossed, results not finite) as
a status, and :func:`compiled_dynamics` raises from it exactly the error the
numpy engine raises (same class, message and fields).  The inputs are
checked once, at the public entry :func:`prp3.family.family_inverse_dynamics`.
Every output lies in one buffer allocated by numpy, the arrays of the same
size per sample side by side, so that the results are views taken by one
reshape per size.

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

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.family.chain import ChainFrames
from prp3.family.compiled_legs import (
    FRAME_AX,
    FRAME_END,
    FRAME_FA,
    FRAME_FCS,
    FRAME_FO,
    FRAME_JA,
    FRAME_JO,
    PAR_COS,
    PAR_GRAVITY,
    PAR_LINK1,
    PAR_LINK2,
    PAR_LOAD,
    PAR_PAYLOAD,
    PAR_PLATFORM,
    PAR_SIGMA,
    PAR_SIN,
    STATUS_NOT_FINITE_DYN,
    STATUS_NOT_FINITE_KIN,
    STATUS_OK,
    STATUS_OUT_OF_RANGE,
    STATUS_SINGULAR_LEG,
    STATUS_SINGULAR_PAR,
    STATUS_UNREACHABLE,
    body_rate,
    inv3,
    inv3j,
    njit_compiled,
    numba,
    pack,
    point_acceleration,
    point_velocity,
    scalar_leg_chain,
    scalar_leg_jacobian,
)
from prp3.family.compiled_path import follow_path
from prp3.family.mechanics import (
    FamilyKinematics,
    FamilySolution,
    on_the_way,
    pose_bound_error,
    singular_error,
    unreachable_error,
)
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.validation import LEGS, require_finite

try:  # the threads of the 3-PRP's numba engine: its block, threshold and threading layer
    from prp3.engines.numba import BLOCK, PARALLEL_MIN_SAMPLES, parallel_layer
except ImportError:  # pragma: no cover - the numba extra is not installed: one thread
    BLOCK, PARALLEL_MIN_SAMPLES = 1, 0

    def parallel_layer() -> str | None:
        return None


__all__ = ["compiled_dynamics"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

# ------------------------------------------------------------------ the buffer
#: The outputs of one sample by their number of doubles, in the buffer's order: first
#: those of the motion's batch shape (``()`` for one sample), ``q, dq, ddq, moment``
#: (9 each), ``mu_leg, tau, power`` (3), ``force`` (18), ``mu_par`` (1); then those of
#: shape ``(N, ...)`` always, the frames ``joint_angle, angle, end`` (9),
#: ``joint_origin, origin, axis`` (18) and ``jacobian, jacobian_inverse`` (27).
_GROUPS = ((9, 4), (3, 3), (18, 1), (1, 1), (9, 3), (18, 3), (27, 2))
_WIDTH = sum(size * count for size, count in _GROUPS)
#: After the outputs: the kernel's status (4, as doubles) and its ``info`` (4).
_TAIL = 8


@njit_compiled
def _samples(ints: IntArray, par: FloatArray, pose: FloatArray, velocity: FloatArray,
             acceleration: FloatArray, q: FloatArray, dq: FloatArray, ddq: FloatArray,
             jo: FloatArray, ja: FloatArray, fo: FloatArray, fa: FloatArray, ax: FloatArray,
             end: FloatArray, jac: FloatArray, inv: FloatArray, tau: FloatArray,
             power: FloatArray, force: FloatArray, moment: FloatArray, start: int,
             stop: int) -> int:  # fmt: skip
    """Steps 2 and 3 at the samples ``start:stop`` (``q`` given): the status ``STATUS_OK`` or not finite."""
    a = ints[4]
    gvx, gvy = par[PAR_GRAVITY], par[PAR_GRAVITY + 1]
    work = np.zeros(144)  # every small array, in one allocation
    fr = work[0:33]
    one = work[33:36]
    rows = work[36:45].reshape((3, 3))
    links = work[45:63].reshape((3, 2, 3))
    b = work[63:72].reshape((3, 3))
    rhs = work[72:75]
    matrix = work[75:84].reshape((3, 3))
    minv = work[84:93].reshape((3, 3))
    bias = work[93:102].reshape((3, 3))
    jm = work[102:111].reshape((3, 3))
    km = work[111:138].reshape((3, 3, 3))
    v = work[138:141]
    acc = work[141:144]
    kin_ok = True
    dyn_ok = True
    for k in range(start, stop):
        gx, gy, phi = pose[k, 0], pose[k, 1], pose[k, 2]
        vgx, vgy, omega = velocity[k, 0], velocity[k, 1], velocity[k, 2]
        agx, agy, alpha = acceleration[k, 0], acceleration[k, 1], acceleration[k, 2]
        for j in range(3):
            scalar_leg_chain(ints, par, par[PAR_COS + j], par[PAR_SIN + j], par[PAR_SIGMA + j], q[k, j, 0],
                   q[k, j, 1], q[k, j, 2], fr)  # fmt: skip
            for c in range(3):
                jo[k, j, c, 0] = fr[FRAME_JO + 2 * c]
                jo[k, j, c, 1] = fr[FRAME_JO + 2 * c + 1]
                ja[k, j, c] = fr[FRAME_JA + c]
                fo[k, j, c, 0] = fr[FRAME_FO + 2 * c]
                fo[k, j, c, 1] = fr[FRAME_FO + 2 * c + 1]
                fa[k, j, c] = fr[FRAME_FA + c]
                ax[k, j, c, 0] = fr[FRAME_AX + 2 * c]
                ax[k, j, c, 1] = fr[FRAME_AX + 2 * c + 1]
                end[k, j, c] = fr[FRAME_END + c]
            scalar_leg_jacobian(ints, fr, gx, gy, 1.0, jm)
            inv3j(jm, km, j)
            for i in range(3):
                v[i] = km[j, i, 0] * vgx + km[j, i, 1] * vgy + km[j, i, 2] * omega
            # J̇: R columns perp(Ġ − Ȯ_c), P columns ω_{J_c}·perp(u_c)
            for c in range(3):
                if ints[c] == 0:
                    ovx, ovy = point_velocity(
                        ints, fr, v, c + 1, fr[FRAME_FO + 2 * c], fr[FRAME_FO + 2 * c + 1]
                    )
                    bias[0, c] = -(vgy - ovy)
                    bias[1, c] = vgx - ovx
                else:
                    w = body_rate(ints, v, c)
                    bias[0, c] = w * -fr[FRAME_AX + 2 * c + 1]
                    bias[1, c] = w * fr[FRAME_AX + 2 * c]
            rhs[0] = agx - (bias[0, 0] * v[0] + bias[0, 1] * v[1] + bias[0, 2] * v[2])
            rhs[1] = agy - (bias[1, 0] * v[0] + bias[1, 1] * v[1] + bias[1, 2] * v[2])
            rhs[2] = alpha
            for i in range(3):
                acc[i] = km[j, i, 0] * rhs[0] + km[j, i, 1] * rhs[1] + km[j, i, 2] * rhs[2]
            for i in range(3):
                dq[k, j, i] = v[i]
                ddq[k, j, i] = acc[i]
                if not (math.isfinite(v[i]) and math.isfinite(acc[i])):
                    kin_ok = False
                for c in range(3):
                    jac[k, j, i, c] = jm[i, c]
                    inv[k, j, i, c] = km[j, i, c]
            # the wrench each link needs, about G
            for body in range(1, 3):
                at = PAR_LINK1 if body == 1 else PAR_LINK2
                mass, comx, comy, inertia = par[at], par[at + 1], par[at + 2], par[at + 3]
                ca, sa = fr[FRAME_FCS + 2 * (body - 1)], fr[FRAME_FCS + 2 * (body - 1) + 1]
                cx = fr[FRAME_FO + 2 * (body - 1)] + (ca * comx - sa * comy)
                cy = fr[FRAME_FO + 2 * (body - 1) + 1] + (sa * comx + ca * comy)
                lax, lay = point_acceleration(ints, fr, v, acc, body, cx, cy)
                fx = mass * (lax - gvx)
                fy = mass * (lay - gvy)
                links[j, body - 1, 0] = fx
                links[j, body - 1, 1] = fy
                links[j, body - 1, 2] = (inertia * body_rate(ints, acc, body)
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
        # the platform's need minus the load (with the payload)
        pm, pi_ = par[PAR_PLATFORM], par[PAR_PLATFORM + 1]
        lm, lcx, lcy, li = (
            par[PAR_PAYLOAD],
            par[PAR_PAYLOAD + 1],
            par[PAR_PAYLOAD + 2],
            par[PAR_PAYLOAD + 3],
        )
        cp, sp = math.cos(phi), math.sin(phi)
        rx = cp * lcx - sp * lcy
        ry = sp * lcx + cp * lcy
        plx = lm * (agx + alpha * -ry - (omega * omega) * rx - gvx)
        ply = lm * (agy + alpha * rx - (omega * omega) * ry - gvy)
        rhs[0] = pm * (agx - gvx) + plx - par[PAR_LOAD]
        rhs[1] = pm * (agy - gvy) + ply - par[PAR_LOAD + 1]
        rhs[2] = pi_ * alpha + li * alpha + (rx * ply - ry * plx) - par[PAR_LOAD + 2]
        # virtual work: Σ_L τ_L·K_L[a, :] = w_platform + Σ_L K_Lᵀ·B_L
        for i in range(3):
            for j in range(3):
                rhs[i] += km[j, 0, i] * b[j, 0] + km[j, 1, i] * b[j, 1] + km[j, 2, i] * b[j, 2]
                matrix[i, j] = km[j, a, i]
        inv3(matrix, minv)
        for j in range(3):
            t_j = minv[j, 0] * rhs[0] + minv[j, 1] * rhs[1] + minv[j, 2] * rhs[2]
            tau[k, j] = t_j
            power[k, j] = t_j * dq[k, j, a]
            if not (math.isfinite(t_j) and math.isfinite(power[k, j])):
                dyn_ok = False
            # every joint force: W_3 = K_Lᵀ·(τ_L·e_a − B_L), W_2 = N_2 + W_3, W_1 = N_1 + W_2
            e0 = (t_j if a == 0 else 0.0) - b[j, 0]
            e1 = (t_j if a == 1 else 0.0) - b[j, 1]
            e2 = (t_j if a == 2 else 0.0) - b[j, 2]
            for i in range(3):
                one[i] = km[j, 0, i] * e0 + km[j, 1, i] * e1 + km[j, 2, i] * e2
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
        return STATUS_NOT_FINITE_KIN
    if not dyn_ok:
        return STATUS_NOT_FINITE_DYN
    return STATUS_OK


def _blocks(ints: IntArray, par: FloatArray, pose: FloatArray, velocity: FloatArray,
            acceleration: FloatArray, q: FloatArray, dq: FloatArray, ddq: FloatArray,
            jo: FloatArray, ja: FloatArray, fo: FloatArray, fa: FloatArray, ax: FloatArray,
            end: FloatArray, jac: FloatArray, inv: FloatArray, tau: FloatArray,
            power: FloatArray, force: FloatArray, moment: FloatArray, start: int,
            stop: int) -> int:  # pragma: no cover  # fmt: skip
    """:func:`_samples` on ``start:stop`` block by block on every thread; the worst status.

    Each block of :data:`~prp3.engines.numba.BLOCK` samples is one call of
    :func:`_samples` (the same machine code for each sample as on one thread);
    a block with a kinematic result not finite outranks one with a dynamic one,
    as in one pass.
    """
    blocks = (stop - start + BLOCK - 1) // BLOCK
    status = np.zeros(blocks, dtype=np.int64)
    for b in _prange(blocks):
        first = start + b * BLOCK
        last = min(stop, first + BLOCK)
        status[b] = _samples(ints, par, pose, velocity, acceleration, q, dq, ddq, jo, ja, fo,
                             fa, ax, end, jac, inv, tau, power, force, moment, first, last)  # fmt: skip
    worst = STATUS_OK
    for b in range(blocks):
        if status[b] == STATUS_NOT_FINITE_KIN:
            return STATUS_NOT_FINITE_KIN
        if status[b] != STATUS_OK:
            worst = status[b]
    return worst


_prange = range if numba is None else numba.prange
_samples_parallel = (
    _blocks
    if numba is None
    else numba.njit(cache=True, error_model="numpy", parallel=True)(_blocks)
)


@njit_compiled
def family_kernel(ints: IntArray, par: FloatArray, pose: FloatArray, velocity: FloatArray,
            acceleration: FloatArray, buffer: FloatArray, threads: bool) -> int:  # fmt: skip
    """Every output at the samples into ``buffer`` (``n·_WIDTH + _TAIL``, from numpy); the status.

    ``threads``: steps 2 and 3 on every thread (:func:`_samples_parallel`),
    else on the calling thread; the path of step 1 is sequential.
    """
    n = pose.shape[0]
    at = 0
    ranked = buffer[at : at + 36 * n].reshape((4, n, 3, 3))
    at += 36 * n
    legs = buffer[at : at + 9 * n].reshape((3, n, 3))
    at += 9 * n
    force = buffer[at : at + 18 * n].reshape((n, 3, 3, 2))
    at += 18 * n
    mu_par = buffer[at : at + n]
    at += n
    angles = buffer[at : at + 27 * n].reshape((3, n, 3, 3))
    at += 27 * n
    points = buffer[at : at + 54 * n].reshape((3, n, 3, 3, 2))
    at += 54 * n
    block27 = buffer[at : at + 54 * n].reshape((2, n, 3, 3, 3))
    at += 54 * n
    q, dq, ddq, moment = ranked[0], ranked[1], ranked[2], ranked[3]
    mu_leg, tau, power = legs[0], legs[1], legs[2]
    ja, fa, end = angles[0], angles[1], angles[2]
    jo, fo, ax = points[0], points[1], points[2]
    status = np.zeros(4, dtype=np.int64)
    info = np.zeros(4)
    follow_path(ints, par, pose, q, mu_leg, mu_par, status, info)
    if status[0] == STATUS_OK:
        if threads:
            status[0] = _samples_parallel(ints, par, pose, velocity, acceleration, q, dq, ddq, jo,
                                          ja, fo, fa, ax, end, block27[0], block27[1], tau, power,
                                          force, moment, 0, n)  # fmt: skip
        else:
            status[0] = _samples(ints, par, pose, velocity, acceleration, q, dq, ddq, jo, ja, fo,
                                 fa, ax, end, block27[0], block27[1], tau, power, force, moment,
                                 0, n)  # fmt: skip
    for i in range(4):
        buffer[at + i] = status[i]
        buffer[at + 4 + i] = info[i]
    return int(status[0])


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
    pose = motion.pose.reshape(-1, 3)
    n = pose.shape[0]
    buffer = np.empty(_WIDTH * n + _TAIL)  # allocated by numpy: huge pages for a large N
    status = family_kernel(
        ints, par, _c(pose), _c(motion.velocity.reshape(-1, 3)),
        _c(motion.acceleration.reshape(-1, 3)), buffer, uses_threads(n),
    )  # fmt: skip
    # the views by integer indexing (the cheapest views numpy makes)
    ranked = buffer[: 36 * n].reshape(4, *shape, 3, 3)
    q, dq, ddq, moment = ranked[0], ranked[1], ranked[2], ranked[3]
    at = 36 * n
    legs = buffer[at : at + 9 * n].reshape(3, *shape, 3)
    mu_leg, tau, power = legs[0], legs[1], legs[2]
    at += 9 * n
    force = buffer[at : at + 18 * n].reshape(*shape, 3, 3, 2)
    at += 18 * n
    mu_par = buffer[at : at + n].reshape(shape)
    at += n
    angles = buffer[at : at + 27 * n].reshape(3, n, 3, 3)
    at += 27 * n
    points = buffer[at : at + 54 * n].reshape(3, n, 3, 3, 2)
    at += 54 * n
    jacobians = buffer[at : at + 54 * n].reshape(2, n, 3, 3, 3)
    at += 54 * n
    if status != STATUS_OK:
        t = motion.t.reshape(-1)
        batch = [a.reshape(n, *a.shape[len(shape) :]) for a in (dq, ddq, tau, power, force, moment)]
        _refuse(robot, buffer[at:], pose, t, *batch)
    end = angles[2]
    frames = ChainFrames(
        points[0], angles[0], points[1], angles[1], points[2], end[:, :, :2], end[:, :, 2]
    )
    kin = FamilyKinematics(
        robot, motion, q, dq, ddq, mu_leg, mu_par, frames, jacobians[0], jacobians[1]
    )  # fmt: skip
    return FamilySolution(kin, q, dq, ddq, tau, power, force, moment, "fast")


def uses_threads(samples: int) -> bool:
    """Whether a batch of ``samples`` runs its steps 2 and 3 on every thread.

    As the 3-PRP's batches (:func:`prp3.engines.numba.batch_loops`): from
    :data:`~prp3.engines.numba.PARALLEL_MIN_SAMPLES` samples when numba's
    threading layer is thread-safe (:func:`~prp3.engines.numba.parallel_layer`);
    a function of ``samples`` and of what the process offers, never of earlier
    calls; both give the same numbers.
    """
    return samples >= PARALLEL_MIN_SAMPLES and parallel_layer() is not None


def _c(values: FloatArray) -> FloatArray:
    """``values`` as the kernel's one compiled signature takes it: C-contiguous, read-only."""
    flags = values.flags
    if flags.c_contiguous and not flags.writeable:
        return values
    out = np.ascontiguousarray(values, dtype=np.float64)
    if out is values:
        out = out.copy()
    out.flags.writeable = False
    return out


def _refuse(
    robot: FamilyRobot,
    tail: FloatArray,
    pose: FloatArray,
    t: FloatArray,
    dq: FloatArray,
    ddq: FloatArray,
    tau: FloatArray,
    power: FloatArray,
    force: FloatArray,
    moment: FloatArray,
) -> None:
    """Raise the numpy engine's error for the kernel's status (docs/family.md §5, §6)."""
    code, k, leg, exact = (int(v) for v in tail[:4])
    info = tail[4:8]
    if code == STATUS_OUT_OF_RANGE:
        raise pose_bound_error(robot, pose, t, k)
    if code == STATUS_UNREACHABLE:
        note = "" if exact else on_the_way(t, k)
        raise unreachable_error(robot, leg, info, note, k, t)
    if code in (STATUS_SINGULAR_LEG, STATUS_SINGULAR_PAR):
        home_leg, home_par = robot.home_measures
        name, at_home = (
            (f"mu_leg of leg {LEGS[leg]}", home_leg[leg]) if code == STATUS_SINGULAR_LEG
            else ("mu_par", home_par)
        )  # fmt: skip
        raise singular_error(
            name, float(info[3]), info, pose, t, k,
            LEGS[leg] if code == STATUS_SINGULAR_LEG else None, at_home,
        )  # fmt: skip
    require_finite({"dq": dq, "ddq": ddq}, (t.size,), "motion", t)
    finite = {"tau": tau, "p": power, "force": force, "moment": moment}  # p = τ·q̇a: may overflow
    require_finite(finite, (t.size,), "motion", t)
