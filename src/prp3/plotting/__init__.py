"""Figures and animations; the only part of prp3 that imports matplotlib.

matplotlib is imported lazily inside the functions (never at import time of
``prp3``), with the non-interactive Agg backend when no backend was chosen.
"""

from __future__ import annotations

__all__: list[str] = []
