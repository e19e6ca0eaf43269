#!/usr/bin/env python
"""The full table of tracking errors of ``docs/control.md``: both plants, ~2 minutes.

Run from the repository root (MuJoCo optional: its column is skipped without it)::

    python benchmarks/control_table.py            # the paper's rotation motion
    python benchmarks/control_table.py --motion vertical

The table, its plants and controllers are those of
``docs/examples/control_table.py`` (whose prp3-plant column the document quotes
and ``tests/test_docs.py`` checks); this adds the MuJoCo plant's column.
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[1] / "docs" / "examples" / "control_table.py"

if __name__ == "__main__":
    try:
        import mujoco  # noqa: F401

        plants = "prp3,mujoco"
    except ImportError:
        print("MuJoCo not installed: its column is skipped", file=sys.stderr)
        plants = "prp3"
    sys.argv = [str(SCRIPT), *sys.argv[1:], "--plants", plants]
    runpy.run_path(str(SCRIPT), run_name="__main__")
