"""A family robot as a MuJoCo MJCF model (``prp3 export mjcf`` of a family-form robot file).

:func:`family_mjcf_model` writes the closed chain of docs/family.md §2 as
MuJoCo XML text, in the plane ``x-y`` of MuJoCo's world (``z`` out of the
plane, gravity ``(g_x, g_y, 0)``).  It needs no MuJoCo installation.  Per leg
``i = A, B, C`` (index ``j``, ``σ_j = 2πj/3``) a chain of three bodies hangs
from the world:

``link1_i``
    placed at the joint-1 frame ``J_1`` (the placement ``joint1`` in the start
    frame ``(O, σ_j)``); its joint ``q1_i`` is a hinge about ``z`` at the body
    origin (R) or a slide along the body's ``x`` axis (P), so that the body
    frame is ``F_1`` and ``qpos = q1`` (rad or m, docs/family.md §2).  Mass,
    ``com`` (in ``F_1``) and ``I_zz`` of ``[link1]``.
``link2_i``
    at the placement ``joint2`` in ``F_1``, joint ``q2_i``: frame ``F_2``,
    ``qpos = q2``; ``[link2]``.
``platform_i``
    at ``joint3`` in ``F_2``, joint ``q3_i``: frame ``F_3``, ``qpos = q3``;
    one third of the platform, mass ``m/3`` and ``I_zz/3`` at the attachment
    origin (which is ``G`` when the leg is closed).

The motor ``actuator_i`` drives ``q{a}_i`` (``a = actuated``): ``ctrl = tau_i``
(N along ``+u_a`` for P, N·m about ``+z`` for R, gear 1, no control limit), the
sign convention of docs/family.md §7.  The welds ``weld_AB`` and ``weld_AC``
hold ``platform_B`` and ``platform_C`` at their closed pose relative to
``platform_A``: the closure ``E_j = (G, φ + σ_j)`` with ``E_j = F_3^j·T_P``
(``T_P`` the attachment placement) gives ``(F_3^A)⁻¹·F_3^j = T_P·Rot(σ_j)·T_P⁻¹``,
a constant written as each weld's ``relpose``.  The three thirds welded
together are one rigid body of mass ``m`` and inertia ``I`` about ``G``.

As for the 3-PRP (:mod:`prp3.apps.mjcf`): an ``I_zz`` below ``INERTIA_FLOOR·m·ℓ²``
(``ℓ`` = ``[leg] scale``) is written as that floor; masses below MuJoCo's
``MUJOCO_MIN_VALUE`` are refused; ``I_xx = I_yy = I_zz``; the ``[payload]`` is a
body without joint inside ``platform_A``; the constant ``[load]`` is the
custom numeric ``prp3_load`` to be applied as ``data.xfrc_applied[platform_A]``
(a :class:`~prp3.apps.mjcf.MjcfWarning` says so).  The keyframe ``closed`` holds
a configuration where the loops close: the family's joint values at rest at
the pose ``P̄``, the mean of the legs' home poses (docs/family.md §5; with the
default designs ``P̄ = 0`` and ``qpos = home``); it is left out when ``P̄`` is
out of reach or singular.  MuJoCo's reference
configuration ``qpos = 0`` need not close them (the welds' ``relpose`` is
explicit).  The inertial frame of ``platform_A`` is the platform frame
``(G, φ)``: the sensors ``platform_position`` and ``platform_orientation`` read
the pose.

>>> from prp3.family.model import FamilyRobot
>>> text = family_mjcf_model(FamilyRobot.default("3-RRR"))
>>> text.count("<joint name="), text.count("<motor "), text.count("<weld ")
(9, 3, 2)
>>> '<motor name="actuator_A" joint="q1_A"' in text
True
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from prp3.apps.mjcf import (
    MUJOCO_MIN_VALUE,
    SENSORS,
    inertial_element,
    num,
    payload_body,
    preamble,
    quat_z,
    vec,
    warn_left_out,
    welds_motors_load,
)
from prp3.errors import ParameterError, Prp3Error
from prp3.family.chain import SIGMA
from prp3.family.model import FamilyRobot
from prp3.model.motion import Motion
from prp3.validation import LEGS, check_instance

__all__ = ["closed_configuration", "family_mjcf_model", "joint_names", "weld_relpose"]

FloatArray = NDArray[np.float64]


def joint_names(robot: FamilyRobot) -> list[str]:
    """The model's joints in tree order: ``q1_A, q2_A, q3_A, q1_B, ...``.

    >>> from prp3.family.model import FamilyRobot
    >>> joint_names(FamilyRobot.default("3-RPR"))[:4]
    ['q1_A', 'q2_A', 'q3_A', 'q1_B']
    """
    check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    return [f"q{k}_{leg}" for leg in LEGS for k in (1, 2, 3)]


def closed_configuration(robot: FamilyRobot) -> list[float] | None:
    """``q`` of every leg at rest at the mean of the legs' home poses, or None (refused pose).

    >>> from prp3.family.model import FamilyRobot
    >>> robot = FamilyRobot.default("3-RPR")
    >>> q = closed_configuration(robot)
    >>> max(abs(a - b) for a, b in zip(q, robot.leg.home * 3)) < 1e-15
    True
    """
    from prp3.family.mechanics import family_kinematics

    try:
        kin = family_kinematics(robot, Motion.at_rest(robot.home_poses.mean(axis=0)))
    except Prp3Error:
        return None
    return [float(v) for v in kin.q.reshape(9)]


def _homogeneous(a: float, b: float, angle: float) -> FloatArray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, a], [s, c, b], [0.0, 0.0, 1.0]])


def weld_relpose(robot: FamilyRobot, leg: int) -> tuple[float, float, float]:
    """``(x, y, angle)`` of ``platform_{leg}`` in ``platform_A`` when the loops close.

    ``T_P·Rot(σ_j)·T_P⁻¹`` with ``T_P`` the attachment placement (module notes).

    >>> from prp3.family.model import FamilyRobot
    >>> [round(v, 12) for v in weld_relpose(FamilyRobot.default("3-RRR"), 0)]
    [0.0, 0.0, 0.0]
    """
    a, b, gamma = robot.leg.attachment
    placement = _homogeneous(a, b, gamma)
    relative = placement @ _homogeneous(0.0, 0.0, float(SIGMA[leg])) @ np.linalg.inv(placement)
    return (
        float(relative[0, 2]),
        float(relative[1, 2]),
        float(SIGMA[leg]),  # the rotation part of T_P·Rot(σ)·T_P⁻¹ is Rot(σ)
    )


def _joint(robot: FamilyRobot, k: int, leg: str) -> str:
    kind = "hinge" if robot.types[k] == "R" else "slide"
    axis = "0 0 1" if kind == "hinge" else "1 0 0"
    return f'<joint name="q{k + 1}_{leg}" type="{kind}" axis="{axis}"/>'


def _drawing(a: float, b: float, size: float, rgba: str) -> str:
    """A capsule from the body origin to ``(a, b)`` (a sphere when they nearly coincide)."""
    if math.hypot(a, b) < 10.0 * size:
        return f'<geom type="sphere" size="{num(size)}" rgba="{rgba}"/>'
    return (
        f'<geom type="capsule" size="{num(size / 2)}" '
        f'fromto="{vec(0.0, 0.0, 0.0, a, b, 0.0)}" rgba="{rgba}"/>'
    )


def unrepresented(robot: FamilyRobot) -> list[str]:
    """What of the robot the MJCF model does not carry: the constant ``[load]`` (applied by hand).

    >>> from prp3.family.model import FamilyRobot
    >>> unrepresented(FamilyRobot.default("3-RRR"))
    []
    """
    if not robot.load.present:
        return []
    fx, fy = robot.load.force
    return [
        "the constant [load]: apply it as data.xfrc_applied[platform_A] = "
        f"({num(fx)}, {num(fy)}, 0, 0, 0, {num(robot.load.moment)}) (numeric prp3_load)"
    ]


def family_mjcf_model(robot: FamilyRobot) -> str:
    """The family robot as a MuJoCo MJCF model (XML text), closed by two welds.

    Parameters
    ----------
    robot : FamilyRobot
        Architecture, actuation, leg A's chain, inertias, payload, load, gravity.

    Returns
    -------
    str
        MJCF text: 9 joints ``q{k}_{leg}`` in tree order (qpos = the family's
        ``q{k}`` of docs/family.md §2), 3 motors ``actuator_{leg}`` on
        ``q{a}_{leg}``, 2 welds, the keyframe ``closed`` (module notes).

    Warns
    -----
    MjcfWarning
        When the robot has a constant ``[load]`` (MJCF cannot hold it; see the module notes).

    Raises
    ------
    ParameterError
        If ``robot`` is not a :class:`FamilyRobot`, or ``link1.mass``,
        ``link2.mass`` or ``platform.mass / 3`` is below MuJoCo's smallest
        mass of a moving body, ``MUJOCO_MIN_VALUE`` (naming the key).
    """
    robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
    _check_masses(robot)
    warn_left_out(unrepresented(robot))
    lines = preamble(
        [
            f"  <!-- {robot.architecture} planar parallel robot (actuated joint {robot.actuated}),",
            "       written by prp3 (docs/family.md). Plane x-y, z out of the plane. Joints (qpos):",
            "       q1_i, q2_i, q3_i of leg i = the family's q1, q2, q3 (rad for R, m for P).",
            f"       Motors actuator_i: ctrl = tau_i on q{robot.actuated}_i. The platform is three",
            "       welded thirds platform_A/B/C (each m/3, I/3 at G). Geoms are drawings only. -->",
        ],
        robot.gravity,
    )
    for j in range(3):
        lines += _leg_chain(robot, j)
    welds = []
    for j in (1, 2):
        x, y, angle = weld_relpose(robot, j)
        welds.append((LEGS[j], f"{vec(x, y, 0.0)} {quat_z(angle)}"))
    motors = [f"q{robot.actuated}_{leg}" for leg in LEGS]
    lines += welds_motors_load(welds, motors, robot.load)
    closed = closed_configuration(robot)
    if closed is not None:
        lines += [
            "  <keyframe>",
            f'    <key name="closed" qpos="{vec(*closed)}"/>',
            "  </keyframe>",
        ]
    lines += SENSORS
    return "\n".join(lines) + "\n"


def _check_masses(robot: FamilyRobot) -> None:
    """Refuse a moving body MuJoCo cannot load: ``link1.mass``, ``link2.mass`` or
    ``platform.mass / 3`` below :data:`~prp3.apps.mjcf.MUJOCO_MIN_VALUE` (naming the key)."""
    for name, mass in (
        ("link1.mass", robot.link1.mass),
        ("link2.mass", robot.link2.mass),
        ("platform.mass", robot.platform.mass / 3.0),
    ):
        if mass < MUJOCO_MIN_VALUE:
            shown = "platform.mass / 3" if name == "platform.mass" else name
            raise ParameterError(
                f"{shown} = {mass!r} kg is below MuJoCo's smallest mass of a moving body "
                f"{MUJOCO_MIN_VALUE!r} kg (the MJCF model cannot carry it)",
                subject="robot",
                key=name,
            )


def _leg_chain(robot: FamilyRobot, j: int) -> list[str]:
    """Leg ``j``'s bodies ``link1_i`` / ``link2_i`` / ``platform_i`` at their placements
    (module notes), the payload inside ``platform_A``."""
    scale, placements, leg = robot.leg.scale, robot.leg.placements, LEGS[j]
    size = scale / 60.0
    a_p, b_p, gamma_p = robot.leg.attachment
    bodies = (
        ("link1", robot.link1.mass, robot.link1.com, robot.link1.inertia, "0.2 0.4 0.8 1"),
        ("link2", robot.link2.mass, robot.link2.com, robot.link2.inertia, "0.9 0.6 0.1 1"),
        ("platform", robot.platform.mass / 3.0, (a_p, b_p), robot.platform.inertia / 3.0,
         "0.3 0.7 0.3 1"),
    )  # fmt: skip
    sigma = float(SIGMA[j])
    c, s = math.cos(sigma), math.sin(sigma)
    lines: list[str] = []
    opened: list[str] = []
    for k, (name, mass, com, izz, rgba) in enumerate(bodies):
        a, b, gamma = (float(v) for v in placements[k])
        if k == 0:  # the placement joint1 in the start frame (O, σ_j)
            a, b, gamma = c * a - s * b, s * a + c * b, gamma + sigma
        ind = "    " + "  " * k
        nxt = placements[k + 1]
        lines += [
            f'{ind}<body name="{name}_{leg}" pos="{vec(a, b, 0.0)}" quat="{quat_z(gamma)}">',
            f"{ind}  " + _joint(robot, k, leg),
            f"{ind}  " + inertial_element(mass, com, izz, scale, gamma_p if k == 2 else 0.0),
            f"{ind}  " + _drawing(float(nxt[0]), float(nxt[1]), size, rgba),
        ]
        opened.append(f"{ind}</body>")
    if j == 0 and robot.payload.present:
        payload = robot.payload
        cg, sg = math.cos(gamma_p), math.sin(gamma_p)
        px, py = payload.com
        inner = "        "
        body = payload_body(payload, size, inner)
        # the payload's com is given in the platform frame E_A = T_P in F_3
        at = (a_p + cg * px - sg * py, b_p + sg * px + cg * py)
        body[0] = f'{inner}<body name="payload" pos="{vec(at[0], at[1], 0.0)}">'
        lines += body
    return lines + opened[::-1]
