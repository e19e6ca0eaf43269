"""The fast paths of the kernel: a batch path and a single-sample path.

Both run the one closed form of :mod:`prp3.kernel` (inverse geometry eq. 10,
conditions of connectivity eqs. 14, 17, body wrenches eqs. 19–22 and virtual
work eqs. 15, 16, 21, 23–25):

* :func:`paper_forces` — ``(N, 3)`` arrays in, ``(N, 3)`` arrays out: the
  kernel traced into numpy ufunc calls on :data:`DEFAULT_CHUNK` samples at a
  time (memory bounded for any N), or compiled by numba
  (``backend="numba"``); :func:`actuator_forces` the same for ``f10`` alone.
* :func:`sample_forces` — one sample with plain floats, on a
  :class:`CompiledRobot` built once by :func:`compile_robot`: the kernel traced
  once into straight-line code (:mod:`prp3._trace`) that performs the kernel's
  own floating-point operations in the kernel's order, with the checks of the
  batch path written into it; an optional time-varying load.
  :func:`sample_actuator_forces` the same for ``f10`` alone.
  :func:`sample_forces_unchecked` is its inner function for a control loop
  that has validated its input already.

The two paths agree to round-off (the same operations; only ``cos`` and
``sin`` of numpy and of :mod:`math` may differ in the last bit).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Literal, NamedTuple, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import kernel
from ._trace import array_function, loop_source, non_finite_reach, scalar_function
from .errors import Prp3Error, TrajectoryError
from .geometry import inverse_geometry as _inverse_geometry
from .model import Robot
from .validation import (
    MAX_ORIENTATION,
    POSE_BOUND,
    SINGULARITY_THRESHOLD,
    check_choice,
    check_finite,
    check_integer,
    check_poses,
    check_real,
    require_finite,
)

__all__ = [
    "DEFAULT_CHUNK",
    "FRICTION_OUTPUTS",
    "KERNEL_OUTPUTS",
    "MAX_CHUNK",
    "CompiledRobot",
    "FastForces",
    "SampleForces",
    "actuator_forces",
    "compile_robot",
    "paper_forces",
    "sample_actuator_forces",
    "sample_forces",
    "sample_forces_unchecked",
    "solve_batch",
]

FloatArray = NDArray[np.float64]

#: Samples per chunk of the batch path (its work arrays stay in the CPU caches).
DEFAULT_CHUNK = 8192

#: Up to this many samples (without reactions) :func:`paper_forces` loops over
#: the single-sample function: below it numpy's per-call overhead dominates.
_FEW_SAMPLES = 16

#: Until this many samples have been computed for a robot whose batch code is
#: not built yet, the kernel runs on numpy directly: tracing (about 15 ms)
#: would cost more than it saves; then the batch code is traced (once).
_TRACE_SAMPLES = 20_000

#: Every per-leg output of the kernel, in the order of :class:`~prp3.kernel.KernelSolution`.
KERNEL_OUTPUTS: tuple[str, ...] = kernel.KernelSolution._fields[:14]
_FORCES = ("f10", "p10", "f21y", "f21z")
#: The friction outputs of the kernel (with a robot's ``[friction]``).
FRICTION_OUTPUTS: tuple[str, ...] = ("fric10", "fric21", "fric32")
_REACTIONS = ("n10", "m10", "n32", "m32")
_INPUTS = ("pose", "velocity", "acceleration")

#: Names of the three columns of each input, for messages.
_COMPONENTS = (("x", "y", "phi"), ("dx", "dy", "dphi"), ("ddx", "ddy", "ddphi"))


@dataclass(frozen=True, eq=False)
class CompiledRobot:
    """A robot prepared for the fast paths by :func:`compile_robot`; read-only.

    Attributes
    ----------
    robot : Robot
        The robot.
    parameters : KernelParameters
        Its constants as the kernel uses them.
    stroke : tuple of float or None
        ``robot.limits.stroke``.
    """

    robot: Robot
    parameters: kernel.KernelParameters
    stroke: tuple[float, float] | None

    @cached_property
    def sample_function(self) -> Callable[..., tuple[float, ...]]:
        """The kernel traced into straight-line float code (built on first use).

        ``f(x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈)`` returns the 12 floats ``f10, p10,
        f21y, f21z`` of legs A, B, C, followed by the 3 ``λ10`` when the robot
        has a stroke (for the check).  Its source is its ``__doc__``.  The
        constant load and the viscous and Coulomb friction are in the traced
        code; with ``μ`` terms (implicit) it is the kernel on floats with its
        Newton solve (NaN where the friction locks).
        """
        return self._unchecked(f10_only=False)

    @cached_property
    def actuator_sample_function(self) -> Callable[..., tuple[float, ...]]:
        """:attr:`sample_function` for ``f10`` alone: ``f(x, …, φ̈)`` returns its 3 floats.

        The kernel traced for ``f10`` only (the same operations for ``f10``,
        fewer in all), for a control loop that needs only the drives' forces.
        """
        return self._unchecked(f10_only=True)

    def _unchecked(self, f10_only: bool) -> Callable[..., tuple[float, ...]]:
        params, stroke = self.parameters, self.stroke is not None and not f10_only

        def forces(sol: kernel.KernelSolution) -> tuple[kernel.Value, ...]:
            if f10_only:
                return tuple(sol.f10)
            return (*sol.f10, *sol.p10, *sol.f21y, *sol.f21z, *(sol.lambda10 if stroke else ()))

        if params.has_mu:  # implicit friction: the kernel on floats, with its Newton solve

            def implicit(*state: float) -> tuple[float, ...]:
                sol = kernel.solve(kernel.MATH, params, *state, reactions=False)
                if sol.iterations is not None and sol.iterations < 0:
                    return (math.nan,) * (3 if f10_only else 15 if stroke else 12)
                return forces(sol)

            return implicit

        def outputs(ops: kernel.Ops, *state: kernel.Value) -> tuple[kernel.Value, ...]:
            return forces(kernel.solve(ops, params, *state, reactions=False))

        name = "sample_actuator_forces_kernel" if f10_only else "sample_forces_kernel"
        return scalar_function(outputs, kernel.STATE_SYMBOLS, name)

    @cached_property
    def checked_function(self) -> Callable[..., SampleForces | None]:
        """:func:`sample_forces`' traced kernel with its checks (built on first use).

        ``f(pose, velocity, acceleration)``, each a tuple, list or ``(3,)``
        ndarray of three floats, returns the :class:`SampleForces`, or
        ``None`` where :func:`paper_forces` could refuse the sample: a value
        that is not a float (an int, a boolean, text: the batch path's checks
        decide), a pose beyond the bounds of
        :func:`~prp3.validation.check_poses` or not finite, a velocity or
        acceleration not finite, ``|sin(φ − π/3)|`` below the singularity
        threshold (tested before the kernel divides by it), ``λ10`` outside
        the stroke, a result that is not finite.  An input that is not three
        values raises TypeError or ValueError.  Its source is its ``__doc__``.
        """
        return self._checked(loaded=False)

    @cached_property
    def loaded_function(self) -> Callable[..., SampleForces | None]:
        """:attr:`checked_function` with a time-varying load (built on first use).

        ``f(pose, velocity, acceleration, load)``: the wrench ``load = (f_x,
        f_y, m_z)`` of the environment on the platform (as ``load`` of
        :func:`solve_batch`) is three more traced inputs; ``None`` also where
        the load is not finite.
        """
        return self._checked(loaded=True)

    @cached_property
    def actuator_function(self) -> Callable[..., tuple[float, float, float] | None]:
        """:attr:`checked_function` for ``f10`` alone (:func:`sample_actuator_forces`).

        ``f(pose, velocity, acceleration)`` returns ``(f10_A, f10_B, f10_C)``
        or ``None``, with the same checks, from the kernel traced for ``f10``
        only.  Its source is its ``__doc__``.
        """
        return self._checked(loaded=False, f10_only=True)

    @cached_property
    def loaded_actuator_function(self) -> Callable[..., tuple[float, float, float] | None]:
        """:attr:`actuator_function` with a time-varying load, as :attr:`loaded_function`."""
        return self._checked(loaded=True, f10_only=True)

    def _checked(self, loaded: bool, f10_only: bool = False) -> Callable[..., Any]:
        params, stroke = self.parameters, self.stroke
        reach = POSE_BOUND * self.robot.l0
        arguments = kernel.STATE_SYMBOLS + (_LOAD_SYMBOLS if loaded else ())
        sequences = _INPUTS + (("load",) if loaded else ())
        # tuples and lists of floats as they are, a (3,) ndarray by ``tolist`` (floats, or
        # ints, booleans, ... that the type test sends to the batch path's checks)
        prologue = [
            f"if type({name}) is not tuple:\n"
            f"    if type({name}) is ndarray:\n        {name} = {name}.tolist()\n"
            f"    elif type({name}) is not list:\n        return None"
            for name in sequences
        ]
        prologue += [
            f"{', '.join(arguments[3 * k : 3 * k + 3])} = {name}"
            for k, name in enumerate(sequences)
        ]
        prologue.append(
            "if not (" + " and ".join(f"type({a}) is float" for a in arguments) + "):\n"
            "    return None"
        )
        singular = f"-{SINGULARITY_THRESHOLD!r} < {{}} < {SINGULARITY_THRESHOLD!r}"
        outside = "" if stroke is None else f"not {stroke[0]!r} <= {{}} <= {stroke[1]!r}"
        checks = 1 if stroke is None else 4
        if params.has_mu:  # implicit friction: the kernel on floats with its Newton solve
            return _implicit_checked(self, loaded, f10_only)

        def outputs(ops: kernel.Ops, *values: kernel.Value) -> tuple[kernel.Value, ...]:
            state, load = values[:9], (values[9:] if loaded else None)
            geo = kernel.kernel_geometry(ops, params, *state[:3])
            sol = kernel.solve(ops, params, *state, reactions=False, load=load)
            lam = sol.lambda10 if stroke is not None else ()
            forces = sol.f10 if f10_only else (*sol.f10, *sol.p10, *sol.f21y, *sol.f21z)
            return (geo.D, *lam, *forces)

        # comparisons rather than calls (cheaper in CPython); NaN fails every comparison, and
        # 0·s == 0 says that the sum s is finite (a sum that overflows goes the slow way).
        # A rate (or load) whose non-finite value always reaches a result is checked with
        # the results (non_finite_reach), the others on entry.
        shown = _shown_inputs(outputs, len(arguments), checks)
        rates = [a for k, a in enumerate(arguments) if k >= 3 and k not in shown]
        entry = (
            f"not (-{reach!r} <= x <= {reach!r} and -{reach!r} <= y <= {reach!r}"
            f" and -{MAX_ORIENTATION!r} <= phi <= {MAX_ORIENTATION!r}"
            + (f" and 0.0 * ({' + '.join(rates)}) == 0.0)" if rates else ")")
        )
        f = [f"{{{checks + k}}}" for k in range(3 if f10_only else 12)]
        returns = "new(SampleForces, (({}, {}, {}), ({}, {}, {}), ({}, {}, {}), ({}, {}, {})))"
        name = ("sample_actuator_forces" if f10_only else "sample_forces") + "_checked"
        return scalar_function(
            outputs, arguments, name + ("_loaded" if loaded else ""),
            entry=[entry],
            checks={0: singular, **{k: outside for k in range(1, checks)}},
            final=f"0.0 * ({' + '.join(f)}) != 0.0",
            returns=("({}, {}, {})" if f10_only else returns).format(*f),
            namespace={"new": tuple.__new__, "SampleForces": SampleForces, "ndarray": np.ndarray},
            parameters=sequences, prologue=prologue,
        )  # fmt: skip

    def batch_function(self, names: tuple[str, ...]) -> Callable[..., None]:
        """The kernel traced into numpy ufunc calls on work rows (built once per ``names``).

        ``f(x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈, out)`` of 1-D arrays writes ``sin(φ − π/3)``,
        then ``λ10`` of the three legs when the robot has a stroke (for the
        checks), then the three legs of each of ``names`` (fields of
        :class:`~prp3.kernel.KernelSolution`).  Its source is its ``__doc__``.
        """
        cache: dict[tuple[str, ...], Callable[..., None]]
        cache = self.__dict__.setdefault("_batch_functions", {})
        if names not in cache:
            cache[names] = array_function(
                self._outputs(names), kernel.STATE_SYMBOLS, "batch_kernel"
            )
        return cache[names]

    def numba_function(self, names: tuple[str, ...]) -> Callable[..., None]:
        """The outputs of :meth:`batch_function` by the kernel's scalar code compiled by numba.

        ``f(pose, velocity, acceleration, checks, *targets)``: the inputs
        ``(n, 3)`` as given, ``checks`` ``(1 or 4, n)`` (``sin(φ − π/3)``, and
        ``λ10`` with a stroke), one ``(n, 3)`` target per name, written in
        place; the same straight-line code as the single-sample path, in a
        loop that numba compiles to machine code (built once per ``names``;
        compiling takes about a second).  Its source is its ``source``
        attribute.
        """
        cache: dict[tuple[str, ...], Callable[..., None]]
        cache = self.__dict__.setdefault("_numba_functions", {})
        if names not in cache:
            try:
                import numba
            except ImportError:
                raise Prp3Error(
                    'backend="numba" needs numba, which is not installed: pip install "prp3[numba]"'
                ) from None
            checks = 1 if self.stroke is None else 4
            sources = [f"{array}[i, {k}]" for array in _INPUTS for k in range(3)]
            targets = [f"checks[{k}, i]" for k in range(checks)]
            targets += [f"{name}_[i, {leg}]" for name in names for leg in range(3)]
            source = loop_source(
                self._outputs(names), kernel.STATE_SYMBOLS, "batch_kernel_loop",
                parameters=(*_INPUTS, "checks", *(f"{name}_" for name in names)),
                sources=sources, targets=targets,
            )  # fmt: skip
            namespace: dict[str, Any] = {"cos": math.cos, "sin": math.sin, "sqrt": math.sqrt,
                                         "tanh": math.tanh, "abs": abs}  # fmt: skip
            exec(compile(source, "<prp3 kernel: numba loop>", "exec"), namespace)
            function = numba.njit(error_model="numpy")(namespace["batch_kernel_loop"])
            function.source = source  # type: ignore[attr-defined]
            cache[names] = function
        return cache[names]

    def results_check_rates(self, names: tuple[str, ...]) -> bool:
        """Whether a non-finite velocity or acceleration always gives a non-finite result.

        True when every component of ``velocity`` and ``acceleration`` reaches
        one of the outputs ``names`` through operations that keep an infinity
        or a NaN (:func:`prp3._trace.non_finite_reach`): the finiteness check
        of the results then also checks these inputs, and the batch path reads
        them once less.  It would be False where a rate entered the results only
        through the sign or ``tanh`` of a friction law (it enters the inertia
        terms of every robot with positive masses).
        """
        cache: dict[tuple[str, ...], bool] = self.__dict__.setdefault("_results_check_rates", {})
        if names not in cache:
            checks = 4 if self.stroke is not None else 1
            shown = _shown_inputs(self._outputs(names), len(kernel.STATE_SYMBOLS), checks)
            cache[names] = set(range(3, 9)) <= shown
        return cache[names]

    def _outputs(self, names: tuple[str, ...]) -> Callable[..., tuple[kernel.Value, ...]]:
        """The function of the kernel that the batch paths trace (see :meth:`batch_function`)."""
        params, stroke = self.parameters, self.stroke is not None
        reactions = any(name in _REACTIONS for name in names)

        def outputs(ops: kernel.Ops, *state: kernel.Value) -> tuple[kernel.Value, ...]:
            geo = kernel.kernel_geometry(ops, params, *state[:3])
            sol = kernel.solve(ops, params, *state, reactions=reactions)
            checks = (geo.D, *(sol.lambda10 if stroke else ()))
            return (*checks, *(v for name in names for v in _field(sol, name)))

        return outputs


def _shown_inputs(
    function: Callable[..., tuple[kernel.Value, ...]], arity: int, checks: int
) -> frozenset[int]:
    """The inputs whose non-finite value always makes a result non-finite.

    The results are the outputs of ``function`` after its first ``checks``
    (the singularity measure and the strokes, which are not tested for
    finiteness); see :func:`prp3._trace.non_finite_reach`.
    """
    return frozenset().union(*non_finite_reach(function, arity)[checks:])


def _field(sol: kernel.KernelSolution, name: str) -> kernel.Legs:
    """The three legs of output ``name`` of a kernel solution (friction included)."""
    if name in FRICTION_OUTPUTS:
        if sol.friction is None:
            return (0.0, 0.0, 0.0)
        return tuple(getattr(sol.friction, name))
    return tuple(getattr(sol, name))


def compile_robot(robot: Robot) -> CompiledRobot:
    """Prepare ``robot`` for :func:`paper_forces` and :func:`sample_forces` (compile once).

    Raises
    ------
    Prp3Error
        If ``robot`` is not a :class:`~prp3.model.Robot`.

    Examples
    --------
    >>> compiled = compile_robot(Robot())
    >>> compiled.parameters.platform_inertia
    0.0675
    """
    if not isinstance(robot, Robot):
        raise Prp3Error(f"robot must be a prp3.Robot, got {type(robot).__name__}")
    return CompiledRobot(robot, kernel.kernel_parameters(robot), robot.limits.stroke)


# ---------------------------------------------------------------------- batch
@dataclass(frozen=True)
class FastForces:
    """Actuator forces, input powers and joint forces from :func:`paper_forces`.

    Every array has the batch shape of the input and legs A, B, C last:
    ``(N, 3)``, or ``(3,)`` for a single sample.  Signs and units as in
    :class:`prp3.dynamics.InverseDynamics`.

    Attributes
    ----------
    f10 : ndarray
        Force of actuator i on its piston along ``+e_i`` (N), eq. (23).
    p10 : ndarray
        Input power ``f10·λ̇10`` (W).
    f21y, f21z : ndarray
        Force of piston i on link 2 along ``n_i`` and ``e_i`` (N), eqs. (24), (25).
    n10, m10, n32, m32 : ndarray or None
        The other reactions (N, N·m), or ``None`` unless ``reactions=True``.
    """

    f10: FloatArray
    p10: FloatArray
    f21y: FloatArray
    f21z: FloatArray
    n10: FloatArray | None = None
    m10: FloatArray | None = None
    n32: FloatArray | None = None
    m32: FloatArray | None = None


def paper_forces(
    robot: Robot | CompiledRobot,
    pose: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    *,
    reactions: bool = False,
    out: FastForces | None = None,
    chunk_size: int = DEFAULT_CHUNK,
    backend: Literal["numpy", "numba"] = "numpy",
) -> FastForces:
    """Joint forces of the kernel (eqs. 10, 14, 17, 19–25) for a batch of samples.

    Computed in chunks of ``chunk_size`` samples: memory beyond inputs and
    outputs stays bounded.  Up to 16 samples without ``reactions`` are
    computed one by one by the single-sample function.

    Parameters
    ----------
    robot : Robot or CompiledRobot
        The robot (compiled on the fly when a :class:`Robot` is given).
    pose, velocity, acceleration : array_like, shape (N, 3) or (3,)
        ``(x, y, φ)``, ``(ẋ, ẏ, φ̇)``, ``(ẍ, ÿ, φ̈)`` of the platform (SI units, rad).
    reactions : bool
        Also compute ``n10, m10, n32, m32``.
    out : FastForces, optional
        Arrays to write into (C-contiguous float64 of the output shape; with
        ``reactions=True`` the reaction arrays too).  They are returned.  If
        an error is raised, their content is unspecified.
    chunk_size : int
        Samples per chunk, from 1 to :data:`MAX_CHUNK`.
    backend : {"numpy", "numba"}
        ``"numpy"``: the kernel traced into numpy ufunc calls (the default
        install); ``"numba"``: the kernel's scalar code compiled by numba
        (the ``numba`` extra; the same operations, several times faster).

    Returns
    -------
    FastForces
        Arrays ``(N, 3)``, or ``(3,)`` for a single sample.

    Raises
    ------
    TrajectoryError
        Shapes differ or are not ``(N, 3)``/``(3,)``, a value is not finite,
        or a result overflows.
    SingularPoseError, UnreachablePoseError
        As :func:`prp3.geometry.inverse_geometry` (same messages and sample index).
    Prp3Error
        Bad ``out`` or ``chunk_size``.

    Examples
    --------
    >>> forces = paper_forces(Robot(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    >>> forces.f10.round(4).tolist()     # static central configuration
    [31.8589, -8.4957, -23.3632]
    """
    compiled = robot if isinstance(robot, CompiledRobot) else compile_robot(robot)
    names = _FORCES + (_REACTIONS if reactions else ())
    flat, shape = _inputs(pose, velocity, acceleration)
    result = _outputs(out, names, shape)
    samples, chunk, engine = flat[0].shape[0], _chunk_size(chunk_size), _backend(backend)
    targets = {name: array.reshape(-1, 3) for name, array in result.items()}
    if samples and not reactions and samples <= _FEW_SAMPLES:
        _sample_table(compiled, flat, targets)
    elif samples:
        _compute(compiled, flat, targets, chunk, engine)
    return FastForces(**result)


def actuator_forces(
    robot: Robot | CompiledRobot,
    pose: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    *,
    out: FloatArray | None = None,
    chunk_size: int = DEFAULT_CHUNK,
    backend: Literal["numpy", "numba"] = "numpy",
) -> FloatArray:
    """The actuator forces ``f10`` alone (eq. 23) for a batch of samples.

    :func:`paper_forces` without ``p10``, ``f21y`` and ``f21z``: the kernel
    traced for ``f10`` only (about a fifth fewer operations, and one output
    array), for what needs only the drives' forces — a feed-forward, the
    sizing of the actuators, a design sweep.  The same validation, errors,
    chunks and backends as :func:`paper_forces`, and the same numbers.

    Parameters
    ----------
    robot, pose, velocity, acceleration, chunk_size, backend
        As :func:`paper_forces`.
    out : ndarray, optional
        A writeable C-contiguous float64 array of the output shape to write
        into (returned).

    Returns
    -------
    ndarray
        ``f10`` (N), ``(N, 3)``, or ``(3,)`` for a single sample.

    Examples
    --------
    >>> actuator_forces(Robot(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]).round(4)
    array([ 31.8589,  -8.4957, -23.3632])
    """
    compiled = robot if isinstance(robot, CompiledRobot) else compile_robot(robot)
    flat, shape = _inputs(pose, velocity, acceleration)
    f10 = np.empty(shape) if out is None else _out_array("out", out, shape)
    samples, chunk, engine = flat[0].shape[0], _chunk_size(chunk_size), _backend(backend)
    targets = {"f10": f10.reshape(-1, 3)}
    if samples and samples <= _FEW_SAMPLES:
        _sample_table(compiled, flat, targets)
    elif samples:
        _compute(compiled, flat, targets, chunk, engine)
    return f10


def solve_batch(
    robot: Robot | CompiledRobot,
    pose: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    *,
    chunk_size: int = DEFAULT_CHUNK,
    load: ArrayLike | None = None,
) -> dict[str, FloatArray]:
    """Every output of the kernel for a batch of samples, validated: name → ``(N, 3)``.

    The names are :data:`KERNEL_OUTPUTS` (joint displacements, rates, forces
    and reactions), with a robot's ``[friction]`` also :data:`FRICTION_OUTPUTS`
    and, with ``μ`` terms, ``"iterations"`` (shape ``(N,)``: Newton
    iterations of each sample) and ``"near_lock"`` (shape ``(N,)``: 1.0 where
    the sample is near a lock, :data:`prp3.kernel.NEAR_LOCK_MU`, else 0.0);
    shapes as :func:`paper_forces`.  ``load``:
    the time-varying wrench ``(f_x, f_y, m_z)`` on the platform, shaped as
    ``pose``.

    >>> sorted(solve_batch(Robot(), [0.0, 0.0, 0.0], [0, 0, 0], [0, 0, 0]))[:3]
    ['ddlambda10', 'ddlambda32', 'dlambda10']
    """
    compiled = robot if isinstance(robot, CompiledRobot) else compile_robot(robot)
    flat, shape = _inputs(pose, velocity, acceleration)
    friction = compiled.robot.friction is not None
    result = _outputs(None, KERNEL_OUTPUTS + (FRICTION_OUTPUTS if friction else ()), shape)
    wrench = None
    if load is not None:
        wrench = _load(load, shape).reshape(-1, 3)
    implicit = compiled.parameters.has_mu
    iterations = np.zeros(shape[:-1]) if implicit else None
    near_lock = np.zeros(shape[:-1]) if implicit else None
    if flat[0].shape[0]:
        targets = {name: array.reshape(-1, 3) for name, array in result.items()}
        _compute(
            compiled, flat, targets, _chunk_size(chunk_size), load=wrench,
            mu_iterations=None if iterations is None else iterations.reshape(-1),
            mu_near_lock=None if near_lock is None else near_lock.reshape(-1),
        )  # fmt: skip
    if iterations is not None and near_lock is not None:
        result["iterations"] = iterations
        result["near_lock"] = near_lock
    return result


def _backend(backend: object) -> str:
    return check_choice("backend", backend, ("numpy", "numba"))


#: The largest ``chunk_size``: work rows of at most about 200 MB.
MAX_CHUNK = 10**6


def _chunk_size(chunk_size: object) -> int:
    return check_integer("chunk_size", chunk_size, 1, MAX_CHUNK)


def _inputs(
    pose: ArrayLike, velocity: ArrayLike, acceleration: ArrayLike
) -> tuple[list[FloatArray], tuple[int, ...]]:
    arrays = [_as_samples(name, value) for name, value in _named(pose, velocity, acceleration)]
    if not arrays[0].shape == arrays[1].shape == arrays[2].shape:
        shapes = ", ".join(f"{name} {a.shape}" for name, a in zip(_INPUTS, arrays, strict=True))
        raise TrajectoryError(
            f"pose, velocity and acceleration must have the same shape, got {shapes}"
        )
    return [a.reshape(-1, 3) for a in arrays], arrays[0].shape


def _named(*values: ArrayLike) -> zip[tuple[str, ArrayLike]]:
    return zip(_INPUTS, values, strict=True)


def _as_samples(name: str, value: ArrayLike) -> FloatArray:
    if type(value) is np.ndarray and value.dtype == np.float64:
        array = value  # what check_real accepts as it is; read, never written: no copy
    else:
        array = check_real(name, value)  # the one validation layer: booleans, text, None, ...
    if array.ndim not in (1, 2) or array.shape[-1] != 3:
        raise TrajectoryError(f"{name} must have shape (3,) or (N, 3), got {array.shape}")
    return array


def _outputs(
    out: FastForces | None, names: tuple[str, ...], shape: tuple[int, ...]
) -> dict[str, FloatArray]:
    if out is None:
        # one block: large enough for numpy to ask for huge pages (fewer page faults)
        block = np.empty((len(names), *shape))
        return dict(zip(names, block, strict=True))
    if not isinstance(out, FastForces):
        raise Prp3Error(f"out must be a FastForces, got {type(out).__name__}")
    return {name: _out_array(f"out.{name}", getattr(out, name), shape) for name in names}


def _out_array(label: str, array: object, shape: tuple[int, ...]) -> FloatArray:
    """``array`` if it can take an output of ``shape``, else a Prp3Error naming ``label``."""
    if (
        not isinstance(array, np.ndarray)
        or array.dtype != np.float64
        or array.shape != shape
        or not array.flags.c_contiguous
        or not array.flags.writeable
    ):
        described = (
            "None" if array is None else f"{type(array).__name__} {getattr(array, 'shape', '')}"
        )
        raise Prp3Error(
            f"{label} must be a writeable C-contiguous float64 array of shape {shape}, "
            f"got {described}"
        )
    return array


def _compute(
    compiled: CompiledRobot,
    inputs: list[FloatArray],
    targets: dict[str, FloatArray],
    chunk_size: int,
    backend: str = "numpy",
    load: FloatArray | None = None,
    mu_iterations: FloatArray | None = None,
    mu_near_lock: FloatArray | None = None,
) -> None:
    """The kernel on chunks of samples into ``targets`` (name → ``(N, 3)``); validated.

    The numpy backend writes each output straight into its column of the
    target; the numba backend into a block, then copied.  ``load``: the
    time-varying wrench ``(N, 3)`` on the platform, or ``None``;
    ``mu_iterations``: an ``(N,)`` array for the Newton iterations of the
    ``μ`` terms, ``mu_near_lock`` one for their near-lock flags (1.0).  With
    either, the kernel runs on numpy arrays directly
    (:func:`_compute_direct`).
    """
    samples = inputs[0].shape[0]
    traced = tuple(targets) in compiled.__dict__.get("_batch_functions", {})
    # samples computed so far without the traced code: once they add up to
    # _TRACE_SAMPLES, tracing (once) costs less than it saves
    direct = compiled.__dict__.get("_direct_samples", 0) + samples
    if (
        load is not None
        or compiled.parameters.has_mu
        or (backend == "numpy" and direct < _TRACE_SAMPLES and not traced)
    ):  # a few samples of a new robot: tracing would cost more than it saves
        compiled.__dict__["_direct_samples"] = direct
        _compute_direct(compiled, inputs, targets, chunk_size, load, mu_iterations, mu_near_lock)
        return
    width = min(chunk_size, samples)
    names = tuple(targets)
    checks = 4 if compiled.stroke is not None else 1
    scratch = np.empty((checks, width))
    state = np.empty((9, width))  # the numpy backend's inputs of one chunk, as rows
    numpy_function = compiled.batch_function(names) if backend == "numpy" else None
    numba_function = compiled.numba_function(names) if backend == "numba" else None
    # the rates are checked with the results when a non-finite rate shows there
    rates = () if compiled.results_check_rates(names) else inputs[1:]
    if not _finite(*rates) or _beyond(inputs[0], POSE_BOUND * compiled.robot.l0):
        _raise_input_error(compiled, inputs, samples)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        for start in range(0, samples, width):
            stop = min(start + width, samples)
            n = stop - start
            if numpy_function is not None:
                # the inputs copied into contiguous rows once (the kernel reads most of
                # them several times), the outputs written straight into their columns
                rows = state[:, :n]
                for k, array in enumerate(inputs):
                    np.copyto(rows[3 * k : 3 * k + 3], array[start:stop].T)
                columns = [
                    target[start:stop, leg] for target in targets.values() for leg in range(3)
                ]
                numpy_function(*rows, [*scratch[:checks, :n], *columns])
            else:
                assert numba_function is not None
                numba_function(
                    *(array[start:stop] for array in inputs), scratch[:, :n],
                    *(target[start:stop] for target in targets.values()),
                )  # fmt: skip
            measure = np.absolute(scratch[0, :n], scratch[0, :n])  # |sin(φ − π/3)|, in place
            if float(measure.min()) < SINGULARITY_THRESHOLD or (
                compiled.stroke is not None and _outside(scratch[1:4, :n], compiled.stroke)
            ):
                _raise_input_error(compiled, inputs, stop)
    _require_finite_results(targets, inputs)


def _compute_direct(
    compiled: CompiledRobot,
    inputs: list[FloatArray],
    targets: dict[str, FloatArray],
    chunk_size: int,
    load: FloatArray | None = None,
    mu_iterations: FloatArray | None = None,
    mu_near_lock: FloatArray | None = None,
) -> None:
    """:func:`_compute` by the kernel on numpy arrays (a time-varying load, ``μ`` terms).

    Raises TrajectoryError naming the first sample whose friction self-locks.
    """
    samples = inputs[0].shape[0]
    width = min(chunk_size, samples)
    reactions = any(name in targets for name in _REACTIONS)
    state = np.empty((9, width))  # x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈ of one chunk, as rows
    params, stroke = compiled.parameters, compiled.stroke
    reach = POSE_BOUND * compiled.robot.l0
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        for start in range(0, samples, width):
            stop = min(start + width, samples)
            rows = state[:, : stop - start]
            for k, array in enumerate(inputs):
                np.copyto(rows[3 * k : 3 * k + 3], array[start:stop].T)
            x, y, phi, dx, dy, dphi, ddx, ddy, ddphi = rows
            if not np.isfinite(rows).all() or _beyond(rows[:3].T, reach):
                _raise_input_error(compiled, inputs, stop)
            geo = kernel.kernel_geometry(kernel.NUMPY, params, x, y, phi)
            if float(np.abs(geo.D).min()) < SINGULARITY_THRESHOLD or (
                stroke is not None and _outside(geo.lambda10, stroke)
            ):
                _raise_input_error(compiled, inputs, stop)
            kin = kernel.kernel_kinematics(params, geo, dx, dy, dphi, ddx, ddy, ddphi)
            wrench = (
                None
                if load is None
                else (load[start:stop, 0], load[start:stop, 1], load[start:stop, 2])
            )
            f10, f21y, f21z, rest, friction, iterations, near_lock = kernel.dynamics(
                kernel.NUMPY, params, kin, ddx, ddy, dphi, ddphi, reactions=reactions, load=wrench
            )
            values = {"f10": f10, "f21y": f21y, "f21z": f21z}
            values["p10"] = tuple(f * v for f, v in zip(f10, kin.dlambda10, strict=True))
            if rest is not None:
                values.update(zip(_REACTIONS, rest, strict=True))
            if friction is not None:
                values.update(zip(FRICTION_OUTPUTS, friction, strict=True))
            else:  # a [friction] table of zeros
                values.update(dict.fromkeys(FRICTION_OUTPUTS, (0.0, 0.0, 0.0)))
            if iterations is not None:
                locked = np.flatnonzero(np.asarray(iterations) < 0)
                if locked.size:
                    raise TrajectoryError(
                        "the joint friction locks: no inverse dynamics reached continuously "
                        "from mu = 0 (the friction cone of a joint swallows the drive: "
                        "self-locking); lower the mu coefficients or change the motion",
                        subject="motion",
                        sample=start + int(locked[0]),
                    )
                if mu_iterations is not None:
                    mu_iterations[start:stop] = iterations
                if mu_near_lock is not None:
                    mu_near_lock[start:stop] = near_lock
            for name in ("lambda10", "lambda32"):
                values[name] = getattr(geo, name)
            for name in ("dlambda10", "ddlambda10", "dlambda32", "ddlambda32"):
                values[name] = getattr(kin, name)
            for name, target in targets.items():
                for leg in range(3):
                    target[start:stop, leg] = values[name][leg]
    _require_finite_results(targets, inputs)


def _finite(*arrays: FloatArray) -> bool:
    """Whether every value of ``arrays`` is finite (a finite sum of their sums says so).

    One pass over each array; the exact test only when the sum is not finite
    (a value that is not, or a sum that overflows).
    """
    with np.errstate(over="ignore", invalid="ignore"):
        total = sum(float(np.add.reduce(array, axis=None)) for array in arrays)
    return math.isfinite(total) or all(bool(np.isfinite(array).all()) for array in arrays)


def _beyond(pose: FloatArray, reach: float) -> bool:
    """Whether poses ``(N, 3)`` leave the bounds of :func:`prp3.validation.check_poses`.

    Also true for a pose that is not finite.  The common case in two passes:
    every coordinate within the smaller of the two bounds.
    """
    largest = max(-float(pose.min()), float(pose.max()))  # NaN if a value is NaN
    if largest <= min(reach, MAX_ORIENTATION):
        return False
    return not (
        float(np.abs(pose[:, :2]).max()) <= reach
        and float(np.abs(pose[:, 2]).max()) <= MAX_ORIENTATION
    )


def _outside(lambda10: Any, stroke: tuple[float, float]) -> bool:
    lower, upper = stroke
    return any(float(lam.min()) < lower or float(lam.max()) > upper for lam in lambda10)


def _require_finite_results(targets: dict[str, FloatArray], inputs: list[FloatArray]) -> None:
    """A TrajectoryError naming the first non-finite input, else the first overflowed result."""
    if _finite(*targets.values()):
        return
    for name, array, components in zip(_INPUTS, inputs, _COMPONENTS, strict=True):
        check_finite(name, array, components=components)
    require_finite(targets, (inputs[0].shape[0],), "motion")


def _raise_input_error(compiled: CompiledRobot, inputs: list[FloatArray], stop: int) -> None:
    """Raise the error the reference path raises for these inputs (chunks up to ``stop``).

    In the reference's order: non-finite values, singular poses (anywhere),
    then actuator strokes.
    """
    for name, array, components in zip(_INPUTS, inputs, _COMPONENTS, strict=True):
        check_finite(name, array, components=components)
    check_poses(inputs[0], compiled.robot)  # beyond the bounds, singular: as the reference
    _inverse_geometry(compiled.robot, inputs[0][:stop])  # UnreachablePoseError, as the reference
    raise AssertionError("a chunk failed a check that the reference passes")  # pragma: no cover


# -------------------------------------------------------------- single sample
#: One pose, velocity or acceleration: three numbers.
SampleInput = Sequence[float] | FloatArray


class SampleForces(NamedTuple):
    """Forces of one sample, each ``(A, B, C)``: eqs. (23), (24), (25) (N) and ``p10`` (W)."""

    f10: tuple[float, float, float]
    p10: tuple[float, float, float]
    f21y: tuple[float, float, float]
    f21z: tuple[float, float, float]


def sample_forces(
    compiled: CompiledRobot,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
    load: SampleInput | None = None,
) -> SampleForces:
    """Forces of one sample by the kernel, with plain floats.

    Validates its input (finite numbers, not singular, inside the stroke) and
    its result (finite) as :func:`paper_forces` does, in the traced kernel
    itself (:attr:`CompiledRobot.checked_function`); anything the traced
    checks do not pass is handed to the batch path, which refuses it with the
    batch path's message or computes it.

    Parameters
    ----------
    compiled : CompiledRobot
        From :func:`compile_robot` (compile once, call many times).
    pose, velocity, acceleration : sequence of 3 floats or ndarray (3,)
        ``(x, y, φ)``, ``(ẋ, ẏ, φ̇)``, ``(ẍ, ÿ, φ̈)`` (SI units, rad).
    load : sequence of 3 floats or ndarray (3,), optional
        A time-varying wrench ``(f_x, f_y, m_z)`` of the environment on the
        platform (force at ``G`` in the fixed frame, N; moment, N·m), as the
        ``load`` of :func:`solve_batch`; added to the robot's constant
        ``[load]``.

    Returns
    -------
    SampleForces
        ``f10``, ``p10``, ``f21y``, ``f21z`` of legs A, B, C (N, W).

    Raises
    ------
    TrajectoryError, SingularPoseError, UnreachablePoseError
        As :func:`paper_forces` (and :func:`solve_batch` for ``load``).

    Examples
    --------
    >>> compiled = compile_robot(Robot())
    >>> forces = sample_forces(compiled, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    >>> [round(f, 4) for f in forces.f10]
    [31.8589, -8.4957, -23.3632]
    >>> still = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    >>> pushed = sample_forces(compiled, *still, load=(0.0, -10.0, 0.0))  # 10 N downwards
    >>> [round(f, 4) for f in pushed.f10]
    [37.6324, -11.3825, -26.25]
    """
    if type(compiled) is not CompiledRobot:
        _not_compiled(compiled)
    try:  # the traced kernel with its checks: None (or an error) where it cannot decide
        if load is None:
            f = compiled.checked_function(pose, velocity, acceleration)
        else:
            f = compiled.loaded_function(pose, velocity, acceleration, load)
    except (ArithmeticError, TypeError, ValueError):
        f = None  # the batch path's checks decide (not three values, a division by zero, ...)
    if f is not None:
        return f
    return _sample_slow(compiled, pose, velocity, acceleration, load)


def _not_compiled(compiled: object) -> NoReturn:
    raise Prp3Error(f"compiled must come from compile_robot(robot), got {type(compiled).__name__}")


#: Names of the traced load's inputs (:attr:`CompiledRobot.loaded_function`).
_LOAD_SYMBOLS = ("fx", "fy", "mz")


def sample_actuator_forces(
    compiled: CompiledRobot,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
    load: SampleInput | None = None,
) -> tuple[float, float, float]:
    """The actuator forces ``f10`` alone (eq. 23) of one sample, with plain floats.

    :func:`sample_forces` for what needs only the drives' forces (a
    feed-forward in a control loop): the kernel traced for ``f10`` only
    (:attr:`CompiledRobot.actuator_function`), the same checks, errors and
    numbers.

    Parameters
    ----------
    compiled, pose, velocity, acceleration, load
        As :func:`sample_forces`.

    Returns
    -------
    tuple of 3 floats
        ``f10`` of legs A, B, C (N).

    Raises
    ------
    TrajectoryError, SingularPoseError, UnreachablePoseError
        As :func:`sample_forces`.

    Examples
    --------
    >>> compiled = compile_robot(Robot())
    >>> [round(f, 4) for f in sample_actuator_forces(compiled, (0.0, 0.0, 0.0), (0, 0, 0), (0, 0, 0))]
    [31.8589, -8.4957, -23.3632]
    """
    if type(compiled) is not CompiledRobot:
        _not_compiled(compiled)
    try:  # as sample_forces (written out in both: one Python call less on the hot path)
        if load is None:
            f = compiled.actuator_function(pose, velocity, acceleration)
        else:
            f = compiled.loaded_actuator_function(pose, velocity, acceleration, load)
    except (ArithmeticError, TypeError, ValueError):
        f = None
    if f is not None:
        return f
    return _sample_slow(compiled, pose, velocity, acceleration, load).f10


def _sample_slow(
    compiled: CompiledRobot,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
    load: SampleInput | None,
) -> SampleForces:
    """One sample by the batch path: its refusals and messages, or its forces."""
    arrays = [_as_samples(name, value) for name, value in _named(pose, velocity, acceleration)]
    for name, array in zip(_INPUTS, arrays, strict=True):
        if array.shape != (3,):
            raise TrajectoryError(f"{name} must be 3 numbers (shape (3,)), got shape {array.shape}")
    wrench = None if load is None else _load(load, (3,)).reshape(1, 3)
    targets = {name: np.empty((1, 3)) for name in _FORCES}
    _compute(compiled, [array[None, :] for array in arrays], targets, 1, load=wrench)
    f10, p10, f21y, f21z = (tuple(targets[name][0].tolist()) for name in _FORCES)
    return SampleForces(f10, p10, f21y, f21z)


def _load(load: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """The time-varying load ``(f_x, f_y, m_z)``, validated: real, shaped as the pose, finite."""
    wrench = _as_samples("load", load)
    if wrench.shape != shape:
        raise TrajectoryError(f"load must have the shape of pose {shape}, got {wrench.shape}")
    return check_finite("load", wrench, components=("fx", "fy", "mz"))


def _implicit_checked(
    compiled: CompiledRobot, loaded: bool, f10_only: bool = False
) -> Callable[..., Any]:
    """:meth:`CompiledRobot._checked` with ``μ`` terms: the kernel on floats with its Newton solve.

    ``None`` also where the friction locks (the batch path then names the sample).
    """
    params, stroke = compiled.parameters, compiled.stroke
    reach = POSE_BOUND * compiled.robot.l0

    def checked(*sequences: SampleInput) -> SampleForces | tuple[float, ...] | None:
        values = [v for seq in sequences for v in _plain_floats(seq)]
        if len(values) != 3 * len(sequences):
            return None
        x, y, phi = values[:3]
        if not (
            abs(x) <= reach
            and abs(y) <= reach
            and abs(phi) <= MAX_ORIENTATION
            and math.isfinite(sum(values[3:]))
        ):
            return None
        geo = kernel.kernel_geometry(kernel.MATH, params, x, y, phi)
        if not abs(geo.D) >= SINGULARITY_THRESHOLD:
            return None
        if stroke is not None and not all(stroke[0] <= lam <= stroke[1] for lam in geo.lambda10):
            return None
        load = (values[9], values[10], values[11]) if loaded else None
        sol = kernel.solve(kernel.MATH, params, *values[:9], reactions=False, load=load)
        if sol.iterations is not None and sol.iterations < 0:
            return None
        forces = SampleForces(sol.f10, sol.p10, sol.f21y, sol.f21z)
        if not math.isfinite(sum(sum(f) for f in forces)):
            return None
        return tuple(sol.f10) if f10_only else forces

    return checked


def _plain_floats(values: SampleInput) -> list[float]:
    """The three floats of a tuple, list or ``(3,)`` ndarray; ``[]`` for anything else."""
    if type(values) is np.ndarray:
        values = values.tolist()
    if type(values) not in (tuple, list) or len(values) != 3:
        return []
    return list(values) if all(type(v) is float for v in values) else []


def _sample_table(
    compiled: CompiledRobot, inputs: list[FloatArray], targets: dict[str, FloatArray]
) -> None:
    """Few samples: the single-sample function in a loop (numpy's call overhead dominates).

    With ``μ`` terms the kernel's Newton solve on numpy arrays takes the few
    samples at once, faster than one solve per sample on floats.
    """
    if compiled.parameters.has_mu and inputs[0].shape[0] > 1:
        _compute(compiled, inputs, targets, _FEW_SAMPLES)
        return
    checked = compiled.checked_function
    for k, (pose, velocity, acceleration) in enumerate(
        zip(*(array.tolist() for array in inputs), strict=True)
    ):
        try:
            f = checked(pose, velocity, acceleration)
        except ArithmeticError:
            f = None
        if f is None:
            _compute(compiled, inputs, targets, _FEW_SAMPLES)  # raises as the batch path does
            return
        for name, values in zip(_FORCES, f, strict=True):
            if name in targets:
                targets[name][k] = values


def sample_forces_unchecked(
    compiled: CompiledRobot,
    x: float,
    y: float,
    phi: float,
    dx: float,
    dy: float,
    dphi: float,
    ddx: float,
    ddy: float,
    ddphi: float,
) -> tuple[float, ...]:
    """Inner function of :func:`sample_forces`: NO validation, for a control loop.

    The caller guarantees finite floats and ``|sin(φ − π/3)| >= 1e-4``; a
    singular pose gives huge or infinite numbers or ZeroDivisionError, a pose
    outside the stroke is not noticed.

    Returns
    -------
    tuple of 12 floats
        ``f10_A, f10_B, f10_C`` (N), ``p10_A, p10_B, p10_C`` (W),
        ``f21y_A, f21y_B, f21y_C``, ``f21z_A, f21z_B, f21z_C`` (N)
        (and ``λ10`` of the three legs when the robot has a stroke).

    Examples
    --------
    >>> f = sample_forces_unchecked(compile_robot(Robot()), 0.0, 0.0, 0.0, 0, 0, 0, 0, 0, 0)
    >>> round(f[0], 4)
    31.8589
    """
    return compiled.sample_function(x, y, phi, dx, dy, dphi, ddx, ddy, ddphi)
