"""Figures and animations; the only part of prp3 that imports matplotlib.

matplotlib is imported lazily inside the functions (never at import time of
``prp3`` or of this package) and the figures are
:class:`matplotlib.figure.Figure` objects rendered by Agg, without pyplot.

* :mod:`prp3.plotting.figures`: the paper's Figs. 3–8 (input powers ``p10``,
  joint forces ``f21y``, ``f21z`` of legs A, B, C against time) and the
  actuator forces ``f10`` and displacements ``λ10``, from the columns of
  ``results.csv``; with friction, the friction forces of every joint.
* :mod:`prp3.plotting.animation`: an animated GIF of the mechanism.

>>> import subprocess, sys
>>> code = "import sys, prp3.plotting; print('matplotlib' in sys.modules)"
>>> subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.split()
['False']
"""

from __future__ import annotations

from prp3.plotting.animation import (
    MechanismFrame,
    draw_frame,
    frame_indices,
    frame_schedule,
    mechanism_figure,
    mechanism_frame,
    save_animation,
)
from prp3.plotting.figures import (
    figure_names,
    friction_figure,
    leg_figure,
    results_figures,
    save_figure,
    save_figures,
)

__all__ = [
    "MechanismFrame",
    "draw_frame",
    "figure_names",
    "frame_indices",
    "frame_schedule",
    "friction_figure",
    "leg_figure",
    "mechanism_figure",
    "mechanism_frame",
    "results_figures",
    "save_animation",
    "save_figure",
    "save_figures",
]
