"""The independent routes: the paper's recursive matrix method as printed (`paper_kinematics`, `paper_wrenches`, `paper`) and Newton-Euler of the seven bodies (`newton_euler`).

The paper's matrices and relations that docs/paper_walkthrough.md shows line by line
against the typeset equations are public here, as ``prp3.references.<name>``:

>>> from prp3.references import THETA_1, rot
>>> bool((THETA_1 @ THETA_1.T == rot(0.0)).all())
True
"""

from __future__ import annotations

from prp3.references.paper_kinematics import (
    THETA_1,
    THETA_2,
    orientation_condition,
    rot,
    theta_alpha,
)

__all__ = ["THETA_1", "THETA_2", "orientation_condition", "rot", "theta_alpha"]
