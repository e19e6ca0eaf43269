"""Maps of a spatial robot's workspace slice (docs/spatial.md §17).

``workspace.png``: three panels over the grid of
:func:`prp3.spatial.workspace.spatial_workspace` — where the robot reaches and
why not (regular, reachable near a singularity, a P beyond its stroke, a joint
beyond its limit, no closure, not a pose of its degrees of freedom), the
smallest serial measure over the legs and the parallel measure.  Each measure is
drawn divided by its value at home (so the working mode's side is positive,
blue, and home is 1) wherever the legs close, the reachable region's border
dashed and the singular locus ``μ = 0`` solid black.  ``statics.png``: the
largest and the smallest actuator effort over the legs and the largest ``|τ|``
at rest over the regular points (grey elsewhere).  matplotlib is imported
inside the functions only (Agg, no pyplot).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from prp3.errors import ParameterError
from prp3.files import atomic_path
from prp3.plotting.workspace import effort_panel, grey_points

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from prp3.spatial.workspace import SpatialWorkspace

__all__ = [
    "save_spatial_statics_map",
    "save_spatial_workspace_map",
    "spatial_statics_figure",
    "spatial_workspace_figure",
]

#: The colours of the reachability panel: regular, near-singular, then reasons 2, 3, 1, 4.
_CLASSES = (
    ("regular: every measure on its home side", (0.55, 0.75, 0.9, 1.0)),
    ("reachable, a measure below 1e-4 × its home sign", (0.95, 0.6, 0.35, 1.0)),
    ("a P beyond its stroke", (0.82, 0.82, 0.82, 1.0)),
    ("an R, U or S beyond its limit", (0.62, 0.62, 0.62, 1.0)),
    ("a leg cannot close (too far)", (0.35, 0.35, 0.35, 1.0)),
    ("not a pose of the robot's DOF", (0.75, 0.6, 0.85, 1.0)),
)


def _label(name: str) -> str:
    return f"{name} (rad)" if name in ("roll", "pitch", "yaw") else f"{name} (m)"


def _frame(ax: Axes, ws: SpatialWorkspace) -> None:
    """A map panel's frame: the home pose's coordinates marked ``+``, the grid's window."""
    first, second = ws.axes
    home = {"x": 0, "y": 1, "z": 2}
    if ws.plane == "rp":
        ax.plot(0.0, 0.0, marker="+", color="black", markersize=9)
    else:
        centre = ws.robot.home_position
        ax.plot(centre[home[first]], centre[home[second]], marker="+", color="black",
                markersize=9)  # fmt: skip
        ax.set_aspect("equal")
    ax.set_xlim(ws.u[0], ws.u[-1])
    ax.set_ylim(ws.v[0], ws.v[-1])
    ax.set_xlabel(_label(first))
    ax.set_ylabel(_label(second))


def _border(ax: Axes, ws: SpatialWorkspace) -> None:
    reachable = ws.reachable.astype(np.float64)
    if 0.0 < reachable.mean() < 1.0:
        ax.contour(ws.u, ws.v, reachable, levels=[0.5], colors="black", linewidths=0.9,
                   linestyles="dashed")  # fmt: skip


def _measure_panel(
    figure: Figure, ax: Axes, ws: SpatialWorkspace, values: np.ndarray, home: float, title: str
) -> None:
    ratio = values / home
    grey_points(ax, ws.u, ws.v, np.isfinite(ratio))
    finite = ratio[np.isfinite(ratio)]
    bound = max(float(np.abs(finite).max()) if finite.size else 1.0, 1.0)
    mesh = ax.pcolormesh(ws.u, ws.v, np.ma.masked_invalid(ratio), cmap="RdBu", vmin=-bound,
                         vmax=bound, shading="nearest")  # fmt: skip
    if finite.size and finite.min() < 0.0 < finite.max():
        ax.contour(ws.u, ws.v, ratio, levels=[0.0], colors="black", linewidths=1.2)
    _border(ax, ws)
    _frame(ax, ws)
    ax.set_title(title, fontsize=9)
    figure.colorbar(mesh, ax=ax, shrink=0.85, label="measure / its value at home")


def _where(ws: SpatialWorkspace) -> str:
    if ws.plane == "rp":
        return f"roll-pitch plane at z = {ws.offset:.4g} m, yaw = {ws.rpy[2]:.4g} rad"
    from prp3.spatial.workspace import SPATIAL_PLANES

    first, second, third = SPATIAL_PLANES[ws.plane]
    rpy = ", ".join(f"{v:.3g}" for v in ws.rpy)
    return f"{first}{second} plane at {third} = {ws.offset:.4g} m, rpy = ({rpy}) rad"


