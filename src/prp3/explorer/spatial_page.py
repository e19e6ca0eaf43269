"""The 3-D explorer of a spatial run: one self-contained HTML page (plotly), docs/spatial.md §22.

``prp3 simulate --robot SPATIAL.toml ... --html FILE.html`` and ``prp3 explore --robot
SPATIAL.toml --results DIR`` show a spatial run (the columns of docs/spatial.md §9) in the
browser, in 3-D: the base and platform polygons, every leg's chain of bodies, every joint at its
joint point (the actuated ones in black, a P's sleeve, an R's or U's axes), the platform origin
and its path, and the **reaction force of every joint** (``F<x|y|z>_<leg>_<joint>``, on the
distal body) as an arrow from its joint point: a shaft ``F / k`` long and a cone at its tip,
for one scale ``k`` (N per m) over the run, stated in the legend's title.  A slider and a
play button go through the samples (at most
:data:`~prp3.explorer.scrubber.MAX_HTML_FRAMES`, evenly spread, first and last kept); hovering
a joint or an arrow names the leg, the joint and the force's components.

What is drawn is the :class:`~prp3.spatial.drawing.SpatialFrame` the animation draws
(:func:`prp3.spatial.drawing.spatial_frame`, the same scale :func:`~prp3.spatial.drawing.force_scale`):
:func:`spatial_page_figure` builds the plotly figure as plain data (a dict of lists, every
frame's traces precomputed: nothing is computed in the browser) and :func:`spatial_run_html` the
page, plotly's JavaScript inline, so that it opens offline.  Each trace is named by its
``meta`` (``"leg 1"``, ``"joint U1"``, ``"force U1"``, ...), the layout's ``meta`` holds the
scale and the samples of the frames.  plotly is imported inside :func:`spatial_run_html`
only; without it, :func:`require_plotly` refuses in one line.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import Prp3Error
from prp3.explorer.scrubber import MAX_HTML_FRAMES
from prp3.files import atomic_writer
from prp3.plotting.animation import frame_indices  # a pure function: matplotlib is not imported
from prp3.plotting.spatial_animation import run_frames, scale_heading  # nor here
from prp3.spatial.drawing import (
    AXIS_HALF,
    JOINT_COLOURS,
    JOINT_NAMES,
    LEG_COLOURS,
    VIEW,
    SpatialFrame,
    axis_segments,
    platform_path,
    spatial_samples,
    view_direction,
)
from prp3.spatial.model import SpatialRobot

__all__ = [
    "HEAD_FRACTION",
    "require_plotly",
    "spatial_page_figure",
    "spatial_run_html",
    "write_spatial_run_html",
]

FloatArray = NDArray[np.float64]

#: An arrow's cone is this fraction of the robot's size long at most (and of its shaft).
HEAD_FRACTION: float = 0.04

#: The id of the page's plotly figure (``document.getElementById``).
FIGURE_ID: str = "prp3-spatial"


def require_plotly(what: str = "the 3-D explorer") -> None:
    """Refuse, in one line, when plotly is not installed."""
    try:
        import plotly  # noqa: F401
    except ImportError:
        raise Prp3Error(
            f"{what} needs plotly, which is not installed: pip install 'prp3[explore]'"
        ) from None


def _xyz(points: FloatArray) -> dict[str, list[float | None]]:
    """``x, y, z`` lists of ``points (m, 3)``, NaN as ``None`` (a gap in a line)."""
    rows = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return {
        axis: [None if math.isnan(v) else float(v) for v in rows[:, c].tolist()]
        for c, axis in enumerate("xyz")
    }


def _fan(polygon: FloatArray) -> dict[str, Any]:
    """A polygon ``(m, 3)`` as a mesh: a fan of triangles about its centroid (the last vertex)."""
    m = polygon.shape[0]
    vertices = np.concatenate([polygon, polygon.mean(axis=0)[None]])
    return {
        **_xyz(vertices),
        "i": [m] * m,
        "j": list(range(m)),
        "k": [(v + 1) % m for v in range(m)],
    }


def _closed(polygon: FloatArray) -> FloatArray:
    return np.concatenate([polygon, polygon[:1]])


def _force_text(frame: SpatialFrame, leg: int, k: int) -> str:
    """The hover text of joint ``k`` of ``leg`` (0-based): the leg, the joint, its force."""
    kind = frame.kinds[k]
    actuated = ", actuated" if k == frame.actuated else ""
    fx, fy, fz = (float(v) for v in frame.forces[leg, k])
    size = math.sqrt(fx * fx + fy * fy + fz * fz)
    return (
        f"leg {leg + 1}, joint {frame.labels[k]} ({JOINT_NAMES[kind]}{actuated})<br>"
        f"F = ({fx:.6g}, {fy:.6g}, {fz:.6g}) N, |F| = {size:.6g} N<br>"
        f"on the distal body, at ({', '.join(f'{v:.4g}' for v in frame.points[leg, k])}) m"
    )


def _head(tail: FloatArray, tip: FloatArray, size: float) -> FloatArray:
    """The cone's vector at ``tip``: along the arrow, ``min(0.3·|tip − tail|, HEAD_FRACTION·size)``
    long; zero for a zero force."""
    d = tip - tail
    length = float(np.linalg.norm(d))
    if length == 0.0:
        return np.zeros(3)
    return d / length * min(0.3 * length, HEAD_FRACTION * size)


def _frame_traces(frame: SpatialFrame, scale: float, size: float) -> list[dict[str, Any]]:
    """Every moving trace of one frame, in the figure's order (the figure's first traces; the
    platform origin's path, the last trace, is drawn once)."""
    legs, n = frame.points.shape[:2]
    half = AXIS_HALF * size
    traces: list[dict[str, Any]] = [
        {"type": "mesh3d", **_fan(frame.base)},
        {"type": "scatter3d", **_xyz(_closed(frame.base))},
        {"type": "mesh3d", **_fan(frame.platform)},
        {"type": "scatter3d", **_xyz(_closed(frame.platform))},
    ]
    traces += [{"type": "scatter3d", **_xyz(frame.chain[i])} for i in range(legs)]
    for k, kind in enumerate(frame.kinds):
        if kind == "P":
            bars = np.concatenate([frame.sleeves[:, k], np.full((legs, 1, 3), np.nan)], axis=1)
            traces.append({"type": "scatter3d", **_xyz(bars)})
    for k, kind in enumerate(frame.kinds):
        if kind in ("R", "U"):
            segments = axis_segments(frame.axes[:, k], frame.points[:, k], half)
            traces.append({"type": "scatter3d", **_xyz(segments)})
    texts = [[_force_text(frame, i, k) for i in range(legs)] for k in range(n)]
    for k in range(n):
        traces.append({"type": "scatter3d", **_xyz(frame.points[:, k]), "text": texts[k]})
    tips = frame.points + (frame.forces / scale if scale > 0.0 else 0.0 * frame.forces)
    for k in range(n):
        shafts = np.stack(
            [frame.points[:, k], tips[:, k], np.full((legs, 3), np.nan)], axis=1
        )  # (legs, 3, 3): tail, tip, gap
        text: list[str | None] = []
        for i in range(legs):
            text += [None, texts[k][i], None]  # the tail's is the joint marker's
        traces.append({"type": "scatter3d", **_xyz(shafts), "text": text})
    for k in range(n):
        heads = np.stack([_head(frame.points[i, k], tips[i, k], size) for i in range(legs)])
        uvw = _xyz(heads)
        traces.append(
            {"type": "cone", **_xyz(tips[:, k]), "u": uvw["x"], "v": uvw["y"], "w": uvw["z"]}
        )
    traces.append({"type": "scatter3d", **_xyz(frame.centre[None])})
    return traces


