"""The compiled engine's path of docs/family.md §5, generated per structure from the one source on ``Ops``.

The scalar form of :func:`prp3.family.mechanics.inverse_geometry` for
:mod:`prp3.family.compiled`.  The poses are checked in range, then each leg
follows the path from its home pose through the samples in the sub-steps of
:func:`prp3.family.mechanics.follow` (a segment cut in
``max(1, ⌈max(|Δφ|/MAX_TURN, |ΔG|/(MAX_MOVE·length))⌉)`` equal steps, the
sample itself the last point; the three legs side by side from sample 0 on).
The branch rule, exactly as the numpy engine applies it at every point:

1. the candidates are the closed-form closure solutions of the leg
   (:func:`prp3.family.sample_mechanics.leg_solutions`, the pose turned by
   ``−σ_j``; one for PRP, PPR, RPP, two for RRR, RPR, PRR, RRP, in the order
   of :mod:`prp3.family.legs`), each with ``μ_leg = det Ĵ``;
2. the chosen one is the first candidate with the largest *finite*
   ``s_L·μ_leg`` (``s_L`` the sign of ``μ_leg`` at home); when none is finite
   the point's joint values are NaN;
3. a point whose chosen joint values are not all finite makes the leg
   unreachable there (the first such point); a point with
   ``not s_L·μ_leg ≥ SINGULAR`` (NaN included) is the leg's first singular
   point; ``μ_par`` of the three legs' transmitted wrenches is checked at every
   point from sample 0 on (``not s_par·μ_par ≥ SINGULAR``);
4. the R angles but the last are unwrapped along the path from the home joint
   values (``numpy.unwrap``'s rule, :func:`unwrap_step`); the last R angle closes
   ``Σ R angles = φ − Γ`` plus the whole turns the leg has at home;
5. the refusal reported: a lost leg first (legs A, B, C in turn), else the
   earliest sample of a singular ``μ_leg`` (the first leg on a tie) or of a
   singular ``μ_par`` (``μ_leg`` on a tie).

The per-point closed forms are not written here: the candidates' joint
values, ``μ_leg`` and transmitted wrenches are the trace of
:func:`prp3.family.sample_mechanics.path_candidates` (the one source the C and
the samples' kernel come from), with the design's 13 numbers as inputs, made
Python source by :func:`prp3.engines.traced_numba.python_statements`
(:func:`point_source`: ``leg_point``, its constants hoisted by
``point_constants``).  The loop itself is the plain Python of this module
(:func:`follow_path`, :func:`path` and their helpers), copied into the same
generated module (:func:`path_source`) so that the module's hash covers every
line numba compiles.  It never raises: the first refusal is reported in
``status`` and ``info`` as the numpy engine would raise it.

>>> from prp3.family.model import FamilyRobot
>>> ints, par = pack(FamilyRobot.default("3-RRR"))
>>> ints.tolist(), par.shape
([0, 0, 0, 3, 0, 1, 2], (26,))
"""

from __future__ import annotations

import inspect
import math
import re
from collections.abc import Callable
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from prp3.engines.traced_numba import Statements, python_statements
from prp3.family.chain import SIGMA, SINGULAR
from prp3.family.legs import LEG_GEOMETRY
from prp3.family.mechanics import MAX_MOVE, MAX_TURN, robot_length
from prp3.family.model import FamilyRobot
from prp3.family.sample_mechanics import DESIGN_VALUES, Design, path_candidates
from prp3.mechanics.ops import Ops
from prp3.pose_validation import MAX_ORIENTATION, POSE_BOUND
from prp3.validation import LEGS

numba: Any
try:
    import numba
except ImportError:  # pragma: no cover - the numba extra is not installed
    numba = None

