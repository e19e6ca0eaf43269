"""Scalar numba source from a traced function, written to a cached module file (internal).

The functions of :mod:`prp3.family.sample_mechanics` are written once on
:class:`prp3.mechanics.ops.Ops`; :func:`prp3.engines.trace.trace` records each
floating-point operation.  Here the record becomes Python source, one
statement per recorded operation (as :mod:`prp3.family.codegen` makes C of
it), for a scalar loop that numba compiles:

* :func:`python_statements` — the statements of one traced function whose
  arguments are split into *constants* (a robot's numbers, read once per call)
  and per-sample values: a statement that depends on constants alone is
  hoisted before the sample loop (the ``prelude``), the others form the
  loop's body;
* :func:`generated_module` — the source written to a module file in
  :func:`cache_directory`, named by a hash of the source, and imported, so that
  numba's ``cache=True`` compiles each generated function once per machine;
* :data:`MODULE_HEADER` and :func:`parallel_source` — the module's imports
  and the ``prange`` wrapper over blocks of samples (each block one call of
  the sequential loop, so the numbers are those of one thread).

The generator knows nothing of robots: it takes the traced functions as
arguments.

>>> def f(ops, k, x):
...     return (k * k * x, ops.sqrt(k))
>>> code = python_statements(f, ("k", "x"), "t", constants={"k"})
>>> code.prelude, code.body, code.outputs
(['t0 = k * k', 't2 = sqrt(k)'], ['t1 = t0 * x'], ['t1', 't2'])
"""

from __future__ import annotations

import hashlib
import importlib.util
import math
import os
import sys
import tempfile
import types
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from prp3.engines.trace import trace

__all__ = [
    "MODULE_HEADER",
    "Statements",
    "cache_directory",
    "generated_module",
    "parallel_source",
    "python_statements",
]

#: The imports of a generated module: math's functions by name, numba's compiler.
MODULE_HEADER = (
    "from math import atan2, cos, sin, sqrt, tanh, inf, nan, isfinite\n"
    "import numpy as np\nimport numba\n"
)

_BINARY = {"+", "-", "*", "/"}
_CALLS = {"cos", "sin", "sqrt", "tanh", "abs"}


@dataclass(frozen=True)
class Statements:
    """The Python statements of one traced function.

    Attributes
    ----------
    prelude : list of str
        Statements depending on the constants alone (once per call).
    body : list of str
        The others, in the traced order (once per sample).
    outputs : list of str
        The Python expression of each output (a name or a number).
    operations : int
        Recorded operations (prelude and body).
    """

    prelude: list[str]
    body: list[str]
    outputs: list[str]
    operations: int


def _number(value: float) -> str:
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "(-inf)"
    return repr(float(value))


def _expression(operation: str, a: Sequence[str]) -> str:
    if operation in _BINARY:
        return f"{a[0]} {operation} {a[1]}"
    if operation == "neg":
        return f"-{a[0]}"
    if operation in _CALLS:
        return f"{operation}({a[0]})"
    if operation == "atan2":
        return f"atan2({a[0]}, {a[1]})"
    if operation == "sign":
        return f"float(({a[0]} > 0.0) - ({a[0]} < 0.0))"
    raise AssertionError(operation)  # pragma: no cover - trace records no other operation


def python_statements(
    function: Callable[..., Sequence[Any]],
    arguments: Sequence[str],
    prefix: str,
    constants: Collection[str] = (),
) -> Statements:
    """Trace ``function(ops, *arguments)`` into Python statements ``{prefix}{line} = …``.

    ``constants`` names the arguments that do not change from sample to
    sample; a statement whose operands are constants, numbers or such
    statements goes to the prelude.  The operations and their order are the
    traced function's (a hoisted statement is computed once, with the same
    operands), so the results are bit for bit those of the function on floats.
    """
    lines, outputs = trace(function, len(arguments))
    fixed: set[int] = {-1 - k for k, a in enumerate(arguments) if a in constants}

    def name(operand: int | float) -> str:
        if isinstance(operand, int):
            return arguments[-1 - operand] if operand < 0 else f"{prefix}{operand}"
        return _number(float(operand))

    prelude, body = [], []
    for index, (operation, operands) in lines:
        text = f"{prefix}{index} = {_expression(operation, [name(o) for o in operands])}"
        if all(not isinstance(o, int) or o in fixed for o in operands):
            fixed.add(index)
            prelude.append(text)
        else:
            body.append(text)
    return Statements(prelude, body, [name(o) for o in outputs], len(lines))


