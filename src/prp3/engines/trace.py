"""Straight-line numpy code from the kernel, for the design sweeps of :mod:`prp3.apps.design_evaluation` (internal).

:mod:`prp3.engines.entries` does not use it: its engines run the kernel itself
(:mod:`prp3.engines.select`).

:func:`trace` runs a function of the kernel (:mod:`prp3.mechanics.kernel`) once on
tracing values instead of numbers: every arithmetic operation and function
call on them is recorded, in the order the kernel performs it, while the
operations between plain floats (the robot's constants) are done at once.
The record becomes

* :func:`array_function` — a function of 1-D float64 arrays that runs the
  same operations as numpy ufuncs into a few preallocated work rows (no
  temporary arrays);
* :func:`broadcast_function` — the same for inputs of several shapes that
  broadcast (a design sweep: the robots' constants as a column, the states
  as a row), each operation computed at the shape of the inputs it depends
  on (what depends on the robot alone once per robot, on the state alone
  once per sample), into work blocks the caller allocates once.

Both perform exactly the kernel's floating-point operations in the kernel's
order, so their results are bit for bit those of the kernel on floats (up to
the sign of a zero, see :class:`Traced`, and numpy's ``cos``/``sin``).

>>> def f(ops, x, y):
...     return (x * y + 2.0 * 3.0, ops.cos(x))
>>> import numpy as np
>>> out = np.empty((2, 2))
>>> array_function(f, ("x", "y"))(np.zeros(2), np.full(2, 5.0), out)
>>> out.tolist()
[[6.0, 6.0], [1.0, 1.0]]
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from prp3.mechanics.ops import Ops

__all__ = [
    "TRACE",
    "Traced",
    "array_function",
    "broadcast_function",
    "trace",
]

# operation -> (scalar template, numpy ufunc name)
_BINARY = {"+": "add", "-": "subtract", "*": "multiply", "/": "divide", "atan2": "arctan2"}
_UNARY = {"neg": "negative", "cos": "cos", "sin": "sin", "sqrt": "sqrt", "tanh": "tanh",
          "abs": "absolute", "sign": "sign"}  # fmt: skip

#: One recorded operation: (operation, operands); an operand is a line index or a float.
Line = tuple[str, tuple[int | float, ...]]


class _Tape:
    def __init__(self) -> None:
        self.lines: list[Line] = []
        # each operation on the same operands once; the key tells a line index from a
        # constant of the same value (2 and 2.0 are equal keys of a dict)
        self.seen: dict[tuple[str, tuple[tuple[bool, int | float], ...]], Traced] = {}

    def record(self, operation: str, *operands: Any) -> Traced:
        line: Line = (
            operation,
            tuple(o.index if isinstance(o, Traced) else float(o) for o in operands),
        )
        key = (operation, tuple((isinstance(o, int), o) for o in line[1]))
        if key in self.seen:
            return self.seen[key]
        value = Traced(self, len(self.lines))
        self.lines.append(line)
        self.seen[key] = value
        return value


def _is(value: Any, constant: float) -> bool:
    return not isinstance(value, Traced) and value == constant


class Traced:
    """A value of the traced function: its operations are recorded on a tape.

    Identities with a constant operand (exact for the finite values the kernel
    is called with, up to the sign of a zero) keep the code short: a robot
    without centre-of-mass offsets loses every term of the offsets.
    Inputs have negative indices.
    """

    __slots__ = ("index", "tape")

    def __init__(self, tape: _Tape, index: int) -> None:
        self.tape, self.index = tape, index

    def __add__(self, other: Any) -> Any:
        return self if _is(other, 0.0) else self.tape.record("+", self, other)

    def __radd__(self, other: Any) -> Any:
        return self if _is(other, 0.0) else self.tape.record("+", other, self)

    def __sub__(self, other: Any) -> Any:
        return self if _is(other, 0.0) else self.tape.record("-", self, other)

    def __rsub__(self, other: Any) -> Any:
        return -self if _is(other, 0.0) else self.tape.record("-", other, self)

    def __mul__(self, other: Any) -> Any:
        if _is(other, 0.0):
            return 0.0
        if _is(other, 1.0):
            return self
        if _is(other, -1.0):
            return -self
        return self.tape.record("*", self, other)

    def __rmul__(self, other: Any) -> Any:
        return self.__mul__(other)  # a·b = b·a exactly

    def __truediv__(self, other: Any) -> Any:
        return self if _is(other, 1.0) else self.tape.record("/", self, other)

    def __rtruediv__(self, other: Any) -> Any:
        return self.tape.record("/", other, self)

    def __neg__(self) -> Any:
        return self.tape.record("neg", self)


def _function(name: str, plain: Callable[[float], float]) -> Callable[[Any], Any]:
    def call(value: Any) -> Any:
        return value.tape.record(name, value) if isinstance(value, Traced) else plain(value)

    return call


def _atan2(y: Any, x: Any) -> Any:
    """``atan2(y, x)`` recorded when either is traced (no identity: signed zeros matter)."""
    if isinstance(y, Traced):
        return y.tape.record("atan2", y, x)
    if isinstance(x, Traced):
        return x.tape.record("atan2", y, x)
    return math.atan2(y, x)


#: The kernel's functions on traced values (floats stay floats).
TRACE = Ops(
    "trace",
    _function("cos", math.cos),
    _function("sin", math.sin),
    _function("sqrt", math.sqrt),
    _function("tanh", math.tanh),
    _function("abs", abs),
    _function("sign", lambda v: float((v > 0.0) - (v < 0.0))),
    _atan2,
)


def trace(
    function: Callable[..., Sequence[Any]], arity: int
) -> tuple[list[tuple[int, Line]], list[int | float]]:
    """Record ``function(TRACE, *inputs)``: (needed lines, outputs).

    Lines are ``(index, (operation, operands))``, only those the outputs need;
    operands and outputs are line indices (``-1 … -arity`` for the inputs) or
    floats (an output that does not depend on the inputs).
    """
    tape = _Tape()
    inputs = [Traced(tape, -1 - k) for k in range(arity)]
    outputs = [o.index if isinstance(o, Traced) else float(o) for o in function(TRACE, *inputs)]
    needed: set[int] = set()
    stack = [o for o in outputs if isinstance(o, int) and o >= 0]
    while stack:
        index = stack.pop()
        if index not in needed:
            needed.add(index)
            stack.extend(o for o in tape.lines[index][1] if isinstance(o, int) and o >= 0)
    return [(k, line) for k, line in enumerate(tape.lines) if k in needed], outputs


def _compile(source: str, name: str, namespace: dict[str, Any]) -> Callable[..., Any]:
    exec(compile(source, f"<prp3 kernel: {name}>", "exec"), namespace)
    compiled: Callable[..., Any] = namespace[name]
    compiled.__doc__ = source
    return compiled


def _own_names(arguments: Sequence[str]) -> None:
    """Refuse argument names of the generated code's own locals (``w3``, ``o0``, ``k2``, …)."""
    taken = [a for a in arguments if re.fullmatch(r"[wok]\d+(_\d+)?", a)]
    if taken:
        raise ValueError(f"argument names {taken} are the generated code's own")