__all__ = ["pack", "path_source", "point_source"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

# ------------------------------------------------------------------ parameters
# Offsets into the float parameters ``par`` (see :func:`pack`).
PAR_BOUND, PAR_MAXPHI, PAR_LENGTH, PAR_TURN, PAR_MOVE, PAR_SINGULAR = 0, 1, 2, 3, 4, 5
PAR_TOTAL, PAR_SIGN_PAR, PAR_SIGN_LEG, PAR_HOME, PAR_OFFSET, PAR_HOME_POSES = 6, 7, 8, 11, 14, 17
PAR_PARAMETERS = 26
#: Per candidate of :func:`~prp3.family.sample_mechanics.path_candidates`: q (3), μ_leg, wrench (3).
CANDIDATE = 7

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
    """The robot's parameters as the path reads them: ``(ints (7,), par (26,))``, read-only.

    ``ints``: the joint types (0 = R, 1 = P), the number of R joints and their
    indices; ``par``: the bounds of the poses, the sub-steps' limits, ``SINGULAR``,
    ``Γ``, the home signs, the home joint values, the whole turns of each leg's
    R angles at home and the legs' home poses, computed by the numpy engine's
    expressions and kept on the robot (it is immutable).
    """
    cached = robot.__dict__.get("_compiled_parameters")
    if cached is not None:
        return cast(tuple[IntArray, FloatArray], cached)
    types = robot.types
    geometry = LEG_GEOMETRY[types](robot.leg.placements)
    home_leg, home_par = robot.home_measures
    home = np.asarray(robot.leg.home)
    revolute = [k for k in range(3) if types[k] == "R"]
    ints = np.zeros(7, dtype=np.int64)
    ints[:3] = [0 if kind == "R" else 1 for kind in types]
    ints[3] = len(revolute)
    ints[4 : 4 + len(revolute)] = revolute
    par = np.zeros(PAR_PARAMETERS)
    length = robot_length(robot)
    par[PAR_BOUND], par[PAR_MAXPHI], par[PAR_LENGTH] = POSE_BOUND * length, MAX_ORIENTATION, length
    par[PAR_TURN], par[PAR_MOVE], par[PAR_SINGULAR] = MAX_TURN, MAX_MOVE, SINGULAR
    par[PAR_TOTAL] = geometry.total
    par[PAR_SIGN_PAR] = math.copysign(1.0, home_par)
    par[PAR_SIGN_LEG : PAR_SIGN_LEG + 3] = [math.copysign(1.0, v) for v in home_leg]
    par[PAR_HOME : PAR_HOME + 3] = home
    for j in range(3):  # the same expression as inverse_geometry's
        turns = home[revolute].sum() - (robot.home_poses[j, 2] - geometry.total)
        par[PAR_OFFSET + j] = 2.0 * math.pi * round(turns / (2.0 * math.pi))
    par[PAR_HOME_POSES : PAR_HOME_POSES + 9] = robot.home_poses.reshape(-1)
    ints.flags.writeable = False
    par.flags.writeable = False
    robot.__dict__["_compiled_parameters"] = (ints, par)
    return ints, par


# ------------------------------------------------------------------ the loop (copied as source)
# The functions below are compiled in the generated module only (path_source), where
# ``leg_point`` and ``point_constants`` are the structure's generated closed forms.


def det3(m: FloatArray) -> float:
    """:func:`~prp3.family.chain.det3` (cofactors of row 0)."""
    return float(
        m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
        - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
        + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0])
    )


def parallel(w: FloatArray, rows: FloatArray) -> float:
    """:func:`~prp3.family.chain.parallel_measure` of the wrenches ``w (3 legs, 3)``."""
    for j in range(3):
        norm = math.sqrt(w[j, 0] * w[j, 0] + w[j, 1] * w[j, 1] + w[j, 2] * w[j, 2])
        for i in range(3):
            rows[j, i] = w[j, i] / norm if norm > 0.0 else 0.0
    return det3(rows)


def mod_2pi(x: float) -> float:
    """``numpy.mod(x, 2π)`` (the result has the divisor's sign)."""
    period = 2.0 * math.pi
    m = np.fmod(x, period)
    if m != 0.0 and m < 0.0:
        m += period
    return float(m)


def unwrap_step(previous: float, value: float) -> float:
    """The correction ``numpy.unwrap`` adds for the step ``previous → value`` (multiple of 2π)."""
    dd = value - previous
    if abs(dd) < math.pi:
        return 0.0
    ddmod = mod_2pi(dd + math.pi) - math.pi
    if ddmod == -math.pi and dd > 0.0:
        ddmod = math.pi
    return ddmod - dd


def segment_steps(x0: float, y0: float, p0: float, x1: float, y1: float, p1: float,
           length: float, turn: float, move: float) -> int:  # fmt: skip
    """Sub-steps of a segment: ``max(1, ceil(max(|Δφ|/MAX_TURN, |ΔG|/(MAX_MOVE·length))))``."""
    dist = math.hypot(x1 - x0, y1 - y0) / (move * length)
    return max(1, math.ceil(max(abs(p1 - p0) / turn, dist)))


