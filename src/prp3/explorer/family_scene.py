"""What the explorer draws for a family robot (docs/family.md), as plain columns.

The same page structure as the 3-PRP's (:mod:`prp3.explorer.scene`): a
:class:`~prp3.explorer.scene.View` of plain columns, no Bokeh.  The numbers
come only from :mod:`prp3.family`:

* one instant is solved by :func:`prp3.family.family_inverse_dynamics` and
  turned into the 64 columns of ``results.csv`` by
  :func:`prp3.family.family_results_table` (:func:`family_pose_table`); a
  refused pose (unreachable, singular, crossed) raises the library's error;
* :func:`family_view` places those columns in the plane: the chain frames of
  every leg from :func:`prp3.family.leg_chain` at the table's joint values
  (docs/family.md §2), R joints as circles at ``O_k``, P joints as slides
  along ``u_k`` on their guides (the geometry of
  :func:`prp3.plotting.family_animation.family_frame`), and every joint force
  ``(fx{k}, fy{k})`` (§7) as an arrow with its tail at ``O_k``; for an actuated
  P joint the actuator's share ``tau·u_a`` is drawn as well (an actuated R
  joint's ``tau`` is a couple: in the table);
* the singularity measures of §6 at the pose, ``μ_leg`` of each leg and
  ``μ_par``, from the same chain (:func:`prp3.family.leg_jacobian` at ``G``
  with ``ℓ = [leg] scale``, :func:`prp3.family.leg_measure`,
  :func:`prp3.family.transmitted_wrench`, :func:`prp3.family.parallel_measure`),
  with their home signs and the threshold ``1e-4``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.drawing import GUIDE_OVERHANG, LEG_COLOURS, SLIDE_HALF_LENGTH
from prp3.errors import Prp3Error
from prp3.explorer.scene import (
    ArrowStyle,
    Columns,
    State,
    View,
    arrow_columns,
    design_value,
    with_design_values,
)
from prp3.family import (
    FamilyRobot,
    family_inverse_dynamics,
    family_results_table,
    leg_chain,
    leg_jacobian,
    leg_measure,
    parallel_measure,
    transmitted_wrench,
)
from prp3.family.chain import SIGMA, SINGULAR
from prp3.family.outputs import LEG_COLUMNS
from prp3.model.motion import Motion
from prp3.validation import LEGS

__all__ = [
    "FAMILY_ARROWS",
    "FAMILY_DESIGN_PARAMETERS",
    "HOME",
    "FamilyScene",
    "family_arrow_scale",
    "family_design_parameters",
    "family_design_robot",
    "family_design_values",
    "family_extent",
    "family_measures",
    "family_pose_table",
    "family_view",
]

FloatArray = NDArray[np.float64]

#: The force arrows of a family robot: quantity → its style.
FAMILY_ARROWS: dict[str, ArrowStyle] = {
    "F1": ArrowStyle("F1 = (fx1, fy1): base/link 0 on link 1 at O_1", "#d62728"),
    "F2": ArrowStyle("F2 = (fx2, fy2): link 1 on link 2 at O_2", "#9467bd"),
    "F3": ArrowStyle("F3 = (fx3, fy3): link 2 on the platform at O_3", "#e377c2"),
    "tau": ArrowStyle("tau·u_a: the actuator's share of an actuated P joint", "#000000"),
}

#: Editable design parameters of a family robot: dotted key → (label, unit).
#: The design keys' components of the home coordinates ``q1, q2, q3``.
HOME: tuple[str, str, str] = ("a", "b", "gamma")

#: Every value of the family-form robot file (docs/family.md §3) but its architecture and
#: actuation; keys are the file's dotted keys, with ``.x``/``.y`` or ``.a``/``.b``/``.gamma``
#: for a pair's or a placement's components.
FAMILY_DESIGN_PARAMETERS: dict[str, tuple[str, str]] = {
    **{
        key: value
        for link in ("link1", "link2")
        for key, value in {
            f"{link}.mass": (f"link {link[-1]} mass", "kg"),
            f"{link}.inertia": (f"link {link[-1]} I", "kg·m²"),
            f"{link}.com.x": (f"link {link[-1]} com x", "m"),
            f"{link}.com.y": (f"link {link[-1]} com y", "m"),
        }.items()
    },
    "platform.mass": ("platform mass", "kg"),
    "platform.inertia": ("platform I", "kg·m²"),
    "payload.mass": ("payload mass", "kg"),
    "payload.inertia": ("payload I", "kg·m²"),
    "payload.com.x": ("payload com x", "m"),
    "payload.com.y": ("payload com y", "m"),
    "load.force.x": ("load F_x", "N"),
    "load.force.y": ("load F_y", "N"),
    "load.moment": ("load M", "N·m"),
    "gravity.x": ("gravity x", "m/s²"),
    "gravity.y": ("gravity y", "m/s²"),
    **{
        f"leg.{frame}.{part}": (f"{frame} {symbol}", unit)
        for frame in ("joint1", "joint2", "joint3", "attachment")
        for part, symbol, unit in (("a", "a", "m"), ("b", "b", "m"), ("gamma", "γ", "rad"))
    },
    **{f"leg.home.{part}": (f"home q{k}", "m or rad") for k, part in enumerate(HOME, 1)},
    "leg.scale": ("measure scale ℓ", "m"),
}


def family_design_parameters(robot: FamilyRobot) -> dict[str, tuple[str, str]]:
    """:data:`FAMILY_DESIGN_PARAMETERS` with the unit of each home coordinate of ``robot``'s
    joints (m for a P joint, rad for an R joint).

    >>> family_design_parameters(FamilyRobot.default("3-RPR"))["leg.home.b"]
    ('home q2', 'm')
    >>> len(FAMILY_DESIGN_PARAMETERS)  # the fields docs/explore.md counts
    35
    """
    units = {
        part: "m" if kind == "P" else "rad" for part, kind in zip(HOME, robot.types, strict=True)
    }
    return {
        key: (label, units[key.rsplit(".", 1)[1]]) if key.startswith("leg.home.") else (label, unit)
        for key, (label, unit) in FAMILY_DESIGN_PARAMETERS.items()
    }


def family_pose_table(robot: FamilyRobot, state: State) -> dict[str, FloatArray]:
    """The 64 columns of ``results.csv`` for one instant (each of shape ``(1,)``).

    Solved by :func:`prp3.family.family_inverse_dynamics` (the default route);
    a refused pose raises the library's :class:`~prp3.errors.Prp3Error`.

    >>> table = family_pose_table(FamilyRobot.default("3-RRR"), State())
    >>> len(table), [round(float(table[f"tau_{leg}"][0]), 4) for leg in "ABC"]
    (64, [7.1123, -3.5561, -3.5561])
    """
    if state.load is not None:
        raise Prp3Error("a family robot's load is its [load] table, not a load per sample")
    motion = Motion(
        t=np.zeros(()),
        pose=np.array(state.pose, dtype=np.float64),
        velocity=np.array(state.velocity, dtype=np.float64),
        acceleration=np.array(state.acceleration, dtype=np.float64),
    )
    table = family_results_table(family_inverse_dynamics(robot, motion))
    return {name: np.atleast_1d(values) for name, values in table.items()}


def _joint_values(table: Mapping[str, FloatArray], index: int) -> FloatArray:
    return np.array(
        [[float(table[f"q{k}_{leg}"][index]) for k in (1, 2, 3)] for leg in LEGS]
    )  # (3 legs, 3 joints)


def family_measures(
    robot: FamilyRobot, q: FloatArray, pose: FloatArray
) -> tuple[FloatArray, float]:
    """``μ_leg`` of legs A, B, C and ``μ_par`` (docs/family.md §6) at joint values ``q (3, 3)``.

    ``Ĵ_L`` from :func:`prp3.family.leg_jacobian` at ``G = (x, y)`` with
    ``ℓ = [leg] scale``; ``μ_leg = det Ĵ_L``; ``μ_par`` from the legs'
    transmitted wrenches.

    >>> robot = FamilyRobot.default("3-RRR")
    >>> table = family_pose_table(robot, State())
    >>> mu_leg, mu_par = family_measures(robot, _joint_values(table, 0), np.zeros(3))
    >>> [round(float(v), 4) for v in mu_leg], round(mu_par, 4)
    ([0.4444, 0.4444, 0.4444], 0.9977)
    """
    frames = leg_chain(robot.types, robot.leg.placements, SIGMA, q)
    centre = np.broadcast_to(np.asarray(pose[:2], dtype=np.float64), (3, 2))
    hat = leg_jacobian(robot.types, frames, centre, robot.leg.scale)
    mu_leg = np.asarray(leg_measure(hat), dtype=np.float64)
    mu_par = float(parallel_measure(transmitted_wrench(hat, robot.actuated)))
    return mu_leg, mu_par


def _unit(types: str, actuated: int, name: str, k: int | None) -> str:
    if name == "tau":
        return "N" if types[actuated - 1] == "P" else "N·m"
    if name == "p":
        return "W"
    if name.startswith(("fx", "fy")):
        return "N"
    if name.startswith("m"):
        return "N·m"
    assert k is not None
    base = "m" if types[k - 1] == "P" else "rad"
    return {"q": base, "dq": f"{base}/s", "ddq": f"{base}/s²"}[name.rstrip("123")]


def family_view(
    robot: FamilyRobot, table: Mapping[str, FloatArray], index: int, scale: float
) -> View:
    """The drawing, the force arrows, the values and the measures of sample ``index``.

    Parameters
    ----------
    robot : FamilyRobot
        The robot of the table.
    table : mapping of str to ndarray (N,)
        The 64 columns of ``results.csv`` in family form (:func:`family_pose_table`).
    index : int
        The sample drawn.
    scale : float
        Arrow length per newton (m/N).

    Returns
    -------
    View
        ``shapes``: ``base`` (the triangle of the three joint-1 frames), ``platform``
        (the triangle of the three ``O_3``), ``links`` (two segments per leg),
        ``revolute`` (``x, y, colour, outline, leg, joint``), ``sliders`` and
        ``guides`` (segments), ``centre``, ``payload`` and ``measures``
        (``measure, value, home, margin``); ``arrows`` as the 3-PRP's (quantity
        ``F1, F2, F3, tau``, tail at ``O_k``); ``table``: the 20 per-leg
        quantities of the 64 columns and ``mu_leg``, one row each.

    Examples
    --------
    >>> robot = FamilyRobot.default("3-RRR")
    >>> view = family_view(robot, family_pose_table(robot, State()), 0, 0.001)
    >>> row = view.arrows["quantity"].index("F1")
    >>> view.arrows["leg"][row], round(view.arrows["fx"][row], 4), round(view.arrows["fy"][row], 4)
    ('A', 0.0, 40.4663)
    """
    types, act = robot.types, robot.actuated
    q = _joint_values(table, index)
    pose = np.array([float(table[name][index]) for name in ("x", "y", "phi")])
    frames = leg_chain(types, robot.leg.placements, SIGMA, q)
    origin, joint_origin, axis = frames.origin, frames.joint_origin, frames.axis
    colours = [LEG_COLOURS[leg] for leg in LEGS]
    links: Columns = {"xs": [], "ys": [], "colour": [], "leg": []}
    revolute: Columns = {"x": [], "y": [], "colour": [], "outline": [], "leg": [], "joint": []}
    sliders: Columns = {"xs": [], "ys": [], "colour": [], "leg": [], "joint": []}
    guides: Columns = {"xs": [], "ys": []}
    for j, leg in enumerate(LEGS):
        o, jo, u = origin[j], joint_origin[j], axis[j]
        for start, end in ((o[0], jo[1]), (o[1], jo[2])):
            links["xs"].append([float(start[0]), float(end[0])])
            links["ys"].append([float(start[1]), float(end[1])])
            links["colour"].append(colours[j])
            links["leg"].append(leg)
        for k in range(3):
            driven = k == act - 1
            if types[k] == "R":
                revolute["x"].append(float(o[k, 0]))
                revolute["y"].append(float(o[k, 1]))
                revolute["colour"].append(colours[j])
                revolute["outline"].append("#000000" if driven else colours[j])
                revolute["leg"].append(leg)
                revolute["joint"].append(k + 1)
            else:
                ends = np.stack([o[k] - SLIDE_HALF_LENGTH * u[k], o[k] + SLIDE_HALF_LENGTH * u[k]])
                sliders["xs"].append(ends[:, 0].tolist())
                sliders["ys"].append(ends[:, 1].tolist())
                sliders["colour"].append("#000000" if driven else colours[j])
                sliders["leg"].append(leg)
                sliders["joint"].append(k + 1)
                travel = float((o[k] - jo[k]) @ u[k])
                low = min(travel, 0.0) - GUIDE_OVERHANG
                high = max(travel, 0.0) + GUIDE_OVERHANG
                guide = np.stack([jo[k] + low * u[k], jo[k] + high * u[k]])
                guides["xs"].append(guide[:, 0].tolist())
                guides["ys"].append(guide[:, 1].tolist())
    base = joint_origin[:, 0, :]
    plate = origin[:, 2, :]
    centre = pose[:2]
    payload = robot.payload
    c, s = math.cos(pose[2]), math.sin(pose[2])
    com = centre + np.array(
        [c * payload.com[0] - s * payload.com[1], s * payload.com[0] + c * payload.com[1]]
    )
    mu_leg, mu_par = family_measures(robot, q, pose)
    home_leg, home_par = robot.home_measures
    signs = [*(math.copysign(1.0, v) for v in home_leg), math.copysign(1.0, home_par)]
    values = [*(float(v) for v in mu_leg), mu_par]
    shapes: dict[str, Columns] = {
        "base": {"xs": [base[:, 0].tolist()], "ys": [base[:, 1].tolist()]},
        "platform": {"xs": [plate[:, 0].tolist()], "ys": [plate[:, 1].tolist()]},
        "links": links,
        "revolute": revolute,
        "sliders": sliders,
        "guides": guides,
        "centre": {"x": [float(centre[0])], "y": [float(centre[1])]},
        "payload": (
            {"x": [float(com[0])], "y": [float(com[1])], "radius": [0.01]}
            if payload.mass > 0.0
            else {"x": [], "y": [], "radius": []}
        ),
        "measures": {
            "measure": ["μ_leg A", "μ_leg B", "μ_leg C", "μ_par"],
            "value": values,
            "home": signs,
            "margin": [sign * value for sign, value in zip(signs, values, strict=True)],
        },
    }
    forces = [
        (f"F{k}", leg, origin[j, k - 1], *(float(table[f"f{c}{k}_{leg}"][index]) for c in "xy"))
        for k in (1, 2, 3)
        for j, leg in enumerate(LEGS)
    ]
    if types[act - 1] == "P":  # the actuator's share tau·u_a at its joint
        for j, leg in enumerate(LEGS):
            tau, u = float(table[f"tau_{leg}"][index]), axis[j, act - 1]
            forces.append(("tau", leg, origin[j, act - 1], tau * float(u[0]), tau * float(u[1])))
    arrows = arrow_columns(forces, scale)
    rows: Columns = {"quantity": [], "unit": [], "A": [], "B": [], "C": []}
    for name in LEG_COLUMNS:
        rows["quantity"].append(name)
        rows["unit"].append(_unit(types, act, name, int(name[-1]) if name[-1].isdigit() else None))
        for leg in LEGS:
            rows[leg].append(float(table[f"{name}_{leg}"][index]))
    rows["quantity"].append("mu_leg")
    rows["unit"].append("-")
    for j, leg in enumerate(LEGS):
        rows[leg].append(float(mu_leg[j]))
    return View(shapes=shapes, arrows=arrows, table=rows)


def family_extent(robot: FamilyRobot) -> float:
    """Half width of the drawing window (m): 1.25 × the farthest point drawn at the central pose.

    >>> round(family_extent(FamilyRobot.default("3-RRR")), 4)
    0.4498
    """
    view = family_view(robot, family_pose_table(robot, State()), 0, 0.0)
    points = [
        *(v for xs in view.shapes["guides"]["xs"] for v in xs),
        *(v for ys in view.shapes["guides"]["ys"] for v in ys),
        *(v for xs in view.shapes["links"]["xs"] for v in xs),
        *(v for ys in view.shapes["links"]["ys"] for v in ys),
    ]
    return 1.25 * max(abs(float(v)) for v in points)


def family_arrow_scale(robot: FamilyRobot, fraction: float = 0.35) -> float:
    """Arrow length per newton (m/N): the largest joint force at rest at the centre drawn
    ``fraction × [leg] scale`` long (1 N when every force vanishes).

    >>> round(family_arrow_scale(FamilyRobot.default("3-RRR")), 8)   # 0.35·0.3 m / 40.4663 N
    0.00259475
    """
    view = family_view(robot, family_pose_table(robot, State()), 0, 0.0)
    peak = max(view.arrows["value"], default=0.0)
    return fraction * robot.leg.scale / (peak if peak > 0.0 else 1.0)


def family_design_values(robot: FamilyRobot) -> dict[str, float]:
    """The current value of each of :data:`FAMILY_DESIGN_PARAMETERS`.

    >>> family_design_values(FamilyRobot.default("3-RRR"))["platform.mass"]
    3.0
    """
    return {key: design_value(robot, key) for key in FAMILY_DESIGN_PARAMETERS}


def family_design_robot(robot: FamilyRobot, values: Mapping[str, float]) -> FamilyRobot:
    """``robot`` with the design values ``values`` (keys of :data:`FAMILY_DESIGN_PARAMETERS`).

    Validated by the model's own classes: a bad value raises the library's
    :class:`~prp3.errors.ParameterError` naming the key.

    >>> robot = family_design_robot(FamilyRobot.default("3-RRR"), {"payload.mass": 2.0})
    >>> robot.payload.mass
    2.0
    """
    unknown = sorted(set(values) - set(FAMILY_DESIGN_PARAMETERS))
    if unknown:
        raise Prp3Error(f"unknown design parameter {unknown[0]!r}", key=unknown[0])
    changed: FamilyRobot = with_design_values(robot, values)
    return changed


@dataclass(frozen=True)
class FamilyScene:
    """A family robot as a scene of the explorer: :func:`family_pose_table`, :func:`family_view`.

    >>> FamilyScene().threshold
    0.0001
    """

    threshold: float = SINGULAR

    def table(self, robot: FamilyRobot, state: State) -> dict[str, FloatArray]:
        return family_pose_table(robot, state)

    def view(
        self, robot: FamilyRobot, table: Mapping[str, FloatArray], index: int, scale: float
    ) -> View:
        return family_view(robot, table, index, scale)
