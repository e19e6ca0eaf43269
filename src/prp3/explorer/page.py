"""What the explorer's two pages share: their few lines of JavaScript, bounds, the table.

The 3-PRP page (:mod:`prp3.explorer.app`) and the family's
(:mod:`prp3.explorer.family_app`) both import from here, so neither imports the
other at module level (one way, no cycle).  Bokeh is imported inside the
functions only.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from prp3.explorer.scene import LEG_COLOURS
from prp3.plotting.animation import frame_indices  # a pure function: matplotlib is not imported
from prp3.validation import LEGS

__all__ = [
    "MAX_CURVE_POINTS",
    "MAX_HTML_FRAMES",
    "Key",
    "arrow_layers",
    "browser_scrubber",
    "server_scrubber",
    "slider_with_field",
    "time_plots",
]

#: Largest number of frames of the robot in an HTML file of a run.
MAX_HTML_FRAMES: int = 200
#: Largest number of points of each curve of the linked plots.
MAX_CURVE_POINTS: int = 2000
#: Copies frame ``k`` of every frame source into its drawn source (the only JavaScript).
_COPY_FRAME = """
const k = Math.round(slider.value);
for (const [name, target] of Object.entries(targets)) {
  const frames = sources[name];
  const data = {};
  for (const column of Object.keys(frames.data)) data[column] = frames.data[column][k];
  target.data = data;
}
for (const table of tables) table.view.change.emit();  // a DataTable redraws on a change of its view only
for (const span of spans) span.location = times[k];
slider.title = "t = " + times[k].toFixed(3) + " s";
"""

#: Copies the columns of the one row of the server's bundle into the drawn sources.
_UNBUNDLE = """
const data = bundle.data instanceof Map ? Object.fromEntries(bundle.data) : bundle.data;
const grouped = {};
for (const [key, values] of Object.entries(data)) {
  const [name, column] = key.split("|");
  (grouped[name] = grouped[name] || {})[column] = values[0];
}
// not synced back: the server sent these columns (an echo would cost a patch each way)
for (const [name, columns] of Object.entries(grouped)) targets[name].setv({data: columns}, {sync: false});
// BokehJS redraws a DataTable when its view's rows change, not when the data of the same
// rows does: tell it
if ("values" in grouped) table.view.change.emit();
"""

#: Steps the scrubber while the play button is down (the browser's timer; no computation).
_PLAY = """
if (toggle.active) {
  toggle.label = "❚❚ pause";
  window._prp3_timer = setInterval(() => {
    slider.value = slider.value >= slider.end ? slider.start : slider.value + 1;
  }, period);
} else {
  toggle.label = "▶ play";
  clearInterval(window._prp3_timer);
}
"""


def _table(source: Any) -> Any:
    from bokeh.models import DataTable, NumberFormatter, TableColumn

    number = NumberFormatter(format="0.0000")
    columns = [
        TableColumn(field="quantity", title="quantity", width=62),
        TableColumn(field="unit", title="unit", width=40),
        *(TableColumn(field=leg, title=f"leg {leg}", formatter=number, width=72) for leg in LEGS),
    ]
    return DataTable(
        source=source,
        columns=columns,
        name="table",
        width=330,
        height=330,
        index_position=None,
        reorderable=False,
        autosize_mode="none",  # no measuring of the texts at every update
        sortable=False,  # no sort, no selection to restore at every update
        selectable=False,
    )


def _escape(text: str) -> str:
    import html

    return html.escape(text)


def _line(
    colour: str, width: float, dash: str = "solid", alpha: float = 1.0, size: int = 18
) -> str:
    return (
        f'<span style="display:inline-block;width:{size}px;vertical-align:middle;'
        f'border-top:{max(round(width), 1)}px {dash} {colour};opacity:{alpha:g}"></span>'
    )


def _symbol(method: str, style: Mapping[str, Any]) -> str:
    """The HTML sample of a glyph in the key: a line, a box or a marker in its colours."""
    line = str(style.get("line_color", style.get("color", "#000000")))
    colours = list(LEG_COLOURS.values()) if line in ("colour", "outline") else [line]
    width = float(style.get("line_width", 1.0))
    dash = {"dotted": "dotted", "dashed": "dashed"}.get(str(style.get("line_dash", "")), "solid")
    if method == "scatter":
        fill = str(style.get("fill_color", style.get("color", line)))
        mark = {"triangle": "▲", "cross": "+"}.get(str(style.get("marker", "circle")), "●")
        if fill == "white":
            return "".join(f'<span style="color:{c}">○</span>' for c in colours)
        return f'<span style="color:{fill};opacity:{float(style.get("fill_alpha", 1.0)):g}">{mark}</span>'
    if method == "patches":
        area = style.get("fill_color")
        alpha = float(style.get("fill_alpha", 1.0)) if area is not None else 0.0
        return (
            f'<span style="display:inline-block;width:14px;height:8px;vertical-align:middle;'
            f"border:{max(round(width), 1)}px {dash} {line};"
            f'background:{area or "none"};background-clip:padding-box;opacity:{max(alpha, 0.6):g}">'
            "</span>"
        )
    alpha = float(style.get("line_alpha", 1.0))
    return "".join(_line(c, min(width, 8.0), dash, alpha, 18 // len(colours)) for c in colours)


class Key:
    """The key of a robot figure: an HTML legend (a ``Div``) beside it, with no canvas.

    A Bokeh legend draws each entry's glyph in a canvas of its own, and the
    browser composites every canvas of the page at every frame of a move; a
    ``Div`` of text and coloured marks is laid out once.  :meth:`draw` draws a
    glyph on ``fig`` and, with a ``legend``, lists it.
    """

    def __init__(self, fig: Any) -> None:
        self.fig = fig
        self.entries: list[tuple[str, str]] = []

    def draw(self, method: str, *fields: str, source: Any, legend: str = "", **style: Any) -> Any:
        """``fig.<method>(*fields, source=source, **style)``; listed in the key under ``legend``."""
        renderer = getattr(self.fig, method)(*fields, source=source, **style)
        if legend:
            self.entries.append((_symbol(method, style), legend))
        return renderer

    def div(self, width: int) -> Any:
        """The key: its entries in two columns, in the order drawn (down, then across)."""
        from bokeh.models import Div

        items = "".join(
            f'<div style="white-space:nowrap">{symbol} {_escape(label)}</div>'
            for symbol, label in self.entries
        )
        rows = (len(self.entries) + 1) // 2  # down the first column, then the second
        return Div(
            text='<div style="display:grid;grid-template-columns:1fr 1fr;column-gap:8px;'
            f"grid-template-rows:repeat({rows},auto);grid-auto-flow:column;"
            f'font-size:8pt;line-height:1.5">{items}</div>',
            width=width,
            name="key",
        )


def arrow_layers(fig: Any, key: Key, source: Any, arrows: Mapping[str, tuple[str, str]]) -> Any:
    """The arrows of every joint force on ``fig``, listed in ``key``, and their toggles.

    ``arrows`` maps a quantity of ``source`` (a column ``quantity``) to its
    legend label and colour.  All the arrows are two renderers (the shafts and
    the heads, coloured by quantity), so that a move repaints two glyphs, not
    two per quantity; the check boxes below the key show or hide a quantity's
    arrows by the filter of their rows (in the browser, no computation).
    Returns the key and the check boxes.
    """
    from bokeh.layouts import column
    from bokeh.models import CDSView, CheckboxGroup, CustomJS, GroupFilter, HoverTool, UnionFilter
    from bokeh.transform import factor_cmap

    groups = [GroupFilter(column_name="quantity", group=quantity) for quantity in arrows]
    shown = UnionFilter(operands=list(groups), name="arrow_filter")
    colours = factor_cmap(
        "quantity", palette=[colour for _, colour in arrows.values()], factors=list(arrows)
    )
    segment = fig.segment(
        "x0", "y0", "x1", "y1", source=source, view=CDSView(filter=shown),
        line_color=colours, line_width=2.5,
    )  # fmt: skip
    fig.scatter(
        "x1", "y1", angle="angle", marker="triangle", size=10, source=source,
        view=CDSView(filter=shown), color=colours,
    )  # fmt: skip
    fig.add_tools(
        HoverTool(
            renderers=[segment],
            tooltips=[
                ("", "@quantity leg @leg"),
                ("|F|", "@value{0.000} N"),
                ("Fx, Fy", "@fx{0.000}, @fy{0.000} N"),
            ],
        )
    )
    for label, colour in arrows.values():
        key.entries.append((_line(colour, 2.5) + f'<span style="color:{colour}">▶</span>', label))
    toggles = CheckboxGroup(
        labels=[f"{quantity} arrows" for quantity in arrows],
        active=list(range(len(arrows))),
        inline=True,
        name="arrow_toggles",
    )
    nothing = GroupFilter(column_name="quantity", group="")  # no row: every box unticked
    toggles.js_on_change(
        "active",
        CustomJS(
            args={"groups": groups, "shown": shown, "box": toggles, "nothing": nothing},
            code="shown.operands = box.active.length ? box.active.map((i) => groups[i]) : [nothing];",
        ),
    )
    return column(key.div(560), toggles)


def time_plots(table: Mapping[str, Any], titles: Mapping[str, str]) -> tuple[list[Any], list[Any]]:
    """The quantities ``titles`` names (``quantity_L`` columns of ``table``) of the three legs
    against time, one figure each with its title, and one shared time line (a Span) each.
    """
    from bokeh.models import Span
    from bokeh.plotting import figure

    t = np.asarray(table["t"])
    kept = frame_indices(t.size, MAX_CURVE_POINTS)
    spans: list[Any] = []
    figures: list[Any] = []
    x_range = None
    for quantity, title in titles.items():
        fig = figure(
            title=title,
            width=330,
            height=140,
            tools="xpan,xwheel_zoom,reset",
            toolbar_location=None,
            **({"x_range": x_range} if x_range is not None else {}),
        )
        fig.title.text_font_size = "9pt"
        x_range = fig.x_range
        for leg in LEGS:
            fig.line(
                t[kept],
                np.asarray(table[f"{quantity}_{leg}"])[kept],
                color=LEG_COLOURS[leg],
                legend_label=leg,
            )
        legend = fig.legend[0]
        legend.label_text_font_size = "8pt"
        legend.padding = 2
        legend.spacing = 0
        fig.add_layout(legend, "right")
        span = Span(location=float(t[0]), dimension="height", line_color="black", line_width=1)
        fig.add_layout(span)
        spans.append(span)
        figures.append(fig)
    figures[-1].xaxis.axis_label = "t (s)"
    return figures, spans


#: A slider's handle without a layer of its own or an animation: noUiSlider's ``will-change:
#: transform`` gives each of the page's sliders two compositor layers, which every frame of
#: every move then lays out and commits (``benchmarks/bench_explore.py``); a value set by
#: the server or the scrubber jumps, as a drag does.
SLIDER_CSS: str = (
    ".noUi-connect, .noUi-origin { will-change: auto; }\n"
    ".noUi-state-tap .noUi-connect, .noUi-state-tap .noUi-origin { transition: none; }"
)


def _plain_slider(**properties: Any) -> Any:
    """A Bokeh ``Slider`` drawn without its own layers (:data:`SLIDER_CSS`)."""
    from bokeh.models import InlineStyleSheet, Slider

    return Slider(stylesheets=[InlineStyleSheet(css=SLIDER_CSS)], **properties)


def slider_with_field(control: Any, low: float, high: float) -> tuple[Any, Any]:
    """A slider of one motion ``control`` over ``[low, high]`` and its numeric field, linked.

    Returns the slider (named ``control.name``) and the row of both; the two are
    linked in the browser (``js_link``), so either sets the other.
    """
    from bokeh.layouts import row
    from bokeh.models import Spinner

    slider = _plain_slider(
        start=low,
        end=high,
        value=0.0,
        step=control.step,
        name=control.name,
        title=f"{control.label} ({control.unit})",
        width=190,
        show_value=False,
    )
    field = Spinner(
        low=low,
        high=high,
        step=control.step,
        value=0.0,
        width=88,
        name=f"{control.name}_field",
        format="0.[0000]",
    )
    slider.js_link("value", field, "value")
    field.js_link("value", slider, "value")
    return slider, row(slider, field)


# ---------------------------------------------------------------- the scrubber of a run
def frame_sources(views: Sequence[Any]) -> dict[str, Any]:
    """A source per drawn source of ``views`` (:class:`~prp3.explorer.scene.View`), a row per view.

    Row ``k`` of source ``name`` holds the columns of ``views[k].sources()[name]``
    (named ``frames:<name>``), which :func:`browser_scrubber` copies at frame ``k``.
    """
    from bokeh.models import ColumnDataSource

    first = views[0].sources()
    every = [view.sources() for view in views]
    return {
        name: ColumnDataSource(
            {c: [drawn[name][c] for drawn in every] for c in first[name]}, name=f"frames:{name}"
        )
        for name in first
    }


def _scrubber_widgets(times: Sequence[float], width: int) -> tuple[Any, Any]:
    from bokeh.models import Toggle

    slider = _plain_slider(
        start=0,
        end=max(len(times) - 1, 1),
        value=0,
        step=1,
        name="time",
        title=f"t = {times[0]:.3f} s",
        width=width,
        show_value=False,
    )
    return slider, Toggle(label="▶ play", name="play", width=90)


def _period(times: Sequence[float]) -> float:
    """Milliseconds of the run between two of ``times`` (its real pace)."""
    return 1000.0 * float(times[-1] - times[0]) / max(len(times) - 1, 1)


def browser_scrubber(
    times: Sequence[float],
    frames: Mapping[str, Any],
    targets: Mapping[str, Any],
    tables: Sequence[Any],
    spans: Sequence[Any],
    width: int = 400,
) -> Any:
    """The scrubber ``time`` and the button ``play`` of an HTML file of a run (no server).

    ``frames`` maps a drawn source's name to a source of its columns at every
    frame (a row per frame); moving the scrubber to frame ``k`` copies row ``k``
    into each of ``targets``, redraws the ``tables`` (DataTables), moves the
    time lines ``spans`` to ``times[k]``.  The play button steps the scrubber on
    the browser's timer, at the run's pace (at most 33 frames a second).
    Returns the row of the two.
    """
    from bokeh.layouts import row
    from bokeh.models import CustomJS

    slider, play = _scrubber_widgets(times, width)
    slider.js_on_change(
        "value",
        CustomJS(
            args={
                "slider": slider,
                "sources": dict(frames),
                "targets": dict(targets),
                "tables": list(tables),
                "spans": list(spans),
                "times": [float(v) for v in times],
            },
            code=_COPY_FRAME,
        ),
    )
    period = max(30, int(_period(times)))
    play.js_on_change(
        "active", CustomJS(args={"toggle": play, "slider": slider, "period": period}, code=_PLAY)
    )
    return row(slider, play)


def server_scrubber(
    doc: Any,
    times: Sequence[float],
    show: Callable[[int], None],
    spans: Sequence[Any],
    width: int = 500,
) -> Any:
    """The scrubber ``time`` and the button ``play`` of a run on the server's page.

    Moving the scrubber to sample ``k`` moves the time lines ``spans`` and calls
    ``show(k)`` (in Python: the page sets its sliders to the run's state at
    ``k`` and recomputes it).  The play button steps the scrubber on the
    server's timer at the run's pace, by as many samples as keep a step at
    least 40 ms apart.  ``show(0)`` runs at once: the page starts at the run's
    first sample.  Returns the row of the two.
    """
    from bokeh.layouts import row

    slider, play = _scrubber_widgets(times, width)
    samples = len(times)
    pace = _period(times)
    period = max(40, int(pace))
    stride = max(1, round(40 / pace)) if pace > 0 else 1
    timer: list[Any] = [None]

    def to_sample(k: int) -> None:
        k = min(max(int(k), 0), samples - 1)
        for span in spans:
            span.location = float(times[k])
        slider.title = f"t = {float(times[k]):.3f} s"
        show(k)

    def step() -> None:
        following = int(slider.value) + stride
        slider.value = following if following < samples else 0

    def on_play(attr: str, old: Any, new: Any) -> None:
        if new:
            play.label = "❚❚ pause"
            timer[0] = doc.add_periodic_callback(step, period)
        else:
            play.label = "▶ play"
            if timer[0] is not None:
                doc.remove_periodic_callback(timer[0])
                timer[0] = None

    slider.on_change("value", lambda attr, old, new: to_sample(int(new)))
    play.on_change("active", on_play)
    to_sample(0)  # the page starts at the run's first sample
    return row(slider, play)
