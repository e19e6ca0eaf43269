"""Draw the seven default designs of docs/family.md at home: ``docs/figures/family_designs.png``.

Run ``python docs/examples/family_drawings.py``; ``tests/test_family_docs.py`` runs it and
checks that the committed figure is the one it draws.
"""

from __future__ import annotations

import sys
from pathlib import Path

FIGURE = Path(__file__).resolve().parents[1] / "figures" / "family_designs.png"


def draw(path: Path = FIGURE) -> Path:
    """Write the figure to ``path`` (atomically) and return it."""
    from prp3 import ARCHITECTURES, FamilyRobot
    from prp3.plotting import designs_figure, save_figure

    robots = [FamilyRobot.default(name) for name in ARCHITECTURES]
    return save_figure(designs_figure(robots), path)


if __name__ == "__main__":
    print(draw(Path(sys.argv[1]) if len(sys.argv) > 1 else FIGURE))
