"""MuJoCo exchange of the spatial robots: MJCF with the loops closed (docs/spatial.md §16).

:func:`spatial_mjcf_model` writes a :class:`~prp3.spatial.model.SpatialRobot`
(the 6-UPS, the 3-RPS, the Delta as a 3-RUU) as MuJoCo XML text, and
:func:`read_spatial_mjcf` reads such a file back into the same robot.  Neither
imports MuJoCo (the file is written as text and read with :mod:`xml.etree`).

The model (names with the leg ``i = 1 … L`` and the joint labels of §9):

``leg{i}_body{k}``
    body ``k`` of leg ``i`` (between joints ``k`` and ``k + 1``), a child of body
    ``k − 1`` (of the world for ``k = 1``) placed by joint ``k``'s placement
    (``pos``, ``xyaxes``: the joint frame ``J_k`` at ``q = 0``); its body frame is
    the distal frame ``F_k`` of §2.  Its joints are joint ``k``'s coordinates,
    ``qpos`` = prp3's ``q``: an R is the hinge ``leg{i}_R{k}`` about ``z``, a P the
    slide ``leg{i}_P{k}`` along ``x``, a U the hinges ``leg{i}_U{k}_a`` about ``z``
    then ``leg{i}_U{k}_b`` about ``y`` (MuJoCo applies a body's joints in order:
    ``R_J·Rot_z(a)·Rot_y(b)``).  Its ``<inertial>`` is the body's mass, mass centre
    and inertia tensor about it in ``F_k`` (``diaginertia`` when the tensor is
    diagonal, else ``fullinertia``), exactly prp3's.
``platform``
    a free body (``freejoint`` named ``platform``: ``qpos = (p, quaternion of R)``,
    ``qvel = (v, Rᵀ·ω)``, ``qacc = (a, Rᵀ·α)``) whose frame is the platform frame
    ``(p, R)``, with the platform's inertial; the site ``platform_leg{i}`` is leg
    ``i``'s attachment ``(c_A, R_A)``.
the closing joint of each leg (the last, at the platform)
    an **S** is the equality ``<connect name="leg{i}_S{n}">`` of the site
    ``leg{i}_S{n}`` (the S's placement in the rod) and ``platform_leg{i}``: the
    two points coincide, the rotation is free — a ball joint closing the loop.
    Any other joint (the Delta's U) is written in the tree as above, into the body
    ``leg{i}_end`` whose frame is the leg's end ``F_n``, welded to the platform
    by ``<weld name="leg{i}_U{n}">`` of its site ``leg{i}_end`` and
    ``platform_leg{i}`` (the two frames coincide).  MuJoCo refuses a moving body
    without mass, so ``leg{i}_end`` carries :data:`END_MASS_FRACTION` of the
    platform's mass (at its origin, the joint point, and a matching small
    inertia): it moves the efforts by about ``1e-12`` relative.
``actuator_{i}``
    a ``<motor>`` on the actuated joint, ``gear = 1``, no control limit:
    ``ctrl = tau_i`` (N along a P's ``x``, N·m about an R's ``z``, on the distal
    body, the sign of §9).

Joint limits of an R, P or U coordinate are the joints' ``range`` (MuJoCo
enforces them; at prp3's poses, which are within them, they are inactive); a
limit that is infinite on one side and an S's rotation limit (MuJoCo has none
for a connect) are the custom numerics ``prp3_range_<joint>``.  What MJCF has no
element for is kept in ``<custom>``: ``prp3_spatial`` (the mark of a prp3 model),
``prp3_name``, ``prp3_parasitic``, ``prp3_home`` (the home position and rotation,
row by row), ``prp3_scale`` and the bodies' names ``prp3_body_*``.  The keyframe
``home`` is the configuration at the home pose, where every loop closes; MuJoCo's
``qpos = 0`` does not close them (the equalities are between sites, so this does
not matter).  Gravity is the robot's; contacts are disabled and the geoms are
drawings only (no mass, no contact).

>>> from prp3.spatial.model import hexapod
>>> text = spatial_mjcf_model(hexapod())
>>> text.count("<joint name="), text.count("<connect "), text.count("<motor ")
(18, 6, 6)
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
from numpy.typing import NDArray

from prp3.apps.mjcf import MUJOCO_MIN_VALUE, TIMESTEP, num, vec
from prp3.errors import InputFileError, ParameterError, Prp3Error
from prp3.files import read_text
from prp3.spatial.kinematics import spatial_kinematics
from prp3.spatial.model import Body, Joint, Leg, Matrix, SpatialRobot, check_rotation, check_vector
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.rotations import matrix_quaternion
from prp3.validation import check_file_path, check_instance

__all__ = [
    "END_MASS_FRACTION",
    "MAX_MJCF_BYTES",
    "SPATIAL_MJCF_MARK",
    "read_spatial_mjcf",
    "spatial_mjcf_joint_names",
    "spatial_mjcf_model",
    "spatial_mjcf_robot",
]

FloatArray = NDArray[np.float64]

#: The custom text that marks a model written by :func:`spatial_mjcf_model`.
SPATIAL_MJCF_MARK: str = "prp3_spatial"

#: The mass of a ``leg{i}_end`` body as a fraction of the platform's (module notes).
END_MASS_FRACTION: float = 1e-12

#: The largest MJCF file :func:`read_spatial_mjcf` reads (bytes).
MAX_MJCF_BYTES: int = 10_000_000

_IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def _orientation(rotation: tuple[tuple[float, float, float], ...]) -> str:
    """The ``xyaxes`` attribute of a rotation (its first two columns), empty for the identity."""
    if rotation == _IDENTITY:
        return ""
    r = np.asarray(rotation)
    return f' xyaxes="{vec(*r[:, 0], *r[:, 1])}"'


def _check_body(name: str, body: Body) -> None:
    """MuJoCo's bounds on a moving body: mass and principal moments above ``mjMINVAL``
    (the error's key is ``<body name>.mass`` or ``.inertia``)."""
    if body.mass < MUJOCO_MIN_VALUE:
        raise ParameterError(
            f"{name}.mass = {body.mass!r} kg is below MuJoCo's smallest mass of a moving body "
            f"{MUJOCO_MIN_VALUE!r} kg (the MJCF model cannot carry it)",
            subject="robot",
            key=f"{body.name}.mass",
        )
    smallest = float(np.linalg.eigvalsh(np.asarray(body.inertia)).min())
    if smallest < MUJOCO_MIN_VALUE:
        raise ParameterError(
            f"{name}.inertia has the principal moment {smallest:.6g} kg m^2, below MuJoCo's "
            f"smallest {MUJOCO_MIN_VALUE!r} kg m^2 (the MJCF model cannot carry it)",
            subject="robot",
            key=f"{body.name}.inertia",
        )


def _inertial(body: Body) -> str:
    i = body.inertia
    if i[0][1] == i[0][2] == i[1][2] == 0.0:
        tensor = f'diaginertia="{vec(i[0][0], i[1][1], i[2][2])}"'
    else:
        tensor = f'fullinertia="{vec(i[0][0], i[1][1], i[2][2], i[0][1], i[0][2], i[1][2])}"'
    return f'<inertial pos="{vec(*body.centre)}" mass="{num(body.mass)}" {tensor}/>'


def spatial_mjcf_joint_names(robot: SpatialRobot) -> list[str]:
    """The model's hinges and slides in ``qpos`` order (the free joint ``platform`` follows).

    Each leg's coordinates but those of a closing S (the connect), ``leg{i}_<coordinate>``.

    >>> from prp3.spatial.model import delta
    >>> spatial_mjcf_joint_names(delta())[:5]
    ['leg1_R1', 'leg1_U2_a', 'leg1_U2_b', 'leg1_U3_a', 'leg1_U3_b']
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    names = []
    for i, leg in enumerate(robot.legs, 1):
        for k, (joint, label) in enumerate(zip(leg.joints, leg.labels, strict=True)):
            if joint.kind == "S" and k == len(leg.joints) - 1:
                continue
            names += [f"leg{i}_{c}" for c in joint.coordinates(label)]
    return names


def _joint_elements(joint: Joint, label: str, leg: int, ind: str, numerics: list[str]) -> list[str]:
    """The hinges or slide of an R, P or U joint (``range`` when both limits are finite)."""
    axes = {"R": ["0 0 1"], "P": ["1 0 0"], "U": ["0 0 1", "0 1 0"]}[joint.kind]
    kind = "slide" if joint.kind == "P" else "hinge"
    lines = []
    for coordinate, axis, (low, high) in zip(
        joint.coordinates(label), axes, joint.limits, strict=True
    ):
        name = f"leg{leg}_{coordinate}"
        bounded = math.isfinite(low) and math.isfinite(high)
        limit = f' range="{vec(low, high)}"' if bounded else ""
        if not bounded and (low, high) != (-math.inf, math.inf):
            numerics.append(f'    <numeric name="prp3_range_{name}" data="{_limit(low, high)}"/>')
        lines.append(f'{ind}<joint name="{name}" type="{kind}" axis="{axis}"{limit}/>')
    return lines


def _limit(low: float, high: float) -> str:
    return " ".join("inf" if v == math.inf else "-inf" if v == -math.inf else num(v)
                    for v in (low, high))  # fmt: skip


def _home_qpos(robot: SpatialRobot) -> list[float] | None:
    """``qpos`` at rest at the home pose (every loop closed), or None (a refused home)."""
    try:
        kin = spatial_kinematics(
            robot, PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
        )
    except Prp3Error:
        return None
    qpos: list[float] = []
    for i, leg in enumerate(robot.legs):
        column = 0
        for k, joint in enumerate(leg.joints):
            if not (joint.kind == "S" and k == len(leg.joints) - 1):
                qpos += [float(v) for v in kin.q[0, i, column : column + joint.dof]]
            column += joint.dof
    quaternion = matrix_quaternion(np.asarray(robot.home_rotation))
    return [*qpos, *robot.home_position, *(float(v) for v in quaternion)]


def spatial_mjcf_model(robot: SpatialRobot) -> str:
    """The spatial robot as a MuJoCo MJCF model (XML text) with its loops closed.

    Parameters
    ----------
    robot : SpatialRobot
        Legs, bodies, platform, gravity, home pose (docs/spatial.md §2, §7, §11, §12).

    Returns
    -------
    str
        MJCF text (module notes; docs/spatial.md §16): each leg an open chain of
        bodies ``leg{i}_body{k}`` with its R, P, U joints, the free ``platform``,
        one equality per leg closing the loop (``connect`` for an S, ``weld`` of
        ``leg{i}_end`` otherwise), one motor per leg, the keyframe ``home``.

    Raises
    ------
    ParameterError
        ``robot`` is not a :class:`SpatialRobot`; a body's mass or a principal moment
        of its inertia is below MuJoCo's smallest, ``MUJOCO_MIN_VALUE`` (naming the
        body); an S that is not a leg's last joint.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    _check_mjcf_robot(robot)
    texts, numerics = _robot_customs(robot)
    lines = _preamble(robot)
    equalities: list[str] = []
    for i, leg in enumerate(robot.legs, 1):
        chain, closure = _leg_elements(robot, i, leg, texts, numerics)
        lines += chain
        equalities.append(closure)
    lines += _platform_elements(robot, texts)
    lines += ["  <equality>", *equalities, "  </equality>"]
    lines += _actuators(robot)
    lines += ["  <custom>", *texts, *numerics, "  </custom>"]
    home = _home_qpos(robot)
    if home is not None:
        lines += ["  <keyframe>", f'    <key name="home" qpos="{vec(*home)}"/>', "  </keyframe>"]
    lines += [
        "  <sensor>",
        '    <framepos name="platform_position" objtype="body" objname="platform"/>',
        '    <framequat name="platform_orientation" objtype="body" objname="platform"/>',
        "  </sensor>",
        "</mujoco>",
    ]
    return "\n".join(lines) + "\n"


