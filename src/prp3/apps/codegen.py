"""The inverse dynamics as C code for an embedded controller (``prp3 export c``).

:func:`c_inverse_dynamics` writes a C99 header and source that compute the
actuator forces ``f10`` and the joint forces ``f21y``, ``f21z`` of the three
legs from the platform's pose, velocity and acceleration — the paper's
closed form (eqs. 10, 14, 17, 19–25) for one robot, whose parameters become
constants of the source.  The code is *generated* from prp3's one symbolic
source of the equations: the same Python function that computes the forces
numerically is evaluated on :mod:`sympy` symbols, the expressions are
shared by common-subexpression elimination (``sympy.cse``) and printed by
sympy's C99 code printer.  Nothing in it is written by hand but the checks
of the input and the frame of the function::

    int prp3_inverse_dynamics(const double pose[3], const double velocity[3],
                              const double acceleration[3],
                              double f10[3], double f21y[3], double f21z[3]);

Return codes, one per kind of failure (:data:`RETURN_CODES`, each defined
and explained in the header): :data:`C_OK` (0: every output computed and
finite), :data:`C_NOT_FINITE` (1: an input is NaN or infinite),
:data:`C_SINGULAR` (2: ``|sin(φ − π/3)| < 1e-4``, as prp3 refuses),
:data:`C_OUTSIDE_STROKE` (3: some ``λ10`` outside ``limits.stroke``, or not
a number; only when the robot has one), :data:`C_UNREACHABLE` (4: a leg of a
family robot cannot reach the pose; never returned by the 3-PRP's code, whose
pistons reach every pose), :data:`C_OVERFLOW` (5: the inputs are finite but
an output is not — they are too large for double precision, where prp3
raises its overflow :class:`~prp3.errors.TrajectoryError`).  The last is one
``isfinite`` pass over the outputs at the end, so the code never returns
:data:`C_OK` with a non-finite output.  On a non-zero return every output is
NaN.  The code needs only ``<math.h>`` and compiles with ``cc -std=c99
-pedantic-errors -Wall -Wextra -Werror`` (no ``M_PI``: its own constants).

>>> from prp3.model.robot import Robot
>>> code = c_inverse_dynamics(Robot())
>>> "int prp3_inverse_dynamics(const double pose[3]" in code.header
True
>>> "M_PI" in code.source, code.source.count("#include")
(False, 2)
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass

from prp3.errors import ParameterError, Prp3Error
from prp3.mechanics import kernel
from prp3.mechanics.joint_motion import PI_3
from prp3.mechanics.ops import sympy_ops
from prp3.mechanics.parameters import INERTIAL_FIELDS, KernelParameters, kernel_parameters
from prp3.model.elements import ELEMENTS
from prp3.model.robot import Robot
from prp3.pose_validation import SINGULARITY_THRESHOLD

__all__ = [
    "C_NOT_FINITE",
    "C_OK",
    "C_OUTSIDE_STROKE",
    "C_OVERFLOW",
    "C_SINGULAR",
    "C_UNREACHABLE",
    "HEADER_NAME",
    "RETURN_CODES",
    "SOURCE_NAME",
    "CSource",
    "c_inverse_dynamics",
]

#: File names written by ``prp3 export c``.
HEADER_NAME: str = "prp3_inverse_dynamics.h"
SOURCE_NAME: str = "prp3_inverse_dynamics.c"

#: Return codes of ``prp3_inverse_dynamics`` (the 3-PRP's and the family's alike).
C_OK: int = 0
C_NOT_FINITE: int = 1
C_SINGULAR: int = 2
C_OUTSIDE_STROKE: int = 3
C_UNREACHABLE: int = 4
C_OVERFLOW: int = 5

#: Every return code: its C name, its value and what it means, the header's comment
#: of its ``#define`` (the 3-PRP's and the family's headers say which they never return).
RETURN_CODES: tuple[tuple[str, int, str], ...] = (
    ("PRP3_OK", C_OK, "every output computed and finite"),
    ("PRP3_NOT_FINITE", C_NOT_FINITE, "an input is NaN or infinite"),
    ("PRP3_SINGULAR", C_SINGULAR, "the pose is singular (a measure below 1e-4)"),
    ("PRP3_OUTSIDE_STROKE", C_OUTSIDE_STROKE, "an actuator displacement is outside the stroke"),
    ("PRP3_UNREACHABLE", C_UNREACHABLE, "a leg cannot reach the pose"),
    (
        "PRP3_OVERFLOW",
        C_OVERFLOW,
        "the inputs are finite, an output is not: too large for double precision",
    ),
)

#: The inputs, in the order of the C arrays.
_INPUTS = ("x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi")
_ARRAYS = ("pose", "velocity", "acceleration")


@dataclass(frozen=True)
class CSource:
    """The generated C code.

    Attributes
    ----------
    header : str
        Text of ``prp3_inverse_dynamics.h``.
    source : str
        Text of ``prp3_inverse_dynamics.c``.
    robot : Robot
        The robot whose parameters are the constants of the source.
    """

    header: str
    source: str
    robot: Robot


def _scalars(robot: Robot) -> tuple[str, ...]:
    """Constants of the closed form: the inertial fields of :class:`prp3.mechanics.parameters.KernelParameters`
    and the fields of the robot's elements that are not zero (a zero field adds no operation)."""
    parameters = kernel_parameters(robot)
    effects = tuple(
        name
        for element in robot.elements
        for name in element.fields
        if float(getattr(parameters, name)) != 0.0
    )
    return INERTIAL_FIELDS + effects


