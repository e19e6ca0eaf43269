"""A compiled engine for the family's inverse dynamics (numba), proposed as the fast route.

:func:`compiled_inverse_dynamics` computes the actuator efforts, every joint
wrench and the singularity measures of a family robot along a motion with the
straight-line code of :mod:`prp3.family.codegen` (the same traced operations
as ``prp3 export c``) in a loop over the samples that numba compiles to
machine code, once per robot (cached in the process).  It needs the ``numba``
extra.

Per sample, as the C: the closure solutions of each leg, the branch of
docs/family.md §5 (largest ``s_L·μ_leg``), then the dynamics.  The refusals are
those of the family route at the samples: a pose beyond the pose bounds, a
leg that cannot reach a pose, ``s_L·μ_leg,L < 1e-4`` or ``s_par·μ_par < 1e-4``
at a sample (the errors name the sample, its time, the pose and the leg).
What it does not do: follow the path from home in sub-steps, so a
singularity crossed *and re-crossed* between two samples is not seen (one
crossed once is refused at the next sample, whose measure has the wrong
sign); and it reports no joint values (``q``, ``q̇``, ``q̈``: the family route
gives them).

>>> from prp3.family.model import FamilyRobot
>>> source = engine_source(FamilyRobot.default("3-RRR"))
>>> source.splitlines()[0], "atan2" in source
('def family_loop(pose, velocity, acceleration, bound, limit, tau, joint, measures, info):', False)

Timings (``benchmarks/bench_family_export.py``): the batch and single-call
targets of the fast route are met by this engine once compiled; compiling
takes a few seconds per robot (numba's front end on the straight-line code),
so it serves long motions and repeated calls on one robot, not a sweep over
many designs (a version with the robot's constants as run-time inputs would
compile once per architecture and actuation).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._trace import _scalar_code, trace
from ..errors import Prp3Error, SingularPoseError, TrajectoryError, UnreachablePoseError
from ..kernel import Ops
from ..motion import Motion
from ..validation import LEGS, MAX_ORIENTATION, POSE_BOUND
from .chain import SIGMA, SINGULAR
from .codegen import _Design, _Inertia, _turn, leg_candidates, sample_dynamics
from .mechanics import check_inputs, check_poses, robot_length
from .model import FamilyRobot

__all__ = ["CompiledSolution", "compiled_inverse_dynamics", "engine_source"]

FloatArray = NDArray[np.float64]


def _renamed(lines: list[str], prefix: str) -> list[str]:
    return [re.sub(r"\bt(\d+)\b", rf"{prefix}\1", line) for line in lines]


def _stage(
    function: Callable[..., Any], arguments: tuple[str, ...], prefix: str, indent: str
) -> tuple[list[str], list[str]]:
    lines, outs = trace(function, len(arguments))
    body, outputs = _scalar_code(lines, outs, arguments, indent)
    return _renamed(body, prefix), _renamed(outputs, prefix)


def engine_source(robot: FamilyRobot) -> str:
    """Python source of the loop numba compiles (one robot's constants folded in).

    ``family_loop(pose, velocity, acceleration, bound, limit, tau, joint, measures, info)``:
    inputs ``(N, 3)`` each, the pose bounds (m, rad); outputs ``tau (N, 3)``,
    ``joint (N, 3, 3, 3)`` (``fx, fy, m`` of each leg and joint), ``measures (N, 4)``
    (``μ_leg`` of A, B, C, ``μ_par``).  It stops at the first refused sample and
    returns 1 with ``info = (sample, code, leg)``: code 1 an output not finite,
    2 singular (leg −1: ``μ_par``), 4 out of reach, 5 beyond the pose bounds;
    else 0.
    """
    design, inertia = _Design.of(robot), _Inertia.of(robot)
    home_leg, home_par = robot.home_measures
    ind = "        "

    def refuse(code: int, leg: int) -> list[str]:
        return [
            f"{ind}    info[0] = i",
            f"{ind}    info[1] = {code}",
            f"{ind}    info[2] = {leg}",
            f"{ind}    return 1",
        ]

    src = [
        "def family_loop(pose, velocity, acceleration, bound, limit, tau, joint, measures, info):",
        "    for i in range(pose.shape[0]):",
        *(f"{ind}{name} = {_ARRAYS[k // 3]}[i, {k % 3}]" for k, name in enumerate(_INPUTS)),
        f"{ind}if abs(x) > bound or abs(y) > bound or abs(phi) > limit:",
        *refuse(5, -2),
        f"{ind}cos_phi = cos(phi)",
        f"{ind}sin_phi = sin(phi)",
    ]
    for j, leg in enumerate(LEGS):
        cs, ss = math.cos(float(SIGMA[j])), math.sin(float(SIGMA[j]))

        def geometry(
            ops: Ops, x: Any, y: Any, c: Any, s: Any, cs: float = cs, ss: float = ss
        ) -> list[Any]:
            local = (cs * x + ss * y, cs * y - ss * x)
            values: list[Any] = []
            for origins, rotations, mu in leg_candidates(ops, design, local, (c, s)):
                for o in origins:
                    values += _turn((cs, ss), o)
                for r in rotations:
                    values += _turn((cs, ss), r)
                values.append(mu)
            return values

        body, outs = _stage(geometry, ("x", "y", "cos_phi", "sin_phi"), f"g{leg}_", ind)
        count = len(outs) // 13
        sign = repr(math.copysign(1.0, home_leg[j]))
        src += body
        src += [f"{ind}best = -inf", f"{ind}chosen = -1"]
        for n in range(count):
            src += [
                f"{ind}if {sign} * {outs[13 * n + 12]} > best:",
                f"{ind}    best = {sign} * {outs[13 * n + 12]}",
                f"{ind}    chosen = {n}",
            ]
        src += [f"{ind}if chosen < 0:", *refuse(4, j)]
        src += [f"{ind}if not best >= {SINGULAR!r}:", *refuse(2, j)]
        src += [f"{ind}measures[i, {j}] = {sign} * best"]
        for n in range(count):
            head = "if chosen == 0:" if n == 0 else "else:"
            if count > 1:
                src.append(f"{ind}{head}")
            pad = ind + ("    " if count > 1 else "")
            src += [f"{pad}s{leg}_{k} = {outs[13 * n + k]}" for k in range(12)]
    state = ("x", "y", "cos_phi", "sin_phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")
    legs = tuple(f"s{leg}_{k}" for leg in LEGS for k in range(12))

    def dynamics(ops: Ops, *values: Any) -> list[Any]:
        chains = []
        rest = values[10:]
        for j in range(3):
            v = rest[12 * j : 12 * j + 12]
            chains.append(
                ([(v[2 * k], v[2 * k + 1]) for k in range(3)],
                 [(v[6 + 2 * k], v[7 + 2 * k]) for k in range(3)])
            )  # fmt: skip
        return sample_dynamics(ops, design.types, inertia, design.scale, values[:10], chains)

    body, outs = _stage(dynamics, (*state, *legs), "d_", ind)
    src += body
    src += [
        f"{ind}measures[i, 3] = {outs[0]}",
        f"{ind}if not {math.copysign(1.0, home_par)!r} * {outs[0]} >= {SINGULAR!r}:",
        *refuse(2, -1),
        *(f"{ind}tau[i, {k}] = {outs[1 + k]}" for k in range(3)),
        *(f"{ind}joint[i, {k // 9}, {k // 3 % 3}, {k % 3}] = {outs[4 + k]}" for k in range(27)),
        f"{ind}if not isfinite({' + '.join(outs[1:])}):",
        *refuse(1, -2),
    ]
    src.append("    return 0")
    return "\n".join(src) + "\n"


_INPUTS = ("x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")
_ARRAYS = ("pose", "velocity", "acceleration")


#: The engines built in this process, by robot (equal robots share one).
_ENGINES: dict[FamilyRobot, tuple[Callable[..., None], float]] = {}
_LAST: list[Any] = [None, None]


def _engine(robot: FamilyRobot) -> tuple[Callable[..., None], float]:
    """The compiled loop of ``robot`` and its pose bound (m), built once per robot."""
    if robot is _LAST[0]:
        last: tuple[Callable[..., None], float] = _LAST[1]
        return last
    if robot not in _ENGINES:
        if len(_ENGINES) >= 32:
            _ENGINES.pop(next(iter(_ENGINES)))
        _ENGINES[robot] = (_build(robot), POSE_BOUND * robot_length(robot))
    _LAST[:] = [robot, _ENGINES[robot]]
    return _ENGINES[robot]


def _build(robot: FamilyRobot) -> Callable[..., None]:
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is a test dependency
        raise Prp3Error(
            'the compiled family engine needs numba, which is not installed: pip install "prp3[numba]"'
        ) from None
    namespace: dict[str, Any] = {"cos": math.cos, "sin": math.sin, "sqrt": math.sqrt,
                                 "inf": math.inf, "isfinite": math.isfinite}  # fmt: skip
    exec(compile(engine_source(robot), "<prp3 family engine>", "exec"), namespace)
    function: Callable[..., None] = numba.njit(error_model="numpy")(namespace["family_loop"])
    return function


@dataclass(frozen=True)
class CompiledSolution:
    """Actuator efforts, joint wrenches and measures of the compiled engine (batch ``(N,)`` or ``()``).

    Attributes
    ----------
    tau : ndarray, shape ``(..., 3)``
    force : ndarray, shape ``(..., 3, 3, 2)``
        ``(fx{k}, fy{k})`` of each leg and joint (N).
    moment : ndarray, shape ``(..., 3, 3)``
        ``m{k}`` about ``O_k`` (N·m).
    mu_leg : ndarray, shape ``(..., 3)``
    mu_par : ndarray, shape ``(...)``
    """

    tau: FloatArray
    force: FloatArray
    moment: FloatArray
    mu_leg: FloatArray
    mu_par: FloatArray


def _refuse(robot: FamilyRobot, info: NDArray[np.int64], pose: FloatArray, t: FloatArray) -> None:
    """Raise the error of the refused sample ``info = (sample, code, leg)``."""
    k, code, index = (int(v) for v in info)
    where = (float(pose[k, 0]), float(pose[k, 1]), float(pose[k, 2]))
    if code == 5:
        check_poses(robot, pose[k : k + 1], t[k : k + 1])  # raises, naming the bound
    if code == 1:
        raise TrajectoryError(
            "the joint forces overflow float64 (rates or accelerations out of range)",
            subject="motion",
            sample=k,
            time=float(t[k]),
        )
    leg = LEGS[index] if index >= 0 else None
    if code == 4:
        raise UnreachablePoseError(
            f"leg {leg} cannot reach the pose {where} (the {robot.architecture}'s closure "
            "has no real solution)",
            sample=k,
            time=float(t[k]),
            leg=leg,
            pose=where,
        )
    name = f"mu_leg of leg {leg}" if leg is not None else "mu_par"
    raise SingularPoseError(
        f"{name} is below {SINGULAR:g} with its sign at home at the pose {where}: a singular "
        "pose, or a singularity crossed since home",
        sample=k,
        time=float(t[k]),
        leg=leg,
        pose=where,
    )


def compiled_inverse_dynamics(robot: FamilyRobot, motion: Motion) -> CompiledSolution:
    """The family's inverse dynamics by the compiled engine (see the module notes).

    Parameters
    ----------
    robot : FamilyRobot
    motion : prp3.Motion
        Without a time-varying load (docs/family.md §9).

    Raises
    ------
    TrajectoryError
        A pose beyond the pose bounds (named).
    UnreachablePoseError, SingularPoseError
        At the first refused sample, naming it, its time, the pose and the leg.
    """
    robot, motion = check_inputs(robot, motion)
    engine, bound = _engine(robot)
    t = np.atleast_1d(motion.t)
    pose, velocity, acceleration = (
        np.ascontiguousarray(v.reshape(-1, 3))
        for v in (motion.pose, motion.velocity, motion.acceleration)
    )
    n = t.size
    tau = np.empty((n, 3))
    joint = np.empty((n, 3, 3, 3))
    measures = np.empty((n, 4))
    info = np.zeros(3, dtype=np.int64)
    if engine(pose, velocity, acceleration, bound, MAX_ORIENTATION, tau, joint, measures, info):
        _refuse(robot, info, pose, t)
    shape = motion.t.shape
    return CompiledSolution(
        tau=tau.reshape(*shape, 3),
        force=joint[..., :2].reshape(*shape, 3, 3, 2),
        moment=joint[..., 2].reshape(*shape, 3, 3),
        mu_leg=measures[:, :3].reshape(*shape, 3),
        mu_par=measures[:, 3].reshape(shape),
    )
