"""The figure of an identification: measured and fitted actuator forces against time.

For each leg (A, B, C) a panel with the measured ``f10`` and the forces of
the identified base parameters on top of each other, and under it a thin
panel of that leg's residual ``measured − fitted`` with its RMS (the three
legs' residuals share one scale, so that their sizes compare).

>>> IDENTIFICATION_FIGURE
'identification.png'
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from prp3.plotting.control import scaled_unit
from prp3.plotting.figures import LEG_STYLES
from prp3.validation import LEGS

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
    figure = Figure(figsize=(8.0, 9.6), dpi=120, layout="constrained")
    axes = figure.subplots(6, 1, sharex=True, height_ratios=(1.0, 0.55) * 3)
    residual = data - model
    scale, unit = scaled_unit(float(np.abs(residual).max()), "N")
    bound = 1.1 * float(np.abs(residual).max()) / scale
    for leg in range(3):
        color, _ = LEG_STYLES[LEGS[leg]]
        forces, error = axes[2 * leg], axes[2 * leg + 1]
        forces.plot(time, data[:, leg], color="0.55", linewidth=2.6, label="measured")
        forces.plot(time, model[:, leg], color=color, linestyle="--", linewidth=1.4, label="fitted")
        forces.set_ylabel(f"$f_{{10}}^{LEGS[leg]}$ (N)")
        forces.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
        rms = float(np.sqrt(np.mean(residual[:, leg] ** 2)))
        error.plot(time, residual[:, leg] / scale, color=color, linewidth=0.8,
                   label=f"residual {LEGS[leg]}\nRMS {rms / scale:.3g} {unit}")  # fmt: skip
        error.axhline(0.0, color="0.45", linewidth=0.8, zorder=3)
        error.set_ylim(-bound, bound)
        error.set_ylabel(f"residual\n({unit})")
        error.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False,
                     handlelength=1.2)  # fmt: skip
    axes[-1].set_xlabel("time $t$ (s)")
    axes[-1].set_xlim(float(time[0]), float(time[-1]))
    for ax in axes:
        ax.grid(True, color="0.88")
    figure.suptitle(title, fontsize=12, fontweight="bold")
    if subtitle:
        axes[0].set_title(subtitle, fontsize=10, color="0.3")
    return figure
