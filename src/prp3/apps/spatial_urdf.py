"""URDF exchange of the spatial robots with their loop closures (docs/spatial.md §25).

:func:`spatial_urdf_model` writes a :class:`~prp3.spatial.model.SpatialRobot`
(the 6-UPS, the 3-RPS, the Delta as a 3-RUU) as the URDF of its spanning tree,
and :func:`spatial_urdf_closures` the side file of its loop closures in the
Extended-URDF convention of Gepetto's example-parallel-robots (``robot.urdf``
beside ``robot.yaml``: the keys ``closed_loop``, the pairs of frames that the
loops hold together, ``type``, ``3D`` or ``6D`` per pair, and ``name_mot``, the
actuated joints).  :func:`read_spatial_urdf` reads the pair back into the same
robot (the URDF with :mod:`xml.etree`, the YAML with PyYAML).  Writing needs
neither Pinocchio nor PyYAML.

The tree (names with the leg ``i = 1 … L`` and the joint labels of §9):

``leg{i}_body{k}``
    body ``k`` of leg ``i`` (between joints ``k`` and ``k + 1``): its ``<inertial>``
    is prp3's (mass, mass centre and the inertia tensor about it in the body frame
    ``F_k``).  The joint ``k`` before it has the joint's placement as its
    ``<origin>`` (``xyz``, ``rpy``: the joint frame ``J_k`` in body ``k − 1``, in the
    world for ``k = 1``): an R is the ``revolute`` ``leg{i}_R{k}`` about ``z``, a P
    the ``prismatic`` ``leg{i}_P{k}`` along ``x``, a U the ``revolute``
    ``leg{i}_U{k}_a`` about ``z`` into the link ``leg{i}_U{k}_cross`` (no mass),
    then the ``revolute`` ``leg{i}_U{k}_b`` about ``y``; the joint values are prp3's
    ``q``.  Their ``<limit>`` is the joint's range (an unbounded R is
    ``continuous``); a range infinite on one side is in ``<prp3_spatial>``.
``platform``
    a child of the world by the ``floating`` joint ``platform``: the platform frame
    ``(p, R)``, with the platform's inertial.
the cut at each leg's closing joint (the last, at the platform)
    a closing **S** is cut: the fixed link ``closedloop{i}_A`` at the S's placement
    in the last body and the fixed link ``closedloop{i}_B`` at the attachment
    ``(c_A, R_A)`` in the platform, a ``3D`` closure (the two points coincide).  A
    closing U (the Delta) is in the tree as above into the link ``leg{i}_end`` (no
    mass, the leg's end ``F_n``), with ``closedloop{i}_A`` fixed on it (identity), a
    ``6D`` closure with ``closedloop{i}_B`` (the two frames coincide).
``<prp3_spatial>``
    what URDF has no element for (urdfdom ignores the element): the mark of a prp3
    file, the name, gravity, the parasitic components, the home pose, the scale
    ``ℓ``, the bodies' names, the S's rotation limit and the half-infinite ranges.

>>> from prp3.spatial.model import hexapod
>>> text = spatial_urdf_model(hexapod())
>>> text.count('type="revolute"'), text.count('type="prismatic"'), text.count('type="floating"')
(12, 6, 1)
>>> print(spatial_urdf_closures(hexapod()).splitlines()[1])
type: ['3D', '3D', '3D', '3D', '3D', '3D']
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from prp3.apps.mjcf import num, vec
from prp3.errors import InputFileError, ParameterError
from prp3.files import read_text
from prp3.spatial.model import Body, Joint, Leg, Matrix, SpatialRobot, check_rotation, check_vector
from prp3.validation import check_file_path, check_instance

__all__ = [
    "MAX_URDF_BYTES",
    "SPATIAL_URDF_MARK",
    "URDF_UNBOUNDED",
    "closure_frames",
    "closures_path",
    "read_spatial_urdf",
    "rotation_rpy",
    "rpy_rotation",
    "spatial_urdf_closures",
    "spatial_urdf_model",
    "spatial_urdf_robot",
]

#: The element that marks a URDF written by :func:`spatial_urdf_model`.
SPATIAL_URDF_MARK: str = "prp3_spatial"

#: The largest URDF or closures file :func:`read_spatial_urdf` reads (bytes).
MAX_URDF_BYTES: int = 10_000_000

#: What a URDF ``<limit>`` says for an infinite side (and the effort and velocity limits:
#: prp3 has none); the true value is in ``<prp3_spatial>``.
URDF_UNBOUNDED: float = 1e300

_IDENTITY: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def rotation_rpy(rotation: Matrix) -> tuple[float, float, float]:
    """URDF's ``rpy`` of a rotation: ``R = Rot_z(yaw)·Rot_y(pitch)·Rot_x(roll)`` (rad).

    >>> rotation_rpy(((1, 0, 0), (0, 0, 1), (0, -1, 0)))
    (-1.5707963267948966, -0.0, 0.0)
    """
    r = np.asarray(rotation, dtype=float)
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if math.hypot(r[0, 0], r[1, 0]) < 1e-12:  # pitch ±π/2: the yaw taken as zero
        return (math.atan2(-r[1, 2], r[1, 1]), pitch, 0.0)
    return (math.atan2(r[2, 1], r[2, 2]), pitch, math.atan2(r[1, 0], r[0, 0]))


def rpy_rotation(roll: float, pitch: float, yaw: float) -> Matrix:
    """The rotation of URDF's ``rpy``; entries within ``1e-15`` of zero are zero (so that
    ``Rot_x(−π/2)`` and the identity come back exactly).

    >>> rpy_rotation(-math.pi / 2, 0.0, 0.0)
    ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0))
    """
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch),
                              math.sin(pitch), math.cos(yaw), math.sin(yaw))  # fmt: skip
    r = np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])  # fmt: skip
    r[np.abs(r) < 1e-15] = 0.0
    return check_rotation("rpy", r + 0.0)


def _origin(position: tuple[float, ...], rotation: Matrix) -> str:
    return f'<origin xyz="{vec(*position)}" rpy="{vec(*rotation_rpy(rotation))}"/>'


def _inertial(body: Body) -> str:
    i = body.inertia
    return (
        f'<inertial><origin xyz="{vec(*body.centre)}" rpy="0 0 0"/><mass value="{num(body.mass)}"/>'
        f'<inertia ixx="{num(i[0][0])}" ixy="{num(i[0][1])}" ixz="{num(i[0][2])}" '
        f'iyy="{num(i[1][1])}" iyz="{num(i[1][2])}" izz="{num(i[2][2])}"/></inertial>'
    )


def _bound(value: float) -> str:
    return num(max(-URDF_UNBOUNDED, min(URDF_UNBOUNDED, value)))


def _joint(name: str, kind: str, parent: str, child: str, origin: str, axis: str,
           limit: tuple[float, float] | None) -> str:  # fmt: skip
    text = f'  <joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
    text += origin + (f'<axis xyz="{axis}"/>' if axis else "")
    if limit is not None and kind != "continuous":
        text += (
            f'<limit lower="{_bound(limit[0])}" upper="{_bound(limit[1])}" '
            f'effort="{num(URDF_UNBOUNDED)}" velocity="{num(URDF_UNBOUNDED)}"/>'
        )
    return text + "</joint>"


def _joint_lines(
    joint: Joint, label: str, leg: int, parent: str, child: str, ranges: list[str]
) -> list[str]:
    """The URDF joints (and a U's cross link) of an R, P or U joint between two links."""
    origin = _origin(joint.position, joint.rotation)
    for coordinate, (low, high) in zip(joint.coordinates(label), joint.limits, strict=True):
        if math.isinf(low) or math.isinf(high):  # ±1e300 in <limit>, or continuous
            ranges.append(
                f'    <range joint="leg{leg}_{coordinate}" low="{num(low)}" high="{num(high)}"/>'
            )
    if joint.kind in "RP":
        unbounded = joint.kind == "R" and joint.limits[0] == (-math.inf, math.inf)
        kind = "continuous" if unbounded else "revolute" if joint.kind == "R" else "prismatic"
        axis = "0 0 1" if joint.kind == "R" else "1 0 0"
        return [_joint(f"leg{leg}_{label}", kind, parent, child, origin, axis, joint.limits[0])]
    cross = f"leg{leg}_{label}_cross"
    kinds = ["continuous" if lim == (-math.inf, math.inf) else "revolute" for lim in joint.limits]
    identity = '<origin xyz="0 0 0" rpy="0 0 0"/>'
    return [
        _joint(f"leg{leg}_{label}_a", kinds[0], parent, cross, origin, "0 0 1", joint.limits[0]),
        f'  <link name="{cross}"/>',
        _joint(f"leg{leg}_{label}_b", kinds[1], cross, child, identity, "0 1 0", joint.limits[1]),
    ]


def _check_robot(robot: SpatialRobot) -> None:
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    for i, leg in enumerate(robot.legs, 1):
        if any(j.kind == "S" for j in leg.joints[:-1]):
            raise ParameterError(
                f"leg {i}: an S joint before the platform has no URDF form here (only a "
                "closing S, cut)",
                subject="robot",
                key="legs",
            )


def _leg_lines(
    robot: SpatialRobot, i: int, leg: Leg, ranges: list[str], names: list[str]
) -> list[str]:
    lines: list[str] = []
    parent = "world"
    n = len(leg.joints)
    for k in range(n - 1):
        child = f"leg{i}_body{k + 1}"
        lines += _joint_lines(leg.joints[k], leg.labels[k], i, parent, child, ranges)
        lines.append(f'  <link name="{child}">{_inertial(leg.bodies[k])}</link>')
        names.append(f'    <body link="{child}" name={quoteattr(leg.bodies[k].name)}/>')
        parent = child
    last, label = leg.joints[-1], leg.labels[-1]
    if last.kind == "S":
        origin = _origin(last.position, last.rotation)
        low, high = last.limits[0]
        ranges.append(f'    <range joint="leg{i}_{label}" low="{num(low)}" high="{num(high)}"/>')
    else:
        lines += _joint_lines(last, label, i, parent, f"leg{i}_end", ranges)
        lines.append(f'  <link name="leg{i}_end"/>')
        parent, origin = f"leg{i}_end", _origin((0.0, 0.0, 0.0), _IDENTITY)
    lines += [
        _joint(f"leg{i}_cut_A", "fixed", parent, f"closedloop{i}_A", origin, "", None),
        f'  <link name="closedloop{i}_A"/>',
    ]
    return lines


def spatial_urdf_model(robot: SpatialRobot) -> str:
    """The spatial robot as the URDF of its spanning tree, cut at the closing joints.

    Parameters
    ----------
    robot : SpatialRobot
        Legs, bodies, platform, gravity, home pose (docs/spatial.md §2, §7, §11, §12).

    Returns
    -------
    str
        URDF text (module notes; docs/spatial.md §25): each leg an open chain from the
        world, the platform a ``floating`` child of the world, the closure frames
        ``closedloop{i}_A`` (leg) and ``closedloop{i}_B`` (platform) of each cut, and
        ``<prp3_spatial>``.  The closures are :func:`spatial_urdf_closures`.

    Raises
    ------
    ParameterError
        ``robot`` is not a :class:`SpatialRobot`; an S that is not a leg's last joint.
    """
    _check_robot(robot)
    ranges: list[str] = []
    names: list[str] = []
    lines = [
        '<?xml version="1.0"?>',
        f"<!-- {robot.name} spatial parallel robot written by prp3 (docs/spatial.md §25): the",
        "     spanning tree (legs leg{i} from the world, the platform floating), cut at each leg's",
        "     closing joint between the frames closedloop{i}_A and closedloop{i}_B; the closures",
        "     are the side file (Extended URDF: closed_loop, type, name_mot). -->",
        '<robot name="prp3_spatial">',
        '  <link name="world"/>',
    ]
    for i, leg in enumerate(robot.legs, 1):
        lines += _leg_lines(robot, i, leg, ranges, names)
    identity = '<origin xyz="0 0 0" rpy="0 0 0"/>'
    lines += [
        _joint("platform", "floating", "world", "platform", identity, "", None),
        f'  <link name="platform">{_inertial(robot.platform)}</link>',
    ]
    names.append(f'    <body link="platform" name={quoteattr(robot.platform.name)}/>')
    for i, leg in enumerate(robot.legs, 1):
        origin = _origin(leg.attachment_position, leg.attachment_rotation)
        lines += [
            _joint(f"leg{i}_cut_B", "fixed", "platform", f"closedloop{i}_B", origin, "", None),
            f'  <link name="closedloop{i}_B"/>',
        ]
    home = (*robot.home_position, *np.asarray(robot.home_rotation).reshape(9))
    lines += [
        f'  <{SPATIAL_URDF_MARK} name={quoteattr(robot.name)} gravity="{vec(*robot.gravity)}" '
        f'parasitic="{" ".join(robot.parasitic) or "none"}" home="{vec(*home)}" '
        f'scale="{num(robot.scale)}">',
        *names,
        *ranges,
        f"  </{SPATIAL_URDF_MARK}>",
        "</robot>",
    ]
    return "\n".join(lines) + "\n"


def closure_frames(robot: SpatialRobot) -> list[tuple[str, str, str]]:
    """The loop closures: ``(frame on the leg, frame on the platform, "3D" | "6D")`` per leg.

    >>> from prp3.spatial.model import delta
    >>> closure_frames(delta())[0]
    ('closedloop1_A', 'closedloop1_B', '6D')
    """
    _check_robot(robot)
    return [
        (f"closedloop{i}_A", f"closedloop{i}_B", "3D" if leg.joints[-1].kind == "S" else "6D")
        for i, leg in enumerate(robot.legs, 1)
    ]


def spatial_urdf_closures(robot: SpatialRobot) -> str:
    """The closures' side file (YAML text, Extended URDF of Gepetto's example-parallel-robots).

    ``closed_loop``: the pairs of frames of :func:`closure_frames`; ``type``: ``3D``
    (a cut S: the points coincide) or ``6D`` (a cut below a U: the frames coincide);
    ``name_mot``: the actuated joints' URDF names, one per leg.

    >>> from prp3.spatial.model import delta
    >>> print(spatial_urdf_closures(delta()), end="")
    closed_loop: [['closedloop1_A', 'closedloop1_B'], ['closedloop2_A', 'closedloop2_B'], ['closedloop3_A', 'closedloop3_B']]
    type: ['6D', '6D', '6D']
    name_mot: ['leg1_R1', 'leg2_R1', 'leg3_R1']
    """
    pairs = closure_frames(robot)
    motors = [
        f"leg{i}_{leg.coordinates[leg.actuated_coordinate]}" for i, leg in enumerate(robot.legs, 1)
    ]
    loops = ", ".join(f"['{a}', '{b}']" for a, b, _ in pairs)
    types = ", ".join(f"'{t}'" for _, _, t in pairs)
    return (
        f"closed_loop: [{loops}]\ntype: [{types}]\n"
        f"name_mot: [{', '.join(repr(m) for m in motors)}]\n"
    )


# ---------------------------------------------------------------- reading back
class _ForeignError(Exception):
    """A pair of files that is not one prp3 writes (the reason)."""


def _floats(element: ET.Element, attribute: str, count: int) -> tuple[float, ...]:
    text = element.get(attribute)
    try:
        values = tuple(float(v) for v in (text or "").split())
    except ValueError:
        values = ()
    if len(values) != count:
        raise _ForeignError(
            f"<{element.tag} name={element.get('name')!r}> {attribute}={text!r}: expected "
            f"{count} numbers"[:300]
        )
    return values


def _placement(joint: ET.Element) -> tuple[tuple[float, float, float], Matrix]:
    origin = joint.find("origin")
    if origin is None:
        return (0.0, 0.0, 0.0), _IDENTITY
    x, y, z = _floats(origin, "xyz", 3) if origin.get("xyz") is not None else (0.0, 0.0, 0.0)
    roll, pitch, yaw = _floats(origin, "rpy", 3) if origin.get("rpy") is not None else (0.0,) * 3
    return check_vector("xyz", (x, y, z)), rpy_rotation(roll, pitch, yaw)


def _body_of(link: ET.Element, name: str) -> Body:
    inertial = link.find("inertial")
    mass = inertial.find("mass") if inertial is not None else None
    tensor = inertial.find("inertia") if inertial is not None else None
    if inertial is None or mass is None or tensor is None:
        raise _ForeignError(
            f"<link name={link.get('name')!r}> has no <inertial> with mass and inertia"
        )
    centre, rotation = _placement(inertial)
    if rotation != _IDENTITY:
        raise _ForeignError(f"<link name={link.get('name')!r}>: its inertial frame is turned")
    (m,) = _floats(mass, "value", 1)
    xx, xy, xz, yy, yz, zz = (
        _floats(tensor, a, 1)[0] for a in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    )
    return Body(m, centre, ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz)), name)


