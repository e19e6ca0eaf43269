"""A run on the explorer's pages: its force plots against time and its scrubber.

The linked plots of a run's quantities against time (:func:`time_plots`), and
the scrubber ``time`` with its button ``play``: in the HTML file of a run
(:func:`browser_scrubber`, the precomputed frames copied in the browser) and on
the server's page (:func:`server_scrubber`, the sample recomputed in Python).
Both pages (:mod:`prp3.explorer.app`, :mod:`prp3.explorer.family_app`) and the
HTML file (:mod:`prp3.explorer.html_file`) import them.  Bokeh is imported
inside the functions only.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from prp3.drawing import LEG_COLOURS
from prp3.explorer.page import REDRAW_TABLES, clip_overlays, plain_slider
from prp3.plotting.animation import frame_indices  # a pure function: matplotlib is not imported
from prp3.validation import LEGS

__all__ = [
    "MAX_CURVE_POINTS",
    "MAX_HTML_FRAMES",
    "browser_scrubber",
    "frame_sources",
    "run_page",
    "server_scrubber",
    "time_plots",
]

#: Largest number of frames of the robot in an HTML file of a run.
MAX_HTML_FRAMES: int = 200
#: Largest number of points of each curve of the linked plots.
MAX_CURVE_POINTS: int = 2000
#: Copies frame ``k`` of every frame source into its drawn source (the only JavaScript).
_COPY_FRAME = (
    REDRAW_TABLES
    + """
const k = Math.round(slider.value);
for (const [name, target] of Object.entries(targets)) {
  const frames = sources[name];
  const data = {};
  for (const column of Object.keys(frames.data)) data[column] = frames.data[column][k];
  target.data = data;
}
for (const table of tables) redraw(table);
for (const span of spans) span.location = times[k];
slider.title = "t = " + times[k].toFixed(3) + " s";
"""
)

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


def run_page(
    title: str,
    table: Mapping[str, Any],
    view: Callable[[int], Any],
    draw: Callable[[Any], tuple[Mapping[str, Any], Sequence[Any], Sequence[Any]]],
    titles: Mapping[str, str],
    heading: Callable[[int], str],
    beside: bool = False,
) -> str:
    """The self-contained HTML page of a run: Bokeh's JavaScript inline, it opens offline.

    At most :data:`MAX_HTML_FRAMES` samples of the run are drawn, precomputed;
    the scrubber and the play button only pick a frame (:func:`browser_scrubber`).

    Parameters
    ----------
    title : str
        The page's title.
    table : mapping of str to ndarray (N,)
        The run's columns (``t`` and the per-leg quantities ``titles`` names, plotted).
    view : callable
        ``view(k)``: the :class:`~prp3.explorer.scene.View` of sample ``k``.
    draw : callable
        ``draw(first)``: the page's sources made from the first frame's view, the
        robot's figure as laid out, its key and the figure itself (its glyphs
        clipped to its frame, :func:`~prp3.explorer.page.clip_overlays`), and the
        tables beside it (the plots below them, or ``beside`` them).
    heading : callable
        ``heading(frames)``: the HTML of the page's first line.
    """
    from bokeh.document import Document
    from bokeh.embed import file_html
    from bokeh.layouts import column, row
    from bokeh.models import Div
    from bokeh.resources import INLINE

    t = np.asarray(table["t"], dtype=np.float64)
    frames = [int(k) for k in frame_indices(int(t.size), MAX_HTML_FRAMES)]
    views = [view(k) for k in frames]
    sources, (layout, key, figure), tables = draw(views[0])
    plots, spans = time_plots(table, titles)
    frames_of = frame_sources(views)
    targets = {name: sources[name] for name in frames_of}
    scrubber = browser_scrubber([float(t[k]) for k in frames], frames_of, targets, tables, spans)
    right = [column(*tables), column(*plots)] if beside else [column(*tables, *plots)]
    doc = Document()
    doc.add_root(
        column(
            Div(text=heading(len(frames)), width=900), scrubber, row(column(layout, key), *right)
        )
    )
    clip_overlays(doc, [figure])
    return str(file_html(doc, resources=INLINE, title=title))


def _scrubber_widgets(times: Sequence[float], width: int) -> tuple[Any, Any]:
    from bokeh.models import Toggle

    slider = plain_slider(
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
