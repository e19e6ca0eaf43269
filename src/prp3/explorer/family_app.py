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
``message``; in the HTML file of a run the scrubber ``time`` and ``play``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.explorer.family_scene import (
    FAMILY_ARROWS,
    FAMILY_DESIGN_PARAMETERS,
    FamilyScene,
    family_arrow_scale,
    family_design_robot,
    family_design_values,
    family_extent,
)
from prp3.explorer.page import (
    _COPY_FRAME,
    _PLAY,
    _UNBUNDLE,
    MAX_HTML_FRAMES,
    _escape,
    _table,
    arrow_layers,
    slider_with_field,
    time_plots,
)
from prp3.explorer.scene import MOTION_CONTROLS, Columns, State, View, empty_view
from prp3.family import FamilyRobot
from prp3.plotting.animation import frame_indices  # a pure function: matplotlib is not imported

__all__ = ["family_document", "family_run_html"]

FloatArray = NDArray[np.float64]

#: The per-leg quantities of the linked plots of a run.
FAMILY_PLOTTED: tuple[str, ...] = ("tau", "fx1", "fy1", "p")

SCENE = FamilyScene()


def _figure(robot: FamilyRobot, sources: Mapping[str, Any]) -> tuple[Any, Any]:
    """The robot to scale with its force arrows, and its key (a legend and check boxes)."""
    from bokeh.models import Range1d
    from bokeh.plotting import figure

    half = family_extent(robot)
    driven = robot.types[robot.actuated - 1]
    fig = figure(
        name="robot",
        title=f"{robot.architecture} to scale, joint {robot.actuated} ({driven}) driven (black); "
        "arrows: forces at O_k",
        frame_width=470,
        frame_height=470,
        x_range=Range1d(-half, half),
        y_range=Range1d(-half, half),
        x_axis_label="x (m)",
        y_axis_label="y (m)",
        tools="pan,wheel_zoom,reset,save",
        toolbar_location="above",
    )
    fig.title.text_font_size = "9pt"
    key = figure(
        name="key",
        width=560,
        height=120,
        x_range=Range1d(100.0, 101.0),
        y_range=Range1d(100.0, 101.0),
        tools="",
        toolbar_location=None,
        outline_line_color=None,
        min_border=0,
    )
    key.axis.visible = False
    key.grid.visible = False

    def draw(method: str, *fields: str, source: Any, legend: str = "", **style: Any) -> Any:
        from bokeh.models import ColumnDataSource

        renderer = getattr(fig, method)(*fields, source=source, **style)
        data = source.data
        rows = len(next(iter(data.values()), []))
        if "view" in style:
            group = style["view"].filter.group
            rows = sum(1 for q in data["quantity"] if q == group)
        if legend and rows:  # a legend for what this robot has (a 3-RRR has no slides)
            first = {k: list(v[:1]) for k, v in data.items()}
            if "view" in style:
                k = list(data["quantity"]).index(style["view"].filter.group)
                first = {c: list(v[k : k + 1]) for c, v in data.items()}
            style = {k: v for k, v in style.items() if k != "view"}
            getattr(key, method)(
                *fields, source=ColumnDataSource(first), legend_label=legend, **style
            )
        return renderer

    draw(
        "patches",
        "xs",
        "ys",
        source=sources["base"],
        fill_alpha=0.0,
        line_color="#777777",
        line_dash="dotted",
        line_width=1.5,
        legend="base (the joint-1 frames)",
    )
    draw(
        "multi_line",
        "xs",
        "ys",
        source=sources["guides"],
        line_color="#595959",
        line_dash="dashed",
        line_width=1,
        legend="guides of the P joints",
    )
    draw(
        "patches",
        "xs",
        "ys",
        source=sources["platform"],
        fill_color="#bbbbbb",
        fill_alpha=0.6,
        line_color="#222222",
        line_width=2,
        legend="platform (the O_3)",
    )
    draw(
        "multi_line",
        "xs",
        "ys",
        source=sources["links"],
        line_color="colour",
        line_width=3,
        legend="links 1, 2 (legs A, B, C)",
    )
    draw(
        "multi_line",
        "xs",
        "ys",
        source=sources["sliders"],
        line_color="colour",
        line_width=8,
        legend="P joints (slides)",
    )
    draw(
        "scatter",
        "x",
        "y",
        source=sources["revolute"],
        marker="circle",
        size=11,
        fill_color="white",
        line_color="outline",
        line_width=2.5,
        legend="R joints",
    )
    draw(
        "scatter",
        "x",
        "y",
        source=sources["payload"],
        marker="circle",
        size=14,
        fill_color="#444444",
        fill_alpha=0.8,
        legend="payload",
    )
    fig.scatter("x", "y", source=sources["centre"], marker="cross", size=10, color="black")
    present = [q for q in FAMILY_ARROWS if q in sources["arrows"].data["quantity"]]
    arrows = {quantity: FAMILY_ARROWS[quantity] for quantity in present}
    return fig, arrow_layers(fig, key, draw, sources["arrows"], arrows)


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
    )