class _Tree:
    """The URDF's joints by the link they move, its links by name, prp3's element."""

    def __init__(self, root: ET.Element) -> None:
        if root.tag != "robot":
            raise _ForeignError(f"the root element is <{root.tag}>, not <robot>")
        mark = root.find(SPATIAL_URDF_MARK)
        if mark is None:
            raise _ForeignError(f"it has no <{SPATIAL_URDF_MARK}> element")
        self.mark = mark
        self.links = {link.get("name", ""): link for link in root.findall("link")}
        self.by_child: dict[str, ET.Element] = {}
        for joint in root.findall("joint"):
            child = joint.find("child")
            if child is not None:
                self.by_child[child.get("link", "")] = joint
        self.ranges = {r.get("joint", ""): _floats(r, "low", 1) + _floats(r, "high", 1)
                       for r in mark.findall("range")}  # fmt: skip
        self.names = {b.get("link", ""): b.get("name", "") for b in mark.findall("body")}

    def joint_into(self, link: str, name: str, kind: str, axis: str) -> ET.Element:
        """The joint that moves ``link``, checked to be ``name`` of a ``kind`` about ``axis``."""
        joint = self.by_child.get(link)
        if joint is None or joint.get("name") != name:
            found = None if joint is None else joint.get("name")
            raise _ForeignError(f"the link {link} is moved by {found!r} where prp3 writes {name!r}")
        kinds = ("revolute", "continuous") if kind == "revolute" else (kind,)
        axis_element = joint.find("axis")
        written = "1 0 0" if axis_element is None else axis_element.get("xyz", "")
        try:
            same = [float(v) for v in written.split()] == [float(v) for v in axis.split()]
        except ValueError:
            same = False
        if joint.get("type") not in kinds or (axis and not same):
            raise _ForeignError(
                f"joint {name}: type {joint.get('type')!r} axis {written!r}, prp3 writes {kind} "
                f"about {axis!r}"[:300]
            )
        return joint

    def limit(self, joint: ET.Element) -> tuple[float, float]:
        name = joint.get("name", "")
        if name in self.ranges:
            low, high = self.ranges[name]
            return (low, high)
        if joint.get("type") == "continuous":
            return (-math.inf, math.inf)
        element = joint.find("limit")
        if element is None:
            raise _ForeignError(f"joint {name} has no <limit>")
        return (_floats(element, "lower", 1)[0], _floats(element, "upper", 1)[0])


