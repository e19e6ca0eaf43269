"""The 3-PRP page of the explorer: its figures and the live Bokeh document of ``prp3 explore``.

Bokeh is imported inside the functions only.  Every number drawn comes from
:mod:`prp3.explorer.scene` (prp3's own engines): the server recomputes a
pose in Python at every slider move, and sends every drawn source that
changed in one message.  The server itself is :mod:`prp3.explorer.server`,
the HTML file of a run :mod:`prp3.explorer.html_file`.

Names of the page's models (``Bokeh.documents[0].get_model_by_name``), for
tests and scripts: the sliders ``x, y, phi, dx, dy, dphi, ddx, ddy, ddphi``
(and a spinner ``<name>_field`` each), the design fields ``design:<key>``, the
sources ``arrows``, ``values`` (the table), ``platform``, ``joints``,
``pistons``, ``sleeves``, ``base``, ``payload``, ``overlay``, the message
``message``, the key ``key`` (a ``Div``), the check boxes ``arrow_toggles`` and
the filter of the arrows' rows ``arrow_filter``, and with a run the scrubber
``time`` and the button ``play``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.explorer.page import (
    _UNBUNDLE,
    Key,
    _escape,
    _table,
    arrow_layers,
    server_scrubber,
    slider_with_field,
    time_plots,
)
from prp3.explorer.run_folder import Run, run_motion
from prp3.explorer.scene import (
    ARROWS,
    DESIGN_PARAMETERS,
    MOTION_CONTROLS,
    PRP3_SCENE,
    Columns,
    Scene,
    State,
    View,
    arrow_scale,
    design_robot,
    design_values,
    empty_view,
    singularity_curve,
    stroke_bands,
    workspace_overlay,
)
from prp3.model.motion import Motion
from prp3.model.robot import Robot

__all__ = ["PLOTTED", "explorer_document", "require_bokeh", "set_state", "widened"]

FloatArray = NDArray[np.float64]

#: The per-leg quantities of the linked plots against time.
PLOTTED: tuple[str, ...] = ("f10", "f21y", "f21z", "n32")


def require_bokeh(what: str = "prp3 explore") -> None:
    """Refuse, in one line, when Bokeh is not installed."""
    try:
        import bokeh  # noqa: F401
    except ImportError:
        raise Prp3Error(
            f"{what} needs Bokeh, which is not installed: pip install 'prp3[explore]'"
        ) from None


# ---------------------------------------------------------------- figures
def _limits(robot: Robot) -> float:
    return 1.3 * robot.l0


def _robot_figure(
    robot: Robot, sources: Mapping[str, Any], overlay: bool, peak: float = 1.0
) -> tuple[Any, Any]:
    """The robot to scale, its stroke bands, the force arrows and (optionally) the statics map.

    Returns the figure (with the map, in a row with its colour bar) and, to put below it, its
    key (:class:`~prp3.explorer.page.Key`, HTML) and the check boxes that show or hide the
    arrows of each quantity.
    """
    from bokeh.layouts import row
    from bokeh.models import ColorBar, LinearColorMapper, Range1d
    from bokeh.plotting import figure

    half = _limits(robot)
    fig = figure(
        name="robot",
        title="3-PRP robot to scale; arrows: joint forces at P_i",
        frame_width=470,
        frame_height=470,
        x_range=Range1d(-half, half),
        y_range=Range1d(-half, half),
        x_axis_label="x (m)",
        y_axis_label="y (m)",
        tools="pan,wheel_zoom,reset,save",
        toolbar_location="above",
    )
    key = Key(fig)
    draw = key.draw

    bar: Any = None
    if overlay:
        mapper = LinearColorMapper(palette="Viridis256", low=0.0, high=peak, nan_color=(0, 0, 0, 0))
        mapper.name = "overlay_colours"
        image = fig.image(
            image="image",
            x="x",
            y="y",
            dw="dw",
            dh="dh",
            source=sources["overlay"],
            color_mapper=mapper,
            alpha=0.45,
            level="image",
        )
        image.name = "overlay_image"
        draw(
            "patches",
            "xs",
            "ys",
            source=sources["region"],
            fill_alpha=0.0,
            line_color="#444444",
            line_dash="dotted",
            line_width=1.5,
            legend="reachable region (strokes)",
        )
        # the colour bar in a figure of its own, beside: painted when the map changes, not at
        # every move of the robot (a colour bar is an axis, ticks and labels to measure)
        bar = figure(
            name="colour_bar",
            width=75,
            height=545,
            frame_width=1,
            min_border_top=31,
            min_border_bottom=44,
            min_border_left=0,
            x_range=Range1d(0.0, 1.0),
            y_range=Range1d(0.0, 1.0),
            tools="",
            toolbar_location=None,
            outline_line_color=None,
        )
        bar.axis.visible = False
        bar.grid.visible = False
        bar.scatter([], [])  # a renderer, drawing nothing (a figure without one is a warning)
        bar.add_layout(
            ColorBar(
                color_mapper=mapper,
                title="statics: max |f10| at rest (N)",
                width=10,
                title_text_font_size="9pt",
            ),
            "right",
        )
    draw(
        "patches",
        "xs",
        "ys",
        source=sources["base"],
        fill_color="#dddddd",
        fill_alpha=0.5,
        line_color="#555555",
        line_width=2,
        legend="base (guides)",
    )
    draw(
        "multi_line",
        "xs",
        "ys",
        source=sources["strokes"],
        line_color="colour",
        line_width=9,
        line_alpha=0.25,
        legend="strokes",
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
        legend="platform",
    )
    draw(
        "multi_line",
        "xs",
        "ys",
        source=sources["pistons"],
        line_color="colour",
        line_width=7,
        legend="pistons (legs A, B, C)",
    )
    draw(
        "multi_line",
        "xs",
        "ys",
        source=sources["sleeves"],
        line_color="colour",
        line_width=4,
        line_dash="dashed",
        legend="links 2 (sleeves)",
    )
    fig.scatter("x", "y", source=sources["joints"], color="colour", size=9, line_color="black")
    draw(
        "scatter",
        "x",
        "y",
        source=sources["payload"],
        marker="circle",
        size=16,
        fill_color="#444444",
        fill_alpha=0.8,
        legend="payload",
    )
    fig.scatter("x", "y", source=sources["centre"], marker="cross", size=10, color="black")
    key_and_toggles = arrow_layers(fig, key, sources["arrows"], ARROWS)
    return (fig if bar is None else row(fig, bar)), key_and_toggles


def _singularity_figure(phi_range: tuple[float, float], scene: Scene) -> tuple[Any, Any]:
    from bokeh.models import ColumnDataSource, Span
    from bokeh.plotting import figure

    curve = singularity_curve(phi_range)
    fig = figure(
        title="sin(φ − π/3): singular at the red lines",
        width=330,
        height=170,
        x_axis_label="φ (rad)",
        tools="",
        toolbar_location=None,
    )
    fig.title.text_font_size = "9pt"
    fig.line(curve["phi"], list(scene.singularity(np.array(curve["phi"]))), color="#333333")
    for k in range(-2, 3):
        phi = math.pi / 3.0 + k * math.pi
        if phi_range[0] <= phi <= phi_range[1]:
            fig.add_layout(
                Span(
                    location=phi,
                    dimension="height",
                    line_color="red",
                    line_dash="dashed",
                    line_width=2,
                )
            )
    marker = ColumnDataSource(
        {"phi": [0.0], "measure": [float(scene.singularity(np.zeros(())))]},
        name="singularity_marker",
    )
    fig.scatter("phi", "measure", source=marker, size=10, color="#d62728")
    return fig, marker


def _empty_overlay() -> dict[str, Columns]:
    """The columns of the statics map when none is shown."""
    return {
        "image": {"image": [], "x": [], "y": [], "dw": [], "dh": []},
        "region": {"xs": [], "ys": []},
    }


def _sources(view: View, overlay: Mapping[str, Columns] | None, strokes: Columns) -> dict[str, Any]:
    from bokeh.models import ColumnDataSource

    sources: dict[str, Any] = {
        name: ColumnDataSource(columns, name=name) for name, columns in view.sources().items()
    }
    sources["strokes"] = ColumnDataSource(strokes, name="strokes")
    for name, columns in (overlay or _empty_overlay()).items():
        sources["overlay" if name == "image" else name] = ColumnDataSource(
            columns, name="overlay" if name == "image" else name
        )
    return sources


# ---------------------------------------------------------------- the server's document
def explorer_document(
    doc: Any, robot: Robot, run: Run | None = None, scene: Scene = PRP3_SCENE
) -> None:
    """Fill a Bokeh ``Document`` with the live explorer of ``robot`` (and of a ``run``).

    Every change of a slider, field or design parameter recomputes the pose
    with prp3's engines in Python (:meth:`Scene.table`, :meth:`Scene.view`) and
    replaces the columns of the drawn sources; a refused pose empties them and
    shows the library's one-line message.
    """
    from bokeh.layouts import column, row
    from bokeh.models import Checkbox, ColumnDataSource, CustomJS, Div, Spinner

    base_robot = robot
    current: dict[str, Any] = {"robot": robot, "load": None, "busy": False, "served": False}
    motion = run_motion(robot, run) if run is not None else None
    scale = [arrow_scale(robot)]
    first = scene.view(robot, scene.table(robot, State()), 0, scale[0])
    try:
        overlay0: dict[str, Columns] | None = workspace_overlay(robot, 0.0)
    except Prp3Error:
        overlay0 = None
    sources = _sources(first, overlay0, stroke_bands(robot))
    message = Div(
        text="", name="message", width=860, styles={"color": "#b00000", "font-weight": "bold"}
    )

    sliders: dict[str, Any] = {}
    fields: list[Any] = []
    for control in MOTION_CONTROLS:
        low, high = control.low, control.high
        if control.length:
            low, high = low * robot.l0, high * robot.l0
        if motion is not None:
            low, high = widened(low, high, motion, control.name)
        slider, pair = slider_with_field(control, low, high)
        sliders[control.name] = slider
        fields.append(pair)
    design_fields: dict[str, Any] = {}
    for key, (label, unit) in DESIGN_PARAMETERS.items():
        design_fields[key] = Spinner(
            title=f"{label} ({unit})",
            value=design_values(robot)[key],
            low=0.0,
            step=0.01,
            width=130,
            name=f"design:{key}",
            format="0.[0000]",
        )
    scale_field = Spinner(
        title="arrow scale (mm/N)",
        value=round(scale[0] * 1e3, 4),
        low=1e-6,
        step=0.1,
        width=120,
        name="arrow_scale",
    )
    overlay_box = Checkbox(
        label="statics map of the workspace at φ",
        active=overlay0 is not None,
        name="overlay_toggle",
    )
    singularity, marker = _singularity_figure((sliders["phi"].start, sliders["phi"].end), scene)
    peak0 = float(np.nanmax(overlay0["image"]["image"][0])) if overlay0 is not None else 1.0
    figure_, key = _robot_figure(robot, sources, overlay=True, peak=peak0 if peak0 > 0 else 1.0)
    overlay_phi: list[float | None] = [0.0 if overlay0 is not None else None]

    shown: dict[str, Columns] = dict(first.sources())
    values_table = _table(sources["values"])
    # every drawn source of an update travels in one message: one row of the bundle holds
    # each changed source's columns, which _UNBUNDLE copies into it in the browser (one
    # message and one repaint instead of one per source)
    bundle = ColumnDataSource({}, name="bundle")
    bundle.js_on_change(
        "data",
        CustomJS(
            args={
                "bundle": bundle,
                "targets": {name: sources[name] for name in shown},
                "table": values_table,
            },
            code=_UNBUNDLE,
        ),
    )

    def show(view: View) -> None:
        changed: dict[str, list[Any]] = {}
        for name, columns in view.sources().items():
            if shown.get(name) == columns:  # only what changed goes to the browser
                continue
            shown[name] = columns
            if not current["served"]:  # the browser has not the document yet: its sources
                sources[name].data = columns
                continue
            changed.update({f"{name}|{key}": [values] for key, values in columns.items()})
        if changed:
            bundle.data = changed

    def refresh_overlay(phi: float, robot_now: Robot) -> None:
        if not overlay_box.active:
            sources["overlay"].data = _empty_overlay()["image"]
            sources["region"].data = _empty_overlay()["region"]
            overlay_phi[0] = None
            return
        if overlay_phi[0] == phi:
            return
        try:
            layers = workspace_overlay(robot_now, phi)
        except Prp3Error:  # a singular φ: the message says it; no map
            layers = _empty_overlay()
        sources["overlay"].data = layers["image"]
        sources["region"].data = layers["region"]
        if layers["image"]["image"]:
            peak = float(np.nanmax(layers["image"]["image"][0]))
            figure_.select_one({"name": "overlay_colours"}).high = peak if peak > 0 else 1.0
        overlay_phi[0] = phi

    def update() -> None:
        if current["busy"]:
            return
        doc.hold("combine")  # every change of this update reaches the browser in one message
        try:
            _update()
        finally:
            doc.unhold()

    def _update() -> None:
        values = {name: float(slider.value) for name, slider in sliders.items()}
        base_state = State.from_controls(values)
        state = State(
            base_state.pose, base_state.velocity, base_state.acceleration, current["load"]
        )
        if marker.data["phi"] != [state.pose[2]]:
            measure = float(scene.singularity(np.array(state.pose[2])))
            marker.data = {"phi": [state.pose[2]], "measure": [measure]}
        robot_now: Robot = current["robot"]
        try:
            table = scene.table(robot_now, state)
            view = scene.view(robot_now, table, 0, scale[0])
        except Prp3Error as error:
            refuse(error)
            return
        show(view)
        message.text = ""
        refresh_overlay(state.pose[2], robot_now)

    def refuse(error: Prp3Error) -> None:
        """Draw nothing that belongs to the refused pose (the base stays), and say why."""
        blank = empty_view(first)
        show(View({**blank.shapes, "base": shown["base"]}, blank.arrows, blank.table))
        sources["overlay"].data = _empty_overlay()["image"]
        sources["region"].data = _empty_overlay()["region"]
        overlay_phi[0] = None
        message.text = _escape(str(error))

    def on_slider(attr: str, old: Any, new: Any) -> None:
        update()

    def on_design(attr: str, old: Any, new: Any) -> None:
        values = {
            key: float(field.value)
            for key, field in design_fields.items()
            if field.value is not None
        }
        try:
            robot_now = design_robot(base_robot, values)
        except Prp3Error as error:
            refuse(error)
            return
        current["robot"] = robot_now
        sources["strokes"].data = stroke_bands(robot_now)
        overlay_phi[0] = None
        update()

    def on_scale(attr: str, old: Any, new: Any) -> None:
        if new is not None and float(new) > 0.0:
            scale[0] = float(new) * 1e-3
            update()

    def on_overlay(attr: str, old: Any, new: Any) -> None:
        overlay_phi[0] = None
        update()

    for slider in sliders.values():
        slider.on_change("value", on_slider)
    for field in design_fields.values():
        field.on_change("value", on_design)
    scale_field.on_change("value", on_scale)
    overlay_box.on_change("active", on_overlay)

    stroke = robot.limits.stroke
    info = Div(
        text=(
            f"l0 = {robot.l0:g} m; strokes: "
            + (f"[{stroke[0]:g}, {stroke[1]:g}] m (bands on the guides)" if stroke else "none")
            + "; singular at φ = π/3 mod π.  The check boxes show or hide the arrows."
        ),
        width=500,
        styles={"font-size": "9pt", "color": "#444"},
    )
    controls = column(Div(text="<b>platform pose, velocity, acceleration</b>"), *fields, width=300)
    design = column(
        Div(text="<b>design</b> (the robot's parameters; forces update live)"),
        row(*list(design_fields.values())[:5], scale_field),
        row(*list(design_fields.values())[5:9]),
        row(*list(design_fields.values())[9:]),
        overlay_box,
    )
    right = [values_table, singularity]
    top: list[Any] = [message]
    if run is not None and motion is not None:
        right_extra, time_widgets = _run_widgets(doc, motion, sliders, current, update, run.table)
        right.extend(right_extra)
        top.insert(0, time_widgets)
    layout = column(
        *top,
        row(column(figure_, key, info), controls, column(*right)),
        design,
    )
    doc.add_root(layout)
    doc.add_root(bundle)  # drawn by nothing: a root, so that it reaches the browser
    doc.title = "prp3 explore"
    update()
    for pair in fields:  # a slider set before the page is served: its field shows its value
        slider_now, field_now = pair.children
        field_now.value = slider_now.value
    current["served"] = True  # from now on, every change reaches the browser in the bundle


def _run_widgets(
    doc: Any,
    motion: Motion,
    sliders: Mapping[str, Any],
    current: dict[str, Any],
    update: Callable[[], None],
    table: Mapping[str, Any],
) -> tuple[list[Any], Any]:
    """The scrubber, the play button and the linked plots of a run (server side)."""
    from bokeh.layouts import column

    plots, spans = time_plots(table, {q: f"{q} (N)" for q in PLOTTED})

    def show(k: int) -> None:
        current["load"] = None if motion.load is None else tuple(float(v) for v in motion.load[k])
        set_state(sliders, current, motion, k)
        update()

    scrubber = server_scrubber(doc, [float(v) for v in motion.t], show, spans)
    return [column(*plots)], scrubber


def widened(low: float, high: float, motion: Motion, name: str) -> tuple[float, float]:
    """A motion slider's range ``[low, high]`` widened to the run's values of its control."""
    values = np.concatenate([motion.pose, motion.velocity, motion.acceleration], axis=-1)
    k = [c.name for c in MOTION_CONTROLS].index(name)
    return min(low, float(values[:, k].min())), max(high, float(values[:, k].max()))


def set_state(sliders: Mapping[str, Any], current: dict[str, Any], motion: Motion, k: int) -> None:
    """Set the nine motion sliders to sample ``k`` of ``motion``, without an update per slider."""
    values = np.concatenate([motion.pose[k], motion.velocity[k], motion.acceleration[k]])
    current["busy"] = True
    try:
        for name, value in zip(sliders, values, strict=True):
            sliders[name].value = float(value)
    finally:
        current["busy"] = False
