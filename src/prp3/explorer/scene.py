"""What the explorer draws, as plain columns: the robot, its joint forces, a run, the workspace.

Nothing here imports Bokeh: every function returns plain ``dict[str, list]``
columns (what a Bokeh ``ColumnDataSource`` holds), so that the numbers the
page shows are testable without a browser, and so that another
architecture can plug into the same page by giving the same columns
(:class:`Scene`).

A run of ``prp3 simulate`` is read by :mod:`prp3.explorer.run_folder`
(:class:`~prp3.explorer.run_folder.Run`, :func:`~prp3.explorer.run_folder.read_run`).

The forces come only from prp3's own engines: a pose is solved by
:func:`prp3.analysis.inverse_dynamics.inverse_dynamics` (the kernel, eqs. 10–25) and turned
into the columns of ``results.csv`` by :func:`prp3.io.results.results_table`; a run of
``prp3 simulate`` is drawn from its own columns.  Both go through
:func:`scene_view`, which only places the reported components in the plane:

* ``f10_i`` (eq. 23), the actuator force on piston ``i``: ``f10·e_i`` at ``P_i``;
* ``f21_i`` (eqs. 24, 25), the force of piston ``i`` on link 2 at ``P_i``:
  ``f21y·n_i + f21z·e_i``;
* ``n10_i``, the base guide's reaction on piston ``i``: ``n10·n_i`` (its moment
  ``m10`` about ``P_i`` is in the table);
* ``n32_i``, the reaction of link 2 on the platform: ``n32·d⊥_i`` (its moment
  ``m32`` about ``P_i`` is in the table);
* with ``[friction]``: ``fric10·e_i`` and ``fric32·d_i`` (``fric21``, a moment,
  is in the table).

``e_i = (cos α_i, sin α_i)``, ``n_i = J·e_i`` with ``α = (π/3, π, −π/3)``
(eq. 1), ``d_i`` the platform edge direction and ``d⊥_i = J·d_i`` (eq. 9).
Every arrow starts at ``P_i``: the reactions are reported about ``P_i``
(``docs/model.md``, *Quantities and signs*).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from typing import Any, NamedTuple, Protocol

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.analysis.workspace import workspace_statics
from prp3.drawing import LEG_COLOURS, PISTON_HALF_LENGTH, SLEEVE_HALF_LENGTH
from prp3.errors import Prp3Error
from prp3.io.results import (
    OUTPUT_QUANTITIES,
    results_table,
)
from prp3.mechanics.geometry import (
    LEG_AXIS,
    base_vertices,
    inverse_geometry,
    perp,
    platform_vertices,
)
from prp3.model.motion import Motion
from prp3.model.parameters import Friction, JointFriction
from prp3.model.robot import Robot
from prp3.moved_paths import moved_attribute
from prp3.pose_validation import SINGULARITY_THRESHOLD, singularity_measure
from prp3.validation import LEGS

__all__ = [
    "ARROWS",
    "ARROW_COLUMNS",
    "DESIGN_COMPONENTS",
    "DESIGN_PARAMETERS",
    "MOTION_CONTROLS",
    "PRP3_SCENE",
    "ArrowStyle",
    "Columns",
    "MotionControl",
    "Scene",
    "State",
    "View",
    "arrow_columns",
    "arrow_scale",
    "design_robot",
    "design_value",
    "design_values",
    "empty_view",
    "pose_table",
    "scene_view",
    "signed_design_key",
    "singularity_curve",
    "stroke_bands",
    "with_design_values",
    "workspace_overlay",
]

FloatArray = NDArray[np.float64]
#: The columns of one data source: name → values.
Columns = dict[str, list[Any]]


class ArrowStyle(NamedTuple):
    """How the arrows of one quantity are drawn: their label in the key, and their colour."""

    label: str
    colour: str


#: The force arrows: quantity → its style.
ARROWS: dict[str, ArrowStyle] = {
    "f10": ArrowStyle("f10: actuator force on the piston (along e)", "#d62728"),
    "f21": ArrowStyle("f21: piston on link 2 (f21y n + f21z e)", "#9467bd"),
    "n10": ArrowStyle("n10: guide reaction on the piston (along n)", "#8c564b"),
    "n32": ArrowStyle("n32: link 2 on the platform (along d⊥)", "#e377c2"),
    "fric10": ArrowStyle("fric10: guide friction on the piston (along e)", "#7f7f7f"),
    "fric32": ArrowStyle("fric32: sleeve friction on the platform (along d)", "#bcbd22"),
}

#: The rows of the table of values, in order (columns of ``results.csv``).
TABLE_QUANTITIES: tuple[str, ...] = (
    "lambda10",
    "lambda32",
    "f10",
    "p10",
    "f21y",
    "f21z",
    "n10",
    "m10",
    "n32",
    "m32",
    "fric10",
    "fric21",
    "fric32",
)


@dataclass(frozen=True)
class MotionControl:
    """One slider of the platform motion: its name, label, unit and range (as multiples of ``l0``
    for lengths)."""

    name: str
    label: str
    unit: str
    low: float
    high: float
    step: float
    length: bool  # the range scales with l0


#: Sliders of the pose, velocity and acceleration of the platform.
MOTION_CONTROLS: tuple[MotionControl, ...] = (
    MotionControl("x", "x", "m", -0.6, 0.6, 0.001, True),
    MotionControl("y", "y", "m", -0.6, 0.6, 0.001, True),
    MotionControl("phi", "φ", "rad", -math.pi, math.pi, 0.001, False),
    MotionControl("dx", "ẋ", "m/s", -1.0, 1.0, 0.001, False),
    MotionControl("dy", "ẏ", "m/s", -1.0, 1.0, 0.001, False),
    MotionControl("dphi", "φ̇", "rad/s", -5.0, 5.0, 0.001, False),
    MotionControl("ddx", "ẍ", "m/s²", -10.0, 10.0, 0.01, False),
    MotionControl("ddy", "ÿ", "m/s²", -10.0, 10.0, 0.01, False),
    MotionControl("ddphi", "φ̈", "rad/s²", -50.0, 50.0, 0.01, False),
)

#: Editable design parameters: key → (label, unit).  Keys are dotted ``ROBOT.toml`` keys.
DESIGN_PARAMETERS: dict[str, tuple[str, str]] = {
    "l0": ("l0", "m"),
    "piston.mass": ("piston mass", "kg"),
    "link.mass": ("link mass", "kg"),
    "platform.mass": ("platform mass", "kg"),
    "payload.mass": ("payload mass", "kg"),
    "piston.inertia": ("piston I", "kg·m²"),
    "piston.com.x": ("piston com x", "m"),
    "piston.com.y": ("piston com y", "m"),
    "link.inertia": ("link I", "kg·m²"),
    "link.com.x": ("link com x", "m"),
    "link.com.y": ("link com y", "m"),
    "payload.inertia": ("payload I", "kg·m²"),
    "payload.com.x": ("payload com x", "m"),
    "payload.com.y": ("payload com y", "m"),
    "load.force.x": ("load F_x", "N"),
    "load.force.y": ("load F_y", "N"),
    "load.moment": ("load M", "N·m"),
    "gravity.x": ("gravity x", "m/s²"),
    "gravity.y": ("gravity y", "m/s²"),
    "friction.actuator.viscous": ("guide b", "N·s/m"),
    "friction.actuator.coulomb": ("guide c", "N"),
    "friction.actuator.mu": ("guide μ", "-"),
    "friction.revolute.viscous": ("pin b", "N·m·s/rad"),
    "friction.revolute.coulomb": ("pin c", "N·m"),
    "friction.sleeve.viscous": ("sleeve b", "N·s/m"),
    "friction.sleeve.coulomb": ("sleeve c", "N"),
    "friction.sleeve.mu": ("sleeve μ", "-"),
}


@dataclass(frozen=True)
class State:
    """The motion of the platform at one instant: pose, velocity, acceleration (and a load).

    Attributes
    ----------
    pose, velocity, acceleration : tuple of 3 float
        ``(x, y, φ)`` (m, m, rad) and its first and second time derivatives.
    load : tuple of 3 float or None
        A time-varying wrench ``(f_x, f_y, m_z)`` on the platform (a run's
        load columns), ``None`` without.
    """

    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    acceleration: tuple[float, float, float] = (0.0, 0.0, 0.0)
    load: tuple[float, float, float] | None = None

    @classmethod
    def from_controls(cls, values: Mapping[str, float]) -> State:
        """The state of the sliders named as in :data:`MOTION_CONTROLS` (missing ones are 0)."""
        v = [float(values.get(control.name, 0.0)) for control in MOTION_CONTROLS]
        return cls((v[0], v[1], v[2]), (v[3], v[4], v[5]), (v[6], v[7], v[8]))

    def controls(self) -> dict[str, float]:
        """The slider values of this state, by name."""
        values = (*self.pose, *self.velocity, *self.acceleration)
        return {c.name: float(v) for c, v in zip(MOTION_CONTROLS, values, strict=True)}


@dataclass(frozen=True)
class View:
    """Everything the page draws for one instant, as the columns of its data sources.

    Attributes
    ----------
    shapes : dict of Columns
        ``base``, ``platform`` (patches ``xs, ys``), ``pistons``, ``sleeves``
        (lines ``xs, ys, colour, leg``), ``joints`` (``x, y, colour, leg``),
        ``payload`` (``x, y, radius``).
    arrows : Columns
        One row per arrow: ``quantity, leg, x0, y0, x1, y1, fx, fy, value,
        angle`` (tail at the joint, ``fx, fy`` the force in N, ``x1 = x0 +
        scale·fx``; ``angle`` of the head, rad).
    table : Columns
        One row per quantity of the table: ``quantity, unit, A, B, C``.
    message : str
        ``""``, or the library's one-line message when the pose is refused.
    """

    shapes: dict[str, Columns]
    arrows: Columns
    table: Columns
    message: str = ""

    def sources(self) -> dict[str, Columns]:
        """The columns of every data source by the source's name."""
        return {**self.shapes, "arrows": self.arrows, "values": self.table}


