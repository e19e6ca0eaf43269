"""The workspace map: reachable region, Jacobian conditioning and singular loci (PNG).

Left: the slice at one orientation ``φ`` — the condition number of the
normalised Jacobian (:func:`prp3.analysis.reachability.jacobian_condition`, log colour
scale) over the reachable grid points, unreachable points in grey, the exact
boundary of the region, the base triangle and the platform at ``(0, 0, φ)``
for scale.  The singular set of the slice is empty unless ``φ`` is singular
(prp3 refuses singular slices), which the panel states.  Right: a scan of
``φ`` — the reachable area (exact and counted on the grid) and the best and
worst conditioning over the reachable grid points, with the singular
orientations ``φ ≡ π/3 (mod π)`` marked.

The statics map (:func:`statics_figure`): the largest actuator force
``max_i |f10_i|`` that holds the platform at rest at each reachable grid point
(:func:`prp3.analysis.workspace.workspace_statics`), unreachable points in grey, the
exact boundary, and with ``[limits] max_force`` its contour and the points
beyond it hatched.

matplotlib is imported inside the functions only; the figure is a
:class:`matplotlib.figure.Figure` rendered by Agg, without pyplot.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from prp3.analysis.reachability import SINGULAR_ORIENTATIONS
from prp3.analysis.workspace import OrientationScan, WorkspaceSlice, WorkspaceStatics
from prp3.files import atomic_path
from prp3.mechanics.geometry import base_vertices, platform_vertices
from prp3.model.robot import Robot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.colorbar import Colorbar
    from matplotlib.figure import Figure

__all__ = ["save_statics_map", "save_workspace_map", "statics_figure", "workspace_figure"]


def cm_grey() -> tuple[float, float, float, float]:
    """The colour of the unreachable grid points (``Greys`` at 1/4, as drawn)."""
    from matplotlib import colormaps

    return tuple(colormaps["Greys"](0.25))  # type: ignore[return-value]


def cm_viridis() -> tuple[float, float, float, float]:
    """A colour of the κ map, for the legend."""
    from matplotlib import colormaps

    return tuple(colormaps["viridis"](0.5))  # type: ignore[return-value]


def grey_points(ax: Axes, x: np.ndarray, y: np.ndarray, shown: np.ndarray) -> None:
    """Light grey (the colour of :func:`cm_grey`) on the grid points where ``shown`` is False."""
    ax.pcolormesh(
        x, y, np.where(shown, np.nan, 1.0), cmap="Greys", vmin=0.0, vmax=4.0, shading="nearest"
    )


def effort_panel(
    figure: Figure,
    ax: Axes,
    grid: tuple[np.ndarray, np.ndarray, np.ndarray],
    values: np.ndarray,
    scale: tuple[str, float, float],
    unit: str,
) -> None:
    """A map of actuator efforts at rest: grey where ``grid[2]`` (regular) is False, colour bar.

    ``grid``: the axes ``u``, ``v`` and the regular points; ``scale``: the
    colour map and its range ``(cmap, low, high)``; non-finite values are not drawn.
    """
    u, v, regular = grid
    cmap, low, high = scale
    grey_points(ax, u, v, regular)
    mesh = ax.pcolormesh(u, v, np.ma.masked_invalid(values), cmap=cmap, vmin=low, vmax=high,
                         shading="nearest")  # fmt: skip
    figure.colorbar(mesh, ax=ax, shrink=0.85, label=unit)


def _closed(points: np.ndarray) -> np.ndarray:
    return np.vstack([points, points[:1]])


def workspace_figure(
    robot: Robot, workspace: WorkspaceSlice, scan: OrientationScan | None = None
) -> Figure:
    """The workspace map of ``workspace`` (and the φ-scan ``scan`` when given).

    Parameters
    ----------
    robot : Robot
        The robot the slice was computed for (base triangle, ``l0``, stroke).
    workspace : WorkspaceSlice
        From :func:`prp3.analysis.workspace.workspace_slice`.
    scan : OrientationScan, optional
        From :func:`prp3.analysis.workspace.orientation_scan` on the same grid; adds the
        right-hand panel.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    panels = 2 if scan is not None else 1
    figure = Figure(figsize=(6.4 * panels + 0.6, 5.6), layout="constrained")
    axes = figure.subplots(1, panels, squeeze=False)[0]
    _slice_panel(figure, axes[0], robot, workspace)
    if scan is not None:
        _scan_panel(axes[1], workspace, scan, robot.limits.stroke is not None)
    return figure