def poses_in_range(par: FloatArray, pose: FloatArray, status: IntArray) -> bool:
    """:func:`~prp3.family.mechanics.check_poses`: the first pose out of range in ``status``."""
    for k in range(pose.shape[0]):
        if (abs(pose[k, 0]) > par[PAR_BOUND] or abs(pose[k, 1]) > par[PAR_BOUND]
                or abs(pose[k, 2]) > par[PAR_MAXPHI]):  # fmt: skip
            status[0], status[1] = STATUS_OUT_OF_RANGE, k
            return False
    return True


def first_refusal(flags: IntArray, lost_pose: FloatArray, bad_leg_mu: FloatArray,
                  bad_leg_pose: FloatArray, bad_par: int, bad_par_mu: float,
                  bad_par_pose: FloatArray, status: IntArray, info: FloatArray) -> None:  # fmt: skip
    """The numpy engine's order: a lost leg first, then the earliest singular measure.

    ``flags``: the first lost point's sample of each leg (3), whether it is the
    sample itself (3), the first singular point's sample of each leg (3), −1 for none.
    """
    lost_at, lost_exact, bad_leg = flags[0:3], flags[3:6], flags[6:9]
    for j in range(3):
        if lost_at[j] >= 0:
            status[0], status[1], status[2], status[3] = (
                STATUS_UNREACHABLE, lost_at[j], j, lost_exact[j]
            )  # fmt: skip
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


def leg_point(pre: FloatArray, j: int, x: float, y: float, cphi: float, sphi: float,
              sign: float, out: FloatArray) -> None:  # fmt: skip
    """Leg ``j``'s chosen candidate at ``(x, y, φ)`` into ``out (7,)``: generated (:func:`point_source`)."""
    raise NotImplementedError("generated per structure by point_source")


def point_constants(c: FloatArray) -> FloatArray:
    """The constants ``leg_point`` reads, from the kernel's ``c``: generated (:func:`point_source`)."""
    raise NotImplementedError("generated per structure by point_source")


def follow_path(ints: IntArray, par: FloatArray, pre: FloatArray, pose: FloatArray,
                q: FloatArray, mu_leg: FloatArray, mu_par: FloatArray, status: IntArray,
                info: FloatArray) -> None:  # fmt: skip
    """``q (n, 3, 3)``, ``mu_leg (n, 3)``, ``mu_par (n,)`` at the samples, or a refusal in ``status``.

    ``status[0]`` the code (``STATUS_OK`` untouched), ``status[1]`` the sample,
    ``status[2]`` the leg, ``status[3]`` 1 when the point is the sample itself;
    ``info`` the point and the measure.  ``pre``: ``point_constants(c)``.
    """
    n = pose.shape[0]
    if not poses_in_range(par, pose, status):
        return
    singular, length, turn, move = par[PAR_SINGULAR], par[PAR_LENGTH], par[PAR_TURN], par[PAR_MOVE]
    work = np.zeros(79)  # every small array of the path, in one allocation
    found = work[0:7]  # leg_point's: q (3), μ_leg, the transmitted wrench (3)
    raw = work[7:16].reshape((3, 3))  # the previous point's raw R angles of each leg
    unwrapped = work[16:25].reshape((3, 3))
    correction = work[25:34].reshape((3, 3))
    wrench = work[34:43].reshape((3, 3))
    lost_pose, bad_leg_mu = work[43:52].reshape((3, 3)), work[52:55]
    bad_leg_pose, bad_par_pose = work[55:64].reshape((3, 3)), work[64:67]
    rows, point = work[67:76].reshape((3, 3)), work[76:79]
    homes = par[PAR_HOME_POSES : PAR_HOME_POSES + 9].reshape((3, 3))
    flags = np.full(12, -1)
    lost_at, lost_exact, bad_leg, steps_of = flags[0:3], flags[3:6], flags[6:9], flags[9:12]
    steps_of[:] = 1
    bad_par = -1
    bad_par_mu = 0.0
    nrev = ints[3]
    for sample in range(-1, n):  # -1: each leg's home pose itself
        if sample == 0:  # each leg from its home pose
            for j in range(3):
                steps_of[j] = segment_steps(homes[j, 0], homes[j, 1], homes[j, 2], pose[0, 0],
                                     pose[0, 1], pose[0, 2], length, turn, move)  # fmt: skip
        elif sample > 0:  # the same segment for the three legs
            steps_of[:] = segment_steps(pose[sample - 1, 0], pose[sample - 1, 1],
                                        pose[sample - 1, 2], pose[sample, 0], pose[sample, 1],
                                        pose[sample, 2], length, turn, move)  # fmt: skip
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
                sign = par[PAR_SIGN_LEG + j]
                leg_point(pre, j, point[0], point[1], math.cos(point[2]), math.sin(point[2]),
                          sign, found)  # fmt: skip
                owner = max(sample, 0)
                if not (math.isfinite(found[0]) and math.isfinite(found[1])
                        and math.isfinite(found[2])) and lost_at[j] < 0:  # fmt: skip
                    lost_at[j], lost_exact[j] = owner, 1 if step == steps else 0
                    lost_pose[j, :] = point
                mu = found[3]
                if step == steps and sample >= 0:
                    mu_leg[sample, j] = mu
                if not (sign * mu >= singular) and bad_leg[j] < 0:
                    bad_leg[j], bad_leg_mu[j] = owner, mu
                    bad_leg_pose[j, :] = point
                # R angles continuous from home (numpy.unwrap along the path)
                for r in range(nrev - 1):
                    k = ints[4 + r]
                    previous = par[PAR_HOME + k] if sample == -1 else raw[j, k]
                    correction[j, k] += unwrap_step(previous, found[k])
                    raw[j, k] = found[k]
                    unwrapped[j, k] = found[k] + correction[j, k]
                if nrev > 0:
                    others = 0.0
                    for r in range(nrev - 1):
                        others += unwrapped[j, ints[4 + r]]
                    unwrapped[j, ints[4 + nrev - 1]] = (
                        point[2] - par[PAR_TOTAL] + par[PAR_OFFSET + j] - others
                    )  # fmt: skip
                if step == steps and sample >= 0:
                    for k in range(3):
                        q[sample, j, k] = unwrapped[j, k] if ints[k] == 0 else found[k]
                if sample >= 1 or (sample == 0 and step == steps):
                    wrench[j, :] = found[4:7]
            if sample >= 1 or (sample == 0 and step == most):
                value = parallel(wrench, rows)
                mu_par[sample] = value  # the last step of a segment is its sample
                if not (par[PAR_SIGN_PAR] * value >= singular) and bad_par < 0:
                    bad_par, bad_par_mu = sample, value
                    bad_par_pose[:] = point
    first_refusal(flags, lost_pose, bad_leg_mu, bad_leg_pose, bad_par, bad_par_mu, bad_par_pose,
                  status, info)  # fmt: skip