def array_function(
    function: Callable[..., Sequence[Any]], arguments: Sequence[str], name: str = "traced"
) -> Callable[..., None]:
    """A function of equal-length 1-D float64 arrays with the recorded operations.

    ``f(*inputs, out)`` writes the outputs into ``out`` (a sequence of 1-D
    float64 arrays of the inputs' length, any strides): every operation is
    one numpy ufunc call, into the output array it computes or into a row of
    one work block (rows are reused once their value is dead), so a call
    allocates one block of ``rows × n`` floats and nothing else.  The
    function's ``rows`` attribute is the number of work rows.
    """
    _own_names(arguments)
    lines, outputs = trace(function, len(arguments))
    last_use: dict[int, int] = {}
    for position, (_, (_, operands)) in enumerate(lines):
        for o in operands:
            if isinstance(o, int) and o >= 0:
                last_use[o] = position
    direct: dict[int, int] = {}  # line -> the output it is written into
    for k, o in enumerate(outputs):
        if isinstance(o, int) and o >= 0 and o not in direct:
            direct[o] = k
    place: dict[int, str] = {}
    free: list[int] = []
    rows = 0

    constants: dict[str, str] = {}  # repr -> name of a 0-d array (numpy converts a float per call)

    def operand(o: int | float) -> str:
        if not isinstance(o, int):
            return constants.setdefault(repr(o), f"k{len(constants)}")
        return arguments[-1 - o] if o < 0 else place[o]

    body = []
    for position, (index, (operation, operands)) in enumerate(lines):
        a = [operand(o) for o in operands]
        for o in set(operands):  # operands dead after this line free their rows
            if isinstance(o, int) and o >= 0 and last_use[o] == position and o not in direct:
                free.append(int(place[o][1:]))
        if index in direct:
            place[index] = f"o{direct[index]}"
        else:
            if free:
                row = free.pop()
            else:
                row, rows = rows, rows + 1
            place[index] = f"w{row}"
        ufunc = _BINARY.get(operation) or _UNARY[operation]
        body.append(f"    {ufunc}({', '.join(a)}, {place[index]})")
    for k, o in enumerate(outputs):  # outputs not computed in place: constants, inputs, repeats
        if not (isinstance(o, int) and o >= 0 and direct[o] == k):
            body.append(f"    o{k}[...] = {operand(o)}")
    # the rows and outputs as local names (an index costs more than the operation on a
    # row of a few thousand floats), the output passed by position (cheaper than out=)
    work = "".join(f"w{k}, " for k in range(max(rows, 1)))
    unpack = "".join(f"o{k}, " for k in range(len(outputs)))
    source = (
        "".join(f"{k} = array({value})\n" for value, k in constants.items())
        + f"def {name}({', '.join(arguments)}, out):\n"
        f"    {work}= empty(({max(rows, 1)}, {arguments[0]}.shape[0]))\n"
        f"    {unpack}= out\n" + "\n".join(body) + "\n"
    )
    namespace: dict[str, Any] = {"empty": np.empty, "array": np.array, "inf": math.inf,
                                 "nan": math.nan}  # fmt: skip
    namespace.update({u: getattr(np, u) for u in (*_BINARY.values(), *_UNARY.values())})
    compiled = _compile(source, name, namespace)
    compiled.rows = rows  # type: ignore[attr-defined]
    return compiled


