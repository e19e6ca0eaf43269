"""The friction forces with their load-dependent ``μ`` terms: an implicit problem, solved per sample.

A friction force with a ``μ`` term depends on the magnitude of its joint's
reaction, which depends on the friction forces: :func:`solve_mu` solves the
9 magnitudes of the three legs by Newton's method on numpy arrays, with
continuation from ``μ = 0`` (:data:`MU_STEPS`), and tells the samples whose
branch does not reach :data:`NEAR_LOCK_MU` times the coefficients (*near a
lock*).  The stages it solves through are the kernel's own
(:func:`prp3.mechanics.wrenches.body_wrenches`,
:func:`prp3.mechanics.virtual_work.joint_forces`); :func:`prp3.mechanics.kernel.dynamics`
calls it.  Not compiled by numba: a robot with ``μ`` terms runs on numpy.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from prp3.mechanics.joint_motion import KernelKinematics
from prp3.mechanics.ops import NUMPY, Legs, Ops, Value
from prp3.mechanics.parameters import KernelParameters
from prp3.mechanics.virtual_work import joint_forces
from prp3.mechanics.wrenches import KernelFriction, body_wrenches
from prp3.model.element_base import rate_sign
from prp3.model.elements import FRICTIONS

__all__ = ["MU_MAX_ITERATIONS", "MU_STEPS", "NEAR_LOCK_MU", "solve_mu"]

FloatArray = np.ndarray[Any, np.dtype[np.float64]]
BoolArray = np.ndarray[Any, np.dtype[np.bool_]]

#: Steps of the continuation in ``μ`` of :func:`solve_mu` (fractions of the full ``μ``).
MU_STEPS: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0)
#: Newton iterations allowed per continuation step.
MU_MAX_ITERATIONS: int = 40
#: A sample is *near a lock* when the branch of :func:`solve_mu` reached continuously from
#: ``μ = 0`` does not extend to this multiple of the ``μ`` coefficients: friction 20 %
#: higher (well within the uncertainty of a friction coefficient) would lock it.  Every
#: sample with a second solution close by (the branch folds back before ``1.2·μ``) is one.
NEAR_LOCK_MU: float = 1.2


def _arr(value: Value) -> FloatArray:
    """``value`` (a float or an array) as a float array of at least one axis."""
    return np.atleast_1d(np.asarray(value, dtype=np.float64))


def _unit_friction_reactions(
    k: KernelParameters, kin: KernelKinematics, samples: int
) -> FloatArray:
    """``R`` ``(N, 12, 9)``: the reactions of unit friction forces.

    Column ``q`` holds ``(n10, F21y, F21z, n32)`` of the three legs (12 rows) when
    friction force ``q`` (fric10_A..C, fric21_A..C, fric32_A..C) is 1 and nothing
    else loads the robot (no inertia, no gravity, no actuation).
    """
    R = np.empty((samples, 12, 9))
    for q in range(9):
        unit = [0.0] * 9
        unit[q] = 1.0
        fr = KernelFriction(
            (unit[0], unit[1], unit[2]), (unit[3], unit[4], unit[5]), (unit[6], unit[7], unit[8])
        )
        w = body_wrenches(k, kin, 0.0, 0.0, 0.0, 0.0, friction=fr, inertia=False)
        _, fy, fz, rest = joint_forces(k, kin, w, True)
        assert rest is not None
        columns = [*rest[0], *fy, *fz, *rest[2]]
        for row, value in enumerate(columns):
            R[:, row, q] = _arr(value) if not isinstance(value, float) else value
    return R


def _mu_coefficients(
    k: KernelParameters, kin: KernelKinematics, dphi: Value, samples: int
) -> FloatArray:
    """The diagonal of ``C = diag(−μ·s(v))`` of the 9 friction forces, ``(N, 9)``."""
    mus = tuple(element.mu(k) for element in FRICTIONS)
    smooth = tuple(element.smoothing(k) for element in FRICTIONS)
    rates = tuple(element.rates(kin, dphi) for element in FRICTIONS)
    coefficient = np.empty((samples, 9))
    for a in range(3):
        for j in range(3):
            sv = _arr(rate_sign(NUMPY, _arr(rates[a][j]), smooth[a]))
            coefficient[:, 3 * a + j] = -float(mus[a]) * sv
    return coefficient


def solve_mu(
    ops: Ops,
    k: KernelParameters,
    kin: KernelKinematics,
    explicit: KernelFriction,
    reactions: tuple[Legs, Legs, Legs, Legs],
    dphi: Value,
) -> tuple[KernelFriction, Value, Value]:
    """The friction forces with their ``μ`` terms: the implicit problem solved per sample.

    The velocities are given, so ``s(v)`` is known and every friction force is
    ``fric = fric_e − μ·s(v)·N`` with ``fric_e`` its explicit (viscous and
    Coulomb) part and ``N`` the magnitude of its joint's reaction
    (``|n10|``, ``r_r·|F21|``, ``|n32|``).  The reactions are affine in the
    friction forces (the virtual work is linear in the body wrenches):
    ``r = r_e + R·(fric − fric_e)``, the 9 columns of ``R`` from
    :func:`joint_forces` of unit friction forces.  The 9 magnitudes ``u`` of
    the three legs solve ``u = g(r_e + R·C·u)``, ``C = diag(−μ·s)``,
    ``g = (|n10|, |F21|, |n32|)``: by Newton's method (the Jacobian
    ``I − g'·R·C`` exactly), from the solution without ``μ`` terms, the ``μ``
    raised in the steps :data:`MU_STEPS` (continuation: the branch reached
    continuously from ``μ = 0``), to round-off.  A sample whose Newton
    iteration does not converge, or whose Jacobian determinant changes sign
    on the way (a fold: the friction cone swallows the drive), has no such
    solution: ``-1`` iterations.

    Near a lock: from the solution, the continuation goes on to
    :data:`NEAR_LOCK_MU` times the ``μ`` coefficients (a discarded stage); a
    sample whose branch ends before (no convergence, a fold, a magnitude
    driven through zero) is *near a lock*: coefficients 20 % higher would lock
    it, and a second solution may lie close to the one reported (the branch
    folds back: two solutions merge at the lock).

    Returns
    -------
    (KernelFriction, iterations, near_lock)
        The friction forces, the Newton iterations of each sample (``-1``: it
        locks) and whether it is near a lock (floats and a bool for
        :data:`~prp3.mechanics.ops.MATH`, arrays for :data:`~prp3.mechanics.ops.NUMPY`).
    """
    single = ops.name == "math"
    arr = _arr
    n10, f21y, f21z, n32 = (np.stack([arr(v) for v in legs], axis=-1) for legs in reactions)
    samples = n10.shape[0]
    r0 = np.concatenate([n10, f21y, f21z, n32], axis=-1)  # (N, 12)
    R = _unit_friction_reactions(k, kin, samples)
    coefficient = _mu_coefficients(k, kin, dphi, samples)
    scale = np.abs(r0).max(axis=-1) + 1.0
    u = _magnitudes(r0)[0]
    iterations = np.zeros(samples)
    failed = np.zeros(samples, dtype=bool)
    with np.errstate(all="ignore"):
        for step in MU_STEPS:
            failed |= _newton_stage(r0, R * (step * coefficient)[:, None, :], u, scale, failed,
                                    iterations)  # fmt: skip
        # near a lock: the branch ends before NEAR_LOCK_MU·μ (its result is discarded)
        beyond = u.copy()
        B = R * (NEAR_LOCK_MU * coefficient)[:, None, :]
        near = ~failed & _newton_stage(r0, B, beyond, scale, failed.copy(), None)
    iterations[failed] = -1.0
    u[failed] = 0.0
    fric = coefficient * u  # the μ terms
    values: list[Value] = []
    explicit_all = (*explicit.fric10, *explicit.fric21, *explicit.fric32)
    for q in range(9):
        total = explicit_all[q] + (float(fric[0, q]) if single else fric[:, q])
        values.append(total)
    result = KernelFriction(
        (values[0], values[1], values[2]), (values[3], values[4], values[5]),
        (values[6], values[7], values[8]),
    )  # fmt: skip
    if single:
        return result, float(iterations[0]), bool(near[0])
    return result, iterations, near


def _newton_stage(
    r0: FloatArray,
    B: FloatArray,
    u: FloatArray,
    scale: FloatArray,
    skip: BoolArray,
    iterations: FloatArray | None,
) -> BoolArray:
    """One stage of the continuation of :func:`solve_mu`: Newton on ``u = g(r0 + B·u)``.

    Updates ``u`` (and ``iterations``) in place for the samples not in
    ``skip``; returns the samples that fail: no convergence to round-off, a
    Jacobian determinant ``det(I − g'·B)`` not positive at the solution (a
    fold), or magnitudes that are not finite or negative.
    """
    eye = np.eye(9)
    done = skip.copy()
    for _ in range(MU_MAX_ITERATIONS):
        r = r0 + np.einsum("nrq,nq->nr", B, u)
        g, dg = _magnitudes(r)
        residual = u - g
        size = np.abs(residual).max(axis=-1)
        done |= size <= 8e-16 * (np.abs(u).max(axis=-1) + scale)
        active = ~done
        if not active.any():
            break
        jac = eye - np.einsum("nur,nrq->nuq", dg[active], B[active])
        u[active] = u[active] - np.linalg.solve(jac, residual[active][..., None])[..., 0]
        if iterations is not None:
            iterations[active] += 1
    r = r0 + np.einsum("nrq,nq->nr", B, u)
    _, dg = _magnitudes(r)
    det = np.linalg.det(eye - np.einsum("nur,nrq->nuq", dg, B))
    converged = done & ~skip
    bad = ~converged | ~(det > 0.0) | ~np.isfinite(u).all(axis=-1) | (u < 0.0).any(axis=-1)
    return np.asarray(bad & ~skip)


def _magnitudes(r: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``g = (|n10|, |F21|, |n32|)`` of reactions ``r (N, 12)`` and its Jacobian ``(N, 9, 12)``."""
    n10, f21y, f21z, n32 = r[:, 0:3], r[:, 3:6], r[:, 6:9], r[:, 9:12]
    f21 = np.hypot(f21y, f21z)
    g = np.concatenate([np.abs(n10), f21, np.abs(n32)], axis=-1)
    dg = np.zeros((r.shape[0], 9, 12))
    safe = np.where(f21 > 0.0, f21, 1.0)
    for j in range(3):
        dg[:, j, j] = np.sign(n10[:, j])
        dg[:, 3 + j, 3 + j] = f21y[:, j] / safe[:, j]
        dg[:, 3 + j, 6 + j] = f21z[:, j] / safe[:, j]
        dg[:, 6 + j, 9 + j] = np.sign(n32[:, j])
    return g, dg
