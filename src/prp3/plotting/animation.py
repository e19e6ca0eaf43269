"""Animation of the mechanism: base triangle, pistons, sleeves, platform, mass centre trace.

What is drawn for a sample is computed by the pure function
:func:`mechanism_frame` (plain arrays, testable without matplotlib):

* the base triangle ``A0 B0 C0`` (its edges are the actuators' guides);
* on edge ``i`` the piston (actuated slider) as a thick bar along ``e_i``
  centred on the revolute joint ``P_i``;
* the sleeve (link 2) turning about ``P_i``, a bar along ``d_i``, through
  which the platform edge slides;
* the platform triangle, its mass centre ``G`` and the path ``G`` has followed;
* the time stamp.

:func:`mechanism_figure` builds the matplotlib artists once and
:func:`draw_frame` moves them to a :class:`MechanismFrame`;
:func:`save_animation` writes the frames as an animated GIF: the still background is
rendered once, the moving artists are drawn over it for each frame (blitting)
and Pillow (a dependency of matplotlib) writes the GIF.  matplotlib is imported inside the
functions only.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from prp3.drawing import PISTON_HALF_LENGTH, SLEEVE_HALF_LENGTH
from prp3.files import atomic_path
from prp3.mechanics.geometry import LEG_AXIS, base_vertices, platform_vertices
from prp3.mechanics.kinematics import Kinematics
from prp3.model.robot import Robot
from prp3.plotting.figures import LEG_STYLES
from prp3.validation import LEGS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon
    from matplotlib.text import Text

__all__ = [
    "MAX_FRAMES",
    "MechanismArtists",
    "MechanismFrame",
    "draw_frame",
    "frame_indices",
    "frame_schedule",
    "mechanism_figure",
    "mechanism_frame",
    "save_animation",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Default largest number of frames of an animation (the samples are thinned out).
MAX_FRAMES: int = 100


@dataclass(frozen=True)
class MechanismFrame:
    """Coordinates of everything drawn for one sample (m, fixed frame).

    Attributes
    ----------
    t : float
        Time of the sample (s).
    base : ndarray (3, 2)
        Base vertices ``A0, B0, C0``.
    joints : ndarray (3, 2)
        Revolute joint centres ``P_A, P_B, P_C``.
    pistons : ndarray (3, 2, 2)
        End points of each piston bar, along ``e_i`` and centred on ``P_i``.
    sleeves : ndarray (3, 2, 2)
        End points of each sleeve bar, along ``d_i`` and centred on ``P_i``.
    platform : ndarray (3, 2)
        Platform vertices; the edge through ``P_i`` joins vertices
        ``i + 1`` and ``i + 2`` (mod 3).
    centre : ndarray (2,)
        Platform mass centre ``G``.
    trace : ndarray (k + 1, 2)
        ``G`` at the samples ``0 … k`` of the kinematics, ``k`` the frame's index.
    """

    t: float
    base: FloatArray
    joints: FloatArray
    pistons: FloatArray
    sleeves: FloatArray
    platform: FloatArray
    centre: FloatArray
    trace: FloatArray


def mechanism_frame(robot: Robot, kin: Kinematics, index: int) -> MechanismFrame:
    """What to draw for sample ``index`` of ``kin`` (batch kinematics ``(N, …)``).

    >>> from prp3.mechanics.kinematics import inverse_kinematics
    >>> from prp3.model.motion import paper_motion
    >>> robot = Robot()
    >>> frame = mechanism_frame(robot, inverse_kinematics(robot, paper_motion("vertical", 5)), 0)
    >>> frame.joints[0].round(4).tolist(), frame.trace.shape    # P_A = A0 + (l0/√3)·e_A at t = 0
    ([0.0866, -0.15], (1, 2))
    """
    geometry = kin.geometry
    joints = np.array(geometry.joint[index], dtype=np.float64)
    slide = geometry.slide[index]
    piston_half = PISTON_HALF_LENGTH * robot.l0 * LEG_AXIS
    sleeve_half = SLEEVE_HALF_LENGTH * robot.l0 * slide
    pose = kin.motion.pose
    return MechanismFrame(
        t=float(kin.motion.t[index]),
        base=base_vertices(robot),
        joints=joints,
        pistons=np.stack([joints - piston_half, joints + piston_half], axis=1),
        sleeves=np.stack([joints - sleeve_half, joints + sleeve_half], axis=1),
        platform=platform_vertices(robot, pose[index]),
        centre=np.array(pose[index, :2], dtype=np.float64),
        trace=np.array(pose[: index + 1, :2], dtype=np.float64),
    )


#: How long the last frame stays before the animation loops (ms).
END_HOLD_MS: int = 500


def frame_schedule(t: FloatArray, max_frames: int = MAX_FRAMES) -> tuple[IntArray, list[int]]:
    """The samples shown as frames and how long each is shown, so that the motion plays in real time.

    At most ``max_frames`` samples are spread evenly (:func:`frame_indices`),
    fewer when a frame would last less than 30 ms on average.  Frame ``k``
    lasts until the next frame's time: the durations are the differences of
    the frame times rounded to the hundredths of a second a GIF counts in
    (rounded together, so that they add up to the motion's duration), every
    one at least 20 ms (a frame that would be shorter is left out).  The last
    frame, the end of the motion, is held :data:`END_HOLD_MS` before the
    animation loops.

    Parameters
    ----------
    t : ndarray (N,)
        Strictly increasing sample times (s), ``N >= 1``.
    max_frames : int
        Largest number of frames, ``>= 2``.

    Returns
    -------
    indices : ndarray of int (M,)
        The samples shown, first and last included.
    durations : list of int (M,)
        Milliseconds each frame is shown, multiples of 10.

    Examples
    --------
    >>> indices, durations = frame_schedule(np.linspace(0.0, 2.0, 201), 5)
    >>> indices.tolist(), durations, sum(durations[:-1])   # 2 s in real time
    ([0, 50, 100, 150, 200], [500, 500, 500, 500, 500], 2000)
    """
    times = np.asarray(t, dtype=np.float64)
    samples = times.size
    if samples == 1:
        return np.zeros(1, dtype=np.int64), [END_HOLD_MS]
    hundredths = 100.0 * (times - times[0])
    limit = max(2, min(max_frames, int(hundredths[-1] // 3) + 1))
    spread = frame_indices(samples, limit)
    bounds = np.rint(hundredths[spread]).astype(np.int64)
    kept = [0]
    for k in range(1, spread.size - 1):
        if bounds[k] - bounds[kept[-1]] >= 2:
            kept.append(k)
    if len(kept) > 1 and bounds[-1] - bounds[kept[-1]] < 2:
        kept.pop()
    kept.append(spread.size - 1)
    chosen = bounds[kept]
    durations = [10 * max(int(step), 2) for step in np.diff(chosen)] + [END_HOLD_MS]
    return spread[kept], durations


def frame_indices(samples: int, max_frames: int = MAX_FRAMES) -> IntArray:
    """Indices of the samples shown as frames: all, or ``max_frames`` evenly spread.

    The first and last samples are always included.

    >>> frame_indices(5).tolist(), frame_indices(1001, 5).tolist()
    ([0, 1, 2, 3, 4], [0, 250, 500, 750, 1000])
    """
    if samples <= max_frames:
        return np.arange(samples, dtype=np.int64)
    spread = np.rint(np.linspace(0.0, samples - 1.0, max(max_frames, 2)))
    return np.unique(spread.astype(np.int64))


@dataclass(frozen=True)
class MechanismArtists:
    """The matplotlib artists :func:`draw_frame` moves."""

    figure: Figure
    canvas: Any  # FigureCanvasAgg, whose blitting methods matplotlib leaves untyped
    pistons: tuple[Line2D, ...]
    sleeves: tuple[Line2D, ...]
    joints: Line2D
    platform: Polygon
    centre: Line2D
    trace: Line2D
    clock: Text

    def moving(self) -> list[Any]:
        """Every artist that changes from frame to frame, bottom to top (drawing order)."""
        return [
            self.platform,
            *self.pistons,
            *self.sleeves,
            self.joints,
            self.trace,
            self.centre,
            self.clock,
        ]


def _draw_base(axes: Axes, robot: Robot, kin: Kinematics) -> None:
    """The still parts: the base triangle with its vertices' and legs' names, the axes'
    limits (the base and the platform over every sample of ``kin``, with a margin) and
    labels."""
    from matplotlib.patches import Polygon

    base = base_vertices(robot)
    extent = np.concatenate([base, platform_vertices(robot, kin.motion.pose).reshape(-1, 2)])
    low, high = extent.min(axis=0), extent.max(axis=0)
    margin = 0.15 * robot.l0
    axes.set_xlim(float(low[0] - margin), float(high[0] + margin))
    axes.set_ylim(float(low[1] - margin), float(high[1] + margin))
    axes.set_aspect("equal")
    axes.set_xlabel("$x_0$ (m)")
    axes.set_ylabel("$y_0$ (m)")
    axes.grid(True, color="0.92")
    axes.add_patch(Polygon(base, closed=True, facecolor="0.95", edgecolor="0.35", linewidth=1.5))
    for j, name in enumerate(("$A_0$", "$B_0$", "$C_0$")):
        offset = 0.07 * robot.l0 * base[j] / np.linalg.norm(base[j])
        x, y = (base[j] + offset).tolist()
        axes.text(x, y, name, ha="center", va="center", color="0.3")
    for j, leg in enumerate(LEGS):  # the legs' names beside their guides, outside the base
        # guide j runs from base vertex j along e_j to the next vertex (A0 -> B0 for leg A)
        midpoint = 0.5 * (base[j] + base[(j + 1) % 3])
        outward = midpoint / np.linalg.norm(midpoint)
        x, y = (midpoint + 0.17 * robot.l0 * outward).tolist()
        axes.text(
            x, y, f"leg {leg}", ha="center", va="center", color=LEG_STYLES[leg][0],
            fontsize=12, fontweight="bold",
        )  # fmt: skip


def mechanism_figure(robot: Robot, kin: Kinematics, *, title: str = "") -> MechanismArtists:
    """Build the figure and its artists for the samples of ``kin``.

    The axes keep the same limits for every frame (the extent of the base
    and of the platform over all the samples) and an equal aspect ratio.
    The artists show sample 0 until :func:`draw_frame` moves them.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    figure = Figure(figsize=(7.2, 7.2), dpi=100, layout="constrained")  # 720 x 720 px
    canvas = FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    _draw_base(axes, robot, kin)
    platform = Polygon(
        np.zeros((3, 2)),
        closed=True,
        facecolor=(0.58, 0.40, 0.74, 0.25),  # translucent fill, opaque edges
        edgecolor="indigo",
        linewidth=1.5,
        label="platform",
    )
    axes.add_patch(platform)
    pistons = []
    sleeves = []
    for leg in LEGS:
        color, _ = LEG_STYLES[leg]
        (piston,) = axes.plot([], [], color=color, linewidth=9, solid_capstyle="butt")
        (sleeve,) = axes.plot([], [], color="0.1", linewidth=5, solid_capstyle="butt")
        pistons.append(piston)
        sleeves.append(sleeve)
    sleeves[0].set_label("sleeves (links 2)")
    (joints,) = axes.plot([], [], "o", color="white", markeredgecolor="black", markersize=6)
    (trace,) = axes.plot([], [], color="tab:red", linewidth=1.2, label="path of G")
    (centre,) = axes.plot([], [], "o", color="tab:red", markersize=5)
    clock = axes.text(0.03, 0.96, "", transform=axes.transAxes, va="top", family="monospace")
    from matplotlib.legend_handler import HandlerTuple

    found, labels = axes.get_legend_handles_labels()
    handles: list[Any] = list(found)
    handles.insert(1, tuple(pistons))  # one swatch per piston, in its leg's colour
    labels.insert(1, "pistons of legs A, B, C")
    axes.legend(
        handles,
        labels,
        handler_map={tuple: HandlerTuple(ndivide=None, pad=0.0)},
        loc="lower right",
        fontsize=9,
        framealpha=0.9,
    )
    axes.set_title(
        (title or "3-PRP planar parallel robot")
        + f"\nplays in real time, then holds the end {END_HOLD_MS / 1000:g} s",
        fontsize=11,
    )
    artists = MechanismArtists(
        figure=figure,
        canvas=canvas,
        pistons=tuple(pistons),
        sleeves=tuple(sleeves),
        joints=joints,
        platform=platform,
        centre=centre,
        trace=trace,
        clock=clock,
    )
    draw_frame(artists, mechanism_frame(robot, kin, 0))
    return artists


def draw_frame(artists: MechanismArtists, frame: MechanismFrame) -> list[Any]:
    """Move the artists to ``frame``; return the artists that changed."""
    for j in range(3):
        artists.pistons[j].set_data(frame.pistons[j, :, 0], frame.pistons[j, :, 1])
        artists.sleeves[j].set_data(frame.sleeves[j, :, 0], frame.sleeves[j, :, 1])
    artists.joints.set_data(frame.joints[:, 0], frame.joints[:, 1])
    artists.platform.set_xy(frame.platform)
    artists.centre.set_data([frame.centre[0]], [frame.centre[1]])
    artists.trace.set_data(frame.trace[:, 0], frame.trace[:, 1])
    artists.clock.set_text(f"t = {frame.t:7.3f} s")
    return artists.moving()


def save_animation(
    robot: Robot,
    kin: Kinematics,
    path: str | Path,
    *,
    max_frames: int = MAX_FRAMES,
    title: str = "",
    progress: Callable[[int, int], None] | None = None,
    durations: Sequence[int] | None = None,
) -> int:
    """Write an animated GIF of the mechanism following the samples of ``kin``.

    Parameters
    ----------
    robot : Robot
    kin : Kinematics
        Batch kinematics ``(N, …)``, ``N >= 1``; at most ``max_frames`` of
        its samples become frames (:func:`frame_schedule`: real time), unless
        ``durations`` is given.
    path : str or Path
        The GIF file, written atomically.
    max_frames : int
        Largest number of frames.
    title : str
        Axes title (default: the robot's name).
    progress : callable, optional
        ``progress(frames_done, frames)`` after each frame.
    durations : sequence of int, optional
        Milliseconds each sample of ``kin`` is shown (one per sample, every
        sample a frame), e.g. from :func:`frame_schedule` of a longer motion.

    Returns
    -------
    int
        The number of frames written.  The GIF loops forever; it plays in real
        time (see :func:`frame_schedule`), which its title says.
    """
    from PIL import Image

    if durations is None:
        indices, shown = frame_schedule(np.atleast_1d(kin.motion.t), max_frames)
    else:
        indices, shown = np.arange(kin.motion.samples, dtype=np.int64), list(durations)
        if len(shown) != kin.motion.samples:
            raise ValueError(f"durations: one per sample ({kin.motion.samples}), got {len(shown)}")
    artists = mechanism_figure(robot, kin, title=title)
    figure, canvas = artists.figure, artists.canvas
    moving = artists.moving()
    for artist in moving:
        artist.set_animated(True)  # left out of the background, drawn per frame
    canvas.draw()  # lays the figure out once and renders the still background
    figure.set_layout_engine("none")
    background = canvas.copy_from_bbox(figure.bbox)
    frames = []
    for done, index in enumerate(indices.tolist(), start=1):
        draw_frame(artists, mechanism_frame(robot, kin, index))
        canvas.restore_region(background)
        for artist in moving:
            figure.draw_artist(artist)
        rgb = np.asarray(canvas.buffer_rgba())[..., :3]
        image = Image.fromarray(np.ascontiguousarray(rgb))
        frames.append(image.quantize(colors=256, method=Image.Quantize.FASTOCTREE))
        if progress is not None:
            progress(done, len(indices))
    with atomic_path(path) as temporary:
        frames[0].save(
            temporary,
            format="GIF",
            save_all=True,
            append_images=frames[1:],
            duration=shown,
            loop=0,
        )
    return len(indices)