def _joint_of(tree: _Tree, leg: int, k: int, link: str) -> tuple[Joint, str]:
    """Joint ``k`` (1-based) of ``leg``, which moves ``link``; and the link before it."""
    joint = tree.by_child.get(link)
    name = "" if joint is None else joint.get("name", "")
    limits: tuple[tuple[float, float], ...]
    if name == f"leg{leg}_R{k}":
        element = tree.joint_into(link, name, "revolute", "0 0 1")
        kind, limits = "R", (tree.limit(element),)
    elif name == f"leg{leg}_P{k}":
        element = tree.joint_into(link, name, "prismatic", "1 0 0")
        kind, limits = "P", (tree.limit(element),)
    else:
        second = tree.joint_into(link, f"leg{leg}_U{k}_b", "revolute", "0 1 0")
        if _placement(second) != ((0.0, 0.0, 0.0), _IDENTITY):
            raise _ForeignError(f"joint leg{leg}_U{k}_b is placed off its cross")
        element = tree.joint_into(f"leg{leg}_U{k}_cross", f"leg{leg}_U{k}_a", "revolute", "0 0 1")
        kind, limits = "U", (tree.limit(element), tree.limit(second))
    parent = element.find("parent")
    position, rotation = _placement(element)
    return Joint(kind, position, rotation, limits), "" if parent is None else parent.get("link", "")