def _check_mjcf_robot(robot: SpatialRobot) -> None:
    """Refuse what the model cannot carry: a body below MuJoCo's bounds (:func:`_check_body`),
    an S joint before a leg's last."""
    for i, leg in enumerate(robot.legs, 1):
        for k, body in enumerate(leg.bodies, 1):
            _check_body(f"leg {i} body {k} ({body.name})", body)
        if any(j.kind == "S" for j in leg.joints[:-1]):
            raise ParameterError(
                f"leg {i}: an S joint before the platform has no MJCF form here (only a "
                "closing S, as a connect)",
                subject="robot",
                key="legs",
            )
    _check_body("platform", robot.platform)


def _robot_customs(robot: SpatialRobot) -> tuple[list[str], list[str]]:
    """The ``<custom>`` lines of the robot as a whole: the texts (the mark, the name, the
    parasitic coordinates) and the numerics (the home pose, the scale); the legs' and the
    platform's lines are appended to these lists as their elements are written."""
    texts = [
        f'    <text name="{SPATIAL_MJCF_MARK}" data="prp3 spatial robot, docs/spatial.md 16"/>',
        f'    <text name="prp3_name" data={quoteattr(robot.name or " ")}/>',
        f'    <text name="prp3_parasitic" data={quoteattr(" ".join(robot.parasitic) or "none")}/>',
    ]
    numerics = [
        f'    <numeric name="prp3_home" '
        f'data="{vec(*robot.home_position, *np.asarray(robot.home_rotation).reshape(9))}"/>',
        f'    <numeric name="prp3_scale" data="{num(robot.scale)}"/>',
    ]
    return texts, numerics