def path(ints: IntArray, par: FloatArray, c: FloatArray, pose: FloatArray, buffer: FloatArray,
         width: int) -> int:  # fmt: skip
    """The path into the compiled route's ``buffer`` (``n·width + 8``): ``q``, ``μ_leg``, ``μ_par``; the status.

    :func:`follow_path` with ``q``, ``mu_leg``, ``mu_par`` the buffer's
    (:data:`prp3.family.compiled._GROUPS`) and its status and ``info`` after
    the ``n·width`` outputs; ``c`` the kernel's constants
    (:func:`prp3.family.compiled_kernel.constants`).
    """
    n = pose.shape[0]
    q = buffer[: 9 * n].reshape((n, 3, 3))
    mu_leg = buffer[36 * n : 39 * n].reshape((n, 3))
    mu_par = buffer[63 * n : 64 * n]
    status = np.zeros(4, dtype=np.int64)
    info = np.zeros(4)
    follow_path(ints, par, point_constants(c), pose, q, mu_leg, mu_par, status, info)
    at = width * n
    for i in range(4):
        buffer[at + i] = status[i]
        buffer[at + 4 + i] = info[i]
    return int(status[0])


# ------------------------------------------------------------------ the generated module's part
#: The loop's functions in the order they are written, and whether numba inlines them
#: (those that take arrays: a plain call counts the arrays' references).
_LOOP: tuple[tuple[Callable[..., Any], bool], ...] = (
    (det3, True), (parallel, True), (mod_2pi, False), (unwrap_step, False),
    (segment_steps, False), (poses_in_range, True), (first_refusal, True),
    (follow_path, False), (path, False),
)  # fmt: skip
#: The module constants the loop reads.
_NAMES = ("PAR_BOUND", "PAR_MAXPHI", "PAR_LENGTH", "PAR_TURN", "PAR_MOVE", "PAR_SINGULAR",
          "PAR_TOTAL", "PAR_SIGN_PAR", "PAR_SIGN_LEG", "PAR_HOME", "PAR_OFFSET", "PAR_HOME_POSES",
          "STATUS_OUT_OF_RANGE", "STATUS_UNREACHABLE", "STATUS_SINGULAR_LEG",
          "STATUS_SINGULAR_PAR")  # fmt: skip