def _leg_of(tree: _Tree, i: int, closure: str, motor: str) -> Leg:
    k = 1
    while f"leg{i}_body{k + 1}" in tree.links:
        k += 1
    joints: list[Joint] = []
    bodies: list[Body] = []
    for j in range(k, 0, -1):
        joint, parent = _joint_of(tree, i, j, f"leg{i}_body{j}")
        if parent != (f"leg{i}_body{j - 1}" if j > 1 else "world"):
            raise _ForeignError(f"joint {j} of leg {i} hangs from {parent!r}")
        joints.insert(0, joint)
        link = tree.links[f"leg{i}_body{j}"]
        bodies.insert(0, _body_of(link, tree.names.get(f"leg{i}_body{j}", "body")))
    cut = tree.joint_into(f"closedloop{i}_A", f"leg{i}_cut_A", "fixed", "")
    if f"leg{i}_end" in tree.links:
        last, _ = _joint_of(tree, i, k + 1, f"leg{i}_end")
        expected = "6D"
    else:
        position, rotation = _placement(cut)
        s_range = tree.ranges.get(f"leg{i}_S{k + 1}", (0.0, math.inf))
        last, expected = Joint("S", position, rotation, ((s_range[0], s_range[1]),)), "3D"
    if closure != expected:
        raise _ForeignError(
            f"the closure of leg {i} is {closure!r}; its cut joint needs {expected!r}"
        )
    attach = tree.joint_into(f"closedloop{i}_B", f"leg{i}_cut_B", "fixed", "")
    joints.append(last)
    labels = [f"{j.kind}{n}" for n, j in enumerate(joints, 1)]
    actuated = [n for n, (j, lab) in enumerate(zip(joints, labels, strict=True))
                if j.dof == 1 and motor == f"leg{i}_{lab}"]  # fmt: skip
    if len(actuated) != 1:
        raise _ForeignError(f"the motor {motor!r} of leg {i} is not one of its R or P joints")
    position, rotation = _placement(attach)
    return Leg(tuple(joints), tuple(bodies), position, rotation, actuated[0])


