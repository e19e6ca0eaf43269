#!/usr/bin/env python
"""Latency of the explorer: a slider move to the redrawn robot and arrows, in the browser.

Run from the repository root (needs Bokeh, the ``playwright`` package and the
OS's Chromium, as the browser tests do)::

    python benchmarks/bench_explore.py            # 60 moves of each slider, about a minute
    python benchmarks/bench_explore.py --moves 20

Starts ``prp3 explore --no-browser`` (the paper's robot, the defaults: the
statics map on) on a free port of 127.0.0.1, opens the page in headless
Chromium and, for each move, sets a slider's ``value`` in the page (what a
drag does), then waits in the page for every source the move redraws to
change (:data:`DRAWN`: the ``arrows``, which arrive with the robot in the same
message, and for ``phi`` the statics map ``overlay`` as well) and for the next
animation frame to be painted (a ``requestAnimationFrame`` callback, then a
task after it): ``performance.now()`` from the move to that paint.  The ``x``
slider recomputes the pose; the ``phi`` slider also recomputes the statics map
of the workspace (41 × 41 poses).

Measured in the same run, interleaved in batches of 10 moves (the same load
for all), as peers of the page's latency: the smallest Bokeh server app of
the same kind (:data:`PEER`: one slider whose Python callback replaces a
12-row source of segments), the floor of a Bokeh server round trip on the
machine at that moment, with ``TCP_NODELAY`` on its websocket as the
explorer sets it (``prp3.explorer.server._no_delay``) and as Bokeh ships it;
and the Python work of one update alone (``pose_table`` and ``scene_view``,
and for ``phi`` ``workspace_overlay``), timed in this process.  The ratios
are what travel between machines.  Exit status 1 if the median latency of
either slider at the defaults exceeds :data:`TARGET` (50 ms).
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import socket
import statistics
import subprocess
import sys
import time
from pathlib import Path

from playwright.sync_api import sync_playwright

from prp3 import Robot
from prp3.explorer.scene import State, arrow_scale, pose_table, scene_view, workspace_overlay

ROOT = Path(__file__).resolve().parents[1]
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]

MOVES = """
async ([name, values, drawn]) => {
  const doc = Bokeh.documents[0];
  const slider = doc.get_model_by_name(name);
  const sources = drawn.map((source) => doc.get_model_by_name(source));
  const times = [];
  for (const value of values) {
    // every source the move redraws has changed (they arrive in one message), then a frame
    // is painted
    const changed = sources.map((source) => new Promise((resolve) => {
      const done = () => {
        source.change.disconnect(done);
        resolve();
      };
      source.change.connect(done);
    }));
    const painted = Promise.all(changed).then(() => new Promise((resolve) => {
      requestAnimationFrame(() => setTimeout(() => resolve(performance.now()), 0));
    }));
    const start = performance.now();
    slider.value = value;
    times.push((await painted) - start);
    await new Promise((resolve) => setTimeout(resolve, 30));
  }
  return times;
}
"""

#: The sources each slider's move redraws: the arrows (and the robot, in the same message);
#: ``phi`` also the statics map.
DRAWN: dict[str, list[str]] = {"x": ["arrows"], "phi": ["arrows", "overlay"]}

#: The largest median latency at the defaults (ms): the issue's target.
TARGET: float = 50.0


#: The peer: the smallest Bokeh server app of the same kind (a slider whose Python callback
#: replaces a 12-row source of arrows drawn in one figure), served the same way.
PEER = """
import sys
from bokeh.server.views.ws import WSHandler
if "--no-delay" in sys.argv:  # as prp3.explorer.server._no_delay does
    opened = WSHandler.open
    def open_without_delay(self):
        self.set_nodelay(True)
        opened(self)
    WSHandler.open = open_without_delay
from bokeh.application import Application
from bokeh.application.handlers.function import FunctionHandler
from bokeh.layouts import column
from bokeh.models import ColumnDataSource, Slider
from bokeh.plotting import figure
from bokeh.server.server import Server

def make(doc):
    arrows = ColumnDataSource({"x0": [0.0] * 12, "y0": [0.0] * 12, "x1": [0.0] * 12,
                               "y1": [0.0] * 12}, name="arrows")
    slider = Slider(start=-1, end=1, value=0, step=0.001, name="x")
    fig = figure(width=500, height=500)
    fig.segment("x0", "y0", "x1", "y1", source=arrows)
    def moved(attr, old, new):
        arrows.data = {"x0": [new] * 12, "y0": [0.0] * 12, "x1": [new + 0.1] * 12,
                       "y1": [0.1] * 12}
    slider.on_change("value", moved)
    doc.add_root(column(slider, fig))

