"""The figure of a closed-loop run: tracking errors and actuator forces against time.

Drawn from the columns of ``tracking.csv`` (``t, x, y, phi, x_ref, y_ref,
phi_ref, f10_A, f10_B, f10_C``), so that it can be redrawn from the file.
Three panels share the time axis: the position errors ``x_ref − x`` and
``y_ref − y``, the orientation error ``φ_ref − φ`` (each in the decimal unit
that suits its size) and the forces ``f10`` of legs A, B, C.

>>> scaled_unit(3e-6, "m"), scaled_unit(0.2, "rad"), scaled_unit(0.0, "m")
((1e-06, 'µm'), (0.001, 'mrad'), (1.0, 'm'))
"""

from __future__ import annotations

import textwrap
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from prp3.plotting.figures import LEG_STYLES
from prp3.validation import LEGS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["TRACKING_FIGURE", "scaled_unit", "spatial_tracking_figure", "tracking_figure"]

FloatArray = NDArray[np.float64]

#: File name of the figure ``prp3 control`` writes.
TRACKING_FIGURE: str = "tracking.png"

_PREFIXES = ((1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"), (1e-12, "p"))


def scaled_unit(peak: float, unit: str) -> tuple[float, str]:
    """The decimal multiple of ``unit`` in which ``peak`` reads at least 1 (down to pico)."""
    for scale, prefix in _PREFIXES:
        if abs(peak) >= scale:
            return scale, prefix + unit
    return (_PREFIXES[-1][0], _PREFIXES[-1][1] + unit) if peak else (1.0, unit)


def tracking_figure(
    table: Mapping[str, FloatArray],
    *,
    title: str,
    subtitle: str = "",
    stop: str | None = None,
    end: float | None = None,
) -> Figure:
    """Tracking errors and forces of a closed-loop run (columns of ``tracking.csv``).

    Parameters
    ----------
    table : mapping of str to ndarray (N,)
        ``t, x, y, phi, x_ref, y_ref, phi_ref, f10_A, f10_B, f10_C`` (``tau_A, tau_B,
        tau_C`` of a family robot), ``N >= 2``.
    title, subtitle : str
        Figure title and a smaller line under it (controller, plant, model).
    stop : str, optional
        Why the plant stopped before the end (a run stopped early): its last
        row is marked in every panel by a vertical line, and the reason is
        written under the panels.
    end : float, optional
        The planned end of the motion (s); the time axis runs to it, so that a
        stop before it shows.

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot; save it with :func:`prp3.plotting.figures.save_figure`.
    """
    from matplotlib.figure import Figure

    t = np.asarray(table["t"], dtype=np.float64)
    figure = Figure(figsize=(8.0, 7.6), dpi=120, layout="constrained")
    position, orientation, force = figure.subplots(3, 1, sharex=True)
    _plot_errors(position, orientation, t, table)
    _plot_efforts(force, t, table)
    force.set_xlabel("time $t$ (s)")
    force.set_xlim(float(t[0]), max(float(t[-1]), end if end is not None else float(t[-1])))
    for axes in (position, orientation, force):
        axes.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
        if stop is not None:
            axes.axvline(float(t[-1]), color="k", linestyle=":", linewidth=1.6,
                         label=f"stop (last row, t = {float(t[-1]):.4g} s)")  # fmt: skip
        axes.grid(True, color="0.88")
        axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    if stop is not None:  # in the x label, so that the layout leaves it room
        reason = textwrap.fill("the plant stopped early: " + stop, 80)
        force.set_xlabel(f"time $t$ (s)\n\n{reason}", fontsize=9)
    figure.suptitle(title, fontsize=12, fontweight="bold")
    if subtitle:
        position.set_title(subtitle, fontsize=10, color="0.3")
    return figure


def _plot_errors(
    position: Axes, orientation: Axes, t: FloatArray, table: Mapping[str, FloatArray]
) -> None:
    """The tracking errors ``x_ref − x``, ``y_ref − y`` (one panel) and ``φ_ref − φ`` (the
    other), each in a unit that suits its size."""
    errors = {
        name: np.asarray(table[f"{name}_ref"], dtype=np.float64)
        - np.asarray(table[name], dtype=np.float64)
        for name in ("x", "y", "phi")
    }
    scale, unit = scaled_unit(max(np.abs(errors["x"]).max(), np.abs(errors["y"]).max()), "m")
    position.plot(t, errors["x"] / scale, color="tab:blue", linewidth=1.8, label="$x_{ref} - x$")
    position.plot(
        t,
        errors["y"] / scale,
        color="tab:red",
        linestyle="--",
        linewidth=1.8,
        label="$y_{ref} - y$",
    )
    position.set_ylabel(f"position error ({unit})")
    scale, unit = scaled_unit(float(np.abs(errors["phi"]).max()), "rad")
    orientation.plot(
        t,
        errors["phi"] / scale,
        color="tab:purple",
        linewidth=1.8,
        label="$\\varphi_{ref} - \\varphi$",
    )
    orientation.set_ylabel(f"orientation error ({unit})")


def _plot_efforts(force: Axes, t: FloatArray, table: Mapping[str, FloatArray]) -> None:
    """The legs' actuator forces ``f10`` (the 3-PRP) or efforts ``tau`` (a family robot)."""
    family = "tau_A" in table  # a family robot's efforts (N or N·m: docs/family.md)
    for leg in LEGS:
        color, style = LEG_STYLES[leg]
        force.plot(
            t,
            np.asarray(table[f"tau_{leg}" if family else f"f10_{leg}"], dtype=np.float64),
            color=color,
            linestyle=style,
            linewidth=1.8,
            label=f"leg {leg}  " + (f"$\\tau_{leg}$" if family else f"$f_{{10}}^{leg}$"),
        )
    force.set_ylabel("actuator effort tau (N or N·m)" if family else "actuator force (N)")


def spatial_tracking_figure(
    table: Mapping[str, FloatArray], legs: int, *, title: str, subtitle: str = ""
) -> Figure:
    """Pose error and efforts of a spatial robot's closed-loop run (docs/spatial.md §23).

    ``table``: the columns of the spatial ``tracking.csv`` (``t``, ``e_rx .. e_rz``
    (rad), ``e_x .. e_z`` (m), ``tau_1 .. tau_legs``), ``N >= 2``.  Three panels: the
    rotation error, the position error, the efforts.
    """
    from matplotlib.figure import Figure

    t = np.asarray(table["t"], dtype=np.float64)
    figure = Figure(figsize=(8.0, 7.6), dpi=120, layout="constrained")
    rotation, position, effort = figure.subplots(3, 1, sharex=True)
    for axes, names, unit, what in (
        (rotation, ("e_rx", "e_ry", "e_rz"), "rad", "rotation error log(R_ref R^T)"),
        (position, ("e_x", "e_y", "e_z"), "m", "position error p_ref - p"),
    ):
        values = {n: np.asarray(table[n], dtype=np.float64) for n in names}
        scale, shown = scaled_unit(max(float(np.abs(v).max()) for v in values.values()), unit)
        for (name, value), style in zip(values.items(), ("-", "--", ":"), strict=True):
            axes.plot(t, value / scale, linestyle=style, linewidth=1.8, label=name)
        axes.set_ylabel(f"{what}\n({shown})", fontsize=9)
    for leg in range(1, legs + 1):
        effort.plot(t, np.asarray(table[f"tau_{leg}"], dtype=np.float64), linewidth=1.4,
                    label=f"leg {leg}")  # fmt: skip
    effort.set_ylabel("effort tau (N or N·m)")
    effort.set_xlabel("time $t$ (s)")
    effort.set_xlim(float(t[0]), float(t[-1]))
    for axes in (rotation, position, effort):
        axes.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
        axes.grid(True, color="0.88")
        axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    figure.suptitle(title, fontsize=12, fontweight="bold")
    if subtitle:
        rotation.set_title(subtitle, fontsize=10, color="0.3")
    return figure
