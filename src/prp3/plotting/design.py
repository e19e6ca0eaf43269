"""Figures of a design sweep: a Pareto front and parameter-sensitivity plots.

Both are drawn from the columns of ``designs.parquet``
(:class:`prp3.apps.sweep.DesignTable`): any two columns (or the aggregates
``peak_f10`` … = largest of legs A, B, C) for the Pareto front, one panel per
varied parameter for the sensitivity.  Only the designs whose ``status`` is
``ok`` are drawn; the nominal design (the robot the sweep varies) is marked
with a star.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from prp3.apps.design_objective import pareto_front, quantity

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["LABELS", "label", "pareto_figure", "sensitivity_figure"]

#: Axis labels of the result columns (a key path is labelled by itself).
LABELS: dict[str, str] = {
    "peak_f10": "peak actuator force max |f10| over legs (N)",
    "peak_p10": "peak actuator power max |p10| over legs (W)",
    "peak_f21": "peak revolute joint force max |f21| over legs (N)",
    "peak_n32": "peak sleeve normal force max |n32| over legs (N)",
    "energy": "energy delivered by the actuators over the task (J)",
    "workspace_area": "workspace area at φ = 0 (m²)",
    "max_condition": "worst Jacobian condition number over the task",
    "l0": "l0 (m)",
}


def label(name: str) -> str:
    """Axis label of a column.

    >>> label("peak_f10_A"), label("platform.mass"), label("limits.stroke.1"), label("gravity.1")
    ('peak_f10_A (N)', 'platform.mass (kg)', 'limits.stroke.1 (m)', 'gravity.1')
    """
    if name in LABELS:
        return LABELS[name]
    for prefix, unit in (("peak_f", "N"), ("peak_p", "W"), ("peak_n", "N")):
        if name.startswith(prefix):
            return f"{name} ({unit})"
    last = [part for part in name.split(".") if not part.isdigit()][-1]
    units = {"mass": "kg", "inertia": "kg·m²", "com": "m", "stroke": "m", "viscous": "", "mu": ""}
    return f"{name} ({units[last]})" if units.get(last) else name


def _ok(columns: Mapping[str, Any]) -> np.ndarray:
    return np.asarray(np.asarray(columns["status"]) == "ok")


def pareto_figure(
    columns: Mapping[str, Any],
    x: str,
    y: str,
    *,
    maximize_x: bool = False,
    maximize_y: bool = False,
    nominal: Mapping[str, Any] | None = None,
    marks: Mapping[str, Mapping[str, Any]] | None = None,
    title: str = "",
) -> Figure:
    """Every design as a point of ``(x, y)``, the Pareto front drawn over them.

    Parameters
    ----------
    columns : mapping
        Columns of the design table.
    x, y : str
        Columns or aggregates (:func:`prp3.apps.design_objective.quantity`).
    maximize_x, maximize_y : bool
        Whether larger is better on that axis (default: smaller is better).
    nominal : mapping, optional
        The row of the nominal design, marked with a star.
    marks : mapping of str to mapping, optional
        Other rows to mark (e.g. an optimum), by legend label.
    """
    from matplotlib.figure import Figure

    ok = _ok(columns)
    xs, ys = quantity(columns, x), quantity(columns, y)
    front = pareto_front(
        np.where(ok, xs, np.nan),
        np.where(ok, ys, np.nan),
        maximize_x=maximize_x,
        maximize_y=maximize_y,
    )
    figure = Figure(figsize=(7.5, 5.8), layout="constrained")
    axes = figure.add_subplot()
    axes.scatter(xs[ok], ys[ok], s=6, color="0.6", alpha=0.6, label=f"designs ({int(ok.sum())} ok)")
    axes.plot(
        xs[front], ys[front], "-o", color="tab:blue", markersize=4, lw=1.5,
        label=f"Pareto front ({len(front)})",
    )  # fmt: skip
    shown = ({"nominal design": nominal} if nominal is not None else {}) | dict(marks or {})
    styles = (("*", "tab:red", 14), ("D", "tab:green", 8), ("s", "k", 8), ("^", "tab:purple", 8))
    for (text, row), (marker, colour, size) in zip(shown.items(), styles, strict=False):
        nx, ny = (float(quantity({k: np.array([v]) for k, v in row.items()}, n)[0]) for n in (x, y))
        if np.isfinite(nx) and np.isfinite(ny):
            axes.plot(nx, ny, marker, color=colour, markersize=size, label=text, zorder=5)
    failed = int((~ok).sum())
    if failed:
        axes.plot([], [], " ", label=f"{failed} designs fail the task (not drawn)")
    better = ("larger" if maximize_x else "smaller", "larger" if maximize_y else "smaller")
    axes.set_xlabel(f"{label(x)}  [{better[0]} is better]")
    axes.set_ylabel(f"{label(y)}  [{better[1]} is better]")
    axes.set_title(title or f"Pareto front: {y} against {x}")
    axes.grid(True, alpha=0.3)
    # beside the axes, never over the designs
    figure.legend(*axes.get_legend_handles_labels(), loc="outside lower center", ncols=2,
                  fontsize="small")  # fmt: skip
    return figure


def sensitivity_figure(
    columns: Mapping[str, Any],
    parameters: tuple[str, ...],
    y: str,
    *,
    nominal: Mapping[str, Any] | None = None,
    bins: int = 12,
    title: str = "",
) -> Figure:
    """``y`` against each varied parameter: every design, the binned mean, the nominal design.

    One panel per parameter; the curve is the mean of ``y`` over the designs
    in each of ``bins`` equal intervals of the parameter (the effect of that
    parameter averaged over the others).
    """
    from matplotlib.figure import Figure

    ok = _ok(columns)
    values = quantity(columns, y)
    count = len(parameters)
    ncols = min(count, 3)
    nrows = -(-count // ncols)
    width = max(4.2 * ncols, 6.4)  # one parameter: room for the title
    figure = Figure(figsize=(width, 3.4 * nrows + 0.9), layout="constrained")
    grid = figure.subplots(nrows, ncols, squeeze=False, sharey=True)
    for k, name in enumerate(parameters):
        axes = grid[k // ncols][k % ncols]
        p = quantity(columns, name)
        axes.scatter(p[ok], values[ok], s=5, color="0.6", alpha=0.5)
        if ok.any():
            edges = np.linspace(p[ok].min(), p[ok].max(), bins + 1)
            which = np.clip(np.searchsorted(edges, p[ok], side="right") - 1, 0, bins - 1)
            sums = np.bincount(which, values[ok], minlength=bins)
            counts = np.bincount(which, minlength=bins)
            filled = counts > 0
            centres = 0.5 * (edges[1:] + edges[:-1])
            mean = (f"mean over the other parameters in {bins} bins" if count > 1
                    else f"mean of the designs in {bins} bins")  # fmt: skip
            axes.plot(centres[filled], sums[filled] / counts[filled], "-", color="tab:blue", lw=2,
                      label=mean)  # fmt: skip
        if nominal is not None:
            nx, ny = (
                float(nominal.get(name, np.nan)),
                float(quantity({c: np.array([v]) for c, v in nominal.items()}, y)[0]),
            )
            if np.isfinite(nx):
                axes.axvline(nx, color="tab:red", ls="--", lw=1)
                if np.isfinite(ny):
                    axes.plot(nx, ny, "*", color="tab:red", markersize=12, label="nominal design")
                else:
                    axes.lines[-1].set_label("nominal value")
        axes.set_xlabel(label(name))
        if k % ncols == 0:
            axes.set_ylabel(label(y))
        axes.grid(True, alpha=0.3)
    for k in range(count, nrows * ncols):
        grid[k // ncols][k % ncols].set_visible(False)
    handles, labels = grid[0][0].get_legend_handles_labels()
    if handles:  # under the panels, never over the designs
        figure.legend(handles, labels, loc="outside lower center", ncols=len(handles),
                      fontsize="small")  # fmt: skip
    what = parameters[0] if count == 1 else f"{count} parameters"
    figure.suptitle(title or f"Sensitivity of {y} to {what} ({int(ok.sum())} designs)")
    return figure
