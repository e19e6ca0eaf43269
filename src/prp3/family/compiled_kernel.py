"""The family's sample kernel generated from :mod:`prp3.family.sample_mechanics` for numba (docs/family.md §7).

The mechanics of one sample is written once on :class:`~prp3.mechanics.ops.Ops`
(:func:`~prp3.family.sample_mechanics.leg_candidates`,
:func:`~prp3.family.sample_mechanics.sample_dynamics`); the generated C of
:mod:`prp3.family.codegen` is its trace with the robot's numbers folded in.
Here the same trace, with the robot's numbers as *inputs*
(:func:`constants`: the design, the inertias, the home signs), becomes the
Python source of a numba loop over the samples
(:mod:`prp3.engines.trace_numba` … :func:`prp3.engines.traced_numba.python_statements`):
one compiled function per *structure* (architecture × actuated joint) serves
every robot of it, cached on disk by numba.  Per sample, as the C:

1. per leg, the closure candidates in the fixed frame and the branch rule of
   docs/family.md §5 at one pose (the candidate whose ``s_L·μ_leg`` is
   largest, refused below ``1e-4``; none real: out of reach);
2. the dynamics on the chosen configurations: ``μ_par`` (refused below
   ``1e-4`` with its home sign), ``tau``, every joint wrench, and ``q̇``,
   ``q̈``, the powers, ``J`` and ``K = J⁻¹`` of each leg.

The codes are the C's: :data:`STATUS_OK`, :data:`STATUS_NOT_FINITE` (an input),
:data:`STATUS_SINGULAR`, :data:`STATUS_UNREACHABLE`, :data:`STATUS_OVERFLOW`
(an output not finite); on a refusal the sample's outputs are NaN.  The
kernel does not validate and does not follow a path (a motion crossing a
singularity between samples is not seen): it is the C's semantics, for
batches of independent samples.

>>> from prp3.family.model import FamilyRobot
>>> robot = FamilyRobot.default("3-RRR")
>>> status, out = kernel_batch(robot, np.array([[0.0, 0.0, 0.0]]), np.zeros((1, 3)),
...                            np.zeros((1, 3)))
>>> int(status[0]), out.shape
(0, (1, 145))
"""

from __future__ import annotations

import functools
import math
import types as module_types
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from prp3.engines.traced_numba import (
    MODULE_HEADER,
    generated_module,
    parallel_source,
    python_statements,
)
from prp3.family.chain import SIGMA, SINGULAR
from prp3.family.compiled_path import path_source
from prp3.family.model import FamilyRobot
from prp3.family.sample_mechanics import (
    Design,
    Inertia,
    chain_of,
    fixed_candidates,
    legs_of,
    sample_dynamics,
)
from prp3.mechanics.ops import Ops
from prp3.validation import LEGS