class Scene(Protocol):
    """What an architecture gives the explorer (the 3-PRP one is :data:`PRP3_SCENE`).

    ``table(robot, state)`` solves one instant with the architecture's own
    engine and returns its results columns (batch of one); ``view(robot,
    table, index, scale)`` places them in the plane; ``singularity(phi)`` is the
    architecture's singularity measure of the orientation.
    """

    def table(self, robot: Robot, state: State) -> dict[str, FloatArray]: ...

    def view(
        self, robot: Robot, table: Mapping[str, FloatArray], index: int, scale: float
    ) -> View: ...

    def singularity(self, phi: FloatArray) -> FloatArray: ...


def pose_table(robot: Robot, state: State) -> dict[str, FloatArray]:
    """The columns of ``results.csv`` for one instant (each of shape ``(1,)``).

    Solved by :func:`prp3.analysis.inverse_dynamics.inverse_dynamics` (the kernel, eqs. 10–25);
    a refused pose raises the library's :class:`~prp3.errors.Prp3Error`.

    >>> table = pose_table(Robot(), State())
    >>> [round(float(table[f"f10_{leg}"][0]), 4) for leg in "ABC"]   # the statics at rest
    [31.8589, -8.4957, -23.3632]
    """
    load = None if state.load is None else np.array(state.load, dtype=np.float64)
    motion = Motion(  # one sample (rank 0): the library's messages name no sample
        t=np.zeros(()),
        pose=np.array(state.pose, dtype=np.float64),
        velocity=np.array(state.velocity, dtype=np.float64),
        acceleration=np.array(state.acceleration, dtype=np.float64),
        load=load,
    )
    table = results_table(*inverse_dynamics(robot, motion))
    return {name: np.atleast_1d(values) for name, values in table.items()}


