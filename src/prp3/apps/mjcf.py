"""MuJoCo exchange: the robot as an MJCF model (``prp3 export mjcf``).

:func:`mjcf_model` writes the robot as MuJoCo XML text.  It needs no MuJoCo
installation (the library never imports ``mujoco``); loading, checking and
driving the model are described in ``docs/mujoco.md``.

The model is a kinematic tree closed by equality constraints, in the plane
``x-y`` of MuJoCo's world with ``z`` out of the plane and gravity
``(g_x, g_y, 0)`` from :attr:`~prp3.model.robot.Robot.gravity`.  Per leg
``i = A, B, C`` (bodies named with the leg's letter):

``piston_i``
    placed at ``P_i(λ10 = 0) = B_i0 + (l0/√3)·e_i`` with its ``x`` axis along
    ``e_i``; slide joint ``lambda10_i`` along ``e_i`` (qpos = ``λ10_i``, m),
    driven by the motor ``actuator_i`` (ctrl = ``f10_i`` in N, gear 1, no
    control limit).  Mass ``m1``, centre of mass ``c1`` along ``(e_i, n_i)``.
``link_i``
    hinge ``phi_i`` about ``z`` at ``P_i`` whose zero is chosen so that
    qpos = ``φ`` (the link turns with the platform, eq. 7); its ``x`` axis is
    ``d_i``.  Mass ``m2``, centre of mass ``c2`` along ``(d_i, d⊥_i)``, ``I2``.
``platform_i``
    one third of the platform: slide joint ``lambda32_i`` along ``d_i``
    (qpos = ``λ32_i``, m); the body frame is the platform's (origin ``G``,
    orientation ``φ``).  Mass ``m3/3`` at ``G``, ``I_zz = I3/3``.

The welds ``weld_AB`` and ``weld_AC`` glue ``platform_B`` and ``platform_C``
to ``platform_A`` (identity relative pose), which closes the two loops.
Splitting the platform into three thirds welded together is exact: the welded
thirds are one rigid body of mass ``m3`` and inertia ``I3`` about ``G``.

MuJoCo refuses moving bodies with zero mass or inertia.  An ``I_zz`` below
``INERTIA_FLOOR·m·l0²`` (10⁻¹⁰ of the body's natural scale; in particular a
zero one: the piston's default, or a user's zero link or platform inertia) is
written as that floor (and never below MuJoCo's ``MUJOCO_MIN_VALUE``): the
piston never turns, so its value cannot matter, and for a link or platform it
changes the forces by about 10⁻¹⁰ relative.  Masses below
``MUJOCO_MIN_VALUE`` (``m1``, ``m2``, ``m3/3``) are refused.  The out-of-plane
principal moments ``I_xx = I_yy`` are set equal to the (floored) ``I_zz``: no
joint moves out of the plane, so they never enter the planar motion; they only
have to be positive and to satisfy the triangle inequality.

Loads and friction (``docs/loads_and_friction.md``):

``payload``
    the robot's ``[payload]``, a body without joint inside ``platform_A``
    (welded to the platform) at ``com`` in the platform frame, with its mass
    and ``I_zz`` as given (a welded body may have zero mass or inertia).
joint ``damping`` and ``frictionloss``
    viscous friction ``b`` and constant Coulomb friction ``c`` of
    ``[friction.actuator]`` on ``lambda10_i``, ``[friction.revolute]`` on the
    hinges ``phi_i`` (their rate is ``φ̇``, the relative rate of piston and
    link) and ``[friction.sleeve]`` on ``lambda32_i``.
the constant ``[load]``
    MJCF has no constant external force: it is stored as the custom numeric
    ``prp3_load = (F_x, F_y, M_z)`` and must be applied by the user as
    ``data.xfrc_applied[platform_A] = (F_x, F_y, 0, 0, 0, M_z)`` (MuJoCo
    applies it at the body's centre of mass, ``G``).

What MuJoCo cannot represent is left out and named in one
:class:`MjcfWarning`: the load-dependent ``μ`` terms, the ``tanh`` smoothing
of the Coulomb terms (``frictionloss`` is MuJoCo's own soft dry friction),
and the constant load (applied by hand, as above).

Solver settings (see ``docs/mujoco.md``): timestep ``TIMESTEP``, RK4
integrator, contacts disabled, stiff welds (``solref = WELD_SOLREF``,
``solimp = WELD_SOLIMP``).  The geoms are only drawings (no mass, no contact).

>>> from prp3.model.robot import Robot
>>> text = mjcf_model(Robot())
>>> text.startswith("<mujoco model=\\"prp3\\">")
True
>>> text.count("<joint name="), text.count("<motor "), text.count("<weld ")
(9, 3, 2)
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from prp3.errors import ParameterError
from prp3.mechanics.geometry import ALPHA, LEG_AXIS, base_vertices, platform_vertices
from prp3.model.element_base import number_text
from prp3.model.parameters import Load, Payload
from prp3.model.robot import Robot
from prp3.validation import LEGS, check_robot

__all__ = [
    "INERTIA_FLOOR",
    "MIN_L0",
    "MUJOCO_MIN_VALUE",
    "TIMESTEP",
    "WELD_SOLIMP",
    "WELD_SOLREF",
    "MjcfWarning",
    "mjcf_model",
    "unrepresented",
]

#: Smallest ``l0`` exported (m): MuJoCo refuses a capsule ``fromto`` shorter than about 1e-7 m.
MIN_L0: float = 1e-6

#: An ``I_zz`` below ``INERTIA_FLOOR·m·l0²`` (zero, say) is written as that value.
INERTIA_FLOOR: float = 1e-10

#: MuJoCo's ``mjMINVAL``: it refuses moving bodies whose mass or a principal
#: moment of inertia is below this value (kg, kg·m²).
MUJOCO_MIN_VALUE: float = 1e-15

#: Simulation timestep written in the model (s).
TIMESTEP: float = 1e-4

#: ``solref`` of the loop-closing welds: time constant (s) and damping ratio.
#: Twice the timestep is the stiffest weld MuJoCo integrates stably (its
#: ``refsafe`` flag clamps smaller time constants to that value).
WELD_SOLREF: tuple[float, float] = (2.0 * TIMESTEP, 1.0)

#: ``solimp`` of the welds: impedance 0.9999 (MuJoCo's largest) at any violation.
WELD_SOLIMP: tuple[float, float, float, float, float] = (0.9999, 0.9999, 0.001, 0.5, 2.0)


class MjcfWarning(UserWarning):
    """Parts of the robot that the MJCF model cannot carry (named in the message)."""


#: The kinds of joint friction, in the order of the joints of a leg.


num = number_text


def vec(*values: float) -> str:
    return " ".join(num(v) for v in values)


def quat_z(angle: float) -> str:
    """Quaternion ``(w, x, y, z)`` of a rotation by ``angle`` (rad) about ``z``."""
    return vec(math.cos(angle / 2.0), 0.0, 0.0, math.sin(angle / 2.0))


def _inertia(mass: float, izz: float, l0: float) -> tuple[float, float, float]:
    """Principal moments ``(I_xx, I_yy, I_zz)`` written for a body (see module notes)."""
    izz = max(izz, INERTIA_FLOOR * mass * l0 * l0, MUJOCO_MIN_VALUE)
    return (izz, izz, izz)


def inertial_element(
    mass: float, com: tuple[float, float], izz: float, l0: float, angle: float = 0.0
) -> str:
    """The ``<inertial>`` of a body: its mass centre ``com`` in the body frame, its
    principal axes turned by ``angle`` (rad) about ``z`` when it is not 0."""
    turn = f' quat="{quat_z(angle)}"' if angle != 0.0 else ""
    return (
        f'<inertial pos="{vec(com[0], com[1], 0.0)}"{turn} mass="{num(mass)}" '
        f'diaginertia="{vec(*_inertia(mass, izz, l0))}"/>'
    )


def preamble(comment: list[str], gravity: tuple[float, float]) -> list[str]:
    """The model's opening, from ``<mujoco>`` (with the ``comment`` lines) to the light of
    the ``<worldbody>``: compiler, RK4 at :data:`TIMESTEP`, no contact, no joint defaults."""
    return [
        '<mujoco model="prp3">',
        *comment,
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"/>',
        f'  <option timestep="{num(TIMESTEP)}" integrator="RK4" '
        f'gravity="{vec(gravity[0], gravity[1], 0.0)}">',
        '    <flag contact="disable"/>',
        "  </option>",
        "  <default>",
        '    <geom contype="0" conaffinity="0" group="1"/>',
        '    <joint damping="0" armature="0" frictionloss="0"/>',
        "  </default>",
        "  <worldbody>",
        '    <light pos="0 0 3" dir="0 0 -1"/>',
    ]


def welds_motors_load(
    welds: list[tuple[str, str]], motor_joints: list[str], load: Load
) -> list[str]:
    """After the bodies: the welds of ``platform_A`` to ``platform_{leg}`` (``(leg, relpose)``
    each), a motor on each leg's joint of ``motor_joints`` (legs A, B, C) and the
    constant ``[load]`` as a custom numeric (MuJoCo does not apply it)."""
    solref, solimp = vec(*WELD_SOLREF), vec(*WELD_SOLIMP)
    lines = ["  </worldbody>", "  <equality>"]
    for leg, relpose in welds:
        lines.append(
            f'    <weld name="weld_A{leg}" body1="platform_A" body2="platform_{leg}" '
            f'relpose="{relpose}" solref="{solref}" solimp="{solimp}"/>'
        )
    lines += ["  </equality>", "  <actuator>"]
    for leg, joint in zip(LEGS, motor_joints, strict=True):
        lines.append(
            f'    <motor name="actuator_{leg}" joint="{joint}" gear="1" ctrllimited="false"/>'
        )
    lines.append("  </actuator>")
    if load.present:
        fx, fy = load.force
        lines += [
            "  <custom>",
            "    <!-- the constant [load] (N, N, N m): not applied by MuJoCo; set",
            "         data.xfrc_applied[platform_A] = (F_x, F_y, 0, 0, 0, M_z) -->",
            f'    <numeric name="prp3_load" data="{vec(fx, fy, load.moment)}"/>',
            "  </custom>",
        ]
    return lines


#: The model's end: the platform's pose as sensors.
SENSORS: tuple[str, ...] = (
    "  <sensor>",
    '    <framepos name="platform_position" objtype="body" objname="platform_A"/>',
    '    <framequat name="platform_orientation" objtype="body" objname="platform_A"/>',
    "  </sensor>",
    "</mujoco>",
)


def _joint_attributes(robot: Robot) -> dict[str, str]:
    """The attributes each of the robot's elements sets on the joints, by joint.

    ``lambda10``, ``phi``, ``lambda32`` map to their attribute text (empty
    without); the attributes of several elements on one joint add
    (:meth:`prp3.model.element_base.Element.mjcf_joints`: viscous friction and the
    spring's damper both give ``damping``).
    """
    merged: dict[str, dict[str, float]] = {"lambda10": {}, "phi": {}, "lambda32": {}}
    for element in robot.elements:
        for joint, attributes in element.mjcf_joints(robot).items():
            for name, value in attributes.items():
                merged[joint][name] = merged[joint].get(name, 0.0) + value
    return {
        joint: "".join(f' {name}="{num(value)}"' for name, value in attributes.items())
        for joint, attributes in merged.items()
    }


def unrepresented(robot: Robot) -> list[str]:
    """What of the robot's loads and friction the MJCF model does not carry.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    list of str
        One phrase per item, empty when the model is complete: the ``μ``
        terms, the ``tanh`` smoothing of Coulomb terms, a constant ``[load]``.

    Examples
    --------
    >>> from prp3.model.parameters import Friction, JointFriction
    >>> unrepresented(Robot(friction=Friction(sleeve=JointFriction(mu=0.1))))
    ['the load-dependent friction friction.sleeve.mu']
    """
    return [
        item for element in check_robot(robot).elements for item in element.mjcf_omissions(robot)
    ]


def payload_body(payload: Payload, size: float, ind: str) -> list[str]:
    """The payload as a body without joint (welded to its parent), drawn as a sphere."""
    com = payload.com
    inertia = num(payload.inertia)
    return [
        f'{ind}<body name="payload" pos="{vec(com[0], com[1], 0.0)}">',
        f'{ind}  <inertial pos="0 0 0" mass="{num(payload.mass)}" '
        f'diaginertia="{inertia} {inertia} {inertia}"/>',
        f'{ind}  <geom type="sphere" size="{num(2 * size)}" rgba="0.8 0.2 0.2 1"/>',
        f"{ind}</body>",
    ]


def mjcf_model(robot: Robot) -> str:
    """The robot as a MuJoCo MJCF model (XML text).

    Parameters
    ----------
    robot : Robot
        Robot parameters: ``l0``, gravity, masses, centres of mass, inertias,
        the payload, viscous and constant Coulomb friction.  ``robot.limits``
        are not exported (MuJoCo's joint ranges would add constraints; prp3
        checks the strokes itself).

    Returns
    -------
    str
        MJCF text: 9 joints in tree order (``lambda10_i``, ``phi_i``,
        ``lambda32_i`` for ``i = A, B, C``), 3 motors ``actuator_i`` on the
        ``lambda10_i`` sliders, 2 welds closing the loops.  At ``qpos = 0`` the
        robot is in the central configuration ``x = y = φ = 0``, where the
        welds are satisfied.

    Warns
    -----
    MjcfWarning
        Naming what the model leaves out (:func:`unrepresented`): ``μ``
        terms, ``tanh`` smoothing, the constant ``[load]``.

    Raises
    ------
    ParameterError
        If ``robot`` is not a :class:`~prp3.model.robot.Robot`, ``l0 < MIN_L0``, or a
        body mass (``m1``, ``m2`` or ``m3/3``) is below MuJoCo's smallest mass
        ``MUJOCO_MIN_VALUE``.

    Examples
    --------
    >>> from prp3.model.robot import Robot
    >>> 'gravity="0 -9.81 0"' in mjcf_model(Robot())
    True
    """
    _check_exportable(robot)
    warn_left_out(unrepresented(robot))
    l0 = robot.l0
    size = l0 / 30.0  # drawing thickness
    lines = preamble(
        [
            "  <!-- 3-PRP planar parallel robot (Staicu & Chablat), written by prp3.",
            "       Plane x-y, z out of the plane. Joints (qpos): lambda10_i (m), phi_i = platform",
            "       angle (rad), lambda32_i (m). Motors actuator_i: ctrl = f10_i (N) along e_i.",
            "       The platform is three welded thirds platform_A/B/C (each m3/3 at G, I3/3).",
            "       Geoms are drawings only: no mass, no contact. -->",
        ],
        robot.gravity,
    )
    lines += _base_triangle(base_vertices(robot), size)
    for i in range(3):
        lines += _leg_bodies(robot, i, size)
    welds = [(other, "0 0 0 1 0 0 0") for other in ("B", "C")]
    lines += welds_motors_load(welds, [f"lambda10_{leg}" for leg in LEGS], robot.load)
    lines += SENSORS
    return "\n".join(lines) + "\n"


def _check_exportable(robot: Robot) -> None:
    """Refuse what MuJoCo cannot load: not a :class:`Robot`, ``l0 < MIN_L0``, a body mass
    (``m1``, ``m2``, ``m3/3``) below :data:`MUJOCO_MIN_VALUE`."""
    if not isinstance(robot, Robot):
        raise ParameterError(f"robot must be a prp3.Robot, got {type(robot).__name__}")
    l0 = robot.l0
    if l0 < MIN_L0:
        raise ParameterError(
            f"robot: l0 = {l0!r} m is too small for a MuJoCo model (at least {MIN_L0!r} m: "
            "MuJoCo refuses geoms shorter than about 1e-7 m)"
        )
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    for name, mass in (("piston.mass", m1), ("link.mass", m2), ("platform.mass / 3", m3 / 3.0)):
        if mass < MUJOCO_MIN_VALUE:
            raise ParameterError(
                f"robot: {name} = {mass!r} kg is below MuJoCo's smallest body mass "
                f"{MUJOCO_MIN_VALUE!r} kg"
            )


def warn_left_out(left_out: list[str]) -> None:
    """One :class:`MjcfWarning` naming what the model leaves out (none when nothing is),
    pointed at the caller of the model writer that calls this."""
    if left_out:
        warnings.warn(
            "the MuJoCo model leaves out " + "; ".join(left_out), MjcfWarning, stacklevel=3
        )


def _base_triangle(base: np.ndarray, size: float) -> list[str]:
    """The base triangle ``B_A0 B_B0 B_C0`` drawn as three capsules of the world."""
    lines = []
    for k in range(3):
        a, b = base[k], base[(k + 1) % 3]
        lines.append(
            f'    <geom name="base_edge_{k}" type="capsule" size="{num(size / 2)}" '
            f'fromto="{vec(a[0], a[1], 0.0, b[0], b[1], 0.0)}" rgba="0.5 0.5 0.5 1"/>'
        )
    return lines


def _leg_bodies(robot: Robot, i: int, size: float) -> list[str]:
    """Leg ``i``'s chain ``piston_i`` / ``link_i`` / ``platform_i`` at the central
    configuration (module notes), the payload inside ``platform_A``."""
    l0, leg, alpha = robot.l0, LEGS[i], float(ALPHA[i])
    # P_i at λ10 = 0: B_i0 + (l0/√3)·e_i
    origin = base_vertices(robot)[i] + (l0 / math.sqrt(3.0)) * LEG_AXIS[i]
    # G − P_i at the central configuration, in link i's frame (x along d_i):
    # eq. (10) gives G − P_i = λ32·d_i + Rot(α_i + φ)·c, i.e. Rot(π/3)·c in that frame.
    c = 0.5 * l0 * np.array([1.0 / math.sqrt(3.0), 1.0])
    cos60, sin60 = 0.5, math.sqrt(3.0) / 2.0
    third_in_link = (cos60 * c[0] - sin60 * c[1], sin60 * c[0] + cos60 * c[1])
    corners = platform_vertices(robot, [0.0, 0.0, 0.0])  # in the platform frame at G
    # platform edge i runs through P_i along d_i, from corner i+1 to corner i+2
    start, end = corners[(i + 1) % 3], corners[(i + 2) % 3]
    slide_axis = alpha - math.pi / 3.0  # d_i in the platform frame at φ
    joints = _joint_attributes(robot)
    actuator, revolute, sleeve = joints["lambda10"], joints["phi"], joints["lambda32"]
    m1, m2, m3 = robot.piston.mass, robot.link.mass, robot.platform.mass
    payload, ind = robot.payload, "    "
    return [
        f'{ind}<body name="piston_{leg}" pos="{vec(origin[0], origin[1], 0.0)}" '
        f'quat="{quat_z(alpha)}">',
        f'{ind}  <joint name="lambda10_{leg}" type="slide" axis="1 0 0"{actuator}/>',
        f"{ind}  " + inertial_element(m1, robot.piston.com, robot.piston.inertia, l0),
        f'{ind}  <geom type="box" size="{vec(2 * size, size, size)}" rgba="0.2 0.4 0.8 1"/>',
        f'{ind}  <body name="link_{leg}" quat="{quat_z(-math.pi / 3.0)}">',
        f'{ind}    <joint name="phi_{leg}" type="hinge" axis="0 0 1"{revolute}/>',
        f"{ind}    " + inertial_element(m2, robot.link.com, robot.link.inertia, l0),
        f'{ind}    <geom type="cylinder" size="{vec(size, size)}" rgba="0.9 0.6 0.1 1"/>',
        f'{ind}    <body name="platform_{leg}" pos="{vec(*third_in_link, 0.0)}" '
        f'quat="{quat_z(math.pi / 3.0 - alpha)}">',
        f'{ind}      <joint name="lambda32_{leg}" type="slide" '
        f'axis="{vec(math.cos(slide_axis), math.sin(slide_axis), 0.0)}"{sleeve}/>',
        f"{ind}      " + inertial_element(m3 / 3.0, (0.0, 0.0), robot.platform_inertia / 3.0, l0),
        f'{ind}      <geom type="capsule" size="{num(size / 2)}" '
        f'fromto="{vec(start[0], start[1], 0.0, end[0], end[1], 0.0)}" '
        f'rgba="0.3 0.7 0.3 1"/>',
        *(payload_body(payload, size, ind + "      ") if i == 0 and payload.present else []),
        f"{ind}    </body>",
        f"{ind}  </body>",
        f"{ind}</body>",
    ]
