"""Effects as elements: each applied effect of the robot model written in one place.

The paper's model (section 3) is the inertia of the seven bodies; everything
that acts on them besides the actuators is an *element*: gravity, a payload
fixed to the platform, the constant ``[load]``, the motion's time-varying
wrench ``fx, fy, mz``, the friction of each kind of joint and the linear
spring with damper of the actuators.  An element says, in one class,

* which fields of :class:`prp3.mechanics.parameters.KernelParameters` it owns and their
  values for a robot (:meth:`Element.parameters`);
* where its contribution to the wrench each body needs is written: in
  :func:`prp3.mechanics.wrenches.body_wrenches` and its helpers (``_leg_spring``,
  ``_leg_friction``, the load), in the kernel's ``+ − × ÷`` on tuples, so that
  the same code runs on floats, arrays, sympy and compiled by numba (which
  cannot call methods of these objects); the element owns its fields, and a
  field that is zero adds no operation;
* its power on the robot, its potential energy where it has one and the
  power it dissipates (:meth:`Element.power`, :meth:`Element.potential`,
  :meth:`Element.dissipation`, on a :class:`State` of arrays;
  ``tests/test_energy.py`` sums them);
* what supports it: the generated C code (:attr:`Element.generated_c`), the
  MJCF model (:meth:`Element.mjcf_joints`, :meth:`Element.mjcf_omissions`),
  the identification regressor (:attr:`Element.regressor`, the fields the
  forces are linear and homogeneous in, with :attr:`Element.symbols` and
  :attr:`Element.units`), the design sweeps (:attr:`Element.broadcast`:
  fields the kernel runs the same operations for whatever their values) and
  forward dynamics (:meth:`Element.check_forward`).

:data:`ELEMENTS` lists them; :attr:`prp3.model.robot.Robot.elements` gives those a
robot has.  Every consumer (kernel, codegen, identification, design, mjcf,
forward) asks the elements; none keeps its own list of effects.

The module imports nothing of prp3 but the errors: the robot and the kernel's
values are read by their attributes.

>>> [element.name for element in ELEMENTS]  # doctest: +NORMALIZE_WHITESPACE
['gravity', 'payload', 'load', 'wrench', 'friction.actuator', 'friction.revolute',
 'friction.sleeve', 'spring.actuator']
>>> SPRING.fields, SPRING.generated_c
(('spring_stiffness', 'spring_rest', 'spring_damping'), True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from prp3.errors import ParameterError

__all__ = [
    "ELEMENTS",
    "FRICTIONS",
    "GRAVITY",
    "LOAD",
    "PAYLOAD",
    "SPRING",
    "WRENCH",
    "Element",
    "FrictionElement",
    "GravityElement",
    "LoadElement",
    "PayloadElement",
    "SpringElement",
    "State",
    "WrenchElement",
    "effect_fields",
    "is_zero",
    "number_text",
    "rate_sign",
]

FloatArray = NDArray[np.float64]
#: A number of the kernel: a float, a 1-D float64 array or a sympy expression.
Value = Any

_SQRT3 = math.sqrt(3.0)
#: ``α_i`` of legs A, B, C (eq. 1), rad.
_ALPHA = np.array([math.pi / 3.0, math.pi, -math.pi / 3.0])
_E = np.stack([np.cos(_ALPHA), np.sin(_ALPHA)], axis=-1)  # e_i (3, 2)
_N = np.stack([-np.sin(_ALPHA), np.cos(_ALPHA)], axis=-1)  # n_i


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
    friction forces ``(fric10, fric21, fric32)`` or ``None``.
    """

    pose: FloatArray
    velocity: FloatArray
    lambda10: FloatArray
    dlambda10: FloatArray
    dlambda32: FloatArray
    wrench: FloatArray | None = None
    friction: tuple[FloatArray, FloatArray, FloatArray] | None = None