def _preamble(robot: SpatialRobot) -> list[str]:
    """The lines up to the legs: the comment, compiler, option (gravity, no contact), the
    defaults and the opening of the worldbody with its light."""
    return [
        '<mujoco model="prp3_spatial">',
        f"  <!-- {robot.name} spatial parallel robot written by prp3 (docs/spatial.md §16).",
        "       Legs leg{i}: open chains of bodies leg{i}_body{k}, joints leg{i}_<coordinate>",
        "       (qpos = prp3's q); the free body platform (qpos = p, quaternion of R); the loops",
        "       closed by a connect (S) or a weld of leg{i}_end (U) per leg; motors actuator_{i}",
        "       (ctrl = tau_i). Geoms are drawings only: no mass, no contact. -->",
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"/>',
        f'  <option timestep="{num(TIMESTEP)}" integrator="RK4" gravity="{vec(*robot.gravity)}">',
        '    <flag contact="disable"/>',
        "  </option>",
        "  <default>",
        '    <geom contype="0" conaffinity="0" group="1"/>',
        '    <joint damping="0" armature="0" frictionloss="0"/>',
        "  </default>",
        "  <worldbody>",
        '    <light pos="0 0 3" dir="0 0 -1"/>',
    ]


def _leg_elements(
    robot: SpatialRobot, i: int, leg: Leg, texts: list[str], numerics: list[str]
) -> tuple[list[str], str]:
    """Leg ``i``'s nested bodies ``leg{i}_body{k}`` (joints, inertial, a sphere) with its
    closing joint inside the last, and the equality that closes its loop; the bodies' names
    are appended to ``texts``, the joints' custom ranges to ``numerics``."""
    n = len(leg.joints)
    size = robot.scale / 20.0
    lines: list[str] = []
    opened: list[str] = []
    for k in range(n - 1):
        joint, label, body = leg.joints[k], leg.labels[k], leg.bodies[k]
        ind = "    " + "  " * k
        texts.append(
            f'    <text name="prp3_body_leg{i}_{k + 1}" data={quoteattr(body.name or " ")}/>'
        )
        lines.append(
            f'{ind}<body name="leg{i}_body{k + 1}" pos="{vec(*joint.position)}"'
            f"{_orientation(joint.rotation)}>"
        )
        lines += _joint_elements(joint, label, i, ind + "  ", numerics)
        lines += [
            f"{ind}  " + _inertial(body),
            f'{ind}  <geom type="sphere" size="{num(size)}" rgba="0.2 0.4 0.8 1"/>',
        ]
        opened.append(f"{ind}</body>")
    closing, equality = _closing_elements(robot, i, leg, "    " + "  " * (n - 1), numerics)
    return [*lines, *closing, *opened[::-1]], equality


