"""The validated entries of the kernel for a batch of samples.

Each public function here validates its arguments once, through the
validation layer (:mod:`prp3.validation`, :mod:`prp3.pose_validation`), and
hands the validated samples to an engine (:mod:`prp3.engines.select`) that
runs the one closed form of :mod:`prp3.mechanics.kernel` (inverse geometry
eq. 10, rates eqs. 14, 17, body wrenches eqs. 19–22, virtual work eqs. 15,
16, 21, 23–25): :func:`paper_forces` — ``(N, 3)`` arrays in, ``(N, 3)``
arrays out; :func:`actuator_forces` the same for ``f10`` alone;
:func:`solve_batch` every output of the kernel (and a time-varying load).
One sample is :mod:`prp3.engines.sample_entries`; the robot is prepared once
by :func:`~prp3.engines.compiled_robot.compile_robot`.

``engine`` of each: ``"numba"`` (the kernel compiled by numba: the default
when numba is installed), ``"numpy"`` (the kernel on numpy arrays), or
``None`` for the default (:func:`prp3.engines.select.default_engine`).  A robot with
joint friction runs on numpy (:func:`prp3.engines.select.runs_on`).  The engines
agree to round-off (tests: 1e-13 relative).

What is checked, in this order (the order of the reference path): the
inputs' types and shapes, their finiteness, the poses' bounds and
singularity (:func:`prp3.pose_validation.check_pose_array`), the actuator strokes
(:func:`prp3.mechanics.geometry.check_stroke`); then, after the engine, the results'
finiteness (:func:`prp3.validation.require_finite`) and, with ``μ`` terms, a
self-locking joint.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prp3.engines.compiled_robot import (
    CompiledRobot,
    Engine,
    ParameterArray,
    as_compiled,
    engine_for,
)
from prp3.engines.select import CHUNK, numba_module, run_numpy
from prp3.errors import Prp3Error, TrajectoryError
from prp3.mechanics import kernel
from prp3.mechanics.geometry import check_stroke
from prp3.mechanics.joint_motion import kernel_geometry
from prp3.mechanics.ops import NUMPY
from prp3.model.robot import Robot
from prp3.pose_validation import check_pose_array
from prp3.validation import check_finite, check_integer, check_real, require_finite

__all__ = [
    "DEFAULT_CHUNK",
    "FORCE_OUTPUTS",
    "FRICTION_OUTPUTS",
    "KERNEL_OUTPUTS",
    "MAX_CHUNK",
    "FastForces",
    "actuator_forces",
    "paper_forces",
    "solve_batch",
]

FloatArray = NDArray[np.float64]

#: Samples per chunk of the numpy engine (its work arrays stay in the CPU caches).
DEFAULT_CHUNK = CHUNK

#: The largest ``chunk_size``.
MAX_CHUNK = 10**6

#: Every per-leg output of the kernel, in the order of :class:`~prp3.mechanics.kernel.KernelSolution`.
KERNEL_OUTPUTS: tuple[str, ...] = kernel.KernelSolution._fields[:14]
#: The forces of :class:`FastForces` (and of one sample's ``SampleForces``), in their order.
FORCE_OUTPUTS: tuple[str, ...] = ("f10", "p10", "f21y", "f21z")
#: The friction outputs of the kernel (with a robot's ``[friction]``).
FRICTION_OUTPUTS: tuple[str, ...] = ("fric10", "fric21", "fric32")
_REACTIONS = ("n10", "m10", "n32", "m32")
_INPUTS = ("pose", "velocity", "acceleration")

#: Names of the three columns of each input, for messages.
_COMPONENTS = (("x", "y", "phi"), ("dx", "dy", "dphi"), ("ddx", "ddy", "ddphi"))
_LOAD_COMPONENTS = ("fx", "fy", "mz")


@dataclass(frozen=True)
class FastForces:
    """Actuator forces, input powers and joint forces from :func:`paper_forces`.

    Every array has the batch shape of the input and legs A, B, C last:
    ``(N, 3)``, or ``(3,)`` for a single sample.  Signs and units as in
    :class:`prp3.mechanics.forces.InverseDynamics`.

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
    compiled = as_compiled(robot)
    names = FORCE_OUTPUTS + (_REACTIONS if reactions else ())
    flat, shape = _inputs(compiled, pose, velocity, acceleration)
    result = _outputs(out, names, shape)
    targets = {key: array.reshape(-1, 3) for key, array in result.items()}
    _run(compiled, engine, flat, targets, chunk_size)
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
    compiled = as_compiled(robot)
    flat, shape = _inputs(compiled, pose, velocity, acceleration)
    f10 = np.empty(shape) if out is None else _out_array("out", out, shape)
    _run(compiled, engine, flat, {"f10": f10.reshape(-1, 3)}, chunk_size)
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
    compiled = as_compiled(robot)
    flat, shape = _inputs(compiled, pose, velocity, acceleration)
    friction = compiled.robot.friction is not None
    names = KERNEL_OUTPUTS + (FRICTION_OUTPUTS if friction else ())
    block = np.empty((len(names), flat[0].shape[0], 3))  # (14, N, 3): the numba engine's output
    result = {key: block[k].reshape(shape) for k, key in enumerate(names)}
    wrench = None if load is None else check_load(load, shape).reshape(-1, 3)
    targets = {key: block[k] for k, key in enumerate(names)}
    iterations = _run(compiled, engine, flat, targets, chunk_size, wrench, block)
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