def _constant_values(robot: Robot) -> dict[str, float]:
    """The robot's constants by their C names (``prp3_l0``, ``prp3_link_mass``, ...)."""
    parameters = kernel_parameters(robot)
    return {f"prp3_{name}": float(getattr(parameters, name)) for name in _scalars(robot)}


@dataclass(frozen=True)
class _Template:
    """The generated code of every robot: constants are names, filled in per robot."""

    constants: tuple[str, ...]  # names of the constants the code uses, in order
    body: tuple[str, ...]  # "const double tK = ...;" lines of the shared subexpressions
    outputs: tuple[str, ...]  # "f10[0] = ...;" lines
    stroke_test: str  # C condition "some lambda10 outside [LOWER, UPPER]" ("" without)


@functools.lru_cache(maxsize=4)
def _template(with_stroke: bool, scalars: tuple[str, ...]) -> _Template:
    """Evaluate prp3's closed form on sympy symbols, share subexpressions, print C99.

    ``scalars`` are the fields of :class:`~prp3.mechanics.parameters.KernelParameters` that are
    symbols (constants of the C code); the others are the number 0.
    """
    import sympy
    from sympy.printing.c import C99CodePrinter

    parameters = KernelParameters(
        **{name: sympy.Symbol(f"prp3_{name}", real=True) for name in scalars}
    )
    inputs = tuple(sympy.Symbol(name, real=True) for name in _INPUTS)
    # the one kernel, evaluated on sympy symbols
    solution = kernel.solve(sympy_ops(), parameters, *inputs, reactions=False)
    outputs = [*solution.f10, *solution.f21y, *solution.f21z]
    checks = list(solution.lambda10) if with_stroke else []
    # cos(φ − π/3) and sin(φ − π/3) once, before the singularity check that uses the sine
    psi = inputs[2] - PI_3
    trig = {sympy.cos(psi): sympy.Symbol("cos_psi"), sympy.sin(psi): sympy.Symbol("sin_psi")}
    outputs = [expr.xreplace(trig) for expr in outputs]
    checks = [expr.xreplace(trig) for expr in checks]
    replacements, reduced = sympy.cse(outputs + checks, symbols=sympy.numbered_symbols("t"))
    printer = C99CodePrinter()
    body = tuple(
        f"const double {symbol} = {printer.doprint(expr)};" for symbol, expr in replacements
    )
    used = {
        str(symbol)
        for expr in [*(expr for _, expr in replacements), *reduced]
        for symbol in expr.free_symbols
    }
    names = [f"prp3_{name}" for name in scalars]
    lines = tuple(
        f"{name}[{leg}] = {printer.doprint(reduced[3 * k + leg])};"
        for k, name in enumerate(("f10", "f21y", "f21z"))
        for leg in range(3)
    )
    # negated, so that a displacement that is not a number (an overflow) is outside too
    test = " ||\n        ".join(
        f"!((lambda10_{leg} = {printer.doprint(reduced[9 + j])}) >= PRP3_STROKE_LOWER"
        f" && lambda10_{leg} <= PRP3_STROKE_UPPER)"
        for j, leg in enumerate("ABC")
    ) if with_stroke else ""  # fmt: skip
    return _Template(
        constants=tuple(name for name in names if name in used),
        body=body,
        outputs=lines,
        stroke_test=test,
    )


