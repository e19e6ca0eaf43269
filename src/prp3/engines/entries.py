"""The validated entries of the kernel: a batch of samples, or one sample.

Each public function here validates its arguments once, through
:mod:`prp3.validation`, and hands the validated samples to an engine
(:mod:`prp3.engines.select`) that runs the one closed form of :mod:`prp3.mechanics.kernel`
(inverse geometry eq. 10, rates eqs. 14, 17, body wrenches eqs. 19–22,
virtual work eqs. 15, 16, 21, 23–25):

* :func:`paper_forces` — ``(N, 3)`` arrays in, ``(N, 3)`` arrays out;
  :func:`actuator_forces` the same for ``f10`` alone; :func:`solve_batch`
  every output of the kernel (and a time-varying load);
* :func:`sample_forces` — one sample, on a :class:`CompiledRobot` built once
  by :func:`compile_robot`; Python floats, ints, numpy scalars, lists and
  ``(3,)`` arrays alike; an optional time-varying load.
  :func:`sample_actuator_forces` the same for ``f10`` alone;
  :func:`sample_forces_unchecked` the unvalidated call for a control loop.

``engine`` of each: ``"numba"`` (the kernel compiled by numba: the default
when numba is installed), ``"numpy"`` (the kernel on numpy arrays), or
``None`` for the default (:func:`prp3.engines.select.default_engine`).  A robot with
joint friction runs on numpy (:func:`prp3.engines.select.runs_on`).  The engines
agree to round-off (tests: 1e-13 relative).

What is checked, in this order (the order of the reference path): the
inputs' types and shapes, their finiteness, the poses' bounds and
singularity (:func:`prp3.validation.check_pose_array`), the actuator strokes
(:func:`prp3.mechanics.geometry.check_stroke`); then, after the engine, the results'
finiteness (:func:`prp3.validation.require_finite`) and, with ``μ`` terms, a
self-locking joint.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Literal, NamedTuple, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.engines.select import (
    CHUNK,
    ENGINES,
    default_engine,
    numba_module,
    resolve_engine,
    run_numpy,
)
from prp3.errors import Prp3Error, TrajectoryError
from prp3.mechanics import kernel
from prp3.mechanics.geometry import check_stroke
from prp3.mechanics.joint_motion import kernel_geometry
from prp3.mechanics.ops import MATH, NUMPY
from prp3.mechanics.parameters import KernelParameters, kernel_parameters
from prp3.model.robot import Robot
from prp3.validation import (
    check_finite,
    check_integer,
    check_pose_array,
    check_real,
    check_robot,
    check_state_sample,
    require_finite,
)

__all__ = [
    "DEFAULT_CHUNK",
    "ENGINES",
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
#: The engine argument: ``"numba"``, ``"numpy"`` or ``None`` (the default engine).
Engine = Literal["numba", "numpy"] | None

#: Samples per chunk of the numpy engine (its work arrays stay in the CPU caches).
DEFAULT_CHUNK = CHUNK

#: The largest ``chunk_size``.
MAX_CHUNK = 10**6

#: Every per-leg output of the kernel, in the order of :class:`~prp3.mechanics.kernel.KernelSolution`.
KERNEL_OUTPUTS: tuple[str, ...] = kernel.KernelSolution._fields[:14]
_FORCES = ("f10", "p10", "f21y", "f21z")
#: The friction outputs of the kernel (with a robot's ``[friction]``).
FRICTION_OUTPUTS: tuple[str, ...] = ("fric10", "fric21", "fric32")
_REACTIONS = ("n10", "m10", "n32", "m32")
_INPUTS = ("pose", "velocity", "acceleration")

#: Names of the three columns of each input, for messages.
_COMPONENTS = (("x", "y", "phi"), ("dx", "dy", "dphi"), ("ddx", "ddy", "ddphi"))
_LOAD_COMPONENTS = ("fx", "fy", "mz")


@dataclass(frozen=True, eq=False)
class CompiledRobot:
    """A robot prepared for the kernel by :func:`compile_robot`; read-only.

    Attributes
    ----------
    robot : Robot
        The robot.
    parameters : KernelParameters
        Its constants as the kernel uses them.
    stroke : tuple of float or None
        ``robot.limits.stroke``.
    array : ndarray
        The fields of ``parameters`` as a float64 array (the numba engine's input).
    compiled_kernel : bool
        Whether the numba engine runs this robot (no joint friction):
        :func:`prp3.engines.select.runs_on`.
    """

    robot: Robot
    parameters: KernelParameters
    stroke: tuple[float, float] | None
    array: FloatArray
    compiled_kernel: bool

    def sample_function(self, engine: Engine = None) -> Callable[..., tuple[float, ...]]:
        """The unvalidated kernel of one sample: ``f(x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈)``.

        Returns the 12 floats ``f10, p10, f21y, f21z`` of legs A, B, C,
        followed by the 3 ``λ10`` when the robot has a stroke.  With ``μ``
        terms NaN where the friction locks.
        """
        return _unchecked(self, _engine(self, engine), f10_only=False)

    def actuator_sample_function(self, engine: Engine = None) -> Callable[..., tuple[float, ...]]:
        """:meth:`sample_function` for ``f10`` alone: ``f(x, …, φ̈)`` returns its 3 floats."""
        return _unchecked(self, _engine(self, engine), f10_only=True)


def _engine(compiled: CompiledRobot, engine: object) -> str:
    """The engine that runs ``compiled`` for the argument ``engine`` (validated)."""
    name = resolve_engine(engine)
    return name if compiled.compiled_kernel else "numpy"


def _unchecked(
    compiled: CompiledRobot, engine: str, f10_only: bool
) -> Callable[..., tuple[float, ...]]:
    array, params, stroke = compiled.array, compiled.parameters, compiled.stroke is not None
    numba = numba_module() if engine == "numba" else None
    if numba is not None:
        if f10_only:
            f10 = numba.sample_f10

            def numba_f10(*state: float) -> tuple[float, ...]:
                return f10(array, *state)  # type: ignore[no-any-return]

            return numba_f10
        forces, lam = numba.sample_forces, numba.lambda10_sample

        def numba_forces(*state: float) -> tuple[float, ...]:
            f = forces(array, *state)
            extra = lam(array, *state[:3]) if stroke else ()
            return (*f[0], *f[1], *f[2], *f[3], *extra)

        return numba_forces

    def floats(*state: float) -> tuple[float, ...]:
        sol = kernel.solve(MATH, params, *state, reactions=False)
        if sol.iterations is not None and sol.iterations < 0:
            return (math.nan,) * (3 if f10_only else 15 if stroke else 12)
        if f10_only:
            return tuple(sol.f10)
        return (*sol.f10, *sol.p10, *sol.f21y, *sol.f21z, *(sol.lambda10 if stroke else ()))

    return floats


def compile_robot(robot: Robot) -> CompiledRobot:
    """Prepare ``robot`` for :func:`paper_forces` and :func:`sample_forces` (compile once).

    Raises
    ------
    ParameterError
        If ``robot`` is not a :class:`~prp3.model.robot.Robot`.

    Examples
    --------
    >>> compiled = compile_robot(Robot())
    >>> compiled.parameters.platform_inertia
    0.0675
    """
    check_robot(robot)
    parameters = kernel_parameters(robot)
    array = np.array(
        [float(getattr(parameters, name)) for name in KernelParameters.__dataclass_fields__]
    )
    array.flags.writeable = False
    friction = robot.friction is not None or parameters.has_mu
    return CompiledRobot(robot, parameters, robot.limits.stroke, array, not friction)


def _compiled(robot: object) -> CompiledRobot:
    return robot if isinstance(robot, CompiledRobot) else compile_robot(robot)  # type: ignore[arg-type]


# ---------------------------------------------------------------------- batch
@dataclass(frozen=True)
class FastForces:
    """Actuator forces, input powers and joint forces from :func:`paper_forces`.

    Every array has the batch shape of the input and legs A, B, C last:
    ``(N, 3)``, or ``(3,)`` for a single sample.  Signs and units as in
    :class:`prp3.analysis.inverse_dynamics.InverseDynamics`.

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
    engine: Engine = None,
) -> FastForces:
    """Joint forces of the kernel (eqs. 10, 14, 17, 19–25) for a batch of samples.

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
        Samples per chunk of the numpy engine, from 1 to :data:`MAX_CHUNK`
        (its memory beyond inputs and outputs stays bounded).
    engine : {"numba", "numpy"} or None
        ``"numba"``: the kernel compiled by numba; ``"numpy"``: the kernel on
        numpy arrays; ``None``: :func:`prp3.engines.select.default_engine` (numba
        when installed).  The same numbers to round-off.

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
        As :func:`prp3.mechanics.geometry.inverse_geometry` (same messages and sample index).
    Prp3Error
        Bad ``out``, ``chunk_size`` or ``engine``.

    Examples
    --------
    >>> forces = paper_forces(Robot(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    >>> forces.f10.round(4).tolist()     # static central configuration
    [31.8589, -8.4957, -23.3632]
    """
    compiled = _compiled(robot)
    names = _FORCES + (_REACTIONS if reactions else ())
    flat, shape = _inputs(compiled, pose, velocity, acceleration)
    result = _outputs(out, names, shape)
    chunk, name = _chunk_size(chunk_size), _engine(compiled, engine)
    targets = {key: array.reshape(-1, 3) for key, array in result.items()}
    _run(compiled, name, flat, targets, chunk)
    return FastForces(**result)