def parallel_source(name: str, loop: str, arguments: Sequence[str], block: int) -> str:
    """Source of ``name(*arguments, start, stop)``: ``loop`` on blocks of ``block`` samples on every thread.

    ``loop(*arguments, start, stop)`` is the sequential loop, returning an
    integer of flags; each block is one call of it (the same machine code per
    sample as on one thread), and the result is the bitwise or of the blocks'.
    """
    args = ", ".join(arguments)
    return (
        '@numba.njit(cache=True, error_model="numpy", parallel=True)\n'
        f"def {name}({args}, start, stop):\n"
        f"    blocks = (stop - start + {block} - 1) // {block}\n"
        "    flags = np.zeros(blocks, dtype=np.int64)\n"
        "    for b in numba.prange(blocks):\n"
        f"        first = start + b * {block}\n"
        f"        flags[b] = {loop}({args}, first, min(stop, first + {block}))\n"
        "    result = 0\n"
        "    for b in range(blocks):\n"
        "        result |= flags[b]\n"
        "    return result\n"
    )


def cache_directory() -> Path:
    """Where generated modules are written: a writable directory, made if needed.

    ``$NUMBA_CACHE_DIR/prp3_generated`` when ``NUMBA_CACHE_DIR`` is set; else
    ``__pycache__/prp3_generated`` beside this file when it can be written
    (numba then caches beside it too); else numba's user-wide cache directory
    (a read-only installation).
    """
    candidates = []
    if os.environ.get("NUMBA_CACHE_DIR"):
        candidates.append(Path(os.environ["NUMBA_CACHE_DIR"]) / "prp3_generated")
    candidates.append(Path(__file__).parent / "__pycache__" / "prp3_generated")
    candidates.append(_user_cache() / "prp3_generated")
    for folder in candidates:
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if os.access(folder, os.W_OK | os.X_OK):
            return folder
    raise OSError(f"no writable directory for prp3's generated kernels among {candidates}")


def _user_cache() -> Path:
    try:
        from numba.misc.appdirs import AppDirs
    except ImportError:  # pragma: no cover - numba missing: the caller does not compile
        return Path(tempfile.gettempdir()) / "prp3"
    dirs: Any = AppDirs
    return Path(dirs(appname="numba", appauthor=False).user_cache_dir)


_LOADED: dict[str, types.ModuleType] = {}


def generated_module(source: str, stem: str) -> types.ModuleType:
    """The module of ``source``, written once to ``stem_<hash>.py`` in :func:`cache_directory`.

    The file is named by a hash of the source, so a change of the generating
    code makes a new file (and numba's cache of the old one is not used); an
    existing file is never rewritten (numba's cache is keyed on its time
    stamp).  The file is written atomically (a temporary file renamed), so
    processes generating the same module at once agree.
    """
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    module_name = f"prp3_generated_{stem}_{digest}"
    if module_name in _LOADED:
        return _LOADED[module_name]
    folder = cache_directory()
    path = folder / f"{module_name}.py"
    if not path.exists() or path.read_text() != source:
        handle, temporary = tempfile.mkstemp(dir=folder, suffix=".tmp")
        with os.fdopen(handle, "w") as stream:
            stream.write(source)
        os.replace(temporary, path)
    spec = importlib.util.spec_from_file_location(module_name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    spec.loader.exec_module(module)
    _LOADED[module_name] = module
    return module