port = int(sys.argv[-1])
server = Server({"/": Application(FunctionHandler(make))}, port=port, address="127.0.0.1",
                allow_websocket_origin=[f"127.0.0.1:{port}"])
server.start()
print("serving", flush=True)
server.io_loop.start()
"""


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _python_update(name: str, values: list[float]) -> list[float]:
    robot = Robot()
    scale = arrow_scale(robot)
    times = []
    for value in values:
        state = State.from_controls({name: value})
        start = time.perf_counter()
        scene_view(robot, pose_table(robot, state), 0, scale)
        if name == "phi":
            workspace_overlay(robot, value)
        times.append(1e3 * (time.perf_counter() - start))
    return times


def _summary(times: list[float]) -> str:
    ordered = sorted(times)
    p90 = ordered[min(len(ordered) - 1, round(0.9 * (len(ordered) - 1)))]
    return f"median {statistics.median(times):6.1f} ms, p90 {p90:6.1f} ms, max {max(times):6.1f} ms"


def _ready(page: object, url: str) -> None:
    page.goto(url)  # type: ignore[attr-defined]
    page.wait_for_function(  # type: ignore[attr-defined]
        "() => window.Bokeh && Bokeh.documents.length > 0 && "
        "Bokeh.documents[0].get_model_by_name('arrows') !== null",
        timeout=30_000,
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--moves", type=int, default=60, help="moves of each slider (default 60)")
    args = parser.parse_args()
    chromium = os.environ.get("PRP3_CHROMIUM") or shutil.which("chromium")
    if chromium is None:
        print("bench_explore: no chromium (apt-get install chromium)", file=sys.stderr)
        return 2
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    commands = {
        "explorer": [sys.executable, "-m", "prp3", "explore", "--no-browser", "--port"],
        "peer, TCP_NODELAY": [sys.executable, "-c", PEER, "--no-delay"],
        "peer, Bokeh as shipped": [sys.executable, "-c", PEER],
    }
    ports = {name: _free_port() for name in commands}
    servers = {
        name: subprocess.Popen(
            [*command, str(ports[name])], env=env, stdout=subprocess.PIPE, text=True
        )
        for name, command in commands.items()
    }
    for process in servers.values():
        assert process.stdout is not None
        process.stdout.readline()
    sweeps = {
        "x": [0.002 * ((k % 40) - 20) + 0.0005 for k in range(args.moves)],
        "phi": [0.01 * ((k % 40) - 20) + 0.001 for k in range(args.moves)],
    }
    print(
        f"bench_explore: {platform.processor() or platform.machine()}, Python "
        f"{platform.python_version()}, {chromium}; {args.moves} moves per slider; "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    status = 0
    try:
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=chromium, args=FLAGS)
            pages = {name: browser.new_page() for name in commands}
            for name, page in pages.items():
                _ready(page, f"http://127.0.0.1:{ports[name]}/")
                page.evaluate(MOVES, ["x", [0.0011, 0.0021, 0.0031], ["arrows"]])  # warm-up
            for slider, values in sweeps.items():
                times: dict[str, list[float]] = {name: [] for name in pages}
                for start in range(0, len(values), 10):  # interleaved: the same load for all
                    for name, page in pages.items():
                        moved = slider if name == "explorer" else "x"
                        drawn = DRAWN[slider] if name == "explorer" else ["arrows"]
                        batch = values[start : start + 10]
                        times[name] += page.evaluate(MOVES, [moved, batch, drawn])
                times["Python update alone"] = _python_update(slider, values)
                median = statistics.median(times["explorer"])
                print(f"slider {slider}:")
                for name, measured in times.items():
                    ratio = median / statistics.median(measured)
                    print(f"  {name:<24} {_summary(measured)}; explorer / this = {ratio:5.2f}")
                if median > TARGET:
                    print(f"  the median of {slider} is above the target of {TARGET:g} ms")
                    status = 1
            browser.close()
    finally:
        for process in servers.values():
            process.terminate()
            process.communicate(timeout=30)
    return status


if __name__ == "__main__":
    sys.exit(main())
