"""The self-contained HTML file of a run: ``prp3 simulate --html``, ``prp3 explore --export``.

The frames of the run (at most :data:`~prp3.explorer.scrubber.MAX_HTML_FRAMES`)
are precomputed by the page's scene (:func:`prp3.explorer.scene.scene_view`,
or the family's); the few lines of ``CustomJS`` of
:func:`~prp3.explorer.scrubber.browser_scrubber` only copy frame ``k``'s columns
into the drawn sources (no force is computed in the browser).  Bokeh's
JavaScript is inline: the file opens offline.  Bokeh is imported inside the
functions only.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.explorer.app import PLOTTED, build_robot_figure, figure_sources
from prp3.explorer.page import escape, results_table
from prp3.explorer.scene import PRP3_SCENE, View, arrow_scale, stroke_bands
from prp3.explorer.scrubber import run_page
from prp3.family import FamilyRobot
from prp3.files import atomic_writer
from prp3.model.robot import Robot

__all__ = ["run_html", "write_run_html"]

FloatArray = NDArray[np.float64]


def run_html(robot: Robot | FamilyRobot, table: Mapping[str, FloatArray], title: str) -> str:
    """One self-contained HTML page of a run: the robot with its force arrows, and linked plots.

    Parameters
    ----------
    robot : Robot or FamilyRobot
        The robot of the run; a family robot's page is
        :func:`prp3.explorer.family_app.family_run_html`.
    table : mapping of str to ndarray (N,)
        The run's columns of ``results.csv`` (``prp3 simulate``'s table; the
        64 of the family form for a family robot).
    title : str
        The page's title.

    Returns
    -------
    str
        The page, with Bokeh's JavaScript inline (``bokeh.resources.INLINE``):
        it opens offline.  At most :data:`~prp3.explorer.scrubber.MAX_HTML_FRAMES`
        frames, precomputed by :func:`prp3.explorer.scene.scene_view`; the
        scrubber and the play button only pick a frame.
    """
    if isinstance(robot, FamilyRobot):
        from prp3.explorer.family_app import family_run_html

        return family_run_html(robot, table, title)
    scale = arrow_scale(robot)

    def draw(first: View) -> tuple[dict[str, Any], tuple[Any, Any, Any], list[Any]]:
        sources = figure_sources(first, None, stroke_bands(robot))
        drawn = build_robot_figure(robot, sources, overlay=False)
        return sources, (drawn.layout, drawn.key, drawn.plot), [results_table(sources["values"])]

    t = np.asarray(table["t"], dtype=np.float64)
    return run_page(
        title,
        table,
        lambda k: PRP3_SCENE.view(robot, table, k, scale),
        draw,
        {q: f"{q} (N)" for q in PLOTTED},
        lambda frames: (
            f"<b>{escape(title)}</b>: {t.size} samples over t = {t[0]:g} .. "
            f"{t[-1]:g} s, {frames} frames; forces by prp3 (the kernel, eqs. 10-25)"
        ),
    )


def write_run_html(
    path: str | Path, robot: Robot | FamilyRobot, table: Mapping[str, FloatArray], title: str
) -> None:
    """Write :func:`run_html` to ``path`` atomically (whole or not at all)."""
    page = run_html(robot, table, title)
    with atomic_writer(path) as stream:
        stream.write(page)