def spatial_workspace_figure(ws: SpatialWorkspace) -> Figure:
    """The reachability map and both singularity maps of the slice ``ws``.

    Parameters
    ----------
    ws : SpatialWorkspace
        From :func:`prp3.spatial.workspace.spatial_workspace`.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    figure = Figure(figsize=(15.0, 6.0), layout="constrained")
    axes = figure.subplots(1, 3)
    ax = axes[0]
    regular = ws.regular
    shade = np.select(
        [regular, ws.reachable, ws.reason == 2, ws.reason == 3, ws.reason == 1],
        [0.0, 1.0, 2.0, 3.0, 4.0],
        5.0,
    )
    colours = ListedColormap([colour for _, colour in _CLASSES])
    ax.pcolormesh(ws.u, ws.v, shade, cmap=colours, vmin=-0.5, vmax=5.5, shading="nearest")
    _frame(ax, ws)
    counts = [int((shade == k).sum()) for k in range(len(_CLASSES))]
    ax.set_title(
        f"where the legs reach: {int(ws.reachable.sum())} of {ws.reason.size} points\n"
        f"(regular {counts[0]})",
        fontsize=9,
    )
    ax.legend(
        handles=[
            Patch(facecolor=colour, label=f"{label} ({count})")
            for (label, colour), count in zip(_CLASSES, counts, strict=True)
            if count
        ],
        loc="upper center", bbox_to_anchor=(0.5, -0.13), fontsize=7, frameon=False,
    )  # fmt: skip
    signed = ws.mu_leg / np.sign(ws.home_leg)
    smallest = np.where(np.isfinite(signed).all(axis=-1), signed.min(axis=-1), np.nan)
    home_min = float((ws.home_leg / np.sign(ws.home_leg)).min())
    _measure_panel(
        figure, axes[1], ws, smallest, home_min,
        f"serial: min over legs of μ_leg·sign, ÷ {home_min:.3g}\n"
        "black: μ_leg = 0, dashed: reach border",
    )  # fmt: skip
    _measure_panel(
        figure, axes[2], ws, ws.mu_par, ws.home_par,
        f"parallel: μ_par ÷ ({ws.home_par:+.3g}, at home)\n"
        "black: μ_par = 0, dashed: reach border",
    )  # fmt: skip
    figure.suptitle(f"{ws.robot.name}: workspace slice, {_where(ws)}", fontsize=12)
    return figure


def save_spatial_workspace_map(path: str | Path, ws: SpatialWorkspace) -> Path:
    """Write :func:`spatial_workspace_figure` as a PNG, atomically."""
    path = Path(path)
    with atomic_path(path) as temporary:
        spatial_workspace_figure(ws).savefig(temporary, format="png")
    return path


def spatial_statics_figure(ws: SpatialWorkspace) -> Figure:
    """The actuator efforts at rest over the regular points of ``ws`` (computed with statics).

    Three panels: the largest and the smallest ``τ`` over the legs (one diverging scale
    centred on 0) and the largest ``|τ|``.
    """
    from matplotlib.figure import Figure

    if ws.tau is None:
        raise ParameterError("ws has no efforts: compute it with statics=True", key="ws")
    tau = ws.tau
    regular = ws.regular
    largest = np.where(regular, np.max(np.where(regular[..., None], tau, -np.inf), axis=-1), np.nan)
    smallest = np.where(regular, np.min(np.where(regular[..., None], tau, np.inf), axis=-1), np.nan)
    peak = np.where(regular, np.maximum(np.abs(largest), np.abs(smallest)), np.nan)
    finite = peak[np.isfinite(peak)]
    bound = float(finite.max()) if finite.size and finite.max() > 0.0 else 1.0
    unit = ws.unit
    figure = Figure(figsize=(15.0, 5.2), layout="constrained")
    axes = figure.subplots(1, 3)
    panels = (
        (largest, ("RdBu", -bound, bound), f"largest tau over the legs ({unit})"),
        (smallest, ("RdBu", -bound, bound), f"smallest tau over the legs ({unit})"),
        (peak, ("viridis", 0.0, bound), f"largest |tau| over the legs ({unit})"),
    )
    for ax, (values, scale, title) in zip(axes, panels, strict=True):
        effort_panel(figure, ax, (ws.u, ws.v, regular), values, scale, unit)
        _frame(ax, ws)
        ax.set_title(title, fontsize=9)
    figure.suptitle(
        f"{ws.robot.name}: actuator efforts holding the robot at rest (its weight), "
        f"{_where(ws)}; grey: not regular",
        fontsize=11,
    )
    return figure


def save_spatial_statics_map(path: str | Path, ws: SpatialWorkspace) -> Path:
    """Write :func:`spatial_statics_figure` as a PNG, atomically."""
    path = Path(path)
    with atomic_path(path) as temporary:
        spatial_statics_figure(ws).savefig(temporary, format="png")
    return path