def _closures(text: str) -> tuple[list[str], list[str]]:
    """The closures' types and the motors of a side file written by :func:`spatial_urdf_closures`."""
    try:
        import yaml  # type: ignore[import-untyped]
    except ImportError:
        raise ParameterError(
            "reading the closures' YAML side file needs PyYAML (pip install 'prp3[urdf]')",
            subject="urdf",
        ) from None
    try:
        content = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise _ForeignError(
            f"the closures are not YAML ({' '.join(str(error).split())})"[:300]
        ) from None
    if not isinstance(content, dict) or not {"closed_loop", "type", "name_mot"} <= set(content):
        raise _ForeignError("the closures have no closed_loop, type and name_mot")
    loops, types, motors = content["closed_loop"], content["type"], content["name_mot"]
    if not (isinstance(loops, list) and isinstance(types, list) and isinstance(motors, list)
            and len(loops) == len(types) == len(motors)):  # fmt: skip
        raise _ForeignError("closed_loop, type and name_mot are not lists of one entry per leg")
    for i, pair in enumerate(loops, 1):
        if pair != [f"closedloop{i}_A", f"closedloop{i}_B"]:
            raise _ForeignError(f"closed_loop entry {i} is {pair!r}, prp3 writes "
                                f"['closedloop{i}_A', 'closedloop{i}_B']"[:300])  # fmt: skip
    return [str(t).upper() for t in types], [str(m) for m in motors]


