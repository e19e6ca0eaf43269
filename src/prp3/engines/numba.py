"""The numba engine: the kernel's own functions compiled to machine code (internal).

Nothing here is written twice: every function of the kernel's stages
(:data:`STAGE_MODULES`: :mod:`prp3.mechanics.joint_motion`,
:mod:`prp3.mechanics.wrenches`, :mod:`prp3.mechanics.virtual_work`) is compiled
by numba from its own bytecode (:func:`_compiled_kernel`), with the functions
of :mod:`math` as its :class:`~prp3.mechanics.ops.Ops` and the robot's
constants as one numpy record of the fields of
:class:`~prp3.mechanics.parameters.KernelParameters`
(:data:`~prp3.engines.compiled_robot.PARAMETER_RECORD`, read where it lies,
so that one compiled function serves every robot).  The loops below
only call the kernel's stages in the order of :func:`prp3.mechanics.kernel.solve` —
:func:`~prp3.mechanics.joint_motion.kernel_geometry`,
:func:`~prp3.mechanics.joint_motion.kernel_kinematics`,
:func:`~prp3.mechanics.wrenches.body_wrenches`,
:func:`~prp3.mechanics.virtual_work.joint_forces` — and store what they
return.  What the kernel does not write on plain floats (the friction laws,
the implicit ``μ`` solve) is not compiled: the numpy engine runs it
(:mod:`prp3.engines.select`).

A batch of :data:`PARALLEL_MIN_SAMPLES` samples or more runs on every thread
of numba's threading layer (:func:`batch_loops`: the ``*_parallel`` loops,
``parallel=True``, ``prange`` over blocks of :data:`BLOCK` samples, each block
one call of the loop on one thread, so that the numbers are those of one
thread), a smaller one on the calling thread (waking the threads would cost
more than they save).  The layer must be thread-safe (:data:`THREAD_SAFE_LAYERS`:
the explorer's server, dask's threads or a user's threads may call at once;
numba's ``workqueue`` aborts the process then): :func:`parallel_layer` asks
numba for one, and without one the batches run on one thread, said once by an
:class:`~prp3.engines.select.EngineWarning`.  ``numba.set_num_threads`` sets
the threads of the calling thread's batches.

The machine code is cached on disk (``cache=True``: in ``__pycache__`` beside
this file where it is writable, else numba's user cache directory, or
``NUMBA_CACHE_DIR``), so the compile cost (about two seconds per function)
is paid once per installation.  The cache is keyed on the source of this
file *and* of every module whose functions it compiles or whose layout it
reads (:data:`KERNEL_SOURCES`, :class:`_KernelStamp`): a change of any of
them recompiles.

The engine does not validate: its callers (:mod:`prp3.engines.entries`) pass finite,
non-singular samples.  Division by a zero is IEEE's (``error_model="numpy"``).
"""

from __future__ import annotations

import math
import os
import threading
import types
import warnings
from collections import namedtuple
from typing import Any, NamedTuple

import numba
from numba.core import caching

from prp3.engines.compiled_robot import PARAMETER_RECORD
from prp3.engines.select import EngineWarning
from prp3.mechanics import joint_motion, parameters, virtual_work, wrenches
from prp3.model import joint_elements

__all__ = [
    "KERNEL_SOURCES",
    "MACHINE_CODE",
    "PARALLEL_MIN_SAMPLES",
    "STAGE_MODULES",
    "THREAD_SAFE_LAYERS",
    "BatchLoops",
    "batch_loops",
    "f10_loop",
    "f10_loop_parallel",
    "forces_loop",
    "forces_loop_parallel",
    "lambda10_sample",
    "machine_code",
    "parallel_layer",
    "reactions_loop",
    "reactions_loop_parallel",
    "sample_f10",
    "sample_f10_loaded",
    "sample_forces",
    "sample_forces_loaded",
    "solve_loop",
    "solve_loop_parallel",
]

