"""The 3-RPS's default workspace slice of docs/spatial.md §17: ``docs/figures/spatial_workspace.png``.

Run ``python docs/examples/spatial_workspace.py [PATH]``: the map ``prp3 workspace`` writes as
``workspace.png`` for ``architecture = "3-RPS"`` (the roll-pitch plane at the home height).
"""

from __future__ import annotations

import sys
from pathlib import Path

FIGURE = Path(__file__).resolve().parents[1] / "figures" / "spatial_workspace.png"


def draw(path: Path = FIGURE) -> Path:
    """Write the figure to ``path`` (atomically) and return it."""
    from prp3 import spatial_workspace, three_rps
    from prp3.plotting import save_spatial_workspace_map

    return save_spatial_workspace_map(path, spatial_workspace(three_rps()))


if __name__ == "__main__":
    print(draw(Path(sys.argv[1]) if len(sys.argv) > 1 else FIGURE))