def _per_leg(table: Mapping[str, FloatArray], name: str, index: int) -> FloatArray | None:
    if f"{name}_A" not in table:
        return None
    return np.array([float(table[f"{name}_{leg}"][index]) for leg in LEGS])


def scene_view(robot: Robot, table: Mapping[str, FloatArray], index: int, scale: float) -> View:
    """The drawing and the force arrows of sample ``index`` of a results table.

    Parameters
    ----------
    robot : Robot
        The robot of the table (its ``l0``, strokes and payload are drawn).
    table : mapping of str to ndarray (N,)
        Columns of ``results.csv`` (:func:`pose_table`, :func:`prp3.explorer.run_folder.read_run`).
    index : int
        The sample drawn.
    scale : float
        Length of an arrow per newton (m/N).

    Examples
    --------
    >>> view = scene_view(Robot(), pose_table(Robot(), State()), 0, 0.001)
    >>> row = view.arrows["quantity"].index("f10")                  # leg A: along e_A
    >>> view.arrows["leg"][row], round(view.arrows["fx"][row], 4), round(view.arrows["fy"][row], 4)
    ('A', 15.9295, 27.5906)
    """
    pose = np.array([float(table[name][index]) for name in ("x", "y", "phi")])
    geo = inverse_geometry(robot, pose)
    joint, slide = geo.joint, geo.slide
    normal = perp(LEG_AXIS)
    piston = PISTON_HALF_LENGTH * robot.l0 * LEG_AXIS
    sleeve = SLEEVE_HALF_LENGTH * robot.l0 * slide
    colours = [LEG_COLOURS[leg] for leg in LEGS]

    def bars(half: FloatArray) -> Columns:
        ends = np.stack([joint - half, joint + half], axis=1)  # (3, 2 ends, 2)
        return {
            "xs": [ends[j, :, 0].tolist() for j in range(3)],
            "ys": [ends[j, :, 1].tolist() for j in range(3)],
            "colour": colours,
            "leg": list(LEGS),
        }

    base = base_vertices(robot)
    plate = platform_vertices(robot, pose)
    centre = pose[:2]
    payload = robot.payload
    c, s = math.cos(pose[2]), math.sin(pose[2])
    com = centre + np.array(
        [c * payload.com[0] - s * payload.com[1], s * payload.com[0] + c * payload.com[1]]
    )
    radius = 0.04 * robot.l0 * math.sqrt(payload.mass / max(robot.platform.mass, 1e-12))
    shapes: dict[str, Columns] = {
        "base": {"xs": [base[:, 0].tolist()], "ys": [base[:, 1].tolist()]},
        "platform": {"xs": [plate[:, 0].tolist()], "ys": [plate[:, 1].tolist()]},
        "pistons": bars(piston),
        "sleeves": bars(sleeve),
        "joints": {
            "x": joint[:, 0].tolist(),
            "y": joint[:, 1].tolist(),
            "colour": colours,
            "leg": list(LEGS),
        },
        "centre": {"x": [float(centre[0])], "y": [float(centre[1])]},
        "payload": (
            {"x": [float(com[0])], "y": [float(com[1])], "radius": [radius]}
            if payload.mass > 0.0
            else {"x": [], "y": [], "radius": []}
        ),
    }
    components = _force_components(table, index, normal, slide)
    arrows = arrow_columns(
        (
            (quantity, leg, joint[j], float(vectors[j, 0]), float(vectors[j, 1]))
            for quantity, vectors in components.items()
            if vectors is not None
            for j, leg in enumerate(LEGS)
        ),
        scale,
    )
    rows = _table_rows(table, index)
    return View(shapes=shapes, arrows=arrows, table=rows)


