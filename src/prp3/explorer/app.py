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
from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np

from prp3.errors import Prp3Error
from prp3.explorer.live import Bundle, Changes, LivePage, refused
from prp3.explorer.page import (
    LEVEL,
    Glyph,
    Key,
    arrow_layers,
    clip_overlays,
    results_table,
    robot_figure,
)
from prp3.explorer.run_folder import Run, run_motion
from prp3.explorer.scene import (
    ARROWS,
    DESIGN_PARAMETERS,
    PRP3_SCENE,
    Columns,
    MotionControl,
    Scene,
    State,
    View,
    arrow_scale,
    design_robot,
    design_values,
    singularity_curve,
    stroke_bands,
    workspace_overlay,
)
from prp3.model.robot import Robot
from prp3.moved_paths import moved_attribute

__all__ = ["PLOTTED", "explorer_document", "require_bokeh"]

#: The per-leg quantities of the linked plots against time.
PLOTTED: tuple[str, ...] = ("f10", "f21y", "f21z", "n32")

#: Design fields per row of the page.
DESIGN_ROW = 7


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


class RobotFigure(NamedTuple):
    """The robot's figure of a page (:func:`build_robot_figure`)."""

    #: The figure (with the map, in a row with its colour bar).
    layout: Any
    #: To put below it: its key (:class:`~prp3.explorer.page.Key`, HTML) and the check boxes
    #: that show or hide the arrows of each quantity.
    key: Any
    #: The figure itself.
    plot: Any
    #: The map's colour mapper (``None`` without the map).
    colours: Any


#: The statics map's reachable region, drawn first (under the robot) with the map.
_REGION: Glyph = (
    "patches",
    "region",
    "reachable region (strokes)",
    {"fill_alpha": 0.0, "line_color": "#444444", "line_dash": "dotted", "line_width": 1.5},
)

#: The 3-PRP's glyphs, in drawing order (the arrows follow them).
_GLYPHS: tuple[Glyph, ...] = (
    (
        "patches",
        "base",
        "base (guides)",
        {"fill_color": "#dddddd", "fill_alpha": 0.5, "line_color": "#555555", "line_width": 2},
    ),
    (
        "multi_line",
        "strokes",
        "strokes",
        {"line_color": "colour", "line_width": 9, "line_alpha": 0.25},
    ),
    (
        "patches",
        "platform",
        "platform",
        {"fill_color": "#bbbbbb", "fill_alpha": 0.6, "line_color": "#222222", "line_width": 2},
    ),
    ("multi_line", "pistons", "pistons (legs A, B, C)", {"line_color": "colour", "line_width": 7}),
    (
        "multi_line",
        "sleeves",
        "links 2 (sleeves)",
        {"line_color": "colour", "line_width": 4, "line_dash": "dashed"},
    ),
    ("scatter", "joints", "", {"color": "colour", "size": 9, "line_color": "black"}),
    (
        "scatter",
        "payload",
        "payload",
        {"marker": "circle", "size": 16, "fill_color": "#444444", "fill_alpha": 0.8},
    ),
    ("scatter", "centre", "", {"marker": "cross", "size": 10, "color": "black"}),
)


def build_robot_figure(
    robot: Robot, sources: Mapping[str, Any], overlay: bool, peak: float = 1.0
) -> RobotFigure:
    """The robot to scale, its stroke bands, the force arrows and (optionally) the statics map.

    Every glyph at :data:`~prp3.explorer.page.LEVEL`: a move repaints them, not the axes.
    """
    from bokeh.layouts import row
    from bokeh.models import ColorBar, LinearColorMapper, Range1d
    from bokeh.plotting import figure

    fig = robot_figure("3-PRP robot to scale; arrows: joint forces at P_i", _limits(robot))
    key = Key(fig)
    bar: Any = None
    mapper: Any = None
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
            level=LEVEL,
        )
        image.name = "overlay_image"
        key.draw_glyphs([_REGION], sources)
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
    key.draw_glyphs(_GLYPHS, sources)
    key_and_toggles = arrow_layers(fig, key, sources["arrows"], ARROWS)
    return RobotFigure((fig if bar is None else row(fig, bar)), key_and_toggles, fig, mapper)


def _padded(values: Any) -> Any:
    """A fixed range around ``values``: their span and 5 % of it on each side, as Bokeh's
    automatic range pads it (which would be computed again at every move of the marker)."""
    from bokeh.models import Range1d

    low, high = float(np.min(values)), float(np.max(values))
    return Range1d(low - 0.05 * (high - low), high + 0.05 * (high - low))


def _singularity_figure(phi_range: tuple[float, float], scene: Scene) -> tuple[Any, Any]:
    from bokeh.models import ColumnDataSource, Span
    from bokeh.plotting import figure

    curve = singularity_curve(phi_range)
    measure = scene.singularity(np.array(curve["phi"]))
    fig = figure(
        title="sin(φ − π/3): singular at the red lines",
        width=330,
        height=170,
        x_axis_label="φ (rad)",
        x_range=_padded(curve["phi"]),
        y_range=_padded(measure),
        tools="",
        toolbar_location=None,
    )
    fig.title.text_font_size = "9pt"
    fig.line(curve["phi"], list(measure), color="#333333")
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
    fig.scatter("phi", "measure", source=marker, size=10, color="#d62728", level=LEVEL)
    return fig, marker


