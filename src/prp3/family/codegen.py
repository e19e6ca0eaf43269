"""The family's inverse dynamics as C99 code (``prp3 export c`` of a family-form robot file).

:func:`family_c_inverse_dynamics` writes a C99 header and source computing,
for one robot of docs/family.md, the actuator efforts ``tau`` and every joint
wrench from the platform's pose, velocity and acceleration::

    int prp3_inverse_dynamics(const double pose[3], const double velocity[3],
                              const double acceleration[3],
                              double tau[3], double joint[27]);

``tau[L]`` is ``tau_L`` of legs A, B, C (N along ``+u_a`` or N·m about ``+z0``);
``joint[9·L + 3·(k − 1) + c]`` is ``fx{k}_L`` (``c = 0``), ``fy{k}_L`` (1) and
``m{k}_L`` (2) of docs/family.md §7.  The return codes are those of the 3-PRP's
C (:data:`prp3.apps.codegen.RETURN_CODES`): ``PRP3_OK`` (0: every output finite),
``PRP3_NOT_FINITE`` (1: an input is NaN or infinite), ``PRP3_SINGULAR`` (2:
``s_L·μ_leg,L < 1e-4`` for a leg or ``s_par·μ_par < 1e-4``, the refusals of
docs/family.md §6 at the pose, with the signs ``s`` of the home configuration),
``PRP3_UNREACHABLE`` (4: a leg's closure has no real solution) and
``PRP3_OVERFLOW`` (5: the inputs are finite but an output is not, one
``isfinite`` pass over the 30 outputs at the end); ``PRP3_OUTSIDE_STROKE`` (3) is
defined but never returned (a family robot has no stroke).  On a non-zero
return every output is NaN.  Only ``<math.h>``; strict C99.

How it is generated: the mechanics of :mod:`prp3.family.sample_mechanics` is
written once on scalars, in the vector form of the chain (each frame's
rotation as ``(cos, sin)``, so no angle is ever needed: ``cos φ`` and ``sin φ``
are the only trigonometry), and run on the tracer of :mod:`prp3.engines.trace`: every floating-point operation on
the inputs is recorded as one C statement, the robot's constants folded in.
Three traced stages per call:

1. per leg, in the leg's frame
   (:func:`~prp3.family.sample_mechanics.leg_candidates`): the closed-form
   closure solutions of :mod:`prp3.family.legs` (one for PRP, PPR, RPP; two for RRR, RPR, PRR,
   RRP), each as its frame rotations ``R_{F_k}`` and P values, the joint origins
   by the chain of docs/family.md §2, and ``μ_leg``;
2. the branch rule of docs/family.md §5, in C: the solution whose
   ``s_L·μ_leg`` is largest (the other has the opposite sign), refused below
   ``1e-4``;
3. the dynamics of :mod:`prp3.family.mechanics` on the chosen configurations
   (:func:`~prp3.family.sample_mechanics.sample_dynamics`):
   ``q̇ = J⁻¹·t``, ``q̈ = J⁻¹·(ṫ − J̇·q̇)``, the body wrenches, virtual work for
   ``tau``, every joint wrench, and ``μ_par``.

The pose bounds of the Python entry (``POSE_BOUND`` robot lengths,
``MAX_ORIENTATION``) and the path rule "no singularity crossed since home"
need the motion, not one sample: the C checks the signs only.

>>> from prp3.family.model import FamilyRobot
>>> code = family_c_inverse_dynamics(FamilyRobot.default("3-RRR"))
>>> "double tau[3], double joint[27]);" in code.header
True
>>> "M_PI" in code.source, code.source.count("#include"), code.source.count("atan2")
(False, 2, 0)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from prp3.apps.codegen import (
    C_NOT_FINITE,
    C_OK,
    C_OVERFLOW,
    C_SINGULAR,
    C_UNREACHABLE,
    FINITE_FUNCTION,
    HEADER_NAME,
    SOURCE_NAME,
    c_number,
    header_text,
    input_lines,
    signature,
    version,
)
from prp3.engines.trace import trace
from prp3.family.chain import SIGMA, SINGULAR
from prp3.family.model import FamilyRobot
from prp3.family.sample_mechanics import (
    Design,
    Inertia,
    fixed_candidates,
    leg_candidates,
    legs_of,
    sample_dynamics,
    turn,
)
from prp3.mechanics.ops import MATH, Ops
from prp3.validation import LEGS, check_instance

__all__ = [
    "C_UNREACHABLE",
    "FamilyCSource",
    "family_c_inverse_dynamics",
    "python_sample",
]


# ------------------------------------------------------------------ C text
@dataclass(frozen=True)
class FamilyCSource:
    """The generated C code of a family robot.

    Attributes
    ----------
    header, source : str
        Texts of ``prp3_inverse_dynamics.h`` and ``.c``.
    robot : FamilyRobot
    operations : int
        Floating-point operations of the straight-line code (every stage, both
        candidates of each leg).
    """

    header: str
    source: str
    robot: FamilyRobot
    operations: int


_C_BINARY = {"+", "-", "*", "/"}


def c_statements(
    function: Callable[..., Sequence[Any]],
    arguments: Sequence[str],
    prefix: str,
    indent: str,
) -> tuple[list[str], list[str], int]:
    """C statements of the traced ``function`` and the C text of each output."""
    lines, outputs = trace(function, len(arguments))

    def name(operand: int | float) -> str:
        if isinstance(operand, int):
            return arguments[-1 - operand] if operand < 0 else f"{prefix}{operand}"
        return c_number(float(operand))

    body = []
    for index, (operation, operands) in lines:
        a = [name(o) for o in operands]
        if operation in _C_BINARY:
            text = f"{a[0]} {operation} {a[1]}"
        elif operation == "neg":
            text = f"-{a[0]}"
        elif operation in ("cos", "sin", "sqrt"):
            text = f"{operation}({a[0]})"
        elif operation == "atan2":
            text = f"atan2({a[0]}, {a[1]})"
        else:  # pragma: no cover - the mechanics uses no other function
            raise AssertionError(operation)
        body.append(f"{indent}const double {prefix}{index} = {text};")
    return body, [name(o) for o in outputs], len(lines)


def family_c_inverse_dynamics(robot: FamilyRobot) -> FamilyCSource:
    """Generate the C99 header and source of the inverse dynamics of a family robot.

    Parameters
    ----------
    robot : FamilyRobot
        Its design, inertias, payload, load and gravity become constants of the source.

    Returns
    -------
    FamilyCSource

    Raises
    ------
    ParameterError
        If ``robot`` is not a :class:`FamilyRobot`.
    """
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    design = Design.of(robot)
    inertia = Inertia.of(robot)
    home_leg, home_par = robot.home_measures
    sign_par = math.copysign(1.0, home_par)
    ind = "    "
    body: list[str] = []
    operations = 0
    # stage 1 and 2: per leg, the candidates and the branch rule
    count = 0
    for j, leg in enumerate(LEGS):
        cs, ss = math.cos(float(SIGMA[j])), math.sin(float(SIGMA[j]))

        def geometry(
            ops: Ops, x: Any, y: Any, c: Any, s: Any, cs: float = cs, ss: float = ss
        ) -> list[Any]:
            return fixed_candidates(ops, design, (cs, ss), x, y, c, s)

        lines, outs, n = c_statements(geometry, ("x", "y", "cos_phi", "sin_phi"), f"g{leg}", ind)
        operations += n
        count = len(outs) // 13
        sign = math.copysign(1.0, home_leg[j])
        body.append(
            f"{ind}/* leg {leg}: the closure solutions (origins O_k, rotations of F_k, mu_leg) */"
        )
        body += lines
        body.append(f"{ind}{{")
        body.append(f"{ind}    double best = -HUGE_VAL;")
        body.append(f"{ind}    int chosen = -1;")
        for n_c in range(count):
            mu = outs[13 * n_c + 12]
            body.append(f"{ind}    if ({c_number(sign)} * {mu} > best) {{ /* NaN compares false */")
            body.append(f"{ind}        best = {c_number(sign)} * {mu};")
            body.append(f"{ind}        chosen = {n_c};")
            body.append(f"{ind}    }}")
        body.append(f"{ind}    if (chosen < 0) {{")
        body.append(f"{ind}        return prp3_refuse(tau, joint, PRP3_UNREACHABLE);")
        body.append(f"{ind}    }}")
        body.append(f"{ind}    if (!(best >= PRP3_SINGULARITY_THRESHOLD)) {{")
        body.append(f"{ind}        return prp3_refuse(tau, joint, PRP3_SINGULAR);")
        body.append(f"{ind}    }}")
        for n_c in range(count):
            test = "if" if n_c == 0 else "} else if" if n_c < count - 1 else "} else"
            condition = f" (chosen == {n_c})" if test != "} else" else ""
            if count == 1:
                body += [f"{ind}    {{"]
            else:
                body += [f"{ind}    {test}{condition} {{"]
            for i in range(12):
                body.append(f"{ind}        state_{leg}[{i}] = {outs[13 * n_c + i]};")
        body.append(f"{ind}    }}")
        body.append(f"{ind}}}")
    # stage 3: the dynamics on the chosen configurations
    state_names = ("x", "y", "cos_phi", "sin_phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")
    leg_names = tuple(f"state_{leg}[{i}]" for leg in LEGS for i in range(12))

    def dynamics(ops: Ops, *values: Any) -> list[Any]:
        state, legs = values[:10], legs_of(values[10:])
        return sample_dynamics(ops, design.types, inertia, design.scale, state, legs)

    lines, outs, n = c_statements(dynamics, (*state_names, *leg_names), "d", ind)
    operations += n
    body.append(
        f"{ind}/* the dynamics: rates, accelerations, body wrenches, virtual work, joints */"
    )
    body += lines
    body += [
        f"{ind}if (!({c_number(sign_par)} * {outs[0]} >= PRP3_SINGULARITY_THRESHOLD)) {{",
        f"{ind}    return prp3_refuse(tau, joint, PRP3_SINGULAR);",
        f"{ind}}}",
    ]
    body += [f"{ind}tau[{i}] = {outs[1 + i]};" for i in range(3)]
    body += [f"{ind}joint[{i}] = {outs[4 + i]};" for i in range(27)]
    body += [
        f"{ind}/* the inputs are finite: an output that is not has overflowed */",
        f"{ind}if (!(prp3_finite(tau, 3) && prp3_finite(joint, 27))) {{",
        f"{ind}    return prp3_refuse(tau, joint, PRP3_OVERFLOW);",
        f"{ind}}}",
    ]
    unpack, finite = input_lines()
    source_lines = [
        f"/* {SOURCE_NAME}: inverse dynamics of a {robot.architecture} planar parallel robot.",
        f" * Generated by prp3 {version()} (prp3 export c) from prp3's family mechanics",
        " * (docs/family.md) traced into straight-line code. Do not edit: regenerate.",
        " * Robot: " + _robot_line(robot) + " */",
        "#include <math.h>",
        f'#include "{HEADER_NAME}"',
        "",
        f"static const double PRP3_SINGULARITY_THRESHOLD = {c_number(SINGULAR)};",
        "",
        "static int prp3_refuse(double tau[3], double joint[27], int code)",
        "{",
        "    int i;",
        "    for (i = 0; i < 3; ++i) {",
        "        tau[i] = NAN;",
        "    }",
        "    for (i = 0; i < 27; ++i) {",
        "        joint[i] = NAN;",
        "    }",
        "    return code;",
        "}",
        "",
        *FINITE_FUNCTION,
        "",
        *signature("double tau[3], double joint[27]"),
        "{",
        *unpack,
        "    double state_A[12], state_B[12], state_C[12];",
        "    double cos_phi, sin_phi;",
        f"    if (!({finite})) {{",
        "        return prp3_refuse(tau, joint, PRP3_NOT_FINITE);",
        "    }",
        "    cos_phi = cos(phi);",
        "    sin_phi = sin(phi);",
        *body,
        "    return PRP3_OK;",
        "}",
    ]
    source = "\n".join(source_lines) + "\n"
    return FamilyCSource(header=_header(robot), source=source, robot=robot, operations=operations)


def _robot_line(robot: FamilyRobot) -> str:
    return (
        f"{robot.architecture}, actuated = {robot.actuated}, gravity = {list(robot.gravity)!r}, "
        f"link masses = {robot.link1.mass!r}, {robot.link2.mass!r}, "
        f"platform mass = {robot.platform.mass!r} kg"
    )


def _header(robot: FamilyRobot) -> str:
    kind = "N along +u_a" if robot.types[robot.actuated - 1] == "P" else "N m about +z0"
    lines = [
        f"/* {HEADER_NAME}: inverse dynamics of a {robot.architecture} planar parallel robot (C99).",
        f" * Generated by prp3 {version()} (prp3 export c). Robot: {_robot_line(robot)}",
        " *",
        " * prp3_inverse_dynamics(pose, velocity, acceleration, tau, joint)",
        " *   pose = (x, y, phi): mass centre G of the platform (m) and orientation (rad);",
        " *   velocity, acceleration: their first and second time derivatives (SI units).",
        f" *   tau[L]: effort of the actuator of joint {robot.actuated} of leg L = A, B, C ({kind});",
        " *   joint[9 L + 3 (k - 1) + c]: the wrench of the proximal on the distal body through",
        " *   joint k of leg L: c = 0, 1 its force fx, fy (N, fixed frame), c = 2 its moment about",
        " *   z0 taken about the joint origin O_k (N m) (docs/family.md section 7).",
        " * Returns one of the codes below: PRP3_OK (0) only when every output is finite.",
        " * On a non-zero return every output is NaN. Reentrant, no allocation, only",
        " * <math.h>. Do not compile with -ffast-math: it assumes no NaN and removes the checks.",
        " */",
    ]
    codes = {
        "PRP3_SINGULAR": "mu_leg of a leg or mu_par, with its sign at home, is below 1e-4:"
        " the pose is singular",
        "PRP3_OUTSIDE_STROKE": "never returned: a family robot has no stroke",
        "PRP3_UNREACHABLE": "a leg's closure has no real solution: it cannot reach the pose",
    }
    return header_text(lines, "double tau[3], double joint[27]", codes)


def python_sample(
    robot: FamilyRobot,
    pose: Sequence[float],
    velocity: Sequence[float],
    acceleration: Sequence[float],
) -> tuple[int, list[float]]:
    """The generated code's steps on Python floats: ``(code, [tau (3), joint (27)])``.

    The same mechanics as the C (the functions above with :data:`prp3.mechanics.ops.MATH`),
    for checks of the mechanics independent of a compiler.
    """
    design, inertia = Design.of(robot), Inertia.of(robot)
    inputs = [float(v) for v in (*pose, *velocity, *acceleration)]
    if not all(math.isfinite(v) for v in inputs):
        return C_NOT_FINITE, [math.nan] * 30
    x, y, phi = (float(v) for v in pose)
    c, s = math.cos(phi), math.sin(phi)
    home_leg, home_par = robot.home_measures
    legs = []
    ops = _SAFE
    for j in range(3):
        cs, ss = math.cos(float(SIGMA[j])), math.sin(float(SIGMA[j]))
        local = (cs * x + ss * y, cs * y - ss * x)
        best, chosen = -math.inf, None
        for origins, rotations, mu in leg_candidates(ops, design, local, (c, s)):
            value = math.copysign(1.0, home_leg[j]) * mu
            if value > best:
                best, chosen = value, (origins, rotations)
        if chosen is None:
            return C_UNREACHABLE, [math.nan] * 30
        if not best >= SINGULAR:
            return C_SINGULAR, [math.nan] * 30
        legs.append(
            ([turn((cs, ss), o) for o in chosen[0]], [turn((cs, ss), r) for r in chosen[1]])
        )
    state = (x, y, c, s, *(float(v) for v in velocity), *(float(v) for v in acceleration))
    out = sample_dynamics(ops, design.types, inertia, design.scale, state, legs)
    if not math.copysign(1.0, home_par) * out[0] >= SINGULAR:
        return C_SINGULAR, [math.nan] * 30
    values = [float(v) for v in out[1:]]
    if not all(math.isfinite(v) for v in values):
        return C_OVERFLOW, [math.nan] * 30
    return C_OK, values


def _safe_sqrt(value: float) -> float:
    return math.sqrt(value) if value >= 0.0 else math.nan


#: Plain floats, with C's ``sqrt`` of a negative number (NaN, not an exception).
_SAFE = Ops("math", MATH.cos, MATH.sin, _safe_sqrt, MATH.tanh, MATH.abs, MATH.sign, MATH.atan2)