def _styles(frame: SpatialFrame, legs: int) -> list[dict[str, Any]]:
    """The style of every trace of :func:`_frame_traces` (names, colours, legend, hover)."""
    skip = {"hoverinfo": "skip"}
    hover = {"hovertemplate": "%{text}<extra></extra>"}
    styles: list[dict[str, Any]] = [
        {"meta": "base", "name": "base", "color": "#b0b0b0", "opacity": 0.5, "flatshading": True,
         "showlegend": False, **skip},
        {"meta": "base outline", "name": "base", "mode": "lines",
         "line": {"color": "#737373", "width": 3}, "showlegend": False, **skip},
        {"meta": "platform", "name": "platform", "color": "#9467bd", "opacity": 0.35,
         "flatshading": True, "showlegend": False, **skip},
        {"meta": "platform outline", "name": "platform", "mode": "lines",
         "line": {"color": "indigo", "width": 4}, "showlegend": False, **skip},
    ]  # fmt: skip
    for i in range(legs):
        styles.append(
            {"meta": f"leg {i + 1}", "name": f"leg {i + 1}", "mode": "lines",
             "line": {"color": LEG_COLOURS[i % len(LEG_COLOURS)], "width": 5},
             "legendgroup": "legs", "legendgrouptitle": {"text": "legs"}, **skip}
        )  # fmt: skip
    for k, kind in enumerate(frame.kinds):
        if kind == "P":
            actuated = k == frame.actuated
            styles.append(
                {"meta": f"sleeve {frame.labels[k]}", "mode": "lines",
                 "name": f"{frame.labels[k]}: prismatic, its sleeve"
                 + (" (actuated)" if actuated else ""),
                 "line": {"color": "black" if actuated else "#808080", "width": 12},
                 "opacity": 0.85, "legendgroup": "joints", "legendgrouptitle": {"text": "joints"},
                 **skip}
            )  # fmt: skip
    for k, kind in enumerate(frame.kinds):
        if kind in ("R", "U"):
            actuated = k == frame.actuated
            styles.append(
                {"meta": f"axes {frame.labels[k]}", "mode": "lines",
                 "name": f"{frame.labels[k]}: its axis" + ("es" if kind == "U" else ""),
                 "line": {"color": "black" if actuated else "#404040",
                          "width": 5 if actuated else 3},
                 "legendgroup": "joints", "legendgrouptitle": {"text": "joints"},
                 "showlegend": False, **skip}
            )  # fmt: skip
    symbols = {"R": "circle-open", "U": "square", "S": "circle", "P": "diamond"}
    for k, kind in enumerate(frame.kinds):
        actuated = k == frame.actuated
        styles.append(
            {"meta": f"joint {frame.labels[k]}", "mode": "markers",
             "name": f"{frame.labels[k]}: {JOINT_NAMES[kind]}" + (" (actuated)" if actuated else ""),
             "marker": {"symbol": symbols[kind], "size": 7 if kind != "S" else 8,
                        "color": "black" if actuated or kind == "S" else "white",
                        "line": {"color": "black", "width": 2}},
             "legendgroup": "joints", "legendgrouptitle": {"text": "joints"}, **hover}
        )  # fmt: skip
    for k in range(len(frame.kinds)):
        colour = JOINT_COLOURS[k % len(JOINT_COLOURS)]
        styles.append(
            {"meta": f"force {frame.labels[k]}", "mode": "lines",
             "name": f"force at {frame.labels[k]} (on the distal body)",
             "line": {"color": colour, "width": max(8 - 2 * k, 3)},
             "legendgroup": f"force {frame.labels[k]}",
             "legendgrouptitle": {"text": "joint reaction forces"} if k == 0 else {}, **hover}
        )  # fmt: skip
    for k in range(len(frame.kinds)):
        colour = JOINT_COLOURS[k % len(JOINT_COLOURS)]
        styles.append(
            {"meta": f"head {frame.labels[k]}", "name": f"force at {frame.labels[k]}",
             "anchor": "tip", "sizemode": "raw", "sizeref": 1.0, "showscale": False,
             "colorscale": [[0.0, colour], [1.0, colour]],
             "legendgroup": f"force {frame.labels[k]}", "showlegend": False, **skip}
        )  # fmt: skip
    styles.append(
        {"meta": "centre", "name": "platform origin", "mode": "markers",
         "marker": {"symbol": "cross", "size": 5, "color": "black"}, "showlegend": False, **skip}
    )  # fmt: skip
    return styles