def _closing_elements(
    robot: SpatialRobot, i: int, leg: Leg, ind: str, numerics: list[str]
) -> tuple[list[str], str]:
    """Leg ``i``'s closing joint, indented ``ind``, and its equality: an S as the site
    ``leg{i}_S{n}`` and a ``connect`` (its rotation limit a custom numeric), any other joint
    as the body ``leg{i}_end`` (the small mass of :data:`END_MASS_FRACTION`) and a ``weld``."""
    last, label = leg.joints[-1], leg.labels[-1]
    if last.kind == "S":
        low, high = last.limits[0]
        numerics.append(
            f'    <numeric name="prp3_range_leg{i}_{label}" data="{_limit(low, high)}"/>'
        )
        site = (
            f'{ind}<site name="leg{i}_{label}" pos="{vec(*last.position)}"'
            f"{_orientation(last.rotation)}/>"
        )
        return [site], (
            f'    <connect name="leg{i}_{label}" site1="leg{i}_{label}" site2="platform_leg{i}"/>'
        )
    mass = END_MASS_FRACTION * robot.platform.mass
    inertia = max(mass * robot.scale**2, 10.0 * MUJOCO_MIN_VALUE)
    lines = [
        f'{ind}<body name="leg{i}_end" pos="{vec(*last.position)}"{_orientation(last.rotation)}>',
        *_joint_elements(last, label, i, ind + "  ", numerics),
        f'{ind}  <inertial pos="0 0 0" mass="{num(max(mass, 10.0 * MUJOCO_MIN_VALUE))}" '
        f'diaginertia="{vec(inertia, inertia, inertia)}"/>',
        f'{ind}  <site name="leg{i}_end"/>',
        f"{ind}</body>",
    ]
    return lines, f'    <weld name="leg{i}_{label}" site1="leg{i}_end" site2="platform_leg{i}"/>'


