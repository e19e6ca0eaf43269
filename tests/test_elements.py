"""The effects as elements (``prp3.model.elements``): one place per effect, asked by every consumer.

Structure: every field of the kernel's parameters after the inertial ones
belongs to exactly one element, and what an element declares (regressor,
kept, broadcast fields, symbols, units) are its own fields.  Consumers: what
they accept follows the element's capability, not a list of their own (a
spring declared unsupported by C is refused by ``prp3 export c`` by name;
the identification parameters and the design broadcast fields are the
elements').  The numbers of each element are checked where they are used
(``test_loads_friction``, ``test_energy``, ``test_codegen``, ``test_mjcf``,
``test_identification``, ``test_sweep``, ``test_forward_loads``).
"""

from __future__ import annotations

import dataclasses

import pytest

import prp3.apps.design_evaluation
import prp3.apps.regressor
import prp3.model.robot
from prp3.apps.codegen import c_inverse_dynamics
from prp3.errors import ParameterError
from prp3.mechanics.parameters import EFFECT_FIELDS, INERTIAL_FIELDS, KernelParameters
from prp3.model.element_base import Element
from prp3.model.elements import ELEMENTS, SPRING
from prp3.model.parameters import Friction, JointFriction, Load, Payload, Spring, SpringParameters
from prp3.model.robot import Robot


def test_every_effect_field_belongs_to_exactly_one_element() -> None:
    names = [f.name for f in dataclasses.fields(KernelParameters)]
    assert names == [*INERTIAL_FIELDS, *EFFECT_FIELDS]
    owned = [name for element in ELEMENTS for name in element.fields]
    assert sorted(owned) == sorted(EFFECT_FIELDS) and len(set(owned)) == len(owned)
    for element in ELEMENTS:
        assert {*element.regressor, *element.kept, *element.broadcast} <= set(element.fields)
        assert [n for n, _ in element.symbols] == list(element.regressor)
        assert [n for n, _ in element.units] == list(element.regressor)


def test_a_robot_lists_the_elements_it_has() -> None:
    robot = Robot(
        gravity=(0.0, 0.0),
        payload=Payload(mass=1.0),
        load=Load(moment=1.0),
        friction=Friction(sleeve=JointFriction(viscous=1.0)),
        spring=Spring(SpringParameters(stiffness=1.0)),
    )
    assert [e.name for e in robot.elements] == [
        "payload", "load", "friction.actuator", "friction.revolute", "friction.sleeve",
        "spring.actuator",
    ]  # fmt: skip
    assert Robot().elements == (ELEMENTS[0],)


def test_consumers_follow_the_elements(monkeypatch: pytest.MonkeyPatch) -> None:
    # identification's parameters and design's broadcast fields are the elements'
    assert prp3.apps.regressor.ELEMENT_PARAMETERS == tuple(n for e in ELEMENTS for n in e.regressor)
    assert {
        n for e in ELEMENTS for n in e.broadcast
    } <= prp3.apps.design_evaluation.BROADCAST_FIELDS
    # the C code supports the spring because its element says so: declared otherwise, the
    # robot is refused by the element's name
    robot = Robot(spring=Spring(SpringParameters(stiffness=10.0)))
    assert "prp3_spring_stiffness" in c_inverse_dynamics(robot).source
    unsupported: Element = dataclasses.replace(SPRING, generated_c=False)
    elements = tuple(unsupported if e is SPRING else e for e in ELEMENTS)
    monkeypatch.setattr(prp3.model.robot, "ELEMENTS", elements)
    with pytest.raises(ParameterError, match=r"not \[spring\.actuator\]"):
        c_inverse_dynamics(robot)
