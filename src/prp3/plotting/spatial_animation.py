"""The spatial robot drawn in 3-D, with its joint reactions: ``pose.png`` and ``mechanism.gif``.

docs/spatial.md §15.  What is drawn for a sample is the
:class:`~prp3.spatial.drawing.SpatialFrame` of :func:`prp3.spatial.drawing.spatial_frame` (no
matplotlib: the 3-D explorer's page draws the same, docs/spatial.md §22), from the joint values ``q`` of a spatial ``results.csv``
(docs/spatial.md §9) through the chain of frames of §2:

* every joint at its **joint point** (§2: the origin of its distal frame, where its wrench is
  reduced): an R as a circle with a short segment along its axis, a U as a square with its
  two axes (the first fixed in the proximal body, the cross's second), an S as a ball; a P
  as a **sleeve**, a thick bar from its joint frame's origin along its slide (of one length
  over the run), the leg's rod sliding in it up to the joint point;
* each leg as the chain of its bodies from the base to the platform; the base polygon (the
  legs' first joints) and the platform polygon (their last joints); the platform origin's
  path so far;
* the **reaction force** of every joint (the force the proximal body exerts on the distal
  one, columns ``F<x|y|z>_<leg>_<joint>``) as an arrow from the joint point, of length
  ``|F| / k`` for one scale ``k`` (N per m) over the whole run
  (:func:`~prp3.spatial.drawing.force_scale`: the run's largest force drawn
  :data:`~prp3.spatial.drawing.ARROW_FRACTION` of the robot's size at most);
* the actuated joints in black.

:func:`spatial_robot_figure` builds the figure and its artists once (fixed view limits over
every frame: a cube, the three axes scaled alike) and :func:`draw_spatial_frame` moves them
to a frame; :func:`spatial_pose_figure` is one frame as a still figure and
:func:`save_spatial_animation` writes the run as an animated GIF (Pillow), atomically, in real
time (:func:`prp3.plotting.animation.frame_schedule`).  matplotlib is imported inside the
functions only.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import ParameterError
from prp3.files import atomic_path
from prp3.spatial.drawing import (
    ARROW_FRACTION,
    AXIS_HALF,
    JOINT_COLOURS,
    JOINT_NAMES,
    LEG_COLOURS,
    SLEEVE_FRACTION,
    VIEW,
    SpatialFrame,
    axis_segments,
    force_scale,
    platform_path,
    robot_size,
    scene_extent,
    sleeve_lengths,
    spatial_frame,
    spatial_samples,
    view_direction,
)
from prp3.spatial.model import SpatialRobot
from prp3.validation import check_instance, check_integer

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.text import Text

Line3D = Any  # mpl_toolkits.mplot3d.art3d's artists, which have no type hints
Poly3DCollection = Any

__all__ = [
    "ARROW_FRACTION",
    "JOINT_COLOURS",
    "LEG_COLOURS",
    "SLEEVE_FRACTION",
    "VIEW",
    "SpatialArtists",
    "SpatialFrame",
    "draw_spatial_frame",
    "force_scale",
    "robot_size",
    "save_spatial_animation",
    "spatial_frame",
    "spatial_pose_figure",
    "spatial_robot_figure",
    "spatial_samples",
]

FloatArray = NDArray[np.float64]


def _arrow_width(k: int) -> float:
    """The line width of joint ``k``'s arrows: thinner up the leg, so that two arrows at one
    point (a UPS leg's P and S share their joint point) both show."""
    return max(3.0 - 0.9 * k, 1.0)


def _format_scale(scale: float) -> str:
    return f"{scale:.0f}" if scale >= 1.0 else f"{scale:.3g}"


@dataclass(frozen=True)
class SpatialArtists:
    """The figure and the artists :func:`draw_spatial_frame` moves.

    Attributes
    ----------
    joints : tuple of Line3D
        Per joint of a leg (base to platform): its markers, one point per leg (P: its joint
        point, under the rod's end).
    axes : tuple of Line3D
        Per joint: the axis segments of every leg (NaN-separated), empty for P and S.
    arrows, heads : tuple of tuple of Line3D
        ``[leg][joint]``: the arrow's shaft (its two ends: tail at the joint point, tip at
        the point plus ``F / scale``) and its head.
    scale : float
        N per m of the arrows (:func:`force_scale`; 0: no arrows).
    """

    figure: Figure
    canvas: Any  # FigureCanvasAgg, whose drawing methods matplotlib leaves untyped
    joints: tuple[Line3D, ...]
    axes: tuple[Line3D, ...]
    links: tuple[Line3D, ...]
    sleeves: tuple[Line3D, ...]
    arrows: tuple[tuple[Line3D, ...], ...]
    heads: tuple[tuple[Line3D, ...], ...]
    base: Poly3DCollection
    platform: Poly3DCollection
    trace: Line3D
    centre: Line3D
    clock: Text
    scale: float
    size: float

    def moving(self) -> list[Any]:
        """Every artist that changes from frame to frame, bottom to top (drawing order)."""
        return [
            self.base,
            self.platform,
            *self.links,
            *self.sleeves,
            *self.axes,
            *self.joints,
            *(line for pair in zip(self.arrows, self.heads, strict=True) for row in pair
              for line in row),
            self.trace,
            self.centre,
            self.clock,
        ]  # fmt: skip


def _head(tail: FloatArray, tip: FloatArray, size: float) -> FloatArray:
    """An arrow head at ``tip``: a V in the plane facing the viewer, ``(3, 3)``."""
    d = tip - tail
    length = float(np.linalg.norm(d))
    if length == 0.0:
        return np.full((3, 3), np.nan)
    d = d / length
    h = min(0.3 * length, 0.035 * size)
    side = np.cross(d, view_direction())
    norm = float(np.linalg.norm(side))
    side = (
        side / norm
        if norm > 1e-9
        else np.cross(d, [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0])
    )
    side = side / float(np.linalg.norm(side))
    back = tip - h * d
    return np.stack([back + 0.45 * h * side, tip, back - 0.45 * h * side])


def scale_heading(scale: float) -> str:
    """The legend's title of the arrows' scale ``scale`` (N per m; 0: every force is zero),
    the same in the animation and in the 3-D explorer's page.

    >>> scale_heading(200.0)
    'force arrows: 200 N per m (1 cm: 2 N)'
    >>> scale_heading(0.0)
    'force arrows: every joint force is zero'
    """
    if scale > 0.0:
        return f"force arrows: {_format_scale(scale)} N per m (1 cm: {scale / 100:.3g} N)"
    return "force arrows: every joint force is zero"


def run_frames(
    robot: SpatialRobot, t: FloatArray, q: FloatArray, force: FloatArray, indices: list[int]
) -> tuple[list[SpatialFrame], float, float]:
    """The frames of the samples ``indices`` of a run, the robot's size over them and the
    run's arrow scale, as the animation and the 3-D explorer's page draw them.

    Parameters
    ----------
    robot : SpatialRobot
        The robot of the run.
    t, q, force : ndarray
        The run's samples, ``(N,)``, ``(N, legs, dof)``, ``(N, legs, joints, 3)``
        (:func:`~prp3.spatial.drawing.spatial_samples`).
    indices : list of int
        The samples drawn.

    Returns
    -------
    frames : list of SpatialFrame
        One per index (:func:`~prp3.spatial.drawing.spatial_frame`, a P's sleeve of one
        length over the run: :func:`~prp3.spatial.drawing.sleeve_lengths`).
    size : float
        :func:`robot_size` of ``frames`` (m).
    scale : float
        :func:`force_scale` of every sample's forces (N per m).
    """
    sleeve = sleeve_lengths(robot, q)
    frames = [spatial_frame(robot, q[k], force[k], t=float(t[k]), sleeve=sleeve) for k in indices]
    size = robot_size(frames)
    return frames, size, force_scale(force, size)


def spatial_robot_figure(
    robot: SpatialRobot,
    frames: list[SpatialFrame],
    *,
    scale: float | None = None,
    title: str = "",
    trace: FloatArray | None = None,
    dpi: float = 100.0,
) -> SpatialArtists:
    """Build the figure (720 × 720 px at ``dpi`` 100) and its artists for ``frames``.

    The view limits hold everything drawn over ``frames`` (the legs, the arrows' tips) in one
    cube, the three axes scaled alike; ``scale`` (N per m) by default
    :func:`force_scale` of the frames' forces.  The artists show ``frames[0]`` until
    :func:`draw_spatial_frame` moves them.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    if not frames:
        raise ParameterError("frames: at least one frame to draw, got none", key="frames")
    size = robot_size(frames)
    if scale is None:
        scale = force_scale(np.stack([f.forces for f in frames]), size)
    figure = Figure(figsize=(7.2, 7.2), dpi=dpi)
    canvas = FigureCanvasAgg(figure)
    ax = _scene_axes(figure, *scene_extent(frames, scale))
    first = frames[0]
    base, platform = _polygons(ax, first)
    links, sleeves, axis_lines, joints = _leg_artists(ax, first)
    arrows, heads = _arrow_artists(ax, first)
    (trace_line,) = ax.plot([], [], [], color="tab:red", linewidth=1.0, zorder=8)
    (centre,) = ax.plot([], [], [], linestyle="", marker="+", color="black", markersize=9,
                        zorder=8)  # fmt: skip
    clock = figure.text(0.02, 0.9, "", family="monospace", fontsize=10)
    _legend(figure, frames, joints, trace_line, scale)
    figure.suptitle(title or robot.name, fontsize=11, y=0.985)
    artists = SpatialArtists(
        figure=figure,
        canvas=canvas,
        joints=joints,
        axes=axis_lines,
        links=links,
        sleeves=sleeves,
        arrows=arrows,
        heads=heads,
        base=base,
        platform=platform,
        trace=trace_line,
        centre=centre,
        clock=clock,
        scale=scale,
        size=size,
    )
    draw_spatial_frame(artists, first, trace=trace)
    return artists


def _scene_axes(figure: Figure, middle: FloatArray, half: float) -> Any:
    """The figure's 3-D axes: seen from :data:`VIEW`, the cube of half side ``half`` about
    ``middle`` (m), the three axes scaled alike, labelled in metres, light panes."""
    ax: Any = figure.add_axes((-0.07, -0.01, 1.1, 0.96), projection="3d", computed_zorder=False)
    ax.view_init(elev=VIEW[0], azim=VIEW[1])
    for k, setter in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
        setter(middle[k] - half, middle[k] + half)
    ax.set_box_aspect((1.0, 1.0, 1.0), zoom=0.92)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.tick_params(labelsize=8)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.pane.set_alpha(0.35)
    return ax


def _polygons(ax: Any, first: SpatialFrame) -> tuple[Poly3DCollection, Poly3DCollection]:
    """The base polygon (grey) and the platform polygon (purple), drawn under the legs."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]

    base = Poly3DCollection([first.base], facecolor="0.82", edgecolor="0.45", alpha=0.6, zorder=1)
    platform = Poly3DCollection(
        [first.platform], facecolor=(0.58, 0.40, 0.74, 0.35), edgecolor="indigo", linewidth=1.5,
        zorder=2,
    )  # fmt: skip
    ax.add_collection3d(base)
    ax.add_collection3d(platform)
    return base, platform


def _leg_artists(
    ax: Any, first: SpatialFrame
) -> tuple[tuple[Line3D, ...], tuple[Line3D, ...], tuple[Line3D, ...], tuple[Line3D, ...]]:
    """The legs' lines (one per leg, its colour) and, per joint of a leg, the sleeves, the axis
    segments and the joint markers (R a circle, U a square, S a ball; the actuated in black)."""
    legs, n = first.points.shape[:2]
    links = tuple(
        ax.plot([], [], [], color=LEG_COLOURS[i % len(LEG_COLOURS)], linewidth=2.0, zorder=3)[0]
        for i in range(legs)
    )
    sleeves = tuple(
        ax.plot([], [], [], color="black" if k == first.actuated else "0.5", linewidth=7.0,
                solid_capstyle="butt", alpha=0.85, zorder=4)[0]
        for k in range(n)
    )  # fmt: skip
    axis_lines = tuple(
        ax.plot([], [], [], color="black" if k == first.actuated else "0.25",
                linewidth=2.2 if k == first.actuated else 1.2, zorder=5)[0]
        for k in range(n)
    )  # fmt: skip
    style = {"R": ("o", 7.0), "U": ("s", 6.5), "S": ("o", 9.0), "P": ("|", 0.0)}
    joints = []
    for k, kind in enumerate(first.kinds):
        marker, size = style[kind]
        driven = k == first.actuated
        joints.append(
            ax.plot([], [], [], linestyle="", marker=marker, markersize=size,
                    markerfacecolor="0.3" if kind == "S" else ("black" if driven else "white"),
                    markeredgecolor="black", markeredgewidth=2.0 if driven else 1.0, zorder=6)[0]
        )  # fmt: skip
    return links, sleeves, axis_lines, tuple(joints)


def _arrow_artists(
    ax: Any, first: SpatialFrame
) -> tuple[tuple[tuple[Line3D, ...], ...], tuple[tuple[Line3D, ...], ...]]:
    """The force arrows' shafts and heads, ``[leg][joint]``, in joint ``k``'s colour and
    :func:`_arrow_width`, over everything but the path."""
    legs, n = first.points.shape[:2]
    arrows, heads = [], []
    for _ in range(legs):
        arrows.append(tuple(
            ax.plot([], [], [], color=JOINT_COLOURS[k % len(JOINT_COLOURS)],
                    linewidth=_arrow_width(k), zorder=7)[0]
            for k in range(n)
        ))  # fmt: skip
        heads.append(tuple(
            ax.plot([], [], [], color=JOINT_COLOURS[k % len(JOINT_COLOURS)],
                    linewidth=_arrow_width(k), zorder=7)[0]
            for k in range(n)
        ))  # fmt: skip
    return tuple(arrows), tuple(heads)


def _legend(
    figure: Figure,
    frames: list[SpatialFrame],
    joints: tuple[Line3D, ...],
    trace_line: Line3D,
    scale: float,
) -> None:
    """The legend, top right: each joint of a leg (its marker or sleeve), each joint's force
    arrow, the platform origin's path; titled by :func:`scale_heading` and the largest force
    over ``frames``."""
    from matplotlib.lines import Line2D

    first = frames[0]
    handles: list[Any] = []
    labels: list[str] = []
    for k, (label, kind) in enumerate(zip(first.labels, first.kinds, strict=True)):
        actuated = " (actuated)" if k == first.actuated else ""
        if kind == "P":
            handles.append(Line2D([], [], color="black" if actuated else "0.5", linewidth=6.0))
            labels.append(f"{label}: {JOINT_NAMES[kind]}, its sleeve{actuated}")
        else:
            handles.append(joints[k])
            labels.append(
                f"{label}: {JOINT_NAMES[kind]}{', axes' if kind in 'RU' else ''}{actuated}"
            )
    for k, label in enumerate(first.labels):
        handles.append(Line2D([], [], color=JOINT_COLOURS[k % len(JOINT_COLOURS)],
                              linewidth=_arrow_width(k)))  # fmt: skip
        labels.append(f"force at {label} (on the distal body)")
    handles.append(trace_line)
    labels.append("platform origin (+) and its path")
    largest = float(np.linalg.norm(np.stack([f.forces for f in frames]), axis=-1).max())
    heading = scale_heading(scale) + (
        f"\nthe largest force shown: {largest:.3g} N" if scale > 0.0 else ""
    )
    figure.legend(handles, labels, loc="upper right", bbox_to_anchor=(0.995, 0.93), fontsize=8,
                  title=heading, title_fontsize=8.5, framealpha=0.9, ncol=1)  # fmt: skip


def _set(line: Line3D | Line2D, points: FloatArray) -> None:
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    line.set_data_3d(points[:, 0], points[:, 1], points[:, 2])  # type: ignore[union-attr]


def draw_spatial_frame(
    artists: SpatialArtists, frame: SpatialFrame, *, trace: FloatArray | None = None
) -> None:
    """Move the artists to ``frame``; ``trace (m, 3)``: the platform origin's path so far."""
    legs, n = frame.points.shape[:2]
    for i in range(legs):
        _set(artists.links[i], frame.chain[i])
    half = AXIS_HALF * artists.size
    for k in range(n):
        _set(artists.joints[k], frame.points[:, k])
        _set(artists.axes[k], axis_segments(frame.axes[:, k], frame.points[:, k], half))
        bars = frame.sleeves[:, k]
        nan = np.full((legs, 1, 3), np.nan)
        _set(artists.sleeves[k], np.concatenate([bars, nan], axis=1))
        for i in range(legs):
            tail = frame.points[i, k]
            tip = tail + frame.forces[i, k] / artists.scale if artists.scale > 0.0 else tail
            _set(artists.arrows[i][k], np.stack([tail, tip]))
            _set(artists.heads[i][k], _head(tail, tip, artists.size))
    artists.base.set_verts([frame.base])
    artists.platform.set_verts([frame.platform])
    _set(artists.trace, frame.centre[None] if trace is None else trace)
    _set(artists.centre, frame.centre[None])
    artists.clock.set_text(f"t = {frame.t:7.3f} s")


def spatial_pose_figure(
    robot: SpatialRobot, table: Mapping[str, NDArray[Any]], *, index: int = 0, what: str = ""
) -> Figure:
    """The robot at sample ``index`` of a spatial results table, with its joint forces.

    The arrows' scale is that of the whole run (:func:`force_scale`), as in the animation.
    """
    t, q, force = spatial_samples(robot, table)
    k = check_integer("index", index, 0, t.size - 1)
    frames, _, scale = run_frames(robot, t, q, force, [k])
    title = f"{robot.name} at t = {t[k]:g} s" + (f", {what}" if what else "")
    artists = spatial_robot_figure(
        robot, frames, scale=scale, title=title + "\njoint reaction forces"
    )
    return artists.figure


def _rendered_frames(
    artists: SpatialArtists,
    frames: list[SpatialFrame],
    indices: list[int],
    trace: FloatArray,
    progress: Callable[[int, int], None] | None,
) -> list[Any]:
    """The GIF's images, one per frame: the still parts rendered once, the moving artists
    of each frame (the platform's path up to its sample) drawn over them (blitting)."""
    from PIL import Image

    figure, canvas = artists.figure, artists.canvas
    moving = artists.moving()
    for artist in moving:
        artist.set_animated(True)  # left out of the background, drawn per frame
    canvas.draw()  # the axes, panes, legend and titles: rendered once
    background = canvas.copy_from_bbox(figure.bbox)
    images = []
    for done, (index, frame) in enumerate(zip(indices, frames, strict=True), start=1):
        draw_spatial_frame(artists, frame, trace=trace[: index + 1])
        canvas.restore_region(background)
        for artist in moving:
            if hasattr(artist, "do_3d_projection"):
                artist.do_3d_projection()  # a 3-D collection projects before it draws
            figure.draw_artist(artist)
        rgb = np.asarray(artists.canvas.buffer_rgba())[..., :3]
        image = Image.fromarray(np.ascontiguousarray(rgb))
        images.append(image.quantize(colors=256, method=Image.Quantize.FASTOCTREE))
        if progress is not None:
            progress(done, len(frames))
    return images


def save_spatial_animation(
    robot: SpatialRobot,
    table: Mapping[str, NDArray[Any]],
    path: str | Path,
    *,
    max_frames: int = 100,
    title: str = "",
    progress: Callable[[int, int], None] | None = None,
    dpi: float = 100.0,
) -> int:
    """Write an animated GIF of the robot over the samples of a spatial results table.

    Parameters
    ----------
    robot : SpatialRobot
        The robot of the run (its legs' joints name the columns).
    table : mapping of str to (N,) arrays
        The columns of docs/spatial.md §9 (the Newton–Euler route: with the joint forces).
    path : str or Path
        The GIF file, written atomically.
    max_frames : int
        Largest number of frames, ``>= 2``: at most that many samples are shown, in real time
        (:func:`prp3.plotting.animation.frame_schedule`).
    title : str
        The figure's title (default: the robot's name).
    progress : callable, optional
        ``progress(frames_done, frames)`` after each frame.
    dpi : float
        Pixels per inch of the 7.2 in × 7.2 in frames (100: 720 × 720 px).

    Returns
    -------
    int
        The number of frames written.  The view limits and the arrows' scale are those of the
        whole run; the GIF loops forever.
    """

    from prp3.plotting.animation import END_HOLD_MS, frame_schedule

    t, q, force = spatial_samples(robot, table)
    limit = check_integer("max_frames", max_frames, 2, 10**6)
    indices, durations = frame_schedule(t, limit)
    frames, _, scale = run_frames(robot, t, q, force, indices.tolist())
    trace = platform_path(robot, q)
    artists = spatial_robot_figure(
        robot,
        frames,
        scale=scale,
        title=(title or robot.name)
        + f"\njoint reaction forces; plays in real time, then holds the end "
        f"{END_HOLD_MS / 1000:g} s",
        dpi=dpi,
    )
    images = _rendered_frames(artists, frames, indices.tolist(), trace, progress)
    with atomic_path(path) as temporary:
        images[0].save(temporary, format="GIF", save_all=True, append_images=images[1:],
                       duration=durations, loop=0)  # fmt: skip
    return len(images)