def _platform_elements(robot: SpatialRobot, texts: list[str]) -> list[str]:
    """The free body ``platform`` (inertial, a sphere, the legs' attachment sites
    ``platform_leg{i}``) and the end of the worldbody; its name is appended to ``texts``."""
    texts.append(
        f'    <text name="prp3_body_platform" data={quoteattr(robot.platform.name or " ")}/>'
    )
    lines = [
        '    <body name="platform">',
        '      <freejoint name="platform"/>',
        "      " + _inertial(robot.platform),
        f'      <geom type="sphere" size="{num(2 * (robot.scale / 20.0))}" rgba="0.3 0.7 0.3 1"/>',
    ]
    for i, leg in enumerate(robot.legs, 1):
        lines.append(
            f'      <site name="platform_leg{i}" pos="{vec(*leg.attachment_position)}"'
            f"{_orientation(leg.attachment_rotation)}/>"
        )
    return [*lines, "    </body>", "  </worldbody>"]


def _actuators(robot: SpatialRobot) -> list[str]:
    """The ``<actuator>`` section: a motor ``actuator_{i}`` on each leg's actuated joint."""
    lines = ["  <actuator>"]
    for i, leg in enumerate(robot.legs, 1):
        coordinate = leg.coordinates[leg.actuated_coordinate]
        lines.append(
            f'    <motor name="actuator_{i}" joint="leg{i}_{coordinate}" gear="1" '
            'ctrllimited="false"/>'
        )
    return [*lines, "  </actuator>"]


