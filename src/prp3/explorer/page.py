"""What the explorer's two live pages draw alike: the robot's figure, its key and arrows, the table.

The 3-PRP page (:mod:`prp3.explorer.app`) and the family's
(:mod:`prp3.explorer.family_app`) both import from here, so neither imports the
other at module level (one way, no cycle): the robot's figure and its glyphs
(:func:`robot_figure`, :class:`Key`, :func:`arrow_layers`), the table of
values, and the motion sliders with their fields.  The update loop of a live
page is :mod:`prp3.explorer.live`; a run's plots and scrubber
:mod:`prp3.explorer.scrubber`.  Bokeh is imported inside the functions only.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from prp3.drawing import LEG_COLOURS
from prp3.explorer.scene import ArrowStyle
from prp3.moved_paths import moved_attribute
from prp3.validation import LEGS

__all__ = [
    "LEVEL",
    "REDRAW_TABLES",
    "Glyph",
    "Key",
    "arrow_layers",
    "clip_overlays",
    "plain_slider",
    "robot_figure",
    "slider_with_field",
]

#: Defines ``redraw(table, old, changed)``: BokehJS redraws a DataTable when the rows of its
#: view change, not when the data of the same rows does.  While their number stays, the cells
#: are redrawn in place (SlickGrid's ``updateCell``: the cell's text, no row rebuilt and laid
#: out anew), only those of the ``changed`` columns whose value differs from the ``old`` one
#: when both are given; the whole table (its view's change) otherwise.
REDRAW_TABLES = """
const redraw = (table, old = null, changed = null) => {
  const view = Bokeh.index.find_one(table);
  const grid = view == null ? null : view.grid;
  const rows = table.source.get_length() ?? 0;
  if (grid == null || grid.getDataLength() !== rows || typeof grid.updateCell !== "function"
      || view.data == null || typeof view.data.init !== "function") {
    table.view.change.emit();
    return;
  }
  view.data.init(table.source, table.view);
  const columns = grid.getColumns();
  for (let c = 0; c < columns.length; c++) {
    const field = columns[c].field;
    if (changed != null && !(field in changed)) continue;
    const before = old == null || changed == null ? null : old[field];
    for (let r = 0; r < rows; r++) {
      const k = view.data.index[r];
      if (before == null || before[k] !== changed[field][k]) grid.updateCell(r, c);
    }
  }
};
"""

#: The level of every glyph of a robot figure (and of the singularity marker).  BokehJS
#: paints a figure on two canvases: the primary one (background, grid, axes and their
#: labels, title, and the renderers of the other levels), and the overlay one, which a
#: change of its renderers alone repaints without the primary one (``PlotView._actual_paint``).
#: A move then repaints the robot, its arrows and the map, not the axes, the grid and the
#: text around them.
LEVEL: str = "overlay"

#: Clips the overlay canvas of each of ``figures`` to its frame, as BokehJS clips the glyphs of
#: the primary canvas (not those of the overlay one): set once the page is laid out, and
#: again after every repaint that moved the frame (a zoom that widened the axis labels).
_CLIP_OVERLAYS = """
for (const figure of figures) {
  const view = Bokeh.index.find_one(figure);
  if (view == null) continue;
  const layer = view.canvas_view.overlays.el;
  const clip = () => {
    const frame = view.frame.bbox;
    const canvas = view.canvas_view.bbox;
    const inset = `inset(${frame.top}px ${canvas.width - frame.right}px `
      + `${canvas.height - frame.bottom}px ${frame.left}px)`;
    if (layer.dataset.inset !== inset) {
      layer.dataset.inset = inset;
      layer.style.clipPath = inset;
    }
  };
  clip();
  view.repainted.connect(clip);
}
"""


def clip_overlays(doc: Any, figures: Sequence[Any]) -> None:
    """Clip the glyphs of ``figures`` drawn at :data:`LEVEL` to each one's frame, in ``doc``."""
    from bokeh.events import DocumentReady
    from bokeh.models import CustomJS

    doc.js_on_event(DocumentReady, CustomJS(args={"figures": list(figures)}, code=_CLIP_OVERLAYS))


def results_table(source: Any) -> Any:
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


def escape(text: str) -> str:
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


#: A glyph of a robot figure: the figure's method (``patches``, ``multi_line``, ``scatter``),
#: the name of its source, its label in the key (``""``: not listed) and its style.
Glyph = tuple[str, str, str, dict[str, Any]]

#: The columns a glyph method draws.
_FIELDS: dict[str, tuple[str, str]] = {
    "patches": ("xs", "ys"),
    "multi_line": ("xs", "ys"),
    "scatter": ("x", "y"),
}


def robot_figure(title: str, half: float) -> Any:
    """The figure ``robot`` of a page: the robot to scale over ``[-half, half]²`` (m), 470 px."""
    from bokeh.models import Range1d
    from bokeh.plotting import figure

    return figure(
        name="robot",
        title=title,
        frame_width=470,
        frame_height=470,
        x_range=Range1d(-half, half),
        y_range=Range1d(-half, half),
        x_axis_label="x (m)",
        y_axis_label="y (m)",
        tools="pan,wheel_zoom,reset,save",
        toolbar_location="above",
    )


