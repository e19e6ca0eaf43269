"""A robot prepared once for the kernel: :class:`CompiledRobot`, :func:`compile_robot`.

The entries of the kernel (:mod:`prp3.engines.entries` for batches,
:mod:`prp3.engines.sample_entries` for one sample) take a
:class:`CompiledRobot`: the robot's constants as the kernel uses them
(:class:`~prp3.mechanics.parameters.KernelParameters`), packed into the record
array that the numba engine reads, the stroke, and whether the compiled
kernel runs the robot (no joint friction).  Its :meth:`CompiledRobot.sample_function`
is the unvalidated kernel of one sample for a control loop.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType
from typing import Literal

import numpy as np

from prp3.engines.select import numba_module, resolve_engine, runs_on
from prp3.errors import Prp3Error
from prp3.mechanics import kernel
from prp3.mechanics.ops import MATH
from prp3.mechanics.parameters import KernelParameters, kernel_parameters
from prp3.model.robot import Robot
from prp3.validation import check_robot

__all__ = ["PARAMETER_RECORD", "CompiledRobot", "Engine", "ParameterArray", "compile_robot"]

#: The read-only ``(1,)`` array of :data:`PARAMETER_RECORD` the numba engine reads.
ParameterArray = np.ndarray[tuple[int], np.dtype[np.void]]
#: The kernel's parameters as the numba engine reads them: one record of the fields of
#: :class:`~prp3.mechanics.parameters.KernelParameters`, in order, each a float64.
PARAMETER_RECORD = np.dtype(
    [(name, np.float64) for name in KernelParameters.__dataclass_fields__], align=True
)
#: The engine argument: ``"numba"``, ``"numpy"`` or ``None`` (the default engine).
Engine = Literal["numba", "numpy"] | None


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
        The fields of ``parameters`` as a read-only array of one
        :data:`PARAMETER_RECORD` (the numba engine's input, the type its
        machine code is called with: checked).
    compiled_kernel : bool
        Whether the numba engine runs this robot (no joint friction):
        :func:`prp3.engines.select.runs_on`.

    Raises
    ------
    Prp3Error
        ``array`` is not such an array of the kernel's parameters.
    """

    robot: Robot
    parameters: KernelParameters
    stroke: tuple[float, float] | None
    array: ParameterArray
    compiled_kernel: bool

    def __post_init__(self) -> None:
        array = self.array
        if not (
            type(array) is np.ndarray
            and array.dtype == PARAMETER_RECORD
            and array.shape == (1,)
            and array.flags.c_contiguous
            and array.flags.aligned
            and not array.flags.writeable
        ):
            raise Prp3Error(
                "the array of a CompiledRobot must be the read-only record array of its "
                "kernel parameters: build it by compile_robot(robot)"
            )

    def sample_function(self, engine: Engine = None) -> Callable[..., tuple[float, ...]]:
        """The unvalidated kernel of one sample: ``f(x, y, φ, ẋ, ẏ, φ̇, ẍ, ÿ, φ̈)``.

        Returns the 12 floats ``f10, p10, f21y, f21z`` of legs A, B, C,
        followed by the 3 ``λ10`` when the robot has a stroke.  With ``μ``
        terms NaN where the friction locks.
        """
        return _unchecked(self, engine_for(self, engine), f10_only=False)

    def actuator_sample_function(self, engine: Engine = None) -> Callable[..., tuple[float, ...]]:
        """:meth:`sample_function` for ``f10`` alone: ``f(x, …, φ̈)`` returns its 3 floats."""
        return _unchecked(self, engine_for(self, engine), f10_only=True)


def engine_for(compiled: CompiledRobot, engine: object) -> str:
    """The engine that runs ``compiled`` for the argument ``engine`` (validated)."""
    name = resolve_engine(engine)
    return name if compiled.compiled_kernel else "numpy"


def _unchecked(
    compiled: CompiledRobot, engine: str, f10_only: bool
) -> Callable[..., tuple[float, ...]]:
    array, params, stroke = compiled.array, compiled.parameters, compiled.stroke is not None
    numba = numba_module() if engine == "numba" else None
    if numba is not None:  # called as their machine code once compiled (numba.machine_code)
        if f10_only:
            code, machine_code, f10 = numba.MACHINE_CODE, numba.machine_code, numba.sample_f10

            def numba_f10(*state: float) -> tuple[float, ...]:
                return (code.get(f10) or machine_code(f10))(array, *state)  # type: ignore[no-any-return]

            return numba_f10

        def numba_forces(*state: float) -> tuple[float, ...]:
            return numba_sample_forces(numba, array, stroke, *state)

        return numba_forces

    def floats(*state: float) -> tuple[float, ...]:
        sol = kernel.solve(MATH, params, *state, reactions=False)
        if sol.iterations is not None and sol.iterations < 0:
            return (math.nan,) * (3 if f10_only else 15 if stroke else 12)
        if f10_only:
            return tuple(sol.f10)
        return (*sol.f10, *sol.p10, *sol.f21y, *sol.f21z, *(sol.lambda10 if stroke else ()))

    return floats


def numba_sample_forces(
    numba: ModuleType, array: ParameterArray, stroke: bool, *state: float
) -> tuple[float, ...]:
    """:meth:`CompiledRobot.sample_function` on the numba engine: the 12 floats (and ``λ10``).

    ``numba`` is :mod:`prp3.engines.numba`, ``array`` the robot's parameter
    record, ``stroke`` whether ``λ10`` follows; ``state`` nine Python floats.
    """
    code, machine_code = numba.MACHINE_CODE, numba.machine_code
    forces = numba.sample_forces
    f = (code.get(forces) or machine_code(forces))(array, *state)
    if not stroke:
        return (*f[0], *f[1], *f[2], *f[3])
    lam = numba.lambda10_sample
    return (*f[0], *f[1], *f[2], *f[3], *(code.get(lam) or machine_code(lam))(array, *state[:3]))


def compile_robot(robot: Robot) -> CompiledRobot:
    """Prepare ``robot`` for the entries of the kernel (compile once).

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
        [tuple(float(getattr(parameters, name)) for name in KernelParameters.__dataclass_fields__)],
        dtype=PARAMETER_RECORD,
    )
    array.flags.writeable = False
    compiled_kernel = runs_on("numba", parameters, robot.friction is not None) == "numba"
    return CompiledRobot(robot, parameters, robot.limits.stroke, array, compiled_kernel)


def as_compiled(robot: object) -> CompiledRobot:
    """``robot`` if it is a :class:`CompiledRobot`, else :func:`compile_robot` of it (validated)."""
    return robot if isinstance(robot, CompiledRobot) else compile_robot(robot)  # type: ignore[arg-type]