# ---------------------------------------------------------------- reading back
class _ForeignError(Exception):
    """A model that is not one :func:`spatial_mjcf_model` writes (the reason)."""


def _numbers(element: ET.Element, attribute: str, count: int) -> tuple[float, ...]:
    text = element.get(attribute)
    if text is None:
        raise _ForeignError(f"<{element.tag} name={element.get('name')!r}> has no {attribute}")
    try:
        values = tuple(float(v) for v in text.split())
    except ValueError:
        values = ()
    if len(values) != count:
        raise _ForeignError(
            f"<{element.tag} name={element.get('name')!r}> {attribute}={text!r}: expected "
            f"{count} numbers"[:300]
        )
    return values


def _vector(element: ET.Element, attribute: str) -> tuple[float, float, float]:
    if element.get(attribute) is None:
        return (0.0, 0.0, 0.0)
    x, y, z = _numbers(element, attribute, 3)
    return (x, y, z)


def _rotation(element: ET.Element) -> Matrix:
    """The rotation of ``xyaxes`` (identity without): ``x``, ``y`` as written (normalised and
    orthogonalised, as MuJoCo does, only when they are not unit and orthogonal to ``1e-12``),
    ``z = x × y`` normalised."""
    if element.get("xyaxes") is None:
        for other in ("quat", "axisangle", "euler", "zaxis"):
            if element.get(other) is not None:
                raise _ForeignError(f"<{element.tag} name={element.get('name')!r}> has {other}")
        return check_rotation("xyaxes", np.eye(3))
    values = np.array(_numbers(element, "xyaxes", 6))
    if not np.abs(values).max() < 1e100:  # x·x would overflow; prp3 writes unit axes
        raise _ForeignError(f"<{element.tag} name={element.get('name')!r}> xyaxes beyond 1e100")
    x, y = values[:3], values[3:]
    if not (abs(x @ x - 1.0) < 1e-12 and abs(y @ y - 1.0) < 1e-12 and abs(x @ y) < 1e-12):
        if not np.linalg.norm(np.cross(x, y)) > 1e-9 * np.linalg.norm(x) * np.linalg.norm(y):
            raise _ForeignError(f"<{element.tag} name={element.get('name')!r}> xyaxes are parallel")
        x = x / np.linalg.norm(x)
        y = y - (x @ y) * x
        y = y / np.linalg.norm(y)
    z = np.cross(x, y)
    return check_rotation("xyaxes", np.stack([x, y, z / np.linalg.norm(z)], axis=1))


def _body_of(element: ET.Element, name: str) -> Body:
    inertial = element.find("inertial")
    if inertial is None:
        raise _ForeignError(f"<body name={element.get('name')!r}> has no <inertial>")
    (mass,) = _numbers(inertial, "mass", 1)
    if inertial.get("diaginertia") is not None:
        a, b, c = _numbers(inertial, "diaginertia", 3)
        tensor = ((a, 0.0, 0.0), (0.0, b, 0.0), (0.0, 0.0, c))
    else:
        a, b, c, ab, ac, bc = _numbers(inertial, "fullinertia", 6)
        tensor = ((a, ab, ac), (ab, b, bc), (ac, bc, c))
    return Body(mass, _vector(inertial, "pos"), tensor, name)


_KINDS: dict[tuple[tuple[str, str], ...], str] = {
    (("hinge", "0 0 1"),): "R",
    (("slide", "1 0 0"),): "P",
    (("hinge", "0 0 1"), ("hinge", "0 1 0")): "U",
}