def _empty_overlay() -> dict[str, Columns]:
    """The columns of the statics map when none is shown."""
    return {
        "image": {"image": [], "x": [], "y": [], "dw": [], "dh": []},
        "region": {"xs": [], "ys": []},
    }


def figure_sources(
    view: View, overlay: Mapping[str, Columns] | None, strokes: Columns
) -> dict[str, Any]:
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
    with prp3's engines in Python (:meth:`Scene.table`, :meth:`Scene.view`;
    the statics map when ``φ`` or the robot changed) and sends the columns
    that changed (:class:`~prp3.explorer.live.LivePage`); a refused pose
    empties them and shows the library's one-line message.
    """
    from bokeh.layouts import row
    from bokeh.models import Checkbox

    current: dict[str, Robot] = {"robot": robot}
    motion = run_motion(robot, run) if run is not None else None

    def limits(control: MotionControl) -> tuple[float, float]:
        scale = robot.l0 if control.length else 1.0
        return control.low * scale, control.high * scale

    live = LivePage(
        doc, limits, motion, DESIGN_PARAMETERS, design_values(robot), arrow_scale(robot)
    )
    first = scene.view(robot, scene.table(robot, State()), 0, live.scale)
    try:
        overlay0: dict[str, Columns] | None = workspace_overlay(robot, 0.0)
    except Prp3Error:
        overlay0 = None
    sources = figure_sources(first, overlay0, stroke_bands(robot))
    overlay_box = Checkbox(
        label="statics map of the workspace at φ",
        active=overlay0 is not None,
        name="overlay_toggle",
    )
    phi_range = (live.sliders["phi"].start, live.sliders["phi"].end)
    singularity, sources["singularity_marker"] = _singularity_figure(phi_range, scene)
    peak0 = float(np.nanmax(overlay0["image"]["image"][0])) if overlay0 is not None else 1.0
    drawn = build_robot_figure(robot, sources, overlay=True, peak=peak0 if peak0 > 0 else 1.0)
    clip_overlays(doc, [drawn.plot, singularity])
    values_table = results_table(sources["values"])
    models = {"overlay_colours": drawn.colours, "message": live.message}
    # the colour scale reaches the browser with the map's image, which is coloured with it
    bundle = Bundle(sources, models, [values_table], quiet=["overlay_colours"])
    # the statics map of the last (φ, robot, shown): recomputed when one of them changes
    overlay: dict[str, Any] = {"key": (0.0, robot, True) if overlay0 is not None else None}

    def layers(phi: float, robot_now: Robot) -> Changes:
        key = (phi, robot_now, bool(overlay_box.active))
        if overlay["key"] == key:
            return {}
        overlay["key"] = key
        try:
            maps = workspace_overlay(robot_now, phi) if overlay_box.active else _empty_overlay()
        except Prp3Error:  # a singular φ: the message says it; no map
            maps = _empty_overlay()
        changes: Changes = {"overlay": maps["image"], "region": maps["region"]}
        if maps["image"]["image"]:
            peak = float(np.nanmax(maps["image"]["image"][0]))
            changes["overlay_colours"] = {"high": peak if peak > 0 else 1.0}
        return changes

    def marker(state: State) -> Changes:
        phi = state.pose[2]
        measure = float(scene.singularity(np.array(phi)))
        return {"singularity_marker": {"phi": [phi], "measure": [measure]}}

    def compute(state: State) -> Changes:
        robot_now = current["robot"]
        changes = marker(state)  # moves with φ, also when the pose is refused
        view = scene.view(robot_now, scene.table(robot_now, state), 0, live.scale)
        changes.update(view.sources())
        changes["strokes"] = stroke_bands(robot_now)
        changes.update(layers(state.pose[2], robot_now))
        return changes

    def blank(state: State) -> Changes:
        """Nothing that belongs to the refused pose (the base stays), no map of another φ."""
        overlay["key"] = None
        maps = _empty_overlay()
        return {
            **marker(state),
            **refused(first),
            "overlay": maps["image"],
            "region": maps["region"],
        }

    def redesign(values: Mapping[str, float]) -> None:
        current["robot"] = design_robot(robot, values)

    live.connect(bundle, compute, blank, redesign)
    overlay_box.on_change("active", lambda attr, old, new: live.update())
    stroke = robot.limits.stroke
    info = (
        f"l0 = {robot.l0:g} m; strokes: "
        + (f"[{stroke[0]:g}, {stroke[1]:g}] m (bands on the guides)" if stroke else "none")
        + "; singular at φ = π/3 mod π.  The check boxes show or hide the arrows."
    )
    fields = [*live.design_fields.values(), live.scale_field]
    design = [
        "<b>design</b> (the robot's parameters; forces update live; a value the model refuses "
        "is named in the message)",
        *(row(*fields[k : k + DESIGN_ROW]) for k in range(0, len(fields), DESIGN_ROW)),
        overlay_box,
    ]
    right = [values_table, singularity]
    scrubber = None
    if run is not None and motion is not None:
        plots, scrubber = live.run_widgets(run.table, {q: f"{q} (N)" for q in PLOTTED}, motion)
        right.append(plots)
    live.start("prp3 explore", drawn.layout, [drawn.key], info, right, design, scrubber)


def __getattr__(name: str) -> object:
    """The names this module had in prp3 0.1, now elsewhere (a DeprecationWarning names where)."""
    return moved_attribute(__name__, name)
