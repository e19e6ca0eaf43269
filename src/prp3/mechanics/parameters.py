"""The robot's constants as the kernel uses them: :class:`KernelParameters`.

Each body enters through its standard (barycentric-free) inertial parameters
— mass, first moments ``m·c`` and the inertia about its reference point —,
in which the joint forces are linear (the regressor of identification); every
other field belongs to one element of :mod:`prp3.model.elements`.  The fields
are floats (:func:`kernel_parameters` of a robot) or sympy symbols
(:func:`symbolic_parameters`).
"""

from __future__ import annotations

from dataclasses import dataclass

from prp3.mechanics.ops import Value
from prp3.model import elements as _elements
from prp3.model.elements import FRICTIONS, LOAD, PAYLOAD
from prp3.model.robot import Robot

__all__ = [
    "EFFECT_FIELDS",
    "INERTIAL_FIELDS",
    "KernelParameters",
    "kernel_parameters",
    "symbolic_parameters",
]


@dataclass(frozen=True)
class KernelParameters:
    """The robot's constants as the closed form uses them (floats or sympy symbols).

    The inertial parameters of each body are its standard (barycentric-free)
    parameters: mass, first moments ``m·c`` and the inertia about the body's
    reference point.  The joint forces are linear in them (the regressor of
    identification), and a payload adds to the platform's.

    Attributes
    ----------
    l0 : Value
        Circumradius of base and platform (m).
    gravity_x, gravity_y : Value
        Gravity ``g`` (m/s²).
    piston_mass : Value
        ``m1`` (kg).
    piston_moment_x, piston_moment_y : Value
        ``m1·c1`` along ``(e_i, n_i)`` (kg·m), about ``P_i``.
    link_mass : Value
        ``m2`` (kg).
    link_moment_x, link_moment_y : Value
        ``m2·c2`` along ``(d_i, d⊥_i)`` (kg·m), about ``P_i``.
    link_inertia : Value
        ``I2 + m2·|c2|²``: link 2's inertia about ``P_i`` (kg·m²).
    platform_mass : Value
        ``m3`` (kg).
    platform_moment_x, platform_moment_y : Value
        First moment about ``G`` in the platform frame (kg·m): zero for the
        platform alone (``G`` is its mass centre).
    platform_inertia : Value
        Inertia about ``G`` (kg·m²).
    load_x, load_y, load_moment : Value
        The constant wrench of the environment on the platform (``[load]``):
        force at ``G`` in the fixed frame (N), moment about ``z0`` (N·m).
    actuator_viscous, actuator_coulomb, actuator_mu, actuator_smoothing : Value
        Friction of the base guide on piston i (``b_a, c_a, μ_a, v_s``).
    revolute_viscous, revolute_coulomb, revolute_mu, revolute_pin_radius, revolute_smoothing : Value
        Friction of the revolute joint at ``P_i`` (``b_r, c_r, μ_r, r_r``, smoothing).
    sleeve_viscous, sleeve_coulomb, sleeve_mu, sleeve_smoothing : Value
        Friction of the sleeve of link 2 on the platform (``b_s, c_s, μ_s``, smoothing).
    spring_stiffness, spring_rest, spring_damping : Value
        The spring with damper of each actuated joint (``k``, ``λ_rest``, ``c``).
    revolute_spring_stiffness, revolute_spring_rest, revolute_spring_damping : Value
        The torsion spring with damper of each revolute joint, on ``φ`` (``k_r``, ``φ_rest``, ``c_r``).
    sleeve_spring_stiffness, sleeve_spring_rest, sleeve_spring_damping : Value
        The spring with damper of each sleeve, on ``λ32_i`` (``k_s``, ``λ32_rest``, ``c_s``).

    Every field after ``platform_inertia`` belongs to one element of
    :mod:`prp3.model.elements` (:data:`EFFECT_FIELDS`) and defaults to ``0.0``; a
    field that is the number zero adds no operation at all (the results are
    bit for bit those without it).
    """

    l0: Value
    gravity_x: Value
    gravity_y: Value
    piston_mass: Value
    piston_moment_x: Value
    piston_moment_y: Value
    link_mass: Value
    link_moment_x: Value
    link_moment_y: Value
    link_inertia: Value
    platform_mass: Value
    platform_moment_x: Value
    platform_moment_y: Value
    platform_inertia: Value
    load_x: Value = 0.0
    load_y: Value = 0.0
    load_moment: Value = 0.0
    actuator_viscous: Value = 0.0
    actuator_coulomb: Value = 0.0
    actuator_mu: Value = 0.0
    actuator_smoothing: Value = 0.0
    revolute_viscous: Value = 0.0
    revolute_coulomb: Value = 0.0
    revolute_mu: Value = 0.0
    revolute_pin_radius: Value = 0.0
    revolute_smoothing: Value = 0.0
    sleeve_viscous: Value = 0.0
    sleeve_coulomb: Value = 0.0
    sleeve_mu: Value = 0.0
    sleeve_smoothing: Value = 0.0
    spring_stiffness: Value = 0.0
    spring_rest: Value = 0.0
    spring_damping: Value = 0.0
    revolute_spring_stiffness: Value = 0.0
    revolute_spring_rest: Value = 0.0
    revolute_spring_damping: Value = 0.0
    sleeve_spring_stiffness: Value = 0.0
    sleeve_spring_rest: Value = 0.0
    sleeve_spring_damping: Value = 0.0

    @property
    def has_mu(self) -> bool:
        """Whether a load-dependent friction term acts: the inverse dynamics is implicit."""
        return any(element.has_mu(self) for element in FRICTIONS)

    @property
    def has_friction(self) -> bool:
        """Whether a friction element acts (its forces read the joint rates' signs)."""
        return any(element.acts(self) for element in FRICTIONS)