def _sources(view: View) -> dict[str, Any]:
    from bokeh.models import ColumnDataSource

    return {name: ColumnDataSource(columns, name=name) for name, columns in view.sources().items()}


def family_document(doc: Any, robot: FamilyRobot) -> None:
    """Fill a Bokeh ``Document`` with the live explorer of a family robot.

    Every slider or design change solves the pose with
    :func:`prp3.family.family_inverse_dynamics` in Python
    (:func:`~prp3.explorer.family_scene.family_pose_table`) and replaces the drawn
    columns; a refused pose empties them (the base stays) and shows the
    library's one-line message.
    """
    from bokeh.layouts import column, row
    from bokeh.models import ColumnDataSource, CustomJS, Div, Spinner

    base_robot = robot
    current: dict[str, Any] = {"robot": robot}
    scale = [family_arrow_scale(robot)]
    first = SCENE.view(robot, SCENE.table(robot, State()), 0, scale[0])
    sources = _sources(first)
    message = Div(
        text="", name="message", width=860, styles={"color": "#b00000", "font-weight": "bold"}
    )
    reach = 0.45 * family_extent(robot)
    sliders: dict[str, Any] = {}
    fields: list[Any] = []
    for control in MOTION_CONTROLS:
        low, high = control.low, control.high
        if control.length:
            low, high = -reach, reach
        slider, pair = slider_with_field(control, low, high)
        sliders[control.name] = slider
        fields.append(pair)
    design_fields = {
        key: Spinner(
            title=f"{label} ({unit})",
            value=family_design_values(robot)[key],
            low=0.0,
            step=0.01,
            width=130,
            name=f"design:{key}",
            format="0.[0000]",
        )
        for key, (label, unit) in FAMILY_DESIGN_PARAMETERS.items()
    }
    scale_field = Spinner(
        title="arrow scale (mm/N)",
        value=round(scale[0] * 1e3, 4),
        low=1e-6,
        step=0.1,
        width=120,
        name="arrow_scale",
    )
    figure_, key = _figure(robot, sources)
    values_table = _table(sources["values"])
    values_table.height = 420
    measures_table = _measures_table(sources["measures"])
    shown: dict[str, Columns] = dict(first.sources())
    bundle = ColumnDataSource({}, name="bundle")
    bundle.js_on_change(
        "data",
        CustomJS(
            args={
                "bundle": bundle,
                "targets": {name: sources[name] for name in shown},
                "table": values_table,
                "measures": measures_table,
            },
            code=_UNBUNDLE + "\nif ('measures' in grouped) measures.view.change.emit();",
        ),
    )

    def show(view: View) -> None:
        changed: dict[str, list[Any]] = {}
        for name, columns in view.sources().items():
            if shown.get(name) == columns:
                continue
            shown[name] = columns
            changed.update({f"{name}|{key}": [values] for key, values in columns.items()})
        if changed:
            bundle.data = changed

    def update() -> None:
        doc.hold("combine")
        try:
            state = State.from_controls({name: float(s.value) for name, s in sliders.items()})
            robot_now: FamilyRobot = current["robot"]
            try:
                view = SCENE.view(robot_now, SCENE.table(robot_now, state), 0, scale[0])
            except Prp3Error as error:
                refuse(error)
                return
            show(view)
            message.text = ""
        finally:
            doc.unhold()

    def refuse(error: Prp3Error) -> None:
        blank = empty_view(first)
        show(View({**blank.shapes, "base": shown["base"]}, blank.arrows, blank.table))
        message.text = _escape(str(error))

    def on_slider(attr: str, old: Any, new: Any) -> None:
        update()

    def on_design(attr: str, old: Any, new: Any) -> None:
        values = {k: float(f.value) for k, f in design_fields.items() if f.value is not None}
        try:
            current["robot"] = family_design_robot(base_robot, values)
        except Prp3Error as error:
            refuse(error)
            return
        update()

    def on_scale(attr: str, old: Any, new: Any) -> None:
        if new is not None and float(new) > 0.0:
            scale[0] = float(new) * 1e-3
            update()

    for slider in sliders.values():
        slider.on_change("value", on_slider)
    for field in design_fields.values():
        field.on_change("value", on_design)
    scale_field.on_change("value", on_scale)
    home_leg, home_par = robot.home_measures
    info = Div(
        text=(
            f"{robot.architecture}, joint {robot.actuated} driven; legs B, C are leg A turned by "
            f"120°, 240°.  Home measures: μ_leg = {home_leg[0]:.4f}, μ_par = {home_par:.4f}; a "
            "pose is refused when sign·μ < 1e-4 (docs/family.md §6)."
        ),
        width=500,
        styles={"font-size": "9pt", "color": "#444"},
    )
    controls = column(Div(text="<b>platform pose, velocity, acceleration</b>"), *fields, width=300)
    design = column(
        Div(text="<b>design</b> (masses; forces update live)"),
        row(*design_fields.values(), scale_field),
    )
    layout = column(
        message,
        row(column(figure_, key, info), controls, column(values_table, measures_table)),
        design,
    )
    doc.add_root(layout)
    doc.add_root(bundle)
    doc.title = f"prp3 explore: {robot.architecture}"
    update()


