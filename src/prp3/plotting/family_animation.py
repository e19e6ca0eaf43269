"""Animation of a family robot (``prp3 simulate --animate``): the robot's own legs.

What is drawn for a sample is computed by the pure function
:func:`family_frame` from the leg chain (docs/family.md §2) at the sample's
joint values, testable without matplotlib:

* every R joint as a circle at its centre ``O_k``;
* every P joint as a slider (a short bar along its axis ``u_k`` centred on
  ``O_k``) on its guide (a line along ``u_k`` through the joint frame's
  origin: fixed for joint 1, carried by the link before it otherwise);
* the links: link 1 from ``O_1`` to the origin of joint 2's frame, link 2
  from ``O_2`` to the origin of joint 3's frame;
* the platform: the triangle through the three legs' ``O_3``, its mass centre
  ``G`` and the path ``G`` has followed; the driven joint outlined in black.

:func:`save_family_animation` renders the frames with Agg and writes an
animated GIF (Pillow), atomically, in real time (:func:`prp3.plotting.animation.frame_schedule`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from prp3.drawing import GUIDE_OVERHANG, SLIDE_HALF_LENGTH
from prp3.files import atomic_path
from prp3.plotting.figures import LEG_STYLES
from prp3.validation import LEGS

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from prp3.family import FamilyKinematics, FamilyRobot

__all__ = ["FamilyFrame", "family_frame", "save_family_animation"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class FamilyFrame:
    """What one frame shows (fixed-frame coordinates, m).

    Attributes
    ----------
    revolute : ndarray (r, 2)
        Centres of the R joints (the circles).
    revolute_leg : list of int
        The leg of each (0, 1, 2).
    sliders, guides : ndarray (s, 2, 2)
        End points of each P joint's slider bar and of its guide.
    slider_leg : list of int
    driven : list of bool
        Per R joint then per P joint: whether it is the actuated one.
    links : ndarray (3, 2, 2, 2)
        Per leg, link 1 and link 2 as segments.
    platform : ndarray (3, 2)
        The platform triangle (each leg's ``O_3``).
    centre : ndarray (2,)
        ``G``.
    """

    revolute: FloatArray
    revolute_leg: list[int]
    revolute_driven: list[bool]
    sliders: FloatArray
    guides: FloatArray
    slider_leg: list[int]
    slider_driven: list[bool]
    links: FloatArray
    platform: FloatArray
    centre: FloatArray


def family_frame(robot: FamilyRobot, q: FloatArray, pose: FloatArray) -> FamilyFrame:
    """The frame of joint values ``q`` ``(3 legs, 3 joints)`` at the platform pose ``(x, y, φ)``."""
    from prp3.family import leg_chain
    from prp3.family.chain import SIGMA

    frames = leg_chain(robot.types, robot.leg.placements, SIGMA, np.asarray(q, dtype=np.float64))
    act = robot.actuated - 1
    revolute, r_leg, r_driven = [], [], []
    sliders, guides, s_leg, s_driven = [], [], [], []
    links = np.empty((3, 2, 2, 2))
    for j in range(3):
        o, jo, u = frames.origin[j], frames.joint_origin[j], frames.axis[j]
        for k in range(3):
            if robot.types[k] == "R":
                revolute.append(o[k])
                r_leg.append(j)
                r_driven.append(k == act)
            else:
                sliders.append(
                    np.stack([o[k] - SLIDE_HALF_LENGTH * u[k], o[k] + SLIDE_HALF_LENGTH * u[k]])
                )
                travel = float((o[k] - jo[k]) @ u[k])
                low = min(travel, 0.0) - GUIDE_OVERHANG
                high = max(travel, 0.0) + GUIDE_OVERHANG
                guides.append(np.stack([jo[k] + low * u[k], jo[k] + high * u[k]]))
                s_leg.append(j)
                s_driven.append(k == act)
        links[j, 0] = np.stack([o[0], jo[1]])
        links[j, 1] = np.stack([o[1], jo[2]])
    return FamilyFrame(
        revolute=np.array(revolute).reshape(-1, 2),
        revolute_leg=r_leg,
        revolute_driven=r_driven,
        sliders=np.array(sliders).reshape(-1, 2, 2),
        guides=np.array(guides).reshape(-1, 2, 2),
        slider_leg=s_leg,
        slider_driven=s_driven,
        links=links,
        platform=frames.origin[:, 2, :].copy(),
        centre=np.asarray(pose[:2], dtype=np.float64),
    )


def _draw(ax: Axes, frame: FamilyFrame, trace: FloatArray) -> None:
    from matplotlib.patches import Circle, Polygon

    ax.add_patch(Polygon(frame.platform, closed=True, facecolor="0.85", edgecolor="0.3", zorder=1))
    for guide, j in zip(frame.guides, frame.slider_leg, strict=True):
        ax.plot(*guide.T, color="0.35", linewidth=1.0, linestyle="--", zorder=2)
        del j
    for j in range(3):
        colour = LEG_STYLES[LEGS[j]][0]
        for segment in frame.links[j]:
            ax.plot(*segment.T, color=colour, linewidth=3.0, solid_capstyle="round", zorder=3)
    for bar, j, driven in zip(frame.sliders, frame.slider_leg, frame.slider_driven, strict=True):
        ax.plot(*bar.T, color="black" if driven else LEG_STYLES[LEGS[j]][0], linewidth=7.0,
                solid_capstyle="butt", zorder=4)  # fmt: skip
    for centre, j, driven in zip(
        frame.revolute, frame.revolute_leg, frame.revolute_driven, strict=True
    ):
        ax.add_patch(
            Circle(tuple(centre), 0.012, facecolor="white", zorder=5,
                   edgecolor="black" if driven else LEG_STYLES[LEGS[j]][0],
                   linewidth=2.5 if driven else 1.5)
        )  # fmt: skip
    ax.plot(*trace.T, color="tab:red", linewidth=1.0, zorder=6)
    ax.plot(*frame.centre, marker="+", color="black", markersize=10, zorder=7)


def save_family_animation(
    robot: FamilyRobot,
    kin: FamilyKinematics,
    path: str | Path,
    *,
    max_frames: int = 100,
    title: str = "",
    progress: Callable[[int, int], None] | None = None,
    durations: Sequence[int] | None = None,
) -> int:
    """Write an animated GIF of the robot following the samples of ``kin``; return the frames.

    At most ``max_frames`` samples are shown, in real time
    (:func:`prp3.plotting.animation.frame_schedule`), unless ``durations``
    (one per sample, milliseconds) is given.  The axes keep the same limits
    for every frame: the extent of everything drawn over the motion.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from PIL import Image

    from prp3.plotting.animation import frame_schedule

    t = np.atleast_1d(kin.motion.t)
    q = kin.q.reshape(-1, 3, 3)
    pose = kin.motion.pose.reshape(-1, 3)
    if durations is None:
        indices, shown = frame_schedule(t, max_frames)
    else:
        indices, shown = np.arange(t.size, dtype=np.int64), list(durations)
        if len(shown) != t.size:
            raise ValueError(f"durations: one per sample ({t.size}), got {len(shown)}")
    frames = [family_frame(robot, q[i], pose[i]) for i in indices.tolist()]
    points = np.concatenate(
        [
            np.concatenate([f.guides.reshape(-1, 2), f.links.reshape(-1, 2), f.platform])
            for f in frames
        ]
    )
    middle = 0.5 * (points.min(axis=0) + points.max(axis=0))
    half = 0.54 * float((points.max(axis=0) - points.min(axis=0)).max()) + 0.02
    low, high = middle - half, middle + half  # a square window: equal axes, fixed limits
    figure = Figure(figsize=(6.0, 6.0), dpi=90)
    canvas: Any = FigureCanvasAgg(figure)  # its drawing methods are untyped
    ax = figure.add_axes((0.1, 0.08, 0.85, 0.84))
    images = []
    for done, (index, frame) in enumerate(zip(indices.tolist(), frames, strict=True), start=1):
        ax.cla()
        _draw(ax, frame, pose[: index + 1, :2])
        ax.set_xlim(low[0], high[0])
        ax.set_ylim(low[1], high[1])
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.grid(True, color="0.92")
        name = title or f"{robot.architecture} (joint {robot.actuated} driven)"
        ax.set_title(f"{name}\nt = {t[index]:.3f} s (real time)", fontsize=10)
        canvas.draw()
        rgb = np.asarray(canvas.buffer_rgba())[..., :3]
        image = Image.fromarray(np.ascontiguousarray(rgb))
        images.append(image.quantize(colors=256, method=Image.Quantize.FASTOCTREE))
        if progress is not None:
            progress(done, len(frames))
    with atomic_path(path) as temporary:
        images[0].save(temporary, format="GIF", save_all=True, append_images=images[1:],
                       duration=shown, loop=0)  # fmt: skip
    return len(images)