# ------------------------------------------------------------------ the cache
#: The modules whose functions :func:`_compiled_kernel` compiles (the kernel's stages).
#: :mod:`prp3.model.joint_elements` gives the force of its elements that the kernel applies
#: (:func:`~prp3.model.joint_elements.spring_force`).
STAGE_MODULES: tuple[types.ModuleType, ...] = (joint_elements, joint_motion, wrenches, virtual_work)
#: The source files the cached machine code depends on besides this one: the stages and
#: :mod:`prp3.mechanics.parameters` (the fields, in order, of the record they read).
KERNEL_SOURCES: tuple[str, ...] = tuple(
    str(module.__file__) for module in (*STAGE_MODULES, parameters)
)


class _KernelStamp:
    """A cache locator whose stamp is this file's and those of :data:`KERNEL_SOURCES`.

    numba stamps a cached function with its own source file only; the loops
    here inline the kernel's stages, so a change of any of their files must
    invalidate them too.
    """

    def get_source_stamp(self) -> Any:
        stamp = super().get_source_stamp()  # type: ignore[misc]
        return (stamp, *(_source_stamp(path) for path in KERNEL_SOURCES))

    @classmethod
    def from_function(cls, py_func: Any, py_file: str) -> Any:
        if os.path.abspath(py_file) != os.path.abspath(__file__):
            return None
        return super().from_function(py_func, py_file)  # type: ignore[misc]


def _source_stamp(path: str) -> Any:
    """numba's stamp of the source file ``path`` (its modification time and size)."""
    st = os.stat(path)
    return caching._hash_source_file(path, st.st_mtime, st.st_size)


def _install_locators() -> None:
    """Put the :class:`_KernelStamp` locators first in numba's list (once)."""
    impl = caching.CacheImpl
    if any(issubclass(c, _KernelStamp) for c in impl._locator_classes):
        return
    ours: list[type] = [
        type(f"Kernel{base.__name__}", (_KernelStamp, base), {"__module__": __name__})
        for base in (
            caching.UserProvidedCacheLocator,
            caching.InTreeCacheLocator,
            caching.UserWideCacheLocator,
        )
    ]
    impl._locator_classes = [*ours, *impl._locator_classes]  # type: ignore[list-item]


_install_locators()


# ------------------------------------------------------- the kernel, compiled
def _inline(function: Any) -> Any:
    return numba.njit(inline="always")(function)


def _cos(value: float) -> float:
    return math.cos(value)


def _sin(value: float) -> float:
    return math.sin(value)


def _sqrt(value: float) -> float:
    return math.sqrt(value)


def _tanh(value: float) -> float:
    return math.tanh(value)


def _abs(value: float) -> float:
    return abs(value)


def _sign(value: float) -> float:
    return float((value > 0.0) - (value < 0.0))


def _zero(value: float) -> bool:
    return value == 0.0


_Ops = namedtuple("_Ops", ("name", "cos", "sin", "sqrt", "tanh", "abs", "sign"))


def _compiled_kernel() -> types.ModuleType:
    """Every function of :data:`STAGE_MODULES`, compiled by numba from its own bytecode.

    Each function is rebuilt from its code object with one namespace, that of
    the stages together, in which their names are the compiled functions,
    ``_zero`` tests a float (numba has no ``isinstance`` of unions) and
    :data:`OPS` is :mod:`math`'s.  Compilation is lazy: only what the loops
    call is compiled.
    """
    module = types.ModuleType("prp3.kernel_numba")
    namespace = module.__dict__
    for stage in STAGE_MODULES:
        namespace.update(vars(stage))
    for stage in STAGE_MODULES:
        for name, value in vars(stage).items():
            if isinstance(value, types.FunctionType) and value.__module__ == stage.__name__:
                clone = types.FunctionType(
                    value.__code__, namespace, value.__name__, value.__defaults__, value.__closure__
                )
                clone.__kwdefaults__ = value.__kwdefaults__
                namespace[name] = _inline(clone)
    namespace["_zero"] = _inline(_zero)
    return module


_kernel = _compiled_kernel()
OPS = _Ops(
    "numba", *(_inline(f) for f in (_cos, _sin, _sqrt, _tanh, _abs, _sign))
)  # the kernel's Ops on floats, for numba


