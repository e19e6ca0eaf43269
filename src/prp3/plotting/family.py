"""Figures of a family robot's run (docs/family.md): actuator efforts and powers, every joint force.

Built from the 64 columns of a family-form ``results.csv``
(:data:`prp3.family.FAMILY_COLUMNS`); matplotlib is imported inside the
functions only, figures rendered by Agg without pyplot.

>>> family_figure_names()
('tau.png', 'power.png', 'joint_forces.png')
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from prp3.plotting.figures import LEG_MARKERS, LEG_STYLES, leg_figure, motion_description
from prp3.validation import LEGS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from prp3.family import FamilyRobot

__all__ = ["designs_figure", "family_figure_names", "family_figures", "joint_forces_figure"]

FloatArray = NDArray[np.float64]


def family_figure_names() -> tuple[str, ...]:
    """The PNG files ``prp3 simulate --plots`` writes for a family robot."""
    return ("tau.png", "power.png", "joint_forces.png")


def _legs(table: Mapping[str, FloatArray], column: str) -> FloatArray:
    return np.stack([np.asarray(table[f"{column}_{leg}"], dtype=np.float64) for leg in LEGS], -1)


def joint_forces_figure(
    table: Mapping[str, FloatArray], *, title: str, subtitle: str, types: str, actuated: int
) -> Figure:
    """Every joint force: rows ``fx``, ``fy`` (N) and ``m`` (N·m), one column per joint, 3 legs each.

    The moment of a passive revolute joint is zero by definition (docs/family.md
    §7): its axes say so instead of drawing round-off.
    """
    from matplotlib.figure import Figure

    t = np.asarray(table["t"], dtype=np.float64)
    figure = Figure(figsize=(12.0, 8.0), dpi=110, layout="constrained")
    axes = figure.subplots(3, 3, sharex=True)
    rows = (("fx", "$f_x$ (N)"), ("fy", "$f_y$ (N)"), ("m", "$m$ about $O_k$ (N·m)"))
    step = max(len(t) // 10, 1)
    for k in range(3):
        for r, (name, label) in enumerate(rows):
            ax = axes[r, k]
            if name == "m" and types[k] == "R" and k != actuated - 1:
                ax.text(
                    0.5,
                    0.5,
                    "$m = 0$: a passive revolute joint\ntransmits no moment",
                    ha="center",
                    va="center",
                    transform=ax.transAxes,
                    color="0.35",
                )
                ax.set_yticks([])
                if k == 0:
                    ax.set_ylabel(label)
                ax.set_xlabel("time $t$ (s)")
                continue
            values = _legs(table, f"{name}{k + 1}")
            for j, leg in enumerate(LEGS):
                color, style = LEG_STYLES[leg]
                ax.plot(
                    t,
                    values[:, j],
                    color=color,
                    linestyle=style,
                    linewidth=1.6,
                    marker=LEG_MARKERS[leg],
                    markersize=4,
                    markevery=(j * step // 3, step),
                    label=f"leg {leg}",
                )
            ax.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
            ax.grid(True, color="0.88")
            ax.set_xlim(float(t[0]), float(t[-1]))
            if r == 0:
                ax.set_title(f"joint {k + 1} ({types[k]})", fontsize=11)
            if k == 0:
                ax.set_ylabel(label)
            if r == 2:
                ax.set_xlabel("time $t$ (s)")
    axes[0, 2].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    figure.suptitle(
        f"{title}\n{subtitle}: force of the proximal on the distal body through each joint",
        fontsize=12,
    )
    return figure


def family_figures(
    table: Mapping[str, FloatArray],
    *,
    architecture: str,
    actuated: int,
    motion: str | None = None,
    source: str | None = None,
) -> dict[str, Figure]:
    """The figures of a family run: ``tau.png``, ``power.png``, ``joint_forces.png``.

    Parameters
    ----------
    table : mapping
        The 64 family columns (``(N,)`` arrays).
    architecture : str
        ``"3-RRR"`` ...; ``actuated`` its driven joint (1..3).
    motion, source : str, optional
        The paper motion's name, or the trajectory file, for the subtitles.
    """
    t = np.asarray(table["t"], dtype=np.float64)
    types = architecture[2:]
    kind = types[actuated - 1]
    unit = "N" if kind == "P" else "N·m"
    what = motion_description(motion, source)
    joint = f"joint {actuated} ({'prismatic' if kind == 'P' else 'revolute'})"
    return {
        "tau.png": leg_figure(
            t,
            _legs(table, "tau"),
            title=f"{architecture}: actuator effort",
            ylabel=f"$\\tau$ ({unit})",
            subtitle=f"{what}; actuated {joint}",
            symbol="\\tau",
        ),
        "power.png": leg_figure(
            t,
            _legs(table, "p"),
            title=f"{architecture}: actuator power",
            ylabel="$p = \\tau\\,\\dot q_a$ (W)",
            subtitle=f"{what}; actuated {joint}",
            symbol="p",
        ),
        "joint_forces.png": joint_forces_figure(
            table,
            title=f"{architecture}: every joint force",
            subtitle=what,
            types=types,
            actuated=actuated,
        ),
    }


def _draw_design(ax: Axes, robot: FamilyRobot) -> None:
    """One design at home: ground, guides, sliders, pivots, links, platform, ``G``."""
    from matplotlib.patches import Polygon

    from prp3.family import leg_chain
    from prp3.family.chain import SIGMA

    types = robot.types
    q = np.tile(np.asarray(robot.leg.home), (3, 1))
    frames = leg_chain(types, robot.leg.placements, SIGMA, q)
    act = robot.actuated - 1
    distal = frames.origin[:, 2, :]
    ax.add_patch(Polygon(distal, closed=True, facecolor="0.85", edgecolor="0.3", zorder=1))
    for j, leg in enumerate(LEGS):
        color = LEG_STYLES[leg][0]
        o, jo, u = frames.origin[j], frames.joint_origin[j], frames.axis[j]
        # links: from joint k's origin to joint k+1's frame origin (on the proximal body)
        for k in (0, 1):
            ax.plot(*np.stack([o[k], jo[k + 1]]).T, color=color, linewidth=3.0, zorder=2)
        ax.plot(
            *np.stack([o[2], frames.end_origin[j]]).T,
            color="0.4",
            linewidth=1.0,
            linestyle=":",
            zorder=2,
        )
        for k in range(3):
            _draw_joint(ax, types[k], k, (o[k], jo[k], u[k]), color, driven=k == act)
        if types[0] == "R":  # a ground mark under the base pivot
            base = o[0]
            ax.add_patch(
                Polygon(
                    base + np.array([[0, 0], [-0.02, -0.03], [0.02, -0.03]]),
                    closed=True,
                    facecolor="0.3",
                    zorder=3,
                )
            )
    ax.plot(0.0, 0.0, marker="+", color="black", markersize=10, zorder=5)
    ax.set_aspect("equal")
    ax.set_xlim(-0.45, 0.45)
    ax.set_ylim(-0.45, 0.45)
    ax.set_xticks([-0.4, 0.0, 0.4])
    ax.set_yticks([-0.4, 0.0, 0.4])
    ax.grid(True, color="0.92")
    ax.set_title(f"{robot.architecture} (joint {robot.actuated} driven)", fontsize=11)


def _draw_joint(
    ax: Axes,
    kind: str,
    k: int,
    frame: tuple[FloatArray, FloatArray, FloatArray],
    color: str,
    *,
    driven: bool,
) -> None:
    """Joint ``k`` of a leg (``kind`` R or P) at its origin ``o``, joint origin ``jo`` and axis
    ``u`` (``frame``): a pivot, or a slider on its guide; the driven one edged in black."""
    from matplotlib.patches import Rectangle

    o, jo, u = frame
    edge = "black" if driven else color
    if kind == "R":
        ax.plot(
            *o,
            marker="o",
            markersize=9,
            markerfacecolor="white",
            markeredgecolor=edge,
            markeredgewidth=2.5 if driven else 1.5,
            zorder=4,
        )
    else:
        stroke = float((o - jo) @ u)
        low, high = min(stroke, 0.0) - 0.07, max(stroke, 0.0) + 0.07
        guide = np.stack([jo + low * u, jo + high * u])
        ax.plot(
            *guide.T,
            color="0.2" if k == 0 else color,
            linewidth=1.2,
            linestyle="-" if k == 0 else "--",
            zorder=2,
        )
        if k > 0:  # the proximal link runs along its guide to the slider
            ax.plot(*np.stack([jo, o]).T, color=color, linewidth=3.0, zorder=2)
        angle = float(np.degrees(np.arctan2(u[1], u[0])))
        w, h = 0.05, 0.025
        corner = o - (w / 2) * u - (h / 2) * np.array([-u[1], u[0]])
        ax.add_patch(
            Rectangle(
                tuple(corner),
                w,
                h,
                angle=angle,
                facecolor="white",
                edgecolor=edge,
                linewidth=2.5 if driven else 1.5,
                zorder=3,
            )
        )


def designs_figure(robots: list[FamilyRobot]) -> Figure:
    """The default designs at home (docs/family.md §3): one axes each, metres.

    Pivots are circles, sliders rectangles on their guides (dashed when the
    guide is on a moving link), the driven joint outlined in black, the platform
    the grey triangle through the three platform-side joints, ``G`` the cross.
    """
    from matplotlib.figure import Figure

    columns = 4
    rows = -(-len(robots) // columns)
    figure = Figure(figsize=(3.3 * columns, 3.5 * rows), dpi=110, layout="constrained")
    axes = figure.subplots(rows, columns, squeeze=False)
    for index, ax in enumerate(axes.flat):
        if index < len(robots):
            _draw_design(ax, robots[index])
        else:
            ax.axis("off")
            lines = [
                "legs A, B, C: blue, orange, green",
                "o  revolute joint",
                "[ ]  slider on its guide",
                "     (dashed: guide on a link)",
                "black outline: driven joint",
                "grey: platform; +: G at home",
                "axes in metres",
            ]
            ax.text(0.02, 0.95, "\n".join(lines), va="top", fontsize=10, transform=ax.transAxes)
    figure.suptitle("The default designs of the family at home (x = y = phi = 0)", fontsize=13)
    return figure
