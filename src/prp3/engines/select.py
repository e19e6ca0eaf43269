"""The engines that run the kernel: *how* the equations of :mod:`prp3.mechanics.kernel` are evaluated.

The kernel says *what* is computed (inverse geometry eq. 10, rates eqs. 14
and 17, body wrenches eqs. 19–22, virtual work eqs. 15, 16, 21, 23–25); an
engine runs it on many samples:

* ``"numba"`` — :mod:`prp3.engines.numba`: the kernel's own functions compiled
  by numba (machine code cached on disk, compiled once per installation), one
  loop over the samples, on every thread of numba's threading layer from
  :data:`prp3.engines.numba.PARALLEL_MIN_SAMPLES` samples; no temporary arrays.
  The default when numba imports.
* ``"numpy"`` — :func:`run_numpy`: :func:`prp3.mechanics.kernel.solve` itself on 1-D
  float64 arrays (:data:`~prp3.mechanics.ops.NUMPY`), :data:`CHUNK` samples at a time
  (memory bounded for any ``N``); a breakpoint in
  :func:`prp3.mechanics.wrenches.body_wrenches` stops there.  It runs every effect of the
  kernel, among them the joint friction and its implicit ``μ`` terms
  (:func:`prp3.mechanics.implicit_friction.solve_mu`, Newton on arrays), which the numba engine
  does not compile: a robot with ``[friction]`` runs on numpy whichever
  engine is asked (:func:`runs_on`).

The engine is an explicit argument of the public functions of
:mod:`prp3.engines.entries` and :func:`prp3.analysis.inverse_dynamics.inverse_dynamics`; ``None`` means
:func:`default_engine`.  Engines do not validate: :mod:`prp3.engines.entries` checks
their inputs first (through :mod:`prp3.validation`) and their results after.

>>> ENGINES
('numba', 'numpy')
>>> default_engine()
'numba'
"""

from __future__ import annotations

import importlib
import warnings
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.mechanics import kernel
from prp3.mechanics.ops import NUMPY
from prp3.mechanics.parameters import KernelParameters
from prp3.validation import check_choice

__all__ = [
    "CHUNK",
    "ENGINES",
    "EngineWarning",
    "default_engine",
    "numba_module",
    "resolve_engine",
    "run_numpy",
    "runs_on",
]

FloatArray = NDArray[np.float64]

#: The engines, the default first.
ENGINES: tuple[str, ...] = ("numba", "numpy")

#: Samples per chunk of the numpy engine (its temporary arrays stay in the CPU caches).
CHUNK = 8192

_MISSING = object()
_numba: Any = _MISSING


class EngineWarning(UserWarning):
    """The compiled engine, or its threads, are not available (said once).

    Without numba the numpy engine runs (:func:`default_engine`); without a
    thread-safe threading layer of numba its batches run on one thread
    (:func:`prp3.engines.numba.parallel_layer`).
    """


def numba_module() -> ModuleType | None:
    """:mod:`prp3.engines.numba` (imported on first use), or ``None`` without numba."""
    global _numba
    if _numba is _MISSING:
        try:
            _numba = importlib.import_module("prp3.engines.numba")
        except ImportError:
            _numba = None
    return _numba  # type: ignore[no-any-return]


_warned = False


def default_engine() -> str:
    """``"numba"`` when numba imports, else ``"numpy"`` (with one :class:`EngineWarning`)."""
    global _warned
    if (_numba is not _MISSING and _numba is not None) or numba_module() is not None:
        return "numba"
    if not _warned:
        _warned = True
        warnings.warn(
            "numba is not installed: prp3 runs its numpy engine (several times slower); "
            'pip install "prp3[numba]" for the compiled one',
            EngineWarning,
            stacklevel=3,
        )
    return "numpy"


def resolve_engine(engine: object) -> str:
    """The engine named by ``engine`` (``None``: :func:`default_engine`), validated.

    Raises
    ------
    ParameterError
        ``engine`` is not one of :data:`ENGINES`.
    Prp3Error
        ``"numba"`` is asked and numba is not installed.
    """
    if engine is None:
        return default_engine()
    name = check_choice("engine", engine, ENGINES)
    if name == "numba" and numba_module() is None:
        raise Prp3Error(
            'engine="numba" needs numba, which is not installed: pip install "prp3[numba]"'
        )
    return name


def runs_on(engine: str, parameters: KernelParameters, friction: bool) -> str:
    """The engine that runs a robot: ``engine``, or ``"numpy"`` for what numba does not compile.

    The numba engine compiles the kernel without joint friction (the friction
    laws and the implicit ``μ`` solve run on arrays); a robot with
    ``[friction]`` runs on numpy.
    """
    if engine == "numba" and (friction or parameters.has_mu):
        return "numpy"
    return engine


def run_numpy(
    parameters: KernelParameters,
    inputs: list[FloatArray],
    targets: dict[str, FloatArray],
    *,
    chunk_size: int = CHUNK,
    load: FloatArray | None = None,
    iterations: FloatArray | None = None,
    near_lock: FloatArray | None = None,
) -> None:
    """:func:`prp3.mechanics.kernel.solve` on numpy arrays, chunk by chunk, into ``targets``.

    ``inputs``: pose, velocity, acceleration ``(N, 3)``; ``targets``: output
    name (a field of :class:`~prp3.mechanics.kernel.KernelSolution`, or ``fric10``,
    ``fric21``, ``fric32``) → ``(N, 3)`` array, written in place; ``load``
    the time-varying wrench ``(N, 3)`` or ``None``; ``iterations``,
    ``near_lock`` ``(N,)`` arrays for the ``μ`` solve's Newton iterations
    (``-1``: the friction locks) and near-lock flags (1.0).
    """
    samples = inputs[0].shape[0]
    width = max(1, min(chunk_size, samples))
    reactions = any(name in targets for name in ("n10", "m10", "n32", "m32"))
    state = np.empty((9, width))  # x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈ of one chunk, as rows
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        for start in range(0, samples, width):
            stop = min(start + width, samples)
            rows = state[:, : stop - start]
            for k, array in enumerate(inputs):
                np.copyto(rows[3 * k : 3 * k + 3], array[start:stop].T)
            wrench = None if load is None else tuple(load[start:stop].T)
            sol = kernel.solve(NUMPY, parameters, *rows, reactions=reactions, load=wrench)
            if sol.iterations is not None and iterations is not None:
                iterations[start:stop] = sol.iterations
            if sol.near_lock is not None and near_lock is not None:
                near_lock[start:stop] = sol.near_lock
            for name, target in targets.items():
                if name.startswith("fric"):
                    legs = (0.0, 0.0, 0.0) if sol.friction is None else getattr(sol.friction, name)
                else:
                    legs = getattr(sol, name)
                for leg in range(3):
                    target[start:stop, leg] = legs[leg]
