"""The screenshot of docs/explore.md's family section: a 3-RRR page at Chromium's default window.

    PYTHONPATH=src python docs/figures/explore_3rrr.py docs/figures/explore_3rrr.png

Serves ``prp3 explore --robot rrr.toml`` (the default 3-RRR, written next to
the working directory), sets the sliders of the caption, waits for the page
and takes the screenshot at Playwright's default viewport (1280 × 720).
"""
import os, subprocess, sys, time, socket
from pathlib import Path
from playwright.sync_api import sync_playwright
ROOT = Path(__file__).resolve().parents[2]
from prp3.family import FamilyRobot
robot_file = Path(sys.argv[2] if len(sys.argv) > 2 else "rrr.toml"); robot_file.write_text(FamilyRobot.default("3-RRR").to_toml())
with socket.socket() as s:
    s.bind(("127.0.0.1", 0)); port = s.getsockname()[1]
env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
server = subprocess.Popen([sys.executable, "-m", "prp3", "explore", "--no-browser", "--port", str(port), "--robot", str(robot_file)], env=env, stdout=subprocess.PIPE, text=True)
print(server.stdout.readline())
try:
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path="/usr/bin/chromium", args=["--headless", "--no-sandbox", "--disable-gpu"])
        page = b.new_page()
        page.goto(f"http://127.0.0.1:{port}/")
        page.wait_for_function("() => window.Bokeh && Bokeh.documents.length > 0 && Bokeh.documents[0].get_model_by_name('arrows') !== null", timeout=30000)
        for name, value in {"x": 0.02, "y": -0.015, "phi": 0.1, "dx": 0.2, "ddy": 2.0}.items():
            page.evaluate("([n, v]) => { Bokeh.documents[0].get_model_by_name(n).value = v; }", [name, value])
        time.sleep(2)
        page.screenshot(path=sys.argv[1])
        print(page.viewport_size)
        b.close()
finally:
    server.terminate(); server.communicate(timeout=30)
