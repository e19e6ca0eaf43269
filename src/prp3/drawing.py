"""What the figures and the explorer's pages draw alike: the legs' colours, the bars' sizes.

:mod:`prp3.plotting` (matplotlib: figures, animations) and :mod:`prp3.explorer`
(the browser) both draw the robot and its three legs; the conventions they
share are here, in a layer below both (ARCHITECTURE.md), so that a drawing in
the browser and one in a file look alike and neither package imports the
other.  Plain data: this module imports nothing.

>>> LEG_COLOURS["A"], PISTON_HALF_LENGTH
('#1f77b4', 0.12)
"""

from __future__ import annotations

__all__ = [
    "GUIDE_OVERHANG",
    "LEG_COLOURS",
    "PISTON_HALF_LENGTH",
    "SLEEVE_HALF_LENGTH",
    "SLIDE_HALF_LENGTH",
]

#: The colour of each leg, in every figure and page (matplotlib's tab:blue, tab:orange,
#: tab:green, as hexadecimal colours).
LEG_COLOURS: dict[str, str] = {"A": "#1f77b4", "B": "#ff7f0e", "C": "#2ca02c"}

#: Half-lengths of the 3-PRP's piston and sleeve bars, as fractions of ``l0``.
PISTON_HALF_LENGTH: float = 0.12
SLEEVE_HALF_LENGTH: float = 0.09

#: A family robot's P joint: half length of its slide bar, and how far its guide reaches
#: beyond the slide's travel (m).
SLIDE_HALF_LENGTH: float = 0.025
GUIDE_OVERHANG: float = 0.07