def _cube(
    frames: list[SpatialFrame], scale: float, size: float, path: FloatArray
) -> tuple[FloatArray, float]:
    """The middle and half side of the scene's cube: everything drawn over ``frames`` (the
    legs, the arrows' tips, the joints' axis segments, the path) with a margin of a tenth."""
    parts = [path]
    half_axis = AXIS_HALF * size
    for frame in frames:
        parts += [frame.chain.reshape(-1, 3), frame.sleeves.reshape(-1, 3)]
        if scale > 0.0:
            parts.append((frame.points + frame.forces / scale).reshape(-1, 3))
        for k in range(frame.points.shape[1]):
            parts.append(axis_segments(frame.axes[:, k], frame.points[:, k], half_axis))
    points = np.concatenate(parts)
    points = points[~np.isnan(points).any(axis=1)]
    low, high = points.min(axis=0), points.max(axis=0)
    return 0.5 * (low + high), 0.55 * float((high - low).max())


def spatial_page_figure(
    robot: SpatialRobot, table: Mapping[str, NDArray[Any]], title: str = ""
) -> dict[str, Any]:
    """The plotly figure of a spatial run, as plain data (``data``, ``layout``, ``frames``).

    Parameters
    ----------
    robot : SpatialRobot
        The robot of the run (its legs' joints name the columns).
    table : mapping of str to (N,) arrays
        The columns of docs/spatial.md §9 (``t``, ``q_<leg>_<joint>...``,
        ``F<x|y|z>_<leg>_<joint>``).
    title : str
        The figure's title (default: the robot's name).

    Returns
    -------
    dict
        ``data``: the traces of the first frame, each named by its ``meta``; ``frames``: one
        per sample shown (at most :data:`~prp3.explorer.scrubber.MAX_HTML_FRAMES`), named by
        the sample's index, with every trace's data in the order of ``data``; ``layout``: the
        scene (a cube holding everything drawn over the run, seen from
        :data:`~prp3.spatial.drawing.VIEW`), the slider, the play button, and ``meta``:
        ``scale`` (N per m: an arrow is ``F / scale`` long), ``samples`` and ``times`` of the
        frames.  The joint points are the frames' of :func:`~prp3.spatial.drawing.spatial_frame`;
        a force arrow's shaft is ``(point, point + F / scale, gap)`` per leg.

    Raises
    ------
    ParameterError
        A column of the run missing for the robot (names it).
    """
    t, q, force = spatial_samples(robot, table)
    indices = [int(k) for k in frame_indices(int(t.size), MAX_HTML_FRAMES)]
    frames, size, scale = run_frames(robot, t, q, force, indices)
    path = platform_path(robot, q)
    styles = _styles(frames[0], len(robot.legs))
    plotted = [_frame_traces(frame, scale, size) for frame in frames]
    data = [{**trace, **style} for trace, style in zip(plotted[0], styles, strict=True)]
    middle, half = _cube(frames, scale, size, path)
    data.append(
        {"type": "scatter3d", **_xyz(path), "meta": "path", "mode": "lines",
         "name": "platform origin's path (+: now)", "line": {"color": "#d62728", "width": 3},
         "hoverinfo": "skip"}
    )  # fmt: skip
    heading = scale_heading(scale)
    layout: dict[str, Any] = {
        "title": {"text": f"{html.escape(title or robot.name)}<br><sup>{heading}; "
                          f"{_largest_force(robot, t, force)}</sup>",
                  "x": 0.02, "xanchor": "left"},
        "meta": {"scale": scale, "samples": indices, "times": [float(t[k]) for k in indices],
                 "size": size, "view": list(VIEW)},
        "scene": _scene(middle, half),
        "legend": {"title": {"text": heading}, "groupclick": "toggleitem", "tracegroupgap": 4,
                   "x": 1.0, "xanchor": "right", "y": 0.98, "bgcolor": "rgba(255,255,255,0.85)"},
        "margin": {"l": 0, "r": 0, "t": 70, "b": 0},
        "uirevision": "keep",
        "sliders": [_slider(t, indices)],
        "updatemenus": [_play_buttons(t, indices)],
    }  # fmt: skip
    return {
        "data": data,
        "layout": layout,
        "frames": [
            {"name": str(k), "data": traces, "traces": list(range(len(traces)))}
            for k, traces in zip(indices, plotted, strict=True)
        ],
    }


