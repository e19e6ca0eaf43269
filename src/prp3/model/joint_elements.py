"""The elements of the joints: the friction of each kind of joint and the actuators' spring.

Each class is one effect of :mod:`prp3.model.elements` (the interface:
:class:`~prp3.model.element_base.Element`): the friction of one kind of joint,
the three legs alike (:class:`FrictionElement`, one per kind by
:func:`friction_element`), and the linear spring with damper of the actuated
joints (:class:`SpringElement`).  The module imports nothing of prp3 but the
errors and the element base.

>>> sleeve = friction_element("sleeve")
>>> sleeve.name, sleeve.regressor
('friction.sleeve', ('sleeve_viscous', 'sleeve_coulomb'))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from prp3.errors import ParameterError
from prp3.model.element_base import Element, FloatArray, State, Value, is_zero, rate_sign

__all__ = [
    "SMOOTHING_FLOOR",
    "SPRING_KINDS",
    "FrictionElement",
    "SpringElement",
    "friction_element",
    "spring_element",
    "spring_force",
]

#: Forward dynamics refuses a Coulomb or ``μ`` smoothing below this fraction of the
#: robot's size per second (``l0`` m/s; rad/s for the revolute joints): the round-off of
#: the joint rates (``prp3.path_validation.RATE_TOLERANCE``), which float64 cannot
#: tell from the exact sign.
SMOOTHING_FLOOR: float = 1e-12


def spring_force(
    stiffness: Value, rest: Value, damping: Value, displacement: Value, rate: Value
) -> Value:
    """The force of a linear spring with damper on its joint: ``s = −k·(λ − λ_rest) − c·λ̇``.

    Plain arithmetic, written once: the kernel applies it to each piston
    (:func:`prp3.mechanics.wrenches.body_wrenches`, compiled by numba, traced
    for C, run on sympy for the regressor) and :class:`SpringElement` takes its
    power from it.

    >>> spring_force(100.0, 0.01, 2.0, 0.03, 0.5)
    -3.0
    """
    return -(stiffness * (displacement - rest)) - damping * rate


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
            floor = SMOOTHING_FLOOR * (1.0 if self.kind == "revolute" else robot.l0)
            if value > 0.0 and 0.0 < joint.smoothing < floor:
                speed = "rad/s" if self.kind == "revolute" else "m/s"
                raise ParameterError(
                    f"{self.name}.smoothing = {joint.smoothing!r} {speed} with {key} = {shown}: "
                    f"below the round-off of the joint rates ({floor:.3g} {speed}, "
                    f"{SMOOTHING_FLOOR:g} of the robot's size per second), float64 cannot "
                    "resolve it from the exact sign; forward dynamics needs "
                    f"{self.name}.smoothing >= {floor:.3g}",
                    subject="robot",
                    key=f"{self.name}.smoothing",
                )
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


def friction_element(kind: str) -> FrictionElement:
    """The friction element of the joints of kind ``kind`` (``"actuator"``, ``"revolute"``, ``"sleeve"``)."""
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
    """A linear spring with damper on one kind of joint (``[spring.KIND]``), the three legs alike.

    Its force on the joint's outer body, along the joint (a moment, on the revolute
    joint): ``s_i = −k·(q_i − q_rest) − c·q̇_i`` (:func:`spring_force`), ``q_i`` the
    joint's coordinate: ``λ10_i`` on piston i along ``e_i`` (``[spring.actuator]``);
    ``φ`` of piston i on link 2 about ``z0`` (``[spring.revolute]``: link 2 turns with
    the platform, eq. 7, so every leg's joint turns by ``φ``); ``λ32_i`` of link 2 on
    the platform along ``d_i`` (``[spring.sleeve]``).  Potential energy
    ``½·k·Σ_i (q_i − q_rest)²``; power ``Σ_i s_i·q̇_i`` (the damper dissipates
    ``c·Σ_i q̇_i²``).  ``f10`` remains the whole force the actuator supplies (a spring
    helps it).  Linear and homogeneous in ``k`` (for the robot's ``q_rest``) and ``c``:
    two regressor columns.  MuJoCo's own joint ``stiffness``, ``springref`` and
    ``damping`` carry it exactly (the ``qpos`` of the joints ``lambda10_i``, ``phi_i``,
    ``lambda32_i`` are ``λ10_i``, ``φ``, ``λ32_i``).

    Adding an effect is one element like this one: its fields in
    :class:`~prp3.mechanics.parameters.KernelParameters`, its force in the kernel's
    :func:`prp3.mechanics.wrenches.body_wrenches`, its power, potential and dissipation
    here, and its instance in :mod:`prp3.model.elements` (ARCHITECTURE.md, "A new
    element").
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
    kind: str = "actuator"

    def _spring(self, robot: Any) -> Any:
        """The robot's :class:`~prp3.model.parameters.SpringParameters` of this joint, or None."""
        if robot.spring is None:
            return None
        spring = getattr(robot.spring, self.kind)
        if self.kind != "actuator" and spring.is_zero:
            return None  # a zero spring off the actuators adds no operation
        return spring

    def present(self, robot: Any) -> bool:
        return self._spring(robot) is not None

    def parameters(self, robot: Any) -> dict[str, float]:
        s = self._spring(robot)
        if s is None:
            return {}
        stiffness, rest, damping = self.fields
        return {stiffness: s.stiffness, rest: s.rest, damping: s.damping}

    def changes_statics(self, robot: Any) -> bool:
        s = self._spring(robot)
        return s is not None and s.stiffness != 0.0

    def _coordinate(self, state: State) -> tuple[FloatArray, FloatArray]:
        """The joint coordinates ``q`` and rates ``q̇`` of the three legs, ``(N, 3)``."""
        if self.kind == "actuator":
            return state.lambda10, state.dlambda10
        if self.kind == "revolute":
            phi, dphi = state.pose[:, 2:3], state.velocity[:, 2:3]
            return np.repeat(phi, 3, axis=1), np.repeat(dphi, 3, axis=1)
        if state.lambda32 is None:
            raise ValueError("the sleeve's spring needs the state's lambda32")
        return state.lambda32, state.dlambda32

    def _stretch(self, robot: Any, state: State) -> tuple[FloatArray, FloatArray, FloatArray]:
        s = self._spring(robot)
        q, rate = self._coordinate(state)
        force = spring_force(s.stiffness, s.rest, s.damping, q, rate)
        return force, q - s.rest, rate

    def power(self, robot: Any, state: State) -> FloatArray:
        if self._spring(robot) is None:
            return np.zeros(state.pose.shape[0])
        force, _, rate = self._stretch(robot, state)
        return np.asarray((force * rate).sum(axis=-1))

    def potential(self, robot: Any, state: State) -> FloatArray | None:
        s = self._spring(robot)
        if s is None:
            return None
        _, stretch, _ = self._stretch(robot, state)
        return np.asarray(0.5 * s.stiffness * (stretch * stretch).sum(axis=-1))

    def dissipation(self, robot: Any, state: State) -> FloatArray:
        """The damper's ``c·Σ_i q̇_i²``."""
        s = self._spring(robot)
        if s is None:
            return np.zeros(state.pose.shape[0])
        _, _, rate = self._stretch(robot, state)
        return np.asarray(s.damping * (rate * rate).sum(axis=-1))

    def mjcf_joints(self, robot: Any) -> dict[str, dict[str, float]]:
        s = self._spring(robot)
        if s is None:
            return {}
        attributes: dict[str, float] = {}
        if s.stiffness != 0.0:
            attributes["stiffness"] = float(s.stiffness)
            if s.rest != 0.0:
                attributes["springref"] = float(s.rest)
        if s.damping != 0.0:
            attributes["damping"] = float(s.damping)
        joint = {"actuator": "lambda10", "revolute": "phi", "sleeve": "lambda32"}[self.kind]
        return {joint: attributes} if attributes else {}

    def identified(self, robot: Any, values: dict[str, float]) -> Any:
        stiffness_field, _, damping_field = self.fields
        stiffness, damping = values[stiffness_field], values[damping_field]
        if self._spring(robot) is None and stiffness == 0.0 and damping == 0.0:
            return robot
        _refuse_negative(self, values)
        return robot.with_keys(
            {f"{self.name}.stiffness": stiffness, f"{self.name}.damping": damping}
        )


#: The joints a spring can act on (``[spring.<kind>]`` of a robot file).
SPRING_KINDS: tuple[str, ...] = ("actuator", "revolute", "sleeve")


def spring_element(kind: str) -> SpringElement:
    """The spring with damper of the joints of kind ``kind`` (``"actuator"``, ``"revolute"``, ``"sleeve"``).

    >>> spring_element("sleeve").fields
    ('sleeve_spring_stiffness', 'sleeve_spring_rest', 'sleeve_spring_damping')
    """
    if not isinstance(kind, str) or kind not in SPRING_KINDS:
        raise ParameterError(
            f"kind must be one of {', '.join(SPRING_KINDS)}, got {kind!r}", key="kind"
        )
    if kind == "actuator":
        return SpringElement()
    prefix, letter = f"{kind}_spring", kind[0]
    stiffness, rest, damping = (f"{prefix}_{n}" for n in ("stiffness", "rest", "damping"))
    units = {"revolute": ("N m/rad", "N m s/rad"), "sleeve": ("N/m", "N s/m")}[kind]
    return SpringElement(
        name=f"spring.{kind}",
        fields=(stiffness, rest, damping),
        regressor=(stiffness, damping),
        kept=(rest,),
        broadcast=(stiffness, rest, damping),
        symbols=((stiffness, f"k_s{letter}"), (damping, f"c_s{letter}")),
        units=((stiffness, units[0]), (damping, units[1])),
        kind=kind,
    )
