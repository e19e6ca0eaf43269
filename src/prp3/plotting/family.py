"""Figures of a family robot's run (docs/family.md): actuator efforts and powers, every joint force.

Built from the 64 columns of a family-form ``results.csv``
(:data:`prp3.family.FAMILY_COLUMNS`); matplotlib is imported inside the
functions only, figures rendered by Agg without pyplot.

>>> family_figure_names()
('tau.png', 'power.png', 'joint_forces.png')
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..validation import LEGS
from .figures import LEG_MARKERS, LEG_STYLES, leg_figure, motion_description

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["family_figure_names", "family_figures", "joint_forces_figure"]

FloatArray = NDArray[np.float64]


def family_figure_names() -> tuple[str, ...]:
    """The PNG files ``prp3 simulate --plots`` writes for a family robot."""
    return ("tau.png", "power.png", "joint_forces.png")


def _legs(table: Mapping[str, FloatArray], column: str) -> FloatArray:
    return np.stack([np.asarray(table[f"{column}_{leg}"], dtype=np.float64) for leg in LEGS], -1)


def joint_forces_figure(
    table: Mapping[str, FloatArray], *, title: str, subtitle: str, types: str, actuated: int
) -> Figure:
    """Every joint force: rows ``fx``, ``fy`` (N) and ``m`` (N·m), one column per joint, 3 legs each.

    The moment of a passive revolute joint is zero by definition (docs/family.md
    §7): its axes say so instead of drawing round-off.
    """
    from matplotlib.figure import Figure

    t = np.asarray(table["t"], dtype=np.float64)
    figure = Figure(figsize=(12.0, 8.0), dpi=110, layout="constrained")
    axes = figure.subplots(3, 3, sharex=True)
    rows = (("fx", "$f_x$ (N)"), ("fy", "$f_y$ (N)"), ("m", "$m$ about $O_k$ (N·m)"))
    step = max(len(t) // 10, 1)
    for k in range(3):
        for r, (name, label) in enumerate(rows):
            ax = axes[r, k]
            if name == "m" and types[k] == "R" and k != actuated - 1:
                ax.text(
                    0.5,
                    0.5,
                    "$m = 0$: a passive revolute joint\ntransmits no moment",
                    ha="center",
                    va="center",
                    transform=ax.transAxes,
                    color="0.35",
                )
                ax.set_yticks([])
                if k == 0:
                    ax.set_ylabel(label)
                ax.set_xlabel("time $t$ (s)")
                continue
            values = _legs(table, f"{name}{k + 1}")
            for j, leg in enumerate(LEGS):
                color, style = LEG_STYLES[leg]
                ax.plot(
                    t,
                    values[:, j],
                    color=color,
                    linestyle=style,
                    linewidth=1.6,
                    marker=LEG_MARKERS[leg],
                    markersize=4,
                    markevery=(j * step // 3, step),
                    label=f"leg {leg}",
                )
            ax.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
            ax.grid(True, color="0.88")
            ax.set_xlim(float(t[0]), float(t[-1]))
            if r == 0:
                ax.set_title(f"joint {k + 1} ({types[k]})", fontsize=11)
            if k == 0:
                ax.set_ylabel(label)
            if r == 2:
                ax.set_xlabel("time $t$ (s)")
    axes[0, 2].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    figure.suptitle(
        f"{title}\n{subtitle}: force of the proximal on the distal body through each joint",
        fontsize=12,
    )
    return figure


def family_figures(
    table: Mapping[str, FloatArray],
    *,
    architecture: str,
    actuated: int,
    motion: str | None = None,
    source: str | None = None,
) -> dict[str, Figure]:
    """The figures of a family run: ``tau.png``, ``power.png``, ``joint_forces.png``.

    Parameters
    ----------
    table : mapping
        The 64 family columns (``(N,)`` arrays).
    architecture : str
        ``"3-RRR"`` ...; ``actuated`` its driven joint (1..3).
    motion, source : str, optional
        The paper motion's name, or the trajectory file, for the subtitles.
    """
    t = np.asarray(table["t"], dtype=np.float64)
    types = architecture[2:]
    kind = types[actuated - 1]
    unit = "N" if kind == "P" else "N·m"
    what = motion_description(motion, source)
    joint = f"joint {actuated} ({'prismatic' if kind == 'P' else 'revolute'})"
    return {
        "tau.png": leg_figure(
            t,
            _legs(table, "tau"),
            title=f"{architecture}: actuator effort",
            ylabel=f"$\\tau$ ({unit})",
            subtitle=f"{what}; actuated {joint}",
            symbol="\\tau",
        ),
        "power.png": leg_figure(
            t,
            _legs(table, "p"),
            title=f"{architecture}: actuator power",
            ylabel="$p = \\tau\\,\\dot q_a$ (W)",
            subtitle=f"{what}; actuated {joint}",
            symbol="p",
        ),
        "joint_forces.png": joint_forces_figure(
            table,
            title=f"{architecture}: every joint force",
            subtitle=what,
            types=types,
            actuated=actuated,
        ),
    }
