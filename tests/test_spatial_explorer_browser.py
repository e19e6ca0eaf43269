"""The 3-D explorer of a spatial run in a real browser (headless Chromium driven by Playwright).

The page ``prp3 simulate --robot SPATIAL.toml --html`` writes is opened from ``file://`` with
the network off; the plotly figure's data is read from the DOM
(``document.querySelector('.js-plotly-plot').data``) and held against the joint points rebuilt
from the run's ``q`` columns and its ``F`` columns times the stated scale (tests/spatial_pages.py),
to 1e-12; a click on the slider's rail and the play button move it, and the drawn frame is the
slider's sample.  The page ``prp3 explore --robot SPATIAL.toml --results DIR`` serves is the
same.  docs/examples/spatial_explorer_screenshot.py is run into a temporary folder.

Skipped, with one line, when plotly, Playwright or Chromium is missing.
"""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from browsertools import ROOT, explore_server, prp3_env, require_browser, run_prp3
from prp3.io.tables import read_table_csv
from prp3.spatial.model import hexapod
from spatial_pages import expected_points, reported_forces

pytest.importorskip("plotly", reason="the 3-D explorer needs plotly (pip install 'prp3[explore]')")
require_browser()

_READY = """() => { const g = document.querySelector('.js-plotly-plot');
  return !!(g && g._fullLayout && g.data && g.data.length > 0); }"""

#: The slider's step, the figure's meta and every trace's drawn data (typed arrays as lists).
_READ = """() => { const g = document.querySelector('.js-plotly-plot');
  const plain = (v) => (v && typeof v === 'object' && 'length' in v && typeof v !== 'string')
    ? Array.from(v) : v;
  return {
    active: g._fullLayout.sliders[0].active,
    meta: g.layout.meta,
    shown: (Array.from(document.querySelectorAll('text.slider-label'))
      .find((e) => e.textContent.startsWith('t = ')) || {}).textContent,
    data: g.data.map((d) => ({meta: d.meta, x: plain(d.x), y: plain(d.y), z: plain(d.z),
                             text: plain(d.text)})),
  };
}"""

SAMPLES = 61


@pytest.fixture(scope="module")
def tilt(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, Path]:
    folder = tmp_path_factory.mktemp("spatial_browser")
    robot = folder / "hexapod.toml"
    robot.write_text('architecture = "6-UPS"\n', encoding="utf-8")
    run_prp3("simulate", "--robot", str(robot), "--motion", "tilt", "--samples", str(SAMPLES),
             "--output", str(folder / "run"), "--html", str(folder / "tilt.html"))  # fmt: skip
    return robot, folder / "run", folder / "tilt.html"


def _points(trace: dict[str, Any]) -> np.ndarray:
    return np.array(
        [[np.nan if v is None else float(v) for v in trace[a]] for a in "xyz"], dtype=float
    ).T


def _check(state: dict[str, Any], table: dict[str, Any]) -> int:
    """The drawn traces are those of the slider's sample; return that sample."""
    robot = hexapod()
    k = int(state["meta"]["samples"][state["active"]])
    scale = float(state["meta"]["scale"])
    points, force = expected_points(robot, table, k), reported_forces(robot, table, k)
    traces = {trace["meta"]: trace for trace in state["data"]}
    for j, label in enumerate(robot.legs[0].labels):
        np.testing.assert_allclose(
            _points(traces[f"joint {label}"]), points[:, j], rtol=0, atol=1e-12
        )
        shafts = _points(traces[f"force {label}"]).reshape(6, 3, 3)
        np.testing.assert_allclose(shafts[:, 0], points[:, j], rtol=0, atol=1e-12)
        np.testing.assert_allclose(
            (shafts[:, 1] - shafts[:, 0]) * scale, force[:, j], rtol=0, atol=1e-12 * scale
        )
        for i in range(6):
            fx, fy, fz = force[i, j]
            text = traces[f"joint {label}"]["text"][i]
            assert text.startswith(f"leg {i + 1}, joint {label} (")
            assert f"F = ({fx:.6g}, {fy:.6g}, {fz:.6g}) N" in text
    assert state["shown"] == f"t = {float(table['t'][k]):.3f} s"
    return k