def _slice_panel(figure: Figure, ax: Axes, robot: Robot, ws: WorkspaceSlice) -> None:
    """The slice at φ: κ over the reachable points, the exact boundary, base and platform."""
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.patches import Patch

    kappa = np.ma.masked_array(ws.condition, mask=~ws.reachable | ~np.isfinite(ws.condition))
    grey_points(ax, ws.x, ws.y, ws.reachable)
    finite = ws.condition[ws.reachable & np.isfinite(ws.condition)]
    if finite.size:
        low, high = float(finite.min()), max(float(finite.max()), float(finite.min()) * 1.001)
        wide = high / low > 10.0  # log colours only when κ spans a decade
        mesh = ax.pcolormesh(
            ws.x,
            ws.y,
            kappa,
            cmap="viridis",
            shading="nearest",
            norm=LogNorm(vmin=low, vmax=high) if wide else Normalize(vmin=low, vmax=high),
        )
        scale = " (log scale)" if wide else ""
        # beside the map itself (an inset of its axes: it follows the equal-aspect window)
        bar = figure.colorbar(mesh, cax=ax.inset_axes((1.03, 0.0, 0.045, 1.0)))
        bar.set_label(f"condition number κ of J·diag(1, 1, 1/l0){scale}", fontsize=10)
    if ws.region is not None and len(ws.region):
        outline = _closed(ws.region)
        area = f"; reachable area {ws.area:.4g} m² (grid {ws.grid_area:.4g} m²)"
        ax.plot(
            outline[:, 0],
            outline[:, 1],
            color="black",
            lw=1.2,
            label="boundary of the reachable region (exact)"
            + (area if math.isfinite(ws.area) else ""),
        )
    _scale_shapes(ax, robot, ws)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    stroke = robot.limits.stroke
    limits = f"stroke [{stroke[0]:g}, {stroke[1]:g}] m" if stroke else "no stroke limits"
    ax.set_title(
        f"workspace at φ = {ws.phi:.4g} rad ({math.degrees(ws.phi):.3g}°), {limits}\n"
        f"no singular point at this φ (|sin(φ − π/3)| = {abs(ws.determinant):.3g});\n"
        "singular: φ ≡ π/3 (mod π), every (x, y)",
        fontsize=10,
    )
    handles, _ = ax.get_legend_handles_labels()
    if not ws.reachable.all():
        handles.append(
            Patch(facecolor=cm_grey(), edgecolor="none", label="unreachable grid points")
        )
    handles.append(Patch(facecolor=cm_viridis(), edgecolor="none", label="reachable: colour = κ"))
    # below the axes: nothing drawn in the window is covered
    ax.legend(
        handles=handles,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.1),
        fontsize=9,
        ncols=1,
        frameon=False,
    )


def _scale_shapes(ax: Axes, robot: Robot, ws: WorkspaceSlice) -> None:
    """The base triangle and the platform at ``(0, 0, φ)`` for scale, and the window's limits.

    Drawn when the window shows some of them, whole (the window grows to their
    tips), in colours of their own (red marks the singular orientations, the
    legs have theirs).
    """

    def visible(points: np.ndarray) -> bool:
        inside_x = (points[:, 0] >= ws.x[0]) & (points[:, 0] <= ws.x[-1])
        return bool((inside_x & (points[:, 1] >= ws.y[0]) & (points[:, 1] <= ws.y[-1])).any())

    low_x, high_x, low_y, high_y = float(ws.x[0]), float(ws.x[-1]), float(ws.y[0]), float(ws.y[-1])
    base = _closed(base_vertices(robot))
    platform = _closed(platform_vertices(robot, [0.0, 0.0, ws.phi]))
    for points, colour, style, text in (
        (base, "0.2", "--", "base triangle"),
        (platform, "tab:brown", ":", f"platform at (0, 0, {ws.phi:.3g})"),
    ):
        if visible(points):
            ax.plot(points[:, 0], points[:, 1], color=colour, lw=1.4, ls=style, label=text)
            low_x, high_x = min(low_x, points[:, 0].min()), max(high_x, points[:, 0].max())
            low_y, high_y = min(low_y, points[:, 1].min()), max(high_y, points[:, 1].max())
    drawn = any(visible(points) for points in (base, platform))  # their tips off the edge
    margin = 0.03 * max(high_x - low_x, high_y - low_y) if drawn else 0.0
    ax.set_xlim(low_x - margin, high_x + margin)
    ax.set_ylim(low_y - margin, high_y + margin)


