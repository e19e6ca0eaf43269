"""Figures of a spatial robot's run (docs/spatial.md §15): actuator efforts, joint reactions, pose.

Built from the columns of a spatial ``results.csv`` (docs/spatial.md §9,
:func:`prp3.spatial.outputs.spatial_results_table`): ``efforts.png`` (each
leg's actuator effort and power against time), ``joint_reactions.png``
(the magnitudes ``|F|`` and ``|M|`` of every joint's wrench, one column of
axes per joint of the legs) and ``pose.png`` (the robot in 3-D at the first
sample with its joint forces as arrows:
:func:`prp3.plotting.spatial_animation.spatial_pose_figure`).  matplotlib is
imported inside the functions only; the figures are rendered by Agg, without pyplot.

>>> spatial_figure_names()
('efforts.png', 'joint_reactions.png', 'pose.png')
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from prp3.plotting.spatial_animation import LEG_COLOURS, spatial_pose_figure
from prp3.spatial.model import SpatialRobot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "joint_reactions_figure",
    "platform_motion_figure",
    "spatial_efforts_figure",
    "spatial_figure_names",
    "spatial_figures",
]

FloatArray = NDArray[np.float64]

#: Line styles of the legs (the colours of :data:`LEG_COLOURS`, and dashes for legs 4 to 6).
_LEG_DASHES = ("-", "-", "-", "--", "--", "--")

_JOINT_NAMES = {"R": "revolute", "P": "prismatic", "U": "universal", "S": "spherical"}


def spatial_figure_names() -> tuple[str, ...]:
    """The PNG files ``prp3 simulate --plots`` writes for a spatial robot."""
    return ("efforts.png", "joint_reactions.png", "pose.png")


def _column(table: Mapping[str, FloatArray], name: str) -> FloatArray:
    return np.asarray(table[name], dtype=np.float64)


def _plot_legs(ax: Axes, t: FloatArray, values: list[FloatArray]) -> None:
    for i, column in enumerate(values):
        ax.plot(
            t,
            column,
            color=LEG_COLOURS[i % len(LEG_COLOURS)],
            linestyle=_LEG_DASHES[i % len(_LEG_DASHES)],
            linewidth=1.5,
            label=f"leg {i + 1}",
        )
    ax.grid(True, color="0.88")
    ax.set_xlim(float(t[0]), float(t[-1]))


def spatial_efforts_figure(
    table: Mapping[str, FloatArray], robot: SpatialRobot, what: str
) -> Figure:
    """Each leg's actuator effort ``tau`` (top) and power (bottom) against time."""
    from matplotlib.figure import Figure

    t = _column(table, "t")
    legs = len(robot.legs)
    leg = robot.legs[0]
    joint = leg.joints[leg.actuated]
    unit = "N" if joint.kind == "P" else "N·m"
    figure = Figure(figsize=(9.0, 6.4), dpi=110, layout="constrained")
    top, bottom = figure.subplots(2, 1, sharex=True)
    _plot_legs(top, t, [_column(table, f"tau_{i + 1}") for i in range(legs)])
    _plot_legs(bottom, t, [_column(table, f"power_{i + 1}") for i in range(legs)])
    top.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
    bottom.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
    top.set_ylabel(f"effort $\\tau$ ({unit})")
    bottom.set_ylabel("power $\\tau\\,\\dot q_a$ (W)")
    bottom.set_xlabel("time $t$ (s)")
    top.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    label = leg.labels[leg.actuated]
    figure.suptitle(
        f"{robot.name}: actuator efforts ({label}, {_JOINT_NAMES[joint.kind]}, of each leg)\n{what}",
        fontsize=12,
    )
    return figure


