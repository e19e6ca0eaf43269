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

__all__ = ["FrictionElement", "SpringElement", "friction_element", "spring_force"]


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
        force = spring_force(s.stiffness, s.rest, s.damping, state.lambda10, state.dlambda10)
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
