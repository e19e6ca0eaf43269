"""The explorer's Bokeh documents for a family robot (docs/family.md): live page and HTML file.

The same page as the 3-PRP's (:mod:`prp3.explorer.app`), for the columns of
:mod:`prp3.explorer.family_scene`: the robot's own legs to scale (R joints as
circles, P joints as slides on their guides, the driven joint in black), every
joint force ``(fx{k}, fy{k})`` as an arrow at ``O_k``, the 20 per-leg
quantities of the 64 columns in a table, and the singularity measures ``μ_leg``
of each leg and ``μ_par`` at the pose.  A refused pose empties every drawn
source but the base and shows the library's one-line message.  Bokeh is
imported inside the functions only; no force is computed in the browser.

Names of the page's models, for tests and scripts: the sliders ``x, y, phi,
dx, dy, dphi, ddx, ddy, ddphi`` (and ``<name>_field``), the design fields
``design:<key>`` (keys of
:data:`~prp3.explorer.family_scene.FAMILY_DESIGN_PARAMETERS`), the sources
``arrows``, ``values``, ``measures``, ``platform``, ``links``, ``revolute``,
``sliders``, ``guides``, ``base``, ``payload``, ``centre``, the message
``message``; with a run (the server's page or its HTML file) the scrubber
``time`` and the button ``play``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.explorer.family_scene import (
    FAMILY_ARROWS,
    FamilyScene,
    family_arrow_scale,
    family_design_parameters,
    family_design_robot,
    family_design_values,
    family_extent,
)
from prp3.explorer.live import Bundle, Changes, LivePage, refused
from prp3.explorer.page import (
    Glyph,
    Key,
    arrow_layers,
    clip_overlays,
    escape,
    results_table,
    robot_figure,
)
from prp3.explorer.run_folder import Run, family_run_motion
from prp3.explorer.scene import MotionControl, State, View
from prp3.explorer.scrubber import run_page
from prp3.family import FamilyRobot

__all__ = ["family_document", "family_run_html"]

FloatArray = NDArray[np.float64]

#: The per-leg quantities of the linked plots of a run.
FAMILY_PLOTTED: tuple[str, ...] = ("tau", "fx1", "fy1", "p")

SCENE = FamilyScene()

#: Design fields per row of the page.
DESIGN_ROW = 7


#: A family robot's glyphs, in drawing order (the arrows follow them).
_GLYPHS: tuple[Glyph, ...] = (
    (
        "patches",
        "base",
        "base (the joint-1 frames)",
        {"fill_alpha": 0.0, "line_color": "#777777", "line_dash": "dotted", "line_width": 1.5},
    ),
    (
        "multi_line",
        "guides",
        "guides of the P joints",
        {"line_color": "#595959", "line_dash": "dashed", "line_width": 1},
    ),
    (
        "patches",
        "platform",
        "platform (the O_3)",
        {"fill_color": "#bbbbbb", "fill_alpha": 0.6, "line_color": "#222222", "line_width": 2},
    ),
    ("multi_line", "links", "links 1, 2 (legs A, B, C)", {"line_color": "colour", "line_width": 3}),
    ("multi_line", "sliders", "P joints (slides)", {"line_color": "colour", "line_width": 8}),
    (
        "scatter",
        "revolute",
        "R joints",
        {
            "marker": "circle",
            "size": 11,
            "fill_color": "white",
            "line_color": "outline",
            "line_width": 2.5,
        },
    ),
    (
        "scatter",
        "payload",
        "payload",
        {"marker": "circle", "size": 14, "fill_color": "#444444", "fill_alpha": 0.8},
    ),
    ("scatter", "centre", "", {"marker": "cross", "size": 10, "color": "black"}),
)


def _figure(robot: FamilyRobot, sources: Mapping[str, Any]) -> tuple[Any, Any]:
    """The robot to scale with its force arrows, and its key (a legend and check boxes): of
    what this robot has (a glyph without rows is not listed).

    Every glyph at :data:`~prp3.explorer.page.LEVEL`: a move repaints them, not the axes.
    """
    driven = robot.types[robot.actuated - 1]
    fig = robot_figure(
        f"{robot.architecture} to scale, joint {robot.actuated} ({driven}) driven (black); "
        "arrows: forces at O_k",
        family_extent(robot),
    )
    fig.title.text_font_size = "9pt"
    key = Key(fig)
    key.draw_glyphs(_GLYPHS, sources, present=True)
    present = [q for q in FAMILY_ARROWS if q in sources["arrows"].data["quantity"]]
    arrows = {quantity: FAMILY_ARROWS[quantity] for quantity in present}
    return fig, arrow_layers(fig, key, sources["arrows"], arrows)


def _measures_table(source: Any) -> Any:
    from bokeh.models import DataTable, NumberFormatter, TableColumn

    number = NumberFormatter(format="0.0000")
    return DataTable(
        source=source,
        columns=[
            TableColumn(field="measure", title="measure", width=70),
            TableColumn(field="value", title="value", formatter=number, width=80),
            TableColumn(field="home", title="home sign", formatter=number, width=70),
            TableColumn(field="margin", title="sign·value", formatter=number, width=80),
        ],
        name="measures_table",
        width=330,
        height=130,
        index_position=None,
        reorderable=False,
        autosize_mode="none",
        sortable=False,
        selectable=False,
    )


def _sources(view: View) -> dict[str, Any]:
    from bokeh.models import ColumnDataSource

    return {name: ColumnDataSource(columns, name=name) for name, columns in view.sources().items()}


def family_document(doc: Any, robot: FamilyRobot, run: Run | None = None) -> None:
    """Fill a Bokeh ``Document`` with the live explorer of a family robot (and of a ``run``).

    Every slider or design change solves the pose with
    :func:`prp3.family.family_inverse_dynamics` in Python
    (:func:`~prp3.explorer.family_scene.family_pose_table`) and sends the drawn
    columns that changed (:class:`~prp3.explorer.live.LivePage`); a refused pose
    empties them (the base stays) and shows the library's one-line message.
    With a ``run`` (:func:`~prp3.explorer.run_folder.read_family_run`) the
    scrubber sets the sliders to the run's state at a sample
    (:func:`~prp3.explorer.run_folder.family_run_motion`) and the page recomputes
    it, beside the run's force plots against time.
    """
    from bokeh.layouts import row

    current = {"robot": robot}
    motion = family_run_motion(robot, run) if run is not None else None
    reach = 0.45 * family_extent(robot)

    def limits(control: MotionControl) -> tuple[float, float]:
        return (-reach, reach) if control.length else (control.low, control.high)

    live = LivePage(
        doc,
        limits,
        motion,
        family_design_parameters(robot),
        family_design_values(robot),
        family_arrow_scale(robot),
    )
    first = SCENE.view(robot, SCENE.table(robot, State()), 0, live.scale)
    sources = _sources(first)
    figure_, key = _figure(robot, sources)
    clip_overlays(doc, [figure_])
    values_table = results_table(sources["values"])
    values_table.height = 420
    measures_table = _measures_table(sources["measures"])
    bundle = Bundle(sources, {"message": live.message}, [values_table, measures_table])

    def compute(state: State) -> Changes:
        robot_now = current["robot"]
        return SCENE.view(robot_now, SCENE.table(robot_now, state), 0, live.scale).sources()

    def redesign(values: Mapping[str, float]) -> None:
        current["robot"] = family_design_robot(robot, values)

    live.connect(bundle, compute, lambda state: refused(first), redesign)
    home_leg, home_par = robot.home_measures
    info = (
        f"{robot.architecture}, joint {robot.actuated} driven; legs B, C are leg A turned by "
        f"120°, 240°.  Home measures: μ_leg = {home_leg[0]:.4f}, μ_par = {home_par:.4f}; a "
        "pose is refused when sign·μ < 1e-4 (docs/family.md §6)."
    )
    fields = [*live.design_fields.values(), live.scale_field]
    design = [
        "<b>design</b> (every value of the robot file; forces update live; a value the model "
        "refuses is named in the message)",
        *(row(*fields[k : k + DESIGN_ROW]) for k in range(0, len(fields), DESIGN_ROW)),
    ]
    right = [values_table, measures_table]
    scrubber = None
    if run is not None and motion is not None:
        plots, scrubber = live.run_widgets(run.table, {q: q for q in FAMILY_PLOTTED}, motion)
        right.append(plots)
    title = f"prp3 explore: {robot.architecture}"
    live.start(title, figure_, [key], info, right, design, scrubber)


def family_run_html(robot: FamilyRobot, table: Mapping[str, FloatArray], title: str) -> str:
    """One self-contained HTML page of a family run (the 64 columns of ``results.csv``).

    At most :data:`~prp3.explorer.scrubber.MAX_HTML_FRAMES` frames of
    :func:`~prp3.explorer.family_scene.family_view`, precomputed; the scrubber
    and the play button only pick a frame.  Bokeh's JavaScript is inline: it
    opens offline.
    """
    scale = family_arrow_scale(robot)

    def draw(first: View) -> tuple[dict[str, Any], tuple[Any, Any, Any], list[Any]]:
        sources = _sources(first)
        fig, key = _figure(robot, sources)
        values = results_table(sources["values"])
        values.height = 420
        return sources, (fig, key, fig), [values, _measures_table(sources["measures"])]

    samples = len(table["t"])
    return run_page(
        title,
        table,
        lambda k: SCENE.view(robot, table, k, scale),
        draw,
        {q: q for q in FAMILY_PLOTTED},
        lambda frames: (
            f"<b>{escape(title)}</b>; {frames} frames of {samples} samples; forces by prp3.family"
        ),
        beside=True,
    )
