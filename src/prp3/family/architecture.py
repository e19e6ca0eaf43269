"""The leg chain of docs/family.md as a :class:`~prp3.mechanics.architecture.LegArchitecture`.

Every architecture of the family (3-RRR, 3-RPR, …, and the 3-PRP of any
design) runs the four stages of :mod:`prp3.mechanics.architecture` on its
leg chain: :func:`prp3.family.mechanics.inverse_geometry` (the closed-form
closure solutions of :mod:`prp3.family.legs`, the branch of the working
mode), :func:`~prp3.family.mechanics.joint_rates`,
:func:`~prp3.family.mechanics.body_wrenches` and
:func:`~prp3.family.mechanics.virtual_work`.  :func:`architecture_of` gives
the architecture of any robot: the kernel's closed form for a docs/model.md
robot, the leg chain for a family robot.

>>> import numpy as np
>>> from prp3.family.model import FamilyRobot
>>> from prp3.mechanics.architecture import solve_stages
>>> from prp3.model.motion import Motion
>>> solution = solve_stages(architecture_of(FamilyRobot.default("3-RRR")), Motion.at_rest([0, 0, 0]))
>>> solution.tau.shape, solution.force.shape
((3,), (3, 3, 2))
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from prp3.family import mechanics
from prp3.family.model import FamilyRobot
from prp3.mechanics.architecture import ClosedForm3PRP, JointSolution, LegArchitecture
from prp3.model.motion import Motion
from prp3.model.robot import Robot
from prp3.validation import check_instance

__all__ = ["LegChain", "architecture_of"]

FloatArray = NDArray[np.float64]


class LegChain:
    """A family robot's leg chain as a :class:`~prp3.mechanics.architecture.LegArchitecture`.

    Parameters
    ----------
    robot : FamilyRobot
    """

    def __init__(self, robot: FamilyRobot) -> None:
        self.robot = check_instance("robot", robot, FamilyRobot, "a prp3.family.FamilyRobot")
        self.architecture = self.robot.architecture

    def check(self, motion: Motion) -> None:
        """No time-varying load (the family's robots take the ``[load]`` table only)."""
        mechanics.check_inputs(self.robot, motion)

    def inverse_geometry(self, motion: Motion) -> mechanics.Geometry:
        """Stage 1 (docs/family.md §5): the closure solutions of the working mode, followed
        from home; the refusals of §6 (unreachable, singular, crossed) name the sample."""
        pose = motion.pose.reshape(-1, 3)
        return mechanics.inverse_geometry(self.robot, pose, np.atleast_1d(motion.t))

    def rates(self, motion: Motion, geometry: mechanics.Geometry) -> mechanics.FamilyKinematics:
        """Stage 2: ``q̇ = J⁻¹·t``, ``q̈ = J⁻¹·(ṫ − J̇·q̇)``."""
        return mechanics.joint_rates(self.robot, motion, geometry)

    def body_wrenches(
        self, motion: Motion, kinematics: mechanics.FamilyKinematics
    ) -> tuple[FloatArray, FloatArray]:
        """Stage 3 (§4): the links' wrenches about ``G`` and the platform's need minus the load."""
        return mechanics.body_wrenches(kinematics)

    def virtual_work(
        self,
        motion: Motion,
        kinematics: mechanics.FamilyKinematics,
        wrenches: tuple[FloatArray, FloatArray],
    ) -> JointSolution:
        """Stage 4 (§7): the actuator efforts by virtual work, then every joint force."""
        solution = mechanics.virtual_work(kinematics, *wrenches)
        return JointSolution(
            q=solution.q,
            dq=solution.dq,
            ddq=solution.ddq,
            tau=solution.tau,
            force=solution.force,
            moment=solution.moment,
        )


def architecture_of(robot: Robot | FamilyRobot) -> LegArchitecture:
    """The mechanics of ``robot``: :class:`ClosedForm3PRP` or :class:`LegChain`."""
    if isinstance(robot, Robot):
        return ClosedForm3PRP(robot)
    return LegChain(check_instance("robot", robot, FamilyRobot, "a prp3.Robot or a FamilyRobot"))
