"""What the explorer's two pages share: their few lines of JavaScript, bounds, the table.

The 3-PRP page (:mod:`prp3.explorer.app`) and the family's
(:mod:`prp3.explorer.family_app`) both import from here, so neither imports the
other at module level (one way, no cycle).  Bokeh is imported inside the
functions only.
"""

from __future__ import annotations

from typing import Any

from ..geometry import LEGS

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
