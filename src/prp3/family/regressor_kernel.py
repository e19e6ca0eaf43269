"""The family regressor generated from the family's one kernel: ``Y = ∂τ/∂π`` (docs/identification.md).

The actuator efforts ``τ`` of :func:`prp3.family.sample_mechanics.sample_dynamics`
(the kernel that also becomes numba, :mod:`prp3.family.compiled_kernel`, and C,
:mod:`prp3.family.codegen`) are linear in the standard parameters ``π`` of
:mod:`prp3.apps.family_regressor`, for a fixed geometry, actuation and gravity::

    τ = Y·π + τ_known,   Y = ∂τ/∂π (free of π),   τ_known = τ(π = 0) (the [load]).

The kernel's inputs are the file's values ``v`` (per link ``m, c, I`` about the
mass centre; the platform's ``m``, ``I`` and the payload's ``m, c, I``), not ``π``
(``h = m·c``, ``J = I + m·|c|²``), so the columns come by the chain rule
``∂τ/∂v = Y·∂π/∂v`` at the point where ``∂π/∂v`` is the identity: each link of
mass 1 at ``c = 0``, a payload of mass 1 at ``c = 0`` (there ``∂J/∂m = |c|² = 0``,
``∂h/∂c = m = 1``, ``∂J/∂c = 2·m·c = 0``), so that

``Y[:, m_k] = ∂τ/∂m_k``, ``Y[:, h_kx] = ∂τ/∂c_kx``, ``Y[:, J_k] = ∂τ/∂I_k`` (links),
``Y[:, m3] = ∂τ/∂m_platform``, ``Y[:, h3x] = ∂τ/∂c_px``, ``Y[:, J3] = ∂τ/∂I_platform``.

The derivatives are exact: the kernel runs once on :class:`Dual` numbers whose
parts are the tracer's values (:mod:`prp3.engines.trace`), so every derivative
is itself a recorded sequence of operations (forward differentiation of the
kernel's source, the product, quotient and chain rules applied to each of its
operations); derivatives that vanish identically are never recorded.  The
record is emitted as numpy code (:func:`prp3.engines.trace.broadcast_function`:
the robot's numbers once, the samples as arrays), one function per architecture
× actuated joint, built once per process (:func:`regressor_function`).  The
kinematics are inputs (``q`` of the nine joints, the platform's state: the
branch followed from home by :func:`prp3.family.mechanics.family_kinematics`), and
the legs' frames come from ``q`` by :func:`prp3.family.sample_mechanics.chain_of`.

>>> from prp3.family.model import FamilyRobot
>>> robot = FamilyRobot.default("3-RPR")
>>> state = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]])
>>> q = np.array([[0.0, 0.3, 0.0] * 3])
>>> Y, known = regressor_batch(robot, state, q)
>>> Y.shape, known.shape
((1, 3, 12), (1, 3))
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.engines.trace import TRACE, broadcast_function
from prp3.family.chain import SIGMA
from prp3.family.model import FamilyRobot
from prp3.family.sample_mechanics import Design, Inertia, chain_of, sample_dynamics
from prp3.mechanics.ops import Ops

__all__ = [
    "COLUMNS",
    "CONSTANTS",
    "DUAL",
    "Dual",
    "regressor_batch",
    "regressor_constants",
    "regressor_function",
    "regressor_outputs",
]

FloatArray = NDArray[np.float64]

#: The columns of ``Y``, in the order of the outputs (the names of
#: :data:`prp3.apps.family_regressor.FAMILY_PARAMETERS`).
COLUMNS: tuple[str, ...] = (
    "link1_mass", "link1_moment_x", "link1_moment_y", "link1_inertia",
    "link2_mass", "link2_moment_x", "link2_moment_y", "link2_inertia",
    "platform_mass", "platform_moment_x", "platform_moment_y", "platform_inertia",
)  # fmt: skip
#: The robot's numbers the generated function takes: design (13), gravity (2), load (3).
CONSTANTS = 18
#: Samples per call of the generated function (its work rows are this long).
CHUNK = 4096


# ------------------------------------------------------------------ forward derivatives
class Dual:
    """A value and its derivatives: ``value + Σ_i d[i]·ε_i`` (``ε_i ε_j = 0``).

    ``value`` and the coefficients are floats or traced values; a derivative
    that is identically zero is absent from ``d`` (so nothing is recorded for it).
    """

    __slots__ = ("d", "value")

    def __init__(self, value: Any, d: dict[int, Any] | None = None) -> None:
        self.value, self.d = value, d or {}

    @staticmethod
    def of(other: Any) -> Dual:
        return other if isinstance(other, Dual) else Dual(other)

    def _combine(self, value: Any, a: Any, other: Dual, b: Any) -> Dual:
        """``Dual(value, a·d_self + b·d_other)`` (``a``, ``b`` None: a factor 1)."""
        d: dict[int, Any] = {}
        for source, factor in ((self.d, a), (other.d, b)):
            for i, v in source.items():
                term = v if factor is None else v * factor
                d[i] = d[i] + term if i in d else term
        return Dual(value, {i: v for i, v in d.items() if not _zero(v)})

    def __add__(self, other: Any) -> Dual:
        o = Dual.of(other)
        return self._combine(self.value + o.value, None, o, None)

    __radd__ = __add__

    def __sub__(self, other: Any) -> Dual:
        o = Dual.of(other)
        return self._combine(self.value - o.value, None, o, -1.0)

    def __rsub__(self, other: Any) -> Dual:
        return Dual.of(other) - self

    def __mul__(self, other: Any) -> Dual:
        o = Dual.of(other)
        return self._combine(self.value * o.value, o.value, o, self.value)

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> Dual:
        o = Dual.of(other)
        quotient = self.value / o.value
        if not o.d:
            return self._combine(quotient, 1.0 / o.value, o, None)
        # (a/b)' = (a' − (a/b)·b')/b
        return self._combine(quotient, 1.0 / o.value, o, -quotient / o.value)

    def __rtruediv__(self, other: Any) -> Dual:
        return Dual.of(other) / self

    def __neg__(self) -> Dual:
        return Dual(-self.value, {i: -v for i, v in self.d.items()})


def _zero(value: Any) -> bool:
    return isinstance(value, float) and value == 0.0


def _chain_rule(
    plain: Callable[[Any], Any], slope: Callable[[Any, Any], Any]
) -> Callable[[Any], Any]:
    """The function on duals: ``f(a + d·ε) = f(a) + slope(a, f(a))·d·ε``."""

    def call(x: Any) -> Any:
        x = Dual.of(x)
        value = plain(x.value)
        if not x.d:
            return Dual(value)
        k = slope(x.value, value)
        return Dual(value, {i: v * k for i, v in x.d.items()})

    return call


def _flat(x: Any) -> Any:
    """A dual with no derivative (a function the kernel only applies to the geometry)."""
    x = Dual.of(x)
    if x.d:
        raise ValueError("a derivative through abs/sign/atan2 is not needed by the kernel")
    return x.value


def _no_slope(name: str) -> Callable[..., Any]:
    plain = getattr(TRACE, name)
    return lambda *xs: Dual(plain(*(_flat(x) for x in xs)))


#: The kernel's functions on :class:`Dual` numbers over the tracer's values.
DUAL = Ops(
    "dual",
    _chain_rule(TRACE.cos, lambda a, f: -TRACE.sin(a)),
    _chain_rule(TRACE.sin, lambda a, f: TRACE.cos(a)),
    _chain_rule(TRACE.sqrt, lambda a, f: 0.5 / f),
    _chain_rule(TRACE.tanh, lambda a, f: 1.0 - f * f),
    _no_slope("abs"),
    _no_slope("sign"),
    _no_slope("atan2"),
)


# ------------------------------------------------------------------ the traced function
def _unit_inertia(load: Sequence[Any], gravity: Sequence[Any], actuated: int) -> Inertia:
    """The point where ``∂π/∂v`` is the identity, each of the 12 directions a derivative."""

    def unit(i: int, value: float) -> Dual:
        return Dual(value, {i: 1.0})

    links = tuple(
        (unit(4 * k, 1.0), (unit(4 * k + 1, 0.0), unit(4 * k + 2, 0.0)), unit(4 * k + 3, 0.0))
        for k in range(2)
    )
    return Inertia(
        links=links,  # type: ignore[arg-type]
        platform=(unit(8, 0.0), unit(11, 0.0)),  # type: ignore[arg-type]
        payload=(1.0, (unit(9, 0.0), unit(10, 0.0)), 0.0),  # type: ignore[arg-type]
        load=tuple(load),
        gravity=tuple(gravity),
        actuated=actuated,
    )


def regressor_outputs(types: str, actuated: int) -> Callable[..., list[Any]]:
    """The traced function: ``(ops, design 13, gravity 2, load 3, state 9, q 9) → Y (36), τ_known (3)``.

    ``Y`` row-major per leg (legs A, B, C; :data:`COLUMNS`); ``actuated``
    0-based.  ``ops`` must be the tracer's (the derivatives are recorded on it).
    """

    def function(ops: Ops, *values: Any) -> list[Any]:
        del ops  # the duals carry the tracer's functions
        duals = [Dual(v) for v in values]
        design = Design.from_values(types, duals[:13])
        gravity, load = duals[13:15], duals[15:18]
        x, y, phi, *rest = duals[18:27]
        q = duals[27:36]
        legs = []
        for j in range(3):
            _, origins, rotations = chain_of(DUAL, design, float(SIGMA[j]), q[3 * j : 3 * j + 3])
            legs.append((origins, rotations))
        state = (x, y, DUAL.cos(phi), DUAL.sin(phi), *rest)
        unit = _unit_inertia((0.0, 0.0, 0.0), gravity, actuated)
        tau = sample_dynamics(DUAL, types, unit, design.scale, state, legs)[1:4]
        columns = [Dual.of(t).d.get(i, 0.0) for t in tau for i in range(12)]
        massless = Inertia(((0.0, (0.0, 0.0), 0.0),) * 2, (0.0, 0.0), (0.0, (0.0, 0.0), 0.0),
                           tuple(load), tuple(gravity), actuated)  # type: ignore[arg-type]  # fmt: skip
        known = sample_dynamics(DUAL, types, massless, design.scale, state, legs)[1:4]
        return [*columns, *(Dual.of(t).value for t in known)]

    return function


@functools.cache
def regressor_function(types: str, actuated: int) -> Callable[..., None]:
    """The generated numpy function of one structure (joints ``types``, ``actuated`` 1–3), built once.

    ``f(c0 … c17, x, y, phi, dx, dy, dphi, ddx, ddy, ddphi, q0 … q8, out, work)``
    (:func:`prp3.engines.trace.broadcast_function`: the constants of shape
    ``(1,)``, the samples of shape ``(n,)``).
    """
    names = (*(f"c{i}" for i in range(CONSTANTS)),
             "x", "y", "phi", "dx", "dy", "dphi", "ddx", "ddy", "ddphi",
             *(f"q{i}" for i in range(9)))  # fmt: skip
    groups = [0] * CONSTANTS + [1] * 18
    return broadcast_function(
        regressor_outputs(types, actuated - 1), names, groups, name=f"regressor_{types}"
    )


def regressor_constants(robot: FamilyRobot) -> FloatArray:
    """The generated function's constants of ``robot``: design (13), gravity (2), load (3)."""
    values = (*Design.of(robot).values(), *robot.gravity, *robot.load.force, robot.load.moment)
    return np.array(values, dtype=np.float64)