class Key:
    """The key of a robot figure: an HTML legend (a ``Div``) beside it, with no canvas.

    A Bokeh legend draws each entry's glyph in a canvas of its own, and the
    browser composites every canvas of the page at every frame of a move; a
    ``Div`` of text and coloured marks is laid out once.  :meth:`draw` draws a
    glyph on ``fig`` (at :data:`LEVEL` unless ``style`` says another level) and, with a
    ``legend``, lists it.
    """

    def __init__(self, fig: Any) -> None:
        self.fig = fig
        self.entries: list[tuple[str, str]] = []

    def draw(self, method: str, *fields: str, source: Any, legend: str = "", **style: Any) -> Any:
        """``fig.<method>(*fields, source=source, **style)``; listed in the key under ``legend``."""
        renderer = getattr(self.fig, method)(*fields, source=source, **{"level": LEVEL, **style})
        if legend:
            self.entries.append((_symbol(method, style), legend))
        return renderer

    def draw_glyphs(
        self, glyphs: Sequence[Glyph], sources: Mapping[str, Any], present: bool = False
    ) -> None:
        """Draw ``glyphs`` in order, each from its source of ``sources``; with ``present``, a
        glyph whose source has no row is not listed (the key of what this robot has)."""
        for method, name, legend, style in glyphs:
            source = sources[name]
            rows = len(next(iter(source.data.values()), []))
            listed = legend if rows or not present else ""
            self.draw(method, *_FIELDS[method], source=source, legend=listed, **style)

    def div(self, width: int) -> Any:
        """The key: its entries in two columns, in the order drawn (down, then across)."""
        from bokeh.models import Div

        items = "".join(
            f'<div style="white-space:nowrap">{symbol} {escape(label)}</div>'
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


def arrow_layers(fig: Any, key: Key, source: Any, arrows: Mapping[str, ArrowStyle]) -> Any:
    """The arrows of every joint force on ``fig``, listed in ``key``, and their toggles.

    ``arrows`` maps a quantity of ``source`` (a column ``quantity``) to its
    style (:class:`~prp3.explorer.scene.ArrowStyle`: its label in the key, its
    colour).  All the arrows are two renderers (the shafts and the heads,
    coloured by quantity), so that a move repaints two glyphs, not two per
    quantity; the check boxes below the key show or hide a quantity's
    arrows by the filter of their rows (in the browser, no computation).
    Returns the key and the check boxes.
    """
    from bokeh.layouts import column
    from bokeh.models import CDSView, CheckboxGroup, CustomJS, GroupFilter, HoverTool, UnionFilter
    from bokeh.transform import factor_cmap

    groups = [GroupFilter(column_name="quantity", group=quantity) for quantity in arrows]
    shown = UnionFilter(operands=list(groups), name="arrow_filter")
    colours = factor_cmap(
        "quantity", palette=[style.colour for style in arrows.values()], factors=list(arrows)
    )
    segment = fig.segment(
        "x0", "y0", "x1", "y1", source=source, view=CDSView(filter=shown),
        line_color=colours, line_width=2.5, level=LEVEL,
    )  # fmt: skip
    fig.scatter(
        "x1", "y1", angle="angle", marker="triangle", size=10, source=source,
        view=CDSView(filter=shown), color=colours, level=LEVEL,
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


#: A slider's handle without a layer of its own or an animation: noUiSlider's ``will-change:
#: transform`` gives each of the page's sliders two compositor layers, which every frame of
#: every move then lays out and commits (``benchmarks/bench_explore.py``); a value set by
#: the server or the scrubber jumps, as a drag does.
SLIDER_CSS: str = (
    ".noUi-connect, .noUi-origin { will-change: auto; }\n"
    ".noUi-state-tap .noUi-connect, .noUi-state-tap .noUi-origin { transition: none; }"
)


def plain_slider(**properties: Any) -> Any:
    """A Bokeh ``Slider`` drawn without its own layers (:data:`SLIDER_CSS`)."""
    from bokeh.models import InlineStyleSheet, Slider

    return Slider(stylesheets=[InlineStyleSheet(css=SLIDER_CSS)], **properties)


def slider_with_field(control: Any, low: float, high: float) -> tuple[Any, Any]:
    """A slider of one motion ``control`` over ``[low, high]`` and its numeric field, linked.

    Returns the slider (named ``control.name``) and the row of both; the two are
    linked in the browser, so either sets the other.  The slider's value reaches
    the server; the field shows it without sending it (no second patch, and no
    second reply, per move: the server reads the sliders only).
    """
    from bokeh.layouts import row
    from bokeh.models import CustomJS, Spinner

    slider = plain_slider(
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
    shown = "if (field.value !== slider.value) field.setv({value: slider.value}, {sync: false});"
    slider.js_on_change("value", CustomJS(args={"slider": slider, "field": field}, code=shown))
    field.js_link("value", slider, "value")
    return slider, row(slider, field)


def __getattr__(name: str) -> object:
    """The names this module had in prp3 0.1, now elsewhere (a DeprecationWarning names where)."""
    return moved_attribute(__name__, name)
