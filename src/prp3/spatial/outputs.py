"""The spatial inverse dynamics by route and its result columns (docs/spatial.md §8, §9).

:func:`spatial_inverse_dynamics` runs the kinematics and one route —
``"virtual-work"`` (route (a): the efforts only) or ``"newton-euler"``
(route (b): the efforts and every joint's wrench) — and returns one
:class:`SpatialSolution`; :func:`spatial_results_table` names its columns.

>>> from prp3.spatial.model import hexapod
>>> from prp3.spatial.motion import PlatformMotion
>>> robot = hexapod()
>>> solution = spatial_inverse_dynamics(robot, PlatformMotion.at_rest(robot.home_position))
>>> table = spatial_results_table(solution)
>>> len(table), list(table)[:3], round(float(table["Fz_1_S3"][0]), 6)  # 9.81 N / 6 legs
(229, ['t', 'q_1_U1_a', 'q_1_U1_b'], 1.635)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.spatial.dynamics import body_wrenches, virtual_work_efforts
from prp3.spatial.geometry import CHUNK
from prp3.spatial.kinematics import SpatialKinematics, chunk_kinematics, spatial_kinematics
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.newton_euler import recursive_chunk
from prp3.validation import check_choice, check_instance, require_finite

__all__ = [
    "SPATIAL_METHODS",
    "SpatialSolution",
    "spatial_inverse_dynamics",
    "spatial_results_table",
]

FloatArray = NDArray[np.float64]

#: The routes of docs/spatial.md §8.
SPATIAL_METHODS: tuple[str, ...] = ("newton-euler", "virtual-work")


@dataclass(frozen=True)
class SpatialSolution:
    """The inverse dynamics of a motion (docs/spatial.md §9).

    Attributes
    ----------
    robot : SpatialRobot
    t : (N,) s
    kinematics : SpatialKinematics
        ``q, dq, ddq (N, legs, dof)``, the parallel Jacobian and the measures.
    tau, power : (N, legs)
        Actuator efforts (N or N·m) and their powers ``tau·dq_act`` (W).
    force, moment : (N, legs, joints, 3) or None
        Every joint's wrench (N, N·m; world frame, at the joint point); ``None`` for
        ``"virtual-work"``, which gives the efforts only.
    method : str
    """

    robot: SpatialRobot
    t: FloatArray
    kinematics: SpatialKinematics
    tau: FloatArray
    power: FloatArray
    force: FloatArray | None
    moment: FloatArray | None
    method: str


def spatial_inverse_dynamics(
    robot: SpatialRobot, motion: PlatformMotion, method: str = "newton-euler"
) -> SpatialSolution:
    """Joint motions, actuator efforts and powers, and (``"newton-euler"``) every joint's wrench.

    Raises
    ------
    UnreachablePoseError, SingularPoseError
        A pose out of reach or singular (names the sample, time and leg).
    TrajectoryError
        Results that overflow float64 (names the sample, its time and the result).
    ParameterError
        ``method`` not in :data:`SPATIAL_METHODS`; a robot or motion of the wrong type.
    """
    check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    check_instance("motion", motion, PlatformMotion, "a PlatformMotion")
    check_choice("method", method, SPATIAL_METHODS)
    with np.errstate(all="ignore"):  # an overflow is refused below, naming the sample
        if method == "newton-euler":
            kin, tau, force, moment = _newton_euler(robot, motion)
        else:
            kin = spatial_kinematics(robot, motion)
            tau, force, moment = virtual_work_efforts(robot, motion), None, None
        power = tau * kin.dq[..., robot.legs[0].actuated_coordinate]
    results = {"q": kin.q, "dq": kin.dq, "ddq": kin.ddq, "tau": tau, "power": power}
    if force is not None and moment is not None:
        results |= {"force": force, "moment": moment}
    require_finite(results, (len(motion),), "spatial inverse dynamics", motion.t)
    return SpatialSolution(robot, motion.t, kin, tau, power, force, moment, method)


def _newton_euler(
    robot: SpatialRobot, motion: PlatformMotion
) -> tuple[SpatialKinematics, FloatArray, FloatArray, FloatArray]:
    """The kinematics and route (b) (:func:`~prp3.spatial.newton_euler.recursive_chunk`) in one
    pass over chunks of ``CHUNK`` samples."""
    n, legs, dof = len(motion), len(robot.legs), robot.legs[0].dof
    joints = len(robot.legs[0].joints)
    q, dq, ddq = (np.empty((n, legs, dof)) for _ in range(3))
    jp, leg, par = np.empty((n, legs, 6)), np.empty((n, legs)), np.empty(n)
    tau = np.empty((n, legs))
    force, moment = np.empty((n, legs, joints, 3)), np.empty((n, legs, joints, 3))
    for start in range(0, n, CHUNK):
        stop = min(start + CHUNK, n)
        chunk = motion.chunk(start, stop)
        kin = chunk_kinematics(robot, chunk, start)
        part = recursive_chunk(robot, kin, chunk, body_wrenches(robot, kin, chunk))
        q[start:stop], dq[start:stop], ddq[start:stop] = kin.frames.q, kin.dq, kin.ddq
        jp[start:stop], leg[start:stop] = kin.parallel, kin.leg_measure
        par[start:stop] = kin.parallel_measure
        tau[start:stop], force[start:stop], moment[start:stop] = part.tau, part.force, part.moment
    return SpatialKinematics(q, dq, ddq, jp, leg, par), tau, force, moment


def spatial_results_table(solution: SpatialSolution) -> dict[str, FloatArray]:
    """The columns of docs/spatial.md §9, each ``(N,)``: ``t``, ``q_/dq_/ddq_<leg>_<coordinate>``,
    ``tau_<leg>``, ``power_<leg>`` and (Newton–Euler) ``F<x|y|z>_<leg>_<joint>``,
    ``M<x|y|z>_<leg>_<joint>``."""
    check_instance("solution", solution, SpatialSolution, "a SpatialSolution")
    leg0 = solution.robot.legs[0]
    kin = solution.kinematics
    table: dict[str, FloatArray] = {"t": solution.t}
    for name, values in (("q", kin.q), ("dq", kin.dq), ("ddq", kin.ddq)):
        for i in range(values.shape[1]):
            for c, coordinate in enumerate(leg0.coordinates):
                table[f"{name}_{i + 1}_{coordinate}"] = values[:, i, c]
    for i in range(solution.tau.shape[1]):
        table[f"tau_{i + 1}"] = solution.tau[:, i]
    for i in range(solution.tau.shape[1]):
        table[f"power_{i + 1}"] = solution.power[:, i]
    if solution.force is not None and solution.moment is not None:
        for kind, values in (("F", solution.force), ("M", solution.moment)):
            for i in range(values.shape[1]):
                for k, label in enumerate(leg0.labels):
                    for axis, component in enumerate("xyz"):
                        table[f"{kind}{component}_{i + 1}_{label}"] = values[:, i, k, axis]
    return table
