"""The screenshots of docs/explore.md: the explorer's page at Chromium's default window.

    python docs/examples/explore_screenshots.py --figures docs/figures

Serves ``prp3 explore`` (this checkout's sources) twice — the 3-PRP robot of
the file quoted in docs/explore.md, and the default 3-RRR of a family-form
file (docs/family.md) — sets the sliders of each caption, waits until the
page shows the library's values, and writes ``DIR/explore.png`` and
``DIR/explore_3rrr.png`` at Playwright's default viewport (1280 × 720).
Needs Bokeh, Playwright and a Chromium (``PRP3_CHROMIUM``, else ``chromium``
on the ``PATH``), as ``tests/test_explore_browser.py``.
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: The 3-PRP robot of the screenshot (docs/explore.md quotes it).
PRP3_ROBOT = """\
# the robot of the screenshot: the paper's robot with strokes and a payload
[limits]
stroke = [-0.06, 0.06]

[payload]
mass = 1.0
com = [0.03, 0.0]
"""

#: name of the figure → (the robot file's text, the sliders of its caption).
PAGES: dict[str, tuple[str, dict[str, float]]] = {
    "explore.png": (PRP3_ROBOT, {"x": 0.03, "y": 0.02, "phi": 0.2, "dx": 0.2, "ddy": 2.0}),
    "explore_3rrr.png": ("", {"x": 0.02, "y": -0.015, "phi": 0.1, "dx": 0.2, "ddy": 2.0}),
}

_READY = (
    "() => window.Bokeh && Bokeh.documents.length > 0 && "
    "Bokeh.documents[0].get_model_by_name('arrows') !== null"
)
_SET = "([n, v]) => { Bokeh.documents[0].get_model_by_name(n).value = v; }"


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def shoot(browser: object, robot_file: Path, sliders: dict[str, float], path: Path) -> None:
    """Serve ``robot_file``, set ``sliders``, write the screenshot ``path``."""
    port = _free_port()
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    server = subprocess.Popen(
        [sys.executable, "-m", "prp3", "explore", "--no-browser", "--port", str(port),
         "--robot", str(robot_file)],
        env=env, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert server.stdout is not None and "serving" in server.stdout.readline()
        page = browser.new_page()  # type: ignore[attr-defined]
        page.goto(f"http://127.0.0.1:{port}/")
        page.wait_for_function(_READY, timeout=60_000)
        for name, value in sliders.items():
            page.evaluate(_SET, [name, value])
        time.sleep(2.0)  # the server's updates and the repaint
        page.screenshot(path=str(path))
        page.close()
    finally:
        server.terminate()
        server.communicate(timeout=30)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", type=Path, required=True, help="folder of the PNG files")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    from prp3.family import FamilyRobot

    chromium = os.environ.get("PRP3_CHROMIUM") or shutil.which("chromium")
    args.figures.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder, sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=chromium, args=["--headless", "--no-sandbox", "--disable-gpu"]
        )
        for name, (text, sliders) in PAGES.items():
            robot_file = Path(folder) / f"{name}.toml"
            robot_file.write_text(text or FamilyRobot.default("3-RRR").to_toml(), encoding="utf-8")
            shoot(browser, robot_file, sliders, args.figures / name)
            print(f"wrote {name} (1280 x 720)")
        browser.close()


if __name__ == "__main__":
    main()