def _open(browser: Any, url: str, offline: bool) -> tuple[Any, Any, list[str]]:
    context = browser.new_context(offline=offline, viewport={"width": 1280, "height": 800})
    requested: list[str] = []

    def refuse(route: Any) -> None:
        if route.request.url.startswith(("file://", "http://127.0.0.1")):
            route.continue_()
        else:
            requested.append(route.request.url)
            route.abort()

    context.route("**/*", refuse)
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(url)
    page.wait_for_function(_READY, timeout=60_000)
    return context, page, errors + requested


def test_the_page_opens_offline_and_the_slider_draws_the_sample_s_frame(
    browser: Any, tilt: tuple[Path, Path, Path]
) -> None:
    _, run, page_file = tilt
    columns = (run / "results.csv").read_text(encoding="utf-8").splitlines()[0].split(",")
    table = read_table_csv(run / "results.csv", columns)
    context, page, problems = _open(browser, page_file.as_uri(), offline=True)
    try:
        state = page.evaluate(_READ)
        assert state["active"] == 0 and _check(state, table) == 0
        rail = page.locator(".slider-rail-rect").bounding_box()
        for at in (0.4, 0.85):
            before = page.evaluate(_READ)["active"]
            page.mouse.click(rail["x"] + at * rail["width"], rail["y"] + rail["height"] / 2)
            page.wait_for_function(
                "(k) => document.querySelector('.js-plotly-plot')._fullLayout.sliders[0]"
                ".active !== k",
                arg=before,
                timeout=60_000,
            )
            time.sleep(0.3)
            state = page.evaluate(_READ)
            assert abs(state["active"] / (SAMPLES - 1) - at) < 0.1  # near where it was clicked
            _check(state, table)
        # play from there, then pause: the frame drawn is the slider's
        page.mouse.click(rail["x"] + 0.05 * rail["width"], rail["y"] + rail["height"] / 2)
        time.sleep(0.5)
        start = page.evaluate(_READ)["active"]
        page.get_by_text("▶ play").click()
        page.wait_for_function(
            "(k) => document.querySelector('.js-plotly-plot')._fullLayout.sliders[0].active"
            " >= k + 3",
            arg=start,
            timeout=90_000,
        )
        page.get_by_text("❚❚ pause").click()
        time.sleep(0.6)
        state = page.evaluate(_READ)
        assert state["active"] >= start + 3
        _check(state, table)
        assert problems == []
    finally:
        context.close()


def test_explore_serves_the_same_page(browser: Any, tilt: tuple[Path, Path, Path]) -> None:
    robot, run, _ = tilt
    with explore_server("--robot", str(robot), "--results", str(run)) as (url, line):
        assert line.strip() == f"prp3 explore: serving {url} (Ctrl-C stops)"
        columns = (run / "results.csv").read_text(encoding="utf-8").splitlines()[0].split(",")
        table = read_table_csv(run / "results.csv", columns)
        context, page, problems = _open(browser, url, offline=False)
        try:
            assert _check(page.evaluate(_READ), table) == 0
            assert problems == []
        finally:
            context.close()


def test_the_screenshot_script_writes_the_picture_of_docs_spatial_md(tmp_path: Path) -> None:
    from PIL import Image

    printed = subprocess.run(
        [sys.executable, str(ROOT / "docs" / "examples" / "spatial_explorer_screenshot.py"),
         "--figures", str(tmp_path)],
        env=prp3_env(), check=True, capture_output=True, text=True,
    ).stdout  # fmt: skip
    assert printed.startswith("spatial_explorer.png: 1280 × 800 px, the 6-UPS's tilt")
    assert "force arrows 100 N per m" in printed
    with Image.open(tmp_path / "spatial_explorer.png") as image:
        assert image.size == (1280, 800)
        rgb = np.asarray(image.convert("RGB")).reshape(-1, 3).astype(int)
    # the arrows of the U joints (JOINT_COLOURS[0], #B2182B) and leg 1 (#0072B2) are drawn
    for colour in ((0xB2, 0x18, 0x2B), (0x00, 0x72, 0xB2)):
        assert (np.abs(rgb - colour).max(axis=1) <= 12).sum() > 200, colour
    assert (ROOT / "docs" / "figures" / "spatial_explorer.png").is_file()
