"""Effects as elements: each applied effect of the robot model written in one place.

The paper's model (section 3) is the inertia of the seven bodies; everything
that acts on them besides the actuators is an *element*: gravity, a payload
fixed to the platform, the constant ``[load]``, the motion's time-varying
wrench ``fx, fy, mz``, the friction of each kind of joint and the linear
spring with damper of each kind of joint.  An element says, in one class,

* which fields of :class:`prp3.mechanics.parameters.KernelParameters` it owns and their
  values for a robot (:meth:`Element.parameters`);
* where its contribution to the wrench each body needs is written: in
  :func:`prp3.mechanics.wrenches.body_wrenches` and its helpers (``_joint_springs``,
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

The interface is :class:`prp3.model.element_base.Element`; the classes are
in :mod:`prp3.model.body_elements` (gravity, payload, load, the motion's
wrench) and :mod:`prp3.model.joint_elements` (friction of each kind of joint,
the springs with dampers of each kind of joint); this module holds the one instance of each, in the
order the kernel applies them.  These modules import nothing of prp3 but the
errors and one another: the robot and the kernel's values are read by their
attributes.

>>> [element.name for element in ELEMENTS]  # doctest: +NORMALIZE_WHITESPACE
['gravity', 'payload', 'load', 'wrench', 'friction.actuator', 'friction.revolute',
 'friction.sleeve', 'spring.actuator', 'spring.revolute', 'spring.sleeve']
>>> SPRING.fields, SPRING.generated_c
(('spring_stiffness', 'spring_rest', 'spring_damping'), True)
"""

from __future__ import annotations

from prp3.model.body_elements import GravityElement, LoadElement, PayloadElement, WrenchElement
from prp3.model.element_base import Element
from prp3.model.joint_elements import (
    FrictionElement,
    SpringElement,
    friction_element,
    spring_element,
)

__all__ = [
    "ELEMENTS",
    "FRICTIONS",
    "GRAVITY",
    "LOAD",
    "PAYLOAD",
    "SPRING",
    "SPRINGS",
    "WRENCH",
    "effect_fields",
]

#: The elements, in the order the kernel applies them.
GRAVITY = GravityElement()
PAYLOAD = PayloadElement()
LOAD = LoadElement()
WRENCH = WrenchElement()
FRICTIONS: tuple[FrictionElement, FrictionElement, FrictionElement] = (
    friction_element("actuator"),
    friction_element("revolute"),
    friction_element("sleeve"),
)
SPRINGS: tuple[SpringElement, SpringElement, SpringElement] = (
    spring_element("actuator"),
    spring_element("revolute"),
    spring_element("sleeve"),
)
SPRING = SPRINGS[0]
ELEMENTS: tuple[Element, ...] = (GRAVITY, PAYLOAD, LOAD, WRENCH, *FRICTIONS, *SPRINGS)


def effect_fields() -> tuple[str, ...]:
    """Every field of :class:`~prp3.mechanics.parameters.KernelParameters` an element owns, in order."""
    return tuple(name for element in ELEMENTS for name in element.fields)
