"""Figures of a simulation: one PNG per quantity, legs A, B, C against time.

The paper's section 3 shows, for each of its two motions, the input powers
``p10`` (Figs. 3 and 6) and the internal joint forces ``f21y`` (Figs. 4 and 7)
and ``f21z`` (Figs. 5 and 8) of the three legs against time.  prp3 draws these
and also the actuator forces ``f10`` and displacements ``λ10``.

The figures are built from the columns of ``results.csv``
(:data:`prp3.io.results.RESULT_COLUMNS`, a mapping ``name -> (N,)``), so they can
be drawn from a run in memory or from a file read back.  matplotlib is
imported inside the functions only, and the figures are
:class:`matplotlib.figure.Figure` objects rendered by Agg, without pyplot.

With a robot's ``[friction]`` (the columns ``fric10_L, fric21_L, fric32_L``
in the table) one more figure, ``friction.png`` (:func:`friction_figure`):
the friction forces of the three kinds of joint, one axes each.

>>> figure_names("vertical")["p10"], figure_names("rotation")["f21z"], figure_names(None)["f10"]
('fig3_p10.png', 'fig8_f21z.png', 'f10.png')
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from prp3.drawing import LEG_COLOURS
from prp3.files import atomic_path
from prp3.io.results import OUTPUT_QUANTITIES
from prp3.validation import LEGS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "FRICTION_FIGURE",
    "FRICTION_QUANTITIES",
    "LEG_MARKERS",
    "LEG_STYLES",
    "PAPER_FIGURES",
    "QUANTITIES",
    "Quantity",
    "coinciding_legs",
    "figure_names",
    "friction_figure",
    "leg_figure",
    "motion_description",
    "results_figures",
    "save_figure",
    "save_figures",
]

FloatArray = NDArray[np.float64]

#: Colour (:data:`prp3.drawing.LEG_COLOURS`) and line style of each leg's curve (distinct in
#: grey too).
LEG_STYLES: dict[str, tuple[str, str]] = {
    leg: (LEG_COLOURS[leg], style) for leg, style in zip(LEGS, ("-", "--", "-."), strict=True)
}


@dataclass(frozen=True)
class Quantity:
    """A per-leg column of ``results.csv`` as a figure shows it.

    Attributes
    ----------
    column : str
        Column prefix in ``results.csv`` (``"p10"`` for ``p10_A, p10_B, p10_C``).
    caption : str
        What the curves are, in the words of the paper's captions.
    symbol : str
        Symbol in matplotlib mathtext, without the leg superscript.
    unit : str
        Unit of the plotted values.
    scale : float
        Factor from the SI value in the column to the plotted value.
    """

    column: str
    caption: str
    symbol: str
    unit: str
    scale: float = 1.0


#: The quantities drawn by :func:`results_figures`, in the order they are written.
def _plotted(column: str, caption: str, unit: str | None = None, scale: float = 1.0) -> Quantity:
    """A quantity of :data:`prp3.io.results.OUTPUT_QUANTITIES` as plotted.

    Its symbol and unit come from there; or ``unit``, ``scale`` times the SI value.
    """
    quantity = OUTPUT_QUANTITIES[column]
    return Quantity(column, caption, quantity.symbol, unit or quantity.unit, scale)


QUANTITIES: dict[str, Quantity] = {
    "p10": _plotted("p10", "Powers of the three actuators"),
    "f21y": _plotted("f21y", "Internal joint forces"),
    "f21z": _plotted("f21z", "Internal joint forces"),
    "f10": _plotted("f10", "Forces of the three actuators"),
    "lambda10": _plotted("lambda10", "Displacements of the three actuators", "mm", 1e3),
}

#: The friction columns drawn by :func:`friction_figure`, top to bottom.
FRICTION_QUANTITIES: dict[str, Quantity] = {
    "fric10": _plotted("fric10", "actuator guide: force of the base on piston $i$ along $e_i$"),
    "fric21": _plotted("fric21", "revolute joint: moment of piston $i$ on link 2"),
    "fric32": _plotted("fric32", "sleeve: force of link 2 on the platform along $d_i$"),
}

#: File name of the friction figure.
FRICTION_FIGURE: str = "friction.png"

#: Figure numbers of the paper's section 3 for its two motions.
PAPER_FIGURES: dict[str, dict[str, int]] = {
    "vertical": {"p10": 3, "f21y": 4, "f21z": 5},
    "rotation": {"p10": 6, "f21y": 7, "f21z": 8},
}

_DESCRIPTIONS: dict[str, str] = {
    "vertical": "vertical motion: $y = 0.025\\,(1-\\cos \\pi t/3)$ m, $x = \\varphi = 0$",
    "rotation": "rotation: $\\varphi = (\\pi/12)\\,(1-\\cos \\pi t/3)$ rad, $x = y = 0$",
}


def motion_description(motion: str | None, source: str | None = None) -> str:
    """One line saying which motion a figure shows (mathtext).

    >>> motion_description(None, "path.csv")
    'trajectory path.csv'
    """
    if motion in _DESCRIPTIONS:
        return _DESCRIPTIONS[motion]
    return f"trajectory {source}" if source else "user trajectory"


def figure_names(motion: str | None) -> dict[str, str]:
    """PNG file name of each quantity's figure (``quantity -> name``).

    For the paper's motions the three figures of the paper carry its numbers
    (``fig3_p10.png``, ``fig4_f21y.png``, ...); every other name is the
    quantity's (``f10.png``, ``lambda10.png``, and ``p10.png``, ... for a
    user trajectory).
    """
    numbers = PAPER_FIGURES.get(motion or "", {})
    return {
        name: (f"fig{numbers[name]}_{name}.png" if name in numbers else f"{name}.png")
        for name in QUANTITIES
    }


#: Marker of each leg's curve, so that coinciding curves stay visible.
LEG_MARKERS: dict[str, str] = {"A": "o", "B": "s", "C": "^"}


def coinciding_legs(values: FloatArray, rtol: float = 1e-3) -> list[tuple[str, ...]]:
    """Groups of legs whose curves lie on each other at the scale of the figure.

    Two legs coincide when their values differ by at most ``rtol`` times the
    largest magnitude of the three (about a line width at the figure's size).

    >>> v = np.array([[0.0, 0.0, 1.0], [1.0, 1.0, 2.0]])
    >>> coinciding_legs(v), coinciding_legs(np.ones((2, 3)))
    ([('A', 'B')], [('A', 'B', 'C')])
    """
    scale = float(np.abs(values).max()) if values.size else 0.0
    if scale == 0.0 or not np.isfinite(scale):
        return [tuple(LEGS)] if values.size else []
    groups: list[list[int]] = []
    for j in range(len(LEGS)):
        for group in groups:
            if np.abs(values[:, j] - values[:, group[0]]).max() <= rtol * scale:
                group.append(j)
                break
        else:
            groups.append([j])
    return [tuple(LEGS[j] for j in group) for group in groups if len(group) > 1]


def _plot_legs(axes: Axes, t: FloatArray, values: FloatArray, symbol: str = "") -> str:
    """Draw the three legs' curves on ``axes``; return the note on coinciding curves, or "".

    Each leg has its colour, line style and marker, the markers staggered
    from leg to leg (about 12 per curve), so that curves lying on each other
    stay visible; the note says which ones do.
    """
    step = max(len(t) // 12, 1)
    for j, leg in enumerate(LEGS):
        color, style = LEG_STYLES[leg]
        label = f"leg {leg}" + (f"  ${symbol}^{leg}$" if symbol else "")
        axes.plot(
            t,
            values[:, j],
            color=color,
            linestyle=style,
            linewidth=2.0,
            marker=LEG_MARKERS[leg],
            markersize=6,
            markevery=(j * step // 3, step),
            label=label,
        )
    if values.size and not np.abs(values).max() > 0.0:
        return "zero for every leg (drawn on top of each other; markers staggered)"
    together = coinciding_legs(values)
    if not together:
        return ""
    legs = "; ".join(f"legs {', '.join(group[:-1])} and {group[-1]}" for group in together)
    return f"the curves of {legs} coincide (drawn on top of each other; markers staggered)"


def leg_figure(
    t: FloatArray,
    values: FloatArray,
    *,
    title: str,
    ylabel: str,
    subtitle: str = "",
    symbol: str = "",
) -> Figure:
    """A figure with the three legs' curves of ``values`` against time.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Times (s).
    values : ndarray, shape (N, 3)
        One column per leg A, B, C, already in the unit of ``ylabel``.
    title, ylabel, subtitle : str
        Figure title, y-axis label (with unit) and a smaller second title line.
    symbol : str
        Mathtext symbol for the legend entries (``p_{10}`` gives ``p_{10}^A``);
        plain ``leg A`` when empty.

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot; save it with :func:`save_figure`.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(8.0, 4.6), dpi=120, layout="constrained")
    axes = figure.add_subplot()
    note = _plot_legs(axes, t, values, symbol)
    if note:
        subtitle = (subtitle + "\n" if subtitle else "") + note
    axes.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
    axes.set_xlim(float(t[0]), float(t[-1]))
    axes.set_xlabel("time $t$ (s)")
    axes.set_ylabel(ylabel)
    axes.grid(True, color="0.88")
    axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)  # never over a curve
    figure.suptitle(title, fontsize=12, fontweight="bold")
    if subtitle:
        axes.set_title(subtitle, fontsize=10, color="0.3")
    return figure