def _scan_panel(ax: Axes, ws: WorkspaceSlice, scan: OrientationScan, stroke: bool) -> None:
    """The φ-scan: the reachable area (or fraction) and the best and worst κ, against φ."""
    from matplotlib.ticker import FuncFormatter

    if np.isfinite(scan.area).any() and stroke:
        ax.plot(scan.phi, scan.area, color="black", label="reachable area, exact")
        ax.plot(
            scan.phi,
            scan.grid_area,
            ".",
            color="tab:blue",
            ms=3,
            label="reachable area, grid",
        )
        ax.set_ylabel("reachable area (m²)")
    else:
        ax.plot(
            scan.phi,
            scan.reachable.mean(axis=(1, 2)),
            color="black",
            label="reachable fraction of the grid",
        )
        ax.set_ylabel("reachable fraction of the grid")
    for phi in SINGULAR_ORIENTATIONS + (SINGULAR_ORIENTATIONS[0] + 2 * math.pi,):
        if scan.phi[0] <= phi <= scan.phi[-1]:
            ax.axvline(phi, color="tab:red", ls="--", lw=1.0, label="singular orientation")
    ax.axvline(ws.phi, color="tab:green", lw=1.0, label=f"φ of the map ({ws.phi:.3g})")
    ax.set_xlabel("φ (rad)")
    twin = ax.twinx()
    twin.semilogy(
        scan.phi, scan.condition_min, color="tab:purple", lw=0.8, label="κ min (reachable)"
    )
    twin.semilogy(
        scan.phi,
        scan.condition_max,
        color="tab:purple",
        lw=0.8,
        ls="--",
        label="κ max (reachable)",
    )
    twin.set_ylabel("condition number κ over the reachable grid (log scale)")
    spread = scan.condition_max[np.isfinite(scan.condition_max)]
    if spread.size and spread.max() / max(float(np.nanmin(scan.condition_min)), 1.0) < 30.0:
        plain = FuncFormatter(lambda value, _: f"{value:g}")
        twin.yaxis.set_major_formatter(plain)
        twin.yaxis.set_minor_formatter(plain)
    handles, labels = ax.get_legend_handles_labels()
    more, more_labels = twin.get_legend_handles_labels()
    unique = dict(zip(labels + more_labels, handles + more, strict=True))
    ax.legend(  # below the axes, over no curve
        unique.values(),
        unique.keys(),
        fontsize=9,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.1),
        ncols=2,
        frameon=False,
    )
    measure = "reachable area" if stroke else "reachable fraction of the grid"
    ax.set_title(
        f"scan of φ: {measure} (left axis) and the best and worst κ over the\n"
        "reachable grid points (right axis, log scale)",
        fontsize=10,
    )


def save_workspace_map(
    path: str | Path, robot: Robot, workspace: WorkspaceSlice, scan: OrientationScan | None = None
) -> Path:
    """Render :func:`workspace_figure` as a PNG file at ``path``, atomically."""
    path = Path(path)
    figure = workspace_figure(robot, workspace, scan)
    with atomic_path(path) as temporary:
        figure.savefig(temporary, format="png", dpi=120)
    return path


def _loads(robot: Robot) -> str:
    """What the platform carries, for the title of the statics map."""
    parts = [f"platform {robot.platform.mass:g} kg"]
    if robot.payload.present:
        parts.append(f"payload {robot.payload.mass:g} kg")
    if robot.load.present:
        fx, fy = robot.load.force
        parts.append(f"load ({fx:g}, {fy:g}) N, {robot.load.moment:g} N·m")
    gx, gy = robot.gravity
    parts.append(f"g = ({gx:g}, {gy:g}) m/s²")
    return ", ".join(parts)


