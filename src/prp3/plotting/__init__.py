"""Figures and animations; the only part of prp3 that imports matplotlib.

matplotlib is imported lazily inside the functions (never at import time of
``prp3`` or of this package) and the figures are
:class:`matplotlib.figure.Figure` objects rendered by Agg, without pyplot.
Every figure a command draws is made by a public function of this package,
taken as ``prp3.plotting.<name>`` (each loaded from its module on first use):

* the 3-PRP (:mod:`~prp3.plotting.figures`, :mod:`~prp3.plotting.animation`): the
  paper's Figs. 3–8 (input powers ``p10``, joint forces ``f21y``, ``f21z`` of legs
  A, B, C against time), the actuator forces ``f10`` and displacements ``λ10``, the
  friction forces, and the animated GIF of the mechanism;
* the family of planar architectures (``family*``), the spatial robots
  (``spatial*``), workspace and singularity maps, design sweeps, control and
  identification.

>>> import subprocess, sys
>>> code = "import sys, prp3.plotting; print('matplotlib' in sys.modules)"
>>> subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.split()
['False']
>>> import prp3.plotting
>>> prp3.plotting.save_figure.__module__
'prp3.plotting.figures'
"""

from __future__ import annotations

import lazy_loader

# Every public name is listed once, in the stub ``__init__.pyi`` beside this file (which
# type checkers read), and imported from its module on first use (SPEC 1).
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
