"""What the explorer's two pages share: their few lines of JavaScript, bounds, the table.

The 3-PRP page (:mod:`prp3.explorer.app`) and the family's
(:mod:`prp3.explorer.family_app`) both import from here, so neither imports the
other at module level (one way, no cycle).  Bokeh is imported inside the
functions only.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from prp3.explorer.scene import LEG_COLOURS
from prp3.mechanics.geometry import LEGS
from prp3.plotting.animation import frame_indices  # a pure function: matplotlib is not imported

__all__ = ["MAX_CURVE_POINTS", "MAX_HTML_FRAMES"]

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
table.view.change.emit();  // a DataTable redraws on a change of its view only
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
for (const [name, columns] of Object.entries(grouped)) targets[name].data = columns;
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
    )


def _escape(text: str) -> str:
    import html

    return html.escape(text)


def arrow_layers(
    fig: Any, key: Any, draw: Any, source: Any, arrows: Mapping[str, tuple[str, str]]
) -> Any:
    """The arrows of every joint force on ``fig``, a group per quantity, and their toggles.

    ``arrows`` maps a quantity of ``source`` (a column ``quantity``) to its
    legend label and colour; ``draw`` adds a glyph to ``fig`` with its legend
    entry in ``key``.  Returns the legend figure ``key`` with the check boxes
    that show or hide each group (a browser-side toggle, no computation).
    """
    from bokeh.layouts import column
    from bokeh.models import CDSView, CheckboxGroup, CustomJS, GroupFilter, HoverTool

    groups: list[list[Any]] = []
    for quantity, (label, colour) in arrows.items():
        view = CDSView(filter=GroupFilter(column_name="quantity", group=quantity))
        segment = draw(
            "segment",
            "x0",
            "y0",
            "x1",
            "y1",
            source=source,
            view=view,
            line_color=colour,
            line_width=2.5,
            legend=label,
        )
        head = draw(
            "scatter",
            "x1",
            "y1",
            angle="angle",
            marker="triangle",
            size=10,
            source=source,
            view=view,
            color=colour,
            legend=label,
        )
        groups.append([segment, head])
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
    legend = key.legend[0]
    legend.location = "top_left"
    legend.label_text_font_size = "8pt"
    legend.ncols = 2
    legend.spacing = 0
    legend.padding = 2
    legend.border_line_color = None
    toggles = CheckboxGroup(
        labels=[f"{quantity} arrows" for quantity in arrows],
        active=list(range(len(arrows))),
        inline=True,
        name="arrow_toggles",
    )
    toggles.js_on_change(
        "active",
        CustomJS(
            args={"groups": groups, "box": toggles},
            code="groups.forEach((rs, i) => rs.forEach((r) => { r.visible = box.active.includes(i); }));",
        ),
    )
    return column(key, toggles)


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


def slider_with_field(control: Any, low: float, high: float) -> tuple[Any, Any]:
    """A slider of one motion ``control`` over ``[low, high]`` and its numeric field, linked.

    Returns the slider (named ``control.name``) and the row of both; the two are
    linked in the browser (``js_link``), so either sets the other.
    """
    from bokeh.layouts import row
    from bokeh.models import Slider, Spinner

    slider = Slider(
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
