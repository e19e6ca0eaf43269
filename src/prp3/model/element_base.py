"""The element base: what every effect of the robot model says about itself.

:class:`Element` is the interface of one effect (its kernel fields, power,
potential, dissipation and what supports it; :mod:`prp3.model.elements` says
what an element is and lists them), :class:`State` the arrays its power and
potential energy are evaluated on, and :func:`is_zero`, :func:`rate_sign`,
:func:`number_text` the small helpers the elements and the kernel share.  The
module imports nothing of prp3.

>>> is_zero(0.0), is_zero(1e-300), number_text(0.0), number_text(0.25)
(True, False, '0', '0.25')
>>> Element("none").power(None, State(*(np.zeros((2, 3)) for _ in range(5)))).tolist()
[0.0, 0.0]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

__all__ = ["Element", "FloatArray", "State", "Value", "is_zero", "number_text", "rate_sign"]

FloatArray = NDArray[np.float64]
#: A number of the kernel: a float, a 1-D float64 array or a sympy expression.
Value = Any


def number_text(value: float) -> str:
    """Full-precision text of a float (``repr``: the shortest exact form; ``"0"`` for zero)."""
    number = float(value)
    return "0" if number == 0.0 else repr(number)


def is_zero(value: Value) -> bool:
    """Whether ``value`` is the number zero (a symbol or an array is not): it adds no operation."""
    return isinstance(value, int | float) and value == 0.0


def rate_sign(ops: Any, rate: Value, smoothing: Value) -> Value:
    """``s(v)``: ``sign(v)`` (``s(0) = 0``) when ``smoothing`` is zero, else ``tanh(v/smoothing)``."""
    if is_zero(smoothing):
        return ops.sign(rate)
    return ops.tanh(rate / smoothing)


class State(NamedTuple):
    """The state an element's power and potential energy are evaluated on (arrays ``(N, 3)``).

    ``pose, velocity``: ``(x, y, φ)`` and its rate; ``lambda10, dlambda10``,
    ``dlambda32``: joint displacements and rates; ``wrench``: the motion's
    time-varying wrench ``(fx, fy, mz)`` or ``None``; ``friction``: the
    friction forces ``(fric10, fric21, fric32)`` or ``None``; ``lambda32``: the sleeves'
    displacements (the sleeve's spring needs them) or ``None``.
    """

    pose: FloatArray
    velocity: FloatArray
    lambda10: FloatArray
    dlambda10: FloatArray
    dlambda32: FloatArray
    wrench: FloatArray | None = None
    friction: tuple[FloatArray, FloatArray, FloatArray] | None = None
    lambda32: FloatArray | None = None


@dataclass(frozen=True)
class Element:
    """One effect of the robot model (base class; what an element is: :mod:`prp3.model.elements`).

    Attributes
    ----------
    name : str
        Its name, the ``ROBOT.toml`` table where it has one (``"friction.sleeve"``).
    fields : tuple of str
        The fields of :class:`~prp3.mechanics.parameters.KernelParameters` it owns (default ``0.0``).
    regressor : tuple of str
        Fields the joint forces are linear and homogeneous in: the columns it
        adds to identification's regressor.
    kept : tuple of str
        Fields the regressor keeps at the robot's value (the shape of a column).
    broadcast : tuple of str
        Fields a design sweep may vary across the designs of one kernel call.
    symbols, units : dict
        Short symbol and SI unit of each regressor field.
    generated_c : bool
        Whether ``prp3 export c`` computes it (else a robot with it is refused).
    """

    name: str
    fields: tuple[str, ...] = ()
    regressor: tuple[str, ...] = ()
    kept: tuple[str, ...] = ()
    broadcast: tuple[str, ...] = ()
    symbols: tuple[tuple[str, str], ...] = ()
    units: tuple[tuple[str, str], ...] = ()
    generated_c: bool = False

    def present(self, robot: Any) -> bool:
        """Whether ``robot`` has this element."""
        return False

    def parameters(self, robot: Any) -> dict[str, float]:
        """The values of :attr:`fields` for ``robot`` (those it has; the others stay 0)."""
        return {}

    def acts(self, k: Any) -> bool:
        """Whether the kernel parameters ``k`` give it any field other than zero."""
        return any(not is_zero(getattr(k, name)) for name in self.fields)

    def power(self, robot: Any, state: State) -> FloatArray:
        """Power of its forces on the robot (W), shape ``(N,)``."""
        return np.zeros(state.pose.shape[0])

    def potential(self, robot: Any, state: State) -> FloatArray | None:
        """Its potential energy (J), ``(N,)``, or ``None`` when it has none."""
        return None

    def dissipation(self, robot: Any, state: State) -> FloatArray:
        """The power its forces dissipate (W, >= 0), ``(N,)``.

        For an element with a potential, ``power = −d(potential)/dt − dissipation``.
        """
        return np.zeros(state.pose.shape[0])

    def mjcf_joints(self, robot: Any) -> dict[str, dict[str, float]]:
        """MuJoCo joint attributes it sets, by joint (``"lambda10"``, ``"phi"``, ``"lambda32"``).

        Attributes of several elements on one joint add (``damping``).
        """
        return {}

    def mjcf_omissions(self, robot: Any) -> list[str]:
        """What of it the MJCF model does not carry (one phrase each)."""
        return []

    def check_forward(self, robot: Any) -> None:
        """Refuse what forward dynamics cannot integrate (raises :class:`ParameterError`)."""

    def changes_statics(self, robot: Any) -> bool:
        """Whether it changes the forces that hold the robot at rest beyond its own weight.

        ``prp3 workspace`` writes the statics map by default for such a robot.
        """
        return False

    def check_mujoco_plant(self, robot: Any) -> None:
        """Refuse what MuJoCo simulates otherwise than prp3 (the ``mujoco`` plant of control)."""

    def identified(self, robot: Any, values: dict[str, float]) -> Any:
        """``robot`` with the regressor fields of this element set to ``values``."""
        return robot
