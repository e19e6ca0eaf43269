"""The validated entries of the kernel for one sample, on Python floats.

:func:`sample_forces` — one sample on a :class:`~prp3.engines.compiled_robot.CompiledRobot`
built once by :func:`~prp3.engines.compiled_robot.compile_robot`; Python floats,
ints, numpy scalars, lists and ``(3,)`` arrays alike
(:func:`prp3.pose_validation.check_state_sample`); an optional time-varying
load.  :func:`sample_actuator_forces` the same for ``f10`` alone;
:func:`sample_forces_unchecked` the unvalidated call for a control loop.
The checks, their order and their messages are those of the batch entries
(:mod:`prp3.engines.entries`), and so are the numbers (eqs. 10, 14, 17,
19–25 of the one kernel, :mod:`prp3.mechanics.kernel`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NamedTuple, NoReturn

import numpy as np
from numpy.typing import NDArray

from prp3.engines.compiled_robot import CompiledRobot, Engine, numba_sample_forces
from prp3.engines.entries import FORCE_OUTPUTS, check_load, friction_lock
from prp3.engines.select import default_engine, numba_module, resolve_engine
from prp3.errors import Prp3Error
from prp3.mechanics import kernel
from prp3.mechanics.geometry import check_stroke
from prp3.mechanics.joint_motion import kernel_geometry
from prp3.mechanics.ops import MATH
from prp3.pose_validation import check_state_sample
from prp3.validation import require_finite

__all__ = [
    "SampleForces",
    "SampleInput",
    "sample_actuator_forces",
    "sample_forces",
    "sample_forces_unchecked",
]

FloatArray = NDArray[np.float64]

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
    inside the stroke) and its result (finite) as :func:`~prp3.engines.entries.paper_forces` does,
    with the same messages; Python floats, ints, numpy scalars, lists and
    ``(3,)`` arrays at the same cost.

    Parameters
    ----------
    compiled : CompiledRobot
        From :func:`~prp3.engines.compiled_robot.compile_robot` (compile once, call many times).
    pose, velocity, acceleration : sequence of 3 floats or ndarray (3,)
        ``(x, y, φ)``, ``(ẋ, ẏ, φ̇)``, ``(ẍ, ÿ, φ̈)`` (SI units, rad).
    load : sequence of 3 floats or ndarray (3,), optional
        A time-varying wrench ``(f_x, f_y, m_z)`` of the environment on the
        platform (force at ``G`` in the fixed frame, N; moment, N·m), as the
        ``load`` of :func:`~prp3.engines.entries.solve_batch`; added to the robot's constant
        ``[load]``.
    engine : {"numba", "numpy"} or None
        As :func:`~prp3.engines.entries.paper_forces` (``"numpy"``: the kernel on Python floats).

    Returns
    -------
    SampleForces
        ``f10``, ``p10``, ``f21y``, ``f21z`` of legs A, B, C (N, W).

    Raises
    ------
    TrajectoryError, SingularPoseError, UnreachablePoseError
        As :func:`~prp3.engines.entries.paper_forces` (and :func:`~prp3.engines.entries.solve_batch` for ``load``).

    Examples
    --------
    >>> from prp3 import Robot, compile_robot
    >>> compiled = compile_robot(Robot())
    >>> forces = sample_forces(compiled, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    >>> [round(f, 4) for f in forces.f10]
    [31.8589, -8.4957, -23.3632]
    >>> still = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    >>> pushed = sample_forces(compiled, *still, load=(0.0, -10.0, 0.0))  # 10 N downwards
    >>> [round(f, 4) for f in pushed.f10]
    [37.6324, -11.3825, -26.25]
    """
    return _sample(compiled, pose, velocity, acceleration, load, engine, False)  # type: ignore[no-any-return]


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
    >>> from prp3 import Robot, compile_robot
    >>> compiled = compile_robot(Robot())
    >>> [round(f, 4) for f in sample_actuator_forces(compiled, (0.0, 0.0, 0.0), (0, 0, 0), (0, 0, 0))]
    [31.8589, -8.4957, -23.3632]
    """
    return _sample(compiled, pose, velocity, acceleration, load, engine, True)  # type: ignore[no-any-return]


def _sample(
    compiled: object,
    pose: SampleInput,
    velocity: SampleInput,
    acceleration: SampleInput,
    load: SampleInput | None,
    engine: object,
    f10_only: bool,
) -> Any:
    """One sample validated and solved: ``f10`` (3 floats) with ``f10_only``, else :class:`SampleForces`.

    Validated in the order of the batch entries (:mod:`prp3.engines.entries`):
    the robot, the state, the load, the engine, the stroke; the results after.
    The numba engine's functions are called as their machine code
    (:func:`prp3.engines.numba.machine_code`).
    """
    if type(compiled) is not CompiledRobot:
        _not_compiled(compiled)
    state = check_state_sample(pose, velocity, acceleration, compiled.robot)
    wrench = None if load is None else check_load_sample(load)
    name = default_engine() if engine is None else resolve_engine(engine)
    numba = numba_module() if name == "numba" and compiled.compiled_kernel else None
    if compiled.stroke is not None:
        _check_stroke(compiled, state, numba)
    if numba is None:
        sol = _sample_floats(compiled, state, wrench)
        if f10_only:
            return (sol.f10[0], sol.f10[1], sol.f10[2])
        return SampleForces(sol.f10, sol.p10, sol.f21y, sol.f21z)
    if f10_only:
        function = numba.sample_f10 if wrench is None else numba.sample_f10_loaded
    else:
        function = numba.sample_forces if wrench is None else numba.sample_forces_loaded
    run = numba.MACHINE_CODE.get(function) or numba.machine_code(function)
    f = run(compiled.array, *state) if wrench is None else run(compiled.array, *state, *wrench)
    if f10_only:
        if not math.isfinite(f[0] + f[1] + f[2]):
            _check_overflow({"f10": f})
        return f
    a, b, c, d = f
    if not math.isfinite(a[0] + a[1] + a[2] + b[0] + b[1] + b[2] + c[0] + c[1] + c[2] + d[0] + d[1] + d[2]):  # fmt: skip
        _check_overflow(dict(zip(FORCE_OUTPUTS, f, strict=True)))
    return _new(SampleForces, f)


def check_load_sample(load: SampleInput) -> tuple[float, float, float]:
    """One sample's load ``(f_x, f_y, m_z)`` as three Python floats, validated.

    The common case in one pass (three Python floats or numpy float64 scalars,
    in a tuple, a list or a ``(3,)`` array, finite); anything else by
    :func:`~prp3.engines.entries.check_load`, which names what is wrong.
    """
    values = load.tolist() if type(load) is np.ndarray and load.dtype == np.float64 else load
    if type(values) in _UNPACKED and len(values) == 3:
        fx, fy, mz = values
        if type(fx) in _FLOATS and type(fy) in _FLOATS and type(mz) in _FLOATS:
            fx, fy, mz = float(fx), float(fy), float(mz)
            if 0.0 * (fx + fy + mz) == 0.0:
                return fx, fy, mz
    fx, fy, mz = check_load(load, (3,)).tolist()
    return fx, fy, mz


#: What the load's one pass takes as it is (:func:`check_load_sample`).
_UNPACKED = frozenset((tuple, list))
_FLOATS = frozenset((float, np.float64))


def _check_stroke(compiled: CompiledRobot, state: tuple[float, ...], numba: Any) -> None:
    """Refuse a validated pose whose ``λ10`` (eq. 10) lies outside the robot's stroke."""
    stroke = compiled.stroke
    assert stroke is not None
    x, y, phi = state[:3]
    if numba is not None:
        function = numba.lambda10_sample
        lam = (numba.MACHINE_CODE.get(function) or numba.machine_code(function))(
            compiled.array, x, y, phi
        )
    else:
        lam = kernel_geometry(MATH, compiled.parameters, x, y, phi).lambda10
    if not all(stroke[0] <= value <= stroke[1] for value in lam):
        check_stroke(compiled.robot, np.array(lam), np.array([x, y, phi]))