def _largest_force(robot: SpatialRobot, t: FloatArray, force: FloatArray) -> str:
    """The title's note of the run's largest joint force: its size, joint, leg and time."""
    magnitude = np.linalg.norm(force, axis=-1)  # (N, legs, joints)
    # symmetric motions tie to round-off (the tilt's legs 3 and 6): the first of the forces
    # equal to 1e-9 of the largest is named, the same on every machine
    tied = np.round(magnitude / max(float(magnitude.max(initial=0.0)), np.finfo(float).tiny), 9)
    n, i, j = (int(v) for v in np.unravel_index(int(np.argmax(tied)), tied.shape))
    labels = robot.legs[0].labels
    return (
        f"the run's largest joint force: {float(magnitude[n, i, j]):.3g} N at {labels[j]} of "
        f"leg {i + 1}, t = {float(t[n]):.3g} s"
    )


def _scene(middle: FloatArray, half: float) -> dict[str, Any]:
    """The layout's 3-D scene: the cube of half side ``half`` about ``middle`` (m, axes fixed),
    the camera looking from :func:`~prp3.spatial.drawing.view_direction`."""
    eye = 1.55 * view_direction()
    axis = {"showspikes": False, "backgroundcolor": "#f4f4f4", "autorange": False}
    return {
        **{
            f"{name}axis": {**axis, "title": {"text": f"{name} (m)"},
                            "range": [middle[c] - half, middle[c] + half]}
            for c, name in enumerate("xyz")
        },
        "aspectmode": "cube",
        "camera": {"eye": {"x": float(eye[0]), "y": float(eye[1]), "z": float(eye[2])}},
    }  # fmt: skip


