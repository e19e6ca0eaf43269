"""Helpers of the 3-D explorer's tests: independent joint points, and the figure of a page file.

Imported by tests/test_spatial_explorer.py and tests/test_spatial_explorer_browser.py as
``from spatial_pages import ...`` (``tests/`` is on ``sys.path``, see ``conftest.py``).

:func:`expected_points` rebuilds the joint points of a sample from the reported ``q`` columns
by the joints' own rotations, written out here (not the library's chain of frames), and the
Delta's platform joints from the platform pose of docs/spatial.md §15's circle;
:func:`page_figure` reads the plotly figure (``data``, ``layout``, ``frames``) back out of a
page file's script, as the browser receives it.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from prp3.spatial.model import SpatialRobot


def rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def expected_points(robot: SpatialRobot, table: dict[str, np.ndarray], k: int) -> np.ndarray:
    """The joint points ``(legs, 3, 3)`` of sample ``k`` from the reported ``q`` columns
    (docs/spatial.md §2): the base joint fixed; a UPS leg's P point and S centre where the
    slide ``q_P`` along the U-turned axis ends; an RPS leg's likewise, turned by its R; an RUU
    leg's elbow U at the arm's length turned by its R, its platform U at the pose of the
    circle motion (§15: the Delta's platform keeps its orientation)."""
    points = np.empty((len(robot.legs), 3, 3))
    for i, leg in enumerate(robot.legs):
        base = np.array(leg.joints[0].position)
        r_j = np.array(leg.joints[0].rotation)
        q = {c: float(table[f"q_{i + 1}_{c}"][k]) for c in leg.coordinates}
        if leg.pattern == "RUU":
            elbow = base + r_j @ rot_z(q["R1"]) @ np.array(leg.joints[1].position)
            theta = 2.0 * math.pi * float(table["t"][k]) / 3.0
            p = np.array(robot.home_position) + 0.1 * robot.scale * np.array(
                [math.cos(theta) - 1.0, math.sin(theta), 0.0]
            )
            points[i] = [base, elbow, p + np.array(leg.attachment_position)]
            continue
        turn = rot_z(q["U1_a"]) @ rot_y(q["U1_b"]) if leg.pattern == "UPS" else rot_z(q["R1"])
        slide = q["P2"] + leg.joints[1].position[0] + leg.joints[2].position[0]
        end = base + r_j @ turn @ np.array([slide, 0.0, 0.0])
        points[i] = [base, end, end]
    return points


def reported_forces(robot: SpatialRobot, table: dict[str, Any], k: int) -> np.ndarray:
    """The reported joint forces ``(legs, joints, 3)`` of sample ``k`` (N), from the columns."""
    labels = robot.legs[0].labels
    return np.array(
        [
            [[float(table[f"F{c}_{i + 1}_{label}"][k]) for c in "xyz"] for label in labels]
            for i in range(len(robot.legs))
        ]
    )


def xyz(trace: dict[str, Any]) -> np.ndarray:
    """A trace's points ``(m, 3)``, a gap (``None``/``null``) as NaN."""
    return np.array(
        [[np.nan if v is None else float(v) for v in trace[axis]] for axis in "xyz"], dtype=float
    ).T


def page_figure(page: Path) -> dict[str, Any]:
    """The figure of a page file: the data and layout of its ``Plotly.newPlot`` call and the
    frames of its ``Plotly.addFrames`` call, decoded from the script's JSON."""
    text = page.read_text(encoding="utf-8")
    decoder = json.JSONDecoder()
    start = text.index("Plotly.newPlot(")
    after_id = re.compile(r'\s*"[^"]+",\s*').match(text, start + len("Plotly.newPlot("))
    assert after_id is not None
    data, end = decoder.raw_decode(text, after_id.end())
    comma = re.compile(r"\s*,\s*").match(text, end)
    assert comma is not None
    layout, _ = decoder.raw_decode(text, comma.end())
    frames_at = re.compile(r"Plotly\.addFrames\(\s*'[^']+',\s*").search(text)
    assert frames_at is not None
    frames, _ = decoder.raw_decode(text, frames_at.end())
    return {"data": data, "layout": layout, "frames": frames}


def traces_by_meta(traces: list[dict[str, Any]], names: list[str]) -> dict[str, dict[str, Any]]:
    """A frame's traces by the ``meta`` of the figure's trace at the same place."""
    return dict(zip(names, traces, strict=False))