# ------------------------------------------------------------------ the stages
@numba.njit(inline="always")
def _parameters(array: Any) -> Any:
    """The kernel's parameters: the one record of :data:`~prp3.engines.compiled_robot.PARAMETER_RECORD`.

    Its fields are read where they lie (a named tuple built from a float64
    array copied them all at every single-sample call: half of its machine
    code's time).
    """
    return array[0]


@numba.njit(inline="always")
def _solve(k: Any, x: float, y: float, phi: float, dx: float, dy: float, dphi: float,
           ddx: float, ddy: float, ddphi: float, load: Any, reactions: bool) -> Any:  # fmt: skip
    """:func:`prp3.mechanics.kernel.solve` without joint friction: its stages in its order."""
    geo = _kernel.kernel_geometry(OPS, k, x, y, phi)
    kin = _kernel.kernel_kinematics(k, geo, dx, dy, dphi, ddx, ddy, ddphi)
    # load, friction, inertia: numba's inliner binds keyword-only arguments by position
    w = _kernel.body_wrenches(k, kin, ddx, ddy, dphi, ddphi, load, None, True)
    f10, f21y, f21z, rest = _kernel.joint_forces(k, kin, w, reactions)
    return kin, f10, f21y, f21z, rest


@numba.njit(inline="always")
def _store(target: Any, i: int, legs: Any) -> None:
    target[i, 0] = legs[0]
    target[i, 1] = legs[1]
    target[i, 2] = legs[2]


@numba.njit(inline="always")
def _power(f10: Any, rate: Any) -> Any:
    return (f10[0] * rate[0], f10[1] * rate[1], f10[2] * rate[2])  # p10 = f10·λ̇10


@numba.njit(inline="always")
def _solve_row(k: Any, pose: Any, velocity: Any, acceleration: Any, i: int, load: Any,
               reactions: bool) -> Any:  # fmt: skip
    """:func:`_solve` of the sample ``i`` of the arrays ``(n, 3)``."""
    return _solve(
        k, pose[i, 0], pose[i, 1], pose[i, 2], velocity[i, 0], velocity[i, 1], velocity[i, 2],
        acceleration[i, 0], acceleration[i, 1], acceleration[i, 2], load, reactions,
    )  # fmt: skip


@numba.njit(inline="always")
def _store_forces(f10: Any, p10: Any, f21y: Any, f21z: Any, i: int, kin: Any, f: Any, fy: Any,
                  fz: Any) -> None:  # fmt: skip
    """Row ``i`` of ``f10``, ``p10 = f10·λ̇10``, ``f21y``, ``f21z``."""
    _store(f10, i, f)
    _store(p10, i, _power(f, kin.dlambda10))
    _store(f21y, i, fy)
    _store(f21z, i, fz)


@numba.njit(inline="always")
def _store_reactions(n10: Any, m10: Any, n32: Any, m32: Any, i: int, rest: Any) -> None:
    """Row ``i`` of the reactions ``n10, m10, n32, m32``."""
    _store(n10, i, rest[0])
    _store(m10, i, rest[1])
    _store(n32, i, rest[2])
    _store(m32, i, rest[3])


# ---------------------------------------------------------------- the threads
#: Samples from which a batch runs on every thread (:func:`batch_loops`): below, waking the
#: threads costs more than they save (and on a machine whose cores are busy, a thread may
#: wait for one longer than the whole batch takes on the calling thread).
PARALLEL_MIN_SAMPLES = 4096
#: The threading layers of numba whose parallel loops may be called from several Python
#: threads at once (the explorer's server, dask's threads, a user's); ``workqueue`` may not.
THREAD_SAFE_LAYERS: tuple[str, ...] = ("tbb", "omp")

_UNSET: Any = object()
_layer: Any = _UNSET
_NUMBA: Any = numba  # its threading functions and config, as numba documents them
_layer_lock = threading.Lock()