def family_run_html(robot: FamilyRobot, table: Mapping[str, FloatArray], title: str) -> str:
    """One self-contained HTML page of a family run (the 64 columns of ``results.csv``).

    At most :data:`~prp3.explorer.page.MAX_HTML_FRAMES` frames of
    :func:`~prp3.explorer.family_scene.family_view`, precomputed; the scrubber
    and the play button only pick a frame.  Bokeh's JavaScript is inline: it
    opens offline.
    """
    from bokeh.embed import file_html
    from bokeh.layouts import column, row
    from bokeh.models import ColumnDataSource, CustomJS, Div, Slider, Toggle
    from bokeh.resources import INLINE

    t = np.asarray(table["t"], dtype=np.float64)
    frames = frame_indices(int(t.size), MAX_HTML_FRAMES)
    scale = family_arrow_scale(robot)
    views = [SCENE.view(robot, table, int(k), scale) for k in frames]
    sources = _sources(views[0])
    frame_sources = {
        name: ColumnDataSource(
            {c: [view.sources()[name][c] for view in views] for c in views[0].sources()[name]},
            name=f"frames:{name}",
        )
        for name in views[0].sources()
    }
    fig, key = _figure(robot, sources)
    plots, spans = time_plots(table, {q: q for q in FAMILY_PLOTTED})
    times = [float(v) for v in t[frames]]
    slider = Slider(
        start=0,
        end=max(len(frames) - 1, 1),
        value=0,
        step=1,
        name="time",
        title=f"t = {times[0]:.3f} s",
        width=400,
        show_value=False,
    )
    play = Toggle(label="▶ play", name="play", width=90)
    table_widget = _table(sources["values"])
    table_widget.height = 420
    measures = _measures_table(sources["measures"])
    period = max(30, int(1000 * float(t[-1] - t[0]) / max(len(frames) - 1, 1)))
    slider.js_on_change(
        "value",
        CustomJS(
            args={
                "slider": slider,
                "sources": frame_sources,
                "targets": sources,
                "table": table_widget,
                "measures": measures,
                "spans": spans,
                "times": times,
            },
            code=_COPY_FRAME + "\nmeasures.view.change.emit();",
        ),
    )
    play.js_on_change(
        "active", CustomJS(args={"toggle": play, "slider": slider, "period": period}, code=_PLAY)
    )
    heading = Div(
        text=f"<b>{_escape(title)}</b>; {len(frames)} frames of {t.size} samples; "
        "forces by prp3.family",
        width=900,
    )
    layout = column(
        heading,
        row(slider, play),
        row(column(fig, key), column(table_widget, measures), column(*plots)),
    )
    return str(file_html(layout, resources=INLINE, title=title))
