"""The 6-UPS tracking its heave of docs/spatial.md §23: ``docs/figures/spatial_tracking.png``.

Run ``python docs/examples/spatial_tracking.py [PATH]``: the figure ``prp3 control --robot
hexapod.toml --motion heave --plant prp3 --controller computed-torque --initial-error
0,0,0.01,0,0,0.002 --rate 50 --plots`` writes as ``tracking.png`` (about a minute).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

FIGURE = Path(__file__).resolve().parents[1] / "figures" / "spatial_tracking.png"
NAME = "tracking.png"


def draw(path: Path = FIGURE) -> Path:
    """Write the figure to ``path`` and return it."""
    with tempfile.TemporaryDirectory() as folder:
        robot = Path(folder) / "hexapod.toml"
        robot.write_text('architecture = "6-UPS"\n', encoding="utf-8")
        out = Path(folder) / "ctl"
        subprocess.run(
            [sys.executable, "-m", "prp3", "control", "--robot", str(robot), "--motion", "heave",
             "--plant", "prp3", "--controller", "computed-torque", "--initial-error",
             "0,0,0.01,0,0,0.002", "--rate", "50", "--plots", "--output", str(out)],
            check=True,
        )  # fmt: skip
        shutil.copyfile(out / NAME, path)
    return path


if __name__ == "__main__":
    print(draw(Path(sys.argv[1]) if len(sys.argv) > 1 else FIGURE))