def parallel_layer() -> str | None:
    """The thread-safe threading layer the parallel loops run on, or ``None``: one thread.

    Started on the first call (once per process) with numba's choice among
    :data:`THREAD_SAFE_LAYERS` (``"threadsafe"``) unless the user chose a layer
    (``NUMBA_THREADING_LAYER``) or started one before; a layer that is not
    thread-safe, or none at all, leaves the batches on one thread, said once by
    an :class:`~prp3.engines.select.EngineWarning`.  A process forked from one
    that started the threads runs on one thread (GNU OpenMP is not fork-safe).
    """
    global _layer
    if _layer is _UNSET:
        with _layer_lock:
            if _layer is _UNSET:
                _layer = _start_layer()
    return _layer  # type: ignore[no-any-return]


def _start_layer() -> str | None:
    try:
        layer: str | None = _NUMBA.threading_layer()  # started before: as it is
    except ValueError:  # not started yet
        requested = _NUMBA.config.THREADING_LAYER
        if requested == "default":  # not the user's choice: a thread-safe one
            _NUMBA.config.THREADING_LAYER = "threadsafe"
        try:
            _NUMBA.get_num_threads()  # starts the layer
            layer = _NUMBA.threading_layer()
        except ValueError:  # no such layer could be loaded
            layer = None
        finally:
            _NUMBA.config.THREADING_LAYER = requested
    if layer in THREAD_SAFE_LAYERS:
        return layer
    warnings.warn(
        f"numba's threading layer {layer or 'tbb or omp'!r} is not thread-safe or not "
        "available: prp3's batches run on one thread; pip install tbb (or a GNU OpenMP) "
        "for every core",
        EngineWarning,
        stacklevel=4,
    )
    return None


def _after_fork_in_child() -> None:
    """A child of a process whose threads run: one thread (GNU OpenMP is not fork-safe)."""
    global _layer
    try:
        _NUMBA.threading_layer()
    except ValueError:  # no threads before the fork: the child may start its own
        return
    _layer = None


os.register_at_fork(after_in_child=_after_fork_in_child)


# ------------------------------------------------------------------- batches
@numba.njit(cache=True, error_model="numpy")
def f10_loop(a: Any, pose: Any, velocity: Any, acceleration: Any, start: int, stop: int,
             f10: Any) -> None:  # pragma: no cover  # fmt: skip
    """``f10`` ``(n, 3)`` of the samples ``start:stop`` of ``(n, 3)``, written into ``f10``."""
    k = _parameters(a)
    for i in range(start, stop):
        _, f, _, _, _ = _solve_row(k, pose, velocity, acceleration, i, None, False)
        _store(f10, i, f)


@numba.njit(cache=True, error_model="numpy")
def forces_loop(a: Any, pose: Any, velocity: Any, acceleration: Any, start: int, stop: int,
                f10: Any, p10: Any, f21y: Any, f21z: Any) -> None:  # pragma: no cover  # fmt: skip
    """``f10, p10, f21y, f21z`` ``(n, 3)`` of the samples ``start:stop``, written into them."""
    k = _parameters(a)
    for i in range(start, stop):
        kin, f, fy, fz, _ = _solve_row(k, pose, velocity, acceleration, i, None, False)
        _store_forces(f10, p10, f21y, f21z, i, kin, f, fy, fz)


@numba.njit(cache=True, error_model="numpy")
def reactions_loop(a: Any, pose: Any, velocity: Any, acceleration: Any, start: int, stop: int,
                   f10: Any, p10: Any, f21y: Any, f21z: Any, n10: Any, m10: Any, n32: Any,
                   m32: Any) -> None:  # pragma: no cover  # fmt: skip
    """:func:`forces_loop` and the reactions ``n10, m10, n32, m32``."""
    k = _parameters(a)
    for i in range(start, stop):
        kin, f, fy, fz, rest = _solve_row(k, pose, velocity, acceleration, i, None, True)
        _store_forces(f10, p10, f21y, f21z, i, kin, f, fy, fz)
        _store_reactions(n10, m10, n32, m32, i, rest)


