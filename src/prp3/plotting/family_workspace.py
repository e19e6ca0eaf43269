"""The workspace map of a family robot (docs/family.md §6): both singularity measures as maps.

Six panels: the leg measure ``μ_leg`` of legs A, B, C (top), the parallel
measure ``μ_par``, the regular region, and a scan of ``φ`` (bottom).  Each
measure is drawn over the reachable grid points with a diverging colour scale
centred on 0, multiplied by its home sign so that the working mode's side is
positive (blue) and the other side red; its locus ``μ = 0`` is the black
contour.  Unreachable points are grey, as in :mod:`prp3.plotting.workspace`.
matplotlib is imported inside the functions only (Agg, no pyplot).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from prp3.files import atomic_path
from prp3.plotting.workspace import cm_grey, effort_panel, grey_points
from prp3.validation import LEGS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from prp3.family.workspace import FamilyOrientationScan, FamilyStatics, FamilyWorkspace

__all__ = [
    "family_statics_figure",
    "family_workspace_figure",
    "save_family_statics_map",
    "save_family_workspace_map",
]


def _map_axes(ax: Axes, ws: FamilyWorkspace) -> None:
    """A map panel's frame: the centre marked ``+``, equal axes over the grid, in metres."""
    ax.plot(0.0, 0.0, marker="+", color="black", markersize=9)
    ax.set_aspect("equal")
    ax.set_xlim(ws.x[0], ws.x[-1])
    ax.set_ylim(ws.y[0], ws.y[-1])
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _measure_panel(
    figure: Figure,
    ax: Axes,
    ws: FamilyWorkspace,
    values: np.ndarray,
    sign: float,
    title: str,
) -> None:
    grey_points(ax, ws.x, ws.y, ws.reachable)
    signed = np.ma.masked_invalid(sign * values)
    mesh = ax.pcolormesh(ws.x, ws.y, signed, cmap="RdBu", vmin=-1.0, vmax=1.0, shading="nearest")
    if np.isfinite(values).any() and np.nanmin(signed) < 0.0 < np.nanmax(signed):
        ax.contour(ws.x, ws.y, np.ma.filled(signed, np.nan), levels=[0.0], colors="black",
                   linewidths=1.2)  # fmt: skip
    _map_axes(ax, ws)
    ax.set_title(title, fontsize=9)
    figure.colorbar(mesh, ax=ax, shrink=0.85, label="measure × its home sign")