def spatial_urdf_robot(text: str, closures: str) -> SpatialRobot:
    """The robot of a URDF text and its closures' YAML text written by prp3.

    Raises
    ------
    ParameterError
        Malformed XML (naming the line and column) or YAML; a file not written by
        :func:`spatial_urdf_model` (no ``<prp3_spatial>``, or an element where prp3
        writes another: named), closures that are not those of the tree; a robot the
        elements do not make; PyYAML missing.
    """
    check_instance("text", text, str, "the text of a URDF")
    check_instance("closures", closures, str, "the text of the closures' YAML side file")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as error:
        line, column = error.position
        raise ParameterError(
            f"not well-formed XML at line {line}, column {column} ({error})"[:300], subject="urdf"
        ) from None
    try:
        return _robot_of(root, *_closures(closures))
    except _ForeignError as error:
        raise ParameterError(
            f"not a URDF of a spatial robot with its closures written by prp3 (prp3 export "
            f"urdf): {error}",
            subject="urdf",
        ) from None


def _robot_of(root: ET.Element, types: list[str], motors: list[str]) -> SpatialRobot:
    tree = _Tree(root)
    legs: list[Leg] = []
    while f"leg{len(legs) + 1}_body1" in tree.links:
        i = len(legs) + 1
        if i > len(types):
            raise _ForeignError(f"leg {i} has no closure")
        legs.append(_leg_of(tree, i, types[i - 1], motors[i - 1]))
    if len(legs) != len(types):
        raise _ForeignError(f"{len(types)} closures for {len(legs)} legs")
    tree.joint_into("platform", "platform", "floating", "")
    if "platform" not in tree.links:
        raise _ForeignError("no link platform")
    platform = _body_of(tree.links["platform"], tree.names.get("platform", "platform"))
    mark = tree.mark
    home = _floats(mark, "home", 12)
    parasitic = mark.get("parasitic", "none").split()
    return SpatialRobot(
        mark.get("name", ""), tuple(legs), platform, check_vector("gravity", _floats(mark, "gravity", 3)),
        check_vector("home", home[:3]), check_rotation("home rotation", np.array(home[3:]).reshape(3, 3)),
        _floats(mark, "scale", 1)[0], () if parasitic == ["none"] else tuple(parasitic),
    )  # fmt: skip