def _force_components(
    table: Mapping[str, FloatArray], index: int, normal: FloatArray, slide: FloatArray
) -> dict[str, FloatArray | None]:
    """The arrows' vectors ``(3, 2)`` per quantity at sample ``index``: ``f10`` along
    ``e_i``, ``f21`` and ``n10`` from ``normal`` (``n_i``) and ``e_i``, ``n32`` across the
    sleeve's direction ``slide``, the friction forces where the table has them (else None)."""
    components: dict[str, FloatArray | None] = {}
    f10, f21y, f21z = (_per_leg(table, n, index) for n in ("f10", "f21y", "f21z"))
    n10, n32 = _per_leg(table, "n10", index), _per_leg(table, "n32", index)
    fric10, fric32 = _per_leg(table, "fric10", index), _per_leg(table, "fric32", index)
    assert f10 is not None and f21y is not None and f21z is not None
    assert n10 is not None and n32 is not None
    components["f10"] = f10[:, None] * LEG_AXIS
    components["f21"] = f21y[:, None] * normal + f21z[:, None] * LEG_AXIS
    components["n10"] = n10[:, None] * normal
    components["n32"] = n32[:, None] * perp(slide)
    components["fric10"] = None if fric10 is None else fric10[:, None] * LEG_AXIS
    components["fric32"] = None if fric32 is None else fric32[:, None] * slide
    return components


