"""The update loop of the explorer's live pages: recompute in Python, send what changed at once.

:class:`LivePage` holds the widgets of a live page of the server but its
figures (the motion sliders, the design fields, the arrows' scale, the
message) and recomputes the page with prp3's engines at every change;
:class:`Bundle` sends what an update changed to the browser in one message.
Both pages (:mod:`prp3.explorer.app`, :mod:`prp3.explorer.family_app`) use
them.  Bokeh is imported inside the functions only.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from prp3.errors import Prp3Error
from prp3.explorer.page import REDRAW_TABLES, escape, slider_with_field
from prp3.explorer.scene import (
    MOTION_CONTROLS,
    MotionControl,
    State,
    View,
    empty_view,
    signed_design_key,
)
from prp3.explorer.scrubber import server_scrubber, time_plots
from prp3.model.motion import Motion

__all__ = ["Bundle", "Changes", "LivePage", "refused", "widened"]

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
                low=None if signed_design_key(key) else 0.0,
                step=0.01,
                width=130,
                name=f"design:{key}",
                format="0.[000000]",
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
        self.bundle.send({**blank, "message": {"text": escape(str(error))}})

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

    def run_widgets(
        self, run: Mapping[str, Any], titles: Mapping[str, str], motion: Motion
    ) -> tuple[Any, Any]:
        """A run's plots against time (the per-leg quantities ``titles`` names, of the run's
        table ``run``), and its scrubber, which shows the run's sample at each of its steps
        (:meth:`show_sample`; the first one at once)."""
        from bokeh.layouts import column

        plots, spans = time_plots(run, titles)
        times = [float(v) for v in motion.t]
        return column(*plots), server_scrubber(
            self.doc, times, lambda k: self.show_sample(motion, k), spans
        )

    def start(
        self,
        title: str,
        figure: Any,
        below: Sequence[Any],
        info: str,
        right: Sequence[Any],
        design: Sequence[Any],
        scrubber: Any = None,
    ) -> None:
        """Lay the page out and add it to the document, draw the sliders' state, then send
        every later change in the bundle.

        Above, the run's ``scrubber`` (if any) and the message; then the robot's
        ``figure`` with what goes ``below`` it and the line ``info``, the motion
        sliders, and the column ``right``; the ``design`` widgets last, under their
        title (their first item).
        """
        from bokeh.layouts import column, row
        from bokeh.models import Div

        assert self.bundle is not None
        note = Div(text=info, width=500, styles={"font-size": "9pt", "color": "#444"})
        controls = column(
            Div(text="<b>platform pose, velocity, acceleration</b>"), *self.fields, width=300
        )
        top = [self.message] if scrubber is None else [scrubber, self.message]
        middle = row(column(figure, *below, note), controls, column(*right))
        self.doc.add_root(column(*top, middle, column(Div(text=design[0]), *design[1:])))
        self.doc.add_root(self.bundle.source)  # drawn by nothing: a root, to reach the browser
        self.doc.title = title
        self.update()
        for pair in self.fields:  # a slider set before the page is served: its field shows it
            slider, field = pair.children
            field.value = slider.value
        self.bundle.served = True


def refused(like: View) -> Changes:
    """What a page draws while its pose is refused: every source of ``like`` empty, but the
    fixed base (no stale picture)."""
    return {name: columns for name, columns in empty_view(like).sources().items() if name != "base"}
