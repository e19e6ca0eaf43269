"""Complete inverse dynamics: actuator forces, input powers and every joint reaction.

Three methods give the same numbers (``method`` of :func:`inverse_dynamics`):

* ``"fast"`` — :func:`kernel_method`, the kernel's closed form of the paper's
  method (eqs. 10–25, :mod:`prp3.mechanics.kernel`), the default;
* ``"paper"`` — :func:`prp3.references.paper.paper_method`, the paper's recursive 3×3
  matrices as printed, kinematics and forces (nothing from the kernel);
* ``"newton-euler"`` — :func:`prp3.references.newton_euler.newton_euler`, the balances of
  the 7 bodies in maximal coordinates, one 21×21 solve per sample.

All return :class:`~prp3.mechanics.forces.InverseDynamics` (signs in ``docs/model.md``).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from prp3.engines.compiled_robot import Engine
from prp3.engines.entries import solve_batch
from prp3.engines.select import resolve_engine
from prp3.errors import Prp3Error
from prp3.mechanics.forces import FORCE_NAMES, FRICTION_NAMES, InverseDynamics, checked
from prp3.mechanics.kinematics import Kinematics, inverse_kinematics
from prp3.model.motion import Motion, name_overflow_input
from prp3.model.robot import Robot
from prp3.path_validation import check_path
from prp3.references.newton_euler import newton_euler
from prp3.references.paper import paper_method
from prp3.validation import check_choice, check_instance, check_robot

__all__ = [
    "METHODS",
    "inverse_dynamics",
    "kernel_method",
]

FloatArray = NDArray[np.float64]
Method = Literal["fast", "paper", "newton-euler"]

#: Names accepted by :func:`inverse_dynamics`'s ``method``.
METHODS: tuple[str, ...] = ("fast", "paper", "newton-euler")


def kernel_method(robot: Robot, kin: Kinematics, *, engine: Engine = None) -> InverseDynamics:
    """Inverse dynamics by the kernel's closed form (eqs. 19–25), with every reaction.

    :func:`prp3.engines.entries.solve_batch` on the motion of ``kin``, run by ``engine``
    (``"numba"``, ``"numpy"`` or ``None``: :func:`prp3.engines.select.default_engine`).

    Examples
    --------
    >>> from prp3.model.motion import Motion
    >>> robot = Robot()
    >>> dyn = kernel_method(robot, inverse_kinematics(robot, Motion.at_rest([0.0, 0.0, 0.0])))
    >>> dyn.f10.round(4).tolist()    # static central configuration, see tests
    [31.8589, -8.4957, -23.3632]
    """
    check_robot(robot)
    motion = check_instance("kin", kin, Kinematics, "a prp3.Kinematics").motion
    values = solve_batch(
        robot, motion.pose, motion.velocity, motion.acceleration, load=motion.load, engine=engine
    )
    names = FORCE_NAMES + (FRICTION_NAMES if robot.friction is not None else ())
    implicit = "iterations" in values
    result = InverseDynamics(
        **{name: values[name] for name in names},
        method="fast",
        iterations=values["iterations"] if implicit else None,
        near_lock=values["near_lock"] > 0.5 if implicit else None,
    )
    return checked(result, motion.t)


def inverse_dynamics(
    robot: Robot, motion: Motion, method: Method = "fast", *, engine: Engine = None
) -> tuple[Kinematics, InverseDynamics]:
    """Kinematics and complete inverse dynamics of a platform motion.

    Parameters
    ----------
    robot : Robot
    motion : Motion
        ``N`` samples or a single one.
    method : {"fast", "paper", "newton-euler"}
        :func:`kernel_method` (the kernel's closed form of eqs. 19–25, the
        default), :func:`prp3.references.paper.paper_method` (the paper's recursive 3×3
        matrices as printed: its own kinematics too) or
        :func:`prp3.references.newton_euler.newton_euler`.
    engine : {"numba", "numpy"} or None
        The engine of ``method="fast"`` (:mod:`prp3.engines.select`; ``None``: the
        default, numba when installed); validated for every method.

    Returns
    -------
    (Kinematics, InverseDynamics)

    Examples
    --------
    >>> from prp3.model.motion import paper_motion
    >>> kin, dyn = inverse_dynamics(Robot(), paper_motion("vertical", samples=3))
    >>> dyn.f10.shape
    (3, 3)
    """
    check_instance("motion", motion, Motion, "a prp3.Motion")
    check_choice("method", method, METHODS)
    engine = resolve_engine(engine)  # type: ignore[assignment]
    check_path(motion.t, motion.pose)  # no singular orientation between two samples
    try:
        if method == "paper":
            return paper_method(robot, motion)
        kin = inverse_kinematics(robot, motion)
        if method == "fast":
            return kin, kernel_method(robot, kin, engine=engine)
        return kin, newton_euler(robot, motion)
    except Prp3Error as error:  # results that overflow: the input that made them is named
        raise name_overflow_input(error, motion) from None