def _table_rows(table: Mapping[str, FloatArray], index: int) -> Columns:
    """The explorer's table of sample ``index``: one row per quantity the table has, with
    its unit and its value for legs A, B, C."""
    rows: Columns = {"quantity": [], "unit": [], "A": [], "B": [], "C": []}
    for quantity in TABLE_QUANTITIES:
        values = _per_leg(table, quantity, index)
        if values is None:
            continue
        rows["quantity"].append(quantity)
        rows["unit"].append(OUTPUT_QUANTITIES[quantity].unit)
        for j, leg in enumerate(LEGS):
            rows[leg].append(float(values[j]))
    return rows


#: The columns of the arrows' source (:attr:`View.arrows`).
ARROW_COLUMNS: tuple[str, ...] = (
    "quantity", "leg", "x0", "y0", "x1", "y1", "fx", "fy", "value", "angle",
)  # fmt: skip


def arrow_columns(
    rows: Iterable[tuple[str, str, FloatArray, float, float]], scale: float
) -> Columns:
    """The columns of :attr:`View.arrows`, a row per ``(quantity, leg, tail, fx, fy)`` of ``rows``.

    The force ``(fx, fy)`` (N) with its tail at the point ``tail`` (m) and its
    head at ``tail + scale·(fx, fy)``; ``value`` its magnitude (N), ``angle``
    the direction of its head (rad, for a triangle that points up).

    >>> arrows = arrow_columns([("f10", "A", np.zeros(2), 3.0, 4.0)], 0.01)
    >>> arrows["x1"], arrows["value"]
    ([0.03], [5.0])
    """
    arrows: Columns = {key: [] for key in ARROW_COLUMNS}
    for quantity, leg, tail, fx, fy in rows:
        x0, y0 = float(tail[0]), float(tail[1])
        for key, value in zip(
            ARROW_COLUMNS,
            (quantity, leg, x0, y0, x0 + scale * fx, y0 + scale * fy, fx, fy,
             math.hypot(fx, fy), math.atan2(fy, fx) - math.pi / 2.0),
            strict=True,
        ):  # fmt: skip
            arrows[key].append(value)
    return arrows


def empty_view(like: View) -> View:
    """The same sources with no rows: what is drawn while a pose is refused (no stale picture)."""
    return View(
        shapes={name: {key: [] for key in columns} for name, columns in like.shapes.items()},
        arrows={key: [] for key in like.arrows},
        table={key: [] for key in like.table},
    )


def arrow_scale(robot: Robot, fraction: float = 0.35) -> float:
    """Arrow length per newton (m/N): the largest statics force at the centre drawn ``fraction·l0``.

    The statics at rest (``pose_table`` at the central pose); the weight of the
    platform when every force there vanishes (no gravity: 1 N).

    >>> round(arrow_scale(Robot()), 8)      # 0.35·0.3 m over |f10_A| = 31.86 N
    0.00329578
    """
    table = pose_table(robot, State())
    names = [f"{q}_{leg}" for q in ("f10", "f21y", "f21z", "n10", "n32") for leg in LEGS]
    peak = max(abs(float(table[name][0])) for name in names)
    return fraction * robot.l0 / (peak if peak > 0.0 else 1.0)


# ---------------------------------------------------------------- limits
def singularity_curve(phi_range: tuple[float, float], samples: int = 721) -> Columns:
    """The singularity measure ``sin(φ − π/3)`` over ``phi_range`` (:func:`prp3.pose_validation.singularity_measure`),
    with the threshold below which poses are refused.

    >>> curve = singularity_curve((-math.pi, math.pi), 5)
    >>> [round(v, 6) for v in curve["measure"]], curve["threshold"][0]
    ([0.866025, -0.5, -0.866025, 0.5, 0.866025], 0.0001)
    """
    phi = np.linspace(phi_range[0], phi_range[1], samples)
    return {
        "phi": phi.tolist(),
        "measure": singularity_measure(phi).tolist(),
        "threshold": [SINGULARITY_THRESHOLD] * samples,
    }