def actuator_forces(
    robot: Robot | CompiledRobot,
    pose: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    *,
    out: FloatArray | None = None,
    chunk_size: int = DEFAULT_CHUNK,
    engine: Engine = None,
) -> FloatArray:
    """The actuator forces ``f10`` alone (eq. 23) for a batch of samples.

    :func:`paper_forces` without ``p10``, ``f21y`` and ``f21z``, for what needs
    only the drives' forces — a feed-forward, the sizing of the actuators, a
    design sweep.  The same validation, errors, chunks and engines as
    :func:`paper_forces`, and the same numbers.

    Parameters
    ----------
    robot, pose, velocity, acceleration, chunk_size, engine
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
    compiled = _compiled(robot)
    flat, shape = _inputs(compiled, pose, velocity, acceleration)
    f10 = np.empty(shape) if out is None else _out_array("out", out, shape)
    chunk, name = _chunk_size(chunk_size), _engine(compiled, engine)
    _run(compiled, name, flat, {"f10": f10.reshape(-1, 3)}, chunk)
    return f10


def solve_batch(
    robot: Robot | CompiledRobot,
    pose: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    *,
    chunk_size: int = DEFAULT_CHUNK,
    load: ArrayLike | None = None,
    engine: Engine = None,
) -> dict[str, FloatArray]:
    """Every output of the kernel for a batch of samples, validated: name → ``(N, 3)``.

    The names are :data:`KERNEL_OUTPUTS` (joint displacements, rates, forces
    and reactions), with a robot's ``[friction]`` also :data:`FRICTION_OUTPUTS`
    and, with ``μ`` terms, ``"iterations"`` (shape ``(N,)``: Newton
    iterations of each sample) and ``"near_lock"`` (shape ``(N,)``: 1.0 where
    the sample is near a lock, :data:`prp3.mechanics.implicit_friction.NEAR_LOCK_MU`, else 0.0);
    shapes as :func:`paper_forces`.  ``load``: the time-varying wrench
    ``(f_x, f_y, m_z)`` on the platform, shaped as ``pose``.  ``engine`` as
    :func:`paper_forces`.

    >>> sorted(solve_batch(Robot(), [0.0, 0.0, 0.0], [0, 0, 0], [0, 0, 0]))[:3]
    ['ddlambda10', 'ddlambda32', 'dlambda10']
    """
    compiled = _compiled(robot)
    flat, shape = _inputs(compiled, pose, velocity, acceleration)
    friction = compiled.robot.friction is not None
    names = KERNEL_OUTPUTS + (FRICTION_OUTPUTS if friction else ())
    block = np.empty((len(names), flat[0].shape[0], 3))  # (14, N, 3): the numba engine's output
    result = {key: block[k].reshape(shape) for k, key in enumerate(names)}
    wrench = None if load is None else _load(load, shape).reshape(-1, 3)
    chunk, name = _chunk_size(chunk_size), _engine(compiled, engine)
    targets = {key: block[k] for k, key in enumerate(names)}
    iterations = _run(compiled, name, flat, targets, chunk, wrench, block)
    if iterations is not None:
        result["iterations"], result["near_lock"] = (a.reshape(shape[:-1]) for a in iterations)
    return result


def _chunk_size(chunk_size: object) -> int:
    return check_integer("chunk_size", chunk_size, 1, MAX_CHUNK)


def _inputs(
    compiled: CompiledRobot, pose: ArrayLike, velocity: ArrayLike, acceleration: ArrayLike
) -> tuple[list[FloatArray], tuple[int, ...]]:
    """The three inputs as ``(N, 3)`` float64 arrays, validated, and their shape.

    In the reference's order: types and shapes, finiteness (pose, velocity,
    acceleration), the poses' bounds and singularity, the strokes.
    """
    arrays = [_as_samples(name, value) for name, value in zip(_INPUTS, (pose, velocity, acceleration), strict=True)]  # fmt: skip
    if not arrays[0].shape == arrays[1].shape == arrays[2].shape:
        shapes = ", ".join(f"{name} {a.shape}" for name, a in zip(_INPUTS, arrays, strict=True))
        raise TrajectoryError(
            f"pose, velocity and acceleration must have the same shape, got {shapes}"
        )
    for name, array, components in zip(_INPUTS, arrays, _COMPONENTS, strict=True):
        check_finite(name, array, components=components)
    if arrays[0].size:
        check_pose_array(arrays[0], compiled.robot, finite=True)
    flat = [a.reshape(-1, 3) for a in arrays]
    if compiled.stroke is not None and flat[0].shape[0]:
        check_stroke(compiled.robot, _lambda10(compiled, flat[0]), arrays[0])
    return flat, arrays[0].shape


def _lambda10(compiled: CompiledRobot, pose: FloatArray) -> FloatArray:
    """``λ10`` ``(N, 3)`` of validated poses (eq. 10), chunk by chunk: for the stroke check."""
    lam = np.empty_like(pose)
    for start in range(0, pose.shape[0], DEFAULT_CHUNK):
        rows = pose[start : start + DEFAULT_CHUNK]
        geo = kernel_geometry(NUMPY, compiled.parameters, *rows.T)
        for leg in range(3):
            lam[start : start + DEFAULT_CHUNK, leg] = geo.lambda10[leg]
    return lam


def _as_samples(name: str, value: ArrayLike) -> FloatArray:
    if type(value) is np.ndarray and value.dtype == np.float64:
        array = value  # what check_real accepts as it is; read, never written: no copy
    else:
        array = check_real(name, value)  # the one validation layer: booleans, text, None, ...
    if array.ndim not in (1, 2) or array.shape[-1] != 3:
        raise TrajectoryError(f"{name} must have shape (3,) or (N, 3), got {array.shape}")
    return array


def _load(load: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """The time-varying load ``(f_x, f_y, m_z)``, validated: real, shaped as the pose, finite."""
    wrench = _as_samples("load", load)
    if wrench.shape != shape:
        raise TrajectoryError(f"load must have the shape of pose {shape}, got {wrench.shape}")
    return check_finite("load", wrench, components=_LOAD_COMPONENTS)


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


def _run(
    compiled: CompiledRobot,
    engine: str,
    inputs: list[FloatArray],
    targets: dict[str, FloatArray],
    chunk_size: int,
    load: FloatArray | None = None,
    block: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray] | None:
    """Validated samples through ``engine`` into ``targets``; the results then checked.

    ``block``: the ``(14, N, 3)`` array under ``targets`` when they are
    :data:`KERNEL_OUTPUTS` (:func:`solve_batch`).

    Returns the ``μ`` solve's ``(iterations, near_lock)`` ``(N,)`` with ``μ``
    terms, else ``None``.  Raises TrajectoryError where a result is not
    finite or the friction locks.
    """
    samples = inputs[0].shape[0]
    mu = compiled.parameters.has_mu
    flags = (np.zeros(samples), np.zeros(samples)) if mu else None
    if not samples:
        return flags
    numba = numba_module() if engine == "numba" else None
    if numba is None:
        iterations, near_lock = flags if flags is not None else (None, None)
        run_numpy(
            compiled.parameters, inputs, targets, chunk_size=chunk_size, load=load,
            iterations=iterations, near_lock=near_lock,
        )  # fmt: skip
    else:
        _run_numba(numba, compiled.array, inputs, targets, load, block)
    require_finite(targets, (samples,), "motion")
    if flags is not None:
        locked = np.flatnonzero(flags[0] < 0)
        if locked.size:
            raise TrajectoryError(
                "the joint friction locks: no inverse dynamics reached continuously "
                "from mu = 0 (the friction cone of a joint swallows the drive: "
                "self-locking); lower the mu coefficients or change the motion",
                subject="motion",
                sample=int(locked[0]),
            )
    return flags


def _frozen(array: FloatArray) -> FloatArray:
    """A C-contiguous, read-only view of ``array`` (a copy only where it is not contiguous).

    numba compiles a loop once per argument type, and a read-only array is
    another type than a writable one: the same flags on every call keep one
    machine code per loop (each compile costs seconds).
    """
    view = np.ascontiguousarray(array).view()
    view.flags.writeable = False
    return view


def _run_numba(
    numba: Any,
    array: FloatArray,
    inputs: list[FloatArray],
    targets: dict[str, FloatArray],
    load: FloatArray | None,
    block: FloatArray | None,
) -> None:
    """The numba engine's loop for the outputs ``targets`` (C-contiguous inputs).

    On every thread from :data:`prp3.engines.numba.PARALLEL_MIN_SAMPLES` samples
    (:func:`prp3.engines.numba.batch_loops`), on one below.
    """
    pose, velocity, acceleration = (_frozen(a) for a in inputs)
    samples = pose.shape[0]
    loops = numba.batch_loops(samples)
    rows = (array, pose, velocity, acceleration, 0, samples)
    names = tuple(targets)
    if names == ("f10",):
        loops.f10(*rows, targets["f10"])
    elif names == _FORCES:
        loops.forces(*rows, *targets.values())
    elif names == _FORCES + _REACTIONS:
        loops.reactions(*rows, *targets.values())
    else:
        assert block is not None and names == KERNEL_OUTPUTS
        wrench = None if load is None else _frozen(load)
        loops.solve(*rows, wrench, block)


# -------------------------------------------------------------- single sample
#: One pose, velocity or acceleration: three numbers.
SampleInput = Sequence[float] | FloatArray


class SampleForces(NamedTuple):
    """Forces of one sample, each ``(A, B, C)``: eqs. (23), (24), (25) (N) and ``p10`` (W)."""

    f10: tuple[float, float, float]
    p10: tuple[float, float, float]
    f21y: tuple[float, float, float]
    f21z: tuple[float, float, float]


_new = tuple.__new__


def sample_forces(
    compiled: CompiledRobot,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
    load: SampleInput | None = None,
    *,
    engine: Engine = None,
) -> SampleForces:
    """Forces of one sample by the kernel, with plain floats.

    Validates its input (finite numbers, within the bounds, not singular,
    inside the stroke) and its result (finite) as :func:`paper_forces` does,
    with the same messages; Python floats, ints, numpy scalars, lists and
    ``(3,)`` arrays at the same cost.

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
    engine : {"numba", "numpy"} or None
        As :func:`paper_forces` (``"numpy"``: the kernel on Python floats).

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
    state, wrench, numba = _sample_inputs(compiled, pose, velocity, acceleration, load, engine)
    if numba is not None:
        if wrench is None:
            f = numba.sample_forces(compiled.array, *state)
        else:
            f = numba.sample_forces_loaded(compiled.array, *state, *wrench)
        a, b, c, d = f
        if math.isfinite(a[0] + a[1] + a[2] + b[0] + b[1] + b[2] + c[0] + c[1] + c[2] + d[0] + d[1] + d[2]):  # fmt: skip
            return _new(SampleForces, f)
        _overflow(dict(zip(_FORCES, f, strict=True)))
    sol = _sample_floats(compiled, state, wrench)
    return SampleForces(sol.f10, sol.p10, sol.f21y, sol.f21z)