_DECORATOR = '@numba.njit(cache=True, error_model="numpy"{})'
_NAME = re.compile(r"\b(c\d+|p[ABC]\d+)\b")


def _leg_code(types: str, actuated: int, j: int) -> Statements:
    """The trace of leg ``j``'s :func:`~prp3.family.sample_mechanics.path_candidates` (design inputs)."""
    sigma = (math.cos(float(SIGMA[j])), math.sin(float(SIGMA[j])))
    names = [f"c{i}" for i in range(DESIGN_VALUES)]

    def function(ops: Ops, *values: Any) -> list[Any]:
        design = Design.from_values(types, values[:DESIGN_VALUES])
        return path_candidates(ops, design, sigma, actuated - 1, *values[DESIGN_VALUES:])

    arguments = (*names, "x", "y", "cphi", "sphi")
    return python_statements(function, arguments, f"p{LEGS[j]}", names)


def _pick(outputs: list[str], ind: str) -> list[str]:
    """The branch rule on the candidates' ``outputs``: the first largest finite ``sign·μ`` into ``out``."""
    count = len(outputs) // CANDIDATE
    lines = [f"{ind}best = -inf", f"{ind}chosen = -1"]
    for n in range(count):
        lines += [f"{ind}value = sign * {outputs[CANDIDATE * n + 3]}",
                  f"{ind}if isfinite(value) and value > best:",
                  f"{ind}    best = value", f"{ind}    chosen = {n}"]  # fmt: skip
    for n in range(count):
        lines.append(f"{ind}{'if' if n == 0 else 'elif'} chosen == {n}:")
        lines += [f"{ind}    out[{i}] = {outputs[CANDIDATE * n + i]}" for i in range(CANDIDATE)]
    return [*lines, f"{ind}else:", f"{ind}    out[:] = nan"]


def point_source(types: str, actuated: int) -> list[str]:
    """Source of ``point_constants(c)`` and ``leg_point(pre, j, x, y, cphi, sphi, sign, out)``.

    ``leg_point`` writes the chosen candidate's 7 numbers (rule 2 of the module
    docstring; NaN when none is finite); what depends on the design alone is
    computed once per call by ``point_constants``.
    """
    codes = [_leg_code(types, actuated, j) for j in range(3)]
    hoisted: list[str] = [f"c{i}" for i in range(DESIGN_VALUES)]
    uses = []
    for code in codes:
        assigned = {line.split(" = ")[0] for line in code.body}
        used = sorted({m for text in (*code.body, *code.outputs) for m in _NAME.findall(text)}
                      - assigned, key=lambda name: (name[0], int(name.lstrip("cpABC"))))  # fmt: skip
        hoisted += [name for name in used if name not in hoisted]
        uses.append(used)
    constants = [_DECORATOR.format(""), "def point_constants(c):"]
    constants += [f"    c{i} = c[{i}]" for i in range(DESIGN_VALUES)]
    constants += ["    " + line for code in codes for line in code.prelude]
    constants += [f"    pre = np.empty({len(hoisted)})"]
    constants += [f"    pre[{i}] = {name}" for i, name in enumerate(hoisted)]
    point = [_DECORATOR.format(', inline="always"'),
             "def leg_point(pre, j, x, y, cphi, sphi, sign, out):"]  # fmt: skip
    for j, (code, used) in enumerate(zip(codes, uses, strict=True)):
        point.append(f"    {'if' if j == 0 else 'elif' if j == 1 else 'else'}"
                     + (f" j == {j}:" if j < 2 else ":"))  # fmt: skip
        point += [f"        {name} = pre[{hoisted.index(name)}]" for name in used]
        point += ["        " + line for line in code.body]
        point += _pick(code.outputs, "        ")
    return [*constants, "    return pre", "", "", *point]


def path_source(types: str, actuated: int) -> str:
    """The path's part of the structure's generated module: ``path(ints, par, c, pose, buffer, width)``.

    The constants the loop reads, the generated :func:`point_source`, then the
    source of each function of the loop (this module's own text) under numba's
    decorator.
    """
    lines = ["import math", "FloatArray = IntArray = None  # the annotations of the copied source"]
    lines += [f"{name} = {globals()[name]!r}" for name in _NAMES]
    lines += ["", "", *point_source(types, actuated)]
    for function, inline in _LOOP:
        lines += ["", "", _DECORATOR.format(', inline="always"' if inline else "")]
        lines.append(inspect.getsource(function).rstrip())
    return "\n".join(lines) + "\n"