def stroke_bands(robot: Robot) -> Columns:
    """Where each joint ``P_i`` may go: its actuator's stroke on the guide (lines ``xs, ys``).

    ``P_i = B_i0 + (l0/√3 + λ10_i)·e_i`` (eq. 10) at both ends of
    ``[limits] stroke``; no rows without a stroke.

    >>> from prp3.model.parameters import Limits
    >>> bands = stroke_bands(Robot(limits=Limits(stroke=(-0.05, 0.05))))
    >>> [round(v, 4) for v in bands["xs"][0]], bands["leg"]
    ([0.0616, 0.1116], ['A', 'B', 'C'])
    """
    stroke = robot.limits.stroke
    if stroke is None:
        return {"xs": [], "ys": [], "colour": [], "leg": []}
    base = base_vertices(robot)
    ends = [
        base + (robot.l0 / math.sqrt(3.0) + limit) * LEG_AXIS for limit in stroke
    ]  # (3, 2) each
    return {
        "xs": [[float(ends[0][j, 0]), float(ends[1][j, 0])] for j in range(3)],
        "ys": [[float(ends[0][j, 1]), float(ends[1][j, 1])] for j in range(3)],
        "colour": [LEG_COLOURS[leg] for leg in LEGS],
        "leg": list(LEGS),
    }


def workspace_overlay(robot: Robot, phi: float, points: int = 41) -> dict[str, Columns]:
    """The statics map of ``prp3 workspace`` at orientation ``phi``, as an image and a region.

    :func:`prp3.analysis.workspace.workspace_statics` on a square grid of ``points²``
    poses over ``|x|, |y| <= 0.6·l0``: ``image`` holds ``max_i |f10_i|`` (N)
    where the pose is within the strokes, NaN elsewhere; ``region`` the exact
    reachable boundary (no rows without a stroke).

    >>> from prp3.model.parameters import Limits
    >>> overlay = workspace_overlay(Robot(limits=Limits(stroke=(-0.05, 0.05))), 0.0, 41)
    >>> round(float(np.nanmax(overlay["image"]["image"][0])), 3), len(overlay["region"]["xs"][0]) > 3
    (36.547, True)
    """
    half = 0.6 * robot.l0
    grid = np.linspace(-half, half, points)
    statics = workspace_statics(robot, phi, grid, grid)
    peak = np.where(statics.reachable, statics.peak, np.nan)
    step = grid[1] - grid[0]
    region = statics.region
    return {
        "image": {
            "image": [peak],
            "x": [float(grid[0] - step / 2)],
            "y": [float(grid[0] - step / 2)],
            "dw": [float(2 * half + step)],
            "dh": [float(2 * half + step)],
        },
        "region": (
            {"xs": [region[:, 0].tolist()], "ys": [region[:, 1].tolist()]}
            if region is not None
            else {"xs": [], "ys": []}
        ),
    }


# ---------------------------------------------------------------- design
def signed_design_key(key: str) -> bool:
    """Whether a design key may be negative: a coordinate, a load or gravity."""
    return key.rsplit(".", 1)[-1] in DESIGN_COMPONENTS or key.startswith(("load.", "gravity."))


#: The components of a pair or a placement in a design key: ``gravity.y``, ``leg.joint2.gamma``.
DESIGN_COMPONENTS: dict[str, int] = {"x": 0, "y": 1, "a": 0, "b": 1, "gamma": 2}


def design_value(model: Any, key: str) -> float:
    """The value of a dotted design key of an immutable robot (``link.com.x``, ``load.moment``).

    A part that is ``None`` (a robot without ``[friction]``) gives 0; the last
    part of a key into a tuple names its component (:data:`DESIGN_COMPONENTS`).

    >>> design_value(Robot(), "gravity.y"), design_value(Robot(), "friction.actuator.mu")
    (-9.81, 0.0)
    """
    value: Any = model
    for part in key.split("."):
        if value is None:  # no [friction]: every coefficient is 0
            return 0.0
        value = value[DESIGN_COMPONENTS[part]] if isinstance(value, tuple) else getattr(value, part)
    return float(value)


