"""prp3: kinematics and complete inverse dynamics of the 3-PRP planar parallel robot.

After S. Staicu and D. Chablat, *Internal joint forces in dynamics of a 3-PRP
planar parallel robot*.  The robot is an immutable :class:`Robot`; the
algorithms are pure functions of ``(robot, motion)`` that return typed
result dataclasses.

>>> import prp3
>>> kin, dyn = prp3.inverse_dynamics(prp3.Robot(), prp3.paper_motion("vertical"))
>>> dyn.f10.shape
(301, 3)
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

import lazy_loader

from prp3 import moved_paths

# Every public name is listed once, in the stub ``__init__.pyi`` beside this file (which
# type checkers read), and imported from its module on first use (SPEC 1).
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
__all__ = sorted([*__all__, "__version__"])

try:
    __version__ = version("prp3")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

moved_paths.install()