def _joint_of(
    element: ET.Element, leg: int, k: int, ranges: dict[str, tuple[float, float]]
) -> Joint:
    """Joint ``k`` (1-based) of ``leg`` from the body it moves (its placement and joints)."""
    joints = element.findall("joint")
    key = tuple((j.get("type", "hinge"), j.get("axis", "")) for j in joints)
    if key not in _KINDS:
        raise _ForeignError(
            f"<body name={element.get('name')!r}>: joints {key!r} are not an R, P or U"[:300]
        )
    kind = _KINDS[key]
    joint_names = [f"leg{leg}_{c}" for c in Joint(kind, (0, 0, 0)).coordinates(f"{kind}{k}")]
    limits = []
    for name, j in zip(joint_names, joints, strict=True):
        if j.get("name") != name:
            raise _ForeignError(f"joint {j.get('name')!r} where prp3 writes {name!r}")
        if j.get("range") is not None:
            low, high = _numbers(j, "range", 2)
            limits.append((low, high))
        else:
            limits.append(ranges.get(name, (-math.inf, math.inf)))
    return Joint(kind, _vector(element, "pos"), _rotation(element), tuple(limits))


def _custom(root: ET.Element) -> tuple[dict[str, str], dict[str, tuple[float, ...]]]:
    texts: dict[str, str] = {}
    numerics: dict[str, tuple[float, ...]] = {}
    for custom in root.findall("custom"):
        for text in custom.findall("text"):
            texts[text.get("name", "")] = text.get("data", "")
        for numeric in custom.findall("numeric"):
            data = numeric.get("data", "")
            try:
                numerics[numeric.get("name", "")] = tuple(float(v) for v in data.split())
            except ValueError:
                raise _ForeignError(f"numeric {numeric.get('name')!r} = {data!r}"[:300]) from None
    return texts, numerics


def _leg_of(
    world: ET.Element, platform: ET.Element, i: int, texts: dict[str, str],
    ranges: dict[str, tuple[float, float]], equalities: dict[str, ET.Element],
    actuators: dict[str, str],
) -> Leg:  # fmt: skip
    element = world.find(f"body[@name='leg{i}_body1']")
    if element is None:
        raise _ForeignError(f"no body leg{i}_body1 in the worldbody")
    joints, bodies = [], []
    k = 1
    while True:
        joints.append(_joint_of(element, i, k, ranges))
        bodies.append(_body_of(element, texts.get(f"prp3_body_leg{i}_{k}", "body").strip() or ""))
        child = element.find(f"body[@name='leg{i}_body{k + 1}']")
        if child is None:
            break
        element, k = child, k + 1
    site = platform.find(f"site[@name='platform_leg{i}']")
    if site is None:
        raise _ForeignError(f"no site platform_leg{i} in the body platform")
    end = element.find(f"body[@name='leg{i}_end']")
    if end is not None:
        last = _joint_of(end, i, k + 1, ranges)
        label = f"{last.kind}{k + 1}"
        tag = "weld"
    else:
        label = f"S{k + 1}"
        s_site = element.find(f"site[@name='leg{i}_{label}']")
        if s_site is None:
            raise _ForeignError(
                f"leg {i} ends neither in a body leg{i}_end nor a site leg{i}_{label}"
            )
        last = Joint(
            "S", _vector(s_site, "pos"), _rotation(s_site),
            (ranges.get(f"leg{i}_{label}", (0.0, math.inf)),),
        )  # fmt: skip
        tag = "connect"
    closure = equalities.get(f"leg{i}_{label}")
    if closure is None or closure.tag != tag:
        raise _ForeignError(f"no <{tag} name='leg{i}_{label}'> closing leg {i}")
    joints.append(last)
    driven = actuators.get(f"actuator_{i}", "")
    actuated = [
        k
        for k, (joint, label) in enumerate(
            zip(joints, (f"{j.kind}{n}" for n, j in enumerate(joints, 1)), strict=True)
        )
        if joint.dof == 1 and driven == f"leg{i}_{label}"
    ]
    if len(actuated) != 1:
        raise _ForeignError(f"actuator_{i} drives {driven!r}, not an R or P of leg {i}")
    return Leg(tuple(joints), tuple(bodies), _vector(site, "pos"), _rotation(site), actuated[0])


