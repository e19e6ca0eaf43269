"""The figure of an identification: measured and fitted actuator forces against time.

One panel per leg (A, B, C) with the measured ``f10`` and the forces of the
identified base parameters on top of each other, and a bottom panel with the
residuals ``measured − fitted`` of the three legs.

>>> IDENTIFICATION_FIGURE
'identification.png'
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..geometry import LEGS
from .control import scaled_unit
from .figures import LEG_STYLES

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["IDENTIFICATION_FIGURE", "identification_figure"]

#: File name of the figure ``prp3 identify`` writes.
IDENTIFICATION_FIGURE: str = "identification.png"


def identification_figure(
    t: ArrayLike, measured: ArrayLike, fitted: ArrayLike, *, title: str, subtitle: str = ""
) -> Figure:
    """Measured and fitted ``f10`` of legs A, B, C, and the residuals.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times (s), ``N >= 2``.
    measured, fitted : array_like, shape (N, 3)
        Forces (N).
    title, subtitle : str
        Figure title and a smaller line under it.

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot; save it with :func:`prp3.plotting.figures.save_figure`.
    """
    from matplotlib.figure import Figure

    time = np.asarray(t, dtype=np.float64)
    data = np.asarray(measured, dtype=np.float64)
    model = np.asarray(fitted, dtype=np.float64)
    figure = Figure(figsize=(8.0, 8.4), dpi=120, layout="constrained")
    axes = figure.subplots(4, 1, sharex=True, height_ratios=(1.0, 1.0, 1.0, 0.8))
    for leg, ax in enumerate(axes[:3]):
        color, _ = LEG_STYLES[LEGS[leg]]
        ax.plot(time, data[:, leg], color="0.55", linewidth=2.6, label="measured")
        ax.plot(time, model[:, leg], color=color, linestyle="--", linewidth=1.4, label="fitted")
        ax.set_ylabel(f"$f_{{10}}^{LEGS[leg]}$ (N)")
    residual = data - model
    scale, unit = scaled_unit(float(np.abs(residual).max()), "N")
    for leg in range(3):
        color, style = LEG_STYLES[LEGS[leg]]
        axes[3].plot(
            time,
            residual[:, leg] / scale,
            color=color,
            linestyle=style,
            linewidth=1.0,
            label=f"leg {LEGS[leg]}",
        )
    axes[3].set_ylabel(f"measured − fitted ({unit})")
    axes[3].set_xlabel("time $t$ (s)")
    axes[3].set_xlim(float(time[0]), float(time[-1]))
    axes[3].axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
    for ax in axes:
        ax.grid(True, color="0.88")
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    figure.suptitle(title, fontsize=12, fontweight="bold")
    if subtitle:
        axes[0].set_title(subtitle, fontsize=10, color="0.3")
    return figure
