"""The explorer's Bokeh documents: the live app of ``prp3 explore`` and the HTML file of a run.

Bokeh is imported inside the functions only.  Every number drawn comes from
:mod:`prp3.explorer.scene` (prp3's own engines): the server recomputes a
pose in Python at every slider move; the standalone HTML file holds the
frames of a run precomputed, and its few lines of ``CustomJS`` only copy
frame ``k``'s columns into the drawn sources (no force is computed in the
browser).

Names of the page's models (``Bokeh.documents[0].get_model_by_name``), for
tests and scripts: the sliders ``x, y, phi, dx, dy, dphi, ddx, ddy, ddphi``
(and a spinner ``<name>_field`` each), the design fields ``design:<key>``, the
sources ``arrows``, ``values`` (the table), ``platform``, ``joints``,
``pistons``, ``sleeves``, ``base``, ``payload``, ``overlay``, the message
``message``, and with a run the scrubber ``time`` and the button ``play``.
"""

from __future__ import annotations

import contextlib
import errno
import math
import signal
import socket
import webbrowser
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
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
from prp3.explorer.scene import (
    ARROWS,
    DESIGN_PARAMETERS,
    MOTION_CONTROLS,
    PRP3_SCENE,
    Columns,
    Run,
    Scene,
    State,
    View,
    arrow_scale,
    design_robot,
    design_values,
    empty_view,
    run_motion,
    singularity_curve,
    stroke_bands,
    workspace_overlay,
)
from prp3.family import FamilyRobot
from prp3.files import atomic_writer
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.plotting.animation import frame_indices  # a pure function: matplotlib is not imported

__all__ = [
    "DEFAULT_HOST",
    "DEFAULT_PORT",
    "MAX_HTML_FRAMES",
    "explorer_document",
    "require_bokeh",
    "run_html",
    "serve",
    "write_run_html",
]

FloatArray = NDArray[np.float64]

