"""Straight-line code from the kernel (internal).

:func:`trace` runs a function of the kernel (:mod:`prp3.kernel`) once on
tracing values instead of numbers: every arithmetic operation and function
call on them is recorded, in the order the kernel performs it, while the
operations between plain floats (the robot's constants) are done at once.
:func:`scalar_function` turns the record into the source of a Python function
of plain floats without calls, tuples or loops — the single-sample fast path —
that performs exactly the kernel's floating-point operations in the kernel's
order, so its results are bit for bit those of the kernel on :data:`~prp3.kernel.MATH`.

>>> def f(ops, x, y):
...     return (x * y + 2.0 * 3.0, ops.cos(x))
>>> fn = scalar_function(f, ("x", "y"))
>>> fn(0.0, 5.0)
(6.0, 1.0)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from .kernel import Ops

__all__ = ["Traced", "scalar_function", "trace"]


class _Tape:
    def __init__(self) -> None:
        self.lines: list[tuple[str, str, tuple[int, ...]]] = []  # (name, expression, inputs)
        self.seen: dict[str, Traced] = {}  # expression -> its value: each computed once

    def record(self, template: str, *operands: Any) -> Traced:
        names, inputs = [], []
        for operand in operands:
            if isinstance(operand, Traced):
                names.append(operand.name)
                inputs.append(operand.index)
            else:
                names.append(repr(float(operand)))
        expression = template.format(*names)
        if expression in self.seen:  # the same operation on the same operands
            return self.seen[expression]
        index = len(self.lines)
        name = f"t{index}"
        self.lines.append((name, expression, tuple(inputs)))
        self.seen[expression] = value = Traced(self, name, index)
        return value


class Traced:
    """A value of the traced function: its operations are recorded on a tape."""

    __slots__ = ("index", "name", "tape")

    def __init__(self, tape: _Tape, name: str, index: int) -> None:
        self.tape, self.name, self.index = tape, name, index

    # Identities with a constant operand (exact for the finite values the kernel
    # is called with, up to the sign of a zero) keep the straight-line code short:
    # a robot without centre-of-mass offsets loses every term of the offsets.
    def __add__(self, other: Any) -> Any:
        if _is(other, 0.0):
            return self
        return self.tape.record("{} + {}", self, other)

    def __radd__(self, other: Any) -> Any:
        if _is(other, 0.0):
            return self
        return self.tape.record("{} + {}", other, self)

    def __sub__(self, other: Any) -> Any:
        if _is(other, 0.0):
            return self
        return self.tape.record("{} - {}", self, other)

    def __rsub__(self, other: Any) -> Any:
        if _is(other, 0.0):
            return -self
        return self.tape.record("{} - {}", other, self)

    def __mul__(self, other: Any) -> Any:
        if _is(other, 0.0):
            return 0.0
        if _is(other, 1.0):
            return self
        if _is(other, -1.0):
            return -self
        return self.tape.record("{} * {}", self, other)

    def __rmul__(self, other: Any) -> Any:
        return self.__mul__(other)

    def __truediv__(self, other: Any) -> Any:
        if _is(other, 1.0):
            return self
        return self.tape.record("{} / {}", self, other)

    def __rtruediv__(self, other: Any) -> Traced:
        return self.tape.record("{} / {}", other, self)

    def __neg__(self) -> Traced:
        return self.tape.record("-{}", self)


def _is(value: Any, constant: float) -> bool:
    return not isinstance(value, Traced) and value == constant


def _function(name: str) -> Callable[[Any], Any]:
    def call(value: Any) -> Any:
        if isinstance(value, Traced):
            return value.tape.record(f"{name}({{}})", value)
        return getattr(math, name)(value) if name != "abs" else abs(value)

    return call


def _sign(value: Any) -> Any:
    if isinstance(value, Traced):
        return value.tape.record("(({0} > 0.0) - ({0} < 0.0))", value)
    return (value > 0.0) - (value < 0.0)


#: The kernel's functions on traced values (floats stay floats).
TRACE = Ops("trace", _function("cos"), _function("sin"), _function("sqrt"),
            _function("tanh"), _function("abs"), _sign)  # fmt: skip


def trace(
    function: Callable[..., Sequence[Any]], arguments: Sequence[str]
) -> tuple[list[str], list[str]]:
    """Record ``function(TRACE, *arguments)``; returns (code lines, output expressions).

    Only the lines the outputs depend on are kept.  An output that does not
    depend on the arguments is a float literal.
    """
    tape = _Tape()
    inputs = [Traced(tape, name, -1) for name in arguments]
    outputs = function(TRACE, *inputs)
    needed: set[int] = set()
    stack = [out.index for out in outputs if isinstance(out, Traced) and out.index >= 0]
    while stack:
        index = stack.pop()
        if index not in needed:
            needed.add(index)
            stack.extend(i for i in tape.lines[index][2] if i >= 0)
    lines = [f"{name} = {expr}" for k, (name, expr, _) in enumerate(tape.lines) if k in needed]
    results = [out.name if isinstance(out, Traced) else repr(float(out)) for out in outputs]
    return lines, results


def scalar_function(
    function: Callable[..., Sequence[Any]], arguments: Sequence[str], name: str = "traced"
) -> Callable[..., tuple[float, ...]]:
    """A plain-float Python function with the recorded operations of ``function``."""
    lines, results = trace(function, arguments)
    body = "\n".join(f"    {line}" for line in lines)
    source = f"def {name}({', '.join(arguments)}):\n{body}\n    return ({', '.join(results)},)\n"
    namespace: dict[str, Any] = {
        "cos": math.cos, "sin": math.sin, "sqrt": math.sqrt, "tanh": math.tanh, "abs": abs,
    }  # fmt: skip
    exec(compile(source, f"<prp3 kernel: {name}>", "exec"), namespace)
    compiled: Callable[..., tuple[float, ...]] = namespace[name]
    compiled.__doc__ = source
    return compiled