def c_number(value: float) -> str:
    """A double constant as C text that reads back exactly (``repr``, always with a point)."""
    text = repr(float(value))
    if not math.isfinite(value):
        raise ParameterError(f"robot: a constant of the C code is not finite: {value!r}")
    return text if any(ch in text for ch in ".en") else text + ".0"


def c_inverse_dynamics(robot: Robot) -> CSource:
    """Generate the C99 header and source of the inverse dynamics of ``robot``.

    Parameters
    ----------
    robot : Robot
        Its ``l0``, gravity, masses, inertias and centres of mass, and the
        parameters of its elements that the C code supports
        (:attr:`prp3.model.element_base.Element.generated_c`: the payload, the
        actuators' spring), become constants of the source;
        ``limits.stroke`` (when set) the stroke check.

    Returns
    -------
    CSource

    Raises
    ------
    ParameterError
        If ``robot`` is not a :class:`~prp3.model.robot.Robot`, or has an element
        the C code does not support (named: ``[load]``, ``[friction.actuator]``...).
    """
    if not isinstance(robot, Robot):
        raise ParameterError(f"robot must be a prp3.Robot, got {type(robot).__name__}")
    refused = [element.name for element in robot.elements if not element.generated_c]
    if refused:
        raise ParameterError(
            "robot: the generated C code covers the inertial model and the elements "
            + ", ".join(e.name for e in ELEMENTS if e.generated_c)
            + f", not [{refused[0]}]: remove it from the robot to export C"
        )
    try:
        import sympy
        from sympy.printing.c import C99CodePrinter
    except ImportError:
        raise Prp3Error(
            'generating C code needs sympy, which is not installed: pip install "prp3[codegen]"'
        ) from None
    del sympy, C99CodePrinter  # imported above only to fail early without sympy
    stroke = robot.limits.stroke
    template = _template(stroke is not None, _scalars(robot))
    constants, stroke_lines = _constant_lines(robot, template)
    source_lines = [
        *_preamble_lines(robot, constants),
        *_function_lines(template, stroke_lines),
    ]
    source = "\n".join(source_lines) + "\n"
    if re.search(r"\bM_\w+", source):  # e.g. M_PI, M_SQRT2: POSIX, not C99
        raise AssertionError("the C printer used a non-C99 constant")  # pragma: no cover
    return CSource(header=_header(robot), source=source, robot=robot)


def _constant_lines(robot: Robot, template: _Template) -> tuple[list[str], list[str]]:
    """The C constants of ``robot``'s parameters, and the lines of its stroke check.

    Returns
    -------
    constants : list of str
        One ``static const double`` line per constant of ``template`` (and the
        stroke's bounds when ``robot.limits.stroke`` is set).
    stroke_lines : list of str
        The check of the actuator displacements ``lambda10`` against the stroke
        (empty without a stroke).
    """
    stroke = robot.limits.stroke
    values = _constant_values(robot)
    constants = [
        f"static const double {name} = {c_number(values[name])};" for name in template.constants
    ]
    stroke_lines: list[str] = []
    if stroke is not None:
        lower, upper = stroke
        constants += [
            f"static const double PRP3_STROKE_LOWER = {c_number(lower)};",
            f"static const double PRP3_STROKE_UPPER = {c_number(upper)};",
        ]
        stroke_lines = [
            "double lambda10_A, lambda10_B, lambda10_C;",
            f"if ({template.stroke_test}) {{",
            "    return prp3_refuse(f10, f21y, f21z, PRP3_OUTSIDE_STROKE);",
            "}",
        ]
    return constants, stroke_lines


