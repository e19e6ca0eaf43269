"""The family of planar 3-leg parallel robots: 3-PRP, 3-RPR, 3-RRR, 3-PRR, 3-PPR, 3-RPP, 3-RRP.

The model of ``docs/family.md``: three identical legs, each a serial chain of
three one-DOF joints (R or P) from the base to the platform, one of them
actuated; legs B and C are leg A turned by 120° and 240°.  Every joint force is
computed, by three routes that check each other.

Stable API (other modules build on these names only)
----------------------------------------------------
``ARCHITECTURES``
    The seven architecture names.
``FamilyRobot``, ``LegDesign``, ``Body``, ``PlatformBody``
    The immutable, validated model; ``FamilyRobot.default(architecture, actuated=None)``,
    ``FamilyRobot.from_mapping``, ``FamilyRobot.from_toml``, ``FamilyRobot.to_toml``;
    ``robot.types`` (``"RRR"``), ``robot.home_poses``, ``robot.home_measures``.
``robot_file_form(mapping)``, ``read_robot_file(path)``, ``family_template(robot_or_name)``
    Which form a ``ROBOT.toml`` is in; read either form; a documented file.
``family_kinematics(robot, motion) -> FamilyKinematics``
    Joint values, rates, accelerations ``(..., 3 legs, 3 joints)``, ``mu_leg``,
    ``mu_par``, the chain frames and the leg Jacobians; refuses unreachable and
    singular poses (the errors name sample, time, leg, pose and measure).
``family_inverse_dynamics(robot, motion, method="fast", engine=DEFAULT_ENGINE) -> FamilySolution``
    ``method`` in ``FAMILY_METHODS`` (``"fast"``, ``"paper"``, ``"newton-euler"``);
    ``tau``, ``power`` ``(..., 3)``, ``force`` ``(..., 3, 3, 2)``, ``moment`` ``(..., 3, 3)``;
    the fast route's ``engine`` in ``FAMILY_ENGINES``: ``"numba"`` (one compiled loop,
    :mod:`prp3.family.compiled`; the default when numba is installed) or ``"numpy"``
    (:mod:`prp3.family.mechanics`), the same results to round-off and the same errors.
``family_results_table(solution)``, ``FAMILY_COLUMNS``
    The 64 columns of ``results.csv``.
``leg_chain``, ``leg_jacobian``, ``leg_measure``, ``transmitted_wrench``, ``parallel_measure``
    The chain of docs/family.md §2 and the measures of §6 for given joint values.
``paper_steps(robot, motion)``
    Every intermediate quantity of the paper route.

>>> from prp3.model.motion import paper_motion
>>> robot = FamilyRobot.default("3-RRR")
>>> solution = family_inverse_dynamics(robot, paper_motion("vertical", 3))
>>> table = family_results_table(solution)
>>> len(table), round(float(table["tau_A"][0]), 6)
(64, 7.130481)
"""

from __future__ import annotations

from prp3.family.chain import (
    leg_chain,
    leg_jacobian,
    leg_measure,
    parallel_measure,
    transmitted_wrench,
)
from prp3.family.mechanics import FamilyKinematics, FamilySolution, family_kinematics
from prp3.family.model import (
    ARCHITECTURES,
    Body,
    FamilyRobot,
    LegDesign,
    PlatformBody,
    family_template,
    read_robot_file,
    robot_file_form,
)
from prp3.family.outputs import (
    DEFAULT_ENGINE,
    FAMILY_COLUMNS,
    FAMILY_ENGINES,
    FAMILY_METHODS,
    family_inverse_dynamics,
    family_results_table,
)
from prp3.family.paper import paper_steps

__all__ = [
    "ARCHITECTURES",
    "DEFAULT_ENGINE",
    "FAMILY_COLUMNS",
    "FAMILY_ENGINES",
    "FAMILY_METHODS",
    "Body",
    "FamilyKinematics",
    "FamilyRobot",
    "FamilySolution",
    "LegDesign",
    "PlatformBody",
    "family_inverse_dynamics",
    "family_kinematics",
    "family_results_table",
    "family_template",
    "leg_chain",
    "leg_jacobian",
    "leg_measure",
    "paper_steps",
    "parallel_measure",
    "read_robot_file",
    "robot_file_form",
    "transmitted_wrench",
]