DEFAULT_HOST: str = "127.0.0.1"
DEFAULT_PORT: int = 8765

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

    Returns the figure and, to put below it, its key: a legend drawn in a figure of its own
    (painted once, not at every update of the robot's figure) and check boxes that show or
    hide the arrows of each quantity.
    """
    from bokeh.models import (
        ColorBar,
        ColumnDataSource,
        LinearColorMapper,
        Range1d,
    )
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
    key = figure(
        name="key",
        width=560,
        height=160,
        x_range=Range1d(100.0, 101.0),  # the key's glyphs lie outside: only the legend shows
        y_range=Range1d(100.0, 101.0),
        tools="",
        toolbar_location=None,
        outline_line_color=None,
        min_border=0,
    )
    key.axis.visible = False
    key.grid.visible = False

    def draw(method: str, *fields: str, source: Any, legend: str = "", **style: Any) -> Any:
        """Draw on the robot's figure; the same glyph, one row of it, in the key."""
        renderer = getattr(fig, method)(*fields, source=source, **style)
        if legend:
            data = source.data
            rows = len(next(iter(data.values()), []))
            first = {k: list(v[:1]) for k, v in data.items()} if rows else {k: [] for k in data}
            style = {k: v for k, v in style.items() if k != "view"}
            getattr(key, method)(
                *fields, source=ColumnDataSource(first), legend_label=legend, **style
            )
        return renderer

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
        fig.add_layout(
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
    return fig, arrow_layers(fig, key, draw, sources["arrows"], ARROWS)


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
    current: dict[str, Any] = {"robot": robot, "load": None, "busy": False, "timer": None}
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
            values = np.concatenate([motion.pose, motion.velocity, motion.acceleration], axis=-1)
            k = [c.name for c in MOTION_CONTROLS].index(control.name)
            low, high = min(low, float(values[:, k].min())), max(high, float(values[:, k].max()))
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
        right_extra, time_widgets = _run_widgets(doc, run, motion, sliders, current, update)
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


def _run_widgets(
    doc: Any,
    run: Run,
    motion: Motion,
    sliders: Mapping[str, Any],
    current: dict[str, Any],
    update: Callable[[], None],
) -> tuple[list[Any], Any]:
    """The scrubber, the play button and the linked plots of a run (server side)."""
    from bokeh.layouts import column, row
    from bokeh.models import Slider, Toggle

    t = motion.t
    samples = int(t.size)
    scrubber = Slider(
        start=0,
        end=max(samples - 1, 1),
        value=0,
        step=1,
        name="time",
        title=f"t = {float(t[0]):.3f} s",
        width=500,
        show_value=False,
    )
    play = Toggle(label="▶ play", name="play", width=90)
    plots, spans = time_plots(run.table, {q: f"{q} (N)" for q in PLOTTED})
    period = max(40, int(1000 * float(t[-1] - t[0]) / max(samples - 1, 1)))
    stride = max(1, round(40 / (1000 * float(t[-1] - t[0]) / max(samples - 1, 1))))

    def to_sample(k: int) -> None:
        k = min(max(int(k), 0), samples - 1)
        state_values = np.concatenate([motion.pose[k], motion.velocity[k], motion.acceleration[k]])
        current["busy"] = True
        try:
            for control_name, value in zip(sliders, state_values, strict=True):
                sliders[control_name].value = float(value)
        finally:
            current["busy"] = False
        current["load"] = None if motion.load is None else tuple(float(v) for v in motion.load[k])
        for span in spans:
            span.location = float(t[k])
        scrubber.title = f"t = {float(t[k]):.3f} s"
        update()

    def on_scrub(attr: str, old: Any, new: Any) -> None:
        to_sample(int(new))

    def step() -> None:
        following = int(scrubber.value) + stride
        scrubber.value = following if following < samples else 0

    def on_play(attr: str, old: Any, new: Any) -> None:
        if new:
            play.label = "❚❚ pause"
            current["timer"] = doc.add_periodic_callback(step, period)
        else:
            play.label = "▶ play"
            if current["timer"] is not None:
                doc.remove_periodic_callback(current["timer"])
                current["timer"] = None

    scrubber.on_change("value", on_scrub)
    play.on_change("active", on_play)
    doc.add_next_tick_callback(lambda: to_sample(0))
    return [column(*plots)], row(scrubber, play)


# ---------------------------------------------------------------- the HTML file of a run
def run_html(robot: Robot | FamilyRobot, table: Mapping[str, FloatArray], title: str) -> str:
    """One self-contained HTML page of a run: the robot with its force arrows, and linked plots.

    Parameters
    ----------
    robot : Robot or FamilyRobot
        The robot of the run; a family robot's page is
        :func:`prp3.explorer.family_app.family_run_html`.
    table : mapping of str to ndarray (N,)
        The run's columns of ``results.csv`` (``prp3 simulate``'s table; the
        64 of the family form for a family robot).
    title : str
        The page's title.

    Returns
    -------
    str
        The page, with Bokeh's JavaScript inline (``bokeh.resources.INLINE``): it
        opens offline.  At most :data:`MAX_HTML_FRAMES` frames, precomputed by
        :func:`prp3.explorer.scene.scene_view`; the scrubber and the play button
        only pick a frame.
    """
    from bokeh.embed import file_html
    from bokeh.layouts import column, row
    from bokeh.models import ColumnDataSource, CustomJS, Div, Slider, Toggle
    from bokeh.resources import INLINE

    if isinstance(robot, FamilyRobot):
        from prp3.explorer.family_app import family_run_html

        return family_run_html(robot, table, title)
    t = np.asarray(table["t"], dtype=np.float64)
    frames = frame_indices(int(t.size), MAX_HTML_FRAMES)
    scale = arrow_scale(robot)
    views = [PRP3_SCENE.view(robot, table, int(k), scale) for k in frames]
    sources = _sources(views[0], None, stroke_bands(robot))
    frame_sources: dict[str, Any] = {}
    targets: dict[str, Any] = {}
    for name in views[0].sources():
        columns = list(views[0].sources()[name])
        frame_sources[name] = ColumnDataSource(
            {c: [view.sources()[name][c] for view in views] for c in columns},
            name=f"frames:{name}",
        )
        targets[name] = sources[name]
    fig, key = _robot_figure(robot, sources, overlay=False)
    plots, spans = time_plots(table, {q: f"{q} (N)" for q in PLOTTED})
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
    duration = float(t[-1] - t[0])
    period = max(30, int(1000 * duration / max(len(frames) - 1, 1)))
    slider.js_on_change(
        "value",
        CustomJS(
            args={
                "slider": slider,
                "sources": frame_sources,
                "targets": targets,
                "table": table_widget,
                "spans": spans,
                "times": times,
            },
            code=_COPY_FRAME,
        ),
    )
    play.js_on_change(
        "active", CustomJS(args={"toggle": play, "slider": slider, "period": period}, code=_PLAY)
    )
    heading = Div(
        text=f"<b>{_escape(title)}</b>: {t.size} samples over t = {t[0]:g} .. {t[-1]:g} s, "
        f"{len(frames)} frames; forces by prp3 (the kernel, eqs. 10-25)",
        width=900,
    )
    layout = column(heading, row(slider, play), row(column(fig, key), column(table_widget, *plots)))
    return str(file_html(layout, resources=INLINE, title=title))


def write_run_html(
    path: str | Path, robot: Robot | FamilyRobot, table: Mapping[str, FloatArray], title: str
) -> None:
    """Write :func:`run_html` to ``path`` atomically (whole or not at all)."""
    page = run_html(robot, table, title)
    with atomic_writer(path) as stream:
        stream.write(page)


# ---------------------------------------------------------------- the server
def _listen_error(host: str, port: int, error: OSError) -> Prp3Error:
    if error.errno == errno.EADDRINUSE:
        return Prp3Error(
            f"port {port} on {host} is busy (another program listens there): "
            "choose another with --port",
            origin=f"--port {port}",
        )
    return Prp3Error(
        f"cannot listen on {host}:{port}: {error.strerror or error}", origin=f"--host {host}"
    )


def _no_delay() -> None:
    """Send the server's websocket messages at once (``TCP_NODELAY``), in this process.

    Bokeh's websocket handler leaves Nagle's algorithm on: a small message
    (the columns of one update) then waits for the browser's delayed
    acknowledgement, about 40 ms on loopback, at every slider move
    (``benchmarks/bench_explore.py`` measures the difference).
    """
    from bokeh.server.views.ws import WSHandler

    if getattr(WSHandler, "_prp3_no_delay", False):
        return
    opened = WSHandler.open

    def open_without_delay(self: Any) -> None:
        self.set_nodelay(True)
        opened(self)

    WSHandler.open = open_without_delay
    WSHandler._prp3_no_delay = True


def _check_port(host: str, port: int) -> None:
    """Refuse a port that is taken or an address this machine cannot listen on (one line)."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except OSError as error:
        raise Prp3Error(
            f"cannot listen on {host}:{port}: {error.strerror or error}", origin=f"--host {host}"
        ) from None
    for family, kind, protocol, _, address in infos:
        with socket.socket(family, kind, protocol) as probe:
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as the server does
            try:
                probe.bind(address)
            except OSError as error:
                raise _listen_error(host, port, error) from None


def serve(
    robot: Robot | FamilyRobot,
    run: Run | None = None,
    *,
    host: str = DEFAULT_HOST,
    port: int = DEFAULT_PORT,
    open_browser: bool = True,
    announce: Callable[[str], None] = print,
) -> None:
    """Serve the explorer at ``http://host:port/`` until interrupted.

    A :class:`~prp3.family.FamilyRobot` is served by
    :func:`prp3.explorer.family_app.family_document` (no ``run``: the page of
    a pose).

    Raises
    ------
    Prp3Error
        The port is busy, or the address cannot be listened on (one line naming it);
        a run given with a family robot.
    """
    from bokeh.application import Application
    from bokeh.application.handlers.function import FunctionHandler
    from bokeh.server.server import Server

    if isinstance(robot, FamilyRobot):
        if run is not None:
            raise Prp3Error(
                f"--results with the {robot.architecture} of a family-form robot file is not "
                "supported yet (its page explores poses; prp3 simulate --html writes its runs)",
                key="--results",
            )
        family_robot = robot

        def make(doc: Any) -> None:
            from prp3.explorer.family_app import family_document

            family_document(doc, family_robot)

    else:
        plain_robot = robot
        if run is not None:
            run_motion(plain_robot, run)  # refused before the server starts

        def make(doc: Any) -> None:
            explorer_document(doc, plain_robot, run)

    _check_port(host, port)
    _no_delay()
    origins = [f"{host}:{port}", f"localhost:{port}", f"127.0.0.1:{port}"]
    try:
        server = Server(
            {"/": Application(FunctionHandler(make))},
            address=host,
            port=port,
            allow_websocket_origin=origins,
            num_procs=1,
        )
    except OSError as error:  # taken between the check and the server's own bind
        raise _listen_error(host, port, error) from None
    url = f"http://{host}:{port}/"
    server.start()
    announce(url)
    if open_browser:
        server.io_loop.add_callback(lambda: webbrowser.open(url))
    received = _stop_on_signals(server.io_loop.asyncio_loop)
    try:
        server.io_loop.start()
    finally:
        server.stop()
        _raise_received(server.io_loop.asyncio_loop, received)


#: The signals that stop the server (the command line turns them into 130 and 143).
_STOP_SIGNALS: tuple[signal.Signals, ...] = (signal.SIGINT, signal.SIGTERM)


def _stop_on_signals(loop: Any) -> list[int]:
    """Stop ``loop`` at SIGINT or SIGTERM, between two callbacks; return the signals received.

    A Python signal handler that raises would raise inside whichever callback
    of the server runs at that moment, and asyncio logs and drops the
    exception of a callback: the server would go on.  The loop's own handlers
    run between callbacks; :func:`_raise_received` then hands the signal to
    the previous handler (the command line's), once the loop has stopped.
    """
    received: list[int] = []

    def stop(number: int) -> None:
        received.append(number)
        loop.stop()

    for number in _STOP_SIGNALS:
        try:
            loop.add_signal_handler(number, stop, int(number))
        except (NotImplementedError, RuntimeError, ValueError):  # not the main thread
            break
    return received


def _raise_received(loop: Any, received: list[int]) -> None:
    for number in _STOP_SIGNALS:
        with contextlib.suppress(NotImplementedError, RuntimeError, ValueError):
            loop.remove_signal_handler(number)
    if received:
        signal.raise_signal(received[0])