def family_workspace_figure(
    ws: FamilyWorkspace, scan: FamilyOrientationScan | None = None
) -> Figure:
    """The map of the slice ``ws`` (and of the φ-scan ``scan`` when given).

    Parameters
    ----------
    ws : FamilyWorkspace
        From :func:`prp3.family.workspace.family_workspace_slice`.
    scan : FamilyOrientationScan, optional
        From :func:`prp3.family.workspace.family_orientation_scan` on the same grid.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    robot = ws.robot
    home_leg, home_par = robot.home_measures
    figure = Figure(figsize=(15.0, 9.6), layout="constrained")
    axes = figure.subplots(2, 3)
    for j, leg in enumerate(LEGS):
        _measure_panel(
            figure, axes[0, j], ws, ws.mu_leg[..., j], math.copysign(1.0, home_leg[j]),
            f"μ_leg of leg {leg} (home {home_leg[j]:+.3g}); black: μ_leg = 0",
        )  # fmt: skip
    _measure_panel(
        figure, axes[1, 0], ws, ws.mu_par, math.copysign(1.0, home_par),
        f"μ_par (home {home_par:+.3g}); black: μ_par = 0",
    )  # fmt: skip
    ax = axes[1, 1]
    shade = np.where(ws.regular, 2.0, np.where(ws.reachable, 1.0, 0.0))
    colours = ListedColormap([cm_grey(), (0.95, 0.75, 0.6, 1.0), (0.55, 0.75, 0.9, 1.0)])
    ax.pcolormesh(ws.x, ws.y, shade, cmap=colours, vmin=-0.5, vmax=2.5, shading="nearest")
    _map_axes(ax, ws)
    ax.set_title(
        f"regular region: {ws.regular_area:.4g} m² (reachable {ws.area:.4g} m², grid counts)",
        fontsize=9,
    )
    ax.legend(
        handles=[
            Patch(facecolor=(0.55, 0.75, 0.9), label="regular: every measure on its home side"),
            Patch(facecolor=(0.95, 0.75, 0.6), label="reachable, a measure on the other side"),
            Patch(facecolor=cm_grey(), label="a leg cannot reach"),
        ],
        loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=7, frameon=False,
    )  # fmt: skip
    ax = axes[1, 2]
    if scan is not None:
        ax.plot(scan.phi, scan.area, color="0.4", label="reachable area (grid)")
        ax.plot(scan.phi, scan.regular_area, color="tab:blue", label="regular area (grid)")
        ax.axvline(ws.phi, color="tab:green", lw=1.0, label=f"φ of the maps ({ws.phi:.3g})")
        ax.set_xlabel("φ (rad)")
        ax.set_ylabel("area in the window (m²)")
        ax.set_title("scan of φ: areas of the slices", fontsize=9)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), frameon=False)
        ax.grid(True, color="0.92")
    else:
        ax.axis("off")
    figure.suptitle(
        f"{robot.architecture} (joint {robot.actuated} driven): workspace at φ = {ws.phi:.4g} rad",
        fontsize=12,
    )
    return figure


def save_family_workspace_map(
    path: str | Path, ws: FamilyWorkspace, scan: FamilyOrientationScan | None = None
) -> Path:
    """Write :func:`family_workspace_figure` as a PNG, atomically."""
    path = Path(path)
    with atomic_path(path) as temporary:
        family_workspace_figure(ws, scan).savefig(temporary, format="png")
    return path


def family_statics_figure(statics: FamilyStatics) -> Figure:
    """The statics map of a family robot: each actuator's ``tau_L`` at rest and the largest.

    Four panels over the regular grid points (grey elsewhere): ``tau_A``,
    ``tau_B``, ``tau_C`` on one diverging scale centred on 0, and
    ``max_L |tau_L|``.

    Parameters
    ----------
    statics : FamilyStatics
        From :func:`prp3.family.workspace.family_workspace_statics`.
    """
    from matplotlib.figure import Figure

    ws = statics.workspace
    robot = ws.robot
    unit = "N" if robot.types[robot.actuated - 1] == "P" else "N·m"
    figure = Figure(figsize=(11.0, 9.6), layout="constrained")
    axes = figure.subplots(2, 2).ravel()
    finite = statics.tau[np.isfinite(statics.tau)]
    bound = float(np.abs(finite).max()) if finite.size else 1.0
    bound = bound if bound > 0.0 else 1.0
    panels = [
        (statics.tau[..., j], ("RdBu", -bound, bound), f"tau_{leg} at rest ({unit})")
        for j, leg in enumerate(LEGS)
    ]
    panels.append((statics.peak, ("viridis", 0.0, bound), f"largest |tau| over the legs ({unit})"))
    for ax, (values, scale, title) in zip(axes, panels, strict=True):
        effort_panel(figure, ax, (ws.x, ws.y, ws.regular), values, scale, unit)
        _map_axes(ax, ws)
        ax.set_title(title, fontsize=9)
    figure.suptitle(
        f"{robot.architecture} (joint {robot.actuated} driven): actuator efforts holding the "
        f"platform at rest, φ = {ws.phi:.4g} rad (grey: not regular)",
        fontsize=11,
    )
    return figure


def save_family_statics_map(path: str | Path, statics: FamilyStatics) -> Path:
    """Write :func:`family_statics_figure` as a PNG, atomically."""
    path = Path(path)
    with atomic_path(path) as temporary:
        family_statics_figure(statics).savefig(temporary, format="png")
    return path