@numba.njit(cache=True, error_model="numpy")
def solve_loop(a: Any, pose: Any, velocity: Any, acceleration: Any, start: int, stop: int,
               load: Any, out: Any) -> None:  # pragma: no cover  # fmt: skip
    """Every output of :class:`~prp3.mechanics.kernel.KernelSolution` up to ``m32``: ``out`` ``(14, n, 3)``.

    ``load`` ``(n, 3)``: the time-varying wrench on the platform, or ``None``.
    """
    k = _parameters(a)
    for i in range(start, stop):
        if load is None:
            kin, f, fy, fz, rest = _solve_row(k, pose, velocity, acceleration, i, None, True)
        else:
            wrench = (load[i, 0], load[i, 1], load[i, 2])
            kin, f, fy, fz, rest = _solve_row(k, pose, velocity, acceleration, i, wrench, True)
        geo = kin.geometry
        _store(out[0], i, geo.lambda10)
        _store(out[1], i, kin.dlambda10)
        _store(out[2], i, kin.ddlambda10)
        _store(out[3], i, geo.lambda32)
        _store(out[4], i, kin.dlambda32)
        _store(out[5], i, kin.ddlambda32)
        _store_forces(out[6], out[7], out[8], out[9], i, kin, f, fy, fz)
        _store_reactions(out[10], out[11], out[12], out[13], i, rest)


#: Samples per call of a loop above by its parallel loop (the share of one thread at a time).
BLOCK = 512


