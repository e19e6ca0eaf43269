"""The screenshots of docs/explore.md: ``prp3 explore`` in Chromium at its default window.

Starts ``prp3 explore --no-browser`` on a free port of 127.0.0.1 with the robot
file docs/explore.md shows, opens the page in headless Chromium (the OS's,
driven by Playwright, as tests/test_explore_browser.py does), sets the pose and
rates of the caption and writes ``docs/figures/explore.png`` (1280 × 720); then
the same for the default 3-RRR of a family-form robot file (docs/family.md),
``docs/figures/explore_3rrr.png``.

Needs the ``test`` extra and a Chromium (``PRP3_CHROMIUM`` or ``chromium`` on
the path); prints the file it wrote.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from playwright import sync_api

ROOT = Path(__file__).resolve().parents[2]

#: The robot of the screenshot (docs/explore.md quotes it).
ROBOT = "[limits]\nstroke = [-0.06, 0.06]\n\n[payload]\nmass = 1.0\ncom = [0.03, 0.0]\n"

#: The sliders of the caption: pose (m, rad) and rates.
SETTINGS = {"x": 0.03, "y": 0.02, "phi": 0.2, "dx": 0.2, "ddy": 2.0}

#: The sliders of the 3-RRR's caption.
SETTINGS_3RRR = {"x": 0.02, "y": -0.015, "phi": 0.1, "dx": 0.2, "ddy": 2.0}

FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]  # fmt: skip

_SET = "([name, value]) => { Bokeh.documents[0].get_model_by_name(name).value = value; }"


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def shoot(chromium: str, robot_text: str, settings: dict[str, float], target: Path) -> None:
    """Serve ``robot_text`` as the robot file, set ``settings``, write the screenshot ``target``."""
    with tempfile.TemporaryDirectory() as folder:
        robot = Path(folder) / "robot.toml"
        robot.write_text(robot_text, encoding="utf-8")
        port = _free_port()
        server = subprocess.Popen(
            [sys.executable, "-m", "prp3", "explore", "--no-browser", "--port", str(port),
             "--robot", str(robot)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        try:
            assert server.stdout is not None
            line = server.stdout.readline()
            if "serving" not in line:
                raise SystemExit(f"prp3 explore did not start: {line}")
            with sync_api.sync_playwright() as playwright:
                browser = playwright.chromium.launch(executable_path=chromium, args=FLAGS)
                page = browser.new_page(viewport={"width": 1280, "height": 720})
                page.goto(f"http://127.0.0.1:{port}/")
                page.wait_for_function(
                    "() => window.Bokeh && Bokeh.documents.length > 0 && "
                    "Bokeh.documents[0].get_model_by_name('arrows') !== null",
                    timeout=30_000,
                )
                for name, value in settings.items():
                    page.evaluate(_SET, [name, value])
                time.sleep(1.5)  # the server's update and the repaint
                page.screenshot(path=str(target))
                browser.close()
        finally:
            server.terminate()
            server.communicate(timeout=30)
    print(target.relative_to(ROOT))


def main() -> None:
    from prp3 import FamilyRobot

    chromium = os.environ.get("PRP3_CHROMIUM") or shutil.which("chromium")
    if chromium is None:
        raise SystemExit("no chromium: install it (apt-get install chromium) or set PRP3_CHROMIUM")
    figures = ROOT / "docs" / "figures"
    shoot(chromium, ROBOT, SETTINGS, figures / "explore.png")
    rrr = FamilyRobot.default("3-RRR").to_toml()
    shoot(chromium, rrr, SETTINGS_3RRR, figures / "explore_3rrr.png")


if __name__ == "__main__":
    main()