def _max_force_marks(
    ax: Axes,
    bar: Colorbar,
    st: WorkspaceStatics,
    peak: np.ma.MaskedArray,
    span: tuple[float, float],
    limit: float,
) -> list[object]:
    """``[limits] max_force`` on the statics map: a line on the colour bar, the points it
    cannot hold hatched, its contour; return their legend handles."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    low, high = span
    marks: list[object] = []
    if low <= limit <= high:
        bar.ax.axhline(limit, color="tab:red", lw=1.5)
    over = st.reachable & (st.peak > limit)
    if over.any():
        ax.contourf(
            st.x,
            st.y,
            over.astype(float),
            levels=[0.5, 1.5],
            colors="none",
            hatches=["//"],
        )
        marks.append(
            Patch(
                facecolor="none",
                edgecolor="black",
                hatch="//",
                label=f"max |f10| > max_force = {limit:g} N: cannot hold",
            )
        )
    if low < limit < high:
        ax.contour(st.x, st.y, peak, levels=[limit], colors="tab:red", linewidths=1.5)
        marks.append(
            Line2D(
                [],
                [],
                color="tab:red",
                lw=1.5,
                label=f"max |f10| = max_force = {limit:g} N",
            )
        )
    return marks


def statics_figure(robot: Robot, statics: WorkspaceStatics) -> Figure:
    """The statics map: ``max_i |f10_i|`` at rest over the reachable grid points.

    Parameters
    ----------
    robot : Robot
        The robot the map was computed for (title, base triangle).
    statics : WorkspaceStatics
        From :func:`prp3.analysis.workspace.workspace_statics`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    figure = Figure(figsize=(7.0, 6.4), layout="constrained")
    ax = figure.subplots()
    st = statics
    grey_points(ax, st.x, st.y, st.reachable)
    handles: list[object] = []
    shown = st.peak[st.reachable]
    limit = st.max_force
    if shown.size:
        low, high = float(shown.min()), float(shown.max())
        high = max(high, low + 1e-9 * max(abs(low), 1.0))
        peak = np.ma.masked_array(st.peak, mask=~st.reachable)
        mesh = ax.pcolormesh(
            st.x, st.y, peak, cmap="viridis", shading="nearest", norm=Normalize(low, high)
        )
        bar = figure.colorbar(mesh, ax=ax, label="largest actuator force max |f10| at rest (N)")
        handles.append(
            Patch(facecolor=cm_viridis(), edgecolor="none", label="reachable: colour = max |f10|")
        )
        if limit is not None:
            handles += _max_force_marks(ax, bar, st, peak, (low, high), limit)
    if not st.reachable.all():
        handles.append(
            Patch(facecolor=cm_grey(), edgecolor="none", label="unreachable grid points")
        )
    if st.region is not None and len(st.region):
        outline = _closed(st.region)
        ax.plot(outline[:, 0], outline[:, 1], color="black", lw=1.2)
        handles.append(
            Line2D([], [], color="black", lw=1.2, label="boundary of the reachable region")
        )
    ax.set_xlim(st.x[0], st.x[-1])
    ax.set_ylim(st.y[0], st.y[-1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    fraction = st.unheld_fraction
    verdict = (
        f"above max_force = {limit:g} N on {100.0 * fraction:.3g} % of the reachable points"
        if fraction is not None and limit is not None
        else "no [limits] max_force"
    )
    ax.set_title(
        f"statics at φ = {st.phi:.4g} rad: actuator forces holding the platform at rest\n"
        f"{_loads(robot)}\n{verdict}",
        fontsize=9,
    )
    ax.legend(
        handles=handles,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.1),
        fontsize=7,
        ncols=2,
        frameon=False,
    )
    return figure


def save_statics_map(path: str | Path, robot: Robot, statics: WorkspaceStatics) -> Path:
    """Render :func:`statics_figure` as a PNG file at ``path``, atomically."""
    path = Path(path)
    figure = statics_figure(robot, statics)
    with atomic_path(path) as temporary:
        figure.savefig(temporary, format="png", dpi=120)
    return path