def platform_motion_figure(
    t: FloatArray,
    position: FloatArray,
    rpy: FloatArray,
    robot: SpatialRobot,
    what: str,
    planned: tuple[FloatArray, FloatArray] | None = None,
) -> Figure:
    """The platform's position ``p − p(0)`` (mm, top) and roll, pitch, yaw (mrad, bottom).

    ``position (N, 3)`` m, ``rpy (N, 3)`` rad; ``planned``, the same of a planned
    motion at the same times, is drawn dotted (``prp3 forward`` of a ``results.csv``).
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(9.0, 6.4), dpi=110, layout="constrained")
    top, bottom = figure.subplots(2, 1, sharex=True)
    colours = LEG_COLOURS[:3]
    origin = position[0]
    for c, name in enumerate("xyz"):
        top.plot(t, 1e3 * (position[:, c] - origin[c]), color=colours[c], label=name)
    for c, name in enumerate(("roll", "pitch", "yaw")):
        bottom.plot(t, 1e3 * rpy[:, c], color=colours[c], label=name)
    if planned is not None:
        for c in range(3):
            top.plot(t, 1e3 * (planned[0][:, c] - origin[c]), color="0.2", linestyle=":",
                     linewidth=1.0, label="planned" if c == 0 else None)  # fmt: skip
            bottom.plot(t, 1e3 * planned[1][:, c], color="0.2", linestyle=":",
                        linewidth=1.0, label="planned" if c == 0 else None)  # fmt: skip
    for ax in (top, bottom):
        ax.grid(True, color="0.88")
        ax.set_xlim(float(t[0]), float(t[-1]))
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    top.set_ylabel("$p - p(t_0)$ (mm)")
    bottom.set_ylabel("roll, pitch, yaw (mrad)")
    bottom.set_xlabel("time $t$ (s)")
    figure.suptitle(f"{robot.name}: platform motion integrated from the efforts\n{what}",
                    fontsize=12)  # fmt: skip
    return figure


def joint_reactions_figure(
    table: Mapping[str, FloatArray], robot: SpatialRobot, what: str
) -> Figure:
    """``|F|`` (N, top row) and ``|M|`` (N·m, bottom row) of every joint, one column per joint.

    A passive S joint transmits no moment (docs/spatial.md §8: ``M = 0``): its axes say so
    instead of drawing round-off.
    """
    from matplotlib.figure import Figure

    t = _column(table, "t")
    leg = robot.legs[0]
    legs = len(robot.legs)
    columns = len(leg.joints)
    figure = Figure(figsize=(4.0 * columns + 1.6, 6.4), dpi=110, layout="constrained")
    axes = figure.subplots(2, columns, sharex=True, squeeze=False)
    for k, (joint, label) in enumerate(zip(leg.joints, leg.labels, strict=True)):
        for row, (kind, unit) in enumerate((("F", "N"), ("M", "N·m"))):
            ax = axes[row, k]
            if row == 0:
                ax.set_title(f"{label} ({_JOINT_NAMES[joint.kind]})", fontsize=11)
            if row == 1:
                ax.set_xlabel("time $t$ (s)")
            if k == 0:
                symbol = "|F|" if kind == "F" else "|M|"
                ax.set_ylabel(f"${symbol}$ ({unit})")
            if kind == "M" and joint.kind == "S" and k != leg.actuated:
                ax.text(
                    0.5, 0.5, "$M = 0$: a spherical joint\ntransmits no moment",
                    ha="center", va="center", transform=ax.transAxes, color="0.35",
                )  # fmt: skip
                ax.set_yticks([])
                continue
            magnitudes = [
                np.sqrt(sum(_column(table, f"{kind}{c}_{i + 1}_{label}") ** 2 for c in "xyz"))
                for i in range(legs)
            ]
            _plot_legs(ax, t, magnitudes)
            ax.set_ylim(bottom=0.0)
    axes[0, -1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    figure.suptitle(
        f"{robot.name}: joint reactions, magnitudes of the wrench the proximal body exerts "
        f"on the distal one (world frame, at the joint point)\n{what}",
        fontsize=12,
    )
    return figure


def spatial_figures(
    table: Mapping[str, FloatArray], robot: SpatialRobot, *, what: str
) -> dict[str, Figure]:
    """The figures of a spatial run by file name (:func:`spatial_figure_names`).

    Parameters
    ----------
    table : mapping of str to (N,) arrays
        The columns of docs/spatial.md §9 (the Newton–Euler route: with the wrenches).
    robot : SpatialRobot
        The robot of the run (its legs' joints name the columns).
    what : str
        The motion shown, for the titles (``"heave motion"``, ``"trajectory traj.csv"``).
    """
    return {
        "efforts.png": spatial_efforts_figure(table, robot, what),
        "joint_reactions.png": joint_reactions_figure(table, robot, what),
        "pose.png": spatial_pose_figure(robot, table, index=0, what=what),
    }
