"""``atan2`` on :class:`prp3.mechanics.ops.Ops`, the tracer and every emitter of a trace.

Each route (plain floats, numpy, sympy, the tracer's numpy functions
``array_function`` and ``broadcast_function``, the numba source of
``python_statements`` run as Python and compiled by numba, the C of
``prp3.family.codegen.c_statements`` compiled by the system's compiler) is
held against :func:`math.atan2` in all four quadrants, on the axes and at
every signed zero, bit for bit (and the signed zero's sign).
"""

from __future__ import annotations

import ctypes
import math
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ctools import COMPILER
from prp3.engines.trace import array_function, broadcast_function, trace
from prp3.engines.traced_numba import MODULE_HEADER, generated_module, python_statements
from prp3.family.codegen import c_statements
from prp3.mechanics.ops import MATH, NUMPY, sympy_ops

SPECIAL = [0.0, -0.0, 1.0, -1.0, 2.5, -2.5, 1e-300, -1e-300, 1e300, -1e300, math.inf, -math.inf]
PAIRS = [(y, x) for y in SPECIAL for x in SPECIAL]
finite = st.floats(-1e6, 1e6, allow_nan=False)


def same(a: float, b: float) -> bool:
    """Equal as doubles, the sign of a zero included (NaN equal to NaN)."""
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


def angle(ops: Any, y: Any, x: Any) -> tuple[Any, Any]:
    """A traced function using atan2 on inputs and on an operation's result."""
    return (ops.atan2(y, x), ops.atan2(y * 2.0, x) - 1.0)


def expected(y: float, x: float) -> tuple[float, float]:
    return (math.atan2(y, x), math.atan2(y * 2.0, x) - 1.0)


def test_every_quadrant_and_signed_zero_of_math_and_numpy() -> None:
    assert math.atan2(0.0, -1.0) == math.pi and math.atan2(-0.0, -1.0) == -math.pi
    for y, x in PAIRS:
        assert same(MATH.atan2(y, x), math.atan2(y, x))
        assert same(float(NUMPY.atan2(np.float64(y), np.float64(x))), math.atan2(y, x))


def test_sympy_atan2_is_the_angle() -> None:
    import sympy

    ops = sympy_ops()
    for y, x in [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0), (0.0, -1.0), (3.0, 0.0)]:
        value = float(sympy.N(ops.atan2(sympy.Float(y), sympy.Float(x)), 30))
        assert value == pytest.approx(math.atan2(y, x), rel=1e-15, abs=1e-15)


def test_the_tracer_records_atan2_and_folds_constants() -> None:
    lines, _ = trace(angle, 2)
    assert [op for _, (op, _) in lines].count("atan2") == 2
    constant = trace(lambda ops, y: (ops.atan2(-0.0, -1.0), ops.atan2(y, 1.0)), 1)
    assert constant[1][0] == -math.pi  # two floats: computed at once, signed zero kept
    assert constant[0][0][1] == ("atan2", (-1, 1.0))  # a traced y, a constant x


def test_array_and_broadcast_functions() -> None:
    y = np.array([p[0] for p in PAIRS])
    x = np.array([p[1] for p in PAIRS])
    out = np.empty((2, y.size))
    array_function(angle, ("y", "x"))(y, x, out)
    fn = broadcast_function(angle, ("y", "x"), (0, 1))
    shapes = {1: (y.size, 1), 2: (1, x.size), 3: (y.size, x.size)}
    work = [np.empty((rows, *shapes[mask])) for mask, rows in fn.blocks]
    grid = np.empty((2, y.size, x.size))
    fn(y[:, None], x[None, :], out=grid, work=work)
    for k, (a, b) in enumerate(PAIRS):
        for i in range(2):
            assert same(out[i, k], expected(a, b)[i]), (a, b, i)
    for i, a in enumerate(y):
        for k, b in enumerate(x):
            for n in range(2):
                assert same(grid[n, i, k], expected(float(a), float(b))[n]), (a, b, n)


def _python_source() -> str:
    code = python_statements(angle, ("y", "x"), "t")
    body = "\n".join(f"    {s}" for s in code.prelude + code.body)
    return (
        MODULE_HEADER
        + "\n\n@numba.njit(cache=True)\ndef angle(y, x):\n"
        + body
        + f"\n    return {code.outputs[0]}, {code.outputs[1]}\n\n\n"
        + "def plain(y, x):\n"
        + body
        + f"\n    return {code.outputs[0]}, {code.outputs[1]}\n"
    )


def test_the_numba_source_as_python_and_compiled() -> None:
    module = generated_module(_python_source(), "test_atan2")
    for y, x in PAIRS:
        for got in (module.plain(y, x), module.angle(y, x)):
            for i in range(2):
                assert same(got[i], expected(y, x)[i]), (y, x, i)


@given(finite, finite)
@settings(max_examples=200, deadline=None)
def test_the_numba_source_on_random_points(y: float, x: float) -> None:
    module = generated_module(_python_source(), "test_atan2")
    got = module.angle(y, x)
    assert same(got[0], math.atan2(y, x)) and same(got[1], expected(y, x)[1])


@pytest.mark.skipif(COMPILER is None, reason="no C compiler")
def test_the_c_statements(tmp_path: Path) -> None:
    body, outputs, operations = c_statements(angle, ("y", "x"), "t", "    ")
    assert operations == 4
    source = (
        "#include <math.h>\nvoid angle(double y, double x, double out[2]) {\n"
        + "\n".join(body)
        + f"\n    out[0] = {outputs[0]};\n    out[1] = {outputs[1]};\n}}\n"
    )
    (tmp_path / "angle.c").write_text(source)
    library = tmp_path / "libangle.so"
    assert COMPILER is not None
    done = subprocess.run(
        [COMPILER, "-std=c99", "-pedantic-errors", "-Wall", "-Wextra", "-Werror", "-O2",
         "-shared", "-fPIC", "-o", str(library), str(tmp_path / "angle.c"), "-lm"],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    function = ctypes.CDLL(str(library)).angle
    function.restype = None
    function.argtypes = [ctypes.c_double, ctypes.c_double, ctypes.POINTER(ctypes.c_double)]
    out = (ctypes.c_double * 2)()
    for y, x in PAIRS:
        function(y, x, out)
        for i in range(2):
            assert same(out[i], expected(y, x)[i]), (y, x, i)