def _preamble_lines(robot: Robot, constants: list[str]) -> list[str]:
    """The source's lines before the inverse dynamics: comment, includes, constants, helpers.

    The helpers are ``prp3_refuse`` (NaN outputs and a return code) and
    :data:`FINITE_FUNCTION`.
    """
    return [
        f"/* {SOURCE_NAME}: inverse dynamics of the 3-PRP planar parallel robot.",
        f" * Generated by prp3 {version()} (prp3 export c) from prp3's closed form",
        " * (Staicu & Chablat, eqs. 10, 14, 17, 19-25) with sympy's cse and C99 printer.",
        " * Do not edit: regenerate. Robot: " + _robot_line(robot) + " */",
        "#include <math.h>",
        f'#include "{HEADER_NAME}"',
        "",
        f"static const double PRP3_SINGULARITY_THRESHOLD = {c_number(SINGULARITY_THRESHOLD)};",
        "/* the robot's parameters */",
        *constants,
        "",
        "static int prp3_refuse(double f10[3], double f21y[3], double f21z[3], int code)",
        "{",
        "    int i;",
        "    for (i = 0; i < 3; ++i) {",
        "        f10[i] = NAN;",
        "        f21y[i] = NAN;",
        "        f21z[i] = NAN;",
        "    }",
        "    return code;",
        "}",
        "",
        *FINITE_FUNCTION,
        "",
    ]


def _function_lines(template: _Template, stroke_lines: list[str]) -> list[str]:
    """The C function of the inverse dynamics: input checks, ``template``'s body, output check.

    It refuses non-finite inputs, a singular pose (``|sin(phi - pi/3)|`` below the
    threshold), a displacement outside the stroke (``stroke_lines``) and outputs
    that overflowed, each with its return code and NaN outputs.
    """
    unpack, finite = input_lines()
    return [
        *signature("double f10[3], double f21y[3], double f21z[3]"),
        "{",
        *unpack,
        f"    if (!({finite})) {{",
        "        return prp3_refuse(f10, f21y, f21z, PRP3_NOT_FINITE);",
        "    }",
        "    {",
        f"        const double psi = phi - {c_number(PI_3)};",
        "        const double cos_psi = cos(psi);",
        "        const double sin_psi = sin(psi);",
        "        /* sin(phi - pi/3), the determinant of every leg: singular below 1e-4 */",
        "        if (!(fabs(sin_psi) >= PRP3_SINGULARITY_THRESHOLD)) {",
        "            return prp3_refuse(f10, f21y, f21z, PRP3_SINGULAR);",
        "        }",
        *(f"        {line}" for line in template.body),
        *(f"        {line}" for line in stroke_lines),
        *(f"        {line}" for line in template.outputs),
        "    }",
        "    /* the inputs are finite: an output that is not has overflowed */",
        "    if (!(prp3_finite(f10, 3) && prp3_finite(f21y, 3) && prp3_finite(f21z, 3))) {",
        "        return prp3_refuse(f10, f21y, f21z, PRP3_OVERFLOW);",
        "    }",
        "    return PRP3_OK;",
        "}",
    ]


#: The C function of the one check of the outputs: every one finite (a pass of ``isfinite``).
FINITE_FUNCTION: tuple[str, ...] = (
    "static int prp3_finite(const double values[], int count)",
    "{",
    "    int i;",
    "    for (i = 0; i < count; ++i) {",
    "        if (!isfinite(values[i])) {",
    "            return 0;",
    "        }",
    "    }",
    "    return 1;",
    "}",
)