def _blocks(a: Any, pose: Any, velocity: Any, acceleration: Any, start: int, stop: int,
            *outputs: Any) -> None:  # pragma: no cover  # fmt: skip
    """The loop ``_loop`` on the samples ``start:stop``, block by block on every thread."""
    for b in numba.prange((stop - start + BLOCK - 1) // BLOCK):
        first = start + b * BLOCK
        last = min(stop, first + BLOCK)
        _loop(a, pose, velocity, acceleration, first, last, *outputs)  # type: ignore[name-defined]  # noqa: F821


def _parallel(loop: Any) -> Any:
    """``loop`` on every thread: :func:`_blocks` compiled with ``parallel=True`` for it.

    Each block is one call of ``loop`` (numba's analysis of parallel loops does
    not follow the kernel's tuples inlined), so each sample is computed by the
    same machine code as on one thread.  Compiled from a copy of :func:`_blocks`
    named ``<loop>_parallel`` (numba names a cache entry after its function).
    """
    name = f"{loop.py_func.__name__}_parallel"
    function = types.FunctionType(_blocks.__code__, {**globals(), "_loop": loop}, name)
    function.__qualname__ = name
    function.__doc__ = f":func:`{loop.py_func.__name__}` on every thread, block by block."
    return numba.njit(cache=True, error_model="numpy", parallel=True)(function)


f10_loop_parallel = _parallel(f10_loop)
forces_loop_parallel = _parallel(forces_loop)
reactions_loop_parallel = _parallel(reactions_loop)
solve_loop_parallel = _parallel(solve_loop)


class BatchLoops(NamedTuple):
    """The four batch loops of one kind (:func:`batch_loops`)."""

    f10: Any
    forces: Any
    reactions: Any
    solve: Any


def batch_loops(samples: int) -> BatchLoops:
    """The loops that run a batch of ``samples`` samples: on every thread, or on one.

    On every thread of numba's threading layer (the ``*_parallel`` loops) when
    ``samples >= PARALLEL_MIN_SAMPLES`` and the layer is thread-safe
    (:func:`parallel_layer`), else on the calling thread alone (:func:`f10_loop`,
    ...).  The choice is a function of ``samples`` and of what the process
    offers, never of earlier calls; both kinds give the same numbers (each
    sample is computed alone, by the same machine code).
    """
    if samples >= PARALLEL_MIN_SAMPLES and parallel_layer() is not None:
        return BatchLoops(
            f10_loop_parallel, forces_loop_parallel, reactions_loop_parallel, solve_loop_parallel
        )
    return BatchLoops(f10_loop, forces_loop, reactions_loop, solve_loop)


# ------------------------------------------------------------- single samples
@numba.njit(cache=True, error_model="numpy")
def sample_forces(a: Any, x: float, y: float, phi: float, dx: float, dy: float, dphi: float,
                  ddx: float, ddy: float, ddphi: float) -> Any:  # pragma: no cover  # fmt: skip
    """``(f10, p10, f21y, f21z)`` of one sample, each ``(A, B, C)``."""
    k = _parameters(a)
    kin, f, fy, fz, _ = _solve(k, x, y, phi, dx, dy, dphi, ddx, ddy, ddphi, None, False)
    return f, _power(f, kin.dlambda10), fy, fz


@numba.njit(cache=True, error_model="numpy")
def sample_forces_loaded(a: Any, x: float, y: float, phi: float, dx: float, dy: float,
                         dphi: float, ddx: float, ddy: float, ddphi: float, fx: float,
                         fy: float, mz: float) -> Any:  # pragma: no cover  # fmt: skip
    """:func:`sample_forces` with a time-varying load ``(f_x, f_y, m_z)`` on the platform."""
    k = _parameters(a)
    kin, f, f21y, f21z, _ = _solve(k, x, y, phi, dx, dy, dphi, ddx, ddy, ddphi, (fx, fy, mz), False)
    return f, _power(f, kin.dlambda10), f21y, f21z


@numba.njit(cache=True, error_model="numpy")
def sample_f10(a: Any, x: float, y: float, phi: float, dx: float, dy: float, dphi: float,
               ddx: float, ddy: float, ddphi: float) -> Any:  # pragma: no cover  # fmt: skip
    """``f10`` ``(A, B, C)`` of one sample."""
    k = _parameters(a)
    return _solve(k, x, y, phi, dx, dy, dphi, ddx, ddy, ddphi, None, False)[1]


@numba.njit(cache=True, error_model="numpy")
def sample_f10_loaded(a: Any, x: float, y: float, phi: float, dx: float, dy: float,
                      dphi: float, ddx: float, ddy: float, ddphi: float, fx: float, fy: float,
                      mz: float) -> Any:  # pragma: no cover  # fmt: skip
    """:func:`sample_f10` with a time-varying load ``(f_x, f_y, m_z)`` on the platform."""
    k = _parameters(a)
    return _solve(k, x, y, phi, dx, dy, dphi, ddx, ddy, ddphi, (fx, fy, mz), False)[1]


@numba.njit(cache=True, error_model="numpy")
def lambda10_sample(a: Any, x: float, y: float, phi: float) -> Any:  # pragma: no cover
    """``λ10`` ``(A, B, C)`` of one pose (eq. 10), for the stroke check."""
    return _kernel.kernel_geometry(OPS, _parameters(a), x, y, phi).lambda10


# ------------------------------------------------------------- machine code
#: The numba type of the parameter array of :func:`~prp3.engines.compiled_robot.compile_robot`
#: (one aligned record, C-contiguous, read-only): the first argument of every single-sample
#: function.
_ARRAY_TYPE = numba.types.Array(numba.from_dtype(PARAMETER_RECORD), 1, "C", readonly=True)

#: The machine code of the single-sample functions, by function: :func:`machine_code`.
MACHINE_CODE: dict[Any, Any] = {}


def machine_code(function: Any) -> Any:
    """The machine code of a single-sample function, for a parameter array and floats.

    Called directly, the compiled code skips the dispatcher's resolution of
    each argument's type (a third of a single-sample call).  Only for the
    arguments of that type: the read-only record array of
    :func:`~prp3.engines.compiled_robot.compile_robot` (which
    :class:`~prp3.engines.compiled_robot.CompiledRobot` checks) and Python
    floats.  Until the function is compiled for them (its first call), and
    for anything that is not a numba function, ``function`` itself; once
    found, the code is kept in :data:`MACHINE_CODE`.
    """
    overloads = getattr(function, "overloads", None)
    code = getattr(getattr(function, "py_func", None), "__code__", None)
    if overloads is None or code is None:
        return function
    compiled = overloads.get((_ARRAY_TYPE, *(numba.float64,) * (code.co_argcount - 1)))
    if compiled is None:
        return function
    MACHINE_CODE[function] = compiled.entry_point
    return compiled.entry_point