__all__ = [
    "OUTPUTS",
    "STATUS_NOT_FINITE",
    "STATUS_OK",
    "STATUS_OVERFLOW",
    "STATUS_SINGULAR",
    "STATUS_UNREACHABLE",
    "constants",
    "kernel_batch",
    "structure_module",
    "structure_source",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The C's return codes (:data:`prp3.apps.codegen.RETURN_CODES`).
STATUS_OK, STATUS_NOT_FINITE, STATUS_SINGULAR, STATUS_UNREACHABLE, STATUS_OVERFLOW = 0, 1, 2, 4, 5

_DESIGN, _INERTIA = 13, 19
#: The constants: design (13), inertia (19), ``s_L`` of legs A, B, C (3), ``s_par`` (1).
_CONSTANTS = _DESIGN + _INERTIA + 4
#: The outputs per sample, in order, and their sizes.
OUTPUTS = (("mu_leg", 3), ("mu_par", 1), ("tau", 3), ("joint", 27), ("dq", 9), ("ddq", 9),
           ("power", 3), ("jacobian", 27), ("jacobian_inverse", 27), ("legs", 36))  # fmt: skip
_WIDTH = sum(size for _, size in OUTPUTS)
#: Samples per block on every thread, and the smallest batch that uses the threads.
BLOCK, PARALLEL_MIN_SAMPLES = 512, 4096
_STATE = ("x", "y", "cphi", "sphi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")


def constants(robot: FamilyRobot) -> FloatArray:
    """The kernel's inputs of ``robot``: ``(36,)`` float64 (see :data:`_CONSTANTS`), read-only.

    Kept on the robot (it is immutable), as :func:`prp3.family.compiled_path.pack` keeps its own.
    """
    cached = robot.__dict__.get("_kernel_constants")
    if cached is not None:
        return cast(FloatArray, cached)
    home_leg, home_par = robot.home_measures
    signs = [math.copysign(1.0, v) for v in (*home_leg, home_par)]
    values = (*Design.of(robot).values(), *Inertia.of(robot).values(), *signs)
    out = np.array(values, dtype=np.float64)
    out.flags.writeable = False
    robot.__dict__["_kernel_constants"] = out
    return out


def _leg_stage(types: str, j: int, names: list[str]) -> tuple[list[str], list[str], list[str]]:
    """Leg ``j``'s candidates and branch rule: (prelude, body, the 13 chosen names)."""
    leg = LEGS[j]
    sigma = (math.cos(float(SIGMA[j])), math.sin(float(SIGMA[j])))

    def geometry(ops: Ops, *values: Any) -> list[Any]:
        design = Design.from_values(types, values[:_DESIGN])
        return fixed_candidates(ops, design, sigma, *values[_DESIGN:])

    arguments = (*names[:_DESIGN], "x", "y", "cphi", "sphi")
    code = python_statements(geometry, arguments, f"g{leg}", names)
    count = len(code.outputs) // 13
    sign = names[_DESIGN + _INERTIA + j]
    chosen = [f"s{leg}_{i}" for i in range(13)]
    ind = "        "
    body = [ind + line for line in code.body] + [f"{ind}best = -inf", f"{ind}chosen = -1"]
    for n in range(count):
        mu = code.outputs[13 * n + 12]
        body += [f"{ind}if {sign} * {mu} > best:", f"{ind}    best = {sign} * {mu}",
                 f"{ind}    chosen = {n}"]  # fmt: skip
    body += [f"{ind}if chosen < 0:", f"{ind}    status[k] = {STATUS_UNREACHABLE}",
             f"{ind}    out[k, :] = nan", f"{ind}    continue",
             f"{ind}if not best >= {SINGULAR!r}:", f"{ind}    status[k] = {STATUS_SINGULAR}",
             f"{ind}    out[k, :] = nan", f"{ind}    continue"]  # fmt: skip
    for n in range(count):
        head = "if chosen == 0:" if n == 0 and count > 1 else "else:" if n else ""
        inner = ind + ("    " if head else "")
        if head:
            body.append(ind + head)
        body += [f"{inner}{chosen[i]} = {code.outputs[13 * n + i]}" for i in range(13)]
    return ["    " + line for line in code.prelude], body, chosen


def _dynamics_stage(
    types: str, actuated: int, names: list[str], legs: list[str]
) -> tuple[list[str], list[str], list[str]]:
    """The dynamics on the chosen legs: (prelude, body, the outputs' expressions)."""

    def dynamics(ops: Ops, *values: Any) -> list[Any]:
        scale = values[_DESIGN - 1]
        inertia = Inertia.from_values(values[_DESIGN : _DESIGN + _INERTIA], actuated)
        state = values[_DESIGN + _INERTIA : _DESIGN + _INERTIA + 10]
        chosen = legs_of(values[_DESIGN + _INERTIA + 10 :])
        return sample_dynamics(ops, types, inertia, scale, state, chosen, extended=True)

    arguments = (*names[: _DESIGN + _INERTIA], *_STATE, *legs)
    code = python_statements(dynamics, arguments, "d", names)
    return ["    " + s for s in code.prelude], ["        " + s for s in code.body], code.outputs


def structure_source(types: str, actuated: int) -> str:
    """The module source of the kernel of the joints ``types`` (``"RRR"``…) actuated at ``actuated`` (1–3)."""
    names = [f"c{i}" for i in range(_CONSTANTS)]
    prelude = [f"    {name} = c[{i}]" for i, name in enumerate(names)]
    body = ["    for k in range(start, stop):"]
    inputs = ("x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")
    arrays = ("pose", "velocity", "acceleration")
    body += [f"        {v} = {arrays[i // 3]}[k, {i % 3}]" for i, v in enumerate(inputs)]
    finite = " and ".join(f"isfinite({v})" for v in inputs)
    body += [f"        if not ({finite}):", f"            status[k] = {STATUS_NOT_FINITE}",
             "            out[k, :] = nan", "            continue",
             "        cphi = cos(phi)", "        sphi = sin(phi)"]  # fmt: skip
    mu_leg, legs = [], []
    for j in range(3):
        first, stage, chosen = _leg_stage(types, j, names)
        prelude += first
        body += stage
        legs += [v for i, v in enumerate(chosen) if i < 12]
        mu_leg.append(chosen[12])
    first, stage, outputs = _dynamics_stage(types, actuated - 1, names, legs)
    prelude += first
    body += stage
    body += [f"        if not {names[-1]} * {outputs[0]} >= {SINGULAR!r}:",
             f"            status[k] = {STATUS_SINGULAR}", "            out[k, :] = nan",
             "            continue"]  # fmt: skip
    values = [*mu_leg, *outputs, *legs]
    body += [f"        out[k, {i}] = {v}" for i, v in enumerate(values)]
    body += ["        status[k] = 0", f"        for i in range({len(values)}):",
             "            if not isfinite(out[k, i]):",
             f"                status[k] = {STATUS_OVERFLOW}", "                out[k, :] = nan",
             "                break", "    return 0"]  # fmt: skip
    signature = "c, pose, velocity, acceleration, out, status"
    return (
        f"# prp3's family kernel of the joints {types}, actuated joint {actuated}: generated from\n"
        "# prp3.family.sample_mechanics by prp3.family.compiled_kernel. Do not edit.\n"
        + MODULE_HEADER + "\n\n"
        '@numba.njit(cache=True, error_model="numpy")\n'
        f"def run({signature}, start, stop):\n" + "\n".join(prelude + body) + "\n\n\n"
        + parallel_source("run_parallel", "run", signature.split(", "), BLOCK) + "\n\n"
        + "\n".join(samples_source(types, actuated)) + "\n\n\n"
        + parallel_source("samples_parallel", "samples",
                          ("c", "pose", "velocity", "acceleration", "buffer", "n"), BLOCK)
        + "\n\n" + path_source(types, actuated)
    )  # fmt: skip


@functools.cache
def structure_module(types: str, actuated: int) -> module_types.ModuleType:
    """The generated module of one structure (``run``, ``run_parallel``), loaded once per process."""
    return generated_module(structure_source(types, actuated), f"family_{types}_{actuated}")


def kernel_batch(
    robot: FamilyRobot,
    pose: FloatArray,
    velocity: FloatArray,
    acceleration: FloatArray,
    threads: bool | None = None,
) -> tuple[IntArray, FloatArray]:
    """``(status (N,), outputs (N, 145))`` at the samples (``(N, 3)`` each; not validated).

    ``threads``: the blocks on every thread (default: from
    :data:`PARALLEL_MIN_SAMPLES` samples on).  The outputs of a sample are
    :data:`OUTPUTS` side by side.
    """
    module = structure_module(robot.types, robot.actuated)
    n = pose.shape[0]
    out = np.empty((n, _WIDTH))
    status = np.empty(n, dtype=np.int64)
    parallel = n >= PARALLEL_MIN_SAMPLES if threads is None else threads
    run = module.run_parallel if parallel else module.run
    run(constants(robot), *(np.ascontiguousarray(v, dtype=np.float64) for v in
                            (pose, velocity, acceleration)), out, status, 0, n)  # fmt: skip
    return status, out


# ------------------------------------------------------------------ the compiled route's samples
#: Offsets (in units of the samples ``n``) of the compiled route's buffer
#: (:data:`prp3.family.compiled._GROUPS`): each output's first double is at ``offset·n``.
_AT = {"q": 0, "dq": 9, "ddq": 18, "moment": 27, "mu_leg": 36, "tau": 39, "power": 42,
       "force": 45, "mu_par": 63, "ja": 64, "fa": 73, "end": 82, "jo": 91, "fo": 109,
       "ax": 127, "jac": 145, "inv": 172}  # fmt: skip
#: Doubles per sample of each output (its stride in the buffer).
_SIZE = {"q": 9, "dq": 9, "ddq": 9, "moment": 9, "tau": 3, "power": 3, "force": 18, "ja": 9,
         "fa": 9, "end": 9, "jo": 18, "fo": 18, "ax": 18, "jac": 27, "inv": 27}  # fmt: skip
#: Bits of the samples' result: a kinematic (``q̇``, ``q̈``), a dynamic output not finite.
NOT_FINITE_KIN, NOT_FINITE_DYN = 1, 2


def _targets() -> list[str]:
    """Where each output of :func:`_path_dynamics` goes: ``(name, index within the sample)``."""
    frames = [("jo", 2), ("ja", 1), ("fo", 2), ("fa", 1), ("ax", 2)]
    out = []
    for j in range(3):
        for name, width in frames:
            out += [f"{name}:{j * 3 * width + i}" for i in range(3 * width)]
        out += [f"end:{3 * j + i}" for i in range(3)]
    out += [f"tau:{j}" for j in range(3)]
    for j in range(3):
        for c in range(3):
            out += [f"force:{6 * j + 2 * c}", f"force:{6 * j + 2 * c + 1}", f"moment:{3 * j + c}"]
    out += [f"dq:{i}" for i in range(9)] + [f"ddq:{i}" for i in range(9)]
    out += [f"power:{j}" for j in range(3)]
    out += [f"jac:{i}" for i in range(27)] + [f"inv:{i}" for i in range(27)]
    return out


def _path_dynamics(types: str, actuated: int) -> Any:
    """The traced function of the route's samples: ``q`` known, the frames and the dynamics."""

    def function(ops: Ops, *values: Any) -> list[Any]:
        design = Design.from_values(types, values[:_DESIGN])
        inertia = Inertia.from_values(values[_DESIGN : _DESIGN + _INERTIA], actuated)
        x, y, phi, *rest = values[_DESIGN + _INERTIA : _DESIGN + _INERTIA + 9]
        q = values[_DESIGN + _INERTIA + 9 :]
        frames, legs = [], []
        for j in range(3):
            values_j, origins, rotations = chain_of(
                ops, design, float(SIGMA[j]), q[3 * j : 3 * j + 3]
            )
            frames += values_j
            legs.append((origins, rotations))
        state = (x, y, ops.cos(phi), ops.sin(phi), *rest)
        out = sample_dynamics(ops, types, inertia, design.scale, state, legs, extended=True)
        return frames + out[1:]  # μ_par: the path's

    return function


def samples_source(types: str, actuated: int) -> list[str]:
    """Source of ``samples(c, pose, velocity, acceleration, buffer, n, start, stop)``: the route's samples."""
    names = [f"c{i}" for i in range(_DESIGN + _INERTIA)]
    inputs = ("x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")
    qs = [f"q{i}" for i in range(9)]
    code = python_statements(
        _path_dynamics(types, actuated - 1), (*names, *inputs, *qs), "d", names
    )
    arrays = ("pose", "velocity", "acceleration")
    lines = [f"    {name} = c[{i}]" for i, name in enumerate(names)]
    lines += [f"    at_{name} = {at} * n" for name, at in _AT.items()]
    lines += ["    " + s for s in code.prelude]
    lines += ["    result = 0", "    for k in range(start, stop):"]
    lines += [f"        {v} = {arrays[i // 3]}[k, {i % 3}]" for i, v in enumerate(inputs)]
    lines += [f"        q{i} = buffer[at_q + 9 * k + {i}]" for i in range(9)]
    lines += ["        " + s for s in code.body]
    kin, dyn = [], []
    for target, value in zip(_targets(), code.outputs, strict=True):
        name, index = target.split(":")
        lines.append(f"        buffer[at_{name} + {_SIZE[name]} * k + {index}] = {value}")
        if name in ("dq", "ddq"):
            kin.append(value)
        elif name in ("tau", "power", "force", "moment"):
            dyn.append(value)
    for bit, values in ((NOT_FINITE_KIN, kin), (NOT_FINITE_DYN, dyn)):
        test = " and ".join(f"isfinite({v})" for v in values)
        lines += [f"        if not ({test}):", f"            result |= {bit}"]
    lines.append("    return result")
    return ['@numba.njit(cache=True, error_model="numpy")',
            "def samples(c, pose, velocity, acceleration, buffer, n, start, stop):", *lines]  # fmt: skip