def broadcast_function(
    function: Callable[..., Sequence[Any]],
    arguments: Sequence[str],
    groups: Sequence[int],
    name: str = "traced",
) -> Callable[..., None]:
    """A function of arrays of several broadcasting shapes with the recorded operations.

    Argument ``k`` belongs to group ``groups[k]`` (``0 <= group < 8``); the
    arguments of one group have one shape, and the shapes of the groups
    broadcast (e.g. ``(B, 1)`` robots and ``(1, N)`` states).  Each recorded
    operation is one numpy ufunc call at the broadcast shape of the groups it
    depends on: an operation on the robot's constants alone is done once per
    robot, one on the state alone once per sample.

    ``f(*inputs, out, work)`` writes the outputs into ``out`` (a sequence of
    arrays of the broadcast shape of every group).  ``work`` is a sequence of
    float64 arrays, one per entry ``(mask, rows)`` of the function's
    ``blocks`` attribute, each of shape ``(rows, *shape)`` with ``shape`` the
    broadcast shape of the groups whose bits are set in ``mask``: the caller
    allocates them once and reuses them, so a call allocates nothing.  The
    operations and their order are the kernel's, as :func:`array_function`.

    >>> def f(ops, a, x):
    ...     return (a * 2.0 * x, ops.cos(x) + 1.0)
    >>> fn = broadcast_function(f, ("a", "x"), (0, 1))
    >>> a, x = np.array([[1.0], [2.0]]), np.zeros((1, 3))
    >>> shapes = {1: a.shape, 2: x.shape, 3: (2, 3)}
    >>> work = [np.empty((rows, *shapes[mask])) for mask, rows in fn.blocks]
    >>> out = np.empty((2, 2, 3))
    >>> fn(a, x, out=out, work=work)
    >>> out.tolist()
    [[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], [[2.0, 2.0, 2.0], [2.0, 2.0, 2.0]]]
    """
    if len(groups) != len(arguments) or not all(0 <= g < 8 for g in groups):
        raise ValueError("one group from 0 to 7 per argument")
    _own_names(arguments)
    lines, outputs = trace(function, len(arguments))
    full = 0
    for g in groups:
        full |= 1 << g
    mask: dict[int, int] = {}  # line -> the groups it depends on

    def mask_of(o: int | float) -> int:
        if not isinstance(o, int):
            return 0
        return 1 << groups[-1 - o] if o < 0 else mask[o]

    last_use: dict[int, int] = {}
    for position, (index, (_, operands)) in enumerate(lines):
        mask[index] = 0
        for o in operands:
            mask[index] |= mask_of(o)
            if isinstance(o, int) and o >= 0:
                last_use[o] = position
    direct: dict[int, int] = {}  # line -> the output it is written into (full shape only)
    kept: set[int] = set()  # outputs of smaller shapes: copied at the end, their rows kept
    for k, o in enumerate(outputs):
        if isinstance(o, int) and o >= 0:
            if mask[o] != full:
                kept.add(o)
            elif o not in direct:
                direct[o] = k
    place: dict[int, tuple[int, int]] = {}  # line -> (mask, row) of its work row
    free: dict[int, list[int]] = {}
    rows: dict[int, int] = {}

    def operand(o: int | float) -> str:
        if not isinstance(o, int):
            return repr(o)
        if o < 0:
            return arguments[-1 - o]
        if o in direct:
            return f"o{direct[o]}"
        m, row = place[o]
        return f"w{m}_{row}"

    body = []
    for position, (index, (operation, operands)) in enumerate(lines):
        a = [operand(o) for o in operands]
        for o in set(operands):  # operands dead after this line free their rows
            if (
                isinstance(o, int)
                and o >= 0
                and last_use[o] == position
                and o not in direct
                and o not in kept
            ):
                m, row = place[o]
                free.setdefault(m, []).append(row)
        if index in direct:
            target = f"o{direct[index]}"
        else:
            m = mask[index]
            spare = free.setdefault(m, [])
            if spare:
                row = spare.pop()
            else:
                row = rows.get(m, 0)
                rows[m] = row + 1
            place[index] = (m, row)
            target = f"w{m}_{row}"
        ufunc = _BINARY.get(operation) or _UNARY[operation]
        body.append(f"    {ufunc}({', '.join(a)}, {target})")
    for k, o in enumerate(outputs):  # outputs not computed in place: smaller shapes, repeats
        if not (isinstance(o, int) and o >= 0 and direct.get(o) == k):
            body.append(f"    o{k}[...] = {operand(o)}")
    blocks = sorted(rows.items())
    # rows and outputs as local names, the output by position: as array_function
    unpack = [
        f"    {''.join(f'w{m}_{row}, ' for row in range(count))}= work[{k}]"
        for k, (m, count) in enumerate(blocks)
    ]
    unpack.append(f"    {''.join(f'o{k}, ' for k in range(len(outputs)))}= out")
    source = f"def {name}({', '.join(arguments)}, out, work):\n" + "\n".join(unpack + body) + "\n"
    namespace: dict[str, Any] = {u: getattr(np, u) for u in (*_BINARY.values(), *_UNARY.values())}
    namespace |= {"inf": math.inf, "nan": math.nan}  # constants as repr writes them
    compiled = _compile(source, name, namespace)
    compiled.blocks = tuple(blocks)  # type: ignore[attr-defined]
    return compiled
