"""What the explorer's two live pages share: the widgets, the key, the arrows, the update loop.

The 3-PRP page (:mod:`prp3.explorer.app`) and the family's
(:mod:`prp3.explorer.family_app`) both import from here, so neither imports the
other at module level (one way, no cycle): the table of values, the key and
the arrows of a robot figure, the motion sliders with their fields, the design
fields, and :class:`LivePage`, which recomputes the page in Python at every
change and sends what changed to the browser in one message
(:class:`Bundle`).  A run's plots and scrubber are
:mod:`prp3.explorer.scrubber`.  Bokeh is imported inside the functions only.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from prp3.errors import Prp3Error
from prp3.explorer.scene import LEG_COLOURS, MOTION_CONTROLS, MotionControl, State
from prp3.mechanics.geometry import LEGS
from prp3.model.motion import Motion

__all__ = [
    "LEVEL",
    "REDRAW_TABLES",
    "Bundle",
    "Key",
    "LivePage",
    "arrow_layers",
    "clip_overlays",
    "plain_slider",
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

#: Copies the one row of the server's bundle into the page: ``source|column`` into the data
#: of ``sources[source]`` (the other columns kept), ``model|property`` into ``models[model]``.
_UNBUNDLE = (
    REDRAW_TABLES
    + """
const data = bundle.data instanceof Map ? Object.fromEntries(bundle.data) : bundle.data;
const grouped = {};
for (const [key, values] of Object.entries(data)) {
  const [name, column] = key.split("|");
  if (column !== undefined) (grouped[name] = grouped[name] || {})[column] = values[0];
}
// not synced back: the server sent these values (an echo would cost a patch each way).  The
// models first; those of `quiet` without a change signal: a source of the same row reads them
// when it is drawn next (a colour mapper: the map's image mapped once, not once for the new
// scale and once for the new image, and its colour bar told by that one mapping)
for (const [name, changed] of Object.entries(grouped)) {
  if (name in models) models[name].setv(changed, {sync: false, silent: quiet.includes(name)});
}
const olds = {};
for (const [name, changed] of Object.entries(grouped)) {
  if (!(name in sources)) continue;
  const source = sources[name];
  const old = source.data instanceof Map ? Object.fromEntries(source.data) : source.data;
  olds[name] = old;
  source.setv({data: {...old, ...changed}}, {sync: false});
}
for (const table of tables) {
  const name = table.source.name;
  if (name in grouped) redraw(table, olds[name], grouped[name]);
}
"""
)

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


# ---------------------------------------------------------------- the live page
def _same(shown: Any, new: Any) -> bool:
    """Whether a column or property ``new`` is the one shown (arrays exactly, NaN equal to NaN)."""
    arrays = (shown, new) if not isinstance(shown, list) else (*shown[:1], *new[:1])
    if any(isinstance(value, np.ndarray) for value in arrays):
        if isinstance(shown, list):
            return len(shown) == len(new) and all(map(_same, shown, new))
        return bool(np.array_equal(shown, new, equal_nan=True))
    return bool(shown == new)


class Bundle:
    """The drawn sources and models of a live page, and the one message of each update.

    Bokeh sends one message per changed model, which the browser applies and
    repaints in turn, and the whole of a changed source.  :meth:`send`
    compares each column of a source, and each property of a model, with the
    one the browser shows, and puts only those that changed in one row of its
    own source :attr:`source` (``bundle``: a root of the document that nothing
    draws), which a few lines of ``CustomJS`` copy into the page in the browser
    (the other columns of a source kept): one message and one repaint per
    update.  Until :attr:`served` is set, the document is not in a browser:
    :meth:`send` sets the sources and models themselves.

    Parameters
    ----------
    sources : mapping of str to ColumnDataSource
        The drawn sources by name.
    models : mapping of str to Model
        Other models whose properties an update sets (a colour mapper's
        ``high``, the message's ``text``), by name.
    tables : sequence of DataTable
        Redrawn when their source changes (:data:`REDRAW_TABLES`).
    quiet : sequence of str
        Models of ``models`` set without a change signal in the browser: each is sent only
        with a change of a source that reads it (the statics map's colour mapper, sent with
        the map's image).  They are set before the sources.
    """

    def __init__(
        self,
        sources: Mapping[str, Any],
        models: Mapping[str, Any],
        tables: Sequence[Any],
        quiet: Sequence[str] = (),
    ) -> None:
        from bokeh.models import ColumnDataSource, CustomJS

        self.sources = dict(sources)
        self.models = dict(models)
        self.shown: dict[str, dict[str, Any]] = {
            **{name: dict(source.data) for name, source in self.sources.items()},
            **{name: {} for name in self.models},
        }
        self.served = False
        self._serial = 0
        self.source = ColumnDataSource({}, name="bundle")
        self.source.js_on_change(
            "data",
            CustomJS(
                args={
                    "bundle": self.source,
                    "sources": self.sources,
                    "models": self.models,
                    "tables": list(tables),
                    "quiet": list(quiet),
                },
                code=_UNBUNDLE,
            ),
        )

    def send(self, changes: Mapping[str, Mapping[str, Any]]) -> None:
        """Show ``changes``: a source's name → columns, or a model's name → properties.

        Only the columns and properties that differ from those shown travel,
        all of them in one message.
        """
        row: dict[str, list[Any]] = {}
        for name, values in changes.items():
            shown = self.shown[name]
            changed = {
                key: value
                for key, value in values.items()
                if key not in shown or not _same(shown[key], value)
            }
            if not changed:
                continue
            shown.update(changed)
            if self.served:
                row.update({f"{name}|{key}": [value] for key, value in changed.items()})
            elif name in self.sources:
                self.sources[name].data = dict(shown)
            else:
                for key, value in changed.items():
                    setattr(self.models[name], key, value)
        if row:
            self._serial += 1  # never the same row twice: each send is a change of the bundle
            self.source.data = {"serial": [self._serial], **row}


def widened(low: float, high: float, motion: Motion, name: str) -> tuple[float, float]:
    """A motion slider's range ``[low, high]`` widened to the run's values of its control."""
    values = np.concatenate([motion.pose, motion.velocity, motion.acceleration], axis=-1)
    k = [c.name for c in MOTION_CONTROLS].index(name)
    return min(low, float(values[:, k].min())), max(high, float(values[:, k].max()))


#: What an update draws: a source's name → its columns, or a model's name → its properties.
Changes = dict[str, dict[str, Any]]


class LivePage:
    """The live page of the server but its figures: the widgets and the update loop.

    The nine motion sliders (:data:`~prp3.explorer.scene.MOTION_CONTROLS`, with
    their fields), a field per design parameter, the arrows' scale
    (``arrow_scale``, mm/N) and the message ``message``.  Once
    :meth:`connect`-ed, every change of a slider or field recomputes the page
    in Python (``compute(state)``: prp3's engines) and sends what changed
    (:class:`Bundle`); a refused pose shows ``blank(state)`` (nothing that
    belongs to it) and the library's one-line message.

    Parameters
    ----------
    doc : bokeh.document.Document
        The document filled.
    limits : callable
        ``limits(control)``: the range ``(low, high)`` of a motion slider.
    motion : Motion or None
        A run's platform motion: the sliders' ranges are widened to hold it.
    design : mapping of str to (str, str)
        The design parameters: key → (label, unit).
    values : mapping of str to float
        Their values.
    scale : float
        The arrows' length per newton (m/N), :attr:`scale`.
    """

    def __init__(
        self,
        doc: Any,
        limits: Callable[[MotionControl], tuple[float, float]],
        motion: Motion | None,
        design: Mapping[str, tuple[str, str]],
        values: Mapping[str, float],
        scale: float,
    ) -> None:
        from bokeh.models import Div, Spinner

        self.doc = doc
        self.scale = scale
        #: The run's wrench on the platform at the sample shown (``None`` without).
        self.load: tuple[float, float, float] | None = None
        self._busy = False
        self._compute: Callable[[State], Changes] | None = None
        self._blank: Callable[[State], Changes] = lambda state: {}
        self.bundle: Bundle | None = None
        self.message = Div(
            text="", name="message", width=860, styles={"color": "#b00000", "font-weight": "bold"}
        )
        self.sliders: dict[str, Any] = {}
        self.fields: list[Any] = []
        for control in MOTION_CONTROLS:
            low, high = limits(control)
            if motion is not None:
                low, high = widened(low, high, motion, control.name)
            slider, pair = slider_with_field(control, low, high)
            self.sliders[control.name] = slider
            self.fields.append(pair)
        self.design_fields: dict[str, Any] = {
            key: Spinner(
                title=f"{label} ({unit})",
                value=values[key],
                low=0.0,
                step=0.01,
                width=130,
                name=f"design:{key}",
                format="0.[0000]",
            )
            for key, (label, unit) in design.items()
        }
        self.scale_field = Spinner(
            title="arrow scale (mm/N)",
            value=round(scale * 1e3, 4),
            low=1e-6,
            step=0.1,
            width=120,
            name="arrow_scale",
        )

    def state(self) -> State:
        """The state of the sliders, with the run's :attr:`load`."""
        values = State.from_controls({n: float(s.value) for n, s in self.sliders.items()})
        return State(values.pose, values.velocity, values.acceleration, self.load)

    def connect(
        self,
        bundle: Bundle,
        compute: Callable[[State], Changes],
        blank: Callable[[State], Changes],
        redesign: Callable[[Mapping[str, float]], None],
    ) -> None:
        """Recompute the page at every change: ``compute(state)`` raises the library's error
        for a refused pose, ``redesign(values)`` takes the design fields' values (and may
        refuse them, too)."""
        self.bundle = bundle
        self._compute, self._blank = compute, blank

        def on_design(attr: str, old: Any, new: Any) -> None:
            fields = self.design_fields.items()
            try:
                redesign({k: float(f.value) for k, f in fields if f.value is not None})
            except Prp3Error as error:
                self.refuse(error)
                return
            self.update()

        def on_scale(attr: str, old: Any, new: Any) -> None:
            if new is not None and float(new) > 0.0:
                self.scale = float(new) * 1e-3
                self.update()

        for slider in self.sliders.values():
            slider.on_change("value", lambda attr, old, new: self.update())
        for field in self.design_fields.values():
            field.on_change("value", on_design)
        self.scale_field.on_change("value", on_scale)

    def update(self) -> None:
        """Recompute the page at the sliders' state and send what changed (one message)."""
        if self._busy or self._compute is None or self.bundle is None:
            return
        state = self.state()
        self.doc.hold("combine")  # every change of this update reaches the browser at once
        try:
            try:
                changes = self._compute(state)
            except Prp3Error as error:
                self.refuse(error, state)
                return
            self.bundle.send({**changes, "message": {"text": ""}})
        finally:
            self.doc.unhold()

    def refuse(self, error: Prp3Error, state: State | None = None) -> None:
        """Draw nothing that belongs to the refused pose, and say why (the library's line)."""
        assert self.bundle is not None
        blank = self._blank(self.state() if state is None else state)
        self.bundle.send({**blank, "message": {"text": _escape(str(error))}})

    def show_sample(self, motion: Motion, k: int) -> None:
        """Set the nine motion sliders (and the load) to sample ``k`` of a run, then update once."""
        values = np.concatenate([motion.pose[k], motion.velocity[k], motion.acceleration[k]])
        load = motion.load
        self.load = (
            None if load is None else (float(load[k, 0]), float(load[k, 1]), float(load[k, 2]))
        )
        self._busy = True
        try:
            for name, value in zip(self.sliders, values, strict=True):
                self.sliders[name].value = float(value)
        finally:
            self._busy = False
        self.update()

    def start(
        self,
        title: str,
        figure: Any,
        below: Sequence[Any],
        right: Sequence[Any],
        design: Any,
        scrubber: Any = None,
    ) -> None:
        """Lay the page out and add it to the document, draw the sliders' state, then send
        every later change in the bundle.

        Above, the run's ``scrubber`` (if any) and the message; then the robot's
        ``figure`` with what goes ``below`` it, the motion sliders, and the column
        ``right``; the ``design`` widgets last.
        """
        from bokeh.layouts import column, row
        from bokeh.models import Div

        assert self.bundle is not None
        controls = column(
            Div(text="<b>platform pose, velocity, acceleration</b>"), *self.fields, width=300
        )
        top = [self.message] if scrubber is None else [scrubber, self.message]
        middle = row(column(figure, *below), controls, column(*right))
        self.doc.add_root(column(*top, middle, design))
        self.doc.add_root(self.bundle.source)  # drawn by nothing: a root, to reach the browser
        self.doc.title = title
        self.update()
        for pair in self.fields:  # a slider set before the page is served: its field shows it
            slider, field = pair.children
            field.value = slider.value
        self.bundle.served = True