def _legs(table: Mapping[str, FloatArray], quantity: Quantity) -> FloatArray:
    """``(N, 3)`` plotted values of a per-leg quantity."""
    return quantity.scale * np.stack(
        [np.asarray(table[f"{quantity.column}_{leg}"], dtype=np.float64) for leg in LEGS], axis=-1
    )


def friction_figure(
    table: Mapping[str, FloatArray],
    *,
    motion: str | None = None,
    source: str | None = None,
) -> Figure:
    """The friction forces of every joint, legs A, B, C against time.

    Three axes sharing the time axis: ``fric10`` (guide on piston along
    ``e_i``, N), ``fric21`` (moment of piston i on link 2, N·m) and ``fric32``
    (link 2 on the platform along ``d_i``, N); signs as in ``results.csv``
    (a friction force opposes its joint's rate).

    Parameters
    ----------
    table : mapping of str to ndarray (N,)
        ``t`` and the columns ``fric10_L, fric21_L, fric32_L`` (``L`` in A, B,
        C) of ``results.csv``; ``N >= 2``.
    motion, source : str or None
        As for :func:`results_figures` (the caption's motion line).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    t = np.asarray(table["t"], dtype=np.float64)
    figure = Figure(figsize=(8.0, 7.2), dpi=120, layout="constrained")
    axes_list = figure.subplots(3, 1, sharex=True)
    for axes, quantity in zip(axes_list, FRICTION_QUANTITIES.values(), strict=True):
        note = _plot_legs(axes, t, _legs(table, quantity))
        axes.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
        axes.set_xlim(float(t[0]), float(t[-1]))
        axes.set_ylabel(f"{quantity.column} ({quantity.unit})")
        axes.set_title(quantity.caption + (f"\n{note}" if note else ""), fontsize=10, loc="left",
                       color="0.3")  # fmt: skip
        axes.grid(True, color="0.88")
        axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    axes_list[-1].set_xlabel("time $t$ (s)")
    figure.suptitle(
        "Friction forces of the joints\n" + motion_description(motion, source),
        fontsize=12,
        fontweight="bold",
    )
    return figure


def results_figures(
    table: Mapping[str, FloatArray],
    *,
    motion: str | None = None,
    source: str | None = None,
) -> dict[str, Figure]:
    """Every figure of a run, by file name (see :func:`figure_names`).

    Parameters
    ----------
    table : mapping of str to ndarray (N,)
        The columns of ``results.csv`` (at least ``t`` and the columns of
        :data:`QUANTITIES` for the three legs); ``N >= 2``.
    motion : {"vertical", "rotation"} or None
        The paper's motion the run is, for the figure numbers and captions.
    source : str or None
        The trajectory file, named in the captions of a user trajectory.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``fig3_p10.png`` (or ``p10.png``), ``..._f21y.png``, ``..._f21z.png``,
        ``f10.png``, ``lambda10.png``; and ``friction.png``
        (:func:`friction_figure`) when the table has the friction columns.
    """
    t = np.asarray(table["t"], dtype=np.float64)
    numbers = PAPER_FIGURES.get(motion or "", {})
    subtitle = motion_description(motion, source)
    figures: dict[str, Figure] = {}
    for name, file_name in figure_names(motion).items():
        quantity = QUANTITIES[name]
        values = quantity.scale * np.stack(
            [np.asarray(table[f"{quantity.column}_{leg}"], dtype=np.float64) for leg in LEGS],
            axis=-1,
        )
        symbols = ", ".join(f"${quantity.symbol}^{leg}$" for leg in LEGS)
        title = f"{quantity.caption} {symbols}"
        if name in numbers:
            title = f"Fig. {numbers[name]}  {title}"
        figures[file_name] = leg_figure(
            t,
            values,
            title=title,
            ylabel=f"${quantity.symbol}$ ({quantity.unit})",
            subtitle=subtitle,
            symbol=quantity.symbol,
        )
    if "fric10_A" in table:
        figures[FRICTION_FIGURE] = friction_figure(table, motion=motion, source=source)
    return figures


def save_figure(figure: Figure, path: str | Path) -> Path:
    """Render ``figure`` as a PNG file at ``path``, atomically (whole or not at all)."""
    path = Path(path)
    with atomic_path(path) as temporary:
        figure.savefig(temporary, format="png")
    return path


def save_figures(
    table: Mapping[str, FloatArray],
    directory: str | Path,
    *,
    motion: str | None = None,
    source: str | None = None,
) -> list[Path]:
    """Write every figure of :func:`results_figures` into ``directory``; return the paths."""
    directory = Path(directory)
    figures = results_figures(table, motion=motion, source=source)
    return [save_figure(figure, directory / name) for name, figure in figures.items()]