@dataclass(frozen=True)
class Element:
    """One effect of the robot model (base class; see the module docstring).

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


def _weight_terms(robot: Any, state: State) -> tuple[FloatArray, FloatArray]:
    """Mass-weighted positions and velocities of the legs' and platform's mass centres.

    Returns ``Σ m r`` and ``Σ m v`` (shape ``(N, 2)``): pistons at
    ``P_i + c1x·e_i + c1y·n_i``, ``P_i = B_i0 + (l0/√3 + λ10_i)·e_i``; links at
    ``P_i + c2x·d_i + c2y·d⊥_i``; the platform at ``G``.
    """
    l0 = robot.l0
    phi = state.pose[:, 2]
    base = l0 * np.stack([np.sin(_ALPHA - math.pi / 3.0), -np.cos(_ALPHA - math.pi / 3.0)], -1)
    P = base + (l0 / _SQRT3 + state.lambda10)[..., None] * _E  # (N, 3, 2)
    Pd = state.dlambda10[..., None] * _E
    angle = _ALPHA + phi[:, None] - math.pi / 3.0
    d = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    dp = np.stack([-d[..., 1], d[..., 0]], axis=-1)
    (c1x, c1y), (c2x, c2y) = robot.piston.com, robot.link.com
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    r1 = P + c1x * _E + c1y * _N
    o2 = c2x * d + c2y * dp
    r2 = P + o2
    w = state.velocity[:, 2, None, None]
    v2 = Pd + w * np.stack([-o2[..., 1], o2[..., 0]], axis=-1)
    G, Gd = state.pose[:, :2], state.velocity[:, :2]
    moment = m1 * r1.sum(axis=1) + m2 * r2.sum(axis=1) + m3 * G
    momentum = m1 * Pd.sum(axis=1) + m2 * v2.sum(axis=1) + m3 * Gd
    return moment, momentum


@dataclass(frozen=True)
class GravityElement(Element):
    """The weight of the bodies (``Robot.gravity``, the paper's eq. 19).

    It enters the kernel through the inertial stage: each body needs
    ``m·(a_C − g)`` (eq. 22), so the fields are those of the model
    (``gravity_x, gravity_y``) and adds no applied force.  Potential
    energy ``−g·Σ m·r_C``; power ``g·Σ m·v_C`` (the payload's weight is the
    payload's).
    """

    name: str = "gravity"
    generated_c: bool = True

    def present(self, robot: Any) -> bool:
        return tuple(robot.gravity) != (0.0, 0.0)

    def power(self, robot: Any, state: State) -> FloatArray:
        return np.asarray(_weight_terms(robot, state)[1] @ np.asarray(robot.gravity))

    def potential(self, robot: Any, state: State) -> FloatArray | None:
        return np.asarray(-(_weight_terms(robot, state)[0] @ np.asarray(robot.gravity)))


def _payload_offset(robot: Any, state: State) -> tuple[FloatArray, FloatArray]:
    """The payload's mass centre from ``G`` (``Rot(φ)·c_p``) and its rate, ``(N, 2)``."""
    phi = state.pose[:, 2]
    cx, cy = robot.payload.com
    r = np.stack([np.cos(phi) * cx - np.sin(phi) * cy, np.sin(phi) * cx + np.cos(phi) * cy], -1)
    rd = state.velocity[:, 2, None] * np.stack([-r[:, 1], r[:, 0]], axis=-1)
    return r, rd


@dataclass(frozen=True)
class PayloadElement(Element):
    """A rigid body fixed to the platform (``[payload]``).

    It enters the kernel through the platform's standard parameters (mass,
    first moment about ``G``, inertia about ``G``; :meth:`inertial`), so the
    generated C code, the MJCF model (a welded body) and the regressor carry
    it as they carry the platform.  Its weight: potential ``−m_p·g·r_p``,
    power ``m_p·g·v_p``.
    """

    name: str = "payload"
    generated_c: bool = True

    def present(self, robot: Any) -> bool:
        return bool(robot.payload.present)

    def changes_statics(self, robot: Any) -> bool:
        return self.present(robot)

    def inertial(self, robot: Any) -> tuple[float, float, float, float]:
        """The platform's ``(m3, h3x, h3y, J3)`` with the payload added (about ``G``)."""
        m3, j3 = robot.platform.mass, robot.platform_inertia
        payload = robot.payload
        if not payload.present:
            return m3, 0.0, 0.0, j3
        mp, (cpx, cpy) = payload.mass, payload.com
        return m3 + mp, mp * cpx, mp * cpy, j3 + payload.inertia + mp * (cpx * cpx + cpy * cpy)

    def power(self, robot: Any, state: State) -> FloatArray:
        _, rd = _payload_offset(robot, state)
        v = state.velocity[:, :2] + rd
        return np.asarray(robot.payload.mass * (v @ np.asarray(robot.gravity)))

    def potential(self, robot: Any, state: State) -> FloatArray | None:
        r, _ = _payload_offset(robot, state)
        return np.asarray(
            -robot.payload.mass * ((state.pose[:, :2] + r) @ np.asarray(robot.gravity))
        )


@dataclass(frozen=True)
class LoadElement(Element):
    """The constant wrench of the environment on the platform (``[load]``): force at ``G``, moment.

    Applied to the platform, with the motion's time-varying wrench
    (:data:`WRENCH`) in :func:`prp3.mechanics.wrenches.body_wrenches`.  Its forces are known, not estimated
    (identification subtracts them); MuJoCo has no constant external force
    (the model stores it as the numeric ``prp3_load``).  Power ``F·Ġ + M·φ̇``.
    """

    name: str = "load"
    fields: tuple[str, ...] = ("load_x", "load_y", "load_moment")
    broadcast: tuple[str, ...] = ("load_x", "load_y", "load_moment")

    def present(self, robot: Any) -> bool:
        return bool(robot.load.present)

    def changes_statics(self, robot: Any) -> bool:
        return self.present(robot)

    def parameters(self, robot: Any) -> dict[str, float]:
        load = robot.load
        if not load.present:
            return {}
        return {"load_x": load.force[0], "load_y": load.force[1], "load_moment": load.moment}

    def power(self, robot: Any, state: State) -> FloatArray:
        fx, fy = robot.load.force
        v = state.velocity
        return np.asarray(fx * v[:, 0] + fy * v[:, 1] + robot.load.moment * v[:, 2])

    def mjcf_omissions(self, robot: Any) -> list[str]:
        if not robot.load.present:
            return []
        (fx, fy), m = robot.load.force, robot.load.moment
        wrench = ", ".join(number_text(v) for v in (fx, fy, 0.0, 0.0, 0.0, m))
        return [
            f"the constant [load]: apply it as data.xfrc_applied[platform_A] = ({wrench}) "
            "(numeric prp3_load)"
        ]


@dataclass(frozen=True)
class WrenchElement(Element):
    """The motion's time-varying wrench ``fx, fy, mz`` on the platform at ``G`` (``TRAJ.csv``).

    Not a robot's parameter (no field): :func:`prp3.mechanics.wrenches.body_wrenches` adds it
    to the constant load.  The generated C code has no input for it.
    Power ``f·Ġ + m_z·φ̇``.
    """

    name: str = "wrench"

    def power(self, robot: Any, state: State) -> FloatArray:
        if state.wrench is None:
            return np.zeros(state.pose.shape[0])
        return np.asarray((state.wrench * state.velocity).sum(axis=-1))


def _law(
    ops: Any, viscous: Value, coulomb: Value, mu: Value, smoothing: Value, rate: Value,
    normal: Value | None,
) -> Value:  # fmt: skip
    """``−(b·v + (c + μ·N)·s(v))`` with only the terms whose coefficients are not zero."""
    total: Value | None = None if is_zero(viscous) else viscous * rate
    level: Value | None = None if is_zero(coulomb) else coulomb
    if normal is not None and not is_zero(mu):
        level = mu * normal if level is None else level + mu * normal
    if level is not None:
        term = level * rate_sign(ops, rate, smoothing)
        total = term if total is None else total + term
    return 0.0 if total is None else -total


_FRICTION_UNITS = {
    "actuator": ("N s/m", "N"),
    "revolute": ("N m s/rad", "N m"),
    "sleeve": ("N s/m", "N"),
}


@dataclass(frozen=True)
class FrictionElement(Element):
    """Friction of one kind of joint, the three legs alike (``[friction.KIND]``).

    ``fric = −(b·v + (c + μ·N)·s(v))`` with the joint's rate ``v`` (λ̇10, φ̇,
    λ̇32) and ``N`` the magnitude of its reaction (``|n10|``, ``r_r·|F21|``,
    ``|n32|``; the ``μ`` terms are implicit: :func:`prp3.mechanics.implicit_friction.solve_mu`).
    Linear in ``b`` and ``c`` (regressor columns); MuJoCo's ``damping`` and
    ``frictionloss`` carry ``b`` and (its own dry friction) ``c``.  Power
    ``Σ_i fric_i·v_i ≤ 0`` (dissipation).
    """

    kind: str = "actuator"

    def present(self, robot: Any) -> bool:
        return robot.friction is not None

    def _joint(self, robot: Any) -> Any:
        return getattr(robot.friction, self.kind)

    def parameters(self, robot: Any) -> dict[str, float]:
        if robot.friction is None:
            return {}
        joint = self._joint(robot)
        return {name: getattr(joint, name.split("_", 1)[1]) for name in self.fields}

    def mu(self, k: Any) -> Value:
        """The coefficient of the reaction magnitude (``μ``, ``μ_r·r_r`` for the pin)."""
        if self.kind == "revolute":
            return k.revolute_mu * k.revolute_pin_radius
        return getattr(k, f"{self.kind}_mu")

    def has_mu(self, k: Any) -> bool:
        """Whether its load-dependent term acts (the inverse dynamics is then implicit)."""
        if self.kind == "revolute":
            return not (is_zero(k.revolute_mu) or is_zero(k.revolute_pin_radius))
        return not is_zero(getattr(k, f"{self.kind}_mu"))

    def smoothing(self, k: Any) -> Value:
        """``v_s`` of ``s(v)``."""
        return getattr(k, f"{self.kind}_smoothing")

    def rates(self, kin: Any, dphi: Value) -> tuple[Value, Value, Value]:
        """The joint's relative rate per leg: ``λ̇10_i``, ``φ̇`` or ``λ̇32_i``."""
        if self.kind == "actuator":
            return kin.dlambda10  # type: ignore[no-any-return]
        if self.kind == "revolute":
            return (dphi, dphi, dphi)
        return kin.dlambda32  # type: ignore[no-any-return]

    def forces(
        self, ops: Any, k: Any, kin: Any, dphi: Value, normals: tuple[Value, Value, Value] | None
    ) -> tuple[Value, Value, Value]:
        """The friction force (or moment) of each leg; the ``μ`` terms only with ``normals``."""
        kind = self.kind
        viscous, coulomb = getattr(k, f"{kind}_viscous"), getattr(k, f"{kind}_coulomb")
        mu, smoothing, rates = self.mu(k), self.smoothing(k), self.rates(kin, dphi)
        a, b, c = (
            _law(ops, viscous, coulomb, mu, smoothing, rates[j],
                 None if normals is None else normals[j])
            for j in range(3)
        )  # fmt: skip
        return a, b, c

    def power(self, robot: Any, state: State) -> FloatArray:
        if state.friction is None:
            return np.zeros(state.pose.shape[0])
        index = ("actuator", "revolute", "sleeve").index(self.kind)
        rate = (state.dlambda10, np.broadcast_to(state.velocity[:, 2, None], state.dlambda10.shape),
                state.dlambda32)[index]  # fmt: skip
        return np.asarray((state.friction[index] * rate).sum(axis=-1))

    def dissipation(self, robot: Any, state: State) -> FloatArray:
        return np.asarray(-self.power(robot, state))

    def mjcf_joints(self, robot: Any) -> dict[str, dict[str, float]]:
        if robot.friction is None:
            return {}
        joint = self._joint(robot)
        attributes = {}
        if joint.viscous != 0.0:
            attributes["damping"] = float(joint.viscous)
        if joint.coulomb != 0.0:
            attributes["frictionloss"] = float(joint.coulomb)
        name = {"actuator": "lambda10", "revolute": "phi", "sleeve": "lambda32"}[self.kind]
        return {name: attributes} if attributes else {}

    def mjcf_omissions(self, robot: Any) -> list[str]:
        if robot.friction is None:
            return []
        joint, items = self._joint(robot), []
        if joint.has_mu:
            items.append(f"the load-dependent friction {self.name}.mu")
        if joint.smoothing != 0.0 and joint.coulomb != 0.0:
            items.append(
                f"the tanh smoothing {self.name}.smoothing (frictionloss is MuJoCo's own dry "
                "friction)"
            )
        return items

    def check_forward(self, robot: Any) -> None:
        """A Coulomb or ``μ`` term with the exact sign has no unique acceleration: refused."""
        if robot.friction is None:
            return
        joint = self._joint(robot)
        unit = "N·m" if self.kind == "revolute" else "N"
        for key, value, shown in (
            ("coulomb", joint.coulomb, f"{joint.coulomb!r} {unit}"),
            ("mu", joint.mu, f"{joint.mu!r}"),
        ):
            if value > 0.0 and joint.smoothing == 0.0:
                raise ParameterError(
                    f"{self.name}.{key} = {shown} with smoothing = 0 (the exact sign): "
                    f"forward dynamics needs {self.name}.smoothing > 0",
                    subject="robot",
                    key=f"{self.name}.{key}",
                )

    def check_mujoco_plant(self, robot: Any) -> None:
        """MuJoCo has no counterpart of prp3's Coulomb law or of the ``μ`` terms: refused."""
        if robot.friction is None:
            return
        joint = self._joint(robot)
        for key, value, law in (
            ("coulomb", joint.coulomb, "prp3's Coulomb friction law (its frictionloss is "
             "its own dry friction)"),
            ("mu", joint.mu, "the load-dependent friction (mu)"),
        ):  # fmt: skip
            if value != 0.0:
                raise ParameterError(
                    f"plant 'mujoco': {self.name}.{key} = {value!r}: MuJoCo has no "
                    f"counterpart of {law}: simulate it with plant 'prp3'"
                )

    def identified(self, robot: Any, values: dict[str, float]) -> Any:
        viscous, coulomb = values[f"{self.kind}_viscous"], values[f"{self.kind}_coulomb"]
        if robot.friction is None and viscous == 0.0 and coulomb == 0.0:
            return robot
        _refuse_negative(self, values)
        return robot.with_keys({f"{self.name}.viscous": viscous, f"{self.name}.coulomb": coulomb})


def _refuse_negative(element: Element, values: dict[str, float]) -> None:
    symbols, units = dict(element.symbols), dict(element.units)
    for name in element.regressor:
        if not values[name] >= 0.0:
            what = element.name.split(".")[0]
            raise ParameterError(
                f"{symbols[name]} = {values[name]!r} {units[name]}: a {what} coefficient must "
                "not be negative"
            )


def _friction_element(kind: str) -> FrictionElement:
    names = ["viscous", "coulomb", "mu"] + (["pin_radius"] if kind == "revolute" else [])
    fields = tuple(f"{kind}_{n}" for n in [*names, "smoothing"])
    linear = (f"{kind}_viscous", f"{kind}_coulomb")
    letter = kind[0]
    return FrictionElement(
        name=f"friction.{kind}",
        fields=fields,
        regressor=linear,
        kept=(f"{kind}_smoothing",),
        broadcast=linear,
        symbols=((linear[0], f"b_{letter}"), (linear[1], f"c_{letter}")),
        units=tuple(zip(linear, _FRICTION_UNITS[kind], strict=True)),
        kind=kind,
    )


@dataclass(frozen=True)
class SpringElement(Element):
    """A linear spring with damper at each actuated joint (``[spring.actuator]``).

    Its force on piston i along ``e_i``:
    ``s_i = −k·(λ10_i − λ_rest) − c·λ̇10_i``; potential energy
    ``½·k·Σ_i (λ10_i − λ_rest)²``; power ``Σ_i s_i·λ̇10_i`` (the damper
    dissipates ``c·Σ_i λ̇10_i²``).  ``f10`` remains the whole force the actuator
    supplies (the spring helps it).  Linear and homogeneous in ``k`` (for the
    robot's ``λ_rest``) and ``c``: two regressor columns.  MuJoCo's own joint
    ``stiffness``, ``springref`` and ``damping`` on the ``lambda10_i`` sliders
    carry it exactly (their ``qpos`` is ``λ10_i``).
    """

    name: str = "spring.actuator"
    fields: tuple[str, ...] = ("spring_stiffness", "spring_rest", "spring_damping")
    regressor: tuple[str, ...] = ("spring_stiffness", "spring_damping")
    kept: tuple[str, ...] = ("spring_rest",)
    broadcast: tuple[str, ...] = ("spring_stiffness", "spring_rest", "spring_damping")
    symbols: tuple[tuple[str, str], ...] = (
        ("spring_stiffness", "k_sp"),
        ("spring_damping", "c_sp"),
    )
    units: tuple[tuple[str, str], ...] = (("spring_stiffness", "N/m"), ("spring_damping", "N s/m"))
    generated_c: bool = True

    def present(self, robot: Any) -> bool:
        return robot.spring is not None

    def parameters(self, robot: Any) -> dict[str, float]:
        if robot.spring is None:
            return {}
        s = robot.spring.actuator
        return {"spring_stiffness": s.stiffness, "spring_rest": s.rest, "spring_damping": s.damping}

    def changes_statics(self, robot: Any) -> bool:
        return robot.spring is not None and robot.spring.actuator.stiffness != 0.0

    def _stretch(self, robot: Any, state: State) -> tuple[FloatArray, FloatArray]:
        s = robot.spring.actuator
        force = -s.stiffness * (state.lambda10 - s.rest) - s.damping * state.dlambda10
        return force, state.lambda10 - s.rest

    def power(self, robot: Any, state: State) -> FloatArray:
        if robot.spring is None:
            return np.zeros(state.pose.shape[0])
        force, _ = self._stretch(robot, state)
        return np.asarray((force * state.dlambda10).sum(axis=-1))

    def potential(self, robot: Any, state: State) -> FloatArray | None:
        if robot.spring is None:
            return None
        _, stretch = self._stretch(robot, state)
        return np.asarray(0.5 * robot.spring.actuator.stiffness * (stretch * stretch).sum(axis=-1))

    def dissipation(self, robot: Any, state: State) -> FloatArray:
        """The damper's ``c·Σ_i λ̇10_i²``."""
        if robot.spring is None:
            return np.zeros(state.pose.shape[0])
        rate = state.dlambda10
        return np.asarray(robot.spring.actuator.damping * (rate * rate).sum(axis=-1))

    def mjcf_joints(self, robot: Any) -> dict[str, dict[str, float]]:
        if robot.spring is None:
            return {}
        s, attributes = robot.spring.actuator, {}
        if s.stiffness != 0.0:
            attributes["stiffness"] = float(s.stiffness)
            if s.rest != 0.0:
                attributes["springref"] = float(s.rest)
        if s.damping != 0.0:
            attributes["damping"] = float(s.damping)
        return {"lambda10": attributes} if attributes else {}

    def identified(self, robot: Any, values: dict[str, float]) -> Any:
        stiffness, damping = values["spring_stiffness"], values["spring_damping"]
        if robot.spring is None and stiffness == 0.0 and damping == 0.0:
            return robot
        _refuse_negative(self, values)
        return robot.with_keys(
            {f"{self.name}.stiffness": stiffness, f"{self.name}.damping": damping}
        )


#: The elements, in the order the kernel applies them.
GRAVITY = GravityElement()
PAYLOAD = PayloadElement()
LOAD = LoadElement()
WRENCH = WrenchElement()
FRICTIONS: tuple[FrictionElement, FrictionElement, FrictionElement] = (
    _friction_element("actuator"),
    _friction_element("revolute"),
    _friction_element("sleeve"),
)
SPRING = SpringElement()
ELEMENTS: tuple[Element, ...] = (GRAVITY, PAYLOAD, LOAD, WRENCH, *FRICTIONS, SPRING)


def effect_fields() -> tuple[str, ...]:
    """Every field of :class:`~prp3.mechanics.parameters.KernelParameters` an element owns, in order."""
    return tuple(name for element in ELEMENTS for name in element.fields)