def with_design_values(model: Any, values: Mapping[str, float]) -> Any:
    """``model`` (a frozen dataclass) with the dotted design keys ``values`` replaced.

    Each part is rebuilt by :func:`dataclasses.replace`, so the model's own
    validation refuses a bad value, naming it.

    >>> with_design_values(Robot(), {"gravity.x": 1.0, "link.com.y": 0.01}).link.com
    (0.0, 0.01)
    """
    if isinstance(model, tuple):
        items = list(model)
        for key, value in values.items():
            items[DESIGN_COMPONENTS[key]] = float(value)
        return tuple(items)
    groups: dict[str, dict[str, float]] = {}
    for key, value in values.items():
        head, _, rest = key.partition(".")
        groups.setdefault(head, {})[rest] = value
    changes = {
        head: float(sub[""]) if "" in sub else with_design_values(getattr(model, head), sub)
        for head, sub in groups.items()
    }
    return replace(model, **changes)


def design_values(robot: Robot) -> dict[str, float]:
    """The current value of each of :data:`DESIGN_PARAMETERS`.

    >>> design_values(Robot())["platform.mass"], design_values(Robot())["friction.sleeve.mu"]
    (3.0, 0.0)
    """
    return {key: design_value(robot, key) for key in DESIGN_PARAMETERS}


def design_robot(robot: Robot, values: Mapping[str, float]) -> Robot:
    """``robot`` with the design parameters ``values`` (keys of :data:`DESIGN_PARAMETERS`).

    The new robot is validated as a ``ROBOT.toml`` is: a bad value raises the
    library's :class:`~prp3.errors.ParameterError` naming the key.  A robot
    without ``[friction]`` gets one only when a coefficient is set above 0.

    >>> design_robot(Robot(), {"payload.mass": 2.0, "l0": 0.25}).payload.mass
    2.0
    >>> design_robot(Robot(), {"link.mass": -1.0})
    Traceback (most recent call last):
    ...
    prp3.errors.ParameterError: robot: link.mass must be a positive finite number (kg), got -1.0
    """
    unknown = sorted(set(values) - set(DESIGN_PARAMETERS))
    if unknown:
        raise Prp3Error(f"unknown design parameter {unknown[0]!r}", key=unknown[0])
    changed: dict[str, float] = {k: float(v) for k, v in values.items()}
    plain = {k: v for k, v in changed.items() if not k.startswith("friction.")}
    robot = with_design_values(robot, plain)
    friction: Friction | None = robot.friction
    wanted = {k: v for k, v in changed.items() if k.startswith("friction.")}
    if wanted and (friction is not None or any(v != 0.0 for v in wanted.values())):
        base = friction if friction is not None else Friction()
        joints: dict[str, JointFriction] = {}
        for kind in ("actuator", "revolute", "sleeve"):
            fields = {
                k.rsplit(".", 1)[1]: v
                for k, v in wanted.items()
                if k.startswith(f"friction.{kind}.")
            }
            joints[kind] = replace(getattr(base, kind), **fields)
        friction = Friction(**joints)
    return replace(robot, friction=friction)


class _Prp3Scene:
    """The 3-PRP robot: :func:`pose_table`, :func:`scene_view` and ``sin(φ − π/3)``."""

    name = "3-PRP"

    def table(self, robot: Robot, state: State) -> dict[str, FloatArray]:
        return pose_table(robot, state)

    def view(self, robot: Robot, table: Mapping[str, FloatArray], index: int, scale: float) -> View:
        return scene_view(robot, table, index, scale)

    def singularity(self, phi: FloatArray) -> FloatArray:
        return singularity_measure(phi)


#: The 3-PRP robot as a :class:`Scene`.
PRP3_SCENE: Scene = _Prp3Scene()


def __getattr__(name: str) -> object:
    """The names this module had in prp3 0.1, now elsewhere (a DeprecationWarning names where)."""
    return moved_attribute(__name__, name)