def version() -> str:
    from prp3 import __version__

    return __version__


def _robot_line(robot: Robot) -> str:
    return (
        f"l0 = {robot.l0!r} m, gravity = {list(robot.gravity)!r} m/s^2, "
        f"m1 = {robot.piston.mass!r}, m2 = {robot.link.mass!r}, m3 = {robot.platform.mass!r} kg, "
        f"stroke = {list(robot.limits.stroke) if robot.limits.stroke else None!r}"
    )


def _header(robot: Robot) -> str:
    lines = [
        f"/* {HEADER_NAME}: inverse dynamics of the 3-PRP planar parallel robot (C99).",
        f" * Generated by prp3 {version()} (prp3 export c). Robot: {_robot_line(robot)}",
        " *",
        " * prp3_inverse_dynamics(pose, velocity, acceleration, f10, f21y, f21z)",
        " *   pose = (x, y, phi): mass centre G of the platform (m) and orientation (rad);",
        " *   velocity, acceleration: their first and second time derivatives (SI units).",
        " *   f10[i]: force of actuator i on its piston along +e_i (N), legs A, B, C;",
        " *   f21y[i], f21z[i]: force of piston i on link 2 along n_i and e_i (N).",
        " * Returns one of the codes below: PRP3_OK (0) only when every output is finite.",
        " * On a non-zero return every output is NaN. Reentrant, no allocation, only",
        " * <math.h>. Do not compile with -ffast-math: it assumes no NaN and removes the checks.",
        " */",
    ]
    stroke = (
        "never returned: the robot has no [limits] stroke"
        if robot.limits.stroke is None
        else "an actuator displacement lambda10 is outside the robot's stroke"
    )
    codes = {
        "PRP3_SINGULAR": "|sin(phi - pi/3)| < 1e-4: the pose is singular",
        "PRP3_OUTSIDE_STROKE": stroke,
        "PRP3_UNREACHABLE": "never returned: the 3-PRP reaches every pose but for its stroke",
    }
    return header_text(lines, "double f10[3], double f21y[3], double f21z[3]", codes)


def input_lines() -> tuple[list[str], str]:
    """The C lines that read the nine inputs from ``pose``, ``velocity``, ``acceleration``,
    and the C condition that every one of them is finite."""
    unpack = [
        f"    const double {name} = {_ARRAYS[k // 3]}[{k % 3}];" for k, name in enumerate(_INPUTS)
    ]
    return unpack, " && ".join(f"isfinite({name})" for name in _INPUTS)


def signature(outputs: str) -> list[str]:
    """The lines of ``prp3_inverse_dynamics``'s declaration, its output arrays ``outputs``."""
    return [
        "int prp3_inverse_dynamics(const double pose[3], const double velocity[3],",
        "                          const double acceleration[3],",
        f"                          {outputs})",
    ]


def header_text(comment: list[str], outputs: str, codes: dict[str, str]) -> str:
    """The header: its ``comment`` lines, every return code of :data:`RETURN_CODES` with its
    comment (``codes`` replaces the comments of the codes it names: what they mean for this
    robot), the declaration with the output arrays ``outputs``, the include guard."""
    *declaration, last = signature(outputs)
    lines = [
        *comment,
        "#ifndef PRP3_INVERSE_DYNAMICS_H",
        "#define PRP3_INVERSE_DYNAMICS_H",
        "",
        "/* the return codes of prp3_inverse_dynamics, one per kind of failure */",
        *(
            f"#define {name} {value} /* {codes.get(name, meaning)} */"
            for name, value, meaning in RETURN_CODES
        ),
        "",
        "#ifdef __cplusplus",
        'extern "C" {',
        "#endif",
        "",
        *declaration,
        last + ";",
        "",
        "#ifdef __cplusplus",
        "}",
        "#endif",
        "",
        "#endif /* PRP3_INVERSE_DYNAMICS_H */",
    ]
    return "\n".join(lines) + "\n"