def check_load(load: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """The time-varying load ``(f_x, f_y, m_z)``, validated: real, shaped as the pose ``shape``, finite."""
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
    engine: object,
    inputs: list[FloatArray],
    targets: dict[str, FloatArray],
    chunk_size: object,
    load: FloatArray | None = None,
    block: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray] | None:
    """Validated samples through ``engine`` into ``targets``; the results then checked.

    ``chunk_size`` and ``engine`` (the arguments of the entry) are validated
    first, after the samples and the outputs.

    ``block``: the ``(14, N, 3)`` array under ``targets`` when they are
    :data:`KERNEL_OUTPUTS` (:func:`solve_batch`).

    Returns the ``μ`` solve's ``(iterations, near_lock)`` ``(N,)`` with ``μ``
    terms, else ``None``.  Raises TrajectoryError where a result is not
    finite or the friction locks.
    """
    chunk, name = _chunk_size(chunk_size), engine_for(compiled, engine)
    samples = inputs[0].shape[0]
    mu = compiled.parameters.has_mu
    flags = (np.zeros(samples), np.zeros(samples)) if mu else None
    if not samples:
        return flags
    numba = numba_module() if name == "numba" else None
    if numba is None:
        iterations, near_lock = flags if flags is not None else (None, None)
        run_numpy(
            compiled.parameters, inputs, targets, chunk_size=chunk, load=load,
            iterations=iterations, near_lock=near_lock,
        )  # fmt: skip
    else:
        _run_numba(numba, compiled.array, inputs, targets, load, block)
    require_finite(targets, (samples,), "motion")
    if flags is not None:
        locked = np.flatnonzero(flags[0] < 0)
        if locked.size:
            raise friction_lock(int(locked[0]))
    return flags


def friction_lock(sample: int) -> TrajectoryError:
    """The refusal of a sample whose joint friction locks (no solution from ``μ = 0``)."""
    return TrajectoryError(
        "the joint friction locks: no inverse dynamics reached continuously "
        "from mu = 0 (the friction cone of a joint swallows the drive: "
        "self-locking); lower the mu coefficients or change the motion",
        subject="motion",
        sample=sample,
    )


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
    array: ParameterArray,
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
    elif names == FORCE_OUTPUTS:
        loops.forces(*rows, *targets.values())
    elif names == FORCE_OUTPUTS + _REACTIONS:
        loops.reactions(*rows, *targets.values())
    else:
        assert block is not None and names == KERNEL_OUTPUTS
        wrench = None if load is None else _frozen(load)
        loops.solve(*rows, wrench, block)