def closures_path(path: Path) -> Path:
    """The closures' side file beside a URDF: the same name with ``.yaml`` (``robot.yaml``)."""
    return path.with_suffix(".yaml")


def read_spatial_urdf(path: str | Path, closures: str | Path | None = None) -> SpatialRobot:
    """Read a URDF written by :func:`spatial_urdf_model` and its closures (``prp3 export
    urdf``) back into its :class:`~prp3.spatial.model.SpatialRobot` (docs/spatial.md §25).

    Parameters
    ----------
    path : str or Path
        The URDF.
    closures : str or Path, optional
        The YAML side file of :func:`spatial_urdf_closures`; by default beside ``path``
        with the suffix ``.yaml``.

    Raises
    ------
    InputFileError
        An unreadable or missing file, malformed XML or YAML, a foreign URDF or one
        without its closures (one line naming the file and the reason), elements
        that do not make a robot, PyYAML missing.
    """
    path = check_file_path("path", path)
    side = closures_path(path) if closures is None else check_file_path("closures", closures)
    text = read_text(path, "URDF", MAX_URDF_BYTES)
    if not side.is_file():
        raise InputFileError(f"the closures' side file {side} is missing (prp3 export urdf writes "
                             "it beside the URDF)", file=path)  # fmt: skip
    side_text = read_text(side, "URDF closures", MAX_URDF_BYTES)
    try:
        return spatial_urdf_robot(text, side_text)
    except ParameterError as error:
        raise InputFileError(error.reason, file=path) from None