def _slider(t: FloatArray, indices: list[int]) -> dict[str, Any]:
    """The slider through the frames: one step per sample shown, labelled by its time."""
    steps = [
        {
            "method": "animate",
            "label": f"{float(t[k]):.3f} s",
            "args": [
                [str(k)],
                {
                    "mode": "immediate",
                    "frame": {"duration": 0, "redraw": True},
                    "transition": {"duration": 0},
                },
            ],
        }
        for k in indices
    ]
    return {
        "active": 0, "steps": steps, "x": 0.17, "len": 0.81, "y": 0.05, "yanchor": "top",
        "pad": {"t": 0}, "ticklen": 2, "font": {"color": "rgba(0,0,0,0)"},
        "currentvalue": {"prefix": "t = ", "font": {"size": 14, "color": "black"}},
    }  # fmt: skip


def _play_buttons(t: FloatArray, indices: list[int]) -> dict[str, Any]:
    """The play and pause buttons; play shows the frames in about real time (40 ms at least
    per frame)."""
    span = float(t[indices[-1]] - t[indices[0]])
    duration = max(40, round(1000.0 * span / max(len(indices) - 1, 1)))
    return {
        "type": "buttons", "direction": "left", "x": 0.0, "y": 0.05, "xanchor": "left",
        "yanchor": "top", "showactive": False, "pad": {"t": 20},
        "buttons": [
            {"label": "▶ play", "method": "animate",
             "args": [None, {"frame": {"duration": duration, "redraw": True},
                             "fromcurrent": True, "transition": {"duration": 0}}]},
            {"label": "❚❚ pause", "method": "animate",
             "args": [[None], {"mode": "immediate", "frame": {"duration": 0, "redraw": False},
                               "transition": {"duration": 0}}]},
        ],
    }  # fmt: skip


def spatial_run_html(
    robot: SpatialRobot, table: Mapping[str, NDArray[Any]], title: str, *, note: str = ""
) -> str:
    """The self-contained HTML page of a spatial run (:func:`spatial_page_figure`).

    plotly's JavaScript is inline: the page opens offline.  ``note``: a line of the page under
    the figure (the run's source).
    """
    require_plotly()
    import plotly.io

    figure = spatial_page_figure(robot, table, title)
    frames = len(figure["frames"])
    t = np.asarray(table["t"], dtype=np.float64)
    div = plotly.io.to_html(
        figure,
        validate=False,
        include_plotlyjs=True,
        auto_play=False,
        full_html=False,
        div_id=FIGURE_ID,
        default_width="100%",
        default_height="88vh",
        config={"displaylogo": False, "responsive": True},
    )
    caption = (
        f"{t.size} samples over t = {t[0]:g} .. {t[-1]:g} s, {frames} frames; every joint's "
        "reaction force (the force the proximal body exerts on the distal one, results.csv's "
        "F columns) as an arrow from its joint point; hover a joint or an arrow for its "
        "components; drag to turn the view"
    )
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{html.escape(title)}</title>\n"
        "<style>body{font-family:sans-serif;margin:8px}p{margin:2px 0;font-size:13px}</style>\n"
        "</head>\n<body>\n"
        f"{div}\n<p>{html.escape(caption)}</p>\n"
        + (f"<p>{html.escape(note)}</p>\n" if note else "")
        + "</body>\n</html>\n"
    )


def write_spatial_run_html(
    path: str | Path, robot: SpatialRobot, table: Mapping[str, NDArray[Any]], title: str,
    *, note: str = "",
) -> None:  # fmt: skip
    """Write :func:`spatial_run_html` to ``path`` atomically (whole or not at all)."""
    page = spatial_run_html(robot, table, title, note=note)
    with atomic_writer(path) as stream:
        stream.write(page)