#: The inertial (and geometric) fields of :class:`KernelParameters`: those of the paper's model.
INERTIAL_FIELDS: tuple[str, ...] = (
    "l0", "gravity_x", "gravity_y", "piston_mass", "piston_moment_x", "piston_moment_y",
    "link_mass", "link_moment_x", "link_moment_y", "link_inertia", "platform_mass",
    "platform_moment_x", "platform_moment_y", "platform_inertia",
)  # fmt: skip

#: The fields of :class:`KernelParameters` that the elements own (``0.0`` unless given).
EFFECT_FIELDS: tuple[str, ...] = _elements.effect_fields()


def kernel_parameters(robot: Robot) -> KernelParameters:
    """The constants of ``robot`` for :func:`prp3.mechanics.kernel.solve` (floats).

    >>> kernel_parameters(Robot()).platform_inertia   # m3·l²/12, l = l0·√3
    0.0675
    """
    m1, m2 = robot.piston.mass, robot.link.mass
    c1x, c1y = robot.piston.com
    c2x, c2y = robot.link.com
    m3, h3x, h3y, j3 = PAYLOAD.inertial(robot)  # a payload adds to the platform's parameters
    effects: dict[str, float] = {}
    for element in robot.elements:
        effects.update(element.parameters(robot))
    return KernelParameters(
        l0=robot.l0,
        gravity_x=robot.gravity[0],
        gravity_y=robot.gravity[1],
        piston_mass=m1,
        piston_moment_x=m1 * c1x,
        piston_moment_y=m1 * c1y,
        link_mass=m2,
        link_moment_x=m2 * c2x,
        link_moment_y=m2 * c2y,
        link_inertia=robot.link.inertia + m2 * (c2x * c2x + c2y * c2y),
        platform_mass=m3,
        platform_moment_x=h3x,
        platform_moment_y=h3y,
        platform_inertia=j3,
        **effects,
    )


def symbolic_parameters(*, effects: bool = False) -> KernelParameters:
    """The parameters of :class:`KernelParameters` as sympy symbols of their fields' names.

    The inertial fields (:data:`INERTIAL_FIELDS`) are symbols; with
    ``effects=True`` also the constant load and the regressor fields of the
    elements (:attr:`prp3.model.elements.Element.regressor`: the viscous and Coulomb
    coefficients, exact sign, the spring's stiffness and damping), the other
    fields staying ``0`` (the ``μ`` terms are implicit, no closed form).
    """
    import sympy

    names = INERTIAL_FIELDS
    if effects:  # the constant load and the fields the joint forces are linear in
        names += LOAD.fields + tuple(n for e in _elements.ELEMENTS for n in e.regressor)
    return KernelParameters(**{name: sympy.Symbol(name, real=True) for name in names})