def _sample_floats(
    compiled: CompiledRobot, state: tuple[float, ...], load: tuple[float, float, float] | None
) -> kernel.KernelSolution:
    """One validated sample by the kernel on Python floats; its results checked."""
    sol = kernel.solve(MATH, compiled.parameters, *state, reactions=False, load=load)
    if sol.iterations is not None and sol.iterations < 0:
        raise friction_lock(0)
    values = (*sol.f10, *sol.p10, *sol.f21y, *sol.f21z)
    if not math.isfinite(sum(values)):
        _check_overflow({name: getattr(sol, name) for name in FORCE_OUTPUTS})
    return sol


def _check_overflow(values: dict[str, Any]) -> None:
    """The error of :func:`~prp3.engines.entries.paper_forces` for one sample's results that are
    not finite, after a sum of them that is not: the sum of finite results may overflow (two
    forces of 1e308), so each one is checked and finite results pass."""
    require_finite({name: np.array([legs]) for name, legs in values.items()}, (1,), "motion")


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
    >>> from prp3 import Robot, compile_robot
    >>> f = sample_forces_unchecked(compile_robot(Robot()), 0.0, 0.0, 0.0, 0, 0, 0, 0, 0, 0)
    >>> round(f[0], 4)
    31.8589
    """
    state = (
        float(x), float(y), float(phi), float(dx), float(dy), float(dphi),
        float(ddx), float(ddy), float(ddphi),
    )  # fmt: skip
    numba = numba_module() if compiled.compiled_kernel and default_engine() == "numba" else None
    if numba is None:
        return compiled.sample_function()(*state)
    return numba_sample_forces(numba, compiled.array, compiled.stroke is not None, *state)
