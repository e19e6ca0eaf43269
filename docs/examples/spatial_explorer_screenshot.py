"""The screenshot of docs/spatial.md §22: the 3-D explorer's page of the hexapod's tilt in Chromium.

Runs ``prp3 simulate --robot hexapod.toml --motion tilt --html tilt.html`` (the default 6-UPS,
301 samples) in a temporary folder, opens the page from ``file://`` in headless Chromium (the
OS's, driven by Playwright, as tests/test_explore_browser.py does) at 1280 × 800 with the
network off, moves the time slider by a click on its rail at 1/4 of its length (the sample
nearest t = 0.75 s), and writes ``spatial_explorer.png`` into ``--figures DIR`` (default
docs/figures).  Prints what the page shows there, read back from the page.

Needs the ``test`` extra and a Chromium (``PRP3_CHROMIUM`` or ``chromium`` on the path).
``tests/test_spatial_explorer_browser.py`` runs it.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from playwright import sync_api

ROOT = Path(__file__).resolve().parents[2]

FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]  # fmt: skip

#: Where the slider's rail is clicked, as a fraction of its length.
AT = 0.25

_READY = """() => { const g = document.querySelector('.js-plotly-plot');
  return g && g._fullLayout && g.data && g.data.length > 0; }"""

_STATE = """() => { const g = document.querySelector('.js-plotly-plot');
  const k = g._fullLayout.sliders[0].active;
  return [k, g.layout.meta.samples[k], g.layout.meta.times[k], g.layout.meta.scale]; }"""


def shoot(chromium: str, target: Path) -> str:
    """Write the screenshot ``target``; return the report line."""
    with tempfile.TemporaryDirectory() as folder:
        robot = Path(folder) / "hexapod.toml"
        robot.write_text('architecture = "6-UPS"\n', encoding="utf-8")
        page_file = Path(folder) / "tilt.html"
        env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
        subprocess.run(
            [sys.executable, "-m", "prp3", "simulate", "--robot", robot.name, "--motion", "tilt",
             "--output", "run", "--html", page_file.name],
            env=env, cwd=folder, check=True, capture_output=True,
        )  # fmt: skip
        with sync_api.sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=chromium, args=FLAGS)
            context = browser.new_context(offline=True, viewport={"width": 1280, "height": 800})
            page = context.new_page()
            page.goto(page_file.as_uri())
            page.wait_for_function(_READY, timeout=60_000)
            rail = page.locator(".slider-rail-rect").bounding_box()
            assert rail is not None
            page.mouse.click(rail["x"] + AT * rail["width"], rail["y"] + rail["height"] / 2)
            page.wait_for_function(
                "() => document.querySelector('.js-plotly-plot')._fullLayout.sliders[0].active > 0"
            )
            time.sleep(1.0)  # the redraw of the WebGL scene
            page.mouse.move(1270, 790)  # off the figure: no hover label or mode bar
            step, sample, t, scale = page.evaluate(_STATE)
            target.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(target))
            browser.close()
    return (
        f"{target.name}: 1280 × 800 px, the 6-UPS's tilt (301 samples, 200 frames) at slider "
        f"step {step}: sample {sample}, t = {t:.3f} s; force arrows {scale:g} N per m"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", type=Path, default=ROOT / "docs" / "figures")
    args = parser.parse_args()
    chromium = os.environ.get("PRP3_CHROMIUM") or shutil.which("chromium")
    if chromium is None:
        raise SystemExit("no chromium: install it (apt-get install chromium) or set PRP3_CHROMIUM")
    print(shoot(chromium, args.figures / "spatial_explorer.png"))


if __name__ == "__main__":
    main()