def regressor_batch(
    robot: FamilyRobot, state: FloatArray, q: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """``Y (N, 3, 12)`` (:data:`COLUMNS`) and ``τ_known (N, 3)`` at the samples (not validated).

    ``state`` is ``(N, 9)``: pose, velocity, acceleration of the platform;
    ``q`` is ``(N, 9)``: the joint values of legs A, B, C (the branch of the
    motion), in chunks of :data:`CHUNK` samples.
    """
    fn = regressor_function(robot.types, robot.actuated)
    constants = [np.full(1, v) for v in regressor_constants(robot)]
    n = state.shape[0]
    out = np.empty((39, n))
    size = min(n, CHUNK)
    work = [np.empty((rows, 1 if mask == 1 else size)) for mask, rows in fn.blocks]  # type: ignore[attr-defined]
    for start in range(0, n, CHUNK):
        stop = min(n, start + CHUNK)
        if stop - start != size:
            size = stop - start
            work = [np.empty((rows, 1 if mask == 1 else size)) for mask, rows in fn.blocks]  # type: ignore[attr-defined]
        columns = [np.ascontiguousarray(state[start:stop, i]) for i in range(9)]
        columns += [np.ascontiguousarray(q[start:stop, i]) for i in range(9)]
        fn(*constants, *columns, out=out[:, start:stop], work=work)
    return out[:36].T.reshape(n, 3, 12), np.ascontiguousarray(out[36:].T)
