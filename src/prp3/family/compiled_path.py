"""The compiled engine's path of docs/family.md §5: each leg from its home pose through the samples.

The scalar form of :func:`prp3.family.mechanics.inverse_geometry` for the
kernel of :mod:`prp3.family.compiled`: the poses checked in range, then the
path from each leg's home pose through the samples in the sub-steps of
:func:`prp3.family.mechanics.follow` (``|Δφ| ≤ MAX_TURN``, ``|ΔG| ≤ MAX_MOVE``
robot lengths).  At every point the closed-form closure solutions of
:mod:`prp3.family.legs`, the one whose ``μ_leg`` has its home sign, R angles
unwrapped continuously from home (``numpy.unwrap``'s rule); ``μ_leg`` and
``μ_par`` checked at every point.  The joint values and both measures at the
samples are written to the kernel's outputs (the measures of the closed-form
``Ĵ``, equal to the chain's to round-off).  It never raises: the first refusal
is reported in ``status`` and ``info`` as the numpy engine would raise it.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from prp3.family.compiled_legs import (
    PAR_BOUND,
    PAR_COS,
    PAR_COSN,
    PAR_HOME,
    PAR_HOME_POSES,
    PAR_LENGTH,
    PAR_MAXPHI,
    PAR_MOVE,
    PAR_OFFSET,
    PAR_SCALE,
    PAR_SIGN_LEG,
    PAR_SIGN_PAR,
    PAR_SIN,
    PAR_SINGULAR,
    PAR_SINN,
    PAR_TOTAL,
    PAR_TURN,
    STATUS_OUT_OF_RANGE,
    STATUS_SINGULAR_LEG,
    STATUS_SINGULAR_PAR,
    STATUS_UNREACHABLE,
    closure_branch,
    det3,
    njit_compiled,
    parallel,
    scalar_transmitted_wrench,
    segment_steps,
    unwrap_step,
)

__all__: list[str] = []

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@njit_compiled
def follow_path(ints: IntArray, par: FloatArray, pose: FloatArray, q: FloatArray,
            mu_leg: FloatArray, mu_par: FloatArray, status: IntArray,
            info: FloatArray) -> None:  # fmt: skip
    """``q (n, 3, 3)``, ``mu_leg (n, 3)``, ``mu_par (n,)`` at the samples, or a refusal in ``status``.

    ``status[0]`` the code (``_OK`` untouched), ``status[1]`` the sample,
    ``status[2]`` the leg, ``status[3]`` 1 when the point is the sample itself;
    ``info`` the point and the measure.
    """
    n = pose.shape[0]
    # 1. poses in range (mechanics.check_poses)
    for k in range(n):
        if (abs(pose[k, 0]) > par[PAR_BOUND] or abs(pose[k, 1]) > par[PAR_BOUND]
                or abs(pose[k, 2]) > par[PAR_MAXPHI]):  # fmt: skip
            status[0], status[1] = STATUS_OUT_OF_RANGE, k
            return
    # 2. the path of §5 (mechanics.follow), the legs side by side from sample 0 on
    scale, singular = par[PAR_SCALE], par[PAR_SINGULAR]
    length, turn, move = par[PAR_LENGTH], par[PAR_TURN], par[PAR_MOVE]
    work = np.zeros(129)  # every small array of the path, in one allocation
    fr = work[0:33]
    cand = work[33:51].reshape((2, 3, 3))
    hat = cand[0]
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
    homes = par[PAR_HOME_POSES : PAR_HOME_POSES + 9].reshape((3, 3))
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
                steps_of[j] = segment_steps(homes[j, 0], homes[j, 1], homes[j, 2], pose[0, 0],
                                     pose[0, 1], pose[0, 2], length, turn, move)  # fmt: skip
        elif sample > 0:  # the same segment for the three legs
            steps_of[0] = segment_steps(pose[sample - 1, 0], pose[sample - 1, 1], pose[sample - 1, 2],
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
                cn, sn = par[PAR_COSN + j], par[PAR_SINN + j]
                gx = cn * point[0] - sn * point[1]
                gy = sn * point[0] + cn * point[1]
                sign = par[PAR_SIGN_LEG + j]
                closure_branch(ints, par, gx, gy, point[2], sign, scale, chosen, cand, fr)
                owner = max(sample, 0)
                finite = (math.isfinite(chosen[0]) and math.isfinite(chosen[1])
                          and math.isfinite(chosen[2]))  # fmt: skip
                if not finite and lost_at[j] < 0:
                    lost_at[j] = owner
                    lost_exact[j] = 1 if step == steps else 0
                    for i in range(3):
                        lost_pose[j, i] = point[i]
                mu = det3(hat)  # det Ĵ does not change when the leg is turned by σ_j
                if step == steps and sample >= 0:
                    mu_leg[sample, j] = mu
                if not (sign * mu >= singular) and bad_leg[j] < 0:
                    bad_leg[j] = owner
                    bad_leg_mu[j] = mu
                    for i in range(3):
                        bad_leg_pose[j, i] = point[i]
                # R angles continuous from home (numpy.unwrap along the path)
                for r in range(nrev - 1):
                    k = ints[6 + r]
                    previous = par[PAR_HOME + k] if sample == -1 else raw[j, k]
                    correction[j, k] += unwrap_step(previous, chosen[k])
                    raw[j, k] = chosen[k]
                    unwrapped[j, k] = chosen[k] + correction[j, k]
                if nrev > 0:
                    others = 0.0
                    for r in range(nrev - 1):
                        others += unwrapped[j, ints[6 + r]]
                    last = ints[6 + nrev - 1]
                    unwrapped[j, last] = point[2] - par[PAR_TOTAL] + par[PAR_OFFSET + j] - others
                if step == steps and sample >= 0:
                    for k in range(3):
                        q[sample, j, k] = unwrapped[j, k] if ints[k] == 0 else chosen[k]
                if sample >= 1 or (sample == 0 and step == steps):
                    scalar_transmitted_wrench(ints, hat, one)  # the shared path: turned by σ_j
                    cs, ss = par[PAR_COS + j], par[PAR_SIN + j]
                    wrench[j, 0] = cs * one[0] - ss * one[1]
                    wrench[j, 1] = ss * one[0] + cs * one[1]
                    wrench[j, 2] = one[2]
            if sample >= 1 or (sample == 0 and step == most):
                value = parallel(wrench, rows)
                mu_par[sample] = value  # the last step of a segment is its sample
                if not (par[PAR_SIGN_PAR] * value >= singular) and bad_par < 0:
                    bad_par = sample
                    bad_par_mu = value
                    for i in range(3):
                        bad_par_pose[i] = point[i]
    for j in range(3):  # the numpy engine's order: a lost leg first, then the earliest measure
        if lost_at[j] >= 0:
            status[0], status[1], status[2], status[3] = (
                STATUS_UNREACHABLE,
                lost_at[j],
                j,
                lost_exact[j],
            )
            info[0], info[1], info[2] = lost_pose[j, 0], lost_pose[j, 1], lost_pose[j, 2]
            return
    first = -1
    for j in range(3):
        if bad_leg[j] >= 0 and (first < 0 or bad_leg[j] < status[1]):
            first = j
            status[0], status[1], status[2] = STATUS_SINGULAR_LEG, bad_leg[j], j
            info[0], info[1], info[2], info[3] = (
                bad_leg_pose[j, 0], bad_leg_pose[j, 1], bad_leg_pose[j, 2], bad_leg_mu[j]
            )  # fmt: skip
    if bad_par >= 0 and (first < 0 or bad_par < status[1]):
        status[0], status[1], status[2] = STATUS_SINGULAR_PAR, bad_par, -1
        info[0], info[1], info[2], info[3] = (
            bad_par_pose[0], bad_par_pose[1], bad_par_pose[2], bad_par_mu
        )  # fmt: skip