def sample_actuator_forces(
    compiled: CompiledRobot,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
    load: SampleInput | None = None,
    *,
    engine: Engine = None,
) -> tuple[float, float, float]:
    """The actuator forces ``f10`` alone (eq. 23) of one sample, with plain floats.

    :func:`sample_forces` for what needs only the drives' forces (a
    feed-forward in a control loop): the same checks, errors and numbers.

    Parameters
    ----------
    compiled, pose, velocity, acceleration, load, engine
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
    state, wrench, numba = _sample_inputs(compiled, pose, velocity, acceleration, load, engine)
    if numba is not None:
        if wrench is None:
            f = numba.sample_f10(compiled.array, *state)
        else:
            f = numba.sample_f10_loaded(compiled.array, *state, *wrench)
        if math.isfinite(f[0] + f[1] + f[2]):
            return f  # type: ignore[no-any-return]
        _overflow({"f10": f})
    sol = _sample_floats(compiled, state, wrench)
    return (sol.f10[0], sol.f10[1], sol.f10[2])


def _sample_inputs(
    compiled: object,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
    load: SampleInput | None,
    engine: object,
) -> tuple[tuple[float, ...], tuple[float, float, float] | None, Any]:
    """One sample's nine floats, its load and the numba engine (``None``: the kernel on floats).

    Validated in the order of :func:`_inputs`.
    """
    if type(compiled) is not CompiledRobot:
        _not_compiled(compiled)
    state = check_state_sample(pose, velocity, acceleration, compiled.robot)
    wrench = None
    if load is not None:
        fx, fy, mz = _load(load, (3,)).tolist()
        wrench = (fx, fy, mz)
    name = default_engine() if engine is None else resolve_engine(engine)
    numba = numba_module() if name == "numba" and compiled.compiled_kernel else None
    stroke = compiled.stroke
    if stroke is not None:
        x, y, phi = state[:3]
        if numba is not None:
            lam = numba.lambda10_sample(compiled.array, x, y, phi)
        else:
            lam = kernel_geometry(MATH, compiled.parameters, x, y, phi).lambda10
        if not all(stroke[0] <= value <= stroke[1] for value in lam):
            check_stroke(compiled.robot, np.array(lam), np.array([x, y, phi]))
    return state, wrench, numba


def _sample_floats(
    compiled: CompiledRobot, state: tuple[float, ...], load: tuple[float, float, float] | None
) -> kernel.KernelSolution:
    """One validated sample by the kernel on Python floats; its results checked."""
    sol = kernel.solve(MATH, compiled.parameters, *state, reactions=False, load=load)
    if sol.iterations is not None and sol.iterations < 0:
        raise TrajectoryError(
            "the joint friction locks: no inverse dynamics reached continuously "
            "from mu = 0 (the friction cone of a joint swallows the drive: "
            "self-locking); lower the mu coefficients or change the motion",
            subject="motion",
            sample=0,
        )
    values = (*sol.f10, *sol.p10, *sol.f21y, *sol.f21z)
    if not math.isfinite(sum(values)):
        _overflow({name: getattr(sol, name) for name in _FORCES})
    return sol


def _overflow(values: dict[str, Any]) -> NoReturn:
    """The error of :func:`paper_forces` for one sample's results that are not finite."""
    require_finite({name: np.array([legs]) for name, legs in values.items()}, (1,), "motion")
    raise AssertionError("results reported not finite are finite")  # pragma: no cover


def _not_compiled(compiled: object) -> NoReturn:
    raise Prp3Error(f"compiled must come from compile_robot(robot), got {type(compiled).__name__}")


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
    """The kernel of one sample with NO validation, for a control loop (the default engine).

    The caller guarantees finite floats and ``|sin(φ − π/3)| >= 1e-4``; a
    singular pose gives huge or infinite numbers, a pose outside the stroke
    is not noticed.  For many calls, take :meth:`CompiledRobot.sample_function`
    once.

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
    state = (x, y, phi, dx, dy, dphi, ddx, ddy, ddphi)
    return compiled.sample_function()(*(float(v) for v in state))