def spatial_mjcf_robot(text: str) -> SpatialRobot:
    """The robot of an MJCF text written by :func:`spatial_mjcf_model`.

    Raises
    ------
    ParameterError
        Malformed XML (naming the line and column); a model not written by
        :func:`spatial_mjcf_model` (no custom text ``prp3_spatial``, or an element
        where prp3 writes another: named); a robot the elements do not make.
    """
    try:
        root = ET.fromstring(text)
    except ET.ParseError as error:
        line, column = error.position
        raise ParameterError(
            f"not well-formed XML at line {line}, column {column} ({error})"[:300], subject="mjcf"
        ) from None
    try:
        return _robot_of(root)
    except _ForeignError as error:
        raise ParameterError(
            f"not an MJCF model of a spatial robot written by prp3 (prp3 export mjcf): {error}",
            subject="mjcf",
        ) from None


def _robot_of(root: ET.Element) -> SpatialRobot:
    if root.tag != "mujoco":
        raise _ForeignError(f"the root element is <{root.tag}>, not <mujoco>")
    texts, numerics = _custom(root)
    if SPATIAL_MJCF_MARK not in texts:
        raise _ForeignError(f"it has no <custom><text name={SPATIAL_MJCF_MARK!r}>")
    world = root.find("worldbody")
    platform = world.find("body[@name='platform']") if world is not None else None
    if world is None or platform is None:
        raise _ForeignError("no body platform in a <worldbody>")
    ranges = {
        name.removeprefix("prp3_range_"): (values[0], values[1])
        for name, values in numerics.items()
        if name.startswith("prp3_range_") and len(values) == 2
    }
    equalities = {e.get("name", ""): e for eq in root.findall("equality") for e in eq}
    actuators = {m.get("name", ""): m.get("joint", "") for a in root.findall("actuator") for m in a}
    placed = []
    i = 1
    while world.find(f"body[@name='leg{i}_body1']") is not None:
        placed.append(_leg_of(world, platform, i, texts, ranges, equalities, actuators))
        i += 1
    option = root.find("option")
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)  # MuJoCo's default
    if option is not None and option.get("gravity") is not None:
        gravity = _vector(option, "gravity")
    home = numerics.get("prp3_home", ())
    scale = numerics.get("prp3_scale", ())
    if len(home) != 12 or len(scale) != 1:
        raise _ForeignError("the custom numerics prp3_home (12 numbers) and prp3_scale are missing")
    parasitic = texts.get("prp3_parasitic", "none").split()
    name = texts.get("prp3_name", "").strip()
    platform_body = _body_of(platform, texts.get("prp3_body_platform", "platform").strip())
    return SpatialRobot(
        name, tuple(placed), platform_body, gravity, check_vector("home", home[:3]),
        check_rotation("home rotation", np.array(home[3:]).reshape(3, 3)), scale[0],
        () if parasitic == ["none"] else tuple(parasitic),
    )  # fmt: skip


def read_spatial_mjcf(path: str | Path) -> SpatialRobot:
    """Read an MJCF file written by :func:`spatial_mjcf_model` (``prp3 export mjcf``) back
    into its :class:`~prp3.spatial.model.SpatialRobot` (docs/spatial.md §16).

    Raises
    ------
    InputFileError
        An unreadable file, malformed XML, a foreign MJCF model (one line naming the
        file and the reason), or elements that do not make a robot.
    """
    path = check_file_path("path", path)
    text = read_text(path, "MJCF", MAX_MJCF_BYTES)
    try:
        return spatial_mjcf_robot(text)
    except ParameterError as error:
        raise InputFileError(error.reason, file=path) from None
