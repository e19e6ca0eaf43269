"""The results table ``results.csv`` (kept for its names; the format lives in :mod:`prp3.io`).

>>> RESULT_COLUMNS[:5]
('t', 'x', 'y', 'phi', 'lambda10_A')
"""

from __future__ import annotations

from .io import FRICTION_COLUMNS, PER_LEG_COLUMNS, RESULT_COLUMNS, result_columns, results_table

__all__ = [
    "FRICTION_COLUMNS",
    "PER_LEG_COLUMNS",
    "RESULT_COLUMNS",
    "result_columns",
    "results_table",
]
